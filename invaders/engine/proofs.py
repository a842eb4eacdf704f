"""Model no more than a scene needs: motion models proved from the masks.

For the moves each kind can make in one tick and the pictures it can show, an entry can stay
discrete only if no start offset exists at which the sweep meets what neither end meets; a
side that erodes (to any shape) must not gain a pixel by sweeping at all. LANDING entries
stay as they are: where things land is their definition.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import replace

import pygame

from invaders.engine import predicates
from invaders.engine.rules import Motion, PairRule, RuleTable

Move = tuple[int, int]


def discrete_counterexample(
    fixed: pygame.mask.Mask, moving: pygame.mask.Mask, dx: int, dy: int
) -> tuple[int, int] | None:
    """A start offset at which `moving`, moving (dx, dy) relative to `fixed`, touches it on
    the way but at neither end: proof that discrete tests miss. None: discrete is exact.
    The first such offset, rows top to bottom, each left to right.

    Only the end of a tick is tested, but the start was the previous tick's end, so a
    discrete test misses exactly what the sweep meets between the two ends. Every start
    offset is tried at once: `Mask.convolve` marks each offset at which two masks overlap,
    so the misses are the sweep's marks less the start's and the end's.
    """
    mw, mh = moving.get_size()
    x0, y0 = -mw - abs(dx), -mh - abs(dy)  # the first start offset that can touch
    fw, fh = fixed.get_size()
    misses = pygame.mask.Mask((fw - x0 + abs(dx) + 1, fh - y0 + abs(dy) + 1))
    # convolve's bit (i, j): `other`'s bottom-right corner at (i, j), its corner at
    # (i - w + 1, j - h + 1); each is drawn where that offset sits on `misses`.
    swept = predicates.swept_mask(moving, dx, dy)
    sw, sh = swept.get_size()
    misses.draw(fixed.convolve(swept), (1 - sw - min(0, dx) - x0, 1 - sh - min(0, dy) - y0))
    touching = fixed.convolve(moving)
    misses.erase(touching, (1 - mw - x0, 1 - mh - y0))
    misses.erase(touching, (1 - mw - dx - x0, 1 - mh - dy - y0))
    if not misses.count():
        return None
    top = min(rect.top for rect in misses.get_bounding_rects())
    left = next(x for x in range(misses.get_size()[0]) if misses.get_at((x, top)))
    return left + x0, top + y0


def sweep_adds_pixels(moving: pygame.mask.Mask, dx: int, dy: int) -> bool:
    """Whether sweeping covers pixels neither end covers: then some target shape (a shield
    eroded to anything) is met on the way but at neither end."""
    w, h = moving.get_size()
    ends = pygame.mask.Mask((w + abs(dx), h + abs(dy)))
    ox, oy = min(0, dx), min(0, dy)
    ends.draw(moving, (-ox, -oy))
    ends.draw(moving, (dx - ox, dy - oy))
    return predicates.swept_mask(moving, dx, dy).count() != ends.count()


def discrete_miss(rule: PairRule, moves: Mapping[int, Sequence[Move]],
                  masks: Mapping[int, Sequence[pygame.mask.Mask]],
                  eroding: frozenset[int] = frozenset()) -> tuple | None:
    """A witness that discrete tests miss for this entry at these moves, or None."""
    for da, db in itertools.product(moves[rule.a], moves[rule.b]):
        dx, dy = db[0] - da[0], db[1] - da[1]
        if rule.a in eroding or rule.b in eroding:
            mover = rule.a if rule.b in eroding else rule.b
            sign = -1 if mover == rule.a else 1
            if any(sweep_adds_pixels(m, sign * dx, sign * dy) for m in masks[mover]):
                return da, db
            continue
        for ma, mb in itertools.product(masks[rule.a], masks[rule.b]):
            found = discrete_counterexample(ma, mb, dx, dy)
            if found is not None:
                return da, db, found
    return None


def cheapest(table: RuleTable, moves: Mapping[int, Sequence[Move]],
             masks: Mapping[int, Sequence[pygame.mask.Mask]]) -> RuleTable:
    """The table with each entry discrete where that is proven exact, swept elsewhere."""

    def model(rule: PairRule) -> PairRule:
        if rule.motion is Motion.LANDING:
            return rule
        missed = discrete_miss(rule, moves, masks, table.eroding)
        return replace(rule, motion=Motion.SWEPT if missed else Motion.DISCRETE)

    return table.map(model)
