"""The emulated original as a yardstick: the Arcade Learning Environment's Space Invaders.

What reinforcement-learning users run: the Atari 2600 cartridge (the ROM ships with
`ale-py`, the optional `compare` extra) emulated frame by frame, one frame a step (frame
skip 1, no sticky actions), the screen kept in the emulator's buffer and never shown. The
bench times it beside our game on the same fixed input cycle.
"""

from __future__ import annotations

import time
from typing import Any

from invaders.game.actions import Action
from invaders.lab.timing import no_gc

# One input cycle for both games: fire, move right a while, fire, move left a while.
CYCLE = ([int(Action.FIRE)] + [int(Action.RIGHT)] * 15 + [0] * 4
         + [int(Action.FIRE)] + [int(Action.LEFT)] * 15 + [0] * 4)


def available() -> bool:
    """Whether ale-py is installed with the Space Invaders ROM (it ships its ROMs)."""
    try:
        from ale_py import roms
    except ImportError:
        return False
    return roms.get_rom_path("space_invaders") is not None


def _ale_action(bits: int) -> Any:
    from ale_py import Action as AleAction

    fire = bits & Action.FIRE
    if bits & Action.RIGHT:
        return AleAction.RIGHTFIRE if fire else AleAction.RIGHT
    if bits & Action.LEFT:
        return AleAction.LEFTFIRE if fire else AleAction.LEFT
    return AleAction.FIRE if fire else AleAction.NOOP


def emulator(seed: int) -> Any:
    """ALE with Space Invaders loaded, quiet, one frame a step."""
    from ale_py import ALEInterface, LoggerMode, roms

    ALEInterface.setLoggerMode(LoggerMode.Error)
    ale = ALEInterface()
    ale.setInt("random_seed", seed)
    ale.setInt("frame_skip", 1)
    ale.setFloat("repeat_action_probability", 0.0)
    rom = roms.get_rom_path("space_invaders")
    assert rom is not None, "ale-py without the Space Invaders ROM: see available()"
    ale.loadROM(rom)
    return ale


def ale_seconds(ale: Any, frames: int) -> float:
    """Wall seconds for `frames` emulated frames on the input cycle (a game that ends is
    reset, as a learner's loop does, inside the time)."""
    cycle = [_ale_action(bits) for bits in CYCLE]
    n = len(cycle)
    act, over, reset = ale.act, ale.game_over, ale.reset_game
    with no_gc():
        start = time.perf_counter()
        for i in range(frames):
            act(cycle[i % n])
            if over():
                reset()
        return time.perf_counter() - start
