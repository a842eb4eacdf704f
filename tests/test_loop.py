"""The fixed-step loop, driven by a fake clock: exact tick counts, alpha, catch-up cap."""

from __future__ import annotations

import pytest

from invaders.app.loop import FixedStepLoop
from tests.helpers import FakeClock


@pytest.mark.parametrize("fps", [30, 60, 144, 75])
def test_ten_seconds_of_frames_run_exactly_600_ticks_at_any_frame_rate(fps):
    clock = FakeClock(100.0)
    loop = FixedStepLoop(clock, tick_hz=60)
    ticks = 0
    for frame in range(1, 10 * fps + 1):
        clock.now = 100.0 + frame / fps
        run, alpha = loop.frame()
        assert 0.0 <= alpha < 1.0
        ticks += run
    assert ticks == 600
    assert loop.dropped_ticks == 0


def test_a_30_fps_display_runs_two_ticks_a_frame():
    clock = FakeClock(100.0)
    loop = FixedStepLoop(clock, tick_hz=60)
    runs = []
    for frame in range(1, 31):
        clock.now = 100.0 + frame / 30
        runs.append(loop.frame()[0])
    # A float clock puts some frames a nanosecond early: the bank carries it to the next.
    assert sum(runs) == 60
    assert set(runs) <= {1, 2, 3}
    assert runs.count(2) >= 10


def test_alpha_is_the_fraction_of_a_tick_banked():
    clock = FakeClock(100.0)
    loop = FixedStepLoop(clock, tick_hz=60)
    clock.now += 1.5 / 60
    ticks, alpha = loop.frame()
    assert ticks == 1 and alpha == pytest.approx(0.5)


def test_a_stall_of_seconds_slows_the_game_instead_of_freezing_it():
    clock = FakeClock(100.0)
    loop = FixedStepLoop(clock, tick_hz=60, max_catch_up=5)
    clock.now += 5.0  # the window was dragged for five seconds
    ticks, _ = loop.frame()
    assert ticks == 5
    assert loop.dropped_ticks == 295
    clock.now += 1 / 60
    assert loop.frame()[0] == 1  # and then it carries on at the normal pace


def test_resume_forgets_paused_time():
    clock = FakeClock(100.0)
    loop = FixedStepLoop(clock, tick_hz=60)
    clock.now += 30.0
    loop.resume()
    clock.now += 1 / 60
    assert loop.frame()[0] == 1


def test_time_going_backwards_runs_nothing():
    clock = FakeClock(100.0)
    loop = FixedStepLoop(clock, tick_hz=60)
    clock.now -= 1.0
    assert loop.frame() == (0, 0.0)
