"""The rack's watch: between two looks it names every place whose alien changed (came,
went, moved or changed picture), whatever happened in between: kills, waves, a player's
rack hidden and drawn again, a copy of the world, looks far apart."""

from __future__ import annotations

import copy
import random

from invaders.game.actions import Action
from invaders.game.events import Event
from invaders.game.players import HOLD
from invaders.game.rack import Rack, RackWatch
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from tests.helpers import step_until


def _places(rack: Rack) -> list[tuple[int, int, int] | None]:
    """What each place shows: its alien's x, y and picture while alive, else nothing."""
    return [(alien.x, alien.y, alien.frame) if alien is not None and alien.alive else None
            for alien in rack.aliens]


class Looker:
    """A watch with what it saw last, checked at each look."""

    def __init__(self) -> None:
        self.watch, self.seen, self.rack, self.tick = RackWatch(), [], None, 0
        self.partial = 0  # looks that named only some places
        self.racks, self.fewest = 0, 55  # racks seen, and the fewest live aliens seen

    def look(self, world: World) -> None:
        rack, now = world.rack, _places(world.rack)
        named = set(self.watch.changed(rack))
        if rack is self.rack:
            changed = {i for i, (was, is_) in enumerate(zip(self.seen, now, strict=True))
                       if was != is_}
            assert changed <= named, (world.tick, sorted(changed - named))
        else:
            assert named == set(range(len(rack.aliens)))
        if len(named) < len(rack.aliens):  # no more than an alien a tick since the last look
            assert rack is self.rack and len(named) <= world.tick - self.tick
        self.partial += len(named) < len(rack.aliens)
        self.racks += rack is not self.rack
        self.fewest = min(self.fewest, rack.live)
        self.seen, self.rack, self.tick = now, rack, world.tick


def test_the_watch_names_every_changed_place_in_whole_games_looked_at_now_and_then():
    """Two players, the autopilot's fire and kills by hand (so that racks are cleared,
    through their last few aliens), new games after game over, copies, looks 1 to 400
    ticks apart."""
    for seed in range(3):
        draw = random.Random(seed)
        world, pilot, looker = World(seed=seed, players=2), Autopilot(seed, "expert"), Looker()
        while world.tick < 20000:
            ticks = draw.choice((1, 2, 4, 4, 4, 7) if draw.random() < 0.9 else (60, 400))
            for _ in range(ticks):
                world.step(pilot.actions(world) | (Action.START2 if draw.random() < 0.1 else 0))
            if draw.random() < 0.02:  # a copy plays on (as an environment's restored state)
                world = copy.deepcopy(world)
            live = world.rack.live_aliens()
            if len(live) > 2 and draw.random() < 0.3:
                world.kill_alien(draw.choice(live), draw.randrange(224))  # (either half)
            looker.look(world)
        assert looker.partial > 250 and looker.racks > 10 and looker.fewest < 4


def test_a_rack_hidden_and_drawn_again_between_two_looks_is_looked_at_whole():
    """Player 1's rack leaves the screen at their death and comes back drawn one alien a
    tick: a look before and one a few draws after see the same rack, with the same aliens
    alive, and fewer draws between than aliens, yet every place changed."""
    world, looker = World(seed=2, players=2), Looker()
    step_until(world, lambda r: world.rack.live == 55 and world.cannon.state == 1, limit=400)
    first = world.rack
    looker.look(world)
    seen_draws = first.draws
    for _ in range(2):  # player 1 dies, then player 2
        world.kill_cannon()
        step_until(world, lambda r: Event.SHIP_LOST in r.events, limit=200)
        step_until(world, lambda r: Event.TURN_STARTED in r.events, limit=HOLD + 400)
    step_until(world, lambda r: first.draws - seen_draws >= 3, limit=10)
    assert world.rack is first and first.live == 55
    looker.look(world)
