"""Rules of the 1978 game, each checked in a running world."""

from __future__ import annotations

import copy
import dataclasses
import io
import itertools
import pickle
import random
import types
from enum import Enum
from typing import ClassVar

import pytest

from invaders.engine import pickling
from invaders.engine.adaptive import BROADPHASES, DEFAULT_BROADPHASE
from invaders.engine.body import Body, fields_of
from invaders.engine.compiled import fields
from invaders.engine.detector import ZoneIndex
from invaders.engine.pickling import mask_bytes
from invaders.engine.predicates import solid_mask
from invaders.game import art, bombs
from invaders.game.actions import Action
from invaders.game.config import DEFAULT_CONFIG
from invaders.game.entities import (
    Alien,
    Blast,
    Bomb,
    BombType,
    Bunker,
    Cannon,
    CannonState,
    Edge,
    Saucer,
    Shot,
)
from invaders.game.events import Event
from invaders.game.kinds import Kind
from invaders.game.replay import Checkpoint
from invaders.game.saucer import SIDE_BITS, fly, from_left_after, launch, score_for
from invaders.game.world import Phase, World
from invaders.lab.autopilot import Autopilot
from tests.helpers import active_world, mask_rows, step_until

G = DEFAULT_CONFIG.geometry


def _ticks_between_rack_steps(world: World, steps: int) -> list[int]:
    gaps, last, ref = [], world.tick, (world.rack.ref_x, world.rack.ref_top)
    while len(gaps) < steps:
        world.step(0)
        now = (world.rack.ref_x, world.rack.ref_top)
        if now != ref:
            gaps.append(world.tick - last)
            last, ref = world.tick, now
    return gaps


def _quiet(world: World) -> None:
    """Keep bombs from firing, so the rack's own timing is all that moves."""
    world.alien_fire_timer = 10**9


def test_the_rack_takes_n_ticks_per_step_for_n_live_aliens():
    world = active_world()
    _quiet(world)
    _ticks_between_rack_steps(world, 1)  # align to a step boundary
    assert _ticks_between_rack_steps(world, 3) == [55, 55, 55]
    for alien in world.rack.live_aliens()[::3]:  # kill 19, leaving 36
        world.rack.kill(alien, world.store)
    _ticks_between_rack_steps(world, 1)
    assert world.rack.live == 36
    assert _ticks_between_rack_steps(world, 3) == [36, 36, 36]


def test_the_rack_steps_two_pixels_and_drops_eight_at_the_edge():
    world = World(seed=0)  # from the wave's start: the rack marches during the cannon's wait
    xs, tops = [world.rack.ref_x], [world.rack.ref_top]
    for _ in range(55 * 12):
        world.step(0)
        if world.alien_fire_timer > 0:
            _quiet(world)  # nothing falls: no death freezes the rack
        if world.rack.ref_x != xs[-1]:
            xs.append(world.rack.ref_x)
            tops.append(world.rack.ref_top)
    steps = [b - a for a, b in itertools.pairwise(xs)]
    assert steps[:8] == [2] * 8  # rightmost lit column 197 + 16 reaches 213
    assert steps[8] == -2 and tops[9] == tops[8] + 8  # drop and step back together
    assert tops[:9] == [128] * 9


def test_the_rack_steps_at_once_when_the_aliens_ahead_of_its_cursor_are_gone():
    # The cursor runs past the dead to the end of the rack and wraps (0141): the reference
    # steps and the walk starts again, so the first alien is drawn a step on at the next
    # tick, then every 20 ticks for the 20 aliens left.
    world = active_world()
    _quiet(world)
    _ticks_between_rack_steps(world, 1)  # a step just made: the walk starts again
    for _ in range(20):  # 20 aliens drawn at the new place
        world.step(0)
    first = world.rack.aliens[0]
    for alien in world.rack.live_aliens()[20:]:
        world.rack.kill(alien, world.store)
    moves, last, x = [], world.tick, first.x
    while len(moves) < 3:
        world.step(0)
        if first.x != x:
            moves.append(world.tick - last)
            last, x = world.tick, first.x
    assert moves == [1, 20, 20]


def _x_of_next_drop(world: World) -> int:
    """The reference x at which the rack next drops (before its step back)."""
    rack = world.rack
    x, top = rack.ref_x, rack.ref_top
    while rack.ref_top == top:
        x = rack.ref_x
        world.step(0)
    return x


def test_the_rack_turns_where_its_live_aliens_lit_columns_meet_the_edge():
    world = active_world()
    _quiet(world)
    _ticks_between_rack_steps(world, 1)  # a step made: the lit columns found
    rack, lit = world.rack, art.ALIEN_LIT_COLUMNS.values()
    step = DEFAULT_CONFIG.speeds.rack_step
    for alien in rack.live_aliens():  # the two right-hand columns shot away
        if alien.col >= G.cols - 2:
            rack.kill(alien, world.store)
    x = _x_of_next_drop(world)  # the first x at which column 8's lit pixels reach the edge
    right = G.cell * (G.cols - 3) + max(hi for _, hi in lit)
    assert x + right >= G.edge_right > x - step + right
    for alien in rack.live_aliens():  # then the two left-hand ones, marching back
        if alien.col < 2:
            rack.kill(alien, world.store)
    x = _x_of_next_drop(world)
    left = G.cell * 2 + min(lo for lo, _ in lit)
    assert x + left <= G.edge_left < x + step + left


def test_every_alien_meets_things_with_the_picture_it_is_drawn_with_in_either_frame():
    world = active_world()
    _quiet(world)
    frames = set()
    for _ in range(55 * 3):
        world.step(0)
        for alien in world.rack.live_aliens():  # (its picture under 8 blank rows)
            blank, picture = "." * 16, art.ALIEN_BY_ROW[alien.row][alien.frame]
            assert mask_rows(alien.mask) == (blank,) * 8 + picture, (world.tick, alien.index)
            frames.add(alien.frame)
    assert frames == {0, 1}


def test_an_invasion_ends_the_game_with_ships_left():
    world = active_world()
    _quiet(world)
    world.rack.ref_top = G.invasion_top  # the next draw lands in the cannon's rows
    landed = step_until(world, lambda r: Event.INVASION in r.events, limit=60)
    # The cannon is blown up first: its whole death animation, then GAME OVER (1971, 16E6).
    assert Event.CANNON_HIT in landed.events and world.cannon.state is CannonState.EXPLODING
    assert world.phase is Phase.PLAYING
    over = step_until(world, lambda r: Event.GAME_OVER in r.events, limit=200)
    assert over.tick - landed.tick == DEFAULT_CONFIG.timing.cannon_death
    assert world.phase is Phase.GAME_OVER
    assert world.ships == 3 and Event.SHIP_LOST not in over.events


def test_the_bombs_move_on_the_tick_the_rack_lands():
    """The cursor that finds an alien in the cannon's rows is the mid-screen interrupt's
    last task (00AB -> 1971); the next interrupt runs the bombs' objects as in any frame:
    the bomb whose turn the tick is steps on it."""
    world = active_world()
    _quiet(world)
    for x, slot in zip((40, 100, 160), world.slots, strict=True):
        slot.bomb = Bomb(world.store.new_id(), slot.btype, x, 60)
        world.store.add(slot.bomb)
    before = [slot.bomb.y for slot in world.slots]
    rack = world.rack
    rack.ref_top = G.invasion_top + G.cell * (rack.next_index() // G.cols)
    turn = world.tick % 3
    report = world.step(0)
    assert Event.INVASION in report.events
    moved = [slot.bomb.y - y for slot, y in zip(world.slots, before, strict=True)]
    assert [m > 0 for m in moved] == [i == turn for i in range(3)]


def test_the_cannon_moves_one_pixel_a_tick_within_its_limits():
    world = active_world()
    _quiet(world)
    x0 = world.cannon.x
    for _ in range(5):
        world.step(Action.RIGHT)
    assert world.cannon.x == x0 + 5
    for _ in range(50):
        world.step(Action.LEFT)
    assert world.cannon.x == G.cannon_min_x
    for _ in range(300):
        world.step(Action.RIGHT)
    assert world.cannon.x == G.cannon_max_x


def test_fire_needs_a_new_press_and_only_one_shot_flies():
    world = active_world()
    _quiet(world)
    report = world.step(Action.FIRE)
    assert Event.SHOT_FIRED in report.events
    assert world.shot is not None and world.shot.x == world.cannon.x + 8
    assert world.shot.y == G.shot_spawn_top
    held = [world.step(Action.FIRE) for _ in range(80)]  # held down: never fires again
    assert not any(Event.SHOT_FIRED in r.events for r in held)
    step_until(world, lambda r: world.shot_ready)
    world.step(0)
    assert Event.SHOT_FIRED in world.step(Action.FIRE).events


def test_the_saucer_scores_300_for_the_eighth_shot():
    assert score_for(DEFAULT_CONFIG, 8) == 300
    assert score_for(DEFAULT_CONFIG, 23) == 300
    assert score_for(DEFAULT_CONFIG, 1) == 50
    world = active_world()
    _quiet(world)
    world.shots_removed = 7  # seven shots gone this wave; the next one is the eighth
    world.saucer.due = True
    world.saucer.from_left = False
    step_until(world, lambda r: Event.SAUCER_LAUNCHED in r.events, limit=10)
    ship = world.saucer.saucer
    shot = Shot(world.store.new_id(), ship.x + 12, G.saucer_top + 12)  # just below, in its path
    world.shot = shot
    world.store.add(shot)
    hit = step_until(world, lambda r: Event.SAUCER_HIT in r.events or world.shot is None)
    assert Event.SAUCER_HIT in hit.events
    assert world.shots_removed == 8
    score = world.score
    step_until(world, lambda r: Event.SAUCER_SCORED in r.events, limit=60)
    assert world.score - score == 300


def test_the_reload_rule_waits_for_other_bombs_to_make_enough_steps():
    assert DEFAULT_CONFIG.reload_steps_for(0) == 48
    assert DEFAULT_CONFIG.reload_steps_for(290) == 48
    assert DEFAULT_CONFIG.reload_steps_for(300) == 16
    assert DEFAULT_CONFIG.reload_steps_for(1100) == 11
    assert DEFAULT_CONFIG.reload_steps_for(2100) == 8
    assert DEFAULT_CONFIG.reload_steps_for(3100) == 7
    slots = bombs.new_slots()
    rolling, plunger, _squiggly = slots
    assert bombs.reload_ready(slots, plunger, 48)  # nothing else in flight
    rolling.bomb = Bomb(1, BombType.ROLLING, 0, 0)
    rolling.steps = 48
    assert not bombs.reload_ready(slots, plunger, 48)  # must be *more* than R
    rolling.steps = 49
    assert bombs.reload_ready(slots, plunger, 48)
    rolling.bomb, rolling.burst, rolling.steps = None, 2, 3  # bursting still counts
    assert not bombs.reload_ready(slots, plunger, 48)
    assert bombs.reload_ready(slots, rolling, 48)  # a type never waits for itself


def test_in_a_game_no_bomb_fires_before_the_others_made_r_steps():
    world = active_world(seed=5)
    for _ in range(3000):
        before = [(s.busy, s.steps) for s in world.slots]
        report = world.step(0)
        if Event.BOMB_FIRED in report.events:
            fired = [i for i, s in enumerate(world.slots)
                     if s.bomb and s.steps == bombs.STEPS_AT_LAUNCH]
            need = DEFAULT_CONFIG.reload_steps_for(world.score)
            for i, (busy, steps) in enumerate(before):
                if i not in fired and busy:
                    assert steps > need
        if world.phase is not Phase.PLAYING or world.cannon.state is not CannonState.ACTIVE:
            break


def test_one_extra_ship_at_1500_once_per_game():
    world = active_world()
    world.add_score(1490)
    assert world.ships == 3
    world.add_score(10)
    assert world.ships == 4
    world.add_score(1500)
    assert world.ships == 4
    assert world.step(0).events.count(Event.EXTRA_SHIP) == 1  # (said once, with the ship)


def test_bombs_come_from_the_lowest_live_alien_of_the_plunger_column():
    world = active_world()
    slot = world.slots[BombType.PLUNGER]
    report = step_until(world, lambda r: slot.bomb is not None, limit=400)
    assert Event.BOMB_FIRED in report.events
    assert slot.table_index == 1  # the first entry of the cycle was used
    shooter = world.rack.lowest_in_column(DEFAULT_CONFIG.rules.plunger_columns[0] - 1)
    assert (slot.bomb.x, slot.bomb.y) == (shooter.x + 7, shooter.top + 10)


def test_a_cleared_wave_starts_the_next_lower_with_fresh_shields():
    world = active_world()
    _quiet(world)
    world.bunkers[0].mask.clear()
    for alien in world.rack.live_aliens()[1:]:
        world.rack.kill(alien, world.store)
    last = world.rack.live_aliens()[0]
    world.kill_alien(last, last.x + 8)
    step_until(world, lambda r: Event.WAVE_STARTED in r.events, limit=200)
    assert world.wave == 2
    assert world.rack.ref_top == DEFAULT_CONFIG.start_top(2) == 152
    assert world.rack.live == 55
    assert world.bunkers[0].mask.count() == world.bunkers[1].mask.count() > 0
    assert world.cannon.x == G.cannon_min_x


def _ground_chipped(world: World) -> tuple[str, ...]:
    """A plunger bomb dropped at the far left, left of the cannon, down to the ground line,
    which its burst chips: the line's pixels after."""
    slot = world.slots[BombType.PLUNGER]
    slot.bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 4, 100)
    world.store.add(slot.bomb)
    step_until(world, lambda r: Event.BOMB_BURST in r.events, limit=400)
    return mask_rows(world.ground)


def test_the_ground_line_keeps_its_chips_through_a_lost_ship_and_is_drawn_afresh_each_wave():
    """The ROM draws the line afresh where a field is set up (0804): after a cleared wave
    (0A30, 0A39 go back there), not after a lost ship (032F goes back to 0817)."""
    world = active_world()
    _quiet(world)
    chipped = _ground_chipped(world)
    assert chipped[0].count(".") > 0 and chipped[0][20:] == "#" * 204  # (only at the left)
    world.kill_cannon()
    step_until(world, lambda r: world.cannon.state is CannonState.ACTIVE, limit=400)
    assert world.ships == 2 and mask_rows(world.ground) == chipped
    for alien in world.rack.live_aliens()[1:]:
        world.rack.kill(alien, world.store)
    last = world.rack.live_aliens()[0]
    world.kill_alien(last, last.x + 8)
    step_until(world, lambda r: Event.WAVE_STARTED in r.events, limit=200)
    assert world.wave == 2 and mask_rows(world.ground) == ("#" * 224,)


@pytest.mark.parametrize("players, broadphase",
                         [(2, DEFAULT_BROADPHASE), *((1, name) for name in BROADPHASES)])
def test_a_deep_copy_of_a_world_plays_on_alone_as_the_same_inputs_from_the_start(
        players, broadphase):
    """What the environment's clone_state keeps: the copy plays on as a world given the same
    inputs from the start, tick by tick (its reports, the collision counters too: its
    detector starts afresh from a copy of the broad phase), whichever broad phase; and the
    world copied stays as it was (the pictures the game changes in place, its shields,
    ground and a waiting player's shields, are its own)."""
    world, pilot, inputs = World(1, players=players, broadphase=broadphase), Autopilot(1), []
    for _ in range(4000):
        inputs.append(pilot.actions(world))
        world.step(inputs[-1])
    assert world.ground.count() < 224 and (players == 1 or len(world.waiting.shields) == 4)

    def replayed() -> World:
        again = World(1, players=players, broadphase=broadphase)
        for bits in inputs:
            again.step(bits)
        return again

    copied, before, again = copy.deepcopy(world), Checkpoint.of(world), replayed()
    for _ in range(4000):
        bits = pilot.actions(copied)
        assert copied.step(bits) == again.step(bits)
    assert Checkpoint.of(world) == before != Checkpoint.of(copied) == Checkpoint.of(again)
    other, fresh = Autopilot(6, "expert"), replayed()  # the world copied, on other inputs
    for _ in range(2000):
        bits = other.actions(world)
        assert world.step(bits) == fresh.step(bits)


def _unchanging(value: object) -> bool:
    """A value no one changes in place: a number, a name, a flag, an enum member, a frozen
    dataclass, a zone index, a function, or a tuple or frozenset of such."""
    if isinstance(value, (tuple, frozenset)):
        return all(_unchanging(item) for item in value)
    frozen = dataclasses.is_dataclass(value) and value.__dataclass_params__.frozen
    return value is None or frozen or isinstance(
        value, (int, str, Enum, ZoneIndex, types.FunctionType, types.BuiltinFunctionType))


@pytest.mark.parametrize("broadphase", BROADPHASES)
def test_what_a_worlds_copy_shares_with_it_nothing_changes(broadphase):
    """The parts of a world with copies of their own making (the world, its store, rack,
    detector, broad phase, saucer and bomb slots) take some fields as they are: those must
    be values no one changes in place, or the world and its copy would change each
    other's."""
    world, pilot = World(5, broadphase=broadphase), Autopilot(5)
    for _ in range(600):
        world.step(pilot.actions(world))
    clone = copy.deepcopy(world)
    pairs = [(world, clone), (world.store, clone.store), (world.rack, clone.rack),
             (world.detector, clone.detector),
             (world.detector.broadphase, clone.detector.broadphase),
             (world.saucer, clone.saucer), *zip(world.slots, clone.slots, strict=True)]
    active = getattr(world.detector.broadphase, "active", None)
    if active is not None:
        pairs.append((active, clone.detector.broadphase.active))
    for original, copied in pairs:
        assert copied is not original
        for name, value in fields(original).items():
            if getattr(copied, name) is value:
                assert _unchanging(value), (type(original).__name__, name, value)


def test_the_worlds_generator_draws_as_one_seeded_with_the_world_at_its_start():
    """World.rng is made when first drawn from: it must draw what a generator seeded with
    the world's seed draws, and a copy or a pickle of the world, made before the first
    draw or after some, must draw on from where the world stood, on its own."""
    world = World(seed=11)
    fresh_copy, fresh_pickle = copy.deepcopy(world), pickle.loads(pickle.dumps(world))
    seeded = random.Random(11)
    assert [world.rng.random() for _ in range(3)] == [seeded.random() for _ in range(3)]
    copied, pickled = copy.deepcopy(world), pickle.loads(pickle.dumps(world))
    next_three = [seeded.random() for _ in range(3)]
    assert [copied.rng.random() for _ in range(3)] == next_three
    assert [pickled.rng.random() for _ in range(3)] == next_three
    assert [world.rng.random() for _ in range(3)] == next_three  # (not the copies' own)
    again = random.Random(11)
    first_six = [again.random() for _ in range(6)]
    assert [fresh_copy.rng.random() for _ in range(6)] == first_six
    assert [fresh_pickle.rng.random() for _ in range(6)] == first_six


def test_the_state_hash_tells_the_generators_draws_apart_once_it_is_drawn_from():
    """No 1978 rule draws from World.rng, so no game's hash includes it (the recorded
    replays' checkpoints hold them as they were); once a rule draws, what it drew decides
    the future, so the hash must differ with the draws and agree without a difference."""
    drawn, again, untouched = World(seed=4), World(seed=4), World(seed=4)
    before = untouched.state_hash()
    drawn.rng.random()
    again.rng.random()
    assert drawn.state_hash() == again.state_hash() != before
    again.rng.random()
    assert again.state_hash() != drawn.state_hash()
    assert untouched.state_hash() == before


def test_a_bodys_fields_but_its_picture_are_numbers_flags_or_tuples_of_numbers():
    """What a body's deep copy takes as it is (Body.__deepcopy__ copies no field but the
    picture): a field that could change in place would be shared by a world and its copy."""
    world, pilot, seen = World(seed=5), Autopilot(5), set()
    for tick in range(4000):
        world.step(pilot.actions(world))
        for body in world.store.by_id.values() if tick % 10 == 0 else ():
            seen.add(type(body))
            for name in set(fields_of(type(body))) - {"mask"}:
                value = getattr(body, name)
                assert isinstance(value, int) or (isinstance(value, tuple) and all(
                    isinstance(number, int) for number in value)), (body, name, value)
    assert seen == {Alien, Bomb, Bunker, Cannon, Edge, Saucer, Shot}


class TaggedBody(Body):
    """A body of a class the game does not have, with a field of its own."""

    __slots__ = ("tag",)

    def __init__(self, tag: tuple[int, int]) -> None:
        super().__init__(99, Kind.SHOT, 3, 4, solid_mask(2, 5))
        self.tag = tag


def test_a_bodys_copy_has_every_field_of_its_class_as_it_is():
    """Body.__deepcopy__ writes Body's fields out and takes a subclass's own by name: every
    field of every body of a played game, and of a class made here, comes out equal (one
    left out raises, one taken from another field differs somewhere in 4,000 ticks)."""
    world, pilot, copied = World(seed=5), Autopilot(5), 0
    tagged = TaggedBody((7, 8))
    tagged.px, tagged.moved_tick = 1, 12
    for tick in range(4000):
        world.step(pilot.actions(world))
        bodies = [*world.store.by_id.values(), tagged] if tick % 10 == 0 else []
        for body in bodies:
            clone = copy.deepcopy(body)
            assert type(clone) is type(body) and clone is not body
            for name in fields_of(type(body)):
                assert getattr(clone, name) == getattr(body, name), (body, name)
            assert clone.mask is body.mask
            copied += 1
    assert copied > 15_000 and "tag" in fields_of(TaggedBody)


def test_a_pickled_world_plays_on_as_it_would_with_the_games_pictures_its_own():
    """pickle (a world handed to another process): loaded, a two-player world in player
    2's turn has the same state hash and plays on as the world does; its bodies hold the
    game's shared pictures themselves, and the masks it erodes (shields, the ground, the
    waiting player's shields) are copies of its own with the same pixels."""
    world, pilot = World(seed=2, players=2), Autopilot(2)
    for _ in range(600):
        world.step(pilot.actions(world))
    world.kill_cannon()
    step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=1000)
    for _ in range(300):
        world.step(pilot.actions(world))
    loaded, pilot_copy = pickle.loads(pickle.dumps(world)), copy.deepcopy(pilot)
    assert loaded.state_hash() == world.state_hash() and world.waiting.shields
    for body_id, body in world.store.by_id.items():
        mask = loaded.store.by_id[body_id].mask
        assert (mask is body.mask) is (body.kind != Kind.BUNKER), body
    owned = [(world.ground, loaded.ground), *zip(world.waiting.shields,
                                                 loaded.waiting.shields, strict=True),
             *((a.mask, b.mask) for a, b in zip(world.bunkers, loaded.bunkers, strict=True))]
    for mask, copied in owned:
        assert copied is not mask and mask_bytes(copied) == mask_bytes(mask)
    assert all(b is loaded.store.by_id[b.id] for b in loaded.bunkers)
    for tick in range(3000):
        world.step(pilot.actions(world))
        loaded.step(pilot_copy.actions(loaded))
        if tick % 500 == 0:
            assert loaded.state_hash() == world.state_hash()
    assert loaded.state_hash() == world.state_hash() and world.score > 0
    loaded.bunkers[0].mask.clear()
    assert world.bunkers[0].mask.count() > 0


class _NotingPickler(pickle.Pickler):
    """pickle's, noting each of the package's objects it pickles, by class, and the type of
    the state its reduction hands pickle (none where the reduction is a call alone)."""

    seen: ClassVar[dict[str, set[str]]] = {}

    def reducer_override(self, obj):
        if type(obj).__module__.startswith("invaders.") and not isinstance(obj, (type, Enum)):
            reduced = obj.__reduce_ex__(pickle.HIGHEST_PROTOCOL)
            state = reduced[2] if isinstance(reduced, tuple) and len(reduced) > 2 else None
            _NotingPickler.seen.setdefault(type(obj).__name__, set()).add(
                type(state).__name__)
        return NotImplemented


def test_a_pickled_world_holds_each_objects_fields_by_name_as_both_builds_read_them(
        monkeypatch):
    """A world pickled by the compiled build loads in the interpreted one, and the other
    way about (workers on machines that built the package differently, states kept across
    a reinstall). Each build reads back a call, or fields by name (a dict), whichever build
    wrote them; by default a class with slots pickles them otherwise (interpreted, a pair;
    a dataclass's, a list) and a compiled one as a dict, and neither reads the other's. So
    every object of the package in a pickled world (its own pickler's too) is a call or a
    dict: bodies (`Body.__reduce__`) and the detector's plan among them."""
    _NotingPickler.seen = {}
    monkeypatch.setattr(pickle, "Pickler", _NotingPickler)  # (the world's own one too)
    world, pilot = World(seed=2, players=2), Autopilot(2)
    for _ in range(900):
        world.step(pilot.actions(world))
    pickle.Pickler(io.BytesIO(), pickle.HIGHEST_PROTOCOL).dump(world)
    seen = _NotingPickler.seen
    assert {"World", "Alien", "Cannon", "Bunker", "Edge", "Plan", "BodyStore"} <= set(seen)
    assert {name for name, states in seen.items() if states - {"NoneType", "dict"}} == set()


def test_a_worlds_deep_copy_never_goes_through_pickle(monkeypatch):
    """A world's copy is made field by field: its pickling (`__reduce__`, which copy.copy
    would also take) costs several copies' time. A copy that pickled it would read its
    shields' pixels."""
    world = World(seed=1)
    world.step(0)

    def pixels_read(*_):
        raise AssertionError("the copy went through pickle")

    monkeypatch.setattr(pickling, "mask_bytes", pixels_read)
    assert copy.deepcopy(world).state_hash() == world.state_hash()
    with pytest.raises(AssertionError, match="through pickle"):
        pickle.loads(pickle.dumps(world))


def test_losing_the_last_ship_ends_the_game_and_start_begins_a_new_one():
    world = active_world()
    world.ships = 1
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 100, 60)  # high: still falling at the end
    world.store.add(bomb)
    world.slots[BombType.PLUNGER].bomb = bomb
    world.kill_cannon()
    report = step_until(world, lambda r: Event.GAME_OVER in r.events, limit=100)
    assert Event.SHIP_LOST in report.events
    assert world.phase is Phase.GAME_OVER
    assert not bomb.alive and all(not slot.busy for slot in world.slots)  # the field's emptied
    world.score = 120
    # START is taken once the game-over pause has run, to the tick, and begins a game of one.
    new = step_until(world, lambda r: Event.NEW_GAME in r.events, actions=Action.START, limit=300)
    assert new.tick - report.tick == DEFAULT_CONFIG.timing.game_over_pause
    assert world.score == 0 and world.ships == 3 and world.wave == 1 and world.games == 2
    assert world.players == 1 and world.waiting is None


def test_the_first_tick_reports_the_first_wave_starting():
    world = World(seed=0)
    first = world.step(0)
    assert first.tick == 0 and Event.WAVE_STARTED in first.events
    assert Event.WAVE_STARTED not in world.step(0).events  # once


def _first_fire(world: World, after: int) -> int:
    """The first tick after `after` (the tick the world is at) at which a press fires, each
    tick tried on a copy of the world (the button released until then)."""
    for tick in range(after + 1, after + 100):
        trial = copy.deepcopy(world)
        while trial.tick < tick:
            trial.step(0)
        if Event.SHOT_FIRED in trial.step(int(Action.FIRE)).events:
            return tick
    raise AssertionError("never fires")


@pytest.mark.parametrize("column, lockout", [(2, 16), (7, 15)])
def test_after_a_kill_fire_is_refused_until_the_aliens_explosion_ends(column, lockout):
    """The shot's object is freed when the 16-tick explosion ends, and a new shot starts
    in the mid-screen interrupt (1B2A), in the same tick right of x 96, in the next one
    left of it, where the object is freed in the mid-screen interrupt itself."""
    world = active_world()
    _quiet(world)
    target = world.rack.aliens[column].x + 7  # a bottom alien between two shields
    for _ in range(target - 8 - world.cannon.x):
        world.step(int(Action.RIGHT))
    world.step(int(Action.FIRE))
    killed = step_until(world, lambda r: Event.ALIEN_KILLED in r.events, limit=100).tick
    assert (world.aliens_killed, world.rack.aliens[column]) == (1, None)
    assert (world.shot_wait > DEFAULT_CONFIG.timing.alien_explosion) == (target < 96)
    assert _first_fire(world, killed) == killed + 1 + lockout


@pytest.mark.parametrize("shield, wait", [(0, 17), (2, 16)])
def test_after_a_burst_fire_is_refused_until_it_ends_a_tick_longer_left_of_x_96(
        shield, wait):
    """The burst's 16 steps of the shot's object (03D7), then the new shot in the
    mid-screen interrupt: a tick later left of x 96 (its object run in that interrupt)."""
    world = active_world()
    _quiet(world)
    for _ in range(world.bunkers[shield].x + 8 - 8 - world.cannon.x):
        world.step(int(Action.RIGHT))
    world.step(int(Action.FIRE))
    report = step_until(world, lambda r: Event.SHOT_BURST in r.events, limit=100)
    assert Event.BUNKER_HIT in report.events
    assert _first_fire(world, report.tick) == report.tick + wait


@pytest.mark.parametrize("x, wait", [(95, 2), (96, 1)])
def test_a_shot_taken_away_frees_its_object_next_tick_or_the_one_after_left_of_x_96(x, wait):
    """A shot that hits the saucer is taken away at once (1579 -> 1545); its object is
    freed at its next run and a new shot starts in the mid-screen interrupt."""
    world = active_world()
    _quiet(world)
    world.step(int(Action.FIRE))
    world.step(0)  # (the button released)
    world.store.move(world.shot, x, world.shot.y)
    world.remove_shot()  # (as in the response of the tick just run)
    assert _first_fire(world, world.tick - 1) == world.tick - 1 + wait
    twin = copy.deepcopy(world)  # (the wait decides the future: in the hash)
    twin.shot_wait += 1
    assert twin.state_hash() != world.state_hash()


@pytest.mark.parametrize("shot_x, on_the_cursor, held", [
    (95, True, 17), (96, True, 16), (95, False, 16), (0, False, 16)])
def test_a_kill_holds_the_rack_through_its_explosion_and_a_dead_alien_under_the_cursor(
        shot_x, on_the_cursor, held):
    """The explosion's countdown takes the alien draw of every tick it runs, the tick it ends
    included (1538); a shot left of x 96 runs in the mid-screen interrupt, before the cursor
    is set on the next alien (03BB, 1A06, 00AB), and if that is the one killed its draw is
    spent on the empty place (0100). Then the walk goes on where it was."""
    world = active_world()
    _quiet(world)
    rack = world.rack
    step_until(world, lambda r: rack.cursor > 12)  # (mid-walk, on the second row)
    coming = [index for index, alien in enumerate(rack.aliens)
              if alien is not None and index >= rack.next_index()]
    killed = coming[0] if on_the_cursor else coming[3]
    world.kill_alien(rack.aliens[killed], shot_x)
    draws = rack.draws
    for _ in range(held):
        world.step(0)
    assert rack.draws == draws
    world.step(0)
    assert rack.draws == draws + 1
    assert rack.last_drawn(1) == [coming[1] if on_the_cursor else coming[0]]
    twin = copy.deepcopy(world)  # (a hold decides the future: in the hash)
    twin.rack.hold(3)
    assert twin.state_hash() != world.state_hash()


def test_a_hold_runs_out_while_a_dead_cannon_freezes_the_rack():
    """The ROM's alien draw runs every frame, the cannon's death or not (0100): the rack
    marches on at once when the next cannon comes."""
    world = active_world()
    _quiet(world)
    rack = world.rack
    world.kill_alien(rack.aliens[rack.next_index()], 10)
    world.kill_cannon()
    draws = rack.draws
    step_until(world, lambda r: world.cannon.state is CannonState.ACTIVE, limit=400)
    assert rack.draws == draws + 1  # (the tick the cannon comes)


def test_the_rack_marches_through_a_hit_cannons_blow_up_delay_then_freezes():
    """The ROM's player object counts the blow-up delay (5) down a frame at a time and
    clears playerOK, which stops the rack's cursor, only when it runs out (0296-029B): the
    5 frames after the hit each draw an alien, the rest of the death and the wait none."""
    world = active_world()
    _quiet(world)
    rack = world.rack
    world.kill_cannon()  # (as a bomb's contact does, in a tick's response)
    draws = rack.draws
    swap = DEFAULT_CONFIG.timing.cannon_death_swap
    for frame in range(1, swap + 1):
        world.step(0)
        assert rack.draws == draws + frame and world.blowing_up
    world.step(0)
    assert rack.draws == draws + swap and not world.blowing_up
    step_until(world, lambda r: world.cannon.state is CannonState.ACTIVE, limit=400)
    assert rack.draws == draws + swap + 1  # (the tick the cannon comes)


def test_bombs_start_in_a_hit_cannons_blow_up_delay_and_not_after_it():
    """Alien fire's enable is cleared with playerOK, when the delay runs out (029E): a
    bomb ready at the hit starts within the delay's frames; after them none starts until
    the next cannon's own fire delay has run."""
    world = active_world()
    world.alien_fire_timer = 0  # (fire on: the wave's first bomb is due)
    world.kill_cannon()
    fired = []
    step_until(world, lambda r: fired.append(Event.BOMB_FIRED in r.events)
               or world.cannon.state is CannonState.ACTIVE, limit=400)
    swap = DEFAULT_CONFIG.timing.cannon_death_swap
    assert any(fired[:swap]) and not any(fired[swap:])


def test_a_bomb_bursts_on_the_blowing_up_cannons_debris_and_sets_its_next_picture_again():
    """The original's bombs meet what is lit in the cannon's rows (05FB-0612): one falling
    on the debris bursts there, flagging the player struck again without a second death
    (the sprite number the debris toggles zeroed, 060F: the next change shows @1C80 again),
    and the death ends on time, one ship taken."""
    timing = DEFAULT_CONFIG.timing
    world = active_world()
    _quiet(world)
    world.kill_cannon()
    cannon, ships = world.cannon, world.ships
    for _ in range(timing.cannon_death_swap):  # the first change: @1C80
        world.step(0)
    assert (cannon.debris, cannon.next_debris) == (1, 0) and cannon.alive
    slot = world.slots[BombType.ROLLING]
    slot.bomb = bomb = Bomb(world.store.new_id(), BombType.ROLLING, cannon.x + 6,
                            cannon.y - 8)
    world.store.add(bomb)
    met = step_until(world, lambda r: not bomb.alive, limit=timing.cannon_death_swap - 1)
    (contact,) = met.contacts
    assert {contact.a_kind, contact.b_kind} == {Kind.CANNON, Kind.BOMB}
    assert Event.BOMB_BURST in met.events and Event.CANNON_HIT not in met.events
    assert slot.burst > 0 and cannon.state is CannonState.EXPLODING
    assert cannon.next_debris == 1
    elapsed = timing.cannon_death - cannon.timer
    for _ in range(timing.cannon_death_swap - elapsed % timing.cannon_death_swap):
        world.step(0)  # to the next change
    assert cannon.debris == 1  # @1C80 again, not @1C70
    lost = step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=timing.cannon_death)
    assert world.ships == ships - 1 and not cannon.alive
    assert lost.tick - met.tick < timing.cannon_death


def test_a_cannon_hit_in_its_wait_at_a_waves_start_blows_up_in_the_store_and_leaves_it():
    """Not in the game's own config (the rack lands 11 drops down, long after the wait),
    but a config may start it lower: the waiting cannon, never added, blows up as a body
    of the store and leaves it when its death ends."""
    world = World(seed=0)
    cannon = world.cannon
    assert cannon.state is CannonState.WAITING and cannon.id not in world.store.by_id
    world.kill_cannon()
    assert world.store.by_id[cannon.id] is cannon
    step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=100)
    assert cannon.id not in world.store.by_id and cannon.state is CannonState.WAITING


def test_a_bomb_falls_through_the_place_of_a_cannon_whose_death_has_ended():
    """The debris is erased at the death's end (02B3): the wait's empty place meets nothing,
    and a bomb falls through it to the ground."""
    world = active_world()
    _quiet(world)
    world.kill_cannon()
    step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=100)
    x, y = world.cannon.x, world.cannon.y
    slot = world.slots[BombType.ROLLING]
    slot.bomb = bomb = Bomb(world.store.new_id(), BombType.ROLLING, x + 6, y - 8)
    world.store.add(bomb)
    ground = step_until(world, lambda r: not bomb.alive, limit=60)
    (contact,) = ground.contacts
    assert {contact.a_kind, contact.b_kind} == {Kind.BOMB, Kind.GROUND}


def test_an_invasion_while_a_hit_cannon_blows_up_ends_the_game_after_its_death():
    """The rack marching through the blow-up delay may land (1971): the death goes on as
    it was (16E6 only flags the player shot again) and the game is over at its end, the
    ship not taken."""
    world = active_world()
    _quiet(world)
    world.kill_cannon()
    rack = world.rack
    row = rack.next_index() // G.cols
    rack.ref_top = G.invasion_top + G.cell * row  # the next draw lands in the cannon's rows
    reports = [world.step(0) for _ in range(DEFAULT_CONFIG.timing.cannon_death)]
    invasions = [r.tick for r in reports if Event.INVASION in r.events]
    assert invasions == [reports[0].tick]  # (once, though the aliens drawn after it land)
    assert [r.tick for r in reports if Event.CANNON_HIT in r.events] == [reports[0].tick]
    assert Event.GAME_OVER in reports[-1].events and world.phase is Phase.GAME_OVER
    assert world.ships == 3


def test_alien_fire_goes_on_during_an_aliens_explosion():
    world = World(seed=3)
    pilot = Autopilot(3)
    fired_in_explosion = 0
    for _ in range(6000):
        exploding = any(e.blast is Blast.ALIEN for e in world.explosions)
        report = world.step(pilot.actions(world))
        fired_in_explosion += exploding and Event.BOMB_FIRED in report.events
    assert fired_in_explosion > 0


@pytest.mark.parametrize("cannon_x, column", [(G.cannon_min_x, 0), (G.cannon_max_x, 10)])
def test_the_aimed_bomb_drops_from_the_edge_column_when_the_cannon_is_beyond_the_rack(
        cannon_x, column):
    world = active_world()
    rack = world.rack
    rack.ref_x = 60 if column == 0 else 8  # the rack clear of the cannon's column
    slot = world.slots[BombType.ROLLING]
    assert bombs.choose_column(slot, world.config, cannon_x + 8, rack) == column


def _rom_column(centre: int, ref_x: int) -> int:
    """Cnt16s as the listing reads, one byte at a time (a check of `aimed_column`)."""
    a, h, c = (ref_x + 32) % 256, (centre + 32) % 256, 0
    if a >= h:
        c, a = c + 1, (a + 16) % 256
        while a >= 128:
            c, a = c + 1, (a + 16) % 256
    while a < h:
        c, a = c + 1, (a + 16) % 256
    return (c if c < 12 else 11) - 1


def test_the_aimed_column_takes_the_left_one_when_the_centre_is_on_a_boundary():
    # The rack at its start (ref x 24): a centre at 24 + 16k is column k-1, one px on is k.
    for k in range(1, 11):
        assert bombs.aimed_column(24 + 16 * k, 24, 16, 11) == k - 1
        assert bombs.aimed_column(24 + 16 * k + 1, 24, 16, 11) == k
    assert bombs.aimed_column(24 + 16 * 11, 24, 16, 11) == 10  # clamped


@pytest.mark.parametrize("ref_x, centre, column", [
    (79, 60, 0),    # the centre left of the reference: one cell makes its byte (127) positive
    (80, 60, 10),   # from x 80 (byte 112) the cells run past 255 and count 16 too many
    (90, 40, 10),
    (-40, 121, 10),  # far left (byte 248): the wrap adds real cells, the count is right
    (-88, 193, 1),  # byte 200 is below the centre's 225: two cells reach it, column 1
])
def test_the_aimed_column_wraps_in_a_byte_as_the_roms_does(ref_x, centre, column):
    assert bombs.aimed_column(centre, ref_x, 16, 11) == _rom_column(centre, ref_x)
    assert bombs.aimed_column(centre, ref_x, 16, 11) == column


def test_the_aimed_column_is_the_roms_for_every_place_of_cannon_and_rack():
    for ref_x in range(-160, 200):
        for centre in range(G.cannon_min_x + 8, G.cannon_max_x + 9):
            assert bombs.aimed_column(centre, ref_x, 16, 11) == _rom_column(centre, ref_x)


def test_a_bomb_counts_its_launch_as_its_first_step():
    world = active_world()
    slot = world.slots[BombType.PLUNGER]
    col = next(c for c in range(11) if world.rack.lowest_in_column(c) is not None)
    bomb = bombs.spawn(slot, world.rack, col, world.store, G.bomb_drop_offset)
    assert bomb is not None and slot.steps == 1
    other = world.slots[BombType.ROLLING]
    for _ in range(47):  # 1 + 47 = 48 steps: not more than R = 48 yet
        bombs.advance(slot, 4, world.store)
    assert not bombs.reload_ready(world.slots, other, 48)
    bombs.advance(slot, 4, world.store)
    assert bombs.reload_ready(world.slots, other, 48)


def test_the_rolling_bombs_skip_is_spent_on_its_very_next_turn_even_with_fire_off():
    world = active_world()
    _quiet(world)  # alien fire held off
    slot = world.slots[BombType.ROLLING]
    slot.skip_next = True
    while world.tick % 3 != BombType.ROLLING:
        world.step(0)
    world.step(0)  # the rolling turn
    assert not slot.skip_next
    world.alien_fire_timer = 0
    for btype in (BombType.PLUNGER, BombType.SQUIGGLY):  # busy, far past the reload count
        other = world.slots[btype]
        other.bomb = Bomb(world.store.new_id(), btype, 60 + 40 * btype, 60)
        other.steps = 100
        world.store.add(other.bomb)
    world.step(0)
    world.step(0)
    fired = world.step(0)  # its next turn fires at once: the skip was spent already
    assert Event.BOMB_FIRED in fired.events and slot.bomb is not None


def test_a_new_cannon_after_a_death_comes_with_the_rolling_bomb_skipping_its_next_attempt():
    # A reset rolling bomb skips its first attempt (047D), as after a death; the plunger and
    # the squiggly do not.
    world = active_world()
    world.kill_cannon()
    step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=200)
    assert [slot.skip_next for slot in world.slots] == [
        btype is BombType.ROLLING for btype in BombType]


def _one_alien_left_under_the_plungers_next_column(world: World):
    plunger = world.slots[BombType.PLUNGER]
    col = DEFAULT_CONFIG.rules.plunger_columns[plunger.table_index] - 1
    keep = world.rack.lowest_in_column(col)
    for alien in list(world.rack.live_aliens()):
        if alien is not keep:
            world.rack.kill(alien, world.store)
    return plunger


def test_an_idle_plunger_fires_once_more_with_one_alien_left_then_is_switched_off():
    world = active_world()
    plunger = _one_alien_left_under_the_plungers_next_column(world)
    world.explosions.clear()
    _quiet(world)
    while world.tick % 3 != BombType.PLUNGER:  # fire held off until the plunger's turn
        world.step(0)
    world.alien_fire_timer = 0
    fired = world.step(0)
    assert Event.BOMB_FIRED in fired.events and plunger.bomb is not None and not plunger.off
    bomb = plunger.bomb
    world.burst_bomb(bomb, bomb.x, bomb.y)  # it ends (on the cannon, say) with one alien left
    step_until(world, lambda r: plunger.burst == 0, limit=60)
    assert plunger.off
    for _ in range(600):
        report = world.step(0)
        assert plunger.bomb is None or Event.BOMB_FIRED not in report.events


def test_a_plunger_bomb_ending_with_two_aliens_left_keeps_the_plunger_on():
    world = active_world()
    slot = world.slots[BombType.PLUNGER]
    for alien in world.rack.live_aliens()[2:]:
        world.rack.kill(alien, world.store)
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 100, 100)
    world.store.add(bomb)
    slot.bomb = bomb
    world.burst_bomb(bomb, 100, 100)
    step_until(world, lambda r: slot.burst == 0, limit=60)
    assert not slot.off
    world.rack.kill(world.rack.live_aliens()[0], world.store)
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 100, 100)
    world.store.add(bomb)
    slot.bomb = bomb
    world.burst_bomb(bomb, 100, 100)
    step_until(world, lambda r: slot.burst == 0, limit=60)
    assert slot.off  # its burst ended with one alien left


def test_the_score_has_four_digits_and_wraps_past_9990_to_0000():
    world = active_world()
    world.add_score(9990)
    world.add_score(10)
    assert world.score == 0
    world.add_score(150)
    assert world.score == 150 and world.ships == 4  # the extra ship came once, at 1500


def test_the_rolling_bomb_skips_an_attempt_after_each_of_its_bombs():
    world = active_world()
    slot = world.slots[BombType.ROLLING]
    slot.skip_next = False
    slot.bomb = Bomb(world.store.new_id(), BombType.ROLLING, 50, 50)
    bombs.start_burst(slot, 50, 50, 3)
    assert slot.skip_next
    plunger = world.slots[BombType.PLUNGER]
    bombs.start_burst(plunger, 50, 50, 3)
    assert not plunger.skip_next


def test_the_step_counter_stands_still_during_a_burst():
    world = active_world()
    slot = world.slots[BombType.PLUNGER]
    bombs.start_burst(slot, 50, 50, 3)
    slot.steps = 7
    while slot.burst:
        world.step(0)
    assert slot.steps == 7


def test_no_squiggly_bomb_falls_while_a_saucer_is_due_flies_or_shows_its_hit():
    # The saucer shares the squiggly's object (section 7): the squiggly fires again only
    # once the saucer's hit has shown to its end.
    world = active_world()
    world.alien_fire_timer = 0
    world.saucer.due = True
    squiggly, seen = world.slots[BombType.SQUIGGLY], set()
    for _ in range(400):
        report = world.step(0)
        ship = world.saucer
        if Event.SAUCER_LAUNCHED in report.events:
            world.hit_saucer()  # a hit at once: its explosion, then its score, show
        busy = ship.due or ship.saucer is not None or ship.hit_steps > 0
        seen.add(busy)
        assert not (busy and squiggly.bomb is not None), world.tick
        if squiggly.bomb is not None:
            break
    assert seen == {True, False} and squiggly.bomb is not None


def test_the_saucer_flies_from_9_to_191_or_from_192_to_8_then_leaves():
    # Removed at x < 8 or x >= 193 (06BA-06D5), 2 px a saucer tick from x 9 or 192.
    for from_left, first, last in ((True, 9, 191), (False, 192, 8)):
        world = active_world()
        world.saucer.from_left = from_left
        ship = launch(world.saucer, world.store, world.config)
        places = [ship.x]
        while world.saucer.saucer is not None:
            fly(world.saucer, world.store, world.config)
            if world.saucer.saucer is not None:
                places.append(ship.x)
        assert places == list(range(first, last + (1 if from_left else -1), ship.dx))
        assert not ship.alive  # (out of the store: nothing meets it any more)


def test_the_first_saucer_of_a_wave_starts_at_the_left_moving_right():
    world = active_world()
    assert world.shots_removed == 0
    ship = saucer_launch(world)
    assert (ship.x, ship.dx) == (G.saucer_start_left, DEFAULT_CONFIG.speeds.saucer)


def _clear_the_wave_with_a_bomb_over_the_cannon(ships: int) -> World:
    """The wave cleared, the pause begun, and a bomb about to hit the cannon in it."""
    world = active_world()
    _quiet(world)
    world.ships = ships
    for alien in list(world.rack.live_aliens()):
        world.rack.kill(alien, world.store)
    step_until(world, lambda r: Event.WAVE_CLEARED in r.events, limit=5)
    cannon = world.cannon
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, cannon.x + 7, cannon.y - 12)
    world.store.add(bomb)
    world.slots[BombType.PLUNGER].bomb = bomb
    return world


def test_a_cannon_hit_in_the_pause_after_a_wave_costs_its_ship_before_the_next_wave():
    world = _clear_the_wave_with_a_bomb_over_the_cannon(ships=3)
    hit = step_until(world, lambda r: Event.CANNON_HIT in r.events, limit=20)
    assert world.phase is Phase.WAVE_END and world.phase_timer > 0
    ticks = hit.tick
    lost = step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=200)
    assert lost.tick - ticks == DEFAULT_CONFIG.timing.cannon_death  # the explosion's end
    # the pause (48 ticks) ended before the explosion (60): the wave starts as it ends
    assert Event.WAVE_STARTED in lost.events and world.wave == 2 and world.ships == 2


def test_the_last_ship_hit_in_the_pause_after_a_wave_ends_the_game():
    world = _clear_the_wave_with_a_bomb_over_the_cannon(ships=1)
    step_until(world, lambda r: Event.CANNON_HIT in r.events, limit=20)
    over = step_until(world, lambda r: Event.GAME_OVER in r.events, limit=200)
    assert Event.WAVE_STARTED not in over.events and world.phase is Phase.GAME_OVER
    assert world.wave == 1 and world.ships == 0


def test_the_cannon_and_bombs_keep_running_in_the_pause_after_a_cleared_wave():
    world = active_world()
    _quiet(world)
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 100, 100)
    world.store.add(bomb)
    world.slots[BombType.PLUNGER].bomb = bomb
    for alien in list(world.rack.live_aliens()):
        world.rack.kill(alien, world.store)
    step_until(world, lambda r: Event.WAVE_CLEARED in r.events, limit=5)
    x0, y0 = world.cannon.x, bomb.y
    for _ in range(6):
        world.step(int(Action.RIGHT))
    assert world.phase is Phase.WAVE_END
    assert world.cannon.x == x0 + 6 and bomb.y > y0


def test_the_player_cannot_fire_in_the_pause_after_a_cleared_wave():
    # The game loop reads the fire button (1618); the pause (0A3C) holds it up.
    world = active_world()
    _quiet(world)
    for alien in list(world.rack.live_aliens()):
        world.rack.kill(alien, world.store)
    step_until(world, lambda r: Event.WAVE_CLEARED in r.events, limit=5)
    events = []
    while world.phase is Phase.WAVE_END:
        events += world.step(int(Action.FIRE) if world.tick % 2 else 0).events
    assert Event.SHOT_FIRED not in events and world.shot is None
    assert Event.WAVE_STARTED in events


def saucer_launch(world: World):
    return launch(world.saucer, world.store, world.config)


def _remove_a_shot(world: World) -> None:
    world.shot = Shot(world.store.new_id(), 100, 150)
    world.store.add(world.shot)
    world.remove_shot()


def test_the_saucers_side_is_bit_0_of_the_rom_bytes_at_0800_by_shot_count():
    # The listing's bytes at 0800-0805 are the opcodes AF 32 C1 20 CD CF: bit 0 of each.
    assert SIDE_BITS[:6] == "".join(str(b & 1) for b in (0xAF, 0x32, 0xC1, 0x20, 0xCD, 0xCF))
    assert len(SIDE_BITS) == 256 and set(SIDE_BITS) == {"0", "1"}
    # One byte of count: the 256th shot reads 0x0800 again, the 257th 0x0801.
    assert [from_left_after(n) for n in (0, 1, 256, 257)] == [True, False, True, False]
    for seed in (0, 1, 99):
        world = active_world(seed)
        world.shot = None
        sequence = []
        for _ in range(300):
            _remove_a_shot(world)
            sequence.append(world.saucer.from_left)
        assert sequence == [SIDE_BITS[n % 256] == "1" for n in range(1, 301)]


def test_after_each_saucer_the_side_is_the_left_until_a_shot_is_counted():
    world = active_world()
    _quiet(world)
    _remove_a_shot(world)
    assert not world.saucer.from_left  # one shot: bit 1 is 0, the right
    ship = saucer_launch(world)
    assert ship.dx < 0
    _remove_a_shot(world)
    _remove_a_shot(world)  # (bit 3 is 0: would be the right; not read while it flies)
    assert not world.saucer.from_left
    step_until(world, lambda r: world.saucer.saucer is None, limit=400)
    assert world.saucer.from_left  # flown out: the left again
    _remove_a_shot(world)
    assert world.saucer.from_left is (SIDE_BITS[4] == "1")


def test_a_shot_counted_while_a_hit_saucer_shows_does_not_turn_the_side():
    world = active_world()
    _quiet(world)
    _remove_a_shot(world)
    saucer_launch(world)
    world.hit_saucer()
    _remove_a_shot(world)  # the count is 2 (bit 2 is 1) but the hit still shows
    assert world.saucer.hit_steps > 0 and not world.saucer.from_left
    step_until(world, lambda r: world.saucer.hit_steps == 0, limit=400)
    assert world.saucer.from_left


def test_a_wave_starts_on_an_empty_field_drawn_one_alien_a_tick_and_marches_at_once():
    world = World(seed=0)
    assert world.bodies(Kind.ALIEN) == []
    first_move = None
    for tick in range(200):
        world.step(0)
        if tick < 55:
            assert len(world.bodies(Kind.ALIEN)) == tick + 1  # one more each tick
        if first_move is None and world.rack.ref_x != DEFAULT_CONFIG.geometry.rack_left:
            first_move = tick
    # The reference alien steps once all 55 are drawn, long before the cannon's wait of
    # 128 ticks is over; the freeze belongs to the wait after a death only.
    assert first_move == 54
    # Alien 0 was drawn again at ticks 55, 110 and 165, each time one 2-px step further.
    assert world.bodies(Kind.ALIEN)[0].x == DEFAULT_CONFIG.geometry.rack_left + 3 * 2


def test_the_rack_waits_while_a_new_cannon_does_after_a_death():
    world = active_world()
    world.kill_cannon()
    step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=100)
    before = (world.rack.ref_x, world.rack.cursor)
    for _ in range(DEFAULT_CONFIG.timing.cannon_wait - 1):
        world.step(0)
    assert (world.rack.ref_x, world.rack.cursor) == before


def test_with_one_alien_left_the_plunger_finishes_its_bomb_then_fires_no_more():
    world = active_world()
    world.alien_fire_timer = 0  # fire on
    slot = world.slots[BombType.PLUNGER]
    bomb = Bomb(world.store.new_id(), BombType.PLUNGER, 100, 60)
    world.store.add(bomb)
    slot.bomb = bomb
    for alien in world.rack.live_aliens()[1:]:
        world.rack.kill(alien, world.store)
    assert world.rack.live == 1
    y0 = bomb.y
    step_until(world, lambda r: slot.bomb is None, limit=600)  # it falls to the end
    assert bomb.y > y0
    fired = 0
    for _ in range(600):
        before = slot.bomb
        world.step(0)
        fired += before is None and slot.bomb is not None
    assert fired == 0


def test_every_report_of_a_game_has_every_field_of_its_type():
    """World.step makes its TickReport with tuple.__new__, which checks nothing: every
    report of whole games (every style, so kills, deaths, waves and game over) has all
    the fields, each of the type it declares."""
    from invaders.engine.stats import CollisionStats, Contact
    from invaders.game.world import TickReport
    from invaders.lab.autopilot import Autopilot

    types = {"tick": int, "stats": CollisionStats, "events": tuple, "contacts": tuple,
             "broadphase": str, "cell": int}
    assert tuple(types) == TickReport._fields
    for style in ("hunter", "defender"):
        world, pilot = World(seed=1), Autopilot(1, style)
        for _ in range(4000):
            report = world.step(pilot.actions(world))
            assert len(report) == len(TickReport._fields)
            assert all(isinstance(getattr(report, name), kind) for name, kind in types.items())
            assert all(isinstance(c, Contact) and len(c) == len(Contact._fields)
                       for c in report.contacts)
            assert len(report.stats) == len(CollisionStats._fields)
