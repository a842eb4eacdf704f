"""What the compiled build (the core compiled by mypyc: docs/compiled.md) needs to be told of
a class, and the one helper that reads an object's fields either way. Interpreted, the
notes are nothing: `mypyc_attr` is mypy's own marker when mypy is installed, else a
decorator that returns the class as it is."""

from __future__ import annotations

from collections.abc import Callable
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

