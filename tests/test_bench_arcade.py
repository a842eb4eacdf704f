"""bench --arcade's reference: Arcade's boxes meet where pygame's rects do, on the same
places, still and moving, so the two sides time the same work."""

from __future__ import annotations

from pathlib import Path

import pygame
import pytest

from invaders.lab.bench_arcade import ArcadeField, Walk, arcade_frame, our_answers, our_frame
from invaders.lab.bench_sprites import groups
from invaders.lab.references import ArcadeScene
from invaders.lab.runner import SceneSpec, record, scene_rules

REPLAYS = Path(__file__).resolve().parents[1] / "replays"


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


@pytest.mark.parametrize("spec", [SceneSpec.storm(300, 12),
                                  SceneSpec("game", 900, replay=str(REPLAYS / "second-wave.json"))],
                         ids=["storm", "game"])
def test_arcades_scene_finds_every_probes_box_overlaps_frame_after_frame(spec):
    frames = record(spec)
    scene = ArcadeScene(frames, scene_rules(spec))
    checked = 0
    for index in range(1, len(frames)):
        scene.frame_seconds(index)  # (applies the frame's adds, moves and removes)
        rects = {kind: {row[0]: pygame.Rect(row[1], row[2], *row[6].get_size()) for row in rows}
                 for kind, rows in frames[index].bodies.items()}
        expected = set()
        for body_id, (x, y, w, h), kind in scene.steps[index].probes:
            probe = pygame.Rect(x, y, w, h)
            expected |= {(min(body_id, other), max(body_id, other))
                         for other, rect in rects[kind].items()
                         if other != body_id and probe.colliderect(rect)}
        assert scene.found(index) == expected
        checked += len(expected)
    assert checked > 10  # (boxes do meet: the check is not of empty sets)
    if spec.replay is not None:  # (bodies come and go in a game: shots, bombs, aliens)
        assert sum(len(changes.removes) for changes in scene.steps) > 10
