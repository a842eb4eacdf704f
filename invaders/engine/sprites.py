"""pygame sprite groups in, contacts and counters out: the engine as a drop-in for
`pygame.sprite.groupcollide(..., collide_mask)` that is exact, swept and, from five sprites
a side, faster (section 5 of `invaders bench` times it).

Each call is one tick. A sprite is a body of its group's kind at `rect.topleft`, shaped by
its `mask` where it has one and by its rect where it has not (`GroupCollide`, as pygame's
`collide_mask`, shapes one with no mask by its `image`'s pixels). A sprite that says where it
was last tick (a `last_rect` attribute) is tested along its motion by swept entries; one that
does not is tested where it is. A float rect (`FRect`) stands where pygame draws it, at
`pygame.Rect(frect)` (its corner truncated towards zero, as `blit` does): contacts are
between the pixels on the screen. The collider keeps the bodies and the broad phase between
calls: each sprite is looked at, and the broad phase hears only of those that moved. Kinds
are small non-negative integers you choose.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping
from fractions import Fraction
from typing import Any, NamedTuple

import pygame
from pygame.sprite import AbstractGroup

from invaders.engine.adaptive import DEFAULT_BROADPHASE, make_broadphase
from invaders.engine.body import Body
from invaders.engine.collide import image_mask
from invaders.engine.detector import Detector
from invaders.engine.grid import DEFAULT_CELL
from invaders.engine.predicates import solid_mask
from invaders.engine.response import first_contacts
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.engine.stats import CollisionStats
from invaders.engine.store import BodyStore


class SpriteContact(NamedTuple):
    """Two sprites that touched this tick: `a` of the entry's kind a, `b` of its kind b, the
    time of first touch within the tick (0 to 1), a screen pixel both lit, and the entry."""

    a: Any
    b: Any
    time: Fraction
    point: tuple[int, int]
    rule: PairRule


class _Tracked:
    """A sprite the collider follows: its body, the last call that saw it, and the solid
    mask last made for its box (where it had no mask)."""

    __slots__ = ("body", "seen", "solid", "sprite")

    def __init__(self, sprite: Any, body: Body, seen: int) -> None:
        self.sprite = sprite  # (held: its id names it only while it lives)
        self.body = body
        self.seen = seen
        self.solid: pygame.mask.Mask | None = None  # (the last made for its box, if any)


class SpriteCollider:
    """The rules table and a broad phase over sprite groups, kept between calls.
    `from_images`: a sprite with no `mask` but an `image` is shaped by the image's pixels,
    the mask `collide_mask` makes of it (made once per image: `image_mask` says what that
    asks of you); one with neither is its rect."""

    def __init__(self, rules: RuleTable, broadphase: str = DEFAULT_BROADPHASE,
                 cell: int = DEFAULT_CELL, from_images: bool = False) -> None:
        self.rules = rules
        self.from_images = from_images
        self.detector = Detector(make_broadphase(broadphase, cell), rules)
        self.store = BodyStore(rules.kinds())
        self.stats = CollisionStats()
        # Each kind's sprites by id, and every one by its body's id.
        self._tracked: dict[int, dict[int, _Tracked]] = {kind: {} for kind in self.store.by_kind}
        self._by_body: dict[int, _Tracked] = {}
        self._started = False

    def collide(self, groups: Mapping[int, Iterable[Any]]) -> list[SpriteContact]:
        """This tick's contacts, earliest first (a side an entry spends meets nothing after
        its first contact); `stats` holds the tick's counters."""
        store = self.store
        for kind in groups:  # (before anything moves; the store holds the rules' kinds)
            if kind not in store.by_kind:
                raise ValueError(f"kind {kind!r}: no entry of the rules names it (they name "
                                 f"{', '.join(map(str, sorted(store.by_kind)))})")
        if self._started:
            store.tick += 1
        self._started = True
        tick, seen = store.tick, 0
        for kind, sprites in groups.items():
            tracked = self._tracked[kind]
            for sprite in sprites:
                known = tracked.get(id(sprite))
                if known is None:
                    self._add(sprite, kind, tick)
                elif known.seen != tick:  # (a sprite listed twice is looked at once)
                    known.seen = tick
                    self._sync(known, sprite)
                else:
                    continue
                seen += 1
        if seen != len(self._by_body):  # (each sprite seen is kept: the rest are gone)
            self._drop_unseen(tick)
        contacts, self.stats = self.detector.detect(store)
        if not contacts:
            return []
        out = []
        for contact in first_contacts(contacts):
            rule: PairRule = contact.rule  # type: ignore[assignment]
            first = self._by_body[contact.a_id].sprite
            second = self._by_body[contact.b_id].sprite
            if contact.a_kind != rule.a:
                first, second = second, first
            out.append(SpriteContact(first, second, contact.time, (contact.px, contact.py),
                                     rule))
        return out

    def _add(self, sprite: Any, kind: int, tick: int) -> None:
        """A sprite first seen (or back): a new body where it stands, swept from where it
        says it was."""
        mask, rect, boxed = self._shape(sprite, getattr(sprite, "mask", None), sprite.rect)
        body = Body(self.store.new_id(), kind, rect.x, rect.y, mask)
        self._tracked[kind][id(sprite)] = self._by_body[body.id] = _Tracked(sprite, body, tick)
        last = getattr(sprite, "last_rect", None)
        if last is not None:
            last = _drawn(last, boxed)
        self.store.add(body, None if last is None else (last.x, last.y))

    def _sync(self, known: _Tracked, sprite: Any) -> None:
        """The body made what its sprite now is: its picture, where it ended the frame and
        where it started it (its `last_rect`, or where it stands)."""
        body = known.body
        mask = getattr(sprite, "mask", None)
        rect = sprite.rect
        boxed = False
        if mask is None or type(rect) is not pygame.Rect:  # (a masked Rect is as it is)
            mask, rect, boxed = self._shape(sprite, mask, rect, known)
        x, y = rect.x, rect.y
        last = getattr(sprite, "last_rect", None)
        if last is None:
            sx, sy = x, y
        else:
            if boxed or type(last) is not pygame.Rect:
                last = _drawn(last, boxed)
            sx, sy = last.x, last.y
        if body.mask is not mask:
            self.store.reshape(body, mask)
        # Not moved yet this call (a body moves only here, once a call): it starts the
        # tick where it ended the last, and stays put if its sprite did.
        if body.x != x or body.y != y or sx != x or sy != y:
            self.store.move_from(body, sx, sy, x, y)

    def _shape(self, sprite: Any, mask: pygame.mask.Mask | None, rect: Any,
               known: _Tracked | None = None) -> tuple[pygame.mask.Mask, pygame.Rect, bool]:
        """The sprite's mask, the rect it stands on and whether that rect is its shape: its
        `mask`, else (`from_images`) its image's, else a solid one of its rect's size (kept
        for the sprite while its size stands)."""
        if mask is None and self.from_images:
            image = getattr(sprite, "image", None)
            mask = None if image is None else image_mask(image)
        boxed = mask is None  # (its rect is its shape)
        if boxed or type(rect) is not pygame.Rect:
            rect = _drawn(rect, boxed)
        if mask is None:
            mask = None if known is None else known.solid
            if mask is None or mask.get_size() != rect.size:
                mask = solid_mask(rect.width, rect.height)
                if known is not None:
                    known.solid = mask
        return mask, rect, boxed

    def _drop_unseen(self, tick: int) -> None:
        """The bodies of sprites this call did not list leave the store."""
        for tracked in self._tracked.values():
            for key in [key for key, known in tracked.items() if known.seen != tick]:
                body = tracked.pop(key).body
                del self._by_body[body.id]
                self.store.remove(body)


def _drawn(rect: Any, boxed: bool) -> pygame.Rect:
    """The pixels a sprite's rect stands on: a `Rect` itself, an `FRect` where pygame draws
    it (whole pixels: the engine's positions and sweeps are). `boxed`: the rect is the
    sprite's shape, and one of negative size covers what pygame's `colliderect` takes it
    to (made positive, `normalize`)."""
    drawn = rect if isinstance(rect, pygame.Rect) else pygame.Rect(rect)
    if boxed and (drawn.width < 0 or drawn.height < 0):
        drawn = drawn.copy()
        drawn.normalize()
    return drawn


# Groups read twice as they are, told apart without asking `Collection` (an abstract class,
# whose check is a Python call: at 1 sprite a side, a tenth of a call).
REREAD = (AbstractGroup, list, tuple)


class GroupCollide:
    """`pygame.sprite.groupcollide(a, b, False, False, collide_mask)`, as the engine does it:
    keep one per pair of groups you test every frame, and call it like the original. A
    sprite is shaped as `collide_mask` shapes it, by its `mask` or else its `image`; one
    with neither (which `collide_mask` refuses) by its rect, as `groupcollide` with no
    predicate."""

    def __init__(self, broadphase: str = DEFAULT_BROADPHASE, cell: int = DEFAULT_CELL) -> None:
        rule = PairRule(0, 1, Shape.MASK, Shape.MASK, Motion.SWEPT)
        self.collider = SpriteCollider(RuleTable((rule,)), broadphase, cell, from_images=True)

    def __call__(self, group_a: Iterable[Any], group_b: Iterable[Any]) -> dict[Any, list[Any]]:
        """Each sprite of `group_a` that touched some of `group_b`, with those, as pygame
        gives them: in the groups' order, and a sprite a list holds twice in `group_b`
        listed twice. A group may be any iterable: one that can be read only once (a
        generator) is read once, here as in pygame for the first group; as the second,
        pygame's loop reads it up for the first sprite alone, where here every sprite
        meets all of it."""
        if not isinstance(group_a, REREAD) and not isinstance(group_a, Collection):
            group_a = list(group_a)  # (each group is read twice below)
        if not isinstance(group_b, REREAD) and not isinstance(group_b, Collection):
            group_b = list(group_b)
        touched: dict[int, set[int]] = {}
        for contact in self.collider.collide({0: group_a, 1: group_b}):
            touched.setdefault(id(contact.a), set()).add(id(contact.b))
        if not touched:
            return {}
        met = set().union(*touched.values())
        listed_b = list(group_b)
        places: dict[int, list[int]] = {}  # (of the sprites met alone: few, most calls)
        for place, sprite in enumerate(listed_b):
            key = id(sprite)
            if key in met:
                places.setdefault(key, []).append(place)
        hits: dict[Any, list[Any]] = {}
        for sprite in group_a:
            ids = touched.get(id(sprite))
            if ids is not None and sprite not in hits:
                hits[sprite] = [listed_b[place] for place in
                                sorted(place for b in ids for place in places[b])]
        return hits

    @property
    def stats(self) -> CollisionStats:
        return self.collider.stats

