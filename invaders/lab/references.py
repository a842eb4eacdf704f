"""Outside references, timed on the same frames as our pipeline.

`pygame.sprite.groupcollide` with `collide_mask` over the rules' group pairs (mask-exact,
as ours), and pymunk's spatial hash answering box queries only (a lower bar: no pixels).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import pygame

from invaders.engine.predicates import solid_mask
from invaders.engine.rules import Shape
from invaders.game.config import DEFAULT_CONFIG
from invaders.game.rules import make_rules
from invaders.lab.frames import Frame
from invaders.lab.timing import no_gc

GAME_RULES = make_rules(DEFAULT_CONFIG)


class _Sprite(pygame.sprite.Sprite):
    def __init__(self, body_id: int, x: int, y: int, mask: pygame.mask.Mask) -> None:
        super().__init__()
        self.body_id = body_id
        self.mask = mask
        self.rect = pygame.Rect((x, y), mask.get_size())


def sprite_groups(frame: Frame) -> list[tuple[pygame.sprite.Group, pygame.sprite.Group]]:
    """The rules' group pairs as pygame groups, each side with the shape the rule tests."""
    pairs = []
    for rule in GAME_RULES:
        sides = []
        for kind, shape in ((rule.a, rule.a_shape), (rule.b, rule.b_shape)):
            group = pygame.sprite.Group()
            for body_id, x, y, _px, _py, _moved, mask in frame.bodies[kind]:
                shape_mask = mask if shape is Shape.MASK else solid_mask(*mask.get_size())
                group.add(_Sprite(body_id, x, y, shape_mask))
            sides.append(group)
        pairs.append((sides[0], sides[1]))
    return pairs


Prepared = list[list[tuple[pygame.sprite.Group, pygame.sprite.Group]]]


def prepare(frames: list[Frame]) -> Prepared:
    """Every frame's rule group pairs as sprite groups, built once, outside any timer."""
    return [sprite_groups(frame) for frame in frames]


def _pairs_of(results: list) -> set[tuple[int, int]]:
    pairs = set()
    for result in results:
        for sprite, others in result.items():
            for other in others:
                pairs.add((min(sprite.body_id, other.body_id),
                           max(sprite.body_id, other.body_id)))
    return pairs


GroupPairs = list[tuple[pygame.sprite.Group, pygame.sprite.Group]]


def _timed(prepared: Prepared,
           collide: Callable[[GroupPairs], list]) -> tuple[float, list[set[tuple[int, int]]]]:
    """Seconds `collide` spends over every frame's group pairs, and the pairs it found."""
    results = []
    seconds = 0.0
    with no_gc():
        for groups in prepared:
            start = time.perf_counter()
            results.append(collide(groups))
            seconds += time.perf_counter() - start
    return seconds, [_pairs_of(hits) for hits in results]


def groupcollide_frames(prepared: Prepared) -> tuple[float, list[set[tuple[int, int]]]]:
    """The naive pygame user: `groupcollide(a, b, False, False, collide_mask)` over every
    rule's pair of groups. Seconds over all frames, and the id pairs found per frame."""
    mask = pygame.sprite.collide_mask
    return _timed(prepared, lambda groups: [
        pygame.sprite.groupcollide(a, b, False, False, mask) for a, b in groups])


def rect_then_mask_frames(prepared: Prepared) -> tuple[float, list[set[tuple[int, int]]]]:
    """The careful pygame user: `groupcollide` on rects, then `collide_mask` only on the
    pairs whose rects overlap. Seconds over all frames, and the id pairs found per frame."""
    mask = pygame.sprite.collide_mask

    def careful(groups: GroupPairs) -> list:
        hits = []
        for a, b in groups:
            found = {}
            for sprite, others in pygame.sprite.groupcollide(a, b, False, False).items():
                masked = [other for other in others if mask(sprite, other)]
                if masked:
                    found[sprite] = masked
            hits.append(found)
        return hits

    return _timed(prepared, careful)


def groupcollide_us(frames: list[Frame], budget: float = 5.0) -> float:
    """Microseconds per frame for groupcollide + collide_mask (as many frames as the budget
    allows, at least one)."""
    seconds, count = 0.0, 0
    with no_gc():
        for frame in frames:
            groups = sprite_groups(frame)
            start = time.perf_counter()
            for a, b in groups:
                pygame.sprite.groupcollide(a, b, False, False, pygame.sprite.collide_mask)
            seconds += time.perf_counter() - start
            count += 1
            if seconds > budget:
                break
    return 1e6 * seconds / count


def pymunk_us(frames: list[Frame]) -> float | None:
    """Microseconds per frame for pymunk's spatial hash: move the shapes that moved, then
    one box query per probing body and rule. None if pymunk is not installed."""
    try:
        import pymunk
    except ImportError:
        return None
    space = pymunk.Space()
    bodies = max(sum(len(v) for v in f.bodies.values()) for f in frames)
    space.use_spatial_hash(32.0, max(1000, 2 * bodies))
    shapes: dict[int, tuple[pymunk.Body, pymunk.Shape, tuple[int, int]]] = {}
    seconds = 0.0
    with no_gc():
        for frame in frames:
            start = time.perf_counter()
            seen = set()
            for kind, rows in frame.bodies.items():
                for body_id, x, y, _px, _py, _moved, mask in rows:
                    seen.add(body_id)
                    entry = shapes.get(body_id)
                    if entry is None:
                        w, h = mask.get_size()
                        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
                        shape = pymunk.Poly.create_box(body, (w, h))
                        shape.filter = pymunk.ShapeFilter(categories=1 << kind)
                        body.position = (x + w / 2, y + h / 2)
                        space.add(body, shape)
                        shapes[body_id] = (body, shape, (x, y))
                    elif entry[2] != (x, y):
                        w, h = mask.get_size()
                        entry[0].position = (x + w / 2, y + h / 2)
                        space.reindex_shapes_for_body(entry[0])
                        shapes[body_id] = (entry[0], entry[1], (x, y))
            for body_id in [i for i in shapes if i not in seen]:
                body, shape, _ = shapes.pop(body_id)
                space.remove(body, shape)
            for rule in GAME_RULES:
                wanted = pymunk.ShapeFilter(mask=1 << rule.b)
                for _id, x, y, _px, _py, _moved, mask in frame.bodies[rule.a]:
                    w, h = mask.get_size()
                    space.bb_query(pymunk.BB(x, y, x + w, y + h), wanted)
            seconds += time.perf_counter() - start
    return 1e6 * seconds / len(frames)


