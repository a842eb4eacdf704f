"""pygame-ce's own example game, aliens.py from the wheel, played headless with a fixed
seed and scripted keys, once with pygame's collision functions and once with ours in their
place: the two games are the same, frame by frame (the score and every sprite's place; a
groupcollide that applied its kills after the whole search differs in 4 of these 30)."""

from __future__ import annotations

import importlib.util
import random
from pathlib import Path

import pygame
import pytest

from invaders.engine import collide

ALIENS = Path(pygame.__file__).parent / "examples" / "aliens.py"
FRAMES = 600


class Keys(dict):
    """What pygame.key.get_pressed gives: pressed keys true, every other key false."""

    def __missing__(self, key: int) -> bool:
        return False


class Clock:
    """pygame's frame clock, without the waiting."""

    def tick(self, framerate: int = 0) -> int:
        return 0


def _play(seed: int, monkeypatch) -> list[tuple]:
    """Each frame of one game as aliens.py plays it: the score and every sprite's place."""
    spec = importlib.util.spec_from_file_location(f"aliens_{seed}", ALIENS)
    game = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(game)
    player = random.Random(seed)  # the scripted player's own choices
    frames: list[tuple] = []
    held = Keys()

    def events() -> list[pygame.event.Event]:
        if len(frames) >= FRAMES:
            return [pygame.event.Event(pygame.QUIT)]
        if player.random() < 0.1:  # now and then, another direction
            held.clear()
            held[player.choice((pygame.K_LEFT, pygame.K_RIGHT, pygame.K_UP))] = True
        held[pygame.K_SPACE] = player.random() < 0.5
        return []

    def flip(*args) -> None:  # each frame: every sprite where it is, and the score
        sprites = game.Player.containers or ()  # (none yet at the first, the background)
        frames.append((game.SCORE, tuple((type(s).__name__, tuple(s.rect)) for s in sprites)))

    monkeypatch.setattr(pygame, "mixer", pygame.mixer)  # the game drops it: no sound
    monkeypatch.setattr(pygame.mixer, "get_init", lambda: None)
    monkeypatch.setattr(pygame, "quit", lambda: None)
    monkeypatch.setattr(pygame.time, "wait", lambda ms: 0)  # its closing second of music
    monkeypatch.setattr(pygame, "Clock", Clock)
    monkeypatch.setattr(pygame.time, "Clock", Clock)
    monkeypatch.setattr(pygame.event, "get", events)
    monkeypatch.setattr(pygame.key, "get_pressed", lambda: held)
    monkeypatch.setattr(pygame.display, "flip", flip)
    monkeypatch.setattr(pygame.display, "update", flip)
    random.seed(seed)  # the game's own chance
    game.main()
    return frames


@pytest.mark.parametrize("seed", range(30))
def test_aliens_plays_the_same_game_with_our_collision_functions(seed, monkeypatch):
    with monkeypatch.context() as patch:
        theirs = _play(seed, patch)
    with monkeypatch.context() as patch:
        for name in ("groupcollide", "spritecollide", "spritecollideany"):
            patch.setattr(pygame.sprite, name, getattr(collide, name))
        ours = _play(seed, patch)
    assert len(theirs) > 50  # it played (a game may end before the last frame)
    assert ours == theirs
