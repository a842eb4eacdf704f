"""The uniform grid: one layer of cells per kind, kept between ticks from the move buffer.

Each body is binned into the cells its box covers; a body spanning several cells is reported
once. Only the bodies the store put in the move buffer since the last query are re-binned:
while few move, the store hears of a body only when its box leaves its cells. Kinds that are
never looked up are never binned.
While no range changed, a query with the same groups gets the last answer without a look.
"""

from __future__ import annotations

from collections.abc import Sequence

from invaders.engine.body import NOWHERE, Body, tick_box
from invaders.engine.broadphase import (
    BroadPhase,
    Group,
    KindSets,
    Pair,
    Scene,
    kept,
    ordered,
    pair_key,
)
from invaders.engine.compiled import mypyc_attr
from invaders.engine.rules import PairRule

# px: about the size of the game's bodies and gaps. `invaders study` times 4 to 128 px on
# each scene (docs/study.md); larger cells gain little at game scale and lose in storms.
DEFAULT_CELL = 32
FEW_MOVES = 8  # bodies in the move buffer up to which a body keeps a larger range...
GAME_SCALE = 64  # ...in a scene of up to this many bodies (the game's most: a wave's start)
LARGE_CELLS = 1024  # a body whose range has more cells is not binned (`Grid.large`)
CellRange = tuple[int, int, int, int]
NONE: CellRange = (1, 1, 0, 0)  # a range of no cells


def is_large(r: CellRange) -> bool:
    """Whether a range has too many cells to bin: its body is met by its range alone."""
    return (r[2] - r[0] + 1) * (r[3] - r[1] + 1) > LARGE_CELLS


def ranges_meet(r: CellRange, q: CellRange) -> bool:
    """Whether two ranges share a cell (what binning both would find)."""
    return r[0] <= q[2] and q[0] <= r[2] and r[1] <= q[3] and q[1] <= r[3]


def exact_fence(cells: tuple[int, int, int, int], c: int, w: int, h: int
                ) -> tuple[int, int, int, int]:
    """The fence of a w x h box whose range is `cells` (their box in px, whole cells of c
    px): where the box covers exactly those cells, so that a move inside it, which the
    store does not report, changes no range. Inside out (every move reported) where the
    box cannot cover them all (a swept range) or has no width or height."""
    if w <= 0 or h <= 0:
        return NOWHERE
    x0, y0, x1, y1 = cells
    return (max(x0, x1 - c - w + 1), max(y0, y1 - c - h + 1),
            min(x1, x0 + c + w - 1), min(y1, y0 + c + h - 1))


def checked_cell(cell: int) -> int:
    """A cell size the broad phases built on cells can use (ValueError if not)."""
    if cell < 1:
        raise ValueError("grid cell size must be at least 1 px")
    return cell


@mypyc_attr(allow_interpreted_subclasses=True)  # (a test's spy derives from it)
class Grid(BroadPhase):
    """Uniform grid, one layer of cells per kind, so a probe only meets kinds it may hit.

    In each rule side `a` probes the layer of kind `b`; kinds that are never looked up are
    never binned, so moving one costs only working out its range.

    Swept kinds are binned by the union of their boxes at the start and end of the tick. A
    body that stopped keeps the range of its last motion until it next changes. While few
    bodies move in a scene of the game's scale, a body's fence is its cells: the store does
    not report it while its box stays inside them (one that moves on keeps the cells it is
    entering), a superset, which is safe, so crossing a cell edge re-bins once, not on
    entering and again on leaving, and the last answer stands more often. When many move
    (a storm), or the scene is larger, larger ranges would only add candidates (a quarter
    more at 10,000 bodies): a body's fence is then where its box covers exactly its cells
    (`exact_fence`), so its range stays exact and a move within the same cells, a sprite
    jittering on the spot, is not heard.

    A body whose range covers more than LARGE_CELLS cells (one the size of a world, or
    swept across one in a tick) is not binned: it is kept aside in `large` and met by
    ranges, against every body of the other side, so its cost grows with the bodies, not
    with its area (binning one swept a million pixels took a minute).
    """

    name = "grid"
    STRIDE = 1 << 16  # cell key = cy * STRIDE + cx; coordinates stay far inside +-2**20 px

    def __init__(self, cell: int = DEFAULT_CELL) -> None:
        self.cell = checked_cell(cell)
        self.move_buffer = []
        self.layers: dict[int, dict[int, list[Body]]] = {}
        # Per layer, how many binned cells each cell row holds: a probe whose rows are all
        # empty in the other layer skips its cells at the cost of one look-up per row.
        self.rows: dict[int, dict[int, int]] = {}
        self.ranges: dict[int, CellRange] = {}  # every live body's, binned or not
        self.large: dict[int, dict[int, Body]] = {}  # per kind, its bodies too large to bin
        self.rebins = 0  # how many times a body changed cells (for the study and tests)
        self.version = 0  # moves whenever a body's range does, or a body comes or goes
        self._last: tuple[int, Sequence[Group], tuple[Pair, ...]] | None = None  # last answer

    # --- keeping the cells in step with the store --------------------------------------------
    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        """Range every body and bin those of the probed kinds afresh (on attaching)."""
        kept(self.move_buffer).clear()
        self.layers = {kind: {} for kind in scene.by_kind}
        self.rows = {kind: {} for kind in scene.by_kind}
        self.ranges = {}
        self.large = {}
        kept(self.move_buffer).extend(body for bodies in scene.by_kind.values() for body in bodies)
        self._drain(scene.tick, kinds)
        self.version += 1

    def _drain(self, tick: int, kinds: KindSets) -> None:
        """Apply the move buffer: what was added, removed, resized or moved out of its
        fence. Every body's cell range is kept (a probe's too, so a query need not work it
        out); only bodies of probed kinds are binned. The version moves when any range
        does. Each body drained gets its cells as its fence while few moved in a scene of
        the game's scale, else its exact fence."""
        swept, probed = kinds
        ranges = self.ranges
        c = self.cell
        changed = False
        buffer = kept(self.move_buffer)
        loose = len(buffer) <= FEW_MOVES and len(ranges) <= GAME_SCALE
        for body in buffer:
            if not body.alive:
                old = ranges.get(body.id)
                if old is not None:
                    if body.kind in probed:
                        self._move_large(body, old, None)
                    del ranges[body.id]
                    changed = True
                continue
            if body.moved_tick == tick and body.kind in swept:
                x0, y0, x1, y1 = tick_box(body, tick)
            else:  # where it is: tick_box's answer, without the call (most drained bodies)
                x0, y0 = body.x, body.y
                x1, y1 = x0 + body.w, y0 + body.h
            cx0 = x0 // c
            cy0 = y0 // c
            cx1 = (x1 - 1) // c
            cy1 = (y1 - 1) // c
            new = (cx0, cy0, cx1, cy1)
            old = ranges.get(body.id)
            if new != old:
                if body.kind in probed:
                    if ((cx1 - cx0 + 1) * (cy1 - cy0 + 1) > LARGE_CELLS  # (is_large, inline)
                            or (self.large and old is not None and is_large(old))):
                        self._move_large(body, old, new)  # (rare: a body too large to bin)
                    elif old is None:
                        self._bin(body, new)
                    else:
                        self._unbin(body, old, new)
                        self._bin(body, new, old)
                    self.rebins += 1
                ranges[body.id] = new
                changed = True
            box = (cx0 * c, cy0 * c, (cx1 + 1) * c, (cy1 + 1) * c)
            body.fence = box if loose else exact_fence(box, c, body.w, body.h)
        buffer.clear()
        if changed:
            self.version += 1

    def _bin(self, body: Body, r: CellRange, keep: CellRange = NONE) -> None:
        """Put the body in the cells of range r but those of `keep` (where it already is:
        a body that moves across a cell edge changes only the cells on either side)."""
        layer = self.layers.setdefault(body.kind, {})
        rows = self.rows.setdefault(body.kind, {})
        stride = self.STRIDE
        kx0, ky0, kx1, ky1 = keep
        for cy in range(r[1], r[3] + 1):
            kept = ky0 <= cy <= ky1
            added = 0
            for cx in range(r[0], r[2] + 1):
                if kept and kx0 <= cx <= kx1:
                    continue
                added += 1
                key = cy * stride + cx
                cell = layer.get(key)
                if cell is None:
                    layer[key] = [body]
                else:
                    cell.append(body)
            if added:
                rows[cy] = rows.get(cy, 0) + added

    def _move_large(self, body: Body, old: CellRange | None, new: CellRange | None) -> None:
        """Take the body out of range `old` and put it in `new` (None: none), either of
        which may be too large to bin: such a body is kept in `large` instead of cells."""
        if old is not None:
            if is_large(old):
                large = self.large[body.kind]
                del large[body.id]
                if not large:
                    del self.large[body.kind]
            else:
                self._unbin(body, old)
        if new is not None:
            if is_large(new):
                self.large.setdefault(body.kind, {})[body.id] = body
            else:
                self._bin(body, new)

    def _unbin(self, body: Body, r: CellRange, keep: CellRange = NONE) -> None:
        """Take the body out of the cells of range r but those of `keep`. (It walks the
        cells as `_bin` does, written out in both: a shared walk doubled a re-bin's cost.)"""
        layer = self.layers[body.kind]
        rows = self.rows[body.kind]
        stride = self.STRIDE
        kx0, ky0, kx1, ky1 = keep
        for cy in range(r[1], r[3] + 1):
            kept = ky0 <= cy <= ky1
            removed = 0
            for cx in range(r[0], r[2] + 1):
                if kept and kx0 <= cx <= kx1:
                    continue
                removed += 1
                key = cy * stride + cx
                cell = layer[key]
                cell.remove(body)
                if not cell:
                    del layer[key]
            if removed:
                left = rows[cy] - removed
                if left:
                    rows[cy] = left
                else:
                    del rows[cy]

    # --- queries ---------------------------------------------------------------------------
    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> tuple[Pair, ...]:
        """The candidates: a function of the cell ranges and the groups only, so while no
        range changed (the version) the same groups get last query's answer again (a
        tuple, so it can be handed out as it is)."""
        if self.move_buffer:
            self._drain(scene.tick, kinds)
        last = self._last
        if last is not None and last[0] == self.version and last[1] is groups:
            return last[2]
        out = tuple(self._query(groups, kinds))
        self._last = (self.version, groups, out)
        return out

    def _query(self, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        out: list[Pair] = []
        stride = self.STRIDE
        ranges = self.ranges
        probed = kinds.probed
        all_rows = self.rows
        layers = self.layers
        all_large = self.large
        for rule, probes, others in groups:
            rows = all_rows.get(rule.b)
            kind_a = rule.a
            if rule.b in all_large:  # (rare: a body of the other side too large to bin)
                self._query_large(rule, probes, others, out)
                continue
            if not rows:
                continue
            if (kind_a in probed and kind_a not in all_large
                    and rows.keys().isdisjoint(all_rows.get(kind_a, ()))):
                continue  # both kinds binned, and no cell row holds both: nothing can meet
            layer = layers[rule.b]
            allowed = None if rule.zone is None else {b.id for b in others}
            for probe in probes:
                # Its range: exact, or for a resting swept body a safe superset.
                cx0, cy0, cx1, cy1 = ranges[probe.id]
                if cy0 == cy1:
                    if cy0 not in rows:
                        continue  # its one row holds no body of the other kind
                    if cx0 == cx1:
                        for other in layer.get(cy0 * stride + cx0, ()):
                            if allowed is None or other.id in allowed:
                                out.append(ordered(probe, other, rule))
                        continue
                if (cx1 - cx0 + 1) * (cy1 - cy0 + 1) > LARGE_CELLS:  # (is_large, inline)
                    self._query_large(rule, (probe,), others, out)
                    continue
                if cy0 != cy1:
                    for cy in range(cy0, cy1 + 1):
                        if cy in rows:
                            break
                    else:
                        continue  # no row of the probe holds any body of the other kind
                seen: set[int] = set()
                for cy in range(cy0, cy1 + 1):
                    for cx in range(cx0, cx1 + 1):
                        for other in layer.get(cy * stride + cx, ()):
                            oid = other.id
                            if oid not in seen and (allowed is None or oid in allowed):
                                seen.add(oid)
                                out.append(ordered(probe, other, rule))
        if len(out) > 1:
            out.sort(key=pair_key)
        return out

    def _query_large(self, rule: PairRule, probes: Sequence[Body], others: Sequence[Body],
                     out: list[Pair]) -> None:
        """Where a body is too large to bin (one of the other side, or the probe): each
        probe meets every other body whose range shares a cell with its own, what the
        cells would find, and the other side's bodies need not be binned."""
        ranges = self.ranges
        for probe in probes:
            r = ranges[probe.id]
            for other in others:
                if ranges_meet(r, ranges[other.id]):
                    out.append(ordered(probe, other, rule))
