"""An environment's episodes written as replays (`record=FOLDER`), each once and none lost.

An episode is written when it ends, or when the next one begins, or at `close`; and, for a
script that never closes its environment (stopped by Ctrl-C or an error, or simply done),
when the environment is dropped or the program ends: a finalizer (`weakref.finalize`)
writes the episode in progress then, as `close` would (not in a process killed by a
signal, which runs nothing more). Each file is written whole under a name no other file
has (`write_new`): a reader never sees a torn one, and none is written over.
"""

from __future__ import annotations

import os
import tempfile
import weakref
from pathlib import Path

from invaders.atomic import write_new
from invaders.game.replay import CHECKPOINT_EVERY, Checkpoint, Replay
from invaders.game.world import World


class EpisodeRecorder:
    """The episode being recorded (its replay, and the world it is of) and the episodes
    written so far, into one folder."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.replay: Replay | None = None  # None between episodes, once one is written
        self.world: World | None = None
        self.written = 0

    @classmethod
    def into(cls, record: str | Path | None) -> EpisodeRecorder | None:
        """A recorder for the folder `record` names, made now and tried with a file
        written and removed, so a folder that cannot take episodes fails here (an OSError
        naming it), not after the first episode's play; None: no recording."""
        if record is None:
            return None
        if not str(record):
            raise ValueError("record '': a folder to write episodes in, or None")
        folder = Path(record)
        folder.mkdir(parents=True, exist_ok=True)
        fd, tried = tempfile.mkstemp(prefix=".episode.", dir=folder)
        os.close(fd)
        os.unlink(tried)
        return cls(folder)

    def watch(self, owner: object) -> None:
        """Write the episode in progress when `owner` (the environment recording) is
        dropped, or when the program ends with it still there, unless written by then."""
        weakref.finalize(owner, self.save)  # (holds the recorder, never the owner)

    def begin(self, world: World) -> None:
        """A new episode of `world` (the last one written first, if it was not)."""
        self.save()
        self.world, self.replay = world, Replay(world.seed, world.config)
        self.replay.checkpoints.append(Checkpoint.of(world))

    def follow(self, world: World, replay: Replay | None) -> None:
        """Record on from a state gone back to: its world and its recording so far (the
        episode in progress is dropped, not written: a search's every try would be)."""
        self.world, self.replay = world, replay

    def note(self, bits: int) -> None:
        """The tick just played with these input bits, with a checkpoint where the format
        keeps one."""
        replay, world = self.replay, self.world
        if replay is None or world is None:  # (a state gone back to that was not recorded)
            return
        replay.append(bits)
        if world.tick % CHECKPOINT_EVERY == 0:
            replay.checkpoints.append(Checkpoint.of(world))

    def save(self) -> None:
        """Write the episode played so far (once; nothing if no tick was played)."""
        replay, world = self.replay, self.world
        self.replay = None
        if replay is None or world is None or not replay.ticks:
            return
        if replay.checkpoints[-1].tick != world.tick:
            replay.checkpoints.append(Checkpoint.of(world))
        self.written += 1
        name = f"episode-{self.written:05d}-seed-{replay.seed}.json"
        write_new(self.folder / name, "".join(replay.lines()))  # (never over another's)
