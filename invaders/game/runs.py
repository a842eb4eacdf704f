"""A replay's input: the bits of every tick, as runs of equal bits, packed in two arrays.

A replay may hold a million runs; as [bits, count] lists they took 80 bytes apiece. Here a
run is two 64-bit words, and consecutive runs always differ (a run added with the bits of
the last one lengthens it), so equal inputs are stored one way only.
"""

from __future__ import annotations

from array import array
from collections.abc import Iterable, Iterator, Sequence

import numpy as np


class Runs:
    """(bits, count) runs in tick order; iterating gives them as pairs."""

    def __init__(self, runs: Iterable[Iterable[int]] = ()) -> None:
        self._bits = array("Q")
        self._counts = array("Q")
        for bits, count in runs:
            self.add(bits, count)

    def add(self, bits: int, count: int = 1) -> None:
        """`count` more ticks of `bits` (count >= 1)."""
        if self._bits and self._bits[-1] == bits:
            self._counts[-1] += count
        else:
            self._bits.append(bits)
            self._counts.append(count)

    def extend(self, bits: Sequence[int] | np.ndarray, counts: Sequence[int] | np.ndarray
               ) -> None:
        """Many runs at once (a block of a replay's lines), merged as `add` merges them."""
        if len(bits) == 0:
            return
        bits_array = np.array(bits, np.uint64)
        starts = np.concatenate(([0], np.flatnonzero(np.diff(bits_array)) + 1))  # new bits
        merged_bits = bits_array[starts].tolist()
        merged_counts = np.add.reduceat(np.array(counts, np.uint64), starts).tolist()
        self.add(merged_bits[0], merged_counts[0])
        self._bits.extend(merged_bits[1:])
        self._counts.extend(merged_counts[1:])

    @property
    def ticks(self) -> int:
        return sum(self._counts)

    def actions(self) -> Iterator[int]:
        """The bits of each tick, one tick at a time."""
        for bits, count in zip(self._bits, self._counts, strict=True):
            for _ in range(count):
                yield bits

    def lists(self) -> list[list[int]]:
        """The runs as [bits, count] lists, as a file writes them."""
        return [[bits, count] for bits, count in self]

    def __len__(self) -> int:
        return len(self._bits)

    def __iter__(self) -> Iterator[tuple[int, int]]:
        return zip(self._bits, self._counts, strict=True)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Runs):
            return self._bits == other._bits and self._counts == other._counts
        return NotImplemented

    def __repr__(self) -> str:
        return f"Runs({self.lists()!r})"
