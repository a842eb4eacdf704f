"""The window of `render_mode="human"`: each environment shown has one of its own (pygame's
`Window`, not the display's one surface), so that two shown in one process each keep
theirs, and closing one leaves the others showing. SDL's display is opened with the first
window and quit with the last, unless the program had it open before (its own window, a
game's say, stays as it was). Without a display the window opens on the driver SDL falls
back to, where it shows nowhere, with a warning saying so: as Gymnasium's own environments
and ALE's do (without the warning), so that code written for them, Gymnasium's checker
among it, runs on a machine with no screen.
"""

from __future__ import annotations

import warnings
import weakref
from typing import ClassVar

import numpy as np
import pygame

from invaders.display import fitting_scale, open_display


class EnvWindow:
    """One environment's window, showing its pictures at a whole scale."""

    # The environments' windows open in this process (one dropped unclosed leaves with it),
    # and whether SDL's display was opened for them (and so is theirs to quit).
    open_ones: ClassVar[weakref.WeakSet[EnvWindow]] = weakref.WeakSet()
    display_ours = False

    def __init__(self, title: str, size: tuple[int, int], scale: int) -> None:
        """Opened now, the picture's `size` at `scale` or the largest that fits on the
        screen (a pygame.error, from `open_display`, where SDL has no driver to open, or
        not the one asked for by name)."""
        if not EnvWindow.open_ones:
            EnvWindow.display_ours = not pygame.display.get_init()
        open_display(nowhere=_shown_nowhere)
        scale = fitting_scale(scale, lambda scale: (size[0] * scale, size[1] * scale))
        self.window = pygame.Window(title, (size[0] * scale, size[1] * scale))
        EnvWindow.open_ones.add(self)

    def show(self, picture: np.ndarray) -> None:
        """The picture (rows, columns, RGB) scaled to fill the window."""
        pygame.event.pump()  # (a window whose events are never read is deemed hung)
        surface = pygame.surfarray.make_surface(picture.transpose(1, 0, 2))
        pygame.transform.scale(surface, self.window.size, self.window.get_surface())
        self.window.flip()

    def close(self) -> None:
        self.window.destroy()
        EnvWindow.open_ones.discard(self)
        if not EnvWindow.open_ones and EnvWindow.display_ours:
            pygame.display.quit()


def _shown_nowhere(why: str) -> None:
    warnings.warn(f"render_mode 'human': {why}: the window opens there and shows nowhere, as "
                  "Gymnasium's own environments' do ('rgb_array' gives the pictures)",
                  RuntimeWarning, stacklevel=4)  # (at the environment's render)
