"""Per-tick counter reports (CSV or JSON Lines) and their aggregation into a summary."""

from __future__ import annotations

import json
from pathlib import Path
from typing import IO

import numpy as np

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
    """Streams one row per tick to an open file."""

    def __init__(self, handle: IO[str], fmt: str) -> None:
        self.handle = handle
        self.fmt = fmt
        if fmt == ".csv":
            handle.write(",".join(COLUMNS) + "\n")

    def row(self, tick: int, stats: CollisionStats, events: tuple[str, ...]) -> None:
        if self.fmt == ".csv":
            cells = [str(tick), *map(str, stats), " ".join(events)]
            self.handle.write(",".join(cells) + "\n")
        else:
            record = {"tick": tick, **stats._asdict(), "events": list(events)}
            self.handle.write(json.dumps(record, separators=(",", ":")) + "\n")


class CounterTable:
    """Every tick's counters in one preallocated array, for totals and medians."""

    def __init__(self, ticks: int) -> None:
        self.rows = np.zeros((ticks, len(STAT_FIELDS)), dtype=np.int64)
        self.count = 0

    def add(self, stats: CollisionStats) -> None:
        self.rows[self.count] = stats
        self.count += 1

    def totals(self) -> dict[str, int]:
        used = self.rows[: self.count]
        return {name: int(v) for name, v in zip(STAT_FIELDS, used.sum(axis=0), strict=True)}

    def medians(self) -> dict[str, float]:
        used = self.rows[: self.count]
        if self.count == 0:
            return dict.fromkeys(STAT_FIELDS, 0.0)
        meds = np.median(used, axis=0)
        return {name: float(v) for name, v in zip(STAT_FIELDS, meds, strict=True)}
