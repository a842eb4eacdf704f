"""The oracle: the true contacts of a tick, by brute force.

Every pair of bodies whose kinds can interact is tested with pixel masks at every pixel of
the pair's relative motion during the tick (nothing moves more than one pixel between two
tests), except the entries whose outcome is defined by where things land (an alien's draw
footprint), which are tested where they land. It shares no code path with the pipeline's
broad phases or its choice of tests, only the pixel primitives, so it can score them.
"""

from __future__ import annotations

from bisect import bisect_left
from typing import NamedTuple

from invaders.engine.body import Body
from invaders.engine.broadphase import Scene
from invaders.engine.predicates import solid_mask, substeps, swept_box_overlap
from invaders.engine.rules import POSITIONAL, RULES, PairRule, Shape


class TrueContact(NamedTuple):
    """A pair that touched during the tick, and how far into the tick it first touched."""

    a_id: int
    b_id: int
    step: int  # first substep that touched
    steps: int  # substeps in the tick for this pair (0: tested where they landed)


def _mask(body: Body, shape: Shape):
    return body.mask if shape is Shape.MASK else solid_mask(body.w, body.h)


def _start(body: Body, tick: int) -> tuple[int, int]:
    return (body.px, body.py) if body.moved_tick == tick else (body.x, body.y)


def pair_contact(a: Body, b: Body, rule: PairRule, tick: int) -> TrueContact | None:
    """The first pixel-exact touch of a and b during the tick (a's id below b's)."""
    a_mask = _mask(a, rule.shape_of(a.kind))
    b_mask = _mask(b, rule.shape_of(b.kind))
    if frozenset({a.kind, b.kind}) in POSITIONAL:
        hit = a_mask.overlap(b_mask, (b.x - a.x, b.y - a.y))
        return None if hit is None else TrueContact(a.id, b.id, 0, 0)
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
    # The tick's first instant was the last of the previous tick, unless a body was born in it.
    first = 0 if steps == 0 or a.shaped_tick == tick or b.shaped_tick == tick else 1
    for i in range(first, steps + 1):
        sx, sy = path[i]
        if a_mask.overlap(b_mask, (ox + sx, oy + sy)) is not None:
            return TrueContact(a.id, b.id, i, steps)
    return None


def _columns(body: Body, tick: int) -> tuple[int, int]:
    """First and one-past-last screen column the body covers at any time in the tick."""
    x0, _ = _start(body, tick)
    return min(x0, body.x), max(x0, body.x) + body.w


def true_contacts(scene: Scene, rules: tuple[PairRule, ...] = RULES) -> list[TrueContact]:
    """All true contacts of the scene's tick, sorted by (low id, high id).

    Every pair of kinds a rule names is considered; a pair whose bodies never share a screen
    column during the tick cannot touch, and is passed over by a bisection on left edges (so
    storms of thousands stay tractable) rather than tested.
    """
    by_kind = scene.by_kind
    tick = scene.tick
    found = []
    for rule in rules:
        side_a, side_b = by_kind[rule.a], by_kind[rule.b]
        if not side_a or not side_b:
            continue
        spans = sorted((*_columns(b, tick), b.id, b) for b in side_b)
        lefts = [span[0] for span in spans]
        widest = max(span[1] - span[0] for span in spans)
        for a in side_a:
            left, right = _columns(a, tick)
            for _, b_right, _, b in spans[bisect_left(lefts, left - widest):
                                          bisect_left(lefts, right)]:
                if b_right <= left:
                    continue
                low, high = (a, b) if a.id < b.id else (b, a)
                contact = pair_contact(low, high, rule, tick)
                if contact is not None:
                    found.append(contact)
    found.sort()
    return found

