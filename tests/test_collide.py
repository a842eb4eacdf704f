"""The pygame-compatible collision functions: pygame-ce's own sprite collision tests pass
with ours in pygame's place, and on random scenes ours give pygame's whole result, its
order and its kills, on both the plain and the fast path."""

from __future__ import annotations

import io
import random
import unittest

import pygame
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from invaders.engine import collide

OURS = ("groupcollide", "spritecollide", "spritecollideany", "collide_rect",
        "collide_rect_ratio", "collide_circle", "collide_circle_ratio", "collide_mask")


def test_pygames_own_sprite_collision_tests_pass_with_ours_in_its_place(monkeypatch):
    from pygame.tests import sprite_test

    for name in OURS:
        monkeypatch.setattr(pygame.sprite, name, getattr(collide, name))
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(sprite_test.SpriteCollideTest)
    assert suite.countTestCases() >= 15
    result = unittest.TextTestRunner(stream=io.StringIO(), verbosity=0).run(suite)
    assert result.wasSuccessful(), result.failures + result.errors


class Thing(pygame.sprite.Sprite):
    def __init__(self, x: int, y: int, w: int, h: int, holes: int = 0, seed: int = 0) -> None:
        super().__init__()
        self.rect = pygame.Rect(x, y, w, h)
        if holes >= 0:
            self.mask = pygame.mask.Mask((max(w, 0), max(h, 0)), fill=True)
            rng = random.Random(seed)
            for _ in range(holes if w > 0 and h > 0 else 0):
                self.mask.set_at((rng.randrange(w), rng.randrange(h)), 0)
        else:  # no mask: collide_mask makes one from the image
            self.image = pygame.Surface((max(w, 0), max(h, 0)), pygame.SRCALPHA)
            self.image.fill((255, 255, 255, 255 if holes == -1 else 0))


def _scene(seed: int, n_a: int, n_b: int) -> tuple[list[Thing], list[Thing]]:
    rng = random.Random(seed)

    def thing() -> Thing:
        return Thing(rng.randrange(-20, 120), rng.randrange(-20, 120), rng.randrange(-3, 30),
                     rng.randrange(-3, 30), rng.choice((-2, -1, 0, 0, 5, 40)),
                     rng.randrange(1000))

    return [thing() for _ in range(n_a)], [thing() for _ in range(n_b)]


PREDICATES = [None, pygame.sprite.collide_rect, pygame.sprite.collide_mask,
              collide.collide_mask, pygame.sprite.collide_circle]


@settings(deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_a=st.integers(0, 30), n_b=st.integers(0, 30),
       which=st.integers(0, len(PREDICATES) - 1), kill_a=st.booleans(),
       kill_b=st.booleans(), holder=st.sampled_from(["group", "layered", "list"]))
def test_groupcollide_gives_pygames_result_order_and_kills(seed, n_a, n_b, which, kill_a,
                                                           kill_b, holder):
    collided = PREDICATES[which]
    results = []
    for function in (pygame.sprite.groupcollide, collide.groupcollide):
        side_a, side_b = _scene(seed, n_a, n_b)
        group_a = pygame.sprite.Group(side_a)
        group_b = (pygame.sprite.LayeredUpdates if holder == "layered" else
                   pygame.sprite.Group)()
        for i, sprite in enumerate(side_b):  # layers out of order: iteration is by layer
            group_b.add(sprite, layer=i * 7 % 3) if holder == "layered" else group_b.add(sprite)
        b = list(side_b) if holder == "list" else group_b
        found = function(group_a, b, kill_a, kill_b, collided)
        index = {id(s): ("a", i) for i, s in enumerate(side_a)}
        index.update({id(s): ("b", i) for i, s in enumerate(side_b)})
        results.append(([(index[id(k)], [index[id(v)] for v in vs]) for k, vs in found.items()],
                        [index[id(s)] for s in group_a], [index[id(s)] for s in group_b]))
    assert results[0] == results[1]


def test_a_shot_that_kills_is_spent_on_the_first_alien_it_meets():
    """aliens.py's groupcollide(aliens, shots, True, True): the shot goes with the first
    alien it meets, so the second alien it overlaps lives (the fast path too)."""
    for extra in (0, 40):  # 40 far-off aliens more: enough pairs for the C tests
        for function in (pygame.sprite.groupcollide, collide.groupcollide):
            aliens = pygame.sprite.Group(Thing(0, 0, 20, 10), Thing(5, 0, 20, 10),
                                         *(Thing(500 + 30 * i, 500, 20, 10)
                                           for i in range(extra)))
            shots = pygame.sprite.Group(Thing(8, 5, 2, 8), Thing(1000, 0, 2, 8))
            found = function(aliens, shots, True, True)
            assert len(found) == 1 and len(aliens) == 1 + extra and len(shots) == 1


@pytest.mark.parametrize("collided", PREDICATES[:4])
def test_the_fast_path_is_taken_and_agrees_on_big_groups(collided, monkeypatch):
    side_a, side_b = _scene(7, 60, 80)
    expected = pygame.sprite.groupcollide(side_a, side_b, False, False, collided)
    fast, calls = collide._groupcollide_fast, []
    monkeypatch.setattr(collide, "_groupcollide_fast", lambda *a: calls.append(1) or fast(*a))
    assert collide.groupcollide(side_a, side_b, False, False, collided) == expected
    assert expected and calls == [1]
