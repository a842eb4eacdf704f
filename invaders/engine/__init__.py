"""A game-agnostic 2D collision engine on pygame masks.

Kinds are small integers its user defines (0 to 63); a rules table says which pairs of
kinds are tested, how (box or pixels, discrete, swept or where they land, inside which
zone), which side each contact spends and what responds to it. Bodies live in a
`BodyStore` that feeds the broad phase's move buffer; a `Detector` returns each tick's
contacts, each with its time of impact as an exact fraction, and the counters of every
pipeline step. It imports nothing else of this package.
"""
