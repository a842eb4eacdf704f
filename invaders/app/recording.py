"""Recording a running game, and writing replay files, so that nothing recorded is lost.

A recording starts by writing the header (and the tick-0 checkpoint) atomically, then only
ever appends whole lines, each flushed and fsynced before the call returns: saving costs the
same at tick 1,000,000 as at tick 1,000, and a crash at any moment leaves a valid replay of
a prefix (a line cut short is ignored when read). Rewriting a whole replay (`--update`) is
atomic: a temporary file beside it, then a rename.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any, Protocol

from invaders.app.outputs import writing
from invaders.atomic import clean_stale, write_atomic
from invaders.game.config import GameConfig
from invaders.game.replay import (
    CHECKPOINT_EVERY,
    MAX_FILE_BYTES,
    MAX_RUNS,
    MAX_SWITCHES,
    MAX_TICKS,
    Checkpoint,
    Replay,
    Switch,
    segment_line,
)
from invaders.game.world import World


class InputSource(Protocol):
    def actions(self, world: World) -> int: ...


class Recorder:
    """Keeps a replay of a running world: call `tick(bits)` after each whole step, and
    `save()` whenever the file should catch up (it does every `save_every` ticks).

    Recording to a file keeps only what the next append needs (the lines not yet written),
    so its memory stays flat however long the game; without a file it keeps the whole
    replay (`finished()`). A recording stays inside the limits its reader keeps: when the
    next checkpoint would take the file past `limit` bytes (or past the input runs, lab
    switches or ticks a replay may hold), recording stops there with one line saying so,
    and the file replays up to its last checkpoint."""

    def __init__(self, world: World, path: str | Path | None = None,
                 save_every: int = 180, config: GameConfig | None = None,
                 limit: int = MAX_FILE_BYTES) -> None:
        self.world = world
        self.path = path
        self.save_every = save_every
        self.limit = limit
        # The game's config; a lab that sped the projectiles up records that as a switch.
        self.replay = Replay(world.seed, config or world.config, players=world.players)
        first = Checkpoint.of(world)
        self._keep = path is None  # the whole replay, for whoever asks for it
        if self._keep:
            self.replay.checkpoints.append(first)
        self._segment: list[list[int]] = []  # input runs since the last checkpoint
        self._switches: list[Switch] = []  # lab switches since the last checkpoint
        self._unsaved: list[str] = [segment_line([], first)]
        self._bytes = len(self.replay.header_line()) + len(self._unsaved[0])  # in the file
        self._runs = 0  # input runs recorded
        self._switched = 0  # lab switches recorded
        self._first_tick = self._last_tick = world.tick  # the last checkpoint's tick
        self._started = False
        self._saved_ticks = 0  # ticks the file on disk holds
        self.stopped: str | None = None  # why recording stopped early, once it has

    @property
    def ticks(self) -> int:
        """Ticks recorded up to the last checkpoint: what the file replays once saved."""
        return self._last_tick - self._first_tick

    def tick(self, bits: int) -> None:
        if self.stopped is not None:
            return
        if self._keep:
            self.replay.append(bits)
        segment = self._segment
        if segment and segment[-1][0] == bits:
            segment[-1][1] += 1
        else:
            segment.append([bits, 1])
            self._runs += 1
        if self.world.tick % CHECKPOINT_EVERY == 0:
            self._checkpoint()
        if self.path is not None and self.world.tick % self.save_every == 0:
            self.save()

    def switch(self, choice: dict[str, Any]) -> None:
        """The lab's choice changed: it takes effect before the next step."""
        entry = (self.world.tick, dict(choice))
        if self._keep:
            self.replay.switches.append(entry)
        self._switches.append(entry)

    def _checkpoint(self) -> None:
        checkpoint = Checkpoint.of(self.world)
        line = segment_line(self._segment, checkpoint, self._switches)
        if (self._bytes + len(line) > self.limit or self._runs > MAX_RUNS
                or self._switched + len(self._switches) > MAX_SWITCHES
                or checkpoint.tick - self._first_tick > MAX_TICKS):
            self._stop()
            return
        if self._keep:
            self.replay.checkpoints.append(checkpoint)
        self._unsaved.append(line)
        self._bytes += len(line)
        self._last_tick = checkpoint.tick
        self._switched += len(self._switches)
        self._segment = []
        self._switches = []

    def _stop(self) -> None:
        """The limit reached: nothing more is recorded (the game goes on), said once."""
        self.stopped = (f"recording stopped at tick {self._last_tick}: a replay holds at most "
                        f"{self.limit:,} bytes, {MAX_RUNS:,} input runs, {MAX_SWITCHES:,} lab "
                        f"switches and {MAX_TICKS:,} ticks; the file replays up to there")
        where = f"{self.path}: " if self.path is not None else ""
        print(f"invaders: {where}{self.stopped}", file=sys.stderr)

    def finished(self) -> Replay:
        """The replay so far, closed with a checkpoint at the current tick (the whole of it
        when recording without a file; with one, the header's fields only)."""
        if self.stopped is None and self._last_tick != self.world.tick:
            self._checkpoint()
        return self.replay

    def save(self) -> None:
        """Bring the file up to the current tick (call it between ticks only)."""
        if self.path is None:
            return
        self.finished()
        kept = (f"; the file keeps its first {self._saved_ticks} ticks, a valid replay"
                if self._started else "")
        with writing(self.path, "replay", kept):
            if not self._started:
                clean_stale(self.path)
                write_atomic(self.path, self.replay.header_line() + "".join(self._unsaved))
                self._started = True
            elif self._unsaved:
                with open(self.path, "a", encoding="utf-8") as handle:
                    handle.write("".join(self._unsaved))
                    handle.flush()
                    os.fsync(handle.fileno())
        self._unsaved = []
        self._saved_ticks = self.ticks


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
