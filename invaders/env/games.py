"""Games stepped together, each writing its step into a row of arrays it is given: what
the native vector environment does in its own process, and each of its workers does with
arrays in shared memory.

Autoreset as Gymnasium 1.x's default (`NEXT_STEP`): the step after a game's episode ends
resets that game (reward 0, its first observation), the others step on.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from invaders.engine.stats import STAT_FIELDS
from invaders.env.observations import PixelObserver
from invaders.env.shrink import Shrink
from invaders.env.space_invaders import SpaceInvadersEnv, step_counters, step_events
from invaders.game.events import Event
from invaders.game.world import TickReport

# The info's numbers, a column each: ALE's, the world's seed, the step's collision counters,
# and how many events it had (their codes in the events' rows).
ALE_NUMBERS = ("lives", "episode_frame_number", "frame_number")
NUMBERS = (*ALE_NUMBERS, "seed", *STAT_FIELDS, "events")
EVENT_COUNT = NUMBERS.index("events")
# A step's events kept in a game's row, as their codes (an Event's value): a step at frame
# skip 4 has a few; one with more (a long frame skip) has them spilled instead
# (`Games.spilled`, which workers send by their pipe).
EVENTS_KEPT = 32


class Rows(NamedTuple):
    """Where the games write: a row (or an element) per game."""

    obs: np.ndarray
    rewards: np.ndarray  # float64
    terminated: np.ndarray  # bool
    truncated: np.ndarray  # bool
    ended: np.ndarray  # bool: terminated or truncated, so the next step resets
    numbers: np.ndarray  # int64, (games, 15): NUMBERS
    events: np.ndarray  # uint8, (games, EVENTS_KEPT): the step's events' codes

    @staticmethod
    def specs(games: int, obs_shape: tuple[int, ...], obs_dtype: Any
              ) -> dict[str, tuple[tuple[int, ...], Any]]:
        """Each field's shape and dtype, for `games` games."""
        return {"obs": ((games, *obs_shape), obs_dtype), "rewards": ((games,), np.float64),
                "terminated": ((games,), np.bool_), "truncated": ((games,), np.bool_),
                "ended": ((games,), np.bool_), "numbers": ((games, len(NUMBERS)), np.int64),
                "events": ((games, EVENTS_KEPT), np.uint8)}

    @classmethod
    def zeros(cls, games: int, obs_shape: tuple[int, ...], obs_dtype: Any) -> Rows:
        return cls(**{name: np.zeros(shape, dtype) for name, (shape, dtype)
                      in cls.specs(games, obs_shape, obs_dtype).items()})


class Games:
    """`SpaceInvadersEnv`s with the same options, and the rows they write. Grey pictures
    made smaller are made together: one picture draws every game's in turn (one canvas and
    one set of sprites and texts, which stay in the cache where a set a game did not: 8
    games step 1.14 times as fast, the median of 40 rounds in turn, a script), each game
    with a backdrop of its own, then one Shrink takes them all (and the stacks move on
    together)."""

    def __init__(self, count: int, rows: Rows, options: dict[str, Any]) -> None:
        resize = options.get("resize")
        self._shrink = Shrink(resize, count) if resize is not None else None
        self._pixels = PixelObserver(grayscale=True) if resize is not None else None
        # Games whose pictures are drawn and shrunk here have no shrink and no stack of
        # their own (a quarter of a megabyte a game, never used: 8 games take 6.3 against
        # 8.4 MB, by tracemalloc), and never make a picture of their own.
        own = {**options, "resize": None, "stack": 1} if resize is not None else options
        self.envs = [SpaceInvadersEnv(**own) for _ in range(count)]
        self.rows = rows
        # The last step's events of the games whose count is past EVENTS_KEPT, by game.
        self.spilled: dict[int, list[Event]] = {}

    def reset(self, seeds: list[int | None], which: list[bool] | None = None) -> None:
        """Every game anew, or those `which` names (their observations, numbers and ends;
        a reset hands out no reward, so the rewards are the steps' alone): the others' rows
        are left as they are (a game that had ended still resets at the next step)."""
        rows = self.rows
        anew = np.ones(len(self.envs), np.bool_) if which is None else np.array(which)
        self.spilled = {}
        for i, (env, seed) in enumerate(zip(self.envs, seeds, strict=True)):
            if anew[i]:
                env.reset(seed=seed)
                self._observe(i, env, first=True)
                rows.numbers[i] = self._note(i, env, [])
        self._shrunk(anew, stepped=False)
        rows.terminated[anew] = rows.truncated[anew] = rows.ended[anew] = False

    def step(self, actions: list[int]) -> None:
        """One step of every game (actions already checked): every game's frames first,
        then every game's picture and numbers. Each half keeps its own code and data in
        the cache, where a game at a time swapped the two eight times a step: compiled,
        8 games stepped 1.03 times as fast (30 rounds in turn, fresh processes)."""
        rows = self.rows
        first = rows.ended.copy()  # NEXT_STEP: this step resets these
        resets = first.tolist()
        self.spilled = {}
        stepped = [self._advance(i, env, action, resets[i])
                   for i, (env, action) in enumerate(zip(self.envs, actions, strict=True))]
        notes = []
        for i, (env, reports) in enumerate(zip(self.envs, stepped, strict=True)):
            self._observe(i, env, resets[i])
            notes.append(self._note(i, env, reports))
        rows.numbers[:] = notes  # (at once: a row at a time costs a conversion a row)
        self._shrunk(first)
        np.logical_or(rows.terminated, rows.truncated, out=rows.ended)

    def _advance(self, i: int, env: SpaceInvadersEnv, action: int, first: bool
                 ) -> list[TickReport]:
        """Game i's frames of this step (none for a game reset by it), its reward and ends
        in its row; the frames' reports."""
        rows = self.rows
        if first:
            env.begin(None)
            rows.rewards[i], rows.terminated[i], rows.truncated[i] = 0.0, False, False
            return []
        reward, terminated, truncated, reports = env.advance(action)
        rows.rewards[i], rows.terminated[i], rows.truncated[i] = reward, terminated, truncated
        return reports

    def _observe(self, i: int, env: SpaceInvadersEnv, first: bool) -> None:
        """Game i's observation in its row, or its grey picture in the shrink's place."""
        if self._shrink is None or self._pixels is None:
            self.rows.obs[i] = env.frame(first)
        else:
            assert env.world is not None
            self._shrink.read(self._pixels.draw(env.world, slot=i), i)

    def _shrunk(self, first: np.ndarray, stepped: bool = True) -> None:
        """The games' grey pictures made smaller, each the newest of its game's stack (a
        game's first fills its stack, as a reset does); after a reset (not `stepped`),
        only the `first` games' are written."""
        if self._shrink is None:
            return
        small, obs = self._shrink.shrink(), self.rows.obs
        stacked = obs.ndim > small.ndim
        if stepped and not stacked:
            obs[:] = small
            return
        if stepped:
            obs[:, :-1] = obs[:, 1:]
            obs[:, -1] = small
        if first.any():
            obs[first] = small[first][:, None] if stacked else small[first]

    def call(self, name: str, args: tuple[Any, ...], kwargs: dict[str, Any]) -> list[Any]:
        """Each game's `name` called with these arguments, or its value if not callable
        (Gymnasium's vectors' `call`)."""
        results = []
        for env in self.envs:
            value = env.get_wrapper_attr(name)
            results.append(value(*args, **kwargs) if callable(value) else value)
        return results

    def set_attr(self, name: str, values: list[Any]) -> None:
        for env, value in zip(self.envs, values, strict=True):
            env.set_wrapper_attr(name, value)

    def close(self) -> None:
        """Every game closed, even where one fails (its episode unwritten): the first
        failure raised then."""
        failures = []
        for env in self.envs:
            try:
                env.close()
            except OSError as failure:
                failures.append(failure)
        if failures:
            raise failures[0]

    def let_go(self) -> None:
        """Every game let go (`SpaceInvadersEnv.let_go`), as a batch goes unclosed."""
        for env in self.envs:
            env.let_go()

    def _note(self, i: int, env: SpaceInvadersEnv, reports: list[TickReport]
              ) -> tuple[int, ...]:
        """Game i's numbers for its row (the step's counters among them), its step's events
        written in its row of codes (or spilled, past EVENTS_KEPT)."""
        assert env.world is not None
        events = step_events(reports)
        count = len(events)
        if count > EVENTS_KEPT:
            self.spilled[i] = events
        elif count:
            self.rows.events[i, :count] = events
        return (env.lives, env.episode_frame_number, env.frame_number, env.world.seed,
                *step_counters(reports), count)
