"""Replays: record a game's inputs, load and validate a file, run it headless and check it.

A replay is JSON (format "invaders-replay", version 1): the seed and rule configuration, the
input bits of every tick run-length encoded, and checkpoints (every 60 ticks and at the end)
with the state hash, score, ships, wave, body counts and one digest per state group, so a
replay that goes wrong says where first and what. Files are always written atomically.
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from invaders import __version__
from invaders.atomic import write_atomic
from invaders.game.actions import ALL_ACTIONS
from invaders.game.config import ConfigError, GameConfig
from invaders.game.statehash import GROUPS, combine
from invaders.game.world import World

FORMAT = "invaders-replay"
VERSION = 1
CHECKPOINT_EVERY = 60
MAX_TICKS = 10_000_000  # 46 hours of play: anything longer is a damaged file
HASH = re.compile(r"^[0-9a-f]{32}$")
GROUP_HASH = re.compile(r"^[0-9a-f]{16}$")


class ReplayError(ValueError):
    """A replay file that cannot be used; the message names the problem."""


@dataclass(frozen=True)
class Checkpoint:
    tick: int
    hash: str
    score: int
    ships: int
    wave: int
    counts: dict[str, int]
    groups: dict[str, str]

    @classmethod
    def of(cls, world: World) -> Checkpoint:
        groups = world.group_hashes()
        return cls(world.tick, combine(groups), world.score, world.ships, world.wave,
                   world.kind_counts(), groups)

    def differences(self, other: Checkpoint) -> list[str]:
        """What differs, most telling first: score, ships, wave, counts, then groups."""
        diffs = [f"{name} {getattr(self, name)} expected {getattr(other, name)}"
                 for name in ("score", "ships", "wave")
                 if getattr(self, name) != getattr(other, name)]
        diffs += [f"{kind} count {self.counts.get(kind)} expected {other.counts.get(kind)}"
                  for kind in sorted(set(self.counts) | set(other.counts))
                  if self.counts.get(kind) != other.counts.get(kind)]
        groups = [g for g in GROUPS if self.groups.get(g) != other.groups.get(g)]
        if groups:
            diffs.append("state differs in " + ", ".join(groups))
        return diffs or ["state hash differs"]


@dataclass
class Replay:
    seed: int
    config: GameConfig
    inputs: list[list[int]] = field(default_factory=list)  # [bits, count] runs
    checkpoints: list[Checkpoint] = field(default_factory=list)
    program: str = f"invaders {__version__}"

    @property
    def ticks(self) -> int:
        return sum(count for _, count in self.inputs)

    def actions(self) -> Iterator[int]:
        for bits, count in self.inputs:
            for _ in range(count):
                yield bits

    def append(self, bits: int) -> None:
        if self.inputs and self.inputs[-1][0] == bits:
            self.inputs[-1][1] += 1
        else:
            self.inputs.append([bits, 1])

    def to_json(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "version": VERSION,
            "program": self.program,
            "seed": self.seed,
            "config": dataclasses.asdict(self.config),
            "ticks": self.ticks,
            "inputs": self.inputs,
            "checkpoints": [dataclasses.asdict(c) for c in self.checkpoints],
        }

    def save(self, path: str | Path) -> None:
        """Write the whole replay atomically: a reader sees the old file or the new one."""
        text = json.dumps(self.to_json(), separators=(",", ":"))
        write_atomic(path, text + "\n")


# --- reading and validating -----------------------------------------------------------------
def _need(cond: bool, problem: str) -> None:
    if not cond:
        raise ReplayError(problem)


def _int(value: Any, name: str, low: int = 0, high: int = 2**63 - 1) -> int:
    _need(type(value) is int, f"{name} must be a whole number")
    _need(low <= value <= high, f"{name} {value} is out of range {low}..{high}")
    return value


# Config fields added after files were first written: a file without one was recorded by a
# program that had the default value written into its code, so the default is what it meant.
ADDED_LATER: dict[str, frozenset[str]] = {
    "config.geometry": frozenset({"saucer_start_left", "saucer_start_right",
                                  "saucer_exit_left", "saucer_exit_right"}),
}


def _config(data: Any, cls: type = GameConfig, name: str = "config") -> Any:
    """Rebuild a frozen config dataclass, checking every field's type against its default."""
    _need(isinstance(data, dict), f"{name} must be an object")
    defaults = cls()
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(str(k) for k in set(data) - set(fields))
    if unknown:
        raise ReplayError(f"{name} has unknown field {unknown[0]!r}")
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
            _need(isinstance(value, list) and value, f"{where} must be a non-empty list")
            values[key] = tuple(_int(v, where) for v in value)
        else:
            values[key] = _int(value, where, 1 if key == "tick_hz" else 0, 10**9)
    try:
        return cls(**values)
    except ConfigError as err:  # names the field, its value and its range
        raise ReplayError(str(err)) from None
    except (TypeError, ValueError) as err:
        raise ReplayError(f"{name}: {err}") from None


def _checkpoint(data: Any, index: int, ticks: int) -> Checkpoint:
    where = f"checkpoint {index}"
    _need(isinstance(data, dict), f"{where} must be an object")
    keys = {"tick", "hash", "score", "ships", "wave", "counts", "groups"}
    _need(set(data) == keys, f"{where} must have exactly the fields {sorted(keys)}")
    tick = _int(data["tick"], f"{where} tick", 0, ticks)
    _need(isinstance(data["hash"], str) and bool(HASH.match(data["hash"])),
          f"{where} hash is not 32 lower-case hex digits")
    counts = data["counts"]
    _need(isinstance(counts, dict), f"{where} counts must be an object")
    groups = data["groups"]
    _need(isinstance(groups, dict) and set(groups) == set(GROUPS),
          f"{where} groups must name exactly {', '.join(GROUPS)}")
    for name, digest in groups.items():
        _need(isinstance(digest, str) and bool(GROUP_HASH.match(digest)),
              f"{where} group {name} is not 16 lower-case hex digits")
    return Checkpoint(tick, data["hash"], _int(data["score"], f"{where} score"),
                      _int(data["ships"], f"{where} ships"), _int(data["wave"], f"{where} wave"),
                      {str(k): _int(v, f"{where} count {k}") for k, v in counts.items()},
                      dict(groups))


def parse(data: Any) -> Replay:
    """A Replay from decoded JSON, or ReplayError naming the first problem."""
    _need(isinstance(data, dict), "the file must hold a JSON object")
    _need(data.get("format") == FORMAT, f"format must be {FORMAT!r}, not {data.get('format')!r}")
    _need(data.get("version") == VERSION,
          f"version {data.get('version')!r} is not supported (this program reads {VERSION})")
    for key in ("program", "seed", "config", "ticks", "inputs", "checkpoints"):
        _need(key in data, f"field {key!r} is missing")
    _need(isinstance(data["program"], str), "program must be a string")
    seed = _int(data["seed"], "seed")
    config = _config(data["config"])
    ticks = _int(data["ticks"], "ticks", 0, MAX_TICKS)
    inputs = data["inputs"]
    _need(isinstance(inputs, list), "inputs must be a list of [bits, count] runs")
    runs: list[list[int]] = []
    total = 0
    for i, run in enumerate(inputs):
        _need(isinstance(run, list) and len(run) == 2, f"input run {i} must be [bits, count]")
        bits = _int(run[0], f"input run {i} bits")
        _need(bits & ~ALL_ACTIONS == 0, f"input run {i} has unknown action bits {bits:#x}")
        count = _int(run[1], f"input run {i} count", 1, MAX_TICKS)
        total += count
        _need(total <= MAX_TICKS, f"inputs run past {MAX_TICKS} ticks")
        runs.append([bits, count])
    _need(total == ticks, f"inputs cover {total} ticks but ticks says {ticks}")
    checkpoints_data = data["checkpoints"]
    _need(isinstance(checkpoints_data, list) and checkpoints_data,
          "checkpoints must be a non-empty list")
    checkpoints = [_checkpoint(c, i, ticks) for i, c in enumerate(checkpoints_data)]
    ticks_seen = [c.tick for c in checkpoints]
    _need(ticks_seen == sorted(set(ticks_seen)), "checkpoint ticks must strictly increase")
    _need(ticks_seen[-1] == ticks, "the last checkpoint must be at the last tick")
    return Replay(seed, config, runs, checkpoints, data["program"])


def load(path: str | Path) -> Replay:
    """Read and validate a replay file; ReplayError names the problem."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ReplayError("no such file") from None
    except IsADirectoryError:
        raise ReplayError("is a folder, not a file") from None
    except UnicodeDecodeError:
        raise ReplayError("not a text file") from None
    except OSError as err:
        raise ReplayError(f"cannot read: {err.strerror}") from None
    if not text.strip():
        raise ReplayError("the file is empty")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as err:
        raise ReplayError(f"invalid JSON at line {err.lineno} column {err.colno}: {err.msg}") \
            from None
    except RecursionError:
        raise ReplayError("invalid JSON: nested too deeply") from None
    return parse(data)


def replay_paths(args: list[str]) -> list[Path]:
    """Files named, and the *.json files of folders named, in order; ReplayError if none."""
    paths: list[Path] = []
    for arg in args:
        path = Path(arg)
        if path.is_dir():
            found = sorted(p for p in path.glob("*.json") if p.is_file())
            if not found:
                raise ReplayError(f"{arg}: no replay files (*.json) in this folder")
            paths.extend(found)
        elif path.exists():
            paths.append(path)
        else:
            raise ReplayError(f"{arg}: no such file or folder")
    return paths


# --- recording and running -------------------------------------------------------------------
class Recorder:
    """Keeps a replay of a running world: call `tick(bits)` after each step."""

    def __init__(self, world: World, path: str | Path | None = None,
                 save_every: int = 180) -> None:
        self.world = world
        self.path = path
        self.save_every = save_every
        self.replay = Replay(world.seed, world.config)
        self.replay.checkpoints.append(Checkpoint.of(world))

    def tick(self, bits: int) -> None:
        self.replay.append(bits)
        if self.world.tick % CHECKPOINT_EVERY == 0:
            self.replay.checkpoints.append(Checkpoint.of(self.world))
        if self.path is not None and self.world.tick % self.save_every == 0:
            self.save()

    def finished(self) -> Replay:
        """The replay so far, closed with a checkpoint at the current tick."""
        if self.replay.checkpoints[-1].tick != self.world.tick:
            self.replay.checkpoints.append(Checkpoint.of(self.world))
        return self.replay

    def save(self) -> None:
        if self.path is not None:
            self.finished().save(self.path)


@dataclass
class CheckResult:
    ticks: int
    checkpoints: int
    final: Checkpoint
    mismatch: str | None = None  # the first checkpoint that differs, described


def run(replay: Replay, broadphase: str = "grid",
        recompute: bool = False) -> tuple[CheckResult, list[Checkpoint]]:
    """Run a replay headless at full speed, checking every checkpoint on the way.

    Returns the result and the checkpoints this run produced (for --update). With
    `recompute`, it does not stop at the first mismatch.
    """
    world = World(replay.seed, replay.config, broadphase=broadphase)
    expected = {c.tick: c for c in replay.checkpoints}
    produced: list[Checkpoint] = []
    mismatch = None

    def visit() -> bool:
        nonlocal mismatch
        if world.tick in expected:
            got = Checkpoint.of(world)
            produced.append(got)
            want = expected[world.tick]
            if got.hash != want.hash and mismatch is None:
                mismatch = f"tick {world.tick}: " + "; ".join(got.differences(want))
                return recompute
        return True

    if visit():
        for bits in replay.actions():
            world.step(bits)
            if world.tick in expected and not visit():
                break
    final = produced[-1] if produced else Checkpoint.of(world)
    return CheckResult(replay.ticks, len(produced), final, mismatch), produced


def record_headless(world: World, source: Any, ticks: int) -> Replay:
    """Play `ticks` ticks with an input source and return the replay of it."""
    recorder = Recorder(world)
    for _ in range(ticks):
        bits = source.actions(world)
        world.step(bits)
        recorder.tick(bits)
    return recorder.finished()
