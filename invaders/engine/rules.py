"""The rules table: which pairs of kinds are ever tested, and how.

A pair of kinds with no entry is never tested: that is the first reduction, done as data.
In each entry side `a` probes: the grid looks up `a`'s cells in the layer of kind `b`, so
kinds that only ever probe (the shot, the cannon) are never binned at all.
Each entry names, per side, whether the box is the whole shape (BOX) or pixels matter (MASK),
whether discrete positions suffice or the relative motion of the tick must be swept, and an
optional zone outside which the pair cannot meet. `tests/test_rules.py` proves each DISCRETE
choice exact for the speeds in the config, so nothing here is modelled more than it needs.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import pygame

from invaders.engine import predicates
from invaders.engine.body import Kind
from invaders.game.config import SCREEN_W, Geometry


class Shape(Enum):
    BOX = "box"  # the box is the shape (the shot; an alien's whole draw footprint)
    MASK = "mask"  # pixels matter


class Motion(Enum):
    DISCRETE = "discrete"  # test where things are at the end of the tick
    SWEPT = "swept"  # test every pixel position along the tick's relative motion


Zone = tuple[int, int, int, int]  # x, y, w, h


@dataclass(frozen=True)
class PairRule:
    a: Kind
    b: Kind
    a_shape: Shape
    b_shape: Shape
    motion: Motion
    zone: Zone | None
    reason: str

    @property
    def needs_pixels(self) -> bool:
        """Box against box is exact on its own; anything else goes on to a pixel test."""
        return self.a_shape is Shape.MASK or self.b_shape is Shape.MASK

    def shape_of(self, kind: Kind) -> Shape:
        return self.a_shape if kind is self.a else self.b_shape


_G = Geometry()
SAUCER_LANE: Zone = (0, _G.saucer_top, SCREEN_W, _G.saucer_lane_h)

B, M = Shape.BOX, Shape.MASK
D, S = Motion.DISCRETE, Motion.SWEPT

RULES: tuple[PairRule, ...] = (
    PairRule(Kind.SHOT, Kind.ALIEN, B, M, S, None,
             "only the player shot kills aliens; a rack step or drop can jump an alien past it"),
    PairRule(Kind.SHOT, Kind.BUNKER, B, M, D, None,
             "the shot erodes shields; its column is solid and as long as its step"),
    PairRule(Kind.SHOT, Kind.SAUCER, B, M, S, SAUCER_LANE,
             "the saucer meets only the player shot, in its lane; both move, the saucer sideways"),
    PairRule(Kind.SHOT, Kind.BOMB, B, M, S, None,
             "shot and bomb close at up to 9 px a tick: discrete tests would let them pass"),
    PairRule(Kind.CANNON, Kind.BOMB, M, M, S, None,
             "bombs kill the cannon; a bomb's 1-px side columns step 4-5 px"),
    PairRule(Kind.BOMB, Kind.BUNKER, M, M, S, None,
             "bombs erode shields, whose eroded edges can be 1 px thin"),
    PairRule(Kind.BUNKER, Kind.ALIEN, M, B, D, None,
             "low aliens clear their 16x16 draw footprint where it lands, chewing the shields"),
)

# Entries whose outcome is defined by where things land, not by the path between: an alien's
# draw overwrites its footprint at its new place, whatever it passed on the way.
POSITIONAL = frozenset({frozenset({Kind.ALIEN, Kind.BUNKER})})

# Pairs of kinds that are never tested, and why (documentation the tests check against).
NEVER: dict[frozenset[Kind], str] = {
    frozenset({Kind.BOMB, Kind.ALIEN}): "no friendly fire: bombs never hurt aliens",
    frozenset({Kind.BUNKER}): "shields are static: they never collide with each other",
    frozenset({Kind.ALIEN}): "aliens move as a rack and never overlap",
    frozenset({Kind.BOMB}): "bombs fall in separate columns; the original draws them apart",
    frozenset({Kind.CANNON, Kind.BUNKER}): "disjoint rows: 216-223 against 192-207",
    frozenset({Kind.CANNON, Kind.ALIEN}): "landing is a height test (invasion), not a collision",
    frozenset({Kind.CANNON, Kind.SHOT}): "the shot cannot hit its own cannon",
    frozenset({Kind.CANNON, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.ALIEN, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.BOMB, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.BUNKER, Kind.SAUCER}): "the saucer meets only the player shot",
    frozenset({Kind.SAUCER}): "one saucer at a time",
    frozenset({Kind.SHOT}): "one player shot at a time",
    frozenset({Kind.CANNON}): "one cannon",
}


def rule_for(a: Kind, b: Kind, rules: tuple[PairRule, ...] = RULES) -> PairRule | None:
    """The entry for a pair of kinds in either order, or None: never tested."""
    for rule in rules:
        if (rule.a, rule.b) in ((a, b), (b, a)):
            return rule
    return None


def probed_kinds(rules: tuple[PairRule, ...] = RULES) -> frozenset[Kind]:
    """Kinds some entry looks up in the grid: only these need cells."""
    return frozenset(r.b for r in rules)


def swept_kinds(rules: tuple[PairRule, ...] = RULES) -> frozenset[Kind]:
    """Kinds that take part in some swept entry: the grid bins them by their swept box."""
    return frozenset(k for r in rules if r.motion is Motion.SWEPT for k in (r.a, r.b))


def discrete_counterexample(
    fixed: pygame.mask.Mask, moving: pygame.mask.Mask, dx: int, dy: int
) -> tuple[int, int] | None:
    """A start offset at which `moving`, moving (dx, dy) relative to `fixed`, touches it on
    the way but at neither end: proof that discrete tests miss. None: discrete is exact.

    Only the end of a tick is tested, but the start was the previous tick's end, so a
    discrete test misses exactly what the sweep meets between the two ends.
    """
    fw, fh = fixed.get_size()
    mw, mh = moving.get_size()
    for oy in range(-mh - abs(dy), fh + abs(dy) + 1):
        for ox in range(-mw - abs(dx), fw + abs(dx) + 1):
            if fixed.overlap(moving, (ox, oy)) or fixed.overlap(moving, (ox + dx, oy + dy)):
                continue
            swept = predicates.swept_mask(moving, dx, dy)
            if fixed.overlap(swept, (ox + min(0, dx), oy + min(0, dy))):
                return ox, oy
    return None


def sweep_adds_pixels(moving: pygame.mask.Mask, dx: int, dy: int) -> bool:
    """Whether sweeping covers pixels neither end covers: then some target shape (a shield
    eroded to anything) is met on the way but at neither end."""
    w, h = moving.get_size()
    ends = pygame.mask.Mask((w + abs(dx), h + abs(dy)))
    ox, oy = min(0, dx), min(0, dy)
    ends.draw(moving, (-ox, -oy))
    ends.draw(moving, (dx - ox, dy - oy))
    return predicates.swept_mask(moving, dx, dy).count() != ends.count()
