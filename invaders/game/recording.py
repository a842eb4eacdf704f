"""A running world's replay, kept as it is played, inside the limits a replay's reader keeps:
what the window's and the headless runs' recordings (`invaders.app.recording`) and the
environment's recorded episodes (`invaders.env.recording`) are made of."""

from __future__ import annotations

import copy
from typing import Any

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


class ReplayRecorder:
    """Keeps a replay of a running world: call `tick(bits)` after each whole step (and
    `switch(choice)` when the lab's choice changes); `finished()` gives the replay closed
    at the current tick.

    Each checkpoint's line of the file is made as the checkpoint is reached, to count the
    file's bytes. With `lines` they are kept (`unsaved`) until the caller has written them
    and empties the list, for a file written as the game goes, and with `keep=False` the
    replay itself is not kept, so that memory stays flat however long the game. A
    recording stays inside the limits its reader keeps: when the next checkpoint would
    take the file past `limit` bytes (or past the input runs, lab switches or ticks a
    replay may hold), recording stops there (`stopped` says so) and the replay ends at its
    last checkpoint; the game goes on."""

    def __init__(self, world: World, config: GameConfig | None = None,
                 limit: int = MAX_FILE_BYTES, keep: bool = True, lines: bool = False) -> None:
        self.world = world
        self.limit = limit
        # The game's config; a lab that sped the projectiles up records that as a switch.
        self.replay = Replay(world.seed, config or world.config, players=world.players)
        first = Checkpoint.of(world)
        self._keep = keep  # the whole replay, for whoever asks for it
        if keep:
            self.replay.checkpoints.append(first)
        self._segment: list[list[int]] = []  # input runs since the last checkpoint
        self._switches: list[Switch] = []  # lab switches since the last checkpoint
        line = segment_line([], first)
        self.unsaved: list[str] | None = [line] if lines else None  # (None: not kept)
        self._bytes = len(self.replay.header_line()) + len(line)  # in the file
        self._runs = 0  # input runs recorded
        self._switched = 0  # lab switches recorded
        self._first_tick = self._last_tick = world.tick  # the last checkpoint's tick
        self.stopped: str | None = None  # why recording stopped early, once it has

    def __deepcopy__(self, memo: dict[int, Any]) -> ReplayRecorder:
        """A recording that goes on apart from this one, of the world's copy (through the
        memo: copied with its world, it records that copy). Its lists are its own (the
        replay, the runs and switches since the last checkpoint, the lines unsaved); every
        other field a number, a string, a path or a config, never changed in place (a test
        fails with any list shared). Field by field, where a generic copy went through
        every field and each item of its lists: an environment's state with its recording
        (its lines) cloned and restored in 334 against 383 us at the episode's 400th
        frame, 345 against 1,041 with 1,667 checkpoints' lines (9 rounds in turn, fresh
        processes)."""
        clone = copy.copy(self)
        memo[id(self)] = clone
        clone.world = copy.deepcopy(self.world, memo)
        clone.replay = copy.deepcopy(self.replay, memo)
        clone._segment = [list(run) for run in self._segment]
        clone._switches = copy.deepcopy(self._switches, memo)
        clone.unsaved = None if self.unsaved is None else list(self.unsaved)
        return clone

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

    def switch(self, choice: dict[str, Any]) -> None:
        """The lab's choice changed: it takes effect before the next step."""
        entry = (self.world.tick, dict(choice))
        if self._keep:
            self.replay.switches.append(entry)
        self._switches.append(entry)

    def finished(self) -> Replay:
        """The replay so far, closed with a checkpoint at the current tick (the whole of it
        when kept; else the header's fields only)."""
        if self.stopped is None and self._last_tick != self.world.tick:
            self._checkpoint()
        return self.replay

    def cut_off(self) -> None:
        """A step was cut off inside a tick (an exception raised in it: Ctrl-C, say), where
        the world may stand half moved and no checkpoint can be made: the replay ends at its
        last checkpoint, where the state was whole, and nothing more is recorded."""
        if self.stopped is None:
            self.stopped = (f"recording stopped at tick {self._last_tick}, its last "
                            "checkpoint: a step after it was cut off inside a tick")

    def file_text(self) -> str:
        """The header and the lines not yet written (with `lines`): the whole file, while
        none of it has been written."""
        return self.replay.header_line() + "".join(self.unsaved or [])

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
        if self.unsaved is not None:
            self.unsaved.append(line)
        self._bytes += len(line)
        self._last_tick = checkpoint.tick
        self._switched += len(self._switches)
        self._segment = []
        self._switches = []

    def _stop(self) -> None:
        """The limit reached: nothing more is recorded (the game goes on)."""
        self.stopped = (f"recording stopped at tick {self._last_tick}: a replay holds at most "
                        f"{self.limit:,} bytes, {MAX_RUNS:,} input runs, {MAX_SWITCHES:,} lab "
                        f"switches and {MAX_TICKS:,} ticks; the file replays up to there")
