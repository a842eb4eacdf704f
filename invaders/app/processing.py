"""What a command is working on, so the one-line internal-error message can name it."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

current: list[str] = []


@contextlib.contextmanager
def working_on(path: object) -> Iterator[None]:
    """Name the file for the duration; an error escaping leaves it named for the report."""
    current.append(str(path))
    yield
    current.pop()
