"""Section 5 of `invaders bench`: `invaders.engine.collide.groupcollide` against pygame-ce's
own, group sizes by predicates, still, moving and on FRects, on the same sprites, taking
turns; then `GroupCollide` (the swept collider, kept from call to call as a game keeps it)
against pygame's `groupcollide` with `collide_mask`, still, moving and swept.

The scenes are square fields of sprites 4 to 24 px a side with masks (a few pixels holed),
as dense at every size (about one sprite's area in 40 x 40 px), so each size has collisions
to find. In a moving scene every sprite takes a step of up to 3 px before each call (a
step both sides are given and neither is timed on); in a `floats` one the rects are
pygame-ce's FRects, their corners and steps fractions of a pixel (sub-pixel motion).
Each round times both on the same groups, the order reversed from one round to the next,
enough calls of each to last about 10 ms; figures are medians over the rounds with their
spread, the ratio the median of the per-round ratios.
"""

from __future__ import annotations

import random
import statistics
import time
from collections.abc import Callable
from typing import Any

import pygame

from invaders.engine import collide
from invaders.engine.sprites import GroupCollide
from invaders.lab.timing import no_gc

SIZES = (1, 5, 10, 100, 1000)
MOTIONS = ("still", "moving", "floats")  # floats: FRects, moving by fractions of a pixel
BIG_SIZE = 2000  # a side, with --big: pygame takes seconds a call there
PREDICATES = (("none", None), ("collide_rect", pygame.sprite.collide_rect),
              ("collide_mask", pygame.sprite.collide_mask),
              ("collide_circle", pygame.sprite.collide_circle))
# The largest groups timed with circles: pygame's loop took 0.48 s a call at 1,000 a side
# and 1.8 s at 2,000 (once each).
LARGEST_CIRCLES = 1000
GOALS = {100: 5.0, 1000: 50.0}  # times faster than pygame with collide_mask, at least
# GroupCollide's rows: the collider kept from call to call, as a game keeps it, its sprites
# still, moving (each tested where it is) and swept (each giving a `last_rect`: tested
# along its step, a touch between the two places found too).
COLLIDER_MOTIONS = ("still", "moving", "swept")
COLLIDER_FROM = 5  # a side: from here GroupCollide's goal, faster than pygame's
ROUND_SECONDS = 0.01


class Block(pygame.sprite.Sprite):
    """A sprite with a rect (an FRect at a fraction of a pixel with `floats`) and a mask, a
    few of its pixels holed."""

    def __init__(self, rng: random.Random, span: int, floats: bool = False) -> None:
        super().__init__()
        w, h = rng.randrange(4, 25), rng.randrange(4, 25)
        x, y = rng.randrange(span), rng.randrange(span)
        self.rect: pygame.Rect | pygame.FRect = (
            pygame.FRect(x + rng.random(), y + rng.random(), w, h) if floats
            else pygame.Rect(x, y, w, h))
        self.mask = pygame.mask.Mask((w, h), fill=True)
        for _ in range(5):
            self.mask.set_at((rng.randrange(w), rng.randrange(h)), 0)


def groups(n: int, seed: int = 1, floats: bool = False
           ) -> tuple[pygame.sprite.Group, pygame.sprite.Group]:
    rng = random.Random(seed)
    span = int(40 * n ** 0.5) + 40
    return (pygame.sprite.Group(Block(rng, span, floats) for _ in range(n)),
            pygame.sprite.Group(Block(rng, span, floats) for _ in range(n)))


def _call(groupcollide: Callable, group_a: pygame.sprite.Group, group_b: pygame.sprite.Group,
          collided: Callable | None) -> Callable[[], object]:
    return lambda: groupcollide(group_a, group_b, False, False, collided)


def _steps(groups_: tuple[pygame.sprite.Group, ...], seed: int = 2, floats: bool = False,
           swept: bool = False) -> Callable[[], None]:
    """A step of each sprite, up to 3 px each way (any fraction of a pixel with `floats`),
    back and forth so the field keeps its density: the scene a game hands over frame after
    frame. `swept`: each sprite's `last_rect` is where it stood before the step."""
    sprites = [s for group in groups_ for s in group]
    rng = random.Random(seed)
    moves = [(rng.uniform(-3, 3), rng.uniform(-3, 3)) if floats
             else (rng.randint(-3, 3), rng.randint(-3, 3)) for _ in sprites]
    count = [0]

    def step() -> None:
        sign = 1 if count[0] % 2 == 0 else -1
        count[0] += 1
        for sprite, (dx, dy) in zip(sprites, moves, strict=True):
            if swept:
                sprite.last_rect = sprite.rect.copy()
            sprite.rect.move_ip(sign * dx, sign * dy)

    return step


def _seconds(call: Callable[[], object], times: int, step: Callable[[], None] | None) -> float:
    """Seconds a call, over `times` calls; with a step, the scene moves before each call
    and only the calls are timed."""
    if step is None:
        start = time.perf_counter()
        for _ in range(times):
            call()
        return (time.perf_counter() - start) / times
    spent = 0.0
    for _ in range(times):
        step()
        start = time.perf_counter()
        call()
        spent += time.perf_counter() - start
    return spent / times


def _turns(calls: dict[str, Callable[[], object]], step: Callable[[], None] | None,
           rounds: int) -> tuple[dict[str, list[float]], list[float]]:
    """pygame's call ("theirs") and ours timed by turns, the order reversed from one round
    to the next: each one's seconds a call by round, and the per-round ratios (pygame's
    time over ours)."""
    once = _seconds(calls["theirs"], 1, None)
    times = max(1, int(ROUND_SECONDS / max(once, 1e-7)))
    spent: dict[str, list[float]] = {"theirs": [], "ours": []}
    with no_gc():
        for index in range(rounds):
            for who in ("theirs", "ours") if index % 2 == 0 else ("ours", "theirs"):
                spent[who].append(_seconds(calls[who], times, step))
    return spent, [a / b for a, b in zip(spent["theirs"], spent["ours"], strict=True)]


def _print_row(n: int, motion: str, name: str, spent: dict[str, list[float]],
               ratios: list[float]) -> None:
    print(f"   {n:>5} a side  {motion:<6} {name:<14} "
          f"pygame {statistics.median(spent['theirs']) * 1e6:>10.1f} us  "
          f"ours {statistics.median(spent['ours']) * 1e6:>9.1f} us  "
          f"{statistics.median(ratios):>6.2f}x ({min(ratios):.2f}..{max(ratios):.2f})")


def _row(n: int, motion: str, name: str, collided: Callable | None, rounds: int
         ) -> list[float] | None:
    """Both sides timed by turns on one scene: the per-round ratios (pygame's time over
    ours), with the row printed; None if the answers differ."""
    floats = motion == "floats"
    group_a, group_b = groups(n, floats=floats)
    step = _steps((group_a, group_b), floats=floats) if motion != "still" else None
    calls = {"theirs": _call(pygame.sprite.groupcollide, group_a, group_b, collided),
             "ours": _call(collide.groupcollide, group_a, group_b, collided)}
    if calls["theirs"]() != calls["ours"]():
        print(f"   WARNING {n} a side, {motion}, {name}: different results")
        return None
    spent, ratios = _turns(calls, step, rounds)
    _print_row(n, motion, name, spent, ratios)
    return ratios


def sprite_table(rounds: int, goal: Callable[..., None], big: bool = False,
                 largest: int | None = None) -> None:
    """Print the table and its goals: no row slower than pygame beyond its spread (some
    round at 1.0x or more), and with collide_mask at least 5x at 100 a side, 50x at 1,000
    (still, moving and on FRects alike: the module keeps nothing between calls)."""
    print("5. pygame's groupcollide against ours (invaders.engine.collide), the same "
          "groups, calls taking turns: median (lowest..highest round)")
    slower = []  # the rows where no round had ours at pygame's speed or better
    sizes = (*SIZES, BIG_SIZE) if big else SIZES
    for n in (n for n in sizes if largest is None or n <= largest):
        for motion in MOTIONS:
            for name, collided in PREDICATES:
                if name == "collide_circle" and n > LARGEST_CIRCLES:
                    continue
                ratios = _row(n, motion, name, collided, rounds)
                if ratios is None or max(ratios) < 1.0:
                    slower.append(f"{n} a side, {motion}, {name}")
                if ratios is not None and name == "collide_mask" and n in GOALS:
                    goal(f"{n} a side, {motion}, collide_mask: >= {GOALS[n]:.0f}x pygame",
                         ratios, GOALS[n])
    goal("no size or predicate slower than pygame beyond its rounds' spread",
         [0.0 if slower else 1.0], 1.0,
         detail="slower: " + "; ".join(slower) if slower else "none slower")


def _collider_row(n: int, motion: str, rounds: int,
                  make: Callable[[], Callable[..., dict]] = GroupCollide) -> list[float] | None:
    """A kept `GroupCollide` (`make`'s) against pygame's `groupcollide` with `collide_mask`
    on one scene, by turns: the per-round ratios, with the row printed; None if, after its
    first call and a step, its answer is not pygame's (swept: does not hold pygame's)."""
    group_a, group_b = groups(n)
    step = _steps((group_a, group_b), swept=motion == "swept") if motion != "still" else None
    collider = make()
    calls = {"theirs": _call(pygame.sprite.groupcollide, group_a, group_b,
                             pygame.sprite.collide_mask),
             "ours": lambda: collider(group_a, group_b)}
    collider(group_a, group_b)  # (its first call: every sprite new to it)
    if step is not None:
        step()
    theirs: Any = calls["theirs"]()
    ours = collider(group_a, group_b)
    if not (ours == theirs if motion != "swept" else _holds(ours, theirs)):
        print(f"   WARNING {n} a side, {motion}, GroupCollide: a different result")
        return None
    spent, ratios = _turns(calls, step, rounds)
    _print_row(n, motion, "GroupCollide", spent, ratios)
    return ratios


def _holds(ours: dict, theirs: dict) -> bool:
    """Whether every pair of pygame's answer is in ours."""
    return all(set(hit) <= set(ours.get(sprite, ())) for sprite, hit in theirs.items())


def collider_table(rounds: int, goal: Callable[..., None], largest: int | None = None,
                   make: Callable[[], Callable[..., dict]] = GroupCollide) -> None:
    """Section 5's second table, on its groups: `GroupCollide` against pygame's
    `groupcollide` with `collide_mask`, and its goal: faster from COLLIDER_FROM a side in
    every motion (the median of the rounds)."""
    print("   GroupCollide (invaders.engine.sprites), kept from call to call, against "
          "pygame's groupcollide with collide_mask:")
    slower = []
    for n in (n for n in SIZES if largest is None or n <= largest):
        for motion in COLLIDER_MOTIONS:
            ratios = _collider_row(n, motion, rounds, make)
            if n >= COLLIDER_FROM and (ratios is None or statistics.median(ratios) < 1.0):
                slower.append(f"{n} a side, {motion}")
    goal(f"GroupCollide faster than pygame's from {COLLIDER_FROM} a side, still, moving and "
         "swept", [0.0 if slower else 1.0], 1.0,
         detail="not: " + "; ".join(slower) if slower else "none slower")
