"""Timing helpers for the bench and the study (never used by the simulation)."""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator


@contextlib.contextmanager
def no_gc() -> Iterator[None]:
    """Time without the cyclic garbage collector, as timeit does, for both sides alike (and
    as timeit, without collecting first: a full collection costs tens of milliseconds on a
    study's heap, and garbage left uncollected costs no time while the collector is off)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
