"""The cabinet's sounds: all there, audible and of sane length; the march follows the rack;
no audio device means silence and no complaint; headless runs never open audio."""

from __future__ import annotations

import itertools
import subprocess
import sys

import numpy as np
import pygame
import pytest

from invaders.app.sound import RATE, SoundBoard, synthesize
from invaders.game.config import DEFAULT_CONFIG
from invaders.game.events import Event
from invaders.game.world import World


def test_every_sound_is_there_audible_and_of_a_sane_length():
    waves = synthesize()
    assert set(waves) == {"march0", "march1", "march2", "march3", "shot", "alien_killed",
                          "cannon_hit", "saucer", "saucer_hit", "extra_ship"}
    for name, wave in waves.items():
        assert wave.dtype == np.int16, name
        assert 0.05 <= wave.size / RATE <= 1.5, name
        assert np.abs(wave.astype(np.int32)).max() > 3000, name  # not silent
    assert len({waves[f"march{i}"].tobytes() for i in range(4)}) == 4  # four notes


def _note_ticks(world: World, board: SoundBoard, ticks: int, at=None) -> list[int]:
    """The ticks on which a march note played; `at` (tick -> action) acts on the world."""
    played = []
    for _ in range(ticks):
        if at is not None:
            at(world)
        before = board.notes_played
        report = world.step(0)
        board.react(report.events, world)
        world.alien_fire_timer = -1  # nothing falls: the rack alone is in play
        if board.notes_played > before:
            played.append(world.tick)
    return played


def _gaps(ticks: list[int]) -> set[int]:
    return {b - a for a, b in itertools.pairwise(ticks)}


@pytest.mark.parametrize("alive, frames", [(55, 52), (43, 46), (11, 19), (8, 16), (1, 5)])
def test_the_march_is_timed_by_the_roms_table_of_live_aliens(alive, frames):
    """The ROM's fleet delays (1A11/1A21): with N live aliens, the listed frames between
    two notes, whatever the rack's own pace (N ticks a step)."""
    board = SoundBoard(muted=True)  # muted: counted, not heard
    world = World(seed=0)
    for alien in world.rack.aliens[alive:]:
        world.rack.kill(alien, world.store)
    assert world.rack.live == alive
    assert _gaps(_note_ticks(world, board, 12 * frames)[1:]) == {frames}


def test_the_march_runs_on_through_an_aliens_explosion():
    """An alien killed 7 frames before a note: the rack stands still while it explodes, and
    the note comes on time all the same (it waited for the rack's step before)."""
    board = SoundBoard(muted=True)
    world = World(seed=0)
    first = _note_ticks(world, board, 200)[-1]  # a note, then 52 frames to the next
    kill_at = first + 52 - 7

    def kill(w: World) -> None:
        if w.tick == kill_at:
            alien = next(a for a in w.rack.aliens if a is not None and a.alive)
            w.kill_alien(alien, alien.x + 8)

    exploding = []

    def kill_then_watch(w: World) -> None:
        kill(w)
        exploding.append((w.tick, w.rack.held > 0))

    played = _note_ticks(world, board, 60, kill_then_watch)
    assert played[0] == first + 52
    assert dict(exploding)[first + 51]  # the tick of that note began with the rack held


def test_the_march_runs_on_through_a_hit_cannons_blow_up_delay_then_waits_for_the_next():
    """The original's fleet counter waits on playerOK (1747), as the rack's cursor does: a
    note due in the 5 frames after a hit comes on time; the counter then stands still
    through the rest of the death and the wait after it, so the next note comes that many
    frames late."""
    timing = DEFAULT_CONFIG.timing
    board = SoundBoard(muted=True)
    world = World(seed=0)
    first = _note_ticks(world, board, 200)[-1]  # a note, then 52 frames to the next
    kill_at = first + 52 - 3  # (before that tick: a hit in the tick before it)

    def kill(w: World) -> None:
        if w.tick == kill_at:
            w.kill_cannon()

    played = _note_ticks(world, board, 400, kill)
    # (the death's frames after the delay, then the wait's but its last: the new cannon
    # plays on that one)
    stood_still = timing.cannon_death - timing.cannon_death_swap + timing.cannon_wait - 1
    assert played[:2] == [first + 52, first + 52 + 52 + stood_still]


def test_without_an_audio_device_the_game_runs_silent(monkeypatch):
    def no_device(*args, **kwargs):
        raise pygame.error("no available audio device")

    monkeypatch.setattr(pygame.mixer, "init", no_device)
    board = SoundBoard()
    assert board.sounds == {}
    world = World(seed=0)
    for _ in range(200):
        board.react((Event.SHOT_FIRED, Event.ALIEN_KILLED), world)
        world.step(0)
    board.toggle_mute()


def test_headless_runs_never_open_audio():
    script = ("import pygame; from invaders.app.cli import main; main(['run', '--ticks', '30',"
              " '--autopilot']); print('mixer', pygame.mixer.get_init())")
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=60, check=True)
    assert result.stdout.strip().endswith("mixer None")
