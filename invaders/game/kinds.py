"""The game's kinds of collidable body, as the engine sees them (small integers)."""

from __future__ import annotations

from enum import IntEnum


class Kind(IntEnum):
    """What a body is, for the rules table. Values are stable: they appear in reports."""

    CANNON = 1
    SHOT = 2
    BOMB = 3
    ALIEN = 4
    BUNKER = 5
    SAUCER = 6
    TOP = 7  # the top limit, where the shot bursts: a playfield edge
    GROUND = 8  # the ground line, where bombs burst: a playfield edge


# The playfield's edges: static bodies, made once with the world, never counted as things.
EDGES = frozenset({Kind.TOP, Kind.GROUND})
THINGS = tuple(kind for kind in Kind if kind not in EDGES)
