"""N games stepped in one process, their observations written into one array kept between
steps: `gymnasium.make_vec("invaders/SpaceInvaders-v0", num_envs=N,
vectorization_mode="vector_entry_point")`. Autoreset as Gymnasium 1.x's default
(`NEXT_STEP`): the step after an episode ends resets that game (reward 0, its first
observation), the others step on. Each game is a `SpaceInvadersEnv`, so each gives what it
would alone; the batch saves the per-game copies, infos and wrappers of a generic vector
environment.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from invaders.env.space_invaders import SpaceInvadersEnv


class SpaceInvadersVectorEnv(VectorEnv):
    """`num_envs` games with the same options (those of `SpaceInvadersEnv`)."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP}  # noqa: RUF012 (Gymnasium's)

    def __init__(self, num_envs: int = 8, copy: bool = True, **options: Any) -> None:
        if not (isinstance(num_envs, int) and num_envs >= 1):
            raise ValueError(f"num_envs {num_envs!r}: a whole number from 1")
        self.envs = [SpaceInvadersEnv(**options) for _ in range(num_envs)]
        self.num_envs, self.copy = num_envs, copy
        self.single_observation_space = self.envs[0].observation_space
        self.single_action_space = self.envs[0].action_space
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.render_mode = options.get("render_mode")
        self._obs = np.zeros(self.observation_space.shape, self.observation_space.dtype)
        self._rewards = np.zeros(num_envs, np.float64)
        self._terminated = np.zeros(num_envs, np.bool_)
        self._truncated = np.zeros(num_envs, np.bool_)
        self._ended = np.zeros(num_envs, np.bool_)

    def reset(self, *, seed: int | list[int | None] | None = None,
              options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        """Every game anew; an int seed gives game i the seed `seed + i` (as Gymnasium's
        own vector environments do)."""
        seeds = ([seed + i for i in range(self.num_envs)] if isinstance(seed, int)
                 else seed if seed is not None else [None] * self.num_envs)
        if len(seeds) != self.num_envs:
            raise ValueError(f"{len(seeds)} seeds for {self.num_envs} games")
        for i, (env, one) in enumerate(zip(self.envs, seeds, strict=True)):
            env.reset(seed=one)
            self._obs[i] = env.frame(first=True)
        self._ended[:] = False
        return self._out(self._obs), self._infos()

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                          dict[str, Any]]:
        actions = np.asarray(actions)
        if actions.shape != (self.num_envs,) or not self.action_space.contains(
                actions.astype(self.action_space.dtype)):
            raise ValueError(f"actions {actions!r} are not in {self.action_space}")
        for i, (env, action) in enumerate(zip(self.envs, actions.tolist(), strict=True)):
            if self._ended[i]:  # NEXT_STEP: this step resets it
                env.begin(None)
                self._rewards[i], self._terminated[i], self._truncated[i] = 0.0, False, False
                self._obs[i] = env.frame(first=True)
                continue
            reward, terminated, truncated, _ = env.advance(action)
            self._rewards[i], self._terminated[i], self._truncated[i] = (
                reward, terminated, truncated)
            self._obs[i] = env.frame()
        np.logical_or(self._terminated, self._truncated, out=self._ended)
        return (self._out(self._obs), self._out(self._rewards), self._out(self._terminated),
                self._out(self._truncated), self._infos())

    def render(self) -> tuple[np.ndarray, ...] | None:
        if self.render_mode != "rgb_array":
            return None
        return tuple(env.render() for env in self.envs)

    def close_extras(self, **kwargs: Any) -> None:
        for env in self.envs:
            env.close()

    def _out(self, array: np.ndarray) -> np.ndarray:
        return array.copy() if self.copy else array

    def _infos(self) -> dict[str, Any]:
        """ALE's per-game numbers as arrays, each with Gymnasium's mask of who has it."""
        present = np.ones(self.num_envs, np.bool_)
        infos: dict[str, Any] = {}
        for key, read in (("lives", lambda e: max(e.world.ships, 0)),
                          ("episode_frame_number", lambda e: e.episode_frame_number),
                          ("frame_number", lambda e: e.frame_number)):
            infos[key] = np.array([read(env) for env in self.envs], np.int64)
            infos[f"_{key}"] = present
        return infos
