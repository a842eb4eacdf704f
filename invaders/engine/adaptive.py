"""The broad phases by name, and `auto`: the one that suits the scene's size.

The cell rects test a probe against a whole kind in C and lead at game scale; the grid's
locality wins from a few hundred bodies, and numpy's arrays from several hundred more. Where
each overtakes the next is measured, not assumed: `invaders bench --big` and the scaling
chart of `invaders study` print the figures (docs/bench.md, docs/study.md).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from invaders.engine.body import Body
from invaders.engine.broadphase import (
    BroadPhase,
    Brute,
    Counted,
    Group,
    KindSets,
    Pair,
    Scene,
    SortAndSweep,
    ZoneTest,
)
from invaders.engine.grid import DEFAULT_CELL, Grid
from invaders.engine.rects import CellRects

BROADPHASES = ("auto", "rects", "grid", "numpy", "brute", "sweep")
DEFAULT_BROADPHASE = "auto"  # the game's, the command line's and the sprite collider's
# Bodies from which the grid takes over from the cell rects, and below which the rects
# come back (apart, so that a count near the crossing does not flap between them).
GRID_FROM = 220
GRID_UNTIL = 160
# Bodies from which the numpy broad phase takes over from the grid, and below which the
# grid comes back. Compiled (docs/compiled.md) the grid's loops run as C and hold out
# longer: storms timed in turn put the crossing near 2,400 bodies there (grid/numpy 0.92x
# at 2,000, 1.14x at 3,000), near 800 interpreted.
COMPILED = not __file__.endswith(".py")  # (the core is built one way or the other whole)
NUMPY_FROM, NUMPY_UNTIL = (2500, 2000) if COMPILED else (800, 600)
# The automatic choice's broad phases, smallest scenes first: each with the body count
# from which it is taken, and the count below which it is left again.
TIERS = (("rects", 0, 0), ("grid", GRID_FROM, GRID_UNTIL), ("numpy", NUMPY_FROM, NUMPY_UNTIL))


class Adaptive(BroadPhase):
    """The cell rects for game-sized scenes, the grid for bigger ones and the numpy broad
    phase for the biggest, by the body count (`TIERS`); the one in use is rebuilt from the
    scene on a change. All give the pairs brute force would test whose boxes may meet, so
    switching changes no contact. The detector calls `fit` when bodies come or go (the
    only time the count moves); between, `pairs` is the active one's own, so choosing
    costs a tick nothing."""

    name = "auto"

    def __init__(self, cell: int = DEFAULT_CELL) -> None:
        self.cell = cell  # (every tier's: each has cells)
        self.move_buffer: list[Body] | None = []
        self._take(0)

    def _take(self, tier: int) -> None:
        """Tier `tier` of `TIERS` made active, and the body counts it is kept between. The
        new one fills its move buffer from the store's: the same list, nothing copied."""
        self._tier = tier
        self._low = TIERS[tier][2]
        self._high = TIERS[tier + 1][1] if tier + 1 < len(TIERS) else sys.maxsize
        self.active: BroadPhase = make_broadphase(TIERS[tier][0], self.cell)
        self.active.move_buffer = self.move_buffer

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        """The tier for the scene's body count, built from the scene itself."""
        self._choose(sum(len(bodies) for bodies in scene.by_kind.values()))
        self.active.rebuild(scene, kinds)  # the buffer is moot

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> Sequence[Pair]:
        return self.active.pairs(scene, groups, kinds)

    def fit(self, scene: Counted, kinds: KindSets) -> None:
        """Bodies came or went: a new tier if the count left the one in use's."""
        n = scene.size
        if not self._low <= n < self._high:
            self._choose(n)
            self.active.rebuild(scene, kinds)

    def _choose(self, n: int) -> None:
        """The tier for n bodies: a tier up to the one in use is kept down to its lower
        count, one above it is taken from its higher."""
        tier = 0
        for place, (_, start, keep) in enumerate(TIERS):
            if n >= (keep if place <= self._tier else start):
                tier = place
        if tier != self._tier:
            self._take(tier)

    def in_zone(self, scene: Scene, kind: int, zone: ZoneTest, kinds: KindSets) -> list[Body]:
        return self.active.in_zone(scene, kind, zone, kinds)


def make_broadphase(name: str, cell: int = DEFAULT_CELL) -> BroadPhase:
    """A broad phase by its command-line name."""
    if name == "grid":
        return Grid(cell)
    if name == "rects":
        return CellRects(cell)
    if name == "brute":
        return Brute()
    if name == "sweep":
        return SortAndSweep()
    if name == "numpy":
        from invaders.engine.numpy_grid import NumpyGrid  # numpy only when asked for

        return NumpyGrid(cell)
    if name == "auto":
        return Adaptive(cell)
    raise ValueError(f"unknown broad phase {name!r} (choose from {', '.join(BROADPHASES)})")


