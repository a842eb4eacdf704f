"""Opening SDL's display for a window: refused where SDL falls back to a driver that shows
nothing (or, for the environment's window, opened there and the caller told why), taken
where that driver is asked for by name (the tests' dummy one)."""

from __future__ import annotations

import pygame
import pytest

from invaders.display import open_display


@pytest.mark.parametrize("fallback", ["offscreen", "dummy"])
def test_a_driver_that_shows_nothing_is_refused_unless_asked_for(monkeypatch, fallback):
    """DISPLAY names a server SDL cannot reach, so SDL falls back (stood in for here: its
    probing is the machine's); the display is closed again and the error names the
    driver. With `nowhere`, it stays open and `nowhere` is told the same. Asked for by
    name, the same driver is taken."""
    opened, closed = [], []
    monkeypatch.setattr(pygame.display, "init", lambda: opened.append(True))
    monkeypatch.setattr(pygame.display, "quit", lambda: closed.append(True))
    monkeypatch.setattr(pygame.display, "get_driver", lambda: fallback)
    monkeypatch.setenv("DISPLAY", ":99")
    monkeypatch.delenv("SDL_VIDEODRIVER")
    with pytest.raises(pygame.error, match=f"SDL fell back to its '{fallback}' driver"):
        open_display()
    assert len(opened) == len(closed) == 1
    told: list[str] = []
    open_display(nowhere=told.append)
    assert told == [f"no display: SDL fell back to its '{fallback}' driver, which shows no "
                    "window"]
    assert len(opened) == 2 and len(closed) == 1
    monkeypatch.setenv("SDL_VIDEODRIVER", fallback)
    open_display(nowhere=told.append)
    assert len(opened) == 3 and len(closed) == 1 and len(told) == 1


@pytest.mark.parametrize("asked, size_at, expected", [
    (8, lambda s: (224 * s, 256 * s), 2),  # 3 is 768 tall: no room for the bars beside it
    (1, lambda s: (224 * s, 256 * s), 1),
    (4, lambda s: (500 * s, 100), 2),  # 1,000 and 16 px of borders across 1,024
    (3, lambda s: (5000, 5000), 1),  # none fits: 1 (the picture's own size)
])
def test_a_window_opens_at_the_largest_scale_asked_that_fits_on_the_screen(asked, size_at,
                                                                           expected):
    """On the dummy driver's 1024x768 screen: the largest scale up to the one asked whose
    window leaves room for its frame and the desktop's bars; the next one up would not."""
    from invaders.display import FRAME_PX, fitting_scale

    open_display()
    screen = pygame.display.get_desktop_sizes()[0]
    assert screen == (1024, 768)
    assert fitting_scale(asked, size_at) == expected
    if expected < asked:
        width, height = size_at(expected + 1)
        assert width + FRAME_PX[0] > screen[0] or height + FRAME_PX[1] > screen[1]
