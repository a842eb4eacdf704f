"""The game's things. Collidable ones are Bodies; explosions are timers with a picture."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum, IntEnum

import pygame

from invaders.engine.body import Body
from invaders.engine.compiled import mypyc_attr
from invaders.engine.predicates import solid_mask
from invaders.game import art
from invaders.game.config import SCREEN_H, SCREEN_W, GameConfig
from invaders.game.kinds import Kind

FOOTPRINT_ABOVE = 8  # blank rows an alien's draw footprint has above its picture


def footprint_mask(picture: art.Art) -> pygame.mask.Mask:
    """An alien's 16x16 draw footprint: 8 blank rows above its 16x8 picture.

    The original draws each alien as two bytes per column, its picture and the 8 px above it,
    which clears that area: that is how low aliens chew through the shields.
    """
    return art.mask_of(("." * 16,) * FOOTPRINT_ABOVE + picture)


ALIEN_MASKS = tuple(tuple(footprint_mask(p) for p in pics) for pics in art.ALIEN_BY_ROW)


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Alien(Body):
    """One rack member. Its body is the draw footprint; (x, y + 8) is its picture's corner."""

    __slots__ = ("col", "frame", "index", "row")

    def __init__(self, body_id: int, index: int, row: int, col: int, x: int, top: int,
                 frame: int) -> None:
        self.index = index
        self.row, self.col = row, col
        self.frame = frame
        super().__init__(body_id, Kind.ALIEN, x, top - FOOTPRINT_ABOVE,
                         ALIEN_MASKS[self.row][frame])

    @property
    def top(self) -> int:
        """First row of the picture (the footprint starts FOOTPRINT_ABOVE rows higher)."""
        return self.y + FOOTPRINT_ABOVE


class CannonState(IntEnum):
    WAITING = 0
    ACTIVE = 1
    EXPLODING = 2


CANNON_MASK = art.mask_of(art.CANNON)
DEBRIS_MASKS = tuple(art.mask_of(picture) for picture in art.CANNON_DEATH)


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Cannon(Body):
    """The player's base. Collidable while ACTIVE and while EXPLODING, with the picture
    drawn (the original's bombs meet whatever is lit in the cannon's rows, its debris
    too: 05FB-0612): the cannon's own, held through the blow-up delay, then the debris
    picture `debris` (-1 before the first). `next_debris` is the one the next change
    shows: @1C80 (1) after a hit, which a bomb meeting the debris sets again (the ROM
    zeroes the sprite number it toggles, 060F, 039B)."""

    __slots__ = ("debris", "next_debris", "state", "timer")

    def __init__(self, body_id: int, x: int, top: int) -> None:
        super().__init__(body_id, Kind.CANNON, x, top, CANNON_MASK)
        self.state = CannonState.WAITING
        self.timer = 0
        self.debris = -1
        self.next_debris = 1


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Shot(Body):
    """The player's single shot: its lit 1x4, so the box is the shape."""

    __slots__ = ()

    def __init__(self, body_id: int, x: int, top: int) -> None:
        super().__init__(body_id, Kind.SHOT, x, top, art.mask_of(art.SHOT))


class BombType(IntEnum):
    """Value = the tick (mod 3) of the type's turn; squiggly shares its turn with the saucer."""

    ROLLING = 0
    PLUNGER = 1
    SQUIGGLY = 2


BOMB_PICTURES = {
    BombType.ROLLING: art.BOMB_ROLLING,
    BombType.PLUNGER: art.BOMB_PLUNGER,
    BombType.SQUIGGLY: art.BOMB_SQUIGGLY,
}
BOMB_MASKS = {t: tuple(art.mask_of(p) for p in pics) for t, pics in BOMB_PICTURES.items()}
# Every bomb picture's height (one value: unpacking fails at import if they ever differ).
(BOMB_H,) = {m.get_size()[1] for masks in BOMB_MASKS.values() for m in masks}


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Bomb(Body):
    """An alien bomb: a 3x8 box with four pictures that cycle as it steps."""

    __slots__ = ("btype", "frame")

    def __init__(self, body_id: int, btype: BombType, x: int, y: int) -> None:
        super().__init__(body_id, Kind.BOMB, x, y, BOMB_MASKS[btype][0])
        self.btype = btype
        self.frame = 0


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Bunker(Body):
    """A shield: static, with a mask of its own that erodes."""

    __slots__ = ()

    def __init__(self, body_id: int, x: int, y: int) -> None:
        super().__init__(body_id, Kind.BUNKER, x, y, art.fresh_mask(art.BUNKER))


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Saucer(Body):
    """The mystery ship, in its lane."""

    __slots__ = ("dx",)

    def __init__(self, body_id: int, x: int, y: int, dx: int) -> None:
        super().__init__(body_id, Kind.SAUCER, x, y, art.mask_of(art.SAUCER))
        self.dx = dx


# How many of its own moves a projectile may make between two looks of a detector: 16
# times its speed, looked at every 8th tick (the lab's limits; a test holds them to this).
MOVES_BETWEEN_LOOKS = 16 * 8


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class Edge(Body):
    """A playfield edge as a static box: its line, and beyond it farther than a projectile
    can go between two looks, so that one that crossed the line is inside the edge at the
    next look, however sparsely it looks. Edges take the ids below every thing's (things
    count from 1), so at an equal time of contact the edge comes first, as the original
    tests the top and the ground before it draws."""

    __slots__ = ()

    def __init__(self, body_id: int, kind: Kind, y: int, h: int) -> None:
        super().__init__(body_id, kind, 0, y, solid_mask(SCREEN_W, h))


def edge_depth(config: GameConfig) -> int:
    """How far the edges reach past their lines: the screen's height, and as far again as
    the fastest projectile goes between two looks."""
    s = config.speeds
    return SCREEN_H + MOVES_BETWEEN_LOOKS * max(s.shot, s.bomb, s.bomb_fast)


def edges(config: GameConfig) -> tuple[Edge, Edge]:
    """The top limit (the shot bursts once its top row reaches `shot_top_limit`) and the
    ground (a bomb bursts once its top row reaches `bomb_ground_top`, that is once its
    bottom row reaches that row plus its height less one)."""
    g = config.geometry
    depth = edge_depth(config)
    top = Edge(-2, Kind.TOP, g.shot_top_limit + 1 - depth, depth)
    ground = Edge(-1, Kind.GROUND, g.bomb_ground_top + BOMB_H - 1, depth)
    return top, ground


class Blast(Enum):
    """Explosion pictures that live on a timer of their own."""

    ALIEN = "alien"
    SHOT = "shot"


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
@dataclass
class Explosion:
    """A picture shown for `ttl` more ticks (and, for aliens, the rack waits for it)."""

    blast: Blast
    x: int
    y: int
    ttl: int
