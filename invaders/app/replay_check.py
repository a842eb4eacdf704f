"""`invaders replay PATH...`: check replays headless, or rewrite their checkpoints."""

from __future__ import annotations

import sys
import time

from invaders.app.recording import save_replay
from invaders.game.replay import ReplayError, load, replay_paths, run


def check_all(args: list[str], update: bool = False, broadphase: str = "grid") -> int:
    """Exit code: 0 all passed, 1 some checkpoint differed, 2 some input was unusable."""
    try:
        paths = replay_paths(args)
    except ReplayError as err:
        print(f"invaders: error: {err}", file=sys.stderr)
        return 2
    worst = 0
    changed = 0
    for path in paths:
        try:
            replay = load(path)
        except ReplayError as err:
            print(f"invaders: error: {path}: {err}", file=sys.stderr)
            worst = 2
            continue
        start = time.perf_counter()
        result, produced = run(replay, broadphase, recompute=update)
        seconds = time.perf_counter() - start
        rate = f"{replay.ticks / seconds:,.0f} ticks/s" if seconds > 0 else ""
        if update:
            if result.mismatch is not None:
                replay.checkpoints = produced
                save_replay(path, replay)
                changed += 1
                print(f"updated {path}: {result.mismatch}")
            continue
        if result.mismatch is None:
            final = result.final
            print(f"ok {path}: {replay.ticks} ticks, {result.checkpoints} checkpoints, "
                  f"score {final.score}, wave {final.wave}, ships {final.ships} ({rate})")
        else:
            print(f"FAIL {path}: first difference at {result.mismatch}")
            worst = max(worst, 1)
    if update:
        print(f"{changed} of {len(paths)} replay files changed")
    return worst

