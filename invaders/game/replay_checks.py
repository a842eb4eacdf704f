"""Checking a replay's decoded JSON field by field, every number bounded before it is used.

Reading never trusts a number before it has checked it: each integer's digits while the JSON
is parsed (and no fraction, NaN or Infinity), then each field's type and range, the count of
input runs and the ticks they cover, the config through its own ranges, and each hash
against its groups. Each problem is one ReplayError naming the field and quoting at most a
short prefix of what the file holds.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
from collections.abc import Sequence
from typing import Any

from invaders.game.actions import ALL_ACTIONS
from invaders.game.checkpoint import COUNT_NAMES, Checkpoint, Checkpoints
from invaders.game.config import ConfigError, GameConfig
from invaders.game.replay_format import (
    CHECKPOINT_FIELDS,
    FORMAT,
    GROUP_HASH,
    HASH,
    HEADER_KEYS,
    MAX_DIGITS,
    MAX_RUNS,
    MAX_SWITCH_FIELDS,
    MAX_SWITCHES,
    MAX_TICKS,
    READS,
    V1_KEYS,
    Replay,
    ReplayError,
    Switch,
)
from invaders.game.runs import Runs
from invaders.game.statehash import GROUPS, combine


# --- reading and validating -----------------------------------------------------------------
def need(cond: bool, problem: str) -> None:
    if not cond:
        raise ReplayError(problem)


def shown(value: Any, most: int = 40) -> str:
    """A value from the file as an error quotes it: its first characters, never all of it
    (a field may hold megabytes)."""
    if isinstance(value, (list, dict)):
        return f"a {type(value).__name__} of {len(value):,} items"
    text = repr(value)
    return text if len(text) <= most else f"{text[:most]}... ({len(text):,} characters)"


def _int(value: Any, name: str, low: int = 0, high: int = 2**63 - 1) -> int:
    if type(value) is not int:
        raise ReplayError(f"{name} must be a whole number")
    if not low <= value <= high:
        raise ReplayError(f"{name} {shown(value)} is out of range {low}..{high}")
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
    need(isinstance(data, dict), f"{name} must be an object")
    defaults = cls()
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(str(k) for k in set(data) - set(fields))
    if unknown:
        raise ReplayError(f"{name} has unknown field {shown(unknown[0])}")
    values = {}
    for key in fields:
        if key not in data and key in ADDED_LATER.get(name, ()):
            values[key] = getattr(defaults, key)
            continue
        need(key in data, f"{name} lacks field {key!r}")
        default = getattr(defaults, key)
        value = data[key]
        where = f"{name}.{key}"
        if dataclasses.is_dataclass(default):
            values[key] = _config(value, type(default), where)
        elif isinstance(default, tuple):
            need(isinstance(value, list) and len(value) <= 64,
                 f"{where} must be a list of at most 64 numbers")
            values[key] = tuple(_int(v, where, -2**63) for v in value)
        else:  # (a size check here; the config itself checks each field's range)
            values[key] = _int(value, where, -2**63)
    try:
        return cls(**values)
    except ConfigError as err:  # names the field, its value and its range
        raise ReplayError(str(err)) from None


_CHECKPOINT_KEYS = frozenset(CHECKPOINT_FIELDS)
_COUNT_KEYS, _GROUP_KEYS = frozenset(COUNT_NAMES), frozenset(GROUPS)


def checkpoint_from(data: Any, where: str, ticks: int) -> Checkpoint:
    # (Each message is made only when it is needed: a long replay has 145,000 checkpoints.)
    if not (isinstance(data, dict) and data.keys() == _CHECKPOINT_KEYS):
        need(isinstance(data, dict), f"{where} must be an object")
        raise ReplayError(f"{where} must have exactly the fields {sorted(_CHECKPOINT_KEYS)}")
    tick = _int(data["tick"], f"{where} tick", 0, ticks)
    digest, counts, groups = data["hash"], data["counts"], data["groups"]
    if not (isinstance(digest, str) and HASH.match(digest)):
        raise ReplayError(f"{where} hash is not 32 lower-case hex digits")
    if not (isinstance(counts, dict) and counts.keys() == _COUNT_KEYS):
        raise ReplayError(f"{where} counts must name exactly {', '.join(sorted(COUNT_NAMES))}")
    if not (isinstance(groups, dict) and groups.keys() == _GROUP_KEYS):
        raise ReplayError(f"{where} groups must name exactly {', '.join(GROUPS)}")
    for name, value in groups.items():
        if not (isinstance(value, str) and GROUP_HASH.match(value)):
            raise ReplayError(f"{where} group {name} is not 16 lower-case hex digits")
    if combine(groups) != digest:
        raise ReplayError(f"{where}: hash does not match its groups")
    return Checkpoint(tick, digest, _int(data["score"], f"{where} score"),
                      _int(data["ships"], f"{where} ships"), _int(data["wave"], f"{where} wave"),
                      {k: _int(v, f"{where} count {k}") for k, v in counts.items()},
                      dict(groups))


def add_runs(inputs: Any, where: str, total: int, runs: Runs) -> int:
    """Append checked input runs; returns the ticks covered so far (bounded while reading)."""
    need(isinstance(inputs, list), f"{where} inputs must be a list of [bits, count] runs")
    need(len(runs) + len(inputs) <= MAX_RUNS, f"more than {MAX_RUNS} input runs")
    for i, run in enumerate(inputs):
        if not (isinstance(run, list) and len(run) == 2 and type(run[0]) is int
                and type(run[1]) is int and run[0] & ~ALL_ACTIONS == 0 and run[0] >= 0
                and 1 <= run[1] <= MAX_TICKS):  # (the message made only when needed)
            _bad_run(run, f"{where} input run {i}")
        total += run[1]
        need(total <= MAX_TICKS, f"inputs run past {MAX_TICKS} ticks")
        runs.add(*run)
    return total


def _bad_run(run: Any, name: str) -> None:
    """Raise the first problem of an input run that is not [bits, count]."""
    need(isinstance(run, list) and len(run) == 2, f"{name} must be [bits, count]")
    bits = _int(run[0], f"{name} bits")
    need(bits & ~ALL_ACTIONS == 0, f"{name} has unknown action bits {bits:#x}")
    _int(run[1], f"{name} count", 1, MAX_TICKS)


def add_switches(listed: Any, where: str, start: int, end: int, out: list[Switch]) -> None:
    """Append checked lab switches: [tick, {name: word or number}], ticks in the line's
    span and increasing (their meaning is checked by whoever applies them)."""
    need(isinstance(listed, list) and len(listed) > 0,
         f"{where} lab must be a list of [tick, choice] switches")
    need(len(out) + len(listed) <= MAX_SWITCHES,
         f"{where}: more than {MAX_SWITCHES:,} lab switches (a replay holds at most that)")
    for i, item in enumerate(listed):
        name = f"{where} lab switch {i}"
        need(isinstance(item, list) and len(item) == 2, f"{name} must be [tick, choice]")
        tick = _int(item[0], f"{name} tick", start, max(start, end - 1))
        need(not out or out[-1][0] <= tick, f"{name}: switch ticks must not decrease")
        choice = item[1]
        need(isinstance(choice, dict) and len(choice) <= MAX_SWITCH_FIELDS,
             f"{name} choice must be an object of at most {MAX_SWITCH_FIELDS} fields")
        for key, value in choice.items():
            need(len(key) <= 32, f"{name} has a field name longer than 32 characters")
            need((type(value) is str and len(value) <= 32) or type(value) is int,
                 f"{name} field {key!r} must be a short word or a whole number")
            if type(value) is int:
                _int(value, f"{name} field {key!r}", -(2**31), 2**31)
        out.append((tick, dict(choice)))


def header_fields(data: Any) -> tuple[int, int, GameConfig, str]:
    """(version, seed, config, program) from a file's first object."""
    need(isinstance(data, dict), "the file must hold a JSON object")
    need(data.get("format") == FORMAT,
         f"format must be {FORMAT!r}, not {shown(data.get('format'))}")
    version = data.get("version")
    need(type(version) is int and version in READS,
         f"version {shown(version)} is not supported (this program reads "
         f"{' and '.join(map(str, READS))})")
    for key in ("program", "seed", "config"):
        need(key in data, f"field {key!r} is missing")
    unknown = sorted(str(k) for k in set(data) - (V1_KEYS if version == 1 else HEADER_KEYS))
    need(not unknown, f"unknown field {shown(unknown[0]) if unknown else ''}")
    need(isinstance(data["program"], str) and len(data["program"]) <= 200,
         "program must be a string of at most 200 characters")
    return version, _int(data["seed"], "seed"), _config(data["config"]), data["program"]


def players_of(header: dict[str, Any]) -> int:
    """How many players the recorded world starts with (1 when the header does not say)."""
    players = header.get("players", 1)
    need(type(players) is int and players in (1, 2),
         f"players must be 1 or 2, not {shown(players)}")
    return players


def finished(seed: int, config: GameConfig, runs: Runs, checkpoints: Checkpoints,
            ticks: Sequence[int], program: str, total: int, switches: list[Switch] | None = None,
            players: int = 1) -> Replay:
    """The replay, once its checkpoints' `ticks` are known to increase up to the last."""
    need(bool(ticks), "there is no checkpoint")
    need(all(a < b for a, b in itertools.pairwise(ticks)),
         "checkpoint ticks must strictly increase")
    need(ticks[-1] == total, "the last checkpoint must be at the last tick")
    return Replay(seed, config, runs, checkpoints, program, switches or [], players)


def parse(data: Any) -> Replay:
    """A version-1 Replay from decoded JSON, or ReplayError naming the first problem."""
    version, seed, config, program = header_fields(data)
    need(version == 1, "a version-2 replay is lines of JSON, not one object")
    for key in ("ticks", "inputs", "checkpoints"):
        need(key in data, f"field {key!r} is missing")
    ticks = _int(data["ticks"], "ticks", 0, MAX_TICKS)
    runs = Runs()
    total = add_runs(data["inputs"], "the", 0, runs)
    need(total == ticks, f"inputs cover {total} ticks but ticks says {ticks}")
    listed = data["checkpoints"]
    need(isinstance(listed, list) and len(listed) <= ticks + 1,
         "checkpoints must be a list, at most one a tick")
    checkpoints = [checkpoint_from(c, f"checkpoint {i}", ticks) for i, c in enumerate(listed)]
    return finished(seed, config, runs, Checkpoints(checkpoints),
                   [c.tick for c in checkpoints], program, ticks)


def _bounded_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise ReplayError(f"a number of {len(text)} digits: no field holds one that long")
    return int(text)


def no_fraction(text: str) -> float:
    raise ReplayError(f"a fraction ({shown(text)}): every number in a replay is whole")


def no_constant(text: str) -> float:
    raise ReplayError(f"{text} is not a number a replay holds")


def overfull(text: str) -> str | None:
    """What the text holds more of than a replay of its length can, if anything (a replay
    spends about 100 characters an object and 20 a field)."""
    if text.count("[") > MAX_RUNS + 64:
        return "lists"
    if text.count("{") > len(text) // 32 + 64:
        return "objects"
    return "fields" if text.count(":") > len(text) // 8 + 256 else None


def decode(text: str, where: str) -> Any:
    """JSON, refused before parsing when it is overfull, and at the first fraction, NaN or
    Infinity, or number too long."""
    if (what := overfull(text)) is not None:
        raise ReplayError(f"{where} holds more {what} than a replay can")
    try:
        return json.loads(text, parse_int=_bounded_int, parse_float=no_fraction,
                          parse_constant=no_constant)
    except ReplayError as err:  # (from a number the hooks refused)
        raise ReplayError(f"{where}: {err}") from None
    except json.JSONDecodeError as err:
        raise ReplayError(f"{where}: invalid JSON at column {err.colno}: {err.msg}") from None
    except RecursionError:
        raise ReplayError(f"{where}: invalid JSON: nested too deeply") from None

