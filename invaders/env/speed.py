"""The environment against ALE's own Gymnasium environment, step for step: `invaders bench
--ale` prints this table. Both with ALE v5's settings (frame skip 4, sticky actions 0.25),
the same fixed cycle of actions, the observation types paired as a learner would pair them
(our picture against ALE's, our state vector against ALE's 128 bytes of RAM), both made by
`gymnasium.make` (so each carries Gymnasium's default wrappers). Each round
times every contender for about a quarter of a second, the order reversed from round to
round; figures are medians over the rounds, ratios the median of the per-round ratios.
"""

from __future__ import annotations

import math
import os
import statistics
import time
from collections.abc import Callable
from typing import Any

import gymnasium
import numpy as np

import invaders.env  # noqa: F401  (registers the id)
from invaders.env.space_invaders import SpaceInvadersEnv
from invaders.lab.ale import available
from invaders.lab.timing import no_gc

ENV_ID = "invaders/SpaceInvaders-v0"  # through gymnasium.make on both sides, wrappers alike
PAIRS = (("rgb", "rgb", 5.0), ("grayscale", "grayscale", 5.0), ("state", "ram", 8.0))
CYCLE = (1, 2, 2, 2, 0, 1, 3, 3, 3, 0, 4, 5)  # ALE's minimal actions, both sides alike
ROUND_SECONDS = 0.25


def _stepper(env: Any) -> Callable[[int], float]:
    """Seconds for n steps of the cycle; an episode that ends is reset inside the time, as a
    learner's loop does."""
    env.reset(seed=0)

    def run(n: int) -> float:
        step, reset = env.step, env.reset
        with no_gc():
            start = time.perf_counter()
            for i in range(n):
                _, _, terminated, truncated, _ = step(CYCLE[i % len(CYCLE)])
                if terminated or truncated:
                    reset()
            return time.perf_counter() - start

    return run


def ale_env(obs_type: str) -> Any:
    import ale_py

    gymnasium.register_envs(ale_py)
    return gymnasium.make("ALE/SpaceInvaders-v5", obs_type=obs_type, frameskip=4,
                          repeat_action_probability=0.25)


def env_table(rounds: int, section: bool = False) -> int:
    """Print ours against ALE per observation type with the goals as ratios (ours alone,
    said in one line, without ale-py); 1 if a goal is missed. `section`: as section 6 of
    `bench --ale`, rather than a run of its own."""
    heading = "6." if section else f"invaders bench --env ({rounds} interleaved rounds):"
    print(f"{heading} the Gymnasium environment against ALE's (ALE/SpaceInvaders-v5), frame "
          "skip 4, sticky actions 0.25: steps a second, median (lowest..highest round)")
    with_ale = available()
    if not with_ale:
        print("   ALE skipped: install the compare extra (ale-py) to time it beside ours")
    missed = 0
    for ours_type, theirs_type, target in PAIRS:
        runs = {"ours": _stepper(gymnasium.make(ENV_ID, obs_type=ours_type))}
        if with_ale:
            runs["ALE"] = _stepper(ale_env(theirs_type))
        rates = _rates(runs, rounds)
        line = f"   ours {ours_type:<9} {_figure(rates['ours'])}"
        if with_ale:
            ratio, said = _ratios(rates["ours"], rates["ALE"])
            met = ratio >= target
            missed += not met
            line += (f"   ALE {theirs_type:<9} {_figure(rates['ALE'])}   {said}"
                     f"   goal >= {target:.0f}x: {'met' if met else 'NOT met'}")
        print(line)
    if with_ale:
        _search_row(rounds)
    return 1 if missed + _vector_rows(rounds) else 0


def _searcher(env: Any, clone: Callable[[], Any], restore: Callable[[Any], None]
              ) -> Callable[[int], float]:
    """Seconds for n nodes of a tree search: a state restored, a step from it and the
    state it leads to cloned (what a search does to try a move), ten steps into an
    episode."""
    env.reset(seed=0)
    for action in CYCLE[:10]:
        env.step(action)
    root = clone()

    def run(n: int) -> float:
        with no_gc():
            start = time.perf_counter()
            for i in range(n):
                restore(root)
                env.step(CYCLE[i % len(CYCLE)])
                clone()
            return time.perf_counter() - start

    return run


def _search_row(rounds: int) -> None:
    """A search's node (the state vector's environment; ALE's RAM's), ours against ALE's,
    reported (no goal)."""
    ours, theirs = gymnasium.make(ENV_ID, obs_type="state"), ale_env("ram")
    ale, game = theirs.unwrapped.ale, ours.unwrapped
    assert isinstance(game, SpaceInvadersEnv)
    runs = {"ours": _searcher(ours, game.clone_state, game.restore_state),
            "ALE": _searcher(theirs, ale.cloneState, ale.restoreState)}
    rates = _rates(runs, rounds)
    print(f"   a search's node (restore, step, clone): ours {_figure(rates['ours'], 'a second')}"
          f"   ALE {_figure(rates['ALE'], 'a second')}   {_ratios(rates['ours'], rates['ALE'])[1]}")


VECTOR_GOAL = 1.5  # the native batch against Gymnasium's sync vector of single games
VECTOR_OPTIONS: dict[str, Any] = {"obs_type": "grayscale", "resize": (84, 84), "stack": 4}


def _vector_stepper(mode: str, n: int, **extra: Any) -> Callable[[int], float]:
    """Seconds for k batch steps of n games (84x84 grey, 4 stacked), autoreset inside."""
    envs = gymnasium.make_vec(ENV_ID, num_envs=n, vectorization_mode=mode, **VECTOR_OPTIONS,
                              **extra)
    envs.reset(seed=0)
    return _batch_timer(envs.step, [np.full(n, action) for action in CYCLE])


def _batch_timer(step: Callable[[np.ndarray], Any], batches: list[np.ndarray]
                 ) -> Callable[[int], float]:
    """Seconds for k batch steps, the actions cycling through `batches`."""
    def run(k: int) -> float:
        with no_gc():
            start = time.perf_counter()
            for i in range(k):
                step(batches[i % len(batches)])
            return time.perf_counter() - start

    return run


def _vector_rows(rounds: int) -> int:
    """8 games in one process: the native batch against the sync vector; 1 if missed."""
    n = 8
    runs = {"native batch": _vector_stepper("vector_entry_point", n),
            "sync vector": _vector_stepper("sync", n)}
    missed = _batch_row(f"{n} games, 84x84 grey x4:", runs, n, rounds, VECTOR_GOAL)
    return missed + _envpool_row(rounds)


def _batch_row(label: str, runs: dict[str, Callable[[int], float]], n: int, rounds: int,
               goal: float) -> int:
    """One line: two batch contenders' steps a second (n games a batch step), the first's
    ratio to the second's against the goal; 1 if missed. Any further contender, timed in
    the same turns, gets a line of its own, the first's ratio to it, and no goal."""
    rates = {who: [n * r for r in rate] for who, rate in _rates(runs, rounds).items()}
    ours, theirs, *others = rates
    ratio, said = _ratios(rates[ours], rates[theirs])
    met = ratio >= goal
    print(f"   {label} {ours} {_figure(rates[ours])}   {theirs} {_figure(rates[theirs])}   "
          f"{said}   goal >= {goal:g}x: {'met' if met else 'NOT met'}")
    for other in others:
        print(f"   {' ' * len(label)} {other} {_figure(rates[other])}   "
              f"ours/this {_ratios(rates[ours], rates[other])[1]}")
    return 0 if met else 1


def _ratios(ours: list[float], theirs: list[float]) -> tuple[float, str]:
    """The median of the rounds' ratios, and it said with their spread."""
    ratios = [a / b for a, b in zip(ours, theirs, strict=True)]
    median = statistics.median(ratios)
    return median, f"{_places(median)}x ({_places(min(ratios))}..{_places(max(ratios))})"


def _places(ratio: float) -> str:
    """A ratio to two places, cut rather than rounded: a median just under its goal reads
    as under it (4.996 of a goal of 5 as 4.99, where rounded it read 5.00, NOT met)."""
    return f"{math.floor(ratio * 100) / 100:.2f}"


ENVPOOL_GOAL = 2.0  # ours against EnvPool, as many games and workers as cores on both sides


def _envpool_stepper(n: int) -> Callable[[int], float] | None:
    """EnvPool's Space Invaders (ALE in C++ threads), n games on n threads, 84x84 grey
    stacked 4, frame skip 4, sticky actions 0.25; None if it is not installed."""
    try:
        import envpool
    except ImportError:
        return None
    pool = envpool.make("SpaceInvaders-v5", env_type="gymnasium", num_envs=n, batch_size=n,
                        num_threads=n, img_height=84, img_width=84, stack_num=4,
                        gray_scale=True, frame_skip=4, repeat_action_probability=0.25)
    pool.reset()
    return _batch_timer(pool.step, [np.full(n, action, dtype=np.int32) for action in CYCLE])


def _ale_vector_stepper(n: int) -> Callable[[int], float] | None:
    """ALE's own vector environment (ale-py 0.11 on: EnvPool's C++ threads, in ALE), n
    games on n threads, 84x84 grey stacked 4, frame skip 4, sticky actions 0.25, doing
    what ours does: no no-op starts, no FIRE at a reset, the last frame alone (not the
    maximum of the last two); None without it."""
    try:
        from ale_py.vector_env import AtariVectorEnv
    except ImportError:
        return None
    envs = AtariVectorEnv("space_invaders", num_envs=n, batch_size=n, num_threads=n,
                          img_height=84, img_width=84, grayscale=True, stack_num=4,
                          frameskip=4, repeat_action_probability=0.25, maxpool=False,
                          noop_max=0, use_fire_reset=False)
    envs.reset(seed=0)
    return _batch_timer(envs.step, [np.full(n, action) for action in CYCLE])


def _envpool_row(rounds: int) -> int:
    """Ours, the native batch on as many cores as the machine has, against EnvPool with as
    many games and threads, and beside them ALE's own vector environment (where ale-py has
    one) and our games in Gymnasium's async vector; 1 if the goal is missed (0, said,
    without EnvPool)."""
    n = os.cpu_count() or 1
    theirs = _envpool_stepper(n)
    if theirs is None:
        print("   EnvPool not timed: not installed (pip install envpool; ALE in C++ threads)")
        return 0
    runs = {"ours (workers)": _vector_stepper("vector_entry_point", n, workers=n),
            "EnvPool": theirs}
    ale_vector = _ale_vector_stepper(n)
    if ale_vector is not None:
        runs["ALE's vector"] = ale_vector
    else:
        print("   ALE's vector not timed: ale-py 0.11 or newer has it (C++ threads)")
    runs["Gymnasium's async vector"] = _vector_stepper("async", n)
    return _batch_row(f"{n} games on {n} workers, 84x84 grey x4:", runs, n, rounds,
                      ENVPOOL_GOAL)


def _rates(runs: dict[str, Callable[[int], float]], rounds: int) -> dict[str, list[float]]:
    """Steps a second per round for each contender, taking turns."""
    counts = {who: max(1, int(ROUND_SECONDS / max(run(20) / 20, 1e-7)))
              for who, run in runs.items()}
    rates: dict[str, list[float]] = {who: [] for who in runs}
    order = list(runs)
    for index in range(rounds):
        for who in order if index % 2 == 0 else order[::-1]:
            rates[who].append(counts[who] / runs[who](counts[who]))
    return rates


def _figure(rates: list[float], unit: str = "steps/s") -> str:
    return (f"{statistics.median(rates):>7,.0f} {unit} "
            f"({min(rates):,.0f}..{max(rates):,.0f})")
