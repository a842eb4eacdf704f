"""`invaders bench --reading`: the longest replay a file may hold, and the worst, read.

Files at the size limit (64 MB) are made in a temporary folder: the longest valid replay
(the program's own lines, one a second of play, 8.7 million ticks), the same written with
json.dumps' default spacing, with a lab switch every 500 lines (cut out of its line, the
rest read by the regular expressions), with its fields sorted (as tools that sort them
write them), in reverse order (an order learnt from the first block), in an order of their
own on every line and with every name and digest escaped, with its counts written twice on
every line (as only hostile files are: the pattern of any order reads them), with the most
lab switches a replay may hold, one a line from the start or spread through the file as
far apart as they go, with the most input runs (a tick each), and with lines ending in
\\r\\n and a blank line after each; and four hostile ones: a header holding 64 MB of empty
objects, of fractions or of fields, and 64 MB of lab switches. Each round reads each in a
fresh process, taking turns; printed: the seconds `load` took and the process's peak
memory, medians over the rounds with their spread, against the goal of 2 s and 100 MB.
"""

from __future__ import annotations

import json
import random
import re
import statistics
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any

from invaders.app.recording import record_headless, save_replay
from invaders.game.actions import Action
from invaders.game.replay import MAX_FILE_BYTES, MAX_RUNS, MAX_SWITCHES
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot

GOAL_SECONDS = 2.0
GOAL_MB = 100

CHILD = """
import json, resource, sys, time
from invaders.game.replay import ReplayError, load
start = time.perf_counter()
try:
    ticks = load(sys.argv[1]).ticks
except ReplayError:
    ticks = None
seconds = time.perf_counter() - start
try:  # this process's own peak (ru_maxrss may hold the parent's from before the fork)
    with open("/proc/self/status") as status:
        peak = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
except OSError:  # (no /proc: the peak getrusage saw, in bytes on macOS, elsewhere in KiB)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    peak = peak / 1024 if sys.platform == "darwin" else peak
print(json.dumps([seconds, peak / 1024, ticks]))
"""


def longest_replay(path: Path, folder: Path, size: int = MAX_FILE_BYTES) -> int:
    """Write to `path` a valid replay as long as `size` bytes let one be: lines in the
    program's own shape, 60 ticks each, every checkpoint a real one's with the tick moved on
    (valid to read; running it would fail at the second checkpoint). Returns its ticks."""
    game = folder / "game.json"
    save_replay(game, record_headless(World(seed=7), Autopilot(7), 120))
    header, *lines = game.read_text().splitlines()
    checkpoint = json.loads(lines[-1])["checkpoint"]
    line = json.dumps({"inputs": [[0, 30], [4, 30]], "checkpoint": dict(checkpoint, tick=0)},
                      separators=(",", ":")).replace('"tick":0', '"tick":%d')
    count = (size - len(header) - 1) // (len(line) + 6)  # (the tick's digits)
    with path.open("w") as out:
        out.write(header + "\n")
        out.writelines(line % (60 * n) + "\n" for n in range(1, count + 1))
    return 60 * count


def rewritten(source: Path, path: Path, size: int = MAX_FILE_BYTES,
              change: Callable[[Any], Any] = lambda value: value,
              spelling: Callable[[str], str] = str, **dumps: Any) -> int:
    """Write `source`'s lines to `path` as `json.dumps(**dumps)` writes them (each value
    changed by `change` first, each line's text by `spelling` last), as many whole lines as
    fit in `size` bytes. Returns the ticks they cover."""
    with source.open() as lines:
        return _capped(path, (json.dumps(change(json.loads(line)), **dumps) + "\n"
                              for line in lines), size, spelling)


def escaped(line: str) -> str:
    """The line with every character of every name and digest written as JSON's escape of
    it (the same line, as only a hostile file would spell it)."""
    return _WORD.sub(lambda word: "".join(f"\\u{ord(char):04x}" for char in word[0]), line)


_WORD = re.compile(r'(?<=")\w+(?=")')


def windows_lines(line: str) -> str:
    """The line ending in \\r\\n, a blank line after it (the same replay, as an editor on
    Windows may save it)."""
    return line.rstrip("\n") + "\r\n\r\n"


def counts_twice(line: str) -> str:
    """The line with its counts written twice, the same each time (JSON keeps the last:
    the same line, as only a hostile file would spell it)."""
    return _COUNTS.sub(r"\1,\1", line, count=1)


_COUNTS = re.compile(r'("counts":\{[^}]*\})')


def order_each_line(seed: int = 0) -> Callable[[Any], Any]:
    """A change to lines that gives every object of each line its fields in an order drawn
    at random (seeded): no order learnt from one block fits the next, the pattern of any
    order reads them."""
    draw = random.Random(seed)

    def change(value: Any) -> Any:
        if isinstance(value, dict):
            fields = [(key, change(item)) for key, item in value.items()]
            draw.shuffle(fields)
            return dict(fields)
        return value

    return change


def reversed_fields(value: Any) -> Any:
    """The same JSON value with every object's fields in the opposite order (an order no
    tool writes: learnt from the file's first block)."""
    if isinstance(value, dict):
        return {key: reversed_fields(item) for key, item in reversed(value.items())}
    return value


def most_runs(source: Path, path: Path, size: int = MAX_FILE_BYTES) -> int:
    """Write `source`'s lines to `path` with as many input runs as a replay may hold (a
    player's fingers are busier than the autopilot's): each line's inputs, from the first,
    split into runs of a tick each, fire and nothing in turn, while the whole file's runs
    stay within the limit; as many whole lines as fit in `size` bytes. Returns the ticks."""
    with source.open() as lines:
        spare = MAX_RUNS - sum(len(json.loads(line).get("inputs", ())) for line in lines)

    def split(value: Any) -> Any:
        nonlocal spare
        runs = value.get("inputs", [])
        ticks = sum(count for _, count in runs)
        if runs and ticks - len(runs) <= spare:
            spare -= ticks - len(runs)
            value["inputs"] = [[int(Action.FIRE) * (tick % 2), 1] for tick in range(ticks)]
        return value

    return rewritten(source, path, size, split, separators=(",", ":"))


def with_switches(source: Path, path: Path, every: int = 500, size: int = MAX_FILE_BYTES,
                  each: int = 1, most: int | None = None,
                  choice: dict[str, Any] | None = None) -> int:
    """Write `source`'s lines to `path` with `each` lab switches (to `choice`) on every
    `every`th line (a line the JSON parser reads on its own), up to `most` lines with
    switches, as many whole lines as fit in `size` bytes. Returns the ticks."""
    def switched(lines: Iterable[str]) -> Iterator[str]:
        start, holding = 0, 0  # the previous checkpoint's tick (the line's first), lines
        for number, text in enumerate(lines):
            if number and number % every == 0 and (most is None or holding < most):
                data = dict(json.loads(text), lab=[[start, choice or _CHOICE]] * each)
                text = json.dumps(data, separators=(",", ":")) + "\n"
                holding += 1
            start = _tick(text, start)
            yield text

    with source.open() as lines:
        return _capped(path, switched(lines), size)


_CHOICE = {"speed": 1}  # (a lab's choice: reading does not check what one means)
# A choice long enough that its objects pass the count of objects a line may hold.
_PADDED = {"speed": 1, "pad": "thirty-two characters at least"}


def _capped(path: Path, lines: Iterable[str], size: int,
            spelling: Callable[[str], str] = str) -> int:
    """Write whole lines to `path`, each spelt by `spelling`, while they fit in `size`
    bytes: the last one's tick."""
    ticks, written = 0, 0
    with path.open("w") as out:
        for line in lines:
            text = spelling(line)
            written += len(text)
            if written > size:
                break
            out.write(text)
            ticks = _tick(line, ticks)
    return ticks


_TICK = re.compile(r'"tick"\s*:\s*([0-9]+)')


def _tick(line: str, otherwise: int) -> int:
    """A checkpoint line's tick (the header has none: `otherwise`)."""
    found = _TICK.search(line)
    return int(found[1]) if found else otherwise


def hostile_headers(folder: Path, header: str, size: int = MAX_FILE_BYTES
                    ) -> dict[str, Path]:
    """Headers of `size` bytes of empty objects, of fractions, of fields (at 64 MB each once
    took 1.2 to 1.9 GB and up to a minute to refuse), written a piece at a time."""
    room, mb = size - 4096, f"{size / 2**20:.4g} MB"
    shapes = {  # what opens the list or object, its items a piece at a time, what closes it
        f"{mb} of {{}} in the header": ('"x":[', _repeated("{},", room // 3), "{}]}"),
        f"{mb} of fractions": ('"x":[', _repeated("0.5,", room // 4), "0.5]}"),
        f"{mb} of fields": ('"x":{', _fields(room // 12), '"":0}}'),
    }
    paths = {}
    for number, (name, (opening, pieces, closing)) in enumerate(shapes.items()):
        paths[name] = folder / f"hostile-{number}.json"
        with paths[name].open("w") as out:
            out.write(header[:-1] + "," + opening)
            out.writelines(pieces)
            out.write(closing + "\n")
    return paths


def _repeated(item: str, count: int, piece: int = 2**16) -> Iterator[str]:
    for start in range(0, count, piece):
        yield item * min(piece, count - start)


def _fields(count: int, piece: int = 2**16) -> Iterator[str]:
    for start in range(0, count, piece):
        yield "".join(f'"{n}":0,' for n in range(start, min(count, start + piece)))


def read_in_fresh_process(path: Path) -> tuple[float, float, int | None]:
    """Seconds `load` took, the process's peak MB, and the ticks read (None: refused)."""
    result = subprocess.run([sys.executable, "-c", CHILD, str(path)], capture_output=True,
                            text=True, check=True, timeout=600)
    seconds, megabytes, ticks = json.loads(result.stdout)
    return seconds, megabytes, ticks


def _spread_switches(source: Path, path: Path, size: int) -> int:
    """The most lab switches a replay may hold, as far apart as they go."""
    with source.open() as lines:
        every = max(1, sum(1 for _ in lines) // MAX_SWITCHES)
    return with_switches(source, path, every, size, most=MAX_SWITCHES)


COMPACT: dict[str, Any] = {"separators": (",", ":")}  # json.dumps' most compact
Writer = Callable[[Path, Path, int], int]  # (the longest replay, the file, its size): ticks
# The longest valid replay written other valid ways: (file, label, writer), in the order read.
REWRITES: tuple[tuple[str, str, Writer], ...] = (
    ("spaced.json", "the same spaced as json.dumps", rewritten),
    ("switched.json", "the same, a lab switch every 500 lines",
     lambda source, path, size: with_switches(source, path, size=size)),
    ("ordered.json", "the same, fields sorted",
     lambda source, path, size: rewritten(source, path, size, sort_keys=True, **COMPACT)),
    ("reordered.json", "the same, fields in reverse order",
     lambda source, path, size: rewritten(source, path, size, reversed_fields, **COMPACT)),
    ("varied.json", "the same, an order of fields a line",
     lambda source, path, size: rewritten(source, path, size, order_each_line(), **COMPACT)),
    ("escaped.json", "the same, every name and digest escaped",
     lambda source, path, size: rewritten(source, path, size, spelling=escaped, **COMPACT)),
    ("twice.json", "the same, its counts twice a line",
     lambda source, path, size: rewritten(source, path, size, spelling=counts_twice,
                                          **COMPACT)),
    ("most-switches.json", f"the same, {MAX_SWITCHES:,} lab switches first",
     lambda source, path, size: with_switches(source, path, 1, size, most=MAX_SWITCHES)),
    ("spread-switches.json", f"the same, {MAX_SWITCHES:,} lab switches spread",
     _spread_switches),
    ("most-runs.json", "the same, the most input runs", most_runs),
    # (lines as an editor on Windows may save them)
    ("windows.json", "the same, \\r\\n and blank lines",
     lambda source, path, size: rewritten(source, path, size, spelling=windows_lines,
                                          **COMPACT)),
)


def bench_files(folder: Path, size: int) -> dict[str, Path]:
    """The files the bench reads, written in `folder`, by their labels: the longest valid
    replay of `size` bytes, the same written other valid ways, and files to refuse."""
    longest = folder / "longest.json"
    files = {f"the longest valid replay ({longest_replay(longest, folder, size):,} ticks)":
             longest}
    for name, label, write in REWRITES:
        files[f"{label} ({write(longest, folder / name, size):,})"] = folder / name
    with longest.open() as lines:
        files.update(hostile_headers(folder, lines.readline().rstrip("\n"), size))
    flood = folder / "switches.json"
    with_switches(longest, flood, 1, size, each=1000, choice=_PADDED)
    files[f"{size / 2**20:.4g} MB of lab switches"] = flood
    return files


def reading_bench(rounds: int, size: int = MAX_FILE_BYTES) -> tuple[list[str], bool]:
    """The table's lines, and whether every file met the goal (files of `size` bytes)."""
    with tempfile.TemporaryDirectory() as name:
        files = bench_files(Path(name), size)
        seen: dict[str, list[tuple[float, float, int | None]]] = {n: [] for n in files}
        for _ in range(rounds):
            for label, path in files.items():
                seen[label].append(read_in_fresh_process(path))
    return _table(seen, size, rounds)


def _table(seen: dict[str, list[tuple[float, float, int | None]]], size: int, rounds: int
           ) -> tuple[list[str], bool]:
    """A line a file (read or refused, its seconds and peak megabytes against the goal)
    under the heading, and whether every file met the goal."""
    lines = [f"reading files at the size limit ({size:,} bytes), {rounds} rounds "
             f"taking turns, each in a fresh process: seconds to read or refuse, the "
             f"process's peak MB; medians (lowest..highest round); goal {GOAL_SECONDS:g} s, "
             f"{GOAL_MB} MB"]
    met = True
    for label, runs in seen.items():
        seconds = [s for s, _, _ in runs]
        megabytes = [m for _, m, _ in runs]
        verdict = "read" if runs[0][2] is not None else "refused"
        ok = statistics.median(seconds) < GOAL_SECONDS and statistics.median(megabytes) < GOAL_MB
        met &= ok
        lines.append(f"   {label:<52} {verdict:<8} {statistics.median(seconds):5.2f} s "
                     f"({min(seconds):.2f}..{max(seconds):.2f})  "
                     f"{statistics.median(megabytes):4.0f} MB ({min(megabytes):.0f}.."
                     f"{max(megabytes):.0f})  {'met' if ok else 'MISSED'}")
    return lines, met
