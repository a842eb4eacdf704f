"""The motion proofs: every start offset tried at once by mask algebra, held to trying
them one by one."""

from __future__ import annotations

import pygame
from hypothesis import given
from hypothesis import strategies as st

from invaders.engine import predicates
from invaders.engine.proofs import discrete_counterexample


def each_offset_in_turn(fixed, moving, dx, dy):
    """The first offset, rows top to bottom, at which the sweep touches and neither end
    does: the definition, tried one offset at a time."""
    fw, fh = fixed.get_size()
    mw, mh = moving.get_size()
    swept = predicates.swept_mask(moving, dx, dy)
    for oy in range(-mh - abs(dy), fh + abs(dy) + 1):
        for ox in range(-mw - abs(dx), fw + abs(dx) + 1):
            if fixed.overlap(moving, (ox, oy)) or fixed.overlap(moving, (ox + dx, oy + dy)):
                continue
            if fixed.overlap(swept, (ox + min(0, dx), oy + min(0, dy))):
                return ox, oy
    return None


@st.composite
def masks(draw, most: int):
    w, h = draw(st.integers(0, most)), draw(st.integers(0, most))
    bits = draw(st.lists(st.booleans(), min_size=w * h, max_size=w * h))
    mask = pygame.mask.Mask((w, h))
    for i, bit in enumerate(bits):
        if bit:
            mask.set_at((i % w, i // w))
    return mask


@given(masks(9), masks(6), st.integers(-12, 12), st.integers(-12, 12))
def test_the_first_witness_is_the_one_found_offset_by_offset(fixed, moving, dx, dy):
    assert discrete_counterexample(fixed, moving, dx, dy) == each_offset_in_turn(
        fixed, moving, dx, dy)


def test_a_thin_bar_is_crossed_unseen_from_a_known_offset():
    bar = pygame.mask.Mask((8, 1), fill=True)
    dot = pygame.mask.Mask((1, 1), fill=True)
    assert discrete_counterexample(bar, dot, 0, 2) == (0, -1)  # above it, then below it
    assert discrete_counterexample(bar, dot, 0, 1) is None  # a step of 1 lands on it
