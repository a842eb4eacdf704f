"""The standard error stream: the C libraries' chatter kept off it, and our own lines on
it, which never stop the program.

Opening the display or the mixer makes SDL try its drivers in turn, and the C libraries it
tries write straight to the process's stderr (eight ALSA lines without a sound card;
"XDG_RUNTIME_DIR is invalid" when DISPLAY names no server). None of it is ours to say:
what matters comes back as a pygame.error, which the caller turns into its own one line.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from typing import TextIO


@contextmanager
def c_stderr_quiet() -> Iterator[None]:
    """While inside, whatever the C library writes to file descriptor 2 is dropped
    (Python's own sys.stderr is flushed first and works again after). A program without a
    console (pythonw on Windows) has no sys.stderr and no descriptor 2: nothing to quiet."""
    if sys.stderr is not None:
        sys.stderr.flush()
    try:
        saved = os.dup(2)
    except OSError:
        yield
        return
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def say(line: str, end: str = "\n") -> None:
    """A line on standard error that never stops the program: where standard error cannot
    take it (its disk full), it is said to no one, and the program goes on to its own
    exit code (an unwritten line ended a window game, or made the exit 1, or 120 at
    Python's last flush)."""
    try:
        if sys.stderr is not None:  # (None without a console: pythonw on Windows)
            print(line, end=end, file=sys.stderr, flush=True)
    except OSError:
        output_to_nothing(sys.stderr)


def output_to_nothing(stream: TextIO | None = None) -> None:
    """Standard output (or `stream`) pointed at nothing, so that what is left in its
    buffer goes there when Python flushes it at the program's end (a reader gone, a disk
    full)."""
    with suppress(OSError, ValueError):  # (a stream with no descriptor)
        descriptor = (sys.stdout if stream is None else stream).fileno()
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, descriptor)
        finally:
            os.close(null)
