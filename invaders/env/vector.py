"""N games stepped together, their observations written into one array kept between
steps: `gymnasium.make_vec("invaders/SpaceInvaders-v0", num_envs=N,
vectorization_mode="vector_entry_point")`, in this process, or with `workers=W` on W
cores (a share of the games stepped here, each other share on a worker process, the
arrays in shared memory: workers.py). Autoreset as Gymnasium 1.x's default (`NEXT_STEP`):
the step after an episode ends resets that game (reward 0, its first observation), the
others step on; or within the step (`SAME_STEP`), or never (`DISABLED`: the caller resets
it), as Gymnasium's own vectors take `autoreset_mode`. Each game is a
`SpaceInvadersEnv`, so each gives what it would alone, and the infos are those
Gymnasium's vectors merge from its games' (events and counters too); the batch saves the
per-game copies, the merging of infos and the wrappers of a generic vector environment
(and, on workers, the pickled infos of Gymnasium's async one), and draws and shrinks its
games' grey pictures together (games.py).
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from invaders.engine.stats import STAT_FIELDS
from invaders.env.games import ALE_NUMBERS, EVENTS_KEPT, NUMBERS, Games, Rows
from invaders.env.recording import on_drop
from invaders.env.space_invaders import SpaceInvadersEnv
from invaders.env.workers import Pool
from invaders.game.events import Event

EVENT_NAMES = {int(event): event.name for event in Event}


class SpaceInvadersVectorEnv(VectorEnv):
    """`num_envs` games with the same options (those of `SpaceInvadersEnv`), in this
    process or in `workers` shares, this process's and `workers - 1` worker processes'
    (started with the multiprocessing `context` named, or the platform's default, as
    Gymnasium's async vector does). A game whose episode ended resets at the next step
    (`autoreset_mode` NEXT_STEP, Gymnasium's default), within the step (SAME_STEP), or
    when the caller resets it (DISABLED: `reset(options={"reset_mask": ...})`), as in
    Gymnasium's vectors. `max_episode_steps` cuts each game's episodes short at that many
    steps, as Gymnasium's `make_vec` asks of a vector entry point (its sync and async
    vectors wrap each game in `TimeLimit`)."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP}  # noqa: RUF012 (Gymnasium's)

    def __init__(self, num_envs: int = 8, copy: bool = True, workers: int = 1,
                 context: str | None = None,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
                 max_episode_steps: int | None = None, **options: Any) -> None:
        if not (isinstance(num_envs, int) and num_envs >= 1):
            raise ValueError(f"num_envs {num_envs!r}: a whole number from 1")
        self.autoreset_mode = _autoreset_mode(autoreset_mode)
        self._step_limit = _step_limit(max_episode_steps)
        self._steps = np.zeros(num_envs, np.int64)  # each game's since its reset
        if not (isinstance(workers, int) and 1 <= workers <= num_envs):
            raise ValueError(f"workers {workers!r}: a whole number from 1 to num_envs")
        if workers > 1 and options.get("render_mode") is not None:
            raise ValueError("render_mode: games on workers are not drawn for the caller")
        if options.get("render_mode") == "human":  # (a vector should not, says Gymnasium)
            raise ValueError("render_mode 'human': the batch opens no window; make it with "
                             "'rgb_array' and wrap it in gymnasium.wrappers.vector."
                             "HumanRendering to watch its games")
        _refuse_ales_vector_options(options)
        single = SpaceInvadersEnv(**options)  # (checks the options here, in one line)
        # (the steps a second its games show, which Gymnasium's HumanRendering reads)
        self.metadata = {**self.metadata, "render_modes": ["rgb_array"],
                         "render_fps": single.metadata["render_fps"],
                         "autoreset_mode": self.autoreset_mode}
        self.num_envs, self.copy = num_envs, copy
        self.single_observation_space = single.observation_space
        self.single_action_space = single.action_space
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.render_mode = options.get("render_mode")
        shape, dtype = self.single_observation_space.shape, self.single_observation_space.dtype
        assert shape is not None  # (a Box's)
        self._action_count = len(single.get_action_meanings())
        # (a stick's actions, continuous=True: each game's read as the single game reads it,
        # once the batch's are checked together)
        self._stick_index = single.stick_index if single.continuous else None
        self._games: Games | Pool
        if workers == 1:
            self._games = Games(num_envs, Rows.zeros(num_envs, shape, dtype), options)
        else:
            self._games = Pool(num_envs, workers, options, shape, dtype, context)
        self._rows = self._games.rows
        self._begun = False  # (reset yet)
        # The games let go (their episodes in progress written, or said lost, the workers
        # ended) when the vector is dropped or the program ends without closing it.
        on_drop(self, self._games.let_go)

    @property
    def envs(self) -> list[SpaceInvadersEnv]:
        """The games, when they are in this process."""
        if not isinstance(self._games, Games):
            raise AttributeError("the games are on worker processes")
        return self._games.envs

    def reset(self, *, seed: int | list[int | None] | None = None,
              options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        """Every game anew, or those `options["reset_mask"]` names (as Gymnasium's own
        vectors: the others' observations stay as they are, and the infos are only the
        reset games'); an int seed gives game i the seed `seed + i`, as theirs does."""
        seeds = ([seed + i for i in range(self.num_envs)] if isinstance(seed, int)
                 else seed if seed is not None else [None] * self.num_envs)
        if len(seeds) != self.num_envs:
            raise ValueError(f"{len(seeds)} seeds for {self.num_envs} games")
        which = _reset_mask(options, self.num_envs)
        if which is not None and not self._begun:
            raise RuntimeError("reset every game before some (options['reset_mask'])")
        self._games.reset(list(seeds), None if which is None else which.tolist())
        self._steps[slice(None) if which is None else which] = 0
        self._begun = True
        return self._out(self._rows.obs), self._infos(which)

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                          dict[str, Any]]:
        if not self._begun:
            raise RuntimeError("call reset() before step()")
        if self.autoreset_mode is AutoresetMode.DISABLED and self._rows.ended.any():
            raise RuntimeError(f"games {np.flatnonzero(self._rows.ended).tolist()} ended: "
                               "reset them (options['reset_mask']) before the next step, "
                               "as autoreset_mode DISABLED asks")
        reset_now = self._rows.ended.copy()  # (NEXT_STEP: these reset in the step)
        self._games.step(self._indices(actions))
        self._cut_at_limit(reset_now)
        infos = self._infos()
        if self.autoreset_mode is AutoresetMode.SAME_STEP:
            infos = self._restart_ended(infos)
        rows = self._rows
        return (self._out(rows.obs), self._out(rows.rewards), self._out(rows.terminated),
                self._out(rows.truncated), infos)

    def _indices(self, actions: Any) -> list[int]:
        """Each game's action, checked, as its place in the game's action meanings."""
        if self._stick_index is not None:
            if not self.action_space.contains(actions):
                raise ValueError(f"actions {actions!r} are not in {self.action_space}")
            return [self._stick_index(stick) for stick in np.asarray(actions, np.float32)]
        actions = np.asarray(actions)
        indices = actions.tolist()
        if (actions.shape != (self.num_envs,) or actions.dtype.kind not in "iu"
                or min(indices) < 0 or max(indices) >= self._action_count):
            raise ValueError(f"actions {actions!r} are not in {self.action_space}")
        return indices

    def _cut_at_limit(self, reset_now: np.ndarray) -> None:
        """`max_episode_steps`, as Gymnasium's `TimeLimit` on each game: the steps since
        each game's reset counted (none for one this step reset), and the episodes that
        reach the limit truncated (so that, ended, they reset as the mode says)."""
        if self._step_limit is None:
            return
        steps, rows = self._steps, self._rows
        steps += 1
        steps[reset_now] = 0
        cut = steps >= self._step_limit
        np.logical_or(rows.truncated, cut, out=rows.truncated)
        np.logical_or(rows.ended, cut, out=rows.ended)

    def _restart_ended(self, infos: dict[str, Any]) -> dict[str, Any]:
        """SAME_STEP: the games whose episodes this step ended reset within it, as in
        Gymnasium's vectors: their observations and infos are the new episodes' first,
        the ended episodes' last in `final_obs` and `final_info`; the step's rewards and
        ends stay. (A reset of those games, as `reset_mask` asks: one more round on
        workers, at an episode's end.)"""
        rows = self._rows
        ended = rows.terminated | rows.truncated
        if not ended.any():
            return infos
        final_obs = np.full(self.num_envs, None, object)
        for i in np.flatnonzero(ended):
            final_obs[i] = rows.obs[i].copy()
        final_info = self._infos(ended)
        kept = rows.terminated.copy(), rows.truncated.copy()  # (a reset clears them)
        self._games.reset([None] * self.num_envs, ended.tolist())
        self._steps[ended] = 0
        rows.terminated[:], rows.truncated[:] = kept
        infos = _where(ended, self._infos(ended), infos)
        infos.update(final_obs=final_obs, _final_obs=ended, final_info=final_info,
                     _final_info=ended)
        return infos

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple[Any, ...]:
        """Each game's `name` called with these arguments (or its value, not callable), as
        Gymnasium's sync and async vectors' `call`; on workers the answers are pickled.
        (The games are single environments: where the batch shrinks and stacks their
        pictures, theirs are the full picture.)"""
        return tuple(self._games.call(name, args, kwargs))

    def get_attr(self, name: str) -> tuple[Any, ...]:
        return self.call(name)

    # (read-only, and tuples where the base class has one of each: as Gymnasium's vectors)
    @property
    def np_random_seed(self) -> tuple[int, ...]:  # type: ignore[override]
        """The games' seeds, as Gymnasium's sync and async vectors give them (the base
        class's is the seed of a generator of the batch's own, which no game draws from)."""
        return self.get_attr("np_random_seed")

    @property  # type: ignore[misc]
    def np_random(self) -> tuple[np.random.Generator, ...]:  # type: ignore[override]
        """The games' generators (on workers, copies), as Gymnasium's vectors give them."""
        return self.get_attr("np_random")

    def set_attr(self, name: str, values: list[Any] | tuple[Any, ...] | Any) -> None:
        """Each game's attribute `name` set: to the value a game of the list or tuple, or
        to the one value given."""
        if not isinstance(values, (list, tuple)):
            values = [values] * self.num_envs
        if len(values) != self.num_envs:
            raise ValueError(f"{len(values)} values for {self.num_envs} games")
        self._games.set_attr(name, list(values))

    def render(self) -> tuple[np.ndarray, ...] | None:
        if self.render_mode != "rgb_array":
            return None
        return tuple(cast(np.ndarray, env.render()) for env in self.envs)  # (rgb_array's)

    def close_extras(self, **kwargs: Any) -> None:
        # (no games where __init__ refused its options: Gymnasium 1.1 closes every vector
        # dropped, made whole or not)
        games = getattr(self, "_games", None)
        if games is not None:
            games.close()

    def _out(self, array: np.ndarray) -> np.ndarray:
        return array.copy() if self.copy else array

    def _infos(self, present: np.ndarray | None = None) -> dict[str, Any]:
        """Each game's info as Gymnasium's sync vector merges them: each number an array,
        the events an array of each game's tuple of names, the counters a dict of arrays,
        each with Gymnasium's mask of who has it (every game, or those `present`: the
        others' numbers 0 and events None, as Gymnasium fills what a game did not give)."""
        numbers = self._rows.numbers.T.copy()  # (the caller's)
        everyone = present is None
        if present is None:
            present = np.ones(self.num_envs, np.bool_)
        else:
            numbers[:, ~present] = 0
        columns = dict(zip(NUMBERS, numbers, strict=True))
        infos: dict[str, Any] = {}
        for key in ALE_NUMBERS:
            infos[key], infos[f"_{key}"] = columns[key], present
        events = self._events(columns["events"].tolist())
        if not everyone:
            events[~present] = None
        infos["events"], infos["_events"] = events, present
        collisions: dict[str, Any] = {}
        for key in STAT_FIELDS:
            collisions[key], collisions[f"_{key}"] = columns[key], present
        infos["collisions"], infos["_collisions"] = collisions, present
        infos["seed"], infos["_seed"] = columns["seed"], present
        return infos

    def _events(self, counts: list[int]) -> np.ndarray:
        """Each game's step's events by name (given how many), from its row of codes (most
        have none) or spilled."""
        rows, spilled = self._rows.events, self._games.spilled
        names = []
        for i, count in enumerate(counts):
            if count:
                codes = spilled[i] if count > EVENTS_KEPT else rows[i, :count].tolist()
                names.append(tuple(EVENT_NAMES[code] for code in codes))
            else:
                names.append(())
        # (an array of the tuples themselves: made from a list, numpy would read them as
        # rows of names)
        return np.fromiter(names, object, len(names))


# The options of ALE's own vector environment (ale_py.vector_env.AtariVectorEnv) that ours
# takes under other names, or leaves to Gymnasium's wrappers: code written for it is told.
PREPROCESSING = ("Gymnasium's AtariPreprocessing, on single games (the batch does not "
                 "preprocess)")
ALES_VECTOR_OPTIONS = {
    "img_height": "resize=(height, width), with obs_type='grayscale'",
    "img_width": "resize=(height, width), with obs_type='grayscale'",
    "grayscale": "obs_type='grayscale'", "stack_num": "stack",
    "num_threads": "workers (worker processes)", "batch_size": "num_envs (every game a step)",
    "thread_affinity_offset": "workers (worker processes)",
    **dict.fromkeys(("maxpool", "noop_max", "episodic_life"), PREPROCESSING),
    "reward_clipping": "gymnasium.wrappers.vector.ClipReward(envs, -1, 1) (the rewards are "
                       "0 or more)",
    "use_fire_reset": "nothing (the game starts at a reset, with no FIRE)",
    "life_loss_info": "info['events'] (SHIP_LOST) or info['lives']",
}


def _refuse_ales_vector_options(options: dict[str, Any]) -> None:
    """One ValueError for the first option of ALE's vector environment given, naming what
    takes its place here."""
    for name in options:
        if name in ALES_VECTOR_OPTIONS:
            raise ValueError(f"{name}: an option of ALE's vector environment; here, "
                             f"{ALES_VECTOR_OPTIONS[name]}")


def _reset_mask(options: dict[str, Any] | None, games: int) -> np.ndarray | None:
    """The games a reset is for, when `options["reset_mask"]` names them (refused as
    Gymnasium's vectors refuse it: a numpy array of `games` bools, one True at least)."""
    if options is None or "reset_mask" not in options:
        return None
    which = options["reset_mask"]
    if not isinstance(which, np.ndarray) or which.dtype != np.bool_:
        raise TypeError(f"options['reset_mask'] {which!r}: a numpy array of bools")
    if which.shape != (games,) or not which.any():
        raise ValueError(f"options['reset_mask'] {which!r}: one bool a game ({games}), "
                         "one True at least")
    return which


def _step_limit(asked: Any) -> int | None:
    """`max_episode_steps` as Gymnasium's `make` takes it: None or -1 for no limit, else
    a whole number from 1 (refused as its `TimeLimit` refuses one)."""
    if asked is None or asked == -1:
        return None
    if not isinstance(asked, int):
        raise TypeError(f"max_episode_steps {asked!r}: a whole number")
    if asked <= 0:
        raise ValueError(f"max_episode_steps {asked!r}: a whole number from 1 (-1 or None: "
                         "no limit)")
    return asked


def _autoreset_mode(asked: Any) -> AutoresetMode:
    """Gymnasium's mode named (the enum or its value)."""
    try:
        return AutoresetMode(asked)
    except ValueError:
        modes = ", ".join(mode.name for mode in AutoresetMode)
        raise ValueError(f"autoreset_mode {asked!r}: one of Gymnasium's ({modes})") from None


def _where(mask: np.ndarray, these: dict[str, Any], others: dict[str, Any]
           ) -> dict[str, Any]:
    """Two infos of the games merged: `these`' entries for the games `mask` names,
    `others`' for the rest (and so their masks of who has each)."""
    return {key: _where(mask, value, others[key]) if isinstance(value, dict)
            else np.where(mask, value, others[key]) for key, value in these.items()}
