"""The earliest contact wins: contacts carry their time of impact, the response takes them
in (time, low id, high id) order, and a body spent by an earlier contact takes part in no
later one. Hand-built scenes in a real world, each placed so that the id order (the old
rule) would pick the other outcome."""

from __future__ import annotations

from fractions import Fraction

from hypothesis import given
from hypothesis import strategies as st

from invaders.engine.body import Body
from invaders.engine.predicates import solid_mask
from invaders.engine.response import first_contacts, respond
from invaders.engine.rules import PairRule
from invaders.engine.stats import Contact, contact_order, contact_time, impact_time
from invaders.game.actions import Action
from invaders.game.entities import BOMB_MASKS, Bomb, BombType, Shot
from invaders.game.events import Event
from invaders.game.kinds import Kind
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from tests.helpers import active_world


class Capture:
    """An observer keeping every contact the detector found in the last tick."""

    def __init__(self) -> None:
        self.found: list[Contact] = []

    def before(self, scene) -> None:
        pass

    def after(self, scene, candidates, contacts, stats) -> None:
        self.found = list(contacts)


def _lit_rows(mask, col: int) -> list[int]:
    return [y for y in range(mask.get_size()[1]) if mask.get_at((col, y))]


def _scene(turn: int):
    """A world on a tick whose bomb turn is `turn`, alien fire off, a capture attached, and
    a bottom-row alien that does not move this tick: its first lit column x and the lowest
    lit row L there."""
    world = active_world(seed=0)
    world.alien_fire_timer = -1  # no new bombs: only the ones a test places
    while world.tick % 3 != turn:
        world.step(0)
    capture = Capture()
    world.detector.observers.append(capture)
    rack = world.rack
    live = [alien.index for alien in rack.live_aliens()]
    drawn_next = next((index for index in live if index >= rack.cursor), live[0])
    alien = rack.aliens[5 if drawn_next != 5 else 6]
    col = next(c for c in range(alien.w) if _lit_rows(alien.mask, c))
    return world, capture, alien, alien.x + col, alien.y + max(_lit_rows(alien.mask, col))


def _fire(world: World, x: int, top: int) -> Shot:
    shot = Shot(world.store.new_id(), x, top)
    world.shot = shot
    world.store.add(shot)
    return shot


def _drop(world: World, btype: BombType, x: int, y: int, frame: int = 0) -> Bomb:
    bomb = Bomb(world.store.new_id(), btype, x, y)
    bomb.frame = frame
    world.store.reshape(bomb, BOMB_MASKS[btype][frame])
    world.slots[btype].bomb = bomb
    world.store.add(bomb)
    return bomb


def _bottom(frame: int) -> int:
    """The lowest lit row of a rolling-bomb picture's middle column."""
    return max(_lit_rows(BOMB_MASKS[BombType.ROLLING][frame], 1))


def _pairs(contacts) -> list[tuple[Fraction, Kind, Kind]]:
    return [(c.time, Kind(c.a_kind), Kind(c.b_kind)) for c in contacts]


def test_a_shot_meeting_a_bomb_then_an_alien_bursts_with_the_bomb_and_the_alien_lives():
    world, capture, alien, x, low = _scene(turn=1)  # the rolling bomb does not move
    _fire(world, x, low + 4)  # rises 4: its top reaches the alien's lowest lit row at the end
    bomb = _drop(world, BombType.ROLLING, x - 1, low + 3 - _bottom(3), frame=3)  # lowest: low+3
    report = world.step(0)
    assert _pairs(capture.found) == [(Fraction(1, 4), Kind.SHOT, Kind.BOMB),
                                     (Fraction(1), Kind.ALIEN, Kind.SHOT)]
    assert alien.id < bomb.id  # by ids alone the alien would have died first
    assert _pairs(report.contacts) == [(Fraction(1, 4), Kind.SHOT, Kind.BOMB)]
    assert alien.alive and world.rack.live == 55 and world.score == 0
    assert not bomb.alive and world.shot is None
    assert {Event.SHOT_BURST, Event.BOMB_BURST} <= set(report.events)
    assert Event.ALIEN_KILLED not in report.events


def _thin_shield(world: World, x: int, top: int, rows: int):
    """The first shield moved (not swept: placed) so that column x has `rows` lit pixels
    from `top` down, and nothing else."""
    bunker = world.bunkers[0]
    bx = x - 5
    world.store.move_from(bunker, bx, top, bx, top)
    bunker.mask.clear()
    for row in range(rows):
        bunker.mask.set_at((5, row), 1)
    return bunker


def test_a_shot_meeting_a_shield_then_an_alien_erodes_the_shield_and_the_alien_lives():
    world, capture, alien, x, low = _scene(turn=1)
    _fire(world, x, low + 4)
    bunker = _thin_shield(world, x, low + 1, 3)  # rows low+1..low+3: met 1 px into the step
    report = world.step(0)
    assert _pairs(capture.found) == [(Fraction(1, 4), Kind.BUNKER, Kind.SHOT),
                                     (Fraction(1), Kind.ALIEN, Kind.SHOT)]
    assert alien.id < bunker.id
    assert _pairs(report.contacts) == [(Fraction(1, 4), Kind.BUNKER, Kind.SHOT)]
    assert alien.alive and world.rack.live == 55
    assert Event.BUNKER_HIT in report.events and Event.ALIEN_KILLED not in report.events
    assert bunker.mask.count() == 0  # the shot's pixels and its burst took the remnant


def test_a_shot_meeting_an_alien_then_a_shield_kills_the_alien_and_spares_the_shield():
    world, capture, alien, x, low = _scene(turn=1)
    _fire(world, x, low + 1)  # its top meets the alien's lowest lit row 1 px into the step
    bunker = _thin_shield(world, x, low - 3, 1)  # one pixel 3 rows higher: met at the end
    report = world.step(0)
    assert _pairs(capture.found) == [
        (Fraction(1, 4), Kind.ALIEN, Kind.SHOT),
        (Fraction(1), Kind.ALIEN, Kind.BUNKER),  # the alien's footprint, where it stands
        (Fraction(1), Kind.BUNKER, Kind.SHOT)]
    # The shot is spent on the alien, and a dead alien draws no footprint.
    assert _pairs(report.contacts) == [(Fraction(1, 4), Kind.ALIEN, Kind.SHOT)]
    assert not alien.alive and world.rack.live == 54
    assert bunker.mask.count() == 1 and Event.BUNKER_HIT not in report.events


def test_of_two_bombs_reaching_the_cannon_in_one_tick_the_earlier_kills_it_the_other_flies_on():
    world, capture, _, _, _ = _scene(turn=1)  # this tick the plunger falls, the squiggly rests
    cannon = world.cannon
    right = max(c for c in range(cannon.w) if _lit_rows(cannon.mask, c))
    still = _drop(world, BombType.SQUIGGLY, 0, cannon.y)
    left = min(c for c in range(3) if _lit_rows(still.mask, c))
    store = world.store
    beside = cannon.x + right + 1 - left  # its lit column just right of the cannon's
    store.move_from(still, beside, cannon.y, beside, cannon.y)
    top = min(y for y in range(cannon.h) if any(cannon.mask.get_at((c, y))
                                                 for c in range(cannon.w)))
    frame1 = BOMB_MASKS[BombType.PLUNGER][1]
    bottom = max(y for y in range(8) if any(frame1.get_at((c, y)) for c in range(3)))
    falling = _drop(world, BombType.PLUNGER, cannon.x + 7, cannon.y + top - bottom - 1)
    assert still.id < falling.id  # by ids alone the resting bomb would have won
    report = world.step(int(Action.RIGHT))  # the cannon steps into the resting bomb
    assert _pairs(capture.found) == [(Fraction(1, 4), Kind.CANNON, Kind.BOMB),
                                     (Fraction(1), Kind.CANNON, Kind.BOMB)]
    assert [(c.a_id, c.b_id) for c in report.contacts] == [(cannon.id, falling.id)]
    assert not falling.alive and still.alive
    assert report.events.count(Event.CANNON_HIT) == 1


def test_contacts_at_the_same_time_go_by_ids():
    world, capture, alien, x, low = _scene(turn=1)
    _fire(world, x, low + 4)
    bomb = _drop(world, BombType.ROLLING, x - 1, low - _bottom(3), frame=3)  # its lowest: low
    report = world.step(0)
    assert [t for t, *_ in _pairs(capture.found)] == [Fraction(1), Fraction(1)]
    assert alien.id < bomb.id
    assert _pairs(report.contacts) == [(Fraction(1), Kind.ALIEN, Kind.SHOT)]
    assert not alien.alive and bomb.alive


def _contact(time: Fraction, a: int, b: int, rule: PairRule) -> Contact:
    return Contact(0, time, a, b, rule.a, rule.b, 0, 0, 0, 0, 0, 0, rule)


def test_first_contacts_drop_only_what_a_spent_side_touches_later():
    hits = PairRule(1, 2, spends_a=True, spends_b=True)  # both sides spent
    erodes = PairRule(1, 3, spends_a=True)  # kind 1 spent, kind 3 (a wall) not
    paints = PairRule(3, 4)  # spends nothing
    contacts = [_contact(Fraction(1, 8), 10, 30, erodes), _contact(Fraction(1, 4), 10, 20, hits),
                _contact(Fraction(1, 2), 30, 40, paints), _contact(Fraction(1), 11, 30, erodes)]
    kept = first_contacts(contacts)
    assert [(c.a_id, c.b_id) for c in kept] == [(10, 30), (30, 40), (11, 30)]


def test_a_body_a_response_killed_takes_part_in_no_later_contact():
    """A response may end a body its entry does not spend (a blast killing a third body):
    a later contact of that body in the tick is not answered, whether the body is still
    in the mapping (dead) or gone from it; the others are, in order."""
    bodies = {i: Body(i, kind, 0, 0, solid_mask(1, 1))
              for i, kind in ((10, 1), (20, 2), (30, 3), (35, 3), (40, 4), (50, 3))}
    answered = []

    def blast(context, a, b, contact) -> None:
        answered.append((a.id, b.id))
        bodies[30].alive = False
        del bodies[50]

    def paint(context, a, b, contact) -> None:
        answered.append((a.id, b.id))

    blasts, paints = PairRule(1, 2, response=blast), PairRule(3, 4, response=paint)
    contacts = [_contact(Fraction(1, 4), 10, 20, blasts), _contact(Fraction(1, 2), 30, 40, paints),
                _contact(Fraction(1, 2), 40, 50, paints), _contact(Fraction(1), 35, 40, paints)]
    applied = respond(contacts, bodies, None)
    assert [(c.a_id, c.b_id) for c in applied] == answered == [(10, 20), (35, 40)]


def test_a_same_kind_entry_spends_by_its_sides_low_id_first():
    rule = PairRule(5, 5, spends_a=True)
    contacts = [_contact(Fraction(1, 2), 1, 2, rule), _contact(Fraction(1, 2), 2, 3, rule),
                _contact(Fraction(1), 1, 3, rule)]
    assert [(c.a_id, c.b_id) for c in first_contacts(contacts)] == [(1, 2), (2, 3)]


def test_every_contact_time_is_an_exact_fraction_of_the_tick():
    world = World(seed=8)
    pilot = Autopilot(8)
    times = set()
    for _ in range(3000):
        for contact in world.step(pilot.actions(world)).contacts:
            assert type(contact.time) is Fraction and 0 <= contact.time <= 1
            times.add(contact.time)
    assert len(times) > 3  # not all at the tick's end



@given(st.lists(st.tuples(st.integers(1, 2**20), st.integers(0, 2**20)), min_size=2,
                max_size=40))
def test_contacts_sort_by_time_as_the_fractions_order_them(times):
    contacts = [Contact(0, Fraction(min(step, steps), steps), i % 3, i % 3 + 1, 0, 0, 0, 0,
                        0, 0, 0, 0, None) for i, (steps, step) in enumerate(times)]
    by_float = sorted(contacts, key=contact_order)
    exact = sorted(contacts, key=lambda c: (c.time, c.a_id, c.b_id))
    assert by_float == exact
    # The detector's contacts come in the pairs' id order: a stable sort by time suffices.
    by_ids = sorted(contacts, key=lambda c: (c.a_id, c.b_id))
    assert sorted(by_ids, key=contact_time) == exact


def test_the_impact_times_kept_are_bounded_however_many_motions_come():
    """A contact's time is kept per pair of numbers for the contacts to share, the latest
    4,096 pairs: motions long and many would otherwise keep one for every substep met."""
    first = impact_time(1, 1_000_003)
    assert first == Fraction(1, 1_000_003) and impact_time(1, 1_000_003) is first
    for steps in range(1_000_004, 1_000_004 + 4096):
        assert impact_time(2, steps) == Fraction(2, steps)
    again = impact_time(1, 1_000_003)
    assert again == first and again is not first  # (let go, and made again)
