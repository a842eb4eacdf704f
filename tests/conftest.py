"""Shared test set-up: headless SDL, and hypothesis profiles.

`ci` (chosen when CI is set): derandomized, so the same commit always gives the same
answer. `fuzz` (HYPOTHESIS_PROFILE=fuzz, by hand): random search; what it finds becomes an
explicit `@example` in the test. `dev`, the default elsewhere: random, no deadline.
"""

from __future__ import annotations

import os

from hypothesis import settings

os.environ["SDL_VIDEODRIVER"] = "dummy"
os.environ["SDL_AUDIODRIVER"] = "dummy"
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True,
                          max_examples=150)
settings.register_profile("fuzz", deadline=None, print_blob=True, max_examples=5000)
settings.register_profile("dev", deadline=None, max_examples=150)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI")
                                                               else "dev"))
