"""The package (pyproject.toml says the rest). With INVADERS_COMPILE=1 the core is compiled
by mypyc, the same source as C extensions: see docs/compiled.md."""

import os

from setuptools import setup

# The modules a tick runs through (the engine's and the game's), and the picture's drawing
# (the environment's pictures and the window's), compiled together.
CORE = [f"invaders/engine/{name}.py" for name in (
    "adaptive", "body", "broadphase", "detector", "grid", "numpy_grid", "predicates",
    "rects", "response", "rules", "store")] + [f"invaders/game/{name}.py" for name in (
        "actions", "art", "bombs", "entities", "events", "kinds", "players", "rack",
        "rules", "saucer", "statehash", "world")] + [
            "invaders/lab/picture.py", "invaders/lab/rack_layer.py"]


def compiled_core() -> list:
    """The core's C extensions when INVADERS_COMPILE=1 asks for them; else none."""
    if os.environ.get("INVADERS_COMPILE") != "1":
        return []
    from mypyc.build import mypycify

    return mypycify(CORE, opt_level="3")


setup(ext_modules=compiled_core())
