"""Model no more than a scene needs: derive each entry's motion model from proofs.

For the speeds of a scene, an entry can stay discrete only if no start offset exists at which
the sweep meets what neither end meets (for every shape each side can show and every move it
can make in one tick); against an erodible side (a shield, eroded to any shape) sweeping must
add no pixel at all. Entries whose outcome is positional stay discrete. At the game's speeds
this reproduces the hand-written table exactly (a test holds it to that).
"""

from __future__ import annotations

import itertools
from dataclasses import replace
from functools import cache

import pygame

from invaders.engine.body import ERODIBLE, Kind
from invaders.engine.rules import (
    POSITIONAL,
    RULES,
    Motion,
    PairRule,
    discrete_counterexample,
    sweep_adds_pixels,
)
from invaders.game import art
from invaders.game.config import DEFAULT_CONFIG, GameConfig
from invaders.game.entities import ALIEN_MASKS, BOMB_MASKS

Move = tuple[int, int]


def kind_moves(config: GameConfig = DEFAULT_CONFIG, multiplier: int = 1) -> dict[Kind, list[Move]]:
    """Every displacement a body of each kind can make in one tick ((0, 0): it stayed);
    projectiles (shot, bombs) at `multiplier` times their speed."""
    s = config.speeds
    m = multiplier
    return {
        Kind.SHOT: [(0, -s.shot * m)],
        Kind.BOMB: [(0, s.bomb * m), (0, s.bomb_fast * m), (0, 0)],
        Kind.ALIEN: [(s.rack_step, 0), (-s.rack_step, 0), (s.rack_step_last_right, 0),
                     (-s.rack_step, s.rack_drop), (s.rack_step, s.rack_drop),
                     (s.rack_step_last_right, s.rack_drop), (0, 0)],
        Kind.SAUCER: [(s.saucer, 0), (-s.saucer, 0), (0, 0)],
        Kind.CANNON: [(s.cannon, 0), (-s.cannon, 0), (0, 0)],
        Kind.BUNKER: [(0, 0)],
    }


def kind_masks() -> dict[Kind, list[pygame.mask.Mask]]:
    """Every picture each kind can show (shields, which erode to anything, aside)."""
    return {
        Kind.SHOT: [art.mask_of(art.SHOT)],
        Kind.BOMB: [m for masks in BOMB_MASKS.values() for m in masks],
        Kind.ALIEN: [m for masks in ALIEN_MASKS for m in masks],
        Kind.SAUCER: [art.mask_of(art.SAUCER)],
        Kind.CANNON: [art.mask_of(art.CANNON)],
    }


def discrete_miss(rule: PairRule, moves: dict[Kind, list[Move]],
                  masks: dict[Kind, list[pygame.mask.Mask]]) -> tuple | None:
    """A witness that discrete tests miss for this entry at these moves, or None."""
    for da, db in itertools.product(moves[rule.a], moves[rule.b]):
        dx, dy = db[0] - da[0], db[1] - da[1]
        if rule.b in ERODIBLE or rule.a in ERODIBLE:
            mover = rule.a if rule.b in ERODIBLE else rule.b
            sign = -1 if mover is rule.a else 1
            if any(sweep_adds_pixels(m, sign * dx, sign * dy) for m in masks[mover]):
                return da, db
            continue
        for ma, mb in itertools.product(masks[rule.a], masks[rule.b]):
            found = discrete_counterexample(ma, mb, dx, dy)
            if found is not None:
                return da, db, found
    return None


@cache
def cheapest_rules(multiplier: int = 1, config: GameConfig = DEFAULT_CONFIG,
                   rules: tuple[PairRule, ...] = RULES) -> tuple[PairRule, ...]:
    """The rules with each entry discrete where that is proven exact, swept elsewhere."""
    moves = kind_moves(config, multiplier)
    masks = kind_masks()
    out = []
    for rule in rules:
        if frozenset({rule.a, rule.b}) in POSITIONAL:
            motion = Motion.DISCRETE
        else:
            motion = Motion.SWEPT if discrete_miss(rule, moves, masks) else Motion.DISCRETE
        out.append(replace(rule, motion=motion))
    return tuple(out)
