"""Two players: the one waiting keeps their own rack, shields, score, ships and wave.

The ROM keeps each player's aliens and shields in a page of their own (2100 and 2200) and
swaps pages at each death while the other player still has ships (02D7-032C): the field is
held two seconds, then PLAY PLAYER<n> with that player's score flashing (088D-08CE), then
that player's own field, redrawn one alien a tick as at a wave's start, the cannon ready at
once (0318).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pygame

from invaders.engine.compiled import mypyc_attr
from invaders.engine.pickling import mask_bytes
from invaders.game.rack import Rack

HOLD = 128  # frames the field stays as it was after the death (0315: TwoSecDelay, 0x80)
PROMPT = 176  # frames of PLAY PLAYER<n> and the flashing score (08A1: 0xB0)
SWITCH_TICKS = HOLD + PROMPT


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
@dataclass
class Turn:
    """A player's things while the other plays."""

    number: int  # 1 or 2
    score: int
    ships: int
    extra_awarded: bool
    wave: int
    rack: Rack | None  # None: a fresh rack for their wave (player 2 before their first turn)
    shields: list[pygame.mask.Mask] = field(default_factory=list)  # empty: fresh ones
    out: bool = False  # no ships left (or invaded): the other plays on alone

    def state(self) -> tuple:
        """What decides the waiting player's future, for the state hash."""
        rack = self.rack
        kept = None if rack is None else (rack.ref_x, rack.ref_top, rack.dx, rack.frame,
                                          rack.live, tuple(a is not None for a in rack.aliens))
        return (self.number, self.score, self.ships, self.extra_awarded, self.wave, self.out,
                kept, b"".join(mask_bytes(m) for m in self.shields))

