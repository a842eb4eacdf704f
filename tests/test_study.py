"""The study: a small plan end to end, the same answers however it is run, and its charts."""

from __future__ import annotations

import csv
import errno
import os
import sys
from pathlib import Path

import pygame
import pytest

from invaders.app.cli import main
from invaders.lab import charts
from invaders.lab.matrix import Method
from invaders.lab.plan import Plan, Progress, execute
from invaders.lab.runner import SceneSpec
from tests.helpers import FullStream

REPLAYS = Path(__file__).resolve().parents[1] / "replays"
# Fields that depend on timing: speeds, and which broad phase an automatic choice made.
TIMING = {"us_per_detection", "us_per_tick", "broad", "cell", "candidates", "rect_tests"}


def _plan() -> Plan:
    methods = [Method(), Method(motion="discrete"), Method(thorough="none"),
               Method(quick="circle"), Method(sampling=4), Method(cell=0)]
    return Plan(work=[(SceneSpec.of_replay(REPLAYS / "cannon-death.json", 400), methods),
                      (SceneSpec.storm(300, 6, multiplier=4), methods)], repeat=1)


@pytest.fixture(scope="module")
def serial_rows() -> list[dict]:
    return execute(_plan())


def _accuracy(rows: list[dict]) -> list[dict]:
    return [{k: v for k, v in row.items() if k not in TIMING} for row in rows]


def _row(rows, scene, method):
    (row,) = [r for r in rows if r["scene"] == scene and r["method"] == method]
    return row


def test_the_default_is_exact_and_cheaper_methods_show_their_failures(serial_rows):
    default = "grid32/rect/mask/auto/every1"
    for scene in ("replay:cannon-death", "storm300x4"):
        row = _row(serial_rows, scene, default)
        assert row["true"] > 0
        assert (row["missed"], row["false"], row["late"]) == (0, 0, 0)
    assert _row(serial_rows, "storm300x4", "grid32/rect/mask/discrete/every1")["missed"] > 0
    assert _row(serial_rows, "replay:cannon-death", "grid32/rect/none/auto/every1")["false"] > 0
    assert _row(serial_rows, "replay:cannon-death", "grid32/rect/mask/auto/every4")["missed"] > 0
    circle = _row(serial_rows, "storm300x4", "grid32/circle/mask/auto/every1")
    assert (circle["missed"], circle["false"]) == (0, 0)  # circles are conservative; masks fix
    auto = _row(serial_rows, "storm300x4", "gridauto/rect/mask/auto/every1")
    assert (auto["missed"], auto["false"], auto["late"]) == (0, 0, 0)


def test_processes_give_the_same_answers_as_a_single_one(serial_rows):
    assert _accuracy(execute(_plan(), jobs=2)) == _accuracy(serial_rows)


def test_a_local_dask_cluster_gives_the_same_answers(serial_rows):
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=1, processes=False, dashboard_address=None) as c:
        rows = execute(_plan(), scheduler=c.scheduler_address)
    assert _accuracy(rows) == _accuracy(serial_rows)


def test_a_study_goes_on_when_its_progress_cannot_be_written(serial_rows, monkeypatch):
    """Standard error on a full disk: the progress lines go nowhere and the study goes on
    to its rows (the first line's failure ended it, exit 2, with nothing written)."""
    monkeypatch.setattr(sys, "stderr", FullStream())
    plan = _plan()
    bar = Progress(plan.cells, "study")
    rows = execute(plan, 1, None, bar.advance)
    bar.close()
    assert _accuracy(rows) == _accuracy(serial_rows)


def test_the_charts_are_drawn(serial_rows, tmp_path):
    charts.speed_accuracy(serial_rows, tmp_path / "a.png")
    charts.counters({"candidates": [0, 1, 3, 2] * 30, "contacts": [0, 0, 1, 0] * 30},
                    tmp_path / "b.png", "counters")
    charts.scaling({"ours": [(100, 150.0), (1000, 1300.0)],
                    "brute": [(100, 1500.0), (1000, 160000.0)]}, tmp_path / "c.png")
    def colours(name: str) -> set[tuple[int, int, int]]:
        image = pygame.image.load(str(tmp_path / f"{name}.png"))
        return {tuple(image.get_at((x, y)))[:3] for x in range(0, image.get_width(), 2)
                for y in range(0, image.get_height(), 2)}

    green, red, grey = (0x2C, 0xA0, 0x2C), (0xD6, 0x27, 0x28), (0x88, 0x99, 0xAA)
    assert {green, red, grey} <= colours("a")  # the default's star, the front, the methods
    blue, orange = (0x1F, 0x77, 0xB4), (0xFF, 0x7F, 0x0E)  # matplotlib's first two lines
    assert {blue, orange} <= colours("b") and {blue, orange} <= colours("c")


def test_the_speed_charts_labels_run_into_nothing(serial_rows):
    """The Pareto front numbered along it and named in the legend under the panel, by
    number (names written beside close points ran into each other, and past the panel's
    edge); no label touches another, the legend, the axis' title or its ratios (1x...)."""
    plt = charts._pyplot()  # (matplotlib as the charts draw with it)

    crowded = [(1.0 + i / 40, 1.0 - i / 9, f"method/{i}") for i in range(9)]  # a front of 9
    for name, points in [*charts.family_points(serial_rows).items(), ("crowded", crowded)]:
        fig, ax = plt.subplots(figsize=(6.5, 5.5))
        charts._speed_accuracy_panel(ax, name, points)
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        front = charts.pareto(points)
        legend = ax.get_legend()
        assert [t.get_text() for t in ax.texts] == [str(n) for n in range(1, len(front) + 1)]
        assert [t.get_text() for t in legend.get_texts()][-len(front):] == [
            label for _, _, label in front]
        ticks = [t for t in ax.get_xticklabels(which="both") if t.get_text()]
        assert ticks and all(t.get_text().endswith("x") for t in ticks)
        boxes = [t.get_window_extent(renderer) for t in [*ax.texts, *ticks, ax.xaxis.label]]
        boxes.append(legend.get_window_extent(renderer))
        for i, box in enumerate(boxes):
            assert not any(box.overlaps(other) for other in boxes[i + 1:]), (name, i)
        plt.close(fig)


def test_counters_equal_at_every_tick_share_a_line_named_for_both():
    series = {"naive pairs": [9, 9], "broad phase": [1, 0], "rect tests": [1, 0],
              "contacts": [0, 0], "mask tests": [0, 0]}
    assert charts.same_counts(series) == [(["naive pairs"], [9, 9]),
                                          (["broad phase", "rect tests"], [1, 0]),
                                          (["contacts", "mask tests"], [0, 0])]


def test_the_counters_and_scaling_legends_stand_clear_of_the_lines(tmp_path, monkeypatch):
    """Beside the panel, not over its lines (the counters' legend covered their ends)."""
    plt = charts._pyplot()  # (matplotlib as the charts draw with it)

    kept = []
    monkeypatch.setattr(plt, "close", kept.append)  # (the figures kept to be read)
    charts.counters({"naive pairs": [500] * 120, "contacts": [0, 1] * 60},
                    tmp_path / "b.png", "counters")
    charts.scaling({"ours": [(100, 150.0), (1000, 1300.0)]}, tmp_path / "c.png")
    for fig in kept:
        ax = fig.axes[0]
        renderer = fig.canvas.get_renderer()
        assert not ax.get_legend().get_window_extent(renderer).overlaps(
            ax.get_window_extent(renderer))
    counted = kept[0].axes[0].get_lines()[1].get_ydata()
    assert min(counted) == 0 and kept[0].axes[0].get_ylim()[0] == 0  # (a zero drawn at 0)


def test_the_pareto_front_keeps_only_points_nothing_beats():
    points = [(1.0, 0.5, "a"), (2.0, 0.1, "b"), (3.0, 0.3, "c"), (4.0, 0.0, "d")]
    assert [p[2] for p in charts.pareto(points)] == ["a", "b", "d"]


def test_study_quick_from_any_folder_studies_the_storms(quick_study):
    code, printed, out = quick_study  # run where there is no ./replays, as after an install
    assert code == 0
    assert printed.startswith("study: no ./replays folder here: studying the storms only")
    assert "default (rect/mask/auto/every1)" in printed and "0.0000 errors" in printed
    with (out / "study.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) > 50 and all(row["scene"].startswith("storm") for row in rows)
    assert {p.name for p in out.iterdir()} == {"study.csv", "scaling.csv",
                                               "speed_accuracy.png", "scaling.png"}
    with (out / "scaling.csv").open() as handle:  # the outside references timed at each size
        scaling = list(csv.DictReader(handle))
    assert scaling and all(float(row[key]) > 0 for row in scaling
                           for key in ("groupcollide_mask", "pymunk_boxes", "arcade_boxes"))
    assert "pymunk (boxes only)" in printed and "Arcade (boxes only)" in printed


@pytest.mark.parametrize("args, problem", [
    (["study", "--replays", "/no/such/folder"], "--replays"),
    (["study", "--jobs", "0"], "--jobs"),
])
def test_bad_study_options_are_one_line(capsys, args, problem):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and problem in err


def test_an_out_folder_that_cannot_be_made_is_named_as_given(capsys, tmp_path):
    """--out inside a file: the one line names the folder asked for (it named the
    study.csv the check tried in the first folder that exists), before any scene runs."""
    (tmp_path / "plain").write_text("")
    out = tmp_path / "plain" / "study"
    assert main(["study", "--quick", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"invaders: error: cannot write study {str(out)!r}: "
                                       f"{str(tmp_path / 'plain')!r} is not a folder\n")


def test_a_study_that_cannot_be_written_is_one_line(capsys, tmp_path, monkeypatch,
                                                   serial_rows):
    """The matrix run, its file cannot be written (the disk full: every fsync fails): one
    line names the folder and the cause, exit 2 (an internal error, exit 3, before)."""
    from invaders.lab import plan

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(plan, "execute", lambda *_: serial_rows)
    monkeypatch.setattr(os, "fsync", full)
    out = tmp_path / "study"
    assert main(["study", "--quick", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"invaders: error: cannot write the study into "
                                       f"{str(out)!r}: no space left on the device\n")
    assert list(out.iterdir()) == []  # (no temporary file left)


def test_speed_is_charted_per_family_relative_to_the_fastest_on_the_same_scenes(serial_rows):
    families = charts.family_points(serial_rows)
    assert set(families) == {"game scale (replays)", "storms of 300 bodies"}
    for points in families.values():
        assert min(x for x, _, _ in points) >= 1.0
        assert any(label == "rect/mask/auto/every1" and y == 0 for _, y, label in points)
    storm = families["storms of 300 bodies"]  # one scene: its fastest method is at 1
    assert min(x for x, _, _ in storm) == 1.0


def test_big_adds_a_storm_of_30000_bodies_to_the_scaling_without_brute_force():
    from invaders.lab.plan import BIG_STORM, RECTS_LIMIT, make_plan

    plan = make_plan([], quick=False, big=True)
    assert plan.scaling[-1] == BIG_STORM == 30000
    ((_, methods),) = [w for w in plan.work if w[0].bodies == BIG_STORM]
    assert {m.broad for m in methods} == {"grid", "sweep", "numpy", "auto"}  # no brute force
    sized: dict[int, set[str]] = {}  # every broad phase a storm of each size is played with
    for spec, methods in plan.work:
        if spec.bodies:
            sized.setdefault(spec.bodies, set()).update(m.broad for m in methods)
    assert sized.keys() == set(plan.scaling)
    assert all(("rects" in broads) == (n <= RECTS_LIMIT) for n, broads in sized.items())
    assert BIG_STORM not in make_plan([], quick=False).scaling
