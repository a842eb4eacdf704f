"""Space Invaders (the 1978 arcade game) as a Gymnasium environment, with ALE's conventions.

An agent's code written for `ALE/SpaceInvaders-v5` runs unchanged: the same six actions in
the same order (18 with `full_action_space`, or ALE's stick with `continuous`: stick.py),
frame skip 4 and sticky actions at 0.25 by default, reward the score gained, `terminated`
at game over, `truncated` at the frame limit, `info` with `lives`, `episode_frame_number`
and `frame_number`. What ALE does not give:
the step's events and collision counters in `info`, a state observation of the game's
objects, and every episode written as a replay that `invaders replay` checks.
"""

from __future__ import annotations

import copy
import functools
import numbers
import random
from collections.abc import Iterable
from dataclasses import dataclass
from math import inf
from operator import add
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pygame
from gymnasium import spaces

from invaders.engine.stats import STAT_FIELDS
from invaders.env.ale_view import MINIMAL_SET, AleAction, AleView
from invaders.env.observations import (
    STATE_HIGH,
    STATE_SIZE,
    PixelObserver,
    Stack,
    StateObserver,
)
from invaders.env.recording import EpisodeRecorder, EpisodeRecording
from invaders.env.shrink import Shrink
from invaders.env.stick import check_stick, stick_meaning, stick_space
from invaders.env.window import EnvWindow
from invaders.game.actions import Action
from invaders.game.config import DEFAULT_CONFIG, SCREEN_H, SCREEN_W
from invaders.game.events import Event
from invaders.game.world import SCORE_WRAP, Phase, TickReport, World

GAME_OVER = Phase.GAME_OVER

NOOP, FIRE = 0, int(Action.FIRE)
LEFT, RIGHT = int(Action.LEFT), int(Action.RIGHT)
MINIMAL_MEANINGS = tuple(action.name for action in MINIMAL_SET)
# ALE's full set: up and down do nothing in this game.
FULL_MEANINGS = tuple(action.name for action in AleAction)
# ALE's keys for human play: w a s d to move, space to fire, e for NOOP (in this order in
# a combination, as ALE's: up or down, left or right, fire).
KEYS = {"UP": "w", "DOWN": "s", "LEFT": "a", "RIGHT": "d", "FIRE": " "}
OBS_TYPES = ("rgb", "grayscale", "state")
NO_COUNTS = (0,) * len(STAT_FIELDS)
MAX_FRAMES = 108_000  # ALE v5's frames an episode (30 minutes at 60 Hz): then truncated


def _bits(meaning: str) -> int:
    return (FIRE if "FIRE" in meaning else 0) | (RIGHT if "RIGHT" in meaning else 0) | (
        LEFT if "LEFT" in meaning else 0)


# ALE's minimal set for Space Invaders, in ALE's order, as our input bits.
MINIMAL_ACTIONS = tuple(map(_bits, MINIMAL_MEANINGS))


def step_events(reports: list[TickReport]) -> list[Event]:
    """A step's events, its frames' in order (`info["events"]` names them)."""
    return [event for report in reports for event in report.events]


def step_counters(reports: list[TickReport]) -> list[int]:
    """A step's collision counters, its frames' summed (all 0 for no frame), in the order
    of `CollisionStats`' fields (`info["collisions"]`)."""
    totals: Iterable[int] = NO_COUNTS
    for report in reports:  # (added field by field: 1.2 times as fast as summing columns)
        totals = map(add, totals, report.stats)
    return list(totals)


@dataclass(frozen=True, eq=False)  # (compared as objects: a world has no equality)
class EnvState:
    """An episode as it stood, from `clone_state`, to go back to with `restore_state`: its
    world, the last frame's input (sticky actions repeat it), the frame counts, the frames
    stacked, the recording so far, and (if asked for) the generator of sticky actions and
    frame skips. Nothing in it changes: its world may be the environment's until the
    environment plays a frame, which it plays on a copy; restored again, it plays the same
    again."""
    world: World
    previous: int
    episode_frames: int
    frame_number: int
    stacked: np.ndarray | None
    recording: EpisodeRecording | None  # (with record: the episode's so far)
    draws: tuple | None  # (random.Random's state, with include_rng)


class SpaceInvadersEnv(gym.Env):
    """One game a episode, from its first wave to game over; see the module docstring."""

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 60}  # noqa: RUF012 (Gymnasium's)

    def __init__(self, obs_type: str = "rgb", frameskip: int | tuple[int, int] = 4,
                 repeat_action_probability: float = 0.25, full_action_space: bool = False,
                 max_num_frames_per_episode: int | None = MAX_FRAMES,
                 render_mode: str | None = None,
                 record: str | Path | None = None, resize: tuple[int, int] | None = None,
                 stack: int = 1, mode: int | None = None, difficulty: int | None = None,
                 continuous: bool = False, continuous_action_threshold: float = 0.5,
                 sound_obs: bool = False) -> None:
        _check_options(obs_type, frameskip, repeat_action_probability, full_action_space,
                       render_mode, resize, stack, max_num_frames_per_episode)
        _check_cartridge(mode, difficulty)
        check_stick(continuous, continuous_action_threshold, sound_obs)
        if isinstance(frameskip, list):  # (a range read from a config file, JSON's say)
            frameskip = (frameskip[0], frameskip[1])
        self.obs_type, self.frameskip = obs_type, frameskip
        # (Python's numbers, whatever number type was given: a frame compares with it)
        self.repeat_action_probability = float(repeat_action_probability)
        if max_num_frames_per_episode is not None:
            max_num_frames_per_episode = int(max_num_frames_per_episode)
        self.max_num_frames_per_episode = max_num_frames_per_episode
        # The frames an episode may last (as ALE's: None, 0 or below is no limit).
        self.frame_limit = max_num_frames_per_episode if (
            max_num_frames_per_episode is not None and max_num_frames_per_episode > 0) else inf
        self.render_mode = render_mode
        # (what Gymnasium's play and video recorders read: steps a second at the game's speed)
        self.metadata = {**self.metadata, "render_fps": _steps_a_second(frameskip)}
        # (as ALE's: a stick's action plays as one of the full set, whose meanings it gives)
        meanings = FULL_MEANINGS if full_action_space or continuous else MINIMAL_MEANINGS
        self._meanings = meanings
        self._actions = tuple(_bits(m) for m in meanings)
        self.continuous = bool(continuous)
        # (kept as given, as ALE's keeps it: a stick is then compared with it as ALE's is)
        self.continuous_action_threshold = continuous_action_threshold
        self.action_space: spaces.Space = (stick_space() if continuous
                                           else spaces.Discrete(len(meanings)))
        self._shrink = Shrink(resize) if resize is not None else None
        shape = resize or (SCREEN_H, SCREEN_W)
        self._stack = Stack(stack, (*shape, 3) if obs_type == "rgb" else shape) if (
            stack > 1) else None
        self.observation_space = _space(obs_type, shape, stack)
        # The observation is the picture as drawn and tinted: neither shrunk nor stacked.
        self._picture_alone = obs_type != "state" and resize is None and stack == 1
        self._state = StateObserver()
        self._shown: PixelObserver | None = None  # for render(), when observations are not RGB
        self._window: EnvWindow | None = None  # the human render's
        self._recorder = EpisodeRecorder.into(record)
        if self._recorder is not None:
            self._recorder.watch(self)
        self.frame_number = 0
        self.world: World | None = None
        # Whether the world is a state's too (`clone_state`, `restore_state`): it is then
        # copied before a frame is played on it, so the state stays as it was.
        self._shared = False

    def __getstate__(self) -> dict[str, Any]:
        """Copied or pickled without its window (a copy that shows the game opens one)."""
        state = self.__dict__.copy()
        state["_window"] = None
        state.pop("_clock", None)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        """A copy, or one loaded, records its own episodes as this one does: written when
        it is dropped or the program ends, too."""
        self.__dict__.update(state)
        if self._recorder is not None:
            self._recorder.watch(self)

    @functools.cached_property
    def _pixels(self) -> PixelObserver:
        """What draws the picture observed, made when first drawn with (a batch that draws
        its games' pictures itself never makes one)."""
        return PixelObserver(self.obs_type == "grayscale")

    @functools.cached_property
    def ale(self) -> AleView:
        """ALE's interface as `ale_py`'s environment has it (the lives, the screen, the
        frame numbers): what Gymnasium's `AtariPreprocessing` and other Atari wrappers read
        from `env.unwrapped.ale`."""
        return AleView(self)

    @property
    def _frameskip(self) -> int | tuple[int, int]:
        """ALE's environment's name for `frameskip`: `AtariPreprocessing` reads it (and
        takes only an environment that skips no frames itself, `frameskip=1`)."""
        return self.frameskip

    @property
    def episode_frame_number(self) -> int:
        return self._episode_frames

    @property
    def cut_short(self) -> bool:
        """Whether the episode has played the frames it may (ALE's truncation)."""
        return self._episode_frames >= self.frame_limit

    @property
    def lives(self) -> int:
        """The ships left, as ALE's lives (0 once the last is lost: the game is over)."""
        assert self.world is not None
        return self.world.ships

    def get_action_meanings(self) -> list[str]:
        return list(self._meanings)

    def get_keys_to_action(self) -> dict[tuple[str, ...], int]:
        """ALE's keys to each action, for Gymnasium's `play` (a person at the keyboard);
        none for a stick's actions (an AttributeError, as ALE's)."""
        if self.continuous:
            raise AttributeError("get_keys_to_action: no keys give a continuous action "
                                 "(continuous=True)")
        return {tuple(key for word, key in KEYS.items() if word in meaning) or ("e",): action
                for action, meaning in enumerate(self._meanings)}

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.begin(seed)
        if self.render_mode == "human":
            self.render()
        return self._observe(first=True), self._info([])

    def step(self, action: int | np.ndarray
             ) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if self.world is None:
            raise RuntimeError("call reset() before step()")
        if self.continuous or not (isinstance(action, (int, np.integer))
                                   and 0 <= action < len(self._actions)):
            action = self.action_index(action)
        reward, terminated, truncated, reports = self.advance(action)
        if self.render_mode == "human":
            self.render()
            if reports:  # the step's frames take their time, as in ALE's human mode
                self._clock.tick(DEFAULT_CONFIG.tick_hz / len(reports))
        return self._observe(), reward, terminated, truncated, self._info(reports)

    def action_index(self, action: Any) -> int:
        """The action, checked, as its place in `get_action_meanings()` (what `advance`
        plays): a stick's (continuous) as the one of ALE's full set it plays as
        (stick.py); a ValueError for one not in the action space. (Gymnasium's Discrete,
        as ALE, also takes an integer array of no dimensions; its Box a list of 3.)"""
        if not self.action_space.contains(action):
            raise ValueError(f"action {action!r} is not in {self.action_space}")
        if self.continuous:
            return self.stick_index(np.asarray(action, np.float32))
        return int(action)

    def stick_index(self, stick: np.ndarray) -> int:
        """A stick's action, already checked (float32), as its place in the full set."""
        return self._meanings.index(stick_meaning(stick, self.continuous_action_threshold))

    def begin(self, seed: int | None) -> None:
        """A new episode, its world seeded from the environment's generator (seeded first
        by `reset`): what reset does besides the observation and info."""
        if seed is not None:  # as ALE, which loads its cartridge again when seeded
            self.frame_number = 0
        world_seed = int(self.np_random.integers(0, 2**31 - 1))
        self.world, self._shared = World(world_seed, DEFAULT_CONFIG), False
        # The episode's sticky actions and frame skips come from a generator of their own
        # (as ALE's from its own), seeded from the environment's: a draw from it costs a
        # few hundredths of a microsecond, a draw of numpy's about ten a step.
        self._draws = random.Random(int(self.np_random.integers(0, 2**63 - 1)))
        self._previous = NOOP  # sticky actions repeat this, as ALE's start from NOOP
        self._episode_frames = 0
        if self._recorder is not None:  # (the last episode written first, if it was not)
            self._recorder.begin(self.world)

    def advance(self, action: int) -> tuple[float, bool, bool, list[TickReport]]:
        """The step's frames (an action already checked): the reward, whether the game is
        over or the episode cut short, and each frame's report. As ALE's, no frame is
        played past the episode's end: the step stops at the frame it ends on, and a step
        after that plays none (reward 0, the same ends) until a reset."""
        world, wanted = self.world, self._actions[action]
        assert world is not None
        if world.phase is GAME_OVER or self.cut_short:
            return 0.0, world.phase is GAME_OVER, self.cut_short, []
        if self._shared:  # (a state's world: played on, the state would change)
            world = self.world = copy.deepcopy(world)
            self._shared = False
        score = world.score
        # Sticky actions, frame by frame: each frame keeps the previous frame's input with
        # the given probability.
        draw, sticky = self._draws.random, self.repeat_action_probability
        recorder, reports = self._recorder, []
        if recorder is not None:
            recorder.keep_to(world)
        frames_left = self.frame_limit - self._episode_frames
        try:
            for _ in range(self._skip()):
                bits = self._previous if draw() < sticky else wanted
                self._previous = bits
                reports.append(world.step(bits))
                if recorder is not None:
                    recorder.note(bits)
                if world.phase is GAME_OVER or len(reports) == frames_left:
                    break
        except BaseException:
            # Cut off inside a frame (Ctrl-C, say): the world may stand inside a tick, and
            # an episode written then would not replay; its file ends at its last checkpoint.
            if recorder is not None:
                recorder.cut_off()
            raise
        self._episode_frames += len(reports)
        self.frame_number += len(reports)
        # (both, as ALE's, when the game ends on the limit's frame)
        terminated = world.phase is GAME_OVER
        truncated = self.cut_short
        if (terminated or truncated) and recorder is not None:
            recorder.save()
        # (the counter has four digits, as the ROM's: points past 9990 wrap to 0000)
        return float((world.score - score) % SCORE_WRAP), terminated, truncated, reports

    def clone_state(self, include_rng: bool = False) -> EnvState:
        """The episode as it stands, for `restore_state` (as ALE's: a search tries moves
        from one state). With include_rng, also the generator of sticky actions and frame
        skips: the same actions after a restore then give the same episode. The world is
        shared with the state until a frame is played (`_share`)."""
        if self.world is None:
            raise RuntimeError("call reset() before clone_state()")
        world, recording = self._share(self.world, None if self._recorder is None
                                       else self._recorder.current)
        return EnvState(world, self._previous, self._episode_frames, self.frame_number,
                        None if self._stack is None else self._stack.frames.copy(), recording,
                        self._draws.getstate() if include_rng else None)

    def restore_state(self, state: EnvState) -> None:
        """Go back to a state `clone_state` gave: the episode plays on from there (and its
        recording, if one is made, is the play up to there; an episode that ends is written
        each time). A state without the generator leaves this one as it is, as ALE's."""
        if self.world is None:
            raise RuntimeError("call reset() before restore_state()")
        if not isinstance(state, EnvState):
            raise TypeError(f"restore_state: {type(state).__name__} is not a state "
                            "clone_state gave")
        stacked = state.stacked
        if self._stack is not None and (stacked is None
                                        or stacked.shape != self._stack.frames.shape):
            raise ValueError("restore_state: the state is of an environment that stacks "
                             "other pictures")
        self.world, recording = self._share(state.world, state.recording)
        self._previous, self._episode_frames = state.previous, state.episode_frames
        self.frame_number = state.frame_number
        if self._stack is not None and stacked is not None:  # (both, as checked above)
            self._stack.frames[:] = stacked
        if self._recorder is not None:
            self._recorder.follow(recording)
        if state.draws is not None:
            self._draws.setstate(state.draws)

    def _share(self, world: World, recording: EpisodeRecording | None
               ) -> tuple[World, EpisodeRecording | None]:
        """A world for a state and the environment both: the same one, copied by `advance`
        before a frame is played on it (a search's node restores, steps and clones: one
        copy, where a copy at each clone and restore made two); or, where episodes are
        recorded (a recording changes as it is written), the world and its recording
        copied now, together (the recording's world is the world's copy)."""
        if self._recorder is None:
            self._shared = True
            return world, None
        return copy.deepcopy((world, recording))

    def render(self) -> np.ndarray | None:
        """The RGB picture (rgb_array), or the picture shown in a window (human); without
        a render mode, a warning, in the words of Gymnasium's own environments."""
        if self.render_mode is None:
            made = self.spec.id if self.spec is not None else "invaders/SpaceInvaders-v0"
            gym.logger.warn("You are calling render method without specifying any render "
                            "mode. You can specify the render_mode at initialization, "
                            f'e.g. gym.make("{made}", render_mode="rgb_array")')
            return None
        if self.world is None:
            return None
        if self.obs_type == "rgb":
            picture = self._pixels.observe(self.world)
        else:
            self._shown = self._shown or PixelObserver(grayscale=False)
            picture = self._shown.observe(self.world)
        if self.render_mode == "rgb_array":
            return picture  # (a new array)
        self._show(picture)
        return None

    def close(self) -> None:
        """The episode in progress written (an OSError if an episode recorded still cannot
        be: kept, for another close) and the window closed."""
        try:
            if self._recorder is not None:
                self._recorder.close()
        finally:
            if self._window is not None:
                self._window.close()
                self._window = None

    def let_go(self) -> None:
        """As the environment goes without a close (dropped, or the program ending): its
        episodes written as far as they can be, any that cannot be said lost in a warning."""
        if self._recorder is not None:
            self._recorder.let_go()

    # --- inside ---------------------------------------------------------------------------
    def _skip(self) -> int:
        if isinstance(self.frameskip, int):
            return self.frameskip
        return self._draws.randrange(*self.frameskip)

    def _observe(self, first: bool = False) -> np.ndarray:
        """This step's observation, an array of its own: the picture alone is tinted into
        a new one; the state, a shrink and a stack are kept and rewritten, so copied."""
        frame = self.frame(first)
        return frame if self._picture_alone else frame.copy()

    def frame(self, first: bool = False) -> np.ndarray:
        """The observation: the picture alone in a new array, any other in the array kept
        for it (rewritten next step); what a batch copies into its own array. `first`: the
        episode's first (a stack starts from it)."""
        assert self.world is not None
        if self.obs_type == "state":
            return self._state.observe(self.world)
        if self._shrink is not None:
            self._shrink.read(self._pixels.draw(self.world))
            frame = self._shrink.shrink()[0]
        else:
            frame = self._pixels.observe(self.world)
        if self._stack is not None:
            frame = self._stack.reset(frame) if first else self._stack.push(frame)
        return frame

    def _info(self, reports: list[TickReport]) -> dict[str, Any]:
        """ALE's fields, the step's events by name and its collision counters summed."""
        world = self.world
        assert world is not None
        return {"lives": self.lives, "episode_frame_number": self._episode_frames,
                "frame_number": self.frame_number,
                "events": tuple([event.name for event in step_events(reports)]),
                "collisions": dict(zip(STAT_FIELDS, step_counters(reports), strict=True)),
                "seed": world.seed}

    def _show(self, picture: np.ndarray) -> None:
        if self._window is None:
            try:
                self._window = EnvWindow("invaders: SpaceInvaders-v0", (SCREEN_W, SCREEN_H), 3)
            except pygame.error as error:
                raise pygame.error(f"render_mode 'human' shows a window, and cannot here "
                                   f"({error}): 'rgb_array' gives its pictures") from None
            self._clock = pygame.time.Clock()
        self._window.show(picture)


def _check_options(obs_type: str, frameskip: Any, repeat_action_probability: Any,
                   full_action_space: Any, render_mode: str | None, resize: Any, stack: Any,
                   max_frames: Any) -> None:
    """One ValueError naming the option, for a value the environment cannot take."""
    if obs_type not in OBS_TYPES:
        instead = " (for ALE's RAM, 'state': the game's objects)" if obs_type == "ram" else ""
        raise ValueError(f"obs_type {obs_type!r}: choose from {', '.join(OBS_TYPES)}{instead}")
    if not _valid_skip(frameskip):
        raise ValueError(f"frameskip {frameskip!r}: a whole number >= 1 or (low, high)")
    if not (isinstance(repeat_action_probability, numbers.Real)  # (numpy's too, as ALE's)
            and 0.0 <= float(repeat_action_probability) <= 1.0):
        raise ValueError(f"repeat_action_probability {repeat_action_probability!r}: 0 to 1")
    if not isinstance(full_action_space, (bool, np.bool_)):
        raise ValueError(f"full_action_space {full_action_space!r}: True or False")
    if not (max_frames is None or isinstance(max_frames, numbers.Integral)):
        raise ValueError(f"max_num_frames_per_episode {max_frames!r}: a whole number (0 or "
                         "below, or None: no limit)")
    if resize is not None and (obs_type != "grayscale" or not _valid_size(resize)):
        raise ValueError(f"resize {resize!r}: (height, width) up to 224, for grayscale")
    if not (isinstance(stack, int) and 1 <= stack <= 64) or (stack > 1 and obs_type == "state"):
        raise ValueError(f"stack {stack!r}: 1 to 64 pictures (not with the state)")
    if render_mode not in (None, *SpaceInvadersEnv.metadata["render_modes"]):
        raise ValueError(f"render_mode {render_mode!r}: None, 'human' or 'rgb_array'")


def _check_cartridge(mode: Any, difficulty: Any) -> None:
    """ALE's `mode` and `difficulty` choose among the 2600 cartridge's variations of its
    game: the arcade game has one, so only ALE's defaults (None, or 0, the cartridge's own
    default) are taken, as code written for ALE may pass them; any other is refused."""
    for name, value in (("mode", mode), ("difficulty", difficulty)):
        if not (value is None or (isinstance(value, (int, np.integer)) and value == 0)):
            raise ValueError(f"{name} {value!r}: None or 0 (the arcade game has no "
                             "variations; ALE's are the 2600 cartridge's)")


def _valid_size(size: Any) -> bool:
    """Two whole numbers from 1 to 224, as a tuple or a list (a config file's)."""
    return (isinstance(size, (tuple, list)) and len(size) == 2
            and all(isinstance(n, (int, np.integer)) and not isinstance(n, bool)
                    and 1 <= n <= 224 for n in size))


def _valid_skip(frameskip: Any) -> bool:
    """A whole number from 1, or ALE's (low, high) range, drawn from per step, as a tuple
    or a list (never a bool: ALE refuses one too)."""
    if isinstance(frameskip, (tuple, list)):
        return (len(frameskip) == 2 and all(_whole(n) for n in frameskip)
                and 1 <= frameskip[0] < frameskip[1])
    return _whole(frameskip) and frameskip >= 1


def _whole(value: Any) -> bool:
    """An int, not a bool (which Python counts among them)."""
    return isinstance(value, int) and not isinstance(value, bool)


def _steps_a_second(frameskip: int | tuple[int, int]) -> int:
    """The steps a second that show the game at its own speed (60 frames a second), for a
    frame skip (a range's mean: its draws are whole numbers from low to high - 1)."""
    low, high = (frameskip, frameskip + 1) if isinstance(frameskip, int) else frameskip
    return max(1, round(DEFAULT_CONFIG.tick_hz / ((low + high - 1) / 2)))


def _space(obs_type: str, shape: tuple[int, int], stack: int) -> spaces.Box:
    if obs_type == "state":
        return spaces.Box(0.0, STATE_HIGH, (STATE_SIZE,), np.float32)
    frame = (*shape, 3) if obs_type == "rgb" else shape
    return spaces.Box(0, 255, (stack, *frame) if stack > 1 else frame, np.uint8)
