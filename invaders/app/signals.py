"""Signals that stop a run or a game at a tick boundary, never inside one.

While a `StopSignals` is active, SIGINT, SIGTERM and SIGHUP (where there is one) only
note that a stop was asked; the loop looks at `received` between ticks and winds down, so
a recording always ends on a whole tick. A signal that was ignored when the program
started (SIGHUP under `nohup`) stays ignored. A second signal while winding down changes
nothing (two sent a millisecond apart still end the run on a whole tick, with the first
one's code); a third stops at once, as a plain Ctrl-C would, for a program that no longer
reaches a tick's end.
"""

from __future__ import annotations

import signal
from types import FrameType, TracebackType

# The stop signals, by name: each where the platform has it (Windows has no SIGHUP).
SIGNAL_NAMES = ("SIGINT", "SIGTERM", "SIGHUP")
FORCE_AFTER = 3  # signals, counting the first, after which the program stops at once


class StopSignals:
    def __init__(self) -> None:
        self.received: int | None = None
        self._count = 0
        self._previous: dict[int, object] = {}

    def __enter__(self) -> StopSignals:
        for signum in [getattr(signal, name) for name in SIGNAL_NAMES
                       if hasattr(signal, name)]:
            if signal.getsignal(signum) is signal.SIG_IGN:
                continue  # ignored by whoever started us (nohup): theirs to decide
            self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        self._count += 1
        if self._count >= FORCE_AFTER:
            raise KeyboardInterrupt
        if self.received is None:
            self.received = signum

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        for signum, handler in self._previous.items():
            signal.signal(signum, handler)  # type: ignore[arg-type]

    @property
    def exit_code(self) -> int:
        """128 + the signal's number, as shells report it (130 for Ctrl-C, 143 for TERM)."""
        return 128 + self.received if self.received is not None else 0

    @property
    def name(self) -> str:
        return signal.Signals(self.received).name if self.received is not None else ""
