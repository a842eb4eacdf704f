"""The playfield's edges are contacts too: the top limit and the ground take part in a
tick's contacts in time order, so what a projectile crosses on its last move before an
edge is hit, at any speed, and the oracle sees the edges as the detector does."""

from __future__ import annotations

from fractions import Fraction

import pytest

from invaders.game.config import DEFAULT_CONFIG
from invaders.game.entities import MOVES_BETWEEN_LOOKS, Bomb, BombType, Saucer, Shot, edge_depth
from invaders.game.events import Event
from invaders.game.kinds import Kind
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from invaders.lab.choices import MULTIPLIERS, SAMPLINGS
from invaders.lab.live import Choice, at_speed, install
from tests.helpers import active_world

SPEEDS = (1, 2, 4, 8, 16)
G = DEFAULT_CONFIG.geometry


def _world_at(multiplier: int) -> World:
    world = active_world(seed=0, config=at_speed(DEFAULT_CONFIG, multiplier))
    world.alien_fire_timer = -1  # no bomb but the test's own
    return world


def test_the_edges_are_boxes_from_their_lines_deeper_than_any_move_between_looks():
    world = World()
    (top,), (ground,) = world.bodies(Kind.TOP), world.bodies(Kind.GROUND)
    assert (top.x, top.y + top.h, top.w) == (0, G.shot_top_limit + 1, 224)
    assert (ground.x, ground.y, ground.w) == (0, G.bomb_ground_top + 8 - 1, 224)
    assert max(MULTIPLIERS) * max(SAMPLINGS) == MOVES_BETWEEN_LOOKS  # the lab's limits
    farthest = MOVES_BETWEEN_LOOKS * DEFAULT_CONFIG.speeds.bomb_fast  # 16x, every 8th tick
    assert top.h == ground.h == edge_depth(DEFAULT_CONFIG) >= farthest
    assert top.id < ground.id < 1 <= min(b.id for b in world.store.by_id.values()
                                         if b.kind not in (Kind.TOP, Kind.GROUND))
    assert "top" not in world.kind_counts() and "ground" not in world.kind_counts()


@pytest.mark.parametrize("multiplier", SPEEDS)
def test_a_bomb_that_crosses_the_cannon_on_its_last_move_hits_it(multiplier):
    world = _world_at(multiplier)
    step = world.config.speeds.bomb
    y = G.bomb_ground_top - step * ((G.bomb_ground_top - 150) // step)  # lands on the line
    slot = world.slots[BombType.ROLLING]
    bomb = slot.bomb = Bomb(world.store.new_id(), BombType.ROLLING, world.cannon.x + 7, y)
    world.store.add(bomb)
    ships = world.ships
    for _ in range(400):
        report = world.step(0)
        if not bomb.alive:
            break
    # (it bursts on the cannon: its one contact is the cannon's, not the ground's)
    assert Event.CANNON_HIT in report.events and Event.BOMB_BURST in report.events
    (contact,) = report.contacts
    assert {contact.a_kind, contact.b_kind} == {Kind.CANNON, Kind.BOMB}
    assert bomb.id in (contact.a_id, contact.b_id)
    if G.bomb_ground_top - step + 8 <= G.cannon_top:  # from above the cannon to the line
        assert bomb.y >= G.bomb_ground_top and contact.time < 1  # on its last move
    while world.cannon.timer > 0:
        world.step(0)
    world.step(0)
    assert world.ships == ships - 1


@pytest.mark.parametrize("multiplier", SPEEDS)
def test_a_shot_that_crosses_the_saucer_lane_on_its_last_move_hits_the_saucer(multiplier):
    world = _world_at(multiplier)
    store = world.store
    ship = world.saucer.saucer = Saucer(store.new_id(), 100, G.saucer_top, 2)
    store.add(ship)
    step = world.config.speeds.shot
    shot = world.shot = Shot(store.new_id(), 107, G.shot_top_limit + step)  # one move left
    store.add(shot)
    report = world.step(0)
    assert Event.SAUCER_HIT in report.events and Event.SHOT_BURST not in report.events
    assert not shot.alive and not ship.alive


@pytest.mark.parametrize("multiplier", SPEEDS)
def test_a_shot_that_meets_nothing_bursts_at_the_top_limit_whatever_its_speed(multiplier):
    world = _world_at(multiplier)
    step = world.config.speeds.shot
    start = G.shot_top_limit + 1 + step // 2
    shot = world.shot = Shot(world.store.new_id(), 60, start)
    world.store.add(shot)
    report = world.step(0)
    assert report.events == (Event.SHOT_BURST,)
    (contact,) = report.contacts
    assert (contact.a_kind, contact.b_kind) == (Kind.TOP, Kind.SHOT)
    assert (contact.bx, contact.by) == (60, start - step)  # where it landed, past the line
    assert contact.time == Fraction(start - G.shot_top_limit, step)  # when it reached it
    (burst,) = world.explosions  # with its top on the line
    assert (burst.x, burst.y) == (60 - 3, G.shot_top_limit - 2)


def test_the_8x_case_that_lost_a_cannon_now_takes_a_ship():
    """Hunter, seed 0, at 8x: on tick 324 a bomb falls from y 202 to 234, through the
    cannon (rows 216-223) to the ground's top (228) later in the same step: neither end of
    its step touches the cannon, and of its two contacts the earlier, the cannon's, counts."""
    world = World(seed=0)
    install(world, Choice(speed=8), DEFAULT_CONFIG, shadow=False)
    pilot = Autopilot(0)
    for _ in range(324):
        world.step(pilot.actions(world))
    (bomb,) = [s.bomb for s in world.slots if s.bomb is not None and s.bomb.y == 202]
    report = world.step(pilot.actions(world))
    assert report.tick == 324 and Event.CANNON_HIT in report.events
    (contact,) = [c for c in report.contacts if Kind.CANNON in (c.a_kind, c.b_kind)]
    assert contact.time == Fraction(9, 32) and bomb.id in (contact.a_id, contact.b_id)


@pytest.mark.parametrize("multiplier", (1, 4, 8, 16))
def test_the_oracle_sees_the_edges_and_the_default_misses_nothing_at_any_speed(multiplier):
    world = World(seed=3)
    detector = install(world, Choice(speed=multiplier), DEFAULT_CONFIG, shadow=True)
    pilot = Autopilot(3)
    edges = 0
    for _ in range(1500):
        report = world.step(pilot.actions(world))
        edges += sum(1 for c in report.contacts if c.a_kind in (Kind.TOP, Kind.GROUND))
    score = detector.shadow.finish()
    assert edges > 0 and score.true >= edges
    assert (score.missed, score.late, score.false) == (0, 0, 0)
