"""Broad phases: from the groups the rules allow, the candidate pairs, sorted by ids.

Brute force pairs every allowed body with every other (the reference). The uniform grid bins
each body into the cells its box covers, keeps static bodies resident, re-bins a mover only
when its cell range changes, and reports a body spanning several cells once. Both return
the same sorted list whenever their boxes overlap, so contacts never depend on the choice.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple, Protocol

from invaders.engine.body import Body, Kind, tick_box
from invaders.engine.rules import PairRule

Group = tuple[PairRule, Sequence[Body], Sequence[Body]]
Pair = tuple[Body, Body, PairRule]


class KindSets(NamedTuple):
    """What the rules say about kinds: which are swept, which are ever looked up."""

    swept: frozenset[Kind]
    probed: frozenset[Kind]


class Scene(Protocol):
    """What the pipeline reads from a world (or from a test's hand-made scene)."""

    tick: int
    dirty: Sequence[Body]  # bodies added, moved or removed since the previous tick's detect
    by_kind: Mapping[Kind, Sequence[Body]]  # live bodies of each kind, in id order


class BroadPhase(Protocol):
    name: str

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        """Candidate pairs (low id first), sorted by (low id, high id)."""
        ...


def _ordered(a: Body, b: Body, rule: PairRule) -> Pair:
    return (a, b, rule) if a.id < b.id else (b, a, rule)


def _pair_key(pair: Pair) -> tuple[int, int]:
    return pair[0].id, pair[1].id


class Brute:
    """Every allowed pair: the reference the grid must agree with."""

    name = "brute"

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        out = [_ordered(a, b, rule) for rule, side_a, side_b in groups
               for a in side_a for b in side_b]
        out.sort(key=_pair_key)
        return out


DEFAULT_CELL = 32  # px; fastest at game scale in `invaders study` (16 and 64 close behind)


class Grid:
    """Uniform grid, one layer of cells per kind, so a probe only meets kinds it may hit.

    In each rule side `a` probes the layer of kind `b`; kinds that are never looked up (in
    the game the shot and the cannon) are never binned, so moving them costs nothing here.

    Swept kinds are binned by the union of their boxes at the start and end of the tick. A
    body that stopped moving keeps its larger range until it next moves: a superset, which
    is safe, and saves re-binning every resting bomb every tick.
    """

    name = "grid"
    STRIDE = 1 << 16  # cell key = cy * STRIDE + cx; coordinates stay far inside +-2**20 px

    def __init__(self, cell: int = DEFAULT_CELL) -> None:
        if cell < 1:
            raise ValueError("grid cell size must be at least 1 px")
        self.cell = cell
        self.layers: dict[Kind, dict[int, list[Body]]] = {kind: {} for kind in Kind}
        # Per layer, how many binned cells each cell row holds: a probe whose rows are all
        # empty in the other layer skips its cells at the cost of one look-up per row.
        self.rows: dict[Kind, dict[int, int]] = {kind: {} for kind in Kind}
        self.ranges: dict[int, tuple[int, int, int, int]] = {}
        self._kinds = KindSets(frozenset(), frozenset())
        self._scene: Scene | None = None
        self._tick = -2
        self.rebins = 0  # how many times a body changed cells (for the study and tests)

    # --- keeping the cells in step with the scene -------------------------------------------
    def sync(self, scene: Scene, kinds: KindSets) -> None:
        """Apply the scene's dirty list, or rebuild if this is not the next tick we saw."""
        tick = scene.tick
        if (scene is not self._scene or kinds is not self._kinds
                or (tick != self._tick + 1 and tick != self._tick)):
            self._rebuild(scene, kinds)
        elif scene.dirty:
            swept, probed = kinds
            update = self._update
            for body in scene.dirty:
                if body.kind in probed:
                    update(body, body.kind in swept, tick)
        self._scene = scene
        self._tick = tick

    def _rebuild(self, scene: Scene, kinds: KindSets) -> None:
        self._kinds = kinds
        self.layers = {kind: {} for kind in Kind}
        self.rows = {kind: {} for kind in Kind}
        self.ranges = {}
        for kind in kinds.probed:
            is_swept = kind in kinds.swept
            for body in scene.by_kind[kind]:
                self._update(body, is_swept, scene.tick)

    def cell_range(self, body: Body, is_swept: bool, tick: int) -> tuple[int, int, int, int]:
        """Cells (cx0, cy0, cx1, cy1) covered by the body's box, swept over the tick if asked."""
        c = self.cell
        x0 = body.x
        y0 = body.y
        w = body.w
        h = body.h
        x1 = x0 + w
        y1 = y0 + h
        if is_swept and body.moved_tick == tick:  # comparisons: cheaper than min() and max()
            px = body.px
            py = body.py
            if px < x0:
                x0 = px
            elif px + w > x1:
                x1 = px + w
            if py < y0:
                y0 = py
            elif py + h > y1:
                y1 = py + h
        return x0 // c, y0 // c, (x1 - 1) // c, (y1 - 1) // c

    def _update(self, body: Body, is_swept: bool, tick: int) -> None:
        old = self.ranges.get(body.id)
        if not body.alive:
            if old is not None:
                self._unbin(body, old)
                del self.ranges[body.id]
            return
        new = self.cell_range(body, is_swept, tick)
        if new == old:
            return
        if old is not None:
            self._unbin(body, old)
        self._bin(body, new)
        self.ranges[body.id] = new
        self.rebins += 1

    def _bin(self, body: Body, r: tuple[int, int, int, int]) -> None:
        layer = self.layers[body.kind]
        rows = self.rows[body.kind]
        stride = self.STRIDE
        for cy in range(r[1], r[3] + 1):
            rows[cy] = rows.get(cy, 0) + r[2] - r[0] + 1
            for cx in range(r[0], r[2] + 1):
                key = cy * stride + cx
                cell = layer.get(key)
                if cell is None:
                    layer[key] = [body]
                else:
                    cell.append(body)

    def _unbin(self, body: Body, r: tuple[int, int, int, int]) -> None:
        layer = self.layers[body.kind]
        rows = self.rows[body.kind]
        stride = self.STRIDE
        for cy in range(r[1], r[3] + 1):
            left = rows[cy] - (r[2] - r[0] + 1)
            if left:
                rows[cy] = left
            else:
                del rows[cy]
            for cx in range(r[0], r[2] + 1):
                key = cy * stride + cx
                cell = layer[key]
                cell.remove(body)
                if not cell:
                    del layer[key]

    # --- queries ---------------------------------------------------------------------------
    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        self.sync(scene, kinds)
        out: list[Pair] = []
        stride = self.STRIDE
        ranges = self.ranges
        unbinned: dict[int, tuple[int, int, int, int]] = {}
        tick = scene.tick
        swept = kinds.swept
        all_rows = self.rows
        for rule, probes, others in groups:
            rows = all_rows[rule.b]
            if not rows:
                continue
            if rule.a in kinds.probed and rows.keys().isdisjoint(all_rows[rule.a]):
                continue  # both kinds binned, and no cell row holds both: nothing can meet
            layer = self.layers[rule.b]
            allowed = None if rule.zone is None else {b.id for b in others}
            for probe in probes:
                # Its binned range (exact, or for a resting swept body a safe superset), or
                # for a kind that is never binned, worked out once per call.
                r = ranges.get(probe.id)
                if r is None:
                    r = unbinned.get(probe.id)
                    if r is None:
                        r = unbinned[probe.id] = self.cell_range(probe, probe.kind in swept, tick)
                cx0, cy0, cx1, cy1 = r
                for cy in range(cy0, cy1 + 1):
                    if cy in rows:
                        break
                else:
                    continue  # no row of the probe holds any body of the other kind
                if cx0 == cx1 and cy0 == cy1:
                    for other in layer.get(cy0 * stride + cx0, ()):
                        if allowed is None or other.id in allowed:
                            out.append(_ordered(probe, other, rule))
                    continue
                seen: set[int] = set()
                for cy in range(cy0, cy1 + 1):
                    for cx in range(cx0, cx1 + 1):
                        for other in layer.get(cy * stride + cx, ()):
                            oid = other.id
                            if oid not in seen and (allowed is None or oid in allowed):
                                seen.add(oid)
                                out.append(_ordered(probe, other, rule))
        if len(out) > 1:
            out.sort(key=_pair_key)
        return out


class SortAndSweep:
    """Sort both sides of a group by the left edge of their boxes and sweep across: only
    boxes whose x-spans overlap are compared, and those must overlap in y too.

    It keeps no state between ticks (a world-sized grid is not needed), so it suits sparse
    scenes or scenes much wider than tall; the study measures where it pays.
    """

    name = "sweep"

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
                        out.append(_ordered(body, other[5], rule))
                active[side].append(item)
        if len(out) > 1:
            out.sort(key=_pair_key)
        return out


BROADPHASES = ("grid", "brute", "sweep")


def make_broadphase(name: str, cell: int = DEFAULT_CELL) -> BroadPhase:
    """A broad phase by its command-line name."""
    if name == "grid":
        return Grid(cell)
    if name == "brute":
        return Brute()
    if name == "sweep":
        return SortAndSweep()
    raise ValueError(f"unknown broad phase {name!r} (choose from {', '.join(BROADPHASES)})")
