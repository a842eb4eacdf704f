"""Learning tests that pin pygame's overlap convention, and our one-pixel boundaries."""

from __future__ import annotations

import itertools
import pickle
import random

import pygame
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.engine import predicates
from invaders.engine.detector import _at
from invaders.engine.pickling import mask_bytes, reduce_with_masks
from tests.helpers import mask


def test_pygame_overlap_offset_is_the_other_corner_relative_to_self():
    # self has one pixel at (2, 1); other has one pixel at (0, 0).
    me = mask("....", "..#.", "....")
    other = mask("#.", "..")
    assert me.overlap(other, (2, 1)) == (2, 1)  # other's corner placed at me's (2, 1)
    assert me.overlap(other, (1, 1)) is None
    assert me.overlap(other, (2, 0)) is None
    # The answer is in self's coordinates, even when other sits up and left.
    other2 = mask("..", ".#")  # lit at (1, 1)
    assert me.overlap(other2, (1, 0)) == (2, 1)


def test_mask_offset_is_b_minus_a():
    assert predicates.mask_offset(10, 20, 13, 18) == (3, -2)


@pytest.mark.parametrize("side", [(1, 0), (-1, 0), (0, 1), (0, -1)])
def test_rects_touching_do_not_overlap_one_shared_pixel_does(side):
    # a covers x and y 0..3; b (4x4) 4 px off on a side touches it, 3 px off shares a row
    # or column of pixels; either way round, as pygame's colliderect answers.
    a = (0, 0, 4, 4)
    touching = (4 * side[0], 4 * side[1], 4, 4)
    sharing = (3 * side[0], 3 * side[1], 4, 4)
    for first, second in ((a, touching), (touching, a)):
        assert not predicates.rects_overlap(*first, *second)
        assert not pygame.Rect(first).colliderect(second)
    for first, second in ((a, sharing), (sharing, a)):
        assert predicates.rects_overlap(*first, *second)
        assert pygame.Rect(first).colliderect(second)


def test_a_rect_of_one_pixel_overlaps_the_pixel_it_covers():
    assert predicates.rects_overlap(0, 0, 4, 4, 3, 3, 1, 1)  # the corner pixel alone
    assert not predicates.rects_overlap(0, 0, 4, 4, 4, 3, 1, 1)


def test_masks_touching_versus_one_pixel_overlap():
    left = mask("..#", ".##", "###")  # lit right edge at x=2
    right = mask("#..", "##.", "###")  # lit left edge at x=0
    # Placed side by side with no gap: edges touch, no shared pixel.
    assert predicates.masks_overlap(left, 0, 0, right, 3, 0) is None
    # One column closer: exactly the column x=2 is shared.
    assert predicates.masks_overlap(left, 0, 0, right, 2, 0) == (2, 0)
    # Boxes overlapping while lit pixels do not: the empty corners.
    dot = mask("#..", "...", "...")
    assert predicates.masks_overlap(left, 0, 0, dot, 1, 0) is None
    assert predicates.masks_overlap(left, 0, 0, dot, 1, 1) == (1, 1)


def test_substeps_are_one_pixel_apart_and_include_both_ends():
    steps = predicates.substeps(3, -7)
    assert steps[0] == (0, 0) and steps[-1] == (3, -7)
    assert len(steps) == 8
    for (x0, y0), (x1, y1) in itertools.pairwise(steps):
        assert abs(x1 - x0) <= 1 and abs(y1 - y0) == 1
    assert predicates.substeps(0, 0) == ((0, 0),)


def test_swept_contact_is_the_first_substep_that_touches():
    wall = mask("#")  # a one-pixel wall at (0, 0)
    bar = mask("#", "#", "#", "#")  # 1x4, starting below the wall, moving up 12
    found = predicates.first_swept_contact(wall, bar, 0, 5, 0, -12)
    assert found is not None
    step, steps, pixel = found
    assert (step, steps, pixel) == (5, 12, (0, 0))  # five rows up, the bar's top reaches it
    # Neither end touches, so a discrete test would have missed it.
    assert wall.overlap(bar, (0, 5)) is None and wall.overlap(bar, (0, -7)) is None


def test_the_swept_masks_kept_are_bounded_however_many_masks_come():
    # A program that makes its sprites' masks afresh each frame brings a new mask (a new
    # key: masks hash by identity) to every swept test; the cache must not keep them all.
    bar = mask("#", "#")
    first = predicates.swept_mask(bar, 0, 3)
    for _ in range(5000):
        predicates.swept_mask(mask("#", "#"), 0, 3)
        assert len(predicates._swept_cache) <= 4097
    # Cleared on the way, it makes the same union again: a bar 1x5.
    again = predicates.swept_mask(bar, 0, 3)
    assert again.get_size() == (1, 5) and again.count() == 5
    assert again.overlap_area(first, (0, 0)) == 5


class Holding:
    """An object holding a mask, pickled as a world is (its masks by `reduce_with_masks`)."""

    def __init__(self, held: pygame.mask.Mask) -> None:
        self.held = held

    def __reduce__(self):
        return reduce_with_masks(self)


def _pickled(held: pygame.mask.Mask) -> pygame.mask.Mask:
    return pickle.loads(pickle.dumps(Holding(held))).held


def test_solid_masks_are_shared_while_kept_and_the_longest_unasked_let_go_first():
    # Two masks each over half the pixels kept: every mask kept before is let go, and
    # then the first of the two, whatever earlier tests asked for.
    wide = predicates.SOLID_KEPT_PIXELS // 2 // 2048 + 1
    predicates.solid_mask(wide, 2048)
    predicates.solid_mask(wide + 1, 2048)
    first, second = predicates.solid_mask(1, 1), predicates.solid_mask(1, 2)
    assert first is predicates.solid_mask(1, 1) and first.count() == 1  # asked: the latest
    assert _pickled(first) is first  # (pickled as the call: the process's own again)
    for h in range(3, predicates.SOLID_KEPT + 2):  # the count passed twice: the big mask
        predicates.solid_mask(1, h)  # let go, then the longest unasked of the two
    assert predicates.solid_mask(1, 1) is first
    again = predicates.solid_mask(1, 2)
    assert again is not second and mask_bytes(again) == mask_bytes(second)
    loaded = _pickled(second)  # let go: pickled as its pixels, a mask of its own
    assert loaded is not second and loaded is not again
    assert mask_bytes(loaded) == mask_bytes(second) and loaded.get_size() == (1, 2)


def test_swept_box_overlap_matches_the_union_of_positions():
    assert predicates.swept_box_overlap(1, 1, 1, 4, 0, 5, 0, -12)
    assert not predicates.swept_box_overlap(1, 1, 1, 4, 1, 5, 0, -12)


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), ox=st.integers(-12, 12), oy=st.integers(-12, 12),
       dx=st.integers(-10, 10), dy=st.integers(-10, 10), from_start=st.booleans())
def test_swept_contact_is_the_first_touching_substep_of_the_path(seed, ox, oy, dx, dy,
                                                               from_start):
    """Against the definition: every substep of the path tested in turn (the swept mask
    only shortens the search and must never change its answer)."""
    rng = random.Random(seed)

    def random_mask() -> pygame.mask.Mask:
        w, h = rng.randrange(1, 9), rng.randrange(1, 9)
        return mask(*("".join(rng.choice("#..") for _ in range(w)) for _ in range(h)))

    fixed, moving = random_mask(), random_mask()
    path = predicates.substeps(dx, dy)
    steps = len(path) - 1
    expected = None
    for i in range(0 if from_start else 1, steps + 1):
        hit = fixed.overlap(moving, (ox + path[i][0], oy + path[i][1]))
        if hit is not None:
            expected = (i, steps, hit)
            break
    if steps == 0:  # no motion: the one position is tested, whatever from_start says
        hit = fixed.overlap(moving, (ox, oy))
        expected = None if hit is None else (0, 0, hit)
    assert predicates.first_swept_contact(fixed, moving, ox, oy, dx, dy, from_start) == expected


def test_a_body_at_a_substep_is_its_own_motion_rounded_as_the_path_is():
    for x0, x1, y0, y1 in itertools.product(range(-6, 7), range(-6, 7), (-3, 0, 2), (-2, 0, 3)):
        for steps in range(0, 9):
            for step in range(steps + 1):
                expected = (x1, y1) if steps == 0 else (
                    x0 + predicates.round_div((x1 - x0) * step, steps),
                    y0 + predicates.round_div((y1 - y0) * step, steps))
                assert _at(x0, y0, x1, y1, step, steps) == expected


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), dx=st.integers(-3000, 3000), dy=st.integers(-3000, 3000),
       at=st.floats(-0.2, 1.2), jitter=st.tuples(st.integers(-12, 12), st.integers(-12, 12)),
       from_start=st.booleans())
def test_a_long_motion_is_walked_where_the_boxes_meet_with_the_paths_answer(
        seed, dx, dy, at, jitter, from_start):
    """A motion whose swept mask would be big (its area grows as the square of the motion,
    and the cache kept each), or whose path is long (kept too), is walked over the
    substeps where the boxes overlap alone: the answer of every substep tested in turn,
    the fixed mask placed near some point of the path (or past either end), and no swept
    mask made nor path kept."""
    rng = random.Random(seed)

    def random_mask() -> pygame.mask.Mask:
        w, h = rng.randrange(1, 30), rng.randrange(1, 30)
        return mask(*("".join(rng.choice("#..") for _ in range(w)) for _ in range(h)))

    fixed, moving = random_mask(), random_mask()
    steps = max(abs(dx), abs(dy))
    near = predicates.substep(dx, dy, round(at * steps))
    ox, oy = jitter[0] - near[0], jitter[1] - near[1]
    path = predicates.substeps(dx, dy)
    assert all(predicates.substep(dx, dy, i) == path[i] for i in range(0, steps + 1, 97))
    expected = None
    for i in range(0 if from_start or not steps else 1, steps + 1):
        hit = fixed.overlap(moving, (ox + path[i][0], oy + path[i][1]))
        if hit is not None:
            expected = (i, steps, hit)
            break
    before = len(predicates._swept_cache)
    predicates.substeps.cache_clear()
    assert predicates.first_swept_contact(fixed, moving, ox, oy, dx, dy, from_start) == expected
    long = (moving.get_size()[0] + abs(dx)) * (moving.get_size()[1] + abs(dy))
    if long > predicates.SWEPT_BITS or steps > predicates.LONG_STEPS:
        assert (moving, dx, dy) not in predicates._swept_cache
        assert len(predicates._swept_cache) == before
        assert predicates.substeps.cache_info().currsize == 0
