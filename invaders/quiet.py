"""SDL's and ALSA's probing chatter kept off the terminal.

Opening the display or the mixer makes SDL try its drivers in turn, and the C libraries it
tries write straight to the process's stderr (eight ALSA lines without a sound card;
"XDG_RUNTIME_DIR is invalid" when DISPLAY names no server). None of it is ours to say:
what matters comes back as a pygame.error, which the caller turns into its own one line.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager


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
