"""`invaders bench`: medians over interleaved rounds, with their spread, as ratios taken in one
run. Never run by the tests.

Machines are noisy, so no figure is a best-of: each round runs every contender once, the
order reversed from one round to the next, with the cyclic garbage collector paused (as
timeit does); each figure is the median over the rounds with the lowest and highest round
beside it, each ratio the median of the per-round ratios, and each goal says how many rounds
missed it. The exit code is 1 when a median misses a goal.

1. Headless ticks per second of one autopilot game, with the default broad phase (`auto`,
   the cell rects at game scale), with the grid and with brute force, and of the same game
   replayed from its recorded inputs (checked).
2. Detection per tick on the same recorded frames: ours (the default) played back and
   inside the running game, the grid played back, and `pygame.sprite.groupcollide` over the
   same group pairs as a naive user writes it (`collide_mask` on every pair) and as a
   careful one does (rects first, then `collide_mask` on the hits), with the contacts
   compared. Those played back take turns a second of game (60 frames) at a time, so a
   slow spell falls on all of them.
3. With `ale`: the Arcade Learning Environment's emulated Space Invaders, frames per second
   on a fixed input cycle, against our autopilot game, its replay, and a bare step loop on
   the same input cycle.
4. With `big`: storms of 1,000 and 10,000 bodies in steady state, ours with each broad
   phase and pymunk's spatial hash. A round there takes a fraction of a second a
   contender, about as long as a busy machine's slow spells, so the contenders take turns
   frame by frame (the order alternating), and a slow spell falls on all of them alike.
5. pygame's `groupcollide` against ours (`invaders.engine.collide`), group sizes from 1
   to 1,000 a side, with no predicate, `collide_rect`, `collide_mask` and `collide_circle`.
"""

from __future__ import annotations

import os
import random
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any

from invaders.engine.adaptive import DEFAULT_BROADPHASE, make_broadphase
from invaders.engine.broadphase import Pair, Scene
from invaders.engine.detector import Detector
from invaders.engine.stats import CollisionStats, Contact
from invaders.game.actions import Action
from invaders.game.replay import Checkpoint, Replay
from invaders.game.replay import run as run_replay
from invaders.game.world import Phase, World
from invaders.lab.autopilot import Autopilot
from invaders.lab.frames import Frame, FrameScene
from invaders.lab.references import (
    GAME_RULES,
    careful_collide,
    naive_collide,
    pairs_of,
    prepare,
)
from invaders.lab.runner import FrameRecorder
from invaders.lab.timing import no_gc

TPS_GOAL = 5000
STARTUP_GOAL = 1.5  # `invaders run --ticks 1` against `python -c "import pygame"`, at most
NAIVE_GOAL = 20.0  # detection, times faster than groupcollide + collide_mask
ALE_GOALS = {"autopilot": 3.0, "replay": 5.0, "bare": 8.0}  # times ALE's frames per second


class BenchFailure(Exception):
    """The bench could not measure what it set out to (one line, exit 1)."""


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


def autopilot_share(ticks: int, seed: int) -> float:
    """The autopilot's part of an autopilot game's time (its calls timed apart)."""
    world = World(seed=seed)
    pilot = Autopilot(seed)
    clock = time.perf_counter
    thinking = stepping = 0.0
    with no_gc():
        for _ in range(ticks):
            t0 = clock()
            bits = pilot.actions(world)
            t1 = clock()
            world.step(bits)
            t2 = clock()
            thinking += t1 - t0
            stepping += t2 - t1
    return thinking / (thinking + stepping)


def startup_seconds(command: list[str]) -> float:
    """Wall seconds for a fresh interpreter to run `command` (the program's own bytecode
    cached where the environment allows it)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    start = time.perf_counter()
    subprocess.run([sys.executable, *command], env=env, capture_output=True, check=True)
    return time.perf_counter() - start


PYGAME_ONLY = ["-c", "import pygame"]
ONE_TICK = ["-m", "invaders.app.cli", "run", "--ticks", "1"]


def bare_seconds(ticks: int, seed: int) -> float:
    """Wall seconds for a bare step loop: the world on the fixed input cycle ALE gets too,
    a new game started whenever one ends (as ALE is reset)."""
    from invaders.lab.ale import CYCLE

    world = World(seed=seed)
    n = len(CYCLE)
    step = world.step
    start_bit = int(Action.START)
    over = Phase.GAME_OVER  # bound once, as ALE's loop binds its calls
    with no_gc():
        start = time.perf_counter()
        for i in range(ticks):
            bits = CYCLE[i % n]
            if world.phase is over:
                bits |= start_bit
            step(bits)
        return time.perf_counter() - start


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


DETECTION_BLOCK = 60  # frames each contender detects in its turn: a second of game


def detection_round(frames: list[Frame], prepared, index: int
                    ) -> tuple[dict[str, float], list[list[Contact]], dict[str, list]]:
    """Ours (the default broad phase, every frame timed), the grid, the naive and the
    careful groupcollide on the same frames, taking turns a block of frames at a time (the
    order alternating, and turned round on odd rounds), so a busy machine's slow spell falls
    on all alike. Seconds of each; our contacts per frame; the id pairs each reference found
    per frame."""
    players = {"ours": FramePlayer(DEFAULT_BROADPHASE, frames, GAME_RULES, warm=False),
               "grid": FramePlayer("grid", frames, GAME_RULES, warm=False)}
    collide = {"naive": naive_collide, "careful": careful_collide}
    seconds = {"ours": 0.0, "grid": 0.0, "naive": 0.0, "careful": 0.0}
    found: dict[str, list] = {"naive": [], "careful": []}
    clock = time.perf_counter
    with no_gc():
        for turn, start in enumerate(range(0, len(frames), DETECTION_BLOCK)):
            block = range(start, min(start + DETECTION_BLOCK, len(frames)))
            order = list(seconds) if (turn + index) % 2 == 0 else list(seconds)[::-1]
            for name in order:
                if name in players:
                    seconds[name] += sum(players[name].frame_seconds(i) for i in block)
                    continue
                for i in block:
                    begin = clock()
                    hits = collide[name](prepared[i])
                    seconds[name] += clock() - begin
                    found[name].append(pairs_of(hits))
    return seconds, players["ours"].found, found


def _body_count(frames: list[Frame]) -> float:
    return sum(sum(len(v) for v in f.bodies.values()) for f in frames) / max(1, len(frames))


class Rounds:
    """Per-round figures of each contender: medians and spreads."""

    def __init__(self) -> None:
        self.values: dict[str, list[float]] = {}

    def add(self, name: str, value: float) -> None:
        self.values.setdefault(name, []).append(value)

    def median(self, name: str) -> float:
        return statistics.median(self.values[name])

    def spread(self, name: str, fmt: str) -> str:
        values = self.values[name]
        return f"({format(min(values), fmt)}..{format(max(values), fmt)})"

    def ratios(self, top: str, bottom: str) -> list[float]:
        return [a / b for a, b in zip(self.values[top], self.values[bottom], strict=True)]


BIG_SIZES = (1000, 10000)
BIG_TICKS = {1000: 40, 10000: 12}
BIG_GOALS = {"numpy/pymunk": 3.0, "auto/grid at 1000": 0.95}
OURS_BIG = ("grid", "numpy", "auto")


class FramePlayer:
    """Our detector on recorded frames, one frame a call. If `warm`, the first frame is
    played on creation, untimed (a broad phase builds its state there, as pymunk's bodies
    are made before timing)."""

    def __init__(self, broadphase: str, frames: list[Frame], rules, warm: bool = True) -> None:
        self.detector = Detector(make_broadphase(broadphase), rules)
        self.scene = FrameScene()
        self.frames = frames
        self.found: list[list[Contact]] = []
        if warm:
            self.scene.load(frames[0])
            self.detector.detect(self.scene.store)

    def frame_seconds(self, index: int) -> float:
        """Time the detection of frame `index` (frames in order); keep its contacts."""
        self.scene.load(self.frames[index])
        start = time.perf_counter()
        contacts, _ = self.detector.detect(self.scene.store)
        seconds = time.perf_counter() - start
        self.found.append(contacts)
        return seconds


def big_scenes(rounds: int, goal) -> None:
    """Section 4: storms of 1,000 and 10,000 bodies, detection per tick in steady state:
    the grid, the numpy broad phase, the automatic choice and pymunk's spatial hash."""
    try:
        import pymunk  # noqa: F401
        has_pymunk = True
    except ImportError:
        has_pymunk = False
    print("4. big scenes: storms (no response, so overlaps persist), detection per tick "
          "after the first frame")
    from invaders.lab.references import PymunkScene

    for n in BIG_SIZES:
        figures, ticks, same = storm_rounds(n, rounds,
                                             {"pymunk": PymunkScene} if has_pymunk else {})
        print(f"   {n:,} bodies, {ticks} ticks"
              + ("" if same else ": WARNING the broad phases found different contacts"))
        _print_storm(figures)
        if n == max(BIG_SIZES):
            if has_pymunk:
                goal(f"numpy >= {BIG_GOALS['numpy/pymunk']:.0f}x faster than pymunk at {n:,}",
                     figures.ratios("pymunk", "numpy"), BIG_GOALS["numpy/pymunk"], same)
        else:
            goal(f"the automatic choice no slower than the grid at {n:,} (within 5%)",
                 figures.ratios("grid", "auto"), BIG_GOALS["auto/grid at 1000"], same)


def storm_rounds(n: int, rounds: int, references: dict[str, Callable[..., Any]]
                  ) -> tuple[Rounds, int, bool]:
    """A storm of `n` bodies detected by each of our broad phases and each reference (made
    from the frames and rules, with a `frame_seconds`), frame by frame in turns, in an
    order shuffled each frame (seeded): the milliseconds a tick of each round, the ticks
    timed, and whether our broad phases found the same contacts. (An order only reversed
    each frame runs the contenders at its ends twice in a row, caches warm, and the one
    beside a cache-hungry one always after it: the automatic choice, which is the grid
    under 2,500 bodies compiled, timed 0.88x the grid beside pymunk and 1.01x without.)"""
    from invaders.lab.runner import SceneSpec, record, scene_rules

    spec = SceneSpec.storm(n, BIG_TICKS[n])
    frames = record(spec)
    rules = scene_rules(spec)
    figures = Rounds()
    contacts: dict[str, list] = {}
    for index in range(rounds):
        players = {name: FramePlayer(name, frames, rules) for name in OURS_BIG}
        for name, make in references.items():
            players[name] = make(frames, rules)
        order, shuffle = list(players), random.Random(index).shuffle
        seconds = dict.fromkeys(players, 0.0)
        with no_gc():  # the contenders take turns frame by frame
            for i in range(1, len(frames)):
                shuffle(order)
                for name in order:
                    seconds[name] += players[name].frame_seconds(i)
        for name, spent in seconds.items():
            figures.add(name, 1e3 * spent / (len(frames) - 1))
        for name in OURS_BIG:
            contacts[name] = players[name].found
    same = contacts["grid"] == contacts["numpy"] == contacts["auto"]
    return figures, len(frames) - 1, same


def _print_storm(figures: Rounds) -> None:
    """Each contender's milliseconds a tick against the grid's, and numpy's against
    pymunk's."""
    for name, label in (("grid", "grid, 32 px"), ("numpy", "numpy broad phase"),
                        ("auto", "automatic choice"),
                        ("pymunk", "pymunk spatial hash, boxes only")):
        if name not in figures.values:
            continue
        ratio = figures.ratios("grid", name)
        print(f"   {label:<44}{figures.median(name):>9.2f} ms  "
              f"{figures.spread(name, '.2f')}   grid/this {statistics.median(ratio):.2f}x")
    if "pymunk" in figures.values:
        ratio = figures.ratios("pymunk", "numpy")
        print(f"   {'numpy against pymunk':<44}{statistics.median(ratio):>8.2f}x faster  "
              f"({min(ratio):.2f}..{max(ratio):.2f})")


class Goals:
    """The goals printed so far and how many missed: a goal is met when the median of its
    rounds reaches its target (and its `extra` condition holds)."""

    def __init__(self, rounds: int) -> None:
        self.rounds = rounds
        self.missed = 0

    def __call__(self, text: str, per_round: list[float], target: float, extra: bool = True,
                 at_most: bool = False, detail: str | None = None) -> None:
        """A goal of at least `target` (or, `at_most`, no more than it); `detail` replaces
        the count of rounds that missed it."""
        sign = -1 if at_most else 1
        missed = sum(sign * value < sign * target for value in per_round)
        met = sign * statistics.median(per_round) >= sign * target and extra
        self.missed += not met
        said = detail if detail is not None else f"{missed} of {self.rounds} rounds missed"
        print(f"   goal {text}: {'met' if met else 'NOT met'} ({said})")


class GameRounds:
    """Sections 1 to 3's figures: every contender once a round, the order reversed from
    one round to the next; the contacts each detection found, and whether ours played back
    found the game's."""

    def __init__(self, ticks: int, seed: int, ale: bool) -> None:
        self.ticks, self.seed = ticks, seed
        self.replays: list[Replay] = []
        _, _, self.frames = play_game(ticks, seed, DEFAULT_BROADPHASE, record=True,
                                      recorder=self.replays)
        self.prepared = prepare(self.frames)
        self.figures = Rounds()
        self.found: dict[str, list[set[tuple[int, int]]]] = {}
        self.same_contacts = True
        self.contenders = [lambda: self.game(DEFAULT_BROADPHASE), lambda: self.game("grid"),
                           lambda: self.game("brute"), self.replay, self.share,
                           self.startup, self.detection]
        if ale:
            from invaders.lab.ale import ale_seconds, emulator

            emulated = emulator(seed)
            self.contenders.append(lambda: self.figures.add(
                "bare ticks/s", ticks / bare_seconds(ticks, seed)))
            self.contenders.append(lambda: self.figures.add(
                "ale frames/s", ticks / ale_seconds(emulated, ticks)))

    def run(self, rounds: int) -> Rounds:
        for index in range(rounds):
            for contender in self.contenders if index % 2 == 0 else self.contenders[::-1]:
                contender()
        return self.figures

    def game(self, name: str) -> None:
        seconds, timer, _ = play_game(self.ticks, self.seed, name, record=False)
        self.figures.add(f"{name} ticks/s", self.ticks / seconds)
        if name == DEFAULT_BROADPHASE:
            self.figures.add("live us", 1e6 * timer.seconds / self.ticks)

    def share(self) -> None:
        self.figures.add("autopilot share", autopilot_share(self.ticks, self.seed))

    def startup(self) -> None:
        self.figures.add("import pygame s", startup_seconds(PYGAME_ONLY))
        self.figures.add("run one tick s", startup_seconds(ONE_TICK))

    def replay(self) -> None:
        self.figures.add("replay ticks/s", self.ticks / replay_seconds(self.replays[0]))

    def detection(self) -> None:
        frames = self.frames
        seconds, ours, theirs = detection_round(
            frames, self.prepared, len(self.figures.values.get("ours us", ())))
        self.same_contacts = self.same_contacts and ours == [f.contacts for f in frames]
        for name, spent in seconds.items():
            self.figures.add(f"{name} us", 1e6 * spent / len(frames))
        self.found.update(theirs)


def _line(figures: Rounds, label: str, name: str, unit: str, fmt: str) -> str:
    """A contender's median and the spread of its rounds."""
    return (f"   {label:<44}{format(figures.median(name), fmt):>9} {unit}  "
            f"{figures.spread(name, fmt)}")


OURS = f"{DEFAULT_BROADPHASE} ticks/s"


def print_game(figures: Rounds, goal: Goals) -> None:
    """Section 1: the headless game with each broad phase, its replay and its start-up."""
    print("1. headless game")
    print(_line(figures, f"{DEFAULT_BROADPHASE} (the default broad phase)", OURS, "ticks/s",
                ",.0f"))
    for name, label in (("grid", "grid"), ("brute", "brute force")):
        ratio = figures.ratios(OURS, f"{name} ticks/s")
        print(_line(figures, label, f"{name} ticks/s", "ticks/s", ",.0f")
              + f"   {DEFAULT_BROADPHASE}/this {statistics.median(ratio):.2f}x")
    print(_line(figures, "replay (its recorded inputs, checked)", "replay ticks/s", "ticks/s",
                ",.0f"))
    print(_line(figures, "the autopilot's part of the game", "autopilot share", "", ".1%"))
    startup_ratio = figures.ratios("run one tick s", "import pygame s")
    print(_line(figures, "start-up: invaders run --ticks 1", "run one tick s", "s", ".3f")
          + f"   {statistics.median(startup_ratio):.2f}x import pygame "
            f"({figures.median('import pygame s'):.3f} s)")
    goal(f"{DEFAULT_BROADPHASE} >= {TPS_GOAL:,} ticks/s", figures.values[OURS], TPS_GOAL)
    goal(f"start-up <= {STARTUP_GOAL}x python -c 'import pygame'", startup_ratio, STARTUP_GOAL,
         at_most=True)


def print_detection(played: GameRounds, goal: Goals) -> None:
    """Section 2: detection per tick, ours against the grid and groupcollide's two ways."""
    figures, frames = played.figures, played.frames
    print(f"2. detection per tick on the same {len(frames)} recorded frames "
          f"({_body_count(frames):.0f} bodies a frame on average)")
    print(_line(figures, f"ours ({DEFAULT_BROADPHASE}), frames played back", "ours us", "us",
                ".2f"))
    print(_line(figures, f"ours ({DEFAULT_BROADPHASE}), inside the running game", "live us",
                "us", ".2f"))
    for name, label in (("grid", "the grid, frames played back"),
                        ("naive", "groupcollide + collide_mask"),
                        ("careful", "groupcollide rects, then collide_mask")):
        ratio = figures.ratios(f"{name} us", "ours us")
        print(_line(figures, label, f"{name} us", "us", ".2f")
              + f"   {statistics.median(ratio):.1f}x ours ({min(ratio):.1f}..{max(ratio):.1f})")
    both, swept_only, missed = compare(frames, played.found["naive"])
    careful_same = played.found["careful"] == played.found["naive"]
    print(f"   contacts: {both} found by both, {swept_only} only by our swept tests, "
          f"{missed} found by groupcollide alone"
          + ("" if careful_same else "; the careful version found others than the naive"))
    if not played.same_contacts:
        print("   WARNING: played back, our detector found other contacts than in the game")
    goal(f"ours >= {NAIVE_GOAL:.0f}x faster than groupcollide + collide_mask, same contacts",
         figures.ratios("naive us", "ours us"), NAIVE_GOAL,
         missed == 0 and played.same_contacts)


def print_ale(figures: Rounds, ticks: int, goal: Goals) -> None:
    """Section 3: ALE's emulated cartridge against our game, its replay and a bare loop."""
    print(f"3. against the Arcade Learning Environment's Space Invaders (the Atari 2600 "
          f"cartridge emulated, one frame a step, {ticks} frames a round)")
    print(_line(figures, "ALE, fixed input cycle", "ale frames/s", "frames/s", ",.0f"))
    keys = {"autopilot": OURS, "replay": "replay ticks/s", "bare": "bare ticks/s"}
    for name, label in (("autopilot", "our autopilot game"),
                        ("replay", "our replay of it, checked"),
                        ("bare", "our bare step loop, same input cycle")):
        ratio = figures.ratios(keys[name], "ale frames/s")
        print(_line(figures, label, keys[name], "ticks/s", ",.0f")
              + f"   {statistics.median(ratio):.1f}x ALE ({min(ratio):.1f}..{max(ratio):.1f})")
    for name, target in ALE_GOALS.items():
        goal(f"{name} >= {target:.0f}x ALE's frames per second",
             figures.ratios(keys[name], "ale frames/s"), target)


def bench(ticks: int = 3600, seed: int = 7, rounds: int = 10, ale: bool = False,
          big: bool = False, largest: int | None = None) -> int:
    """The sections asked for, in order; 1 if any goal's median missed it, else 0."""
    played = GameRounds(ticks, seed, ale)
    figures = played.run(rounds)
    print(f"invaders bench: {ticks}-tick autopilot game, seed {seed}, {rounds} interleaved "
          "rounds: median (lowest..highest round)")
    goal = Goals(rounds)
    print_game(figures, goal)
    print_detection(played, goal)
    if ale:
        print_ale(figures, ticks, goal)
    if big:
        big_scenes(rounds, goal)
    from invaders.lab.bench_sprites import collider_table, sprite_table

    sprite_table(rounds, goal, big, largest)
    collider_table(rounds, goal, largest)
    return 1 if goal.missed else 0
