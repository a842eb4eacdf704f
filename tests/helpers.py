"""Helpers: ASCII masks, hand-made scenes, a world brought to a known moment, and a stream
on a full disk."""

from __future__ import annotations

import errno
import io
import os
from collections.abc import Callable, Sequence
from operator import attrgetter
from typing import Any

import numpy as np
import pygame

from invaders.engine.body import Body
from invaders.engine.store import BodyStore
from invaders.game import art
from invaders.game.config import DEFAULT_CONFIG
from invaders.game.entities import CannonState
from invaders.game.kinds import Kind
from invaders.game.rules import make_rules
from invaders.game.tuning import kind_moves, proof_masks
from invaders.game.world import TickReport, World

# Every picture mask a kind can show (shields, which erode, aside; the edges as boxes).
SHARED_MASKS = proof_masks(kind_moves())
GAME_RULES = make_rules(DEFAULT_CONFIG)


def mask(*rows: str) -> pygame.mask.Mask:
    """A fresh mask from ASCII art ('#' lit)."""
    return art.fresh_mask(art.art(*rows))


def mask_rows(m: pygame.mask.Mask) -> tuple[str, ...]:
    """A mask back as ASCII art, for pixel-exact comparisons with readable failures."""
    w, h = m.get_size()
    return tuple("".join("#" if m.get_at((x, y)) else "." for x in range(w)) for y in range(h))


def store_of(bodies: Sequence[Body], tick: int = 0) -> BodyStore:
    """A hand-made scene in a store of its own, at `tick`. Each body keeps the motion and
    the `shaped_tick` it was given: the scene says itself which bodies are new in it."""
    store = BodyStore(Kind)
    store.tick = tick
    for body in sorted(bodies, key=attrgetter("id")):
        shaped = body.shaped_tick
        store.add(body)
        body.shaped_tick = shaped
    return store


def active_world(seed: int = 0, **kwargs) -> World:
    """A world whose cannon has just become active (wave 1, nothing fired yet)."""
    world = World(seed=seed, **kwargs)
    while world.cannon.state is not CannonState.ACTIVE:
        world.step(0)
    return world


def step_until(world: World, done: Callable[[TickReport], bool], actions: int = 0,
               limit: int = 2000) -> TickReport:
    """Step until a tick's report satisfies `done`; fail loudly if it never does."""
    for _ in range(limit):
        report = world.step(actions)
        if done(report):
            return report
    raise AssertionError(f"condition not met in {limit} ticks")


def rack_moves(world: World, done: Callable[[World], bool],
               limit: int = 2000) -> list[tuple[int, int]]:
    """The reference alien's moves (dx, dy), tick by tick, until `done(world)`, with the
    rack's bombs held back (a death comes only when a test asks for one)."""
    rack, moves = world.rack, []
    for _ in range(limit):
        world.alien_fire_timer = 10**9
        x, top = rack.ref_x, rack.ref_top
        world.step(0)
        if (rack.ref_x, rack.ref_top) != (x, top):
            moves.append((rack.ref_x - x, rack.ref_top - top))
        if done(world):
            return moves
    raise AssertionError(f"not done in {limit} ticks")


class FakeClock:
    """A clock the test moves by hand, for windowed sessions at any frame rate."""

    def __init__(self, start: float = 0.0) -> None:
        self.now = start

    def __call__(self) -> float:
        return self.now


def windowed(world: World, **options):
    """A windowed session on an off-screen surface, and the fake clock that drives it."""
    from invaders.app.play import Session

    clock = FakeClock()
    return Session(world, pygame.Surface((224, 256)), clock, **options), clock


def through_the_prompt(app, clock) -> list[bool]:
    """Frames until PLAY PLAYER<1> has shown its three seconds and the game is on; whether
    each drew."""
    drew = []
    while app.mode == "prompt":
        clock.now += 1 / 60
        drew.append(app.step([], 0)[1])
        assert len(drew) < 400
    return drew


def infos_alike(one: Any, other: Any) -> bool:
    """Two infos of vector environments (or entries of them) equal as Gymnasium merges
    them: arrays of the same type and values (tuples of names, for events; arrays, for
    final observations), or dicts of such arrays."""
    if isinstance(one, dict):
        return one.keys() == other.keys() and all(infos_alike(one[k], other[k]) for k in one)
    return one.dtype == other.dtype and one.shape == other.shape and all(
        np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b
        for a, b in zip(one.tolist(), other.tolist(), strict=True))


def vector_answers_alike(one: tuple, other: tuple) -> bool:
    """Two answers of vector environments (a step's or a reset's) equal part for part: the
    arrays, and the infos as Gymnasium merges them."""
    return len(one) == len(other) and all(
        infos_alike(a, b) if isinstance(a, dict) else np.array_equal(a, b)
        for a, b in zip(one, other, strict=True))


class FullStream(io.StringIO):
    """A stream on a full disk (standard error, say): every write fails."""

    def write(self, text: str) -> int:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
