"""The study's three charts (matplotlib, the [chart] extra), written as PNG atomically.

1. Speed against accuracy, one panel per family of scenes (the game's replays; storms of
   one size): one point per method, its time relative to the fastest method on the same
   scenes against its errors per true contact, the Pareto front and the default marked.
2. Counters per tick over a game: how many pairs each pipeline step considered.
3. Time per tick against body count, log-log: ours, brute force, groupcollide with
   collide_mask, pymunk's and Arcade's spatial hashes (boxes only).
"""

from __future__ import annotations

import math
from collections import defaultdict
from pathlib import Path

from invaders.atomic import atomic_path
from invaders.engine.grid import DEFAULT_CELL


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _finish(plt, fig, ax, path: Path, xlabel: str, ylabel: str, title: str) -> None:
    """Labels, legend and grid as every chart has them; then save (atomically) and close.
    The legend stands beside the panel, where it covers no line (inside, the lines' ends
    ran under it)."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.grid(True, which="both", alpha=0.3)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)


def pareto(points: list[tuple[float, float, str]]) -> list[tuple[float, float, str]]:
    """Points no other point beats on both time and errors (lower is better), by time."""
    front = []
    best = float("inf")
    for x, y, label in sorted(points):
        if y < best:
            front.append((x, y, label))
            best = y
    return front


def method_points(rows: list[dict]) -> list[tuple[float, float, str]]:
    """(mean us per tick, errors per true contact, label) per narrow-phase method, over the
    accuracy cells (the default broad phase) of the scenes every method ran on."""
    time_sum: dict[str, float] = defaultdict(float)
    count: dict[str, int] = defaultdict(int)
    errors: dict[str, int] = defaultdict(int)
    true: dict[str, int] = defaultdict(int)
    cells = [r for r in rows if r["method"].startswith(f"grid{DEFAULT_CELL}/")]
    scenes: dict[str, set[str]] = defaultdict(set)
    for row in cells:
        scenes[row["method"]].add(row["scene"])
    common = set.intersection(*scenes.values()) if scenes else set()
    for row in cells:
        if row["scene"] not in common:
            continue
        label = row["method"].split("/", 1)[1]
        time_sum[label] += float(row["us_per_tick"])
        count[label] += 1
        errors[label] += int(row["missed"]) + int(row["false"]) + int(row["late"])
        true[label] += int(row["true"])
    return [(time_sum[k] / count[k], errors[k] / max(1, true[k]), k) for k in time_sum]


def family(scene: str) -> str:
    """The family a scene is drawn with: the game's replays, or storms of one size."""
    if scene.startswith("replay:"):
        return "game scale (replays)"
    return f"storms of {scene[len('storm'):].split('x')[0]} bodies"


def family_points(rows: list[dict]) -> dict[str, list[tuple[float, float, str]]]:
    """Per family: (time relative to the fastest method on the same scene, averaged over
    the family's scenes; errors per true contact; label) per narrow-phase method."""
    cells = [r for r in rows if r["method"].startswith(f"grid{DEFAULT_CELL}/")]
    fastest: dict[str, float] = {}
    for row in cells:
        us = float(row["us_per_tick"])
        fastest[row["scene"]] = min(fastest.get(row["scene"], us), us)
    out = {}
    names = {family(r["scene"]): r["scene"] for r in cells}
    order = sorted(names, key=lambda n: (n.startswith("storms"), int(
        names[n][len("storm"):].split("x")[0]) if n.startswith("storms") else 0))
    for name in order:
        mine = [r for r in cells if family(r["scene"]) == name]
        relative = [dict(r, us_per_tick=float(r["us_per_tick"]) / max(fastest[r["scene"]],
                                                                       1e-9))
                    for r in mine]
        points = method_points(relative)
        if len(points) > 1:  # a family timed with the default alone says nothing here
            out[name] = points
    return out


def speed_accuracy(rows: list[dict], path: Path) -> None:
    plt = _pyplot()
    families = family_points(rows)
    fig, axes = plt.subplots(1, len(families), figsize=(6.5 * len(families), 5.5),
                             squeeze=False)
    for ax, (name, points) in zip(axes[0], families.items(), strict=True):
        _speed_accuracy_panel(ax, name, points)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)


def _speed_accuracy_panel(ax, name: str, points: list[tuple[float, float, str]]) -> None:
    """One family's methods, its Pareto front numbered along it, and the default. The
    front's names are in the legend, under the panel, by number: written beside their
    points, close ones ran into each other."""
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FuncFormatter

    front = pareto(points)
    ax.scatter([p[0] for p in points], [p[1] for p in points], s=18, color="#8899aa",
               label="methods")
    ax.plot([p[0] for p in front], [p[1] for p in front], "-o", color="#d62728", ms=5,
            label="Pareto front")
    for number, (x, y, _) in enumerate(front, 1):
        ax.annotate(str(number), (x, y), fontsize=8, xytext=(3, 4), color="#d62728",
                    textcoords="offset points")
    default = [p for p in points if p[2] == "rect/mask/auto/every1"]
    if default:
        ax.scatter([default[0][0]], [default[0][1]], s=90, marker="*", color="#2ca02c",
                   zorder=5, label="default (rect/mask/auto/every1)")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=0.01)
    ax.set_ylim(bottom=0)
    ax.xaxis.set_major_formatter(FuncFormatter(_times))
    ax.xaxis.set_minor_formatter(FuncFormatter(_times_if_round))
    ax.set_xlabel("time per tick, relative to the fastest method on the same scenes")
    ax.set_ylabel("errors per true contact (missed + false + late)")
    ax.set_title(f"{name}: quick / thorough / motion / sampling", fontsize=10)
    numbered = [Line2D([], [], linestyle="none", marker=f"${number}$", color="#d62728",
                       markersize=6 + 2 * len(str(number)), label=label)
                for number, (_, _, label) in enumerate(front, 1)]
    handles, _ = ax.get_legend_handles_labels()
    ax.legend(handles=handles + numbered, fontsize=8, ncol=2, loc="upper center",
              bbox_to_anchor=(0.5, -0.13), frameon=False)
    ax.grid(True, which="both", alpha=0.3)


def _times(value: float, _position: object) -> str:
    """A ratio on the time axis: 1x, 10x."""
    return f"{value:g}x"


def _times_if_round(value: float, position: object) -> str:
    """The log axis's minor ticks labelled at 2, 3 and 5 of each decade only (2x, 30x):
    every one of them ran together over two decades."""
    leading = value / 10 ** math.floor(math.log10(value))
    return _times(value, position) if round(leading) in (2, 3, 5) else ""


def counters(series: dict[str, list[int]], path: Path, title: str) -> None:
    """Per-tick counters (a rolling mean over a second), one line per pipeline step; steps
    that counted the same at every tick share one line (one drawn over the other hid it),
    and none is 0.01 where it is 0 (the scale is linear below 0.01)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    window = 60
    for names, values in same_counts(series):
        smoothed = [sum(values[max(0, i - window + 1):i + 1]) / min(i + 1, window)
                    for i in range(len(values))]
        ax.plot(range(len(values)), smoothed, label=" = ".join(names), lw=1.2)
    ax.set_yscale("symlog", linthresh=0.01)
    ax.set_ylim(bottom=0)
    _finish(plt, fig, ax, path, "tick", "pairs per tick (mean over 60 ticks)", title)


def same_counts(series: dict[str, list[int]]) -> list[tuple[list[str], list[int]]]:
    """The series in order, those equal at every tick together under all their names."""
    merged: list[tuple[list[str], list[int]]] = []
    for name, values in series.items():
        same = next((names for names, kept in merged if kept == values), None)
        if same is not None:
            same.append(name)
        else:
            merged.append(([name], values))
    return merged


def scaling(series: dict[str, list[tuple[int, float]]], path: Path) -> None:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for name, points in series.items():
        if points:
            points = sorted(points)
            ax.plot([p[0] for p in points], [p[1] for p in points], "-o", ms=4, label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    _finish(plt, fig, ax, path, "bodies in the scene", "detection time per tick (us)",
            "Time per tick against body count (storm scenes)")
