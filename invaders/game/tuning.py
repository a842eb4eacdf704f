"""Model no more than a scene needs: each entry's motion model from proofs, for any speed.

The moves each kind can make in one tick come from the config (projectiles at `multiplier`
times their speed), the pictures from the art; `engine.proofs.cheapest` keeps an entry
discrete only where that is proven exact. At the game's speeds this reproduces the
hand-written table exactly (a test holds it to that).
"""

from __future__ import annotations

from functools import cache

import pygame

from invaders.engine.predicates import solid_mask
from invaders.engine.proofs import Move, cheapest
from invaders.engine.rules import RuleTable
from invaders.game import art
from invaders.game.config import DEFAULT_CONFIG, SCREEN_W, GameConfig
from invaders.game.entities import ALIEN_MASKS, BOMB_MASKS, CANNON_MASK, DEBRIS_MASKS
from invaders.game.kinds import EDGES, Kind
from invaders.game.rules import make_rules


def kind_moves(config: GameConfig = DEFAULT_CONFIG, multiplier: int = 1) -> dict[int, list[Move]]:
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
        Kind.TOP: [(0, 0)],
        Kind.GROUND: [(0, 0)],
    }


def kind_masks() -> dict[int, list[pygame.mask.Mask]]:
    """Every picture each thing can show (shields, which erode to anything, aside)."""
    return {
        Kind.SHOT: [art.mask_of(art.SHOT)],
        Kind.BOMB: [m for masks in BOMB_MASKS.values() for m in masks],
        Kind.ALIEN: [m for masks in ALIEN_MASKS for m in masks],
        Kind.SAUCER: [art.mask_of(art.SAUCER)],
        Kind.CANNON: [CANNON_MASK, *DEBRIS_MASKS],  # (its debris meets bombs too)
    }


def edge_masks(moves: dict[int, list[Move]]) -> dict[int, list[pygame.mask.Mask]]:
    """The edges as the proofs see them: a box as deep as the longest move. The real edge
    is deeper still (EDGE_DEPTH), and against a solid box only depth matters: a body that
    moves into it less far than it is deep ends inside it, so a proof on this box holds
    for the real one (and a box EDGE_DEPTH deep would take the proof minutes)."""
    reach = max(abs(d) for kind_moves in moves.values() for move in kind_moves for d in move)
    return {kind: [solid_mask(SCREEN_W, reach + 1)] for kind in EDGES}


def proof_masks(moves: dict[int, list[Move]]) -> dict[int, list[pygame.mask.Mask]]:
    """The pictures the proofs try for every kind: the things' own and the edges' boxes."""
    return kind_masks() | edge_masks(moves)


@cache
def cheapest_rules(multiplier: int = 1, config: GameConfig = DEFAULT_CONFIG) -> RuleTable:
    """The game's table with each entry discrete where that is proven exact, swept elsewhere."""
    moves = kind_moves(config, multiplier)
    return cheapest(make_rules(config), moves, proof_masks(moves))
