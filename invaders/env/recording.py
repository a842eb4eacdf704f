"""An environment's episodes written as replays (`record=FOLDER`), each once and none lost.

An episode is written when it ends, or when the next one begins, or at `close`; and, for a
script that never closes its environment (stopped by Ctrl-C or an error, or simply done),
when the environment is dropped or the program ends: a finalizer (`weakref.finalize`)
writes the episode in progress then, as `close` would (not in a process killed by a
signal, which runs nothing more; SIGTERM ends a worker process as an exit does:
`exit_on_sigterm`). An episode whose step was cut off inside a frame (Ctrl-C) is written
up to its last checkpoint, where the game's state was whole. Each file is written whole
under a name no other file has (`write_new`): a reader never sees a torn one, and none is
written over. An episode whose file cannot be written (a full disk, a folder gone) is
kept, with a warning, and written with the next one or at `close`, which raises if it
still cannot be (kept while the process runs); as the environment goes without a close
that wrote it, or closes in a vector's worker process, which ends with it, it is lost, and
a warning says so. An
episode is recorded as the window's games are (`ReplayRecorder`), inside the limits a
replay's reader keeps: past them (an episode without a frame limit, hours of play long),
its recording stops, with a warning, and its file replays up to there.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import tempfile
import threading
import warnings
import weakref
from collections.abc import Callable
from pathlib import Path

from invaders.atomic import write_new
from invaders.game.recording import ReplayRecorder
from invaders.game.replay import MAX_FILE_BYTES
from invaders.game.world import World


class EpisodeRecording(ReplayRecorder):
    """One episode's recording, kept as its file's lines (each made once, as its checkpoint
    is reached, where a replay kept would be made into lines again when written): where
    it stops at a replay's limits, a warning says so."""

    def __init__(self, world: World, folder: Path, limit: int) -> None:
        super().__init__(world, limit=limit, keep=False, lines=True)
        self.folder = folder

    def _stop(self) -> None:
        super()._stop()
        warnings.warn(f"invaders: an episode recorded in {self.folder}: {self.stopped}",
                      RuntimeWarning, stacklevel=2)


class EpisodeRecorder:
    """The episode being recorded and the episodes written so far, into one folder;
    `limit`: the bytes a file may take (a replay's limit)."""

    def __init__(self, folder: Path, limit: int = MAX_FILE_BYTES) -> None:
        self.folder = folder
        self.limit = limit
        self.current: EpisodeRecording | None = None  # (None between episodes)
        self.ended = 0  # episodes ended with play in them: their files' numbers
        # Ended episodes not yet written (the write failed), in order: each file's path and text.
        self.unwritten: list[tuple[Path, str]] = []

    @classmethod
    def into(cls, record: str | Path | None) -> EpisodeRecorder | None:
        """A recorder for the folder `record` names, made now and tried with a file
        written and removed, so a folder that cannot take episodes fails here (an OSError
        naming it), not after the first episode's play; None: no recording."""
        if record is None:
            return None
        if not isinstance(record, (str, os.PathLike)) or not str(record):
            raise ValueError(f"record {record!r}: a folder to write episodes in, or None")
        folder = Path(record)
        if folder.exists() and not folder.is_dir():  # (mkdir's word for it: "File exists")
            raise NotADirectoryError(f"record '{folder}' is there and is not a folder: the "
                                     "episodes are written into a folder")
        folder.mkdir(parents=True, exist_ok=True)
        fd, tried = tempfile.mkstemp(prefix=".episode.", dir=folder)
        os.close(fd)
        os.unlink(tried)
        return cls(folder)

    def watch(self, owner: object) -> None:
        """Write the episode in progress when `owner` (the environment recording) is
        dropped, or when the program ends with it still there, unless written by then; in
        a worker process, when it is ended by SIGTERM too."""
        on_drop(owner, self.let_go)
        exit_on_sigterm()

    def begin(self, world: World) -> None:
        """A new episode of `world` (the last one written first, if it was not)."""
        self.save()
        self.current = EpisodeRecording(world, self.folder, self.limit)

    def follow(self, recording: EpisodeRecording | None) -> None:
        """Record on from a state gone back to: its recording so far, of its world (the
        episode in progress is dropped, not written: a search's every try would be), into
        this folder (a state may be another environment's)."""
        if recording is not None:
            recording.folder = self.folder
        self.current = recording

    def keep_to(self, world: World) -> None:
        """Before a step of `world`: the recording in progress is of it. A reset or a
        restore cut off (Ctrl-C) between the environment's new world and its recording may
        leave them apart, or the world without one, and a tick of one noted in the other
        would make a file that does not replay: the recording is then ended and written as
        it stands, and a world at its start begins one of its own (a world restored past
        its start, without its recording, plays unrecorded)."""
        current = self.current
        if current is not None and current.world is world:
            return
        if world.tick == 0:
            self.begin(world)
        elif current is not None:
            self.save()

    def note(self, bits: int) -> None:
        """The tick just played, with these input bits."""
        if self.current is not None:  # (None: a state gone back to that was not recorded)
            self.current.tick(bits)

    def cut_off(self) -> None:
        """A step was cut off inside a tick: the episode's file ends at its last checkpoint
        (`ReplayRecorder.cut_off`)."""
        if self.current is not None:
            self.current.cut_off()

    def save(self) -> None:
        """End the episode played so far (nothing if no tick was recorded) and write it,
        after any not written before; one that cannot be written (no room, say) is kept,
        with those after it, for the next try, and a warning says so (once an episode)."""
        ended = self._end()
        failure = self._write()
        if failure is not None and ended:
            warnings.warn(f"{self._unwritten_said(failure)}: kept, and written when the next "
                          "episode ends or at close()", RuntimeWarning, stacklevel=2)

    def close(self) -> None:
        """Save; raise the OSError if an episode still cannot be written (kept: another
        close may write it). Not in a child process: there the environment is a vector's
        worker's (Gymnasium's async vector's, the native batch's), which ends with its
        close, so no other can come, and one that raised would print a traceback there:
        the recorder lets go instead (`let_go`: what it cannot write is said lost)."""
        if multiprocessing.parent_process() is not None:
            self.let_go()
            return
        self._end()
        failure = self._write()
        if failure is not None:
            raise OSError(failure.errno, f"{self._unwritten_said(failure)}: kept while "
                          "this process runs, for a close() once the folder can take them")

    def let_go(self) -> None:
        """Save as the environment goes without a close (dropped, or the program ending),
        the last try: what cannot be written now is lost, and a warning says so (nothing
        raised: no one is there to catch it)."""
        self._end()
        failure = self._write()
        if failure is not None:
            warnings.warn(f"{self._unwritten_said(failure)}: lost with the environment",
                          RuntimeWarning, stacklevel=2)
            self.unwritten = []

    def _end(self) -> bool:
        """The episode in progress ended and put to be written: whether there was one with
        play in it."""
        recording, self.current = self.current, None
        if recording is None:
            return False
        recording.finished()  # (closed with a checkpoint where it stands)
        if not recording.ticks:
            return False
        self.ended += 1
        name = f"episode-{self.ended:05d}-seed-{recording.replay.seed}.json"
        self.unwritten.append((self.folder / name, recording.file_text()))
        return True

    def _write(self) -> OSError | None:
        """Every ended episode written in turn: the failure that stopped it, if one did."""
        while self.unwritten:
            path, text = self.unwritten[0]
            try:
                write_new(path, text)  # (never over another's)
            except OSError as failure:
                return failure
            del self.unwritten[0]
        return None

    def _unwritten_said(self, failure: OSError) -> str:
        """How many, where, which files (the batch's games' say each their own), and why."""
        names = [path.name for path, _ in self.unwritten]
        count, which = len(names), " to ".join(dict.fromkeys((names[0], names[-1])))
        return (f"invaders: {count} episode{'s' if count > 1 else ''} recorded not written "
                f"in {self.folder} ({which}: {failure.strerror or failure})")


def exit_on_sigterm() -> None:
    """In a child process, SIGTERM raises SystemExit instead of ending the process at once:
    Gymnasium's async vector ends its workers by SIGTERM when it is dropped unclosed or the
    program ends, and a worker ending by SystemExit closes its game (its own `finally`),
    writing the episode in progress. Not in the main process, whose signals are its
    program's, nor where the process has a SIGTERM handler of its own, nor outside its
    main thread (where none can be set)."""
    if (multiprocessing.parent_process() is None
            or threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL):
        return
    signal.signal(signal.SIGTERM, _exit)


def _exit(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)  # (as a shell reports a signal: 143)


def on_drop(owner: object, callback: Callable[[], None]) -> None:
    """Call `callback` when `owner` is dropped, or when the program ends with it still
    there (`weakref.finalize`; the callback must not hold the owner), in this process
    only: a process forked from this one has a copy of its finalizers, and must neither
    write this process's episodes again nor close its games."""
    pid = os.getpid()

    def in_this_process() -> None:
        if os.getpid() == pid:
            callback()

    weakref.finalize(owner, in_this_process)
