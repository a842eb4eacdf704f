"""ALE's continuous actions (`continuous=True`): a step's action is the joystick as a point
in polar coordinates and the fire button as a pressure, (r, theta, fire) in float32, and it
plays as one of ALE's 18 actions, read as ALE's environment reads it: the stick's x = r
cos(theta) pushes right past the threshold and left below minus it, its y = r sin(theta)
up and down alike, and fire presses past the threshold. Each part is worked out in
float32, as ALE's, so an action on a threshold's edge reads the same on both. Up and down
do nothing in this game, as in the full action set.
"""

from __future__ import annotations

import numbers
from math import isnan, pi
from typing import Any

import numpy as np
from gymnasium import spaces

ACROSS = {-1: "LEFT", 0: "", 1: "RIGHT"}
UPRIGHT = {-1: "DOWN", 0: "", 1: "UP"}


def stick_space() -> spaces.Box:
    """ALE's: r from 0 to 1, theta from -pi to pi, fire from 0 to 1."""
    return spaces.Box(low=np.array([0.0, -pi, 0.0], np.float32),
                      high=np.array([1.0, pi, 1.0], np.float32), shape=(3,), dtype=np.float32)


def stick_meaning(action: np.ndarray, threshold: Any) -> str:
    """The name, in ALE's full set, of the action a stick's (r, theta, fire) plays as
    (a float32 array of 3). A side pushed is +1, -1 or 0 as ALE counts it (past the
    threshold one way, less one past it the other: both, with a threshold below 0, are
    0)."""
    r, theta, fire = action[0], action[1], action[2]
    x, y = r * np.cos(theta), r * np.sin(theta)
    across = int(x > threshold) - int(x < -threshold)
    upright = int(y > threshold) - int(y < -threshold)
    name = UPRIGHT[upright] + ACROSS[across] + ("FIRE" if fire > threshold else "")
    return name or "NOOP"


def check_stick(continuous: Any, threshold: Any, sound_obs: Any) -> None:
    """One ValueError naming the option, for a value the environment cannot take: ALE's
    `continuous` (True or False), its threshold (a number, numpy's too, as ALE takes; not
    NaN, past which nothing would ever be pushed) and `sound_obs` (False: the game's
    sounds play in its window, and no observation holds them)."""
    if not isinstance(continuous, (bool, np.bool_)):
        raise ValueError(f"continuous {continuous!r}: True or False")
    if (not isinstance(threshold, numbers.Real) or isinstance(threshold, (bool, np.bool_))
            or isnan(threshold)):
        raise ValueError(f"continuous_action_threshold {threshold!r}: a number (ALE's "
                         "default 0.5)")
    if not (isinstance(sound_obs, (bool, np.bool_)) and not sound_obs):
        raise ValueError(f"sound_obs {sound_obs!r}: False (the environment observes no "
                         "sound: the game's sounds play in its window)")
