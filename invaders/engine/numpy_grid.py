"""A broad phase on numpy arrays, for big scenes: boxes kept between ticks, cells joined by
sorting, and a vectorised box test so only real candidates reach the pixel tests.

Each kind's boxes live in arrays (x0, y0, x1, y1, half-open), changed only for the bodies
the store put in the move buffer: a swept kind's box covers its motion over the tick, and
a body that stopped keeps that larger box until it next changes (a superset, as in the
grid). For a group, the boxes of both sides are hashed into the cells they cover, one
side's keys are looked up with `searchsorted` in an index of the other's distinct keys
(kept while that kind does not move), and the pairs sharing a cell are kept only if their
boxes overlap; a pair sharing several cells is kept once. The fixed
cost is a few dozen numpy calls a group, so it pays only in big scenes (see
`detector.NUMPY_FROM`); its pairs are those brute force would test whose boxes overlap,
so the contacts are the same as with every other broad phase.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import numpy as np

from invaders.engine.body import NOWHERE, Body
from invaders.engine.broadphase import (
    BroadPhase,
    Group,
    KindSets,
    Pair,
    Scene,
    ZoneTest,
    kept,
)
from invaders.engine.compiled import mypyc_attr
from invaders.engine.grid import DEFAULT_CELL, LARGE_CELLS, checked_cell
from invaders.engine.rules import Zone

STRIDE = 1 << 21  # cell key = cy * STRIDE + cx, with cells offset to be non-negative
OFFSET = 1 << 20
BEYOND = np.iinfo(np.int64).max  # no cell's key
INT64_MIN, INT64_MAX = int(np.iinfo(np.int64).min), int(np.iinfo(np.int64).max)


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Boxes:
    """One kind's bodies and their boxes, row i of the arrays being `objects[i]`."""

    def __init__(self, slot: dict[int, int]) -> None:
        self.n = 0
        self.slot = slot  # body id -> row, shared by the kinds' tables (ids are unique)
        # (typed as arrays of any shape: numpy's stubs give a made array's shape, in some
        # versions, and then a concatenation's other than the array's)
        self.xy: np.ndarray = np.zeros((64, 4), dtype=np.int64)  # x0, y0, x1, y1
        self.ids: np.ndarray = np.zeros(64, dtype=np.int64)  # each row's id, to sort in bulk
        self.objects: np.ndarray = np.empty(64, dtype=object)  # each row's body, picked in bulk
        self.swept_at: np.ndarray = np.full(64, -1, dtype=np.int64)  # tick it spans a motion
        self.version = 0  # changes whenever a row does: cells worked out before are stale
        self._kept: dict[tuple[str, int], tuple[int, tuple]] = {}  # (what, cell): (version, it)

    @property
    def bodies(self) -> list[Body]:
        """The bodies, row by row."""
        return self.objects[:self.n].tolist()

    def cells(self, cell: int) -> Cells:
        """`_cells` of the boxes: kept until a row changes, so a kind that does not move is
        hashed once."""
        kept = self._kept.get(("cells", cell))
        if kept is not None and kept[0] == self.version:
            return kept[1]
        found = _cells(self.xy[:self.n], cell)
        self._kept[("cells", cell)] = (self.version, found)
        return found

    def index(self, cell: int) -> CellIndex:
        """The cells as an index to look keys up in (`_index`); kept as `cells` is."""
        kept = self._kept.get(("index", cell))
        if kept is not None and kept[0] == self.version:
            return kept[1]
        found = _index(*self.cells(cell))
        self._kept[("index", cell)] = (self.version, found)
        return found

    def add(self, body: Body) -> None:
        if self.n == len(self.xy):
            self.xy = np.concatenate([self.xy, np.zeros_like(self.xy)])
            self.ids = np.concatenate([self.ids, np.zeros_like(self.ids)])
            self.objects = np.concatenate([self.objects, np.empty_like(self.objects)])
            self.swept_at = np.concatenate([self.swept_at, np.full_like(self.swept_at, -1)])
        self.slot[body.id] = self.n
        self.ids[self.n] = body.id
        self.objects[self.n] = body
        self.version += 1
        self.n += 1

    def remove(self, body: Body) -> None:
        """Swap the last row into its place."""
        i = self.slot.pop(body.id)
        last = self.n - 1
        if i != last:
            moved = self.objects[last]
            self.slot[moved.id] = i
            self.xy[i] = self.xy[last]
            self.ids[i] = moved.id
            self.objects[i] = moved
            self.swept_at[i] = self.swept_at[last]
        self.objects[last] = None
        self.n = last
        self.version += 1


def _read(bodies: list[Body], slot: dict[int, int]) -> np.ndarray:
    """One row a body: kind, row in its table (-1: none, as for one that went once its row
    is removed), x, y, w, h, px, py, moved_tick, read as it is now (so a body listed twice
    is read the same twice). The fields are packed as C integers by `struct` and the bytes
    handed to numpy at once: about half what numpy takes to read the same ints from an
    iterator."""
    get = slot.get
    pack = _PACK
    return np.frombuffer(b"".join([pack(b.kind, get(b.id, -1), b.x, b.y, b.w, b.h, b.px, b.py,
                                        b.moved_tick) for b in bodies]), np.int64).reshape(-1, 9)


_PACK = struct.Struct("9q").pack  # as native int64s


def _tick_boxes(raw: np.ndarray, moved: np.ndarray) -> np.ndarray:
    """Boxes (x0, y0, x1, y1) of rows `_read` gave, over the tick's motion where `moved`
    (as `tick_box` gives them)."""
    x, y = raw[:, 2], raw[:, 3]
    px = np.where(moved, raw[:, 6], x)
    py = np.where(moved, raw[:, 7], y)
    out = np.empty((len(raw), 4), dtype=np.int64)
    out[:, 0] = np.minimum(x, px)
    out[:, 1] = np.minimum(y, py)
    out[:, 2] = np.maximum(x, px) + raw[:, 4]
    out[:, 3] = np.maximum(y, py) + raw[:, 5]
    return out


# Keys, their rows, the rows too large to bin, and whether no row has more than one key.
Cells = tuple[np.ndarray, np.ndarray, np.ndarray, bool]
NO_ROWS = np.zeros(0, dtype=np.int64)


def _cells(xy: np.ndarray, cell: int) -> Cells:
    """(cell key, row) for every cell each box covers, row by row, each row's cells in
    row-major order; the rows of boxes over LARGE_CELLS cells, left out of the keys (one
    swept a million pixels would have been a billion keys: `box_pairs` meets these box by
    box); and whether each row has one key at most (told, not counted: a box of no width
    has none, so one with two keys could make the counts even)."""
    c0 = xy[:, :2] // cell
    c1 = (xy[:, 2:] - 1) // cell
    x0, y0 = c0[:, 0] + OFFSET, (c0[:, 1] + OFFSET) * STRIDE
    x1, y1 = c1[:, 0] + OFFSET, (c1[:, 1] + OFFSET) * STRIDE
    wide, tall = x1 != x0, y1 != y0
    if not (wide.any() or tall.any()):  # every box in one cell: the common case
        return y0 + x0, np.arange(len(xy)), NO_ROWS, True
    if (x1 - x0).max() <= 1 and (y1 - y0).max() <= STRIDE:  # at most 2x2 cells each
        keys = np.stack([y0 + x0, y0 + x1, y1 + x0, y1 + x1], axis=1)
        keep = np.stack([np.ones(len(xy), dtype=bool), wide, tall, wide & tall], axis=1)
        kept = np.flatnonzero(keep)  # row * 4 + corner: a flat pick is ~4x a 2-D one
        return keys.take(kept), kept >> 2, NO_ROWS, False  # (some row has two)
    span = c1 - c0 + 1  # boxes wider than a cell: every cell of each, counted out
    large = np.flatnonzero(span[:, 0].astype(np.float64) * span[:, 1] > LARGE_CELLS)
    counts = span[:, 0] * span[:, 1]
    counts[large] = 0  # (counted in floats above: a world-sized box's count overflows)
    rows = np.repeat(np.arange(len(xy)), counts)
    first = np.repeat(np.cumsum(counts) - counts, counts)
    k = np.arange(len(rows)) - first
    width = span[rows, 0]
    cx = c0[rows, 0] + k % width
    cy = c0[rows, 1] + k // width
    return (cy + OFFSET) * STRIDE + (cx + OFFSET), rows, large, not (counts > 1).any()


CellIndex = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool, np.ndarray]


def _index(keys: np.ndarray, rows: np.ndarray, large: np.ndarray, single: bool
           ) -> CellIndex:
    """Cells to look up: each distinct key once, sorted (and then `BEYOND`), with where its
    rows start in the rows sorted by key and how many there are; whether each row has one
    key at most; and the rows too large to bin."""
    order = np.argsort(keys)  # any order within a key: the pairs are sorted by ids later
    keys, by_key = keys[order], rows[order]
    if not len(keys):
        return keys, keys, keys, by_key, True, large
    starts = np.flatnonzero(np.concatenate(([True], keys[1:] != keys[:-1])))
    counts = np.diff(np.append(starts, len(keys)))
    # A key above every cell's ends the distinct keys, so a search never runs off them.
    return np.append(keys[starts], BEYOND), starts, counts, by_key, single, large


def distinct(values: np.ndarray) -> np.ndarray:
    """The values sorted, each once: what `np.unique` gives, by a sort and a comparison
    (numpy 2's `np.unique` hashes, about ten times slower on the few hundred values here)."""
    values = np.sort(values)
    if len(values) < 2:
        return values
    return values[np.concatenate(([True], values[1:] != values[:-1]))]


def box_pairs(a: np.ndarray, b: np.ndarray, cell: int, a_cells: Cells | None = None,
              b_index: CellIndex | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Rows (i, j) of boxes a[i] and b[j] that overlap, each pair once, by way of the
    cells they share (`a_cells` and `b_index`, if already worked out); a box too large
    to bin is met box by box."""
    a_cells = a_cells if a_cells is not None else _cells(a, cell)
    b_index = b_index if b_index is not None else _index(*_cells(b, cell))
    i, j = _shared_cells(a, b, a_cells, b_index)
    large_a, large_b = a_cells[2], b_index[5]
    if not (len(large_a) or len(large_b)):
        return i, j
    found_i, found_j = [i], [j]
    for row in large_a.tolist():  # with every box of b
        met = _meeting(b, a[row])
        found_i.append(np.full(len(met), row, dtype=np.int64))
        found_j.append(met)
    for row in large_b.tolist():  # with every box of a not met above
        met = np.setdiff1d(_meeting(a, b[row]), large_a)
        found_i.append(met)
        found_j.append(np.full(len(met), row, dtype=np.int64))
    return np.concatenate(found_i), np.concatenate(found_j)


def _meeting(boxes: np.ndarray, box: np.ndarray) -> np.ndarray:
    """The rows of `boxes` that overlap `box`."""
    return np.flatnonzero((boxes[:, 0] < box[2]) & (box[0] < boxes[:, 2])
                          & (boxes[:, 1] < box[3]) & (box[1] < boxes[:, 3]))


def _shared_cells(a: np.ndarray, b: np.ndarray, a_cells: Cells, b_index: CellIndex
                  ) -> tuple[np.ndarray, np.ndarray]:
    """`box_pairs` of the binned boxes: those that share a cell and overlap, each once."""
    ka, ra, _, a_single = a_cells
    keys, starts, counts, rb, b_single, _ = b_index
    if not len(keys) or not len(ka):
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty
    at = np.searchsorted(keys, ka)  # at most the sentinel's place: see `_index`
    has = keys.take(at) == ka
    if not has.any():
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty
    at = at[has]
    ra, lo, n = ra[has], starts.take(at), counts.take(at)
    total = int(n.sum())
    i = np.repeat(ra, n)
    j = rb.take(np.repeat(lo - (np.cumsum(n) - n), n) + np.arange(total))
    ai, bj = a.take(i, axis=0), b.take(j, axis=0)  # `take`: ~4x `a[i]` on rows of 4
    hit = ((ai[:, 0] < bj[:, 2]) & (bj[:, 0] < ai[:, 2])
           & (ai[:, 1] < bj[:, 3]) & (bj[:, 1] < ai[:, 3]))
    i, j = i[hit], j[hit]
    # A pair can share several cells only if both boxes cover more than one: then once.
    if len(i) > 1 and not b_single and not a_single:
        key = distinct(i * len(b) + j)
        i, j = key // len(b), key % len(b)
    return i, j


def _binned(zone: Zone, cell: int) -> tuple[np.ndarray, CellIndex] | None:
    """A zone's boxes as rows (x0, y0, x1, y1) and binned in cells of `cell` px (a box over
    LARGE_CELLS of them met box by box, as a body's is); or None where a box does not fit
    int64 (one 10^30 px wide raised OverflowError)."""
    if not all(min(x, y) >= INT64_MIN and max(x + w, y + h) <= INT64_MAX
               for x, y, w, h in zone):
        return None
    boxes = np.array([(x, y, x + w, y + h) for x, y, w, h in zone], dtype=np.int64).reshape(-1, 4)
    return boxes, _index(*_cells(boxes, cell))


class NumpyGrid(BroadPhase):
    """Broad phase for big scenes: numpy arrays of boxes, cells joined by sorting."""

    name = "numpy"

    def __init__(self, cell: int = DEFAULT_CELL) -> None:
        self.cell = checked_cell(cell)
        self.move_buffer = []
        self.boxes: dict[int, Boxes] = {}
        self.slot: dict[int, int] = {}  # body id -> its row in its kind's table
        self._zones: dict[int, tuple[ZoneTest, tuple[np.ndarray, CellIndex] | None]] = {}

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        buffer = kept(self.move_buffer)  # the store holds this very list: refill it, never replace
        buffer.clear()
        buffer.extend(b for bodies in scene.by_kind.values() for b in bodies)
        for body in buffer:
            body.fence = NOWHERE  # a fence a grid gave it: here every move is heard
        self.boxes = {}
        self.slot = {}
        self._drain(scene.tick, kinds)

    def _drain(self, tick: int, kinds: KindSets) -> None:
        """Apply the move buffer: the rows of bodies that went removed, then every body in
        it read at once, rows added for the new ones, and the boxes written kind by kind
        (a swept kind's over its motion this tick, if it moved)."""
        boxes = self.boxes
        slot = self.slot
        buffer = kept(self.move_buffer)
        for body in [b for b in buffer if not b.alive]:
            if body.id in slot:
                boxes[body.kind].remove(body)
        raw = _read(buffer, slot)
        rows = raw[:, 1]
        new = np.flatnonzero(rows < 0)
        if len(new):  # rows for the bodies new to the tables; the gone ones are left out
            rows = rows.copy()
            for k in new.tolist():
                body = buffer[k]
                if body.alive:
                    if body.id not in slot:
                        table = boxes.get(body.kind)
                        if table is None:
                            table = boxes[body.kind] = Boxes(slot)
                        table.add(body)
                    rows[k] = slot[body.id]
            live = np.flatnonzero(rows >= 0)
            if len(live) < len(rows):
                raw, rows = raw.take(live, axis=0), rows.take(live)
        buffer.clear()
        if not len(raw):
            return
        kind = raw[:, 0]
        one = int(kind.min()) == int(kind.max())  # one kind moved: no picking apart
        present = [int(kind[0])] if one else distinct(kind).tolist()
        swept = kinds.swept
        moved = raw[:, 8] == tick
        for k in present:
            if k not in swept:
                moved &= kind != k
        xy = _tick_boxes(raw, moved)
        spans = np.where(moved, tick, -1)
        for k in present:
            table = boxes[k]
            if one:
                table.xy[rows] = xy
                table.swept_at[rows] = spans
            else:
                pick = np.flatnonzero(kind == k)
                at = rows.take(pick)
                table.xy[at] = xy.take(pick, axis=0)
                table.swept_at[at] = spans.take(pick)
            table.version += 1

    def in_zone(self, scene: Scene, kind: int, zone: ZoneTest, kinds: KindSets) -> list[Body]:
        """The bodies of a kind whose box over the tick meets a zone, in id order: the
        stored boxes (exact, or a superset for a body that stopped) against the zone's
        boxes at once, then the few that meet one tested exactly. The zone is hashed into
        the grid's own cells, so the kind's cells, worked out for its pairs, serve here too.
        A kind no entry sweeps has its boxes stored where they end, not over the tick (one
        that crossed the zone and left was missed): its bodies are tested one by one, as
        they are where a zone has a box too big to bin."""
        kept = self._zones.get(id(zone))
        if kept is None or kept[0] is not zone:
            kept = self._zones[id(zone)] = (zone, _binned(zone.zone, self.cell))
        binned = kept[1]
        if binned is None or kind not in kinds.swept:  # (each body tested, as by default)
            return zone.within(scene.by_kind[kind], scene.tick)
        if self.move_buffer:
            self._drain(scene.tick, kinds)
        table = self.boxes.get(kind)
        if table is None or not table.n:
            return []
        rows, _ = box_pairs(table.xy[:table.n], binned[0], self.cell, table.cells(self.cell),
                            binned[1])
        if not len(rows):
            return []
        rows = distinct(rows)
        rows = rows[np.argsort(table.ids[rows])]
        tick = scene.tick
        spans = table.swept_at[rows]
        exact = ((spans == -1) | (spans == tick)).tolist()  # its box is this tick's own
        bodies = table.objects
        return [bodies[r] for r, sure in zip(rows.tolist(), exact, strict=True)
                if sure or zone.holds(bodies[r], tick)]

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        if self.move_buffer:
            self._drain(scene.tick, kinds)
        boxes = self.boxes
        ids_a, ids_b, found_a, found_b, rules, counts = [], [], [], [], [], []
        for rule, side_a, side_b in groups:
            table_a, table_b = boxes.get(rule.a), boxes.get(rule.b)
            if table_a is None or table_b is None or not side_a or not side_b:
                continue
            a_rows = self._rows(table_a, side_a)
            b_rows = self._rows(table_b, side_b)
            whole_a = isinstance(a_rows, slice)
            whole_b = isinstance(b_rows, slice)
            i, j = box_pairs(table_a.xy[a_rows], table_b.xy[b_rows], self.cell,
                             table_a.cells(self.cell) if whole_a else None,
                             table_b.index(self.cell) if whole_b else None)
            if not len(i):
                continue
            ida, idb = table_a.ids[a_rows].take(i), table_b.ids[b_rows].take(j)
            bodies_a, bodies_b = table_a.objects[a_rows].take(i), table_b.objects[b_rows].take(j)
            ids_a.append(ida)
            ids_b.append(idb)
            found_a.append(bodies_a)
            found_b.append(bodies_b)
            rules.append(rule)
            counts.append(len(ida))
        if not rules:
            return []
        # One list of (low, high, entry), sorted by ids, built by numpy rather than per pair.
        ida, idb = np.concatenate(ids_a), np.concatenate(ids_b)
        swap = ida > idb
        order = np.lexsort((np.where(swap, ida, idb), np.where(swap, idb, ida)))
        bodies_a, bodies_b = np.concatenate(found_a), np.concatenate(found_b)
        entries = np.empty(len(rules), dtype=object)
        for k, rule in enumerate(rules):
            entries[k] = rule
        return list(zip(np.where(swap, bodies_b, bodies_a).take(order).tolist(),
                        np.where(swap, bodies_a, bodies_b).take(order).tolist(),
                        entries.repeat(counts).take(order).tolist(), strict=True))

    @staticmethod
    def _rows(table: Boxes, side: Sequence[Body]) -> slice | list[int]:
        """The rows of a group's side: the whole table when the side is the whole kind,
        else the rows of the side's bodies (a zone's)."""
        if len(side) == table.n:
            return slice(0, table.n)
        return [table.slot[b.id] for b in side]
