"""The mystery ship: timer, launch conditions, flight in its lane, hit sequence and score."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, cast

from invaders.engine.body import copied
from invaders.engine.compiled import mypyc_attr
from invaders.engine.store import BodyStore
from invaders.game.config import GameConfig
from invaders.game.entities import Saucer

# Bit 0 of the ROM bytes at 0x0800..0x08FF (opcodes that happen to be there), read at
# 0x0800 + the shot count's low byte: 1 the saucer enters from the left, 0 from the right
# (0462-046B), the same sequence every game.
SIDE_BITS = ("1010111010100011011111011100100100101111101000101110111110010111"
             "0010001001111010011000010011000111101010011110111110010000010101"
             "1000000101001111101001100101001110100000000010000001011111100010"
             "1010101010111011010010110000100100010001010100110010111011101011")


def from_left_after(shots: int) -> bool:
    """Whether the next saucer enters from the left once `shots` shots have finished."""
    return SIDE_BITS[shots % len(SIDE_BITS)] == "1"


@mypyc_attr(allow_interpreted_subclasses=True)  # (copied: docs/compiled.md)
@dataclass
class SaucerState:
    """The saucer's object (shared with the squiggly bomb in the original)."""

    timer: int
    due: bool = False
    saucer: Saucer | None = None
    hit_steps: int = 0  # > 0 while the explosion, then the score, is shown
    hit_x: int = 0
    hit_score: int = 0
    from_left: bool = True  # before any shot has finished, and after each saucer: the left

    def __deepcopy__(self, memo: dict[int, Any]) -> SaucerState:
        """A copy with its saucer's (made once, through `memo`), its numbers and flags as
        they are (as a bomb slot's copy)."""
        saucer = None if self.saucer is None else cast(Saucer, copied(self.saucer, memo))
        clone = memo[id(self)] = replace(self, saucer=saucer)
        return clone


def count_down(state: SaucerState, config: GameConfig, ref_top: int) -> None:
    """Per tick; runs only once the rack is below its wave-1 start (Yr < 0x78)."""
    if ref_top <= config.rules.start_tops[0]:  # start_top(1), read directly: every tick
        return
    state.timer -= 1
    if state.timer <= 0:
        state.due = True
        state.timer = config.timing.saucer_timer


def launch(state: SaucerState, store: BodyStore, config: GameConfig) -> Saucer:
    """Start a flight from the side `from_left` says."""
    g, speed = config.geometry, config.speeds.saucer
    x, dx = ((g.saucer_start_left, speed) if state.from_left
             else (g.saucer_start_right, -speed))
    saucer = Saucer(store.new_id(), x, g.saucer_top, dx)
    store.add(saucer)
    state.saucer = saucer
    state.due = False
    return saucer


def fly(state: SaucerState, store: BodyStore, config: GameConfig) -> None:
    """One saucer tick of flight; it leaves at either end of the lane."""
    saucer = state.saucer
    assert saucer is not None
    g = config.geometry
    x = saucer.x + saucer.dx
    if x < g.saucer_exit_left or x >= g.saucer_exit_right:
        store.remove(saucer)
        state.saucer = None
        state.from_left = True  # the saucer's object is set afresh (06F9-0704)
        return
    store.move(saucer, x, saucer.y)


def score_for(config: GameConfig, shots_removed: int) -> int:
    """Mystery score: index = shots removed this wave (the hitting one included) mod 15."""
    table = config.rules.saucer_scores
    return table[shots_removed % len(table)]
