"""Replays: the same hashes whatever runs them, bad files refused in one line, nothing lost."""

from __future__ import annotations

import copy
import dataclasses
import errno
import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pygame
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from invaders.app.cli import main
from invaders.app.play import Session, open_window
from invaders.app.recording import Recorder, record_headless, save_replay
from invaders.game.config import GameConfig
from invaders.game.recording import ReplayRecorder
from invaders.game.replay import Checkpoint, Replay, ReplayError, load, parse, parse_lines, run
from invaders.game.statehash import combine
from invaders.game.world import World
from invaders.lab.autopilot import Autopilot
from tests.helpers import FakeClock, windowed

TICKS = 1500


@pytest.fixture(scope="module")
def replay_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("replays") / "game.json"
    replay = record_headless(World(seed=4), Autopilot(4), TICKS)
    save_replay(path, replay)
    return path


def _objects(path: Path) -> list:
    """A version-2 file as its decoded lines: the header, then one object per checkpoint."""
    return [json.loads(line) for line in path.read_text().splitlines()]


HUGE = "<a number of 5001 digits>"  # json.dumps refuses to write one: spliced in as text


def _write(path: Path, objects: list) -> Path:
    text = "".join(json.dumps(o, separators=(",", ":")) + "\n" for o in objects)
    path.write_text(text.replace(json.dumps(HUGE), "1" + "0" * 5000))
    return path


def _version_1(replay: Replay) -> dict:
    """The same replay as a version-1 object (the format older programs wrote)."""
    header = json.loads(replay.header_line())
    return {**header, "version": 1, "ticks": replay.ticks, "inputs": replay.inputs.lists(),
            "checkpoints": [dataclasses.asdict(c) for c in replay.checkpoints]}


def _final_hash(replay: Replay, broadphase: str = "grid") -> str:
    result, _ = run(replay, broadphase)
    assert result.mismatch is None, result.mismatch
    return result.final.hash



@pytest.mark.parametrize("fps, window", [(30, False), (60, True), (144, False)])
def test_a_windowed_session_at_any_frame_rate_gives_the_recorded_hashes(replay_file, fps,
                                                                        window):
    replay = load(replay_file)
    world = World(replay.seed, replay.config)
    clock = FakeClock()
    target = open_window(1) if window else pygame.Surface((224, 256))  # dummy video driver
    session = Session(world, target, clock, replay=replay)
    expected = {c.tick: c.hash for c in replay.checkpoints}
    seen = {}
    frames = 0
    while not session.replay_done:
        clock.now += 1 / fps
        session.frame(0)
        frames += 1
        if world.tick in expected:
            seen[world.tick] = world.state_hash()
    if window:
        pygame.display.flip()
        pygame.display.quit()
    assert world.tick == replay.ticks
    assert frames >= replay.ticks * fps // 60 - 2
    for tick, digest in seen.items():
        assert expected[tick] == digest, tick
    assert replay.ticks in seen


def test_grid_and_brute_and_a_second_run_in_the_same_process_agree(replay_file):
    replay = load(replay_file)
    first = _final_hash(replay)
    assert _final_hash(replay, "brute") == first
    assert _final_hash(load(replay_file)) == first


def test_fresh_processes_agree_with_this_one(replay_file, tmp_path):
    other = tmp_path / "other.json"
    save_replay(other, record_headless(World(seed=9), Autopilot(9, "expert"), 700))
    in_process = [_final_hash(load(replay_file)), _final_hash(load(other))]
    script = Path(sys.executable).with_name("invaders")
    for path, digest in zip((replay_file, other), in_process, strict=True):
        result = subprocess.run([str(script), "replay", str(path)], capture_output=True,
                                text=True, timeout=120, check=False)
        assert result.returncode == 0, result.stdout + result.stderr
        assert result.stdout.startswith(f"ok {path}")
        assert load(path).checkpoints[-1].hash == digest


def test_a_recording_made_in_a_window_replays_headless_to_the_same_hash():
    world = World(seed=2)

    recorder = Recorder(world)
    session, clock = windowed(world, recorder=recorder)
    for frame in range(600):
        clock.now += 1 / 75
        keys = (1 if frame % 90 < 40 else 2) | (4 if frame % 7 == 0 else 0)
        session.frame(keys)
    replay = recorder.finished()
    assert replay.ticks == world.tick == 480
    assert _final_hash(parse_lines(list(replay.lines()))) == world.state_hash()
    assert _final_hash(parse(_version_1(replay))) == world.state_hash()  # the old format too


def test_the_replay_command_passes_good_files_and_names_the_first_difference(
        replay_file, tmp_path, capsys):
    assert main(["replay", str(replay_file)]) == 0
    lines = _objects(replay_file)
    run_ = lines[len(lines) // 2]["inputs"][0]
    run_[0] = 1 if run_[0] != 1 else 2  # the cannon moves elsewhere: the game goes another way
    bad = _write(tmp_path / "changed.json", lines)
    capsys.readouterr()
    assert main(["replay", str(bad)]) == 1
    out = capsys.readouterr().out
    changed = load(bad)  # played by hand: the first checkpoint the new inputs do not reach
    world, bits = World(changed.seed, changed.config), [b for b, n in changed.inputs
                                                          for _ in range(n)]
    first = None
    for checkpoint in changed.checkpoints:
        while world.tick < checkpoint.tick:
            world.step(bits[world.tick])
        if Checkpoint.of(world) != checkpoint:
            first = (checkpoint, Checkpoint.of(world))
            break
    assert first is not None
    expected, got = first
    assert out.startswith(f"FAIL {bad}: first difference at tick {expected.tick}: ")
    assert out.rstrip().endswith("; ".join(got.differences(expected)))
    assert main(["replay", "--update", str(bad)]) == 0
    assert "1 of 1 replay files changed" in capsys.readouterr().out
    assert main(["replay", str(bad)]) == 0
    assert main(["replay", "--update", str(bad)]) == 0
    assert "0 of 1 replay files changed" in capsys.readouterr().out


def _error_of(capsys, *paths: str) -> tuple[int, str]:
    code = main(["replay", *paths])
    err = capsys.readouterr().err
    return code, err


def _variant(replay_file: Path, tmp_path: Path, name: str, change) -> Path:
    lines = _objects(replay_file)
    change(lines)
    return _write(tmp_path / f"{name}.json", lines)


def _first_run(lines: list) -> list:
    return next(line["inputs"][0] for line in lines[1:] if line["inputs"])


def _rehashed(checkpoint: dict, **groups: str) -> None:
    """Change some group digests and make the hash the digest of the groups as changed."""
    checkpoint["groups"].update(groups)
    checkpoint["hash"] = combine(checkpoint["groups"])


BAD = {  # name: (change to the decoded lines, words the one-line error must hold)
    "wrong-format": (lambda d: d[0].update(format="chess-game"), "format"),
    "wrong-version": (lambda d: d[0].update(version=99), "version 99"),
    "version-true": (lambda d: d[0].update(version=True), "version True"),
    "version-float": (lambda d: d[0].update(version=2.0), "a fraction ('2.0')"),
    "negative-tick": (lambda d: d[2]["checkpoint"].update(tick=-5), "tick"),
    "absurd-count": (lambda d: d[2]["inputs"].append([0, 10**12]), "count"),
    "unknown-action": (lambda d: _first_run(d).__setitem__(0, 64), "unknown action"),
    "hash-not-hex": (lambda d: d[2]["checkpoint"].update(hash="z" * 32), "hex"),
    "hash-not-of-groups": (lambda d: d[2]["checkpoint"]["groups"].update(rack="0" * 16),
                           "hash does not match its groups"),
    "group-newline": (lambda d: _rehashed(d[2]["checkpoint"], rack="0" * 16 + "\n"),
                      "group rack is not 16 lower-case hex digits"),
    "count-key-newline": (lambda d: d[2]["checkpoint"]["counts"].update({"x\ny": 1}),
                          "counts must name exactly"),
    "no-seed": (lambda d: d[0].pop("seed"), "seed"),
    "huge-seed": (lambda d: d[0].update(seed=HUGE), "5001 digits"),
    "config-type": (lambda d: d[0]["config"]["speeds"].update(shot="fast"),
                    "config.speeds.shot"),
    "config-rows": (lambda d: d[0]["config"]["geometry"].update(rows=6),
                    "config.geometry.rows = 6 is out of range 1..5"),
    "plunger-column": (lambda d: d[0]["config"]["rules"]["plunger_columns"].__setitem__(0, 177),
                       "config.rules.plunger_columns = 177 is out of range 1..11"),
    "runaway-drop": (lambda d: d[0]["config"]["speeds"].update(rack_drop=10**9),
                     "config.speeds.rack_drop = 1000000000 is out of range"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_each_bad_file_gets_one_line_naming_file_and_problem(replay_file, tmp_path, capsys,
                                                             name):
    change, problem = BAD[name]
    path = _variant(replay_file, tmp_path, name, change)
    code, err = _error_of(capsys, str(path))
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    assert str(path) in err and problem in err


def test_a_path_that_names_no_replay_is_said_and_the_others_checked(replay_file, tmp_path,
                                                                  capsys):
    """A typo among the paths given: one line for it, each other file still checked (as a
    file that cannot be read is), exit 2."""
    empty, typo = tmp_path / "empty", tmp_path / "typo.json"
    empty.mkdir()
    code = main(["replay", str(typo), str(replay_file), str(empty)])
    out, err = capsys.readouterr()
    assert code == 2 and out.startswith(f"ok {replay_file}:")
    assert err.splitlines() == [f"invaders: error: {typo}: no such file or folder",
                                f"invaders: error: {empty}: no replay files (*.json) in this "
                                "folder"]


def test_a_folders_links_that_lead_nowhere_are_said_not_skipped(replay_file, tmp_path,
                                                                capsys):
    """A link to a file gone, and one round in a loop, beside a replay: each said in one
    line (the folder's check skipped both without a word), the replay still checked."""
    folder = tmp_path / "games"
    folder.mkdir()
    (folder / "game.json").write_text(replay_file.read_text())
    (folder / "gone.json").symlink_to(tmp_path / "unplugged" / "game.json")
    (folder / "loop.json").symlink_to("loop.json")
    code = main(["replay", str(folder)])
    out, err = capsys.readouterr()
    assert code == 2 and out.startswith(f"ok {folder / 'game.json'}:")
    assert err.splitlines() == [f"invaders: error: {folder / 'gone.json'}: no such file",
                                f"invaders: error: {folder / 'loop.json'}: cannot read: "
                                f"{os.strerror(errno.ELOOP)}"]
    assert _error_of(capsys, str(folder / "loop.json")) == (2, err.splitlines()[1] + "\n")


def test_missing_paths_empty_folders_truncated_and_invalid_files(replay_file, tmp_path,
                                                                 capsys):
    code, err = _error_of(capsys, str(tmp_path / "nothing.json"))
    assert code == 2 and "no such file or folder" in err
    empty = tmp_path / "empty"
    empty.mkdir()
    code, err = _error_of(capsys, str(empty))
    assert code == 2 and "no replay files" in err
    truncated = tmp_path / "truncated.json"
    truncated.write_text(replay_file.read_text()[:500])  # inside the header line
    code, err = _error_of(capsys, str(truncated))
    assert code == 2 and "invalid JSON" in err and str(truncated) in err
    blank = tmp_path / "blank.json"
    blank.write_text("")
    code, err = _error_of(capsys, str(blank))
    assert code == 2 and "empty" in err
    assert len(err.strip().splitlines()) == 1


def test_a_last_line_cut_short_is_ignored_and_the_rest_replays(replay_file, tmp_path):
    text = replay_file.read_text()
    cut = text.rfind("\n", 0, len(text) // 2) + 40  # 40 characters into some line
    path = tmp_path / "cut.json"
    path.write_text(text[:cut])
    replay = load(path)
    assert 0 < replay.ticks < load(replay_file).ticks
    assert run(replay)[0].mismatch is None


def test_a_checkpoint_that_lies_about_the_score_fails_the_check(replay_file, tmp_path, capsys):
    lines = _objects(replay_file)
    lines[-1]["checkpoint"]["score"] = 999999  # its hash and groups are still right
    path = _write(tmp_path / "lying.json", lines)
    assert main(["replay", str(path)]) == 1
    assert "score" in capsys.readouterr().out


JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats()  # NaN and Infinity too
    | st.sampled_from([10**19, -(10**40), 2**63]) | st.text(max_size=12),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner,
                                                                max_size=4),
    max_leaves=12)


@st.composite
def mutants(draw, objects: list) -> str:
    """A replay file with one structural change: a value anywhere replaced by any JSON
    value (NaN and Infinity among them), a key deleted or an unknown one added, a huge
    container put in, a lab switch at a speed the config may not take (its speeds pushed
    to their edge), a line dropped, doubled or swapped, blank lines put in, the whole
    written as a pretty-printed version-1 object, or the text cut or a byte changed."""
    lines = json.loads(json.dumps(objects))
    how = draw(st.sampled_from(["replace", "delete", "drop", "double", "swap", "cut", "byte",
                                "unknown", "huge", "lab", "blank", "pretty"]))
    index = draw(st.integers(0, len(lines) - 1))
    if how in ("unknown", "huge", "lab", "pretty"):
        return _grown(draw, lines, how, index)
    if how in ("replace", "delete"):
        parent, key = None, None
        node = lines[index]
        while isinstance(node, dict | list) and node and (parent is None or draw(
                st.booleans())):
            keys = list(node) if isinstance(node, dict) else list(range(len(node)))
            parent, key = node, draw(st.sampled_from(keys))
            node = parent[key]
        if parent is None:
            lines[index] = draw(JSON)
        elif how == "delete":
            del parent[key]
        else:
            parent[key] = draw(JSON)
    elif how == "drop":
        del lines[index]
    elif how == "double":
        lines.insert(index, lines[index])
    elif how == "swap":
        other = draw(st.integers(0, len(lines) - 1))
        lines[index], lines[other] = lines[other], lines[index]
    text = "".join(json.dumps(line) + "\n" for line in lines)
    if how == "blank":
        parts = text.split("\n")
        at = draw(st.integers(0, len(parts) - 1))
        text = "\n".join([*parts[:at], *[" " * draw(st.integers(0, 3))] * 2, *parts[at:]])
    if how == "cut":
        text = text[:draw(st.integers(0, len(text)))]
    elif how == "byte":
        at = draw(st.integers(0, len(text) - 1))
        text = text[:at] + chr(draw(st.integers(0, 127))) + text[at + 1:]
    return text


def _grown(draw, lines: list, how: str, index: int) -> str:
    """The mutations that add: an unknown key, a huge container, a lab switch at an edge
    speed, or the file as one pretty-printed version-1 object."""
    if how == "pretty":
        header = dict(lines[0], version=1, ticks=lines[-1]["checkpoint"]["tick"],
                      inputs=[run for line in lines[1:] for run in line["inputs"]],
                      checkpoints=[line["checkpoint"] for line in lines[1:]])
        return json.dumps(header, indent=draw(st.integers(0, 3))) + "\n"
    if how == "lab" and len(lines) > 2:
        at = draw(st.integers(1, 128))
        lines[0]["config"]["speeds"]["shot"] = draw(st.sampled_from([1, 32, 128 // at, 128]))
        tick = lines[index - 1]["checkpoint"]["tick"] if index > 1 else 0
        lines[max(index, 1)]["lab"] = [[tick, {"speed": at}]]
    elif how in ("unknown", "huge"):
        node = lines[index]
        while isinstance(node, dict) and draw(st.booleans()):
            inner = [v for v in node.values() if isinstance(v, dict)]
            if not inner:
                break
            node = draw(st.sampled_from(inner))
        if isinstance(node, dict):
            value = (draw(JSON) if how == "unknown" else
                     draw(st.sampled_from([[0] * 200_000, {str(i): 0 for i in range(50_000)},
                                           [{}] * 100_000, "x" * 1_000_000])))
            node[draw(st.text(min_size=1, max_size=8)) if how == "unknown"
                 else draw(st.sampled_from(list(node) or ["x"]))] = value
    return "".join(json.dumps(line) + "\n" for line in lines)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])  # count: the profile's
@given(data=st.data())
def test_any_structural_change_is_refused_in_one_line_or_replays_cleanly(replay_file,
                                                                         tmp_path, capsys,
                                                                         data):
    path = tmp_path / "mutant.json"
    path.write_text(data.draw(mutants(_objects(replay_file))))
    code = main(["replay", str(path)])
    out, err = capsys.readouterr()
    assert code in (0, 1, 2), (code, err)
    if code == 2:
        assert len(err.strip().splitlines()) == 1 and str(path) in err
    else:
        assert err == "" and out.count("\n") == 1


def test_a_recording_killed_mid_game_leaves_a_valid_replay_of_a_prefix(tmp_path):
    """A recording run kills itself (SIGKILL: no handler, no last save) on tick 8,000;
    what it saved on its way (every 3,600 ticks) is a valid replay of the first 7,200."""
    path = tmp_path / "killed.json"
    script = textwrap.dedent("""
        import os, signal, sys
        from invaders.app.cli import main
        from invaders.lab.autopilot import Autopilot

        plays = Autopilot.actions

        def actions(self, world):
            if world.tick == 8000:
                os.kill(os.getpid(), signal.SIGKILL)
            return plays(self, world)

        Autopilot.actions = actions
        sys.exit(main(["run", "--autopilot", "--ticks", "20000", "--record", sys.argv[1]]))
    """)
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy")
    done = subprocess.run([sys.executable, "-c", script, str(path)], env=env,
                          capture_output=True, timeout=300, check=False)
    assert done.returncode == -signal.SIGKILL
    replay = load(path)  # valid: saves only append whole lines, and a cut one is ignored
    assert replay.ticks == 7200
    result, _ = run(replay)
    assert result.mismatch is None


def test_a_file_from_before_the_saucer_fields_loads_with_the_values_once_hard_coded(tmp_path):
    data = _version_1(load(Path(__file__).resolve().parents[1] / "replays" /
                           "cannon-death.json"))
    for name in ("saucer_start_left", "saucer_start_right", "saucer_exit_left",
                 "saucer_exit_right", "cannon_centre", "bomb_drop_offset",
                 "shot_burst_offset", "bomb_burst_offset", "ground_burst_offset"):
        del data["config"]["geometry"][name]
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data))
    replay = load(path)
    assert replay.config == GameConfig()
    assert run(replay)[0].mismatch is None
    del data["config"]["geometry"]["saucer_top"]  # a field that was always there
    path.write_text(json.dumps(data))
    with pytest.raises(ReplayError, match="lacks field 'saucer_top'"):
        load(path)


@pytest.mark.parametrize("command", ["replay", "play"])
def test_a_lab_speed_the_config_cannot_take_is_refused_before_any_tick(replay_file, tmp_path,
                                                                       capsys, command):
    """A valid header speed times a lab switch's multiplier past the config's range: one
    line naming the file and the switch, exit 2, nothing run (it once ran, then exit 3)."""
    lines = Path(replay_file).read_text().splitlines()
    header = json.loads(lines[0])
    header["config"]["speeds"]["shot"] = 33
    second = json.loads(lines[2])
    first_tick = json.loads(lines[1])["checkpoint"]["tick"]
    second["lab"] = [[first_tick, {"speed": 4}]]
    path = tmp_path / "fast.json"
    path.write_text("\n".join([json.dumps(header), lines[1], json.dumps(second), *lines[3:]])
                    + "\n")
    args = ["replay", str(path)] if command == "replay" else ["play", "--replay", str(path)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(path) in err[0] and f"lab switch at tick {first_tick}" in err[0]
    assert "speeds.shot" in err[0]


def test_errors_name_the_line_as_the_file_counts_it_blank_lines_included(replay_file,
                                                                         tmp_path, capsys):
    lines = Path(replay_file).read_text().splitlines()
    broken = json.loads(lines[3])
    broken["checkpoint"]["tick"] += 1
    path = tmp_path / "gaps.json"
    path.write_text("\n".join([lines[0], "", lines[1], "   ", "", lines[2], json.dumps(broken),
                               *lines[4:]]) + "\n")
    assert main(["replay", str(path)]) == 2
    assert "line 7" in capsys.readouterr().err  # the fourth line of JSON, seventh of the file


def test_a_version_1_file_may_spread_its_one_object_over_lines(tmp_path):
    replay = record_headless(World(seed=2), Autopilot(2), 240)
    data = {"format": "invaders-replay", "version": 1, "program": "invaders test",
            "seed": replay.seed, "config": dataclasses.asdict(replay.config),
            "ticks": replay.ticks, "inputs": replay.inputs.lists(),
            "checkpoints": [dataclasses.asdict(c) for c in replay.checkpoints]}
    one_line, pretty = tmp_path / "one.json", tmp_path / "pretty.json"
    one_line.write_text(json.dumps(data) + "\n")
    pretty.write_text(json.dumps(data, indent=2) + "\n")
    assert load(pretty) == load(one_line)
    assert main(["replay", str(pretty)]) == 0
    pretty.write_text(json.dumps(data, indent=2)[:-40] + "\n")  # cut: still refused
    with pytest.raises(ReplayError, match="line 1: invalid JSON"):
        load(pretty)


@pytest.mark.parametrize("version", [1, 2])
def test_a_byte_order_mark_before_the_first_line_is_skipped_and_nowhere_else(
        replay_file, tmp_path, version):
    """As editors on Windows save text (JSON's standard lets a reader skip the mark): a
    version-2 file, or a version-1 object spread over lines, with the mark first reads as
    the file without it; the mark anywhere else is refused (naming its line in version 2;
    a version-1 object whose first line is no whole object is named by that line)."""
    plain = tmp_path / "plain.json"
    if version == 1:
        replay = record_headless(World(seed=2), Autopilot(2), 240)
        plain.write_text(json.dumps({
            "format": "invaders-replay", "version": 1, "program": "invaders test",
            "seed": replay.seed, "config": dataclasses.asdict(replay.config),
            "ticks": replay.ticks, "inputs": replay.inputs.lists(),
            "checkpoints": [dataclasses.asdict(c) for c in replay.checkpoints]}, indent=2))
    else:
        plain.write_text(Path(replay_file).read_text())
    marked, inside = tmp_path / "marked.json", tmp_path / "inside.json"
    lines = plain.read_text().splitlines(keepends=True)
    marked.write_text("\ufeff" + "".join(lines), encoding="utf-8")
    inside.write_text("".join([*lines[:2], "\ufeff", *lines[2:]]), encoding="utf-8")
    assert load(marked) == load(plain)
    with pytest.raises(ReplayError, match="line 3" if version == 2 else "line 1: invalid"):
        load(inside)


def test_update_goes_on_past_a_file_it_cannot_write_and_sums_up(tmp_path, monkeypatch, capsys):
    """A full disk on the first file: the second is still updated, the summary printed,
    exit 2 (it stopped at the first, the second never updated, no summary)."""
    import errno

    from invaders.app import replay_check

    source = Path(__file__).resolve().parents[1] / "replays" / "saucer-300.json"
    files = []
    for name in ("a.json", "b.json"):
        lines = source.read_text().splitlines()
        last = json.loads(lines[-1])
        last["checkpoint"]["score"] += 10  # a checkpoint that --update rewrites
        (tmp_path / name).write_text("\n".join([*lines[:-1], json.dumps(last)]) + "\n")
        files.append(tmp_path / name)
    real = replay_check.save_replay

    def full_disk_for_a(path, replay):
        if Path(path).name == "a.json":
            raise OSError(errno.ENOSPC, "No space left on device")
        real(path, replay)

    monkeypatch.setattr(replay_check, "save_replay", full_disk_for_a)
    assert main(["replay", "--update", *map(str, files)]) == 2
    printed = capsys.readouterr()
    assert "no space left on the device" in printed.err and "a.json" in printed.err
    assert "1 of 2 replay files changed" in printed.out
    assert main(["replay", str(files[1])]) == 0


@pytest.mark.parametrize("edit, quoted", [
    (lambda h: h.update(format="x" * 10_000), "... (10,002 characters)"),
    (lambda h: h.update(version=list(range(2_000))), "version a list of 2,000 items"),
    (lambda h: h["config"].update({"k" * 5000: 1}), "... (5,002 characters)"),
])
def test_errors_quote_a_short_prefix_of_what_the_file_holds(replay_file, tmp_path, capsys,
                                                            edit, quoted):
    lines = Path(replay_file).read_text().splitlines()
    header = json.loads(lines[0])
    edit(header)
    path = tmp_path / "long.json"
    path.write_text("\n".join([json.dumps(header), *lines[1:]]) + "\n")
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err
    assert quoted in err and len(err) < 300


def test_a_replays_deep_copy_is_equal_and_changes_apart():
    """A replay's deep copy (the environment makes one with every `clone_state` of a
    recorded episode; Checkpoints copies its columns itself) equals the replay, in its
    file's lines too, and neither its inputs (a new run, or its last run made longer) nor
    its checkpoints changed afterwards reach the replay, nor the replay's reach it."""
    world = World(seed=3)
    replay = record_headless(world, Autopilot(3), 300)
    lines, runs = list(replay.lines()), list(replay.inputs)
    ticks, count = replay.ticks, len(replay.checkpoints)
    copied = copy.deepcopy(replay)
    assert copied == replay and list(copied.lines()) == lines
    assert copied.config is replay.config  # (a config is whole numbers: itself)
    last_bits = runs[-1][0]
    copied.append(last_bits)  # the last run made longer
    copied.append(last_bits ^ 1)  # a new run
    copied.checkpoints.append(Checkpoint.of(world))
    assert list(replay.lines()) == lines and list(replay.inputs) == runs
    assert (replay.ticks, len(replay.checkpoints)) == (ticks, count)
    replay.append(last_bits)
    fresh = Checkpoint.of(World(seed=8))
    replay.checkpoints.append(fresh)
    assert (copied.ticks, len(copied.checkpoints)) == (ticks + 2, count + 1)
    assert copied.checkpoints[-1] == Checkpoint.of(world) != fresh == replay.checkpoints[-1]


def _recorded(inputs: list[int], then: list[int], switch_at: int) -> tuple[list[str], str]:
    """A world recorded through `inputs`, then `then`, a lab switch at `switch_at`: the
    replay's lines and the lines a file would have been given."""
    world = World(seed=6)
    recorder = ReplayRecorder(world, lines=True)
    for tick, bits in enumerate([*inputs, *then]):
        if tick == switch_at:
            recorder.switch({"speed": tick})
        world.step(bits)
        recorder.tick(bits)
    return list(recorder.finished().lines()), "".join(recorder.unsaved or [])


def test_a_recordings_deep_copy_records_its_worlds_copy_apart_from_it():
    """Copied with its world (as a state of the environment is), a recording records the
    world's copy: each goes on with inputs of its own, a lab switch each, and ends with
    the lines it would have had alone, its replay's and its unsaved ones. Fails with any
    of its lists shared (the replay, the runs or switches since a checkpoint, the lines)."""
    first = [tick // 7 % 3 for tick in range(130)]  # (a run open at the copy: tick 130)
    ours, theirs = [1] * 50 + [2] * 20, [2] * 30 + [0] * 40
    world = World(seed=6)
    recorder = ReplayRecorder(world, lines=True)
    for bits in first:
        world.step(bits)
        recorder.tick(bits)
    world_copy, copied = copy.deepcopy((world, recorder))
    assert copied.world is world_copy and copied.replay == recorder.replay
    for w, r, inputs, switch_at in ((world, recorder, ours, 140),
                                    (world_copy, copied, theirs, 150)):
        for tick, bits in enumerate(inputs, start=len(first)):
            if tick == switch_at:
                r.switch({"speed": tick})
            w.step(bits)
            r.tick(bits)
    assert (list(recorder.finished().lines()), "".join(recorder.unsaved or [])) == _recorded(
        first, ours, 140)
    assert (list(copied.finished().lines()), "".join(copied.unsaved or [])) == _recorded(
        first, theirs, 150)
