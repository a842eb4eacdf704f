"""The core runs as it was built: compiled (INVADERS_COMPILE=1, as CI sets it for its second
run, on a build of the same commit) or interpreted (every other run), never quietly the
other. What the compiled build changes of the code is tested by the rest of the suite, run
on both."""

from __future__ import annotations

import os

from invaders.engine import body, detector, store
from invaders.game import rack, world


def test_the_core_is_compiled_exactly_when_built_so():
    compiled = os.environ.get("INVADERS_COMPILE") == "1"
    for module in (body, detector, store, rack, world):
        assert module.__file__.endswith(".py") is not compiled, module.__file__

