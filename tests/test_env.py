"""The Gymnasium environment: Gymnasium's own checker, ALE's conventions (actions, frame
skip, sticky actions, lives, frame numbers), pictures equal to the window's, rewards that
add up to the score, and every episode a replay that checks."""

from __future__ import annotations

import copy
import errno
import gc
import hashlib
import multiprocessing
import os
import pickle
import random
import re
import select
import signal
import subprocess
import sys
import threading
import types

import gymnasium
import numpy as np
import pygame
import pytest
from gymnasium.envs.registration import EnvSpec
from gymnasium.utils import seeding
from gymnasium.utils.env_checker import check_env, data_equivalence
from gymnasium.vector import AutoresetMode
from gymnasium.wrappers.vector import HumanRendering
from hypothesis import given
from hypothesis import strategies as st

import invaders.env  # noqa: F401  (registers the id)
from invaders.app.cli import main
from invaders.app.render import Renderer
from invaders.atomic import write_new
from invaders.engine.stats import STAT_FIELDS
from invaders.env.games import EVENTS_KEPT
from invaders.env.observations import STATE_FIELDS, STATE_SIZE
from invaders.env.space_invaders import MINIMAL_ACTIONS, SpaceInvadersEnv
from invaders.env.vector import SpaceInvadersVectorEnv
from invaders.game.actions import Action
from invaders.game.config import DEFAULT_CONFIG, SCREEN_H, SCREEN_W
from invaders.game.entities import CannonState
from invaders.game.events import Event
from invaders.game.replay import load
from invaders.game.world import Phase, World
from invaders.lab.autopilot import Autopilot
from tests.helpers import infos_alike, vector_answers_alike

ENV_ID = "invaders/SpaceInvaders-v0"


def test_render_without_a_render_mode_warns_as_gymnasiums_own_environments_do():
    """Gymnasium's own environments (CartPole's, say) warn, in these words, and give
    nothing; ours gave nothing without a word (ALE's raises)."""
    env = gymnasium.make(ENV_ID, obs_type="state")
    env.reset(seed=1)
    said = ("You are calling render method without specifying any render mode. You can "
            f'specify the render_mode at initialization, e.g. gym.make("{ENV_ID}", '
            'render_mode="rgb_array")')
    with pytest.warns(UserWarning, match=re.escape(said)):
        assert env.render() is None


@pytest.mark.parametrize("options", [{"obs_type": "rgb"}, {"obs_type": "grayscale"},
                                     {"obs_type": "state"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 4},
                                     {"obs_type": "state", "continuous": True}],
                         ids=["rgb", "grayscale", "state", "grayscale-84x84x4", "continuous"])
@pytest.mark.filterwarnings("ignore:.*symmetric and normalized space")  # (ALE's Box too)
def test_gymnasiums_own_checker_passes(options):
    env = gymnasium.make(ENV_ID, **options)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def test_the_actions_are_ales_minimal_set_in_ales_order():
    env = gymnasium.make(ENV_ID)
    assert env.unwrapped.get_action_meanings() == [
        "NOOP", "FIRE", "RIGHT", "LEFT", "RIGHTFIRE", "LEFTFIRE"]
    full = gymnasium.make(ENV_ID, full_action_space=True)
    assert full.action_space.n == 18 and full.unwrapped.get_action_meanings()[11] == "RIGHTFIRE"
    fire, left = int(Action.FIRE), int(Action.LEFT)
    right = int(Action.RIGHT)
    assert list(MINIMAL_ACTIONS) == [0, fire, right, left, right | fire, left | fire]


def _picture_in_the_window(world) -> np.ndarray:
    """The window's picture at the end of the last tick (alpha 1: the movers where the
    world has them)."""
    target = pygame.Surface((224, 256))
    Renderer().draw(target, world, alpha=1.0)
    return pygame.surfarray.array3d(target).transpose(1, 0, 2)


def _play(env, seed: int, steps: int, actions=(1, 2, 4, 0, 5, 3)) -> list:
    out = []
    obs, _ = env.reset(seed=seed)
    for i in range(steps):
        obs, reward, terminated, truncated, info = env.step(actions[i % len(actions)])
        out.append((obs.copy(), reward, terminated, truncated, info))
        if terminated or truncated:
            break
    return out


def test_pixel_observations_are_the_windows_picture_pixel_for_pixel():
    rgb = SpaceInvadersEnv(obs_type="rgb")
    grey = SpaceInvadersEnv(obs_type="grayscale")
    for steps in (1, 40, 300):
        seen = _play(rgb, 5, steps)[-1][0]
        window = _picture_in_the_window(rgb.world)
        assert seen.shape == (256, 224, 3) and np.array_equal(seen, window)
        colours = {tuple(c) for c in np.unique(window.reshape(-1, 3), axis=0)}
        assert {(0, 0, 0), (255, 255, 255), (64, 255, 64)} <= colours <= {
            (0, 0, 0), (255, 255, 255), (64, 255, 64), (255, 64, 64)}  # the gel's strips
        grey_seen = _play(grey, 5, steps)[-1][0]
        luma = (window.astype(np.uint32) @ np.array([299, 587, 114]) + 500) // 1000
        assert np.array_equal(grey_seen, luma.astype(np.uint8))


def test_the_pictures_movers_are_where_the_state_has_them():
    """The shot, frame by frame from over the cannon (rows 216 on) to under the rack: its
    four lit rows are the state's, not where it was a tick before (the window's picture
    at a tick's start shows that). The cannon's column at the left is clear of shields."""
    env = SpaceInvadersEnv(obs_type="grayscale", frameskip=1, repeat_action_probability=0.0)
    env.reset(seed=0)
    while env.world.cannon.state is not CannonState.ACTIVE:
        env.step(0)
    flights = 0
    for _ in range(3):
        seen, *_ = env.step(1)  # FIRE
        while env.world.shot is not None and env.world.shot.y > 150:
            shot = env.world.shot
            if shot.y + 8 <= 216:
                column = seen[shot.y - 4:shot.y + 8, shot.x] > 0
                assert list(column) == [False] * 4 + [True] * 4 + [False] * 4, shot.y
                flights += 1
            seen, *_ = env.step(0)
        for _ in range(80):
            env.step(0)
    assert flights > 20


def _expected_state(world) -> dict[str, list[float]]:
    """Each field of the state vector as its documentation says, read from the world."""
    def thing(body):
        return [1.0, body.x, body.y] if body is not None else [0.0, 0.0, 0.0]

    aliens = [v for a in world.rack.aliens
              for v in ([1.0, a.x, a.top] if a is not None and a.alive else [0.0, 0.0, 0.0])]
    flying = world.saucer.saucer
    return {"cannon": [world.cannon.x, float(world.cannon.state is CannonState.ACTIVE)],
            "shot": thing(world.shot), "bombs": [v for s in world.slots for v in thing(s.bomb)],
            "aliens": aliens,
            "saucer": [1.0, flying.x] if flying is not None else [0.0, 0.0],
            "shields": [b.mask.count() for b in world.bunkers],
            "game": [world.score, max(world.ships, 0), world.wave]}


def test_every_kept_state_vector_is_the_worlds_fields_read_afresh():
    """The vector is kept between steps, the aliens' places rewritten where the rack's
    watch says (tests/test_rack_watch.py): over whole episodes of an autopilot and random
    moves, with states restored and frame skips of 1 to 30, each is the fields afresh."""
    kills = 0
    for frameskip, seed in ((1, 1), (4, 2), ((2, 31), 3)):
        env = SpaceInvadersEnv(obs_type="state", frameskip=frameskip)
        draw, pilot = random.Random(seed), Autopilot(seed, "expert")
        state, _ = env.reset(seed=seed)
        saved = env.clone_state()
        for _ in range(3000):
            expected = _expected_state(env.world)
            assert list(state) == [v for name, _, _ in STATE_FIELDS for v in expected[name]]
            bits = pilot.actions(env.world) & (Action.FIRE | Action.LEFT | Action.RIGHT)
            action = MINIMAL_ACTIONS.index(bits) if draw.random() < 0.8 else draw.randrange(6)
            if draw.random() < 0.01:
                saved = env.clone_state()
            elif draw.random() < 0.01:
                env.restore_state(saved)
            state, _, terminated, truncated, info = env.step(action)
            kills += info["events"].count("ALIEN_KILLED")
            if terminated or truncated:
                state, _ = env.reset()
    assert kills > 150


def test_the_state_vector_reads_the_worlds_objects_field_by_field():
    env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0)
    pilot = Autopilot(4, "expert")
    state, _ = env.reset(seed=4)
    seen = set()
    for _ in range(1500):
        world = env.world
        at = 0
        for name, count, _ in STATE_FIELDS:
            assert list(state[at:at + count]) == _expected_state(world)[name], name
            at += count
        seen |= {name for name, present in (("shot", world.shot), ("saucer", world.saucer.saucer),
                                             ("bomb", any(s.bomb for s in world.slots)))
                 if present}
        bits = pilot.actions(world)
        action = MINIMAL_ACTIONS.index(bits & (Action.FIRE | Action.LEFT | Action.RIGHT))
        state, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    assert at == STATE_SIZE and seen == {"shot", "saucer", "bomb"}


def test_the_same_seed_and_actions_give_the_same_episode_and_other_seeds_another():
    def episode(seed):
        env = SpaceInvadersEnv(obs_type="state")
        steps = _play(env, seed, 400)
        return env.world.state_hash(), [s[1] for s in steps], steps[-1][0]

    first, again, other = episode(11), episode(11), episode(12)
    assert first[0] == again[0] and first[1] == again[1]
    assert np.array_equal(first[2], again[2])
    assert other[0] != first[0]


def _autopilot_action(bits: int) -> int:
    """The minimal action nearest an autopilot's input bits (it never asks for up or down)."""
    bits &= int(Action.LEFT | Action.RIGHT | Action.FIRE)
    return MINIMAL_ACTIONS.index(bits) if bits in MINIMAL_ACTIONS else 0


@pytest.mark.parametrize("agent", ["random", "autopilot"])
def test_rewards_add_up_to_the_score_and_the_episode_ends_at_game_over(agent):
    env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0)
    env.action_space.seed(3)
    pilot = Autopilot(4)
    _, info = env.reset(seed=4)
    assert set(info["collisions"].values()) == {0}  # (no frame played)
    total, lives, terminated, steps = 0.0, info["lives"], False, 0
    while not terminated:
        world = env.world
        action = (env.action_space.sample() if agent == "random"
                  else _autopilot_action(pilot.actions(world)))
        score = world.score
        _, reward, terminated, truncated, info = env.step(action)
        assert reward == world.score - score and not truncated
        assert info["lives"] <= lives and info["lives"] == world.ships >= 0
        if reward:  # (a saucer's score comes after its explosion, a few frames on)
            assert {"ALIEN_KILLED", "SAUCER_SCORED"} & set(info["events"])
        if "ALIEN_KILLED" in info["events"]:
            assert info["collisions"]["contacts"] >= 1
        lives, total, steps = info["lives"], total + reward, steps + 1
    assert env.world.phase is Phase.GAME_OVER and total == env.world.score > 0
    assert info["episode_frame_number"] == env.world.tick and lives == 0
    over_at = env.world.tick  # as ALE's, no frame is played past the end until a reset
    for action in (1, 2):
        _, reward, terminated, truncated, info = env.step(action)
        assert (reward, terminated, truncated, info["events"]) == (0.0, True, False, ())
        assert env.world.tick == info["episode_frame_number"] == over_at
        assert set(info["collisions"].values()) == {0}


def test_info_sums_the_steps_frames_counters_and_lists_their_events_in_order():
    """Checked against a world of the same seed stepped frame by frame beside the env (no
    sticky actions: each frame's input is the action's)."""
    env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0, frameskip=3)
    _, info = env.reset(seed=8)
    twin, draws, busy = World(info["seed"], DEFAULT_CONFIG), random.Random(8), 0
    for _ in range(600):
        action = draws.randrange(len(MINIMAL_ACTIONS))
        reports = [twin.step(MINIMAL_ACTIONS[action]) for _ in range(3)]
        info = env.step(action)[4]
        summed = {field: sum(getattr(report.stats, field) for report in reports)
                  for field in STAT_FIELDS}
        assert info["collisions"] == summed
        assert info["events"] == tuple(event.name for report in reports
                                       for event in report.events)
        busy += len({report.stats for report in reports}) > 1 and len(info["events"]) > 1
    assert busy > 10  # (steps whose frames differ and have several events between them)


def test_sticky_actions_repeat_the_last_frames_input_with_ales_probability(tmp_path):
    """ALE v5's definition, frame by frame: with probability p the previous frame's input
    is kept instead of the agent's. Replayed here from the episode's own generator, seeded
    from the env's."""
    env = SpaceInvadersEnv(obs_type="state", frameskip=3, record=tmp_path)
    chosen = [i % 6 for i in range(120)]
    _, _ = env.reset(seed=21)
    for action in chosen:
        if env.step(action)[2]:
            break
    env.close()
    (path,) = tmp_path.glob("*.json")
    played = list(load(path).actions())
    seeds, _ = seeding.np_random(21)
    seeds.integers(0, 2**31 - 1)  # the world's seed comes first, then the frames' generator's
    frames = random.Random(int(seeds.integers(0, 2**63 - 1)))
    previous, expected = 0, []
    for action in chosen:
        for _ in range(3):
            bits = previous if frames.random() < 0.25 else MINIMAL_ACTIONS[action]
            previous = bits
            expected.append(bits)
    assert played == expected[:len(played)] and len(played) == 360
    wanted = [MINIMAL_ACTIONS[a] for a in chosen for _ in range(3)]
    overridden = sum(1 for w, p in zip(wanted, played, strict=True) if w != p)
    assert 10 < overridden < 90  # sticky now and then: about a quarter of the changes


def test_a_frameskip_range_takes_a_number_of_frames_from_it_each_step():
    env = SpaceInvadersEnv(obs_type="state", frameskip=(2, 5))
    env.reset(seed=1)
    frames, seen = 0, set()
    for _ in range(60):
        info = env.step(0)[4]
        seen.add(info["episode_frame_number"] - frames)
        frames = info["episode_frame_number"]
    assert seen == {2, 3, 4}


def test_every_episode_is_a_replay_that_checks(tmp_path, capsys):
    env = gymnasium.make(ENV_ID, obs_type="grayscale", record=str(tmp_path / "episodes"))
    env.action_space.seed(0)
    for seed in (1, 2):
        env.reset(seed=seed)
        for _ in range(150):
            env.step(env.action_space.sample())
    env.close()
    files = sorted((tmp_path / "episodes").glob("*.json"))
    assert [f.name for f in files] == [f"episode-0000{n}-seed-{load(f).seed}.json"
                                       for n, f in zip((1, 2), files, strict=True)]
    assert [load(f).ticks for f in files] == [600, 600]
    assert main(["replay", *map(str, files)]) == 0
    assert capsys.readouterr().out.count("ok ") == 2


def _played(env: SpaceInvadersEnv, actions: list[int]) -> list[tuple]:
    """Each step's observation (as bytes), reward, ends and info."""
    return [(obs.tobytes(), reward, terminated, truncated, info)
            for obs, reward, terminated, truncated, info in map(env.step, actions)]


@pytest.mark.parametrize("options", [{"obs_type": "state"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 4}])
def test_a_state_cloned_and_restored_plays_the_same_steps_each_time(options, tmp_path, capsys):
    """ALE's clone_state and restore_state, the generator of sticky actions and frame skips
    in the state: the same actions from the state give the same steps however often it is
    restored, and the episode recorded through the restores checks."""
    env = SpaceInvadersEnv(frameskip=(2, 6), record=tmp_path, **options)
    env.reset(seed=4)
    draw = random.Random(0)
    _played(env, [draw.randrange(6) for _ in range(150)])
    state = env.clone_state(include_rng=True)
    actions = [draw.randrange(6) for _ in range(400)]
    first = _played(env, actions)
    assert sum(step[1] for step in first) > 0 and any(step[4]["events"] for step in first)
    for _ in range(2):
        env.restore_state(state)
        assert _played(env, actions) == first
    env.restore_state(state)
    while not any(env.step(draw.randrange(6))[2:4]):
        pass
    (episode,) = tmp_path.glob("*.json")
    assert main(["replay", str(episode)]) == 0 and "ok " in capsys.readouterr().out


def test_a_states_world_is_the_environments_until_a_frame_is_played_on_a_copy(tmp_path):
    """A search's node restores a state, steps and clones: the state and the environment
    share the world (no copy at a clone or a restore), and the environment copies it
    before it plays a frame, so the state's world stays as it was cloned, however often it
    is restored and played from; a step after game over plays no frame and copies none.
    Where episodes are recorded, a state is copied at once (its recording changes as the
    episode is written)."""
    env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0)
    env.reset(seed=5)
    _played(env, [1, 2, 3] * 20)
    state = env.clone_state()
    assert state.world is env.world
    cloned = state.world.state_hash()
    first = _played(env, [4] * 30)
    assert env.world is not state.world and state.world.state_hash() == cloned
    for _ in range(2):
        env.restore_state(state)
        assert env.world is state.world
        assert _played(env, [4] * 30) == first and state.world.state_hash() == cloned
    while not env.step(1)[2]:
        pass
    over = env.clone_state()
    env.step(1)
    assert env.world is over.world
    recorded = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    recorded.reset(seed=5)
    recorded.step(1)
    assert recorded.clone_state().world is not recorded.world


@pytest.mark.parametrize("options", [{"obs_type": "rgb"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 4}])
def test_a_deep_copy_of_the_environment_plays_on_as_it_would(options):
    """`copy.deepcopy(env)`, as some libraries make them: the copy's steps are the ones the
    environment gives for the same actions, pictures included (each draws its own)."""
    env = SpaceInvadersEnv(**options)
    env.reset(seed=3)
    draw = random.Random(2)
    _played(env, [draw.randrange(6) for _ in range(100)])
    copied, actions = copy.deepcopy(env), [draw.randrange(6) for _ in range(300)]
    assert _played(copied, actions) == _played(env, actions)


@pytest.mark.parametrize("options", [{"obs_type": "rgb"}, {"obs_type": "state"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 4}])
def test_the_environment_pickles_and_the_loaded_one_plays_on_as_it_would(options):
    """Gymnasium's own test of its environments (`test_pickle_env`), which ALE's passes:
    made by `gymnasium.make`, pickled and loaded, it steps and resets as the environment
    does; here after 100 steps of an episode, for 300 more, then a reset and a step."""
    env = gymnasium.make(ENV_ID, **options)
    env.reset(seed=3)
    draw = random.Random(2)
    _played(env, [draw.randrange(6) for _ in range(100)])
    loaded, actions = pickle.loads(pickle.dumps(env)), [draw.randrange(6) for _ in range(300)]
    assert _played(loaded, actions) == _played(env, actions)
    assert data_equivalence(loaded.reset(), env.reset())
    action = env.action_space.sample()
    assert data_equivalence(loaded.step(action), env.step(action))


def test_a_shown_environment_copied_or_pickled_shows_its_own_play():
    """A human-rendered environment's window is not copied: a copy, or one loaded from a
    pickle, steps as the environment does and opens a window when it shows a step."""
    env = SpaceInvadersEnv(obs_type="state", render_mode="human")
    env.reset(seed=1)
    env.step(1)
    assert env._window is not None
    for other in (copy.deepcopy(env), pickle.loads(pickle.dumps(env))):
        assert other._window is None
        assert _played(other, [1, 4]) == _played(copy.deepcopy(env), [1, 4])
        assert other._window is not None and other._window is not env._window
        other.close()
    env.close()


STATE_RESTORED = """
import pickle, sys
from invaders.env.space_invaders import SpaceInvadersEnv
from tests.test_env import steps_digest
env = SpaceInvadersEnv(obs_type="state", frameskip=(2, 6))
env.reset(seed=0)
with open(sys.argv[1], "rb") as file:
    env.restore_state(pickle.load(file))
print(steps_digest(env))
"""


def steps_digest(env: SpaceInvadersEnv) -> str:
    """A digest of 500 steps of fixed actions: observations, rewards, ends and infos."""
    digest = hashlib.sha256()
    for step in _played(env, [(i * 7) % 6 for i in range(500)]):
        digest.update(repr(step).encode())
    return digest.hexdigest()


def test_a_state_pickled_is_restored_in_another_process_and_plays_the_same(tmp_path):
    """ALE's states pickle: one cloned here (with the generator of sticky actions and frame
    skips), written with pickle and restored in a new process plays the steps it plays
    restored here; it holds no reference to this process's objects."""
    env = SpaceInvadersEnv(obs_type="state", frameskip=(2, 6))
    env.reset(seed=8)
    _played(env, [random.Random(3).randrange(6) for _ in range(200)])
    state = env.clone_state(include_rng=True)
    (tmp_path / "state.pickle").write_bytes(pickle.dumps(state))
    here = steps_digest(env)
    env.restore_state(state)
    assert steps_digest(env) == here
    done = subprocess.run([sys.executable, "-c", STATE_RESTORED, str(tmp_path / "state.pickle")],
                          capture_output=True, text=True, check=True,
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
    assert done.stdout.split() == [here]


def test_a_state_restored_without_the_generator_leaves_the_environments_own():
    """As ALE's (include_rng=False): without sticky actions and with a fixed frame skip the
    steps from the state are the same again; the generator goes on where it was. Restored
    before a reset, where the frames stacked cannot be the state's, or not a state at all:
    refused, naming why."""
    env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0)
    env.reset(seed=9)
    state, actions = env.clone_state(), [random.Random(1).randrange(6) for _ in range(300)]
    first = _played(env, actions)
    drawn = env._draws.getstate()
    env.restore_state(state)
    assert env._draws.getstate() == drawn and _played(env, actions) == first
    stacking = SpaceInvadersEnv(obs_type="grayscale", stack=4)
    with pytest.raises(RuntimeError, match="reset"):
        stacking.restore_state(state)
    stacking.reset(seed=9)
    with pytest.raises(ValueError, match="stacks other pictures"):
        stacking.restore_state(state)
    for wrong in (None, state.world, vars(state)):
        with pytest.raises(TypeError, match="is not a state clone_state gave"):
            env.restore_state(wrong)


def test_recording_never_writes_over_an_episode_already_there(tmp_path):
    """Two runs of the same seeds into one folder (a script run twice): the second run's
    episodes get names of their own; every file is kept, and each is its own run's."""
    runs = []
    for actions in (1, 3):  # (FIRE, then LEFT: two different episodes of the same seed)
        env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
        env.reset(seed=5)
        for _ in range(100):
            env.step(actions)
        env.close()
        runs.append(sorted(tmp_path.glob("*.json")))
    (first,), both = runs
    (second,) = set(both) - {first}
    assert second.name == first.name.replace(".json", "-2.json")
    assert load(first).seed == load(second).seed
    assert list(load(first).actions()) != list(load(second).actions())


def test_an_episode_without_a_frame_played_is_not_written(tmp_path):
    """Reset twice, a step, a reset and close: of the three episodes begun, only the one
    played is a file (numbered the first); a reset alone leaves nothing to replay."""
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    env.reset(seed=1)
    env.reset(seed=2)
    played = env.world.seed
    env.step(1)
    env.reset(seed=3)
    env.close()
    (path,) = tmp_path.iterdir()
    assert path.name == f"episode-00001-seed-{played}.json" and load(path).ticks == 4


def test_an_episode_that_cannot_be_written_is_kept_until_it_can_be(tmp_path, monkeypatch):
    """The disk full when two episodes end (every write failing as a full disk's does):
    each end warns and play goes on; close raises, naming the two kept; with room again,
    a second close writes both, in order, each the same file as a run with room all along
    writes (the same seeds and actions)."""
    from invaders.env import recording

    def episodes(folder) -> SpaceInvadersEnv:
        env = SpaceInvadersEnv(obs_type="state", record=folder, max_num_frames_per_episode=80)
        for seed in (4, 5):
            env.reset(seed=seed)
            while not env.step(seed % 6)[3]:  # (truncated at 80 frames)
                pass
        return env

    room = episodes(tmp_path / "room")
    room.close()
    full = [True]

    def write_new_or_fail(path, text):
        if full[0]:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return write_new(path, text)

    monkeypatch.setattr(recording, "write_new", write_new_or_fail)
    with pytest.warns(RuntimeWarning) as warned:
        env = episodes(tmp_path / "full")
    first, second = sorted(path.name for path in (tmp_path / "room").iterdir())
    assert [str(w.message) for w in warned] == [
        f"invaders: {n} recorded not written in {tmp_path / 'full'} ({which}: No space left "
        "on device): kept, and written when the next episode ends or at close()"
        for n, which in (("1 episode", first), ("2 episodes", f"{first} to {second}"))]
    with pytest.raises(OSError, match="2 episodes recorded not written") as raised:
        env.close()
    assert raised.value.errno == errno.ENOSPC
    assert list((tmp_path / "full").iterdir()) == []
    full[0] = False
    env.close()
    written, expected = (sorted((tmp_path / run).iterdir()) for run in ("full", "room"))
    assert [path.name for path in written] == [path.name for path in expected]
    assert [path.read_text() for path in written] == [path.read_text() for path in expected]
    assert [load(path).ticks for path in written] == [80, 80]


def test_a_batch_closes_every_game_when_one_cannot_write_its_episode(tmp_path, monkeypatch):
    """The first write fails (game 0's, at close): close raises it, having closed game 1
    too (its episode written); game 0's is kept, and written when the batch is dropped."""
    from invaders.env import recording

    tries = []

    def write_new_failing_first(path, text):
        tries.append(path)
        if len(tries) == 1:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return write_new(path, text)

    monkeypatch.setattr(recording, "write_new", write_new_failing_first)
    envs = SpaceInvadersVectorEnv(2, obs_type="state", record=tmp_path)
    envs.reset(seed=3)
    for _ in range(10):
        envs.step(np.array([1, 2]))
    seeds = [env.world.seed for env in envs.envs]
    with pytest.raises(OSError, match="1 episode recorded not written"):
        envs.close()
    assert [load(path).seed for path in tmp_path.iterdir()] == seeds[1:]
    del envs
    gc.collect()
    assert sorted(load(path).seed for path in tmp_path.iterdir()) == sorted(seeds)
    assert [load(path).ticks for path in tmp_path.iterdir()] == [40, 40]


CLOSED_WITHOUT_ROOM = """
import sys
from pathlib import Path

import gymnasium
import numpy as np

import invaders.env  # noqa: F401

how, folder = sys.argv[1], Path(sys.argv[2])
envs = gymnasium.make_vec("invaders/SpaceInvaders-v0", num_envs=2, obs_type="state",
                          record=str(folder), **({"vectorization_mode": "async"}
                          if how == "async" else {"workers": 2,
                          "vectorization_mode": "vector_entry_point"}))
envs.reset(seed=3)
for _ in range(10):
    info = envs.step(np.array([1, 2]))[4]
folder.rmdir()  # (nothing written yet: every episode is in progress)
folder.write_text("")
try:
    envs.close()
    raised = "nothing"
except OSError as failure:
    raised = "kept" if "kept while this process runs" in str(failure) else str(failure)
print(info["seed"][0], info["seed"][1], raised)
"""


@pytest.mark.parametrize(("how", "raised"), [("workers", "kept"), ("async", "nothing")])
def test_a_vector_on_workers_closed_without_room_says_what_each_game_loses(how, raised,
                                                                           tmp_path):
    """The folder gone before close (a file in its place), 2 games on worker processes:
    each worker's game, which ends with its worker, is said lost there, in one warning
    naming its file, with no traceback; the native batch's close raises its caller's own
    game's failure (kept, for another close; lost, and said so, when the program ends).
    Before, a worker's game went without a word behind the caller's failure, and
    Gymnasium's async workers printed tracebacks that said the episode kept."""
    done = subprocess.run([sys.executable, "-c", CLOSED_WITHOUT_ROOM, how,
                           str(tmp_path / "e")], capture_output=True, text=True, timeout=120)
    first, second, said_raised = done.stdout.split()
    said = re.findall(r"RuntimeWarning: invaders: 1 episode recorded not written in \S+ "
                      r"\((episode-\d+-seed-\d+\.json): Not a directory\): lost with the "
                      r"environment", done.stderr)
    assert said_raised == raised and "Traceback" not in done.stderr, done.stderr
    assert sorted(said) == sorted(f"episode-00001-seed-{seed}.json"
                                  for seed in (first, second)), done.stderr


def test_two_processes_recording_the_same_episode_keep_both(tmp_path):
    """Gymnasium's async vector, both games seeded alike: each process writes the same
    episode under the same name at the same moment; both files are kept, equal."""
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="async",
                              obs_type="state", record=str(tmp_path),
                              max_num_frames_per_episode=40)
    envs.reset(seed=[7, 7])
    for _ in range(10):
        envs.step(np.array([1, 1]))
    envs.close()
    first, second = sorted(tmp_path.glob("*.json"), key=lambda path: len(path.name))
    assert second.name == first.name.replace(".json", "-2.json")
    assert first.read_text() == second.read_text() and load(first).ticks == 40


@pytest.mark.parametrize(("folder", "said"), [("", "record ''"), ("a-file/episodes", "a-file"),
                                              ("a-file", "a-file' is there and is not a folder")])
def test_a_record_folder_that_cannot_take_episodes_fails_before_any_play(tmp_path, folder,
                                                                         said):
    """An empty name, a folder inside a file, or a file (a name taken for the file to
    write, say): refused when the environment is made, not after its first episode's play."""
    (tmp_path / "a-file").write_text("not a folder")
    error = ValueError if not folder else OSError
    with pytest.raises(error, match=said):
        SpaceInvadersEnv(obs_type="state", record=str(tmp_path / folder) if folder else "")
    assert (tmp_path / "a-file").read_text() == "not a folder"


def test_a_new_file_takes_the_first_free_name_even_without_hard_links(tmp_path, monkeypatch):
    """write_new never replaces a file: with hard links (which take only a free name) and
    on a file system without them (the name taken empty first, then filled)."""
    (tmp_path / "game.json").write_text("kept")
    assert write_new(tmp_path / "game.json", "second") == tmp_path / "game-2.json"

    def no_links(*_):
        raise OSError(errno.EPERM, "no hard links here")

    monkeypatch.setattr(os, "link", no_links)
    assert write_new(tmp_path / "game.json", "third") == tmp_path / "game-3.json"
    assert write_new(tmp_path / "new.json", "fourth") == tmp_path / "new.json"
    assert {p.name: p.read_text() for p in tmp_path.iterdir()} == {
        "game.json": "kept", "game-2.json": "second", "game-3.json": "third",
        "new.json": "fourth"}


def test_games_on_workers_record_their_episodes_when_closed(tmp_path, capsys):
    """Each game records where it runs; closing the vector closes every game (its last
    episode written) and ends the workers, several times over (an ended worker's pipe
    says nothing more). Each run's 6 episodes are kept beside the runs' before (the same
    seeds: the same names, numbered on)."""
    folder = tmp_path / "episodes"
    for _ in range(4):
        envs = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                  workers=2, obs_type="state", record=str(folder),
                                  max_num_frames_per_episode=200)
        envs.reset(seed=4)
        for _ in range(60):  # 50 steps an episode, then 9 of the next
            envs.step(np.array([1, 2, 3]))
        envs.close()
    files = sorted(folder.glob("*.json"))
    assert sorted(load(f).ticks for f in files) == [36] * 12 + [200] * 12
    assert main(["replay", str(folder)]) == 0
    assert capsys.readouterr().out.count("ok ") == 24


UNCLOSED = """
import os
import shutil
import signal
import sys

import gymnasium
import numpy as np

import invaders.env  # noqa: F401

how, folder = sys.argv[1], sys.argv[2]
if how in ("workers", "async", "killed"):
    envs = gymnasium.make_vec("invaders/SpaceInvaders-v0", num_envs=3, obs_type="state",
                              record=folder, **({"vectorization_mode": "async"}
                              if how == "async" else {"workers": 2,
                              "vectorization_mode": "vector_entry_point"}))
    envs.reset(seed=4)
    for _ in range(25):
        envs.step(np.array([1, 2, 3]))
    if how == "killed":  # (its worker's pid and games, then killed as the OOM killer kills)
        pool = envs.unwrapped._games
        print(pool._workers[0].process.pid, pool._shares[0][1] - pool._shares[0][0],
              flush=True)
        os.kill(os.getpid(), signal.SIGKILL)
else:
    env = gymnasium.make("invaders/SpaceInvaders-v0", obs_type="state", record=folder)
    env.reset(seed=0)
    for i in range(100):
        env.step(i % 6)
    if how == "interrupted":
        raise KeyboardInterrupt
    if how == "failed":
        raise RuntimeError("a training script's own error")
if sys.argv[3:] == ["gone"]:  # (a file in the folder's place: no episode can be written)
    shutil.rmtree(folder)
    open(folder, "w").close()
"""


# (Python ends on an uncaught Ctrl-C by its own SIGINT, as the shell expects)
@pytest.mark.parametrize(("how", "exit_code"), [("ended", 0), ("interrupted", -signal.SIGINT),
                                                ("failed", 1), ("workers", 0), ("async", 0)])
def test_a_script_that_never_closes_its_environment_loses_no_episode(how, exit_code,
                                                                     tmp_path, capsys):
    """A script that ends without closing: at its last line, stopped by Ctrl-C or by an
    error. The episode in progress is written as close writes it; so are those of the
    native batch's games on workers, which the program's end would otherwise kill, and
    those of Gymnasium's async vector, whose workers it ends by SIGTERM."""
    folder = tmp_path / "episodes"
    done = subprocess.run([sys.executable, "-c", UNCLOSED, how, str(folder)],
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy"},
                          capture_output=True, text=True)
    assert done.returncode == exit_code, done.stderr
    files = sorted(folder.glob("*.json"))
    assert [load(f).ticks for f in files] == ([100] * 3 if how in ("workers", "async")
                                              else [400])
    assert main(["replay", str(folder)]) == 0
    assert capsys.readouterr().out.count("ok ") == len(files)


@pytest.mark.parametrize(("how", "games"), [("ended", 1), ("workers", 3), ("async", 3)])
def test_a_script_that_never_closes_its_environment_says_each_episode_it_cannot_write(
        how, games, tmp_path):
    """As above, the folder gone at the script's end (a file in its place): each game's
    episode in progress is said lost, in one warning naming its file, in whichever process
    has the game; no traceback (a batch's drop raised its first game's OSError, printed
    as an exception ignored, and said "kept" when nothing was)."""
    folder = tmp_path / "episodes"
    done = subprocess.run([sys.executable, "-c", UNCLOSED, how, str(folder), "gone"],
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy"},
                          capture_output=True, text=True)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    said = re.findall(r"RuntimeWarning: invaders: 1 episode recorded not written in "
                      rf"{re.escape(str(folder))} \((episode-0000\d-seed-\d+\.json): Not a "
                      r"directory\): lost with the environment", done.stderr)
    assert len(set(said)) == len(said) == games, done.stderr


def _sigterm_handler_after_recording(folder: str, own: bool, answers) -> None:
    """In a child process: SIGTERM's handler once an environment records there (with
    one of the process's own set before, or not)."""
    if own:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
    SpaceInvadersEnv(obs_type="state", record=folder).close()
    answers.put(repr(signal.getsignal(signal.SIGTERM)))


@pytest.mark.skipif(not hasattr(os, "fork"), reason="a child forked with this test's code")
@pytest.mark.skipif(not hasattr(os, "pidfd_open"), reason="waits on a process it did not start")
def test_the_batchs_workers_close_their_games_when_the_caller_is_killed(tmp_path, capsys):
    """Killed (SIGKILL, as the kernel's OOM killer kills), the caller closes nothing: its
    worker, waiting for the next command, sees that the caller is gone, closes its games
    (their episodes in progress written) and ends, where it waited forever."""
    folder = tmp_path / "episodes"
    done = subprocess.run([sys.executable, "-c", UNCLOSED, "killed", str(folder)],
                          env={**os.environ, "SDL_VIDEODRIVER": "dummy"},
                          capture_output=True, text=True, timeout=120)  # (its output's
    assert done.returncode == -signal.SIGKILL, done.stderr  # end is the worker's too)
    pid, games = map(int, done.stdout.split())
    try:
        ended = os.pidfd_open(pid)
    except ProcessLookupError:
        pass  # (ended already)
    else:
        assert select.select([ended], [], [], 60)[0], "the worker outlived its caller"
        os.close(ended)
    files = sorted(folder.glob("*.json"))
    assert [load(f).ticks for f in files] == [100] * games and games >= 1
    assert main(["replay", str(folder)]) == 0


@pytest.mark.forks
def test_only_a_child_process_without_its_own_handler_is_ended_by_sigterm_gently(tmp_path,
                                                                             alone):
    """An environment that records makes SIGTERM raise SystemExit only in a child process
    (as Gymnasium's async vector's workers are) whose SIGTERM was the default: the main
    process's signals are its program's, and a child's own handler is kept."""
    before = signal.getsignal(signal.SIGTERM)
    SpaceInvadersEnv(obs_type="state", record=tmp_path).close()
    assert signal.getsignal(signal.SIGTERM) is before
    context = multiprocessing.get_context("fork")
    answers = context.Queue()
    for own in (False, True):
        child = context.Process(target=_sigterm_handler_after_recording,
                                args=(str(tmp_path), own, answers))
        child.start()
        child.join()
        assert child.exitcode == 0
    assert "_exit" in answers.get(timeout=10)
    assert answers.get(timeout=10) == repr(signal.SIG_IGN)


def test_an_environment_dropped_unclosed_writes_its_episode_and_so_does_its_copy(tmp_path):
    """Garbage collected without close, an environment writes the episode it was playing;
    a copy of it (pickled and loaded) records on by itself, and writes its own."""
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    env.reset(seed=2)
    for _ in range(50):
        env.step(1)
    loaded = pickle.loads(pickle.dumps(env))
    for _ in range(20):
        loaded.step(2)
    del env, loaded
    gc.collect()
    shorter, longer = sorted(map(load, tmp_path.glob("*.json")), key=lambda r: r.ticks)
    assert (shorter.ticks, longer.ticks) == (200, 280)
    assert list(longer.actions())[:200] == list(shorter.actions())


@pytest.mark.skipif(not hasattr(os, "fork"), reason="a fork is what this is about")
@pytest.mark.forks
def test_a_forked_process_never_writes_its_parents_episode(tmp_path, alone):
    """A process forked (as multiprocessing's workers are, on Linux) has a copy of the
    parent's finalizers: an environment left for the garbage collector (in a cycle, as
    reading `env.unwrapped.ale` makes one) and collected in the child writes nothing
    there; the parent, collecting it, writes the episode once."""
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    env.reset(seed=2)
    for _ in range(30):
        env.step(1)
    assert env.ale.lives() == 3  # (the view holds the environment: a cycle)
    gc.disable()
    try:
        del env
        pid = os.fork()
        if pid == 0:  # the child: collects the environment, then ends at once
            gc.collect()
            os._exit(0)
        assert os.waitpid(pid, 0)[1] == 0
        assert list(tmp_path.glob("*.json")) == []
    finally:
        gc.enable()
    gc.collect()
    assert [load(f).ticks for f in tmp_path.glob("*.json")] == [120]


class Interrupting:
    """An observer of a world's detection that raises KeyboardInterrupt inside tick `at`,
    its moves made and its contacts not yet found nor answered: Ctrl-C at the worst
    moment for a recording."""

    def __init__(self, at: int) -> None:
        self.at = at

    def before(self, scene) -> None:
        if scene.tick == self.at:
            raise KeyboardInterrupt

    def after(self, scene, candidates, contacts, stats) -> None:
        pass


@pytest.mark.parametrize("at", [130, 181])
def test_an_episode_cut_off_inside_a_tick_is_written_up_to_its_last_checkpoint(tmp_path, at):
    """A step cut off inside a tick (Ctrl-C) leaves the world half moved, where no
    checkpoint can be made: the episode is written up to its last checkpoint, and replays
    (written where the world stood, it did not); the next episode is recorded whole."""
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    env.reset(seed=5)
    env.world.detector.observers.append(Interrupting(at))
    with pytest.raises(KeyboardInterrupt):
        for step in range(100):
            env.step(1 + step % 5)
    env.reset(seed=6)  # (the cut episode written, the next begun)
    for _ in range(30):
        env.step(2)
    env.close()
    cut, whole = (load(path).ticks for path in sorted(tmp_path.glob("*.json")))
    assert (cut, whole) == (at // 60 * 60, 120)
    assert main(["replay", str(tmp_path)]) == 0


def _cut_off_once(recorder, name):
    """Ctrl-C as the recorder's method `name` is called: raised instead, once."""
    def interrupted(*args):
        delattr(recorder, name)  # (the method itself from then on)
        raise KeyboardInterrupt
    setattr(recorder, name, interrupted)


def test_a_reset_cut_off_before_its_recording_begins_is_recorded_all_the_same(tmp_path):
    """Ctrl-C between a reset's new world and its recording begun, and the script plays
    on: the episode before is written whole and the new one recorded from its start, where
    the new world's ticks went into the old recording, whose file did not replay."""
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    env.reset(seed=5)
    for _ in range(40):
        env.step(1)
    _cut_off_once(env._recorder, "begin")
    with pytest.raises(KeyboardInterrupt):
        env.reset(seed=6)
    for _ in range(30):
        env.step(2)
    env.close()
    files = sorted(tmp_path.glob("*.json"))
    assert [load(f).ticks for f in files] == [160, 120]
    assert main(["replay", str(tmp_path)]) == 0


def test_a_restore_cut_off_before_its_recording_follows_keeps_the_episode_recorded(tmp_path):
    """Ctrl-C between a restored world and its recording followed: the episode recorded
    so far is written as it stood, and the restored world, past its start, plays on
    unrecorded (its ticks noted in that recording made a file that did not replay)."""
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path)
    env.reset(seed=5)
    for _ in range(20):
        env.step(1)
    state = env.clone_state()
    for _ in range(25):
        env.step(4)
    _cut_off_once(env._recorder, "follow")
    with pytest.raises(KeyboardInterrupt):
        env.restore_state(state)
    for _ in range(10):
        env.step(3)
    env.close()
    (path,) = tmp_path.glob("*.json")
    assert load(path).ticks == 180
    assert main(["replay", str(tmp_path)]) == 0


def test_an_episode_past_a_replays_limits_is_recorded_up_to_them_with_a_warning(
        tmp_path, monkeypatch, capsys):
    """The input runs a replay may hold lowered to 30 (a million in the program, which an
    episode without a frame limit could pass after hours of play): a new input every step
    (4 frames) makes 15 runs between checkpoints, so the recording stops at the second
    checkpoint (tick 120), said once by a warning; the game plays on, and the file
    written at the episode's end replays under the same limit."""
    from invaders.game import recording, replay_checks, replay_reading

    for module in (recording, replay_checks, replay_reading):
        monkeypatch.setattr(module, "MAX_RUNS", 30)
    env = SpaceInvadersEnv(obs_type="state", record=tmp_path, repeat_action_probability=0.0)
    env.reset(seed=3)
    with pytest.warns(RuntimeWarning, match="recording stopped at tick 120") as warned:
        for i in range(100):
            env.step(i % 6)
    assert len(warned) == 1 and env.episode_frame_number == 400
    env.close()
    (path,) = tmp_path.glob("*.json")
    assert load(path).ticks == 120
    assert main(["replay", str(path)]) == 0
    assert capsys.readouterr().out.startswith("ok ")


def test_a_state_restored_in_another_environment_records_into_its_folder(tmp_path,
                                                                          monkeypatch):
    """A state cloned in one recording environment and restored in another: the episode
    goes on in the other's folder, and its stop at a replay's limits (the runs' limit
    lowered to 30, as above) is said naming that folder."""
    import re

    from invaders.game import recording

    monkeypatch.setattr(recording, "MAX_RUNS", 30)
    first, second = (SpaceInvadersEnv(obs_type="state", record=tmp_path / name,
                                      repeat_action_probability=0.0)
                     for name in ("first", "second"))
    first.reset(seed=3)
    second.reset(seed=4)
    for i in range(20):
        first.step(i % 6)
    second.restore_state(first.clone_state())
    said = f"recorded in {tmp_path / 'second'}: recording stopped at tick 120"
    with pytest.warns(RuntimeWarning, match=re.escape(said)):
        for i in range(20, 60):
            second.step(i % 6)
    first.close()
    second.close()
    assert [load(f).ticks for f in (tmp_path / "first").glob("*.json")] == [80]
    assert [load(f).ticks for f in (tmp_path / "second").glob("*.json")] == [120]


def test_a_worker_killed_is_said_at_the_next_step_and_closing_still_closes(tmp_path):
    from invaders.env.workers import WorkerEnded

    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                              workers=2, obs_type="state", record=str(tmp_path))
    envs.reset(seed=4)
    envs.step(np.array([1, 1]))
    envs.unwrapped._games._workers[0].process.kill()
    with pytest.raises(WorkerEnded, match=r"a games worker ended \(exit code -9\)"):
        for _ in range(3):  # (the kill may land after the first of them)
            envs.step(np.array([1, 1]))
    envs.close()  # the caller's own game is closed: its episode written
    assert len(list(tmp_path.glob("*.json"))) == 1


def test_an_interrupted_step_on_workers_is_never_taken_for_the_next(monkeypatch):
    """Ctrl-C in the caller's own share: the workers' answers are still taken, and the
    vector steps on. Ctrl-C while waiting on a worker: the next step is refused (the
    worker's answer would be taken for it), and closing still ends the workers."""
    from invaders.env import workers

    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                              workers=2, obs_type="state")
    envs.reset(seed=4)
    pool = envs.unwrapped._games

    def interrupted(*_):
        raise KeyboardInterrupt

    with monkeypatch.context() as patch:
        patch.setattr(pool._here, "step", interrupted)
        with pytest.raises(KeyboardInterrupt):
            envs.step(np.array([1, 1]))
    assert envs.step(np.array([1, 1]))[0].shape == (2, 188)
    with monkeypatch.context() as patch:
        patch.setattr(workers._Worker, "answer", interrupted)
        with pytest.raises(KeyboardInterrupt):
            envs.step(np.array([1, 1]))
    with pytest.raises(RuntimeError, match="interrupted before every worker answered"):
        envs.step(np.array([1, 1]))
    process = pool._workers[0].process
    envs.close()
    assert not process.is_alive()


def test_an_action_is_what_the_action_space_contains():
    """A whole number, numpy's too, or an integer array of no dimensions (as a policy's
    argmax gives it: Gymnasium's Discrete and ALE take it); anything else refused."""
    env, twin = SpaceInvadersEnv(obs_type="state"), SpaceInvadersEnv(obs_type="state")
    env.reset(seed=4)
    twin.reset(seed=4)
    for action in (np.array(2), np.int64(4), np.array(1, np.uint8), 3):
        assert np.array_equal(env.step(action)[0], twin.step(int(action))[0])
    for action in (np.array([2]), 2.0, 6, -1, np.array(7), "1"):
        with pytest.raises(ValueError, match="is not in Discrete"):
            env.step(action)


def test_bad_options_are_refused_in_one_line():
    for options in ({"obs_type": "ram"}, {"frameskip": 0}, {"frameskip": (4, 2)},
                    {"repeat_action_probability": 2.0}, {"render_mode": "window"},
                    {"repeat_action_probability": "0.2"}, {"max_num_frames_per_episode": 1.5},
                    {"resize": (84, 84, 3)}, {"stack": 0}, {"stack": 4, "obs_type": "state"},
                    {"mode": 1}, {"mode": "0"}, {"difficulty": 1}, {"difficulty": 0.0},
                    {"resize": 84, "obs_type": "grayscale"},
                    {"resize": "84", "obs_type": "grayscale"},
                    {"resize": (84.5, 84), "obs_type": "grayscale"},
                    {"resize": (True, 84), "obs_type": "grayscale"},
                    {"record": 123}, {"full_action_space": "yes"}, {"frameskip": True},
                    {"frameskip": (1, True)}, {"frameskip": (2, 2)}, {"stack": 65},
                    {"resize": (225, 84), "obs_type": "grayscale"}):
        with pytest.raises(ValueError, match=next(iter(options))):
            SpaceInvadersEnv(**options)
    with pytest.raises(ValueError, match="for ALE's RAM, 'state': the game's objects"):
        SpaceInvadersEnv(obs_type="ram")  # (ALE's RAM: training code may ask for it)


def test_an_env_spec_saved_as_json_makes_the_same_environment():
    """Gymnasium's `EnvSpec.to_json` (an experiment's config kept) turns the ranges into
    lists: made again from it, the environment plays the same episode."""
    env = gymnasium.make(ENV_ID, obs_type="grayscale", frameskip=(2, 5), resize=(84, 84),
                         stack=4, max_episode_steps=50)
    again = gymnasium.make(EnvSpec.from_json(env.spec.to_json()))
    assert again.spec.kwargs["frameskip"] == [2, 5]  # (as JSON gives it back)
    played = []
    for one in (env, again):
        observation, _ = one.reset(seed=5)
        frames, ended = [observation], False
        while not ended:
            observation, _, terminated, truncated, info = one.step(1 + len(frames) % 5)
            frames.append(observation)
            ended = terminated or truncated
        played.append((np.array(frames), info["episode_frame_number"],
                       one.unwrapped.world.state_hash()))
    assert np.array_equal(played[0][0], played[1][0]) and played[0][1:] == played[1][1:]
    assert len(played[0][0]) == 51 and 2 * 50 < played[0][1] < 4 * 50  # (2 to 4 a step)


def test_numpys_numbers_are_taken_where_ales_are_and_play_as_pythons():
    """ALE takes a numpy number for the sticky actions' probability and the frame limit
    (a sweep's values often are); the episode is the one the Python number gives."""
    played = []
    for sticky, limit in ((0.5, 400), (np.float32(0.5), np.int64(400)), (np.float16(0.5), 400)):
        env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=sticky,
                               max_num_frames_per_episode=limit)
        env.reset(seed=3)
        steps = 0
        while not env.step(steps % 6)[3]:
            steps += 1
        played.append((steps, env.unwrapped.world.state_hash()))
    assert played[0] == played[1] == played[2] and played[0][0] == 99  # (400 frames: 100 steps)
    assert type(SpaceInvadersEnv(repeat_action_probability=np.int64(0))
                .repeat_action_probability) is float


@pytest.mark.parametrize("cartridge", [{"mode": None, "difficulty": None},
                                       {"mode": 0, "difficulty": np.int64(0)}])
def test_ales_default_mode_and_difficulty_are_taken_and_play_the_one_game(cartridge):
    # (code written for ALE may pass them: the arcade game has no variations to choose)
    played = []
    for options in ({}, cartridge):
        env = gymnasium.make(ENV_ID, obs_type="state", **options)
        env.reset(seed=2)
        env.action_space.seed(2)
        rewards = [env.step(env.action_space.sample())[1] for _ in range(300)]
        played.append((rewards, env.unwrapped.world.state_hash()))
    assert played[0] == played[1] and sum(played[0][0]) > 0


def test_the_frame_number_counts_on_across_episodes_until_a_seeded_reset():
    """ALE's two counts: the episode's frames, and the frames since the game was loaded,
    which a reset goes on from and a seeded reset (a load, in ALE) starts again."""
    env = SpaceInvadersEnv(obs_type="state", max_num_frames_per_episode=40)
    counts = [env.reset(seed=1)[1]]
    counts += [env.step(0)[4] for _ in range(11)]  # (the last after the end: no frame)
    counts += [env.reset()[1], env.step(0)[4], env.reset(seed=2)[1]]
    assert [(info["episode_frame_number"], info["frame_number"]) for info in counts] == [
        *((4 * step, 4 * step) for step in range(11)), (40, 40), (0, 40), (4, 44), (0, 0)]


def test_an_episode_cut_short_is_truncated_not_terminated():
    """ALE's two limits: `gymnasium.make`'s max_episode_steps (its TimeLimit) and the
    environment's own max_num_frames_per_episode (frames, as ALE counts them: 40 are 10
    steps of 4)."""
    by_steps = gymnasium.make(ENV_ID, obs_type="state", max_episode_steps=10)
    by_frames = gymnasium.make(ENV_ID, obs_type="state", max_num_frames_per_episode=40)
    for env in (by_steps, by_frames):
        env.reset(seed=1)
        steps = [env.step(0) for _ in range(10)]
        assert [step[2:4] for step in steps] == [(False, False)] * 9 + [(False, True)]
        assert steps[-1][4]["episode_frame_number"] == 40


def test_a_step_stops_at_the_frame_limit_and_none_plays_past_it(tmp_path):
    """As ALE's: 6 frames at 4 a step end in the second step's second frame, a step after
    plays nothing (the world's tick stands), and the episode recorded holds the 6."""
    env = SpaceInvadersEnv(obs_type="state", max_num_frames_per_episode=6, record=tmp_path)
    env.reset(seed=5)
    ends = [env.step(1)[2:] for _ in range(3)]
    assert [(terminated, truncated, info["episode_frame_number"])
            for terminated, truncated, info in ends] == [(False, False, 4), (False, True, 6),
                                                        (False, True, 6)]
    assert env.world.tick == 6 and ends[-1][2]["events"] == ()
    [episode] = tmp_path.glob("*.json")
    assert load(episode).ticks == 6


def test_a_game_over_on_the_limits_frame_is_both_ends():
    """As ALE's (its game_over and game_truncated are apart): the same episode with its
    limit at the game's last frame ends terminated and truncated, one frame sooner only
    truncated."""
    def ends(limit):
        env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0,
                               max_num_frames_per_episode=limit)
        env.reset(seed=6)
        step = 0
        while True:
            _, _, terminated, truncated, info = env.step(step % 6)
            step += 1
            if terminated or truncated:
                return terminated, truncated, info["episode_frame_number"]

    _, _, last = ends(None)
    assert [ends(last), ends(last - 1)] == [(True, True, last), (False, True, last - 1)]


@pytest.mark.parametrize("limit", [None, 0, -5])
def test_no_frame_limit_where_ale_has_none(limit):
    """None, 0 or below: ALE plays on (its limit counts only above 0)."""
    env = SpaceInvadersEnv(obs_type="state", max_num_frames_per_episode=limit)
    env.reset(seed=5)
    steps = [env.step(0) for _ in range(30)]
    assert not any(truncated for _, _, _, truncated, _ in steps)
    assert steps[-1][4]["episode_frame_number"] == env.world.tick == 120


def test_gymnasiums_module_form_makes_it_in_a_process_that_never_imported_it():
    import subprocess
    import sys

    code = ('import gymnasium; env = gymnasium.make("invaders.env:invaders/SpaceInvaders-v0",'
            ' obs_type="state"); print(env.reset(seed=0)[0].shape, env.spec.id)')
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
    assert done.stdout.split() == [f"({STATE_SIZE},)", ENV_ID]


def test_without_gymnasium_the_package_says_which_extra_brings_it():
    import subprocess
    import sys

    code = 'import sys; sys.modules["gymnasium"] = None; import invaders.env'  # (not there)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False)
    assert done.returncode == 1
    assert done.stderr.splitlines()[-1] == (
        "ModuleNotFoundError: invaders.env needs Gymnasium, the rl extra: pip install "
        "'.[rl]'")


def test_human_rendering_shows_each_step_in_a_window_at_the_largest_scale_that_fits():
    """render_mode="human" (SDL's dummy driver here, its screen 1024x768): after each step
    the window holds the RGB picture of the world, every pixel a 2x2 square (3x3, 768 px
    tall, would not fit with a title bar and a task bar)."""
    pygame.display.quit()  # (from no display: the window's opens it, and quits it)
    env = gymnasium.make(ENV_ID, obs_type="state", render_mode="human")
    env.reset(seed=2)
    assert pygame.display.get_desktop_sizes()[0] == (1024, 768)
    for action in (1, 2, 2):
        env.step(action)
        assert np.array_equal(_shown(env)[1::2, 1::2],
                              _picture_in_the_window(env.unwrapped.world))
    assert env.unwrapped._window.window.size == (224 * 2, 256 * 2)
    env.close()
    assert not pygame.display.get_init()


def _shown(env) -> np.ndarray:
    """What an environment's window shows, as (rows, columns, RGB)."""
    surface = env.unwrapped._window.window.get_surface()
    return pygame.surfarray.array3d(surface).transpose(1, 0, 2)


def test_two_environments_shown_at_once_each_keep_a_window_of_their_own():
    """Each environment shown has its own window: closing one leaves the other showing its
    game (it stopped, 'video system not initialized'); the display is quit with the last,
    and one the program had open before stays open, its window as it was."""
    pygame.display.quit()
    for program_window in (False, True):
        if program_window:
            mine = pygame.display.set_mode((20, 10))
            mine.fill((1, 2, 3))
        envs = [gymnasium.make(ENV_ID, obs_type="state", render_mode="human")
                for _ in range(2)]
        for seed, env in enumerate(envs):
            env.reset(seed=seed)
        for action in (1, 4, 5):
            for env in envs:
                env.step(action)
        envs[0].close()
        for action in (2, 3):
            envs[1].step(action)
            assert np.array_equal(_shown(envs[1])[1::2, 1::2],
                                  _picture_in_the_window(envs[1].unwrapped.world))
        envs[1].close()
        assert pygame.display.get_init() is program_window
        if program_window:
            assert pygame.display.get_surface().get_at((0, 0)) == (1, 2, 3)
            pygame.display.quit()


def _without_a_display(code: str, driver: str | None = None) -> subprocess.CompletedProcess:
    """`code` run by Python in a process with no display (and SDL's driver as given)."""
    env = {key: value for key, value in os.environ.items()
           if key not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    if driver is not None:
        env["SDL_VIDEODRIVER"] = driver
    return subprocess.run([sys.executable, "-W", "always", "-c", code], capture_output=True,
                          text=True, check=True, env=env, timeout=120)


def test_human_rendering_with_a_driver_asked_for_that_cannot_open_says_so_at_reset():
    """An SDL driver asked for by name that cannot open: reset in human mode raises a
    pygame.error naming the mode and why."""
    code = ("import gymnasium, pygame, invaders.env\n"
            f"env = gymnasium.make({ENV_ID!r}, obs_type='state', render_mode='human')\n"
            "try:\n    env.reset(seed=0)\n"
            "except pygame.error as error:\n    print(error)")
    done = _without_a_display(code, "x11")
    assert done.stdout.startswith("render_mode 'human' shows a window, and cannot here")
    assert "x11 not available" in done.stdout


def test_without_a_display_human_rendering_warns_and_gymnasiums_checker_passes():
    """Without a display the window opens on the driver SDL falls back to, where it shows
    nowhere, as Gymnasium's own environments' and ALE's do: a warning says so, and
    Gymnasium's checker, which opens every render mode the metadata names, passes for each
    observation (reset raised a pygame.error there, and the checker with it)."""
    code = ("import gymnasium, invaders.env\n"
            "from gymnasium.utils.env_checker import check_env\n"
            "for obs_type in ('rgb', 'grayscale', 'state'):\n"
            f"    env = gymnasium.make({ENV_ID!r}, obs_type=obs_type)\n"
            "    check_env(env.unwrapped)\n"
            "    print('checked', obs_type)\n"
            f"env = gymnasium.make({ENV_ID!r}, obs_type='state', render_mode='human')\n"
            "env.reset(seed=0)\n"
            "print(env.step(1)[4]['episode_frame_number'])\n"
            "env.close()")
    done = _without_a_display(code)
    assert done.stdout.split() == ["checked", "rgb", "checked", "grayscale", "checked",
                                   "state", "4"]
    assert ("RuntimeWarning: render_mode 'human': no display: neither DISPLAY nor "
            "WAYLAND_DISPLAY is set: the window opens there and shows nowhere") in done.stderr


def test_the_window_shows_the_game_at_its_own_speed():
    """In the window each step takes its frames' time at 60 a second (the clock asked for
    60 / frames steps a second), as ALE's human mode runs at the game's speed; `render_fps`,
    which Gymnasium's play and video recorders read, is that speed in steps a second."""
    env = SpaceInvadersEnv(obs_type="state", render_mode="human", frameskip=(2, 5))
    env.reset(seed=2)
    asked, frames = [], []
    env._clock = types.SimpleNamespace(tick=asked.append)
    for _ in range(8):
        before = env.episode_frame_number
        env.step(0)
        frames.append(env.episode_frame_number - before)
    env.close()
    assert asked == [60 / n for n in frames] and set(frames) == {2, 3, 4}
    assert [SpaceInvadersEnv(frameskip=skip).metadata["render_fps"]
            for skip in (1, 4, (2, 5))] == [60, 15, 20]


def test_render_gives_the_rgb_picture_whatever_the_observation():
    env = SpaceInvadersEnv(obs_type="state", render_mode="rgb_array")
    _play(env, 6, 50)
    assert np.array_equal(env.render(), _picture_in_the_window(env.world))


@pytest.mark.parametrize("options", [{"obs_type": "rgb"}, {"obs_type": "grayscale"},
                                     {"obs_type": "state"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 4}],
                         ids=["rgb", "grayscale", "state", "grayscale-84x84x4"])
def test_what_the_environment_hands_out_is_never_written_again(options):
    """An agent keeps observations (a replay buffer), pictures rendered and screens read:
    each array handed out is the caller's, unchanged by the steps after it (the arrays the
    environment draws and keeps its observations in are its own)."""
    env = SpaceInvadersEnv(render_mode="rgb_array", **options)
    obs, _ = env.reset(seed=5)
    handed = [obs, env.render(), env.ale.getScreenRGB(), env.ale.getScreenGrayscale()]
    kept = [array.copy() for array in handed]
    for action in [1, 2, 2, 1, 3, 3, 1, 0] * 6:
        obs, *_ = env.step(action)
        handed += [obs, env.render(), env.ale.getScreenRGB(), env.ale.getScreenGrayscale()]
        kept += [array.copy() for array in handed[-4:]]
    assert not np.array_equal(handed[0], handed[-4])  # (the steps changed what is seen)
    assert all(np.array_equal(a, b) for a, b in zip(handed, kept, strict=True))
    assert len({id(array) for array in handed}) == len(handed)


def test_vector_environments_step_worlds_side_by_side():
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="sync", obs_type="state")
    obs, _ = envs.reset(seed=[7, 8])
    assert obs.shape == (2, 188) and np.array_equal(obs[0], obs[1])  # both at the start
    for _ in range(60):  # (the cannons wait a moment at the start)
        obs, rewards, _, _, infos = envs.step(np.array([3, 2]))  # left, right
    assert obs[0][0] < obs[1][0]  # the cannons went their own ways
    assert list(infos["lives"]) == list(obs[:, 186]) and rewards.shape == (2,)
    envs.close()


EPISODE = """
import hashlib, sys
import gymnasium
import invaders.env
env = gymnasium.make("invaders/SpaceInvaders-v0", obs_type="grayscale")
obs, _ = env.reset(seed=31)
digest = hashlib.sha256(obs.tobytes())
for i in range(300):
    obs, reward, terminated, truncated, info = env.step(i % 6)
    digest.update(obs.tobytes())
print(env.unwrapped.world.state_hash(), digest.hexdigest())
"""


def test_an_episode_is_the_same_in_other_processes_whatever_the_hash_seed():
    import os
    import subprocess
    import sys

    outputs = set()
    for hash_seed in ("0", "1", "12345"):
        env = {**os.environ, "PYTHONHASHSEED": hash_seed, "SDL_VIDEODRIVER": "dummy"}
        done = subprocess.run([sys.executable, "-c", EPISODE], env=env, capture_output=True,
                              text=True, check=True)
        outputs.add(done.stdout.strip())
    assert len(outputs) == 1 and len(next(iter(outputs)).split()) == 2


def test_async_vector_environments_and_gymnasiums_frame_stacking_work_on_it():
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="async", obs_type="state")
    obs, _ = envs.reset(seed=[7, 7])
    for _ in range(10):
        obs, *_ = envs.step(np.array([1, 1]))
    assert np.array_equal(obs[0], obs[1])  # the same seed and actions in two processes
    envs.close()
    stacked = gymnasium.wrappers.FrameStackObservation(
        gymnasium.make(ENV_ID, obs_type="grayscale"), stack_size=4)
    frames, _ = stacked.reset(seed=3)
    frames, *_ = stacked.step(2)
    assert frames.shape == (4, 256, 224) and np.array_equal(
        frames[-1], stacked.unwrapped.ale.getScreenGrayscale())


@pytest.mark.parametrize("obs_type", ["rgb", "grayscale"])
def test_gymnasiums_own_grey_resize_and_stack_wrappers_work_on_it(obs_type):
    """As Atari agents wrap ALE's environment: Gymnasium's GrayscaleObservation (for the
    RGB picture), ResizeObservation (OpenCV's area shrink, to 84x84) and
    FrameStackObservation (4). Each step's newest frame is the wrappers' own work on the
    picture the environment just drew, pixel for pixel, the older ones the steps before."""
    from gymnasium.wrappers import (
        FrameStackObservation,
        GrayscaleObservation,
        ResizeObservation,
    )

    env = gymnasium.make(ENV_ID, obs_type=obs_type)
    grey = GrayscaleObservation(env) if obs_type == "rgb" else env
    shrunk = ResizeObservation(grey, (84, 84))
    stacked = FrameStackObservation(shrunk, stack_size=4)
    assert stacked.observation_space.shape == (4, 84, 84)
    frames, _ = stacked.reset(seed=3)
    seen = []
    for action in (1, 2, 2, 3, 1, 0):
        frames, *_ = stacked.step(action)
        ale = env.unwrapped.ale  # (the picture of the state the step left)
        picture = ale.getScreenRGB() if obs_type == "rgb" else ale.getScreenGrayscale()
        newest = shrunk.observation(grey.observation(picture) if obs_type == "rgb" else picture)
        assert stacked.observation_space.contains(frames)
        assert np.array_equal(frames[-1], newest) and newest.max() > 0
        seen.append(newest)
    assert all(np.array_equal(a, b) for a, b in zip(frames, seen[-4:], strict=True))


def _area_average(picture: np.ndarray, height: int, width: int) -> np.ndarray:
    """The definition, pixel by pixel, in whole numbers: each output pixel the mean of the
    input area it covers, pixels cut by its edges weighted by the part inside, rounded half
    up. Lengths are counted in 1/height (1/width) of a pixel, so every overlap is whole."""
    h, w = picture.shape
    out = np.zeros((height, width), np.uint8)
    for i in range(height):
        for j in range(width):
            total = 0
            for y in range(i * h // height, -(-(i + 1) * h // height)):
                dy = min((i + 1) * h, (y + 1) * height) - max(i * h, y * height)
                for x in range(j * w // width, -(-(j + 1) * w // width)):
                    dx = min((j + 1) * w, (x + 1) * width) - max(j * w, x * width)
                    total += dy * dx * int(picture[y, x])
            out[i, j] = (2 * total + h * w) // (2 * h * w)
    return out


def test_grey_pictures_shrink_by_area_and_stack_in_order():
    env = SpaceInvadersEnv(obs_type="grayscale", resize=(84, 84), stack=4)
    full = SpaceInvadersEnv(obs_type="grayscale")
    assert env.observation_space.shape == (4, 84, 84)
    first, _ = env.reset(seed=9)
    full.reset(seed=9)
    assert all(np.array_equal(frame, first[0]) for frame in first)  # a reset fills it
    seen = [first[-1]]
    for action in (1, 2, 2, 3):
        stacked = env.step(action)[0]
        picture = full.step(action)[0]
        assert np.array_equal(stacked[-1], _area_average(picture, 84, 84))
        seen.append(stacked[-1])
    assert all(np.array_equal(a, b) for a, b in zip(stacked, seen[-4:], strict=True))
    assert stacked[-1].max() > 0 and not np.array_equal(stacked[-1], stacked[0])


def _in_lockstep(one, other, seed: int) -> tuple[int, np.ndarray]:
    """Two vectors of 3 games reset with one seed, then 210 steps of the same random
    actions, each step's observations, rewards, ends and infos equal: how many episodes
    were cut short, and the last observations."""
    first = [venv.reset(seed=seed) for venv in (one, other)]
    assert np.array_equal(first[0][0], first[1][0])
    rng = np.random.default_rng(seed)
    ends = 0
    for _ in range(210):
        obs, _, _, truncated, _ = _step_alike(one, other, rng.integers(0, 6, 3))
        ends += int(truncated.sum())
    return ends, obs


def _step_alike(one, other, actions: np.ndarray) -> tuple:
    """A step of two vectors with the same actions: their observations, rewards, ends
    and infos equal. The first one's step."""
    steps = [venv.step(actions) for venv in (one, other)]
    assert vector_answers_alike(*steps)
    return steps[0]


def _reset_alike(one, other, seed: int, which: np.ndarray) -> dict:
    """The games `which` names reset in two vectors: their observations and infos equal.
    The first one's infos."""
    resets = [venv.reset(seed=seed, options={"reset_mask": which.copy()})
              for venv in (one, other)]
    assert vector_answers_alike(*resets)
    return resets[0][1]


@pytest.mark.parametrize("options", [{"obs_type": "state"}, {"obs_type": "grayscale"},
                                     {"obs_type": "rgb"},
                                     {"obs_type": "grayscale", "resize": (84, 84)},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 2}],
                         ids=["state", "grayscale", "rgb", "grayscale-84x84",
                              "grayscale-84x84x2"])
def test_the_native_vector_environment_steps_as_gymnasiums_sync_one(options):
    """The same games step for step, across episode ends (NEXT_STEP autoreset: the step
    after an end resets that game)."""
    options = {**options, "max_num_frames_per_episode": 400}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", **options)
    assert type(native).__name__ == "SpaceInvadersVectorEnv"
    assert native.observation_space == sync.observation_space
    if "resize" in options:  # (the batch shrinks and stacks: its games draw full size)
        assert {env.observation_space.shape for env in native.envs} == {(SCREEN_H, SCREEN_W)}
    ends, _ = _in_lockstep(native, sync, 5)  # (every info: events, counters, seed)
    assert ends == 6  # each game cut at 400 frames, twice in 210 steps
    native.close()
    sync.close()


@pytest.mark.parametrize("workers", [1, 2])
def test_the_native_vectors_events_past_what_its_rows_keep_are_given_whole(workers):
    """A step of 1,000 frames firing has more events than a game's row keeps: they are
    spilled (on workers, sent by pipe) and the infos are still the sync vector's."""
    options = {"obs_type": "state", "frameskip": 1000}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", **options)
    for venv in (native, sync):
        venv.reset(seed=4)
    counts = []
    for actions in ([1, 4, 5], [5, 1, 4], [4, 5, 1], [1, 1, 1]):
        (*_, info), (*_, theirs) = native.step(np.array(actions)), sync.step(np.array(actions))
        assert infos_alike(info, theirs)
        counts += [len(events) for events in info["events"]]
    assert max(counts) > EVENTS_KEPT and min(counts) <= EVENTS_KEPT
    native.close()
    sync.close()


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("options", [{"obs_type": "state"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 2}],
                         ids=["state", "grayscale-84x84x2"])
def test_the_native_vector_resets_some_games_as_gymnasiums_sync_one(options, workers):
    """Gymnasium's partial reset (`options["reset_mask"]`): only the games named start
    anew, the others' observations stay (stacks too) and the infos are the reset games'
    alone; a game that ended and is not named still resets at the next step. The same
    as the sync vector's, step for step, across episode ends."""
    options = {**options, "max_num_frames_per_episode": 400}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", **options)
    with pytest.raises(RuntimeError, match="reset every game before some"):
        native.reset(options={"reset_mask": np.array([True, False, True])})
    for venv in (native, sync):
        venv.reset(seed=3)
    rng, partial, left = np.random.default_rng(3), 0, 0
    for step in range(260):
        _, _, terminated, truncated, _ = _step_alike(native, sync, rng.integers(0, 6, 3))
        ended = terminated | truncated
        if ended.any() or step % 37 == 36:  # (in turn, the ended games or the others)
            which = (ended if partial % 2 else ~ended) if ended.any() else rng.random(3) < 0.5
            which[step % 3] |= not which.any()
            left += int((ended & ~which).sum())  # (these reset at the next step)
            assert list(_reset_alike(native, sync, step, which)["_seed"]) == list(which)
            partial += 1
    assert partial >= 8 and left >= 2
    # (refused as Gymnasium's vectors refuse it, of 1.4: those of 1.1 asserted instead)
    for bad, error in ((np.array([1, 0, 1]), TypeError), ([True, False, True], TypeError),
                       (np.array([True, False]), ValueError), (np.zeros(3, bool), ValueError)):
        with pytest.raises(error, match="reset_mask"):
            native.reset(options={"reset_mask": bad})
    native.close()
    sync.close()


@pytest.mark.parametrize("workers", [1, 2])
def test_the_native_vector_without_autoreset_plays_as_gymnasiums_sync_one(workers):
    """`autoreset_mode` DISABLED: an ended game waits for the caller to reset it (by
    `reset_mask`, as Gymnasium's documentation loops); stepped before that, refused. The
    same as the sync vector's, step for step, across episode ends. A mode that is none of
    Gymnasium's is refused naming the option."""
    options = {"obs_type": "grayscale", "resize": (84, 84), "stack": 2,
               "max_num_frames_per_episode": 300}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, autoreset_mode="Disabled", **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync",
                              vector_kwargs={"autoreset_mode": AutoresetMode.DISABLED}, **options)
    assert native.metadata["autoreset_mode"] is AutoresetMode.DISABLED
    for venv in (native, sync):
        venv.reset(seed=6)
    rng, resets = np.random.default_rng(6), 0
    for step in range(200):
        _, _, terminated, truncated, _ = _step_alike(native, sync, rng.integers(0, 6, 3))
        ended = terminated | truncated
        if ended.any():
            with pytest.raises(RuntimeError, match=r"ended: reset them"):
                native.step(np.zeros(3, np.int64))
            _reset_alike(native, sync, step, ended)
            resets += 1
    assert resets >= 2
    native.close()
    sync.close()
    for mode in ("next step", 1, None):
        with pytest.raises(ValueError, match="autoreset_mode"):
            gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                               obs_type="state", autoreset_mode=mode)


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("options", [{"obs_type": "state"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 2}],
                         ids=["state", "grayscale-84x84x2"])
def test_the_native_vector_resetting_within_the_step_plays_as_gymnasiums_sync_one(
        options, workers):
    """`autoreset_mode` SAME_STEP: a game whose episode ends resets within the step (its
    observation and info the new episode's first), its last observation and info in the
    step's `final_obs` and `final_info`, its reward and ends the step's. The same as the
    sync vector's, step for step, across episode ends (ended by the limit or at game
    over, some games at once: seed 3 makes each of those, the last assert holds it)."""
    options = {**options, "frameskip": 30, "max_num_frames_per_episode": 2400}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, autoreset_mode=AutoresetMode.SAME_STEP,
                                **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync",
                              vector_kwargs={"autoreset_mode": "SameStep"}, **options)
    assert native.metadata["autoreset_mode"] is AutoresetMode.SAME_STEP
    for venv in (native, sync):
        venv.reset(seed=3)
    rng, finals, game_overs, at_once = np.random.default_rng(3), 0, 0, 0
    for step in range(240):
        if step == 30:  # (one game's episodes out of step with the others')
            _reset_alike(native, sync, 3, np.array([False, True, False]))
        obs, _, terminated, truncated, info = _step_alike(native, sync, rng.integers(0, 6, 3))
        ended = terminated | truncated
        game_overs, at_once = game_overs + terminated.sum(), at_once + (ended.sum() > 1)
        assert ("final_obs" in info) == ended.any()
        if ended.any():
            assert list(info["_final_obs"]) == list(ended) == list(info["_final_info"])
            for i in np.flatnonzero(ended):  # (the new episode's first, and the last)
                assert info["episode_frame_number"][i] == 0
                assert info["final_info"]["episode_frame_number"][i] > 0
                assert not np.array_equal(info["final_obs"][i], obs[i])
            finals += int(ended.sum())
    assert finals >= 5 and game_overs >= 1 and at_once >= 1
    native.close()
    sync.close()


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("mode", list(AutoresetMode), ids=lambda mode: mode.value)
def test_the_native_vector_cuts_episodes_at_max_episode_steps_as_gymnasiums_sync_one(
        mode, workers):
    """`max_episode_steps`, which Gymnasium's `make_vec` hands a vector entry point (its
    sync vector wraps each game in `TimeLimit`): a game's episode is truncated at that
    many steps since its reset, whole or partial, in each autoreset mode; the same as
    the sync vector's step for step, beside episodes the frame limit ends first (frame
    skips drawn from 2 to 6). -1 or None is no limit; others are refused as `TimeLimit`
    refuses them."""
    options = {"obs_type": "state", "frameskip": (2, 7), "max_num_frames_per_episode": 148,
               "max_episode_steps": 37}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, autoreset_mode=mode, **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync",
                              vector_kwargs={"autoreset_mode": mode}, **options)
    for venv in (native, sync):
        venv.reset(seed=9)
    rng, by_steps, by_frames = np.random.default_rng(9), 0, 0
    for step in range(160):
        if step == 20:  # (one game's count out of step with the others')
            _reset_alike(native, sync, 9, np.array([False, True, False]))
        _, _, _, truncated, info = _step_alike(native, sync, rng.integers(0, 6, 3))
        frames = info.get("final_info", info)["episode_frame_number"][truncated]
        by_steps += int((frames < 148).sum())
        by_frames += int((frames == 148).sum())
        if mode is AutoresetMode.DISABLED and truncated.any():
            _reset_alike(native, sync, step, truncated)
    assert by_steps >= 3 and by_frames >= 3
    native.close()
    sync.close()
    unlimited = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                                   obs_type="state", max_episode_steps=-1)
    unlimited.reset(seed=1)
    assert not any(unlimited.step(np.zeros(2, np.int64))[3].any() for _ in range(40))
    for limit, error in ((0, ValueError), (2.5, TypeError), ("37", TypeError)):
        with pytest.raises(error, match="max_episode_steps"):
            gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                               obs_type="state", max_episode_steps=limit)


@pytest.mark.parametrize("workers", [1, 2])
def test_the_native_vectors_games_are_called_and_set_as_in_gymnasiums_sync_one(workers):
    """`call`, `get_attr` and `set_attr`, as Gymnasium's vectors have them: the games'
    answers in order (on workers pickled, a whole world's each), a value for each game
    or one for all; refused, naming why, with the wrong count of values or with a value
    that cannot go to a worker, and the batch plays on."""
    options = {"obs_type": "state", "full_action_space": True}
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, **options)
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", **options)
    for venv in (native, sync):
        venv.reset(seed=12)
    _step_alike(native, sync, np.array([1, 4, 17]))
    for venv in (native, sync):
        venv.set_attr("tag", ["a", "b", "c"])
    assert native.get_attr("tag") == sync.get_attr("tag") == ("a", "b", "c")
    assert native.call("get_action_meanings") == sync.call("get_action_meanings")
    assert len(native.call("get_action_meanings")[2]) == 18
    assert native.get_attr("lives") == sync.get_attr("lives")
    hashes = [[world.state_hash() for world in venv.get_attr("world")] for venv in (native, sync)]
    assert hashes[0] == hashes[1] and len(set(hashes[0])) == 3
    native.set_attr("tag", 7)
    assert native.get_attr("tag") == (7, 7, 7)
    with pytest.raises(ValueError, match="2 values for 3 games"):
        native.set_attr("tag", [1, 2])
    if workers > 1:
        with pytest.raises(pickle.PicklingError, match=r"set_attr: .* cannot be pickled"):
            native.set_attr("tag", [1, 2, lambda: 3])  # (the third game's is on a worker)
        big, done = np.arange(300_000), []  # (each way larger than a pipe holds)
        worker = threading.Thread(daemon=True, target=lambda: done.append(
            native.set_attr("tag", big) or native.get_attr("tag")))
        worker.start()
        worker.join(timeout=60)
        assert done, "a large value waited on a worker"
        assert all(np.array_equal(tag, big) for tag in done[0]) and len(done[0]) == 3
    _step_alike(native, sync, np.array([5, 0, 3]))
    native.close()
    sync.close()


@pytest.mark.parametrize("workers", [1, 2])
def test_the_native_vectors_seeds_and_generators_are_its_games_as_in_gymnasiums_sync_one(
        workers):
    """`np_random_seed` and `np_random` are the games' own, as Gymnasium's vectors give
    them (its tests ask for `seed + i` after a reset with an int seed, kept by a reset
    with none): before a reset each game's drawn, then those reset give, partly too."""
    native = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                                workers=workers, obs_type="state")
    sync = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", obs_type="state")
    assert len(set(native.np_random_seed)) == 3
    for venv in (native, sync):
        venv.reset(seed=42)
    assert native.np_random_seed == sync.np_random_seed == (42, 43, 44)
    _step_alike(native, sync, np.array([1, 2, 3]))
    for venv in (native, sync):
        venv.reset()
    assert native.np_random_seed == sync.np_random_seed == (42, 43, 44)
    _reset_alike(native, sync, 7, np.array([False, True, False]))
    assert native.np_random_seed == sync.np_random_seed == (42, 8, 44)
    draws = [[generator.integers(2**62) for generator in venv.np_random]
             for venv in (native, sync)]
    assert draws[0] == draws[1] and len(set(draws[0])) == 3
    native.close()
    sync.close()


@pytest.mark.parametrize("options", [{"obs_type": "state"},
                                     {"obs_type": "state", "context": "spawn"},
                                     {"obs_type": "grayscale", "resize": (84, 84), "stack": 2}],
                         ids=["state", "state-spawned", "grayscale-84x84x2"])
def test_the_native_vector_on_worker_processes_steps_as_in_one_process(options):
    """The same games step for step, across episode ends, whether in this process or
    shared among workers (the observations, rewards and ends through shared memory)."""
    options = {**options, "max_num_frames_per_episode": 400}
    here = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                              **options)
    apart = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point",
                               workers=2, **options)
    ends, last = _in_lockstep(here, apart, 11)
    assert ends == 6 and last.max() > 0  # each game cut at 400 frames, twice in 210 steps
    here.close()
    apart.close()
    with pytest.raises(AttributeError):
        apart.unwrapped.envs  # noqa: B018  (the games are not in this process)


@pytest.mark.forks
def test_a_workers_spill_of_any_size_arrives_without_a_wait(monkeypatch, alone):
    """A worker sends its spilled events after its answer: a message larger than a pipe
    holds (here 300,000 events a game, as a step of millions of frames might have) would
    otherwise wait for a caller that waits for the answer. Forked workers have the
    patched count of events; the step must come back, every event given."""
    huge = [Event.SHOT_FIRED] * 300_000
    monkeypatch.setattr("invaders.env.games.step_events",
                        lambda reports: huge if reports else [])
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                              workers=2, context="fork", obs_type="state")
    envs.reset(seed=1)
    done: list = []
    stepper = threading.Thread(target=lambda: done.append(envs.step(np.array([1, 1]))),
                               daemon=True)
    stepper.start()
    stepper.join(timeout=60)
    assert done, "the step waited on a worker's spill"
    assert [len(events) for events in done[0][4]["events"]] == [300_000, 300_000]
    envs.close()


def test_a_workers_failure_is_raised_in_the_caller_and_bad_steps_and_counts_refused():
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                              workers=2, obs_type="state")
    with pytest.raises(RuntimeError, match=r"a games worker failed: .*[Ss]eed"):
        envs.reset(seed=[1, -1])  # (the second worker's game refuses a negative seed)
    envs.close()
    for workers in (1, 2):  # (as the single environment: a RuntimeError, not a game's)
        envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                                  obs_type="state", workers=workers)
        with pytest.raises(RuntimeError, match=r"call reset\(\) before step\(\)"):
            envs.step(np.array([0, 0]))
        envs.close()
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                              obs_type="state")
    envs.reset(seed=0)
    for actions in ([0, 6], [-1, 0], [0.0, 1.0], [True, False], [0, 1, 2], [[0, 1]]):
        with pytest.raises(ValueError, match="are not in"):
            envs.step(np.array(actions))
    envs.close()
    for bad in ({"workers": 0}, {"workers": 3}, {"workers": 2, "render_mode": "rgb_array"}):
        with pytest.raises(ValueError, match=r"workers|render_mode"):
            gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                               obs_type="state", **bad)
    # One refused closes quietly (Gymnasium 1.1 closes every vector dropped, made or not).
    SpaceInvadersVectorEnv.__new__(SpaceInvadersVectorEnv).close()


@pytest.mark.parametrize(("mode", "options", "refuses"), [
    ("async", {}, True), ("vector_entry_point", {"workers": 2}, True),
    ("sync", {}, False), ("vector_entry_point", {}, False)])
def test_a_closed_batch_goes_on_as_gymnasiums_vector_of_its_kind(mode, options, refuses):
    """Closed, a batch on workers refuses to step or reset with Gymnasium's
    ClosedEnvironmentError, as Gymnasium's async vector (its workers have ended too; they
    raised a zip's ValueError and a claim of an interrupted step); one in a single process
    plays on, as Gymnasium's sync vector does."""
    envs = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode=mode, obs_type="state",
                              **options)
    envs.reset(seed=0)
    envs.close()
    for step in (True, False):
        if refuses:
            with pytest.raises(gymnasium.error.ClosedEnvironmentError):
                envs.step(np.array([1, 1])) if step else envs.reset(seed=1)
        else:
            went = envs.step(np.array([1, 1])) if step else envs.reset(seed=1)
            assert went[0].shape == (2, STATE_SIZE)


def test_the_batch_is_watched_through_gymnasiums_wrapper_not_a_window_of_its_own():
    """A vector environment should not draw a window itself (Gymnasium's own tests say
    so): the native batch refuses render_mode 'human', saying how to watch it (it showed
    its games' first pictures, then never another); made with 'rgb_array', Gymnasium's
    HumanRendering shows its game's picture after each step, at the pace the batch gives
    (`render_fps`: the wrapper refused a batch without it)."""
    with pytest.raises(ValueError, match=r"render_mode 'human'.*HumanRendering"):
        gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point",
                           obs_type="state", render_mode="human")
    batch = gymnasium.make_vec(ENV_ID, num_envs=1, vectorization_mode="vector_entry_point",
                               obs_type="state", render_mode="rgb_array", frameskip=3)
    watched = HumanRendering(batch)
    watched.reset(seed=4)
    for action in (1, 2, 2):
        watched.step(np.array([action]))
        shown = pygame.surfarray.array3d(pygame.display.get_surface()).transpose(1, 0, 2)
        assert np.array_equal(shown, _picture_in_the_window(batch.envs[0].world))
    assert watched.metadata["render_fps"] == 20  # (60 frames a second, 3 a step)
    watched.close()


def test_the_reward_is_the_points_scored_across_the_counters_wrap_at_10000():
    env = SpaceInvadersEnv(obs_type="state", repeat_action_probability=0.0, frameskip=1)
    env.reset(seed=0)
    world = env.world
    world.score = 9990

    class Scoring:  # the world, scoring 30 points on its frame, as a top-row alien gives
        def __getattr__(self, name):
            return getattr(world, name)

        def step(self, bits):
            world.add_score(30)
            return world.step(bits)

    env.world = Scoring()
    _, reward, *_ = env.step(0)
    assert world.score == 20 and reward == 30.0


SIZES = [(84, 84), (224, 224), (1, 1), (7, 200), (210, 13), (83, 97), (160, 160), (56, 28)]


def _canvases(seed: int) -> list[np.ndarray]:
    """Grey canvases as the picture draws them (a lit byte 255, any other 0): sparse and
    dense random ones, every pixel lit (the largest sums there are: the exactness's bound)
    and one whose every 8 pixels of a row are another set lit, all 256 of them in turn."""
    rng = np.random.default_rng(seed)
    sets = (np.arange(256 * 28).reshape(256, 28) * 29 + seed) % 256
    every = np.unpackbits(sets.astype(np.uint8)[:, :, None], axis=2).reshape(256, 224)
    return [255 * (rng.random((256, 224)) < 0.05).astype(np.uint8),
            255 * (rng.random((256, 224)) < 0.5).astype(np.uint8),
            np.full((256, 224), 255, np.uint8), 255 * every]


def _tinted(canvas: np.ndarray) -> np.ndarray:
    """The grey picture a canvas shows under the cabinet's gel."""
    from invaders.env.observations import gel_array

    return np.minimum(canvas, gel_array(grayscale=True))


@pytest.mark.parametrize("size", SIZES)
def test_the_shrink_is_the_exact_area_average_of_the_picture_drawn(size):
    """Pixel for pixel against the definition, the canvas tinted by the gel, whether the
    table makes the columns' outputs (widths a multiple of 28) or products do."""
    from invaders.env.shrink import Shrink

    shrink = Shrink(size)
    assert (shrink.cols is None) == (size[1] % 28 == 0)
    for canvas in _canvases(sum(size)):
        shrink.read(canvas)
        assert np.array_equal(shrink.shrink()[0], _area_average(_tinted(canvas), *size))


@pytest.mark.parametrize("size", SIZES)
def test_games_shrunk_together_are_each_the_exact_area_average_of_its_picture(size):
    from invaders.env.shrink import Shrink

    canvases = [np.zeros((256, 224), np.uint8), *_canvases(sum(size))]
    shrink = Shrink(size, games=len(canvases))  # (products of several games, and of one)
    for game, canvas in enumerate(canvases):
        shrink.read(canvas, game)
    small = shrink.shrink()
    for game, canvas in enumerate(canvases):
        assert np.array_equal(small[game], _area_average(_tinted(canvas), *size))


def _overlaps(size_in: int, size_out: int) -> np.ndarray:
    """(size_out, size_in): how much of input j output i covers, in 1/size_out of a pixel
    (the definition's lengths, as `_area_average` counts them)."""
    i, j = np.arange(size_out)[:, None], np.arange(size_in)[None, :]
    return np.maximum(np.minimum((i + 1) * size_in, (j + 1) * size_out)
                      - np.maximum(i * size_in, j * size_out), 0).astype(np.int64)


def _area_average_at_once(picture: np.ndarray, height: int, width: int) -> np.ndarray:
    """`_area_average` as two products of whole numbers (fast enough for many sizes)."""
    h, w = picture.shape
    total = _overlaps(h, height) @ picture.astype(np.int64) @ _overlaps(w, width).T
    return ((2 * total + h * w) // (2 * h * w)).astype(np.uint8)


def test_the_area_average_at_once_is_the_definitions():
    picture = _tinted(_canvases(5)[1])
    for size in [(84, 84), (7, 200), (83, 97)]:
        assert np.array_equal(_area_average_at_once(picture, *size),
                              _area_average(picture, *size))


@given(height=st.integers(1, 256),
       width=st.one_of(st.sampled_from([28 * k for k in range(1, 9)]), st.integers(1, 224)),
       games=st.integers(1, 3), seed=st.integers(0, 2**32 - 1),
       lit=st.sampled_from([0.0, 0.03, 0.5, 0.97, 1.0]))
def test_any_size_of_any_games_shrinks_to_the_exact_area_average(height, width, games,
                                                                 seed, lit):
    """Every size the option takes, the widths whose columns the table makes (each number
    of outputs a group of 8 pixels, padded to 1, 2, 4 or 8) among them."""
    from invaders.env.shrink import Shrink

    rng = np.random.default_rng(seed)
    canvases = [255 * (rng.random((256, 224)) < lit).astype(np.uint8) for _ in range(games)]
    shrink = Shrink((height, width), games)
    for game, canvas in enumerate(canvases):
        shrink.read(canvas, game)
    small = shrink.shrink()
    for game, canvas in enumerate(canvases):
        assert np.array_equal(small[game],
                              _area_average_at_once(_tinted(canvas), height, width))


@pytest.mark.parametrize("size", SIZES)
def test_the_shrinks_table_entries_are_a_power_of_two_floats_and_its_pads_zeros(size):
    """What the shrink's speed stands on (numpy's lookup copies an item of 4, 8, 16 or 32
    bytes as one number, any other size by a call): every entry of its table is one of
    those sizes, its outputs first and then zeros, which the output leaves out (the
    tests above hold the outputs exact)."""
    from invaders.env.shrink import Shrink

    shrink = Shrink(size)
    assert shrink.table.dtype.itemsize in (4, 8, 16, 32)
    floats = shrink.table.view(np.float32).reshape(len(shrink.table), -1)
    per_group = 8 * size[1] // 224 if shrink.cols is None else 8
    assert floats.shape[1] == 1 << (per_group - 1).bit_length()
    assert not floats[:, per_group:].any()
    assert floats[:, :per_group].any()


@pytest.mark.parametrize(("size", "games"), [((84, 84), 1), ((84, 84), 8), ((83, 97), 2)])
def test_the_shrink_allocates_no_array_a_step(size, games):
    """Read and shrunk in the arrays it keeps (the docstring's "nothing allocated"): what
    Python traces while it works stays under the smallest array it handles, the 84x84
    output of one game (7,056 bytes), so neither its lookup nor a product made a copy."""
    import tracemalloc

    from invaders.env.shrink import Shrink

    shrink = Shrink(size, games)
    canvas = _canvases(1)[1]
    shrink.read(canvas)
    shrink.shrink()  # (numpy's first calls may cache what they need)
    tracemalloc.start()
    try:
        for game in range(games):
            shrink.read(canvas, game)
        shrink.shrink()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4096


def test_each_8_pixels_are_read_as_a_number_of_their_own_for_which_are_lit():
    """The 256 sets of 8 pixels lit give 256 numbers from 0 to 255, one a set, wherever
    they stand in a row (the table's entries are found by them)."""
    from invaders.env.shrink import read_groups

    sets = np.unpackbits(np.arange(256, dtype=np.uint8)[:, None], axis=1)  # (256, 8)
    canvas = 255 * np.tile(sets, (1, 28))
    numbers = read_groups(canvas, np.zeros((256, 28), np.uint64))
    assert (numbers == numbers[:, :1]).all()
    assert sorted(numbers[:, 0].tolist()) == list(range(256))


@pytest.mark.parametrize("games", [1, 8])
@pytest.mark.parametrize("size", SIZES)
def test_each_product_of_the_shrink_stays_on_one_blas_thread_and_the_blocks_cover_it(
        size, games):
    """The invariant the blocked shrink keeps: no product passes the work under which
    OpenBLAS stays on the calling thread (a product of the rows' is one for each period of
    each game), each reads and writes the shrink's own arrays (no copy), and each axis's
    blocks, put back together, are a period's whole weights (each output once, none of its
    weights left out), the periods covering the picture."""
    from invaders.env.shrink import BLOCK_WORK, Shrink, area_weights

    shrink = Shrink(size, games)
    for weights, inputs, outputs in shrink.row_products:
        assert weights.shape[0] * weights.shape[1] * inputs.shape[-1] <= BLOCK_WORK
        assert np.shares_memory(inputs, shrink._narrow)
        assert np.shares_memory(outputs, shrink._small)
    for weights, inputs, outputs in shrink.column_products:
        assert inputs.shape[0] * weights.shape[0] * weights.shape[1] <= BLOCK_WORK
        assert np.shares_memory(inputs, shrink._read)
        assert np.shares_memory(outputs, shrink._narrow)
    axes = [(shrink.rows, 256, size[0])]
    if shrink.cols is not None:
        axes.append((shrink.cols, 224, size[1]))
    for axis, size_in, size_out in axes:
        assert axis.periods * axis.period_in == size_in
        assert axis.periods * axis.period_out == size_out
        weights = area_weights(axis.period_in, axis.period_out)
        rebuilt = np.zeros_like(weights)
        for outputs, span, part in axis.blocks:
            rebuilt[outputs, span] += part
        assert np.array_equal(rebuilt, weights)  # (a block twice would count twice)


def test_the_speed_tables_batch_row_judges_the_first_against_the_second(capsys):
    """Contenders timed by stand-ins (seconds for k steps, fixed): the goal judged on the
    first two, a third reported beside them, the first's ratio to it, without a goal."""
    from invaders.env.speed import _batch_row

    runs = {"ours": lambda k: k / 3000, "theirs": lambda k: k / 1000,
            "another": lambda k: k / 500}
    assert _batch_row("2 games:", runs, 2, 3, goal=2.0) == 0
    assert _batch_row("2 games:", runs, 2, 3, goal=4.0) == 1
    first, other, second, _ = capsys.readouterr().out.splitlines()
    assert "ours   6,000 steps/s (6,000..6,000)   theirs   2,000 steps/s" in first
    assert first.endswith("3.00x (3.00..3.00)   goal >= 2x: met")
    assert second.endswith("3.00x (3.00..3.00)   goal >= 4x: NOT met")
    assert other.endswith(
        "another   1,000 steps/s (1,000..1,000)   ours/this 6.00x (6.00..6.00)")


def test_a_ratio_just_under_its_goal_never_reads_as_on_it():
    """Cut to two places, not rounded: 4.996 of a goal of 5 reads 4.99 (rounded, it read
    5.00 beside NOT met); the median judged is the ratio itself."""
    from invaders.env.speed import _ratios

    median, said = _ratios([4.996, 5.2, 4.9949], [1.0, 1.0, 1.0])
    assert median == 4.996 and said == "4.99x (4.99..5.20)"
    assert _ratios([1.5], [1.0])[1] == "1.50x (1.50..1.50)"


@pytest.mark.parametrize("per_group", [3, 5, 6, 7])
def test_the_shrinks_pads_are_dropped_and_every_other_byte_kept_as_it_is(per_group):
    """What the shrink's last copy stands on where there are pads: SDL's blit from RGBX
    pixels to RGB ones keeps each of the first three bytes as it is (84 wide: three
    outputs and a pad a group), numpy's take the others. Random bytes, pads and all, come
    out as the kept places of each group."""
    from invaders.env.shrink import GROUPS, _pads_dropped

    padded = 1 << (per_group - 1).bit_length()
    rng = np.random.default_rng(per_group)
    with_pads = rng.integers(0, 256, (3, 5, GROUPS * padded), dtype=np.uint8)
    out = np.zeros((3, 5, GROUPS * per_group), np.uint8)
    _pads_dropped(with_pads, out, per_group, padded)()
    kept = with_pads.reshape(3, 5, GROUPS, padded)[..., :per_group].reshape(out.shape)
    assert np.array_equal(out, kept)
