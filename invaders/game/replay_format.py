"""The replay format: its limits, the Replay, and the lines a version-2 file is made of.

Version 2 (what this program writes) is JSON Lines: a header line (format, version,
program, seed, config), then one line per checkpoint holding the input runs since the
previous checkpoint and the checkpoint itself, and, when the player switched the collision
method in the lab during them, each switch and the tick it took effect (what a switch means
is the lab's to say: the game only bounds it and hands it to whoever runs the replay). A
recorder only ever appends whole lines, so saving costs the same at any length; a last line
cut short (no newline: a write that was interrupted) is ignored, so a recording is always a
valid replay of a prefix. Version 1 (one JSON object holding everything) is still read.
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from invaders import __version__
from invaders.engine.adaptive import DEFAULT_BROADPHASE
from invaders.game.checkpoint import Checkpoint, Checkpoints
from invaders.game.config import GameConfig
from invaders.game.runs import Runs
from invaders.game.world import World

FORMAT = "invaders-replay"
VERSION = 2
READS = (1, 2)
CHECKPOINT_EVERY = 60
MAX_TICKS = 10_000_000  # 46 hours of play: anything longer is a damaged file
MAX_FILE_BYTES = 64 * 1024 * 1024  # about 8 million ticks of play
MAX_RUNS = 1_000_000  # input changes; a recorded game makes one every 7 to 12 ticks
MAX_DIGITS = 20  # the longest number a field holds (a 63-bit seed) has 19 digits
# Lab switches in a whole replay: each is a key pressed in the live lab (kept as objects,
# a few hundred bytes each, so the limit bounds what a file of them can make a reader hold).
MAX_SWITCHES = 10_000
MAX_SWITCH_FIELDS = 16
# Lines are bounded so that no parse of a structure not yet checked can be large: the
# header (a config of a few hundred fields) and each checkpoint's line (at most a
# checkpoint's worth of input runs, lab switches and the checkpoint). A version-1 file is
# one object holding everything: it is bounded as a whole (version 2 writes long games).
MAX_HEADER_BYTES = 16 * 1024
MAX_LINE_BYTES = 256 * 1024
MAX_V1_BYTES = 8 * 1024 * 1024
# A checkpoint line's fields, and its checkpoint's, in the order the program writes them.
LINE_FIELDS = ("inputs", "checkpoint")
CHECKPOINT_FIELDS = ("tick", "hash", "score", "ships", "wave", "counts", "groups")
HEADER_KEYS = frozenset({"format", "version", "program", "seed", "config", "players"})
V1_KEYS = HEADER_KEYS - {"players"} | {"ticks", "inputs", "checkpoints"}
Switch = tuple[int, dict[str, Any]]  # a lab choice, and the tick before whose step it began
# (\Z, not $: $ also matches before a newline at the end, which a JSON string may hold)
HASH = re.compile(r"[0-9a-f]{32}\Z")
GROUP_HASH = re.compile(r"[0-9a-f]{16}\Z")


class ReplayError(ValueError):
    """A replay file that cannot be used; the message names the problem."""


@dataclass
class Replay:
    """A game as a replay holds it: where it starts, every tick's input, its checkpoints."""

    seed: int
    config: GameConfig
    inputs: Runs = field(default_factory=Runs)  # (given as [bits, count] runs, or Runs)
    checkpoints: Checkpoints = field(default_factory=Checkpoints)
    program: str = f"invaders {__version__}"
    switches: list[Switch] = field(default_factory=list)  # lab choices, by tick
    players: int = 1  # the first game's (a later game's start button is in the inputs)

    def __post_init__(self) -> None:  # (kept packed: a long replay holds a million runs)
        if not isinstance(self.inputs, Runs):
            self.inputs = Runs(self.inputs)
        if not isinstance(self.checkpoints, Checkpoints):
            self.checkpoints = Checkpoints(self.checkpoints)

    @property
    def ticks(self) -> int:
        return self.inputs.ticks

    def actions(self) -> Iterator[int]:
        return self.inputs.actions()

    def append(self, bits: int) -> None:
        self.inputs.add(bits)

    def header_line(self) -> str:
        header = {"format": FORMAT, "version": VERSION, "program": self.program,
                  "seed": self.seed, "config": dataclasses.asdict(self.config)}
        if self.players != 1:  # (written only for two: one-player files are as they were)
            header["players"] = self.players
        return _line(header)

    def world(self, broadphase: str = DEFAULT_BROADPHASE) -> World:
        """The world this replay starts from."""
        return World(self.seed, self.config, broadphase=broadphase, players=self.players)

    def lines(self) -> Iterator[str]:
        """The whole replay in the current format, line by line."""
        yield self.header_line()
        start = 0
        runs = iter(self.inputs)
        pending: list[int] | None = None
        for checkpoint in self.checkpoints:
            segment: list[list[int]] = []
            need = checkpoint.tick - start
            while need > 0:
                if pending is None:
                    pending = list(next(runs))
                take = min(need, pending[1])
                segment.append([pending[0], take])
                pending[1] -= take
                need -= take
                if pending[1] == 0:
                    pending = None
            yield segment_line(segment, checkpoint,
                               [s for s in self.switches if start <= s[0] < checkpoint.tick])
            start = checkpoint.tick


def segment_line(runs: list[list[int]], checkpoint: Checkpoint,
                 switches: list[Switch] | tuple[()] = ()) -> str:
    """One line of a version-2 file: the input runs up to a checkpoint, the lab switches
    among them (if any), and the checkpoint."""
    data: dict[str, Any] = {"inputs": runs}
    if switches:
        data["lab"] = [[tick, choice] for tick, choice in switches]
    # Its fields as they are, written out at once (`dataclasses.asdict` copies each value
    # deeply: 28 against 1.2 us a checkpoint, a script).
    data["checkpoint"] = {field.name: getattr(checkpoint, field.name)
                          for field in dataclasses.fields(checkpoint)}
    return _line(data)


def _line(data: dict[str, Any]) -> str:
    return json.dumps(data, separators=(",", ":")) + "\n"

