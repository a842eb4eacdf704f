"""The part of ALE's interface that training code reads through `env.unwrapped.ale`.

Gymnasium's `AtariPreprocessing` asks ALE for the screen itself (RGB or grey, into arrays
it keeps) and for the lives; Stable-Baselines3's Atari wrappers ask for the lives; a search
clones and restores states; other code maps its actions by ALE's action sets. Here they
read the game: the same pictures the observations are (upright, 256x224, the cabinet's
gel), and the ships left; a state is the environment's own (`clone_state`); the action
sets are ALE's for this game. Nothing here but `restoreState` changes the game.
"""

from __future__ import annotations

from enum import IntEnum
from typing import Any, Protocol

import numpy as np

from invaders.env.observations import PixelObserver
from invaders.game.config import SCREEN_H, SCREEN_W
from invaders.game.world import Phase, World


class AleAction(IntEnum):
    """ALE's 18 actions by its numbers and names (`ale_py.Action`'s): the action sets the
    view gives, each a number with a name (`.name`, `.value`, and `int()`, which older
    ale-py's took)."""

    NOOP = 0
    FIRE = 1
    UP = 2
    RIGHT = 3
    LEFT = 4
    DOWN = 5
    UPRIGHT = 6
    UPLEFT = 7
    DOWNRIGHT = 8
    DOWNLEFT = 9
    UPFIRE = 10
    RIGHTFIRE = 11
    LEFTFIRE = 12
    DOWNFIRE = 13
    UPRIGHTFIRE = 14
    UPLEFTFIRE = 15
    DOWNRIGHTFIRE = 16
    DOWNLEFTFIRE = 17


# ALE's minimal set for Space Invaders, in ALE's order: the environment's six actions.
MINIMAL_SET = (AleAction.NOOP, AleAction.FIRE, AleAction.RIGHT, AleAction.LEFT,
               AleAction.RIGHTFIRE, AleAction.LEFTFIRE)


class Episode(Protocol):
    """What the view reads of an environment (`SpaceInvadersEnv`)."""

    world: World | None
    frame_number: int

    @property
    def episode_frame_number(self) -> int: ...

    @property
    def cut_short(self) -> bool: ...

    @property
    def lives(self) -> int: ...

    def clone_state(self, include_rng: bool = False) -> Any: ...

    def restore_state(self, state: Any) -> None: ...


class AleView:
    """ALE's names, as `ale_py.ALEInterface` has them, for one environment's game."""

    def __init__(self, env: Episode) -> None:
        self._env = env
        self._rgb: PixelObserver | None = None  # (made when first asked for)
        self._grey: PixelObserver | None = None

    def lives(self) -> int:
        self._world()  # (refused before a reset)
        return self._env.lives

    def getMinimalActionSet(self) -> list[AleAction]:
        """The game's own actions, ALE's minimal set (what the environment's six are,
        whatever its action space): code written for ALE maps its actions by them."""
        return list(MINIMAL_SET)

    def getLegalActionSet(self) -> list[AleAction]:
        """All 18 (up and down do nothing in this game)."""
        return list(AleAction)

    def getAvailableModes(self) -> list[int]:
        """The game's variations (the arcade game has one: ALE's cartridge's 16 are the
        2600's), as the environment's `mode` takes them."""
        return [0]

    def getAvailableDifficulties(self) -> list[int]:
        """The difficulty switch's settings (one: as `difficulty` takes them)."""
        return [0]

    def getScreenDims(self) -> tuple[int, int]:
        """(height, width), as ALE's."""
        return SCREEN_H, SCREEN_W

    def getScreenRGB(self, array: np.ndarray | None = None) -> np.ndarray | None:
        """The picture, (256, 224, 3): a new array, or written into `array` (then None)."""
        self._rgb = self._rgb or PixelObserver(grayscale=False)
        return _into(self._rgb, self._world(), array)

    def getScreenGrayscale(self, array: np.ndarray | None = None) -> np.ndarray | None:
        """The grey picture, (256, 224), as `obs_type="grayscale"`: a new array, or written
        into `array` (then None)."""
        self._grey = self._grey or PixelObserver(grayscale=True)
        return _into(self._grey, self._world(), array)

    def game_over(self, *, with_truncation: bool = True) -> bool:
        return self._world().phase is Phase.GAME_OVER or (with_truncation
                                                          and self.game_truncated())

    def game_truncated(self) -> bool:
        return self._env.cut_short

    def cloneState(self, include_rng: bool = False) -> Any:
        """The episode as it stands, for `restoreState` (the environment's `clone_state`:
        with include_rng, the sticky actions' and frame skips' generator too)."""
        return self._env.clone_state(include_rng)

    def restoreState(self, state: Any) -> None:
        """Go back to a state `cloneState` gave (the environment's `restore_state`)."""
        self._env.restore_state(state)

    def getEpisodeFrameNumber(self) -> int:
        return self._env.episode_frame_number

    def getFrameNumber(self) -> int:
        return self._env.frame_number

    def _world(self) -> World:
        world = self._env.world
        if world is None:
            raise RuntimeError("call reset() before reading the game")
        return world


def _into(pixels: PixelObserver, world: World, array: np.ndarray | None) -> np.ndarray | None:
    """The picture in a new array, or written into `array` (then None), refused as ALE
    refuses one of another shape (RuntimeError) or type (TypeError)."""
    if array is None:
        return pixels.observe(world)
    if not isinstance(array, np.ndarray) or array.dtype != np.uint8:
        raise TypeError("the screen goes into a numpy array of uint8")
    shape = pixels.gel.shape
    if array.shape != shape:
        raise RuntimeError(f"Invalid shape {array.shape}, expecting shape {shape}")
    pixels.observe(world, array)
    return None
