"""The three alien bomb types: turns, reload rule, column tables, steps and bursts."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, cast

from invaders.engine.body import copied
from invaders.engine.compiled import mypyc_attr
from invaders.engine.store import BodyStore
from invaders.game.config import GameConfig
from invaders.game.entities import BOMB_MASKS, Bomb, BombType
from invaders.game.rack import Rack

STEPS_AT_LAUNCH = 1  # the launch counts as the bomb's first step (05BF)


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
@dataclass
class BombSlot:
    """One bomb type's object: at most one bomb of each type exists, flying or bursting."""

    btype: BombType
    bomb: Bomb | None = None
    steps: int = 0  # steps made since it fired, counted while flying or bursting
    burst: int = 0  # bomb-steps left of the burst picture
    burst_x: int = 0
    burst_y: int = 0
    table_index: int = 0  # plunger and squiggly column cycles
    skip_next: bool = False  # rolling skips its next turn after each reset (04AB, 047D)
    off: bool = False  # the plunger, once one of its bombs ends with one alien left

    @property
    def busy(self) -> bool:
        return self.bomb is not None or self.burst > 0

    def __deepcopy__(self, memo: dict[int, Any]) -> BombSlot:
        """A copy with its bomb's (made once, through `memo`), its numbers and flags as they
        are: `replace` copies a field added later too, at a quarter of the generic copy's
        cost."""
        bomb = None if self.bomb is None else cast(Bomb, copied(self.bomb, memo))
        clone = memo[id(self)] = replace(self, bomb=bomb)
        return clone


def new_slots() -> list[BombSlot]:
    """A wave's or a turn's slots: no bomb, and the rolling bomb skipping its first
    attempt, as after every reset (04AB)."""
    return [BombSlot(t, skip_next=t is BombType.ROLLING) for t in BombType]


def reload_ready(slots: list[BombSlot], me: BombSlot, steps_needed: int) -> bool:
    """A type may fire only if every *other* busy bomb has made more than R steps."""
    for other in slots:  # a loop, not all(): this is asked every tick
        if other is not me and other.steps <= steps_needed and other.busy:
            return False
    return True


def choose_column(slot: BombSlot, config: GameConfig, cannon_centre: int, rack: Rack) -> int | None:
    """The 0-based column this attempt fires from, or None; advances the table cycles."""
    rules = config.rules
    if slot.btype is BombType.ROLLING:
        return aimed_column(cannon_centre, rack.ref_x, config.geometry.cell,
                            config.geometry.cols)
    table = rules.plunger_columns if slot.btype is BombType.PLUNGER else rules.squiggly_columns
    col = table[slot.table_index] - 1
    slot.table_index = (slot.table_index + 1) % len(table)
    return col


XR = 0x20  # the ROM's x coordinates (Xr) are the screen's plus 32, kept in one byte


def aimed_column(cannon_centre: int, ref_x: int, cell: int, cols: int) -> int:
    """The rolling bomb's column, counted as the ROM counts it, in bytes (Cnt16s and
    WrapRef, 1554-1596; the clamp at 0625): cells of `cell` px from the reference alien
    until past the cannon's centre, so a centre exactly on a boundary takes the column to
    its left. A reference at or beyond the centre first has cells added until its byte
    is below 128, which is one cell when it is left of x 80 and on screen, and otherwise
    wraps through 256 and counts too many (once edge columns are cleared the reference
    alien can be far outside the rack's lit part). Counts past the last column clamp to it.
    """
    target = (cannon_centre + XR) & 0xFF
    ref = (ref_x + XR) & 0xFF
    count = 0
    if ref >= target:
        while True:  # WrapRef: "until the sign bit is clear"
            count += 1
            ref = (ref + cell) & 0xFF
            if ref < 0x80:
                break
    for _ in range(256 // max(cell, 1)):  # (the ROM would loop forever past 255)
        if ref >= target:
            break
        ref = (ref + cell) & 0xFF
        count += 1
    return min(count, cols) - 1


def spawn(slot: BombSlot, rack: Rack, col: int, store: BodyStore, drop: tuple[int, ...]
          ) -> Bomb | None:
    """Drop a bomb from the lowest live alien of `col`, `drop` (x, y) from its x and its
    picture's top."""
    shooter = rack.lowest_in_column(col)
    if shooter is None:
        return None
    bomb = Bomb(store.new_id(), slot.btype, shooter.x + drop[0], shooter.top + drop[1])
    store.add(bomb)
    slot.bomb = bomb
    slot.steps = STEPS_AT_LAUNCH
    return bomb


def advance(slot: BombSlot, speed: int, store: BodyStore) -> None:
    """One bomb step: down `speed` px, next picture."""
    bomb = slot.bomb
    assert bomb is not None
    slot.steps += 1
    bomb.frame = (bomb.frame + 1) % 4
    store.reshape(bomb, BOMB_MASKS[bomb.btype][bomb.frame])
    store.move(bomb, bomb.x, bomb.y + speed)


def finish(slot: BombSlot) -> None:
    """The slot's bomb is gone. The rolling bomb's object is reset after each of its bombs,
    and a reset rolling bomb skips its next firing attempt (04AB)."""
    slot.bomb = None
    if slot.btype is BombType.ROLLING:
        slot.skip_next = True


def start_burst(slot: BombSlot, x: int, y: int, steps: int) -> None:
    """The bomb is gone; its burst picture stays `steps` bomb-steps at (x, y)."""
    finish(slot)
    slot.burst = steps
    slot.burst_x = x
    slot.burst_y = y
