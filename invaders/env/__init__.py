"""Space Invaders for reinforcement learning: `gymnasium.make("invaders/SpaceInvaders-v0")`
once this package is imported (Gymnasium is the `[rl]` extra; nothing else imports it)."""

from __future__ import annotations

import warnings

try:
    import gymnasium
except ModuleNotFoundError as missing:  # (every module here reads it: said once, here)
    raise ModuleNotFoundError("invaders.env needs Gymnasium, the rl extra: pip install "
                              "'.[rl]'", name=missing.name) from missing

from invaders.engine.compiled import shadowed_note
from invaders.env.space_invaders import SpaceInvadersEnv

ENV_ID = "invaders/SpaceInvaders-v0"  # ALE v5's settings (frame skip 4, sticky actions)
# The id of recipes written before ALE's v5, whose wrappers skip frames themselves
# (Stable-Baselines3's `make_atari_env`, CleanRL's Atari scripts): ALE's name in our
# namespace, with ALE's settings for it.
NO_FRAMESKIP_ID = "invaders/SpaceInvadersNoFrameskip-v4"
SETTINGS = {ENV_ID: {}, NO_FRAMESKIP_ID: {"frameskip": 1, "repeat_action_probability": 0.0}}

for env_id, settings in SETTINGS.items():
    if env_id not in gymnasium.registry:
        gymnasium.register(env_id, entry_point="invaders.env.space_invaders:SpaceInvadersEnv",
                           vector_entry_point="invaders.env.vector:SpaceInvadersVectorEnv",
                           kwargs=settings)

if (_note := shadowed_note()) is not None:  # (a clone's sources run where a build is meant)
    warnings.warn(_note, RuntimeWarning, stacklevel=2)

__all__ = ["ENV_ID", "NO_FRAMESKIP_ID", "SpaceInvadersEnv"]
