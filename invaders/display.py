"""SDL's display opened for a window: the game's, and the environment's in human mode.

Where there is no display, SDL falls back without a word to a driver that shows nothing
('offscreen', 'dummy'): a window opened there would never be seen, so the game's is refused
with a pygame.error saying why, which the caller turns into its own one line; the
environment's opens there all the same, told why (Gymnasium's environments and ALE's show
theirs nowhere without a word, and Gymnasium's checker opens every render mode). A driver
asked for by name (SDL_VIDEODRIVER) is taken as asked: the tests' dummy one. A window is
opened no larger than the screen holds (`fitting_scale`).
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


def open_display(nowhere: Callable[[str], None] | None = None) -> None:
    """SDL's display, ready for `pygame.display.set_mode`, or pygame.error if it would show
    no window; with `nowhere`, opened all the same on the driver SDL falls back to, and
    `nowhere` told why no window shows."""
    asked = os.environ.get("SDL_VIDEODRIVER")
    unseen = None  # why no window would show, if none would
    if (asked is None and sys.platform.startswith("linux")
            and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY")):
        unseen = "no display: neither DISPLAY nor WAYLAND_DISPLAY is set"
        if nowhere is None:
            raise pygame.error(unseen)
    # A window's picture is a plain surface: SDL shows it through the native framebuffer
    # (X11's shared memory) rather than uploading it to a renderer each frame, which
    # without a GPU (Mesa's llvmpipe, Xvfb) costs 7 ms of CPU a frame at scale 3, against
    # 0.06 ms. Set the variable to choose otherwise.
    os.environ.setdefault("SDL_FRAMEBUFFER_ACCELERATION", "0")
    with c_stderr_quiet():  # (SDL's drivers probed in turn say why each is not there)
        pygame.display.init()
    driver = pygame.display.get_driver()
    if unseen is None and driver in NO_WINDOW_DRIVERS and asked != driver:
        unseen = f"no display: SDL fell back to its '{driver}' driver, which shows no window"
        if nowhere is None:
            pygame.display.quit()
            raise pygame.error(unseen)
    if unseen is not None and nowhere is not None:
        nowhere(unseen)


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
