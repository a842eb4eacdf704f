"""Cell rects: the grid's cells without the grid. Each body's cells as one `pygame.Rect`,
and each probe tested against a whole kind's rects at once, in C (`Rect.collidelistall`).

Brute force, but pygame's loop over a kind's 55 rects costs less than the grid's walk over
a probe's cells in Python, and a body that crosses a cell edge changes one rect in place
instead of leaving and joining cell lists. So at game scale it answers sooner than the
grid; from a few hundred bodies the grid's locality wins (`detector.GRID_FROM`). Two
bodies' rects overlap exactly when their cell ranges share a cell, and the rects follow the
grid's rules (a body's cells are its fence while few move at game scale, else its exact
fence; a resting swept body keeps the range of its last motion), so the candidates are the
grid's, pair for pair.
"""

from __future__ import annotations

import copy
from bisect import insort
from collections.abc import Sequence
from operator import attrgetter
from typing import Any

import pygame

from invaders.engine.body import Body, copy_bodies, tick_box
from invaders.engine.broadphase import BroadPhase, Group, KindSets, Pair, Scene, kept, pair_key
from invaders.engine.grid import DEFAULT_CELL, FEW_MOVES, GAME_SCALE, checked_cell, exact_fence
from invaders.engine.rules import PairRule

_ID = attrgetter("id")
MANY = 8  # rects from which a lone probe is first tested against their union
READY_KEPT = 32  # groups made ready and kept (one for each set of kinds present)
# A group made ready to query: its rule, sides, kinds, and the rects of each side.
Ready = tuple[PairRule, Sequence[Body], Sequence[Body], int, int, list[pygame.Rect],
              list[pygame.Rect]]


# A pygame Rect holds 32-bit numbers and sums them so (x + w wraps past 2**31 - 1, and
# larger numbers are cut to 32 bits): its edges are kept within +-EDGE px.
EDGE = 2**30 - 1


def held(start: int, end: int) -> tuple[int, int]:
    """A span's edges (start <= end) held within +-EDGE: one past it stands at it, a pixel
    wide. Spans that overlapped still overlap (held, start < end stays so); spans apart
    may come to overlap, which costs a candidate, never a contact."""
    return min(max(start, -EDGE), EDGE - 1), min(max(end, 1 - EDGE), EDGE)


class CellRects(BroadPhase):
    """Per kind, its live bodies in id order and beside them their cells' rects."""

    name = "rects"

    def __init__(self, cell: int = DEFAULT_CELL) -> None:
        self.cell = checked_cell(cell)
        self.move_buffer = []
        self.bodies: dict[int, list[Body]] = {}
        self.rects: dict[int, list[pygame.Rect]] = {}  # rects[kind][i] is bodies[kind][i]'s
        self.rect_of: dict[int, pygame.Rect] = {}  # body id -> its rect (the same object)
        # Per kind, a box round all its rects: their union when made, grown as they move,
        # made again when a body comes or goes (None until needed).
        self.bounds: dict[int, pygame.Rect | None] = {}
        self._ready: dict[int, tuple[Sequence[Group], list[Ready]]] = {}
        self._made: tuple[Sequence[Group], list[Ready]] = ((), [])  # the last made ready

    def __deepcopy__(self, memo: dict[int, Any]) -> CellRects:
        """A copy with rects of its own (pygame copies a rect several times faster than
        Python's generic copy), each beside its body as here; the groups made ready are
        not kept (they are the original's, and made again when asked)."""
        clone = CellRects.__new__(CellRects)
        memo[id(self)] = clone
        clone.cell = self.cell
        clone.move_buffer = copy.deepcopy(self.move_buffer, memo)
        clone.bodies = {kind: copy_bodies(bodies, memo) for kind, bodies in self.bodies.items()}
        clone.rects = {kind: [rect.copy() for rect in rects] for kind, rects in self.rects.items()}
        clone.rect_of = {body.id: rect for kind, bodies in clone.bodies.items()
                         for body, rect in zip(bodies, clone.rects[kind], strict=True)}
        clone.bounds = {kind: None if bound is None else bound.copy()
                        for kind, bound in self.bounds.items()}
        clone._ready, clone._made = {}, ((), [])
        return clone

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        """Every body's rect afresh (on attaching)."""
        kept(self.move_buffer).clear()
        self.bodies = {kind: [] for kind in scene.by_kind}
        self.rects = {kind: [] for kind in scene.by_kind}
        self.rect_of = {}
        self.bounds = dict.fromkeys(scene.by_kind)
        self._ready = {}
        self._made = ((), [])
        kept(self.move_buffer).extend(body for bodies in scene.by_kind.values() for body in bodies)
        self._drain(scene.tick, kinds)

    def _drain(self, tick: int, kinds: KindSets) -> None:
        """Apply the move buffer: each body's rect is the cells its box covers (over the
        tick's motion for swept kinds), changed in place; the fence is the same box while
        few moved in a scene of the game's scale, else the exact fence (as the grid's)."""
        swept = kinds.swept
        rect_of = self.rect_of
        bounds = self.bounds
        c = self.cell
        buffer = kept(self.move_buffer)
        loose = len(buffer) <= FEW_MOVES and len(rect_of) <= GAME_SCALE
        for body in buffer:
            rect = rect_of.get(body.id)
            if not body.alive:
                if rect is not None:
                    self._forget(body)
                continue
            if body.moved_tick == tick and body.kind in swept:
                x0, y0, x1, y1 = tick_box(body, tick)
            else:  # where it is: tick_box's answer, without the call (most drained bodies)
                x0, y0 = body.x, body.y
                x1, y1 = x0 + body.w, y0 + body.h
            # The cells' box (never inside out: a box of no width still has its left edge).
            fx0 = x0 // c * c
            fy0 = y0 // c * c
            fx1 = -(-x1 // c) * c
            fy1 = -(-y1 // c) * c
            cells = (fx0, fy0, fx1, fy1)
            body.fence = cells if loose else exact_fence(cells, c, body.w, body.h)
            if not (-EDGE <= fx0 <= fx1 <= EDGE and -EDGE <= fy0 <= fy1 <= EDGE):
                fx0, fx1 = held(fx0, fx1)
                fy0, fy1 = held(fy0, fy1)
            if rect is None:
                self._add(body, pygame.Rect(fx0, fy0, fx1 - fx0, fy1 - fy0))
            else:  # (reported: it left its fence, its old cells, or changed its size)
                rect.update(fx0, fy0, fx1 - fx0, fy1 - fy0)
                bound = bounds[body.kind]
                if bound is not None:  # grown, not made again: a box round them all will do
                    bound.union_ip(rect)
        buffer.clear()

    def _add(self, body: Body, rect: pygame.Rect) -> None:
        kind = body.kind
        bodies = self.bodies.get(kind)
        if bodies is None:  # a kind the scene did not list when rebuilt
            bodies = self.bodies[kind] = []
            self.rects[kind] = []
        rects = self.rects[kind]
        self.rect_of[body.id] = rect
        self.bounds[kind] = None
        if not bodies or bodies[-1].id < body.id:
            bodies.append(body)
            rects.append(rect)
        else:
            insort(bodies, body, key=_ID)
            rects.insert(bodies.index(body), rect)

    def _forget(self, body: Body) -> None:
        bodies = self.bodies[body.kind]
        place = bodies.index(body)
        del bodies[place]
        del self.rects[body.kind][place]
        del self.rect_of[body.id]
        self.bounds[body.kind] = None

    def _bound(self, kind: int) -> pygame.Rect:
        """The union of a kind's rects, kept (and grown as they move) until a body of the
        kind comes or goes: a box that holds them all only ever skips less."""
        rects = self.rects[kind]
        bound = self.bounds[kind] = rects[0].unionall(rects)
        return bound

    def _prepare(self, groups: Sequence[Group]) -> list[Ready]:
        """Each group with the rects of its side b: the kind's own list when the side is the
        whole kind (a side is always some of a kind's bodies, in id order), else picked.
        Kept per groups (a detector asks with the same groups while the same kinds are
        present, and the kinds' lists change in place), a few at a time."""
        ready = self._ready.get(id(groups))
        if ready is not None and ready[0] is groups:
            self._made = ready
            return ready[1]
        rects_of = self.rects
        bodies_of = self.bodies
        rect_of = self.rect_of
        made = [(rule, probes, others, rule.a, rule.b,
                 rects_of[rule.a] if len(probes) == len(bodies_of[rule.a])
                 else [rect_of[probe.id] for probe in probes],
                 rects_of[rule.b] if len(others) == len(bodies_of[rule.b])
                 else [rect_of[other.id] for other in others])
                for rule, probes, others in groups]
        whole = all(rects_a is rects_of[kind_a] and rects_b is rects_of[kind_b]
                    for _, _, _, kind_a, kind_b, rects_a, rects_b in made)
        if whole:  # (a zone's picked rects hold only for its tick)
            if len(self._ready) >= READY_KEPT:
                self._ready.clear()
            # The groups are held by the entry: their id stays theirs while it is kept.
            self._ready[id(groups)] = self._made = (groups, made)
        return made

    def pairs(self, scene: Scene, groups: Sequence[Group], kinds: KindSets) -> list[Pair]:
        """The candidates, as the grid's: each probe's rect against the other side's."""
        if self.move_buffer:
            self._drain(scene.tick, kinds)
        out: list[Pair] = []
        bounds = self.bounds
        made = self._made
        mixed = False  # pairs from more than one probe: each probe's come sorted, not all
        for rule, probes, others, kind_a, kind_b, probe_rects, rects in (
                made[1] if made[0] is groups else self._prepare(groups)):
            if len(probes) == 1:  # the usual group at game scale (a shot, the cannon)
                rect = probe_rects[0]
                if len(rects) > MANY and not rect.colliderect(bounds[kind_b]
                                                              or self._bound(kind_b)):
                    continue  # clear of them all (the shot below the rack)
                hits = rect.collidelistall(rects)
                if hits:
                    mixed = mixed or bool(out)
                    probe = probes[0]
                    probe_id = probe.id
                    for i in hits:
                        other = others[i]
                        out.append((probe, other, rule) if probe_id < other.id
                                   else (other, probe, rule))
                continue
            # Several probes: first, whether the two kinds' rects meet at all.
            bound_a = bounds[kind_a] or self._bound(kind_a)
            bound_b = bounds[kind_b] or self._bound(kind_b)
            if not bound_a.colliderect(bound_b):
                continue
            for probe, rect in zip(probes, probe_rects, strict=True):
                hits = rect.collidelistall(rects)
                if hits:
                    mixed = mixed or bool(out)
                    probe_id = probe.id
                    for i in hits:
                        other = others[i]
                        out.append((probe, other, rule) if probe_id < other.id
                                   else (other, probe, rule))
        if mixed:
            out.sort(key=pair_key)
        return out
