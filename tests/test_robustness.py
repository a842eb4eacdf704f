"""Bad input never crashes and nothing recorded is lost: every output path checked in one
place, every write failure one line, special files refused, an internal error one line
(exit 3), signals stop recordings on a whole tick, and memory stays flat however long a run.
"""

from __future__ import annotations

import errno
import io
import os
import random
import signal
import statistics
import subprocess
import sys
import textwrap
import time
from collections import Counter
from pathlib import Path

import pytest

from invaders.app import cli
from invaders.app.cli import main
from invaders.app.report import CounterTable
from invaders.atomic import append_whole, write_atomic
from invaders.engine.stats import STAT_FIELDS, CollisionStats
from invaders.game.replay import load, run
from tests.helpers import FullStream

ROOT = Path(__file__).resolve().parents[1]
INVADERS = str(Path(sys.executable).with_name("invaders"))
ENV = dict(os.environ, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy")


def _one_line_error(capsys, args: list[str]) -> str:
    assert main(args) == 2
    out, err = capsys.readouterr()
    assert len(err.strip().splitlines()) == 1 and err.startswith("invaders: error: ")
    assert "saved" not in out
    return err


@pytest.mark.parametrize("target, words", [
    ("", "argument --record: an empty name"),
    ("missing/game.json", "no such folder"),
    ("/dev/null", "not a regular file"),
    ("x" * 300 + ".json", "longer than 241 bytes"),
    ("x" * 240 + ".json", "longer than 241 bytes"),  # fits, but its temporary name does not
    ("game.txt", "must end in .json"),
])
def test_a_recording_that_cannot_be_written_is_refused_before_the_run(capsys, tmp_path,
                                                                     monkeypatch, target,
                                                                     words):
    monkeypatch.chdir(tmp_path)
    err = _one_line_error(capsys, ["run", "--ticks", "5", "--record", target])
    assert words in err


def test_nothing_ever_replaces_a_link_or_a_folder(capsys, tmp_path):
    real = tmp_path / "real.json"
    real.write_text("precious")
    link = tmp_path / "link.json"
    link.symlink_to(real)
    assert "not a regular file" in _one_line_error(
        capsys, ["run", "--ticks", "5", "--record", str(link)])
    folder = tmp_path / "folder.json"
    folder.mkdir()
    assert "it is a folder" in _one_line_error(
        capsys, ["run", "--ticks", "5", "--record", str(folder)])
    assert real.read_text() == "precious" and link.is_symlink()


def test_a_file_read_only_to_the_user_is_not_replaced(capsys, tmp_path, monkeypatch):
    """A replay its owner made read-only (as another user's): refused in one line, as a
    plain write to it would be, and kept (the rename over it, which the folder allows,
    replaced it, and the recorded game was lost). Root may write any file, as a plain
    write may: os.access answers for the user running it, here made to say no."""
    replay, picture = tmp_path / "precious.json", tmp_path / "precious.png"
    replay.write_text("a recorded game")
    picture.write_text("a picture")
    asked = os.access

    def read_only(path, mode, **kwargs):
        if Path(path) in (replay, picture) and mode & os.W_OK:
            return False
        return asked(path, mode, **kwargs)

    monkeypatch.setattr(os, "access", read_only)
    for what, path, words in (("replay", replay, ["run", "--ticks", "5", "--record"]),
                              ("screenshot", picture, ["play", "--ticks", "2", "--screenshot"])):
        assert _one_line_error(capsys, [*words, str(path)]) == (
            f"invaders: error: cannot write {what} {str(path)!r}: permission denied (the "
            "file is read-only to you, and will not be replaced)\n")
    assert (replay.read_text(), picture.read_text()) == ("a recorded game", "a picture")


@pytest.mark.skipif(not hasattr(os, "fchmod"), reason="files have no such modes here")
def test_a_replaced_file_keeps_its_permissions_and_a_new_one_gets_the_usual(capsys, tmp_path):
    """As a plain write would: a private replay recorded over stays private (it became
    0644, readable by all), and a new file gets 0666 less the umask."""
    private, new = tmp_path / "private.json", tmp_path / "new.json"
    private.write_text("{}")
    private.chmod(0o600)
    umask = os.umask(0o027)
    try:
        for path in (private, new):
            assert main(["run", "--ticks", "5", "--record", str(path)]) == 0
    finally:
        os.umask(umask)
    capsys.readouterr()
    assert (private.stat().st_mode & 0o777, new.stat().st_mode & 0o777) == (0o600, 0o640)
    assert load(private).ticks == 5


@pytest.mark.skipif(not hasattr(os, "fchmod") or not os.path.exists("/proc/self/status"),
                    reason="the system does not say the umask")
def test_a_new_files_permissions_read_the_umask_without_setting_it(tmp_path, monkeypatch):
    """The umask was read by setting it to 0 and back, and a file another thread made in
    that instant got every permission; where the system says it (Linux), it is read, and
    a new file still gets 0666 less it, under either umask."""
    modes = []
    for umask in (0o077, 0o002):
        old = os.umask(umask)
        try:
            with monkeypatch.context() as patch:
                patch.setattr(os, "umask", lambda mask: pytest.fail("the umask was set"))
                write_atomic(tmp_path / f"new-{umask:o}.json", "{}")
        finally:
            os.umask(old)
        modes.append((tmp_path / f"new-{umask:o}.json").stat().st_mode & 0o777)
    assert modes == [0o600, 0o664]


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                    reason="only root may give a file to another user")
def test_a_file_replaced_by_root_stays_its_owners(capsys, tmp_path):
    """`sudo invaders run --record` over a user's replay: the new file is still the user's,
    as a plain write would leave it (it became root's, and the user could record over it
    no more)."""
    theirs = tmp_path / "theirs.json"
    theirs.write_text("{}")
    os.chown(theirs, 65534, 65534)
    assert main(["run", "--ticks", "5", "--record", str(theirs)]) == 0
    capsys.readouterr()
    assert (theirs.stat().st_uid, theirs.stat().st_gid) == (65534, 65534)
    assert load(theirs).ticks == 5


def _disk_full(monkeypatch) -> None:
    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", full)


def test_a_full_disk_is_one_line_and_the_old_file_survives(capsys, tmp_path, monkeypatch):
    screenshot = tmp_path / "shot.png"
    screenshot.write_bytes(b"old picture")
    _disk_full(monkeypatch)
    err = _one_line_error(capsys, ["play", "--screenshot", str(screenshot), "--ticks", "2"])
    assert "no space left" in err
    assert screenshot.read_bytes() == b"old picture"
    assert [p.name for p in tmp_path.iterdir()] == ["shot.png"]  # no temporary file left
    report = tmp_path / "r.csv"
    assert "no space left" in _one_line_error(
        capsys, ["run", "--ticks", "3", "--report", str(report)])
    assert not report.exists()


@pytest.mark.parametrize("buffered", [True, False])
def test_a_reader_gone_ends_the_output_quietly(buffered):
    """`invaders run | head -1`, head gone before the summary is written (a pipe whose
    reading end is closed), Python's output buffered or not: exit 0, and not a word."""
    env = {key: value for key, value in ENV.items() if key != "PYTHONUNBUFFERED"}
    reading, writing = os.pipe()
    os.close(reading)
    try:
        done = subprocess.run([INVADERS, "run", "--ticks", "10"], stdout=writing,
                              env=env if buffered else {**env, "PYTHONUNBUFFERED": "1"},
                              stderr=subprocess.PIPE, timeout=60)
    finally:
        os.close(writing)
    assert (done.returncode, done.stderr) == (0, b"")


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="a device that is always full")
@pytest.mark.parametrize("buffered", [True, False])
@pytest.mark.parametrize("words", [["run", "--ticks", "10"], ["--help"], ["run", "--help"],
                                   ["--version"]])
def test_output_to_a_full_disk_is_one_line_not_an_internal_error(buffered, words):
    """`invaders run > file` on a full disk (/dev/full: every write fails so), whether
    Python buffers its output (the failure then comes at the flush) or not: one line,
    exit 2 (an internal error, exit 3, or Python's own lines and 120 at the exit). Help
    and the version too (argparse dropped the error: exit 0 unbuffered, 120 buffered)."""
    env = {key: value for key, value in ENV.items() if key != "PYTHONUNBUFFERED"}
    with open("/dev/full", "w") as full:
        done = subprocess.run([INVADERS, *words], stdout=full,
                              env=env if buffered else {**env, "PYTHONUNBUFFERED": "1"},
                              stderr=subprocess.PIPE, text=True, timeout=60)
    assert (done.returncode, done.stderr) == (
        2, "invaders: error: cannot write the output: no space left on the device\n")


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="a device that is always full")
@pytest.mark.parametrize("buffered", [True, False])
@pytest.mark.parametrize("words, code", [(["run", "--ticks", "x"], 2),
                                         (["replay", "missing.json"], 2),
                                         (["run", "--ticks", "5"], 0)])
def test_errors_to_a_full_disk_keep_the_exit_code(buffered, words, code, tmp_path):
    """`invaders ... 2> log` with the log's disk full: the error line cannot be written,
    and the exit code still says what happened (it was 1, as if a check had failed, with
    Python's error output unbuffered, and 120 with it buffered)."""
    env = {key: value for key, value in ENV.items() if key != "PYTHONUNBUFFERED"}
    with open("/dev/full", "w") as full:
        done = subprocess.run([INVADERS, *words], stderr=full, stdout=subprocess.DEVNULL,
                              env=env if buffered else {**env, "PYTHONUNBUFFERED": "1"},
                              cwd=tmp_path, timeout=60)
    assert done.returncode == code


def test_a_file_name_the_outputs_encoding_lacks_is_escaped_not_an_internal_error(tmp_path):
    """A replay named in Japanese, checked with the output in an encoding without those
    letters (ASCII here; a Windows code page, where the output goes to a file): the name
    is printed escaped, as Python's own stderr escapes it (it was an internal error,
    exit 3, after the check had passed)."""
    path = tmp_path / "g\u00e4me-\u65e5\u672c.json"
    path.write_text((ROOT / "replays" / "cannon-death.json").read_text())
    done = subprocess.run([INVADERS, "replay", str(path)], capture_output=True, timeout=120,
                          env={**ENV, "PYTHONIOENCODING": "ascii"})
    assert done.returncode == 0, done.stderr
    escaped = str(tmp_path).encode() + rb"/g\xe4me-\u65e5\u672c.json"
    assert done.stdout.startswith(b"ok " + escaped + b": 3600 ticks")


def test_a_report_that_cannot_be_written_is_named_alone_and_the_recording_kept(
        capsys, tmp_path, monkeypatch):
    """The report's writes fail (its disk full), the recording's do not: the one line
    names the report (it said "report or replay"), and the replay is written whole."""
    from invaders.app.report import ReportWriter

    def full(*_):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(ReportWriter, "row", full)
    report, recording = tmp_path / "r.csv", tmp_path / "run.json"
    err = _one_line_error(capsys, ["run", "--ticks", "90", "--report", str(report),
                                   "--record", str(recording)])
    assert err == (f"invaders: error: cannot write report {str(report)!r}: no space left on "
                   "the device\n")
    replay = load(recording)  # (the tick played before the report failed)
    assert not report.exists() and replay.ticks == 1 and run(replay)[0].mismatch is None


def test_an_update_that_cannot_be_written_leaves_the_replay_as_it_was(capsys, tmp_path,
                                                                      monkeypatch):
    path = tmp_path / "game.json"
    text = (ROOT / "replays" / "cannon-death.json").read_text()
    lines = text.splitlines(keepends=True)
    path.write_text(lines[0] + lines[1] + lines[2].replace('"score":0', '"score":1'))
    _disk_full(monkeypatch)
    assert main(["replay", "--update", str(path)]) == 2
    assert "no space left" in capsys.readouterr().err
    assert path.read_text().count("\n") == 3 and '"score":1' in path.read_text()


def test_a_picture_must_be_a_png(capsys, tmp_path):
    assert "must end in .png" in _one_line_error(
        capsys, ["play", "--screenshot", str(tmp_path / "x.txt"), "--ticks", "1"])


@pytest.mark.parametrize("kind", ["pipe", "device-link"])
def test_a_pipe_or_a_device_is_refused_at_once_not_read(capsys, tmp_path, monkeypatch, kind):
    """Refused before it is opened: opening the pipe for reading would block forever, and
    reading the device would never end."""
    import builtins

    path = tmp_path / "game.json"
    if kind == "pipe":
        os.mkfifo(path)
    else:
        path.symlink_to("/dev/zero")
    opened = []
    for module, name in ((builtins, "open"), (io, "open"), (os, "open")):
        real = getattr(module, name)
        monkeypatch.setattr(module, name, lambda file, *a, real=real, **k:
                            opened.append(str(file)) or real(file, *a, **k))
    assert main(["replay", str(path)]) == 2
    assert "not a regular file" in capsys.readouterr().err
    assert str(path) not in opened
    regular = ROOT / "replays" / "saucer-300.json"
    assert main(["replay", str(regular)]) == 0 and str(regular) in opened  # (the spy sees)


def test_a_file_name_too_long_is_one_line(capsys):
    assert main(["replay", "y" * 300 + ".json"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "too long" in err


def test_an_internal_error_is_one_line_and_exit_3_and_debug_shows_it(capsys, monkeypatch):
    def broken(args) -> int:
        raise RuntimeError("a\nbug")

    monkeypatch.setitem(cli.COMMANDS, "run", cli.COMMANDS["run"]._replace(run=broken))
    assert main(["run"]) == 3
    err = capsys.readouterr().err
    assert err.startswith("invaders: internal error: RuntimeError: a bug")
    assert "--debug" in err and len(err.strip().splitlines()) == 1
    assert main(["run", "--debug"]) == 3
    assert "Traceback" in capsys.readouterr().err


def test_an_internal_error_names_the_replay_being_checked(capsys, monkeypatch):
    import invaders.app.replay_check as replay_check

    def broken(*args, **kwargs):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr(replay_check, "run", broken)
    path = ROOT / "replays" / "invasion.json"
    assert main(["replay", str(path)]) == 3
    assert f"while processing {path}: ZeroDivisionError: boom" in capsys.readouterr().err


SIGNALS = [(signal.SIGINT, 130, 1234), (signal.SIGTERM, 143, 2345), (signal.SIGHUP, 129, 777)]


@pytest.fixture(autouse=True)
def signals_not_ignored():
    """Each test starts with the signals at Python's defaults, whoever started the suite (a
    job in the background starts with SIGINT ignored, one under nohup with SIGHUP): the
    program keeps an ignored signal ignored, so a test sending one would wait for nothing."""
    defaults = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL,
                signal.SIGHUP: signal.SIG_DFL}
    previous = {signum: signal.signal(signum, handler) for signum, handler in defaults.items()}
    yield
    for signum, handler in previous.items():
        signal.signal(signum, handler)


def _autopilot_sends(monkeypatch, at: int, *signums: int) -> None:
    """The autopilot sends these signals to this process while tick `at` is played."""
    from invaders.lab.autopilot import Autopilot

    plays = Autopilot.actions

    def actions(self, world):
        if world.tick == at:
            for signum in signums:
                os.kill(os.getpid(), signum)
        return plays(self, world)

    monkeypatch.setattr(Autopilot, "actions", actions)


@pytest.mark.parametrize("signum, code, at", SIGNALS, ids=lambda v: str(v))
def test_a_signal_stops_a_recording_run_on_a_whole_tick_and_saves_it(
        tmp_path, capsys, monkeypatch, signum, code, at):
    """The signal arrives while tick `at` is being played (the autopilot sends it, well into
    the game and between two saves): that tick is finished, the run stops before the next,
    and the recording holds exactly the ticks played, as a replay that checks."""
    _autopilot_sends(monkeypatch, at, signum)
    path = tmp_path / "run.json"
    assert main(["run", "--autopilot", "--ticks", "100000000", "--record", str(path)]) == code
    name = signal.Signals(signum).name
    assert capsys.readouterr().err.splitlines() == [
        f"invaders: stopped by {name} at tick {at + 1}; saved {path} ({at + 1} ticks)"]
    replay = load(path)
    assert replay.ticks == at + 1
    assert run(replay)[0].mismatch is None
    assert [p.name for p in tmp_path.iterdir()] == ["run.json"]


def test_a_stale_temporary_file_is_cleaned_at_the_next_save(tmp_path):
    """One left two minutes ago by a kill goes; one written a moment ago, as another
    recording of the same name writes its file, stays (removing it failed that save)."""
    stale, busy = tmp_path / ".game.json.abc123.tmp", tmp_path / ".game.json.def456.tmp"
    stale.write_text("left by a kill")
    busy.write_text("being written")
    two_minutes_ago = time.time() - 120
    os.utime(stale, (two_minutes_ago, two_minutes_ago))
    assert main(["run", "--ticks", "70", "--record", str(tmp_path / "game.json")]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [".game.json.def456.tmp",
                                                          "game.json"]


def test_the_summary_medians_and_totals_are_exact_from_value_counts():
    rng = random.Random(3)
    table = CounterTable()
    rows = [CollisionStats(*(rng.randrange(6) for _ in STAT_FIELDS)) for _ in range(501)]
    for row in rows:
        table.add(row)
    for i, name in enumerate(STAT_FIELDS):
        column = [row[i] for row in rows]
        assert table.medians()[name] == statistics.median(column)
        assert table.totals()[name] == sum(column)
    table.add(CollisionStats())  # an even count: the mean of the middle two
    assert table.medians()["objects"] == statistics.median([r[0] for r in rows] + [0])


def test_memory_stays_flat_over_a_long_headless_run():
    script = textwrap.dedent("""
        import os
        os.environ["SDL_VIDEODRIVER"] = "dummy"
        from invaders.app.headless import Idle, run
        from invaders.game.world import World

        def rss():
            with open("/proc/self/statm") as f:
                return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

        TICKS = 150_000
        seen = {}

        class Watch(Idle):
            def actions(self, world):
                if world.tick in (TICKS // 10, TICKS - 1):
                    seen[world.tick] = rss()
                return 8 if world.tick % 50 == 0 else 0  # keeps starting new games

        run(World(seed=1), Watch(), TICKS)
        print(seen[TICKS // 10], seen[TICKS - 1])
    """)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=300, env=ENV, check=True)
    early, late = map(int, result.stdout.split())
    assert late - early < 3 * 2**20, (early, late)  # a per-tick list would add ~10 MB


def test_hostile_files_are_refused_in_bounded_time_and_memory(tmp_path):
    """Each in a process of its own with 1 GiB of address space at most: 64 MB of empty
    objects, of fractions or of fields (in the header, in a checkpoint's line, as a
    version-1 object) once took 1.2 to 1.9 GB to parse."""
    header = (ROOT / "replays" / "cannon-death.json").read_text().splitlines()[0]
    size = 64 * 2**20 - 4096  # each up to the size limit
    objects = header[:-1] + ',"x":[' + "{}," * (size // 3) + "{}]}\n"
    floats = header[:-1] + ',"x":[' + "0.5," * (size // 4) + "0.5]}\n"
    keys = header[:-1] + ',"x":{' + ",".join(map('"{}":0'.format, range(size // 12))) + "}}\n"
    segment = (ROOT / "replays" / "cannon-death.json").read_text().splitlines()[1]
    files = {
        "objects.json": objects, "floats.json": floats, "keys.json": keys,
        "objects-line.json": header + "\n" + segment[:-1] + objects[len(header) - 1:][:2**21]
                             + "{}]}\n",
        "keys-v1.json": keys[:2**21].replace('"version":2', '"version":1') + '0":0}}\n',
        "digits.json": header.replace('"seed":1', '"seed":' + "9" * 1_000_000) + "\n",
        "runs.json": header + "\n" + '{"inputs":[' + ",".join(["[0,1]"] * 3_000_000)
                     + '],"checkpoint":{}}\n',
        "nested.json": "[" * 200_000 + "]" * 200_000 + "\n",
        "big.json": " " * (64 * 2**20 + 1),
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    limit = textwrap.dedent(f"""
        import resource, sys
        resource.setrlimit(resource.RLIMIT_AS, ({2**30}, {2**30}))
        from invaders.app.cli import main
        sys.exit(main(["replay", *sys.argv[1:]]))
    """)
    # One process for all: each file is read, refused and let go before the next (the
    # timeout only stops a hang; it measures nothing).
    result = subprocess.run([sys.executable, "-c", limit, *(str(tmp_path / n) for n in files)],
                            capture_output=True, text=True, timeout=300, env=ENV, check=False)
    assert result.returncode == 2, result.stderr[-300:]
    refused = result.stderr.strip().splitlines()
    assert [line.split(": ")[2] for line in refused] == [str(tmp_path / n) for n in files]
    assert Counter(p.suffix for p in tmp_path.iterdir()) == {".json": 9}


def test_saving_a_recording_costs_the_same_late_in_a_game_as_early(tmp_path):
    from invaders.app.recording import Recorder
    from invaders.game.world import World
    from invaders.lab.autopilot import Autopilot

    path = tmp_path / "long.json"
    world = World(seed=2)
    pilot = Autopilot(2)
    recorder = Recorder(world, path, save_every=10**9)  # saved only when asked
    grown = []
    for until in (1_200, 1_380, 30_000, 30_180):
        while world.tick < until:
            bits = pilot.actions(world)
            world.step(bits)
            recorder.tick(bits)
        before = path.stat().st_size if path.exists() else 0
        recorder.save()
        grown.append(path.stat().st_size - before)
    # 180 ticks (three checkpoints' lines) appended early and late: about the same bytes,
    # and far fewer than the whole file, which is not rewritten.
    assert 0.5 < grown[3] / grown[1] < 2
    assert grown[3] < path.stat().st_size / 50
    assert run(load(path))[0].mismatch is None


def on_the_tests_clock(monkeypatch, now: list[float]) -> None:
    """The window's game on a clock the test moves (`now[0]`, in seconds), pygame's frame
    pacing without waiting."""
    import types

    import pygame

    import invaders.app.play as play_module

    class Paced:
        def tick(self, fps: int = 0) -> int:
            return 0

    monkeypatch.setattr(play_module, "time", types.SimpleNamespace(perf_counter=lambda: now[0]))
    monkeypatch.setattr(pygame.time, "Clock", Paced)


def test_a_signal_ends_a_recorded_window_game_with_its_code_and_a_valid_file(
        tmp_path, capsys, monkeypatch):
    """A window game on a clock the test moves (a 60th of a second a frame) and a player
    who fires, with SIGTERM arriving at frame 400: the game ends with 143, saved on a whole
    tick (past two autosaves), and the file replays."""
    import pygame

    now = [0.0]
    frames = [0]

    def events():
        frames[0] += 1
        now[0] += 1 / 60
        if frames[0] == 400:
            os.kill(os.getpid(), signal.SIGTERM)
        key = pygame.KEYDOWN if frames[0] % 20 == 0 else pygame.KEYUP
        return [pygame.event.Event(key, key=pygame.K_SPACE, mod=0, unicode=" ", scancode=0)]

    on_the_tests_clock(monkeypatch, now)
    monkeypatch.setattr(pygame.event, "get", events)
    path = tmp_path / "played.json"
    assert main(["play", "--record", str(path), "--seed", "3"]) == 143
    out, err = capsys.readouterr()
    (line,) = err.splitlines()  # one line for the stop and the file (it was two)
    assert line.startswith(f"invaders: stopped by SIGTERM; saved {path}: ") and out == ""
    replay = load(path)
    assert 360 < replay.ticks <= 400 and run(replay)[0].mismatch is None
    assert sum(1 for bits, n in replay.inputs if bits & 4 for _ in range(n)) > 0  # it fired


@pytest.mark.parametrize("errors_full", [False, True])
def test_a_window_game_plays_on_through_a_full_disk_and_saves_it_all_after(
        tmp_path, capsys, monkeypatch, errors_full):
    """The disk full from the second autosave to the fifth (every append failing), in a
    window game on the test's clock, closed at frame 1,000: one line says so the first
    time and the game plays on (it ended with the error, the player thrown out); the
    saves after it write what was kept, and the file replays all 1,000 ticks. With
    standard error on the full disk too, the line goes nowhere and the game plays on (its
    failure ended the game, exit 2)."""
    import pygame

    from invaders import atomic

    now, frames, appends = [0.0], [0], []

    def events():
        frames[0] += 1
        now[0] += 1 / 60
        return [pygame.event.Event(pygame.QUIT)] if frames[0] == 1000 else []

    def full_for_a_while(fd, text):
        appends.append(frames[0])
        if len(appends) <= 3:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        append_whole(fd, text)

    on_the_tests_clock(monkeypatch, now)
    monkeypatch.setattr(pygame.event, "get", events)
    monkeypatch.setattr(atomic, "append_whole", full_for_a_while)
    if errors_full:
        monkeypatch.setattr(sys, "stderr", FullStream())
    path = tmp_path / "played.json"
    assert main(["play", "--record", str(path), "--seed", "3"]) == 0
    out, err = capsys.readouterr()
    assert err == "" if errors_full else err == (
        f"invaders: cannot write replay {str(path)!r}: no space left on the device; the file "
        "keeps its first 180 ticks, a valid replay; play goes on, and what is not written is "
        "kept for the next autosave (and the last, at the end)\n")
    replay = load(path)
    assert out == f"saved {path}: {replay.ticks} ticks\n" and len(appends) == 5
    assert replay.ticks == 999 and run(replay)[0].mismatch is None


def test_the_temporary_name_is_as_much_longer_as_the_check_allows_for(tmp_path):
    from invaders.atomic import TEMPORARY_EXTRA, atomic_writer

    target = tmp_path / ("y" * 200 + ".json")
    with atomic_writer(target) as handle:
        handle.write("{}")
        (temporary,) = [p for p in tmp_path.iterdir() if p != target]
    assert len(temporary.name) == len(target.name) + TEMPORARY_EXTRA
    longest = tmp_path / ("z" * (255 - TEMPORARY_EXTRA - 5) + ".json")
    with atomic_writer(longest) as handle:  # the longest name the check lets through
        handle.write("{}")
    assert longest.read_text() == "{}"


def test_another_users_file_in_a_sticky_folder_is_refused_before_the_run(tmp_path, capsys,
                                                                        monkeypatch):
    folder = tmp_path / "shared"
    folder.mkdir()
    folder.chmod(0o1777)  # as /tmp: only a file's owner may replace it
    (folder / "game.json").write_text("{}")  # (ours, as root; the check is told otherwise)
    monkeypatch.setattr(os, "geteuid", lambda: 12345)
    err = _one_line_error(capsys, ["run", "--ticks", "5", "--record",
                                   str(folder / "game.json")])
    assert "another user's file" in err and (folder / "game.json").read_text() == "{}"


def test_a_recording_stops_at_the_readers_limit_and_the_file_replays(tmp_path, capsys):
    """The limit lowered to 3,000 bytes: the recording stops at the last checkpoint that
    fits, says so in one line, and its reader takes the whole file (it once wrote files of
    67,522,325 bytes that its reader refused)."""
    from invaders.app.recording import Recorder
    from invaders.game.replay import load, run
    from invaders.game.world import World
    from invaders.lab.autopilot import Autopilot

    world, pilot, path = World(seed=3), Autopilot(3), tmp_path / "long.json"
    recorder = Recorder(world, path, save_every=60, limit=3000)
    for _ in range(2000):
        bits = pilot.actions(world)
        world.step(bits)
        recorder.tick(bits)
    recorder.save()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"recording stopped at tick {recorder.ticks}" in err[0]
    assert 2000 > recorder.ticks > 0 and recorder.ticks % 60 == 0
    assert path.stat().st_size <= 3000
    replay = load(path)
    assert replay.ticks == recorder.ticks
    assert run(replay)[0].mismatch is None


def test_recording_to_a_file_keeps_no_more_memory_late_than_early(tmp_path, monkeypatch):
    """Python keeps freed tuples for reuse and imports a module or two at the first contact,
    so a flat recording still shows some growth; keeping every input run and checkpoint,
    as the recorder did, added about 500 KB over these 12,000 ticks. The solid masks kept
    start empty: the thousands earlier tests leave there are a dict whose table, rebuilt
    here, counts as 288 KB more (the old one was made before the tracing, so its freeing
    is not counted), whatever the recording keeps."""
    import tracemalloc

    from invaders.app.recording import Recorder
    from invaders.engine import predicates
    from invaders.game.world import World
    from invaders.lab.autopilot import Autopilot

    monkeypatch.setattr(predicates, "_solids", predicates.KeptSolids())

    world, pilot = World(seed=5), Autopilot(5)
    recorder = Recorder(world, tmp_path / "game.json", save_every=600)
    tracemalloc.start()
    sizes = {}
    for tick in range(1, 16_001):
        bits = pilot.actions(world) | (8 if tick % 3000 == 0 else 0)  # games end and start
        world.step(bits)
        recorder.tick(bits)
        if tick in (4_000, 16_000):
            sizes[tick] = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    assert sizes[16_000] - sizes[4_000] < 200 * 1024, sizes


def test_two_signals_a_moment_apart_still_end_on_a_whole_tick_with_the_first_ones_code(
        tmp_path, capsys, monkeypatch):
    # (it once exited 130, "interrupted")
    _autopilot_sends(monkeypatch, 500, signal.SIGTERM, signal.SIGINT)
    path = tmp_path / "run.json"
    assert main(["run", "--autopilot", "--ticks", "100000", "--record", str(path)]) == 143
    assert capsys.readouterr().err.splitlines() == [
        f"invaders: stopped by SIGTERM at tick 501; saved {path} (501 ticks)"]
    assert run(load(path))[0].mismatch is None


def test_a_signal_ignored_when_the_program_started_stays_ignored(capsys, monkeypatch):
    """As under nohup: SIGHUP ignored by whoever started us does not stop the run."""
    _autopilot_sends(monkeypatch, 100, signal.SIGHUP)
    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        assert main(["run", "--autopilot", "--ticks", "300"]) == 0
    finally:
        signal.signal(signal.SIGHUP, previous)
    assert "ran 300 ticks" in capsys.readouterr().out


def test_ctrl_c_while_the_program_is_still_loading_is_one_line(capsys, monkeypatch):
    import builtins

    from invaders.__main__ import run as command

    real = builtins.__import__

    def interrupted(name, *args, **kwargs):
        if name == "invaders.app.cli":
            raise KeyboardInterrupt
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", interrupted)
    assert command(["run", "--ticks", "1"]) == 130
    assert capsys.readouterr().err == "invaders: interrupted\n"


def test_an_append_that_fails_says_how_many_ticks_the_file_keeps(tmp_path, capsys,
                                                                 monkeypatch):
    """The disk fills at the second save (tick 7,200): one line, exit 2, and the number of
    ticks the file still holds, which replay."""
    import errno

    from invaders import atomic

    def no_space(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(atomic, "append_whole", no_space)
    path = tmp_path / "run.json"
    assert main(["run", "--autopilot", "--ticks", "8000", "--record", str(path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "no space left on the device" in err[0]
    assert "the file keeps its first 3600 ticks" in err[0]
    replay = load(path)
    assert replay.ticks == 3600 and run(replay)[0].mismatch is None


CUT_SHORT = """
import os, resource, signal, sys
from invaders.app.outputs import OutputError
from invaders.app.recording import Recorder
from invaders.game.world import World

signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # (a write past the limit fails, as on a full disk)
soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
world = World(seed=3)
recorder = Recorder(world, sys.argv[1], save_every=600)
for tick in range(1, 3001):
    if tick == 1000:  # room for 100 bytes of the next save's 600 ticks
        resource.setrlimit(resource.RLIMIT_FSIZE, (os.path.getsize(sys.argv[1]) + 100, hard))
    if tick == 1500:  # room again
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
    bits = (0, 1, 2, 4, 5, 6)[tick % 6]
    world.step(bits)
    try:
        recorder.tick(bits)
    except OutputError as failure:
        print(failure)
recorder.save()
"""


@pytest.mark.skipif(not hasattr(signal, "SIGXFSZ"), reason="a file size limit (Unix)")
def test_an_append_cut_short_is_taken_back_so_the_next_one_follows_a_whole_line(tmp_path):
    """The disk fills in the middle of an append (a file size limit cuts the write after
    100 bytes), then has room again: the cut is taken back, so the next save appends
    after the last whole line and the file replays whole; the torn line stayed before,
    the next save's lines ran on from it, and the file no longer read."""
    path = tmp_path / "game.json"
    done = subprocess.run([sys.executable, "-c", CUT_SHORT, str(path)], env=ENV,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout == (f"cannot write replay {str(path)!r}: File too large; the file "
                           "keeps its first 600 ticks, a valid replay\n")
    replay = load(path)
    assert replay.ticks == 3000 and run(replay)[0].mismatch is None


def _recording(path: Path, seed: int):
    from invaders.app.recording import Recorder
    from invaders.game.world import World

    world = World(seed=seed)
    return world, Recorder(world, path, save_every=300)


def _play(world, recorder, ticks: int) -> None:
    for _ in range(ticks):
        bits = (0, 1, 2, 4, 5, 6)[(world.tick * 7 + world.seed) % 6]
        world.step(bits)
        recorder.tick(bits)


def test_two_recordings_of_one_name_at_once_keep_both_whole(tmp_path, capsys):
    """A second recording under the name of one in progress (two windows, two runs, or
    a slip of the shell's history): the first, at its next save, finds another file
    there, says so in one line and goes on, whole, under the next free name; each file
    replays every tick of its own game (their lines were interleaved in one file that
    neither could read, after both had said "saved")."""
    path = tmp_path / "game.json"
    first, second = _recording(path, 1), _recording(path, 2)
    _play(*first, 700)   # saved at 300 and 600
    _play(*second, 400)  # its first save, at 300, replaces the first's file
    _play(*first, 500)
    _play(*second, 800)
    for _, recorder in (first, second):
        recorder.save()
    moved = tmp_path / "game-2.json"
    assert capsys.readouterr().err == (f"invaders: {path} was replaced or removed meanwhile, "
                                       f"not by this recording: it goes on, whole, in {moved}\n")
    assert (first[1].path, second[1].path) == (moved, path)
    for (world, _), name in ((first, moved), (second, path)):
        replay = load(name)
        assert (replay.seed, replay.ticks) == (world.seed, 1200)
        assert run(replay)[0].mismatch is None


def test_a_recording_whose_file_is_removed_goes_on_whole_under_its_name(tmp_path, capsys):
    """Removed mid-game, the file is written again, whole, at its next save, under the
    same name (free again), and the game recorded on: nothing said, nothing lost."""
    path = tmp_path / "game.json"
    world, recorder = _recording(path, 3)
    _play(world, recorder, 700)
    path.unlink()
    _play(world, recorder, 500)
    recorder.save()
    assert capsys.readouterr().err == ""
    replay = load(path)  # (the next save failed: no file to append to)
    assert replay.ticks == 1200 and run(replay)[0].mismatch is None


class FailingInTick:
    """An observer of a world's detection that raises inside tick `at`, its moves made and
    its contacts not yet found nor answered: an error (or a forced stop) mid-tick."""

    def __init__(self, at: int) -> None:
        self.at = at

    def before(self, scene) -> None:
        if scene.tick == self.at:
            raise RuntimeError("a bug mid-tick")

    def after(self, scene, candidates, contacts, stats) -> None:
        pass


def test_an_error_inside_a_tick_of_a_recording_run_saves_it_up_to_its_last_checkpoint(
        tmp_path, capsys, monkeypatch):
    """An internal error raised inside tick 1,000 (between its moves and its contacts)
    ends a recording run with exit 3, and what is saved is the game up to its last
    checkpoint, a replay that checks: where the world stood, half moved, no checkpoint can
    be made (the one made there did not replay)."""
    from invaders.lab.autopilot import Autopilot

    plays = Autopilot.actions

    def actions(self, world):
        if world.tick == 990:
            world.detector.observers.append(FailingInTick(1000))
        return plays(self, world)

    monkeypatch.setattr(Autopilot, "actions", actions)
    path = tmp_path / "run.json"
    assert main(["run", "--autopilot", "--ticks", "5000", "--record", str(path)]) == 3
    assert "RuntimeError: a bug mid-tick" in capsys.readouterr().err
    replay = load(path)
    assert replay.ticks == 960 and run(replay)[0].mismatch is None


def test_an_error_inside_a_tick_of_a_recorded_window_game_saves_it_up_to_its_last_checkpoint(
        tmp_path, capsys, monkeypatch):
    """The same in a window game on a clock the test moves: exit 3, and the file replays
    up to the last checkpoint before the tick the error cut."""
    import invaders.app.play as play_module

    now, cut = [0.0], []
    step = play_module.App.step

    def stepped(app, *args, **kwargs):
        now[0] += 1 / 60
        world = app.session.world
        if not cut and world.tick >= 300:
            cut.append(world.tick + 10)
            world.detector.observers.append(FailingInTick(cut[0]))
        return step(app, *args, **kwargs)

    on_the_tests_clock(monkeypatch, now)
    monkeypatch.setattr(play_module.App, "step", stepped)
    path = tmp_path / "played.json"
    assert main(["play", "--record", str(path), "--seed", "3"]) == 3
    assert "RuntimeError: a bug mid-tick" in capsys.readouterr().err
    replay = load(path)
    assert replay.ticks == cut[0] // 60 * 60 and run(replay)[0].mismatch is None


def test_a_program_without_a_console_plays_runs_and_records(tmp_path, monkeypatch):
    """pythonw on Windows (the game started from a shortcut, no console) has no standard
    output nor error (None) and no descriptor 2: a window game and a run each record and
    end with 0. The window did not open (the quieting of SDL's chatter flushed stderr and
    copied descriptor 2), and a run's output was flushed at its end: both said an internal
    error, exit 3, to no one."""
    import pygame

    from invaders import quiet

    real_dup, now, frames = os.dup, [0.0], [0]

    def dup(fd: int) -> int:
        if fd == 2:
            raise OSError(errno.EBADF, os.strerror(errno.EBADF))
        return real_dup(fd)

    def events():
        frames[0] += 1
        now[0] += 1 / 60
        return [pygame.event.Event(pygame.QUIT)] if frames[0] == 200 else []

    monkeypatch.setattr(sys, "stdout", None)
    monkeypatch.setattr(sys, "stderr", None)
    monkeypatch.setattr(quiet.os, "dup", dup)
    on_the_tests_clock(monkeypatch, now)
    monkeypatch.setattr(pygame.event, "get", events)
    played, ran = tmp_path / "played.json", tmp_path / "run.json"
    assert main(["play", "--record", str(played)]) == 0
    assert main(["run", "--autopilot", "--ticks", "300", "--record", str(ran)]) == 0
    assert [load(path).ticks for path in (played, ran)] == [199, 300]
    assert all(run(load(path))[0].mismatch is None for path in (played, ran))


def test_a_platform_without_sighup_or_fchmod_runs_records_and_stops_on_a_signal(
        tmp_path, capsys, monkeypatch):
    """Windows has no SIGHUP, no os.statvfs nor os.geteuid, and before Python 3.13 no
    os.fchmod: a run there still records (its file checked and written the same way,
    without a file system's flags, an owner or modes to read or give) and Ctrl-C still
    stops it on a whole tick (each was read unguarded once: the program could not start,
    or said an internal error at the check of the file to record)."""
    for name in ("statvfs", "geteuid", "fchmod"):
        monkeypatch.delattr(os, name)
    monkeypatch.delattr(signal, "SIGHUP")
    _autopilot_sends(monkeypatch, 300, signal.SIGINT)
    path = tmp_path / "run.json"
    assert main(["run", "--autopilot", "--ticks", "100000", "--record", str(path)]) == 130
    assert capsys.readouterr().err.splitlines() == [
        f"invaders: stopped by SIGINT at tick 301; saved {path} (301 ticks)"]
    assert run(load(path))[0].mismatch is None
