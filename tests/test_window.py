"""The window as a player meets it, driven through events on SDL's dummy driver: short
presses are never lost, a replay's end is shown with its verdict, and without a display
`play` says so in one line instead of running invisibly."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pygame
import pytest

from invaders.app.recording import Recorder, record_headless
from invaders.game.actions import Action
from invaders.game.runs import Runs
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
    changed.inputs = Runs()
    for b in bits:
        changed.append(b)
    assert len(bits) == 240
    checkpoint = (first // 60 + 1) * 60  # the first checkpoint after the change
    assert _watch_to_the_end(changed).replay_verdict() == f"DIFFERS FROM TICK {checkpoint}"


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
    return App(world, pygame.Surface((224, 256)), clock), clock, world


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
    env["DISPLAY"] = f":{_display_without_server()}"
    script = str(Path(sys.executable).with_name("invaders"))
    result = subprocess.run([script, "play", "--mute"], capture_output=True, text=True,
                            timeout=60, env=env, check=False)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("invaders: error:")


def _display_without_server() -> int:
    """A display number no X server on this machine holds (neither its socket nor its
    lock file exists): a developer's own server may hold any given one."""
    return next(n for n in range(97, 1000) if not Path(f"/tmp/.X11-unix/X{n}").exists()
                and not Path(f"/tmp/.X{n}-lock").exists())


def test_the_c_librarys_stderr_comes_back_after_the_quiet_part():
    code = ("import os, sys\nfrom invaders.quiet import c_stderr_quiet\n"
            "with c_stderr_quiet():\n    os.write(2, b'chatter\\n')\n"
            "os.write(2, b'after\\n'); print('python', file=sys.stderr)")
    assert _stderr_of(code) == "after\npython\n"


def _display_session(scale: int):
    """A session drawing into the display's own window (on the dummy driver)."""
    from invaders.app.play import Session, open_window
    from tests.helpers import FakeClock

    window = open_window(scale)
    return Session(World(seed=0), window, FakeClock())


def test_a_window_too_big_for_the_screen_opens_smaller_saying_so_if_its_scale_was_asked(
        capsys):
    """The dummy driver's screen is 1024x768: the default scale, 3, would fill its height,
    so the window opens at 2 without a word; --scale 3 asked for says so in one line."""
    from invaders.app.play import open_window

    assert open_window(None).get_size() == (448, 512)
    assert capsys.readouterr().err == ""
    assert open_window(3).get_size() == (448, 512)
    assert capsys.readouterr().err == (
        "invaders: a window at scale 3 would not fit on this 1024x768 screen: opened at "
        "scale 2 (resize it, or F11 for the full screen)\n")
    pygame.display.quit()


def test_f11_fills_the_screen_and_brings_the_window_back_at_its_own_size_and_place():
    session = _display_session(2)
    place = pygame.display.get_window_position()
    session.handle(_key(pygame.KEYDOWN, pygame.K_F11))
    assert pygame.display.is_fullscreen()
    assert session.target.get_size() == pygame.display.get_desktop_sizes()[0]
    session.handle(_key(pygame.KEYDOWN, pygame.K_F11))
    assert not pygame.display.is_fullscreen()
    assert session.target.get_size() == (448, 512)
    assert pygame.display.get_window_position() == place
    pygame.display.quit()


def test_f4_widens_the_window_where_it_stands_and_never_past_the_screen():
    from invaders.app.labpanel import panel_width
    from invaders.app.play import Session, fit_beside_panel
    from tests.helpers import FakeClock

    session = _display_session(2)
    place = pygame.display.get_window_position()
    session.handle(_key(pygame.KEYDOWN, pygame.K_F4))
    assert session.target.get_size() == (448 + panel_width(2), 512)
    assert pygame.display.get_window_position() == place
    session.handle(_key(pygame.KEYDOWN, pygame.K_F4))
    assert session.target.get_size() == (448, 512)
    pygame.display.quit()
    pygame.display.set_mode((672, 768), pygame.RESIZABLE)  # (made that size: 672 + 336
    session = Session(World(seed=0), pygame.display.get_surface(), FakeClock())  # fit 1024)
    session.handle(_key(pygame.KEYDOWN, pygame.K_F4))
    assert session.target.get_size() == (672 + panel_width(3), 768)
    pygame.display.quit()
    w, h = fit_beside_panel(1120, 1280, 1024)  # scale 5 on that screen: made smaller
    assert w + panel_width(h / 256) <= 1024 and abs(w / h - 224 / 256) < 0.01
    bigger = h + 1  # the largest that fits: one row more would not
    assert round(bigger * 224 / 256) + panel_width(bigger / 256) > 1024


XVFB_CHILD = """
import json, time, pygame
from invaders.app.play import Session, open_window
from invaders.game.world import World
window = open_window(3)
session = Session(World(seed=0), window, time.perf_counter)
def now():
    for _ in range(20):
        pygame.event.pump()
        time.sleep(0.02)
    return [pygame.display.get_window_size(), pygame.display.get_window_position(),
            pygame.display.is_fullscreen()]
seen = [now()]
for key in (pygame.K_F11, pygame.K_F11, pygame.K_F4):
    session.handle(pygame.event.Event(pygame.KEYDOWN, key=key, mod=0, unicode="", scancode=0))
    seen.append(now())
print(json.dumps(seen))
"""


@contextlib.contextmanager
def _x_server():
    """An Xvfb display (1280x1024), with openbox as its window manager where installed: the
    environment to run in it."""
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed (apt-get install xvfb openbox): no real X server")
    for number in range(71, 99):
        if not Path(f"/tmp/.X11-unix/X{number}").exists():
            break
    server = subprocess.Popen(["Xvfb", f":{number}", "-screen", "0", "1280x1024x24"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    env = {k: v for k, v in os.environ.items() if k not in ("SDL_VIDEODRIVER", "WAYLAND_DISPLAY")}
    env["DISPLAY"] = f":{number}"
    for _ in range(100):
        if Path(f"/tmp/.X11-unix/X{number}").exists():
            break
        time.sleep(0.05)
    manager = (subprocess.Popen(["openbox"], env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL) if shutil.which("openbox") else None)
    time.sleep(0.5)
    try:
        yield env
    finally:
        for process in (manager, server):
            if process is not None:
                process.terminate()
                process.wait(10)


def test_in_a_real_x_server_f11_comes_back_to_the_windows_place_and_f4_stays_there():
    with _x_server() as env:
        result = subprocess.run([sys.executable, "-c", XVFB_CHILD], capture_output=True,
                                text=True, timeout=120, env=env, check=False)
    assert result.returncode == 0, result.stderr
    assert "Warning" not in result.stderr  # (pygame's toggle_fullscreen warned each time)
    start, full, back, panel = json.loads(result.stdout)
    assert start[0] == [672, 768] and full == [[1280, 1024], [0, 0], True]
    assert back == start
    assert panel[0][0] > 672 and panel[1] == start[1] and panel[0][0] <= 1280


MAXIMIZED_CHILD = """
import json, time, warnings, pygame
from invaders.app.play import Session, open_window
from invaders.game.world import World
session = Session(World(seed=0), open_window(3), time.perf_counter)
def now():
    for _ in range(25):
        for event in pygame.event.get():
            session.handle(event)
        time.sleep(0.02)
    return [list(pygame.display.get_window_size()), list(session.target.get_size())]
with warnings.catch_warnings():  # (pygame's Window of the display's: deprecated, not gone)
    warnings.simplefilter("ignore", DeprecationWarning)
    pygame.Window.from_display_module().maximize()
seen = [now()]
for key in (pygame.K_F4, pygame.K_F4):
    session.handle(pygame.event.Event(pygame.KEYDOWN, key=key, mod=0, unicode="", scancode=0))
    seen.append(now())
print(json.dumps(seen))
"""


def test_in_a_real_x_server_f4_in_a_maximized_window_shares_it_with_the_panel_quietly():
    """The window manager keeps a maximized window's size when F4 asks for another: the
    panel shares the window, and nothing is printed (pygame warned, twice, with our
    source line, that the size was forced)."""
    if shutil.which("openbox") is None:
        pytest.skip("openbox is not installed: no window manager to maximize the window")
    with _x_server() as env:
        result = subprocess.run([sys.executable, "-c", MAXIMIZED_CHILD], capture_output=True,
                                text=True, timeout=120, env=env, check=False)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""
    maximized, opened, closed = json.loads(result.stdout)
    assert maximized[0][0] == 1280 and maximized[0][1] > 768  # (less the title bar)
    assert opened == closed == maximized  # the window's own size, drawn into in full


def test_in_a_real_x_server_a_scale_too_big_for_the_screen_opens_one_that_fits():
    """`--scale 8` on a 1280x1024 screen: a window 2,048 px tall opened with its title bar
    and score above the screen. It opens at scale 3 below the screen's top, and says so."""
    child = ("import json, time, pygame\n"
             "from invaders.app.play import open_window\n"
             "open_window(8)\n"
             "for _ in range(20):\n    pygame.event.pump(); time.sleep(0.02)\n"
             "print(json.dumps([pygame.display.get_window_size(),\n"
             "                  pygame.display.get_window_position()]))\n")
    with _x_server() as env:
        result = subprocess.run([sys.executable, "-c", child], capture_output=True,
                                text=True, timeout=120, env=env, check=False)
    assert result.returncode == 0, result.stderr
    size, place = json.loads(result.stdout)
    assert size == [224 * 3, 256 * 3] and place[1] >= 0
    assert result.stderr == ("invaders: a window at scale 8 would not fit on this 1280x1024 "
                             "screen: opened at scale 3 (resize it, or F11 for the full "
                             "screen)\n")


def test_bench_window_needs_a_display_and_says_so_in_one_line():
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    script = str(Path(sys.executable).with_name("invaders"))
    result = subprocess.run([script, "bench", "--window", "--rounds", "3"], capture_output=True,
                            text=True, timeout=60, env=env, check=False)
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "needs a display" in result.stderr


def test_bench_window_times_both_ways_of_showing_the_window_in_a_real_x_server():
    """Each way in a window of the size the header names: scale 8 does not fit on the
    1280x1024 screen, and the window timed is at scale 3 (the header said scale 8)."""
    code = ("from invaders.app.windowbench import window_bench\n"
            "print('\\n'.join(window_bench(rounds=1, seconds=1, scale=8)))")
    with _x_server() as env:
        result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                timeout=120, env=env, check=False)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == 4 and "native framebuffer" in lines[1] and "renderer" in lines[2]
    assert lines[0].startswith("a game in a 672x768 window (scale 3), 1 rounds of 1 s ")
    assert all("frames a second" in line for line in lines[1:3])


def test_the_window_is_of_the_programs_class_however_it_is_started():
    """`python -m invaders` too: window managers group windows and match them to a
    launcher by their class, which pygame takes from `argv[0]` ('__main__.py' there)."""
    if shutil.which("xdotool") is None:
        pytest.skip("xdotool is not installed (apt-get install xdotool): no window to find")
    with _x_server() as env:
        game = subprocess.Popen([sys.executable, "-m", "invaders", "--scale", "1"], env=env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            found = ""
            for _ in range(100):  # (the window opens within a second or two)
                found = subprocess.run(["xdotool", "search", "--class", "^invaders$"],
                                       env=env, capture_output=True, text=True).stdout
                if found or game.poll() is not None:
                    break
                time.sleep(0.1)
        finally:
            game.terminate()
            game.wait(10)
    assert found.split(), "no window of class 'invaders'"
