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
DODGE_MARGIN = 9  # a bomb within this many columns of the cannon's centre will hit it
SHOT_TICKS_TO_LANE = 42  # ticks the shot needs from the barrel to the saucer lane


class Autopilot:
    """`actions(world)` -> this tick's input bits."""

    def __init__(self, seed: int, skill: float = 0.85) -> None:
        self.rng = random.Random(f"autopilot:{seed}")
        self.skill = skill
        self._fire_held = False
        self._noticed: dict[int, bool] = {}
        self._wander = 0
        self._wander_dir = 0
        self._through_shields = False  # re-rolled at each shot: now and then shoot a shield

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
            if move is not None and not self._safe(world, centre + move):
                move = 0
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

    def _danger(self, world: World) -> list[tuple[int, int]]:
        """Cannon-centre intervals that noticed bombs, falling close above, will hit."""
        zones = []
        for slot in world.slots:
            bomb = slot.bomb
            if bomb is None:
                continue
            if not self._noticed.setdefault(bomb.id, self.rng.random() < self.skill):
                continue
            above = world.cannon.y - (bomb.y + bomb.h)
            if above <= DODGE_LOOKAHEAD and bomb.y < world.cannon.y + world.cannon.h:
                zones.append((bomb.x + 1 - DODGE_MARGIN, bomb.x + 1 + DODGE_MARGIN))
        if len(self._noticed) > 64:
            live = {s.bomb.id for s in world.slots if s.bomb is not None}
            self._noticed = {k: v for k, v in self._noticed.items() if k in live}
        return zones

    def _dodge(self, world: World, centre: int) -> int | None:
        """Step out of a noticed bomb's path (towards the nearer side with room)."""
        g = world.config.geometry
        for low, high in self._danger(world):
            if low <= centre <= high:
                left_room = world.cannon.x > g.cannon_min_x
                right_room = world.cannon.x < g.cannon_max_x
                go_left = (centre - low <= high - centre and left_room) or not right_room
                return -1 if go_left else 1
        return None

    def _safe(self, world: World, centre: int) -> bool:
        return all(not low <= centre <= high for low, high in self._danger(world))

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
            blocked = _under_shield(world, x) and not self._through_shields
            key = (blocked, -alien.top, abs(x - world.cannon.x - 8))
            if best is None or key < best[0]:
                best = (key, x)
        return None if best is None else best[1]

    def _approach(self, world: World, centre: int) -> int:
        target = self._target_x(world)
        if target is None or abs(target - centre) <= 1:
            return 0
        step = 1 if target > centre else -1
        return step if self._safe(world, centre + step) else 0

    def _want_fire(self, world: World, centre: int) -> bool:
        if self._fire_held or world.shot is not None:
            return False
        target = self._target_x(world)
        if target is None:
            return False
        if _under_shield(world, centre) and not self._through_shields:
            return False
        fire = abs(target - centre) <= 3 or self.rng.random() < 0.02
        if fire:
            self._through_shields = self.rng.random() < 0.15
        return fire


def _under_shield(world: World, x: int) -> bool:
    """Whether a shield pixel stands in column x above the cannon."""
    for bunker in world.bunkers:
        if bunker.x <= x < bunker.x + bunker.w:
            return any(bunker.mask.get_at((x - bunker.x, y)) for y in range(bunker.h))
    return False
