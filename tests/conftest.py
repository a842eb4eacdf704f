"""Shared test set-up: headless SDL, hypothesis profiles, how processes are started, and
the one quick study.

`ci` (chosen when CI is `true` or `1`): derandomized, so the same commit always gives the same
answer. `fuzz` (HYPOTHESIS_PROFILE=fuzz, by hand): random search; what it finds becomes an
explicit `@example` in the test. `dev`, the default elsewhere: random, no deadline.
"""

from __future__ import annotations

import contextlib
import io
import multiprocessing
import os
import sys
import threading

import pytest
from hypothesis import settings

os.environ["SDL_VIDEODRIVER"] = "dummy"
os.environ["SDL_AUDIODRIVER"] = "dummy"
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True,
                          max_examples=150)
settings.register_profile("fuzz", deadline=None, print_blob=True, max_examples=5000)
settings.register_profile("dev", deadline=None, max_examples=150)
CI = os.environ.get("CI", "").lower() in ("true", "1")  # CI=false and CI=0 are not CI
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if CI else "dev"))

# The suite's process has threads once some tests ran (importing Arcade starts pyglet's
# media thread, Dask's client its IO loop), and a child forked from a process with threads
# may deadlock (Python 3.12 and newer warn of each such fork). There, processes are started
# by a fork server, as Python 3.14 starts them by default; the platform's own default
# (a fork, on Linux) is what runs on older versions, CI's among them. The tests that fork
# this process themselves are marked `forks` and run first, before any thread is started.
if sys.version_info >= (3, 12) and "forkserver" in multiprocessing.get_all_start_methods():
    multiprocessing.set_start_method("forkserver")
    # (imported once, in the server: each worker then starts with them, as a fork would)
    multiprocessing.set_forkserver_preload(["invaders.env.workers", "invaders.lab.plan"])


def pytest_configure(config):
    config.addinivalue_line("markers", "forks: forks the suite's process itself: runs first")


def pytest_collection_modifyitems(config, items):
    items.sort(key=lambda item: item.get_closest_marker("forks") is None)  # (stable)


@pytest.fixture
def alone():
    """For a test that forks this process: no other thread runs in it (the `forks` tests
    run first for this; a fork copies no thread, and one holding a lock leaves it held)."""
    others = [t.name for t in threading.enumerate() if t is not threading.main_thread()]
    assert not others, f"threads running before a fork: {others}"


@pytest.fixture(scope="session")
def quick_study(tmp_path_factory):
    """`invaders study --quick --jobs 2` run once for the session, from a folder with no
    replays (as after an install): its exit code, what it printed and its output folder.
    (The study's smallest run still takes half a minute: the tests that need it share it.)"""
    from invaders.app.cli import main

    folder = tmp_path_factory.mktemp("quick-study")
    here = os.getcwd()
    os.chdir(folder)
    try:
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            code = main(["study", "--quick", "--jobs", "2", "--out", "nested/study"])
    finally:
        os.chdir(here)
    return code, printed.getvalue(), folder / "nested" / "study"
