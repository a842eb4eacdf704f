"""Recorded frames: the bodies a detector saw on each tick, to play back to any method.

A frame keeps each body's id, position, start-of-tick position and mask (shield masks are
copied, since they erode). `FrameScene` plays frames back as one scene, tick after tick, with
the dirty list a world would have given. `sampled` keeps every k-th frame with the motion of
the k frames between folded into one step, as a detector that runs less often would see it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import pygame

from invaders.engine.body import Body, Kind
from invaders.engine.stats import Contact

BodyRow = tuple[int, int, int, int, int, int, pygame.mask.Mask]  # id, x, y, px, py, moved, mask


@dataclass
class Frame:
    """One tick's collidable bodies as the detector saw them, and what it found."""

    tick: int
    bodies: dict[Kind, list[BodyRow]]
    contacts: list[Contact]


def snapshot(scene, contacts: Sequence[Contact] = ()) -> Frame:
    """The scene's bodies now (shield masks copied)."""
    bodies = {kind: [(b.id, b.x, b.y, b.px, b.py, b.moved_tick,
                      b.mask.copy() if kind is Kind.BUNKER else b.mask)
                     for b in scene.by_kind[kind]] for kind in Kind}
    return Frame(scene.tick, bodies, list(contacts))


class FrameScene:
    """Frames played back as one scene (the Scene protocol of the pipeline)."""

    def __init__(self) -> None:
        self.tick = -1
        self.dirty: list[Body] = []
        self.by_kind: dict[Kind, list[Body]] = {kind: [] for kind in Kind}
        self._bodies: dict[int, Body] = {}

    def load(self, frame: Frame) -> None:
        self.tick = frame.tick
        dirty = []
        seen = set()
        for kind, rows in frame.bodies.items():
            listed = []
            for body_id, x, y, px, py, moved, mask in rows:
                seen.add(body_id)
                body = self._bodies.get(body_id)
                if body is None:
                    body = self._bodies[body_id] = Body(body_id, kind, x, y, mask)
                    body.shaped_tick = frame.tick
                    dirty.append(body)
                elif (body.x, body.y, body.moved_tick) != (x, y, moved):
                    dirty.append(body)  # as the world reports moves (a new mask comes with one)
                if body.mask is not mask and kind is not Kind.BUNKER:
                    body.shaped_tick = frame.tick  # a new picture (shields only erode)
                body.x, body.y, body.px, body.py, body.moved_tick = x, y, px, py, moved
                body.mask = mask
                listed.append(body)
            self.by_kind[kind] = listed
        for body_id in [i for i in self._bodies if i not in seen]:
            body = self._bodies.pop(body_id)
            body.alive = False
            dirty.append(body)
        self.dirty = dirty


def sampled(frames: Sequence[Frame], k: int) -> list[Frame]:
    """Every k-th frame, renumbered, each body moving in one step from where it was k frames
    before (or from where it appeared, if that was later)."""
    if k == 1:
        return list(frames)
    out = []
    previous: dict[int, tuple[int, int]] = {}
    for n, frame in enumerate(frames[k - 1::k]):
        bodies = {}
        seen: dict[int, tuple[int, int]] = {}
        for kind, rows in frame.bodies.items():
            new_rows = []
            for body_id, x, y, px, py, moved, mask in rows:
                start = previous.get(body_id)
                if start is None:  # appeared since the last sample: from its own start
                    start = (px, py) if moved == frame.tick else (x, y)
                moved_now = n if start != (x, y) else -1
                new_rows.append((body_id, x, y, start[0], start[1], moved_now, mask))
                seen[body_id] = (x, y)
            bodies[kind] = new_rows
        previous = seen
        out.append(Frame(n, bodies, []))
    return out


def play_frames(detector, frames: Sequence[Frame]) -> tuple[float, list[list[Contact]], list[int]]:
    """Play frames through a detector in a tight loop: seconds spent detecting (garbage
    collector paused), each frame's contacts, and the counters summed."""
    import time

    from invaders.lab.timing import no_gc

    scene = FrameScene()
    seconds = 0.0
    found = []
    totals = [0] * 10
    with no_gc():
        for frame in frames:
            scene.load(frame)
            start = time.perf_counter()
            contacts, stats = detector.detect(scene)
            seconds += time.perf_counter() - start
            found.append(contacts)
            totals = [t + s for t, s in zip(totals, stats, strict=True)]
    return seconds, found, totals
