"""detect(store) -> (contacts, stats): reduce, quick test, thorough test. Reads only.

Step 1 keeps only pairs of kinds the rules table lists (inside their zones, judged on each
body's box over the whole tick) and asks the broad phase for candidates; step 2 tests boxes
(swept boxes for swept entries); step 3 tests pixels where the entry says the shape is not
its box, or walks the relative motion for swept entries. Every contact carries its time of
first touch within the tick; they come out in (time, low id, high id) order. Step 4,
response, is `response.respond`.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from typing import Protocol

import pygame

from invaders.engine import predicates
from invaders.engine.body import Body, tick_box
from invaders.engine.broadphase import (
    BroadPhase,
    Brute,
    Group,
    KindSets,
    Pair,
    Scene,
    SortAndSweep,
)
from invaders.engine.grid import DEFAULT_CELL, Grid
from invaders.engine.rects import CellRects
from invaders.engine.rules import Motion, PairRule, RuleTable, Zone
from invaders.engine.stats import CollisionStats, Contact, contact_time, impact_time
from invaders.engine.store import BodyStore

QuickTest = Callable[[tuple[int, int, int, int], tuple[int, int, int, int]], bool]
BROADPHASES = ("auto", "rects", "grid", "numpy", "brute", "sweep")
DEFAULT_BROADPHASE = "auto"  # the game's, the command line's and the sprite collider's
# Bodies from which the grid beats the cell rects (brute force in C), as measured on storms
# (30 ticks, 5-7 rounds taking turns frame by frame, the grid's time over the rects'): 100
# bodies 1.07, 200 1.04, 250 0.95, 300 0.94, 400 0.94. On a game's frames the rects take
# three quarters of the grid's time.
GRID_FROM = 220
GRID_UNTIL = 160  # below this an automatic choice goes back to the rects (no flapping)
# Bodies from which the numpy broad phase beats the grid, as measured on storms on a busy
# 2-core machine (ms of detection a tick, grid then numpy). `invaders study` (docs/study/
# scaling.csv, each a median of three plays): 300 bodies 0.86 and 1.56, 1,000 2.91 and 2.44,
# 3,000 9.79 and 4.15, 10,000 29.19 and 9.92; `invaders bench --big` (20 rounds, turns frame
# by frame) at 1,000: 2.44 and 2.24. In steady state over 9 interleaved rounds, storms of
# 400, 500, 600, 700 and 900 bodies gave the grid's time over numpy's as 0.62, 0.68, 0.76,
# 0.88 and 1.15: the two meet between 700 and 900 bodies, and the switch sits between.
NUMPY_FROM = 800
NUMPY_UNTIL = 600  # below this an automatic choice goes back to the grid (no flapping)
# The automatic choice's broad phases, smallest scenes first: each with the body count
# from which it is taken, and the count below which it is left again.
TIERS = (("rects", 0, 0), ("grid", GRID_FROM, GRID_UNTIL), ("numpy", NUMPY_FROM, NUMPY_UNTIL))
SWEPT, LANDING = Motion.SWEPT, Motion.LANDING  # an enum member by name costs a slow look-up
_solid_mask = predicates.solid_mask
_kept_swept_mask = predicates.kept_swept_mask
_first_touch = predicates.first_touch
_substeps = predicates.substeps
_new = tuple.__new__  # a NamedTuple from a tuple: half the cost of its own constructor


class Adaptive:
    """The cell rects for game-sized scenes, the grid for bigger ones and the numpy broad
    phase for the biggest, by the body count (`TIERS`); the one in use is rebuilt from the
    scene on a change. All give the pairs brute force would test whose boxes may meet, so
    switching changes no contact. The detector calls `fit` when bodies come or go (the
    only time the count moves); between, `pairs` is the active one's own, so choosing
    costs a tick nothing."""

    name = "auto"

    def __init__(self, cell: int = DEFAULT_CELL) -> None:
        self._cell = cell
        self.move_buffer: list[Body] = []
        self._take(0)

    @property
    def cell(self) -> int:
        return self.active.cell

    def _take(self, tier: int) -> None:
        """Tier `tier` of `TIERS` made active, and the body counts it is kept between. The
        new one fills its move buffer from the store's: the same list, nothing copied."""
        self._tier = tier
        self._low = TIERS[tier][2]
        self._high = TIERS[tier + 1][1] if tier + 1 < len(TIERS) else sys.maxsize
        self.active: BroadPhase = make_broadphase(TIERS[tier][0], self._cell)
        self.active.move_buffer = self.move_buffer
        self.pairs = self.active.pairs

    def rebuild(self, scene: Scene, kinds: KindSets) -> None:
        """The tier for the scene's body count, built from the scene itself."""
        self._choose(sum(len(bodies) for bodies in scene.by_kind.values()))
        self.active.rebuild(scene, kinds)  # the buffer is moot

    def fit(self, store: BodyStore, kinds: KindSets) -> None:
        """Bodies came or went: a new tier if the count left the one in use's."""
        n = store.size
        if not self._low <= n < self._high:
            self._choose(n)
            self.active.rebuild(store, kinds)

    def _choose(self, n: int) -> None:
        """The tier for n bodies: a tier up to the one in use is kept down to its lower
        count, one above it is taken from its higher."""
        tier = 0
        for place, (_, start, keep) in enumerate(TIERS):
            if n >= (keep if place <= self._tier else start):
                tier = place
        if tier != self._tier:
            self._take(tier)

    def in_zone(self, scene: Scene, kind: int, zone: ZoneIndex, kinds: KindSets) -> list[Body]:
        in_zone = getattr(self.active, "in_zone", None)
        if in_zone is not None:
            return in_zone(scene, kind, zone, kinds)
        return _tested_in_zone(scene, kind, zone, kinds)


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


class DetectionObserver(Protocol):
    """Something that watches each detection: an overlay, a timer, a recorder, the oracle.

    `before` runs as detection starts, `after` once it is done and before any response, so
    the scene is exactly what the detector saw. Observers are called in the order they were
    added after, and in the reverse order before: the first one added wraps the tightest.
    """

    def before(self, scene: Scene) -> None: ...

    def after(self, scene: Scene, candidates: Sequence[Pair], contacts: Sequence[Contact],
              stats: CollisionStats) -> None: ...


class ZoneIndex:
    """A zone's boxes binned in coarse cells, so that testing a body costs the same however
    many boxes the zone has (a storm repeats the saucer lane in every tile)."""

    CELL = 64

    def __init__(self, zone: Zone) -> None:
        self.zone = zone
        self.cells: dict[tuple[int, int], list[tuple[int, int, int, int]]] = {}
        c = self.CELL
        for zx, zy, zw, zh in zone:
            for cy in range(zy // c, (zy + zh - 1) // c + 1):
                for cx in range(zx // c, (zx + zw - 1) // c + 1):
                    self.cells.setdefault((cx, cy), []).append((zx, zy, zx + zw, zy + zh))

    def within(self, bodies: Sequence[Body], tick: int) -> list[Body]:
        """Those of the bodies whose box over the tick meets the zone, in their order."""
        return [body for body in bodies if self.holds(body, tick)]

    def holds(self, body: Body, tick: int) -> bool:
        """Whether the body's box over the whole tick meets the zone: a body that crosses
        it within one tick is in it."""
        x0, y0, x1, y1 = tick_box(body, tick)
        c = self.CELL
        cells = self.cells
        for cy in range(y0 // c, (y1 - 1) // c + 1):
            for cx in range(x0 // c, (x1 - 1) // c + 1):
                for bx0, by0, bx1, by1 in cells.get((cx, cy), ()):
                    if x0 < bx1 and bx0 < x1 and y0 < by1 and by0 < y1:
                        return True
        return False


def _shape_mask(body: Body, rule: PairRule) -> pygame.mask.Mask:
    """What the entry tests of the body: its mask, or its whole box."""
    return body.mask if body.kind in rule.masked else _solid_mask(body.w, body.h)


class Detector:
    """A rules table and a broad phase; holds only the broad phase's own bookkeeping."""

    def __init__(self, broadphase: BroadPhase, rules: RuleTable,
                 quick: QuickTest | None = None) -> None:
        self.broadphase = broadphase
        self.rules = rules
        self.quick = quick  # None: exact box overlap, inlined; else a study's stand-in
        self.kinds = KindSets(rules.swept_kinds(), rules.probed_kinds())
        self.eroding = rules.eroding
        self.observers: list[DetectionObserver] = []
        self._table = tuple((rule, rule.a, rule.b, None if rule.zone is None
                             else ZoneIndex(rule.zone)) for rule in rules)
        self._plans: dict[int, tuple] = {}  # kinds present (bit mask) -> groups that apply
        # What holds until a body comes or goes (the store's membership moves): the plan,
        # the pairs its zone-less groups allow, and the counters of a tick with no pairs.
        self._planned_for: BodyStore | None = None
        self._membership = 0  # the store's membership when planned (never a store's own)
        self._groups: list[Group] = []
        self._zoned: list[tuple[int, PairRule, ZoneIndex]] = []
        self._allowed = 0
        self._quiet = CollisionStats()
        # A broad phase that keeps state answers the same groups the same until it hears of
        # a change (its move buffer fills): the groups last asked, and the answer.
        self._asked: Sequence[Group] | None = None
        self._answer: Sequence[Pair] = ()
        self._settled = 0  # the store's membership when it was given for groups with no zone
        # (bodies, pairs allowed, candidates) -> the counters of a tick whose candidates all
        # parted at the quick test
        self._quiet_by_count: dict[tuple[int, int, int], CollisionStats] = {}
        self._parted: Sequence[Pair] = ()  # the last pairs that all parted, and the counters
        self._parted_stats = CollisionStats()
        # A broad phase may find the bodies in a zone faster than testing each one.
        self._in_zone = getattr(broadphase, "in_zone", None) or _tested_in_zone
        self._fit = getattr(broadphase, "fit", None)  # told when bodies come or go

    def detect(self, store: BodyStore) -> tuple[list[Contact], CollisionStats]:
        """This tick's contacts in (time, low id, high id) order, and the counters."""
        observers = self.observers
        if observers:
            for observer in reversed(observers):
                observer.before(store)
        if store.membership == self._settled and not self.broadphase.move_buffer:
            # The usual tick: no body came, went or was heard since the broad phase last
            # answered the same groups, with no zone to filter: the same candidates.
            pairs = self._answer
            if not pairs and not observers:  # (most ticks at game scale)
                return [], self._quiet
            allowed = self._allowed
            zoned = ()
        else:
            if store.membership != self._membership:  # (bodies came or went, or new to us)
                self._replan(store)
            broadphase = self.broadphase
            groups = self._groups
            allowed = self._allowed
            zoned = self._zoned
            if zoned:
                heard = bool(broadphase.move_buffer)  # first: finding a zone's bodies may drain it
                groups, in_zones = self._with_zones(store, groups, zoned)
                allowed += in_zones
            else:
                heard = broadphase.move_buffer  # (its truth is all that is read)
            if groups is self._asked and not heard:
                pairs = self._answer  # nothing heard since the same groups were asked
            elif groups:
                pairs = broadphase.pairs(store, groups, self.kinds)
                if broadphase.move_buffer is not None:  # it keeps state: the answer holds
                    self._asked = groups
                    self._answer = pairs
                    if not zoned:
                        self._settled = store.membership
            else:
                pairs = ()
        if not pairs:  # the usual tick at game scale: the same counters as last time
            contacts: list[Contact] = []
            stats = self._quiet if not zoned else self._quiet_counters(store.size, allowed)
            if observers:
                for observer in observers:
                    observer.after(store, pairs, contacts, stats)
            return contacts, stats

        tick = store.tick
        quick = self.quick
        contacts = []
        rect_hits = mask_tests = mask_hits = swept_tests = 0  # every pair gets a rect test
        for a, b, rule in pairs:
            if quick is not None and not quick(_xywh(a, tick, rule), _xywh(b, tick, rule)):
                continue
            motion = rule.motion
            if motion is SWEPT:
                # The quick test, predicates.swept_box_overlap inlined (the hot path): b's box
                # moved by the pair's motion relative to a, from offset (ox, oy) to (ex, ey),
                # against a's box. The x axis first: most pairs part there.
                a_moved = a.moved_tick == tick
                b_moved = b.moved_tick == tick
                apx = a.px if a_moved else a.x
                ox = (b.px if b_moved else b.x) - apx
                ex = b.x - a.x
                if ex < ox:
                    if not (ex < a.w and ox + b.w > 0):
                        continue
                elif not (ox < a.w and ex + b.w > 0):
                    continue
                apy = a.py if a_moved else a.y
                oy = (b.py if b_moved else b.y) - apy
                ey = b.y - a.y
                if ey < oy:
                    if not (ey < a.h and oy + b.h > 0):
                        continue
                elif not (oy < a.h and ey + b.h > 0):
                    continue
                swept_tests += 1  # a rect hit too: counted in at the end
                contact = self._walk(a, b, rule, tick, apx, apy, ox, oy, ex - ox, ey - oy)
                if contact is not None:
                    contacts.append(contact)
                continue
            if quick is None and not (a.x < b.x + b.w and b.x < a.x + a.w
                                      and a.y < b.y + b.h and b.y < a.y + a.h):
                continue
            rect_hits += 1
            if rule.needs_pixels:
                mask_tests += 1
                point = predicates.masks_overlap(
                    _shape_mask(a, rule), a.x, a.y, _shape_mask(b, rule), b.x, b.y)
                if point is None:
                    continue
                mask_hits += 1
            else:
                point = (max(a.x, b.x), max(a.y, b.y))
            if motion is LANDING:
                contacts.append(_new(Contact, (tick, impact_time(1, 1), a.id, b.id, a.kind,
                                               b.kind, a.x, a.y, b.x, b.y, *point, rule)))
                continue
            # Discrete: found where they landed; its time is when they first touched.
            apx, apy = a.start_of_tick(tick)
            bpx, bpy = b.start_of_tick(tick)
            walked = self._walk(a, b, rule, tick, apx, apy, bpx - apx, bpy - apy,
                                (b.x - bpx) - (a.x - apx), (b.y - bpy) - (a.y - apy))
            time = walked.time if walked is not None else impact_time(1, 1)
            contacts.append(_new(Contact, (tick, time, a.id, b.id, a.kind, b.kind, a.x, a.y,
                                           b.x, b.y, *point, rule)))
        if contacts or rect_hits or swept_tests:
            if len(contacts) > 1:  # by time; ties stay in the pairs' (low id, high id) order
                contacts.sort(key=contact_time)
            n = store.size
            stats = _new(CollisionStats, (n, n * (n - 1) // 2, allowed, len(pairs), len(pairs),
                                          rect_hits + swept_tests, mask_tests, mask_hits,
                                          swept_tests, len(contacts)))
        elif pairs is self._parted and allowed == self._parted_stats.allowed_pairs:
            stats = self._parted_stats  # the same pairs parted again, as on most such ticks
        else:  # every pair parted at the quick test, as on most ticks with pairs
            stats = self._parted_stats = self._quiet_counters(store.size, allowed, len(pairs))
            self._parted = pairs
        if observers:
            for observer in observers:
                observer.after(store, pairs, contacts, stats)
        return contacts, stats

    def _replan(self, store: BodyStore) -> None:
        """A body came or went (or the store is new to this detector, or its broad phase
        was detached): the plan for the kinds present now (kept per set of kinds, for the
        store it was made for), the pairs its zone-less groups allow, and the counters of a
        tick that finds no pairs."""
        broadphase = self.broadphase
        if store.listener is not broadphase and broadphase.move_buffer is not None:
            # A broad phase that keeps state hears of every later change from the store;
            # it starts from the store as it is. (Stateless ones need not listen.)
            store.attach(broadphase)
            broadphase.rebuild(store, self.kinds)
        if self._planned_for is not store:  # plans hold a store's own lists of bodies
            self._plans.clear()
            self._planned_for = store
        self._membership = store.membership
        self._asked = None  # (a broad phase that fits itself to the count may start afresh)
        if self._fit is not None:
            self._fit(store, self.kinds)
        plan = self._plans.get(store.present)
        if plan is None:
            plan = self._plans[store.present] = self._plan(store)
        self._groups, self._zoned = plan
        allowed = 0
        for _, side_a, side_b in self._groups:
            allowed += len(side_a) * len(side_b)
        self._allowed = allowed
        n = store.size  # a body came or went: nearly always counters not seen before
        self._quiet = _new(CollisionStats, (n, n * (n - 1) // 2, allowed, 0, 0, 0, 0, 0, 0, 0))

    def _quiet_counters(self, n: int, allowed: int, candidates: int = 0) -> CollisionStats:
        """The counters of a tick whose candidates (if any) all parted at the quick test
        (kept: most ticks are one, and they repeat while the counts do)."""
        key = (n, allowed, candidates)
        stats = self._quiet_by_count.get(key)
        if stats is None:
            if len(self._quiet_by_count) > 255:
                self._quiet_by_count.clear()
            stats = self._quiet_by_count[key] = _new(CollisionStats, (
                n, n * (n - 1) // 2, allowed, candidates, candidates, 0, 0, 0, 0, 0))
        return stats

    def _plan(self, store: BodyStore
              ) -> tuple[list[Group], list[tuple[int, PairRule, ZoneIndex]]]:
        """For the kinds the store has now: the groups of the entries without a zone (the
        store's own lists, the same every tick) and, by place in the table, the entries
        with one and their zones (filtered every tick)."""
        by_kind = store.by_kind
        present = store.present
        groups: list[Group] = []
        zoned: list[tuple[int, PairRule, ZoneIndex]] = []
        for rule, kind_a, kind_b, zone in self._table:
            if present >> kind_a & 1 and present >> kind_b & 1:
                if zone is None:
                    groups.append((rule, by_kind[kind_a], by_kind[kind_b]))
                else:
                    zoned.append((len(groups) + len(zoned), rule, zone))
        return groups, zoned

    def _with_zones(self, store: BodyStore, fixed: list[Group],
                    zoned: list[tuple[int, PairRule, ZoneIndex]]) -> tuple[list[Group], int]:
        """The tick's groups in table order: the fixed ones, and each zoned entry with the
        bodies of its sides inside its zone (left out if a side has none); and the pairs
        those zoned groups allow. With none in, the groups are `fixed` itself (so the grid
        can answer the same groups from its last look)."""
        groups = fixed
        allowed = 0
        in_zone = self._in_zone
        skipped = 0  # zoned entries left out before this one
        for place, rule, zone in zoned:
            side_a = in_zone(store, rule.a, zone, self.kinds)
            side_b = in_zone(store, rule.b, zone, self.kinds) if side_a else ()
            if side_a and side_b:
                if groups is fixed:
                    groups = list(fixed)
                groups.insert(place - skipped, (rule, side_a, side_b))
                allowed += len(side_a) * len(side_b)
            else:
                skipped += 1
        return groups, allowed

    def _walk(self, a: Body, b: Body, rule: PairRule, tick: int, apx: int, apy: int,
              ox: int, oy: int, dx: int, dy: int) -> Contact | None:
        """The pixel walk along the pair's relative motion (dx, dy), from a's start (apx,
        apy) with b at (ox, oy) from it: the first touch, or None. (The quick test is the
        caller's.) The side that never erodes is the one swept, so its swept mask can be
        kept; `predicates.first_swept_contact`'s first step, the swept mask's one test, is
        inlined: most walks end there."""
        masked = rule.masked  # _shape_mask, inlined
        a_mask = a.mask if a.kind in masked else _solid_mask(a.w, a.h)
        b_mask = b.mask if b.kind in masked else _solid_mask(b.w, b.h)
        b_swept = b.kind not in self.eroding
        if b_swept:
            fixed, moving, sox, soy, sdx, sdy = a_mask, b_mask, ox, oy, dx, dy
        else:  # b erodes (a shield): a is swept against it
            fixed, moving, sox, soy, sdx, sdy = b_mask, a_mask, -ox, -oy, -dx, -dy
        if dx or dy:
            swept = _kept_swept_mask((moving, sdx, sdy))
            if swept is None:
                swept = predicates.swept_mask(moving, sdx, sdy)
            if fixed.overlap(swept, (sox + sdx if sdx < 0 else sox,
                                     soy + sdy if sdy < 0 else soy)) is None:
                return None
        found = _first_touch(fixed, moving, sox, soy, sdx, sdy,
                             a.shaped_tick == tick or b.shaped_tick == tick)
        if found is None:
            return None
        step, steps, (hx, hy) = found
        sx, sy = _substeps(sdx, sdy)[step]
        if b_swept:  # the fixed side placed at its own point of the tick, the other from it
            x, y = a.x, a.y
            ax, ay = (x, y) if x == apx and y == apy else _at(apx, apy, x, y, step, steps)
            bx, by = ax + ox + sx, ay + oy + sy
            hx, hy = ax + hx, ay + hy
        else:
            bx, by = _at(apx + ox, apy + oy, b.x, b.y, step, steps)
            ax, ay = bx - ox + sx, by - oy + sy
            hx, hy = bx + hx, by + hy
        return _new(Contact, (tick, impact_time(step, steps), a.id, b.id, a.kind, b.kind,
                              ax, ay, bx, by, hx, hy, rule))


def _tested_in_zone(scene: Scene, kind: int, zone: ZoneIndex, kinds: KindSets) -> list[Body]:
    """The bodies of a kind in a zone, each tested (for broad phases with no faster way)."""
    return zone.within(scene.by_kind[kind], scene.tick)


def _xywh(body: Body, tick: int, rule: PairRule) -> tuple[int, int, int, int]:
    """The box a study's quick test sees: over the tick's motion for swept entries."""
    x0, y0, x1, y1 = tick_box(body, tick, rule.motion is Motion.SWEPT)
    return x0, y0, x1 - x0, y1 - y0


def _at(x0: int, y0: int, x1: int, y1: int, step: int, steps: int) -> tuple[int, int]:
    """A body's own position `step` substeps of `steps` into the tick."""
    if steps == 0 or step == steps or (x0 == x1 and y0 == y1):  # at the end, or it stayed
        return x1, y1
    return (x0 + predicates.round_div((x1 - x0) * step, steps),
            y0 + predicates.round_div((y1 - y0) * step, steps))
