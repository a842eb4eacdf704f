"""The attract cycle: what the cabinet shows between games, until a player starts one.

The ROM's sequence (`invaders.app.splash`), frame by frame at 60 a second: the title and the
score advance table typed out, the alien that straightens PLAY's Y (every other cycle), the
demo (a game of its own, played by the ROM's demo moves until its cannon is hit, scoring
nothing and showing the player's scores), INSERT  COIN and the credit lines, and on the
same cycles the alien that shoots the extra C of INSERT CCOIN. Enter or 1 starts a game,
2 a game of two (as a coin and a start button would); Esc quits.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import pygame

from invaders.app.render import Renderer
from invaders.app.splash import FPS, Screen, Script
from invaders.game import art
from invaders.game.world import World

DEMO_SEED = 1978
# Screens `play --screenshot --attract` can save: a step of the first (animated) cycle and
# how many frames into it.
STILLS = {"title": (2, None), "table": (8, None), "pull": (12, 50), "insert": (-4, None)}

Card = list[tuple[str, int, int]]


class Demo(Protocol):
    """The demo's game as the cycle drives it (the window's session of an autopilot game)."""

    world: World
    target: pygame.Surface
    needs_draw: bool

    def frame(self, held: int) -> bool: ...


def card(still: str) -> tuple[Card, list[tuple[art.Art, int, int]]]:
    """The texts and pictures of a moment of the cycle (a step's end, or a frame into it)."""
    script = Script(animated=True)
    index, frame = STILLS[still]
    index %= len(script.steps)
    step = script.steps[index]
    screen = script.screen_at(index, frame if frame is not None else (step.frames or 0))
    return screen.texts, screen.drawn()


class Attract:
    """The cycle's steps one after the other as real time passes (the demo as long as its
    game lasts); the first cycle has the animations, and every other one after it."""

    def __init__(self, target: pygame.Surface, clock: Callable[[], float], scores: World,
                 make_demo: Callable[[], Demo]) -> None:
        self.target = target
        self.clock = clock
        self.scores = scores  # the player's world: its score bar is shown throughout
        self.make_demo = make_demo
        self.renderer = Renderer()
        self.animated = True
        self.restart()

    def restart(self) -> None:
        self.script = Script(self.animated)
        self.index = 0
        self.since = self.clock()  # when the current step began
        self.demo: Demo | None = None
        self.shown: tuple | None = None  # what the last drawing showed

    @property
    def step(self) -> str:
        """The kind of step under way ("demo" while the demo plays)."""
        return self.script.steps[self.index].kind

    def frames_per_second(self) -> int:
        return FPS

    def frame(self) -> bool:
        """Move through the steps whose time is up; draw what shows. Returns whether it
        drew."""
        now = self.clock()
        while True:
            step = self.script.steps[self.index]
            if step.kind == "demo":
                drew = self._demo_frame()
                if self.demo is not None:
                    return drew
                self.since = now
                continue
            if step.frames is None or now - self.since < step.frames / FPS:
                break
            self.since += step.frames / FPS
            self._next_step()
        elapsed = int((now - self.since) * FPS)
        screen = self.script.screen_at(self.index, elapsed)
        shown = (tuple(screen.texts), tuple(screen.drawn()))
        if shown == self.shown:
            return False
        self._draw(screen)
        self.shown = shown
        return True

    def _next_step(self) -> None:
        self.index += 1
        if self.index == len(self.script.steps):
            self.animated = not self.animated  # (0BDA: the splash animations every other time)
            self.script = Script(self.animated)
            self.index = 0

    def _demo_frame(self) -> bool:
        """A frame of the demo; once its cannon has been hit and exploded, the next step."""
        if self.demo is None:
            self.demo = self.make_demo()
            world = self.demo.world
            world.score, world.hi_score = self.scores.score, self.scores.hi_score
            self.demo_ships = world.ships
        self.demo.target = self.target
        drew = self.demo.frame(0)
        world = self.demo.world
        if world.ships < self.demo_ships or world.phase.name == "GAME_OVER":
            self.demo = None
            self.shown = None
            self._next_step()
        return drew

    def _draw(self, screen: Screen) -> None:
        self.renderer.draw_card(self.target, self.scores, screen.texts, screen.drawn())

    def redraw(self, target: pygame.Surface) -> None:
        self.target = target
        self.shown = None
        if self.demo is not None:
            self.demo.needs_draw = True


def demo_world(broadphase: str):
    """The demo's own world, which scores nothing, and its player: the ROM's demo moves."""
    from invaders.app.splash import DemoPilot

    world = World(seed=DEMO_SEED, broadphase=broadphase)
    world.scoring = False
    return world, DemoPilot()
