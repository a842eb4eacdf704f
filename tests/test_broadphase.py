"""Every broad phase agrees with brute force on random scenes, in real games and in big
storms; the grid re-bins lazily; the automatic choice moves to numpy and back."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.engine.adaptive import GRID_FROM, GRID_UNTIL, NUMPY_FROM, NUMPY_UNTIL, Adaptive
from invaders.engine.body import Body
from invaders.engine.broadphase import BroadPhase, Brute, SortAndSweep
from invaders.engine.detector import Detector
from invaders.engine.grid import Grid
from invaders.engine.numpy_grid import NumpyGrid
from invaders.engine.rects import CellRects
from invaders.game import art
from invaders.game.kinds import Kind
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from tests.helpers import GAME_RULES, SHARED_MASKS, active_world, store_of


def _random_body(rng: random.Random, body_id: int, kind: Kind, tick: int) -> Body:
    if kind is Kind.BUNKER:
        mask = art.fresh_mask(art.BUNKER)
        for _ in range(rng.randrange(0, 40)):  # eroded somewhere
            mask.set_at((rng.randrange(22), rng.randrange(16)), 0)
    else:
        mask = rng.choice(SHARED_MASKS[kind])
    x, y = rng.randrange(-30, 250), rng.randrange(-30, 280)
    body = Body(body_id, kind, x, y, mask)
    if kind is not Kind.BUNKER and rng.random() < 0.7:  # it moved this tick
        body.moved_tick = tick
        body.px, body.py = x + rng.randrange(-16, 17), y + rng.randrange(-16, 17)
    return body


@st.composite
def scenes(draw):
    seed = draw(st.integers(0, 2**32 - 1))
    count = draw(st.integers(0, 120))
    rng = random.Random(seed)
    ids = rng.sample(range(1, 10_000), count)
    kinds = [rng.choice(list(Kind)) for _ in ids]
    # Crowd some of them together so that contacts actually happen.
    bodies = [_random_body(rng, i, k, 5) for i, k in zip(ids, kinds, strict=True)]
    for body in bodies[: count // 2]:
        body.x, body.y = 100 + rng.randrange(-12, 12), 120 + rng.randrange(-12, 12)
    return bodies


@settings(max_examples=150, deadline=None)
@given(bodies=scenes(), cell=st.sampled_from([4, 7, 16, 32, 64, 128]))
def test_grid_and_brute_give_identical_contacts_in_identical_order(bodies, cell):
    scene = store_of(bodies, tick=5)
    brute_contacts, brute_stats = Detector(Brute(), GAME_RULES).detect(scene)
    grid_contacts, grid_stats = Detector(Grid(cell), GAME_RULES).detect(scene)
    assert grid_contacts == brute_contacts
    rects_contacts, rects_stats = Detector(CellRects(cell), GAME_RULES).detect(scene)
    assert rects_contacts == brute_contacts
    assert rects_stats == grid_stats  # the grid's cells as rects: the same candidates
    sweep_contacts, sweep_stats = Detector(SortAndSweep(), GAME_RULES).detect(scene)
    assert sweep_contacts == brute_contacts
    numpy_contacts, numpy_stats = Detector(NumpyGrid(cell), GAME_RULES).detect(scene)
    assert numpy_contacts == brute_contacts
    assert numpy_stats.allowed_pairs == brute_stats.allowed_pairs
    assert numpy_stats.candidates <= sweep_stats.candidates  # only boxes that overlap
    assert sweep_stats.candidates <= brute_stats.candidates
    assert [(c.time, c.a_id, c.b_id) for c in grid_contacts] == sorted(
        (c.time, c.a_id, c.b_id) for c in grid_contacts)
    assert grid_stats.allowed_pairs == brute_stats.allowed_pairs
    assert grid_stats.candidates <= brute_stats.candidates
    # From the quick test on, every step counts the same pairs whichever broad phase ran
    # (the study's automatic choice picks one by timing, and its counters must not move).
    after = [s[5:] for s in (brute_stats, grid_stats, sweep_stats, numpy_stats)]
    assert after.count(after[0]) == 4


@pytest.mark.parametrize("make", [Grid, CellRects, SortAndSweep, NumpyGrid, Adaptive])
def test_every_broad_phase_meets_bodies_that_come_back_or_appear_far_in_id_order(make):
    """Nine targets in a row, met by three lone probes of their own entries, the entries'
    order not the ids': the contacts, ties in id order, are brute force's when a target
    appears far from the others (past the box round them all) and one that left comes
    back with its old id (in its place among their lists)."""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    block = art.mask_of(("########",) * 8)
    rules = RuleTable(tuple(PairRule(kind, 2, Shape.BOX, Shape.BOX, Motion.DISCRETE)
                            for kind in (1, 3, 4)))
    store = BodyStore((1, 2, 3, 4))
    targets = [Body(store.new_id(), 2, 10 * i, 0, block) for i in range(9)]  # ids 1 to 9
    for kind, x in ((3, 0), (1, 80), (4, 500)):  # ids 10, 11, 12: on targets 1, 9, none
        targets.append(Body(store.new_id(), kind, x, 0, block))
    for body in targets:
        store.add(body)
    ours, brute = Detector(make(), rules), Detector(Brute(), rules)
    met = []
    for change in (lambda: None,
                   lambda: store.add(Body(store.new_id(), 2, 500, 0, block)),  # far: id 13
                   lambda: store.remove(targets[4]),
                   lambda: store.add(targets[4])):  # id 5 back
        change()
        contacts = ours.detect(store)[0]
        assert contacts == brute.detect(store)[0]
        met.append([(contact.a_id, contact.b_id) for contact in contacts])
        store.tick += 1
    assert met == [[(1, 10), (9, 11)]] + [[(1, 10), (9, 11), (12, 13)]] * 3


@pytest.mark.parametrize("make", [Grid, CellRects, SortAndSweep, NumpyGrid, Adaptive])
def test_every_broad_phase_pairs_a_kind_with_itself_once_and_never_a_body_with_itself(make):
    """An entry of one kind (bodies that meet their own, as billiard balls): each pair of
    two that touch once, low id first, and no body met by itself; the pairs it allows
    counted so. (Every broad phase met each body by itself and each pair twice: found by
    this test.)"""
    from invaders.engine.rules import PairRule, RuleTable
    from invaders.engine.store import BodyStore

    block = art.mask_of(("####",) * 4)
    rules = RuleTable((PairRule(1, 1),))
    store = BodyStore((1,))
    for x in (0, 2, 20, 22, 40):  # ids 1 to 5: 1 on 2, 3 on 4, 5 alone
        store.add(Body(store.new_id(), 1, x, 0, block))
    contacts, stats = Detector(make(), rules).detect(store)
    assert contacts == Detector(Brute(), rules).detect(store)[0]
    assert [(contact.a_id, contact.b_id) for contact in contacts] == [(1, 2), (3, 4)]
    assert stats.allowed_pairs == 10 == stats.naive_pairs  # (5 bodies: each two once)


@pytest.mark.parametrize("make", [Grid, CellRects, SortAndSweep, NumpyGrid, Adaptive])
@pytest.mark.parametrize("far", [2**30 - 5, 2**31 - 6, -(2**31), 2**31 + 5, 2**40, -(2**40),
                                 2**62])
def test_every_broad_phase_meets_bodies_far_out_as_brute_force_does(make, far):
    """A block that moved onto another, and a third apart, far out on both axes: the
    contact is brute force's. A pygame Rect holds 32 bits and sums them so: the cell
    rects met nothing where a block's cells crossed 2**31 - 1 px, where a sprite's own
    rect still stands, and cut bodies past it to 32 bits (found by this test)."""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    block = art.mask_of(("########",) * 8)
    rules = RuleTable((PairRule(1, 2, Shape.MASK, Shape.MASK, Motion.SWEPT),))
    store = BodyStore((1, 2))
    mover = Body(store.new_id(), 1, far - 40, far, block)
    for body in (mover, Body(store.new_id(), 2, far + 3, far + 2, block),
                 Body(store.new_id(), 2, far + 100, far - 100, block)):
        store.add(body)
    store.tick = 1
    store.move(mover, far, far)  # (swept: from 40 px to the left)
    contacts = Detector(make(), rules).detect(store)[0]
    assert contacts == Detector(Brute(), rules).detect(store)[0]
    assert [(contact.a_id, contact.b_id) for contact in contacts] == [(1, 2)]


@pytest.mark.parametrize("make", [Grid, CellRects, SortAndSweep, NumpyGrid, Adaptive])
@pytest.mark.parametrize("motion", ["SWEPT", "DISCRETE", "LANDING"])
def test_bodies_that_crossed_a_zone_and_stopped_outside_it_are_out_of_it(make, motion):
    """Two bodies cross a zone in one tick and land on each other outside it: they meet
    in that tick (the zone holds their motion), and in the next, at rest outside, they
    do not, whatever box a broad phase keeps for them from the tick before. So for every
    motion: numpy, keeping the boxes of kinds no entry sweeps where they end, lost the
    pair of a discrete or landing entry."""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    block = art.mask_of(("####",) * 4)
    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion[motion],
                                zone=((0, 0, 20, 20),)),))
    store = BodyStore((1, 2))
    bodies = [Body(store.new_id(), kind, 4, 4 * kind, block) for kind in (1, 2)]
    for body in bodies:
        store.add(body)
    ours, brute = Detector(make(), rules), Detector(Brute(), rules)
    met = []
    for tick in range(3):
        store.tick = tick
        if tick == 1:
            for body in bodies:
                store.move(body, 100, 0)
        contacts = ours.detect(store)[0]
        assert contacts == brute.detect(store)[0]
        met.append(len(contacts))
    assert met == [0, 1, 0]  # (apart at first: side by side)


@pytest.mark.parametrize("make", [Grid, CellRects, SortAndSweep, NumpyGrid, Adaptive])
@pytest.mark.parametrize("size", [100_000, 2**62, 10**30])
def test_a_zone_of_any_size_holds_the_pairs_inside_it(make, size):
    """A zone of a box as wide and tall as `size` (from the origin's far side) and a
    small one: pairs inside either meet, a pair outside both does not. (The numpy broad
    phase binned the big box in its cells: at 100,000 px 1.8 s and 700 MB, at 2^62 a
    count that overflowed and met nothing, at 10^30 an OverflowError.)"""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    zone = ((-size, -size, size, size), (50, 50, 20, 20))
    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion.DISCRETE, zone=zone),))
    store = BodyStore((1, 2))
    block = art.mask_of(("####",) * 4)
    for x, y in ((-30, -30), (52, 52), (200, 200), (-40_000, -90_000)):  # (200: outside)
        for kind in (1, 2):
            store.add(Body(store.new_id(), kind, x, y + kind, block))
    contacts = Detector(make(), rules).detect(store)[0]
    assert contacts == Detector(Brute(), rules).detect(store)[0]
    assert [(c.a_id, c.b_id) for c in contacts] == [(1, 2), (3, 4), (7, 8)]


@pytest.mark.parametrize("make", [Grid, CellRects, SortAndSweep, NumpyGrid, Adaptive])
def test_bodies_swept_across_a_world_in_a_tick_meet_as_brute_forces_do(make):
    """Bodies that now and then jump up to a million pixels in a tick and back, swept (a
    box a million pixels square over the tick), among bodies that move a few: every
    tick's contacts are brute force's, for an entry of two kinds and one of one kind with
    itself. (The grid binned such a box in a billion cells, a minute a tick; the numpy
    broad phase ran out of memory.)"""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.MASK, Motion.SWEPT),
                       PairRule(2, 2, Shape.MASK, Shape.MASK, Motion.SWEPT),
                       PairRule(3, 1, Shape.BOX, Shape.BOX, Motion.DISCRETE)))
    store = BodyStore((1, 2, 3))
    rng = random.Random(4)
    masks = [art.mask_of(("####", "#..#", "####")), art.mask_of(("##",) * 5)]
    bodies = [Body(store.new_id(), kind, rng.randrange(0, 160), rng.randrange(0, 160),
                   rng.choice(masks)) for kind in (1, 2, 3) for _ in range(12)]
    for body in bodies:
        store.add(body)
    ours, brute = Detector(make(), rules), Detector(Brute(), rules)
    contacts = jumps = 0
    for _ in range(60):
        store.tick += 1
        for body in rng.sample(bodies, 20):
            if abs(body.x) > 1000 or rng.random() < 0.1:  # a jump out, or back
                far = rng.choice([10**5, 10**6]) * rng.choice([-1, 1])
                x, y = (rng.randrange(0, 160), rng.randrange(0, 160)) if abs(body.x) > 1000 \
                    else (body.x + far, body.y + rng.choice([0, far, -far]))
                jumps += 1
            else:
                x, y = body.x + rng.randrange(-6, 7), body.y + rng.randrange(-6, 7)
            store.move(body, x, y)
        found = ours.detect(store)[0]
        assert found == brute.detect(store)[0]
        contacts += len(found)
    assert contacts > 60 and jumps > 60


def test_every_broad_phase_agrees_tick_by_tick_in_a_game():
    worlds = [World(seed=11, detector=Detector(b, GAME_RULES))
              for b in (Grid(), CellRects(), Brute(), SortAndSweep(), NumpyGrid(), Adaptive())]
    pilots = [Autopilot(11) for _ in worlds]
    contacts = 0
    for _ in range(4000):
        reports = [w.step(p.actions(w)) for w, p in zip(worlds, pilots, strict=True)]
        assert all(r.contacts == reports[0].contacts for r in reports)
        assert reports[1].stats == reports[0].stats  # rects and grid: the same candidates
        contacts += len(reports[0].contacts)
    assert contacts > 50
    assert len({w.state_hash() for w in worlds}) == 1


def _storm_contacts(broadphase, bodies: int, ticks: int, shrink_to: int | None = None):
    """Contacts of every tick of a storm (its own rules, zones in every tile); with
    `shrink_to`, projectiles, then aliens, are taken out half-way until that many bodies
    are left."""
    from invaders.game.config import DEFAULT_CONFIG
    from invaders.game.rules import make_rules
    from invaders.lab.storm import Storm, storm_rules

    storm = Storm(bodies, seed=2, speed=4)
    detector = Detector(broadphase, storm_rules(make_rules(DEFAULT_CONFIG), bodies))
    seen = []
    for tick in range(ticks):
        if shrink_to is not None and tick == ticks // 2:
            movers = [b for kind in (Kind.SHOT, Kind.BOMB, Kind.ALIEN)
                      for b in storm.store.by_kind[kind]]
            for body in movers[: storm.count - shrink_to]:
                storm.store.remove(body)
        contacts, _ = detector.detect(storm.store)
        seen.append(contacts)
        storm.advance()
    return seen, detector


def test_in_big_storms_numpy_finds_what_the_grid_finds_tick_by_tick():
    grid, _ = _storm_contacts(Grid(), 2500, 12)
    numpy, _ = _storm_contacts(NumpyGrid(), 2500, 12)
    assert sum(len(c) for c in grid) > 1000
    assert numpy == grid


def test_the_automatic_choice_takes_numpy_for_big_scenes_and_the_grid_again_when_small():
    grid, _ = _storm_contacts(Grid(), NUMPY_FROM + 100, 10, shrink_to=NUMPY_UNTIL - 100)
    auto = Adaptive()
    seen, _ = _storm_contacts(auto, NUMPY_FROM + 100, 10, shrink_to=NUMPY_UNTIL - 100)
    assert seen == grid
    assert auto.active.name == "grid"  # it went back when the scene shrank
    big = Adaptive()
    _storm_contacts(big, NUMPY_FROM + 100, 3)
    assert big.active.name == "numpy"


def test_the_automatic_choice_takes_the_rects_for_small_scenes_and_holds_a_tier_to_its_floor():
    start, shrunk, held = GRID_FROM + 40, GRID_UNTIL - 20, GRID_UNTIL + 20
    grid, _ = _storm_contacts(Grid(), start, 10, shrink_to=shrunk)
    auto = Adaptive()
    seen, _ = _storm_contacts(auto, start, 10, shrink_to=shrunk)
    assert seen == grid
    assert auto.active.name == "rects"  # it went down when the scene shrank
    between = Adaptive()
    _storm_contacts(between, start, 10, shrink_to=held)
    assert between.active.name == "grid"  # fewer than it takes the grid for, not below
    small = Adaptive()
    _storm_contacts(small, GRID_FROM - 20, 3)
    assert small.active.name == "rects"


def test_static_bodies_stay_binned_and_movers_rebin_only_when_cells_change():
    world = active_world(seed=1, broadphase="grid")
    grid = world.detector.broadphase
    assert isinstance(grid, Grid)
    world.step(0)
    bunker_ranges = {b.id: grid.ranges[b.id] for b in world.bunkers}
    before = grid.rebins
    moved = 0
    for _ in range(40):  # nothing fired yet: only the rack moves, one alien a tick
        report = world.step(0)
        assert not report.contacts
        moved += 1
    assert grid.rebins - before <= moved
    assert grid.rebins - before < moved  # some draws stayed inside their cells
    assert {b.id: grid.ranges[b.id] for b in world.bunkers} == bunker_ranges


def test_a_body_spanning_many_cells_is_reported_once():
    saucer = Body(1, Kind.SAUCER, 0, 40, art.mask_of(art.SAUCER))
    shot = Body(2, Kind.SHOT, 10, 41, art.mask_of(art.SHOT))
    scene = store_of([saucer, shot])
    contacts, stats = Detector(Grid(4), GAME_RULES).detect(scene)  # the saucer covers 6x2 cells
    assert stats.candidates == 1
    assert [(c.a_id, c.b_id) for c in contacts] == [(1, 2)]


def _cells(broadphase, body_id: int) -> tuple[int, int, int, int]:
    """The cells (first and last column and row) a broad phase holds a body in: the
    grid's range, or the cells the rect of `CellRects` spans."""
    if isinstance(broadphase, Grid):
        return broadphase.ranges[body_id]
    c = broadphase.cell
    rect = broadphase.rect_of[body_id]
    assert rect.x % c == rect.y % c == rect.w % c == rect.h % c == 0
    return rect.x // c, rect.y // c, rect.right // c - 1, rect.bottom // c - 1


ON_CELLS = pytest.mark.parametrize("make", [Grid, CellRects], ids=["grid", "rects"])


def _two_blocks(probe_at: tuple[int, int], target_at: tuple[int, int], swept: bool = False,
                make=Grid):
    """A store of two 4x4 blocks, kind 1 probing kind 2 by boxes (discrete, or `swept`),
    and a broad phase on 32-px cells: (store, broad phase, detector, probe, target)."""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    motion = Motion.SWEPT if swept else Motion.DISCRETE
    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, motion),))
    store = BodyStore((1, 2))
    grid = make(32)
    detector = Detector(grid, rules)
    block = art.mask_of(("####",) * 4)
    probe, target = Body(1, 1, *probe_at, block), Body(2, 2, *target_at, block)
    store.add(probe)
    store.add(target)
    return store, grid, detector, probe, target


class Looks(BroadPhase):
    """A broad phase that asks the one it holds, noting the tick of each time it is asked."""

    def __init__(self, inner: BroadPhase) -> None:
        self.inner, self.ticks = inner, []
        self.name, self.cell, self.move_buffer = inner.name, inner.cell, inner.move_buffer

    def rebuild(self, scene, kinds):
        self.inner.rebuild(scene, kinds)

    def pairs(self, scene, groups, kinds):
        self.ticks.append(scene.tick)
        return self.inner.pairs(scene, groups, kinds)


@ON_CELLS
def test_the_grid_answers_from_its_last_look_only_while_no_cell_range_changes(make):
    """Candidates depend on cell ranges alone: a move inside a cell reuses the last answer
    (and the exact tests still see the new places); a move across a cell edge looks again."""
    store, grid, detector, probe, _ = _two_blocks((0, 0), (20, 20),
                                                  make=lambda cell: Looks(make(cell)))
    looks = grid.ticks  # the ticks on which the broad phase was asked

    def tick(x: int, y: int) -> tuple[int, list[tuple[int, int]]]:
        store.tick += 1
        store.move(probe, x, y)
        contacts, stats = detector.detect(store)
        return stats.candidates, [(c.a_id, c.b_id) for c in contacts]

    contacts, stats = detector.detect(store)
    assert (stats.candidates, contacts, looks) == (1, [], [0])  # both in cell (0, 0)
    assert tick(8, 8) == (1, [])  # still in cell (0, 0): the same candidate, still apart
    assert tick(18, 18) == (1, [(1, 2)])  # overlapping now, found from the same candidate
    assert looks == [0]  # no look since the first
    assert tick(40, 0) == (0, [])  # in cell (1, 0): looked again, no candidate left
    assert looks == [0, 3]
    assert tick(20, 20) == (1, [(1, 2)])  # back: looked again
    assert looks == [0, 3, 4]


@ON_CELLS
def test_detectors_taking_turns_on_one_store_each_see_the_moves_made_for_the_other(make):
    """A store feeds one broad phase: attaching another detector's takes the moves away
    from the first, which must then start again from the store, not answer from its last
    look."""
    store, _, first, probe, _ = _two_blocks((0, 0), (40, 0), make=make)
    second = Detector(make(32), first.rules)
    assert first.detect(store)[1].candidates == 0  # apart: in cells 0 and 1
    assert second.detect(store)[1].candidates == 0  # the store now feeds the second's
    store.tick += 1
    store.move(probe, 38, 0)  # into the target's cell, overlapping it
    contacts, stats = first.detect(store)
    assert (stats.candidates, [(c.a_id, c.b_id) for c in contacts]) == (1, [(1, 2)])
    store.tick += 1
    store.move(probe, 0, 0)  # back, heard by the first's broad phase alone
    assert second.detect(store)[1].candidates == 0


def test_a_body_crossing_a_cell_edge_is_re_binned_once_and_keeps_the_cells_it_entered():
    """While few bodies move: entering the next cell re-bins (the box spans both); moving
    on inside the range it has keeps it, a superset the exact tests see through; leaving it
    re-bins again."""
    store, grid, detector, _, mover = _two_blocks((2, 2), (26, 2))
    detector.detect(store)
    seen = []
    for x in (30, 34, 58, 62, 66):
        store.tick += 1
        store.move(mover, x, 2)
        contacts, stats = detector.detect(store)
        seen.append((grid.ranges[mover.id], grid.rebins, stats.candidates, len(contacts)))
    assert seen == [
        ((0, 0, 1, 0), 2, 1, 0),  # 30..33: spans cells 0 and 1, re-binned (the first bin is 1)
        ((0, 0, 1, 0), 2, 1, 0),  # 34..37: inside cell 1, keeps cell 0 too: still a candidate
        ((0, 0, 1, 0), 2, 1, 0),  # 58..61
        ((1, 0, 2, 0), 3, 0, 0),  # 62..65: enters cell 2, leaves cell 0: re-binned once
        ((1, 0, 2, 0), 3, 0, 0),  # 66..69: inside cell 2
    ]
    assert set(grid.layers[2]) == {1, 2}  # binned in cells 1 and 2 of row 0


@ON_CELLS
def test_a_body_keeps_a_larger_range_only_while_few_bodies_move_at_game_scale(make):
    """A larger range spares a re-bin and a look; with many bodies moving out of their
    cells the grid looks anyway, and in a scene past the game's scale larger ranges would
    cost candidates, so there a body (here a probe) gets its exact range back."""
    from invaders.engine.grid import FEW_MOVES, GAME_SCALE

    for others, step in ((0, 0), (FEW_MOVES, 32), (GAME_SCALE, 0)):
        store, grid, detector, probe, _ = _two_blocks((26, 2), (200, 200), make=make)
        crowd = [Body(10 + k, 1, 100 + 8 * k, 100, probe.mask) for k in range(others)]
        for body in crowd:
            store.add(body)
        detector.detect(store)
        ranges = []
        for x in (30, 34):
            store.tick += 1
            store.move(probe, x, 2)
            for body in crowd if step else ():
                store.move(body, body.x, body.y + step)
            detector.detect(store)
            ranges.append(_cells(grid, probe.id))
        kept = (0, 0, 1, 0) if others == 0 else (1, 0, 1, 0)
        assert ranges == [(0, 0, 1, 0), kept], others


def test_a_move_the_store_does_not_report_inside_an_exact_fence_changes_no_cells():
    """The invariant the exact fence keeps, for every alignment of boxes of 1 to 12 px on
    cells of 1, 3 and 8, along x and along y: from a range (the cells of a box, or of its
    path on, as a swept body's), the store reports a move (the box leaves the fence)
    exactly when the box's cells are no longer that range; a range the box cannot cover
    all of reports every move."""
    from types import SimpleNamespace

    import pygame

    from invaders.engine.grid import exact_fence
    from invaders.engine.store import BodyStore

    store, buffer = BodyStore((1,)), []
    store.attach(SimpleNamespace(move_buffer=buffer))
    ids = iter(range(1, 1000))
    for c in (1, 3, 8):
        across = -(-4 // c) * c  # (the other axis: a box 4 px deep at 0 covers 0..across)
        for size in range(1, 13):
            def span(start: int, c: int = c, size: int = size) -> tuple[int, int]:
                return start // c * c, -(-(start + size) // c) * c

            for along_y in (False, True):
                shape = (4, size) if along_y else (size, 4)
                body = Body(next(ids), 1, 0, 0, pygame.mask.Mask(shape, fill=True))
                store.add(body)
                for start in range(2 * c):
                    for path in (0, size // 2, size + c):  # (a box, or a path from it)
                        lo, hi = span(start)[0], span(start + path)[1]
                        cells = (0, lo, across, hi) if along_y else (lo, 0, hi, across)
                        for step in range(-2 * c - size, 2 * c + size + 1):
                            body.x, body.y = (0, start) if along_y else (start, 0)
                            body.fence = exact_fence(cells, c, body.w, body.h)
                            buffer.clear()
                            store.tick += 1
                            to = start + step
                            store.move(body, *((0, to) if along_y else (to, 0)))
                            assert bool(buffer) == (span(to) != (lo, hi)), (
                                c, size, along_y, start, path, step)
                store.remove(body)


@ON_CELLS
def test_beyond_game_scale_a_move_within_the_same_cells_goes_unheard_and_ranges_stay_exact(
        make):
    """Past GAME_SCALE bodies (or when many move) a body's fence is exact: of bodies
    jittering a pixel or two, the broad phase hears those whose cells changed and only
    those, and every range stays the cells of its box (what a fresh broad phase bins)."""
    from invaders.engine.grid import GAME_SCALE
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    rng = random.Random(5)
    store, broad = BodyStore((1, 2)), make(32)
    detector = Detector(broad, RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion.DISCRETE),)))
    block = art.mask_of(("#####",) * 5)
    bodies = [Body(i + 1, 1 + i % 2, rng.randrange(300), rng.randrange(300), block)
              for i in range(GAME_SCALE + 36)]
    for body in bodies:
        store.add(body)
    detector.detect(store)

    def cells(body: Body) -> tuple[int, int, int, int]:
        return body.x // 32, body.y // 32, (body.x + 4) // 32, (body.y + 4) // 32

    heard_in_all = 0
    for tick in range(1, 40):
        store.tick = tick
        changed = 0
        for body in bodies:
            was = cells(body)
            store.move(body, body.x + rng.randint(-2, 2), body.y + rng.randint(-2, 2))
            changed += cells(body) != was
        assert len(broad.move_buffer) == changed
        heard_in_all += changed
        detector.detect(store)
        assert all(_cells(broad, body.id) == cells(body) for body in bodies)
    assert 0 < heard_in_all < len(bodies) * 39 // 4  # (most moves kept their cells)


@ON_CELLS
def test_a_swept_body_is_seen_over_its_whole_path_when_its_start_was_not_its_last_place(make):
    """While few move, a swept body whose box stays inside its cells is not reported, as
    its start was its last place. When its start is elsewhere (put down so, or it moved
    away on a tick the grid did not look at and came back on the next), the path from the
    start is binned: here it runs back across the target and ends in the cell it left."""
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape

    brute = Detector(Brute(), RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion.SWEPT),)))
    for skipped_a_look in (False, True):
        store, grid, detector, probe, _ = _two_blocks((2, 2), (64, 2), swept=True, make=make)
        detector.detect(store)
        store.tick += 1
        if skipped_a_look:  # it goes right on a tick nobody looked, and back on the next
            store.move(probe, 100, 2)
            store.tick += 1
            store.move(probe, 4, 2)
        else:  # played back: this tick it went from x = 100 to x = 4
            store.move_from(probe, 100, 2, 4, 2)
        contacts, _ = detector.detect(store)
        # The first touch: the probe at x 67..70 meets the target at 64..67.
        assert [(c.a_id, c.b_id, c.ax) for c in contacts] == [(1, 2, 67)]
        assert contacts == brute.detect(store)[0]
        assert _cells(grid, probe.id) == (0, 0, 3, 0)  # x 4..104: cells 0 to 3


def test_the_store_reports_a_move_only_when_the_box_leaves_its_fence():
    """A fence (here x and y 0..16) spares the broad phase the moves inside it; any move
    that leaves it is heard, the second of a tick too, and a move played back from a start
    outside it."""
    from types import SimpleNamespace

    from invaders.engine.store import BodyStore

    store = BodyStore((1,))
    buffer: list[Body] = []
    store.attach(SimpleNamespace(move_buffer=buffer))
    body = Body(1, 1, 4, 4, art.mask_of(("####",) * 4))
    store.add(body)
    assert buffer == [body]  # added: always heard
    buffer.clear()
    body.fence = (0, 0, 16, 16)
    heard = []
    for tick, move in ((1, lambda: store.move(body, 12, 12)),  # 12..16: inside
                       (1, lambda: store.move(body, 13, 12)),  # 13..17: out, same tick
                       (2, lambda: store.move_from(body, 8, 8, 4, 4)),  # both ends inside
                       (3, lambda: store.move_from(body, 20, 0, 4, 4)),  # from outside:
                       (4, lambda: store.move_from(body, -8, 4, 4, 4)),  # the right, left,
                       (5, lambda: store.move_from(body, 4, 20, 4, 4)),  # below
                       (6, lambda: store.move_from(body, 4, -8, 4, 4))):  # and above
        store.tick = tick
        move()
        heard.append(len(buffer))
        buffer.clear()
    assert heard == [0, 1, 0, 1, 1, 1, 1]


def test_the_numpy_broad_phase_hears_every_move_of_a_body_the_grid_fenced():
    """The grid lets a body move unheard inside its cells; the numpy broad phase must hear
    every move, so its bodies lose their fences when it takes the store over, and a body
    that comes back later has none. Here the probe moves, inside its old cell, onto the
    target."""
    from invaders.engine.adaptive import make_broadphase

    for comes_back in (False, True):
        store, _, detector, probe, _ = _two_blocks((2, 2), (26, 2))
        detector.detect(store)  # few bodies: the grid fences each in its cell, x 0..32
        assert probe.fence == (0, 0, 32, 32)
        if comes_back:
            store.tick += 1
            store.remove(probe)
            detector.detect(store)
        numpy = Detector(make_broadphase("numpy"), detector.rules)
        numpy.detect(store)
        if comes_back:
            store.tick += 1
            store.add(probe)
            numpy.detect(store)
        store.tick += 1
        store.move(probe, 24, 2)  # 24..28 against the target's 26..30
        contacts, _ = numpy.detect(store)
        assert [(c.a_id, c.b_id) for c in contacts] == [(1, 2)]


@pytest.mark.parametrize("name", ["numpy", "auto", "rects", "grid"])
def test_a_move_is_heard_though_finding_a_zones_bodies_took_it_from_the_buffer(name):
    """The detector reuses a stateful broad phase's answer only while its move buffer stays
    empty; the numpy broad phase drains that buffer when asked for a zone's bodies, which
    comes first. Here kind 3 meets kind 1 only in a zone far off, so the groups are the
    same each tick, and the probe moves onto the target."""
    from invaders.engine.adaptive import make_broadphase
    from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
    from invaders.engine.store import BodyStore

    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion.DISCRETE),
                       PairRule(3, 1, Shape.BOX, Shape.BOX, Motion.DISCRETE,
                                zone=((500, 500, 10, 10),))))
    store = BodyStore((1, 2, 3))
    block = art.mask_of(("####",) * 4)
    probe = Body(1, 1, 2, 2, block)
    for body in (probe, Body(2, 2, 40, 2, block), Body(3, 3, 90, 90, block)):
        store.add(body)
    detector = Detector(make_broadphase(name), rules)
    assert detector.detect(store)[0] == []
    store.tick += 1
    assert detector.detect(store)[0] == []
    store.tick += 1
    store.move(probe, 38, 2)
    contacts, _ = detector.detect(store)
    assert [(c.a_id, c.b_id) for c in contacts] == [(1, 2)]


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), cell=st.sampled_from([3, 8, 32]),
       a_size=st.integers(1, 40), b_size=st.integers(1, 40))
def test_numpy_box_pairs_are_the_overlapping_boxes_each_once(seed, cell, a_size, b_size):
    """Boxes that cover one cell each and boxes that cover many (where a pair shares several
    cells and must still come out once): exactly the pairs brute force finds overlapping.
    Among them boxes of no width or height, which have no pixel, so no pair of theirs
    matters, but which may have no cell: one such and one of two cells on a side made
    its cells as many as its boxes, taken as one cell each, and a pair sharing two cells
    came out twice."""
    import numpy as np

    from invaders.engine.numpy_grid import box_pairs

    rng = random.Random(seed)

    def boxes(n: int, size: int) -> np.ndarray:
        rows = []
        for _ in range(n):
            x, y = rng.randrange(-50, 50), rng.randrange(-50, 50)
            rows.append((x, y, x + rng.randrange(0, size + 1), y + rng.randrange(0, size + 1)))
        return np.array(rows, dtype=np.int64).reshape(-1, 4)

    a, b = boxes(rng.randrange(0, 30), a_size), boxes(rng.randrange(0, 30), b_size)
    i, j = box_pairs(a, b, cell)
    found = list(zip(i.tolist(), j.tolist(), strict=True))
    assert len(found) == len(set(found))
    empty = {("a", p) for p in range(len(a)) if a[p, 2] == a[p, 0] or a[p, 3] == a[p, 1]} | {
        ("b", q) for q in range(len(b)) if b[q, 2] == b[q, 0] or b[q, 3] == b[q, 1]}
    expected = [(p, q) for p in range(len(a)) for q in range(len(b))
                if a[p, 0] < b[q, 2] and b[q, 0] < a[p, 2]
                and a[p, 1] < b[q, 3] and b[q, 1] < a[p, 3]
                and ("a", p) not in empty and ("b", q) not in empty]
    assert sorted(pair for pair in found if ("a", pair[0]) not in empty
                  and ("b", pair[1]) not in empty) == expected


def test_a_box_of_no_cell_does_not_hide_a_pair_that_shares_two():
    """Found by a search against the oracle: a's second box and b's second share two
    cells of 3 px; b's first box, of no height, has no cell, so b's keys were as many as
    its boxes and taken as one each, and the pair came out twice (two contacts)."""
    import numpy as np

    from invaders.engine.numpy_grid import box_pairs

    a = np.array([[15, -1, 15, -1], [7, 31, 15, 39]], dtype=np.int64)
    b = np.array([[22, 24, 30, 24], [8, 35, 11, 36], [33, 29, 36, 30], [25, 2, 26, 3]],
                 dtype=np.int64)
    i, j = box_pairs(a, b, 3)
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == [(1, 1)]


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), cell=st.sampled_from([3, 8, 32]))
def test_numpy_box_pairs_meet_boxes_too_large_to_bin_box_by_box(seed, cell):
    """Boxes of a few cells and boxes of millions (up to 10^6 px a side, and a few cells
    wide but a world long), on either side: exactly the overlapping pairs, each once."""
    import numpy as np

    from invaders.engine.grid import LARGE_CELLS
    from invaders.engine.numpy_grid import _cells, box_pairs

    rng = random.Random(seed)

    def boxes(n: int) -> np.ndarray:
        rows = []
        for _ in range(n):
            x, y = rng.randrange(-200, 200), rng.randrange(-200, 200)
            w, h = rng.choice([(rng.randrange(1, 40), rng.randrange(1, 40)),
                               (rng.randrange(1, 10**6), rng.randrange(1, 10**6)),
                               (rng.randrange(1, 20), 10**6)])
            rows.append((x - w // 2, y - h // 2, x - w // 2 + w, y - h // 2 + h))
        return np.array(rows, dtype=np.int64).reshape(-1, 4)

    a, b = boxes(rng.randrange(0, 20)), boxes(rng.randrange(0, 20))
    i, j = box_pairs(a, b, cell)
    expected = [(p, q) for p in range(len(a)) for q in range(len(b))
                if a[p, 0] < b[q, 2] and b[q, 0] < a[p, 2]
                and a[p, 1] < b[q, 3] and b[q, 1] < a[p, 3]]
    assert sorted(zip(i.tolist(), j.tolist(), strict=True)) == expected
    both = np.concatenate([a, b])
    keys, rows, large, _ = _cells(both, cell)
    cells = [((x1 - 1) // cell - x0 // cell + 1) * ((y1 - 1) // cell - y0 // cell + 1)
             for x0, y0, x1, y1 in both.tolist()]
    assert large.tolist() == [r for r, n in enumerate(cells) if n > LARGE_CELLS]
    assert len(keys) == len(rows) == sum(n for n in cells if n <= LARGE_CELLS)


@settings(max_examples=60, deadline=None)
@given(values=st.lists(st.integers(-(2**40), 2**40), max_size=60), repeats=st.integers(1, 3))
def test_distinct_is_numpys_unique(values, repeats):
    import numpy as np

    from invaders.engine.numpy_grid import distinct

    array = np.array(values * repeats, dtype=np.int64)
    assert distinct(array).tolist() == np.unique(array).tolist()


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), cell=st.sampled_from([3, 8, 32]),
       size=st.integers(1, 70))
def test_numpy_cells_are_every_cell_each_box_covers(seed, cell, size):
    """Boxes in one cell, in up to 2x2 and in more: each row's cells, row by row."""
    import numpy as np

    from invaders.engine.numpy_grid import OFFSET, STRIDE, _cells

    rng = random.Random(seed)
    rows = []
    for _ in range(rng.randrange(1, 25)):
        x, y = rng.randrange(-100, 100), rng.randrange(-100, 100)
        rows.append((x, y, x + rng.randrange(1, size + 1), y + rng.randrange(1, size + 1)))
    keys, of, large, single = _cells(np.array(rows, dtype=np.int64), cell)
    assert single == (len(of) == len(set(of.tolist())))
    assert not len(large)  # (at most 24 x 24 cells: none too large to bin)
    found = list(zip(of.tolist(), keys.tolist(), strict=True))
    expected = [(r, (cy + OFFSET) * STRIDE + cx + OFFSET)
                for r, (x0, y0, x1, y1) in enumerate(rows)
                for cy in range(y0 // cell, (y1 - 1) // cell + 1)
                for cx in range(x0 // cell, (x1 - 1) // cell + 1)]
    assert found == expected


@settings(max_examples=100, deadline=None)
@given(rows=st.lists(st.tuples(st.integers(-300, 300), st.integers(-300, 300),
                               st.integers(1, 40), st.integers(1, 40),
                               st.integers(-40, 40), st.integers(-40, 40), st.booleans()),
                     min_size=1, max_size=30))
def test_numpy_bins_by_the_same_box_over_the_tick_as_every_other_broad_phase(rows):
    """`tick_box` is the rule the grid, the cell rects and sort-and-sweep bin by; numpy's
    arrays must give the same boxes, moved or not, any size, either direction."""
    from invaders.engine.body import tick_box
    from invaders.engine.numpy_grid import _read, _tick_boxes

    bodies = []
    for i, (x, y, w, h, dx, dy, moved) in enumerate(rows, 1):
        body = Body(i, 1, x, y, art.fresh_mask(art.art(*["#" * w] * h)))
        if moved:
            body.px, body.py, body.moved_tick = x - dx, y - dy, 5
        bodies.append(body)
    raw = _read(bodies, {})
    boxes = _tick_boxes(raw, raw[:, 8] == 5)
    assert boxes.tolist() == [list(tick_box(b, 5)) for b in bodies]
