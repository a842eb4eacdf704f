"""The cabinet's sounds: all there, audible and of sane length; the march follows the rack;
no audio device means silence and no complaint; headless runs never open audio."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pygame

from invaders.app.sound import RATE, SoundBoard, synthesize
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


def _notes_in(world: World, board: SoundBoard, ticks: int) -> int:
    before = board.notes_played
    for _ in range(ticks):
        report = world.step(0)
        board.react(report.events, world)
        world.alien_fire_timer = -1  # nothing falls: the rack alone sets the tempo
    return board.notes_played - before


def test_the_march_tempo_follows_the_number_of_live_aliens():
    board = SoundBoard(muted=True)  # muted: counted, not heard
    full = World(seed=0)
    _notes_in(full, board, 60)  # the rack is drawn
    many = _notes_in(full, board, 1100)
    few = World(seed=0)
    _notes_in(few, board, 60)
    for alien in few.rack.live_aliens()[11:]:
        few.rack.kill(alien, few.store)
    fewer = _notes_in(few, board, 1100)
    assert many == 1100 // 55 and fewer == 1100 // 11  # one note per step of the rack


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
