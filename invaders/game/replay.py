"""Replays: a game's seed, config and inputs with checkpoints, so that a replay that goes
wrong says where first and what; and checking one headless.

A replay holds the seed and rule configuration, the input bits of every tick run-length
encoded, and checkpoints (every 60 ticks and at the end) with the state hash, score, ships,
wave, body counts and one digest per state group. The format and its limits are in
replay_format.py, reading a file in replay_reading.py (its fields checked in
replay_checks.py); writing files is the application's (recording.py). This module runs a
replay and gives the names the rest of the program uses.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from invaders.engine.adaptive import DEFAULT_BROADPHASE
from invaders.game.checkpoint import Checkpoint, Checkpoints
from invaders.game.replay_checks import need, parse
from invaders.game.replay_format import (
    CHECKPOINT_EVERY,
    FORMAT,
    MAX_FILE_BYTES,
    MAX_RUNS,
    MAX_SWITCHES,
    MAX_TICKS,
    VERSION,
    Replay,
    ReplayError,
    Switch,
    segment_line,
)
from invaders.game.replay_reading import load, parse_lines
from invaders.game.world import World

__all__ = ["CHECKPOINT_EVERY", "FORMAT", "MAX_FILE_BYTES", "MAX_RUNS", "MAX_SWITCHES",
           "MAX_TICKS", "VERSION",
           "CheckResult", "Checkpoint", "Checkpoints", "Replay", "ReplayError", "Switch",
           "load", "parse", "parse_lines", "replay_paths", "run", "segment_line"]


def replay_paths(arg: str) -> list[Path]:
    """The file named, or the *.json files of the folder named, in order; ReplayError if
    there is none. A link that leads nowhere (or round in a loop) is kept, for its reading
    to say so: a folder's would otherwise go unchecked without a word."""
    path = Path(arg)
    try:
        is_dir, exists = path.is_dir(), path.exists() or path.is_symlink()
    except OSError as err:
        raise ReplayError(f"{arg[:80]}: {err.strerror}") from None
    if is_dir:
        found = sorted(p for p in path.glob("*.json") if not p.is_dir())
        if not found:
            raise ReplayError(f"{arg}: no replay files (*.json) in this folder")
        return found
    if not exists:
        raise ReplayError(f"{arg}: no such file or folder")
    return [path]


# --- running ----------------------------------------------------------------------------------
@dataclass
class CheckResult:
    ticks: int
    checkpoints: int
    final: Checkpoint
    mismatch: str | None = None  # the first checkpoint that differs, described


def run(replay: Replay, broadphase: str = DEFAULT_BROADPHASE, recompute: bool = False,
        switch: Callable[[World, dict[str, Any]], None] | None = None,
        ) -> tuple[CheckResult, Checkpoints]:
    """Run a replay headless at full speed, checking every field of every checkpoint.

    Returns the result and the checkpoints this run produced (for --update). With
    `recompute`, it does not stop at the first mismatch. A replay with lab switches needs
    `switch`, which puts each into the world before the step of its tick (ReplayError
    without it, or when it refuses one with ValueError).
    """
    need(not replay.switches or switch is not None,
         "the replay switches collision methods in the lab: it needs the lab to run")
    world = replay.world(broadphase)
    pending = iter(replay.switches)
    upcoming = next(pending, None)
    expected = iter(replay.checkpoints)  # in tick order, unpacked one at a time
    due = next(expected, None)
    produced = Checkpoints()
    mismatch = None

    def visit() -> bool:
        """Compare the world with the checkpoint due at its tick, if one is: go on?"""
        nonlocal mismatch, due
        if due is None or world.tick != due.tick:
            return True
        got = Checkpoint.of(world)
        produced.append(got)
        diffs = got.differences(due)
        due = next(expected, None)
        if diffs and mismatch is None:
            mismatch = f"tick {world.tick}: " + "; ".join(diffs)
            return recompute
        return True

    if visit():
        for bits in replay.actions():
            while upcoming is not None and upcoming[0] == world.tick:
                try:
                    switch(world, upcoming[1])  # type: ignore[misc]
                except ValueError as err:
                    raise ReplayError(f"lab switch at tick {upcoming[0]}: {err}") from None
                upcoming = next(pending, None)
            world.step(bits)
            if not visit():
                break
    final = produced[-1] if produced else Checkpoint.of(world)
    return CheckResult(replay.ticks, len(produced), final, mismatch), produced

