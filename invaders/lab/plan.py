"""`invaders study`: which scenes, which cells, run where; CSV and charts out.

Accuracy cells run over the replays and over storms at every speed multiplier; broad-phase
cells over the replays and storms of growing size (brute force only where it can finish).
Work is split by scene: serially, over --jobs processes, or on a Dask cluster.
"""

from __future__ import annotations

import csv
import io
import sys
import time
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, field
from pathlib import Path

from invaders.atomic import write_atomic
from invaders.engine.grid import DEFAULT_CELL
from invaders.lab.choices import MULTIPLIERS
from invaders.lab.matrix import Method, accuracy_matrix, broad_matrix
from invaders.lab.runner import SceneSpec, run_scene
from invaders.quiet import say

BRUTE_LIMIT = 1000  # bodies: above this, brute force would take minutes a tick
RECTS_LIMIT = 3000  # bodies: above this, brute force in C (the cell rects) takes seconds


@dataclass
class Plan:
    work: list[tuple[SceneSpec, list[Method]]] = field(default_factory=list)
    scaling: list[int] = field(default_factory=list)  # storm sizes for the scaling chart
    scaling_ticks: int = 8
    repeat: int = 3  # each cell's time is the median of this many plays

    @property
    def cells(self) -> int:
        return sum(len(methods) for _, methods in self.work)


BIG_STORM = 30000  # bodies, with --big (brute force left out, as above BRUTE_LIMIT)


def make_plan(replays: Iterable[Path], quick: bool, big: bool = False) -> Plan:
    replays = sorted(replays)
    plan = Plan()
    multipliers: tuple[int, ...]
    sizes: tuple[int, ...]
    if quick:
        replays, replay_ticks, storm_ticks = replays[:2], 600, 8
        multipliers, sizes = (1, 4, 16), (100, 300, 1000)
    else:
        replay_ticks, storm_ticks = 1800, 16
        multipliers, sizes = MULTIPLIERS, (100, 300, 1000, 3000, 10000)
    if big:
        sizes = (*sizes, BIG_STORM)
    accuracy = accuracy_matrix(quick)
    broad = broad_matrix(quick)
    both = list(dict.fromkeys(accuracy + broad))  # the default is in both lists
    for path in replays:
        plan.work.append((SceneSpec.of_replay(path, replay_ticks), both))
    for m in multipliers:
        plan.work.append((SceneSpec.storm(300 if quick else 1000, storm_ticks, m), accuracy))
    for n in sizes:
        methods = [x for x in broad if (x.broad != "brute" or n <= BRUTE_LIMIT)
                   and (x.broad != "rects" or n <= RECTS_LIMIT)]
        plan.work.append((SceneSpec.storm(n, storm_ticks), methods))
    plan.scaling = list(sizes)
    plan.scaling_ticks = storm_ticks
    plan.repeat = 1 if quick else 3
    return plan


class Progress:
    """A one-line progress bar on stderr (plain lines when stderr is not a terminal), which
    never stops the study (`say`)."""

    def __init__(self, total: int, label: str) -> None:
        self.total = total
        self.done = 0
        self.label = label
        self.start = time.perf_counter()
        self.tty = sys.stderr is not None and sys.stderr.isatty()  # (None: pythonw's)

    def advance(self, n: int, what: str) -> None:
        self.done += n
        width = 30
        filled = width * self.done // max(1, self.total)
        bar = "#" * filled + "." * (width - filled)
        line = (f"{self.label} [{bar}] {self.done}/{self.total} cells, "
                f"{time.perf_counter() - self.start:.0f}s  {what}")
        say(("\r" + line[:100].ljust(100)) if self.tty else line, end="" if self.tty else "\n")

    def close(self) -> None:
        if self.tty:
            say("")


def execute(plan: Plan, jobs: int = 1, scheduler: str | None = None,
            progress: Callable[[int, str], None] | None = None) -> list[dict]:
    """Run every scene's cells; rows come back in the plan's order whatever ran them."""
    results: list[list[dict] | None] = [None] * len(plan.work)

    repeat = plan.repeat

    def done(index: int, rows: list[dict]) -> None:
        results[index] = rows
        if progress is not None:
            progress(len(rows), plan.work[index][0].name)

    if scheduler is not None:
        from dask.distributed import Client
        from dask.distributed import as_completed as dask_completed

        with Client(scheduler) as client:
            futures = {client.submit(run_scene, spec, methods, repeat, pure=False): i
                       for i, (spec, methods) in enumerate(plan.work)}
            for future in dask_completed(futures):
                done(futures[future], future.result())
    elif jobs > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            futures = {pool.submit(run_scene, spec, methods, repeat): i
                       for i, (spec, methods) in enumerate(plan.work)}
            for future in as_completed(futures):
                done(futures[future], future.result())
    else:
        for i, (spec, methods) in enumerate(plan.work):
            done(i, run_scene(spec, methods, repeat))
    return [row for rows in results if rows for row in rows]


def write_csv(path: Path, rows: list[dict]) -> None:
    """All rows in one CSV (columns: the union, in first-seen order), written atomically."""
    columns: list[str] = []
    for row in rows:
        columns += [k for k in row if k not in columns]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    write_atomic(path, buffer.getvalue())


def game_counters(replay: Path, ticks: int = 3600) -> dict[str, list[int]]:
    """Per-tick counters of the default pipeline over a replay's first ticks."""
    from invaders.game.replay import load

    data = load(replay)
    world = data.world()
    series: dict[str, list[int]] = {"naive pairs": [], "rules allow": [], "broad phase": [],
                                    "rect tests": [], "mask + swept tests": [], "contacts": []}
    for n, bits in enumerate(data.actions()):
        if n >= ticks:
            break
        s = world.step(bits).stats
        for name, value in zip(series, (s.naive_pairs, s.allowed_pairs, s.candidates,
                                        s.rect_tests, s.mask_tests + s.swept_tests, s.contacts),
                               strict=True):
            series[name].append(value)
    return series


def scaling_rows(plan: Plan, rows: list[dict], budget: float) -> list[dict]:
    """Per storm size: ours (chosen from the scene, the engine's automatic choice, the grid,
    numpy, the cell rects), brute force (from the cells), groupcollide, and pymunk and
    Arcade given the same work (`references.PymunkScene`, `references.ArcadeScene`)."""
    from invaders.lab.references import arcade_steady_us, groupcollide_us, pymunk_steady_us
    from invaders.lab.runner import record, scene_rules

    out = []
    for n in plan.scaling:
        name = f"storm{n}x1"
        mine = {r["method"].split("/")[0]: float(r["us_per_tick"]) for r in rows
                if r["scene"] == name and r["method"].endswith("rect/mask/auto/every1")}
        spec = SceneSpec.storm(n, plan.scaling_ticks)
        frames = record(spec)
        out.append({"bodies": n, "ours_auto": mine.get("gridauto"),
                    "engine_auto": mine.get("auto"),
                    "grid_default": mine.get(f"grid{DEFAULT_CELL}"),
                    "sweep": mine.get("sweep"), "brute": mine.get("brute"),
                    "numpy": mine.get("numpy"), "rects": mine.get("rects"),
                    "groupcollide_mask": round(groupcollide_us(frames, budget), 1),
                    "pymunk_boxes": pymunk_steady_us(frames, scene_rules(spec)),
                    "arcade_boxes": arcade_steady_us(frames, scene_rules(spec))})
    return out


def study(out: Path, replays: Path | None, quick: bool = False, jobs: int = 1,
          scheduler: str | None = None, big: bool = False,
          saving: Callable[[], AbstractContextManager[object]] = nullcontext) -> int:
    """Run the study; write study.csv, scaling.csv and the charts into `out`, each write
    inside `saving()` (the command line's names a failed write's file and cause)."""
    out.mkdir(parents=True, exist_ok=True)
    recorded = sorted(replays.glob("*.json")) if replays is not None else []
    plan = make_plan(recorded, quick, big)
    where = f"on {scheduler}" if scheduler else f"{jobs} process{'es' if jobs > 1 else ''}"
    print(f"study: {plan.cells} cells over {len(plan.work)} scenes, {where}")
    bar = Progress(plan.cells, "study")
    rows = execute(plan, jobs, scheduler, bar.advance)
    bar.close()
    with saving():  # (the matrix kept before the scaling's timings, which take a while)
        write_csv(out / "study.csv", rows)
    scale = scaling_rows(plan, rows, budget=2.0 if quick else 20.0)
    with saving():
        write_csv(out / "scaling.csv", scale)
    for line in summary(rows, scale):
        print(line)
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("charts skipped: install the [chart] extra (matplotlib) to draw them")
        return 0
    with saving():
        draw_charts(out, rows, scale, recorded[0] if recorded else None)
    print(f"wrote {out / 'study.csv'}, {out / 'scaling.csv'} and "
          f"{'three' if recorded else 'two'} charts in {out}")
    return 0


def draw_charts(out: Path, rows: list[dict], scale: list[dict], game: Path | None) -> None:
    """The speed against accuracy, the counters of a recorded `game` (if one), and the
    scaling, as PNGs in `out`."""
    from invaders.lab import charts  # (it draws with matplotlib)

    charts.speed_accuracy(rows, out / "speed_accuracy.png")
    if game is not None:
        charts.counters(game_counters(game), out / "counters.png",
                        f"Pipeline counters per tick, {game.stem}")
    series = {label: [(r["bodies"], r[key]) for r in scale if r.get(key)]
              for label, key in (("ours (broad phase chosen from the scene)", "ours_auto"),
                                 ("ours (auto: chosen by body count)", "engine_auto"),
                                 ("grid, 32 px", "grid_default"),
                                 ("cell rects (brute force in C)", "rects"),
                                 ("numpy broad phase", "numpy"),
                                 ("brute force", "brute"), ("sort-and-sweep", "sweep"),
                                 ("groupcollide + collide_mask", "groupcollide_mask"),
                                 ("pymunk spatial hash, boxes only", "pymunk_boxes"),
                                 ("Arcade spatial hashes, boxes only", "arcade_boxes"))}
    charts.scaling(series, out / "scaling.png")


def game_scale(rows: list[dict]) -> list[str]:
    """The default against every exact single method over the replays (game scale)."""
    replays = [r for r in rows if r["scene"].startswith("replay:")]
    scenes = {r["scene"] for r in replays}
    by_method: dict[str, list[float]] = {}
    errors: dict[str, int] = {}
    for row in replays:
        by_method.setdefault(row["method"], []).append(float(row["us_per_tick"]))
        errors[row["method"]] = errors.get(row["method"], 0) + sum(
            int(row[k]) for k in ("missed", "false", "late"))
    exact = {m: sum(t) / len(t) for m, t in by_method.items()
             if errors[m] == 0 and len(t) == len(scenes)}
    default = "auto/rect/mask/auto/every1"  # the game's own broad phase
    if default not in exact:
        return []
    best = min(exact, key=lambda method: exact[method])
    return [f"at game scale ({len(scenes)} replays): default {exact[default]:.2f} us a tick; "
            f"best exact single method {best} {exact[best]:.2f} us "
            f"({exact[default] / exact[best]:.2f}x)"]


def summary(rows: list[dict], scale: list[dict]) -> list[str]:
    """What the study found, in a few lines."""
    from invaders.lab.charts import method_points, pareto

    points = method_points(rows)
    default = [p for p in points if p[2] == "rect/mask/auto/every1"]
    lines = []
    if default:
        lines.append(f"default (rect/mask/auto/every1): {default[0][0]:.1f} us a tick, "
                     f"{default[0][1]:.4f} errors per true contact")
    exact = sorted(p for p in points if p[1] == 0)
    if exact:
        lines.append(f"fastest exact method: {exact[0][2]} at {exact[0][0]:.1f} us a tick")
    front = ", ".join(label for _, _, label in pareto(points))
    lines.append(f"Pareto front: {front}")
    lines += game_scale(rows)
    if scale:
        big = max(scale, key=lambda r: r["bodies"])
        ours = big["ours_auto"] or big["grid_default"]
        if ours:
            lines.append(f"at {big['bodies']} bodies: ours {ours:.0f} us a tick, "
                         f"groupcollide {big['groupcollide_mask'] / ours:.0f}x slower"
                         + "".join(f", {name} (boxes only) {big[key] / ours:.1f}x slower"
                                   for name, key in (("pymunk", "pymunk_boxes"),
                                                     ("Arcade", "arcade_boxes"))
                                   if big[key]))
    return lines
