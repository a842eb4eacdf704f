"""detect(store) -> (contacts, stats): reduce, quick test, thorough test.

Step 1 keeps only pairs of kinds the rules table lists (inside their zones, judged on each
body's box over the whole tick) and asks the broad phase for candidates; step 2 tests boxes
(swept boxes for swept entries); step 3 tests pixels where the entry says the shape is not
its box, or walks the relative motion for swept entries. Every contact carries its time of
first touch within the tick; they come out in (time, low id, high id) order. Step 4,
response, is `response.respond`. The detector moves no body: it attaches its broad phase to
the store it is given (which then fills the broad phase's move buffer), and that is all it
changes outside itself.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import pygame

from invaders.engine import predicates
from invaders.engine.body import Body, tick_box
from invaders.engine.broadphase import BroadPhase, Group, KindSets, Pair, Scene, once_each
from invaders.engine.compiled import mypyc_attr
from invaders.engine.rules import Motion, PairRule, RuleTable, Zone
from invaders.engine.stats import CollisionStats, Contact, contact_time, impact_time
from invaders.engine.store import BodyStore

QuickTest = Callable[[tuple[int, int, int, int], tuple[int, int, int, int]], bool]
SWEPT, LANDING = Motion.SWEPT, Motion.LANDING  # an enum member by name costs a slow look-up


class DetectionObserver(Protocol):
    """Something that watches each detection: an overlay, a timer, a recorder, the oracle.

    `before` runs as detection starts, `after` once it is done and before any response, so
    the scene is exactly what the detector saw. Observers are called in the order they were
    added after, and in the reverse order before: the first one added wraps the tightest.
    """

    def before(self, scene: Scene) -> None: ...

    def after(self, scene: Scene, candidates: Sequence[Pair], contacts: Sequence[Contact],
              stats: CollisionStats) -> None: ...


class Detecting(Protocol):
    """What a world asks of its detector: a `Detector`, or what stands in its place (the
    live lab's, which times and scores one)."""

    @property
    def broadphase(self) -> BroadPhase: ...

    @property
    def observers(self) -> list[DetectionObserver]: ...

    def detect(self, store: BodyStore) -> tuple[list[Contact], CollisionStats]: ...


WIDE = 1024  # px: a body's box wider or taller meets a zone's boxes one by one
BINNED = 256  # cells: a zone's box over more is not binned


class ZoneIndex:
    """A zone's boxes binned in coarse cells, so that testing a body costs the same however
    many boxes the zone has (a storm repeats the saucer lane in every tile). Where a box
    is over BINNED cells (left unbinned: one 100,000 px square took 3 s and 1.1 GB to
    bin), or a body's box over WIDE px (it would walk every cell it covers), the body
    meets each of the zone's boxes directly instead."""

    CELL = 64

    def __init__(self, zone: Zone) -> None:
        self.zone = zone
        self.boxes = [(zx, zy, zx + zw, zy + zh) for zx, zy, zw, zh in zone]
        self.large = False  # (some box is left unbinned)
        self.cells: dict[tuple[int, int], list[tuple[int, int, int, int]]] = {}
        c = self.CELL
        for box in self.boxes:
            x0, y0, x1, y1 = box
            across, down = (x1 - 1) // c + 1 - x0 // c, (y1 - 1) // c + 1 - y0 // c
            if across * down > BINNED:  # (counted, not a range's len: a ssize_t at most)
                self.large = True
                continue
            for cy in range(y0 // c, y0 // c + down):
                for cx in range(x0 // c, x0 // c + across):
                    self.cells.setdefault((cx, cy), []).append(box)

    def __deepcopy__(self, memo: dict[int, Any]) -> ZoneIndex:
        """Itself: never changed once made (copied with every world's detector)."""
        return self

    def __reduce__(self) -> tuple[type[ZoneIndex], tuple[Zone]]:
        """Pickled as the call that makes it again from its zone."""
        return ZoneIndex, (self.zone,)

    def within(self, bodies: Sequence[Body], tick: int) -> list[Body]:
        """Those of the bodies whose box over the tick meets the zone, in their order."""
        return [body for body in bodies if self.holds(body, tick)]

    def holds(self, body: Body, tick: int) -> bool:
        """Whether the body's box over the whole tick meets the zone: a body that crosses
        it within one tick is in it."""
        x0, y0, x1, y1 = tick_box(body, tick)
        if self.large or x1 - x0 > WIDE or y1 - y0 > WIDE:  # (rare: each box met directly)
            for bx0, by0, bx1, by1 in self.boxes:
                if x0 < bx1 and bx0 < x1 and y0 < by1 and by0 < y1:
                    return True
            return False
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
    return body.mask if body.kind in rule.masked else predicates.solid_mask(body.w, body.h)


@dataclass(slots=True)
class Plan:
    """What a detector works out when bodies come or go, and keeps until they next do:
    valid while the store's membership value is the one it was made for (a value no store
    ever takes twice: bodies added or removed, or a broad phase attached or detached, give a
    new one, so an equal value means the same store with the same bodies, fed to the same
    broad phase). `tests/test_engine.py` breaks if any of those changes leaves it standing."""

    membership: int
    groups: list[Group]  # entries without a zone: (rule, the store's own lists of each side)
    zoned: list[tuple[int, PairRule, ZoneIndex]]  # entries with one, by place in the table
    bodies: int
    allowed: int  # the pairs the groups allow
    quiet: CollisionStats  # the counters of a tick with no candidate and nothing zoned
    # Those of a tick whose candidates (by their number) all parted at the quick test,
    # nothing zoned: the bodies and the pairs allowed are the plan's, so they repeat while
    # it stands (most ticks with candidates at game scale are such).
    parted: dict[int, CollisionStats]

    def __reduce__(self) -> tuple[type[Plan], tuple[Any, ...]]:
        """Pickled as the call that makes it: by default each build pickles its slots its
        own way, and neither reads the other's back (see `Body.__reduce__`)."""
        return Plan, (self.membership, self.groups, self.zoned, self.bodies, self.allowed,
                      self.quiet, self.parted)


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Detector:
    """A rules table and a broad phase, and three answers kept between ticks: the groups
    for each set of kinds present, the plan (while no body comes or goes) and the broad
    phase's last candidates (while it hears of no change). It attaches its broad phase to
    the store it is given and never moves a body."""

    def __init__(self, broadphase: BroadPhase, rules: RuleTable,
                 quick: QuickTest | None = None) -> None:
        self.broadphase = broadphase
        self.rules = rules
        self.quick = quick  # None: the exact box test; else a study's stand-in for it
        self.kinds = KindSets(rules.swept_kinds(), rules.probed_kinds())
        self.eroding = rules.eroding
        self.observers: list[DetectionObserver] = []
        self._table = tuple((rule, rule.a, rule.b, None if rule.zone is None
                             else ZoneIndex(rule.zone)) for rule in rules)
        self._one_kind = any(rule.a == rule.b for rule in rules)  # an entry's sides alike
        self._plan = Plan(0, [], [], 0, 0, CollisionStats(), {})  # membership 0: no store's
        # The groups for each set of kinds present (a bit per kind), for one store: they
        # hold that store's own lists of bodies, which it keeps for its life, so they stay
        # right for it whatever comes and goes; and the same objects each time those kinds
        # are present again, which lets a broad phase keep what it made of them.
        self._grouped: dict[int, tuple[list[Group], list[tuple[int, PairRule, ZoneIndex]]]] = {}
        self._grouped_for: BodyStore | None = None
        self._fed: BodyStore | None = None  # the store its broad phase was last attached to
        # The broad phase's last answer: the groups asked (held, so never another's by
        # identity) and its candidates. A broad phase that keeps state gives the same
        # groups the same answer until its move buffer fills, and the store puts every
        # change of a body there; a new plan drops it. (None: nothing kept.)
        self._asked: Sequence[Group] | None = None
        self._answer: Sequence[Pair] = ()

    def __deepcopy__(self, memo: dict[int, Any]) -> Detector:
        """A detector that detects as this one would, for a copied world: its broad phase
        and observers copied (what a broad phase keeps decides the candidates, and so the
        counters), its rules shared; what it works out from a store (the plan, the groups,
        the last answer) is worked out again at its first tick, from the copied store: the
        same, being a function of the same bodies (a test compares a copy's reports with
        a world's given the same inputs from the start)."""
        clone = copy.copy(self)  # (the rules, the stand-in, the kinds: shared)
        memo[id(self)] = clone
        clone.broadphase = copy.deepcopy(self.broadphase, memo)
        clone.observers = copy.deepcopy(self.observers, memo)
        clone._plan = Plan(0, [], [], 0, 0, CollisionStats(), {})
        clone._grouped, clone._grouped_for = {}, None
        clone._fed = copy.deepcopy(self._fed, memo)
        clone._asked, clone._answer = None, ()
        return clone

    def detect(self, store: BodyStore) -> tuple[list[Contact], CollisionStats]:
        """This tick's contacts in (time, low id, high id) order, and the counters: step 1
        gives the candidates, step 2 those whose boxes meet, step 3 the contacts among
        those; most ticks at game scale end at step 1 or 2 with the counters kept."""
        observers = self.observers
        if observers:
            for observer in reversed(observers):
                observer.before(store)
        plan = self._plan
        if plan.membership != store.membership:  # bodies came or went, or a new store
            plan = self._replan(store)
        if (self._asked is plan.groups and not plan.zoned
                and not self.broadphase.move_buffer):  # the plan's groups, nothing heard
            pairs, allowed = self._answer, plan.allowed
            if not pairs and not observers:  # the usual tick at game scale
                return [], plan.quiet
        else:
            pairs, allowed = self._candidates(store, plan)
        contacts: list[Contact]
        if not pairs and allowed == plan.allowed:  # nothing in a zone, no candidates
            contacts, stats = [], plan.quiet
        else:
            contacts, stats = self._tested(plan, pairs, allowed, store.tick)
        if observers:
            for observer in observers:
                observer.after(store, pairs, contacts, stats)
        return contacts, stats

    def _tested(self, plan: Plan, pairs: Sequence[Pair], allowed: int, tick: int
                ) -> tuple[list[Contact], CollisionStats]:
        """Steps 2 and 3 on the candidates, and the counters. A tick whose candidates all
        parted at the quick test has the counters of the plan's for that many (made once
        while the plan stands, when its zone-less groups are all there is)."""
        hits = self._quick_test(pairs, tick)
        n = len(pairs)
        if hits:
            contacts, mask_tests, mask_hits, swept_tests = self._thorough_test(hits, tick)
            return contacts, CollisionStats(plan.bodies, plan.quiet.naive_pairs, allowed, n,
                                            n, len(hits), mask_tests, mask_hits, swept_tests,
                                            len(contacts))
        stats = plan.parted.get(n) if allowed == plan.allowed else None
        if stats is None:
            stats = CollisionStats(plan.bodies, plan.quiet.naive_pairs, allowed, n, n)
            if allowed == plan.allowed:
                plan.parted[n] = stats
        return [], stats

    def _replan(self, store: BodyStore) -> Plan:
        """The plan for the kinds the store has now. A broad phase that keeps state is
        attached first (it hears of every later change from the store, and starts from the
        store as it is; a store it heard before is detached), which gives the store a new
        membership value; one that fits itself to the body count is told it."""
        broadphase = self.broadphase
        if store.listener is not broadphase and broadphase.move_buffer is not None:
            fed = self._fed
            if fed is not None and fed is not store and fed.listener is broadphase:
                fed.detach()  # it hears one store: the other starts afresh when next given
            store.attach(broadphase)
            broadphase.rebuild(store, self.kinds)  # (drains the buffer: nothing "heard")
            self._fed = store
        broadphase.fit(store, self.kinds)  # (may change to another broad phase)
        self._asked = None  # either way, the last answer may not stand
        if self._grouped_for is not store:
            self._grouped = {}
            self._grouped_for = store
        grouped = self._grouped.get(store.present)
        if grouped is None:
            grouped = self._grouped[store.present] = self._group(store)
        groups, zoned = grouped
        allowed = 0
        for rule, side_a, side_b in groups:
            allowed += _allowed(rule, side_a, side_b)
        n = store.size
        self._plan = Plan(store.membership, groups, zoned, n, allowed,
                          CollisionStats(n, n * (n - 1) // 2, allowed), {})
        return self._plan

    def _group(self, store: BodyStore
               ) -> tuple[list[Group], list[tuple[int, PairRule, ZoneIndex]]]:
        """The entries whose kinds the store has now: those without a zone as groups of the
        store's own lists of bodies (which it keeps up to date), those with one by place."""
        by_kind, present = store.by_kind, store.present
        groups: list[Group] = []
        zoned: list[tuple[int, PairRule, ZoneIndex]] = []
        for rule, kind_a, kind_b, zone in self._table:
            if present >> kind_a & 1 and present >> kind_b & 1:
                if zone is None:
                    groups.append((rule, by_kind[kind_a], by_kind[kind_b]))
                else:
                    zoned.append((len(groups) + len(zoned), rule, zone))
        return groups, zoned

    def _candidates(self, store: BodyStore, plan: Plan) -> tuple[Sequence[Pair], int]:
        """Step 1, reduce: the groups the rules allow (zoned entries filtered to the bodies
        in their zones), the candidate pairs the broad phase finds in them, and how many
        pairs the groups allow."""
        broadphase = self.broadphase
        heard = bool(broadphase.move_buffer)  # first: finding a zone's bodies may drain it
        groups, allowed = plan.groups, plan.allowed
        if plan.zoned:
            groups, in_zones = self._with_zones(store, plan)
            allowed += in_zones
        if not groups:
            return (), allowed
        if groups is self._asked and not heard:
            return self._answer, allowed  # nothing heard since these groups were asked
        pairs = broadphase.pairs(store, groups, self.kinds)
        if self._one_kind:
            pairs = once_each(pairs)
        if broadphase.move_buffer is not None:  # (one that keeps no state answers afresh)
            self._asked, self._answer = groups, pairs
        return pairs, allowed

    def _with_zones(self, store: BodyStore, plan: Plan) -> tuple[list[Group], int]:
        """The tick's groups in table order: the plan's, and each zoned entry with the
        bodies of its sides inside its zone (left out if a side has none); and the pairs
        those zoned groups allow. With none in, the groups are the plan's own list (so the
        broad phase's last answer can stand)."""
        groups = plan.groups
        allowed = skipped = 0  # zoned entries left out before this one
        for place, rule, zone in plan.zoned:
            side_a = self.broadphase.in_zone(store, rule.a, zone, self.kinds)
            side_b = self.broadphase.in_zone(store, rule.b, zone, self.kinds) if side_a else ()
            if side_a and side_b:
                if groups is plan.groups:
                    groups = list(groups)
                groups.insert(place - skipped, (rule, side_a, side_b))
                allowed += _allowed(rule, side_a, side_b)
            else:
                skipped += 1
        return groups, allowed

    def _quick_test(self, pairs: Sequence[Pair], tick: int) -> list[Pair]:
        """Step 2: the candidates whose boxes meet (for swept entries, b's box moved by
        the pair's relative motion over the tick, against a's), or with a study's
        stand-in for this test, those it passes."""
        quick = self.quick
        if quick is not None:
            return [(a, b, rule) for a, b, rule in pairs
                    if quick(_xywh(a, tick, rule), _xywh(b, tick, rule))]
        hits = []
        for pair in pairs:
            a, b, rule = pair
            if rule.motion is not SWEPT:
                if a.x < b.x + b.w and b.x < a.x + a.w and a.y < b.y + b.h and b.y < a.y + a.h:
                    hits.append(pair)
                continue
            # b's corner off a's goes from (ox, oy) to (ex, ey); where each started read in
            # place (as Body.start_of_tick says): the x axis first, most pairs part there.
            # Each axis: the span b's corner covers, low end below a's far edge and high end
            # plus b's size past a's near one.
            a_moved, b_moved = a.moved_tick == tick, b.moved_tick == tick
            ox = (b.px if b_moved else b.x) - (a.px if a_moved else a.x)
            ex = b.x - a.x
            if not (ex < a.w and ox + b.w > 0 if ex < ox else ox < a.w and ex + b.w > 0):
                continue
            oy = (b.py if b_moved else b.y) - (a.py if a_moved else a.y)
            ey = b.y - a.y
            if ey < a.h and oy + b.h > 0 if ey < oy else oy < a.h and ey + b.h > 0:
                hits.append(pair)
        return hits

    def _thorough_test(self, hits: list[Pair], tick: int
                       ) -> tuple[list[Contact], int, int, int]:
        """Step 3 on the pairs whose boxes met: pixels where they landed (or boxes, where
        those are the shapes), or the walk along the relative motion for swept entries.
        The contacts by time (ties in the pairs' (low id, high id) order), and the counts
        of mask tests, mask hits and swept tests."""
        contacts: list[Contact] = []
        mask_tests = mask_hits = swept_tests = 0
        for a, b, rule in hits:
            if rule.motion is SWEPT:
                swept_tests += 1
                contact = self._walk(a, b, rule, tick)
            else:
                contact = self._landed(a, b, rule, tick)
                if rule.needs_pixels:
                    mask_tests += 1
                    mask_hits += contact is not None
            if contact is not None:
                contacts.append(contact)
        if len(contacts) > 1:
            contacts.sort(key=contact_time)
        return contacts, mask_tests, mask_hits, swept_tests

    def _landed(self, a: Body, b: Body, rule: PairRule, tick: int) -> Contact | None:
        """A discrete or landing entry's thorough test, where the pair landed: their
        pixels (or boxes, where those are the shapes). A landing contact is timed at the
        tick's end; a discrete one at its first touch along the tick's motion."""
        if rule.needs_pixels:
            point = predicates.masks_overlap(
                _shape_mask(a, rule), a.x, a.y, _shape_mask(b, rule), b.x, b.y)
            if point is None:
                return None
        elif a.w and a.h and b.w and b.h:
            point = (max(a.x, b.x), max(a.y, b.y))
        else:  # (a box of no pixel meets nothing, as in the pixel tests and pygame's rects)
            return None
        time = impact_time(1, 1)
        if rule.motion is not LANDING:
            walked = self._walk(a, b, rule, tick)
            if walked is not None:
                time = walked.time
        return Contact(tick, time, a.id, b.id, a.kind, b.kind, a.x, a.y, b.x, b.y, *point,
                       rule)

    def _walk(self, a: Body, b: Body, rule: PairRule, tick: int) -> Contact | None:
        """The pixel walk along the pair's relative motion over the tick: the first touch,
        or None. The side that never erodes is the one swept, so its swept mask can be
        kept; one test of that swept mask answers most walks."""
        apx, apy = (a.px, a.py) if a.moved_tick == tick else (a.x, a.y)  # start_of_tick,
        bpx, bpy = (b.px, b.py) if b.moved_tick == tick else (b.x, b.y)  # read in place
        ox, oy = bpx - apx, bpy - apy  # b's corner off a's, at the start
        dx, dy = (b.x - bpx) - (a.x - apx), (b.y - bpy) - (a.y - apy)  # and its motion
        masked = rule.masked
        a_mask = a.mask if a.kind in masked else predicates.solid_mask(a.w, a.h)
        b_mask = b.mask if b.kind in masked else predicates.solid_mask(b.w, b.h)
        b_swept = b.kind not in self.eroding
        if b_swept:
            fixed, moving, sox, soy, sdx, sdy = a_mask, b_mask, ox, oy, dx, dy
        else:  # b erodes (a shield): a is swept against it
            fixed, moving, sox, soy, sdx, sdy = b_mask, a_mask, -ox, -oy, -dx, -dy
        found = predicates.first_swept_contact(fixed, moving, sox, soy, sdx, sdy,
                                               a.shaped_tick == tick or b.shaped_tick == tick)
        if found is None:
            return None
        step, steps, (hx, hy) = found
        sx, sy = predicates.substep(sdx, sdy, step)
        if b_swept:  # the fixed side placed at its own point of the tick, the other from it
            ax, ay = _at(apx, apy, a.x, a.y, step, steps)
            bx, by = ax + ox + sx, ay + oy + sy
            hx, hy = ax + hx, ay + hy
        else:
            bx, by = _at(bpx, bpy, b.x, b.y, step, steps)
            ax, ay = bx - ox + sx, by - oy + sy
            hx, hy = bx + hx, by + hy
        return Contact(tick, impact_time(step, steps), a.id, b.id, a.kind, b.kind,
                       ax, ay, bx, by, hx, hy, rule)


def _allowed(rule: PairRule, side_a: Sequence[Body], side_b: Sequence[Body]) -> int:
    """The pairs an entry's sides allow: each body of one with each of the other, or, for
    an entry of one kind (its two sides the same bodies), each two of them once."""
    n = len(side_a)
    return n * (n - 1) // 2 if rule.a == rule.b else n * len(side_b)


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
