"""`invaders bench --arcade`: Arcade's collision checks against ours, on the same work.

Arcade, the Python game library, finds what a sprite touches with
`arcade.check_for_collision_with_list(sprite, sprite_list)`: the list's spatial hash gives
the sprites near it, and their hit boxes (polygons) are tested. Two tables: sprite groups,
and storms (section 4's, 1,000 and 10,000 bodies under the game's rules: ours with each
broad phase against `references.ArcadeScene`, a sprite list a kind given the same box
queries pymunk is given there, frame by frame in turns).

1. The groups are section 5's (bench_sprites.py): fields of boxes 4 to 24 px a side, as
dense at every size. Arcade's sprites are solid boxes where the pygame sprites' rects are
(a solid box's hit box is its box: boxes that only touch do not collide, as with pygame's
rects), so the work is `groupcollide` with `collide_rect`, and the answers are compared
before and after the rounds (a row whose answers differ is not counted as met). Arcade
gets its fastest set-up for these scenes: the second group in a list with a spatial hash,
moving scenes included (at 1,000 a side, moving, a frame took 26 ms with the hash and its
upkeep, 182 ms with a list without one), its cells 32 px, as our grid's (as fast as its
default 128 or faster at every size: 16% at 1,000 a side, still; scripts, in turn).

A frame is a check of every sprite of the first group (Arcade's) or one `groupcollide`
(ours); in a moving scene every sprite first takes a step of up to 3 px, back and forth,
each side moving its own sprites by the same steps. Arcade's hash is brought up to date as
its sprites move, so the moves are timed on both sides. The two take turns as in section
5: enough frames of each to last about 10 ms a round, the order reversed from one round
to the next; medians over the rounds with their spread, ratios per round.

2. The storms are section 4's, timed as there (the first frame untimed; Arcade's sprites
made before it). Ours tests pixels and sweeps where the rules ask; Arcade boxes only, a
lower bar.
"""

from __future__ import annotations

import random
import statistics
import time
from collections.abc import Callable
from typing import Any

import pygame

from invaders.engine import collide
from invaders.lab.bench import BIG_SIZES, Goals, storm_rounds
from invaders.lab.bench_sprites import ROUND_SECONDS, SIZES, groups
from invaders.lab.references import ARCADE_CELL, ArcadeScene, arcade_box
from invaders.lab.timing import no_gc

Answers = dict[pygame.sprite.Sprite, set[pygame.sprite.Sprite]]


class Walk:
    """Every sprite a step of up to 3 px each way a frame, back and forth so the field
    keeps its density; each side walks its own sprites with a walk of the same seed."""

    def __init__(self, count: int, seed: int = 2) -> None:
        rng = random.Random(seed)
        self.forth = [(rng.randint(-3, 3), rng.randint(-3, 3)) for _ in range(count)]
        self.back = [(-dx, -dy) for dx, dy in self.forth]
        self.frames = 0

    def steps(self) -> list[tuple[int, int]]:
        """This frame's steps, a sprite each."""
        self.frames += 1
        return self.forth if self.frames % 2 else self.back


class ArcadeField:
    """Arcade's twins of two pygame groups: a solid box where each sprite's rect is, the
    second group's in a sprite list with a spatial hash (lazy: no OpenGL until drawn,
    which is never here)."""

    def __init__(self, group_a: pygame.sprite.Group, group_b: pygame.sprite.Group) -> None:
        import arcade

        self._check = arcade.check_for_collision_with_list
        self.firsts = [(sprite, arcade_box(arcade, *sprite.rect)) for sprite in group_a]
        self.seconds: Any = arcade.SpriteList(use_spatial_hash=True, lazy=True,
                                              spatial_hash_cell_size=ARCADE_CELL)
        self._pygame: dict[Any, pygame.sprite.Sprite] = {}
        for sprite in group_b:
            twin = arcade_box(arcade, *sprite.rect)
            self.seconds.append(twin)
            self._pygame[twin] = sprite
        # Every twin, in the order of the pygame sprites [*group_a, *group_b].
        self.twins = [twin for _, twin in self.firsts] + list(self.seconds)

    def collide(self) -> list[list[Any]]:
        """Each first sprite's hits among the second list: a frame's work."""
        check, seconds = self._check, self.seconds
        return [check(twin, seconds) for _, twin in self.firsts]

    def answers(self) -> Answers:
        """The hits as pygame sprites, each first one with any to the set of them."""
        return {sprite: {self._pygame[hit] for hit in hits}
                for (sprite, _), hits in zip(self.firsts, self.collide(), strict=True) if hits}


def our_answers(group_a: pygame.sprite.Group, group_b: pygame.sprite.Group) -> Answers:
    """`groupcollide` with `collide_rect` (ours), each first sprite with any to its set."""
    found = collide.groupcollide(group_a, group_b, False, False, pygame.sprite.collide_rect)
    return {sprite: set(hits) for sprite, hits in found.items()}


def arcade_frame(field: ArcadeField, walk: Walk | None) -> Callable[[], object]:
    """Arcade's frame: its twins moved by the walk's steps (if moving), then checked."""
    if walk is None:
        return field.collide

    def frame() -> object:
        for twin, (dx, dy) in zip(field.twins, walk.steps(), strict=True):
            x, y = twin.position
            twin.position = (x + dx, y + dy)
        return field.collide()

    return frame


def our_frame(group_a: pygame.sprite.Group, group_b: pygame.sprite.Group,
              walk: Walk | None) -> Callable[[], object]:
    """Our frame: the sprites moved by the walk's steps (if moving), then collided."""
    sprites = [*group_a, *group_b]
    rect = pygame.sprite.collide_rect

    def frame() -> object:
        if walk is not None:
            for sprite, (dx, dy) in zip(sprites, walk.steps(), strict=True):
                sprite.rect.move_ip(dx, dy)
        return collide.groupcollide(group_a, group_b, False, False, rect)

    return frame


def _seconds(frame: Callable[[], object], times: int) -> float:
    start = time.perf_counter()
    for _ in range(times):
        frame()
    return (time.perf_counter() - start) / times


def _row(n: int, motion: str, rounds: int) -> tuple[list[float], bool]:
    """Both sides' frames timed by turns on one scene: the per-round ratios (Arcade's time
    over ours), with the row printed, and whether the answers were the same before and
    after the rounds (both sides having taken as many steps)."""
    group_a, group_b = groups(n)
    field = ArcadeField(group_a, group_b)
    same = field.answers() == our_answers(group_a, group_b)
    moving = motion == "moving"
    count = len(group_a) + len(group_b)
    frames = {"arcade": arcade_frame(field, Walk(count) if moving else None),
              "ours": our_frame(group_a, group_b, Walk(count) if moving else None)}
    once = {who: _seconds(frame, 1) for who, frame in frames.items()}
    times = max(1, int(ROUND_SECONDS / max(once["arcade"], 1e-7)))
    spent: dict[str, list[float]] = {"arcade": [], "ours": []}
    with no_gc():
        for index in range(rounds):
            for who in ("arcade", "ours") if index % 2 == 0 else ("ours", "arcade"):
                spent[who].append(_seconds(frames[who], times))
    same = same and field.answers() == our_answers(group_a, group_b)
    ratios = [a / b for a, b in zip(spent["arcade"], spent["ours"], strict=True)]
    print(f"   {n:>5} a side  {motion:<6} arcade {statistics.median(spent['arcade']) * 1e6:>9.1f}"
          f" us  ours {statistics.median(spent['ours']) * 1e6:>8.1f} us  "
          f"{statistics.median(ratios):>6.2f}x ({min(ratios):.2f}..{max(ratios):.2f})"
          + ("" if same else "   WARNING: different answers"))
    return ratios, same


def arcade_table(rounds: int) -> int:
    """Print both tables and their goals; 1 if any missed, else 0."""
    import arcade

    print(f"invaders bench --arcade ({rounds} interleaved rounds): Arcade "
          f"{arcade.version.VERSION}'s check_for_collision_with_list (spatial hashes of "
          f"{ARCADE_CELL}-px cells, box hit boxes) against ours: median (lowest..highest "
          "round)")
    goal = Goals(rounds)
    sprite_rows(rounds, goal)
    storm_rows(rounds, goal)
    return 1 if goal.missed else 0


def sprite_rows(rounds: int, goal: Goals) -> None:
    """Section 5's boxes, a frame's time: the rows and their goal, ours faster than Arcade
    in every row with the same answers."""
    print("1. sprite groups: ours (invaders.engine.collide.groupcollide, collide_rect), the "
          "same boxes")
    medians, all_same = {}, True
    for n in SIZES:
        for motion in ("still", "moving"):
            ratios, same = _row(n, motion, rounds)
            medians[f"{n} a side, {motion}"] = statistics.median(ratios)
            all_same = all_same and same
    slowest = min(medians, key=medians.__getitem__)
    goal("ours faster than Arcade at every size, still and moving, with the same answers",
         [medians[slowest]], 1.0, all_same,
         detail=f"the closest row: {slowest}, {medians[slowest]:.2f}x")


def storm_rows(rounds: int, goal: Goals) -> None:
    """Section 4's storms, detection per tick in steady state: ours (each broad phase)
    against Arcade's hashes given the same work (`references.ArcadeScene`), frame by frame
    in turns; the goal, ours' automatic choice faster at every size."""
    print("2. storms (no response, so overlaps persist), detection per tick after the first "
          "frame: ours (the game's rules, masks and swept tests where they ask) against a "
          "sprite list a kind, one check a probe (the rules' and zones' probes only)")
    for n in BIG_SIZES:
        figures, ticks, same = storm_rounds(n, rounds, {"arcade": ArcadeScene})
        print(f"   {n:,} bodies, {ticks} ticks"
              + ("" if same else ": WARNING the broad phases found different contacts"))
        for name, label in (("auto", "ours, the automatic choice"),
                            ("arcade", "Arcade, boxes only")):
            print(f"   {label:<44}{figures.median(name):>9.2f} ms  {figures.spread(name, '.2f')}")
        ratio = figures.ratios("arcade", "auto")
        print(f"   {'ours against Arcade':<44}{statistics.median(ratio):>8.2f}x faster  "
              f"({min(ratio):.2f}..{max(ratio):.2f})")
        goal(f"ours faster than Arcade at {n:,} bodies", figures.ratios("arcade", "auto"), 1.0,
             same)
