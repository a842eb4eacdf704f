"""The body store: every change to a body goes through it, so the broad phase hears of it.

It keeps the live bodies of each kind in id order (the order contacts depend on) and by id,
and hands every body added, removed, resized or moved out of its fence to the move buffer of
the broad phase attached to it (the broad phase owns the buffer and clears it when it
answers, and sets the fences, as Box2D's `b2BufferMove` and fat boxes). Nothing downstream
guesses what changed.
"""

from __future__ import annotations

import copy
from bisect import bisect_left, insort
from collections.abc import Iterable
from itertools import count
from operator import attrgetter
from typing import Any, Protocol

import pygame

from invaders.engine.body import NOWHERE, Body, copy_bodies
from invaders.engine.compiled import mypyc_attr

_ID = attrgetter("id")
# Membership values, never the same twice in a process: a detector that saw one knows the
# store, its bodies and the broad phase it feeds are as it left them.
_memberships = count(1)


class Listener(Protocol):
    """A broad phase as the store sees it: a buffer to fill (None: it keeps no state)."""

    move_buffer: list[Body] | None


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class BodyStore:
    """Live bodies by kind and by id, the current tick, and the id counter."""

    def __init__(self, kinds: Iterable[int]) -> None:
        self.tick = 0
        self.by_kind: dict[int, list[Body]] = {kind: [] for kind in kinds}
        self.by_id: dict[int, Body] = {}
        self.next_id = 1
        self.listener: Listener | None = None
        self._buffer: list[Body] | None = None
        self.size = 0  # live bodies, and a bit (1 << kind) for each kind that has some:
        self.present = 0  # kept as they change, so a detector need not count every tick
        # A new value whenever a body is added or removed or a broad phase attached or
        # detached (never one another store had).
        self.membership = next(_memberships)

    def __deepcopy__(self, memo: dict[int, Any]) -> BodyStore:
        """A copy with bodies of its own (each copied once, through `memo`); its by-id table
        made from its lists of each kind, which hold the same bodies, rather than copied
        entry by entry."""
        clone = copy.copy(self)  # (its numbers; the rest made anew below)
        memo[id(self)] = clone
        clone.by_kind = {kind: copy_bodies(bodies, memo) for kind, bodies in self.by_kind.items()}
        clone.by_id = {body.id: body for bodies in clone.by_kind.values() for body in bodies}
        clone.listener = copy.deepcopy(self.listener, memo)
        clone._buffer = copy.deepcopy(self._buffer, memo)
        return clone

    def attach(self, listener: Listener) -> None:
        """Send every later change to this broad phase (which rebuilds from the store). A
        store feeds one broad phase that keeps state; attaching another replaces it."""
        self.listener = listener
        self._buffer = listener.move_buffer
        self.membership = next(_memberships)

    def detach(self) -> None:
        """Stop feeding the broad phase attached (its detector was put away): nothing is
        kept for it any more, and the next one to detect attaches itself afresh."""
        self.listener = None
        self._buffer = None
        self.membership = next(_memberships)

    def new_id(self) -> int:
        body_id = self.next_id
        self.next_id += 1
        return body_id

    def add(self, body: Body, start: tuple[int, int] | None = None) -> None:
        """A body appears (or comes back) this tick; with `start`, it moved there from that
        point during the tick (a sprite first seen with its last place, a frame played
        back)."""
        if start is not None and start != (body.x, body.y):
            body.px, body.py = start
            body.moved_tick = self.tick
        body.alive = True
        body.shaped_tick = self.tick
        body.fence = NOWHERE  # until the broad phase gives it one
        bodies = self.by_kind[body.kind]
        self.size += 1
        self.membership = next(_memberships)
        self.present |= 1 << body.kind
        if not bodies or bodies[-1].id < body.id:
            bodies.append(body)
        else:
            insort(bodies, body, key=_ID)
        self.by_id[body.id] = body
        if self._buffer is not None:
            self._buffer.append(body)

    def place(self, body: Body, x: int, y: int) -> None:
        """Put a body that is not in the store at (x, y), where it stays until added (one
        in the store moves with `move`, so that the broad phase hears of it)."""
        if body.alive and self.by_id.get(body.id) is body:
            raise ValueError(f"body {body.id} is in the store: move it instead")
        body.x = body.px = x
        body.y = body.py = y

    def move(self, body: Body, x: int, y: int) -> None:
        """Move a body; the first move of a tick remembers where it started. The broad
        phase hears of it if the box leaves its fence (the start was inside: it was the
        end of a move seen before, or where the broad phase last put the fence)."""
        if body.moved_tick != self.tick:
            body.px = body.x
            body.py = body.y
            body.moved_tick = self.tick
        body.x = x
        body.y = y
        buffer = self._buffer
        if buffer is not None:
            fence = body.fence
            if not (fence[0] <= x and fence[1] <= y and x + body.w <= fence[2]
                    and y + body.h <= fence[3]):
                buffer.append(body)

    def move_from(self, body: Body, px: int, py: int, x: int, y: int) -> None:
        """This tick the body went from (px, py) to (x, y) (for scenes played back, and
        sprites that say where they were): the broad phase hears of it unless both ends are
        inside the fence. A start away from where the body ended the tick before (a jump)
        is an instant no tick has tested: the body is new in it (`shaped_tick`)."""
        tick = self.tick
        moved = body.moved_tick == tick  # (start_of_tick, read in place)
        if px != (body.px if moved else body.x) or py != (body.py if moved else body.y):
            body.shaped_tick = tick
        if px == x and py == y:
            body.moved_tick = -1
        else:
            body.px, body.py, body.moved_tick = px, py, tick
        body.x = x
        body.y = y
        buffer = self._buffer
        if buffer is not None:
            x0, y0, x1, y1 = body.fence
            w, h = body.w, body.h
            if not (x0 <= px and x0 <= x and px + w <= x1 and x + w <= x1
                    and y0 <= py and y0 <= y and py + h <= y1 and y + h <= y1):
                buffer.append(body)

    def reshape(self, body: Body, mask: pygame.mask.Mask) -> None:
        """A new picture. The tick's first instant is new for the body only if the picture
        gains a pixel: one that only loses pixels cannot touch anything at that instant that
        the old one did not touch at the previous tick's end."""
        old = body.mask
        if mask is old:
            return
        size = mask.get_size()
        gained = _gains.get((old, mask))  # gains_pixels' own cache, read first: every tick
        if gained or (gained is None and gains_pixels(old, mask)):
            body.shaped_tick = self.tick
        body.mask = mask
        if size != (body.w, body.h):
            body.w, body.h = size
            if self._buffer is not None:
                self._buffer.append(body)

    def remove(self, body: Body) -> None:
        if not body.alive:
            return
        body.alive = False
        bodies = self.by_kind[body.kind]
        del bodies[bisect_left(bodies, body.id, key=_ID)]
        self.size -= 1
        self.membership = next(_memberships)
        if not bodies:
            self.present &= ~(1 << body.kind)
        del self.by_id[body.id]
        if self._buffer is not None:
            self._buffer.append(body)


_gains: dict[tuple[pygame.mask.Mask, pygame.mask.Mask], bool] = {}
# Pairs kept only of masks up to this many pixels each: a larger pair's answer costs about
# what reading its masks does, and 4,096 pairs of them kept held their memory (a box
# changing size every frame: a new pair each frame).
GAINS_KEPT_PIXELS = 1 << 16


def gains_pixels(old: pygame.mask.Mask, new: pygame.mask.Mask) -> bool:
    """Whether `new`, placed where `old` was, lights a pixel `old` does not. Cached per
    pair of mask objects (pictures are shared): keyed on the masks themselves, which hash
    by identity, so the key holds them and an id is never reused."""
    gained = _gains.get((old, new))
    if gained is None:
        gained = new.overlap_area(old, (0, 0)) < new.count()
        (ow, oh), (nw, nh) = old.get_size(), new.get_size()
        if ow * oh <= GAINS_KEPT_PIXELS and nw * nh <= GAINS_KEPT_PIXELS:
            if len(_gains) > 4096:
                _gains.clear()
            _gains[(old, new)] = gained
    return gained
