"""Game constants, as frozen dataclasses.

Every figure comes from `space_invaders.md` (the reference notes, section numbers in comments),
converted to top-down rows: row = 255 - Yr_up. Positions are integer pixels on the logical
224x256 screen; nothing here is scaled for display.
"""

from __future__ import annotations

from dataclasses import dataclass, field

SCREEN_W = 224
SCREEN_H = 256


@dataclass(frozen=True)
class Geometry:
    """Where things are on the 224x256 screen (reference section 2)."""

    saucer_top: int = 40  # saucer lane, rows 40-47
    rack_left: int = 24  # every wave starts with the reference alien at x=24
    cell: int = 16  # an alien's cell is 16x16
    rows: int = 5
    cols: int = 11
    edge_right: int = 213  # a lit alien pixel in this column while moving right bumps the rack
    edge_left: int = 9
    bunker_xs: tuple[int, ...] = (32, 77, 122, 167)
    bunker_top: int = 192
    cannon_top: int = 216
    cannon_min_x: int = 16
    cannon_max_x: int = 185
    ground_row: int = 239
    shot_spawn_top: int = 212  # lit rows 212-215 at Yr 0x28
    shot_top_limit: int = 36  # at Yr >= 0xD8 the shot bursts at the top
    saucer_lane_h: int = 8  # the saucer meets the shot only inside its lane (Yr >= 0xCE)
    invasion_top: int = 216  # an alien drawn with its top here is in the cannon's rows
    bomb_ground_top: int = 228  # a bomb whose box top reaches this (Yr < 0x15) bursts on the ground


@dataclass(frozen=True)
class Timing:
    """Durations in ticks (1 tick = 1 frame of the original, reference sections 5-12)."""

    cannon_wait: int = 128  # before a new cannon appears or moves
    alien_fire_delay: int = 48  # after the cannon becomes active
    alien_explosion: int = 16  # rack and new fire frozen meanwhile
    shot_burst: int = 16
    bomb_burst_steps: int = 3  # counter 4: drawn at 3, erased at 0
    cannon_death: int = 60  # UNCERTAIN (13.1): we take the code's 12 swaps x 5 frames
    cannon_death_swap: int = 5
    wave_pause: int = 48
    saucer_timer: int = 0x600  # UNCERTAIN (13.4): the value is hex, 1536 frames
    saucer_hit_steps: int = 32  # saucer ticks from hit to clear
    saucer_score_at: int = 24  # the score shows (and is added) at this saucer tick
    saucer_boom_until: int = 24  # the explosion image shows from 31 down to here
    game_over_pause: int = 120  # before START is accepted after a game ends


@dataclass(frozen=True)
class Speeds:
    """Pixels per move (reference sections 4-8)."""

    cannon: int = 1
    shot: int = 4
    bomb: int = 4
    bomb_fast: int = 5  # from the moment 8 or fewer aliens remain (UNCERTAIN 13.3: we take <= 8)
    bomb_fast_at: int = 8
    rack_step: int = 2
    rack_step_last_right: int = 3  # one alien left, moving right
    rack_drop: int = 8
    saucer: int = 2


@dataclass(frozen=True)
class Rules:
    """Rule switches and tables (reference sections 4, 6, 8, 11)."""

    ships: int = 3  # including the one in play (DIP 3-6)
    extra_ship_at: int = 1500  # DIP alternative 1000; awarded once per game
    alien_points: tuple[int, ...] = (10, 10, 20, 20, 30)  # by rack row, bottom first
    # Reference-alien start rows by wave (Yr 0x78, 0x60, 0x50, 0x48 x3, 0x40 x3 -> rows).
    # UNCERTAIN (13.7): after wave 9 we cycle from the wave-2 value, as the code does.
    start_tops: tuple[int, ...] = (128, 152, 168, 176, 176, 176, 184, 184, 184)
    # Reload: a bomb type may fire only if every other live bomb made more than R steps.
    # UNCERTAIN (13.2): the code compares the score's upper BCD digits with <=, so the
    # thresholds are hundreds <= 2, 10, 20, 30 (that is scores below 300, 1100, 2100, 3100).
    reload_hundreds: tuple[int, ...] = (2, 10, 20, 30)
    reload_steps: tuple[int, ...] = (48, 16, 11, 8, 7)
    plunger_columns: tuple[int, ...] = (1, 7, 1, 1, 1, 4, 11, 1, 6, 3, 1, 1, 11, 9, 2, 8)
    squiggly_columns: tuple[int, ...] = (11, 1, 6, 3, 1, 1, 11, 9, 2, 8, 2, 11, 4, 7, 10)
    saucer_scores: tuple[int, ...] = (
        100, 50, 50, 100, 150, 100, 100, 50, 300, 100, 100, 100, 50, 150, 100,
    )
    saucer_min_aliens: int = 8
    plunger_min_aliens: int = 2  # disabled once only one alien remains


@dataclass(frozen=True)
class GameConfig:
    """Everything the simulation needs besides the seed; recorded in replays."""

    geometry: Geometry = field(default_factory=Geometry)
    timing: Timing = field(default_factory=Timing)
    speeds: Speeds = field(default_factory=Speeds)
    rules: Rules = field(default_factory=Rules)
    tick_hz: int = 60

    def reload_steps_for(self, score: int) -> int:
        """Steps every other live bomb must have made before another type may fire."""
        hundreds = score // 100
        for limit, steps in zip(self.rules.reload_hundreds, self.rules.reload_steps, strict=False):
            if hundreds <= limit:
                return steps
        return self.rules.reload_steps[-1]

    def start_top(self, wave: int) -> int:
        """Row of the bottom alien band at the start of `wave` (1-based)."""
        tops = self.rules.start_tops
        if wave <= len(tops):
            return tops[wave - 1]
        cycle = tops[1:]
        return cycle[(wave - 2) % len(cycle)]


DEFAULT_CONFIG = GameConfig()
