"""Game constants, as frozen dataclasses.

Every figure comes from `space_invaders.md` (the reference notes, section numbers in comments),
converted to top-down rows: row = 255 - Yr_up. Positions are integer pixels on the logical
224x256 screen; nothing here is scaled for display.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, is_dataclass
from typing import Any

SCREEN_W = 224
SCREEN_H = 256
PICTURE_ROWS = 5  # the rack rows the art has alien pictures for (art.ALIEN_BY_ROW)


class ConfigError(ValueError):
    """A config value the game cannot honour; the message names the field, value and range."""


def within(default: Any, low: int, high: int, min_len: int = 1, max_len: int = 1) -> Any:
    """A field with its valid range beside its default: every value (every element of a
    tuple, which also has a length range) must lie in low..high."""
    return field(default=default,
                 metadata={"range": (low, high), "length": (min_len, max_len)})


def check_ranges(config: Any, name: str) -> None:
    """Every field of a config dataclass within its declared range (ConfigError if not)."""
    for f in fields(config):
        value = getattr(config, f.name)
        where = f"{name}.{f.name}"
        if is_dataclass(value):
            continue
        low, high = f.metadata.get("range", (None, None))
        if low is None:
            continue
        values = value if isinstance(value, tuple) else (value,)
        if isinstance(value, tuple):
            min_len, max_len = f.metadata["length"]
            if not min_len <= len(value) <= max_len:
                raise ConfigError(f"{where} has {len(value)} values; it takes "
                                  f"{min_len} to {max_len}")
        for item in values:
            if type(item) is not int or not low <= item <= high:
                raise ConfigError(f"{where} = {item!r} is out of range {low}..{high}")


class Section:
    """What the config's dataclasses share: repr, equality and hash written once here, as a
    dataclass's own would work, instead of generated for each (generating them is half of
    this module's import, which every run pays at start-up)."""

    def __repr__(self) -> str:
        section: Any = self  # (a dataclass: every section is one)
        values = ", ".join(f"{f.name}={getattr(self, f.name)!r}" for f in fields(section))
        return f"{type(self).__name__}({values})"

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return _values(self) == _values(other)

    def __hash__(self) -> int:
        return hash(_values(self))

    def __deepcopy__(self, memo: dict[int, Any]) -> Section:
        """Itself: a section is frozen and holds only whole numbers, tuples of them and
        other sections (every other field declares a range, whose check refuses anything
        else: tests/test_config.py), so a copy could never differ. A recorded episode's
        state cloned and restored (its replay copied each time) took 313 against 524 us
        with this and Checkpoints' copy of its columns (9 rounds in turn, fresh
        processes)."""
        return self


def _values(section: Any) -> tuple:
    return tuple(getattr(section, f.name) for f in fields(section))


def _order(config: Any, name: str, *pairs: tuple[str, str]) -> None:
    for low, high in pairs:
        if getattr(config, low) > getattr(config, high):
            raise ConfigError(f"{name}.{low} = {getattr(config, low)} must not exceed "
                              f"{name}.{high} = {getattr(config, high)}")


@dataclass(frozen=True, repr=False, eq=False)
class Geometry(Section):
    """Where things are on the 224x256 screen (reference section 2)."""

    def __post_init__(self) -> None:
        check_ranges(self, "config.geometry")
        _order(self, "config.geometry", ("cannon_min_x", "cannon_max_x"),
               ("edge_left", "edge_right"), ("saucer_exit_left", "saucer_start_left"),
               ("saucer_start_right", "saucer_exit_right"))
        if self.rows > PICTURE_ROWS:
            raise ConfigError(f"config.geometry.rows = {self.rows}: there are alien pictures "
                              f"for {PICTURE_ROWS} rows")
        if self.rack_left + self.cell * (self.cols - 1) + 16 > SCREEN_W:
            raise ConfigError(f"config.geometry: a rack of {self.cols} columns of "
                              f"{self.cell} px from x {self.rack_left} leaves the screen")

    saucer_top: int = within(40, 0, 247)  # saucer lane, rows 40-47
    rack_left: int = within(24, 0, 223)  # every wave starts with the reference alien at x=24
    cell: int = within(16, 1, 32)  # an alien's cell is 16x16
    rows: int = within(5, 1, 5)
    cols: int = within(11, 1, 11)
    # a lit alien pixel in this column while moving right bumps the rack
    edge_right: int = within(213, 1, 223)
    edge_left: int = within(9, 0, 222)
    bunker_xs: tuple[int, ...] = within((32, 77, 122, 167), 0, 202, 0, 8)
    bunker_top: int = within(192, 0, 240)
    cannon_top: int = within(216, 0, 248)
    cannon_min_x: int = within(16, 0, 208)
    cannon_max_x: int = within(185, 0, 208)
    ground_row: int = within(239, 0, 255)
    shot_spawn_top: int = within(212, 8, 252)  # lit rows 212-215 at Yr 0x28
    shot_top_limit: int = within(36, 0, 248)  # at Yr >= 0xD8 the shot bursts at the top
    # the saucer meets the shot only inside its lane (Yr >= 0xCE)
    saucer_lane_h: int = within(8, 1, 256)
    # an alien drawn with its top here is in the cannon's rows
    invasion_top: int = within(216, 0, 255)
    # a bomb whose box top reaches this (Yr < 0x15) bursts on the ground
    bomb_ground_top: int = within(228, 8, 255)
    saucer_start_left: int = within(9, 0, 200)  # a saucer entering from the left starts here (x)
    saucer_start_right: int = within(192, 0, 200)  # ... from the right
    saucer_exit_left: int = within(8, 0, 224)  # it leaves the screen once its x is left of this
    saucer_exit_right: int = within(193, 0, 224)  # ... or reaches this
    # where the shot leaves and the rolling bomb aims: this far right of the cannon's x
    cannon_centre: int = within(8, 0, 15)
    # a bomb drops this far (x, y) from its alien's x and picture top (05A5-05B4)
    bomb_drop_offset: tuple[int, ...] = within((7, 10), -16, 16, 2, 2)
    # bursts' pictures are drawn this far (x, y) from the shot or the bomb (03DF, 0436)
    shot_burst_offset: tuple[int, ...] = within((-3, -2), -8, 8, 2, 2)
    bomb_burst_offset: tuple[int, ...] = within((-2, 2), -8, 8, 2, 2)
    # a bomb bursting on the ground: x from the bomb's, y from the ground row (05F6)
    ground_burst_offset: tuple[int, ...] = within((-2, -7), -8, 8, 2, 2)


@dataclass(frozen=True, repr=False, eq=False)
class Timing(Section):
    """Durations in ticks (1 tick = 1 frame of the original, reference sections 5-12)."""

    def __post_init__(self) -> None:
        check_ranges(self, "config.timing")

    cannon_wait: int = within(128, 1, 100000)  # before a new cannon appears or moves
    alien_fire_delay: int = within(48, 0, 100000)  # after the cannon becomes active
    alien_explosion: int = within(16, 1, 100000)  # no new shot meanwhile; the rack held as long
    shot_burst: int = within(16, 1, 100000)
    bomb_burst_steps: int = within(3, 1, 100000)  # counter 4: drawn at 3, erased at 0
    # UNCERTAIN (13.1): we take the code's 12 swaps x 5 frames
    cannon_death: int = within(60, 1, 100000)
    cannon_death_swap: int = within(5, 1, 100000)
    wave_pause: int = within(48, 1, 100000)
    saucer_timer: int = within(0x600, 1, 100000)  # UNCERTAIN (13.4): the value is hex, 1536 frames
    saucer_hit_steps: int = within(32, 1, 100000)  # saucer ticks from hit to clear
    # the score shows (and is added) at this saucer tick
    saucer_score_at: int = within(24, 0, 100000)
    saucer_boom_until: int = within(24, 0, 100000)  # the explosion image shows from 31 down to here
    game_over_pause: int = within(120, 0, 100000)  # before START is accepted after a game ends


@dataclass(frozen=True, repr=False, eq=False)
class Speeds(Section):
    """Pixels per move (reference sections 4-8)."""

    def __post_init__(self) -> None:
        check_ranges(self, "config.speeds")

    cannon: int = within(1, 1, 32)
    shot: int = within(4, 1, 128)
    bomb: int = within(4, 1, 128)
    # from the moment 8 or fewer aliens remain (UNCERTAIN 13.3: we take <= 8)
    bomb_fast: int = within(5, 1, 128)
    bomb_fast_at: int = within(8, 0, 55)
    rack_step: int = within(2, 1, 32)
    rack_step_last_right: int = within(3, 1, 32)  # one alien left, moving right
    rack_drop: int = within(8, 0, 64)
    saucer: int = within(2, 1, 64)


@dataclass(frozen=True, repr=False, eq=False)
class Rules(Section):
    """Rule switches and tables (reference sections 4, 6, 8, 11)."""

    def __post_init__(self) -> None:
        check_ranges(self, "config.rules")

    ships: int = within(3, 1, 99)  # including the one in play (DIP 3-6)
    extra_ship_at: int = within(1500, 0, 9999)  # DIP alternative 1000; awarded once per game
    # by rack row, bottom first
    alien_points: tuple[int, ...] = within((10, 10, 20, 20, 30), 0, 9990, 1, 5)
    # Reference-alien start rows by wave (Yr 0x78, 0x60, 0x50, 0x48 x3, 0x40 x3 -> rows).
    # UNCERTAIN (13.7): after wave 9 we cycle from the wave-2 value, as the code does.
    start_tops: tuple[int, ...] = within(
        (128, 152, 168, 176, 176, 176, 184, 184, 184), 8, 248, 1, 64)
    # Reload: a bomb type may fire only if every other live bomb made more than R steps.
    # UNCERTAIN (13.2): the code compares the score's upper BCD digits with <=, so the
    # thresholds are hundreds <= 2, 10, 20, 30 (that is scores below 300, 1100, 2100, 3100).
    reload_hundreds: tuple[int, ...] = within((2, 10, 20, 30), 0, 99, 0, 16)
    reload_steps: tuple[int, ...] = within((48, 16, 11, 8, 7), 0, 255, 1, 17)
    plunger_columns: tuple[int, ...] = within(
        (1, 7, 1, 1, 1, 4, 11, 1, 6, 3, 1, 1, 11, 9, 2, 8), 1, 11, 1, 64)
    squiggly_columns: tuple[int, ...] = within(
        (11, 1, 6, 3, 1, 1, 11, 9, 2, 8, 2, 11, 4, 7, 10), 1, 11, 1, 64)
    saucer_scores: tuple[int, ...] = within(
        (100, 50, 50, 100, 150, 100, 100, 50, 300, 100, 100, 100, 50, 150, 100), 0, 9990, 1, 64)
    saucer_min_aliens: int = within(8, 0, 55)
    plunger_min_aliens: int = within(2, 0, 55)  # off once a bomb of it ends with fewer


@dataclass(frozen=True, repr=False, eq=False)
class GameConfig(Section):
    """Everything the simulation needs besides the seed; recorded in replays."""

    geometry: Geometry = field(default_factory=Geometry)
    timing: Timing = field(default_factory=Timing)
    speeds: Speeds = field(default_factory=Speeds)
    rules: Rules = field(default_factory=Rules)
    tick_hz: int = within(60, 1, 1000)

    def __post_init__(self) -> None:
        """The sections' own ranges are checked as they are built; here, what they must
        agree on: the rack's tables fit its rows and columns, and it starts on screen."""
        check_ranges(self, "config")
        g, r = self.geometry, self.rules
        if len(r.alien_points) < g.rows:
            raise ConfigError(f"config.rules.alien_points has {len(r.alien_points)} values "
                              f"for {g.rows} rows")
        for name in ("plunger_columns", "squiggly_columns"):
            column = max(getattr(r, name))
            if column > g.cols:
                raise ConfigError(f"config.rules.{name} names column {column}; the rack has "
                                  f"{g.cols}")
        for top in r.start_tops:
            if top - g.cell * (g.rows - 1) - 8 < 0:
                raise ConfigError(f"config.rules.start_tops: a rack starting at row {top} "
                                  f"begins above the screen")

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
