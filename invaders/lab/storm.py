"""Storm scenes: the game's layout tiled many times over, full of shots and bombs.

A tile is one screen: a rack of 55 aliens, four shields and a cannon, all still, and the
rest of its share of bodies in shots rising and bombs falling through it, at `speed` times
their speeds in the game. Tiles sit side by side, so density stays that of the game while
the body count grows from 100 to 10,000 and beyond. A projectile leaving its tile is
replaced by a new one (a new id) entering at the other end. Deterministic from the seed.
"""

from __future__ import annotations

import math
import random

from invaders.engine.body import Body, Kind
from invaders.game import art
from invaders.game.config import SCREEN_H, SCREEN_W, GameConfig
from invaders.game.entities import ALIEN_MASKS, BOMB_MASKS, BombType

PER_TILE = 100


def _by_id(body: Body) -> int:
    return body.id
STILL_PER_TILE = 55 + 4 + 1


class Storm:
    """A Scene (tick, dirty, by_kind) that `advance()` moves one tick on."""

    def __init__(self, bodies: int, seed: int = 0, speed: int = 1,
                 config: GameConfig | None = None) -> None:
        config = config or GameConfig()
        self.rng = random.Random(f"storm:{seed}")
        self.speed = speed
        self.shot_step = config.speeds.shot * speed
        self.bomb_step = config.speeds.bomb * speed
        self.tick = 0
        self.by_kind: dict[Kind, list[Body]] = {kind: [] for kind in Kind}
        self.dirty: list[Body] = []
        self._next_id = 1
        tiles = max(1, math.ceil(bodies / PER_TILE))
        columns = math.ceil(math.sqrt(tiles))
        self.origins = [((i % columns) * SCREEN_W, (i // columns) * SCREEN_H)
                        for i in range(tiles)]
        g = config.geometry
        for ox, oy in self.origins:
            for index in range(55):
                row, col = divmod(index, 11)
                self._add(Kind.ALIEN, ox + g.rack_left + 16 * col, oy + 128 - 16 * row - 8,
                          ALIEN_MASKS[row][index % 2])
            for x in g.bunker_xs:
                self._add(Kind.BUNKER, ox + x, oy + g.bunker_top, art.fresh_mask(art.BUNKER))
            self._add(Kind.CANNON, ox + self.rng.randrange(16, 186), oy + g.cannon_top,
                      art.mask_of(art.CANNON))
        movers = max(0, bodies - STILL_PER_TILE * tiles)
        for i in range(movers):
            ox, oy = self.origins[i % tiles]
            body = self._spawn(ox, oy + self.rng.randrange(SCREEN_H), shot=i % 2 == 0)
            self.by_kind[body.kind].append(body)

    def _make(self, kind: Kind, x: int, y: int, mask) -> Body:
        body = Body(self._next_id, kind, x, y, mask)
        body.shaped_tick = self.tick
        self._next_id += 1
        self.dirty.append(body)
        return body

    def _add(self, kind: Kind, x: int, y: int, mask) -> Body:
        body = self._make(kind, x, y, mask)
        self.by_kind[kind].append(body)
        return body

    def _spawn(self, ox: int, y: int, shot: bool) -> Body:
        """A new projectile somewhere across the tile at row y (not yet listed)."""
        x = ox + self.rng.randrange(8, SCREEN_W - 8)
        if shot:
            return self._make(Kind.SHOT, x, y, art.mask_of(art.SHOT))
        btype = BombType(self.rng.randrange(3))
        return self._make(Kind.BOMB, x, y, BOMB_MASKS[btype][self.rng.randrange(4)])

    def advance(self) -> None:
        """One tick: shots rise every tick, bombs fall every third (each on its own beat)."""
        self.tick += 1
        self.dirty = []
        for kind, step in ((Kind.SHOT, -self.shot_step), (Kind.BOMB, self.bomb_step)):
            kept = []
            for body in self.by_kind[kind]:
                if kind is Kind.BOMB and (self.tick + body.id) % 3:
                    kept.append(body)
                    continue
                oy = (body.y // SCREEN_H) * SCREEN_H if body.y >= 0 else 0
                y = body.y + step
                if not oy - 8 <= y < oy + SCREEN_H:  # left its tile: a new one comes in
                    body.alive = False
                    self.dirty.append(body)
                    entry = oy + SCREEN_H - 4 if kind is Kind.SHOT else oy
                    ox = (body.x // SCREEN_W) * SCREEN_W
                    kept.append(self._spawn(ox, entry, kind is Kind.SHOT))
                    continue
                body.px, body.py, body.moved_tick = body.x, body.y, self.tick
                body.y = y
                self.dirty.append(body)
                kept.append(body)
            kept.sort(key=_by_id)  # the scene contract: bodies in id order
            self.by_kind[kind] = kept

    @property
    def count(self) -> int:
        return sum(len(b) for b in self.by_kind.values())
