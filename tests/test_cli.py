"""The command line as users and CI call it: summaries, reports, hashes, one-line errors."""

from __future__ import annotations

import csv
import json
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

import pytest

import invaders
from invaders.app.cli import main

HEX = re.compile(r"^[0-9a-f]{32}$")


def _run(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_a_one_minute_autopilot_run_writes_3600_rows_and_the_grid_prunes(tmp_path, capsys):
    report = tmp_path / "r.csv"
    code, out, _ = _run(capsys, "run", "--ticks", "3600", "--seed", "7", "--autopilot",
                        "--report", str(report))
    assert code == 0
    assert HEX.match(out.strip().splitlines()[-1])
    with report.open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 3600
    assert [int(r["tick"]) for r in rows] == list(range(3600))
    candidates = statistics.median(int(r["candidates"]) for r in rows)
    naive = statistics.median(int(r["naive_pairs"]) for r in rows)
    assert naive > 500  # dozens of bodies on screen
    assert candidates <= 0.02 * naive
    assert sum(int(r["contacts"]) for r in rows) > 50  # the game really played
    assert not list(tmp_path.glob(".*.tmp"))  # no temporary file left behind


def test_the_hash_depends_on_the_seed_only_not_on_the_broad_phase(capsys):
    def last(*extra: str) -> str:
        code, out, _ = _run(capsys, "run", "--ticks", "1500", "--autopilot", *extra)
        assert code == 0
        return out.strip().splitlines()[-1]

    grid = last("--seed", "7")
    assert last("--seed", "7") == grid
    assert last("--seed", "7", "--broadphase", "brute") == grid
    assert last("--seed", "7", "--broadphase", "sweep") == grid
    assert last("--seed", "7", "--cell", "40") == grid
    assert last("--seed", "8") != grid


def test_the_summary_totals_and_medians_are_the_reports_columns(capsys, tmp_path):
    """Each pipeline step's line in the summary gives the total and the median of that
    counter over the run's report, tick by tick."""
    report = tmp_path / "r.csv"
    code, out, _ = _run(capsys, "run", "--ticks", "600", "--seed", "1", "--autopilot",
                        "--report", str(report))
    assert code == 0
    with report.open() as handle:
        rows = list(csv.DictReader(handle))
    steps = {"objects": "objects", "naive pairs n(n-1)/2": "naive_pairs",
             "1 reduce: rules allow": "allowed_pairs", "1 reduce: broad phase": "candidates",
             "2 quick: rect tests": "rect_tests", "2 quick: rect hits": "rect_hits",
             "3 thorough: mask tests": "mask_tests", "3 thorough: mask hits": "mask_hits",
             "3 thorough: swept tests": "swept_tests", "4 respond: contacts": "contacts"}
    for label, column in steps.items():
        (line,) = [ln for ln in out.splitlines() if ln.strip().startswith(label)]
        total, median = line[len(label) + 2:].split()
        values = [int(row[column]) for row in rows]
        assert (int(total), float(median)) == (sum(values), statistics.median(values)), label


def test_a_jsonl_report_has_one_object_per_tick(tmp_path, capsys):
    report = tmp_path / "r.jsonl"
    code, _, _ = _run(capsys, "run", "--ticks", "120", "--autopilot", "--report", str(report))
    assert code == 0
    records = [json.loads(line) for line in report.read_text().splitlines()]
    assert len(records) == 120
    assert set(records[0]) >= {"tick", "objects", "naive_pairs", "candidates", "contacts"}


@pytest.mark.parametrize("args, problem", [
    (["run", "--ticks", "-3"], "--ticks"),
    (["run", "--ticks", "lots"], "--ticks"),
    (["run", "--seed", "x"], "--seed"),
    (["run", "--broadphase", "octree"], "octree"),
    (["run", "--report", "out.txt"], ".csv or .jsonl"),
    (["run", "--report", "/no/such/folder/r.csv"], "cannot write report"),
    (["run", "--cell", "0"], "--cell"),
    (["play", "--scale", "99"], "--scale"),
    (["fly"], "fly"),
    (["run", "--broadphase", "brute", "--cell", "16"],
     "--cell is not used here: the brute broad phase has no cells"),
    (["play", "--attract", "title"], "--attract is not used here: they are for"),
    (["play", "--speed", "4"], "--speed is not used here"),
    (["play", "--ticks", "100"], "--ticks is not used here"),
    (["play", "--screenshot", "x.png", "--replay", "r.json"],
     "--replay is not used here: --screenshot plays a game of its own"),
    (["play", "--screenshot", "x.png", "--record", "r.json"], "--record is not used here"),
    (["play", "--replay", "r.json", "--seed", "5"],
     "--seed is not used here: --replay plays the game it holds"),
    (["play", "--replay", "r.json", "--players", "2"], "--players is not used here"),
    (["bench", "--reading", "--env"], "--env: not allowed with argument --reading"),
    (["bench", "--window", "--against", "HEAD"], "--against: not allowed with argument"),
    (["bench", "--reading", "--big"], "--big adds to the full bench; --reading runs instead"),
    (["bench", "--env", "--ale"], "--ale adds to the full bench; --env runs instead"),
    (["bench", "--against", "HEAD", "--largest", "10"], "--largest adds to the full bench"),
    (["bench", "--reading", "--ticks", "600"], "--ticks sets the game the full bench"),
    (["bench", "--arcade", "--env"], "--env: not allowed with argument --arcade"),
    (["bench", "--arcade", "--big"], "--big adds to the full bench; --arcade runs instead"),
    (["bench", "--arcade", "--seed", "3"], "--seed sets the game the full bench and --against"),
    (["study", "--jobs", "2", "--scheduler", "tcp://127.0.0.1:8786"],
     "--scheduler: not allowed with argument --jobs"),
    (["bench", "--window", "--seed", "3"], "--seed sets the game the full bench and --against"),
])
def test_bad_input_is_one_line_naming_the_problem_and_exit_2(capsys, args, problem):
    code, out, err = _run(capsys, *args)
    assert code == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1
    assert problem in err
    assert "Traceback" not in err


def test_bench_against_outside_a_checkout_or_a_name_of_no_commit_is_one_line(
        capsys, monkeypatch, tmp_path):
    """Where the tree has no git history (a release archive), or the name is of no commit,
    --against says so in words, naming the tree or the name."""
    tree = tmp_path / "tree"
    monkeypatch.setattr(invaders, "__file__", str(tree / "invaders" / "__init__.py"))
    words = ["bench", "--rounds", "3", "--ticks", "60", "--against"]
    code, _, err = _run(capsys, *words, "HEAD")
    assert code == 2
    assert err.splitlines() == [
        f"invaders: error: --against compares with the project's git history, and {tree} "
        "is not in a git checkout (an installed package and a release archive have none: run "
        "it from the editable install of a clone)"]
    subprocess.run(["git", "init", "-q", str(tree)], check=True)
    code, _, err = _run(capsys, *words, "no-such-revision")
    assert code == 2
    assert err.splitlines() == [
        f"invaders: error: --against: 'no-such-revision' names no commit of the repository "
        f"at {tree}"]


@pytest.mark.parametrize("words", [["play"], [], ["--scale", "2"]])
def test_play_without_a_display_is_one_line(words):
    """`invaders play`, or `invaders` with no command (alone, or with play's options)."""
    script = Path(sys.executable).with_name("invaders")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    env["SDL_VIDEODRIVER"] = "x11"  # no X server here: the window cannot open
    result = subprocess.run([str(script), *words], capture_output=True, text=True, env=env,
                            timeout=60, check=False)
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1
    assert "cannot open a window" in result.stderr


@pytest.mark.parametrize("command", [[str(Path(sys.executable).with_name("invaders"))],
                                     [sys.executable, "-m", "invaders"]])
def test_the_installed_command_runs_headless(command):
    """The command, or `python -m invaders` (the same program: a command named plays it)."""
    result = subprocess.run([*command, "run", "--ticks", "200", "--seed", "3"],
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    assert HEX.match(result.stdout.strip().splitlines()[-1])
    assert "pygame" not in result.stdout  # no banner: the hash is the last line, cleanly


def test_the_lab_twin_shadows_a_run_without_changing_it(capsys):
    args = ["run", "--autopilot", "--ticks", "2500", "--seed", "3"]
    assert main(args) == 0
    plain = capsys.readouterr().out.strip().splitlines()
    assert main([*args, "--shadow"]) == 0
    shadowed = capsys.readouterr().out.strip().splitlines()
    assert shadowed[-1] == plain[-1]  # watching changes nothing: the same final hash
    line = next(x for x in shadowed if x.startswith("shadow (rect/mask/auto)"))
    assert "missed 0, false 0" in line and "late 0" in line


def test_discrete_tests_at_eight_times_the_speed_miss_what_the_oracle_sees(capsys):
    assert main(["run", "--autopilot", "--ticks", "2500", "--seed", "3", "--shadow",
                 "--motion", "discrete", "--speed-mult", "8"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines()
                if x.startswith("shadow (rect/mask/discrete at 8x)"))
    missed = int(line.split("missed ")[1].split(",")[0])
    assert missed > 0


def test_bench_against_ale_without_the_compare_extra_says_how_to_get_it(monkeypatch, capsys):
    import invaders.lab.ale

    monkeypatch.setattr(invaders.lab.ale, "available", lambda: False)
    assert main(["bench", "--ale"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["invaders: error: --ale needs ale-py: pip install '.[compare]'"]


def test_bench_against_arcade_without_it_says_how_to_get_it(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "arcade", None)  # (its import fails)
    assert main(["bench", "--arcade"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["invaders: error: --arcade needs arcade: pip install '.[compare]'"]


def test_the_bare_step_loop_and_ale_share_one_input_cycle_that_plays_the_game():
    from invaders.game.events import Event
    from invaders.game.world import World
    from invaders.lab.ale import CYCLE

    world = World(seed=7)
    places, fired = set(), 0
    for i in range(1800):
        fired += Event.SHOT_FIRED in world.step(CYCLE[i % len(CYCLE)]).events
        places.add(world.cannon.x)
    # it moves both ways across the field and fires: it plays, not idles
    assert max(places) - min(places) >= 15 and fired > 15 and world.aliens_killed >= 5


@pytest.mark.parametrize("words, problem", [
    (["play", "--record", ""], "argument --record: an empty name"),
    (["play", "--replay", " "], "argument --replay: an empty name"),
    (["play", "--screenshot", ""], "argument --screenshot: an empty name"),
    (["run", "--record", ""], "argument --record: an empty name"),
    (["run", "--report", ""], "argument --report: an empty name"),
    (["replay", ""], "argument PATH: an empty name"),
    (["study", "--out", ""], "argument --out: an empty name"),
    # (an empty folder of replays was the current folder; an empty scheduler, no scheduler
    # until the study asked Dask for one: exit 3)
    (["study", "--replays", ""], "argument --replays: an empty name"),
    (["study", "--scheduler", ""], "argument --scheduler: an empty name"),
    (["run", "--ticks", "9" * 5000], "argument --ticks: must be between 1 and"),
    (["run", "--seed", "x" * 300], "argument --seed: must be a whole number, not 'xxxxxxxx"),
])
def test_empty_names_and_huge_values_are_refused_in_one_short_line(words, problem, capsys):
    assert main(words) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and problem in err and len(err) < 200


def test_a_seed_with_a_leading_zero_is_the_decimal_number(capsys):
    assert main(["run", "--seed", "010", "--ticks", "2"]) == 0
    assert "seed 10," in capsys.readouterr().out


def test_watching_a_replay_while_recording_over_it_is_refused(tmp_path, capsys):
    source = Path(__file__).resolve().parents[1] / "replays" / "invasion.json"
    watched = tmp_path / "game.json"
    watched.write_bytes(source.read_bytes())
    before = watched.read_bytes()
    assert main(["play", "--replay", str(watched), "--record",
                 str(tmp_path / "." / "game.json")]) == 2
    assert "would overwrite it" in capsys.readouterr().err
    assert watched.read_bytes() == before


def test_an_unreachable_dask_scheduler_is_bad_input_and_makes_nothing(tmp_path, monkeypatch,
                                                                      capsys):
    from invaders.app import cli

    monkeypatch.setattr(cli, "SCHEDULER_TIMEOUT", 1.0)
    out = tmp_path / "study-out"
    assert main(["study", "--quick", "--scheduler", "tcp://127.0.0.1:1", "--out",
                 str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "no Dask scheduler answers" in err
    assert not out.exists()


def test_every_option_of_every_command_says_what_it_does_and_its_default():
    """`invaders COMMAND --help` describes each option (--seed, --scale, --ticks and
    --broadphase said nothing), and one that takes a number or a name without a list to
    choose from names its default."""
    import argparse

    from invaders.app.cli import COMMANDS, build_parser

    for command in COMMANDS:
        parser = build_parser(command)
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        for action in sub.choices[command]._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            name = f"{command} {action.option_strings or action.dest}"
            assert action.help, f"{name} has no help"
            if (action.choices is None and action.default is not None
                    and not isinstance(action.default, bool)):
                assert f"{action.default} by default" in action.help, name
