"""A digest of everything that decides the game's future, for replays and determinism tests.

It covers positions, timers, counters, the rack, every bomb slot, the saucer, each shield's
and the ground's pixels, and the id counter. It leaves out what cannot change the game: the
broad phase's bookkeeping, counters of collision work, cosmetic state.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

import pygame

if TYPE_CHECKING:
    from invaders.sim.world import World


def mask_bytes(mask: pygame.mask.Mask) -> bytes:
    """The mask's pixels, one byte each, row by row."""
    surface = mask.to_surface(setcolor=(255, 255, 255, 255), unsetcolor=(0, 0, 0, 255))
    return pygame.image.tobytes(surface, "RGB")[::3]


def state_values(world: World) -> list[object]:
    """The state as plain values, in a fixed order."""
    rack = world.rack
    cannon = world.cannon
    shot = world.shot
    ship = world.saucer
    values: list[object] = [
        world.seed, world.tick, int(world.phase), world.phase_timer, world.score,
        world.hi_score, world.ships, world.extra_awarded, world.wave, world.games,
        world.fire_was_down, world.alien_fire_timer, world.shots_removed, world._next_id,
        rack.ref_x, rack.ref_top, rack.dx, rack.frame, rack.cursor, rack.live,
        [(a.id, a.x, a.y, a.frame) if a is not None else None for a in rack.aliens],
        (int(cannon.state), cannon.timer, cannon.x, cannon.y),
        None if shot is None else (shot.id, shot.x, shot.y),
        [(int(s.btype), s.steps, s.burst, s.burst_x, s.burst_y, s.table_index, s.skip_next,
          None if s.bomb is None else (s.bomb.id, s.bomb.x, s.bomb.y, s.bomb.frame))
         for s in world.slots],
        (ship.timer, ship.due, ship.hit_steps, ship.hit_x, ship.hit_score, ship.from_left,
         None if ship.saucer is None else (ship.saucer.id, ship.saucer.x, ship.saucer.dx)),
        [(e.blast.value, e.x, e.y, e.ttl) for e in world.explosions],
    ]
    return values


def state_hash(world: World) -> str:
    """Hex digest (128 bits) of the state values and the shield and ground pixels."""
    digest = hashlib.blake2b(repr(state_values(world)).encode(), digest_size=16)
    for bunker in world.bunkers:
        digest.update(mask_bytes(bunker.mask))
    digest.update(mask_bytes(world.ground))
    return digest.hexdigest()
