"""ALE's continuous actions (`continuous=True`): a stick's (r, theta, fire) plays as the
one of ALE's 18 actions ALE's environment reads it as, in a game, a batch and on workers;
ALE's other options taken where the game can honour them, refused in one line where not."""

from __future__ import annotations

from math import pi

import gymnasium
import numpy as np
import pytest

import invaders.env  # noqa: F401  (registers the id)
from invaders.env.space_invaders import FULL_MEANINGS, SpaceInvadersEnv
from invaders.game.entities import CannonState
from tests.helpers import vector_answers_alike

ENV_ID = "invaders/SpaceInvaders-v0"
STILL = {"frameskip": 1, "repeat_action_probability": 0.0}


def _stick(r: float, theta: float, fire: float) -> np.ndarray:
    return np.array([r, theta, fire], np.float32)


# A stick's action and what ALE's environment plays it as (its x = r cos theta and y = r
# sin theta against the threshold, 0.5 unless given), worked out by hand.
READINGS = [
    ((1.0, 0.0, 0.0), 0.5, "RIGHT"),
    ((1.0, pi, 0.0), 0.5, "LEFT"),
    ((1.0, pi / 2, 0.0), 0.5, "UP"),
    ((1.0, -pi / 2, 1.0), 0.5, "DOWNFIRE"),
    ((1.0, pi / 4, 1.0), 0.5, "UPRIGHTFIRE"),  # (x = y = 0.71)
    ((1.0, -3 * pi / 4, 0.0), 0.5, "DOWNLEFT"),
    ((0.4, 0.0, 1.0), 0.5, "FIRE"),  # (pushed 0.4: not past the threshold)
    ((0.6, 3 * pi / 4, 0.3), 0.5, "NOOP"),  # (x = -0.42, y = 0.42)
    ((0.5, 0.0, 0.5), 0.5, "NOOP"),  # (on the threshold is not past it)
    ((0.4, pi, 0.31), 0.3, "LEFTFIRE"),
    ((0.0, 0.0, 0.0), -0.5, "FIRE"),  # (below 0: neither side wins; fire is past it)
    ((1.0, 0.0, 1.0), 1.5, "NOOP"),
]


@pytest.mark.parametrize(("stick", "threshold", "meaning"), READINGS)
def test_a_sticks_action_plays_as_the_action_ale_reads_it_as(stick, threshold, meaning):
    """Played in a game of one frame a step, without sticky actions, a stick's action
    plays exactly as the full set's action it reads as: the same state after each step."""
    env = SpaceInvadersEnv(obs_type="state", continuous=True,
                           continuous_action_threshold=threshold, **STILL)
    full = SpaceInvadersEnv(obs_type="state", full_action_space=True, **STILL)
    assert env.get_action_meanings() == list(FULL_MEANINGS)
    assert env.action_index(_stick(*stick)) == FULL_MEANINGS.index(meaning)
    for one in (env, full):
        one.reset(seed=3)
    for _ in range(120):
        ours, theirs = env.step(_stick(*stick)), full.step(FULL_MEANINGS.index(meaning))
        assert np.array_equal(ours[0], theirs[0]) and ours[1:4] == theirs[1:4]
        assert env.world.state_hash() == full.world.state_hash()


def test_a_stick_moves_the_cannon_a_pixel_a_frame_and_fires():
    env = SpaceInvadersEnv(obs_type="state", continuous=True, **STILL)
    env.reset(seed=0)
    while env.world.cannon.state is not CannonState.ACTIVE:
        env.step(_stick(0.0, 0.0, 0.0))
    start, places = env.world.cannon.x, []
    for stick in [(1.0, 0.1, 0.0)] * 3 + [(0.9, pi / 2, 0.0), (0.8, -pi + 0.2, 0.0),
                                          (0.4, pi, 0.0), (1.0, pi, 0.0)]:
        env.step(_stick(*stick))  # right 3 times, up (nothing here), left, too little, left
        places.append(env.world.cannon.x - start)
    assert places == [1, 2, 3, 3, 2, 2, 1] and env.world.shot is None
    *_, info = env.step(_stick(0.0, 0.0, 0.9))
    assert "SHOT_FIRED" in info["events"] and env.world.shot is not None


def test_sticky_actions_repeat_the_sticks_last_frame_as_ales():
    """With sticky actions and frame skips drawn, a stick's episode is the one the full
    set's actions it reads as give (the same generator draws, the same frames kept)."""
    options = {"obs_type": "grayscale", "frameskip": (2, 6), "repeat_action_probability": 0.4}
    env = gymnasium.make(ENV_ID, continuous=True, **options)
    full = gymnasium.make(ENV_ID, full_action_space=True, **options)
    rng = np.random.default_rng(7)
    for one in (env, full):
        one.reset(seed=7)
    for _ in range(300):
        stick = env.action_space.sample()
        stick[:] = rng.uniform([0, -pi, 0], [1, pi, 1])
        ours, theirs = env.step(stick), full.step(env.unwrapped.action_index(stick))
        assert np.array_equal(ours[0], theirs[0]) and ours[1:4] == theirs[1:4]
        assert ours[4]["episode_frame_number"] == theirs[4]["episode_frame_number"]
    assert env.unwrapped.world.state_hash() == full.unwrapped.world.state_hash()


@pytest.mark.parametrize("workers", [1, 2])
def test_the_native_batch_takes_sticks_as_gymnasiums_sync_vector(workers):
    options = {"obs_type": "state", "continuous": True, "max_num_frames_per_episode": 300}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", **options)
    assert native.action_space == sync.action_space
    assert vector_answers_alike(native.reset(seed=2), sync.reset(seed=2))
    rng = np.random.default_rng(2)
    for _ in range(120):
        sticks = rng.uniform([0, -pi, 0], [1, pi, 1], (3, 3)).astype(np.float32)
        assert vector_answers_alike(native.step(sticks), sync.step(sticks))
    for bad in (np.zeros(3, np.int64), np.zeros((3, 3)), np.full((3, 3), 2, np.float32)):
        with pytest.raises(ValueError, match="are not in Box"):
            native.step(bad)
    native.close()
    sync.close()


@pytest.mark.filterwarnings("ignore:.*Casting input x")  # (Gymnasium's Box, given a number)
def test_what_is_not_a_sticks_action_is_refused_in_one_line():
    env = SpaceInvadersEnv(obs_type="state", continuous=True)
    env.reset(seed=1)
    for action in (3, np.array(3), _stick(1.2, 0, 0), _stick(0.5, 4.0, 0),
                   np.array([1.0, 0.0, 0.0]), _stick(np.nan, 0, 0), np.zeros(2, np.float32)):
        with pytest.raises(ValueError, match="is not in Box"):
            env.step(action)
    with pytest.raises(AttributeError, match="no keys give a continuous action"):
        env.get_keys_to_action()  # (as ALE's, which raises for its continuous actions)


def test_ales_options_are_taken_at_ales_defaults_and_refused_in_one_line_past_them():
    """Code that passes every option ALE's environment has, at ALE's defaults, runs; what
    the game cannot honour (a sound observation) or no action can mean is refused."""
    ales_defaults = {"mode": None, "difficulty": None, "obs_type": "rgb", "frameskip": 4,
                     "repeat_action_probability": 0.25, "full_action_space": False,
                     "continuous": False, "continuous_action_threshold": 0.5,
                     "max_num_frames_per_episode": None, "render_mode": None,
                     "sound_obs": False}
    env = gymnasium.make(ENV_ID, **ales_defaults)
    env.reset(seed=1)
    assert env.step(1)[0].shape == (256, 224, 3) and env.action_space.n == 6
    for options in ({"continuous": "yes"}, {"continuous": 1},
                    {"continuous_action_threshold": float("nan")},
                    {"continuous_action_threshold": "0.5"},
                    {"continuous_action_threshold": True},
                    {"sound_obs": True}, {"sound_obs": "no"}):
        with pytest.raises(ValueError, match=next(iter(options))):
            SpaceInvadersEnv(**options)
    taken = SpaceInvadersEnv(continuous=np.bool_(True),
                             continuous_action_threshold=np.float32(0.25))
    taken.reset(seed=1)
    assert taken.action_index(_stick(0.3, 0.0, 0.0)) == FULL_MEANINGS.index("RIGHT")


def test_ales_vector_options_are_refused_naming_what_takes_their_place():
    """Code written for ALE's own vector environment passes its options to the batch: each
    is refused in one line that names ours (where a TypeError named none)."""
    for option, ours in (("img_height", "resize"), ("img_width", "resize"),
                         ("stack_num", "stack"), ("grayscale", "obs_type='grayscale'"),
                         ("num_threads", "workers"), ("batch_size", "num_envs"),
                         ("noop_max", "AtariPreprocessing"),
                         ("reward_clipping", "ClipReward"), ("use_fire_reset", "no FIRE"),
                         ("life_loss_info", "SHIP_LOST")):
        with pytest.raises(ValueError, match=rf"^{option}: an option of ALE's vector .*{ours}"):
            gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                               **{option: 4})
