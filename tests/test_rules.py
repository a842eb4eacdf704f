"""The rules table: complete, proved minimal, and obeyed by the pipeline in real games."""

from __future__ import annotations

import itertools

import pytest

from invaders.autopilot import Autopilot
from invaders.collision.body import Kind
from invaders.collision.broadphase import Grid
from invaders.collision.pipeline import Detector
from invaders.collision.rules import (
    NEVER,
    POSITIONAL,
    RULES,
    Motion,
    discrete_counterexample,
    rule_for,
    sweep_adds_pixels,
)
from invaders.config import DEFAULT_CONFIG
from invaders.sim.world import World
from tests.helpers import SHARED_MASKS as MASKS

S = DEFAULT_CONFIG.speeds
# Every displacement a body of each kind can make in one tick (0, 0: it did not move).
MOVES = {
    Kind.SHOT: [(0, -S.shot)],
    Kind.BOMB: [(0, S.bomb), (0, S.bomb_fast), (0, 0)],
    Kind.ALIEN: [(S.rack_step, 0), (-S.rack_step, 0), (S.rack_step_last_right, 0),
                 (-S.rack_step, S.rack_drop), (S.rack_step, S.rack_drop),
                 (S.rack_step_last_right, S.rack_drop), (0, 0)],
    Kind.SAUCER: [(S.saucer, 0), (-S.saucer, 0), (0, 0)],
    Kind.CANNON: [(S.cannon, 0), (-S.cannon, 0), (0, 0)],
    Kind.BUNKER: [(0, 0)],
}


def test_every_pair_of_kinds_is_either_tested_or_excluded_with_a_reason():
    for a, b in itertools.combinations_with_replacement(Kind, 2):
        tested = rule_for(a, b) is not None
        excluded = frozenset({a, b}) in NEVER
        assert tested != excluded, (a, b)


def test_the_named_exclusions():
    assert rule_for(Kind.BOMB, Kind.ALIEN) is None  # no friendly fire
    assert rule_for(Kind.BUNKER, Kind.BUNKER) is None  # static against static
    assert rule_for(Kind.CANNON, Kind.BUNKER) is None
    for kind in Kind:
        if kind is not Kind.SHOT:
            assert rule_for(Kind.SAUCER, kind) is None
    assert rule_for(Kind.SHOT, Kind.SAUCER).zone is not None  # only in the lane


def _counterexample(rule):
    """Some displacement pair and start offset where the discrete test misses, or None."""
    for da, db in itertools.product(MOVES[rule.a], MOVES[rule.b]):
        dx, dy = db[0] - da[0], db[1] - da[1]
        if rule.b is Kind.BUNKER:  # any eroded shape: sweeping must add no pixel
            if any(sweep_adds_pixels(m, -dx, -dy) for m in MASKS[rule.a]):
                return da, db
            continue
        for ma, mb in itertools.product(MASKS[rule.a], MASKS[rule.b]):
            found = discrete_counterexample(ma, mb, dx, dy)
            if found is not None:
                return da, db, found
    return None


@pytest.mark.parametrize("rule", RULES, ids=lambda r: f"{r.a.name}-{r.b.name}")
def test_each_entry_uses_the_cheapest_motion_model_that_is_exact(rule):
    if frozenset({rule.a, rule.b}) in POSITIONAL:
        assert rule.motion is Motion.DISCRETE
        return
    missed = _counterexample(rule)
    if rule.motion is Motion.DISCRETE:
        assert missed is None, f"discrete misses {missed}: this entry must be swept"
    else:
        assert missed is not None, "discrete is exact here: sweeping is wasted work"


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
    world = World(seed=3, detector=Detector(spy))
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
