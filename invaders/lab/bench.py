"""`invaders bench`: timings taken side by side in one run and printed as ratios.

Machines are noisy, so every figure is the best of --repeat runs, and what counts is the
ratio between methods measured in the same process moments apart, both with the cyclic
garbage collector paused (as timeit does). Never run by the tests.

1. Headless ticks per second of one autopilot game, with the grid and with brute force.
2. Detection per tick on the same recorded frames: our pipeline (as it ran in the game)
   against `pygame.sprite.groupcollide` with `collide_mask` over the same group pairs,
   with the contacts compared (contacts only a swept test can find are counted aside).
"""

from __future__ import annotations

import time
from collections.abc import Sequence

from invaders.engine.broadphase import Pair, Scene
from invaders.engine.detector import Detector, make_broadphase
from invaders.engine.stats import CollisionStats, Contact
from invaders.game.replay import Checkpoint, Replay
from invaders.game.replay import run as run_replay
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from invaders.lab.frames import Frame, play_frames
from invaders.lab.references import GAME_RULES, groupcollide_frames
from invaders.lab.runner import FrameRecorder
from invaders.lab.timing import no_gc

TPS_GOAL = 5000


class BenchFailure(Exception):
    """The bench could not measure what it set out to (one line, exit 1)."""
DETECT_GOAL = 10.0


class DetectionTimer:
    """Observes a detector: the seconds spent in its detect calls, summed."""

    def __init__(self) -> None:
        self.seconds = 0.0
        self._start = 0.0

    def before(self, scene: Scene) -> None:
        self._start = time.perf_counter()

    def after(self, scene: Scene, candidates: Sequence[Pair], contacts: Sequence[Contact],
              stats: CollisionStats) -> None:
        self.seconds += time.perf_counter() - self._start


def play_game(ticks: int, seed: int, broadphase: str, record: bool,
              recorder: list | None = None) -> tuple[float, DetectionTimer, list[Frame]]:
    """Wall seconds for a headless autopilot game, its detection timer and, if `record`,
    the frames its detector saw. If `recorder` is a list, the game's replay is appended."""
    world = World(seed=seed, broadphase=broadphase)
    timer = DetectionTimer()
    world.detector.observers.append(timer)  # first: it wraps the detection the tightest
    frames = FrameRecorder()
    if record:
        world.detector.observers.append(frames)
    pilot = Autopilot(seed)
    inputs = []
    with no_gc():
        start = time.perf_counter()
        for _ in range(ticks):
            bits = pilot.actions(world)
            world.step(bits)
            inputs.append(bits)
        seconds = time.perf_counter() - start
    if recorder is not None:
        replay = Replay(seed, world.config)
        for bits in inputs:
            replay.append(bits)
        replay.checkpoints.append(Checkpoint.of(world))
        recorder.append(replay)
    return seconds, timer, frames.frames


def replay_seconds(replay: Replay) -> float:
    """Wall seconds to run a replay headless and check its checkpoints."""
    with no_gc():
        start = time.perf_counter()
        result, _ = run_replay(replay)
        seconds = time.perf_counter() - start
    if result.mismatch is not None:
        raise BenchFailure(f"the bench's own replay did not replay: {result.mismatch}")
    return seconds


def compare(frames: list[Frame], baseline: list[set[tuple[int, int]]]) -> tuple[int, int, int]:
    """(contacts both found, contacts only a swept test found, baseline contacts we missed)."""
    both = swept_only = missed = 0
    for frame, theirs in zip(frames, baseline, strict=True):
        ours = {(c.a_id, c.b_id) for c in frame.contacts}
        both += len(ours & theirs)
        swept_only += len(ours - theirs)
        missed += len(theirs - ours)
    return both, swept_only, missed


def replay_frames(frames: list[Frame], broadphase: str) -> tuple[float, bool]:
    """Seconds our detector spends on the frames played back in a tight loop, and whether
    it found exactly the contacts it found in the game."""
    seconds, found, _ = play_frames(Detector(make_broadphase(broadphase), GAME_RULES), frames)
    return seconds, all(c == f.contacts for c, f in zip(found, frames, strict=True))


def _body_count(frames: list[Frame]) -> float:
    return sum(sum(len(v) for v in f.bodies.values()) for f in frames) / max(1, len(frames))


def bench(ticks: int = 3600, seed: int = 7, repeat: int = 3) -> int:
    print(f"invaders bench: {ticks}-tick autopilot game, seed {seed}, best of {repeat}")
    best: dict[str, float] = {}
    detect_best = float("inf")
    frames: list[Frame] = []
    replays: list[Replay] = []
    for i in range(repeat):
        for name in ("grid", "brute"):
            first_grid = name == "grid" and i == 0
            seconds, timer, recorded = play_game(ticks, seed, name, record=first_grid,
                                          recorder=replays if first_grid else None)
            best[name] = min(best.get(name, float("inf")), seconds)
            if name == "grid":
                detect_best = min(detect_best, timer.seconds)
                if recorded:
                    frames = recorded
    tps = {name: ticks / s for name, s in best.items()}
    print("1. headless game")
    print(f"   grid   {tps['grid']:>10,.0f} ticks/s")
    speedup = tps["grid"] / tps["brute"]
    print(f"   brute  {tps['brute']:>10,.0f} ticks/s   grid/brute = {speedup:.2f}x")
    replay_tps = ticks / min(replay_seconds(replays[0]) for _ in range(repeat))
    print(f"   replay {replay_tps:>10,.0f} ticks/s   (the same game from its recorded inputs, "
          f"checked; no autopilot to run)")
    missed_goals = 0
    verdict = "met" if tps["grid"] >= TPS_GOAL else "NOT met"
    missed_goals += verdict != "met"
    print(f"   goal >= {TPS_GOAL:,} ticks/s with the grid: {verdict}")

    base_best = replay_best = float("inf")
    found: list[set[tuple[int, int]]] = []
    replayed_same = True
    for _ in range(repeat):
        seconds, same = replay_frames(frames, "grid")
        replay_best = min(replay_best, seconds)
        replayed_same = replayed_same and same
        seconds, found = groupcollide_frames(frames)
        base_best = min(base_best, seconds)
    live_us = 1e6 * detect_best / len(frames)
    ours_us = 1e6 * replay_best / len(frames)
    base_us = 1e6 * base_best / len(frames)
    both, swept_only, missed = compare(frames, found)
    ratio = base_us / ours_us
    print(f"2. detection per tick on the same {len(frames)} recorded frames "
          f"({_body_count(frames):.0f} bodies a frame on average)")
    print(f"   ours, frames played back (grid, mask-exact, swept) {ours_us:>8.2f} us"
          f"   (in the live game: {live_us:.2f} us)")
    print(f"   groupcollide + collide_mask, frames played back    {base_us:>8.2f} us   "
          f"ours is {ratio:.1f}x faster")
    if not replayed_same:
        print("   WARNING: played back, our detector found other contacts than in the game")
    print(f"   contacts: {both} found by both, {swept_only} only by our swept tests, "
          f"{missed} found by groupcollide alone")
    verdict = "met" if ratio >= DETECT_GOAL and missed == 0 and replayed_same else "NOT met"
    missed_goals += verdict != "met"
    print(f"   goal >= {DETECT_GOAL:.0f}x faster with the same contacts: {verdict}")
    return 1 if missed_goals else 0
