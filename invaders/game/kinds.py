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
