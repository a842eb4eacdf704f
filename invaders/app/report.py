"""Per-tick counter reports (CSV or JSON Lines) and their aggregation into a summary."""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import IO

from invaders.engine.stats import STAT_FIELDS, CollisionStats

REPORT_FORMATS = (".csv", ".jsonl")
COLUMNS = ("tick", *STAT_FIELDS, "events")


def report_format(path: str) -> str:
    """The report format a file name asks for, or ValueError naming the problem."""
    suffix = Path(path).suffix.lower()
    if suffix not in REPORT_FORMATS:
        raise ValueError(f"report file {path!r} must end in .csv or .jsonl")
    return suffix


class ReportWriter:
    """Streams one row per tick to an open file; `extra` names columns after the counters
    (a lab's running score, say) whose values each row brings."""

    def __init__(self, handle: IO[str], fmt: str, extra: tuple[str, ...] = ()) -> None:
        self.handle = handle
        self.fmt = fmt
        self.extra = extra
        if fmt == ".csv":
            handle.write(",".join((*COLUMNS, *extra)) + "\n")
        else:
            import json  # only for this format: a plain run starts without it

            self._dumps = json.dumps

    def row(self, tick: int, stats: CollisionStats, events: tuple[str, ...],
            extra: tuple[int, ...] = ()) -> None:
        if self.fmt == ".csv":
            cells = [str(tick), *map(str, stats), " ".join(events), *map(str, extra)]
            self.handle.write(",".join(cells) + "\n")
        else:
            record = {"tick": tick, **stats._asdict(), "events": list(events),
                      **dict(zip(self.extra, extra, strict=True))}
            self.handle.write(self._dumps(record, separators=(",", ":")) + "\n")


class CounterTable:
    """Totals and exact medians of every counter over a run, kept as per-value counts: its
    memory grows with the number of distinct values a counter takes (small integers), not
    with the number of ticks, so a run of any length stays flat."""

    def __init__(self) -> None:
        self.count = 0
        self._totals = [0] * len(STAT_FIELDS)
        self._values: list[Counter[int]] = [Counter() for _ in STAT_FIELDS]

    def add(self, stats: CollisionStats) -> None:
        self.count += 1
        totals = self._totals
        for i, value in enumerate(stats):
            totals[i] += value
            self._values[i][value] += 1

    def totals(self) -> dict[str, int]:
        return dict(zip(STAT_FIELDS, self._totals, strict=True))

    def medians(self) -> dict[str, float]:
        """The median of each counter (the mean of the middle two for an even count)."""
        return {name: _median(values, self.count)
                for name, values in zip(STAT_FIELDS, self._values, strict=True)}


def _median(values: Counter[int], count: int) -> float:
    if count == 0:
        return 0.0
    low_at, high_at = (count - 1) // 2, count // 2  # the middle positions, 0-based
    low = high = 0
    seen = 0
    for value in sorted(values):
        before = seen
        seen += values[value]  # positions before..seen-1 hold this value
        if before <= low_at < seen:
            low = value
        if before <= high_at < seen:
            high = value
            break
    return (low + high) / 2
