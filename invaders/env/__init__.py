"""Space Invaders for reinforcement learning: `gymnasium.make("invaders/SpaceInvaders-v0")`
once this package is imported (Gymnasium is the `[rl]` extra; nothing else imports it)."""

from __future__ import annotations

import warnings

import gymnasium

from invaders.engine.compiled import shadowed_note
from invaders.env.space_invaders import SpaceInvadersEnv

ENV_ID = "invaders/SpaceInvaders-v0"

if ENV_ID not in gymnasium.registry:
    gymnasium.register(ENV_ID, entry_point="invaders.env.space_invaders:SpaceInvadersEnv",
                       vector_entry_point="invaders.env.vector:SpaceInvadersVectorEnv")

if (_note := shadowed_note()) is not None:  # (a clone's sources run where a build is meant)
    warnings.warn(_note, RuntimeWarning, stacklevel=2)

__all__ = ["ENV_ID", "SpaceInvadersEnv"]
