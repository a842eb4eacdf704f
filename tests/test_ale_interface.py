"""`env.unwrapped.ale`: ALE's interface as Atari wrappers read it (the lives, the screen, the
frame numbers, the episode's end), and Gymnasium's own `AtariPreprocessing` on the game."""

from __future__ import annotations

import os

import cv2
import gymnasium
import numpy as np
import pytest
from gymnasium.wrappers import AtariPreprocessing

from invaders.env import NO_FRAMESKIP_ID  # (importing it registers the ids)
from invaders.env.space_invaders import SpaceInvadersEnv

ENV_ID = "invaders/SpaceInvaders-v0"
LEFT, RIGHT = 3, 2  # (ALE's minimal set: NOOP, FIRE, RIGHT, LEFT, RIGHTFIRE, LEFTFIRE)


def test_ales_interface_reads_what_the_steps_give():
    """Each step: the grey screen is the observation and the RGB one the render, pixel for
    pixel, new or written into an array; the lives, frame numbers and ends are the info's
    and the step's, up to the frame limit (40 frames: 10 steps)."""
    env = SpaceInvadersEnv(obs_type="grayscale", render_mode="rgb_array",
                           max_num_frames_per_episode=40)
    ale = env.ale
    obs, info = env.reset(seed=3)
    grey, rgb = np.zeros(obs.shape, np.uint8), np.zeros((*obs.shape, 3), np.uint8)
    ends = []
    for step in range(11):
        assert np.array_equal(ale.getScreenGrayscale(), obs)
        assert ale.getScreenGrayscale(grey) is None and np.array_equal(grey, obs)
        assert np.array_equal(ale.getScreenRGB(), env.render())
        assert ale.getScreenRGB(rgb) is None and np.array_equal(rgb, env.render())
        assert (ale.lives(), ale.getEpisodeFrameNumber(), ale.getFrameNumber()) == (
            info["lives"], info["episode_frame_number"], info["frame_number"])
        obs, _, terminated, truncated, info = env.step(step % 6)
        ends.append((ale.game_over(), ale.game_over(with_truncation=False),
                     ale.game_truncated()) == (terminated or truncated, terminated, truncated))
        assert ale.getEpisodeFrameNumber() == info["episode_frame_number"]
    assert all(ends) and ale.game_truncated() and ale.getScreenDims() == obs.shape


def test_ales_interface_refuses_as_ale_does():
    env = SpaceInvadersEnv()
    with pytest.raises(RuntimeError, match="reset"):
        env.ale.lives()
    env.reset(seed=0)
    with pytest.raises(RuntimeError, match=r"Invalid shape \(210, 160\), expecting shape"):
        env.ale.getScreenGrayscale(np.zeros((210, 160), np.uint8))
    with pytest.raises(TypeError):
        env.ale.getScreenRGB(np.zeros((256, 224, 3), np.float32))


def test_a_search_clones_and_restores_states_through_ales_interface():
    """`ale.cloneState()` and `ale.restoreState(state)`, as search code written for ALE calls
    them: the steps after each restore are the steps after the clone (the generator of
    sticky actions in the state, as ALE's with include_rng)."""
    env = gymnasium.make(ENV_ID, obs_type="state")
    env.reset(seed=4)
    for action in (1, 2, 2, 4, 0):
        env.step(action)
    ale = env.unwrapped.ale
    state = ale.cloneState(include_rng=True)
    runs = []
    for _ in range(3):
        ale.restoreState(state)
        runs.append([(obs.tolist(), reward, ends, info["collisions"])
                     for obs, reward, *ends, info in (env.step(a % 6) for a in range(60))])
    assert runs[0] == runs[1] == runs[2] and ale.getEpisodeFrameNumber() == 5 * 4 + 60 * 4


def test_gymnasiums_atari_preprocessing_takes_the_last_two_frames_of_each_step():
    """Gymnasium's own wrapper, as its documentation sets it up on ALE (frame skip 1 in the
    environment, 4 in the wrapper, the RGB observation): each observation is the grey
    screens of the step's last two frames, their maximum shrunk to 84x84 by OpenCV's area
    averaging, made here from a twin environment stepped frame by frame; with
    `terminal_on_life_loss`, the episode ends when a ship is lost."""
    wrapped = AtariPreprocessing(gymnasium.make(ENV_ID, frameskip=1), noop_max=0,
                                 terminal_on_life_loss=True)
    twin = SpaceInvadersEnv(obs_type="grayscale", frameskip=1)
    obs, info = wrapped.reset(seed=8)
    frame, _ = twin.reset(seed=8)
    assert np.array_equal(obs, cv2.resize(frame, (84, 84), interpolation=cv2.INTER_AREA))
    lives, terminated, steps = info["lives"], False, 0
    while not terminated:
        action = steps % 6
        obs, _, terminated, truncated, info = wrapped.step(action)
        frames = [twin.step(action)[0].copy() for _ in range(4)]
        if not terminated:
            shrunk = cv2.resize(np.maximum(frames[-2], frames[-1]), (84, 84),
                                interpolation=cv2.INTER_AREA)
            assert np.array_equal(obs, shrunk)
        steps += 1
    assert info["lives"] == lives - 1 and steps > 10 and not truncated


def test_ales_no_frameskip_id_steps_a_frame_at_a_time_as_asked():
    """`invaders/SpaceInvadersNoFrameskip-v4` has ALE's settings for that id (its
    registration in ale-py: frame skip 1, no sticky actions, 108,000 frames an episode):
    a step is one frame, and the cannon goes each way it is asked, every step (with
    sticky actions a quarter of the frames would repeat the last way)."""
    env = gymnasium.make(NO_FRAMESKIP_ID, obs_type="state")
    obs, info = env.reset(seed=5)
    assert env.unwrapped.max_num_frames_per_episode == 108_000
    while obs[1] == 0:  # (the cannon waits at the wave's start)
        obs, _, _, _, info = env.step(0)
    frames, moves = info["episode_frame_number"], []
    for step in range(1, 201):
        action = RIGHT if step % 2 else LEFT
        x = obs[0]
        obs, _, _, _, info = env.step(action)
        assert info["episode_frame_number"] == frames + step
        if obs[1] == 1:  # (still there to move)
            moves.append((action, obs[0] - x))
    assert len(moves) > 100
    assert moves == [(action, 1 if action == RIGHT else -1) for action, _ in moves]


PLAYED = """
import gymnasium, pygame
from gymnasium.utils.play import play
import invaders.env

actions = []

def press(*keys):
    for key in set(held) - set(keys):
        pygame.event.post(pygame.event.Event(pygame.KEYUP, key=ord(key)))
    for key in set(keys) - set(held):
        pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=ord(key)))
    held[:] = keys

def callback(obs, next_obs, action, reward, terminated, truncated, info):
    actions.append(action)
    if len(actions) in (3, 5):
        press(*(["d", " "] if len(actions) == 3 else [" "]))
    if len(actions) == 7:
        pygame.event.post(pygame.event.Event(pygame.QUIT))

held = []
env = gymnasium.make("invaders/SpaceInvaders-v0", render_mode="rgb_array")
pygame.init()
press("d")
play(env, callback=callback, fps=240, seed=1)
print(*actions)
"""


def test_gymnasiums_play_takes_ales_keys():
    """A person at the keyboard through Gymnasium's `play`: d held is RIGHT, d and space
    RIGHTFIRE, space alone FIRE (ALE's keys, as its environment maps them)."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", PLAYED], capture_output=True, text=True,
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy",
                               "SDL_AUDIODRIVER": "dummy"}, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-7:] == ["2", "2", "2", "4", "4", "1", "1"]


# ALE's keys for each of its 18 actions (ale_py's `get_keys_to_action`), in its order.
ALE_KEYS = (("e",), (" ",), ("w",), ("d",), ("a",), ("s",), ("w", "d"), ("w", "a"),
            ("s", "d"), ("s", "a"), ("w", " "), ("d", " "), ("a", " "), ("s", " "),
            ("w", "d", " "), ("w", "a", " "), ("s", "d", " "), ("s", "a", " "))


def test_the_keys_to_each_action_are_ales_in_both_action_sets():
    """The same keys as ALE's environment gives, for the full set and the minimal one (its
    NOOP, FIRE, RIGHT, LEFT, RIGHTFIRE, LEFTFIRE: actions 0, 1, 3, 4, 11, 12 of the 18)."""
    full = SpaceInvadersEnv(full_action_space=True).get_keys_to_action()
    assert full == {keys: action for action, keys in enumerate(ALE_KEYS)}
    minimal = SpaceInvadersEnv().get_keys_to_action()
    assert minimal == {ALE_KEYS[ale]: action
                       for action, ale in enumerate((0, 1, 3, 4, 11, 12))}


def test_ales_action_sets_name_the_environments_actions_by_ales_numbers():
    """Code written for ALE maps its actions through the action sets (by `.name`, `.value`
    or `int()`): the minimal set is the six actions in order, by ALE's numbers (ale-py
    0.12.1's for Space Invaders), the legal set the full environment's 18, each number
    its action's place there; a game played on the full set by the numbers the minimal
    set gives is the game the six play. The modes and difficulties named are those the
    environment takes."""
    still = {"obs_type": "state", "frameskip": 1, "repeat_action_probability": 0.0}
    six = SpaceInvadersEnv(**still)
    full = SpaceInvadersEnv(full_action_space=True, **still)
    minimal, legal = six.ale.getMinimalActionSet(), full.ale.getLegalActionSet()
    assert [action.name for action in minimal] == six.get_action_meanings()
    assert [action.value for action in minimal] == [0, 1, 3, 4, 11, 12]
    assert [action.name for action in legal] == full.get_action_meanings()
    assert [int(action) for action in legal] == [action.value for action in legal] == list(
        range(18))
    for env in (six, full):
        env.reset(seed=4)
    for step in range(300):
        action = (1, 2, 4, 0, 5, 3)[step % 6]
        ours, theirs = six.step(action), full.step(minimal[action].value)
        assert ours[1:4] == theirs[1:4] and six.world.state_hash() == full.world.state_hash()
    for mode, difficulty in zip(six.ale.getAvailableModes(), six.ale.getAvailableDifficulties(),
                                strict=True):
        SpaceInvadersEnv(mode=mode, difficulty=difficulty).reset(seed=1)
        with pytest.raises(ValueError, match="mode"):
            SpaceInvadersEnv(mode=mode + 1)
