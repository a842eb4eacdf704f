"""The lab, live: another collision method put into a running world, and scored in shadow.

A `Choice` is what a person picks in the lab: broad phase and cell, quick test, thorough
test, motion, temporal sampling and projectile speed. `install` puts it into a world: the
projectiles' speeds into its config, a `LabDetector` where its detector stands. That
detector detects with the chosen method (every k-th tick if sampled, the motion of the k
ticks folded into one step, as `frames.sampled` does for the study) and, with a shadow,
asks the oracle for every tick's true contacts on the very states the world sees and scores
the method's by episodes (`score.py`), keeping each error with the pixel where it happened.
The game goes on with the method's answer. Time is measured only with a clock the caller
passes: the simulation never reads one.
"""

from __future__ import annotations

import dataclasses
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from statistics import median
from typing import Any

from invaders.engine.adaptive import make_broadphase
from invaders.engine.detector import Detector
from invaders.engine.grid import DEFAULT_CELL
from invaders.engine.response import first_contacts
from invaders.engine.rules import RuleTable
from invaders.engine.stats import CollisionStats, Contact
from invaders.engine.store import BodyStore
from invaders.game.config import GameConfig
from invaders.game.world import World
from invaders.lab.choices import (
    BROADS,
    CELLS,
    MOTIONS,
    MULTIPLIERS,
    QUICK_TESTS,
    SAMPLINGS,
    THOROUGH_TESTS,
)
from invaders.lab.frames import FrameScene, Places, folded, snapshot
from invaders.lab.matrix import Method, detector_for
from invaders.lab.oracle import true_contacts
from invaders.lab.score import Judged, Score, Scorer

OPTIONS: dict[str, tuple] = {
    "broad": BROADS,
    "cell": CELLS,
    "quick": QUICK_TESTS,
    "thorough": THOROUGH_TESTS,
    "motion": MOTIONS,
    "sampling": SAMPLINGS,
    "speed": MULTIPLIERS,
}
MAX_CELL = 1024
MARK_TICKS = 60  # a mark fades over a second of game time
SECOND = 60  # ticks in the rolling window of the timings


@dataclass(frozen=True)
class Choice:
    """One way to detect collisions in the game, and how fast its projectiles fly."""

    broad: str = BROADS[0]
    cell: int = DEFAULT_CELL
    quick: str = QUICK_TESTS[0]
    thorough: str = THOROUGH_TESTS[0]
    motion: str = MOTIONS[0]
    sampling: int = SAMPLINGS[0]
    speed: int = MULTIPLIERS[0]

    @property
    def method(self) -> Method:
        return Method(self.broad, self.cell, self.quick, self.thorough, self.motion,
                      self.sampling)

    @property
    def is_default(self) -> bool:
        """The game's own method (any broad phase gives the same contacts)."""
        return self.method.is_default

    @property
    def label(self) -> str:
        """The narrow-phase method and speed, short: rect/mask/discrete every 2 at 8x."""
        return (f"{self.quick}/{self.thorough}/{self.motion}"
                + (f" every {self.sampling}" if self.sampling > 1 else "")
                + (f" at {self.speed}x" if self.speed > 1 else ""))

    def cycled(self, name: str, step: int = 1) -> Choice:
        """The next (or, with -1, previous) option of one choice; sizes (cell, speed) stop
        at their ends (a cell between two options goes to the next one), the rest wrap."""
        options = OPTIONS[name]
        value = getattr(self, name)
        if name not in ("cell", "speed"):
            new = options[(options.index(value) + step) % len(options)]
        else:
            beyond = [o for o in options if (o - value) * step > 0]
            new = (min(beyond, key=lambda o: abs(o - value)) if beyond else value)
        return dataclasses.replace(self, **{name: new})

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: Any) -> Choice:
        """A Choice from a recording, or ValueError naming the first problem."""
        if not isinstance(data, Mapping):
            raise ValueError("a lab choice must be an object")
        unknown = sorted(set(data) - set(OPTIONS))
        if unknown:
            raise ValueError(f"lab choice {unknown[0]!r} is unknown")
        for name, value in data.items():
            if name == "cell" and type(value) is int and 1 <= value <= MAX_CELL:
                continue  # any grid cell a run may ask for, not only those the lab steps
            if type(value) is not type(OPTIONS[name][0]) or value not in OPTIONS[name]:
                raise ValueError(f"lab choice {name} must be one of "
                                 f"{', '.join(map(str, OPTIONS[name]))}, not {value!r}")
        return cls(**data)


DEFAULT_CHOICE = Choice()


def at_speed(config: GameConfig, multiplier: int) -> GameConfig:
    """The config with the shot and the bombs moving `multiplier` times as far a tick."""
    if multiplier == 1:
        return config
    s = config.speeds
    return dataclasses.replace(config, speeds=dataclasses.replace(
        s, shot=s.shot * multiplier, bomb=s.bomb * multiplier,
        bomb_fast=s.bomb_fast * multiplier))


@dataclass(frozen=True)
class Mark:
    """An error the shadow found: where and on which tick it showed."""

    outcome: str  # missed, late, false
    x: int
    y: int
    tick: int


class Sampler:
    """What a detector that looks every k-th tick sees: a mirror of the world's bodies,
    each moving in one step from where it was at the previous look."""

    def __init__(self, k: int) -> None:
        self.k = k
        self.scene = FrameScene()
        self.previous: Places = {}

    def due(self, tick: int) -> bool:
        return tick % self.k == self.k - 1

    def view(self, store: BodyStore) -> BodyStore:
        look, self.previous = folded(snapshot(store), self.previous, store.tick)
        self.scene.load(look)
        return self.scene.store


class LiveShadow:
    """The oracle beside a live detector: the score since it began, and marks of errors.
    Its running score is also a report's columns (`names`, `values`)."""

    names = ("shadow_true", "shadow_on_time", "shadow_late", "shadow_missed", "shadow_false")

    def __init__(self, rules: RuleTable) -> None:
        self.rules = rules
        self.log: list[Judged] = []
        self.scorer = Scorer(self.log)
        self.points: dict[tuple[tuple[int, int], int], tuple[int, int]] = {}  # episode starts
        self.touching: set[tuple[int, int]] = set()  # pairs in contact on the last tick
        self.marks: deque[Mark] = deque()

    @property
    def score(self) -> Score:
        return self.scorer.score

    def values(self) -> tuple[int, ...]:
        s = self.scorer.score
        return s.true, s.on_time, s.late, s.missed, s.false

    def finish(self) -> Score:
        """The final score: episodes still open are judged as they stand."""
        return self.scorer.finish()

    def truth(self, store: BodyStore) -> None:
        """This tick's true contacts, from the oracle on the world's own bodies."""
        tick = store.tick
        pairs = set()
        for contact in true_contacts(store, self.rules):
            pair = (contact.a_id, contact.b_id)
            pairs.add(pair)
            if pair not in self.touching:  # an episode begins: where it should be found
                self.points[(pair, tick)] = (contact.x, contact.y)
        self.touching = pairs
        self.scorer.truth(tick, pairs)

    def reported(self, start: int, end: int, contacts: list[Contact]) -> None:
        """What the method found over ticks start+1..end; marks for what is now judged."""
        happened = first_contacts(contacts)
        false_at = {(c.a_id, c.b_id): (c.px, c.py) for c in happened}
        self.scorer.reported(start, end, ((c.a_id, c.b_id) for c in happened))
        for outcome, pair, began in self.log:
            point = (false_at[pair] if outcome == "false"
                     else self.points.pop((pair, began), None))
            if outcome != "on time" and point is not None:
                self.marks.append(Mark(outcome, *point, end))
        self.log.clear()
        while self.marks and self.marks[0].tick <= end - MARK_TICKS:
            self.marks.popleft()


class LabDetector:
    """Stands where a world's detector stands: the chosen method, its shadow, its clock."""

    def __init__(self, choice: Choice, rules: RuleTable, config: GameConfig,
                 shadow: bool = True, clock: Callable[[], float] | None = None) -> None:
        self.choice = choice
        self.inner = detector_for(choice.method, choice.speed, rules=rules, config=config)
        self.broadphase = self.inner.broadphase
        self.rules = self.inner.rules
        self.observers = self.inner.observers
        self.sampler = Sampler(choice.sampling) if choice.sampling > 1 else None
        self.shadow = LiveShadow(rules) if shadow else None
        self.clock = clock
        self.stats = CollisionStats()
        self.history: deque[CollisionStats] = deque(maxlen=SECOND)  # every tick's counters
        self.seconds: deque[float] = deque(maxlen=SECOND)  # per tick, a look spread over k
        self.reference_seconds: deque[float] = deque(maxlen=SECOND)
        self.reference: tuple[Detector, FrameScene] | None = None
        if clock is not None and not choice.is_default:
            default = detector_for(Method(), choice.speed, rules=rules, config=config)
            self.reference = default, FrameScene()

    def detect(self, store: BodyStore) -> tuple[list[Contact], CollisionStats]:
        """The chosen method's contacts (none on a tick a sampled method does not look),
        scored in shadow and timed when it was asked to be."""
        tick = store.tick
        k = self.choice.sampling
        looks = self.sampler is None or self.sampler.due(tick)
        clock = self.clock
        started = clock() if clock is not None else 0.0
        contacts: list[Contact]
        if not looks:
            contacts, stats = [], CollisionStats()
        elif self.sampler is None:
            contacts, stats = self.inner.detect(store)
        else:
            contacts, stats = self.inner.detect(self.sampler.view(store))
        if clock is not None:
            if looks:
                self.seconds.extend([(clock() - started) / k] * k)
            self._time_reference(store, clock)
        if looks:
            self.stats = stats
        self.history.append(stats)
        if self.shadow is not None:
            self.shadow.truth(store)
            if looks:
                self.shadow.reported(tick - k, tick, contacts)
        return contacts, stats

    def _time_reference(self, store: BodyStore, clock: Callable[[], float]) -> None:
        if self.reference is None:
            return
        detector, scene = self.reference
        scene.load(snapshot(store))
        started = clock()
        detector.detect(scene.store)
        self.reference_seconds.append(clock() - started)

    def counter_medians(self) -> CollisionStats:
        """Each counter's median over the last second of ticks."""
        if not self.history:
            return CollisionStats()
        return CollisionStats(*(median(column) for column in zip(*self.history, strict=True)))

    def timings(self) -> tuple[float, float, float | None]:
        """The last tick's detection time, the median over the last second (seconds), and
        that median over the default method's on the same ticks (None: this is it)."""
        if not self.seconds:
            return 0.0, 0.0, None
        mid = median(self.seconds)
        if not self.reference_seconds:
            return self.seconds[-1], mid, None
        ref = median(self.reference_seconds)
        return self.seconds[-1], mid, (mid / ref if ref else None)


def replay_switch(base: GameConfig) -> Callable[[World, dict[str, Any]], None]:
    """What a replay's lab switches mean: each a Choice put into the world (unwatched)."""
    def switch(world: World, data: dict[str, Any]) -> None:
        install(world, Choice.from_dict(data), base, shadow=False)
    return switch


def install(world: World, choice: Choice, base: GameConfig, shadow: bool = True,
            clock: Callable[[], float] | None = None) -> Detector | LabDetector:
    """Put a choice into the world from its next tick: the projectiles' speeds (over the
    `base` config) and the detector. The game's own method, unwatched, gets the game's
    own detector back, so a lab that is off costs nothing. The store stops feeding the
    detector put away (else its move buffer would only grow); the new one attaches itself
    on its first tick if it keeps state."""
    world.config = at_speed(base, choice.speed)
    world.store.detach()
    if choice.is_default and choice.speed == 1 and not shadow and clock is None:
        detector: Detector | LabDetector = Detector(
            make_broadphase(choice.broad, choice.cell), world.rules)
    else:
        detector = LabDetector(choice, world.rules, base, shadow, clock)
    world.detector = detector
    return detector
