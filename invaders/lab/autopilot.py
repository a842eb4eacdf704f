"""A deterministic player for headless runs: aims, shoots, dodges bombs, and sometimes fails.

It reads the world and returns input bits, like a keyboard would; it never writes the world.
Its own generator (seeded from the run's seed) makes it imperfect in a repeatable way, so
headless games see every kind of collision: kills, shield hits, saucer hits, shot-bomb
meetings, bombs on shields and on the cannon, deaths, respawns, waves and game over.
"""

from __future__ import annotations

import random

from invaders.engine.predicates import solid_mask
from invaders.game.actions import Action
from invaders.game.config import Speeds
from invaders.game.rack import Rack
from invaders.game.world import ACTIVE, GAME_OVER, World
from invaders.lab.styles import STYLES

DODGE_LOOKAHEAD_TICKS = 45  # bombs further than this from the cannon's rows are ignored
CANNON_LIT = (2, 14)  # first and last lit column of the cannon's 16-px box
DODGE_MARGIN = 2  # columns of room kept between a bomb and the cannon
SHOT_TICKS_TO_LANE = 42  # ticks the shot needs from the barrel to the saucer lane
INF = float("inf")
MOVES_IN_ORDER = {-1: (-1, 0, 1), 0: (0, -1, 1), 1: (1, 0, -1)}  # the wish, stay, the rest
# Plain ints: flag arithmetic on the enum costs more than the rest of a quiet tick.
LEFT, RIGHT, FIRE, START = (int(Action.LEFT), int(Action.RIGHT), int(Action.FIRE),
                            int(Action.START))
START2 = int(Action.START2)




def corridor(world: World) -> int:
    """The rack column a defender clears: the middle one."""
    return world.config.geometry.cols // 2


def target_columns(world: World, which: str) -> range | tuple[int, ...]:
    if which == "all":
        return range(world.config.geometry.cols)
    return (corridor(world),) if which == "middle" else ()


class Autopilot:
    """`actions(world)` -> this tick's input bits.

    Styles: "hunter" shoots the lowest aliens and misses some bombs; "expert" dodges better
    and keeps the shot that would score 300 for the saucer (the table's 8th of every 15);
    "defender" clears one column and then hides under the gap it made (no bomb falls from an
    empty column), so the rest of the rack comes down and invades; "pacifist" only dodges.
    """

    def __init__(self, seed: int, style: str = "hunter") -> None:
        if style not in STYLES:
            raise ValueError(f"unknown autopilot style {style!r} (choose from {', '.join(STYLES)})")
        self.rng = random.Random(f"autopilot:{style}:{seed}" if style != "hunter"
                                 else f"autopilot:{seed}")
        self.style = style
        self.skill, self.columns, self.saucer_trick = STYLES[style]
        self._fire_held = False
        self._noticed: dict[int, bool] = {}
        self._wander = 0
        self._wander_dir = 0
        self._through_shields = False  # re-rolled at each shot: now and then shoot a shield
        self._shields = ShieldColumns()
        self._target_tick = -1
        self._target: int | None = None
        self._has_targets = False
        self._columns = ShooterColumns()
        # the bombs' speeds last seen, and per tick: (fast from, fast, slow)
        self._speeds: Speeds | None = None
        self._per_tick = (0, 0.0, 0.0)

    def actions(self, world: World) -> int:
        if world.phase is GAME_OVER:
            return (START2 if world.players == 2 else START) if world.tick % 30 == 0 else 0
        cannon = world.cannon
        if cannon.state is not ACTIVE:
            return 0
        centre = cannon.x + world.config.geometry.cannon_centre
        # The steps of a tick, the usual cases inlined (calls cost more than most of them).
        target = None
        if self._wander > 0:  # drifting for a while, so games differ by seed
            self._wander -= 1
            wish = self._wander_dir
        else:
            if self.rng.random() < 0.004:
                self._wander = self.rng.randint(10, 60)
                self._wander_dir = self.rng.choice((-1, 1))
            tick = world.store.tick  # approach the target (self._target_x, inlined)
            if self._target_tick != tick:
                self._target_tick = tick
                self._target = self._find_target(world)
            target = self._target
            if target is None or -1 <= target - centre <= 1:
                wish = 0
            else:
                wish = 1 if target > centre else -1
        threats = self._threats(world)
        move = self._choose(world, threats, wish) if threats else wish
        bits = LEFT if move < 0 else RIGHT if move > 0 else 0
        fire = (not self._fire_held and world.shot is None
                and self._want_fire(world, centre, target))
        self._fire_held = fire
        return bits | FIRE if fire else bits

    def _threats(self, world: World) -> list[tuple[int, int, float, float]]:
        """Noticed bombs as (first lit column, last, ticks until they reach the cannon's
        rows, ticks until they have passed them)."""
        cannon = world.cannon
        speeds = world.config.speeds
        if speeds is not self._speeds:
            self._speeds = speeds
            self._per_tick = (speeds.bomb_fast_at, speeds.bomb_fast / 3, speeds.bomb / 3)
        fast_at, fast, slow = self._per_tick
        per_tick = fast if world.rack.live <= fast_at else slow
        top = cannon.y
        bottom = top + cannon.h
        noticed_ids = self._noticed
        threats = []
        for slot in world.slots:
            bomb = slot.bomb
            if bomb is None:
                continue
            noticed = noticed_ids.get(bomb.id)
            if noticed is None:  # seen for the first time: noticed or not, once for all
                noticed = noticed_ids[bomb.id] = self.rng.random() < self.skill
            if not noticed:
                continue
            y = bomb.y
            if y >= bottom:
                continue
            # Bombs jump a whole step every third tick: arrive a step early, leave a step late,
            # and a column of margin either side.
            arrive = (top - (y + bomb.h)) / per_tick - 3
            if arrive < 0.0:
                arrive = 0.0
            elif arrive > DODGE_LOOKAHEAD_TICKS:
                continue
            leave = (bottom - y) / per_tick + 3
            threats.append((bomb.x - DODGE_MARGIN, bomb.x + bomb.w - 1 + DODGE_MARGIN,
                            arrive, leave))
        if len(self._noticed) > 64:
            live = {s.bomb.id for s in world.slots if s.bomb is not None}
            self._noticed = {k: v for k, v in self._noticed.items() if k in live}
        return threats

    def _choose(self, world: World, threats, wish: int) -> int:
        """The wished move if it stays clear of every noticed bomb; else the safest move:
        the one whose first hit, holding it, comes latest."""
        g = world.config.geometry
        low, high = g.cannon_min_x, g.cannon_max_x
        x0 = world.cannon.x
        lit_left, lit_right = CANNON_LIT
        best, latest = wish, -1.0
        for d in MOVES_IN_ORDER[wish]:
            first = INF  # ticks until a threat would hit the cannon holding d
            for left, right, arrive, leave in threats:
                xa = x0 + d * int(arrive)
                xa = low if xa < low else high if xa > high else xa
                xb = x0 + d * int(leave + 1)
                xb = low if xb < low else high if xb > high else xb
                if xa > xb:
                    xa, xb = xb, xa
                if left <= xb + lit_right and xa + lit_left <= right and arrive < first:
                    first = arrive
            if first == INF:
                return d
            if first > latest:  # ties: the earlier option, as the order says
                best, latest = d, first
        return best

    def _target_x(self, world: World) -> int | None:
        """Where to put the cannon's centre this tick (worked out once per tick)."""
        tick = world.store.tick
        if self._target_tick != tick:
            self._target_tick = tick
            self._target = self._find_target(world)
        return self._target

    def _find_target(self, world: World) -> int | None:
        targets = self._columns.shooters(world, self.columns)  # the lowest of each column
        self._has_targets = bool(targets)
        if not targets:
            return _hiding_place(world)
        ship = world.saucer.saucer
        if ship is not None:
            lead = ship.dx * SHOT_TICKS_TO_LANE // 3
            return ship.x + 12 + lead
        # The first alien, in column order, that is least (not under a shield, lowest, then
        # nearest the cannon): those in the clear first, and only if none is, all of them
        # (the comparison written out, as tuples cost more).
        # Alien and cannon alike by the left edge of their 16-px boxes (centres less 8).
        shaded = frozenset() if self._through_shields else self._shields.edges(world)
        cannon_x = world.cannon.x
        for anywhere in (False, True):
            best_x = None
            best_y = -1  # the lowest has the largest y (its footprint's top)
            best_dist = 0
            for alien in targets:
                x = alien.x
                if x in shaded and not anywhere:
                    continue
                y = alien.y
                if y < best_y:
                    continue
                dist = x - cannon_x if x > cannon_x else cannon_x - x
                if y > best_y or dist < best_dist:
                    best_x, best_y, best_dist = x, y, dist
            if best_x is not None:
                return best_x + world.config.geometry.cell // 2  # its centre
        return None

    def _want_fire(self, world: World, centre: int, target: int | None) -> bool:
        """Whether to press fire, the shot being free and not held down last tick (`target`:
        this tick's, if worked out already)."""
        if target is None:
            target = self._target_x(world)
        if target is None or not self._has_targets:
            return False  # nothing it is willing to shoot at: it is hiding
        # The next shot would score 300 on the saucer: keep it for the saucer, and fire it
        # only up a column that no alien or shield blocks.
        if self.saucer_trick and world.shots_removed % 15 == 7 and (
                world.saucer.saucer is None or not self._clear_column(world, centre)):
            return False
        if not self._through_shields and (centre - world.config.geometry.cannon_centre
                                          in self._shields.edges(world)):
            return False
        fire = abs(target - centre) <= 3 or self.rng.random() < 0.02
        if fire:
            self._through_shields = self.rng.random() < 0.15
        return fire

    def _clear_column(self, world: World, x: int) -> bool:
        """Whether a shot fired up column x would meet neither an alien nor a shield."""
        if self._shields.covers(world, x):
            return False
        return all(not alien.x <= x < alien.x + alien.w for alien in world.rack.live_aliens())


class ShooterColumns:
    """The lowest alien of each column, worked out again only when the rack loses one (a
    column's lowest changes only then) or a new rack comes."""

    def __init__(self) -> None:
        self._rack: Rack | None = None
        self._live = -1
        self._which = ""
        self._found: list = []

    def shooters(self, world: World, which: str) -> list:
        rack = world.rack
        if rack is not self._rack or rack.live != self._live or which != self._which:
            self._rack, self._live, self._which = rack, rack.live, which
            found = (rack.lowest_in_column(col) for col in target_columns(world, which))
            self._found = [alien for alien in found if alien is not None]
        return self._found


class ShieldColumns:
    """Which screen columns still have shield pixels, recomputed only when a shield changes
    (the wave's shields, or their wear as the world counts it)."""

    def __init__(self) -> None:
        self._seen: dict[int, tuple[int, frozenset[int]]] = {}
        self._key: tuple = (None, -1)  # the shields and their wear last seen
        self._lit: frozenset[int] = frozenset()
        self._edges: frozenset[int] = frozenset()

    def covers(self, world: World, x: int) -> bool:
        return x in self.lit(world)

    def lit(self, world: World) -> frozenset[int]:
        """Every screen column a shield still covers."""
        self.edges(world)
        return self._lit

    def edges(self, world: World) -> frozenset[int]:
        """The left edges of the 16-px boxes (an alien's, the cannon's) whose centre column
        a shield covers: the columns less the cannon's centre, as the autopilot compares
        boxes."""
        if world.erosions != self._key[1] or world.bunkers is not self._key[0]:
            if world.bunkers is not self._key[0]:  # a new wave's shields: forget the old
                ids = {bunker.id for bunker in world.bunkers}
                self._seen = {i: seen for i, seen in self._seen.items() if i in ids}
            self._key = (world.bunkers, world.erosions)
            self._lit = self._all_columns(world)
            centre = world.config.geometry.cannon_centre
            self._edges = frozenset(x - centre for x in self._lit)
        return self._edges

    def _all_columns(self, world: World) -> frozenset[int]:
        """Lit columns, each judged by the first shield whose box spans it."""
        spanned: set[int] = set()
        lit: set[int] = set()
        for bunker in world.bunkers:
            span = range(bunker.x, bunker.x + bunker.w)
            lit |= self._columns(bunker).difference(spanned)
            spanned.update(span)
        return frozenset(lit)

    def _columns(self, bunker) -> frozenset[int]:
        count = bunker.mask.count()
        seen = self._seen.get(bunker.id)
        if seen is None or seen[0] != count:
            # A column is lit if a one-pixel-wide bar down it meets the mask.
            bar = solid_mask(1, bunker.h)
            lit = frozenset(bunker.x + cx for cx in range(bunker.w)
                            if bunker.mask.overlap(bar, (cx, 0)) is not None)
            seen = self._seen[bunker.id] = (count, lit)
        return seen[1]


def _hiding_place(world: World) -> int:
    """Where a cannon that no longer fires is safest: under an emptied column of the rack if
    there is one (nothing falls from it), else beside the rack, on the side it is not."""
    g = world.config.geometry
    aliens = world.rack.live_aliens()
    middle = corridor(world)
    if aliens and world.rack.lowest_in_column(middle) is None:
        x = world.rack.ref_x + g.cell * middle + g.cell // 2
        if g.cannon_min_x + g.cannon_centre <= x <= g.cannon_max_x + g.cannon_centre:
            return x
    left = min((a.x for a in aliens), default=g.cannon_min_x)
    right = max((a.x + a.w for a in aliens), default=g.cannon_max_x)
    room_left, room_right = left - g.cannon_min_x, g.cannon_max_x + 16 - right
    if room_right >= room_left:
        return g.cannon_max_x + g.cannon_centre
    return g.cannon_min_x + g.cannon_centre
