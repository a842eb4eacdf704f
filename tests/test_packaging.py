"""The package as others get it: `python -m build` makes the source archive (sdist) and,
from the archive as every PyPA frontend does, the wheel. The archive holds what its build
and the test suite read; the wheel holds the package's modules and its command, and,
installed on its own, plays a replay to its checkpoints."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

import invaders

ROOT = Path(__file__).resolve().parents[1]
# A working copy's own things, never a release's: its history, environments, builds, caches
# and compiled extensions.
NOT_SOURCES = shutil.ignore_patterns(".git", ".venv", "build", "dist", "*.egg-info",
                                     "__pycache__", ".*_cache", ".hypothesis", "*.so", "*.pyd")
# What the archive must hold: the build's files and the folders the suite reads.
BUILD_FILES = ("pyproject.toml", "setup.py", "README.md", "LICENSE", "MANIFEST.in")
ARCHIVED_FOLDERS = ("build_support", "invaders", "tests", "docs", "replays", ".ci")


def _files(folder: Path) -> set[str]:
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file()}


@pytest.fixture(scope="module")
def release(tmp_path_factory) -> tuple[Path, Path, Path]:
    """The copied sources, and the archive and the wheel built from them, the core left
    Python (INVADERS_COMPILE=0: the compiled core is CI's second run's; the choice between
    them, tests/test_core_build.py)."""
    work = tmp_path_factory.mktemp("release")
    source = work / "source"
    shutil.copytree(ROOT, source, ignore=NOT_SOURCES)
    env = {**os.environ, "INVADERS_COMPILE": "0"}
    done = subprocess.run([sys.executable, "-m", "build", "--no-isolation", "--outdir",
                           str(work / "dist"), str(source)],
                          env=env, capture_output=True, text=True, cwd=work)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    (archive,) = (work / "dist").glob("*.tar.gz")
    (wheel,) = (work / "dist").glob("*.whl")
    return source, archive, wheel


def test_the_source_archive_holds_what_its_build_and_the_tests_read(release):
    source, archive, _ = release
    with tarfile.open(archive) as tar:
        top = f"{archive.name.removesuffix('.tar.gz')}/"
        held = {m.name.removeprefix(top) for m in tar.getmembers() if m.isfile()}
    wanted = set(BUILD_FILES) | {name for name in _files(source)
                                 if name.split("/")[0] in ARCHIVED_FOLDERS}
    assert wanted - held == set()
    assert not any("__pycache__" in name or name.endswith(".pyc") for name in held)


def test_the_wheel_holds_the_package_its_command_and_its_licence(release):
    source, _, wheel = release
    with zipfile.ZipFile(wheel) as zipped:
        names = set(zipped.namelist())
        info = next(n for n in names if n.endswith(".dist-info/METADATA")).split("/")[0]
        entry_points = zipped.read(f"{info}/entry_points.txt").decode()
        metadata = zipped.read(f"{info}/METADATA").decode()
    package = {f"invaders/{name}" for name in _files(source / "invaders")}
    assert {n for n in names if not n.startswith(info)} == package
    assert f"{info}/licenses/LICENSE" in names
    assert "invaders = invaders.__main__:run" in entry_points.splitlines()
    assert {"License-Expression: MIT", f"Version: {invaders.__version__}"} <= set(
        metadata.splitlines())


def _installed(wheel: Path, folder: Path) -> dict[str, str]:
    """The wheel installed alone in `folder`, and the environment that runs it from there
    (first on the path; pygame and numpy are this environment's)."""
    target = folder / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-index",
                    "--target", str(target), str(wheel)], check=True, capture_output=True)
    env = {**os.environ, "PYTHONPATH": str(target)}
    env.pop("INVADERS_COMPILE", None)
    return env


def test_the_wheel_installed_alone_plays_a_replay_to_its_checkpoints(release, tmp_path):
    source, _, wheel = release
    env = _installed(wheel, tmp_path)
    target = Path(env["PYTHONPATH"])
    replay = source / "replays" / "saucer-300.json"
    done = subprocess.run([sys.executable, "-c", "import invaders; print(invaders.__file__)"],
                          env=env, capture_output=True, text=True, cwd=tmp_path)
    assert Path(done.stdout.strip()).is_relative_to(target), done.stdout + done.stderr
    done = subprocess.run([sys.executable, "-m", "invaders", "replay", str(replay)],
                          env=env, capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith(f"ok {replay}: ")


def test_a_type_checker_reads_the_installed_packages_annotations(release, tmp_path):
    """The package is marked typed (`py.typed`, PEP 561): mypy, checking a user's code
    against the wheel installed, reads its annotations, and finds a wrong call by them.
    Unmarked, it stops at the import (no library stubs or py.typed marker)."""
    _, _, wheel = release
    env = _installed(wheel, tmp_path)
    code = ("from invaders.engine.collide import groupcollide\n"
            "hits = groupcollide([], [], False, False)\n"
            "reveal_type(hits)\n"
            "groupcollide(1, [], False, False)\n")
    done = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "-c", code],
                          env=env, capture_output=True, text=True, cwd=tmp_path)
    said = done.stdout + done.stderr
    assert "py.typed" not in said, said
    assert 'Revealed type is "dict[Any, list[Any]]"' in said, said
    assert 'Argument 1 to "groupcollide" has incompatible type "int"' in said, said
    assert "Found 1 error" in said, said
