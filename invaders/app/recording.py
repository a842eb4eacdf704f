"""Recording a running game, and writing replay files, so that nothing recorded is lost.

A recording starts by writing the header (and the tick-0 checkpoint) atomically, then only
ever appends whole lines, each fsynced before the call returns (an append cut short, by a
full disk, is cut off again; one that finds another file at the name moves the recording,
whole, to a free name: `GrowingFile`): saving costs the same at tick 1,000,000 as at
tick 1,000, and a crash at any moment leaves a valid replay of a prefix (a line cut short
is ignored when read). Rewriting a whole replay (`--update`) is
atomic: a temporary file beside it, then a rename.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Protocol

from invaders.app.outputs import OutputError, writing
from invaders.atomic import GrowingFile, clean_stale, write_atomic
from invaders.game.config import GameConfig
from invaders.game.recording import ReplayRecorder
from invaders.game.replay import MAX_FILE_BYTES, Replay
from invaders.game.world import World
from invaders.quiet import say


class InputSource(Protocol):
    def actions(self, world: World) -> int: ...


class Recorder(ReplayRecorder):
    """Keeps a replay of a running world (`ReplayRecorder`), written to `path` if given:
    call `save()` whenever the file should catch up (it does every `save_every` ticks).

    Recording to a file keeps only what the next append needs (the lines not yet written),
    so its memory stays flat however long the game; without a file it keeps the whole
    replay (`finished()`). Where recording stops at the reader's limits, one line says
    so, and the file replays up to its last checkpoint. An autosave that fails raises
    (an OutputError), unless `on_failure` takes it: the lines not written are then kept
    for the next save."""

    def __init__(self, world: World, path: str | Path | None = None,
                 save_every: int = 180, config: GameConfig | None = None,
                 limit: int = MAX_FILE_BYTES,
                 on_failure: Callable[[OutputError], None] | None = None) -> None:
        super().__init__(world, config, limit, keep=path is None, lines=path is not None)
        self.path = path
        self.save_every = save_every
        self.on_failure = on_failure
        self._file: GrowingFile | None = None  # (from the first save)
        self._saved_ticks = 0  # ticks the file on disk holds

    def tick(self, bits: int) -> None:
        super().tick(bits)
        if self.path is not None and self.world.tick % self.save_every == 0:
            try:
                self.save()
            except OutputError as failure:
                if self.on_failure is None:
                    raise
                self.on_failure(failure)

    def _stop(self) -> None:
        """Said once, in one line."""
        super()._stop()
        where = f"{self.path}: " if self.path is not None else ""
        say(f"invaders: {where}{self.stopped}")

    def save(self) -> None:
        """Bring the file up to the current tick (call it between ticks only)."""
        if self.path is None:
            return
        self.finished()
        kept = (f"; the file keeps its first {self._saved_ticks} ticks, a valid replay"
                if self._file is not None else "")
        unsaved = self.unsaved or []
        try:
            with writing(self.path, "replay", kept):
                if self._file is None:
                    clean_stale(self.path)
                    self._file = GrowingFile(self.path, self.file_text())
                elif unsaved:
                    self._file.append("".join(unsaved))
        finally:
            self._follow()
        self.unsaved = []
        self._saved_ticks = self.ticks

    def _follow(self) -> None:
        """Where another file took the recording's name (or it was removed), the file
        has moved, whole, to a free name: said in one line, and recorded on there."""
        if self._file is not None and self.path is not None and (
                self._file.path != Path(self.path)):
            say(f"invaders: {self.path} was replaced or removed meanwhile, not by this "
                f"recording: it goes on, whole, in {self._file.path}")
            self.path = self._file.path


def save_replay(path: str | Path, replay: Replay) -> None:
    """Write a whole replay atomically: a reader sees the old file or the new one."""
    write_atomic(path, "".join(replay.lines()))


def record_headless(world: World, source: InputSource, ticks: int) -> Replay:
    """Play `ticks` ticks with an input source and return the replay of it."""
    recorder = Recorder(world)
    for _ in range(ticks):
        bits = source.actions(world)
        world.step(bits)
        recorder.tick(bits)
    return recorder.finished()
