"""Rect, mask and swept predicates: the pixel tests the detector and the oracle share.

pygame's `Mask.overlap(other, offset)` places `other`'s top-left corner at `offset` from the
caller's top-left and returns the first overlapping pixel in the caller's coordinates, or None.
Two placed masks are compared through `masks_overlap` (via `mask_offset`); a walk along a
motion passes offsets from the fixed side's corner directly (`first_swept_contact`).
`tests/test_predicates.py` pins the convention against pygame itself.
"""

from __future__ import annotations

from functools import lru_cache

import pygame

from invaders.engine.pickling import forget_recipe, remade_by

Point = tuple[int, int]


def rects_overlap(ax: int, ay: int, aw: int, ah: int, bx: int, by: int, bw: int, bh: int) -> bool:
    """Half-open integer boxes: touching edges do not overlap, one shared pixel does."""
    return ax < bx + bw and bx < ax + aw and ay < by + bh and by < ay + ah


def mask_offset(ax: int, ay: int, bx: int, by: int) -> Point:
    """Offset of b's top-left from a's, as `a_mask.overlap(b_mask, offset)` wants it."""
    return bx - ax, by - ay


# The solid masks kept to be shared: the latest asked for, at most SOLID_KEPT of them and
# SOLID_KEPT_PIXELS pixels all told (2 MiB of bits; one larger is kept alone). A sprite
# whose box is its shape and changes size every frame asks for a new one each frame:
# keeping every one grew a process by 114 MB in 1,500 frames (tests/test_sprites.py).
SOLID_KEPT = 4096
SOLID_KEPT_PIXELS = 1 << 24


class KeptSolids:
    """The solid masks kept, the longest unasked first, and their pixels all told."""

    def __init__(self) -> None:
        self.masks: dict[tuple[int, int], pygame.mask.Mask] = {}
        self.pixels = 0

    def keep(self, w: int, h: int) -> pygame.mask.Mask:
        """A new solid mask, kept; the longest unasked let go while the bounds are passed
        (one let go is not shared with the next of its size, and pickles as its pixels)."""
        masks = self.masks
        mask = masks[w, h] = remade_by(pygame.mask.Mask((w, h), fill=True), solid_mask, w, h)
        self.pixels += w * h
        while len(masks) > 1 and (len(masks) > SOLID_KEPT
                                  or self.pixels > SOLID_KEPT_PIXELS):
            (ow, oh), oldest = next(iter(masks.items()))
            del masks[ow, oh]
            self.pixels -= ow * oh
            forget_recipe(oldest)
        return mask


_solids = KeptSolids()


def solid_mask(w: int, h: int) -> pygame.mask.Mask:
    """A filled w x h mask, for a side whose box is its whole shape (shared while kept:
    pickled as this call)."""
    masks = _solids.masks
    mask = masks.pop((w, h), None)
    if mask is None:
        return _solids.keep(w, h)
    masks[w, h] = mask  # (now the latest asked for)
    return mask


def masks_overlap(
    a_mask: pygame.mask.Mask, ax: int, ay: int, b_mask: pygame.mask.Mask, bx: int, by: int
) -> Point | None:
    """A screen pixel both masks light, placed at (ax, ay) and (bx, by), or None."""
    hit = a_mask.overlap(b_mask, mask_offset(ax, ay, bx, by))
    if hit is None:
        return None
    return ax + hit[0], ay + hit[1]


@lru_cache(maxsize=4096)
def substeps(dx: int, dy: int) -> tuple[Point, ...]:
    """Integer points from (0, 0) to (dx, dy), one pixel apart along the major axis.

    This is the motion model of every swept test and of the oracle: between consecutive
    points nothing moves more than one pixel on either axis. (Kept per motion: a scene has
    few distinct ones, and the walk asks for them on every swept test.)
    """
    n = max(abs(dx), abs(dy))
    if n == 0:
        return ((0, 0),)
    return tuple((round_div(i * dx, n), round_div(i * dy, n)) for i in range(n + 1))


def round_div(num: int, den: int) -> int:
    """num / den rounded half away from zero, in integers (den > 0)."""
    if num >= 0:
        return (2 * num + den) // (2 * den)
    return -((-2 * num + den) // (2 * den))


_swept_cache: dict[tuple[pygame.mask.Mask, int, int], pygame.mask.Mask] = {}


def swept_mask(mask: pygame.mask.Mask, dx: int, dy: int) -> pygame.mask.Mask:
    """The union of `mask` placed at every substep of (dx, dy), with its corner at
    (min(0, dx), min(0, dy)). Cached: only ever pass shared (never-eroded) masks. Keyed on
    the mask itself (masks hash by identity), so the key holds it and an id is never
    reused."""
    swept = _swept_cache.get((mask, dx, dy))
    if swept is not None:
        return swept
    w, h = mask.get_size()
    ox, oy = min(0, dx), min(0, dy)
    swept = pygame.mask.Mask((w + abs(dx), h + abs(dy)))
    for sx, sy in substeps(dx, dy):
        swept.draw(mask, (sx - ox, sy - oy))
    if len(_swept_cache) > 4096:
        _swept_cache.clear()
    _swept_cache[(mask, dx, dy)] = swept
    return swept


def swept_box_overlap(
    fixed_w: int, fixed_h: int, moving_w: int, moving_h: int, ox: int, oy: int, dx: int, dy: int
) -> bool:
    """Quick test: does the box swept from offset (ox, oy) by (dx, dy) meet the fixed box?"""
    return rects_overlap(0, 0, fixed_w, fixed_h, ox + min(0, dx), oy + min(0, dy),
                         moving_w + abs(dx), moving_h + abs(dy))


def first_swept_contact(
    fixed: pygame.mask.Mask, moving: pygame.mask.Mask, ox: int, oy: int, dx: int, dy: int,
    from_start: bool = True,
) -> tuple[int, int, Point] | None:
    """The first substep at which `moving`, starting at offset (ox, oy) from `fixed` and
    moving (dx, dy) relative to it, lights a pixel `fixed` lights.

    With `from_start` false the start itself is not tested (it was the previous tick's end).
    Returns (step, steps, pixel in fixed's coordinates), or None. One test of the swept
    mask answers most calls; only a hit walks the substeps to find the first.
    """
    if dx or dy:
        swept = _swept_cache.get((moving, dx, dy))  # swept_mask's own cache, read first
        if swept is None:
            w, h = moving.get_size()
            ax, ay = abs(dx), abs(dy)
            if ax > LONG_STEPS or ay > LONG_STEPS or (w + ax) * (h + ay) > SWEPT_BITS:
                return long_touch(fixed, moving, ox, oy, dx, dy, from_start)
            swept = swept_mask(moving, dx, dy)
        if fixed.overlap(swept, (ox + dx if dx < 0 else ox, oy + dy if dy < 0 else oy)) is None:
            return None
    return first_touch(fixed, moving, ox, oy, dx, dy, from_start)


# A motion whose swept mask would be bigger, or longer (its path's substeps are kept too),
# is walked by `long_touch`, with neither.
SWEPT_BITS = 1 << 16
LONG_STEPS = 256


def long_touch(
    fixed: pygame.mask.Mask, moving: pygame.mask.Mask, ox: int, oy: int, dx: int, dy: int,
    from_start: bool,
) -> tuple[int, int, Point] | None:
    """`first_touch` for a long motion, with no swept mask (its area grows as the square
    of the motion, and the cache kept each) nor path (kept too): only the substeps at
    which the boxes overlap are walked, a few more than the boxes are long along the
    motion, however far it goes. Those are one run of substeps, as each axis's position
    along the path is monotone."""
    (fw, fh), (mw, mh) = fixed.get_size(), moving.get_size()
    steps = max(abs(dx), abs(dy))
    first, last = 0 if from_start else 1, steps
    for start, move, low, high in ((ox, dx, -mw, fw), (oy, dy, -mh, fh)):
        # (on this axis the boxes overlap while low < position < high)
        enter, leave = (low, high - 1) if move >= 0 else (high, low + 1)
        first = max(first, _first_past(start, move, steps, enter))
        last = min(last, _first_past(start, move, steps, leave) - 1)
    for i in range(first, last + 1):
        hit = fixed.overlap(moving, (ox + round_div(i * dx, steps), oy + round_div(i * dy, steps)))
        if hit is not None:
            return i, steps, hit
    return None


def _first_past(start: int, move: int, steps: int, bound: int) -> int:
    """The least substep i (0 to steps) at which start + round_div(i * move, steps) is past
    `bound` the way it moves (above it for a move of 0 or more, below it for one back), or
    steps + 1 if none is: the positions are monotone, so a binary search finds it."""
    low, high = 0, steps + 1
    while low < high:
        mid = (low + high) // 2
        position = start + round_div(mid * move, steps)
        if position > bound if move >= 0 else position < bound:
            high = mid
        else:
            low = mid + 1
    return low


def substep(dx: int, dy: int, step: int) -> Point:
    """`substeps(dx, dy)[step]`, without making the others (a long motion's are many)."""
    steps = max(abs(dx), abs(dy))
    if steps == 0:
        return 0, 0
    return round_div(step * dx, steps), round_div(step * dy, steps)


def first_touch(
    fixed: pygame.mask.Mask, moving: pygame.mask.Mask, ox: int, oy: int, dx: int, dy: int,
    from_start: bool,
) -> tuple[int, int, Point] | None:
    """`first_swept_contact`'s walk alone, for a caller that has found the swept mask
    meets `fixed`: the substeps tried in order (a motion of none is its start)."""
    ax, ay = (dx if dx >= 0 else -dx), (dy if dy >= 0 else -dy)
    steps = ax if ax >= ay else ay
    if steps == 0:
        hit = fixed.overlap(moving, (ox, oy))
        return None if hit is None else (0, 0, hit)
    path = substeps(dx, dy)
    for i in range(0 if from_start else 1, steps + 1):
        sx, sy = path[i]
        hit = fixed.overlap(moving, (ox + sx, oy + sy))
        if hit is not None:
            return i, steps, hit
    return None  # it touched only at the start, which the previous tick reported
