"""Per-tick player input as bit flags: compact to record, cheap to compare."""

from __future__ import annotations

from enum import IntFlag


class Action(IntFlag):
    NONE = 0
    LEFT = 1
    RIGHT = 2
    FIRE = 4
    START = 8  # the one-player start button (a new game once the last one is over)
    START2 = 16  # the two-player start button


ALL_ACTIONS = int(Action.LEFT | Action.RIGHT | Action.FIRE | Action.START | Action.START2)
