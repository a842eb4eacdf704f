"""The windowed game: keyboard (or a replay) -> actions, the fixed-step loop, the renderer.

`Session` does one frame's work at a time and takes its clock from outside, so tests drive
the real windowed code with a fake clock at any frame rate (dummy video driver).
"""

from __future__ import annotations

import contextlib
import io
import time
import warnings
from collections.abc import Callable, Iterator

import pygame

from invaders.app.attract import Attract, card, demo_world
from invaders.app.labpanel import LabControl, PanelPainter, draw_marks, panel_width
from invaders.app.loop import FixedStepLoop
from invaders.app.outputs import OutputError, writing
from invaders.app.recording import Recorder
from invaders.app.render import CandidateWatch, Renderer
from invaders.app.signals import StopSignals
from invaders.app.sound import SoundBoard
from invaders.app.splash import FPS
from invaders.atomic import atomic_writer
from invaders.display import fitting_scale, open_display
from invaders.engine.adaptive import DEFAULT_BROADPHASE
from invaders.game.actions import Action
from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.players import PROMPT
from invaders.game.replay import Checkpoints, Replay
from invaders.game.world import Phase, TickReport, World
from invaders.lab.autopilot import Autopilot
from invaders.lab.live import Choice
from invaders.lab.picture import Prompt
from invaders.quiet import say

LEFT_KEYS = (pygame.K_LEFT, pygame.K_a)
RIGHT_KEYS = (pygame.K_RIGHT, pygame.K_d)
FIRE_KEYS = (pygame.K_SPACE,)
START_KEYS = (pygame.K_RETURN, pygame.K_KP_ENTER, pygame.K_1)
TWO_PLAYER_KEYS = (pygame.K_2, pygame.K_KP2)
FIRE = int(Action.FIRE)
START = int(Action.START)
START2 = int(Action.START2)
MAX_FPS = 240  # never draw faster than this, whatever the replay speed
IDLE_FPS = 10  # paused or at a replay's end: wake this often, to answer keys
SAVE_EVERY = 180  # ticks between autosaves of a recording (3 s)
DEFAULT_SCALE = 3  # the window's, where none is asked for (and it fits on the screen)


def keyboard_actions(pressed) -> int:
    """This frame's held keys as input bits."""
    bits = Action.NONE
    if any(pressed[k] for k in LEFT_KEYS):
        bits |= Action.LEFT
    if any(pressed[k] for k in RIGHT_KEYS):
        bits |= Action.RIGHT
    if any(pressed[k] for k in FIRE_KEYS):
        bits |= Action.FIRE
    if any(pressed[k] for k in START_KEYS):
        bits |= Action.START
    return int(bits)


def _ask_window_size(size: tuple[int, int]) -> pygame.Surface:
    """The window's surface after asking for `size`: a window manager may keep its own (a
    window maximized or tiled), where pygame warns that the size was forced; the picture
    is laid out in whatever size the window has."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return pygame.display.set_mode(size, pygame.RESIZABLE)


def fit_beside_panel(w: int, h: int, screen_w: int) -> tuple[int, int]:
    """The playfield's size (w, h) made smaller, its shape kept, until it and the lab's
    panel fit across a screen `screen_w` wide."""
    while w + panel_width(h / SCREEN_H) > screen_w and h > SCREEN_H:
        h -= 1
        w = round(h * SCREEN_W / SCREEN_H)
    return w, h


class Session:
    """A game in a window: one `frame()` per displayed frame."""

    def __init__(self, world: World, target: pygame.Surface, clock: Callable[[], float],
                 replay: Replay | None = None, speed: int = 1,
                 recorder: Recorder | None = None, overlay: bool = False,
                 pilot: Autopilot | None = None, sounds: SoundBoard | None = None,
                 lab: Choice | None = None) -> None:
        self.world = world
        self.target = target
        self.clock = clock
        self.pilot = pilot  # plays instead of the keys (the attract cycle's demo)
        self.sounds = sounds
        self.loop = FixedStepLoop(clock, world.config.tick_hz * speed,
                                  max_catch_up=5 * speed)
        self.renderer = Renderer()
        self.inputs: Iterator[int] | None = replay.actions() if replay else None
        # The replay's checkpoints, each compared as the world reaches its tick (kept packed:
        # a replay of 145,000 took 0.5 s to index as objects and ran max() each frame).
        self.checkpoints = replay.checkpoints if replay else Checkpoints()
        self._next_checkpoint = 0  # the first not yet passed
        self.switches = list(reversed(replay.switches)) if replay else []  # lab, by tick
        self.replay_done = False
        self.first_difference: int | None = None  # the first checkpoint tick that differed
        self.start_requested = False  # Enter after a replay's end: the caller starts a game
        self.fire_presses = 0  # fire key-downs not yet given to a tick
        self.start_pressed = False
        self.start_bits = START  # START2 once 2 was pressed: the next game has two players
        self.needs_draw = True  # something besides a tick changed what the window shows
        self.windowed: tuple[tuple[int, int], tuple[int, int]] | None = None  # before F11
        self.tick_rate = world.config.tick_hz * speed
        self.recorder = recorder
        self.watch = CandidateWatch()
        self.overlay = False
        self.set_overlay(overlay)
        self.paused = False
        self.report: TickReport | None = None
        self.lab: LabControl | None = None
        self.lab_open = False
        self.painter = PanelPainter()
        if lab is not None:
            self.set_lab(True, lab)

    def set_lab(self, on: bool, choice: Choice | None = None) -> None:
        """Open the lab panel (with `choice`, or the lab's last one) or close it."""
        if on:
            if self.lab is None:
                self.lab = LabControl(self.world, self.clock, choice or Choice(),
                                      self.recorder)
            elif choice is not None and choice != self.lab.choice:
                self.lab.switch(choice)
            else:
                self.lab.reopen()
        elif self.lab is not None:
            self.lab.close()
        self.lab_open = on
        self.set_overlay(self.overlay)  # the detector may be a new one
        self.needs_draw = True

    def set_overlay(self, on: bool) -> None:
        """The overlay watches the detector only while it is shown: off, it costs nothing."""
        observers = self.world.detector.observers
        if on and self.watch not in observers:
            observers.append(self.watch)
        elif not on and self.watch in observers:
            observers.remove(self.watch)
        self.overlay = on

    def handle(self, event: pygame.event.Event) -> bool:
        """React to one window event; False means quit."""
        if event.type == pygame.QUIT:
            return False
        self.needs_draw = True  # a key, an expose, a resize: show the answer
        if event.type in (pygame.VIDEORESIZE, pygame.WINDOWSIZECHANGED):
            self._follow_window()
        if event.type == pygame.KEYDOWN:
            if event.key == pygame.K_ESCAPE:
                return False
            if event.key in FIRE_KEYS:
                self.fire_presses += 1
            elif event.key in START_KEYS + TWO_PLAYER_KEYS:
                self.start_pressed = True
                self.start_bits = START2 if event.key in TWO_PLAYER_KEYS else START
                if self.replay_done:
                    self.start_requested = True
            if event.key == pygame.K_p:
                self.paused = not self.paused
                self.loop.resume()
            elif event.key == pygame.K_F3:
                self.set_overlay(not self.overlay)
            elif event.key == pygame.K_F4:
                self._resize_for_panel(not self.lab_open)
                self.set_lab(not self.lab_open)
            elif self.lab_open and self.lab is not None and self.lab.key(
                    event.key, bool(event.mod & pygame.KMOD_SHIFT)):
                self.set_overlay(self.overlay)
            elif event.key == pygame.K_m and self.sounds is not None:
                self.sounds.toggle_mute()
            elif event.key == pygame.K_F11:
                with contextlib.suppress(pygame.error):  # a driver that cannot: stay as is
                    self._toggle_fullscreen()
                self._follow_window()
        return True

    def _own_window(self) -> bool:
        """Whether the target is the window (not a surface a test or a screenshot gave)."""
        return pygame.display.get_init() and pygame.display.get_surface() is self.target

    def _toggle_fullscreen(self) -> None:
        """Full screen at the desktop's size, then back to the window's own size and place
        (pygame's toggle_fullscreen re-creates the window and keeps neither)."""
        if not self._own_window():
            return
        if pygame.display.is_fullscreen():
            size, place = self.windowed or (self.target.get_size(), None)
            _ask_window_size(size)  # X11 leaves full screen first, at full size,
            pygame.event.pump()
            if pygame.display.get_window_size() != size:  # and takes the size when asked again
                _ask_window_size(size)
            if place is not None:
                pygame.display.set_window_position(place)
        else:
            self.windowed = (pygame.display.get_window_size(),
                             pygame.display.get_window_position())
            pygame.display.set_mode((0, 0), pygame.FULLSCREEN)

    def _resize_for_panel(self, opening: bool) -> None:
        """Widen the window by the panel (or narrow it back) where it stands, never past the
        screen's width (the playfield made smaller if it must), unless it fills the screen;
        a window the window manager keeps at its size (maximized) shares it with the panel."""
        if not self._own_window() or pygame.display.is_fullscreen():
            return
        w, h = self.target.get_size()
        place = pygame.display.get_window_position()
        if opening:
            w, h = fit_beside_panel(w, h, pygame.display.get_desktop_sizes()[0][0])
            width = w + panel_width(h / SCREEN_H)
        else:
            width = max(SCREEN_W, w - panel_width(h / SCREEN_H))
        self.target = _ask_window_size((width, h))
        pygame.display.set_window_position(place)

    def _follow_window(self) -> None:
        """Draw into the window's surface as it is now (resizing can replace it)."""
        surface = pygame.display.get_surface() if pygame.display.get_init() else None
        if surface is not None:
            self.target = surface

    def frames_per_second(self) -> int:
        """How often the loop should wake: at the tick rate while the game runs (a frame
        per tick), seldom while nothing moves."""
        if self.paused or self.replay_done:
            return IDLE_FPS
        return min(self.tick_rate, MAX_FPS)

    def frame(self, held: int, stop: Callable[[], bool] | None = None) -> bool:
        """Run the ticks real time has banked (with `held` keys, unless watching a replay;
        fewer if `stop()` asks between two), then draw if anything changed. Returns whether
        it drew."""
        ticks, alpha = (0, 0.0) if self.paused or self.replay_done else self.loop.frame()
        ran = 0
        for _ in range(ticks):
            if stop is not None and stop():
                break
            bits = self._tick_input(held)
            if self.inputs is not None:
                replayed = next(self.inputs, None)
                if replayed is None:
                    self.replay_done = True
                    break
                bits = replayed
            while self.switches and self.switches[-1][0] == self.world.tick:
                self._replay_switch(self.switches.pop()[1])
            try:
                self.report = self.world.step(bits)
            except BaseException:
                if self.recorder is not None:  # (half a tick played: saved up to a whole one)
                    self.recorder.cut_off()
                raise
            if self.recorder is not None:
                self.recorder.tick(bits)  # exactly what the tick used
            ran += 1
            if self.sounds is not None:
                self.sounds.react(self.report.events, self.world)
            self._compare()
        checked = self.checkpoints.ticks()
        if self.inputs is not None and not self.replay_done and self.world.tick >= (
                checked[-1] if checked else 0):
            self.replay_done = next(self.inputs, None) is None
            self.needs_draw = True
        if not ran and not self.needs_draw:
            return False
        self.needs_draw = False
        self.draw(alpha)
        return True

    def draw(self, alpha: float = 0.0) -> None:
        """The playfield, and beside it the lab's panel when it is open."""
        target = self.target
        if self.lab_open and self.lab is not None:
            w, h = target.get_size()
            scale = h / SCREEN_H
            width = panel_width(scale)
            play = pygame.Rect(0, 0, max(1, w - width), h)
            field = target.subsurface(play)
            view = self.renderer.draw(field, self.world, alpha, self.overlay, self.report,
                                      self.watch.pairs, self.paused, self.replay_verdict())
            draw_marks(field, view, self.lab)
            self.painter.draw(target, pygame.Rect(play.right, 0, w - play.right, h), self.lab,
                              scale)
            return
        self.renderer.draw(target, self.world, alpha, self.overlay, self.report,
                           self.watch.pairs, self.paused, self.replay_verdict())

    def _replay_switch(self, data: dict) -> None:
        """A replay's lab switch: the method it recorded, shown in the open panel."""
        choice = Choice.from_dict(data)  # checked when the replay was loaded
        if self.lab is None:
            self.set_lab(True, choice)
        else:
            self.lab.switch(choice)
            self.lab_open = True
            self.set_overlay(self.overlay)

    def _tick_input(self, held: int) -> int:
        """This tick's input: the held keys, plus key presses latched from the event queue,
        so a press and release between two frames still counts, once. A press while the
        world still sees fire down waits one tick with fire up, so it is a new press."""
        if self.pilot is not None:
            return self.pilot.actions(self.world)
        bits = held
        if self.start_pressed:
            bits |= self.start_bits
            self.start_pressed = False
        self.start_bits = START  # START2 once 2 was pressed: the next game has two players
        if self.fire_presses:
            if self.world.fire_was_down:
                bits &= ~FIRE
            else:
                bits |= FIRE
                self.fire_presses -= 1
        return bits

    def _compare(self) -> None:
        """The world against the replay's checkpoint at its tick, if there is one: the
        first tick that differs is kept."""
        ticks, tick = self.checkpoints.ticks(), self.world.tick
        while self._next_checkpoint < len(ticks) and ticks[self._next_checkpoint] < tick:
            self._next_checkpoint += 1
        if (self._next_checkpoint < len(ticks) and ticks[self._next_checkpoint] == tick
                and self.first_difference is None
                and self.world.state_hash() != self.checkpoints[self._next_checkpoint].hash):
            self.first_difference = tick

    def replay_verdict(self) -> str | None:
        """Once a replay has ended, what its check found (None while it plays)."""
        if not self.replay_done:
            return None
        if self.first_difference is None:
            return "CHECKPOINTS MATCHED"
        return f"DIFFERS FROM TICK {self.first_difference}"


def open_window(scale: int | None, title: str = "invaders", lab: bool = False
                ) -> pygame.Surface:
    """A window at the scale asked (DEFAULT_SCALE if none), or at the largest that fits on
    the screen, saying so if one was asked for; pygame.error if there is no display to show
    one (`open_display`)."""
    open_display()

    def size_at(scale: int) -> tuple[int, int]:
        return SCREEN_W * scale + (panel_width(scale) if lab else 0), SCREEN_H * scale

    fitting = fitting_scale(scale or DEFAULT_SCALE, size_at)
    if scale is not None and fitting < scale:
        screen_w, screen_h = pygame.display.get_desktop_sizes()[0]
        say(f"invaders: a window at scale {scale} would not fit on this {screen_w}x{screen_h} "
            f"screen: opened at scale {fitting} (resize it, or F11 for the full screen)")
    window = pygame.display.set_mode(size_at(fitting), pygame.RESIZABLE)
    pygame.display.set_caption(f"{title}  (arrows/A D move, space fires, P pause, "
                               "F3 overlay, F4 lab)")
    return window


class App:
    """A window's life: the attract cycle between games, the player's game, or a replay.

    The player's world lives across games (so its high score and a recording carry on) and
    only steps while a game is shown; the attract cycle's demo has a world of its own.
    """

    def __init__(self, world: World, window: pygame.Surface, clock: Callable[[], float],
                 replay: Replay | None = None, speed: int = 1,
                 recorder: Recorder | None = None, overlay: bool = False,
                 broadphase: str = DEFAULT_BROADPHASE, attract_first: bool = True,
                 sounds: SoundBoard | None = None, lab: Choice | None = None) -> None:
        self.window, self.clock, self.broadphase = window, clock, broadphase
        self.session = Session(world, window, clock, replay, speed, recorder, overlay,
                               sounds=sounds, lab=lab)
        self.attract = None if replay is not None else Attract(window, clock, world, self._demo)
        self.mode = "attract" if self.attract is not None and attract_first else "game"

    def _start(self, players: int) -> None:
        """A coin and a start button: PLAY PLAYER<1> with the new score flashing for three
        seconds (088D-08CE), then the next tick starts a game of one or two players (the
        window's first game, not begun yet, is made again for two)."""
        self.mode = "prompt"
        self.prompt_since = self.clock()
        session = self.session
        world = session.world
        if world.tick == 0 and world.players != players and session.recorder is None:
            session = self._fresh_session(players)
            if self.attract is not None:
                self.attract.scores = session.world
        session.start_bits = START2 if players == 2 else START
        self.prompt_players = players
        self.prompted: Prompt | None = None

    def _fresh_session(self, players: int) -> Session:
        """A new world of the same seed in a new session, in the same window with the same
        overlay, sound and lab: the one the window now shows."""
        old = self.session
        lab = old.lab.choice if old.lab_open and old.lab else None
        world = World(seed=old.world.seed, broadphase=self.broadphase, players=players)
        self.session = Session(world, old.target, self.clock, overlay=old.overlay,
                               sounds=old.sounds, lab=lab)
        return self.session

    def _prompt_frame(self) -> bool:
        """A frame of PLAY PLAYER<1>; when its time is up, the game. Returns whether it drew."""
        left = PROMPT - int((self.clock() - self.prompt_since) * FPS)
        session, attract = self.session, self.attract
        assert attract is not None  # (the prompt follows the attract cycle's start keys)
        if left <= 0:
            self.mode = "game"
            session.loop.resume()
            session.start_pressed = True
            session.needs_draw = True
            return False
        prompt = Prompt(self.prompt_players, left)
        if self.prompted is not None and (self.prompted.left & 4) == (left & 4):
            return False
        self.prompted = prompt
        attract.renderer.draw_card(session.target, session.world,
                                   [("PLAY PLAYER<1>", 56, 112)], [], prompt)
        return True

    def _demo(self) -> Session:
        world, pilot = demo_world(self.broadphase)
        return Session(world, self.window, self.clock, pilot=pilot)

    def frames_per_second(self) -> int:
        if self.mode in ("attract", "prompt") and self.attract is not None:
            return self.attract.frames_per_second()
        return self.session.frames_per_second()

    def step(self, events: list[pygame.event.Event], held: int,
             stop: Callable[[], bool] | None = None) -> tuple[bool, bool]:
        """One frame: (go on, drew something)."""
        if self.mode == "prompt":
            if any(event.type == pygame.QUIT or (event.type == pygame.KEYDOWN
                                                 and event.key == pygame.K_ESCAPE)
                   for event in events):
                return False, False
            drew = self._prompt_frame()
            if self.mode == "prompt":
                return True, drew
        if self.mode == "attract" and self.attract is not None:
            for event in events:
                if event.type == pygame.QUIT or (event.type == pygame.KEYDOWN
                                                 and event.key == pygame.K_ESCAPE):
                    return False, False
                if event.type in (pygame.VIDEORESIZE, pygame.WINDOWSIZECHANGED) or (
                        event.type == pygame.KEYDOWN and event.key == pygame.K_F11):
                    self.session.handle(event)  # follows the window (F11 toggles it)
                    self.attract.redraw(self.session.target)
                elif event.type == pygame.KEYDOWN and event.key == pygame.K_m:
                    self.session.handle(event)  # mute or unmute
                elif event.type == pygame.KEYDOWN and event.key in START_KEYS + TWO_PLAYER_KEYS:
                    self._start(2 if event.key in TWO_PLAYER_KEYS else 1)
            if self.mode == "attract":
                return True, self.attract.frame()
            return True, self._prompt_frame()
        elif not all(self.session.handle(event) for event in events):
            return False, False
        before = self.session.world.tick
        drew = self.session.frame(held, stop)
        world = self.session.world
        if self.session.start_requested:  # Enter at a replay's end: a game of one's own
            self._fresh_session(1)
            pygame.display.set_caption("invaders  (arrows/A D move, space fires, "
                                       "P pause, F3 overlay, F4 lab)")
        elif (self.attract is not None and world.tick > before
              and world.phase is Phase.GAME_OVER and world.phase_timer <= 0):
            self.mode = "attract"  # GAME OVER has been shown: the cabinet's cycle again
            self.attract.restart()
            self.attract.redraw(self.session.target)
        return True, drew


def _said_once() -> Callable[[OutputError], None]:
    """What an autosave's failure does in a window: one line, the first time, and the
    game plays on (its lines not written are kept for the next save, the last at its end,
    which says so again if it too fails): a player is not thrown out of a game by a full
    disk."""
    said: list[OutputError] = []

    def say_once(failure: OutputError) -> None:
        if not said:
            say(f"invaders: {failure}; play goes on, and what is not written is kept for the "
                "next autosave (and the last, at the end)")
            said.append(failure)
    return say_once


def play(seed: int = 0, scale: int | None = None, broadphase: str = DEFAULT_BROADPHASE,
         overlay: bool = False, record: str | None = None, replay: Replay | None = None,
         speed: int = 1, mute: bool = False, lab: Choice | None = None, players: int = 1) -> int:
    """Open a window: the attract cycle until Enter or 1 starts a game, 2 a game of two
    players (or a replay to watch), until Esc, the window closes or a signal.

    A recording is saved every few seconds and again when the window closes however it
    closes, always between two ticks, by appending whole lines: at worst the last seconds
    are lost, never the file. A signal (Ctrl-C, TERM, HUP) ends it with the shell's code
    (130, 143, 129) after saying where the recording went.
    """
    if replay is not None:
        world = replay.world(broadphase)
    else:
        world = World(seed=seed, broadphase=broadphase, players=players)
    recorder = Recorder(world, record, SAVE_EVERY, on_failure=_said_once()) if record else None
    title = "invaders" if replay is None else f"invaders: replay at {speed}x"
    window = open_window(scale, title, lab is not None)
    app = App(world, window, time.perf_counter, replay, speed, recorder, overlay,
              broadphase, attract_first=recorder is None,  # a recording starts with its game
              sounds=SoundBoard(muted=mute), lab=lab)
    frame_clock = pygame.time.Clock()
    with StopSignals() as signals:
        try:
            while signals.received is None:
                going, drew = app.step(pygame.event.get(),
                                       keyboard_actions(pygame.key.get_pressed()),
                                       stop=lambda: signals.received is not None)
                if not going:
                    break
                if drew:
                    pygame.display.flip()
                frame_clock.tick(app.frames_per_second())
        finally:
            if recorder is not None:
                with writing(record or "", "replay"):
                    recorder.save()
            pygame.display.quit()
    saved = f"saved {recorder.path}: {recorder.ticks} ticks" if recorder is not None else ""
    if signals.received is not None:  # one line for the stop and what was saved
        say(f"invaders: stopped by {signals.name}" + (f"; {saved}" if saved else ""))
        return signals.exit_code
    if saved:
        print(saved)
    return 0


def screenshot(path: str, seed: int = 0, ticks: int = 600, scale: int = 3,
               overlay: bool = False, broadphase: str = DEFAULT_BROADPHASE,
               attract: str | None = None, lab: Choice | None = None,
               players: int = 1) -> int:
    """Play `ticks` ticks headless with the autopilot, then save the window as a PNG (or,
    with `attract`, that still screen of the attract cycle); with `lab`, the lab's panel
    beside it and the errors of its method marked."""
    from invaders.app.headless import use_dummy_drivers

    use_dummy_drivers()
    world = World(seed=seed, broadphase=broadphase, players=players)
    pilot = Autopilot(seed)
    width = SCREEN_W * scale + (panel_width(scale) if lab is not None else 0)
    target = pygame.Surface((width, SCREEN_H * scale))
    if attract is not None:
        texts, pictures = card(attract)
        Renderer().draw_card(target, World(seed=seed), texts, pictures)
    else:
        session = Session(world, target, time.perf_counter, overlay=overlay, lab=lab)
        for _ in range(ticks):
            session.report = world.step(pilot.actions(world))
        session.draw()
    png = io.BytesIO()
    pygame.image.save(target, png, "screenshot.png")
    with writing(path, "screenshot"), atomic_writer(path, "wb") as handle:
        handle.write(png.getvalue())
    moment = (f"the attract cycle's {attract}" if attract is not None
              else f"after {ticks} ticks (seed {seed})")
    print(f"saved {path}: {moment}")
    return 0
