"""The fixed-step loop: bank real time, run whole ticks, cap catch-up, hand rendering alpha.

Only this module measures real time for the game (the lab's panel times detection with the
same clock, and what it measures never reaches the game's state). Time is banked in integer
units (nanoseconds times the tick rate), so the number of ticks run for a given sequence of
clock readings is exact, not subject to float drift: the same clock gives the same ticks on
every machine.
"""

from __future__ import annotations

from collections.abc import Callable

NS = 1_000_000_000


class FixedStepLoop:
    """`frame()` -> (ticks to run now, alpha in [0, 1) for interpolating the render)."""

    def __init__(self, clock: Callable[[], float], tick_hz: int = 60,
                 max_catch_up: int = 5) -> None:
        if tick_hz < 1 or max_catch_up < 1:
            raise ValueError("tick rate and catch-up cap must be positive")
        self.clock = clock
        self.tick_hz = tick_hz
        self.max_catch_up = max_catch_up
        self.bank = 0  # nanoseconds x tick_hz; one tick costs NS of these
        self.dropped_ticks = 0  # ticks skipped by the cap (the game slowed instead)
        self._last = self._now_ns()

    def _now_ns(self) -> int:
        return round(self.clock() * NS)

    def resume(self) -> None:
        """Forget time spent paused (or blocked): the next frame starts from now."""
        self._last = self._now_ns()
        self.bank = 0

    def frame(self) -> tuple[int, float]:
        now = self._now_ns()
        elapsed = max(0, now - self._last)
        self._last = now
        self.bank += elapsed * self.tick_hz
        ticks, self.bank = divmod(self.bank, NS)
        if ticks > self.max_catch_up:
            self.dropped_ticks += ticks - self.max_catch_up
            ticks = self.max_catch_up
        return ticks, self.bank / NS
