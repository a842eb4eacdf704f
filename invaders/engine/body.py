"""The record the engine reads: an id, a kind, an integer box, a mask, and where it was."""

from __future__ import annotations

import functools
from typing import Any

import pygame

from invaders.engine.compiled import mypyc_attr
from invaders.engine.pickling import with_fields

FAR = 1 << 60
NOWHERE = (FAR, FAR, -FAR, -FAR)  # a fence no box is inside: every move is reported


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Body:
    """A collidable thing at integer position (x, y), the top-left of its w x h box.

    `kind` is a small integer the engine's user defines (an IntEnum works). `moved_tick`
    says on which tick (px, py) was last saved: a body that has not moved this tick is where
    it was at the tick's start, whatever px, py still hold. `shaped_tick` is the tick it
    appeared, last gained pixels or started away from where it ended the tick before (a
    jump, as `BodyStore.move_from` plays one): a tick's contacts are the touches after its
    first instant (that instant was the previous tick's last), and at that instant too when
    a body in the pair is new in it. `fence` (x0, y0, x1, y1, half-open) is where the broad
    phase lets its box go unheard (Box2D's fat box): the store reports a move that leaves it.
    Change bodies through a `BodyStore`, which keeps these fields and tells the broad phase.
    """

    __slots__ = ("alive", "fence", "h", "id", "kind", "mask", "moved_tick", "px", "py",
                 "shaped_tick", "w", "x", "y")

    def __init__(self, body_id: int, kind: int, x: int, y: int, mask: pygame.mask.Mask) -> None:
        self.id = body_id
        self.kind = kind
        self.x = x
        self.y = y
        self.px = x
        self.py = y
        self.moved_tick = -1
        self.shaped_tick = -1
        self.fence = NOWHERE
        self.mask = mask
        self.w, self.h = mask.get_size()
        self.alive = True

    def start_of_tick(self, tick: int) -> tuple[int, int]:
        """Where this body was when `tick` began."""
        if self.moved_tick == tick:
            return self.px, self.py
        return self.x, self.y

    def __repr__(self) -> str:
        return f"{type(self).__name__}(id={self.id}, x={self.x}, y={self.y})"

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled as its class and its fields by name, whether the class is compiled or
        not. By default each build pickles a body its own way (compiled, its fields as a
        dict; interpreted, its slots as a pair), and neither reads the other's back; a world
        pickled by one build must load in the other (workers on machines that built the
        package differently, states kept on disk across a reinstall)."""
        values = {name: getattr(self, name) for name in fields_of(type(self))}
        values.update(getattr(self, "__dict__", {}))  # (a Python subclass's, if it has one)
        return with_fields, (type(self), values)

    def __deepcopy__(self, memo: dict[int, Any]) -> Body:
        """A copy with this body's picture: pictures are shared between bodies and never
        drawn on, and masks cannot be deep-copied. An owner whose bodies' pictures change
        in place (a shield that erodes) puts copies of them in `memo` first. Every other
        field of a body is a number, a flag or a tuple of numbers (a test holds it), taken
        as it is: Body's written out (a world's copy makes some sixty bodies, and a field
        read and set by name costs several times as much), a subclass's own by name."""
        cls = type(self)
        clone = cls.__new__(cls)
        memo[id(self)] = clone
        clone.id = self.id
        clone.kind = self.kind
        clone.x = self.x
        clone.y = self.y
        clone.px = self.px
        clone.py = self.py
        clone.moved_tick = self.moved_tick
        clone.shaped_tick = self.shaped_tick
        clone.fence = self.fence
        clone.mask = memo.get(id(self.mask), self.mask)
        clone.w = self.w
        clone.h = self.h
        clone.alive = self.alive
        for name in _own_fields(cls):  # type: ignore[arg-type]  # (a class is hashable)
            setattr(clone, name, getattr(self, name))
        return clone


def copy_bodies(bodies: list[Body], memo: dict[int, Any]) -> list[Body]:
    """`copy.deepcopy(bodies, memo)` for a list of bodies, without its generic steps for
    each: the list and each body copied once through `memo`, as deepcopy does, so that
    whatever shares them shares the copies."""
    clone = memo.get(id(bodies))
    if clone is None:
        clone = memo[id(bodies)] = [copied(body, memo) for body in bodies]
    return clone


def copied(body: Body, memo: dict[int, Any]) -> Body:
    """`copy.deepcopy(body, memo)`: the body's copy, made once through `memo`."""
    clone = memo.get(id(body))
    return clone if clone is not None else body.__deepcopy__(memo)


@functools.cache
def _own_fields(cls: type) -> tuple[str, ...]:
    """The fields a subclass of Body adds to Body's (none for most of the game's)."""
    body = fields_of(Body)
    return tuple(name for name in fields_of(cls) if name not in body)


def fields_of(cls: type) -> tuple[str, ...]:
    """Every field of a body of this class, Body's and its subclasses' own: each class's
    slots, or compiled (where a class has none) the fields mypyc lists for it (a Python
    subclass of a compiled class has its own slots beside them)."""
    names: dict[str, None] = {}
    for klass in cls.__mro__:
        own = vars(klass)
        names.update(dict.fromkeys(own.get("__mypyc_attrs__", own.get("__slots__", ()))))
    return tuple(names)


def tick_box(body: Body, tick: int, swept: bool = True) -> tuple[int, int, int, int]:
    """x0, y0, x1, y1 (half-open) of the body's box, over its whole motion this tick if
    `swept`: the one rule every broad phase bins by (numpy's `_tick_boxes` is the same on
    arrays, and a test holds the two equal)."""
    x0, y0 = body.x, body.y
    x1, y1 = x0 + body.w, y0 + body.h
    if swept and body.moved_tick == tick:  # (comparisons, not min and max: a hot path)
        px, py = body.px, body.py
        if px < x0:
            x0 = px
        elif px > x0:
            x1 = px + body.w
        if py < y0:
            y0 = py
        elif py > y0:
            y1 = py + body.h
    return x0, y0, x1, y1
