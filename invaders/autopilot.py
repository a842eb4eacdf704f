"""A deterministic player for headless runs: aims, shoots, dodges bombs, and sometimes fails.

It reads the world and returns input bits, like a keyboard would; it never writes the world.
Its own generator (seeded from the run's seed) makes it imperfect in a repeatable way, so
headless games see every kind of collision: kills, shield hits, saucer hits, shot-bomb
meetings, bombs on shields and on the cannon, deaths, respawns, waves and game over.
"""

from __future__ import annotations

import random

from invaders.sim.actions import Action
from invaders.sim.entities import CannonState
from invaders.sim.world import Phase, World

DODGE_LOOKAHEAD = 72  # rows above the cannon in which a falling bomb is taken seriously
SHOT_TICKS_TO_LANE = 42  # ticks the shot needs from the barrel to the saucer lane


class Autopilot:
    """`actions(world)` -> this tick's input bits."""

    def __init__(self, seed: int, skill: float = 0.8) -> None:
        self.rng = random.Random(f"autopilot:{seed}")
        self.skill = skill
        self._fire_held = False
        self._noticed: dict[int, bool] = {}
        self._wander = 0
        self._wander_dir = 0

    def actions(self, world: World) -> int:
        if world.phase is Phase.GAME_OVER:
            return int(Action.START) if world.tick % 30 == 0 else 0
        cannon = world.cannon
        if cannon.state is not CannonState.ACTIVE:
            return 0
        centre = cannon.x + 8
        move = self._dodge(world, centre)
        if move is None:
            move = self._wandering()
        if move is None:
            move = self._approach(world, centre)
        bits = 0
        if move < 0:
            bits |= Action.LEFT
        elif move > 0:
            bits |= Action.RIGHT
        if self._want_fire(world, centre):
            bits |= Action.FIRE
        self._fire_held = bool(bits & Action.FIRE)
        return int(bits)

    def _dodge(self, world: World, centre: int) -> int | None:
        """Step away from a bomb falling onto the cannon, if it was noticed."""
        for slot in world.slots:
            bomb = slot.bomb
            if bomb is None:
                continue
            noticed = self._noticed.setdefault(bomb.id, self.rng.random() < self.skill)
            if not noticed:
                continue
            above = world.cannon.y - (bomb.y + bomb.h)
            if 0 <= above <= DODGE_LOOKAHEAD and abs(bomb.x + 1 - centre) <= 10:
                g = world.config.geometry
                away = 1 if bomb.x + 1 <= centre else -1
                blocked = (away < 0 and world.cannon.x <= g.cannon_min_x) or (
                    away > 0 and world.cannon.x >= g.cannon_max_x)
                return -away if blocked else away
        if len(self._noticed) > 64:
            live = {s.bomb.id for s in world.slots if s.bomb is not None}
            self._noticed = {k: v for k, v in self._noticed.items() if k in live}
        return None

    def _wandering(self) -> int | None:
        """Now and then drift for a while, so games differ by seed."""
        if self._wander > 0:
            self._wander -= 1
            return self._wander_dir
        if self.rng.random() < 0.004:
            self._wander = self.rng.randint(10, 60)
            self._wander_dir = self.rng.choice((-1, 1))
        return None

    def _target_x(self, world: World) -> int | None:
        ship = world.saucer.saucer
        if ship is not None:
            lead = ship.dx * SHOT_TICKS_TO_LANE // 3
            return ship.x + 12 + lead
        rack = world.rack
        best = None
        for col in range(world.config.geometry.cols):
            alien = rack.lowest_in_column(col)
            if alien is None:
                continue
            x = alien.x + 8
            key = (-alien.top, abs(x - world.cannon.x - 8))
            if best is None or key < best[0]:
                best = (key, x)
        return None if best is None else best[1]

    def _approach(self, world: World, centre: int) -> int:
        target = self._target_x(world)
        if target is None or abs(target - centre) <= 1:
            return 0
        return 1 if target > centre else -1

    def _want_fire(self, world: World, centre: int) -> bool:
        if self._fire_held or world.shot is not None:
            return False
        target = self._target_x(world)
        if target is None:
            return False
        return abs(target - centre) <= 3 or self.rng.random() < 0.02
