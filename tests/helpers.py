"""Helpers: ASCII masks, hand-made scenes, and a world brought to a known moment."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import pygame

from invaders.engine.body import Body, Kind
from invaders.game import art
from invaders.game.entities import CannonState
from invaders.game.tuning import kind_masks
from invaders.game.world import TickReport, World

# Every picture mask a kind can show (shields, which erode, aside).
SHARED_MASKS = kind_masks()


def mask(*rows: str) -> pygame.mask.Mask:
    """A fresh mask from ASCII art ('#' lit)."""
    return art.fresh_mask(art.art(*rows))


def mask_rows(m: pygame.mask.Mask) -> tuple[str, ...]:
    """A mask back as ASCII art, for pixel-exact comparisons with readable failures."""
    w, h = m.get_size()
    return tuple("".join("#" if m.get_at((x, y)) else "." for x in range(w)) for y in range(h))


class Scene:
    """A hand-made scene: bodies by kind, all new (so any broad phase starts from scratch)."""

    def __init__(self, bodies: Sequence[Body], tick: int = 0) -> None:
        self.tick = tick
        self.dirty = list(bodies)
        self.by_kind = {kind: sorted((b for b in bodies if b.kind is kind), key=lambda b: b.id)
                        for kind in Kind}

    def bodies(self, kind: Kind) -> list[Body]:
        return self.by_kind[kind]


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
