"""What the compiled build (the core compiled by mypyc: docs/compiled.md) needs to be told of
a class, the one helper that reads an object's fields either way, and whether a compiled
build is installed behind the interpreted sources imported. Interpreted, the notes are
nothing: `mypyc_attr` is mypy's own marker when mypy is installed, else a decorator that
returns the class as it is."""

from __future__ import annotations

import importlib.util
import os
import sys
from collections.abc import Callable, Sequence
from importlib.machinery import EXTENSION_SUFFIXES
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")

try:
    from mypy_extensions import mypyc_attr
except ImportError:  # (installed with mypy: the game runs without it)
    def mypyc_attr(*names: str, **values: bool) -> Callable[[T], T]:  # type: ignore[misc]
        return lambda cls: cls


def fields(obj: Any) -> dict[str, Any]:
    """An object's fields by name: its `__dict__` interpreted, the compiled class's state
    (mypyc keeps no `__dict__`) compiled."""
    own = getattr(obj, "__dict__", None)
    return dict(own if own is not None else obj.__getstate__())


def shadowed_build(path: Sequence[str] | None = None) -> Path | None:
    """A compiled build of this package that the interpreted one imported stands in front
    of on the import path (`sys.path`, or `path`): None if there is none, or if the core
    imported is compiled. Python puts a script's folder first on the path (the current one
    for `python -c`, `-m` and the prompt), so a script run in a clone imports the clone's
    sources, not the compiled build installed for its speed, and nothing says so."""
    spec = importlib.util.find_spec("invaders.engine.adaptive")  # (a module of the core)
    if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
        return None
    for entry in sys.path if path is None else path:  # (the sources' own folder has none)
        package = os.path.abspath(os.path.join(entry or os.curdir, "invaders"))
        # (os.path.isfile: False, not an error, for a folder that cannot be read)
        if any(os.path.isfile(os.path.join(package, "engine", f"adaptive{suffix}"))
               for suffix in EXTENSION_SUFFIXES):
            return Path(package)
    return None


def shadowed_note() -> str | None:
    """What to say where speed is at stake (importing the environment, the bench) when a
    compiled build stands behind the sources imported; None when none does."""
    build = shadowed_build()
    if build is None:
        return None
    return (f"invaders: the sources at {Path(__file__).resolve().parents[1]} are imported, "
            f"not the compiled build behind them at {build}: take the sources off the "
            "path (run from another folder) to use it (docs/compiled.md)")
