"""Where methods fail, and that ours holds: thin targets, crossings, circles, big and
off-screen bodies, touching edges, stalls."""

from __future__ import annotations

from pathlib import Path

import pygame
import pytest

from invaders.app.play import Session
from invaders.engine.body import Body
from invaders.engine.broadphase import Brute
from invaders.engine.detector import Detector
from invaders.engine.grid import Grid
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.game.kinds import Kind
from invaders.game.replay import load, run
from invaders.lab.methods import circles, corners_inside, rect
from tests.helpers import GAME_RULES, store_of

BAR_RULE = RuleTable((PairRule(Kind.SHOT, Kind.BUNKER, Shape.BOX, Shape.MASK, Motion.DISCRETE,
                               reason="a bar against a slab"),), frozenset({Kind.BUNKER}))
SWEPT_BAR_RULE = RuleTable((PairRule(Kind.SHOT, Kind.BUNKER, Shape.BOX, Shape.MASK, Motion.SWEPT,
                                     reason="a bar against a slab, swept"),),
                           frozenset({Kind.BUNKER}))


def _passes(rules, length: int, thickness: int, step: int, start: int) -> bool:
    """Does a 1 x length bar rising `step` px a tick get past a slab `thickness` thick?"""
    slab = Body(1, Kind.BUNKER, 0, 100, pygame.mask.Mask((3, thickness), fill=True))
    bar = Body(2, Kind.SHOT, 1, 100 + thickness + start, pygame.mask.Mask((1, length), fill=True))
    detector = Detector(Brute(), rules)
    for tick in range(1, 200):
        bar.px, bar.py, bar.moved_tick = bar.x, bar.y, tick
        bar.y -= step
        contacts, _ = detector.detect(store_of([slab, bar], tick))
        if contacts:
            return False
        if bar.y + length <= 100:
            return True
    raise AssertionError("never got past")


@pytest.mark.parametrize("length", [1, 2, 4, 7])
@pytest.mark.parametrize("thickness", [1, 2, 3])
def test_discrete_misses_a_thin_target_exactly_when_the_step_reaches_length_plus_thickness(
        length, thickness):
    for step in range(1, 17):
        starts = range(step)  # every phase of the motion against the slab
        discrete_misses = any(_passes(BAR_RULE, length, thickness, step, s) for s in starts)
        assert discrete_misses == (step >= length + thickness), (step, length, thickness)
        assert not any(_passes(SWEPT_BAR_RULE, length, thickness, step, s) for s in starts)


def test_a_corner_only_test_misses_a_crossing_that_the_rect_test_finds():
    tall, wide = (10, 0, 4, 30), (0, 12, 30, 4)  # a plus sign: no corner inside the other
    assert rect(tall, wide)
    assert not corners_inside(tall, wide)
    assert corners_inside((0, 0, 4, 4), (3, 3, 4, 4))  # it does see an ordinary overlap


def test_bounding_circles_report_boxes_that_are_apart():
    a, b = (0, 0, 10, 10), (11, 0, 10, 10)  # side by side, one pixel apart
    assert not rect(a, b)
    assert circles(a, b)
    assert not circles((0, 0, 10, 10), (40, 0, 10, 10))


def _big_scene() -> list[Body]:
    from invaders.game import art

    bodies = []
    # A shield far larger than a small cell, a shot just inside its edge and one touching it
    # from outside (no contact), a shield and a bomb partly off the left of the playfield,
    # and a bomb and a cannon far off-screen.
    bodies.append(Body(1, Kind.BUNKER, 0, 0, art.fresh_mask(art.BUNKER)))
    bodies.append(Body(2, Kind.SHOT, 21, 10, art.mask_of(art.SHOT)))  # inside col 21
    bodies.append(Body(3, Kind.SHOT, 22, 10, art.mask_of(art.SHOT)))  # touching its right edge
    bodies.append(Body(4, Kind.BUNKER, -10, 200, art.fresh_mask(art.BUNKER)))  # partly off
    bodies.append(Body(5, Kind.BOMB, -2, 205, art.mask_of(art.BOMB_PLUNGER[0])))
    bodies.append(Body(6, Kind.BOMB, 300, 300, art.mask_of(art.BOMB_PLUNGER[0])))  # off-screen
    bodies.append(Body(7, Kind.CANNON, 296, 299, art.mask_of(art.CANNON)))
    return bodies


@pytest.mark.parametrize("cell", [1, 4, 16, 128])
def test_big_off_screen_and_touching_bodies_agree_with_brute_force(cell):
    scene = store_of(_big_scene())
    brute, _ = Detector(Brute(), GAME_RULES).detect(scene)
    grid, stats = Detector(Grid(cell), GAME_RULES).detect(scene)
    assert grid == brute
    assert {(c.a_id, c.b_id) for c in grid} == {(1, 2), (4, 5), (6, 7)}
    assert stats.candidates >= 3


def test_a_stall_of_seconds_changes_nothing_but_the_pace():
    path = Path(__file__).resolve().parents[1] / "replays" / "cannon-death.json"
    replay = load(path)
    expected, _ = run(replay)
    from invaders.game.world import World

    world = World(replay.seed, replay.config)
    now = [0.0]
    session = Session(world, pygame.Surface((224, 256)), lambda: now[0],
                      replay=replay)
    frames = 0
    while not session.replay_done:
        now[0] += 5.0 if frames == 100 else 1 / 60  # the window is dragged for 5 s
        session.frame(0)
        frames += 1
    assert session.loop.dropped_ticks > 250  # it slowed down instead of racing to catch up
    assert world.state_hash() == expected.final.hash
