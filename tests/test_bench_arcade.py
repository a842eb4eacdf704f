"""bench --arcade's reference: Arcade's boxes meet where pygame's rects do, on the same
places, still and moving, so the two sides time the same work."""

from __future__ import annotations

import pygame

from invaders.lab.bench_arcade import ArcadeField, Walk, arcade_frame, our_answers, our_frame
from invaders.lab.bench_sprites import groups


class Box(pygame.sprite.Sprite):
    def __init__(self, x: int, y: int, w: int, h: int) -> None:
        super().__init__()
        self.rect = pygame.Rect(x, y, w, h)


def pygames_answers(group_a, group_b):
    found = pygame.sprite.groupcollide(group_a, group_b, False, False,
                                       pygame.sprite.collide_rect)
    return {sprite: set(hits) for sprite, hits in found.items()}


def test_arcades_boxes_meet_where_pygames_rects_overlap_and_not_where_they_only_touch():
    centre = Box(40, 40, 6, 9)
    others = {}  # (dx, dy) of a 6x9 box from the centre's corner: whether they overlap
    for dx in (-7, -6, -5, 0, 5, 6, 7):
        for dy in (-10, -9, -8, 0, 8, 9, 10):
            others[(dx, dy)] = abs(dx) < 6 and abs(dy) < 9
    boxes = {offset: Box(40 + offset[0], 40 + offset[1], 6, 9) for offset in others}
    group_a, group_b = pygame.sprite.Group(centre), pygame.sprite.Group(*boxes.values())
    expected = {centre: {boxes[o] for o, overlaps in others.items() if overlaps}}
    assert pygames_answers(group_a, group_b) == expected  # (the judge agrees with itself)
    assert ArcadeField(group_a, group_b).answers() == expected
    assert our_answers(group_a, group_b) == expected
    assert len(expected[centre]) == 9  # one pixel in from each side and corner, and over it


def test_both_sides_walk_their_sprites_by_the_same_steps_and_keep_the_same_answers():
    group_a, group_b = groups(100)
    field = ArcadeField(group_a, group_b)
    count = len(group_a) + len(group_b)
    arcade_side = arcade_frame(field, Walk(count))
    our_side = our_frame(group_a, group_b, Walk(count))
    before = pygames_answers(group_a, group_b)
    for _ in range(7):  # (an odd count: the sprites end a step away from where they began)
        arcade_side()
        our_side()
    after = pygames_answers(group_a, group_b)
    assert after != before
    assert field.answers() == our_answers(group_a, group_b) == after
    sprites = [*group_a, *group_b]
    assert [(twin.left, twin.bottom, twin.width, twin.height) for twin in field.twins] == [
        (s.rect.x, s.rect.y, s.rect.w, s.rect.h) for s in sprites]
