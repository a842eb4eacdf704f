"""The config is the whole truth: change any geometry field and what it places moves, any
speed and what it times goes by it, and nothing outside the config holds a copy. Bad
values are refused naming field and range."""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Callable

import pytest

from invaders.game import saucer
from invaders.game.actions import Action
from invaders.game.config import ConfigError, GameConfig, Geometry, Rules, Speeds
from invaders.game.entities import Blast, Bomb, BombType, CannonState
from invaders.game.events import Event
from invaders.game.kinds import Kind
from invaders.game.world import World
from tests.helpers import rack_moves, step_until

G = Geometry()


def world_with(**geometry) -> World:
    g = dataclasses.replace(G, **geometry)
    rules = Rules()
    rules = dataclasses.replace(  # the column tables must stay inside a narrower rack
        rules, plunger_columns=tuple(min(c, g.cols) for c in rules.plunger_columns),
        squiggly_columns=tuple(min(c, g.cols) for c in rules.squiggly_columns))
    return World(seed=1, config=GameConfig(geometry=g, rules=rules))


def active(world: World) -> World:
    """The world once its cannon is active, with alien fire off (nothing falls on it)."""
    step_until(world, lambda r: world.cannon.state is CannonState.ACTIVE)
    world.alien_fire_timer = -1
    return world


def _held_right(world: World) -> int:
    active(world)
    for _ in range(250):
        world.step(int(Action.RIGHT))
    return world.cannon.x


def _aliens(world: World):
    return world.rack.aliens


def _lane(world: World):
    return world.rules.rule_for(Kind.SHOT, Kind.SAUCER).zone[0]


def _launched(world: World, from_left: bool):
    world.saucer.from_left = from_left
    return saucer.launch(world.saucer, world.store, world.config)


def _flown_out(world: World, from_left: bool) -> int:
    ship = _launched(world, from_left)
    last = ship.x
    while world.saucer.saucer is not None:
        last = ship.x
        saucer.fly(world.saucer, world.store, world.config)
    return last


def _wraps_at(world: World, moving_right: bool) -> int:
    """The reference x at which the rack first drops, walking it one step at a time."""
    rack = world.rack
    rack.dx = 2 if moving_right else -2
    top = rack.ref_top
    for _ in range(200):
        x = rack.ref_x
        rack._wrap()
        if rack.ref_top != top:
            return x
    raise AssertionError("never dropped")


def _dropped_bomb_burst(world: World) -> tuple[int, int]:
    """A bomb dropped straight down an empty column: where it burst on the ground."""
    slot = world.slots[BombType.PLUNGER]
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 4, 100)
    world.store.add(bomb)
    slot.bomb = bomb
    world.alien_fire_timer = -1
    step_until(world, lambda r: slot.bomb is None, limit=400)
    return slot.burst_y, bomb.y


def _shot_after_firing(world: World):
    world = active(world)
    world.step(int(Action.FIRE))
    return world.shot


def _shot_burst(world: World) -> tuple[int, int]:
    """Fired from the cannon's first place, left of every shield and lit alien pixel: where
    its burst was drawn, from the shot's column and the top limit."""
    x = _shot_after_firing(world).x
    step_until(world, lambda r: Event.SHOT_BURST in r.events, limit=100)
    (burst,) = [e for e in world.explosions if e.blast is Blast.SHOT]
    return burst.x - x, burst.y - world.config.geometry.shot_top_limit


def _shot_burst_top(world: World) -> int:
    """The top row at which the shot bursts (its burst drawn 2 rows above it)."""
    _, dy = _shot_burst(world)
    return world.config.geometry.shot_top_limit + dy + 2


def _bomb_on_a_shield(world: World) -> tuple[int, int]:
    """A bomb dropped onto the first shield: where its burst was drawn, from where it was."""
    active(world)
    bunker = world.bunkers[0]
    slot = world.slots[BombType.PLUNGER]
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, bunker.x + 9, bunker.y - 30)
    world.store.add(bomb)
    slot.bomb = bomb
    step_until(world, lambda r: slot.bomb is None, limit=400)
    return slot.burst_x - bomb.x, slot.burst_y - bomb.y


def _bomb_dropped(world: World) -> tuple[int, int]:
    """The first bomb the rack fires: where it starts, from the x and the top of the lowest
    alien of the column it starts in."""
    step_until(world, lambda r: Event.BOMB_FIRED in r.events, limit=3000)
    (bomb,) = [s.bomb for s in world.slots if s.bomb is not None]
    cell = world.config.geometry.cell
    lowest = [world.rack.lowest_in_column(c) for c in range(world.config.geometry.cols)]
    (shooter,) = [a for a in lowest if a is not None and a.x <= bomb.x < a.x + cell]
    return bomb.x - shooter.x, bomb.y - shooter.top


def _ground_burst(world: World) -> tuple[int, int]:
    """A bomb dropped down an empty column: its burst, from its column and the ground row."""
    slot = world.slots[BombType.PLUNGER]
    _dropped_bomb_burst(world)
    return slot.burst_x - 4, slot.burst_y - world.config.geometry.ground_row


CHECKS: dict[str, tuple[int, Callable[[World], object], Callable[[int], object]]] = {
    # field: (a new value, what to measure in a world, what it should measure for that value)
    "saucer_top": (56, lambda w: (_lane(w)[1], _launched(w, True).y), lambda v: (v, v)),
    "saucer_lane_h": (12, lambda w: _lane(w)[3], lambda v: v),
    "rack_left": (30, lambda w: _aliens(w)[0].x, lambda v: v),
    "cell": (14, lambda w: (_aliens(w)[1].x - _aliens(w)[0].x,
                            _aliens(w)[0].y - _aliens(w)[11 if w.config.geometry.cols == 11
                                                          else 1].y), lambda v: (v, v)),
    "rows": (3, lambda w: (len(_aliens(w)), w.rack.live), lambda v: (v * 11, v * 11)),
    "cols": (8, lambda w: (len(_aliens(w)), _aliens(w)[8].row), lambda v: (5 * v, 1)),
    "edge_right": (150, lambda w: _wraps_at(w, True), lambda v: _wraps_at(world_with(
        edge_right=v), True)),
    "edge_left": (40, lambda w: _wraps_at(w, False), lambda v: _wraps_at(world_with(
        edge_left=v), False)),
    "bunker_xs": ((10, 100), lambda w: [b.x for b in w.bunkers], list),
    "bunker_top": (180, lambda w: {b.y for b in w.bunkers}, lambda v: {v}),
    "cannon_top": (220, lambda w: active(w).cannon.y, lambda v: v),
    "cannon_min_x": (40, lambda w: active(w).cannon.x, lambda v: v),
    "cannon_max_x": (100, _held_right, lambda v: v),
    "ground_row": (235, lambda w: _dropped_bomb_burst(w)[0], lambda v: v - 7),
    "shot_spawn_top": (200, lambda w: _shot_after_firing(w).y, lambda v: v),
    "shot_top_limit": (60, _shot_burst_top, lambda v: range(v - 3, v + 1)),
    "cannon_centre": (5, lambda w: _shot_after_firing(w).x - w.cannon.x, lambda v: v),
    "shot_burst_offset": ((-1, -4), _shot_burst, tuple),
    "bomb_burst_offset": ((0, 5), _bomb_on_a_shield, tuple),
    "ground_burst_offset": ((1, -5), _ground_burst, tuple),
    "bomb_drop_offset": ((3, 12), _bomb_dropped, tuple),
    "invasion_top": (144, lambda w: step_until(
        w, lambda r: Event.INVASION in r.events or w.tick > 2000, limit=3000).tick,
        lambda v: range(128, 2000)),  # the default invades far later
    "bomb_ground_top": (200, lambda w: _dropped_bomb_burst(w)[1], lambda v: range(v, v + 5)),
    "saucer_start_left": (20, lambda w: _launched(w, True).x, lambda v: v),
    "saucer_start_right": (150, lambda w: _launched(w, False).x, lambda v: v),
    "saucer_exit_left": (9, lambda w: _flown_out(w, False), lambda v: range(v, v + 2)),
    "saucer_exit_right": (200, lambda w: _flown_out(w, True), lambda v: range(v - 2, v)),
}


def test_every_geometry_field_has_a_check():
    assert set(CHECKS) == {f.name for f in dataclasses.fields(Geometry)}


@pytest.mark.parametrize("name", sorted(CHECKS))
def test_changing_a_geometry_field_moves_what_it_places(name):
    value, measure, expected = CHECKS[name]
    default = getattr(G, name)
    changed = measure(world_with(**{name: value}))
    want = expected(value)
    if isinstance(want, range):
        assert changed in want, (name, changed)
    else:
        assert changed == want, (name, changed)
    before = measure(World(seed=1))
    assert before != changed, f"{name}: the default {default} gives the same {before}"


def world_going(**speeds) -> World:
    return World(seed=1, config=GameConfig(speeds=dataclasses.replace(Speeds(), **speeds)))


def _cannon_step(world: World) -> int:
    x = active(world).cannon.x
    world.step(int(Action.RIGHT))
    return world.cannon.x - x


def _shot_step(world: World) -> int:
    active(world).step(int(Action.FIRE))
    y = world.shot.y
    world.step(0)
    return y - world.shot.y


def _bomb_step(world: World, live: int = 55) -> int:
    """A plunger bomb's step, high over the field, with `live` aliens left."""
    active(world)
    for alien in world.rack.live_aliens()[live:]:
        world.rack.kill(alien, world.store)
    slot = world.slots[BombType.PLUNGER]
    slot.bomb = bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 100, 60)
    world.store.add(bomb)
    for _ in range(3):  # (a bomb type's turn comes every third tick)
        world.step(0)
    return bomb.y - 60


def _rack_moves(world: World, turns: int, live: int = 55) -> list[tuple[int, int]]:
    """The reference's moves (dx, dy) until it has turned `turns` times, bombs held back."""
    active(world)
    for alien in world.rack.live_aliens()[live:]:
        world.rack.kill(alien, world.store)
    lowest = world.rack.ref_top + turns * world.config.speeds.rack_drop
    return rack_moves(world, lambda w: w.rack.ref_top >= lowest, limit=10000)


SPEED_CHECKS: dict[str, tuple[int, Callable[[World], object], Callable[[int], object]]] = {
    # field: (a new value, what to measure in a world, what it should measure for that value)
    "cannon": (3, _cannon_step, lambda v: v),
    "shot": (7, _shot_step, lambda v: v),
    "bomb": (6, _bomb_step, lambda v: v),
    "bomb_fast": (7, lambda w: _bomb_step(w, live=8), lambda v: v),
    "bomb_fast_at": (20, lambda w: _bomb_step(w, live=20), lambda v: Speeds().bomb_fast),
    # (a step of 1 turns at both edges: the tests of the direction compare with 0)
    "rack_step": (1, lambda w: {dx for dx, _ in _rack_moves(w, 2)}, lambda v: {v, -v}),
    "rack_step_last_right": (5, lambda w: _rack_moves(w, 2, live=1)[-1][0], lambda v: v),
    "rack_drop": (4, lambda w: _rack_moves(w, 1)[-1][1], lambda v: v),
    "saucer": (3, lambda w: _launched(w, True).dx, lambda v: v),
}


def test_every_speed_field_has_a_check():
    assert set(SPEED_CHECKS) == {f.name for f in dataclasses.fields(Speeds)}


@pytest.mark.parametrize("name", sorted(SPEED_CHECKS))
def test_changing_a_speed_changes_what_it_moves_by(name):
    value, measure, expected = SPEED_CHECKS[name]
    changed = measure(world_going(**{name: value}))
    assert changed == expected(value), (name, changed)
    assert measure(World(seed=1)) != changed, f"{name}: the default gives the same"


@pytest.mark.parametrize("section, field, value, message", [
    (Rules, "plunger_columns", (1, 12), "config.rules.plunger_columns = 12 is out of range"),
    (Geometry, "rows", 6, "config.geometry.rows = 6 is out of range 1..5"),
    (Speeds, "rack_drop", 10**9, "config.speeds.rack_drop = 1000000000 is out of range"),
    (Geometry, "cannon_min_x", 190, "config.geometry.cannon_min_x = 190 must not exceed"),
])
def test_a_value_the_game_cannot_honour_is_refused_naming_it(section, field, value, message):
    with pytest.raises(ConfigError, match=message.replace(".", r"\.")):
        section(**{field: value})


def test_sections_must_agree():
    with pytest.raises(ConfigError, match="names column 11; the rack has 8"):
        GameConfig(geometry=dataclasses.replace(G, cols=8))


def test_the_replay_docs_list_every_config_range_as_the_config_declares_it():
    from pathlib import Path

    from invaders.app.configdoc import ranges_table

    page = (Path(__file__).resolve().parents[1] / "docs" / "replays.md").read_text()
    table = ranges_table()
    assert table in page
    assert table.count("\n") == 2 + sum(1 for section in ("geometry", "timing", "speeds",
                                                          "rules")
                                        for _ in dataclasses.fields(getattr(GameConfig(),
                                                                            section))) + 1


def test_a_config_reads_back_from_its_repr_and_compares_and_hashes_by_its_values():
    """The sections' shared repr names every field with its value, nested sections too;
    equal values make equal configs with equal hashes, one changed field an unequal one."""
    config = GameConfig(geometry=dataclasses.replace(G, rows=4), tick_hz=50)
    names = {cls.__name__: cls for cls in (GameConfig, Geometry, Rules, Speeds)}
    names["Timing"] = type(config.timing)
    again = eval(repr(config), names)
    assert again == config and hash(again) == hash(config) and again is not config
    assert repr(G).startswith("Geometry(saucer_top=")
    assert config != GameConfig(tick_hz=50)  # the nested geometry differs
    assert config != dataclasses.replace(config, tick_hz=60)
    assert {config: "kept"}[again] == "kept"


def test_a_config_holds_whole_numbers_all_through_so_its_deep_copy_is_itself():
    """Section.__deepcopy__ returns the section: right only while every field is a section
    or declares a range, whose check takes whole numbers (and tuples of them) alone."""

    def ranged(section) -> None:
        for f in dataclasses.fields(section):
            value = getattr(section, f.name)
            if dataclasses.is_dataclass(value):
                ranged(value)
            else:
                assert "range" in f.metadata, f.name

    config = GameConfig(geometry=dataclasses.replace(G, rows=4))
    ranged(config)
    assert copy.deepcopy(config) is config
    assert copy.deepcopy([config.rules])[0] is config.rules
    with pytest.raises(ConfigError):  # (a list could change in place, and its copies with it)
        Rules(alien_points=[10, 20, 30])
