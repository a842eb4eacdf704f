"""World: every piece of game state, and step(actions) -> TickReport.

One tick, in order: move (input, cannon, shot, one alien, the bomb type whose turn it is, the
saucer; nothing is removed here, not even at the playfield's edges), detect (the engine's
detector: contacts with their times, and the counters), respond (each rules entry's
response, earliest contact first: the only writer of collision outcomes, reaching an edge
included), then the wave's end if the rack is empty. Bodies live in the engine's store,
which tells the broad phase what changed. The world owns the only random generator and
never reads a clock or touches the display.
"""

from __future__ import annotations

import copy
import random
from enum import IntEnum
from typing import Any, NamedTuple

import pygame

from invaders.engine.adaptive import DEFAULT_BROADPHASE, make_broadphase
from invaders.engine.body import Body
from invaders.engine.compiled import fields, mypyc_attr
from invaders.engine.detector import Detecting, Detector
from invaders.engine.grid import DEFAULT_CELL
from invaders.engine.pickling import mask_bytes, reduce_with_masks
from invaders.engine.response import respond
from invaders.engine.stats import CollisionStats, Contact
from invaders.engine.store import BodyStore
from invaders.game import art, bombs, saucer, statehash
from invaders.game.actions import Action
from invaders.game.config import DEFAULT_CONFIG, GameConfig
from invaders.game.entities import (
    CANNON_MASK,
    DEBRIS_MASKS,
    Alien,
    Blast,
    Bomb,
    BombType,
    Bunker,
    Cannon,
    CannonState,
    Explosion,
    Shot,
    edges,
)
from invaders.game.events import Event
from invaders.game.kinds import THINGS, Kind
from invaders.game.players import PROMPT, SWITCH_TICKS, Turn
from invaders.game.rack import Rack
from invaders.game.rules import make_rules

LEFT, RIGHT, FIRE, START, START2 = (int(a) for a in (
    Action.LEFT, Action.RIGHT, Action.FIRE, Action.START, Action.START2))
MOVES = LEFT | RIGHT
SCORE_WRAP = 10_000  # the score is four BCD digits in the ROM
# The player's shot runs in the mid-screen interrupt left of this column, in the end-of-screen
# one from it (its Xr's top bit against the beam's half: 03BB, 1A06; x is Xr - 32).
MID_SCREEN_X = 96


class Phase(IntEnum):
    PLAYING = 0
    WAVE_END = 1
    GAME_OVER = 2
    SWITCH = 3  # two players, between turns: the field held, then PLAY PLAYER<n>


# Members the tick reads, bound once: an enum member looked up by name goes through the
# enum class's __getattr__ hook, several times slower than reading a global.
PLAYING, WAVE_END, GAME_OVER, SWITCH = (Phase.PLAYING, Phase.WAVE_END, Phase.GAME_OVER,
                                        Phase.SWITCH)
ACTIVE, WAITING, EXPLODING = CannonState.ACTIVE, CannonState.WAITING, CannonState.EXPLODING
SQUIGGLY, PLUNGER, ROLLING = BombType.SQUIGGLY, BombType.PLUNGER, BombType.ROLLING


class TickReport(NamedTuple):
    """What one tick did: its number, the collision counters, events, the contacts applied
    (earliest first), and the broad phase that found them (its name and cell size in px,
    0 for none). A named tuple: immutable, and made every tick at a third of the cost of a
    frozen dataclass."""

    tick: int
    stats: CollisionStats
    events: tuple[Event, ...]
    contacts: tuple[Contact, ...]
    broadphase: str = DEFAULT_BROADPHASE
    cell: int = 0


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
class World:
    """The whole game state. Mutated only by step() and, within it, by collision response."""

    def __init__(
        self,
        seed: int = 0,
        config: GameConfig = DEFAULT_CONFIG,
        broadphase: str = DEFAULT_BROADPHASE,
        detector: Detecting | None = None,
        cell: int = DEFAULT_CELL,
        players: int = 1,
    ) -> None:
        if players not in (1, 2):
            raise ValueError(f"players {players!r}: 1 or 2")
        self.config = config
        self.seed = seed
        self._rng: random.Random | None = None  # (made when first drawn from: `rng`)
        self.rules = make_rules(config)
        self.detector: Detecting = detector if detector is not None else Detector(
            make_broadphase(broadphase, cell), self.rules)
        self.store = BodyStore(Kind)
        for edge in edges(config):  # the playfield's, for the world's whole life
            self.store.add(edge)
        self.hi_score = 0
        self.games = 0
        self.aliens_killed = 0
        self.fire_was_down = False
        self.events: list[Event] = []
        self.scoring = True  # False: the attract cycle's demo, which scores nothing
        self._reload: tuple[int, GameConfig | None, int] = (-1, None, 0)  # score, config, steps
        self._new_game(players)

    @property
    def tick(self) -> int:
        """Ticks run so far (the store keeps it: bodies note the tick they moved in)."""
        return self.store.tick

    @property
    def rng(self) -> random.Random:
        """The game's only generator, seeded by the world's seed. The 1978 rules draw nothing
        from chance (the saucer's side is a fixed ROM sequence); a rule that ever needs
        chance draws from this. Made when first asked for, so a world that never draws
        (every game of the 1978 rules) neither seeds nor copies one: the environment's
        clone and restore of a state took 262 against 298 us (9 rounds in turn, fresh
        processes). What it draws is what it would have drawn made at the start, in the
        world and in its copies (tests/test_game.py)."""
        if self._rng is None:
            self._rng = random.Random(self.seed)
        return self._rng

    def kind_counts(self) -> dict[str, int]:
        """Live collidable bodies per kind, by name (what replays compare first)."""
        by_kind = self.store.by_kind
        return {kind.name.lower(): len(by_kind[kind]) for kind in THINGS}

    def __deepcopy__(self, memo: dict[int, Any]) -> World:
        """A world that plays on alone from here (a search tries moves from one state): the
        pictures the game changes in place copied (the shields, the ground, the waiting
        player's shields), its config, rules and every other picture shared (never
        changed)."""
        waiting = self.waiting.shields if self.waiting is not None else []
        for mask in (self.ground, *(b.mask for b in self.bunkers), *self._shields_up,
                     *waiting):
            memo.setdefault(id(mask), mask.copy())
        if self._rng is not None:
            # (seeded by a number, where the system's entropy would cost more; then given
            # the state's 625 numbers at once)
            rng = random.Random(0)
            rng.setstate(self._rng.getstate())
            memo[id(self._rng)] = rng
        memo[id(self.rules)] = self.rules  # (the config's copy is itself: Section)
        cls = type(self)  # (not copy.copy, which would pickle it: `__reduce__`)
        clone = cls.__new__(cls)
        memo[id(self)] = clone
        for name, value in fields(self).items():
            setattr(clone, name, copy.deepcopy(value, memo))
        return clone

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled with its masks (pygame's cannot be): `invaders.engine.pickling`."""
        return reduce_with_masks(self)

    def bodies(self, kind: Kind) -> list[Body]:
        """Live bodies of a kind, in id order."""
        return self.store.by_kind[kind]

    # --- game and wave set-up ------------------------------------------------------------
    def _new_game(self, players: int = 1) -> None:
        self.score = 0
        self.invaded = False
        self.ships = self.config.rules.ships
        self.extra_awarded = False
        self.games += 1
        self.players, self.player = players, 1
        # The rack's step each player's page keeps (2xFB): set going right at a game's start
        # (00D7), saved only when the player leaves for the other's turn (02D7-0329), and taken
        # again at the start of each of their turns and waves (InitRack).
        self.kept_dx = self.config.speeds.rack_step
        # The player waiting for a turn (player 2 starts on a fresh wave 1), or None.
        self.waiting = Turn(2, 0, self.ships, False, 1, None) if players == 2 else None
        self._shields_up: list[pygame.mask.Mask] = []  # the player up's, while PLAY PLAYER<n>
        self._start_wave(1)

    def _start_wave(self, wave: int) -> None:
        """A new rack on a cleared field, with fresh shields and the ground line drawn afresh
        (a cleared wave goes back to 0804, which draws it: 0A30, 0A39)."""
        self.wave = wave
        self.ground = art.fresh_mask(art.GROUND)
        rack = Rack(self.config, self.config.start_top(wave), self.store)
        rack.set_step(self.kept_dx)
        self._set_field(rack, None)
        self.events.append(Event.WAVE_STARTED)

    def _set_field(self, rack: Rack, shields: list[pygame.mask.Mask] | None) -> None:
        """A cleared field with this rack and these shields (fresh ones for None), the
        cannon waiting at the left, no shot, bomb or saucer."""
        cfg = self.config
        g = cfg.geometry
        store = self.store
        self._clear_field()
        self.phase = PLAYING
        self.phase_timer = 0
        self.rack = rack
        self.bunkers = [Bunker(store.new_id(), x, g.bunker_top) for x in g.bunker_xs]
        for bunker, mask in zip(self.bunkers, shields or (), strict=False):
            bunker.mask = mask
        self.erosions = 0  # how many times a shield lost pixels this wave (for observers)
        for bunker in self.bunkers:
            store.add(bunker)
        self.cannon = Cannon(store.new_id(), g.cannon_min_x, g.cannon_top)
        self.cannon.alive = False
        self._cannon_wait()
        self.shot: Shot | None = None
        self.slots = bombs.new_slots()
        self.saucer = saucer.SaucerState(timer=cfg.timing.saucer_timer)
        self.shots_removed = 0
        self.shot_wait = 0  # ticks before the shot's object takes a new shot (`_shot_busy`)
        self.explosions: list[Explosion] = []

    def _clear_field(self) -> None:
        """Every thing out of the store (the playfield's edges stay)."""
        for kind in THINGS:
            for body in list(self.store.by_kind[kind]):
                self.store.remove(body)

    def _cannon_wait(self) -> None:
        self.respawning = False  # a wave's start (a death sets it after this)
        self.cannon.state = WAITING
        self.cannon.timer = self.config.timing.cannon_wait
        self.store.place(self.cannon, self.config.geometry.cannon_min_x, self.cannon.y)
        self.alien_fire_timer = -1  # alien fire is off until the cannon is active

    # --- one tick ------------------------------------------------------------------------
    def step(self, actions: int = 0) -> TickReport:
        """Advance one tick with this tick's input bits; return what happened."""
        fire_down = bool(actions & FIRE)
        fire_pressed = fire_down and not self.fire_was_down
        self.fire_was_down = fire_down
        if self.explosions:
            self._age_explosions()
        if self.shot_wait:
            self.shot_wait -= 1
        if self.phase is PLAYING:
            self._move(actions, fire_pressed)
        elif self.phase is WAVE_END:
            # During the pause after a cleared wave the cannon and the bombs still in the air
            # keep running (0A3C: the interrupts' objects); nothing new is fired from an
            # empty rack, nor by the player, whose fire the game loop reads (1618), not the
            # interrupts. (No shot flies: the last kill's is spent.)
            self._move_cannon(actions, False)
            if self.phase is WAVE_END:  # (not if the last ship was lost just now)
                self._projectile_turn()
                self.phase_timer -= 1
                # A cannon hit in the pause, or on the tick of the last kill, explodes to
                # the end and costs its ship before the next wave starts (0A3C-0A58).
                if self.phase_timer <= 0 and self.cannon.state is not EXPLODING:
                    self._start_wave(self.wave + 1)
        elif self.phase is GAME_OVER:
            self.phase_timer -= 1
            if self.phase_timer <= 0 and actions & (START | START2):
                self._new_game(2 if actions & START2 else 1)
                self.events.append(Event.NEW_GAME)
        elif self.phase is SWITCH:
            self.phase_timer -= 1
            if self.phase_timer == PROMPT:
                self._change_players()
            elif self.phase_timer <= 0:
                self._resume_turn()
        store = self.store
        contacts, stats = self.detector.detect(store)
        applied = respond(contacts, store.by_id, self) if contacts else ()
        if not self.rack.live:
            self._settle()
        broadphase = self.detector.broadphase
        events = self.events
        # Made every tick, from its fields in order, without the call to its constructor;
        # tuple.__new__ checks nothing, so `tests/test_game.py` holds every report of whole
        # games to the full set of fields, each of its type.
        report = tuple.__new__(TickReport, (store.tick, stats, tuple(events) if events else (),
                                            tuple(applied), broadphase.name, broadphase.cell))
        if events:  # events of set-up (the first wave) go out with tick 0's report
            self.events = []
        store.tick += 1
        return report

    def _move(self, actions: int, fire_pressed: bool) -> None:
        self._move_shot()
        self._move_cannon(actions, fire_pressed)
        # The rack marches while the player is OK (`player_ok`); a kill holds it
        # (`kill_alien`).
        cannon_state = self.cannon.state
        if not self.rack.spend_held() and self.player_ok:
            alien = self.rack.step(self.store)
            if alien is not None and alien.top >= self.config.geometry.invasion_top:
                # The cannon is blown up first, then the game is over (1971 -> 16E6); one
                # blowing up already goes on as it was, and the game ends after it. The
                # frame plays on: the cursor was the mid-screen interrupt's last task, and
                # the bombs' objects run in the next interrupt as in any frame.
                if not self.invaded:
                    self.events.append(Event.INVASION)
                    self.invaded = True
                if cannon_state is not EXPLODING:
                    self.kill_cannon()
        self._projectile_turn()
        saucer.count_down(self.saucer, self.config, self.rack.ref_top)

    def _projectile_turn(self) -> None:
        """The bomb type (or the saucer) whose turn this tick is. The saucer shares the
        squiggly's object: the squiggly's turn is the saucer's while one flies or shows its
        hit, and launching a due saucer takes it, so no squiggly fires meanwhile."""
        turn = self.store.tick % 3
        slot = self.slots[turn]
        if turn == SQUIGGLY and (self.saucer.saucer or self.saucer.hit_steps):
            self._saucer_turn()
        else:
            self._bomb_turn(slot)

    def _move_cannon(self, actions: int, fire_pressed: bool) -> None:
        cannon = self.cannon
        g = self.config.geometry
        if cannon.state is WAITING:
            cannon.timer -= 1
            if cannon.timer <= 0:
                cannon.state = ACTIVE
                self.store.add(cannon)
                self.alien_fire_timer = self.config.timing.alien_fire_delay
            return
        if cannon.state is EXPLODING:
            self._blow_up()
            if cannon.timer <= 0:
                if not self.invaded:  # the rack landed: no ship is lost, the game is over
                    self.ships -= 1
                    self.events.append(Event.SHIP_LOST)
                if self.waiting is not None and not self.waiting.out:
                    self._hold_for_the_other_player()
                elif self.out:
                    self._game_over()
                else:
                    self._cannon_wait()
                    self.respawning = True
                    for slot in self.slots:
                        slot.skip_next = slot.btype is ROLLING
            return
        if self.alien_fire_timer > 0:
            self.alien_fire_timer -= 1
        if actions & MOVES:
            dx = (1 if actions & RIGHT else 0) - (1 if actions & LEFT else 0)
            x = cannon.x + dx * self.config.speeds.cannon
            if x < g.cannon_min_x:
                x = g.cannon_min_x
            elif x > g.cannon_max_x:
                x = g.cannon_max_x
            if x != cannon.x:
                self.store.move(cannon, x, cannon.y)
        if fire_pressed and self.shot_ready:
            self.shot = Shot(self.store.new_id(), cannon.x + g.cannon_centre, g.shot_spawn_top)
            self.store.add(self.shot)
            self.events.append(Event.SHOT_FIRED)

    def _move_shot(self) -> None:
        """Up by its speed: reaching the top limit is a contact (with the TOP edge)."""
        shot = self.shot
        if shot is not None:
            self.store.move(shot, shot.x, shot.y - self.config.speeds.shot)

    def _bomb_turn(self, slot: bombs.BombSlot) -> None:
        cfg = self.config
        if slot.bomb is not None:
            fast = self.rack.live <= cfg.speeds.bomb_fast_at
            # Reaching the ground is a contact (with the GROUND edge).
            bombs.advance(slot, cfg.speeds.bomb_fast if fast else cfg.speeds.bomb, self.store)
            return
        if slot.burst > 0:
            slot.burst -= 1  # the step counter stands still during a burst (05CA)
            if slot.burst == 0:
                self._bomb_done(slot)
            return
        if slot.skip_next:  # spent on the rolling bomb's very next turn, whatever else (047D)
            slot.skip_next = False
            return
        if slot.btype is SQUIGGLY and self.saucer.due:
            if self.rack.live >= cfg.rules.saucer_min_aliens:
                saucer.launch(self.saucer, self.store, cfg)
                self.events.append(Event.SAUCER_LAUNCHED)
            else:
                self.saucer.due = False
            return
        self._try_fire(slot)

    def _try_fire(self, slot: bombs.BombSlot) -> None:
        cfg = self.config
        # Alien fire does not look at an alien's explosion (0563-05C0): only the rack waits.
        if self.alien_fire_timer != 0 or self.rack.live == 0:
            return
        if slot.off:
            return
        reload = self._reload
        if reload[0] != self.score or reload[1] is not cfg:  # kept: asked nearly every tick
            reload = self._reload = (self.score, cfg, cfg.reload_steps_for(self.score))
        if not bombs.reload_ready(self.slots, slot, reload[2]):
            return
        col = bombs.choose_column(slot, cfg, self.cannon.x + cfg.geometry.cannon_centre,
                                  self.rack)
        if col is not None and bombs.spawn(slot, self.rack, col, self.store,
                                           cfg.geometry.bomb_drop_offset) is not None:
            self.events.append(Event.BOMB_FIRED)

    def bomb_hits_ground(self, bomb: Bomb) -> None:
        """A bomb at the bottom bursts on the ground line and chips it."""
        slot = self.slots[bomb.btype]
        g = self.config.geometry
        dx, dy = g.ground_burst_offset
        x, y = bomb.x + dx, g.ground_row + dy
        self.ground.erase(art.mask_of(art.BOMB_BURST), (x, y - g.ground_row))
        self.store.remove(bomb)
        bombs.start_burst(slot, x, y, self.config.timing.bomb_burst_steps)
        self.events.append(Event.BOMB_BURST)

    def _saucer_turn(self) -> None:
        state = self.saucer
        if state.hit_steps > 0:
            state.hit_steps -= 1
            if state.hit_steps == self.config.timing.saucer_score_at:
                self.add_score(state.hit_score)
                self.events.append(Event.SAUCER_SCORED)
            if state.hit_steps == 0:  # the saucer's object is set afresh (06F9-0704)
                state.from_left = True
        elif state.saucer is not None:
            saucer.fly(state, self.store, self.config)

    def _age_explosions(self) -> None:
        for explosion in self.explosions:
            explosion.ttl -= 1
        self.explosions = [e for e in self.explosions if e.ttl > 0]

    # --- state the rules ask about ---------------------------------------------------------
    @property
    def shot_ready(self) -> bool:
        """The shot's object is free: the fire button would fire now."""
        return self.shot is None and self.shot_wait == 0

    # --- outcomes, called by movement and by collision response -----------------------------
    def add_score(self, points: int) -> None:
        """Points in the ROM's four BCD digits: 9990 + 10 is 0000. None in the attract
        cycle's demo (0A62: no score outside a game)."""
        if not self.scoring:
            return
        self.score = (self.score + points) % SCORE_WRAP
        if not self.extra_awarded and self.score >= self.config.rules.extra_ship_at:
            self.extra_awarded = True
            self.ships += 1
            self.events.append(Event.EXTRA_SHIP)

    def remove_shot(self) -> None:
        """Every removal of the player shot counts for the saucer's score and side."""
        if self.shot is None:
            return
        self._shot_busy(1, self.shot.x)
        self.store.remove(self.shot)
        self.shot = None
        self.shots_removed += 1
        # The count is read for the side only while no saucer flies or shows its hit
        # (the ROM keeps the side of a saucer on screen: 0462-046B).
        if self.saucer.saucer is None and self.saucer.hit_steps == 0:
            self.saucer.from_left = saucer.from_left_after(self.shots_removed)

    def burst_shot(self, x: int, top: int) -> None:
        """The shot bursts with its 8x8 picture at `shot_burst_offset` from (x, top), (-3, -2),
        punching shields under it.

        The shot's 1x8 box has its 4 lit rows at the bottom (ROM 1C90: 0x0F), so `top - 2` is
        the original's Yr - 2 for the box (03DF-03F7). UNCERTAIN: a second reading of the
        listing put this burst 1 px off; ours gives this place, so we keep it.
        """
        self.remove_shot()
        self._shot_busy(self.config.timing.shot_burst, x)
        dx, dy = self.config.geometry.shot_burst_offset
        corner = (x + dx, top + dy)
        self.erode(art.mask_of(art.SHOT_BURST), *corner)
        self.explosions.append(Explosion(Blast.SHOT, *corner, self.config.timing.shot_burst))
        self.events.append(Event.SHOT_BURST)

    def _shot_busy(self, ticks: int, x: int) -> None:
        """The shot's object, whose shot ended at column `x` this tick, takes a new one
        `ticks` ticks from now: after its burst, or an alien's explosion, or next tick. One
        more left of MID_SCREEN_X: there the object is freed in the mid-screen interrupt,
        and a new shot, its column set back to 0x30 when freed (1B2A, 0436), starts in the
        mid-screen interrupt after the next reading of the fire button (1618)."""
        self.shot_wait = ticks + (x < MID_SCREEN_X)

    def burst_bomb(self, bomb: Bomb, x: int, y: int) -> None:
        """A bomb bursts with its 6x8 picture at `bomb_burst_offset` from (x, y), (-2, 2),
        punching shields under it."""
        slot = self.slots[bomb.btype]
        self.store.remove(bomb)
        dx, dy = self.config.geometry.bomb_burst_offset
        corner = (x + dx, y + dy)
        self.erode(art.mask_of(art.BOMB_BURST), *corner)
        bombs.start_burst(slot, *corner, self.config.timing.bomb_burst_steps)
        self.events.append(Event.BOMB_BURST)

    def _bomb_done(self, slot: bombs.BombSlot) -> None:
        """A bomb's object is set afresh: a plunger's that finishes with one alien left is
        switched off for the rest of the wave (04FC-0505), so an idle plunger may still fire
        once after the count drops."""
        if slot.btype is PLUNGER and self.rack.live < self.config.rules.plunger_min_aliens:
            slot.off = True

    def kill_alien(self, alien: Alien, shot_x: int) -> None:
        """Killed by the shot at column `shot_x`. The cursor holds through the explosion:
        its countdown takes the draw of every tick it runs, the tick it ends included
        (1538). A shot left of MID_SCREEN_X runs in the mid-screen interrupt, just before
        the cursor is set on the next alien (00A8, 00AB): if that is the one killed, one
        more tick's draw is spent on its empty place (0100)."""
        rack = self.rack
        on_the_cursor = shot_x < MID_SCREEN_X and alien.index == rack.next_index()
        rack.kill(alien, self.store)
        rack.hold(self.config.timing.alien_explosion + on_the_cursor)
        self._shot_busy(self.config.timing.alien_explosion, shot_x)  # (1512, 1626)
        self.aliens_killed += 1
        self.add_score(self.config.rules.alien_points[alien.row])
        self.explosions.append(
            Explosion(Blast.ALIEN, alien.x, alien.top, self.config.timing.alien_explosion))
        self.events.append(Event.ALIEN_KILLED)

    def kill_cannon(self) -> None:
        """The cannon is hit: it blows up where it stands, its picture held through the
        blow-up delay, then its debris (`_blow_up`); it stays in the store till then."""
        cannon = self.cannon
        if self.store.by_id.get(cannon.id) is not cannon:  # (a landing in a wave's wait)
            self.store.add(cannon)
        cannon.state = EXPLODING
        cannon.timer = self.config.timing.cannon_death
        cannon.next_debris = 1
        self.events.append(Event.CANNON_HIT)

    def hit_debris(self) -> None:
        """A bomb met the blowing-up cannon: the ROM flags the player struck again (060F),
        zeroing the sprite number its debris toggles, so the next change shows @1C80."""
        self.cannon.next_debris = 1

    def _blow_up(self) -> None:
        """A tick of the cannon's death (0296-02B3): the blow-up delay ending stops alien
        fire (029E); every `cannon_death_swap` ticks the next debris picture is drawn, and
        at the end the cannon leaves the store, its own picture back for the next one."""
        cannon, timing, store = self.cannon, self.config.timing, self.store
        cannon.timer -= 1
        if not self.blowing_up and self.alien_fire_timer != -1:
            self.alien_fire_timer = -1  # the delay ran out: alien fire stops (029E)
        if cannon.timer <= 0:
            store.remove(cannon)
            cannon.mask, cannon.debris = CANNON_MASK, -1  # (out of the store: no reshape)
        elif (timing.cannon_death - cannon.timer) % timing.cannon_death_swap == 0:
            cannon.debris, cannon.next_debris = cannon.next_debris, 1 - cannon.next_debris
            store.reshape(cannon, DEBRIS_MASKS[cannon.debris])

    @property
    def player_ok(self) -> bool:
        """The ROM's playerOK (2068), which the rack's cursor (0141) and the fleet's sound
        (1747) wait on: set while the cannon plays (its object sets it, 033B) and through
        its wait at a wave's start; cleared when a hit cannon's blow-up delay runs out
        (029B) until the next cannon plays, so through the rest of its death and the wait
        after it."""
        state = self.cannon.state
        return state is ACTIVE or (state is WAITING and not self.respawning) or (
            self.blowing_up)

    @property
    def blowing_up(self) -> bool:
        """A hit cannon's blow-up delay runs: the frames after the hit up to its first
        debris. The ROM's player object counts the delay (5) down once a frame and only
        when it runs out sets playerOK and alien fire's enable to 0 (0296-02A3), so the
        rack marches on through them (its cursor stops on playerOK, 0141) and bombs are
        fired as before (the ROM clears the enable in the second half of the last frame,
        a half our tick does not make)."""
        cannon = self.cannon
        timing = self.config.timing
        return cannon.state is EXPLODING and (
            cannon.timer >= timing.cannon_death - timing.cannon_death_swap)

    def hit_saucer(self) -> None:
        state = self.saucer
        ship = state.saucer
        assert ship is not None
        self.store.remove(ship)
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
                self.erosions += 1

    def _settle(self) -> None:
        """After response, with the rack empty: the wave ends."""
        if self.phase is PLAYING:
            self.phase = WAVE_END
            self.phase_timer = self.config.timing.wave_pause
            self.events.append(Event.WAVE_CLEARED)

    # --- two players ------------------------------------------------------------------------
    @property
    def out(self) -> bool:
        """The player up has no ships left, or the rack landed on them."""
        return self.invaded or self.ships <= 0

    def scores(self) -> tuple[int, int | None]:
        """Player 1's and player 2's scores (None for player 2 in a one-player game)."""
        if self.waiting is None:
            return self.score, None
        other = self.waiting.score
        return (self.score, other) if self.player == 1 else (other, self.score)

    def _hold_for_the_other_player(self) -> None:
        """A death with the other player still in: the field stays as it is, then it is the
        other's turn (02D7-0329); one whose last ship it was is out (GAME OVER PLAYER<n>)."""
        self.phase = SWITCH
        self.phase_timer = SWITCH_TICKS
        if self.out:
            self.hi_score = max(self.hi_score, self.score)

    def _change_players(self) -> None:
        """The field cleared and the other player up: their score, ships and wave now,
        their rack and shields when the prompt ends."""
        waiting = self.waiting
        assert waiting is not None
        self.waiting = Turn(self.player, self.score, self.ships, self.extra_awarded, self.wave,
                            self.rack, [bunker.mask for bunker in self.bunkers], out=self.out)
        self._clear_field()
        self.rack.hide()
        self.shot, self.slots, self.explosions, self.bunkers = None, bombs.new_slots(), [], []
        self.saucer = saucer.SaucerState(timer=self.config.timing.saucer_timer)
        self.player, self.score, self.ships = waiting.number, waiting.score, waiting.ships
        self.extra_awarded, self.wave, self.invaded = waiting.extra_awarded, waiting.wave, False
        # (the step they left with is their rack's: it stood still while they waited)
        self.kept_dx = self.config.speeds.rack_step if waiting.rack is None else waiting.rack.dx
        self.rack = waiting.rack or Rack(self.config, self.config.start_top(self.wave),
                                         self.store)
        self._shields_up = waiting.shields
        self.ground = art.fresh_mask(art.GROUND)  # the bottom line drawn afresh (0804)
        self.events.append(Event.PLAYER_UP)

    def _resume_turn(self) -> None:
        """The player up's own shields back and their rack drawn again one alien a tick,
        the cannon ready at once (0318)."""
        self._set_field(self.rack, self._shields_up or None)
        self.rack.set_step(self.kept_dx)
        self._shields_up = []
        self.cannon.state = ACTIVE
        self.store.add(self.cannon)
        self.alien_fire_timer = self.config.timing.alien_fire_delay
        self.events.append(Event.TURN_STARTED)

    def _game_over(self) -> None:
        self.phase = GAME_OVER
        self.phase_timer = self.config.timing.game_over_pause
        self.hi_score = max(self.hi_score, self.score)
        self.remove_shot()  # (the cannon is out of the store already: its death ended)
        for slot in self.slots:
            if slot.bomb is not None:
                self.store.remove(slot.bomb)
                slot.bomb = None
            slot.burst = 0
        self.events.append(Event.GAME_OVER)

    # --- the state, for replays and determinism tests ------------------------------------
    def state_groups(self) -> dict[str, object]:
        """Everything that decides the game's future as plain values, group by group (the
        groups statehash.GROUPS names), in a fixed order."""
        rack = self.rack
        cannon = self.cannon
        shot = self.shot
        ship = self.saucer
        groups: dict[str, Any] = {
            "game": (self.seed, self.tick, int(self.phase), self.phase_timer, self.score,
                     self.hi_score, self.ships, self.extra_awarded, self.wave, self.games,
                     self.fire_was_down, self.alien_fire_timer, self.shots_removed,
                     self.store.next_id, self.invaded, self.respawning),
            "rack": (rack.ref_x, rack.ref_top, rack.dx, rack.frame, rack.cursor, rack.live,
                     tuple((a.id, a.x, a.y, a.frame, a.alive) if a is not None else None
                           for a in rack.aliens))
                    # (held only when it is: a state with none hashes as it did before)
                    + ((rack.held,) if rack.held else ()),
            "cannon": (int(cannon.state), cannon.timer, cannon.x, cannon.y)
                      # (its debris only while it blows up: other states hash as before)
                      + ((cannon.debris, cannon.next_debris) if cannon.state is EXPLODING
                         else ()),
            "shot": None if shot is None else (shot.id, shot.x, shot.y),
            "bombs": tuple((int(s.btype), s.steps, s.burst, s.burst_x, s.burst_y,
                            s.table_index, s.skip_next, s.off,
                            None if s.bomb is None else (s.bomb.id, s.bomb.x, s.bomb.y,
                                                         s.bomb.frame))
                           for s in self.slots),
            "saucer": (ship.timer, ship.due, ship.hit_steps, ship.hit_x, ship.hit_score,
                       ship.from_left,
                       None if ship.saucer is None else (ship.saucer.id, ship.saucer.x,
                                                         ship.saucer.dx)),
            "shields": b"".join(mask_bytes(b.mask) for b in self.bunkers),
            "ground": mask_bytes(self.ground),
            "explosions": tuple((e.blast.value, e.x, e.y, e.ttl) for e in self.explosions),
        }
        if not self.scoring:
            groups["game"] += ("demo",)
        if self.shot_wait:  # (only while the shot's object waits, as the held rack)
            groups["shot"] = (groups["shot"], "wait", self.shot_wait)
        if self.waiting is not None:  # (a one-player game's groups are as they always were)
            groups["game"] += (self.player, self.waiting.state(),
                               b"".join(mask_bytes(m) for m in self._shields_up))
            # (only a step kept other than the first, so that a state with none hashes as it
            # did before the step was kept)
            if self.kept_dx != self.config.speeds.rack_step:
                groups["game"] += ("kept step", self.kept_dx)
        if self._rng is not None:  # (drawn from: no 1978 rule does, so hashes are as they were)
            groups["game"] += (self._rng.getstate(),)
        return groups

    def group_hashes(self) -> dict[str, str]:
        """A short digest per state group."""
        return statehash.group_hashes(self.state_groups())

    def state_hash(self) -> str:
        """Hex digest of everything that decides the game's future."""
        return statehash.combine(self.group_hashes())
