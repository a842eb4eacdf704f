"""The detector's kept answers, each against the change that must end it: the plan when
bodies come or go, the groups when another store is given, and the broad phase's last
candidates when it hears of a move (the last: `test_broadphase.py`, detectors taking turns).
And its steps: the quick test means the same for every motion."""

from __future__ import annotations

import pygame
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from invaders.engine import predicates
from invaders.engine.body import Body
from invaders.engine.broadphase import Brute
from invaders.engine.detector import Detector
from invaders.engine.grid import Grid
from invaders.engine.rects import CellRects
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.engine.stats import CollisionStats, Contact
from invaders.engine.store import BodyStore

BLOCK = pygame.mask.Mask((4, 4), fill=True)
BROAD = pytest.mark.parametrize("make", [Grid, CellRects, Brute], ids=["grid", "rects", "brute"])


def _rules(motion: Motion = Motion.DISCRETE, shape: Shape = Shape.BOX) -> RuleTable:
    return RuleTable((PairRule(1, 2, shape, shape, motion),))


def _store(*places: tuple[int, int, int]) -> BodyStore:
    """A store with a 4x4 block of kind k at (x, y) for each (k, x, y), ids from 1."""
    store = BodyStore((1, 2))
    for kind, x, y in places:
        store.add(Body(store.new_id(), kind, x, y, BLOCK))
    return store


def _found(detector: Detector, store: BodyStore) -> tuple[list[tuple[int, int]], int]:
    contacts, stats = detector.detect(store)
    return [(c.a_id, c.b_id) for c in contacts], stats.allowed_pairs


@BROAD
def test_the_plan_follows_bodies_coming_and_going(make):
    store = _store((1, 0, 0), (2, 40, 0))
    detector = Detector(make(), _rules())
    assert _found(detector, store) == ([], 1)
    store.tick += 1
    store.add(Body(store.new_id(), 2, 2, 2, BLOCK))  # a second target, on the probe
    assert _found(detector, store) == ([(1, 3)], 2)
    store.tick += 1
    store.remove(store.by_id[3])
    assert _found(detector, store) == ([], 1)
    store.tick += 1
    store.remove(store.by_id[2])  # no target left: the entry no longer applies
    assert _found(detector, store) == ([], 0)


@BROAD
def test_a_detector_given_another_store_tests_that_stores_bodies(make):
    """The groups are kept per set of kinds present, for one store: another store with the
    same kinds present gets groups of its own bodies."""
    detector = Detector(make(), _rules())
    touching, apart = _store((1, 0, 0), (2, 2, 2)), _store((1, 0, 0), (2, 40, 0))
    assert _found(detector, touching) == ([(1, 2)], 1)
    assert _found(detector, apart) == ([], 1)
    assert _found(detector, touching) == ([(1, 2)], 1)


@pytest.mark.parametrize("motion", [Motion.DISCRETE, Motion.SWEPT, Motion.LANDING])
def test_a_quick_test_given_takes_the_box_tests_place_for_every_motion(motion):
    """A study's stand-in for the quick test decides which pairs go on to the thorough test,
    whatever the entry's motion: one that passes nothing leaves no contact, one that passes
    everything leaves the pixel test to decide (two blocks overlapping meet; two apart,
    whose boxes the stand-in let through, do not)."""
    for quick, expected in ((lambda a, b: False, []), (lambda a, b: True, [(1, 2)])):
        detector = Detector(Brute(), _rules(motion, Shape.MASK), quick=quick)
        assert _found(detector, _store((1, 0, 0), (2, 2, 2)))[0] == expected
        contacts, stats = detector.detect(_store((1, 0, 0), (2, 40, 0)))
        assert contacts == [] and stats.rect_hits == (1 if expected else 0)


def test_counters_and_contacts_are_built_whole():
    """Every field given, in order: a missing or extra value is refused where it is made."""
    with pytest.raises(TypeError):
        CollisionStats(*range(11))
    with pytest.raises(TypeError):
        Contact(*range(14))
    store = _store((1, 0, 0), (2, 2, 2))
    contacts, stats = Detector(Grid(), _rules()).detect(store)
    assert len(stats) == len(CollisionStats._fields) and stats.contacts == 1
    assert len(contacts[0]) == len(Contact._fields)


DOT = pygame.mask.Mask((4, 4))  # a 4x4 box with its top-left pixel alone lit
DOT.set_at((0, 0))


def _stats_at(detector: Detector, store: BodyStore, moves: dict[int, tuple[int, int]]
              ) -> CollisionStats:
    """The next tick's counters, the bodies `moves` names moved to their places a tick
    before it (a body's box over a tick covers where it went from)."""
    for tick in range(2):
        store.tick += 1
        for body_id, (x, y) in (moves if tick == 0 else {}).items():
            store.move(store.by_id[body_id], x, y)
        stats = detector.detect(store)[1]
    return stats


@pytest.mark.parametrize("make", [Grid, CellRects], ids=["grid", "rects"])
def test_the_counters_count_a_zones_pairs_on_every_tick(make):
    """A probe (kind 1) and a target whose box it meets but not its pixel (kind 2), plus
    a body of kind 3 that the rules pair with the probe only inside a zone, coming into
    it and going out: every tick's counters, field by field, counted by hand. The pairs
    the zone allows count whether or not any is a candidate, and a tick's counters are
    never those of a tick that had other zoned pairs."""
    rules = RuleTable((PairRule(1, 2, Shape.MASK, Shape.MASK, Motion.DISCRETE),
                       PairRule(1, 3, Shape.BOX, Shape.BOX, Motion.DISCRETE,
                                zone=((0, 0, 50, 50),))))
    store = BodyStore((1, 2, 3))
    store.add(Body(store.new_id(), 1, 0, 0, DOT))  # 1: the probe
    store.add(Body(store.new_id(), 2, 2, 2, BLOCK))  # 2: boxes meet, pixels do not
    store.add(Body(store.new_id(), 3, 40, 40, BLOCK))  # 3: in the zone, far from the probe
    detector = Detector(make(16), rules)
    #         objects, naive, allowed, candidates, rect tests and hits, mask tests and
    #         hits, swept tests, contacts
    near = CollisionStats(3, 3, 1, 1, 1, 1, 1, 0, 0, 0)
    assert detector.detect(store)[1] == near._replace(allowed_pairs=2)
    assert _stats_at(detector, store, {3: (300, 300)}) == near  # out of the zone
    parted = near._replace(rect_hits=0, mask_tests=0)  # the target a pixel past the box
    assert _stats_at(detector, store, {2: (4, 4), 3: (40, 40)}) == parted._replace(
        allowed_pairs=2)
    assert _stats_at(detector, store, {3: (300, 300)}) == parted
    alone = CollisionStats(3, 3, 1)  # the target far: no candidate
    assert _stats_at(detector, store, {2: (100, 0)}) == alone
    assert _stats_at(detector, store, {3: (40, 40)}) == alone._replace(allowed_pairs=2)
    assert _stats_at(detector, store, {2: (0, 0)}) == near._replace(
        allowed_pairs=2, mask_hits=1, contacts=1)


PLACES = st.tuples(st.integers(-5, 5), st.integers(-5, 5))
SIZES = st.tuples(st.integers(1, 3), st.integers(1, 3))


@settings(max_examples=1000)
@example(sizes=((1, 1), (2, 1)), starts=((0, 0), (-2, 0)), ends=((0, 0), (-4, 0)), swept=True)
@example(sizes=((1, 1), (1, 2)), starts=((0, 0), (0, -2)), ends=((0, 0), (0, -4)), swept=True)
@given(sizes=st.tuples(SIZES, SIZES), starts=st.tuples(PLACES, PLACES),
       ends=st.tuples(PLACES, PLACES), swept=st.booleans())
def test_the_quick_test_passes_a_pair_exactly_when_its_boxes_meet(sizes, starts, ends,
                                                                  swept):
    """Step 2 on one pair of moving boxes (every pair a candidate): passed when their
    boxes meet at the tick's end or, swept, when b's box swept along the pair's relative
    motion meets a's (`swept_box_overlap`): never a pair more or less."""
    motion = Motion.SWEPT if swept else Motion.DISCRETE
    detector = Detector(Brute(), RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, motion),)))
    store = BodyStore((1, 2))
    bodies = [Body(store.new_id(), kind, *start, pygame.mask.Mask(size, fill=True))
              for kind, start, size in zip((1, 2), starts, sizes, strict=True)]
    for body in bodies:
        store.add(body)
    store.tick += 1
    for body, end in zip(bodies, ends, strict=True):
        store.move(body, *end)
    (aw, ah), (bw, bh) = sizes
    (ax0, ay0), (bx0, by0) = starts
    (ax1, ay1), (bx1, by1) = ends
    if swept:
        meet = predicates.swept_box_overlap(aw, ah, bw, bh, bx0 - ax0, by0 - ay0,
                                            bx1 - bx0 - (ax1 - ax0), by1 - by0 - (ay1 - ay0))
    else:
        meet = predicates.rects_overlap(ax1, ay1, aw, ah, bx1, by1, bw, bh)
    assert detector.detect(store)[1].rect_hits == meet


BOXES = st.tuples(st.integers(-300_000, 300_000), st.integers(-300_000, 300_000),
                  st.integers(1, 200_000) | st.integers(1, 100),
                  st.integers(1, 200_000) | st.integers(1, 100))
SPOTS = st.tuples(st.integers(-300_000, 300_000), st.integers(-300_000, 300_000))


@settings(max_examples=500)
@given(zone=st.lists(BOXES, min_size=1, max_size=4), start=SPOTS, end=SPOTS,
       near=st.booleans())
def test_a_zone_holds_a_body_exactly_when_their_boxes_meet_whatever_their_sizes(
        zone, start, end, near):
    """A zone's index against every box of the zone met by hand, for boxes from 1 to
    200,000 px wide and a body swept up to 600,000 px: the same answer. (A box that
    large took seconds and a gigabyte to bin cell by cell, and a body that large walked
    every cell it crossed.)"""
    from invaders.engine.body import tick_box
    from invaders.engine.detector import BINNED, ZoneIndex

    if near:  # (a short move, mostly among the cells)
        end = (start[0] + end[0] % 200 - 100, start[1] + end[1] % 200 - 100)
    store = BodyStore((1,))
    body = Body(store.new_id(), 1, *start, DOT)
    store.add(body)
    store.tick += 1
    store.move(body, *end)
    index = ZoneIndex(tuple(zone))
    x0, y0, x1, y1 = tick_box(body, store.tick)
    assert index.holds(body, store.tick) == any(
        x0 < zx + zw and zx < x1 and y0 < zy + zh and zy < y1 for zx, zy, zw, zh in zone)
    assert len(index.cells) <= BINNED * len(zone)  # (what binning cost)
