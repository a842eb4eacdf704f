"""Outside references, timed on the same frames as our pipeline.

`pygame.sprite.groupcollide` with `collide_mask` over the rules' group pairs (mask-exact,
as ours), and pymunk's and Arcade's spatial hashes answering box queries only (a lower bar:
no pixels).
"""

from __future__ import annotations

import importlib
import time
from collections.abc import Callable
from typing import Any, NamedTuple, cast

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
            group: pygame.sprite.Group = pygame.sprite.Group()
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


def pairs_of(results: list) -> set[tuple[int, int]]:
    """The id pairs (low first) in one frame's groupcollide results."""
    pairs = set()
    for result in results:
        for sprite, others in result.items():
            for other in others:
                pairs.add((min(sprite.body_id, other.body_id),
                           max(sprite.body_id, other.body_id)))
    return pairs


# collide_mask as groupcollide's predicate: pygame's stubs want one that gives a bool,
# where collide_mask gives the first point the masks share or None (as pygame's docs say).
COLLIDE_MASK = cast(Callable[[Any, Any], bool], pygame.sprite.collide_mask)
GroupPairs = list[tuple[pygame.sprite.Group, pygame.sprite.Group]]


def naive_collide(groups: GroupPairs) -> list:
    """The naive pygame user: `groupcollide(a, b, False, False, collide_mask)` over every
    rule's pair of groups of one frame."""
    return [pygame.sprite.groupcollide(a, b, False, False, COLLIDE_MASK) for a, b in groups]


def careful_collide(groups: GroupPairs) -> list:
    """The careful pygame user: `groupcollide` on rects, then `collide_mask` only on the
    pairs whose rects overlap."""
    mask = pygame.sprite.collide_mask
    hits = []
    for a, b in groups:
        found = {}
        for sprite, others in pygame.sprite.groupcollide(a, b, False, False).items():
            masked = [other for other in others if mask(sprite, other)]
            if masked:
                found[sprite] = masked
        hits.append(found)
    return hits


def groupcollide_us(frames: list[Frame], budget: float = 5.0) -> float:
    """Microseconds per frame for groupcollide + collide_mask (as many frames as the budget
    allows, at least one)."""
    seconds, count = 0.0, 0
    with no_gc():
        for frame in frames:
            groups = sprite_groups(frame)
            start = time.perf_counter()
            for a, b in groups:
                pygame.sprite.groupcollide(a, b, False, False, COLLIDE_MASK)
            seconds += time.perf_counter() - start
            count += 1
            if seconds > budget:
                break
    return 1e6 * seconds / count




Box = tuple[int, int, int, int]  # x, y, w, h


class Changes(NamedTuple):
    """What a frame asks of a reference that keeps its bodies between frames: the bodies
    added (id, kind, box), moved (id, box) and removed (ids), and the probes (id, box, the
    kind it is asked against): each body on the probing side of a rule, only where the
    other side has bodies and only for bodies in the rule's zone."""

    adds: list[tuple[int, int, Box]]
    moves: list[tuple[int, Box]]
    removes: list[int]
    probes: list[tuple[int, Box, int]]


def frame_changes(frames: list[Frame], rules=GAME_RULES) -> list[Changes]:
    """Each frame's changes from the one before (the first's: every body added), worked
    out beforehand, as our store hands ours its move buffer."""
    from invaders.engine.detector import ZoneIndex
    from invaders.lab.frames import FrameScene

    scene = FrameScene()
    zones = {id(r): ZoneIndex(r.zone) for r in rules if r.zone is not None}
    previous: dict[int, tuple[int, int]] = {}
    found = []
    for frame in frames:
        scene.load(frame)
        now = {}
        changes = Changes([], [], [], [])
        for kind, rows in frame.bodies.items():
            for body_id, x, y, _px, _py, _moved, mask in rows:
                box = (x, y, *mask.get_size())
                now[body_id] = (x, y)
                if body_id not in previous:
                    changes.adds.append((body_id, kind, box))
                elif previous[body_id] != (x, y):
                    changes.moves.append((body_id, box))
        changes.removes.extend(i for i in previous if i not in now)
        for rule in rules:
            if not frame.bodies[rule.b]:
                continue
            zone = zones.get(id(rule))
            changes.probes.extend((body.id, (body.x, body.y, body.w, body.h), rule.b)
                                  for body in scene.store.by_kind[rule.a]
                                  if zone is None or zone.holds(body, frame.tick))
        found.append(changes)
        previous = now
    return found


class KeptScene:
    """A reference that keeps its bodies from frame to frame, its frames' changes in
    `steps` and each frame timed by `frame_seconds` (frames in order)."""

    steps: list

    def frame_seconds(self, index: int) -> float:
        raise NotImplementedError

    def seconds(self) -> float:
        """Time the frames after the first, once (a fresh scene for every round)."""
        with no_gc():
            return sum(self.frame_seconds(index) for index in range(1, len(self.steps)))


class PymunkScene(KeptScene):
    """pymunk's spatial hash given the same work as ours, and no more: every body of the
    first frame is created before timing; each later frame's changes (`frame_changes`) are
    applied, then one box query per probe. Boxes only: no pixel tests, a lower bar than
    ours."""

    def __init__(self, frames: list[Frame], rules=GAME_RULES) -> None:
        import pymunk

        self.pymunk = pymunk
        bodies = max(sum(len(v) for v in f.bodies.values()) for f in frames)
        self.space = pymunk.Space()
        self.space.use_spatial_hash(32.0, max(1000, 2 * bodies))
        self.shapes: dict[int, tuple] = {}
        self.steps = []  # per frame: (moves, adds, removes, queries)
        for changes in frame_changes(frames, rules):
            moves = [(body_id, x + w / 2, y + h / 2) for body_id, (x, y, w, h) in changes.moves]
            adds = [(body_id, kind, *box) for body_id, kind, box in changes.adds]
            queries = [(pymunk.BB(x, y, x + w, y + h), pymunk.ShapeFilter(mask=1 << kind))
                       for _, (x, y, w, h), kind in changes.probes]
            self.steps.append((moves, adds, changes.removes, queries))
        self._apply(self.steps[0])  # the first frame's bodies: made before any timing

    def _apply(self, step) -> None:
        pymunk, space, shapes = self.pymunk, self.space, self.shapes
        moves, adds, removes, _ = step
        for body_id, kind, x, y, w, h in adds:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            shape = pymunk.Poly.create_box(body, (w, h))
            shape.filter = pymunk.ShapeFilter(categories=1 << kind)
            body.position = (x + w / 2, y + h / 2)
            space.add(body, shape)
            shapes[body_id] = (body, shape)
        for body_id in removes:
            space.remove(*shapes.pop(body_id))
        reindex = space.reindex_shapes_for_body
        for body_id, cx, cy in moves:
            body = shapes[body_id][0]
            body.position = (cx, cy)
            reindex(body)

    def frame_seconds(self, index: int) -> float:
        """Time frame `index`: its changes applied, its queries asked (frames in order)."""
        step = self.steps[index]
        query = self.space.bb_query
        start = time.perf_counter()
        self._apply(step)
        for bb, wanted in step[3]:
            query(bb, wanted)
        return time.perf_counter() - start


ARCADE_CELL = 32  # px, Arcade's spatial hashes' cells, as our grid's (its default: 128)


def arcade_box(arcade: Any, x: int, y: int, w: int, h: int) -> Any:
    """An Arcade sprite that is a solid box over (x, y, w, h) (Arcade places a sprite by
    its centre; a solid box's hit box is its box)."""
    return arcade.SpriteSolidColor(w, h, x + w / 2, y + h / 2)


class ArcadeScene(KeptScene):
    """Arcade's spatial hashes given the same work as ours, as pymunk's are: a sprite list
    a kind, each with a spatial hash; every body of the first frame made before timing;
    each later frame's changes (`frame_changes`) applied, then one
    `check_for_collision_with_list` per probe, against the list of the kind it is asked
    against. Solid boxes (their hit boxes are their boxes): no pixel tests, a lower bar
    than ours."""

    def __init__(self, frames: list[Frame], rules=GAME_RULES) -> None:
        import arcade

        self.arcade = arcade
        kinds = {kind for frame in frames for kind in frame.bodies}
        self.lists: dict[int, Any] = {kind: arcade.SpriteList(
            use_spatial_hash=True, lazy=True, spatial_hash_cell_size=ARCADE_CELL) for kind in kinds}
        self.sprites: dict[int, Any] = {}
        self.steps = frame_changes(frames, rules)
        self._apply(self.steps[0])  # the first frame's bodies: made before any timing

    def _apply(self, changes: Changes) -> None:
        sprites, lists, arcade = self.sprites, self.lists, self.arcade
        for body_id, kind, (x, y, w, h) in changes.adds:
            sprite = sprites[body_id] = arcade_box(arcade, x, y, w, h)
            lists[kind].append(sprite)
        for body_id in changes.removes:
            sprites.pop(body_id).remove_from_sprite_lists()
        for body_id, (x, y, w, h) in changes.moves:
            sprites[body_id].position = (x + w / 2, y + h / 2)

    def frame_seconds(self, index: int) -> float:
        """Time frame `index`: its changes applied, its probes checked (frames in order)."""
        changes = self.steps[index]
        check, sprites, lists = (self.arcade.check_for_collision_with_list, self.sprites,
                                 self.lists)
        start = time.perf_counter()
        self._apply(changes)
        for body_id, _, kind in changes.probes:
            check(sprites[body_id], lists[kind])
        return time.perf_counter() - start

    def found(self, index: int) -> set[tuple[int, int]]:
        """The id pairs (low first) whose boxes frame `index`'s probes meet (once the
        frame is applied: for tests)."""
        ids = {id(sprite): body_id for body_id, sprite in self.sprites.items()}
        check = self.arcade.check_for_collision_with_list
        pairs = set()
        for body_id, _, kind in self.steps[index].probes:
            for other in check(self.sprites[body_id], self.lists[kind]):
                pairs.add((min(body_id, ids[id(other)]), max(body_id, ids[id(other)])))
        return pairs


def pymunk_steady_us(frames: list[Frame], rules=GAME_RULES) -> float | None:
    """Microseconds per frame for pymunk given the same work as ours (after the first
    frame); None if pymunk is not installed."""
    return _steady_us("pymunk", PymunkScene, frames, rules)


def arcade_steady_us(frames: list[Frame], rules=GAME_RULES) -> float | None:
    """Microseconds per frame for Arcade given the same work as pymunk (after the first
    frame); None if Arcade is not installed."""
    return _steady_us("arcade", ArcadeScene, frames, rules)


def _steady_us(module: str, scene: Callable[[list[Frame], Any], KeptScene],
               frames: list[Frame], rules) -> float | None:
    """The median of three plays of the frames after the first (as ours), microseconds a
    frame; None if the reference's module is not installed."""
    try:
        importlib.import_module(module)
    except ImportError:
        return None
    rounds = [scene(frames, rules).seconds() for _ in range(3)]
    return 1e6 * sorted(rounds)[1] / max(1, len(frames) - 1)
