"""Step 4: apply the tick's contacts, in order, after every pair has been tested.

Detect first, respond after: nothing is killed or eroded while pairs are still being tested
(eroding mid-loop would let a shot drill through a shield). A projectile spent by an earlier
contact of the same tick ignores its later ones. Bursts punch their picture out of the
shields they cover (the world does that), as the original's erase of the burst image does.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from invaders.engine.body import Kind
from invaders.engine.predicates import solid_mask
from invaders.engine.stats import Contact
from invaders.game.events import Event

if TYPE_CHECKING:
    from invaders.game.world import World

Handler = Callable[["World", Any, Any, Contact], None]


def _pos(contact: Contact, body_id: int) -> tuple[int, int]:
    """Where a body was at first contact."""
    if body_id == contact.a_id:
        return contact.ax, contact.ay
    return contact.bx, contact.by


def _shot_alien(world: World, shot: Any, alien: Any, contact: Contact) -> None:
    world.remove_shot()
    world.kill_alien(alien)


def _shot_bunker(world: World, shot: Any, bunker: Any, contact: Contact) -> None:
    x, y = _pos(contact, shot.id)
    world.erode(shot.mask, x, y)
    world.burst_shot(x, y)
    world.events.append(Event.BUNKER_HIT)


def _shot_saucer(world: World, shot: Any, saucer: Any, contact: Contact) -> None:
    world.remove_shot()  # counted first: the hitting shot picks the score
    world.hit_saucer()


def _shot_bomb(world: World, shot: Any, bomb: Any, contact: Contact) -> None:
    # UNCERTAIN (13.9): the original has no pairwise test; we burst both, always.
    world.burst_shot(*_pos(contact, shot.id))
    world.burst_bomb(bomb, *_pos(contact, bomb.id))


def _cannon_bomb(world: World, cannon: Any, bomb: Any, contact: Contact) -> None:
    world.remove_bomb(bomb)
    world.kill_cannon()


def _bomb_bunker(world: World, bomb: Any, bunker: Any, contact: Contact) -> None:
    x, y = _pos(contact, bomb.id)
    world.erode(bomb.mask, x, y)
    world.burst_bomb(bomb, x, y)
    world.events.append(Event.BUNKER_HIT)


def _alien_bunker(world: World, alien: Any, bunker: Any, contact: Contact) -> None:
    world.erode(solid_mask(alien.w, alien.h), *_pos(contact, alien.id))


HANDLERS: dict[tuple[Kind, Kind], Handler] = {
    (Kind.SHOT, Kind.ALIEN): _shot_alien,
    (Kind.SHOT, Kind.BUNKER): _shot_bunker,
    (Kind.SHOT, Kind.SAUCER): _shot_saucer,
    (Kind.SHOT, Kind.BOMB): _shot_bomb,
    (Kind.CANNON, Kind.BOMB): _cannon_bomb,
    (Kind.BOMB, Kind.BUNKER): _bomb_bunker,
    (Kind.ALIEN, Kind.BUNKER): _alien_bunker,
}


def apply(contacts: Sequence[Contact], world: World) -> None:
    """Apply contacts in their (low id, high id) order; skip those whose bodies are gone."""
    by_id = world.by_id
    for contact in contacts:
        a = by_id.get(contact.a_id)
        b = by_id.get(contact.b_id)
        if a is None or b is None:
            continue  # spent earlier this tick
        handler = HANDLERS.get((a.kind, b.kind))
        if handler is not None:
            handler(world, a, b, contact)
        else:
            HANDLERS[(b.kind, a.kind)](world, b, a, contact)
