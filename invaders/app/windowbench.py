"""`invaders bench --window`: what a game costs in a real window, as CPU seconds a second.

Each round plays the autopilot's game in a window for some seconds twice, in fresh processes
taking turns: SDL showing the window's surface through the native framebuffer (what the
program does) and through a renderer (SDL's default where a renderer exists, which without
a GPU draws the whole window in software every frame). Printed as medians over the rounds
with their spread, and the frames a second each held.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys

from invaders.game.config import SCREEN_W

PATHS = (("native framebuffer", "0"), ("renderer", "1"))

CHILD = """
import json, sys, time, pygame
from invaders.app.play import Session, open_window
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
seconds, scale = float(sys.argv[1]), int(sys.argv[2])
window = open_window(scale)
world = World(seed=3)
session = Session(world, window, time.perf_counter, pilot=Autopilot(3))
clock = pygame.time.Clock()
for _ in range(30):  # settle: the window mapped, the first frames drawn
    pygame.event.pump(); session.frame(0) and pygame.display.flip(); clock.tick(60)
start, cpu, frames = time.perf_counter(), time.process_time(), 0
while time.perf_counter() - start < seconds:
    pygame.event.pump()
    if session.frame(0):
        pygame.display.flip()
        frames += 1
    clock.tick(60)
wall = time.perf_counter() - start
print(json.dumps([(time.process_time() - cpu) / wall, frames / wall, window.get_size()]))
"""


class NoWindow(RuntimeError):
    """There is no display to open a window on."""


def _one(acceleration: str, seconds: float, scale: int
         ) -> tuple[float, float, tuple[int, int]]:
    """One game timed in a fresh process: CPU seconds a second, frames a second, and the
    window's size (the scale asked for, or the largest that fits on the screen)."""
    env = {k: v for k, v in os.environ.items() if k != "SDL_VIDEODRIVER"}
    env["SDL_FRAMEBUFFER_ACCELERATION"] = acceleration
    result = subprocess.run([sys.executable, "-c", CHILD, str(seconds), str(scale)],
                            capture_output=True, text=True, env=env, check=False,
                            timeout=seconds * 4 + 60)
    if result.returncode != 0:
        last = (result.stderr.strip().splitlines() or ["no output"])[-1]
        raise NoWindow(f"the window could not be timed: {last}")
    cpu, fps, (width, height) = json.loads(result.stdout)
    return cpu, fps, (width, height)


def window_bench(rounds: int, seconds: float = 10.0, scale: int = 3) -> list[str]:
    """The table's lines: each path's CPU seconds a second and frames a second."""
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise NoWindow("--window needs a display (DISPLAY or WAYLAND_DISPLAY)")
    seen: dict[str, list[tuple[float, float]]] = {name: [] for name, _ in PATHS}
    size = (0, 0)
    for _ in range(rounds):
        for name, acceleration in PATHS:
            cpu_used, frame_rate, size = _one(acceleration, seconds, scale)
            seen[name].append((cpu_used, frame_rate))
    lines = [f"a game in a {size[0]}x{size[1]} window (scale {size[0] // SCREEN_W}), {rounds} "
             f"rounds of {seconds:g} s taking turns: CPU seconds a second, median "
             "(lowest..highest round), frames a second"]
    for name, _ in PATHS:
        cpu = [c for c, _ in seen[name]]
        fps = statistics.median(f for _, f in seen[name])
        lines.append(f"   {name:<20} {statistics.median(cpu):.3f} ({min(cpu):.3f}.."
                     f"{max(cpu):.3f})   {fps:.1f} frames a second")
    ratios = [r / n for (n, _), (r, _) in zip(seen["native framebuffer"], seen["renderer"],
                                                strict=True)]
    lines.append(f"   the renderer costs {statistics.median(ratios):.1f}x "
                 f"({min(ratios):.1f}..{max(ratios):.1f}) the native framebuffer's CPU")
    return lines
