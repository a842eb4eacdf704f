"""Replays: the format, reading it with every field bounded, and checking a replay headless.

A replay holds the seed and rule configuration, the input bits of every tick run-length
encoded, and checkpoints (every 60 ticks and at the end) with the state hash, score, ships,
wave, body counts and one digest per state group, so a replay that goes wrong says where
first and what.

Version 2 (what this program writes) is JSON Lines: a header line (format, version,
program, seed, config), then one line per checkpoint holding the input runs since the
previous checkpoint and the checkpoint itself, and, when the player switched the collision
method in the lab during them, each switch and the tick it took effect (what a switch means
is the lab's to say: the game only bounds it and hands it to whoever runs the replay). A
recorder only ever appends whole lines, so
saving costs the same at any length; a last line cut short (no newline: a write that was
interrupted) is ignored, so a recording is always a valid replay of a prefix. Version 1 (one
JSON object holding everything) is still read. Reading never trusts a number before it has
checked it: the file's size, each line's length, each integer's digits, the count of input
runs and the ticks they cover are bounded while reading. A file is read a block of lines at a
time and kept packed (checkpoint.py, runs.py), so a replay at the size limit takes memory in
proportion to what it means; lines in exactly the shape this program writes are read by the
block (canonical.py), any other through the JSON parser, with the same result. Writing files
is the application's (recording.py).
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import os
import re
import stat
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO

from invaders import __version__
from invaders.engine.adaptive import DEFAULT_BROADPHASE
from invaders.game import canonical
from invaders.game.actions import ALL_ACTIONS
from invaders.game.checkpoint import COUNT_NAMES, Checkpoint, Checkpoints
from invaders.game.config import ConfigError, GameConfig
from invaders.game.runs import Runs
from invaders.game.statehash import GROUPS, combine
from invaders.game.world import World

FORMAT = "invaders-replay"
VERSION = 2
READS = (1, 2)
CHECKPOINT_EVERY = 60
MAX_TICKS = 10_000_000  # 46 hours of play: anything longer is a damaged file
MAX_FILE_BYTES = 64 * 1024 * 1024  # about 8 million ticks of play
MAX_RUNS = 1_000_000  # input changes; a recorded game makes one every 7 to 12 ticks
MAX_DIGITS = 20  # the longest number a field holds (a 63-bit seed) has 19 digits
MAX_SWITCHES = 1000  # lab switches in one line: a person presses keys a few times a second
MAX_SWITCH_FIELDS = 16
# Lines are bounded so that no parse of a structure not yet checked can be large: the
# header (a config of a few hundred fields) and each checkpoint's line (at most a
# checkpoint's worth of input runs, lab switches and the checkpoint). A version-1 file is
# one object holding everything: it is bounded as a whole (version 2 writes long games).
MAX_HEADER_BYTES = 16 * 1024
MAX_LINE_BYTES = 256 * 1024
MAX_V1_BYTES = 8 * 1024 * 1024
HEADER_KEYS = frozenset({"format", "version", "program", "seed", "config", "players"})
V1_KEYS = HEADER_KEYS - {"players"} | {"ticks", "inputs", "checkpoints"}
Switch = tuple[int, dict[str, Any]]  # a lab choice, and the tick before whose step it began
HASH = re.compile(r"^[0-9a-f]{32}$")
GROUP_HASH = re.compile(r"^[0-9a-f]{16}$")


class ReplayError(ValueError):
    """A replay file that cannot be used; the message names the problem."""


@dataclass
class Replay:
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
    data["checkpoint"] = dataclasses.asdict(checkpoint)
    return _line(data)


def _line(data: dict[str, Any]) -> str:
    return json.dumps(data, separators=(",", ":")) + "\n"


# --- reading and validating -----------------------------------------------------------------
def _need(cond: bool, problem: str) -> None:
    if not cond:
        raise ReplayError(problem)


def _shown(value: Any, most: int = 40) -> str:
    """A value from the file as an error quotes it: its first characters, never all of it
    (a field may hold megabytes)."""
    if isinstance(value, (list, dict)):
        return f"a {type(value).__name__} of {len(value):,} items"
    text = repr(value)
    return text if len(text) <= most else f"{text[:most]}... ({len(text):,} characters)"


def _int(value: Any, name: str, low: int = 0, high: int = 2**63 - 1) -> int:
    _need(type(value) is int, f"{name} must be a whole number")
    _need(low <= value <= high, f"{name} {_shown(value)} is out of range {low}..{high}")
    return value


# Config fields added after files were first written: a file without one was recorded by a
# program that had the default value written into its code, so the default is what it meant.
ADDED_LATER: dict[str, frozenset[str]] = {
    "config.geometry": frozenset({"saucer_start_left", "saucer_start_right",
                                  "saucer_exit_left", "saucer_exit_right", "cannon_centre",
                                  "bomb_drop_offset", "shot_burst_offset",
                                  "bomb_burst_offset", "ground_burst_offset"}),
}


def _config(data: Any, cls: type = GameConfig, name: str = "config") -> Any:
    """Rebuild a frozen config dataclass, checking every field's type, then its range."""
    _need(isinstance(data, dict), f"{name} must be an object")
    defaults = cls()
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(str(k) for k in set(data) - set(fields))
    if unknown:
        raise ReplayError(f"{name} has unknown field {_shown(unknown[0])}")
    values = {}
    for key in fields:
        if key not in data and key in ADDED_LATER.get(name, ()):
            values[key] = getattr(defaults, key)
            continue
        _need(key in data, f"{name} lacks field {key!r}")
        default = getattr(defaults, key)
        value = data[key]
        where = f"{name}.{key}"
        if dataclasses.is_dataclass(default):
            values[key] = _config(value, type(default), where)
        elif isinstance(default, tuple):
            _need(isinstance(value, list) and len(value) <= 64,
                  f"{where} must be a list of at most 64 numbers")
            values[key] = tuple(_int(v, where, -2**63) for v in value)
        else:  # (a size check here; the config itself checks each field's range)
            values[key] = _int(value, where, -2**63)
    try:
        return cls(**values)
    except ConfigError as err:  # names the field, its value and its range
        raise ReplayError(str(err)) from None


def _checkpoint(data: Any, where: str, ticks: int) -> Checkpoint:
    _need(isinstance(data, dict), f"{where} must be an object")
    keys = {"tick", "hash", "score", "ships", "wave", "counts", "groups"}
    _need(set(data) == keys, f"{where} must have exactly the fields {sorted(keys)}")
    tick = _int(data["tick"], f"{where} tick", 0, ticks)
    _need(isinstance(data["hash"], str) and bool(HASH.match(data["hash"])),
          f"{where} hash is not 32 lower-case hex digits")
    counts = data["counts"]
    _need(isinstance(counts, dict) and set(counts) == set(COUNT_NAMES),
          f"{where} counts must name exactly {', '.join(sorted(COUNT_NAMES))}")
    groups = data["groups"]
    _need(isinstance(groups, dict) and set(groups) == set(GROUPS),
          f"{where} groups must name exactly {', '.join(GROUPS)}")
    for name, digest in groups.items():
        _need(isinstance(digest, str) and bool(GROUP_HASH.match(digest)),
              f"{where} group {name} is not 16 lower-case hex digits")
    _need(combine(groups) == data["hash"], f"{where}: hash does not match its groups")
    return Checkpoint(tick, data["hash"], _int(data["score"], f"{where} score"),
                      _int(data["ships"], f"{where} ships"), _int(data["wave"], f"{where} wave"),
                      {k: _int(v, f"{where} count {k}") for k, v in counts.items()},
                      dict(groups))


def _runs(inputs: Any, where: str, total: int, runs: Runs) -> int:
    """Append checked input runs; returns the ticks covered so far (bounded while reading)."""
    _need(isinstance(inputs, list), f"{where} inputs must be a list of [bits, count] runs")
    _need(len(runs) + len(inputs) <= MAX_RUNS, f"more than {MAX_RUNS} input runs")
    for i, run in enumerate(inputs):
        name = f"{where} input run {i}"
        _need(isinstance(run, list) and len(run) == 2, f"{name} must be [bits, count]")
        bits = _int(run[0], f"{name} bits")
        _need(bits & ~ALL_ACTIONS == 0, f"{name} has unknown action bits {bits:#x}")
        count = _int(run[1], f"{name} count", 1, MAX_TICKS)
        total += count
        _need(total <= MAX_TICKS, f"inputs run past {MAX_TICKS} ticks")
        runs.add(bits, count)
    return total


def _switches(listed: Any, where: str, start: int, end: int, out: list[Switch]) -> None:
    """Append checked lab switches: [tick, {name: word or number}], ticks in the line's
    span and increasing (their meaning is checked by whoever applies them)."""
    _need(isinstance(listed, list) and 0 < len(listed) <= MAX_SWITCHES,
          f"{where} lab must be a list of 1 to {MAX_SWITCHES} [tick, choice] switches")
    for i, item in enumerate(listed):
        name = f"{where} lab switch {i}"
        _need(isinstance(item, list) and len(item) == 2, f"{name} must be [tick, choice]")
        tick = _int(item[0], f"{name} tick", start, max(start, end - 1))
        _need(not out or out[-1][0] <= tick, f"{name}: switch ticks must not decrease")
        choice = item[1]
        _need(isinstance(choice, dict) and len(choice) <= MAX_SWITCH_FIELDS,
              f"{name} choice must be an object of at most {MAX_SWITCH_FIELDS} fields")
        for key, value in choice.items():
            _need(len(key) <= 32, f"{name} has a field name longer than 32 characters")
            _need((type(value) is str and len(value) <= 32) or type(value) is int,
                  f"{name} field {key!r} must be a short word or a whole number")
            if type(value) is int:
                _int(value, f"{name} field {key!r}", -(2**31), 2**31)
        out.append((tick, dict(choice)))


def _header(data: Any) -> tuple[int, int, GameConfig, str]:
    """(version, seed, config, program) from a file's first object."""
    _need(isinstance(data, dict), "the file must hold a JSON object")
    _need(data.get("format") == FORMAT,
          f"format must be {FORMAT!r}, not {_shown(data.get('format'))}")
    version = data.get("version")
    _need(type(version) is int and version in READS,
          f"version {_shown(version)} is not supported (this program reads "
          f"{' and '.join(map(str, READS))})")
    for key in ("program", "seed", "config"):
        _need(key in data, f"field {key!r} is missing")
    unknown = sorted(str(k) for k in set(data) - (V1_KEYS if version == 1 else HEADER_KEYS))
    _need(not unknown, f"unknown field {_shown(unknown[0]) if unknown else ''}")
    _need(isinstance(data["program"], str) and len(data["program"]) <= 200,
          "program must be a string of at most 200 characters")
    return version, _int(data["seed"], "seed"), _config(data["config"]), data["program"]


def _players(header: dict[str, Any]) -> int:
    """How many players the recorded world starts with (1 when the header does not say)."""
    players = header.get("players", 1)
    _need(type(players) is int and players in (1, 2),
          f"players must be 1 or 2, not {_shown(players)}")
    return players


def _finish(seed: int, config: GameConfig, runs: Runs, checkpoints: Checkpoints,
            ticks: list[int], program: str, total: int, switches: list[Switch] | None = None,
            players: int = 1) -> Replay:
    """The replay, once its checkpoints' `ticks` are known to increase up to the last."""
    _need(bool(ticks), "there is no checkpoint")
    _need(all(a < b for a, b in itertools.pairwise(ticks)),
          "checkpoint ticks must strictly increase")
    _need(ticks[-1] == total, "the last checkpoint must be at the last tick")
    return Replay(seed, config, runs, checkpoints, program, switches or [], players)


def parse(data: Any) -> Replay:
    """A version-1 Replay from decoded JSON, or ReplayError naming the first problem."""
    version, seed, config, program = _header(data)
    _need(version == 1, "a version-2 replay is lines of JSON, not one object")
    for key in ("ticks", "inputs", "checkpoints"):
        _need(key in data, f"field {key!r} is missing")
    ticks = _int(data["ticks"], "ticks", 0, MAX_TICKS)
    runs = Runs()
    total = _runs(data["inputs"], "the", 0, runs)
    _need(total == ticks, f"inputs cover {total} ticks but ticks says {ticks}")
    listed = data["checkpoints"]
    _need(isinstance(listed, list) and len(listed) <= ticks + 1,
          "checkpoints must be a list, at most one a tick")
    checkpoints = [_checkpoint(c, f"checkpoint {i}", ticks) for i, c in enumerate(listed)]
    return _finish(seed, config, runs, Checkpoints(checkpoints),
                   [c.tick for c in checkpoints], program, ticks)


def parse_lines(lines: list[str], numbers: list[int] | None = None) -> Replay:
    """A version-2 Replay from its lines (the header first), or ReplayError; `numbers`: each
    line's number in its file (blank lines left out between them), 1, 2, 3... by default."""
    numbered = list(zip(numbers or range(1, len(lines) + 1), lines, strict=True))
    return _parse_blocks(numbered[0][1], ((number, line.rstrip("\n").encode() + b"\n")
                                          for number, line in numbered[1:]))


def _parse_blocks(header_line: str, blocks: Iterable[tuple[int, bytes]]) -> Replay:
    """A version-2 Replay from its header line and the other lines in blocks of whole lines,
    each with its first line's number (a long replay is never held as text)."""
    _need(len(header_line) <= MAX_HEADER_BYTES,
          f"the header line is {len(header_line):,} characters: at most {MAX_HEADER_BYTES:,}")
    header = _decode(header_line, "the header line")
    _, seed, config, program = _header(header)
    players = _players(header)
    runs, checkpoints, switches = Runs(), Checkpoints(), []
    total = 0
    for first, block in blocks:
        covered = _canonical_block(block, total, runs, checkpoints)
        if covered is not None:
            total = covered
            continue
        for number, line in _block_lines(first, block):  # each as it can be read
            covered = _canonical_block(line, total, runs, checkpoints)
            if covered is None:
                text = _text(line).rstrip("\n")
                covered = _any_line(text, f"line {number}", total, runs, checkpoints, switches)
            total = covered
    return _finish(seed, config, runs, checkpoints, checkpoints.ticks(), program, total,
                   switches, players)


def _block_lines(number: int, block: bytes) -> Iterator[tuple[int, bytes]]:
    """A block's lines that hold something, each with its newline and its number."""
    for offset, line in enumerate(block.splitlines(keepends=True)):
        if line.strip():
            yield number + offset, line


_UNKNOWN_BITS = ~ALL_ACTIONS


def _canonical_block(block: bytes, total: int, runs: Runs,
                     checkpoints: Checkpoints) -> int | None:
    """Take a block of whole lines when each is in exactly the shape this program writes and
    every value in it is good: the ticks covered so far. None (having taken nothing) for
    any other block, whose lines the JSON parser reads (and names the problem of)."""
    read = canonical.read_block(block)
    if read is None:
        return None
    ends = [total + end for end in read.ends]
    good = (read.most_runs + canonical.REST <= MAX_LINE_BYTES
            and len(runs) + len(read.bits) <= MAX_RUNS
            and ends == read.ticks and ends[-1] <= MAX_TICKS
            and min(read.counts, default=1) > 0
            and not any(map(_UNKNOWN_BITS.__and__, read.bits)))
    if not good:
        return None
    runs.extend(read.bits, read.counts)
    checkpoints.extend_columns(read.ticks, read.values, read.digests)
    return ends[-1]


def _any_line(line: str, where: str, total: int, runs: Runs, checkpoints: Checkpoints,
              switches: list[Switch]) -> int:
    """Take a checkpoint's line of any shape JSON allows, checking every field: the ticks
    covered so far, or ReplayError naming the first problem."""
    _need(len(line) <= MAX_LINE_BYTES,
          f"{where} is {len(line):,} characters: a checkpoint's line is at most "
          f"{MAX_LINE_BYTES:,}")
    data = _decode(line, where)
    _need(isinstance(data, dict) and set(data) - {"lab"} == {"inputs", "checkpoint"},
          f"{where} must hold exactly inputs and checkpoint (and lab switches)")
    covered = _runs(data["inputs"], where, total, runs)
    if "lab" in data:
        _switches(data["lab"], where, total, covered, switches)
    checkpoint = _checkpoint(data["checkpoint"], f"{where} checkpoint", MAX_TICKS)
    _need(checkpoint.tick == covered,
          f"{where}: its checkpoint is at tick {checkpoint.tick}, its inputs end at {covered}")
    checkpoints.append(checkpoint)
    return covered


def _bounded_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise ReplayError(f"a number of {len(text)} digits: no field holds one that long")
    return int(text)


def _no_fraction(text: str) -> float:
    raise ReplayError(f"a fraction ({_shown(text)}): every number in a replay is whole")


def _no_constant(text: str) -> float:
    raise ReplayError(f"{text} is not a number a replay holds")


def _decode(text: str, where: str) -> Any:
    """JSON, refused before parsing when it holds more lists, objects or fields than a
    replay of its length can (a replay spends about 100 characters an object and 20 a
    field), and at the first fraction, NaN or Infinity."""
    _need(text.count("[") <= MAX_RUNS + 64, f"{where} holds more lists than a replay can")
    _need(text.count("{") <= len(text) // 32 + 64, f"{where} holds more objects than a replay can")
    _need(text.count(":") <= len(text) // 8 + 256, f"{where} holds more fields than a replay can")
    try:
        return json.loads(text, parse_int=_bounded_int, parse_float=_no_fraction,
                          parse_constant=_no_constant)
    except ReplayError as err:  # (from a number the hooks refused)
        raise ReplayError(f"{where}: {err}") from None
    except json.JSONDecodeError as err:
        raise ReplayError(f"{where}: invalid JSON at column {err.colno}: {err.msg}") from None
    except RecursionError:
        raise ReplayError(f"{where}: invalid JSON: nested too deeply") from None


def _first_line_limit(size: int) -> int:
    """The first line is a header (16 KB at most) or a whole version-1 file (8 MB)."""
    return max(MAX_HEADER_BYTES, min(size, MAX_V1_BYTES))


def load(path: str | Path) -> Replay:
    """Read and validate a replay file of either version, a line at a time; ReplayError
    names the problem."""
    handle, size = _open(path)
    with handle:
        try:
            return _read(handle, size)
        except OSError as err:
            raise ReplayError(f"cannot read: {err.strerror}") from None


def _open(path: str | Path) -> tuple[BinaryIO, int]:
    """A replay file opened for reading, and its size: only a regular file, only up to the
    size limit."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise ReplayError("no such file") from None
    except OSError as err:
        raise ReplayError(f"cannot read: {err.strerror}") from None
    if stat.S_ISDIR(info.st_mode):
        raise ReplayError("is a folder, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise ReplayError("not a regular file (a pipe, a device, or a link to one)")
    if info.st_size > MAX_FILE_BYTES:
        raise ReplayError(f"{info.st_size} bytes: a replay may be at most {MAX_FILE_BYTES}")
    try:
        return open(path, "rb"), info.st_size  # (closed by load)
    except OSError as err:
        raise ReplayError(f"cannot read: {err.strerror}") from None


def _read(handle: BinaryIO, size: int) -> Replay:
    head = handle.read(4096).decode("utf-8", "replace")
    handle.seek(0)
    _need(size <= MAX_V1_BYTES or not _V1_MARK.search(head),
          f"a version-1 replay may be at most {MAX_V1_BYTES:,} bytes (longer games are "
          "written in version 2)")
    number, text = _first_line(handle, size)
    try:
        data = _decode(text, f"line {number}")
    except ReplayError:
        whole = _one_object(handle, size)  # a version-1 file spread over lines, as JSON allows
        if whole is None:
            raise
        return parse(whole)
    if _is_version_1(data):
        _need(not any(line.strip() for _, block in _blocks(handle, number + 1)
                      for line in block.splitlines()),
              "a version-1 replay is one JSON object")
        return parse(data)
    return _parse_blocks(text, _blocks(handle, number + 1))


def _first_line(handle: BinaryIO, size: int) -> tuple[int, str]:
    """The first line that holds something, and its number, bounded before it is decoded
    (as a header or a whole version-1 file). A last line with no newline (a write that was
    interrupted) is left out, unless it is the file's first."""
    limit, number = _first_line_limit(size), 0
    while raw := handle.readline(limit + 1):
        number += 1
        whole = raw.endswith(b"\n")
        if not whole and len(raw) > limit:
            rest, whole = _skip_line(handle)
            _need(not whole and number > 1, _too_long(number, len(raw) + rest, limit))
        if not whole and number > 1:
            _need(not raw.strip(), "the file holds no complete line")
            break
        text = _text(raw[:-1] if whole else raw)
        if text.strip():
            return number, text
    raise ReplayError("the file is empty")


BLOCK_BYTES = 2**18  # some 570 of the program's lines


def _blocks(handle: BinaryIO, number: int) -> Iterator[tuple[int, bytes]]:
    """The rest of the file, from line `number`, in blocks of whole lines (a quarter of a
    megabyte or so), each with its first line's number. A last line with no newline (a
    write that was interrupted) is left out; a line longer than a checkpoint's may be is
    never kept whole."""
    pending = b""
    while chunk := handle.read(BLOCK_BYTES):
        _need(handle.tell() <= MAX_FILE_BYTES, f"a replay may be at most {MAX_FILE_BYTES} bytes")
        pending += chunk
        end = pending.rfind(b"\n") + 1
        if end:
            yield number, pending[:end]
            number += pending.count(b"\n", 0, end)
            pending = pending[end:]
        if len(pending) > MAX_LINE_BYTES:
            rest, ended = _skip_line(handle)
            _need(not ended, _too_long(number, len(pending) + rest, MAX_LINE_BYTES))
            return  # (the file ended inside it: a line cut short)


def _skip_line(handle: BinaryIO) -> tuple[int, bool]:
    """Read past the rest of a line too long to keep: its length, and whether a newline
    ended it (not: the file ended)."""
    length = 0
    while chunk := handle.readline(2**16):
        length += len(chunk)
        if chunk.endswith(b"\n"):
            return length - 1, True
    return length, False


def _too_long(number: int, length: int, limit: int) -> str:
    what = (f"a checkpoint's line is at most {MAX_LINE_BYTES:,}" if limit == MAX_LINE_BYTES
            else f"a header is at most {MAX_HEADER_BYTES:,} (and a version-1 file "
                 f"{MAX_V1_BYTES:,})")
    return f"line {number} is {length:,} characters: {what}"


def _text(raw: bytes) -> str:
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ReplayError("not a text file") from None


_V1_MARK = re.compile(r'"version"\s*:\s*1\b')


def _is_version_1(data: Any) -> bool:
    return isinstance(data, dict) and data.get("version") == 1 and type(data["version"]) is int


def _one_object(handle: BinaryIO, size: int) -> dict | None:
    """The file as one version-1 object over several lines, or None if it is not one."""
    if size > MAX_V1_BYTES:
        return None
    handle.seek(0)
    text = handle.read(MAX_V1_BYTES + 1).decode("utf-8", "replace")
    if not text.lstrip().startswith("{"):
        return None
    try:
        whole = _decode(text, "the file")
    except ReplayError:
        return None
    return whole if _is_version_1(whole) else None


def replay_paths(args: list[str]) -> list[Path]:
    """Files named, and the *.json files of folders named, in order; ReplayError if none."""
    paths: list[Path] = []
    for arg in args:
        path = Path(arg)
        try:
            is_dir, exists = path.is_dir(), path.exists()
        except OSError as err:
            raise ReplayError(f"{arg[:80]}: {err.strerror}") from None
        if is_dir:
            found = sorted(p for p in path.glob("*.json") if p.is_file())
            if not found:
                raise ReplayError(f"{arg}: no replay files (*.json) in this folder")
            paths.extend(found)
        elif exists:
            paths.append(path)
        else:
            raise ReplayError(f"{arg}: no such file or folder")
    return paths


# --- running ----------------------------------------------------------------------------------
@dataclass
class CheckResult:
    ticks: int
    checkpoints: int
    final: Checkpoint
    mismatch: str | None = None  # the first checkpoint that differs, described


def run(replay: Replay, broadphase: str = DEFAULT_BROADPHASE, recompute: bool = False,
        switch: Callable[[World, dict[str, Any]], None] | None = None,
        ) -> tuple[CheckResult, Checkpoints]:
    """Run a replay headless at full speed, checking every field of every checkpoint.

    Returns the result and the checkpoints this run produced (for --update). With
    `recompute`, it does not stop at the first mismatch. A replay with lab switches needs
    `switch`, which puts each into the world before the step of its tick (ReplayError
    without it, or when it refuses one with ValueError).
    """
    _need(not replay.switches or switch is not None,
          "the replay switches collision methods in the lab: it needs the lab to run")
    world = replay.world(broadphase)
    pending = iter(replay.switches)
    upcoming = next(pending, None)
    expected = iter(replay.checkpoints)  # in tick order, unpacked one at a time
    due = next(expected, None)
    produced = Checkpoints()
    mismatch = None

    def visit() -> bool:
        """Compare the world with the checkpoint due at its tick, if one is: go on?"""
        nonlocal mismatch, due
        if due is None or world.tick != due.tick:
            return True
        got = Checkpoint.of(world)
        produced.append(got)
        diffs = got.differences(due)
        due = next(expected, None)
        if diffs and mismatch is None:
            mismatch = f"tick {world.tick}: " + "; ".join(diffs)
            return recompute
        return True

    if visit():
        for bits in replay.actions():
            while upcoming is not None and upcoming[0] == world.tick:
                try:
                    switch(world, upcoming[1])  # type: ignore[misc]
                except ValueError as err:
                    raise ReplayError(f"lab switch at tick {upcoming[0]}: {err}") from None
                upcoming = next(pending, None)
            world.step(bits)
            if not visit():
                break
    final = produced[-1] if produced else Checkpoint.of(world)
    return CheckResult(replay.ticks, len(produced), final, mismatch), produced
