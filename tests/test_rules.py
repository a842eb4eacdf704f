"""The rules table: complete, proved minimal, and obeyed by the pipeline in real games."""

from __future__ import annotations

import itertools
import re

import pytest

from invaders.engine.adaptive import COMPILED
from invaders.engine.body import Body
from invaders.engine.detector import Detector
from invaders.engine.grid import Grid
from invaders.engine.predicates import solid_mask
from invaders.engine.proofs import discrete_miss
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.engine.store import BodyStore
from invaders.game.kinds import Kind
from invaders.game.rules import NEVER
from invaders.game.tuning import cheapest_rules, kind_moves, proof_masks
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from tests.helpers import GAME_RULES


def test_every_pair_of_kinds_is_either_tested_or_excluded_with_a_reason():
    for a, b in itertools.combinations_with_replacement(Kind, 2):
        tested = GAME_RULES.rule_for(a, b) is not None
        excluded = frozenset({a, b}) in NEVER
        assert tested != excluded, (a, b)


@pytest.mark.parametrize(("entries", "eroding", "said"), [
    ((PairRule(1, 2), PairRule(2, 1)), frozenset(), "two entries for kinds 2 and 1"),
    ((PairRule(3, 3), PairRule(3, 3)), frozenset(), "two entries for kinds 3 and 3"),
    ((PairRule(1, 2, motion=Motion.SWEPT),), frozenset({1, 2}), "both sides erode")])
def test_a_table_that_cannot_be_obeyed_is_refused_when_made(entries, eroding, said):
    """Two entries for one pair of kinds (which would answer it?), or a swept entry whose
    sides both erode (neither can be the one swept): refused, saying which; its first entry
    alone, with one side eroding, is taken."""
    with pytest.raises(ValueError, match=said):
        RuleTable(entries, eroding)
    assert list(RuleTable(entries[:1], eroding - {2})) == [entries[0]]  # (one, one eroding)


@pytest.mark.parametrize("kind", ["rocks", -1, 64, 2**70, 1.0, None])
def test_a_kind_that_is_not_a_small_whole_number_is_refused_naming_it(kind):
    """Kinds are whole numbers from 0 to 63 (a store keeps the kinds it holds as one bit
    each): anything else is refused when the entry is made, where it failed later, inside
    the store ("negative shift count", "unsupported operand type(s) for <<")."""
    if COMPILED and not isinstance(kind, int):  # (a compiled entry checks its fields' types)
        said, error = "int object expected", TypeError
    else:
        said, error = f"kind {re.escape(repr(kind))}: a whole number from 0 to 63", ValueError
    for entry in ((1, kind), (kind, 1)):
        with pytest.raises(error, match=said):
            PairRule(*entry)


def test_the_kinds_at_either_end_and_an_enums_meet():
    entries = (PairRule(0, 63, Shape.BOX, Shape.BOX), PairRule(Kind.SHOT, 63))
    store = BodyStore(RuleTable(entries).kinds())
    for kind, x in ((0, 0), (63, 1), (Kind.SHOT, 2)):
        store.add(Body(store.new_id(), kind, x, 0, solid_mask(2, 2)))
    contacts, _ = Detector(Grid(), RuleTable(entries)).detect(store)
    assert sorted(sorted((c.a_kind, c.b_kind)) for c in contacts) == [[0, 63], [Kind.SHOT, 63]]


def test_the_named_exclusions():
    assert GAME_RULES.rule_for(Kind.BOMB, Kind.ALIEN) is None  # no friendly fire
    assert GAME_RULES.rule_for(Kind.BUNKER, Kind.BUNKER) is None  # static against static
    assert GAME_RULES.rule_for(Kind.CANNON, Kind.BUNKER) is None
    for kind in Kind:
        if kind is not Kind.SHOT:
            assert GAME_RULES.rule_for(Kind.SAUCER, kind) is None
    assert GAME_RULES.rule_for(Kind.SHOT, Kind.SAUCER).zone is not None  # only in the lane


@pytest.mark.parametrize("rule", GAME_RULES.entries,
                         ids=lambda r: f"{Kind(r.a).name}-{Kind(r.b).name}")
def test_each_entry_uses_the_cheapest_motion_model_that_is_exact(rule):
    if rule.motion is Motion.LANDING:  # the original tests these where they are drawn
        assert {rule.a, rule.b} in ({Kind.ALIEN, Kind.BUNKER}, {Kind.BOMB, Kind.BUNKER})
        return
    missed = discrete_miss(rule, kind_moves(), proof_masks(kind_moves()), GAME_RULES.eroding)
    if rule.motion is Motion.DISCRETE:
        assert missed is None, f"discrete misses {missed}: this entry must be swept"
    else:
        assert missed is not None, "discrete is exact here: sweeping is wasted work"


def test_the_derived_table_is_the_hand_written_one_at_game_speed():
    assert cheapest_rules(1) == GAME_RULES


def test_faster_projectiles_need_the_shot_swept_against_shields_too():
    fast = {(r.a, r.b): r.motion for r in cheapest_rules(4)}
    assert fast[(Kind.SHOT, Kind.BUNKER)] is Motion.SWEPT
    assert fast[(Kind.BUNKER, Kind.ALIEN)] is Motion.LANDING  # where it lands, at any speed


class SpyGrid(Grid):
    """A grid that remembers the kinds of every candidate pair it reports."""

    def __init__(self) -> None:
        super().__init__()
        self.kind_pairs: set[frozenset[Kind]] = set()

    def pairs(self, scene, groups, kinds):
        out = super().pairs(scene, groups, kinds)
        self.kind_pairs.update(frozenset({a.kind, b.kind}) for a, b, _ in out)
        return out


def test_a_real_game_never_tests_an_excluded_pair():
    spy = SpyGrid()
    world = World(seed=3, detector=Detector(spy, GAME_RULES))
    pilot = Autopilot(3)
    seen_kinds: set[Kind] = set()
    for _ in range(5000):
        world.step(pilot.actions(world))
        seen_kinds.update(k for k in Kind if world.bodies(k))
    assert seen_kinds == set(Kind)  # every kind was on screen at some point
    assert spy.kind_pairs  # and pairs were tested
    for pair in spy.kind_pairs:
        assert pair not in NEVER, pair
    assert frozenset({Kind.BOMB, Kind.ALIEN}) not in spy.kind_pairs
    assert frozenset({Kind.BUNKER}) not in spy.kind_pairs
    assert all(Kind.SAUCER not in pair or Kind.SHOT in pair for pair in spy.kind_pairs)


@pytest.mark.parametrize(("field", "value", "said"), [
    ("a_shape", "mask", "a_shape 'mask': one of Shape.BOX, Shape.MASK"),
    ("b_shape", Motion.SWEPT, "b_shape <Motion.SWEPT: 'swept'>: one of Shape.BOX"),
    ("motion", "swept", "motion 'swept': one of Motion.DISCRETE, Motion.SWEPT, Motion.LAND"),
    ("zone", ((0, 0, 2.5, 4),), r"zone box \(0, 0, 2.5, 4\): four whole numbers"),
    ("zone", ((0, 0, 4),), r"zone box \(0, 0, 4\): four whole numbers"),
    ("zone", (0, 0, 4, 4), "zone box 0: four whole numbers, .*a zone is a tuple of such"),
    ("zone", 7, "zone 7: a tuple of boxes"),
    ("zone", ((0, 0, -1, 4),), r"zone box \(0, 0, -1, 4\): a width or height below 0")])
def test_an_entry_that_is_not_one_is_refused_when_made_naming_the_field(field, value, said):
    """A shape or motion given by its value's string passed as the other member (every
    shape not `Shape.MASK` was tested as a box: pixels silently ignored), and a zone's box
    of floats, three numbers, or a flat tuple failed inside a tick; a negative size meant
    a box that holds nothing."""
    typed = field != "zone" or not isinstance(value, tuple)  # (compiled, the field's type)
    if COMPILED and typed:
        with pytest.raises(TypeError):
            PairRule(1, 2, **{field: value})
        return
    with pytest.raises(ValueError, match=said):
        PairRule(1, 2, **{field: value})


def _meets_in(zone, x) -> bool:
    """Whether a 2 px square at (x, 0) meets a probe on it, kind 1 and 2 paired only in
    `zone`."""
    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion.DISCRETE, zone=zone),))
    store = BodyStore(rules.kinds())
    for kind in (1, 2):
        store.add(Body(store.new_id(), kind, x, 0, solid_mask(2, 2)))
    return bool(Detector(Grid(), rules).detect(store)[0])


def test_a_zone_is_read_as_whole_numbers_and_a_box_of_no_area_holds_nothing():
    """Boxes as lists of NumPy integers are a zone as tuples of ints are; a box of no width (here
    inside the bodies' boxes) holds no pixel and is left out, where the index met it or
    not by where it stood on its cells; and a box of any size is taken (one 10^30 px wide
    overflowed counting its cells)."""
    import numpy as np

    as_lists = PairRule(1, 2, zone=([np.int64(0), 0, np.int32(10), 10],))
    assert as_lists.zone == ((0, 0, 10, 10),)
    assert type(as_lists.zone[0][0]) is int
    assert PairRule(1, 2, zone=((5, 0, 0, 10), (0, 0, 10, 10))).zone == ((0, 0, 10, 10),)
    for x in (63, 64, 65):  # (the index's cells are 64 px)
        assert not _meets_in(((x + 1, 0, 0, 2),), x)
        assert _meets_in(((x + 1, 0, 1, 2),), x)
    assert _meets_in(((-10**30, -5, 2 * 10**30, 10),), 40)
    assert not _meets_in(((-10**30, 5, 2 * 10**30, 10),), 40)
