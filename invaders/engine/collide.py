"""pygame-ce's sprite collision functions, the same answers, faster on big groups.

Import these instead of `pygame.sprite`'s: `groupcollide`, `spritecollide`,
`spritecollideany` and the predicates `collide_rect`, `collide_rect_ratio`,
`collide_circle`, `collide_circle_ratio` and `collide_mask` take the same arguments and
give the same results, in the same order, with sprites killed when and as pygame kills them
(pygame's own predicate objects are accepted as `collided` too). What differs is the cost:
`groupcollide` with no predicate, `collide_rect` or `collide_mask`, on groups of integer
`Rect`s or float `FRect`s, reads each group's boxes once and tests each sprite of the first
group against all of the second in one C call (`collidelistall`) instead of one Python
call a pair (masks' boxes in whole pixels: `float_mask_box`), and on big groups only
against the boxes near its own, found by sorting the boxes (numpy: `_near`; whole pixels
round FRects: `_covering`); with
`collide_circle` or `collide_circle_ratio`, on `Rect`s or `FRect`s, it tests boxes round
the circles in C first, then the circles (`_collide_circles`); any other case runs the
plain loop pygame runs, with `collide_rect` as a rect test and a mask made from an image
once, not once a pair (see `image_mask` for what that asks of you). The module keeps
nothing else between calls. Swept tests and rules tables are the `SpriteCollider`'s
(`invaders.engine.sprites`); nothing here sweeps.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
import pygame
from pygame.sprite import AbstractGroup

Collided = Callable[[Any, Any], Any]
# Pairs (a sprite of the first group times the second) from which the C tests pay, on the
# bench's fields: for the rect tests the plain loop took 3.6 against 4.3 us at 5 sprites a
# side and 6.0 against 5.5 at 7; for masks 8.3 against 6.6 at 4 (a script, 11 to 21 rounds
# in turn); for circles 8.6 against 9.2 at 4 a side (collide_circle; at 100 a side 255 us
# against 4.7 ms, at 1,000 7.8 against 466 ms).
RECTS_FAST_FROM = 49
MASKS_FAST_FROM = 16
CIRCLES_FAST_FROM = 16
# Under the fewest, a call goes straight to the loop without asking which test it has:
# at 1 sprite a side, where the loop is pygame's own, asking first made a call take 1.05
# times pygame's time.
FEWEST_FAST = min(RECTS_FAST_FROM, MASKS_FAST_FROM, CIRCLES_FAST_FROM)
# Pairs from which sorting the boxes first pays: at 500 sprites a side a call took 1.18
# against 1.41 ms, at 1,000 3.0 against 5.6, at 2,000 8.6 against 22.3 and at 4,000 20
# against 88 (collide_rect on section 5's fields of the bench, 5 rounds in turn); at 300 a
# side 0.60 against 0.54. With dokillb, where the plain loop rebuilt the second group's lists
# after each kill: 2.6 against 7.4 ms at 500, 9.2 against 105 at 2,000 (a script, 6 rounds
# in turn). Invariant: `_near` finds every box `colliderect` meets, which
# tests/test_collide.py holds to pygame's answers on big groups of every kind of box.
NEAR_FROM = 250_000


def collide_rect(left: Any, right: Any) -> bool:
    """Whether the sprites' rects overlap (pygame's `collide_rect`)."""
    return left.rect.colliderect(right.rect)


class collide_rect_ratio:  # (pygame's name: a class that is called as a function)
    """Whether the sprites' rects overlap once each is scaled by `ratio` about its centre."""

    def __init__(self, ratio: float) -> None:
        self.ratio = ratio

    def __call__(self, left: Any, right: Any) -> bool:
        return _scaled(left.rect, self.ratio).colliderect(_scaled(right.rect, self.ratio))


def _scaled(rect: Any, ratio: float) -> Any:
    w, h = rect.width, rect.height
    return rect.inflate(w * ratio - w, h * ratio - h)


def _radius(sprite: Any) -> float:
    """The sprite's `radius`, or half its rect's diagonal, kept on the sprite as pygame
    keeps it (a later call, and pygame's own, then read the same value)."""
    try:
        return sprite.radius
    except AttributeError:
        rect = sprite.rect
        sprite.radius = 0.5 * ((rect.width ** 2 + rect.height ** 2) ** 0.5)
        return sprite.radius


def collide_circle(left: Any, right: Any) -> bool:
    """Whether circles about the rects' centres meet (pygame's `collide_circle`)."""
    return _circles(left, right, 1)


def _circles(left: Any, right: Any, ratio: float) -> bool:
    dx = left.rect.centerx - right.rect.centerx
    dy = left.rect.centery - right.rect.centery
    reach = _radius(left) * ratio + _radius(right) * ratio
    return dx ** 2 + dy ** 2 <= reach ** 2


class collide_circle_ratio:  # (pygame's name)
    """Whether the circles meet once each radius is scaled by `ratio`."""

    def __init__(self, ratio: float) -> None:
        self.ratio = ratio

    def __call__(self, left: Any, right: Any) -> bool:
        return _circles(left, right, self.ratio)


_image_masks: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
# What a sprite without a `mask` gives for one: asked with `getattr` and this default, its
# absence makes no exception (a sprite with an image alone: 0.07 against 0.42 us, a script).
NO_MASK: Any = object()


def _mask(sprite: Any) -> pygame.mask.Mask:
    """The sprite's `mask`, or the one `collide_mask` makes from its `image`."""
    mask = getattr(sprite, "mask", NO_MASK)
    return image_mask(sprite.image) if mask is NO_MASK else mask


def _masks(sprites: list[Any]) -> list[pygame.mask.Mask]:
    """Each sprite's `_mask`: read as attributes while every sprite has one (the usual
    group), else asked of each (one exception, where one a sprite would cost the most)."""
    try:
        return [sprite.mask for sprite in sprites]
    except AttributeError:
        return [_mask(sprite) for sprite in sprites]


def image_mask(image: pygame.Surface) -> pygame.mask.Mask:
    """The mask `collide_mask` makes from an image, made once per image (pygame makes it
    again for every pair it tests).

    Invariant: an image keeps its pixels once it has been tested. A sprite whose image is
    drawn on in place should carry a `mask`, or its image be handed to `forget_image`
    after the drawing; a test shows the cache outliving such a drawing and forgotten."""
    try:
        mask = _image_masks.get(image)
    except TypeError:  # (no surface, None say: pygame's own error, not the cache's)
        return pygame.mask.from_surface(image)
    if mask is None:
        mask = _image_masks[image] = pygame.mask.from_surface(image)
    return mask


def forget_image(image: pygame.Surface) -> None:
    """Make the mask of `image` again at its next test (it was drawn on in place)."""
    _image_masks.pop(image, None)


def collide_mask(left: Any, right: Any) -> tuple[int, int] | None:
    """The first pixel the masks share, placed at the rects' corners, or None."""
    offset = (right.rect[0] - left.rect[0], right.rect[1] - left.rect[1])
    try:  # (_mask written in twice: a pair's test is a Python call fewer, as pygame's)
        left_mask = left.mask
    except AttributeError:
        left_mask = image_mask(left.image)
    try:
        right_mask = right.mask
    except AttributeError:
        right_mask = image_mask(right.image)
    return left_mask.overlap(right_mask, offset)


RECT_TESTS = frozenset({None, collide_rect, pygame.sprite.collide_rect})
MASK_TESTS = frozenset({collide_mask, pygame.sprite.collide_mask})
FAST_TESTS = RECT_TESTS | MASK_TESTS
PYGAMES_MASK_TEST = pygame.sprite.collide_mask
# The rect test is no predicate or either collide_rect, told by identity where a call
# counts (a caller's predicate may not hash): spritecollide with pygame's collide_rect at 1
# sprite took 0.86x pygame's speed asking `RECT_TESTS` through a function (a script).
PYGAMES_RECT_TEST = pygame.sprite.collide_rect
GROUP = pygame.sprite.Group



def spritecollide(sprite: Any, group: Iterable[Any], dokill: bool,
                  collided: Collided | None = None) -> list[Any]:
    """The sprites of `group` that collide with `sprite`, in the group's order; with
    `dokill`, each is killed (taken out of every group) once all are found."""
    if collided is None or collided is PYGAMES_RECT_TEST or collided is collide_rect:
        overlaps = sprite.rect.colliderect  # (the rect test, without a Python call a sprite)
        found = [other for other in group if overlaps(other.rect)]
    else:
        if collided is PYGAMES_MASK_TEST:
            collided = collide_mask  # the same answers, a mask made once per image
        found = [other for other in group if collided(sprite, other)]  # type: ignore[misc]
    if dokill:
        for other in found:
            other.kill()
    return found


def spritecollideany(sprite: Any, group: Iterable[Any],
                     collided: Collided | None = None) -> Any | None:
    """The first sprite of `group` that collides with `sprite`, or None."""
    if collided is None or collided is PYGAMES_RECT_TEST or collided is collide_rect:
        overlaps = sprite.rect.colliderect
        for other in group:
            if overlaps(other.rect):
                return other
        return None
    if collided is PYGAMES_MASK_TEST:
        collided = collide_mask
    for other in group:
        if collided(sprite, other):  # type: ignore[misc]
            return other
    return None


def groupcollide(groupa: Iterable[Any], groupb: Iterable[Any], dokilla: bool, dokillb: bool,
                 collided: Collided | None = None) -> dict[Any, list[Any]]:
    """Each sprite of `groupa` that collides with any of `groupb`, with the list of those, as
    pygame gives them: `groupb` looked at again for each sprite of `groupa` (so one that
    `dokillb` killed is not met again), the sprites of `groupa` killed at the end."""
    try:  # a Group's size, read where it keeps its sprites (its len() is a Python call)
        pairs = len(groupa.spritedict) * len(groupb.spritedict)  # type: ignore[attr-defined]
    except AttributeError:
        pairs = _pairs(groupa, groupb)
    if pairs >= FEWEST_FAST:
        fast = _groupcollide_if_fast(groupa, groupb, dokilla, dokillb, collided, pairs)
        if fast is not None:
            return fast
    if collided is PYGAMES_MASK_TEST:
        collided = collide_mask  # the same answers, a mask made once per image
    # pygame's own loop, written in here (small groups, where it runs, feel every Python
    # call): spritecollide inline, `collide_rect` as the rect test it is, and a plain
    # Group's sprites read as its `sprites()` gives them, from its `spritedict` in order (a
    # subclass may order them otherwise, LayeredUpdates by layer).
    found: dict[Any, list[Any]] = {}
    rects = collided is None or collided is PYGAMES_RECT_TEST or collided is collide_rect
    plain = type(groupb) is GROUP
    for sprite in list(groupa.spritedict) if type(groupa) is GROUP else groupa:  # type: ignore
        others = list(groupb.spritedict) if plain else groupb  # type: ignore[attr-defined]
        if rects:
            overlaps = sprite.rect.colliderect
            hits = [other for other in others if overlaps(other.rect)]
        else:
            hits = [other for other in others if collided(sprite, other)]  # type: ignore
        if hits:
            found[sprite] = hits
            if dokillb:
                for other in hits:
                    other.kill()
    if dokilla:
        for sprite in found:
            sprite.kill()
    return found


def _pairs(groupa: Any, groupb: Any) -> int:
    """How many pairs, the sizes read where pygame keeps a Group's sprites (its `len` is a
    Python call, which small groups would feel); 0 for an iterable without a length (pygame
    takes any). Only the choice of loop depends on it."""
    try:
        return len(getattr(groupa, "spritedict", groupa)) * len(
            getattr(groupb, "spritedict", groupb))
    except TypeError:
        return 0


def _fast_sides(groupa: Iterable[Any], groupb: Iterable[Any], masks: bool
                ) -> tuple[list[Any], list[Any], bool] | None:
    """Both groups' sprites, when the C tests give pygame's answer (for a known predicate),
    and whether every rect is an integer Rect (what the sorted boxes of rects take; the
    masks' boxes are whole numbers either way): groups that are looked at again unchanged
    (a Group, whose kills the fast loop follows, or a list or tuple) of Rects or FRects, as
    they come (`collidelistall` meets each box as `colliderect` does, Rect or FRect on
    either side)."""
    kinds = (AbstractGroup, list, tuple)
    if not isinstance(groupa, kinds) or not isinstance(groupb, kinds):
        return None
    side_a, side_b = list(groupa), list(groupb)
    kinds_of_rect = {type(s.rect) for s in side_a} | {type(s.rect) for s in side_b}
    if not kinds_of_rect <= {pygame.Rect, pygame.FRect}:
        return None
    return side_a, side_b, kinds_of_rect <= {pygame.Rect}


def _groupcollide_fast(sides: tuple[list[Any], list[Any], bool], groupb: Iterable[Any],
                       dokilla: bool, dokillb: bool, masks: bool, circles: float | None = None
                       ) -> dict[Any, list[Any]] | None:
    """The loop of `groupcollide` with its tests in C: for circle tests (their radii scaled
    by `circles`) `_collide_circles`, else `_collide_boxes`. None where the plain loop is
    to answer."""
    side_a, side_b, whole = sides
    # (a killed sprite leaves a group, not a list)
    second = _Second(side_b, dokillb, dokillb and isinstance(groupb, AbstractGroup))
    if circles is not None:
        found = _collide_circles(side_a, second, circles)
    else:
        found = _collide_boxes(side_a, second, whole, masks)
    if found is not None and dokilla:
        for sprite in found:
            sprite.kill()
    return found


class _Second:
    """The second group's sprites as the fast loops meet them: with `dokillb` a sprite met
    is killed, and where the group `forgets` it (a group, not a list) marked, never met
    again; `left` counts those not yet forgotten."""

    def __init__(self, sprites: list[Any], dokillb: bool, forgets: bool) -> None:
        self.sprites, self.dokillb, self.forgets = sprites, dokillb, forgets
        self.killed = [False] * len(sprites)
        self.left = len(sprites)

    def met(self, hits: list[int]) -> list[Any]:
        """The sprites at `hits` (ascending), killed in that order with `dokillb`."""
        sprites = self.sprites
        met = [sprites[i] for i in hits]
        if self.dokillb:
            for sprite in met:
                sprite.kill()
            if self.forgets:
                for i in hits:
                    self.killed[i] = True
                self.left -= len(hits)
        return met


def _collide_boxes(side_a: list[Any], second: _Second, whole: bool, masks: bool
                   ) -> dict[Any, list[Any]] | None:
    """The boxes that can meet: the rects, or for masks the masks' own boxes at the rects'
    corners, then the masks themselves; on big groups only the boxes near each other
    (`_collide_near`), else each sprite of the first group against all of the second
    (`_collide_each`). None, for the plain loop to run, where a mask's box of the second
    group cannot be made (a float corner that is no finite number or past BOX_LIMIT)."""
    # (the first sprite meets all of the second group: pygame makes all their masks)
    side_b = second.sprites
    mask_b = _masks(side_b) if masks else None
    try:
        boxes_b = ([s.rect for s in side_b] if mask_b is None
                   else _mask_boxes(side_b, mask_b, whole, 0))
    except (OverflowError, ValueError):
        return None
    found = None
    if side_b and len(side_a) * len(side_b) >= NEAR_FROM:
        found = _collide_near(side_a, second, boxes_b, mask_b, whole)
    if found is None:
        found = _collide_each(side_a, second, boxes_b, mask_b, whole)
    return found


def _mask_boxes(sprites: list[Any], masks: list[pygame.mask.Mask], whole: bool, widen: int
                ) -> list[pygame.Rect]:
    """The boxes of the sprites' masks at their rects' corners: as they are on Rects, else
    through `float_mask_box`, `widen`ed. (Rects through it too: collide_mask at 5 sprites
    a side 1.27x pygame's speed, against 1.49x as they are; two runs of a script, each of
    7 rounds in turn.)"""
    if whole:
        return [pygame.Rect(s.rect.topleft, m.get_size()) for s, m in zip(sprites, masks,
                                                                          strict=True)]
    return [float_mask_box(s.rect, m, widen) for s, m in zip(sprites, masks, strict=True)]


BOX_LIMIT = 2**30  # edges inside it: a box's sums stay inside a Rect's 32 bits


def float_mask_box(rect: Any, mask: pygame.mask.Mask, widen: int) -> pygame.Rect:
    """The box, in whole pixels, of a mask at a float rect's corner (an FRect's), `widen`
    pixels wider each way. pygame places the second mask of a pair at the difference of
    the rects' corners, truncated; that difference is within a pixel of the difference of
    the corners' floors, so the masks of a pair can meet only if the box of the first,
    widened a pixel, overlaps the second's, each at its corner's floor. Invariant held by
    `tests/test_collide.py`, which fails it unwidened. OverflowError or ValueError where a
    corner is no finite number or the box would pass BOX_LIMIT."""
    x, y = rect.topleft
    w, h = mask.get_size()
    left, top = math.floor(x) - widen, math.floor(y) - widen
    w, h = w + 2 * widen, h + 2 * widen
    if not (-BOX_LIMIT <= left <= BOX_LIMIT - w and -BOX_LIMIT <= top <= BOX_LIMIT - h):
        raise OverflowError(f"a box past {BOX_LIMIT}: {rect}")
    return pygame.Rect(left, top, w, h)


def _collide_each(side_a: list[Any], second: _Second, boxes_b: list[pygame.Rect],
                  mask_b: list[pygame.mask.Mask] | None, whole: bool
                  ) -> dict[Any, list[Any]]:
    """Each sprite of the first group tested against all of the second in one C call
    (`collidelistall`), its hits met as `_Second` meets them."""
    found: dict[Any, list[Any]] = {}
    side_b, killed = second.sprites, second.killed
    for sprite in side_a:
        if not second.left:  # all killed: pygame meets no more pairs, so makes no more masks
            break
        if mask_b is not None:
            mask = _mask(sprite)
            x, y = sprite.rect.topleft
            try:
                box = (pygame.Rect(sprite.rect.topleft, mask.get_size()) if whole
                       else float_mask_box(sprite.rect, mask, 1))
                boxed: Iterable[int] = box.collidelistall(boxes_b)
            except (OverflowError, ValueError):  # (the masks alone decide)
                boxed = range(len(side_b))
            near = [i for i in boxed
                    if mask.overlap(mask_b[i], (side_b[i].rect[0] - x, side_b[i].rect[1] - y))]
        else:
            near = sprite.rect.collidelistall(boxes_b)
        hits = [i for i in near if not killed[i]] if second.forgets else near
        if hits:
            found[sprite] = second.met(hits)
    return found


def _collide_near(side_a: list[Any], second: _Second, boxes_b: list[pygame.Rect],
                  mask_b: list[pygame.mask.Mask] | None, whole: bool
                  ) -> dict[Any, list[Any]] | None:
    """The fast loop for big groups: each sprite of the first group tested, in C, only
    against the boxes of the second that `_near` finds by its own (in the second group's
    order, as `collidelistall` gives them), its hits met as `_Second` meets them. None, for the
    plain loop to run, where a first sprite's mask cannot be made: the masks are made
    first here, where pygame makes each at its first pair, and fails there (or never, once
    `dokillb` has emptied the second group), or a mask's box cannot be made, or an FRect's
    span (`_covering`)."""
    if mask_b is None:
        masks_a = None
        boxes_a = [s.rect for s in side_a]
    else:
        try:
            masks_a = _masks(side_a)
            boxes_a = _mask_boxes(side_a, masks_a, whole, 1)
        except Exception:  # (pygame's error, or none, is the plain loop's to give)
            return None
    spans = _spans if whole or mask_b is not None else _covering  # (masks' boxes: whole)
    spans_a, spans_b = spans(boxes_a), spans(boxes_b)
    if spans_a is None or spans_b is None:
        return None
    found: dict[Any, list[Any]] = {}
    side_b, killed = second.sprites, second.killed
    for index, near in enumerate(_near(spans_a, spans_b)):
        box = boxes_a[index]
        hits = [i for i in near if box.colliderect(boxes_b[i]) and not killed[i]]
        if hits and masks_a is not None and mask_b is not None:
            x, y = side_a[index].rect.topleft
            mask = masks_a[index]
            hits = [i for i in hits
                    if mask.overlap(mask_b[i], (side_b[i].rect[0] - x, side_b[i].rect[1] - y))]
        if hits:
            found[side_a[index]] = second.met(hits)
    return found


def _groupcollide_if_fast(groupa: Any, groupb: Any, dokilla: bool, dokillb: bool,
                          collided: Collided | None, pairs: int
                          ) -> dict[Any, list[Any]] | None:
    """groupcollide through the C tests, where its test has them, they pay from this many
    pairs and the groups can take them; None: pygame's loop, written in groupcollide,
    answers it."""
    try:
        known = collided in FAST_TESTS
    except TypeError:  # a caller's predicate that does not hash: pygame calls it all the same
        known = False
    circles = None if known else _circle_ratio(collided)
    if not known and circles is None:
        return None
    masks = known and collided in MASK_TESTS
    fast_from = (MASKS_FAST_FROM if masks else RECTS_FAST_FROM if circles is None
                 else CIRCLES_FAST_FROM)
    if pairs < fast_from:
        return None
    sides = _fast_sides(groupa, groupb, masks)
    if sides is None:
        return None
    return _groupcollide_fast(sides, groupb, dokilla, dokillb, masks, circles)


def _circle_ratio(collided: Any) -> float | None:
    """The ratio a circle test scales the radii by (1 for `collide_circle`, ours or
    pygame's; a `collide_circle_ratio`'s own), or None for any other predicate."""
    if collided is collide_circle or collided is pygame.sprite.collide_circle:
        return 1
    if isinstance(collided, (collide_circle_ratio, pygame.sprite.collide_circle_ratio)):
        return collided.ratio
    return None


def _circle_box(sprite: Any, ratio: float) -> pygame.Rect:
    """A box round the sprite's circle (its radius scaled by `ratio`) a pixel wider each
    way: the boxes of two circles that meet overlap, whatever the rounding of floats."""
    x, y = sprite.rect.center
    reach = abs(_radius(sprite) * ratio) + 1
    left, top = math.floor(x - reach), math.floor(y - reach)
    return pygame.Rect(left, top, math.ceil(x + reach) - left, math.ceil(y + reach) - top)


def _collide_circles(side_a: list[Any], second: _Second, ratio: float
                     ) -> dict[Any, list[Any]] | None:
    """Circle tests with each sprite of the first group tested, in C, against the boxes
    round the second's circles (`_circle_box`), then the circles on the boxes it meets
    (in the second group's order), its hits met as `_Second` meets them. Radii are kept on the
    sprites as pygame keeps them at a sprite's first pair: the second group's all at the
    first sprite's turn, the first's each at its own. None, for the plain loop to run,
    where a box of the second group cannot be made (no rect, a radius that is no finite
    number, a place past a Rect's): pygame fails there, or never, as the plain loop."""
    side_b, killed = second.sprites, second.killed
    try:
        boxes_b = [_circle_box(s, ratio) for s in side_b]
    except Exception:  # (pygame's error, or none, is the plain loop's to give)
        return None
    found: dict[Any, list[Any]] = {}
    for sprite in side_a:
        if not second.left:  # all killed: pygame meets no more pairs, so keeps no more radii
            break
        try:
            near: Iterable[int] = _circle_box(sprite, ratio).collidelistall(boxes_b)
        except Exception:  # (no box: the circles alone decide, or fail as pygame's do)
            near = range(len(side_b))
        hits = [i for i in near if not killed[i] and _circles(sprite, side_b[i], ratio)]
        if hits:
            found[sprite] = second.met(hits)
    return found


def _spans(boxes: list[pygame.Rect]) -> np.ndarray:
    """Each box's left, right, top and bottom as an (n, 4) array, a box of negative size
    turned the right way round (pygame meets those as they are turned)."""
    corners = np.array([tuple(box) for box in boxes], dtype=np.int64).reshape(-1, 4)
    x, y, w, h = corners.T
    return np.stack([np.minimum(x, x + w), np.maximum(x, x + w),
                     np.minimum(y, y + h), np.maximum(y, y + h)], axis=1)


# FRects' corners and sizes within it, for their spans: every whole number up to twice it
# is a float32, which `_covering` relies on.
FLOAT_LIMIT = 2.0**22


def _covering(boxes: list[Any]) -> np.ndarray | None:
    """The spans (as `_spans` gives them) of the whole pixels round each FRect: its low
    edges' floors, its high edges' ceilings. Every box `colliderect` says one meets has a
    span that overlaps its own: it compares edges x and x + w summed in float32, rounded
    to the nearest float32, and the whole numbers either side of such a sum are float32s
    (FLOAT_LIMIT), so the sum it compares lies between the floor and the ceiling of the
    sum taken here (in float64, nearer still). None where a corner or size is past
    FLOAT_LIMIT or no finite number. Invariant held by `tests/test_collide.py` against
    pygame's answers, on random boxes and on a grid of quarter pixels at 2**21 (a float32
    step there); spans a pixel narrower at both ends fail it."""
    corners = np.array([tuple(box) for box in boxes], dtype=np.float64).reshape(-1, 4)
    if not (np.abs(corners) <= FLOAT_LIMIT).all():
        return None
    x, y, w, h = corners.T
    return np.stack([np.floor(np.minimum(x, x + w)), np.ceil(np.maximum(x, x + w)),
                     np.floor(np.minimum(y, y + h)), np.ceil(np.maximum(y, y + h))],
                    axis=1).astype(np.int64)


def _near(a: np.ndarray, b: np.ndarray) -> list[list[int]]:
    """For each span of `a` (as `_spans` gives them), the indices (ascending) of the spans
    of `b` that overlap or touch it: every box that `colliderect` could say it meets, and a
    few more, which the caller asks it about. The second spans sorted by their left sides,
    each first span takes those from its left less the widest of them to its right, then
    keeps those that overlap it both ways."""
    order = np.argsort(b[:, 0], kind="stable")
    lefts = b[order, 0]
    widest = int((b[:, 1] - b[:, 0]).max())
    low = np.searchsorted(lefts, a[:, 0] - widest, "left")
    counts = np.searchsorted(lefts, a[:, 1], "right") - low
    first = np.repeat(np.arange(len(a)), counts)
    # (each first box's run of sorted places: from its low on, counted within the run)
    runs = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts - low, counts)
    second = order[runs]
    meet = ((b[second, 0] <= a[first, 1]) & (b[second, 1] >= a[first, 0])
            & (b[second, 2] <= a[first, 3]) & (b[second, 3] >= a[first, 2]))
    first, second = first[meet], second[meet]
    ranked = np.lexsort((second, first))
    first, second = first[ranked], second[ranked].tolist()
    bounds = np.searchsorted(first, np.arange(len(a) + 1)).tolist()
    return [second[bounds[i]:bounds[i + 1]] for i in range(len(a))]
