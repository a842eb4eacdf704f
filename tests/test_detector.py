"""The detector's kept answers, each against the change that must end it: the plan when
bodies come or go, the groups when another store is given, and the broad phase's last
candidates when it hears of a move (the last: `test_broadphase.py`, detectors taking turns).
And its steps: the quick test means the same for every motion."""

from __future__ import annotations

import pygame
import pytest

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
