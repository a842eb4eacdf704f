"""The cabinet's sounds, made with numpy when the window opens (no sound files), and played
from each tick's events: the simulation stays silent, the application listens to it.

The four-note march is timed as the original times it, by its own counter rather than by the
rack's steps (1740-1775): the frames between two notes come from the number of live aliens
(FLEET_DELAYS), and the counter runs on through an alien's explosion (when the rack stands
still). Then the shot, an alien's explosion, the cannon's, the saucer's warble while it
flies and its hit, and the extra ship's tone. Without an audio device the game simply runs
silent.
"""

from __future__ import annotations

import numpy as np
import pygame

from invaders.game.events import Event
from invaders.game.world import Phase
from invaders.quiet import c_stderr_quiet

RATE = 22050
MARCH = (98.0, 87.0, 78.0, 73.0)  # the four descending bass notes, in Hz
# The ROM's two 16-entry tables (1A11, 1A21): with at least this many live aliens, this many
# frames between two notes of the march.
FLEET_DELAYS = ((50, 52), (43, 46), (36, 39), (28, 34), (22, 28), (17, 24), (13, 21),
                (10, 19), (8, 16), (7, 14), (6, 13), (5, 12), (4, 11), (3, 9), (2, 7), (1, 5))


def fleet_delay(live: int) -> int:
    """Frames between two notes of the march with `live` aliens left."""
    return next((frames for least, frames in FLEET_DELAYS if live >= least), FLEET_DELAYS[-1][1])


def _time(seconds: float) -> np.ndarray:
    return np.arange(int(RATE * seconds)) / RATE


def _square(freq: np.ndarray | float, seconds: float) -> np.ndarray:
    phase = np.cumsum(np.broadcast_to(freq, _time(seconds).shape)) / RATE
    return np.sign(np.sin(2 * np.pi * phase))


def _noise(seconds: float, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1.0, 1.0, _time(seconds).size)


def _fade(wave: np.ndarray, power: float = 1.0) -> np.ndarray:
    return wave * np.linspace(1.0, 0.0, wave.size) ** power


def _marching(world) -> bool:
    """Whether the fleet's counter runs: a wave in play with aliens left while the player
    is OK, as the rack marches (the original's counter waits on playerOK, 1747: it runs
    on through a hit cannon's blow-up delay, and not after it nor through the wait that
    follows). An alien's explosion holds the rack, not the sound."""
    return world.phase is Phase.PLAYING and world.rack.live > 0 and world.player_ok


def synthesize() -> dict[str, np.ndarray]:
    """Every sound as 16-bit mono samples at RATE."""
    waves = {f"march{i}": _fade(_square(f, 0.09), 0.5) for i, f in enumerate(MARCH)}
    waves["shot"] = _fade(_square(np.linspace(1400, 300, _time(0.18).size), 0.18))
    waves["alien_killed"] = _fade(_noise(0.25, 1) * 0.8 + _square(200, 0.25) * 0.2, 2)
    waves["cannon_hit"] = _fade(_noise(1.0, 2), 1.5)
    t = _time(0.4)
    waves["saucer"] = _square(700 + 150 * np.sin(2 * np.pi * 8 * t), 0.4)  # looped
    waves["saucer_hit"] = _fade(_square(np.linspace(900, 150, _time(0.7).size), 0.7))
    waves["extra_ship"] = _square(1200, 0.3) * (np.sin(2 * np.pi * 10 * _time(0.3)) > 0)
    return {name: (np.clip(wave, -1, 1) * 0.25 * 32767).astype(np.int16)
            for name, wave in waves.items()}


ON_EVENT = {Event.SHOT_FIRED: "shot", Event.ALIEN_KILLED: "alien_killed",
            Event.CANNON_HIT: "cannon_hit", Event.SAUCER_HIT: "saucer_hit",
            Event.EXTRA_SHIP: "extra_ship"}


class SoundBoard:
    """Plays a world's sounds; does nothing at all where no audio device opens."""

    def __init__(self, muted: bool = False) -> None:
        self.muted = muted
        self.sounds: dict[str, pygame.mixer.Sound] = {}
        self.notes_played = 0  # march notes so far (what the tempo test counts)
        self._march_timer = 0  # frames to the next note
        self._saucer_channel: pygame.mixer.Channel | None = None
        try:
            with c_stderr_quiet():  # (ALSA's lines without a sound card)
                pygame.mixer.init(RATE, -16, 1, 512)
        except pygame.error:
            return  # no audio device: silent, and nothing to say about it
        self.sounds = {name: pygame.mixer.Sound(buffer=wave.tobytes())
                       for name, wave in synthesize().items()}

    def toggle_mute(self) -> None:
        self.muted = not self.muted
        if self.muted and self.sounds:
            pygame.mixer.stop()

    def _play(self, name: str, loops: int = 0) -> pygame.mixer.Channel | None:
        sound = self.sounds.get(name)
        if sound is None or self.muted:
            return None
        return sound.play(loops=loops)

    def react(self, events: tuple[Event, ...], world) -> None:
        """After a tick: its events' sounds, a march note when the fleet's counter runs out,
        the saucer's warble while it flies."""
        if _marching(world):
            self._march_timer -= 1
            if self._march_timer <= 0:
                self._play(f"march{self.notes_played % 4}")
                self.notes_played += 1
                self._march_timer = fleet_delay(world.rack.live)
        for event in events:
            name = ON_EVENT.get(event)
            if name is not None:
                self._play(name)
        flying = world.saucer.saucer is not None
        if flying and self._saucer_channel is None:
            self._saucer_channel = self._play("saucer", loops=-1) or None
        elif not flying and self._saucer_channel is not None:
            self._saucer_channel.stop()
            self._saucer_channel = None
