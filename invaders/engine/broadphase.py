"""Broad phases: from the groups the rules allow, the candidate pairs, sorted by ids.

Brute force pairs every allowed body with every other (the reference). Sort-and-sweep sorts
each group by left edge and compares only boxes whose x-spans overlap. The uniform grid
(grid.py), the cell rects (rects.py) and the numpy broad phase (numpy_grid.py) keep their
state between ticks, fed by the store's move buffer. All return every pair whose boxes
overlap, sorted, so contacts never depend on the choice.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple, Protocol

from invaders.engine.body import Body, tick_box
from invaders.engine.compiled import mypyc_attr
from invaders.engine.rules import PairRule, Zone

Group = tuple[PairRule, Sequence[Body], Sequence[Body]]
Pair = tuple[Body, Body, PairRule]


class KindSets(NamedTuple):
    """What the rules say about kinds: which are swept, which are ever looked up."""

    swept: frozenset[int]
    probed: frozenset[int]

    def __deepcopy__(self, memo: dict[int, Any]) -> KindSets:
        """Itself: made of frozensets (copied with every world, as a detector holds it)."""
        return self


class Scene(Protocol):
    """What a broad phase reads: the tick and the live bodies of each kind, in id order
    (a `BodyStore` is one)."""

    @property
    def tick(self) -> int: ...

    @property
    def by_kind(self) -> Mapping[int, Sequence[Body]]: ...


class ZoneTest(Protocol):
    """A zone as the detector indexes it: its boxes, and the exact test of bodies."""

    zone: Zone

    def holds(self, body: Body, tick: int) -> bool: ...

    def within(self, bodies: Sequence[Body], tick: int) -> list[Body]: ...


class Counted(Scene, Protocol):
    """A scene that keeps its body count (a `BodyStore` does)."""

    @property
    def size(self) -> int: ...


@mypyc_attr(allow_interpreted_subclasses=True)  # (a broad phase of one's own derives from it)
class BroadPhase:
    """What the detector asks of a broad phase. The concrete ones derive from it, so they
    share its defaults (`in_zone`, `fit`)."""

    name: str
    cell: int  # the grid's cell size in px; 0 for broad phases without cells
    # Filled by the store (None: it keeps no state), emptied only by the broad phase itself
    # when asked. While it stays empty the same groups get the same answer: the detector
    # then answers a tick from the last one without asking.
    move_buffer: list[Body] | None

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        """Start again from every body of the scene."""
        raise NotImplementedError

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> Sequence[Pair]:
        """Candidate pairs (low id first), sorted by (low id, high id). Read only: a broad
        phase may hand out the same answer again."""
        raise NotImplementedError

    def in_zone(self, scene: Scene, kind: int, zone: ZoneTest, kinds: KindSets) -> list[Body]:
        """The bodies of a kind whose box over the tick meets the zone, in id order: by
        default each tested; a broad phase with their boxes at hand may answer faster."""
        return zone.within(scene.by_kind[kind], scene.tick)

    def fit(self, scene: Counted, kinds: KindSets) -> None:
        """Bodies came or went: a broad phase that picks itself by the body count may
        change here (told by the detector's replan). By default nothing."""
        return None


def kept(buffer: list[Body] | None) -> list[Body]:
    """The move buffer of a broad phase that keeps one: a list, never None."""
    assert buffer is not None
    return buffer


def ordered(a: Body, b: Body, rule: PairRule) -> Pair:
    return (a, b, rule) if a.id < b.id else (b, a, rule)


def pair_key(pair: Pair) -> tuple[int, int]:
    return pair[0].id, pair[1].id


def once_each(pairs: Sequence[Pair]) -> list[Pair]:
    """The candidates without a body paired with itself and without a pair given twice by
    one entry: what a broad phase gives for an entry of one kind, whose two sides are the
    same bodies (each body meets itself, and each two meet from either side). Relies on
    the candidates coming sorted by ids (`pair_key`), stably, so that one entry's pair
    given twice comes twice in a row (`tests/test_broadphase.py`, on every broad phase)."""
    out: list[Pair] = []
    last: Pair | None = None
    for pair in pairs:
        a, b, rule = pair
        if a is b or (last is not None and last[0] is a and last[1] is b
                      and last[2] is rule):
            continue
        out.append(pair)
        last = pair
    return out


class Brute(BroadPhase):
    """Every allowed pair: the reference the others must agree with."""

    name = "brute"
    cell = 0
    move_buffer: list[Body] | None = None

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        pass

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        out = [ordered(a, b, rule) for rule, side_a, side_b in groups
               for a in side_a for b in side_b]
        out.sort(key=pair_key)
        return out


class SortAndSweep(BroadPhase):
    """Sort both sides of a group by the left edge of their boxes and sweep across: only
    boxes whose x-spans overlap are compared, and those must overlap in y too.

    It keeps no state between ticks (a world-sized grid is not needed), so it suits sparse
    scenes or scenes much wider than tall; the study measures where it pays.
    """

    name = "sweep"
    cell = 0
    move_buffer: list[Body] | None = None

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        pass

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        tick = scene.tick
        swept = kinds.swept
        out: list[Pair] = []
        for rule, side_a, side_b in groups:
            items = []
            for side, bodies in ((0, side_a), (1, side_b)):
                for body in bodies:
                    x0, y0, x1, y1 = tick_box(body, tick, body.kind in swept)
                    items.append((x0, x1, y0, y1, side, body))
            items.sort(key=lambda item: (item[0], item[5].id))
            active: tuple[list, list] = ([], [])
            for item in items:
                x0, _x1, y0, y1, side, body = item
                for lst in active:
                    if lst and any(o[1] <= x0 for o in lst):
                        lst[:] = [o for o in lst if o[1] > x0]  # ended left of here
                for other in active[1 - side]:
                    if other[2] < y1 and y0 < other[3]:
                        out.append(ordered(body, other[5], rule))
                active[side].append(item)
        if len(out) > 1:
            out.sort(key=pair_key)
        return out
