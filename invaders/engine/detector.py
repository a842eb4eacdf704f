"""detect(scene) -> (contacts, stats): reduce, quick test, thorough test. Mutates nothing.

Step 1 keeps only pairs of kinds the rules table lists (inside their zones) and asks the
broad phase for candidates; step 2 tests boxes (swept boxes for swept entries); step 3 tests
pixels where the entry says the shape is not its box, or walks the relative motion for swept
entries. Response (step 4) is someone else's job: see response.py.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from invaders.engine import predicates
from invaders.engine.body import ERODIBLE, Body, tick_box
from invaders.engine.broadphase import (
    DEFAULT_CELL,
    BroadPhase,
    Group,
    KindSets,
    Scene,
    make_broadphase,
)
from invaders.engine.rules import RULES, Motion, PairRule, Shape, probed_kinds, swept_kinds
from invaders.engine.stats import CollisionStats, Contact

QuickTest = Callable[[tuple[int, int, int, int], tuple[int, int, int, int]], bool]


def _in_zone(body: Body, zone: tuple[int, int, int, int]) -> bool:
    zx, zy, zw, zh = zone
    return predicates.rects_overlap(body.x, body.y, body.w, body.h, zx, zy, zw, zh)


def _shape_mask(body: Body, shape: Shape):  # -> pygame.mask.Mask
    return body.mask if shape is Shape.MASK else predicates.solid_mask(body.w, body.h)


class Detector:
    """A rules table and a broad phase; holds only the broad phase's own bookkeeping."""

    def __init__(self, broadphase: BroadPhase, rules: tuple[PairRule, ...] = RULES,
                 quick: QuickTest | None = None) -> None:
        self.broadphase = broadphase
        self.rules = rules
        self.quick = quick  # None: exact box overlap, inlined; else a study's stand-in
        self.swept = swept_kinds(rules)
        self.kinds = KindSets(self.swept, probed_kinds(rules))
        self._table = tuple((rule, rule.a, rule.b, rule.zone) for rule in rules)
        self._plans: dict[int, tuple] = {}  # kinds present (bit mask) -> entries that apply
        self.last_pairs: Sequence[tuple[int, int]] = ()  # last tick's candidates, for overlays

    def detect(self, scene: Scene) -> tuple[list[Contact], CollisionStats]:
        by_kind = scene.by_kind
        n = 0
        present = 0
        for kind, bodies in by_kind.items():
            if bodies:
                n += len(bodies)
                present |= 1 << kind
        plan = self._plans.get(present)
        if plan is None:
            plan = self._plans[present] = tuple(
                entry for entry in self._table
                if present >> entry[1] & 1 and present >> entry[2] & 1)
        groups: list[Group] = []
        allowed = 0
        for rule, kind_a, kind_b, zone in plan:
            side_a: Sequence[Body] = by_kind[kind_a]
            side_b: Sequence[Body] = by_kind[kind_b]
            if zone is not None:
                side_a = [body for body in side_a if _in_zone(body, zone)]
                side_b = [body for body in side_b if _in_zone(body, zone)]
                if not side_a or not side_b:
                    continue
            allowed += len(side_a) * len(side_b)
            groups.append((rule, side_a, side_b))
        pairs = self.broadphase.pairs(scene, groups, self.kinds) if groups else []
        self.last_pairs = [(a.id, b.id) for a, b, _ in pairs] if pairs else ()

        tick = scene.tick
        quick = self.quick
        contacts: list[Contact] = []
        rect_tests = rect_hits = mask_tests = mask_hits = swept_tests = 0
        for a, b, rule in pairs:
            rect_tests += 1
            if quick is not None and not quick(_xywh(a, tick, rule), _xywh(b, tick, rule)):
                continue
            if rule.motion is Motion.SWEPT:
                box_hit, contact = self._swept(a, b, rule, tick)
                if box_hit:
                    rect_hits += 1
                    swept_tests += 1
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
                    _shape_mask(a, rule.shape_of(a.kind)), a.x, a.y,
                    _shape_mask(b, rule.shape_of(b.kind)), b.x, b.y)
                if point is None:
                    continue
                mask_hits += 1
            else:
                point = (max(a.x, b.x), max(a.y, b.y))
            contacts.append(Contact(tick, a.id, b.id, a.kind, b.kind, a.x, a.y, b.x, b.y, *point))
        stats = CollisionStats(n, n * (n - 1) // 2, allowed, len(pairs), rect_tests, rect_hits,
                               mask_tests, mask_hits, swept_tests, len(contacts))
        return contacts, stats

    def _swept(self, a: Body, b: Body, rule: PairRule, tick: int) -> tuple[bool, Contact | None]:
        """Swept box test, then the pixel walk: (did the boxes meet, the contact or None)."""
        apx, apy = (a.px, a.py) if a.moved_tick == tick else (a.x, a.y)
        bpx, bpy = (b.px, b.py) if b.moved_tick == tick else (b.x, b.y)
        ox, oy = bpx - apx, bpy - apy  # b relative to a at the tick's start
        dx = (b.x - bpx) - (a.x - apx)
        dy = (b.y - bpy) - (a.y - apy)
        # The quick test, predicates.swept_box_overlap inlined (this is the hot path): b's box
        # swept from (ox, oy) by (dx, dy) against a's box at the origin.
        sx0 = ox + dx if dx < 0 else ox
        sy0 = oy + dy if dy < 0 else oy
        if not (sx0 < a.w and sx0 + b.w + abs(dx) > 0 and sy0 < a.h and sy0 + b.h + abs(dy) > 0):
            return False, None
        a_mask = _shape_mask(a, rule.shape_of(a.kind))
        b_mask = _shape_mask(b, rule.shape_of(b.kind))
        if b.kind not in ERODIBLE:
            found = predicates.first_swept_contact(a_mask, b_mask, ox, oy, dx, dy,
                                                   a.shaped_tick == tick or b.shaped_tick == tick)
            if found is None:
                return True, None
            step, steps, (hx, hy) = found
            ax, ay = _at(apx, apy, a.x, a.y, step, steps)
            sx, sy = predicates.substeps(dx, dy)[step]
            bx, by = ax + ox + sx, ay + oy + sy
            return True, Contact(tick, a.id, b.id, a.kind, b.kind, ax, ay, bx, by,
                                 ax + hx, ay + hy)
        # b erodes (a shield): sweep a against it instead, so only shared masks are swept.
        found = predicates.first_swept_contact(b_mask, a_mask, -ox, -oy, -dx, -dy,
                                               a.shaped_tick == tick or b.shaped_tick == tick)
        if found is None:
            return True, None
        step, steps, (hx, hy) = found
        bx, by = _at(bpx, bpy, b.x, b.y, step, steps)
        sx, sy = predicates.substeps(-dx, -dy)[step]
        ax, ay = bx - ox + sx, by - oy + sy
        return True, Contact(tick, a.id, b.id, a.kind, b.kind, ax, ay, bx, by, bx + hx, by + hy)


def _xywh(body: Body, tick: int, rule: PairRule) -> tuple[int, int, int, int]:
    """The box a study's quick test sees: over the tick's motion for swept entries."""
    x0, y0, x1, y1 = tick_box(body, tick, rule.motion is Motion.SWEPT)
    return x0, y0, x1 - x0, y1 - y0


def _at(x0: int, y0: int, x1: int, y1: int, step: int, steps: int) -> tuple[int, int]:
    """A body's own position `step` substeps of `steps` into the tick."""
    if steps == 0:
        return x1, y1
    return (x0 + predicates.round_div((x1 - x0) * step, steps),
            y0 + predicates.round_div((y1 - y0) * step, steps))


def make_detector(broadphase: str = "grid", cell: int = DEFAULT_CELL) -> Detector:
    """A detector with the default rules and the named broad phase."""
    return Detector(make_broadphase(broadphase, cell))
