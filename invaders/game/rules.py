"""The game's rules table, built from its config: which pairs of kinds meet, and what then.

A pair of kinds with no entry is never tested (NEVER says why, and a test holds every pair
to one or the other). Each entry names its shapes, its motion model (proved minimal in
tuning.py), its zone, the sides a contact spends and its response. Responses change the
world only through its outcome methods (removals, bursts, erosion, score, lives); they run
after detection, earliest contact first. The playfield's edges are bodies too (the top
limit, the ground), so reaching one is a contact in the same order as any other.
"""

from __future__ import annotations

from typing import Any, Protocol

import pygame

from invaders.engine.predicates import solid_mask
from invaders.engine.rules import Motion, PairRule, RuleTable, Shape
from invaders.engine.stats import Contact
from invaders.game.config import SCREEN_W, GameConfig
from invaders.game.entities import CannonState
from invaders.game.events import Event
from invaders.game.kinds import Kind


class Outcomes(Protocol):
    """What a response may do to the world: the world's outcome methods."""

    events: list[Event]

    def remove_shot(self) -> None: ...
    def kill_alien(self, alien: Any, shot_x: int) -> None: ...
    def erode(self, mask: pygame.mask.Mask, x: int, y: int) -> None: ...
    def burst_shot(self, x: int, top: int) -> None: ...
    def burst_bomb(self, bomb: Any, x: int, y: int) -> None: ...
    def kill_cannon(self) -> None: ...
    def hit_debris(self) -> None: ...
    def hit_saucer(self) -> None: ...
    def bomb_hits_ground(self, bomb: Any) -> None: ...


def _pos(contact: Contact, body_id: int) -> tuple[int, int]:
    """Where a body was at contact."""
    if body_id == contact.a_id:
        return contact.ax, contact.ay
    return contact.bx, contact.by


def shot_alien(world: Outcomes, shot: Any, alien: Any, contact: Contact) -> None:
    world.remove_shot()
    world.kill_alien(alien, shot.x)


def shot_bunker(world: Outcomes, shot: Any, bunker: Any, contact: Contact) -> None:
    x, y = _pos(contact, shot.id)
    world.erode(shot.mask, x, y)
    world.burst_shot(x, y)
    world.events.append(Event.BUNKER_HIT)


def shot_saucer(world: Outcomes, shot: Any, saucer: Any, contact: Contact) -> None:
    world.remove_shot()  # counted first: the hitting shot picks the score
    world.hit_saucer()


def shot_bomb(world: Outcomes, shot: Any, bomb: Any, contact: Contact) -> None:
    # UNCERTAIN (13.9): the original has no pairwise test; we burst both, always.
    world.burst_shot(*_pos(contact, shot.id))
    world.burst_bomb(bomb, *_pos(contact, bomb.id))


def cannon_bomb(world: Outcomes, cannon: Any, bomb: Any, contact: Contact) -> None:
    """A bomb that meets the cannon's lit pixels in its rows flags the player struck and
    bursts there (0600-0617): a cannon in play is killed; one blowing up already (its
    picture held, or its debris) blows up on, its debris' next picture set again."""
    if cannon.state is CannonState.EXPLODING:
        world.hit_debris()
    else:
        world.kill_cannon()
    world.burst_bomb(bomb, *_pos(contact, bomb.id))


def bomb_bunker(world: Outcomes, bomb: Any, bunker: Any, contact: Contact) -> None:
    x, y = _pos(contact, bomb.id)
    world.erode(bomb.mask, x, y)
    world.burst_bomb(bomb, x, y)
    world.events.append(Event.BUNKER_HIT)


def shot_top(world: Outcomes, shot: Any, top: Any, contact: Contact) -> None:
    x, y = _pos(contact, shot.id)  # where it landed: at speed, past the line
    world.burst_shot(x, max(y, top.y + top.h - 1))  # bursts with its top on the line


def bomb_ground(world: Outcomes, bomb: Any, ground: Any, contact: Contact) -> None:
    world.bomb_hits_ground(bomb)


def alien_bunker(world: Outcomes, bunker: Any, alien: Any, contact: Contact) -> None:
    world.erode(solid_mask(alien.w, alien.h), *_pos(contact, alien.id))


B, M = Shape.BOX, Shape.MASK
D, S, L = Motion.DISCRETE, Motion.SWEPT, Motion.LANDING


def make_rules(config: GameConfig) -> RuleTable:
    """The table for a config (the saucer's lane comes from its geometry)."""
    g = config.geometry
    lane = ((0, g.saucer_top, SCREEN_W, g.saucer_lane_h),)
    return RuleTable((
        PairRule(Kind.SHOT, Kind.ALIEN, B, M, S, None, True, True, shot_alien,
                 "only the player shot kills aliens; a rack step or drop can jump an alien "
                 "past it"),
        PairRule(Kind.SHOT, Kind.BUNKER, B, M, D, None, True, False, shot_bunker,
                 "the shot erodes shields; its column is solid and as long as its step"),
        PairRule(Kind.SHOT, Kind.SAUCER, B, M, S, lane, True, True, shot_saucer,
                 "the saucer meets only the player shot, in its lane; both move, the saucer "
                 "sideways"),
        PairRule(Kind.SHOT, Kind.BOMB, B, M, S, None, True, True, shot_bomb,
                 "shot and bomb close at up to 9 px a tick: discrete tests would let them pass"),
        PairRule(Kind.CANNON, Kind.BOMB, M, M, S, None, True, True, cannon_bomb,
                 "bombs kill the cannon and burst on it, on its debris too; a bomb's 1-px "
                 "side columns step 4-5 px"),
        PairRule(Kind.BOMB, Kind.BUNKER, M, M, L, None, True, False, bomb_bunker,
                 "the original moves a bomb, draws it, then tests where it landed (05E5-05FF): "
                 "a bomb may jump a thin remnant, and its crater is where it was drawn"),
        PairRule(Kind.BUNKER, Kind.ALIEN, M, B, L, None, False, False, alien_bunker,
                 "low aliens clear their 16x16 draw footprint where it lands, chewing the "
                 "shields"),
        PairRule(Kind.SHOT, Kind.TOP, B, B, D, None, True, False, shot_top,
                 "the shot bursts at the top limit (14D8), in time order with what it meets "
                 "on the way; the edge is deeper than any move, so discrete is exact"),
        PairRule(Kind.BOMB, Kind.GROUND, B, B, D, None, True, False, bomb_ground,
                 "a bomb bursts on the ground (05F3), unless it met the cannon first; the "
                 "edge is deeper than any move, so discrete is exact"),
    ), eroding=frozenset({Kind.BUNKER}))


# Pairs of kinds that are never tested, and why (documentation the tests check against).
NEVER: dict[frozenset[Kind], str] = {
    frozenset({Kind.BOMB, Kind.ALIEN}): "no friendly fire: bombs never hurt aliens",
    frozenset({Kind.BUNKER}): "shields are static: they never collide with each other",
    frozenset({Kind.ALIEN}): "aliens move as a rack and never overlap",
    frozenset({Kind.BOMB}): "bombs fall in separate columns; the original draws them apart",
    frozenset({Kind.CANNON, Kind.BUNKER}): "disjoint rows: the cannon's below the shields'",
    frozenset({Kind.CANNON, Kind.ALIEN}): "landing is a height test (invasion), not a collision",
    frozenset({Kind.CANNON, Kind.SHOT}): "the shot cannot hit its own cannon",
    frozenset({Kind.CANNON, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.ALIEN, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.BOMB, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.BUNKER, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.SAUCER}): "one saucer at a time",
    frozenset({Kind.SHOT}): "one player shot at a time",
    frozenset({Kind.CANNON}): "one cannon",
    **{frozenset({Kind.TOP, kind}): "only the shot reaches the top limit (the saucer's lane "
       "and the rack lie below it)" for kind in Kind if kind is not Kind.SHOT},
    **{frozenset({Kind.GROUND, kind}): "only bombs reach the ground (the cannon runs above "
       "it)" for kind in Kind if kind not in (Kind.BOMB, Kind.TOP)},
}
