"""Recorded frames: the bodies a detector saw on each tick, to play back to any method.

A frame keeps each body's id, position, start-of-tick position and mask (shield masks are
copied, since they erode). `FrameScene` plays frames back through a body store, tick after
tick, making the changes a world would have made (so a broad phase hears of the same ones).
`sampled` keeps every k-th frame with the motion of the k frames between folded into one
step, as a detector that runs less often would see it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import pygame

from invaders.engine.body import Body
from invaders.engine.stats import Contact
from invaders.engine.store import BodyStore
from invaders.game.kinds import Kind

BodyRow = tuple[int, int, int, int, int, int, pygame.mask.Mask]  # id, x, y, px, py, moved, mask


@dataclass
class Frame:
    """One tick's collidable bodies as the detector saw them, and what it found."""

    tick: int
    bodies: dict[int, list[BodyRow]]  # by kind
    contacts: list[Contact]


def snapshot(scene, contacts: Sequence[Contact] = ()) -> Frame:
    """The scene's bodies now (shield masks copied)."""
    bodies: dict[int, list[BodyRow]] = {
        kind: [(b.id, b.x, b.y, b.px, b.py, b.moved_tick,
                b.mask.copy() if kind is Kind.BUNKER else b.mask)
               for b in scene.by_kind[kind]] for kind in Kind}
    return Frame(scene.tick, bodies, list(contacts))


class FrameScene:
    """Frames played back as one scene: `store` is what a detector reads."""

    def __init__(self) -> None:
        self.store = BodyStore(Kind)

    def load(self, frame: Frame) -> None:
        store = self.store
        store.tick = frame.tick
        seen = set()
        by_id = store.by_id
        for kind, rows in frame.bodies.items():
            for body_id, x, y, px, py, moved, mask in rows:
                seen.add(body_id)
                body = by_id.get(body_id)
                if body is None:
                    store.add(Body(body_id, kind, x, y, mask),
                              (px, py) if moved == frame.tick else None)
                    continue
                if body.mask is not mask:
                    store.reshape(body, mask)
                start = (px, py) if moved == frame.tick else (x, y)
                if (body.x, body.y) != (x, y) or body.start_of_tick(frame.tick) != start:
                    store.move_from(body, *start, x, y)
        for body_id in [i for i in by_id if i not in seen]:
            store.remove(by_id[body_id])


Places = dict[int, tuple[int, int]]  # body id -> where it was


def folded(frame: Frame, previous: Places, tick: int) -> tuple[Frame, Places]:
    """The frame as tick `tick` of a detector that looked last when the bodies were at
    `previous`: each moves in one step from there (or from where it appeared, if later).
    Also where they are now, for the next look."""
    bodies = {}
    seen: Places = {}
    for kind, rows in frame.bodies.items():
        new_rows = []
        for body_id, x, y, px, py, moved, mask in rows:
            start = previous.get(body_id)
            if start is None:  # appeared since the last look: from its own start
                start = (px, py) if moved == frame.tick else (x, y)
            new_rows.append((body_id, x, y, *start, tick if start != (x, y) else -1, mask))
            seen[body_id] = (x, y)
        bodies[kind] = new_rows
    return Frame(tick, bodies, []), seen


def sampled(frames: Sequence[Frame], k: int) -> list[Frame]:
    """Every k-th frame, renumbered, each body moving in one step from where it was k frames
    before (or from where it appeared, if that was later)."""
    if k == 1:
        return list(frames)
    out = []
    previous: Places = {}
    for n, frame in enumerate(frames[k - 1::k]):
        look, previous = folded(frame, previous, n)
        out.append(look)
    return out


def play_frames(detector, frames: Sequence[Frame],
                untimed: int = 0) -> tuple[float, list[list[Contact]], list[int]]:
    """Play frames through a detector in a tight loop: seconds spent detecting (garbage
    collector paused), each frame's contacts, and the counters summed. The first `untimed`
    frames are played first, outside all of that (a broad phase builds its state there)."""
    import time

    from invaders.lab.timing import no_gc

    scene = FrameScene()
    for frame in frames[:untimed]:
        scene.load(frame)
        detector.detect(scene.store)
    seconds = 0.0
    found = []
    totals = [0] * 10
    with no_gc():
        for frame in frames[untimed:]:
            scene.load(frame)
            start = time.perf_counter()
            contacts, stats = detector.detect(scene.store)
            seconds += time.perf_counter() - start
            found.append(contacts)
            totals = [t + s for t, s in zip(totals, stats, strict=True)]
    return seconds, found, totals
