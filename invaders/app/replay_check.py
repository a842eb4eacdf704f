"""`invaders replay PATH...`: check replays headless, or rewrite their checkpoints."""

from __future__ import annotations

import time
from pathlib import Path

from invaders.app.outputs import REPLAY_SUFFIXES, OutputError, check_output, writing
from invaders.app.processing import working_on
from invaders.app.recording import save_replay
from invaders.engine.adaptive import DEFAULT_BROADPHASE
from invaders.game.replay import Replay, ReplayError, load, replay_paths, run
from invaders.lab.live import Choice, at_speed, replay_switch
from invaders.quiet import say

UPDATED = -1


def check_all(args: list[str], update: bool = False, broadphase: str = DEFAULT_BROADPHASE) -> int:
    """Exit code: 0 all passed, 1 some checkpoint differed, 2 some input was unusable (a
    path that names no replay is said, and the others are checked all the same)."""
    worst, changed, paths = 0, 0, []
    for arg in args:
        try:
            paths += replay_paths(arg)
        except ReplayError as err:
            say(f"invaders: error: {err}")
            worst = 2
    for path in paths:
        try:
            replay = load(path)
            check_switches(replay)
            if update:
                check_output(str(path), "replay", REPLAY_SUFFIXES)
        except (ReplayError, OutputError) as err:
            say(f"invaders: error: {path}: {err}")
            worst = 2
            continue
        try:
            with working_on(path):
                outcome = _check(path, replay, broadphase, update)
        except OutputError as err:  # (a full disk: the others are still checked)
            say(f"invaders: error: {err}")
            worst = 2
            continue
        if outcome == UPDATED:
            changed += 1
        else:
            worst = max(worst, outcome)
    if update:
        print(f"{changed} of {len(paths)} replay files changed")
    return worst


def check_switches(replay: Replay) -> None:
    """ReplayError naming the first lab switch the lab cannot put into a game: a choice it
    does not know, or a speed the config cannot take (checked before any tick runs)."""
    for tick, data in replay.switches:
        try:
            at_speed(replay.config, Choice.from_dict(data).speed)
        except ValueError as err:
            raise ReplayError(f"lab switch at tick {tick}: {err}") from None


def _check(path: Path, replay: Replay, broadphase: str, update: bool) -> int:
    """Run one replay: 0 it passed (or needed no update), 1 it differed, UPDATED."""
    start = time.perf_counter()
    result, produced = run(replay, broadphase, recompute=update,
                           switch=replay_switch(replay.config))
    seconds = time.perf_counter() - start
    if update:
        if result.mismatch is None:
            return 0
        replay.checkpoints = produced
        with writing(path, "replay"):
            save_replay(path, replay)
        print(f"updated {path}: {result.mismatch}")
        return UPDATED
    if result.mismatch is not None:
        print(f"FAIL {path}: first difference at {result.mismatch}")
        return 1
    final = result.final
    rate = f"{replay.ticks / seconds:,.0f} ticks/s" if seconds > 0 else ""
    print(f"ok {path}: {replay.ticks} ticks, {result.checkpoints} checkpoints, "
          f"score {final.score}, wave {final.wave}, ships {final.ships} ({rate})")
    return 0
