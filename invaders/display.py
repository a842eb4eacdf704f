"""SDL's display opened for a window: the game's, and the environment's in human mode.

Where there is no display, SDL falls back without a word to a driver that shows nothing
('offscreen', 'dummy'): a window opened there would never be seen, so it is refused with a
pygame.error saying why, which the caller turns into its own one line. A driver asked for
by name (SDL_VIDEODRIVER) is taken as asked: the tests' dummy one. A window is opened no
larger than the screen holds (`fitting_scale`).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable

import pygame

from invaders.quiet import c_stderr_quiet

NO_WINDOW_DRIVERS = ("dummy", "offscreen")
# What a window's frame and the desktop's own bars take of the screen, across and down,
# beside the window's picture: borders; a title bar and a task bar, or macOS's menu bar,
# dock and title bar (about 130 px, the most of those).
FRAME_PX = (16, 130)


def open_display() -> None:
    """SDL's display, ready for `pygame.display.set_mode`, or pygame.error if it would show
    no window."""
    asked = os.environ.get("SDL_VIDEODRIVER")
    if (asked is None and sys.platform.startswith("linux")
            and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY")):
        raise pygame.error("no display: neither DISPLAY nor WAYLAND_DISPLAY is set")
    # A window's picture is a plain surface: SDL shows it through the native framebuffer
    # (X11's shared memory) rather than uploading it to a renderer each frame, which
    # without a GPU (Mesa's llvmpipe, Xvfb) costs 7 ms of CPU a frame at scale 3, against
    # 0.06 ms. Set the variable to choose otherwise.
    os.environ.setdefault("SDL_FRAMEBUFFER_ACCELERATION", "0")
    with c_stderr_quiet():  # (SDL's drivers probed in turn say why each is not there)
        pygame.display.init()
    driver = pygame.display.get_driver()
    if driver in NO_WINDOW_DRIVERS and asked != driver:
        pygame.display.quit()
        raise pygame.error(f"no display: SDL fell back to its '{driver}' driver, which "
                           "shows no window")


def fitting_scale(asked: int, size_at: Callable[[int], tuple[int, int]]) -> int:
    """The largest scale up to `asked` at which a window of `size_at(scale)` fits on the
    (first) screen with its frame and the desktop's bars (1 where none does: a window
    taller than the screen opens with its title bar above it). The display is open."""
    screen_w, screen_h = pygame.display.get_desktop_sizes()[0]
    for scale in range(asked, 1, -1):
        width, height = size_at(scale)
        if width + FRAME_PX[0] <= screen_w and height + FRAME_PX[1] <= screen_h:
            return scale
    return 1
