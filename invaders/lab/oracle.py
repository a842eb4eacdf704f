"""The oracle: the contacts that truly happen in a tick, by brute force.

Every pair of bodies whose kinds can interact is tested with pixel masks at every pixel of
the pair's relative motion during the tick (nothing moves more than one pixel between two
tests), except LANDING entries, which are tested where things land. That gives each pair's
time of first touch, in the time base of the engine's contacts. The tick is then walked in
time order, and a body spent by an earlier contact (as its entry says) stops: it takes part
in no later contact. So the oracle scores first contacts, not every touch. Zones are not
used: they may only ever drop pairs that cannot touch, and scoring checks that.

It shares no code with the detector, its broad phases or its choice of tests, only the
pixel primitives, so it can score them.
"""

from __future__ import annotations

from bisect import bisect_left
from fractions import Fraction
from typing import NamedTuple

from invaders.engine.body import Body
from invaders.engine.broadphase import Scene
from invaders.engine.predicates import round_div, solid_mask, substeps, swept_box_overlap
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape


class TrueContact(NamedTuple):
    """A pair that touched during the tick, when it first touched (0 to 1), and one pixel
    the two shared then (where a lab marks a contact a method got wrong)."""

    time: Fraction
    a_id: int
    b_id: int
    x: int = 0
    y: int = 0


def _mask(body: Body, shape: Shape):
    return body.mask if shape is Shape.MASK else solid_mask(body.w, body.h)


def _start(body: Body, tick: int) -> tuple[int, int]:
    return (body.px, body.py) if body.moved_tick == tick else (body.x, body.y)


def first_touch(a: Body, b: Body, rule: PairRule, tick: int) -> Fraction | None:
    """When a and b first touch, pixel-exact, during the tick (None: they do not)."""
    touch = _touch(a, b, rule, tick)
    return None if touch is None else touch[0]


def _touch(a: Body, b: Body, rule: PairRule, tick: int) -> tuple[Fraction, int, int] | None:
    """The first touch's time and a pixel the two share then (screen coordinates; a's
    position at that instant rounded along its own motion)."""
    a_mask = _mask(a, rule.shape_of(a.kind))
    b_mask = _mask(b, rule.shape_of(b.kind))
    if rule.motion is Motion.LANDING:
        hit = a_mask.overlap(b_mask, (b.x - a.x, b.y - a.y))
        return None if hit is None else (Fraction(1), a.x + hit[0], a.y + hit[1])
    ax0, ay0 = _start(a, tick)
    bx0, by0 = _start(b, tick)
    ox, oy = bx0 - ax0, by0 - ay0
    dx = (b.x - bx0) - (a.x - ax0)
    dy = (b.y - by0) - (a.y - ay0)
    # A box around every position of the motion: nothing outside it can touch.
    if not swept_box_overlap(a.w, a.h, b.w, b.h, ox, oy, dx, dy):
        return None
    path = substeps(dx, dy)
    steps = len(path) - 1
    # The tick's first instant was the last of the previous tick, unless a body is new in it.
    first = 0 if steps == 0 or a.shaped_tick == tick or b.shaped_tick == tick else 1
    for i in range(first, steps + 1):
        sx, sy = path[i]
        hit = a_mask.overlap(b_mask, (ox + sx, oy + sy))
        if hit is not None:
            if not steps:
                return Fraction(0), a.x + hit[0], a.y + hit[1]
            x = ax0 + round_div(i * (a.x - ax0), steps)
            y = ay0 + round_div(i * (a.y - ay0), steps)
            return Fraction(i, steps), x + hit[0], y + hit[1]
    return None


def _columns(body: Body, tick: int) -> tuple[int, int]:
    """First and one-past-last screen column the body covers at any time in the tick."""
    x0, _ = _start(body, tick)
    return min(x0, body.x), max(x0, body.x) + body.w


def all_touches(scene: Scene, rules: RuleTable) -> list[tuple[Fraction, int, int, PairRule,
                                                             int, int, int]]:
    """Every pair that touches in the tick: (time, low id, high id, entry, low's kind, and a
    pixel they share), in time order.

    A pair whose bodies never share a screen column during the tick cannot touch, and is
    passed over by a bisection on left edges (so storms of thousands stay tractable). In
    an entry of one kind each two bodies are tested once, and none with itself.
    """
    by_kind = scene.by_kind
    tick = scene.tick
    found = []
    for rule in rules:
        side_a, side_b = by_kind.get(rule.a, ()), by_kind.get(rule.b, ())
        if not side_a or not side_b:
            continue
        spans = sorted((*_columns(b, tick), b.id, b) for b in side_b)
        lefts = [span[0] for span in spans]
        widest = max(span[1] - span[0] for span in spans)
        for a in side_a:
            left, right = _columns(a, tick)
            for _, b_right, _, b in spans[bisect_left(lefts, left - widest):
                                          bisect_left(lefts, right)]:
                if b_right <= left or (rule.a == rule.b and b.id <= a.id):
                    continue  # (apart; or in an entry of one kind, itself, or met already)
                low, high = (a, b) if a.id < b.id else (b, a)
                touch = _touch(low, high, rule, tick)
                if touch is not None:
                    time, x, y = touch
                    found.append((time, low.id, high.id, rule, low.kind, x, y))
    found.sort(key=lambda touch: touch[:3])
    return found


def true_contacts(scene: Scene, rules: RuleTable) -> list[TrueContact]:
    """The contacts that happen in the scene's tick, in (time, low id, high id) order: the
    touches walked in time order, each spent body stopping at its first contact."""
    stopped: set[int] = set()
    out = []
    for time, low, high, rule, low_kind, x, y in all_touches(scene, rules):
        if low in stopped or high in stopped:
            continue
        out.append(TrueContact(time, low, high, x, y))
        in_order = low_kind == rule.a  # in a same-kind entry the low id is side a
        if rule.spends_a if in_order else rule.spends_b:
            stopped.add(low)
        if rule.spends_b if in_order else rule.spends_a:
            stopped.add(high)
    return out
