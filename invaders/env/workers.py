"""Games stepped on several cores: the caller steps a share of them itself and each of its
worker processes another share, as the native batch does (`games.Games`), all writing into
arrays in shared memory. A step is the actions written there and a semaphore raised for
each worker; the caller steps its own share meanwhile, then waits on each worker's.

Waiting spins a moment before it sleeps: a process woken from sleep here starts a tenth of
a millisecond or more after it is signalled, which the pipes of a first version of this
pool paid twice a step (a 84x84 step of 2 games on 2 workers took about 720 us against
500 for one game's work). A worker spins at most SPIN_SECONDS after a step for the next,
on its own core, then sleeps.
"""

from __future__ import annotations

import multiprocessing
import pickle
import signal
import time
from collections.abc import Callable
from math import prod
from multiprocessing.connection import Connection
from multiprocessing.reduction import ForkingPickler
from typing import Any

import numpy as np
from gymnasium.error import ClosedEnvironmentError

from invaders.env.games import EVENT_COUNT, EVENTS_KEPT, Games, Rows
from invaders.game.events import Event

Specs = dict[str, tuple[tuple[int, ...], Any]]  # each shared array's shape and dtype
SPIN_SECONDS = 0.001  # how long a waiting process spins before it sleeps
ALIVE_CHECK = 1.0  # seconds between checks that a worker waited on is still running


def _specs(games: int, obs_shape: tuple[int, ...], obs_dtype: Any) -> Specs:
    """The rows' arrays, the actions', and a flag: 1 while the command the workers are
    told to do comes by pipe (anything but a step)."""
    return {**Rows.specs(games, obs_shape, obs_dtype), "actions": ((games,), np.int64),
            "piped": ((1,), np.uint8)}


def _views(raws: dict[str, Any], specs: Specs) -> tuple[Rows, np.ndarray, np.ndarray]:
    """The shared arrays as numpy arrays over their memory: the rows, the actions and the
    flag."""
    arrays = {name: np.frombuffer(raws[name], dtype, prod(shape)).reshape(shape)
              for name, (shape, dtype) in specs.items()}
    actions, piped = arrays.pop("actions"), arrays.pop("piped")
    return Rows(**arrays), actions, piped


def _share(rows: Rows, start: int, stop: int) -> Rows:
    return Rows(*(column[start:stop] for column in rows))


def _spin_then_take(semaphore: Any) -> bool:
    """Take the semaphore if it is raised within SPIN_SECONDS (spinning); False if not."""
    deadline = time.perf_counter() + SPIN_SECONDS
    while not semaphore.acquire(False):
        if time.perf_counter() > deadline:
            return False
    return True


def _told_to_go(go: Any) -> bool:
    """A worker's wait for the go (spinning a moment, then asleep); False if the caller's
    process has ended meanwhile, which it checks every ALIVE_CHECK seconds asleep (as the
    caller checks on its workers)."""
    if _spin_then_take(go):
        return True
    caller = multiprocessing.parent_process()
    while not go.acquire(timeout=ALIVE_CHECK):
        if caller is not None and not caller.is_alive():
            return False
    return True


class WorkerEnded(RuntimeError):
    """A worker process is gone (killed, or out of memory): its games with it."""


class _Worker:
    """The caller's end of one worker process: its pipe (commands other than a step, and
    what went wrong), and its two semaphores (go, and done)."""

    def __init__(self, ctx: Any, raws: dict[str, Any], specs: Specs, start: int, stop: int,
                 options: dict[str, Any]) -> None:
        self.conn, theirs = ctx.Pipe()
        self.go, self.done = ctx.Semaphore(0), ctx.Semaphore(0)
        self.process = ctx.Process(
            target=_work, args=(theirs, self.go, self.done, raws, specs, start, stop, options),
            name=f"invaders-games-{start}-{stop}", daemon=True)
        self.process.start()
        theirs.close()

    def send(self, message: bytes | None) -> None:
        """Go, with a command's message (pickled) unless it is a step: sent after the
        go, so that the worker reads it as it is written (one larger than a pipe holds
        would otherwise wait for a worker waiting for the go)."""
        self.go.release()
        if message is not None:
            try:
                self.conn.send_bytes(message)
            except OSError:  # (its end of the pipe closed: the process is gone)
                raise self.ended() from None

    def spilled(self) -> dict[int, list[int]]:
        """The events its games spilled this step (by game, counted among all the games),
        which it sends after its answer."""
        try:
            return self.conn.recv()
        except EOFError:
            raise self.ended() from None

    def results(self, answer: Any) -> list[Any]:
        """A call's results, which it sends after its answer (as spills: a message of any
        size), unless they came already, or it failed (none then)."""
        if isinstance(answer, str):
            return []
        if isinstance(answer, list):
            return answer
        try:
            return self.conn.recv()
        except EOFError:
            raise self.ended() from None

    def ended(self) -> WorkerEnded:
        self.process.join(timeout=ALIVE_CHECK)
        return WorkerEnded(f"a games worker ended (exit code {self.process.exitcode})")

    def answer(self) -> str | dict[int, list[int]] | list[Any] | None:
        """After a command: None, what went wrong in the worker, or after a step the
        events its games spilled if they came already (see `spilled`), after a call its
        results (see `results`)."""
        if not _spin_then_take(self.done):
            while not self.done.acquire(timeout=ALIVE_CHECK):
                if not self.process.is_alive():
                    raise self.ended()
        try:
            return self.conn.recv() if self.conn.poll() else None
        except EOFError:  # (nothing said: a worker told to close may have ended already)
            return None


class Pool:
    """`games` games with the same options in `workers` shares: the first stepped by the
    caller, each other on a worker process started with the multiprocessing context named
    (or the platform's default); `rows` are all of theirs, in shared memory."""

    def __init__(self, games: int, workers: int, options: dict[str, Any],
                 obs_shape: tuple[int, ...], obs_dtype: Any, context: str | None = None
                 ) -> None:
        ctx = multiprocessing.get_context(context)
        specs = _specs(games, obs_shape, obs_dtype)
        raws = {name: ctx.RawArray("B", prod(shape) * np.dtype(dtype).itemsize)
                for name, (shape, dtype) in specs.items()}
        self.rows, self._actions, self._piped = _views(raws, specs)
        (_, self._mine), *others = [(int(part[0]), int(part[-1]) + 1)
                                    for part in np.array_split(np.arange(games), workers)]
        self._shares = others
        self._workers = [_Worker(ctx, raws, specs, start, stop, options)
                         for start, stop in others]
        self._here = Games(self._mine, _share(self.rows, 0, self._mine), options)
        self.spilled: dict[int, list[int]] = {}  # the last step's, as `Games.spilled`
        self._waiting = False  # a command sent whose answers were not all taken
        self._closed = False
        try:
            self._ask("start", [None] * len(others))
        except RuntimeError:
            self.close()  # (no process left behind)
            raise

    def reset(self, seeds: list[int | None], which: list[bool] | None = None) -> None:
        """Every game anew, or those `which` names (as `Games.reset`)."""
        self._check_usable()
        which = [True] * len(seeds) if which is None else which
        self._ask("reset", [(seeds[start:stop], which[start:stop])
                            for start, stop in self._shares],
                  lambda: self._here.reset(seeds[:self._mine], which[:self._mine]))

    def step(self, actions: list[int]) -> None:
        self._check_usable()
        self._actions[:] = actions
        self._ask("step", [None] * len(self._workers),
                  lambda: self._here.step(actions[:self._mine]))

    def call(self, name: str, args: tuple[Any, ...], kwargs: dict[str, Any]) -> list[Any]:
        """`Games.call` on every game, in order: the workers' answers come by pipe."""
        self._check_usable()
        here: list[Any] = []
        answers = self._ask("call", [(name, args, kwargs)] * len(self._workers),
                            lambda: here.extend(self._here.call(name, args, kwargs)))
        return here + [result for answer in answers for result in answer]

    def set_attr(self, name: str, values: list[Any]) -> None:
        self._check_usable()
        self._ask("set_attr", [(name, values[start:stop]) for start, stop in self._shares],
                  lambda: self._here.set_attr(name, values[:self._mine]))

    def close(self) -> None:
        """Every game closed (an episode being recorded is written); the workers end. A
        worker that has ended already is let be (its failure was raised when it showed)."""
        self._end(self._here.close)

    def let_go(self) -> None:
        """As `close`, as the batch goes without one (dropped, or the program ending): the
        caller's games let go (`Games.let_go`: nothing raised), the workers' closed (which
        in a worker lets them go: `EpisodeRecorder.close`)."""
        self._end(self._here.let_go)

    def _end(self, own: Callable[[], None]) -> None:
        self._closed = True
        if not self._workers:
            return
        try:
            self._workers = [worker for worker in self._workers if worker.process.is_alive()]
            self._ask("close", [None] * len(self._workers), own)
        except WorkerEnded:
            pass  # (one ended meanwhile; a game's failure to close is raised)
        finally:
            for worker in self._workers:
                worker.conn.close()
                worker.process.join(timeout=5)
                if worker.process.is_alive():
                    worker.process.terminate()
            self._workers = []

    def _check_usable(self) -> None:
        """Refuse to go on once closed (the workers have ended, as Gymnasium's async vector
        does), or after a command whose answers were not all taken (Ctrl-C while waiting,
        say): a worker may still be writing, and its answer would be taken for the next
        command's."""
        if self._closed:
            raise ClosedEnvironmentError("the games' workers have ended at close(): make "
                                         "another vector")
        if self._waiting:
            raise RuntimeError("a step of the games was interrupted before every worker "
                               "answered: close this vector and make another")

    def _ask(self, command: str, arguments: list[Any], own: Any = None) -> list[Any]:
        """Each worker the command (with its argument), the caller's own share done
        meanwhile, then each worker's answer; the first failure raised. After a call,
        each worker's results. (Steps and resets check first that the last command was
        answered.)"""
        # (every message pickled before any worker is told: one that cannot be fails here)
        messages = [None if command == "step" else _message(command, argument)
                    for argument in arguments]
        self._waiting = True
        self._piped[0] = command != "step"
        for worker, message in zip(self._workers, messages, strict=True):
            worker.send(message)
        try:
            if own is not None:
                own()
        finally:  # (every answer taken, spills and results too, so none is left over)
            answers = [worker.answer() for worker in self._workers]
            spilled = self._spills(answers) if command == "step" else {}
            results = [worker.results(answer) for worker, answer
                       in zip(self._workers, answers, strict=True)] if command == "call" else []
            self._waiting = False
        failures = [answer for answer in answers if isinstance(answer, str)]
        if failures:
            raise RuntimeError(f"a games worker failed: {failures[0]}")
        self.spilled = {i: list(events) for i, events in self._here.spilled.items()}
        self.spilled.update(spilled)
        return results

    def _spills(self, answers: list[Any]) -> dict[int, list[int]]:
        """The events the workers' games spilled this step: a worker sends them after its
        answer (a message of any size would wait on a caller still waiting for the
        answer), where its games' rows count more than they keep."""
        counts = self.rows.numbers[:, EVENT_COUNT]
        spilled: dict[int, list[int]] = {}
        for worker, (start, stop), answer in zip(self._workers, self._shares, answers,
                                                 strict=True):
            if isinstance(answer, dict):
                spilled.update(answer)
            elif answer is None and counts[start:stop].max() > EVENTS_KEPT:
                spilled.update(worker.spilled())
        return spilled


def _message(command: str, argument: Any) -> bytes:
    """A command's message to a worker, pickled; one that cannot be is refused with a
    PicklingError naming the command (Python's own error is of another type and says
    another thing from one version to the next: up to 3.13 an AttributeError for a local
    function, saying in 3.13 only that it "can't get" it)."""
    try:
        return bytes(ForkingPickler.dumps((command, argument)))
    except (pickle.PicklingError, AttributeError, TypeError) as error:
        raise pickle.PicklingError(f"{command}: what it gives cannot be pickled to go to a "
                                   f"worker process ({error})") from error


def _work(conn: Connection, go: Any, done: Any, raws: dict[str, Any], specs: Specs,
          start: int, stop: int, options: dict[str, Any]) -> None:
    """A worker: its share of the games, stepped each time it is told to go, until told to
    close, or until the caller's process is gone (killed: no close will come),
    when it lets its games go itself (their episodes in progress written, or said lost) and
    ends. Ctrl-C is the caller's to handle (it closes the workers)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    rows, actions, piped = _views(raws, specs)
    games: Games | None = None
    while True:
        if not _told_to_go(go):
            if games is not None:
                games.let_go()
            return
        argument: Any  # (the command's: a reset's seeds and which games)
        command, argument = conn.recv() if piped[0] else ("step", None)
        spilled: dict[int, list[Event]] = {}
        results: Any = None  # (a call's, pickled here: one that cannot be is its failure)
        try:
            if command == "start":
                games = Games(stop - start, _share(rows, start, stop), options)
            elif command == "step" and games is not None:
                games.step(actions[start:stop].tolist())
                spilled = games.spilled  # (events past what the rows keep: rare)
            elif command == "reset" and games is not None:
                games.reset(*argument)
            elif command == "call" and games is not None:
                results = ForkingPickler.dumps(games.call(*argument))
            elif command == "set_attr" and games is not None:
                games.set_attr(*argument)
            elif command == "close" and games is not None:
                games.close()  # (what it cannot write is said lost: the worker ends)
        except Exception as error:  # (said to the caller, which raises it)
            conn.send(f"{type(error).__name__}: {error}")
        done.release()
        if spilled:  # (after the answer: the caller takes them, its rows saying so)
            conn.send({start + i: [int(event) for event in events]
                       for i, events in spilled.items()})
        if results is not None:  # (after the answer too: the caller takes them)
            conn.send_bytes(results)
        if command == "close":
            return
