"""The pygame-compatible collision functions: pygame-ce's own sprite collision tests pass
with ours in pygame's place, and on random scenes ours give pygame's whole result, its
order and its kills, on both the plain and the fast path."""

from __future__ import annotations

import io
import random
import sys
import unittest

import pygame
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.engine import collide

OURS = ("groupcollide", "spritecollide", "spritecollideany", "collide_rect",
        "collide_rect_ratio", "collide_circle", "collide_circle_ratio", "collide_mask")


def test_pygames_own_sprite_collision_tests_pass_with_ours_in_its_place(monkeypatch):
    # (pygame's test package puts its own folders first on sys.path, where its typing.py
    # would hide the standard library's from any process started after: put back after)
    monkeypatch.setattr(sys, "path", list(sys.path))
    from pygame.tests import sprite_test

    for name in OURS:
        monkeypatch.setattr(pygame.sprite, name, getattr(collide, name))
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(sprite_test.SpriteCollideTest)
    assert suite.countTestCases() >= 15
    result = unittest.TextTestRunner(stream=io.StringIO(), verbosity=0).run(suite)
    assert result.wasSuccessful(), result.failures + result.errors


@pytest.mark.parametrize("name, args", [("collide_circle", ()), ("collide_circle_ratio", (0.5,)),
                                        ("collide_rect_ratio", (0.5,)),
                                        ("collide_rect_ratio", (1.5,))])
def test_each_predicate_answers_as_pygames_at_every_offset_touching_ones_among_them(name,
                                                                                   args):
    """Rects 8x3 and 5x12 (not square), radii 6 and 4 (their sum, and half of it, whole
    numbers): at every whole offset from -16 to 16 each way, rects that overlap, touch
    or part when scaled, and circles exactly their reach apart (10 and 5: the 3-4-5
    triangle's offsets among them), ours answers as pygame's does."""
    ours = getattr(collide, name)(*args) if args else getattr(collide, name)
    theirs = getattr(pygame.sprite, name)(*args) if args else getattr(pygame.sprite, name)
    first = Thing(0, 0, 8, 3)
    first.radius = 6
    answers, touching = [], 0
    for dx in range(-16, 17):
        for dy in range(-16, 17):
            second = Thing(dx, dy, 5, 12)
            second.radius = 4
            answers.append(ours(first, second))
            assert answers[-1] == theirs(first, second), (dx, dy)
            gap = (first.rect.centerx - second.rect.centerx, first.rect.centery
                   - second.rect.centery)
            touching += gap[0] ** 2 + gap[1] ** 2 == (10 * (args or (1,))[0]) ** 2
    assert 0 < sum(answers) < len(answers)
    if "circle" in name:
        assert touching >= 8


class Thing(pygame.sprite.Sprite):
    def __init__(self, x: float, y: float, w: float, h: float, holes: int = 0,
                 seed: int = 0) -> None:
        super().__init__()
        floats = isinstance(x, float)
        self.rect = (pygame.FRect if floats else pygame.Rect)(x, y, w, h)
        w, h = int(w), int(h)
        if holes >= 0:
            self.mask = pygame.mask.Mask((max(w, 0), max(h, 0)), fill=True)
            rng = random.Random(seed)
            for _ in range(holes if w > 0 and h > 0 else 0):
                self.mask.set_at((rng.randrange(w), rng.randrange(h)), 0)
        else:  # no mask: collide_mask makes one from the image
            self.image = pygame.Surface((max(w, 0), max(h, 0)), pygame.SRCALPHA)
            self.image.fill((255, 255, 255, 255 if holes == -1 else 0))


def _scene(seed: int, n_a: int, n_b: int, floats: bool = False, span: int = 140
           ) -> tuple[list[Thing], list[Thing]]:
    """Sprites of sizes -3 to 29 (masks holed, full, empty, or made from images) placed in
    a square `span` px a side, some with float rects (FRect) when asked, each side with a
    sprite or two repeated."""
    rng = random.Random(seed)

    def place() -> float:
        return rng.randrange(-20, span - 20) + (rng.choice((0, 0.25, 0.5, 0.75)) if floats
                                                else 0)

    def thing() -> Thing:
        return Thing(place(), place(), rng.randrange(-3, 30), rng.randrange(-3, 30),
                     rng.choice((-2, -1, 0, 0, 5, 40)), rng.randrange(1000))

    side_a, side_b = [thing() for _ in range(n_a)], [thing() for _ in range(n_b)]
    for side in (side_a, side_b):
        if side and rng.random() < 0.3:
            side.insert(rng.randrange(len(side) + 1), rng.choice(side))
    return side_a, side_b


class Recorded:
    """A predicate of the caller's own: pygame calls it for given pairs, in an order; ours
    must call it for the same pairs in the same order."""

    def __init__(self) -> None:
        self.calls: list[tuple[int, int]] = []

    def __call__(self, left, right) -> bool:
        self.calls.append((id(left), id(right)))
        return bool(left.rect.colliderect(right.rect)) and (left.rect.x + right.rect.y) % 3 != 0


PREDICATES = [None, pygame.sprite.collide_rect, pygame.sprite.collide_mask,
              collide.collide_mask, pygame.sprite.collide_circle,
              pygame.sprite.collide_rect_ratio(0.7), collide.collide_circle_ratio(1.3),
              "recorded"]


def _groups(side_a, side_b, holder):
    """The first side in a Group; the second in a Group, a LayeredUpdates (layers out of
    order, so iteration is by layer) or a list (duplicates kept)."""
    group_a = pygame.sprite.Group(side_a)
    group_b = (pygame.sprite.LayeredUpdates if holder == "layered" else pygame.sprite.Group)()
    for i, sprite in enumerate(side_b):
        group_b.add(sprite, layer=i * 7 % 3) if holder == "layered" else group_b.add(sprite)
    return group_a, group_b, (list(side_b) if holder == "list" else group_b)


def _named(things, side_a, side_b):
    """Sprites as (side, first index) so two scenes built alike compare."""
    index = {id(s): ("b", i) for i, s in reversed(list(enumerate(side_b)))}
    index.update({id(s): ("a", i) for i, s in reversed(list(enumerate(side_a)))})
    return [index[id(s)] for s in things]


def _radii(sprites):
    """Each sprite's `radius`, or None: the circle tests keep one on a sprite at its first
    pair (pygame's do)."""
    return [getattr(s, "radius", None) for s in sprites]


def _calls(collided, side_a, side_b):
    """The pairs a Recorded predicate was called with, named (none for other predicates)."""
    by_id = {id(s): s for s in side_a + side_b}
    return [_named([by_id[left], by_id[right]], side_a, side_b)
            for left, right in getattr(collided, "calls", ())]


SCENES = dict(seed=st.integers(0, 2**32 - 1), n_a=st.integers(0, 30), n_b=st.integers(0, 30),
              which=st.integers(0, len(PREDICATES) - 1), floats=st.booleans(),
              holder=st.sampled_from(["group", "layered", "list"]))


@settings(deadline=None)
@given(kill_a=st.booleans(), kill_b=st.booleans(), **SCENES)
def test_groupcollide_gives_pygames_result_order_and_kills(seed, n_a, n_b, which, floats,
                                                           kill_a, kill_b, holder):
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a, side_b = _scene(seed, n_a, n_b, floats)
        group_a, group_b, b = _groups(side_a, side_b, holder)
        collided = Recorded() if PREDICATES[which] == "recorded" else PREDICATES[which]
        found = function(group_a, b, kill_a, kill_b, collided)
        results.append(([(_named([k], side_a, side_b), _named(vs, side_a, side_b))
                         for k, vs in found.items()],
                        _named(group_a, side_a, side_b), _named(group_b, side_a, side_b),
                        _calls(collided, side_a, side_b), _radii(side_a + side_b)))
    assert results[0] == results[1]


@settings(deadline=None)
@given(kill=st.booleans(), **SCENES)
def test_spritecollide_and_spritecollideany_give_pygames_answers(seed, n_a, n_b, which,
                                                                 floats, kill, holder):
    results = []
    for module in (pygame.sprite, collide):
        side_a, side_b = _scene(seed, max(n_a, 1), n_b, floats)
        _, group_b, b = _groups(side_a, side_b, holder)
        collided = Recorded() if PREDICATES[which] == "recorded" else PREDICATES[which]
        first = module.spritecollideany(side_a[0], b, collided)
        found = module.spritecollide(side_a[0], b, kill, collided)
        results.append((_named([first] if first else [], side_a, side_b),
                        _named(found, side_a, side_b), _named(group_b, side_a, side_b),
                        _calls(collided, side_a, side_b)))
    assert results[0] == results[1]


def test_a_mask_is_made_once_per_image_until_the_image_is_forgotten(monkeypatch):
    made = []
    real = pygame.mask.from_surface
    monkeypatch.setattr(pygame.mask, "from_surface", lambda s: made.append(s) or real(s))
    a, b = Thing(0, 0, 4, 4, holes=-1), Thing(2, 2, 4, 4, holes=-1)
    for _ in range(3):
        assert collide.collide_mask(a, b) == (2, 2)
    assert len(made) == 2  # one per image; pygame makes both again on every call
    a.image.fill((0, 0, 0, 0))  # drawn on in place: the invariant broken...
    assert collide.collide_mask(a, b) == (2, 2)  # ...the first mask still answers
    collide.forget_image(a.image)
    assert collide.collide_mask(a, b) is None == pygame.sprite.collide_mask(a, b)


def test_a_shot_that_kills_is_spent_on_the_first_alien_it_meets():
    """aliens.py's groupcollide(aliens, shots, True, True): the shot goes with the first
    alien it meets, so the second alien it overlaps lives (the fast path too)."""
    for extra in (0, 40):  # 40 far-off aliens more: enough pairs for the C tests
        for function in (pygame.sprite.groupcollide, collide.groupcollide):
            first, second, shot, far_shot = (Thing(0, 0, 20, 10), Thing(5, 0, 20, 10),
                                             Thing(8, 5, 2, 8), Thing(1000, 0, 2, 8))
            aliens = pygame.sprite.Group(first, second, *(Thing(500 + 30 * i, 500, 20, 10)
                                                          for i in range(extra)))
            shots = pygame.sprite.Group(shot, far_shot)
            found = function(aliens, shots, True, True)
            assert found == {first: [shot]}
            assert second in aliens and len(aliens) == 1 + extra and shots.sprites() == [far_shot]


@pytest.mark.parametrize("collided", PREDICATES[:4])
def test_the_fast_path_is_taken_and_agrees_on_big_groups(collided, monkeypatch):
    side_a, side_b = _scene(7, 60, 80)
    expected = pygame.sprite.groupcollide(side_a, side_b, False, False, collided)
    fast, calls = collide._groupcollide_fast, []
    monkeypatch.setattr(collide, "_groupcollide_fast", lambda *a: calls.append(1) or fast(*a))
    assert collide.groupcollide(side_a, side_b, False, False, collided) == expected
    assert expected and calls == [1]


@pytest.mark.parametrize("collided", PREDICATES[:4])
@pytest.mark.parametrize("holder", ["group", "layered", "list"])
@pytest.mark.parametrize("kill_b", [False, True])
def test_big_groups_pair_their_boxes_by_a_sort_first_and_give_pygames_answers(
        collided, holder, kill_b, monkeypatch):
    # 600 x 500 sprites, sizes -3 to 29 and masks of every kind, about one in 20 x 20 px:
    # boxes that overlap, touch, nest, or have no size, as pygame meets them; with
    # dokillb, each sprite of the second group met once (a group) or again (a list).
    near, calls = collide._collide_near, []
    monkeypatch.setattr(collide, "_collide_near", lambda *a: calls.append(1) or near(*a))
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a, side_b = _scene(11, 600, 500, span=500)
        group_a, group_b, b = _groups(side_a, side_b, holder)
        found = function(group_a, b, holder == "list", kill_b, collided)  # (kills on a side)
        results.append(([(_named([k], side_a, side_b), _named(vs, side_a, side_b))
                         for k, vs in found.items()],
                        _named(group_a, side_a, side_b), _named(group_b, side_a, side_b)))
    assert results[0] == results[1]
    assert len(results[0][0]) > 100 and calls == [1]
    if kill_b:  # (the second group's sprites that were met are gone)
        assert len(results[0][2]) < 500 - 100


@pytest.mark.parametrize("collided", PREDICATES[:4])
@pytest.mark.parametrize(("n", "span"), [(30, 140), (600, 500)])
@pytest.mark.parametrize("kill_b", [False, True])
def test_float_rects_are_tested_in_c_and_give_pygames_answers(collided, n, span, kill_b,
                                                              monkeypatch):
    """FRects (pygame-ce's float rects) mixed with Rects on both sides, corners a quarter,
    half or three quarters of a pixel on: each sprite of the first group tested against
    the second in one C call, or on big groups only against the boxes near its own (whole
    pixels round the FRects), with pygame's answers, order and kills."""
    calls = []
    for loop in ("_collide_each", "_collide_near"):
        tested = getattr(collide, loop)
        monkeypatch.setattr(collide, loop,
                            lambda *a, loop=loop, tested=tested: calls.append(loop) or tested(*a))
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a, side_b = _scene(5, n, n - n // 6, floats=True, span=span)
        group_a, group_b, b = _groups(side_a, side_b, "group")
        found = function(group_a, b, False, kill_b, collided)
        results.append(([(_named([k], side_a, side_b), _named(vs, side_a, side_b))
                         for k, vs in found.items()], _named(group_b, side_a, side_b)))
    floats = sum(isinstance(s.rect, pygame.FRect) for s in side_a + side_b)
    assert results[0] == results[1]
    assert calls == ["_collide_near" if n == 600 else "_collide_each"]
    assert len(results[0][0]) > n // 10 and 0 < floats < len(side_a + side_b)


class Placed(pygame.sprite.Sprite):
    def __init__(self, x: float, y: float, size: tuple[int, int]) -> None:
        super().__init__()
        self.rect = pygame.FRect(x, y, *size)
        self.mask = pygame.mask.Mask(size, fill=True)


CORNERS = st.builds(lambda whole, part: whole + part, st.integers(-10**6, 10**6),
                    st.sampled_from([0.0, 0.001, 0.25, 0.5, 0.75, 0.999]) | st.floats(0, 1))


@given(ax=CORNERS, ay=CORNERS, bx=CORNERS, by=CORNERS,
       size_a=st.tuples(st.integers(0, 12), st.integers(0, 12)),
       size_b=st.tuples(st.integers(0, 12), st.integers(0, 12)),
       near=st.tuples(st.integers(-14, 14), st.integers(-14, 14)))
def test_masks_that_pygame_finds_meeting_at_float_corners_have_boxes_that_overlap(
        ax, ay, bx, by, size_a, size_b, near):
    """The invariant of `float_mask_box`: pygame places a pair's second mask at the
    difference of the FRects' corners, truncated; the pair's boxes at the corners' floors,
    the first's widened a pixel, overlap whenever those masks meet. (The second sprite is
    put near the first by `near`, whole pixels and its own fraction, for pairs that meet.)
    Unwidened, two pairs that meet here would be missed."""
    a = Placed(ax, ay, size_a)
    b = Placed(int(ax) + near[0] + bx % 1, int(ay) + near[1] + by % 1, size_b)
    if pygame.sprite.collide_mask(a, b):
        assert collide.float_mask_box(a.rect, a.mask, 1).colliderect(
            collide.float_mask_box(b.rect, b.mask, 0))
    for first, second in (((0.5, 0.0), (4.2, 0.0)), ((-0.5, 0.0), (3.4, 0.0))):
        a, b = Placed(*first, (4, 1)), Placed(*second, (4, 1))
        assert pygame.sprite.collide_mask(a, b) == (3, 0)
        assert not collide.float_mask_box(a.rect, a.mask, 0).colliderect(
            collide.float_mask_box(b.rect, b.mask, 0))


SIZES = st.floats(-40, 40, width=32) | st.floats(-2, 2, width=32)  # (boxes under a pixel too)
BOXES = st.tuples(st.floats(-4e6, 4e6, width=32), st.floats(-4e6, 4e6, width=32), SIZES, SIZES)


@given(box_a=BOXES, box_b=BOXES, near=st.tuples(st.floats(-3, 3), st.floats(-3, 3)))
def test_frects_that_pygame_finds_meeting_have_spans_that_meet(box_a, box_b, near):
    """The invariant of `_covering`: two FRects that `colliderect` says meet (in float32,
    sizes negative too, corners up to 4,000,000, where a float32 step is a quarter of a
    pixel) have whole-pixel spans that overlap or touch, as `_near` asks of them. (The
    second box is put near the first by `near`, for pairs that meet.)"""
    a = pygame.FRect(box_a)
    b = pygame.FRect(a.x + near[0], a.y + near[1], box_b[2], box_b[3])
    spans = collide._covering([a, b])
    assert spans is not None
    (a0, a1, a2, a3), (b0, b1, b2, b3) = spans.tolist()
    if a.colliderect(b):
        assert b0 <= a1 and b1 >= a0 and b2 <= a3 and b3 >= a2


@pytest.mark.parametrize("base", [0.0, -7.0, 2.0**21])
def test_frects_on_a_quarter_pixel_grid_that_meet_have_spans_that_meet(base):
    """`_covering`'s invariant on every pair of boxes with corners and sizes on a grid of
    quarter pixels (-2 to 2 from `base`; at 2**21 a float32 step is a quarter of a pixel),
    along each axis: pairs under a pixel apart, touching or overlapping by a quarter."""
    grid = [(base + corner / 4, size / 4) for corner in range(-8, 9) for size in range(-8, 9)]
    for axis in (0, 1):
        boxes = [pygame.FRect((corner, 0.0, size, 1.0) if axis == 0 else
                              (0.0, corner, 1.0, size)) for corner, size in grid]
        spans = collide._covering(boxes).tolist()
        met = 0
        for a, span_a in zip(boxes, spans, strict=True):
            for b, span_b in zip(boxes, spans, strict=True):
                if a.colliderect(b):
                    met += 1
                    assert span_b[0] <= span_a[1] and span_b[1] >= span_a[0], (a, b)
                    assert span_b[2] <= span_a[3] and span_b[3] >= span_a[2], (a, b)
        assert met > 10_000


def test_big_groups_of_frects_past_the_spans_reach_are_met_as_pygame_meets_them():
    """FRects past FLOAT_LIMIT (or not finite) take no spans: each sprite is tested against
    the whole second group, with pygame's answers."""
    rng = random.Random(4)
    far = collide.FLOAT_LIMIT * 2

    def thing(x: float) -> Thing:
        return Thing(x + rng.random(), rng.uniform(0, 300), rng.randrange(1, 20),
                     rng.randrange(1, 20), -2)

    side_a = [thing(rng.uniform(0, 300)) for _ in range(500)]
    side_b = [thing(rng.uniform(0, 300)) for _ in range(499)] + [thing(far)]
    expected = pygame.sprite.groupcollide(side_a, side_b, False, False)
    assert collide._covering([s.rect for s in side_b]) is None
    assert collide.groupcollide(side_a, side_b, False, False) == expected and expected


@pytest.mark.parametrize("far", [1e20, float("inf"), float("nan"), 2**31 - 2.0])
def test_float_corners_past_the_boxes_reach_are_met_as_pygame_meets_them(far):
    """Masks at corners no whole-pixel box can hold (past BOX_LIMIT, not finite): pygame's
    answers, through the plain loop or the masks alone."""
    side_a = [Placed(far - 3.5 if far < 2**31 else 0.5, 0.0, (4, 4)) for _ in range(5)]
    side_b = [Placed(far, 0.0, (4, 4)) for _ in range(5)] + [Placed(0.25, 0.0, (4, 4))]
    expected = pygame.sprite.groupcollide(side_a, side_b, False, False,
                                          pygame.sprite.collide_mask)
    assert collide.groupcollide(side_a, side_b, False, False,
                                pygame.sprite.collide_mask) == expected


CIRCLES = [pygame.sprite.collide_circle, collide.collide_circle,
           pygame.sprite.collide_circle_ratio(0.6), collide.collide_circle_ratio(1.7)]


@pytest.mark.parametrize("collided", CIRCLES)
@pytest.mark.parametrize(("n", "span", "holder"), [(12, 60, "group"), (40, 140, "list"),
                                                   (300, 500, "layered")])
@pytest.mark.parametrize("kill_b", [False, True])
def test_circle_tests_meet_in_c_first_and_give_pygames_answers(collided, n, span, holder,
                                                               kill_b, monkeypatch):
    """Circles round Rects and FRects, some sprites with a radius of their own: each sprite
    of the first group tested in C against boxes round the second's circles, then the
    circles; pygame's answers, order and kills, and the radii it keeps on the sprites."""
    circles, calls = collide._collide_circles, []
    monkeypatch.setattr(collide, "_collide_circles", lambda *a: calls.append(1) or circles(*a))
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a, side_b = _scene(8, n, n - n // 5, floats=True, span=span)
        for sprite in (side_a + side_b)[::7]:
            sprite.radius = (len(side_a) + sprite.rect.x) % 9 * 1.5
        group_a, group_b, b = _groups(side_a, side_b, holder)
        found = function(group_a, b, False, kill_b, collided)
        results.append(([(_named([k], side_a, side_b), _named(vs, side_a, side_b))
                         for k, vs in found.items()],
                        _named(group_b, side_a, side_b), _radii(side_a + side_b)))
    assert results[0] == results[1] and calls == [1]
    assert len(results[0][0]) >= n // 10 >= 1  # (some of the first group met circles)


def test_circles_that_no_box_holds_are_met_as_pygame_meets_them():
    """A radius past any box (infinite) in the second group leaves the answer to the plain
    loop; in the first, its sprite is tested against every circle of the second."""
    for infinite in ("a", "b"):
        results = []
        for function in (pygame.sprite.groupcollide, collide.groupcollide):
            side_a, side_b = _scene(4, 20, 20)
            (side_a if infinite == "a" else side_b)[3].radius = float("inf")
            found = function(side_a, pygame.sprite.Group(side_b), False, True,
                             pygame.sprite.collide_circle)
            results.append(([(_named([k], side_a, side_b), _named(vs, side_a, side_b))
                             for k, vs in found.items()], _radii(side_a + side_b)))
        assert results[0] == results[1] and results[0][0]


def test_once_the_second_group_is_all_killed_no_radius_is_kept_on_the_first():
    """pygame keeps a sprite's radius at its first pair: once `dokillb` has emptied the
    second group, the sprites after have none."""
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a = [Thing(0, 0, 300, 300)] + [Thing(400 + i, 400, 4, 4) for i in range(30)]
        side_b = [Thing(i % 19 * 10, i // 19 * 10, 5, 5) for i in range(40)]
        found = function(side_a, pygame.sprite.Group(side_b), False, True,
                         pygame.sprite.collide_circle)
        results.append(([len(vs) for vs in found.values()], _radii(side_a + side_b)))
    assert results[0] == results[1] and results[0][0] == [40]
    assert results[0][1][1] is None and results[0][1][0] is not None


def test_a_sprite_with_no_picture_met_once_the_second_group_is_all_killed_is_as_pygames():
    """pygame makes a sprite's mask at its first pair: one after the second group is all
    killed never has one made (and has none to make). The big groups' loop makes the first
    group's masks first: where one cannot be made, the plain loop answers, as pygame."""
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a = [Thing(0, 0, 200, 200)] + [Thing(300 + i, 300, 4, 4) for i in range(600)]
        pictureless = pygame.sprite.Sprite()
        pictureless.rect = pygame.Rect(0, 0, 10, 10)
        side_b = [Thing(i % 190, i // 190 * 10, 5, 5) for i in range(500)]
        group_b = pygame.sprite.Group(side_b)
        found = function([*side_a, pictureless], group_b, False, True,
                         pygame.sprite.collide_mask)
        results.append(([(_named([k], side_a, side_b), len(vs)) for k, vs in found.items()],
                        len(group_b)))
    assert results[0] == results[1] == ([([("a", 0)], 500)], 0)  # (the first met all)


@pytest.mark.parametrize("size", [3, 300])  # the plain loop, the fast one
def test_masks_with_one_image_alone_then_one_with_neither_are_met_as_pygame_meets_them(size):
    """Sprites with masks and, among the second group's, one with an image alone: its
    pixels, as pygame's; in its place a plain sprite (no mask, its image None), pygame's
    error."""
    side_a = [Thing(i * 7 % 60, i * 3 % 60, 6, 6, holes=5, seed=i) for i in range(size)]
    side_b = [Thing(i * 5 % 60, i * 11 % 60, 5, 5, holes=3, seed=i) for i in range(size)]
    odd = side_b[size // 2]
    del odd.mask
    odd.image = pygame.Surface((5, 5), pygame.SRCALPHA)
    odd.image.fill((255, 255, 255, 255), (1, 1, 3, 3))
    odd.rect.topleft = side_a[0].rect.move(1, 1).topleft  # (its lit 3x3 on a's 6x6)
    theirs = pygame.sprite.groupcollide(side_a, side_b, False, False, pygame.sprite.collide_mask)
    assert any(odd in met for met in theirs.values())
    assert collide.groupcollide(side_a, side_b, False, False, collide.collide_mask) == theirs
    pictureless = pygame.sprite.Sprite()
    pictureless.rect = odd.rect
    side_b[size // 2] = pictureless
    raised = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        with pytest.raises(TypeError) as error:  # (its image None: no surface to read)
            function(side_a, side_b, False, False, pygame.sprite.collide_mask)
        raised.append(str(error.value))
    assert raised[0] == raised[1]


class Unhashable:
    """A caller's predicate with `__eq__` alone, so no hash: pygame calls it all the same."""

    def __eq__(self, other):
        return self is other

    def __call__(self, left, right):
        return left.rect.colliderect(right.rect)


def test_a_predicate_that_does_not_hash_is_called_as_pygame_calls_it():
    side_a, side_b = _scene(3, 20, 20)
    for function in ("groupcollide", "spritecollide", "spritecollideany"):
        args = {"groupcollide": (side_a, side_b, False, False),
                "spritecollide": (side_a[0], side_b, False),
                "spritecollideany": (side_a[0], side_b)}[function]
        expected = getattr(pygame.sprite, function)(*args, Unhashable())
        assert getattr(collide, function)(*args, Unhashable()) == expected
