"""The attract cycle: what the cabinet shows between games, until a player starts one.

Four screens in turn: PLAY SPACE INVADERS, the score advance table (the saucer's mystery
score and the three aliens' points, with their pictures), a demo game played by the
autopilot in a world of its own, and INSERT COIN / PUSH 1 PLAYER BUTTON. Enter or 1 starts
a game (as a coin and the start button would); Esc quits.
"""

from __future__ import annotations

from collections.abc import Callable

import pygame

from invaders.app.render import Renderer
from invaders.game import art
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot

SCREENS = (("title", 4.0), ("table", 6.0), ("demo", 20.0), ("insert", 4.0))  # seconds each
DEMO_SEED = 1978

Card = list[tuple[str, int, int]]


def card(screen: str) -> tuple[Card, list[tuple[art.Art, int, int]]]:
    """The texts and pictures of a still screen of the cycle (the demo is a game)."""
    if screen == "title":
        return [("PLAY", 96, 64), ("SPACE   INVADERS", 48, 88),
                ("ENTER OR 1 STARTS", 44, 200)], []
    if screen == "table":
        return ([("*SCORE ADVANCE TABLE*", 28, 112), ("=? MYSTERY", 88, 136),
                 ("=30 POINTS", 88, 152), ("=20 POINTS", 88, 168), ("=10 POINTS", 88, 184)],
                [(art.SAUCER, 60, 135), (art.ALIEN_BY_ROW[4][0], 64, 152),
                 (art.ALIEN_BY_ROW[2][0], 64, 168), (art.ALIEN_BY_ROW[0][0], 64, 184)])
    return [("INSERT  COIN", 64, 96), ("PUSH", 96, 128), ("1 PLAYER BUTTON", 52, 144),
            ("ENTER OR 1 STARTS", 44, 200)], []


class Attract:
    """The cycle's screens, one after the other as real time passes."""

    def __init__(self, target: pygame.Surface, clock: Callable[[], float], scale: int,
                 scores: World, make_demo: Callable[[], object]) -> None:
        self.target = target
        self.clock = clock
        self.scores = scores  # the player's world: its score bar is shown throughout
        self.make_demo = make_demo
        self.renderer = Renderer(scale)
        self.restart()

    def restart(self) -> None:
        self.index = 0
        self.since = self.clock()
        self.demo = None
        self.drawn = False

    @property
    def screen(self) -> str:
        return SCREENS[self.index][0]

    def frames_per_second(self) -> int:
        return 60 if self.screen == "demo" else 10

    def frame(self) -> bool:
        """Move on to the next screen when this one's time is up; draw. Returns whether
        it drew."""
        now = self.clock()
        if now - self.since >= SCREENS[self.index][1]:
            self.index = (self.index + 1) % len(SCREENS)
            self.since = now
            self.demo = None
            self.drawn = False
        if self.screen == "demo":
            if self.demo is None:
                self.demo = self.make_demo()
            self.demo.target = self.target
            return self.demo.frame(0)
        if self.drawn:
            return False
        texts, pictures = card(self.screen)
        self.renderer.draw_card(self.target, self.scores, texts, pictures)
        self.drawn = True
        return True

    def redraw(self, target: pygame.Surface) -> None:
        self.target = target
        self.drawn = False
        if self.demo is not None:
            self.demo.needs_draw = True


def demo_world(broadphase: str) -> tuple[World, Autopilot]:
    """The demo's own world and its player (the same game every time)."""
    return World(seed=DEMO_SEED, broadphase=broadphase), Autopilot(DEMO_SEED, "expert")



