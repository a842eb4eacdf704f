"""A digest of everything that decides the game's future, for replays and determinism tests.

The state is split into named groups (game, rack, cannon, shot, bombs, saucer, shields,
ground, explosions), each with its own digest, so that a replay that goes wrong can say
which group went wrong first. The state hash is the digest of the group digests. Left out:
the broad phase's bookkeeping, collision counters, anything cosmetic.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

import pygame

if TYPE_CHECKING:
    from invaders.game.world import World

GROUPS = ("game", "rack", "cannon", "shot", "bombs", "saucer", "shields", "ground",
          "explosions")


def mask_bytes(mask: pygame.mask.Mask) -> bytes:
    """The mask's pixels, one byte each, row by row."""
    surface = mask.to_surface(setcolor=(255, 255, 255, 255), unsetcolor=(0, 0, 0, 255))
    return pygame.image.tobytes(surface, "RGB")[::3]


def group_values(world: World) -> dict[str, object]:
    """The state as plain values, group by group, in a fixed order."""
    rack = world.rack
    cannon = world.cannon
    shot = world.shot
    ship = world.saucer
    return {
        "game": (world.seed, world.tick, int(world.phase), world.phase_timer, world.score,
                 world.hi_score, world.ships, world.extra_awarded, world.wave, world.games,
                 world.fire_was_down, world.alien_fire_timer, world.shots_removed,
                 world.next_id_value),
        "rack": (rack.ref_x, rack.ref_top, rack.dx, rack.frame, rack.cursor, rack.live,
                 tuple((a.id, a.x, a.y, a.frame) if a is not None else None
                       for a in rack.aliens)),
        "cannon": (int(cannon.state), cannon.timer, cannon.x, cannon.y),
        "shot": None if shot is None else (shot.id, shot.x, shot.y),
        "bombs": tuple((int(s.btype), s.steps, s.burst, s.burst_x, s.burst_y, s.table_index,
                        s.skip_next,
                        None if s.bomb is None else (s.bomb.id, s.bomb.x, s.bomb.y, s.bomb.frame))
                       for s in world.slots),
        "saucer": (ship.timer, ship.due, ship.hit_steps, ship.hit_x, ship.hit_score,
                   ship.from_left,
                   None if ship.saucer is None else (ship.saucer.id, ship.saucer.x,
                                                     ship.saucer.dx)),
        "shields": b"".join(mask_bytes(b.mask) for b in world.bunkers),
        "ground": mask_bytes(world.ground),
        "explosions": tuple((e.blast.value, e.x, e.y, e.ttl) for e in world.explosions),
    }


def _digest(value: object) -> str:
    data = value if isinstance(value, bytes) else repr(value).encode()
    return hashlib.blake2b(data, digest_size=8).hexdigest()


def group_hashes(world: World) -> dict[str, str]:
    """A short digest per group."""
    return {name: _digest(value) for name, value in group_values(world).items()}


def combine(groups: dict[str, str]) -> str:
    """The state hash (128 bits, hex) from the group digests."""
    text = ",".join(f"{name}={groups[name]}" for name in GROUPS)
    return hashlib.blake2b(text.encode(), digest_size=16).hexdigest()


def state_hash(world: World) -> str:
    """Hex digest of the whole state."""
    return combine(group_hashes(world))
