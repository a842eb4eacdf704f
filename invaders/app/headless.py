"""Headless runs: no window, no clock; a world, an input source, and what the run measured."""

from __future__ import annotations

import contextlib
import os
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Protocol

from invaders.app.report import CounterTable, ReportWriter, report_format
from invaders.atomic import atomic_writer
from invaders.game.world import World


def use_dummy_drivers() -> None:
    """Select SDL's dummy video and audio drivers, so nothing needs a display or a sound card."""
    os.environ["SDL_VIDEODRIVER"] = "dummy"
    os.environ["SDL_AUDIODRIVER"] = "dummy"


class Recording(Protocol):
    """What a run hands each tick's input to (a recording.Recorder)."""

    def tick(self, bits: int) -> None: ...

    def cut_off(self) -> None: ...  # a tick was cut off: the recording ends at a whole one


class InputSource(Protocol):
    def actions(self, world: World) -> int: ...


class Idle:
    """No one at the controls."""

    def actions(self, world: World) -> int:
        return 0


@dataclass
class RunResult:
    world: World
    table: CounterTable
    events: Counter = field(default_factory=Counter)


class Columns(Protocol):
    """More columns for the report: their names, and each tick's values."""

    names: tuple[str, ...]

    def values(self) -> tuple[int, ...]: ...


def run(world: World, source: InputSource, ticks: int, report: str | None = None,
        recorder: Recording | None = None,
        stop: Callable[[], bool] | None = None, columns: Columns | None = None) -> RunResult:
    """Step `world` `ticks` times with `source`'s input, or until `stop()` says so (asked
    between ticks); optionally write the per-tick report (atomically: the file appears
    whole when the run ends) and record the run as a replay. Keeps nothing per tick."""
    table = CounterTable()
    events: Counter = Counter()
    with _report(report, columns.names if columns is not None else ()) as writer:
        for _ in range(ticks):
            if stop is not None and stop():
                break
            bits = source.actions(world)
            try:
                result = world.step(bits)
            except BaseException:
                if recorder is not None:  # (half a tick played: saved up to a whole one)
                    recorder.cut_off()
                raise
            if recorder is not None:
                recorder.tick(bits)
            table.add(result.stats)
            names = tuple(e.name for e in result.events) if result.events else ()
            if names:
                events.update(names)
            if writer is not None:
                writer.row(result.tick, result.stats, names,
                           columns.values() if columns is not None else ())
    return RunResult(world, table, events)


@contextlib.contextmanager
def _report(path: str | None, extra: tuple[str, ...]) -> Iterator[ReportWriter | None]:
    if path is None:
        yield None
        return
    fmt = report_format(path)
    with atomic_writer(path) as handle:
        yield ReportWriter(handle, fmt, extra)
