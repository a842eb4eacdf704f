"""Events a tick reports besides its collision counters."""

from __future__ import annotations

from enum import IntEnum


class Event(IntEnum):
    """Things a tick can report besides its collision counters."""

    SHOT_FIRED = 1
    ALIEN_KILLED = 2
    SHOT_BURST = 3
    BOMB_FIRED = 4
    BOMB_BURST = 5
    BUNKER_HIT = 6
    CANNON_HIT = 7
    SHIP_LOST = 8
    SAUCER_LAUNCHED = 9
    SAUCER_HIT = 10
    SAUCER_SCORED = 11
    EXTRA_SHIP = 12
    WAVE_CLEARED = 13
    WAVE_STARTED = 14
    INVASION = 15
    GAME_OVER = 16
    NEW_GAME = 17
    PLAYER_UP = 18  # two players: the other's turn begins (PLAY PLAYER<n> is shown)
    TURN_STARTED = 19  # two players: the player up has their own field back
