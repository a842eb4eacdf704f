"""Shared test set-up: headless SDL, hypothesis profiles, and the one quick study.

`ci` (chosen when CI is `true` or `1`): derandomized, so the same commit always gives the same
answer. `fuzz` (HYPOTHESIS_PROFILE=fuzz, by hand): random search; what it finds becomes an
explicit `@example` in the test. `dev`, the default elsewhere: random, no deadline.
"""

from __future__ import annotations

import contextlib
import io
import os

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
