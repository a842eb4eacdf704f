"""The windowed game: keyboard -> actions, the fixed-step loop, the renderer."""

from __future__ import annotations

import time

import pygame

from invaders.atomic import atomic_path
from invaders.autopilot import Autopilot
from invaders.config import SCREEN_H, SCREEN_W
from invaders.loop import FixedStepLoop
from invaders.render import Renderer
from invaders.sim.actions import Action
from invaders.sim.world import World

LEFT_KEYS = (pygame.K_LEFT, pygame.K_a)
RIGHT_KEYS = (pygame.K_RIGHT, pygame.K_d)
FIRE_KEYS = (pygame.K_SPACE,)
START_KEYS = (pygame.K_RETURN, pygame.K_KP_ENTER, pygame.K_1)
MAX_FPS = 240  # render at the display's pace, but never spin faster than this


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


def play(seed: int = 0, scale: int = 3, broadphase: str = "grid", overlay: bool = False) -> int:
    """Open a window and play until Esc or the window closes."""
    pygame.display.init()
    window = pygame.display.set_mode((SCREEN_W * scale, SCREEN_H * scale))
    pygame.display.set_caption("invaders  (arrows/A D move, space fires, P pause, F3 overlay)")
    world = World(seed=seed, broadphase=broadphase)
    renderer = Renderer(scale)
    loop = FixedStepLoop(time.perf_counter, world.config.tick_hz)
    frame_clock = pygame.time.Clock()
    paused = False
    stats = None
    try:
        while True:
            for event in pygame.event.get():
                if event.type == pygame.QUIT:
                    return 0
                if event.type == pygame.KEYDOWN:
                    if event.key == pygame.K_ESCAPE:
                        return 0
                    if event.key == pygame.K_p:
                        paused = not paused
                        loop.resume()
                    if event.key == pygame.K_F3:
                        overlay = not overlay
            ticks, alpha = (0, 0.0) if paused else loop.frame()
            actions = keyboard_actions(pygame.key.get_pressed())
            for _ in range(ticks):
                stats = world.step(actions).stats
            renderer.draw(window, world, alpha, overlay, stats, paused)
            pygame.display.flip()
            frame_clock.tick(MAX_FPS)
    finally:
        pygame.display.quit()


def screenshot(path: str, seed: int = 0, ticks: int = 600, scale: int = 3,
               overlay: bool = False, broadphase: str = "grid") -> int:
    """Play `ticks` ticks headless with the autopilot, then save the window as a PNG."""
    from invaders.headless import use_dummy_drivers

    use_dummy_drivers()
    world = World(seed=seed, broadphase=broadphase)
    pilot = Autopilot(seed)
    stats = None
    for _ in range(ticks):
        stats = world.step(pilot.actions(world)).stats
    target = pygame.Surface((SCREEN_W * scale, SCREEN_H * scale))
    Renderer(scale).draw(target, world, 0.0, overlay, stats)
    with atomic_path(path) as tmp:
        pygame.image.save(target, tmp)
    print(f"saved {path} after {ticks} ticks (seed {seed})")
    return 0
