"""Opening SDL's display for a window: refused where SDL falls back to a driver that shows
nothing, taken where that driver is asked for by name (the tests' dummy one)."""

from __future__ import annotations

import pygame
import pytest

from invaders.display import open_display


@pytest.mark.parametrize("fallback", ["offscreen", "dummy"])
def test_a_driver_that_shows_nothing_is_refused_unless_asked_for(monkeypatch, fallback):
    """DISPLAY names a server SDL cannot reach, so SDL falls back (stood in for here: its
    probing is the machine's); the display is closed again and the error names the
    driver. Asked for by name, the same driver is taken."""
    opened, closed = [], []
    monkeypatch.setattr(pygame.display, "init", lambda: opened.append(True))
    monkeypatch.setattr(pygame.display, "quit", lambda: closed.append(True))
    monkeypatch.setattr(pygame.display, "get_driver", lambda: fallback)
    monkeypatch.setenv("DISPLAY", ":99")
    monkeypatch.delenv("SDL_VIDEODRIVER")
    with pytest.raises(pygame.error, match=f"SDL fell back to its '{fallback}' driver"):
        open_display()
    assert len(opened) == len(closed) == 1
    monkeypatch.setenv("SDL_VIDEODRIVER", fallback)
    open_display()
    assert len(opened) == 2 and len(closed) == 1
