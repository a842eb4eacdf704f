"""The window as a player meets it, driven through events on SDL's dummy driver: short
presses are never lost, a replay's end is shown with its verdict, and without a display
`play` says so in one line instead of running invisibly."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pygame

from invaders.app.recording import Recorder, record_headless
from invaders.game.actions import Action
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from tests.helpers import through_the_prompt, windowed

FIRE = int(Action.FIRE)



def _key(kind: int, key: int) -> pygame.event.Event:
    return pygame.event.Event(kind, key=key, mod=0, unicode="", scancode=0)


def test_every_short_tap_between_two_frames_fires_once():
    world = World(seed=1)
    recorder = Recorder(world)
    session, clock = windowed(world, recorder=recorder)
    taps = 0
    for frame in range(20 * 90):
        if frame % 90 == 45:  # down and up again before the next frame: never held
            session.handle(_key(pygame.KEYDOWN, pygame.K_SPACE))
            session.handle(_key(pygame.KEYUP, pygame.K_SPACE))
            taps += 1
        clock.now += 1 / 60
        session.frame(0)
    ticks_with_fire = sum(count for bits, count in recorder.replay.inputs if bits & FIRE)
    assert taps == 20 and ticks_with_fire == 20  # each tap: one tick, recorded as used


def test_two_taps_in_one_frame_are_two_presses():
    world = World(seed=1)
    recorder = Recorder(world)
    session, clock = windowed(world, recorder=recorder)
    for _ in range(2):
        session.handle(_key(pygame.KEYDOWN, pygame.K_SPACE))
        session.handle(_key(pygame.KEYUP, pygame.K_SPACE))
    for _ in range(5):
        clock.now += 1 / 60
        session.frame(0)
    bits = [b for b, count in recorder.replay.inputs for _ in range(count)]
    assert bits[:3] == [FIRE, 0, FIRE]  # a release between them, so both are presses


def _watch_to_the_end(replay):
    world = World(replay.seed, replay.config)
    session, clock = windowed(world, replay=replay)
    for _ in range(replay.ticks + 10):
        clock.now += 1 / 60
        session.frame(0)
    return session


def test_a_replays_end_shows_the_verdict_and_enter_asks_for_a_game():
    replay = record_headless(World(seed=2), Autopilot(2), 240)
    session = _watch_to_the_end(replay)
    assert session.replay_done and session.replay_verdict() == "CHECKPOINTS MATCHED"
    assert session.world.tick == 240
    session.handle(_key(pygame.KEYDOWN, pygame.K_RETURN))
    assert session.start_requested
    changed = record_headless(World(seed=2), Autopilot(2), 240)
    bits = [b for b, count in changed.inputs for _ in range(count)]
    first = next(t for t, b in enumerate(bits) if b & Action.RIGHT)
    bits[first:first + 20] = [int(Action.LEFT)] * 20  # twenty ticks the other way
    changed.inputs = []
    for b in bits:
        changed.append(b)
    assert len(bits) == 240
    assert _watch_to_the_end(changed).replay_verdict().startswith("DIFFERS FROM TICK ")


def test_without_a_display_play_refuses_in_one_line():
    env = {k: v for k, v in os.environ.items()
           if k not in ("SDL_VIDEODRIVER", "DISPLAY", "WAYLAND_DISPLAY")}
    script = str(Path(sys.executable).with_name("invaders"))
    result = subprocess.run([script, "play"], capture_output=True, text=True, timeout=60,
                            env=env, check=False)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "'invaders run'" in result.stderr


def test_a_paused_game_draws_nothing_new_and_wakes_seldom():
    session, clock = windowed(World(seed=1))
    clock.now += 1 / 60
    assert session.frame(0)  # the game runs: a tick, a picture
    assert session.frames_per_second() == 60
    session.handle(_key(pygame.KEYDOWN, pygame.K_p))
    clock.now += 1 / 60
    assert session.frame(0)  # the word PAUSED is new: drawn once
    tick = session.world.tick
    for _ in range(30):
        clock.now += 1 / 10
        assert not session.frame(0)  # then nothing, however much time passes
    assert session.world.tick == tick and session.frames_per_second() == 10


def _app():
    from invaders.app.play import App
    from tests.helpers import FakeClock

    clock = FakeClock()
    world = World(seed=4)
    return App(world, pygame.Surface((224, 256)), clock, scale=1), clock, world


def test_the_attract_cycle_runs_its_steps_the_demo_until_its_cannon_dies_and_enter_starts():
    app, clock, world = _app()
    world.hi_score, world.score = 1230, 70  # a game played before: the demo shows them
    kinds, demo_ticks, drawn = [], 0, 0
    for _ in range(60 * 200):
        clock.now += 1 / 60
        going, drew = app.step([], 0)
        assert going
        drawn += drew
        if not kinds or kinds[-1] != app.attract.step:
            kinds.append(app.attract.step)
        if app.attract.demo is not None:
            demo = app.attract.demo.world
            demo_ticks = demo.tick
            assert (demo.hi_score, demo.score) == (1230, 70)  # kept: the demo scores nothing
        elif demo_ticks and kinds[-1] == "demo":
            raise AssertionError("the demo step outlived its game")
        if len(kinds) > 2 and kinds[-1] == "wait" and kinds[-2] == "type" and not (
                app.attract.animated):
            break  # into the second cycle's title
    assert kinds[:3] == ["wait", "type", "wait"] and "move" in kinds and "shoot" in kinds
    assert kinds.count("demo") == 1 and demo_ticks > 0
    assert demo.ships == 2 and demo.cannon.state == 0  # it ended at its cannon's death
    assert world.tick == 0  # the player's world waits; the demo played in its own
    assert drawn < 60 * 200  # still frames are not drawn again
    app.step([_key(pygame.KEYDOWN, pygame.K_RETURN)], 0)
    assert app.mode == "prompt"
    drew = through_the_prompt(app, clock)
    assert 170 <= len(drew) <= 180 and 40 <= sum(drew) <= 50  # the score flashing: 8 frames
    assert world.tick == 0
    clock.now += 1 / 60
    app.step([], 0)
    assert app.mode == "game" and world.tick > 0

def test_after_game_over_the_attract_cycle_comes_back_and_the_next_game_keeps_the_high_score():
    app, clock, world = _app()
    app.step([_key(pygame.KEYDOWN, pygame.K_1)], 0)
    through_the_prompt(app, clock)
    world.score = 70
    world.ships = 1
    world.kill_cannon()
    for _ in range(400):
        clock.now += 1 / 60
        app.step([], 0)
        if app.mode == "attract":
            break
    assert app.mode == "attract" and world.hi_score == 70
    app.step([_key(pygame.KEYDOWN, pygame.K_RETURN)], 0)
    through_the_prompt(app, clock)
    for _ in range(3):
        clock.now += 1 / 60
        app.step([], 0)
    assert app.mode == "game" and world.games == 2 and world.score == 0
    assert world.hi_score == 70


def test_esc_quits_from_the_attract_cycle():
    app, _, _ = _app()
    assert app.step([_key(pygame.KEYDOWN, pygame.K_ESCAPE)], 0) == (False, False)


def _stderr_of(code: str, env: dict[str, str] | None = None) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60, env=env, check=False).stderr


def test_opening_the_mixer_without_a_sound_card_says_nothing():
    """Bare, the mixer's probing prints ALSA's lines here (no sound card); ours prints none."""
    bare = _stderr_of("import os; os.environ['PYGAME_HIDE_SUPPORT_PROMPT'] = '1'\n"
                      "import pygame\ntry:\n    pygame.mixer.init(44100, -16, 1, 512)\n"
                      "except pygame.error:\n    pass")
    ours = _stderr_of("from invaders.app.sound import SoundBoard; SoundBoard()")
    assert ours == ""
    assert bare == "" or "ALSA" in bare  # (a machine with a sound card prints nothing)


def test_a_display_naming_no_server_is_refused_in_our_one_line_only():
    env = {k: v for k, v in os.environ.items()
           if k not in ("SDL_VIDEODRIVER", "WAYLAND_DISPLAY", "XDG_RUNTIME_DIR")}
    env["DISPLAY"] = ":97"  # no X server there
    script = str(Path(sys.executable).with_name("invaders"))
    result = subprocess.run([script, "play", "--mute"], capture_output=True, text=True,
                            timeout=60, env=env, check=False)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("invaders: error:")


def test_the_c_librarys_stderr_comes_back_after_the_quiet_part():
    code = ("import os, sys\nfrom invaders.app.quiet import c_stderr_quiet\n"
            "with c_stderr_quiet():\n    os.write(2, b'chatter\\n')\n"
            "os.write(2, b'after\\n'); print('python', file=sys.stderr)")
    assert _stderr_of(code) == "after\npython\n"
