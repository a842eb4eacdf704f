"""World: every piece of game state, and step(actions) -> TickReport.

One tick, in order: move (input, cannon, shot, one alien, the bomb type whose turn it is, the
saucer), detect (reads only), respond (the only writer of collision outcomes), sweep. The
world owns the only random generator and never reads a clock or touches the display.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from enum import IntEnum

import pygame

from invaders.engine.body import Body, Kind
from invaders.engine.detector import Detector, make_detector
from invaders.engine.stats import CollisionStats, Contact
from invaders.game import art, bombs, response, saucer, statehash
from invaders.game.actions import Action
from invaders.game.config import DEFAULT_CONFIG, GameConfig
from invaders.game.entities import (
    Alien,
    Blast,
    Bomb,
    BombType,
    Bunker,
    Cannon,
    CannonState,
    Explosion,
    Shot,
)
from invaders.game.events import Event
from invaders.game.rack import Rack

LEFT, RIGHT, FIRE, START = (int(a) for a in (Action.LEFT, Action.RIGHT, Action.FIRE, Action.START))


class Phase(IntEnum):
    PLAYING = 0
    WAVE_END = 1
    GAME_OVER = 2


@dataclass(frozen=True, slots=True)
class TickReport:
    """What one tick did: its number, the collision counters, events and contacts."""

    tick: int
    stats: CollisionStats
    events: tuple[Event, ...]
    contacts: tuple[Contact, ...]


class World:
    """The whole game state. Mutated only by step() and, within it, by collision response."""

    def __init__(
        self,
        seed: int = 0,
        config: GameConfig = DEFAULT_CONFIG,
        broadphase: str = "grid",
        detector: Detector | None = None,
    ) -> None:
        self.config = config
        self.seed = seed
        self.rng = random.Random(seed)
        # UNCERTAIN (13.5): the saucer's side comes from bit 0 of a ROM byte picked by the shot
        # count, a fixed pseudo-random pattern. We draw such a pattern from the seeded generator.
        self.saucer_sides = tuple(self.rng.getrandbits(1) for _ in range(256))
        self.detector = detector if detector is not None else make_detector(broadphase)
        self.tick = 0
        self.hi_score = 0
        self.games = 0
        self.aliens_killed = 0
        self.fire_was_down = False
        self._next_id = 1
        self.by_kind: dict[Kind, list[Body]] = {kind: [] for kind in Kind}
        self.by_id: dict[int, Body] = {}
        self.dirty: list[Body] = []
        self.events: list[Event] = []
        self.ground = art.fresh_mask(art.GROUND)
        self._new_game()

    # --- the registry the sim parts use --------------------------------------------------
    def new_id(self) -> int:
        body_id = self._next_id
        self._next_id += 1
        return body_id

    def add(self, body: Body) -> None:
        body.alive = True
        body.shaped_tick = self.tick
        self.by_kind[body.kind].append(body)
        self.by_id[body.id] = body
        self.dirty.append(body)

    def move(self, body: Body, x: int, y: int) -> None:
        if body.moved_tick != self.tick:
            body.px = body.x
            body.py = body.y
            body.moved_tick = self.tick
            self.dirty.append(body)
        body.x = x
        body.y = y

    def remove(self, body: Body) -> None:
        if body.alive:
            body.alive = False
            self.by_kind[body.kind].remove(body)
            del self.by_id[body.id]
            self.dirty.append(body)

    @property
    def next_id_value(self) -> int:
        """The id the next body will get (part of the state: ids order the contacts)."""
        return self._next_id

    def kind_counts(self) -> dict[str, int]:
        """Live collidable bodies per kind, by name (what replays compare first)."""
        return {kind.name.lower(): len(bodies) for kind, bodies in self.by_kind.items()}

    def bodies(self, kind: Kind) -> list[Body]:
        """Live bodies of a kind, in id order."""
        return self.by_kind[kind]

    # --- game and wave set-up ------------------------------------------------------------
    def _new_game(self) -> None:
        self.score = 0
        self.ships = self.config.rules.ships
        self.extra_awarded = False
        self.games += 1
        self.ground = art.fresh_mask(art.GROUND)
        self._start_wave(1)

    def _start_wave(self, wave: int) -> None:
        cfg = self.config
        g = cfg.geometry
        for kind in Kind:
            for body in list(self.by_kind[kind]):
                self.remove(body)
        self.wave = wave
        self.phase = Phase.PLAYING
        self.phase_timer = 0
        self.rack = Rack(cfg, cfg.start_top(wave), self)
        self.bunkers = [Bunker(self.new_id(), x, g.bunker_top) for x in g.bunker_xs]
        for bunker in self.bunkers:
            self.add(bunker)
        self.cannon = Cannon(self.new_id(), g.cannon_min_x, g.cannon_top)
        self.cannon.alive = False
        self._cannon_wait()
        self.shot: Shot | None = None
        self.slots = bombs.new_slots()
        bombs.reset_slots(self.slots, self)
        self.saucer = saucer.SaucerState(timer=cfg.timing.saucer_timer)
        self.shots_removed = 0
        self.explosions: list[Explosion] = []
        self.events.append(Event.WAVE_STARTED)

    def _cannon_wait(self) -> None:
        self.cannon.state = CannonState.WAITING
        self.cannon.timer = self.config.timing.cannon_wait
        self.cannon.x = self.cannon.px = self.config.geometry.cannon_min_x
        self.alien_fire_timer = -1  # alien fire is off until the cannon is active

    # --- one tick ------------------------------------------------------------------------
    def step(self, actions: int = 0) -> TickReport:
        """Advance one tick with this tick's input bits; return what happened."""
        self.events = []
        fire_down = bool(actions & FIRE)
        fire_pressed = fire_down and not self.fire_was_down
        self.fire_was_down = fire_down
        self._age_explosions()
        if self.phase is Phase.PLAYING:
            self._move(actions, fire_pressed)
        elif self.phase is Phase.WAVE_END:
            self.phase_timer -= 1
            if self.phase_timer <= 0:
                self._start_wave(self.wave + 1)
        elif self.phase is Phase.GAME_OVER:
            self.phase_timer -= 1
            if self.phase_timer <= 0 and actions & START:
                self._new_game()
                self.events.append(Event.NEW_GAME)
        contacts, stats = self.detector.detect(self)
        self.dirty = []
        if contacts:
            response.apply(contacts, self)
        self._settle()
        report = TickReport(self.tick, stats, tuple(self.events), tuple(contacts))
        self.tick += 1
        return report

    def _move(self, actions: int, fire_pressed: bool) -> None:
        self._move_shot()
        self._move_cannon(actions, fire_pressed)
        if self.cannon.state is CannonState.ACTIVE and not self.alien_exploding:
            alien = self.rack.step(self)
            if alien is not None and alien.top >= self.config.geometry.invasion_top:
                self.events.append(Event.INVASION)
                self._game_over()
                return
        turn = self.tick % 3
        slot = self.slots[turn]
        if turn == BombType.SQUIGGLY and (self.saucer.saucer or self.saucer.hit_steps):
            self._saucer_turn()
        else:
            self._bomb_turn(slot)
        saucer.count_down(self.saucer, self.config, self.rack.ref_top)

    def _move_cannon(self, actions: int, fire_pressed: bool) -> None:
        cannon = self.cannon
        g = self.config.geometry
        if cannon.state is CannonState.WAITING:
            cannon.timer -= 1
            if cannon.timer <= 0:
                cannon.state = CannonState.ACTIVE
                self.add(cannon)
                self.alien_fire_timer = self.config.timing.alien_fire_delay
            return
        if cannon.state is CannonState.EXPLODING:
            cannon.timer -= 1
            if cannon.timer <= 0:
                self.ships -= 1
                self.events.append(Event.SHIP_LOST)
                if self.ships <= 0:
                    self._game_over()
                else:
                    self._cannon_wait()
                    for slot in self.slots:
                        slot.skip_next = slot.btype is BombType.ROLLING
            return
        if self.alien_fire_timer > 0:
            self.alien_fire_timer -= 1
        dx = (1 if actions & RIGHT else 0) - (1 if actions & LEFT else 0)
        if dx:
            x = min(max(cannon.x + dx * self.config.speeds.cannon, g.cannon_min_x), g.cannon_max_x)
            if x != cannon.x:
                self.move(cannon, x, cannon.y)
        if fire_pressed and self.shot is None and not self.shot_bursting:
            self.shot = Shot(self.new_id(), cannon.x + 8, g.shot_spawn_top)
            self.add(self.shot)
            self.events.append(Event.SHOT_FIRED)

    def _move_shot(self) -> None:
        shot = self.shot
        if shot is None:
            return
        y = shot.y - self.config.speeds.shot
        if y <= self.config.geometry.shot_top_limit:
            self.burst_shot(shot.x, y)
            return
        self.move(shot, shot.x, y)

    def _bomb_turn(self, slot: bombs.BombSlot) -> None:
        cfg = self.config
        if slot.bomb is not None:
            fast = self.rack.live <= cfg.speeds.bomb_fast_at
            bombs.advance(slot, cfg.speeds.bomb_fast if fast else cfg.speeds.bomb, self)
            if slot.bomb.y >= cfg.geometry.bomb_ground_top:
                self._bomb_hits_ground(slot)
            return
        if slot.burst > 0:
            slot.burst -= 1
            slot.steps += 1
            return
        if slot.btype is BombType.SQUIGGLY and self.saucer.due:
            if self.rack.live >= cfg.rules.saucer_min_aliens:
                saucer.launch(self.saucer, self, cfg.geometry.saucer_top, cfg.speeds.saucer)
                self.events.append(Event.SAUCER_LAUNCHED)
            else:
                self.saucer.due = False
            return
        self._try_fire(slot)

    def _try_fire(self, slot: bombs.BombSlot) -> None:
        cfg = self.config
        if self.alien_fire_timer != 0 or self.alien_exploding or self.rack.live == 0:
            return
        if slot.btype is BombType.PLUNGER and self.rack.live < cfg.rules.plunger_min_aliens:
            return
        if slot.btype is BombType.SQUIGGLY and self.saucer.busy:
            return
        if not bombs.reload_ready(self.slots, slot, cfg.reload_steps_for(self.score)):
            return
        if slot.skip_next:
            slot.skip_next = False
            return
        col = bombs.choose_column(slot, cfg, self.cannon.x + 8, self.rack)
        if col is not None and bombs.spawn(slot, self.rack, col, self) is not None:
            self.events.append(Event.BOMB_FIRED)

    def _bomb_hits_ground(self, slot: bombs.BombSlot) -> None:
        """A bomb at the bottom bursts on the ground line and chips it."""
        bomb = slot.bomb
        assert bomb is not None
        g = self.config.geometry
        x, y = bomb.x - 2, g.ground_row - 7
        self.ground.erase(art.mask_of(art.BOMB_BURST), (x, y - g.ground_row))
        self.remove(bomb)
        bombs.start_burst(slot, x, y, self.config.timing.bomb_burst_steps)
        self.events.append(Event.BOMB_BURST)

    def _saucer_turn(self) -> None:
        state = self.saucer
        if state.hit_steps > 0:
            state.hit_steps -= 1
            if state.hit_steps == self.config.timing.saucer_score_at:
                self.add_score(state.hit_score)
                self.events.append(Event.SAUCER_SCORED)
        elif state.saucer is not None:
            saucer.fly(state, self)

    def _age_explosions(self) -> None:
        if self.explosions:
            for explosion in self.explosions:
                explosion.ttl -= 1
            self.explosions = [e for e in self.explosions if e.ttl > 0]

    # --- state the rules ask about ---------------------------------------------------------
    @property
    def alien_exploding(self) -> bool:
        """An alien explosion freezes the rack and new alien fire."""
        return any(e.blast is Blast.ALIEN for e in self.explosions)

    @property
    def shot_bursting(self) -> bool:
        """The shot's object is busy while its burst shows: no new shot meanwhile."""
        return any(e.blast is Blast.SHOT for e in self.explosions)

    # --- outcomes, called by movement and by collision response -----------------------------
    def add_score(self, points: int) -> None:
        self.score += points
        if not self.extra_awarded and self.score >= self.config.rules.extra_ship_at:
            self.extra_awarded = True
            self.ships += 1
            self.events.append(Event.EXTRA_SHIP)

    def remove_shot(self) -> None:
        """Every removal of the player shot counts for the saucer's score and side."""
        if self.shot is None:
            return
        self.remove(self.shot)
        self.shot = None
        self.shots_removed += 1
        if self.saucer.saucer is None:
            self.saucer.from_left = bool(self.saucer_sides[self.shots_removed & 0xFF])

    def burst_shot(self, x: int, top: int) -> None:
        """The shot bursts with its 8x8 picture at (x - 3, top - 2), punching shields under it."""
        self.remove_shot()
        corner = (x - 3, top - 2)
        self.erode(art.mask_of(art.SHOT_BURST), *corner)
        self.explosions.append(Explosion(Blast.SHOT, *corner, self.config.timing.shot_burst))
        self.events.append(Event.SHOT_BURST)

    def burst_bomb(self, bomb: Bomb, x: int, y: int) -> None:
        """A bomb bursts with its 6x8 picture at (x - 2, y + 2), punching shields under it."""
        slot = self.slots[bomb.btype]
        self.remove(bomb)
        corner = (x - 2, y + 2)
        self.erode(art.mask_of(art.BOMB_BURST), *corner)
        bombs.start_burst(slot, *corner, self.config.timing.bomb_burst_steps)
        self.events.append(Event.BOMB_BURST)

    def remove_bomb(self, bomb: Bomb) -> None:
        """A bomb that hit the cannon just goes (the cannon's explosion is the picture)."""
        self.remove(bomb)
        self.slots[bomb.btype].bomb = None

    def kill_alien(self, alien: Alien) -> None:
        self.rack.kill(alien, self)
        self.aliens_killed += 1
        self.add_score(self.config.rules.alien_points[alien.row])
        self.explosions.append(
            Explosion(Blast.ALIEN, alien.x, alien.top, self.config.timing.alien_explosion))
        self.events.append(Event.ALIEN_KILLED)

    def kill_cannon(self) -> None:
        cannon = self.cannon
        self.remove(cannon)
        cannon.state = CannonState.EXPLODING
        cannon.timer = self.config.timing.cannon_death
        self.alien_fire_timer = -1
        self.events.append(Event.CANNON_HIT)

    def hit_saucer(self) -> None:
        state = self.saucer
        ship = state.saucer
        assert ship is not None
        self.remove(ship)
        state.saucer = None
        state.hit_steps = self.config.timing.saucer_hit_steps
        state.hit_x = ship.x
        state.hit_score = saucer.score_for(self.config, self.shots_removed)
        self.events.append(Event.SAUCER_HIT)

    def erode(self, mask: pygame.mask.Mask, x: int, y: int) -> None:
        """Erase `mask`, placed at (x, y), from every bunker it covers."""
        w, h = mask.get_size()
        for bunker in self.bunkers:
            if x < bunker.x + bunker.w and bunker.x < x + w and y < bunker.y + bunker.h \
                    and bunker.y < y + h:
                bunker.mask.erase(mask, (x - bunker.x, y - bunker.y))

    def _settle(self) -> None:
        """After response: wave end."""
        if self.phase is Phase.PLAYING and self.rack.live == 0:
            self.phase = Phase.WAVE_END
            self.phase_timer = self.config.timing.wave_pause
            self.events.append(Event.WAVE_CLEARED)

    def _game_over(self) -> None:
        self.phase = Phase.GAME_OVER
        self.phase_timer = self.config.timing.game_over_pause
        self.hi_score = max(self.hi_score, self.score)
        if self.cannon.alive:
            self.remove(self.cannon)
        self.remove_shot()
        for slot in self.slots:
            if slot.bomb is not None:
                self.remove(slot.bomb)
                slot.bomb = None
            slot.burst = 0
        self.events.append(Event.GAME_OVER)

    def state_hash(self) -> str:
        """Hex digest of everything that decides the game's future (see statehash)."""
        return statehash.state_hash(self)
