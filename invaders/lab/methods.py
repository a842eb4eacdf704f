"""Quick tests of the method matrix besides ours: what other code often uses, to measure.

Each is a tiny interchangeable predicate on two integer boxes, like pygame's collide_rect and
collide_circle, so a study can swap them in and count what they get wrong.
"""

from __future__ import annotations

from collections.abc import Callable

from invaders.engine.predicates import rects_overlap

Box = tuple[int, int, int, int]  # x, y, w, h
QuickTest = Callable[[Box, Box], bool]


def rect(a: Box, b: Box) -> bool:
    """Box overlap (ours): exact for boxes."""
    return rects_overlap(*a, *b)


def corners_inside(a: Box, b: Box) -> bool:
    """A common shortcut: is a corner of either box inside the other? It misses crossings,
    where two boxes overlap with no corner of one inside the other."""

    def inside(px: int, py: int, box: Box) -> bool:
        x, y, w, h = box
        return x <= px < x + w and y <= py < y + h

    for box, other in ((a, b), (b, a)):
        x, y, w, h = box
        for px, py in ((x, y), (x + w - 1, y), (x, y + h - 1), (x + w - 1, y + h - 1)):
            if inside(px, py, other):
                return True
    return False


def circles(a: Box, b: Box) -> bool:
    """Bounding circles, as pygame's collide_circle: the circle through each box's corners.
    Cheap and rotation-free, but it reports boxes that are apart as touching."""
    ax, ay, aw, ah = a
    bx, by, bw, bh = b
    # Work in doubled coordinates to stay in integers: centres and squared radii.
    dx = (2 * ax + aw) - (2 * bx + bw)
    dy = (2 * ay + ah) - (2 * by + bh)
    ra2 = aw * aw + ah * ah
    rb2 = bw * bw + bh * bh
    # (ra + rb)^2 >= d^2, with r = sqrt(r2)/1 in doubled units; compare without sqrt:
    d2 = dx * dx + dy * dy
    if d2 <= ra2 + rb2:
        return True
    lhs = d2 - ra2 - rb2
    return lhs * lhs <= 4 * ra2 * rb2


QUICK_TESTS: dict[str, QuickTest] = {"rect": rect, "corners": corners_inside, "circle": circles}
