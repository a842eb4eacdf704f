"""The package (pyproject.toml says the rest), its core compiled by mypyc (the same source
as C extensions) where build_support/core_build.py says so: by default wherever the machine
can, else left Python. See docs/compiled.md."""

import sys
from pathlib import Path

from setuptools import setup

sys.path.insert(0, str(Path(__file__).resolve().parent / "build_support"))
from core_build import FallbackBuild, chosen, compiling, said_python

# The modules a tick runs through (the engine's and the game's), and the picture's drawing
# (the environment's pictures and the window's), compiled together.
CORE = [f"invaders/engine/{name}.py" for name in (
    "adaptive", "body", "broadphase", "detector", "grid", "numpy_grid", "predicates",
    "rects", "response", "rules", "store")] + [f"invaders/game/{name}.py" for name in (
        "actions", "art", "bombs", "entities", "events", "kinds", "players", "rack",
        "rules", "saucer", "statehash", "world")] + [
            "invaders/lab/picture.py", "invaders/lab/rack_layer.py"]


def compiled_core() -> list:
    """The core's C extensions where this build compiles it; else none. Asked for
    (INVADERS_COMPILE=1), a failure fails the build; otherwise it leaves the core Python
    (mypy missing from the build, or a version of Python it cannot compile for)."""
    if not compiling():
        return []
    try:
        from mypyc.build import mypycify

        return mypycify(CORE, opt_level="3")
    except (Exception, SystemExit) as failure:  # (mypyc says its own failures by exiting)
        if chosen() == "1":
            raise
        said_python(f"mypyc could not compile it ({failure})")
        return []


extensions = compiled_core()
setup(ext_modules=extensions,
      cmdclass={} if chosen() == "1" or not extensions else {"build_ext": FallbackBuild})
