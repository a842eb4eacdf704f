"""The engine on pygame sprite groups: the same pairs as groupcollide with collide_mask on
still sprites, and a fast sprite caught where groupcollide lets it pass."""

from __future__ import annotations

import random
import re
import subprocess
import sys
import textwrap
from fractions import Fraction
from pathlib import Path

import pygame
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.engine.sprites import GroupCollide, SpriteCollider
from tests.helpers import mask


class Thing(pygame.sprite.Sprite):
    def __init__(self, x: int, y: int, shape: pygame.mask.Mask | None, w: int = 0,
                 h: int = 0) -> None:
        super().__init__()
        if shape is not None:
            self.mask = shape
            w, h = shape.get_size()
        self.rect = pygame.Rect(x, y, w, h)


def _random_mask(rng: random.Random) -> pygame.mask.Mask:
    w, h = rng.randrange(1, 24), rng.randrange(1, 24)
    m = pygame.mask.Mask((w, h))
    for _ in range(rng.randrange(1, w * h + 1)):
        m.set_at((rng.randrange(w), rng.randrange(h)), 1)
    return m


def _groups(seed: int, count: int) -> tuple[pygame.sprite.Group, pygame.sprite.Group]:
    rng = random.Random(seed)
    groups = pygame.sprite.Group(), pygame.sprite.Group()
    for i in range(count):
        x, y = rng.randrange(-20, 200), rng.randrange(-20, 200)
        groups[i % 2].add(Thing(x, y, _random_mask(rng)))
    return groups


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(0, 80),
       broadphase=st.sampled_from(["grid", "brute", "sweep", "numpy", "auto"]))
def test_still_sprites_give_exactly_what_groupcollide_with_collide_mask_gives(
        seed, count, broadphase):
    shots, aliens = _groups(seed, count)
    expected = pygame.sprite.groupcollide(shots, aliens, False, False,
                                          pygame.sprite.collide_mask)
    ours = GroupCollide(broadphase)(shots, aliens)
    assert ours == expected
    assert list(ours) == list(expected)  # and in the same order


def test_it_stays_equal_frame_after_frame_as_sprites_move_and_leave():
    shots, aliens = _groups(seed=5, count=120)
    collide = GroupCollide()
    rng = random.Random(1)
    matched = 0
    for _ in range(30):
        for sprite in [*shots, *aliens]:
            sprite.rect.move_ip(rng.randrange(-3, 4), rng.randrange(-3, 4))
        for sprite in list(shots)[:2]:
            sprite.kill()
        shots.add(Thing(rng.randrange(200), rng.randrange(200), _random_mask(rng)))
        expected = pygame.sprite.groupcollide(shots, aliens, False, False,
                                              pygame.sprite.collide_mask)
        assert collide(shots, aliens) == expected
        matched += len(expected)
    assert matched > 30
    assert collide.stats.candidates < collide.stats.naive_pairs  # the broad phase at work


class Bullet(Thing):
    """A sprite that says where it was last tick."""

    def __init__(self, x: int, y: int) -> None:
        super().__init__(x, y, mask("##", "##", "##", "##", "##", "##"))
        self.last_rect = self.rect.copy()

    def update(self, dy: int) -> None:
        self.last_rect = self.rect.copy()
        self.rect.move_ip(0, dy)


def test_a_fast_sprite_is_caught_where_groupcollide_lets_it_pass_through():
    bullet = Bullet(50, 92)  # rows 92-97
    wall = Thing(40, 80, mask(*["#" * 20] * 3))  # 3 rows thin: rows 80-82
    bullets, walls = pygame.sprite.Group(bullet), pygame.sprite.Group(wall)
    collide = GroupCollide()
    assert collide(bullets, walls) == {}
    bullet.update(-20)  # to rows 72-77: past the wall in one tick
    theirs = pygame.sprite.groupcollide(bullets, walls, False, False,
                                        pygame.sprite.collide_mask)
    assert theirs == {}  # neither place overlaps the wall: it went straight through
    assert collide(bullets, walls) == {bullet: [wall]}


def test_contacts_know_their_time_and_a_spent_bullet_stops_at_the_first_target():
    SHOTS, TARGETS = 1, 2
    rules = RuleTable((PairRule(SHOTS, TARGETS, Shape.BOX, Shape.MASK, Motion.SWEPT,
                                spends_a=True),))
    collider = SpriteCollider(rules)
    bullet = Bullet(50, 100)
    near = Thing(40, 90, mask(*["#" * 20] * 2))  # rows 90-91
    far = Thing(40, 80, mask(*["#" * 20] * 2))  # rows 80-81
    collider.collide({SHOTS: [bullet], TARGETS: [near, far]})
    bullet.update(-20)  # rows 100-105 to 80-85: through both in one tick
    contacts = collider.collide({SHOTS: [bullet], TARGETS: [near, far]})
    assert [(c.a, c.b, c.time) for c in contacts] == [(bullet, near, Fraction(9, 20))]
    assert collider.stats.swept_tests == 2  # both were tested; the near one came first


def test_a_sprite_that_says_it_came_from_elsewhere_is_swept_from_there():
    """Where it is now is where it was: its `last_rect` alone says it went from rows
    70-75 back to 90-95 this frame, through the wall."""
    bullet = Bullet(50, 90)
    wall = Thing(40, 80, mask(*["#" * 20] * 3))
    groups = pygame.sprite.Group(bullet), pygame.sprite.Group(wall)
    collide = GroupCollide()
    assert collide(*groups) == {}
    bullet.last_rect = bullet.rect.move(0, -20)
    assert collide(*groups) == {bullet: [wall]}


def test_a_sprite_that_starts_a_frame_away_from_where_it_ended_the_last_is_met_there():
    """A jump: the dot says it started this frame inside the rock (its `last_rect`), a
    place it did not stand in at the end of the last frame. That first instant was met by
    no frame before, so it is this frame's: the answer is a fresh collider's. Where a frame
    starts where the last ended, a touch there was the last frame's, and is not met again."""
    rules = RuleTable((PairRule(0, 1),))
    rock, dot = Thing(50, 50, mask(*["#" * 10] * 10)), Thing(0, 0, mask("#"))
    collider = SpriteCollider(rules)

    def met(by: SpriteCollider) -> list[tuple[Fraction, tuple[int, int]]]:
        return [(c.time, c.point) for c in by.collide({0: [dot], 1: [rock]})]

    assert met(collider) == []
    dot.last_rect, dot.rect = pygame.Rect(55, 50, 1, 1), pygame.Rect(55, 51, 1, 1)
    assert met(collider) == met(SpriteCollider(rules)) == [(0, (55, 50))]
    dot.last_rect, dot.rect = dot.rect, pygame.Rect(55, 49, 1, 1)  # out the top, 2 rows
    assert met(collider) == [(Fraction(1, 2), (55, 50))]
    assert met(SpriteCollider(rules)) == [(0, (55, 51))]  # (no last frame: its start too)


def test_a_sprite_that_jumps_onto_where_a_swept_one_starts_is_met_at_that_instant():
    """The dot has no `last_rect`: it stands where it is for the whole frame, here inside
    the rock's place at the frame's start; the rock sweeps away from it. Only that first
    instant touches, and no frame before had the dot there."""
    dot, rock = Thing(0, 0, mask("#")), Thing(50, 50, mask(*["#" * 10] * 10))
    collider = SpriteCollider(RuleTable((PairRule(0, 1),)))
    assert collider.collide({0: [dot], 1: [rock]}) == []
    dot.rect = pygame.Rect(55, 50, 1, 1)
    rock.last_rect, rock.rect = rock.rect.copy(), rock.rect.move(0, 10)
    assert [(c.time, c.point) for c in collider.collide({0: [dot], 1: [rock]})] == [
        (0, (55, 50))]


def _solid_or_own(sprite: Thing) -> pygame.mask.Mask:
    mask = getattr(sprite, "mask", None)
    return mask if mask is not None else pygame.mask.Mask(sprite.rect.size, fill=True)


def _start(sprite: Thing) -> tuple[int, int]:
    last = getattr(sprite, "last_rect", None)
    return sprite.rect.topleft if last is None else last.topleft


def _frame_moves(rng: random.Random, pool: list[Thing]) -> None:
    """Each sprite moved a little or jumped or left alone; swept from where it was, from
    elsewhere or not at all; now and then given a new picture."""
    for sprite in pool:
        old = sprite.rect.copy()
        if rng.random() < 0.6:
            sprite.rect.move_ip(rng.randint(-5, 5), rng.randint(-5, 5))
        elif rng.random() < 0.25:
            sprite.rect.topleft = (rng.randint(0, 25), rng.randint(0, 25))
        swept = rng.random()
        sprite.last_rect = (old if swept < 0.45 else None if swept > 0.6 else
                            sprite.rect.move(rng.randint(-6, 6), rng.randint(-6, 6)))
        if getattr(sprite, "mask", None) is not None and rng.random() < 0.15:
            sprite.mask = _random_mask(rng)
            sprite.rect.size = sprite.mask.get_size()


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1),
       broadphase=st.sampled_from(["grid", "brute", "sweep", "numpy", "auto"]),
       shapes=st.tuples(st.sampled_from(Shape), st.sampled_from(Shape)),
       motion=st.sampled_from([Motion.SWEPT, Motion.DISCRETE]))
def test_a_frames_first_instant_is_its_own_exactly_where_no_frame_before_met_it(
        seed, broadphase, shapes, motion):
    """Frame after frame, each pair's contact is a fresh collider's (one that saw no frame
    before), but where the frame starts as the last ended for both sprites (where each
    stood, no pixel gained) and they move apart: a touch at that first instant was the
    last frame's, so the frame's contact is a later touch or none. The sprites move, jump,
    sweep from elsewhere, change pictures, leave and come back; some have no mask."""
    rng = random.Random(seed)
    rules = RuleTable((PairRule(0, 1, *shapes, motion),))
    pool = []
    for _ in range(rng.randint(2, 10)):
        shape = _random_mask(rng) if rng.random() < 0.85 else None
        pool.append(Thing(rng.randint(0, 25), rng.randint(0, 25), shape, rng.randint(1, 6),
                          rng.randint(1, 6)))
    collider = SpriteCollider(rules, broadphase)
    ended: dict[int, tuple[tuple[int, int], pygame.mask.Mask]] = {}  # at the last frame

    def continues(sprite: Thing) -> bool:
        last = ended.get(id(sprite))
        mask = _solid_or_own(sprite)
        return last is not None and _start(sprite) == last[0] and (
            mask.overlap_area(last[1], (0, 0)) == mask.count())

    for _ in range(10):
        _frame_moves(rng, pool)
        groups = {kind: [s for s in pool[kind::2] if rng.random() < 0.9] for kind in (0, 1)}
        kept = {(id(c.a), id(c.b)): c.time for c in collider.collide(groups)}
        fresh = {(id(c.a), id(c.b)): c.time for c in SpriteCollider(rules).collide(groups)}
        for a in groups[0]:
            for b in groups[1]:
                first, found = fresh.get((id(a), id(b))), kept.get((id(a), id(b)))
                apart = (a.rect.x - _start(a)[0], a.rect.y - _start(a)[1]) != (
                    b.rect.x - _start(b)[0], b.rect.y - _start(b)[1])
                if first == 0 and continues(a) and continues(b) and apart:
                    assert found is None or found > 0
                else:
                    assert found == first
        ended = {id(s): (s.rect.topleft, _solid_or_own(s)) for s in groups[0] + groups[1]}


def test_a_sprite_that_changes_its_picture_is_met_by_the_new_one():
    """An animation's frames as masks put on the sprite in turn: each frame's pixels."""
    walker, target = Thing(0, 0, mask("##..", "##..")), Thing(2, 0, mask("##", "##"))
    groups = pygame.sprite.Group(walker), pygame.sprite.Group(target)
    collide = GroupCollide()
    found = []
    for frame in (mask("##..", "##.."), mask("..##", "..##"), mask("##..", "##..")):
        walker.mask = frame
        found.append(collide(*groups))
        assert found[-1] == pygame.sprite.groupcollide(*groups, False, False,
                                                       pygame.sprite.collide_mask)
    assert found == [{}, {walker: [target]}, {}]


def test_a_sprite_that_drops_its_mask_is_its_rect_and_one_that_takes_one_is_its_mask():
    """A ring's mask put on and taken off a sprite of the same rect: a dot in its hole is
    met only while the sprite has no mask (its rect, solid), however often it changes.
    The collider keeps a box's solid mask while its size stands (not the ring's)."""
    ring = Thing(0, 0, None, 3, 3)
    dot = Thing(1, 1, mask("#"))
    hollow = mask("###", "#.#", "###")
    collider = SpriteCollider(RuleTable((PairRule(0, 1, motion=Motion.DISCRETE),)))
    met = []
    for shape in (None, hollow, None, None, hollow, hollow, None):
        if shape is None:
            ring.__dict__.pop("mask", None)
        else:
            ring.mask = shape
        met.append(len(collider.collide({0: [ring], 1: [dot]})))
    assert met == [1, 0, 1, 1, 0, 0, 1]


def test_the_hits_come_in_the_groups_order_as_pygames_not_the_contacts():
    """Contacts come earliest first, groupcollide's answer in the groups' order: a block
    on its target from the start (the earliest contact) and a bullet that meets the lower
    of two targets before the higher come back as pygame orders them."""
    bullet = Bullet(50, 90)  # rows 90-95, then 80-85
    block, lid = Thing(100, 80, mask("##", "##")), Thing(100, 80, mask("##", "##"))
    high = Thing(40, 80, mask(*["#" * 20] * 2))  # rows 80-81
    low = Thing(40, 84, mask(*["#" * 20] * 2))  # rows 84-85
    movers, targets = pygame.sprite.Group(bullet, block), pygame.sprite.Group(high, low, lid)
    collide = GroupCollide()
    collide(movers, targets)
    bullet.update(-10)
    ours = collide(movers, targets)
    theirs = pygame.sprite.groupcollide(movers, targets, False, False,
                                        pygame.sprite.collide_mask)
    assert ours == theirs == {bullet: [high, low], block: [lid]}
    assert list(ours) == list(theirs)


def _random_image(rng: random.Random) -> pygame.Surface:
    """A picture with holes, as sprites' images have: transparent pixels by alpha or by a
    colour key, which `pygame.mask.from_surface` leaves out."""
    w, h = rng.randrange(1, 24), rng.randrange(1, 24)
    keyed = rng.random() < 0.5
    image = pygame.Surface((w, h), 0 if keyed else pygame.SRCALPHA)
    if keyed:
        image.set_colorkey((0, 0, 0))
    for _ in range(rng.randrange(w * h + 1)):
        image.set_at((rng.randrange(w), rng.randrange(h)), (200, 90, 30, 255))
    return image


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), broadphase=st.sampled_from(["grid", "numpy", "auto"]))
def test_sprites_with_images_and_no_masks_meet_by_their_images_pixels_as_pygames(
        seed, broadphase):
    """`collide_mask` makes a mask of the image where a sprite has none: holes in the
    picture (alpha or colour key) touch nothing, frame after frame as the sprites move,
    and a sprite with both is shaped by its mask."""
    rng = random.Random(seed)
    groups = pygame.sprite.Group(), pygame.sprite.Group()
    for i in range(30):
        sprite = pygame.sprite.Sprite()
        sprite.image = _random_image(rng)
        if rng.random() < 0.3:
            sprite.mask = _random_mask(rng)
        sprite.rect = sprite.image.get_rect(topleft=(rng.randrange(60), rng.randrange(60)))
        groups[i % 2].add(sprite)
    collide = GroupCollide(broadphase)
    for _ in range(4):
        expected = pygame.sprite.groupcollide(*groups, False, False,
                                              pygame.sprite.collide_mask)
        assert collide(*groups) == expected
        for sprite in [*groups[0], *groups[1]]:
            sprite.rect.move_ip(rng.randrange(-4, 5), rng.randrange(-4, 5))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_lists_that_hold_a_sprite_twice_or_share_one_give_what_groupcollide_gives(seed):
    """Lists, not groups, drawn from one pool: a sprite twice in the second is listed twice
    in each answer, one twice in the first answers once, in its first place, and one in
    both meets itself, as pygame's loops make them."""
    rng = random.Random(seed)
    pool = [Thing(rng.randrange(30), rng.randrange(30), _random_mask(rng)) for _ in range(10)]
    a, b = ([rng.choice(pool) for _ in range(7)] for _ in range(2))
    collide = GroupCollide()
    for _ in range(3):
        expected = pygame.sprite.groupcollide(a, b, False, False, pygame.sprite.collide_mask)
        ours = collide(a, b)
        assert ours == expected
        assert list(ours) == list(expected)
        for sprite in pool:
            sprite.rect.move_ip(rng.randrange(-3, 4), rng.randrange(-3, 4))


def test_groups_given_as_iterators_are_read_once_and_met_whole():
    """A generator as the first group gives pygame's answer (its loop reads the first group
    once); as the second, every sprite of the first meets all of it, where pygame's loop
    reads it up for the first sprite alone. (Read twice, the first gave no hits and the
    second raised a KeyError.)"""
    a = [Thing(0, 0, mask("####")), Thing(10, 0, mask("####"))]
    b = [Thing(1, 0, mask("####")), Thing(11, 0, mask("####"))]
    whole = {a[0]: [b[0]], a[1]: [b[1]]}
    assert pygame.sprite.groupcollide(iter(a), b, False, False,
                                      pygame.sprite.collide_mask) == whole
    assert GroupCollide()(iter(a), b) == whole
    assert GroupCollide()(a, (sprite for sprite in b)) == whole
    assert pygame.sprite.groupcollide(a, iter(b), False, False,
                                      pygame.sprite.collide_mask) == {a[0]: [b[0]]}


def test_a_sprite_with_an_image_is_its_pixels_not_its_rect():
    """Two rings whose rects overlap at a corner and whose lit pixels do not."""
    ring = pygame.Surface((10, 10), pygame.SRCALPHA)
    pygame.draw.circle(ring, (255, 255, 255), (5, 5), 4, width=1)
    sprites = []
    for x in (0, 8):
        sprite = pygame.sprite.Sprite()
        sprite.image, sprite.rect = ring, ring.get_rect(topleft=(x, x))
        sprites.append(sprite)
    a, b = pygame.sprite.Group(sprites[0]), pygame.sprite.Group(sprites[1])
    collide = GroupCollide()
    assert collide(a, b) == {} == pygame.sprite.groupcollide(a, b, False, False,
                                                             pygame.sprite.collide_mask)
    sprites[1].rect.topleft = (5, 0)  # the rings cross
    assert collide(a, b) == {sprites[0]: [sprites[1]]}


def test_sprites_without_masks_are_their_rects():
    a = Thing(0, 0, None, 12, 3)  # wider than tall: x 0-11, rows 0-2
    b = Thing(10, 1, None, 5, 5)
    c = Thing(0, 4, None, 5, 5)
    found = GroupCollide()(pygame.sprite.Group(a), pygame.sprite.Group(b, c))
    assert found == pygame.sprite.groupcollide(pygame.sprite.Group(a),
                                               pygame.sprite.Group(b, c), False, False)
    assert found == {a: [b]}


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_sprites_without_masks_meet_as_pygames_rects_do_sizes_negative_and_zero(seed):
    """A rect of negative size covers what pygame's `colliderect` takes it to (its
    corner and size made positive), one of size zero nothing."""
    rng = random.Random(seed)
    groups = [pygame.sprite.Group(), pygame.sprite.Group()]
    for i in range(16):
        box = (rng.randrange(-10, 40), rng.randrange(-10, 40), rng.randrange(-12, 13),
               rng.randrange(-12, 13))
        thing = Thing(0, 0, None)
        thing.rect = pygame.Rect(box)
        groups[i % 2].add(thing)
    expected = pygame.sprite.groupcollide(*groups, False, False)
    assert GroupCollide()(*groups) == expected


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), motion=st.sampled_from(list(Motion)),
       broadphase=st.sampled_from(["grid", "brute", "sweep", "numpy", "rects"]))
def test_box_entries_meet_as_pygames_rects_do_sizes_negative_and_zero(seed, motion,
                                                                      broadphase):
    """An entry of boxes, any motion, on still sprites without masks: the pairs pygame's
    `colliderect` finds. A rect of no width or height meets nothing (a discrete or landing
    entry met one lying inside another's box, and the broad phases disagreed on it)."""
    rng = random.Random(seed)
    groups = [[], []]
    for i in range(16):
        thing = Thing(0, 0, None)
        thing.rect = pygame.Rect(rng.randrange(-10, 40), rng.randrange(-10, 40),
                                 rng.choice([0, 0, rng.randrange(-12, 13)]),
                                 rng.choice([0, rng.randrange(-12, 13)]))
        groups[i % 2].append(thing)
    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, motion),))
    found = {(c.a, c.b) for c in SpriteCollider(rules, broadphase).collide(
        {1: groups[0], 2: groups[1]})}
    expected = pygame.sprite.groupcollide(*groups, False, False)
    assert found == {(a, b) for a, bs in expected.items() for b in bs}


def test_a_sprite_without_a_mask_of_negative_size_is_swept_as_its_box_made_positive():
    rules = RuleTable((PairRule(1, 2, Shape.BOX, Shape.BOX, Motion.SWEPT),))
    found = []
    for now, last in (((5, 0, -3, 2), (5, 30, -3, 2)), ((2, 0, 3, 2), (2, 30, 3, 2))):
        mover, wall = Thing(0, 0, None), Thing(0, 15, None, 10, 1)
        mover.rect, mover.last_rect = pygame.Rect(now), pygame.Rect(last)
        contacts = SpriteCollider(rules).collide({1: [mover], 2: [wall]})
        found.append([(c.time, c.point) for c in contacts])
    # (its top row, from 30 to 0, reaches the wall's one row, 15, 15 rows on: half the way,
    # at x 2, its left column)
    assert found[0] == found[1] == [(Fraction(15, 30), (2, 15))]


def _lit_on_screen(sprite) -> set[tuple[int, int]]:
    """The screen pixels pygame's own `Group.draw` lights for a sprite, its mask its
    picture (on the screen whole where its corner is above -1, each way)."""
    screen = pygame.Surface((100, 100))
    drawn = pygame.sprite.Sprite()
    drawn.image = sprite.mask.to_surface(setcolor=(255, 255, 255), unsetcolor=(0, 0, 0))
    drawn.rect = sprite.rect
    pygame.sprite.Group(drawn).draw(screen)
    lit = pygame.mask.from_threshold(screen, (255, 255, 255), (1, 1, 1, 255))
    return {(x, y) for box in lit.get_bounding_rects() for x in range(box.left, box.right)
            for y in range(box.top, box.bottom) if lit.get_at((x, y))}


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_float_rect_sprites_meet_where_pygame_draws_them_touching(seed):
    """`FRect`s (pygame-ce's float rects): a sprite is at the pixels pygame draws it on,
    so two meet exactly when their drawn pixels share one; fractions of a pixel apart
    either way, as a sprite moved by a float speed stands."""
    rng = random.Random(seed)
    sprites = []
    for _ in range(12):
        sprite = pygame.sprite.Sprite()
        sprite.mask = _random_mask(rng)
        w, h = sprite.mask.get_size()
        # (from -1: pygame draws a corner at -0.7 at 0, truncated towards zero, as at 0.7)
        sprite.rect = pygame.FRect(rng.uniform(-1, 40), rng.uniform(-1, 40), w, h)
        sprites.append(sprite)
    a, b = sprites[:6], sprites[6:]
    drawn = {id(s): _lit_on_screen(s) for s in sprites}
    expected = {x: [y for y in b if drawn[id(x)] & drawn[id(y)]] for x in a}
    assert GroupCollide()(a, b) == {x: ys for x, ys in expected.items() if ys}


def test_float_rect_sprites_are_swept_between_the_pixels_pygame_draws_them_on():
    """A bullet moved by a float speed (`FRect`, with its `last_rect`): the same contacts,
    times and points as its drawn `Rect`s give, where swept tests used to stop on the
    float (a TypeError)."""
    SHOTS, WALLS = 1, 2
    rules = RuleTable((PairRule(SHOTS, WALLS, Shape.BOX, Shape.MASK, Motion.SWEPT),))
    found = []
    for rect_of in (pygame.FRect, lambda *box: pygame.Rect(pygame.FRect(*box))):
        bullet, wall = pygame.sprite.Sprite(), pygame.sprite.Sprite()
        wall.rect, wall.mask = rect_of(40.6, 80.5, 20, 3), mask(*["#" * 20] * 3)
        bullet.rect, bullet.last_rect = rect_of(50.7, 71.9, 2, 6), rect_of(50.2, 93.4, 2, 6)
        contacts = SpriteCollider(rules).collide({SHOTS: [bullet], WALLS: [wall]})
        found.append([(c.a is bullet, c.b is wall, c.time, c.point) for c in contacts])
    # (drawn from row 93 to row 71, 22 rows up: its top meets the wall's lowest row, 82,
    # 11 rows on, at x 50)
    assert found[0] == found[1] == [(True, True, Fraction(11, 22), (50, 82))]


def test_a_sprite_out_of_its_group_is_met_no_more_and_one_back_in_is_met_again():
    """The collider keeps a body for each sprite it was given, and lets go of those not
    given this time (counted, not searched for, when none is missing)."""
    collider = SpriteCollider(RuleTable((PairRule(0, 1, motion=Motion.DISCRETE),)))
    rock = Thing(0, 0, mask("##", "##"))
    near, far = Thing(1, 1, mask("#")), Thing(0, 0, mask("#"))
    shots, rocks = pygame.sprite.Group(near, far), pygame.sprite.Group(rock)

    def met() -> list[tuple[pygame.sprite.Sprite, pygame.sprite.Sprite]]:
        return [(contact.a, contact.b) for contact in collider.collide({0: shots, 1: rocks})]

    assert met() == [(near, rock), (far, rock)] and collider.stats.objects == 3
    far.kill()
    assert met() == [(near, rock)] and collider.stats.objects == 2
    shots.add(far)
    near.kill()
    assert met() == [(far, rock)] and collider.stats.objects == 2
    rocks.add(near)  # (a sprite of the other kind now: one rule, shot against rock)
    assert met() == [(far, rock)] and collider.stats.objects == 3


def test_a_sprite_listed_twice_is_one_body_moved_once_and_hides_no_sprite_gone():
    """A list may hold a sprite twice: the collider looks at it once a call (its body is
    moved once, from its `last_rect`, as the sprite listed once), and counts it once, so a
    sprite missing from that call's list is still let go."""
    rules = RuleTable((PairRule(0, 1, Shape.BOX, Shape.MASK, Motion.SWEPT),))
    twice, once = SpriteCollider(rules), SpriteCollider(rules)
    bullet, other = Bullet(50, 100), Bullet(10, 100)
    walls = [Thing(40, 90, mask(*["#" * 20] * 2)), Thing(0, 90, mask(*["#" * 20] * 2))]

    def met(collider: SpriteCollider, shots: list) -> list[tuple[object, object, Fraction]]:
        return [(c.a, c.b, c.time) for c in collider.collide({0: shots, 1: walls})]

    assert met(twice, [bullet, other]) == met(once, [bullet, other]) == []
    bullet.update(-20)  # through the wall at x 40 in one frame
    other.update(-20)  # through the one at x 0, but gone from the lists
    assert met(twice, [bullet, bullet]) == met(once, [bullet]) == [
        (bullet, walls[0], Fraction(9, 20))]
    assert twice.stats.objects == once.stats.objects == 3


def test_a_group_of_a_kind_no_rule_names_is_refused_naming_it_and_nothing_moves():
    collider = SpriteCollider(RuleTable((PairRule(1, 2),)))
    a, b = Thing(0, 0, None, 2, 2), Thing(1, 1, None, 2, 2)
    with pytest.raises(ValueError, match="kind 7: no entry of the rules names it"):
        collider.collide({1: [a], 7: [b]})
    assert collider.store.tick == 0 and not collider.store.by_kind[1]  # (as it was)
    assert [(c.a, c.b) for c in collider.collide({1: [a], 2: [b]})] == [(a, b)]


def test_the_readme_example_runs_and_prints_what_it_says(capsys):
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    section = readme.split("## The engine on your own sprites", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert len([line for line in code.splitlines() if line.strip()]) <= 15
    exec(compile(code, "README.md", "exec"), {})
    printed = capsys.readouterr().out.strip()
    assert printed == re.search(r"# (True True \S+)", code).group(1) == "True True 1/2"


def test_memory_stays_flat_while_a_sprite_without_a_mask_changes_size_every_frame():
    """A box dragged across a screen (a selection, say): its sprite has no mask, so its
    shape is a solid mask of its rect's size, a new size every frame. Each was kept for
    the process, with its pair of old and new masks (1,500 frames of boxes up to 1,900 x
    1,000 px: 150 MB); now what is kept is bounded. Its answers stay pygame's rects'."""
    script = textwrap.dedent("""
        import os
        os.environ["SDL_VIDEODRIVER"] = "dummy"
        import pygame
        from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
        from invaders.engine.sprites import GroupCollide, SpriteCollider

        def rss():
            with open("/proc/self/statm") as f:
                return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

        box = pygame.sprite.Sprite()
        box.rect = pygame.Rect(0, 0, 1, 1)
        units = []
        for i in range(20):
            unit = pygame.sprite.Sprite()
            unit.rect = pygame.Rect(i * 97 % 1900, i * 53 % 1000, 16, 16)
            unit.mask = pygame.mask.Mask((16, 16), fill=True)
            units.append(unit)
        groups = GroupCollide()
        boxes = SpriteCollider(RuleTable((PairRule(0, 1, Shape.BOX, Shape.MASK),)))
        wrong, seen = 0, []
        for frame in range(1500):
            box.rect.size = (500 + frame * 7 % 1400, 300 + frame * 13 % 700)
            found = groups([box], units)
            wrong += found != pygame.sprite.groupcollide([box], units, False, False)
            met = [contact.b for contact in boxes.collide({0: [box], 1: units})]
            wrong += met != [unit for unit in units if box.rect.colliderect(unit.rect)]
            if frame in (300, 1499):
                seen.append(rss())
        print(wrong, *seen)
    """)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=300, check=True)
    wrong, early, late = map(int, result.stdout.split())
    assert wrong == 0
    assert late - early < 24 * 2**20, (early, late)  # kept for the process: ~120 MB more
