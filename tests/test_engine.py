"""The engine on its own: zones judged on the tick's motion, reshapes that are new only when
they could be, and a grid fed by the store's move buffer that always agrees with brute force."""

from __future__ import annotations

import random

import pygame
from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, invariant, precondition, rule

from invaders.engine import store as store_module
from invaders.engine.body import Body
from invaders.engine.broadphase import Brute
from invaders.engine.detector import Detector
from invaders.engine.grid import Grid
from invaders.engine.numpy_grid import NumpyGrid
from invaders.engine.rects import CellRects
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.engine.store import BodyStore, gains_pixels
from invaders.game import art
from invaders.game.kinds import Kind
from tests.helpers import GAME_RULES, mask, store_of


def _moved(body: Body, tick: int, dx: int, dy: int) -> Body:
    body.px, body.py, body.moved_tick = body.x, body.y, tick
    body.x += dx
    body.y += dy
    return body


def test_a_fast_shot_crossing_the_saucer_lane_within_one_tick_still_meets_the_saucer():
    lane = GAME_RULES.rule_for(Kind.SHOT, Kind.SAUCER).zone
    assert lane == ((0, 40, 224, 8),)
    saucer = Body(1, Kind.SAUCER, 100, 40, art.mask_of(art.SAUCER))
    # Rising 11 px from y 47 to 36: at the end its box (rows 36-39) is above the lane.
    shot = _moved(Body(2, Kind.SHOT, 110, 47, art.mask_of(art.SHOT)), 3, 0, -11)
    contacts, stats = Detector(Grid(), GAME_RULES).detect(store_of([saucer, shot], tick=3))
    assert stats.allowed_pairs == 1
    assert [(c.a_id, c.b_id) for c in contacts] == [(1, 2)]


def test_a_zone_drops_a_pair_whose_motion_never_enters_it():
    saucer = Body(1, Kind.SAUCER, 100, 40, art.mask_of(art.SAUCER))
    shot = _moved(Body(2, Kind.SHOT, 110, 80, art.mask_of(art.SHOT)), 3, 0, -16)  # rows 64-83
    contacts, stats = Detector(Brute(), GAME_RULES).detect(store_of([saucer, shot], tick=3))
    assert stats.allowed_pairs == 0 and contacts == []


BAR = mask("#", "#")
BAR_LOST = mask("#", ".")  # loses a pixel: nothing new to touch
BAR_MOVED = mask(".", "#", "#")  # gains one below


BLOCK = mask(*["####"] * 4)


def test_bodies_added_in_any_order_are_kept_in_id_order():
    """Contacts of a tick tie-break by their pairs' id order, which the store's lists keep:
    a body that comes back (a lower id than the last) goes in its place."""
    store = BodyStore((1,))
    bodies = [Body(store.new_id(), 1, 8 * i, 0, BLOCK) for i in range(4)]
    for body in (bodies[2], bodies[0], bodies[3], bodies[1]):
        store.add(body)
    store.remove(bodies[0])
    store.add(bodies[0])
    assert [body.id for body in store.by_kind[1]] == [1, 2, 3, 4]


def test_a_body_added_with_a_start_meets_what_it_touched_there():
    """A body that appears during a tick, moving from `start` (a sprite first seen with its
    last place): a body it touched at that first instant, and left at once, is met then
    (time 0), as a body already there would be."""
    store = BodyStore((1, 2))
    store.add(Body(store.new_id(), 2, 0, 0, BLOCK))  # the target: x 0..3
    store.tick = 5
    store.add(Body(store.new_id(), 1, 20, 0, BLOCK), start=(3, 0))  # from x 3..6
    detector = Detector(Brute(), RuleTable((PairRule(1, 2, motion=Motion.SWEPT),)))
    contacts, _ = detector.detect(store)
    assert [(contact.a_id, contact.b_id, contact.time, contact.bx) for contact in contacts] == [
        (1, 2, 0, 3)]


def test_a_picture_gains_pixels_only_if_it_lights_one_the_old_did_not():
    assert not gains_pixels(BAR, BAR_LOST)
    assert gains_pixels(BAR_LOST, BAR)
    assert gains_pixels(BAR, BAR_MOVED)
    assert not gains_pixels(BAR, mask("#", "#"))


def test_the_gains_kept_are_bounded_however_many_masks_come():
    # As the swept masks' cache: pictures made afresh each frame are new keys every time.
    for _ in range(5000):
        assert not gains_pixels(BAR, BAR_LOST.copy())
        assert len(store_module._gains) <= 4097
    assert gains_pixels(BAR_LOST, BAR) and not gains_pixels(BAR, BAR_LOST)


def _touching_then_leaving(new_mask: pygame.mask.Mask) -> list:
    """A wall, and a bar touching it at the end of one tick; in the next the bar takes a new
    picture and moves 3 px away: it touches the wall only at that tick's first instant."""
    rules = RuleTable((PairRule(1, 2, Shape.MASK, Shape.MASK, Motion.SWEPT),))
    store = BodyStore((1, 2))
    wall = Body(1, 1, 0, 0, mask("###", "###", "###"))
    bar = Body(2, 2, 2, 0, BAR)
    store.add(wall)
    store.add(bar)
    detector = Detector(Brute(), rules)
    first, _ = detector.detect(store)  # both new: they touch at the first instant
    store.tick += 1
    store.reshape(bar, new_mask)
    store.move(bar, 5, 0)
    again, _ = detector.detect(store)
    return [[c.time for c in first], [c.time for c in again]]


def test_a_reshape_that_only_loses_pixels_reports_no_new_contact():
    assert _touching_then_leaving(BAR_LOST) == [[0], []]


def test_a_reshape_that_gains_pixels_is_a_new_configuration():
    assert _touching_then_leaving(BAR_MOVED) == [[0], [0]]


SHAPES = [art.mask_of(art.SHOT), art.mask_of(art.SAUCER), art.mask_of(art.CANNON),
          pygame.mask.Mask((40, 3), fill=True), pygame.mask.Mask((1, 1), fill=True),
          art.mask_of(art.BOMB_SQUIGGLY[0])]
KINDS = (Kind.SHOT, Kind.BOMB, Kind.ALIEN, Kind.BUNKER, Kind.SAUCER, Kind.CANNON)
SWEPT_RULES = GAME_RULES.map(lambda r: r.__class__(r.a, r.b, r.a_shape, r.b_shape,
                                                   Motion.SWEPT if r.motion is Motion.DISCRETE
                                                   else r.motion, r.zone, r.spends_a,
                                                   r.spends_b, r.response, r.reason))


class GridAgainstBrute(RuleBasedStateMachine):
    """Random adds, moves, reshapes (resizes) and removes, several a tick, through the store:
    after every tick the grid, fed only by the move buffer, finds what brute force finds."""

    def __init__(self) -> None:
        super().__init__()
        self.store = BodyStore(Kind)
        self.grid = Detector(Grid(random.Random(0).choice((4, 16, 32))), SWEPT_RULES)
        self.brute = Detector(Brute(), SWEPT_RULES)

    @rule(kind=st.sampled_from(KINDS), shape=st.integers(0, len(SHAPES) - 1),
          x=st.integers(-40, 260), y=st.integers(-40, 290))
    def add(self, kind, shape, x, y):
        self._add(kind, shape, x, y)

    def _add(self, kind, shape, x, y):
        self.store.add(Body(self.store.new_id(), kind, x, y, SHAPES[shape]))

    def _bodies(self) -> list[Body]:
        return [b for bodies in self.store.by_kind.values() for b in bodies]

    @precondition(lambda self: self.store.size > 0)
    @rule(pick=st.integers(0, 10**6), dx=st.integers(-40, 40), dy=st.integers(-40, 40))
    def move(self, pick, dx, dy):
        self._move(pick, dx, dy)

    def _move(self, pick, dx, dy):
        bodies = self._bodies()
        body = bodies[pick % len(bodies)]
        self.store.move(body, body.x + dx, body.y + dy)

    @precondition(lambda self: self.store.size > 0)
    @rule(pick=st.integers(0, 10**6), sx=st.integers(-40, 40), sy=st.integers(-40, 40),
          dx=st.integers(-40, 40), dy=st.integers(-40, 40))
    def move_played_back(self, pick, sx, sy, dx, dy):
        """This tick the body went from a start that may not be where it was."""
        bodies = self._bodies()
        body = bodies[pick % len(bodies)]
        self.store.move_from(body, body.x + sx, body.y + sy, body.x + dx, body.y + dy)

    @precondition(lambda self: self.store.size > 0)
    @rule(pick=st.integers(0, 10**6), shape=st.integers(0, len(SHAPES) - 1))
    def reshape(self, pick, shape):
        bodies = self._bodies()
        self.store.reshape(bodies[pick % len(bodies)], SHAPES[shape])

    @precondition(lambda self: self.store.size > 0)
    @rule(pick=st.integers(0, 10**6))
    def remove(self, pick):
        bodies = self._bodies()
        self.store.remove(bodies[pick % len(bodies)])

    @rule()
    def next_tick(self):
        grid_contacts, grid_stats = self.grid.detect(self.store)
        brute_contacts, brute_stats = self.brute.detect(self.store)
        assert grid_contacts == brute_contacts
        assert grid_stats.candidates <= brute_stats.candidates
        # The detectors keep counts and quiet ticks' counters between ticks: a detector
        # that has seen no tick before works them out afresh, and agrees.
        _, fresh = Detector(Brute(), SWEPT_RULES).detect(self.store)
        assert brute_stats == fresh
        assert grid_stats[:3] == fresh[:3]  # bodies, naive pairs, pairs the rules allow
        self.store.tick += 1

    @invariant()
    def the_grid_bins_exactly_the_live_probed_bodies(self):
        if self.store.listener is not self.grid.broadphase:
            return  # not attached yet: the first detection builds it
        grid = self.grid.broadphase
        if grid.move_buffer:
            return  # checked once the detector has drained it: the changes are its
        binned = [b.id for layer in grid.layers.values() for cell in layer.values()
                  for b in cell]
        probed = {b.id for kind in self.grid.kinds.probed
                  for b in self.store.by_kind[kind]}
        assert set(binned) == probed
        assert set(grid.ranges) == {b.id for bodies in self.store.by_kind.values()
                                    for b in bodies}  # ranged: every live body
        for body_id in set(binned):  # binned in exactly the cells of its range
            x0, y0, x1, y1 = grid.ranges[body_id]
            assert binned.count(body_id) == (x1 - x0 + 1) * (y1 - y0 + 1)


GridAgainstBrute.TestCase.settings = settings(max_examples=60, stateful_step_count=40,
                                              deadline=None)
test_a_grid_fed_by_the_move_buffer_agrees_with_brute_force = GridAgainstBrute.TestCase


class NumpyAgainstBrute(GridAgainstBrute):
    """The same random adds, moves, reshapes and removes, fed to the numpy broad phase."""

    def __init__(self) -> None:
        super().__init__()
        self.grid = Detector(NumpyGrid(random.Random(0).choice((4, 16, 32))), SWEPT_RULES)

    @invariant()
    def the_grid_bins_exactly_the_live_probed_bodies(self):
        """Its arrays hold exactly the live bodies, each row with its own id."""
        if self.store.listener is not self.grid.broadphase:
            return
        numpy_grid = self.grid.broadphase
        if numpy_grid.move_buffer:
            return  # checked once the detector has drained it: the changes are its
        for kind, table in numpy_grid.boxes.items():
            assert sorted(b.id for b in table.bodies) == [b.id for b in self.store.by_kind[kind]]
            assert list(table.ids[:table.n]) == [b.id for b in table.bodies]


NumpyAgainstBrute.TestCase.settings = settings(max_examples=60, stateful_step_count=40,
                                               deadline=None)
test_numpy_fed_by_the_move_buffer_agrees_with_brute_force = NumpyAgainstBrute.TestCase


class RectsAgainstBrute(GridAgainstBrute):
    """The same random adds, moves, reshapes and removes, fed to the cell rects."""

    def __init__(self) -> None:
        super().__init__()
        self.grid = Detector(CellRects(random.Random(0).choice((4, 16, 32))), SWEPT_RULES)

    @invariant()
    def the_grid_bins_exactly_the_live_probed_bodies(self):
        """Each kind's list is the store's, in id order, each beside its own rect, and the
        rect covers the body's box."""
        if self.store.listener is not self.grid.broadphase:
            return
        rects = self.grid.broadphase
        if rects.move_buffer:
            return  # checked once the detector has drained it: the changes are its
        for kind, bodies in self.store.by_kind.items():
            assert rects.bodies.get(kind, []) == bodies
            assert rects.rects.get(kind, []) == [rects.rect_of[b.id] for b in bodies]
            for body in bodies:
                assert rects.rect_of[body.id].contains((body.x, body.y, body.w, body.h))
        assert set(rects.rect_of) == set(self.store.by_id)


RectsAgainstBrute.TestCase.settings = settings(max_examples=60, stateful_step_count=40,
                                               deadline=None)
test_rects_fed_by_the_move_buffer_agree_with_brute_force = RectsAgainstBrute.TestCase


class SwitchingAgainstBrute(GridAgainstBrute):
    """The same random changes, the store handed back and forth between the grid, the cell
    rects and the numpy broad phase: the first two let a body move unheard inside its cells
    (its fence), numpy must hear every move, so no fence may outlive the broad phase that
    set it. The bodies are crowded and move a few pixels at a time, so most moves stay
    inside a fence and contacts come and go."""

    @rule(kind=st.sampled_from(KINDS), shape=st.integers(0, len(SHAPES) - 1),
          x=st.integers(0, 48), y=st.integers(0, 48))
    def add(self, kind, shape, x, y):
        self._add(kind, shape, x, y)

    @precondition(lambda self: self.store.size > 0)
    @rule(pick=st.integers(0, 10**6), dx=st.integers(-6, 6), dy=st.integers(-6, 6))
    def move(self, pick, dx, dy):
        self._move(pick, dx, dy)

    @rule(to=st.sampled_from((Grid, CellRects, NumpyGrid)), cell=st.sampled_from((16, 32, 64)))
    def switch(self, to, cell):
        self.grid = Detector(to(cell), SWEPT_RULES)

    @invariant()
    def the_grid_bins_exactly_the_live_probed_bodies(self):
        check = {NumpyGrid: NumpyAgainstBrute, CellRects: RectsAgainstBrute}.get(
            type(self.grid.broadphase), GridAgainstBrute)
        check.the_grid_bins_exactly_the_live_probed_bodies(self)


SwitchingAgainstBrute.TestCase.settings = settings(max_examples=60, stateful_step_count=40,
                                                   deadline=None)
test_grid_rects_and_numpy_taking_turns_agree_with_brute_force = SwitchingAgainstBrute.TestCase
