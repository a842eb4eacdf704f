"""Storm scenes: the game's layout tiled many times over, full of shots and bombs.

A tile is one screen: a rack of aliens, the shields and a cannon, all still, a saucer flying
to and fro in the tile's saucer lane, and the rest of its share of bodies in shots rising
and bombs falling through it, all at `speed` times their speeds in the game. Tiles sit side
by side, so density stays that of the game while the body count grows from 100 to 10,000
and beyond; each tile's lane is a zone of the saucer's entry (`storm_rules`). A projectile
leaving its tile is replaced by a new one (a new id) entering at the other end. Every
number comes from the config; deterministic from the seed.
"""

from __future__ import annotations

import math
import random
from dataclasses import replace

from invaders.engine.body import Body
from invaders.engine.rules import RuleTable, Zone
from invaders.engine.store import BodyStore
from invaders.game import art
from invaders.game.config import SCREEN_H, SCREEN_W, GameConfig
from invaders.game.entities import ALIEN_MASKS, BOMB_MASKS, BombType
from invaders.game.kinds import Kind

PER_TILE = 100


def still_per_tile(config: GameConfig) -> int:
    """Bodies of a tile that are not projectiles: the rack, the shields, cannon and saucer."""
    g = config.geometry
    return g.rows * g.cols + len(g.bunker_xs) + 2


def tile_origins(bodies: int) -> list[tuple[int, int]]:
    """Top-left corners of the tiles a storm of `bodies` lays out, in a near-square."""
    tiles = max(1, math.ceil(bodies / PER_TILE))
    columns = math.ceil(math.sqrt(tiles))
    return [((i % columns) * SCREEN_W, (i // columns) * SCREEN_H) for i in range(tiles)]


def storm_rules(rules: RuleTable, bodies: int, config: GameConfig | None = None) -> RuleTable:
    """The rules with each zoned entry's zone (the saucer lane) repeated in every tile."""
    config = config or GameConfig()
    g = config.geometry
    lanes: Zone = tuple((ox, oy + g.saucer_top, SCREEN_W, g.saucer_lane_h)
                        for ox, oy in tile_origins(bodies))
    return rules.map(lambda rule: rule if rule.zone is None else replace(rule, zone=lanes))


class Storm:
    """A scene `advance()` moves one tick on; `store` is what a detector reads."""

    def __init__(self, bodies: int, seed: int = 0, speed: int = 1,
                 config: GameConfig | None = None) -> None:
        config = config or GameConfig()
        g = config.geometry
        self.config = config
        self.rng = random.Random(f"storm:{seed}")
        self.speed = speed
        self.shot_step = config.speeds.shot * speed
        self.bomb_step = config.speeds.bomb * speed
        self.saucer_step = config.speeds.saucer * speed
        self.store = BodyStore(Kind)
        self.origins = tile_origins(bodies)
        top = config.start_top(1)
        for ox, oy in self.origins:
            for index in range(g.rows * g.cols):
                row, col = divmod(index, g.cols)
                self._add(Kind.ALIEN, ox + g.rack_left + g.cell * col,
                          oy + top - g.cell * row - 8, ALIEN_MASKS[row][index % 2])
            for x in g.bunker_xs:
                self._add(Kind.BUNKER, ox + x, oy + g.bunker_top, art.fresh_mask(art.BUNKER))
            self._add(Kind.CANNON, ox + self.rng.randrange(g.cannon_min_x, g.cannon_max_x + 1),
                      oy + g.cannon_top, art.mask_of(art.CANNON))
            self._add(Kind.SAUCER, ox + self.rng.randrange(g.saucer_start_left,
                                                           g.saucer_start_right + 1),
                      oy + g.saucer_top, art.mask_of(art.SAUCER))
        self.saucer_dx = {body.id: self.saucer_step * self.rng.choice((-1, 1))
                          for body in self.store.by_kind[Kind.SAUCER]}
        movers = max(0, bodies - still_per_tile(config) * len(self.origins))
        for i in range(movers):
            ox, oy = self.origins[i % len(self.origins)]
            self.store.add(self._spawn(ox, oy + self.rng.randrange(SCREEN_H), shot=i % 2 == 0))

    @property
    def tick(self) -> int:
        return self.store.tick

    def _add(self, kind: Kind, x: int, y: int, mask) -> Body:
        body = Body(self.store.new_id(), kind, x, y, mask)
        self.store.add(body)
        return body

    def _spawn(self, ox: int, y: int, shot: bool) -> Body:
        """A new projectile somewhere across the tile at row y (not yet in the store)."""
        x = ox + self.rng.randrange(8, SCREEN_W - 8)
        if shot:
            return Body(self.store.new_id(), Kind.SHOT, x, y, art.mask_of(art.SHOT))
        btype = BombType(self.rng.randrange(3))
        return Body(self.store.new_id(), Kind.BOMB, x, y,
                    BOMB_MASKS[btype][self.rng.randrange(4)])

    def advance(self) -> None:
        """One tick: shots rise every tick, bombs fall every third (each on its own beat),
        saucers fly every tick and turn at their lane's ends."""
        store = self.store
        store.tick += 1
        g = self.config.geometry
        for saucer in list(store.by_kind[Kind.SAUCER]):
            ox = (saucer.x // SCREEN_W) * SCREEN_W
            x = saucer.x + self.saucer_dx[saucer.id]
            if not ox + g.saucer_exit_left <= x < ox + g.saucer_exit_right:
                self.saucer_dx[saucer.id] *= -1
                x = saucer.x + self.saucer_dx[saucer.id]
            store.move(saucer, x, saucer.y)
        for kind, step in ((Kind.SHOT, -self.shot_step), (Kind.BOMB, self.bomb_step)):
            for body in list(store.by_kind[kind]):
                if kind is Kind.BOMB and (store.tick + body.id) % 3:
                    continue
                oy = (body.y // SCREEN_H) * SCREEN_H if body.y >= 0 else 0
                y = body.y + step
                if not oy - 8 <= y < oy + SCREEN_H:  # left its tile: a new one comes in
                    store.remove(body)
                    entry = oy + SCREEN_H - 4 if kind is Kind.SHOT else oy
                    ox = (body.x // SCREEN_W) * SCREEN_W
                    store.add(self._spawn(ox, entry, kind is Kind.SHOT))
                    continue
                store.move(body, body.x, y)

    @property
    def count(self) -> int:
        return self.store.size
