"""Recording a running game, and writing replay files, so that nothing recorded is lost.

A recording starts by writing the header (and the tick-0 checkpoint) atomically, then only
ever appends whole lines, each flushed and fsynced before the call returns: saving costs the
same at tick 1,000,000 as at tick 1,000, and a crash at any moment leaves a valid replay of
a prefix (a line cut short is ignored when read). Rewriting a whole replay (`--update`) is
atomic: a temporary file beside it, then a rename.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Protocol

from invaders.atomic import clean_stale, write_atomic
from invaders.game.config import GameConfig
from invaders.game.replay import CHECKPOINT_EVERY, Checkpoint, Replay, Switch, segment_line
from invaders.game.world import World


class InputSource(Protocol):
    def actions(self, world: World) -> int: ...


class Recorder:
    """Keeps a replay of a running world: call `tick(bits)` after each whole step, and
    `save()` whenever the file should catch up (it does every `save_every` ticks)."""

    def __init__(self, world: World, path: str | Path | None = None,
                 save_every: int = 180, config: GameConfig | None = None) -> None:
        self.world = world
        self.path = path
        self.save_every = save_every
        # The game's config; a lab that sped the projectiles up records that as a switch.
        self.replay = Replay(world.seed, config or world.config)
        first = Checkpoint.of(world)
        self.replay.checkpoints.append(first)
        self._segment: list[list[int]] = []  # input runs since the last checkpoint
        self._switches: list[Switch] = []  # lab switches since the last checkpoint
        self._unsaved: list[str] = [segment_line([], first)]
        self._started = False

    def tick(self, bits: int) -> None:
        self.replay.append(bits)
        segment = self._segment
        if segment and segment[-1][0] == bits:
            segment[-1][1] += 1
        else:
            segment.append([bits, 1])
        if self.world.tick % CHECKPOINT_EVERY == 0:
            self._checkpoint()
        if self.path is not None and self.world.tick % self.save_every == 0:
            self.save()

    def switch(self, choice: dict[str, Any]) -> None:
        """The lab's choice changed: it takes effect before the next step."""
        entry = (self.world.tick, dict(choice))
        self.replay.switches.append(entry)
        self._switches.append(entry)

    def _checkpoint(self) -> None:
        checkpoint = Checkpoint.of(self.world)
        self.replay.checkpoints.append(checkpoint)
        self._unsaved.append(segment_line(self._segment, checkpoint, self._switches))
        self._segment = []
        self._switches = []

    def finished(self) -> Replay:
        """The replay so far, closed with a checkpoint at the current tick."""
        if self.replay.checkpoints[-1].tick != self.world.tick:
            self._checkpoint()
        return self.replay

    def save(self) -> None:
        """Bring the file up to the current tick (call it between ticks only)."""
        if self.path is None:
            return
        self.finished()
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
