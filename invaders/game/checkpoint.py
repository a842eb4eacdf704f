"""Checkpoints: what a replay expects of the world at a tick, and a compact list of them.

A replay near the file-size limit holds 145,000 checkpoints; as objects (two dicts and ten
strings each) they took 1.8 KB apiece, 260 MB in all. `Checkpoints` packs each into about 160
bytes (its tick as a 64-bit word, its other numbers as digits, its digests as bytes) and
makes the object again when one is asked for.
"""

from __future__ import annotations

from array import array
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, overload

from invaders.game.kinds import THINGS
from invaders.game.statehash import GROUPS, combine
from invaders.game.world import World

COUNT_NAMES = tuple(kind.name.lower() for kind in THINGS)  # in the order the world lists them


@dataclass(frozen=True)
class Checkpoint:
    tick: int
    hash: str
    score: int
    ships: int
    wave: int
    counts: dict[str, int]
    groups: dict[str, str]

    @classmethod
    def of(cls, world: World) -> Checkpoint:
        groups = world.group_hashes()
        return cls(world.tick, combine(groups), world.score, world.ships, world.wave,
                   world.kind_counts(), groups)

    def differences(self, other: Checkpoint) -> list[str]:
        """What differs, most telling first: score, ships, wave, counts, then groups, then
        the hash (empty: they are the same)."""
        diffs = [f"{name} {getattr(self, name)} expected {getattr(other, name)}"
                 for name in ("score", "ships", "wave")
                 if getattr(self, name) != getattr(other, name)]
        diffs += [f"{kind} count {self.counts.get(kind)} expected {other.counts.get(kind)}"
                  for kind in sorted(set(self.counts) | set(other.counts))
                  if self.counts.get(kind) != other.counts.get(kind)]
        groups = [g for g in GROUPS if self.groups.get(g) != other.groups.get(g)]
        if groups:
            diffs.append("state differs in " + ", ".join(groups))
        if not diffs and self.hash != other.hash:
            diffs.append("state hash differs")
        return diffs


VALUES = ("score", "ships", "wave", *COUNT_NAMES)  # whole numbers from 0 to 2**63 - 1
DIGESTS = ("hash", *GROUPS)  # 16 bytes for the hash, 8 for each group
_WIDTHS = (16, *[8] * len(GROUPS))
VALUES_TEXT = b",".join([b"%d"] * len(VALUES))  # a checkpoint's VALUES as Checkpoints keeps them


class Checkpoints(Sequence[Checkpoint]):
    """Checkpoints in the order added, packed a column a field: the ticks in an array of
    64-bit words, the other numbers of each as one short line of decimal digits ("10,3,1,
    ...": they are only compared, so a long replay's reader never turns them into numbers),
    each digest's bytes in a bytearray."""

    def __init__(self, checkpoints: Iterable[Checkpoint] = ()) -> None:
        self._ticks = array("Q")
        self._values: list[bytes] = []
        self._digests = [bytearray() for _ in DIGESTS]
        for checkpoint in checkpoints:
            self.append(checkpoint)

    def append(self, checkpoint: Checkpoint) -> None:
        counts, groups = checkpoint.counts, checkpoint.groups
        numbers = (checkpoint.score, checkpoint.ships, checkpoint.wave,
                   *[counts[name] for name in COUNT_NAMES])
        self.extend_columns([checkpoint.tick], [VALUES_TEXT % numbers], [
            bytes.fromhex(checkpoint.hash), *[bytes.fromhex(groups[name]) for name in GROUPS]])

    def extend_columns(self, ticks: Sequence[int], values: Sequence[bytes],
                       digests: Sequence[bytes]) -> None:
        """More checkpoints, a column a field: their ticks; their VALUES as decimal digits
        joined by commas (no sign, no leading zero); each of DIGESTS (bytes end to end)."""
        if len(values) != len(ticks) or len(digests) != len(DIGESTS) or any(
                len(column) != len(ticks) * width
                for column, width in zip(digests, _WIDTHS, strict=True)):
            raise ValueError("columns of different lengths")
        self._ticks.extend(ticks)
        self._values.extend(values)
        for column, more in zip(self._digests, digests, strict=True):
            column += more

    def ticks(self) -> array:
        return self._ticks

    def __deepcopy__(self, memo: dict[int, Any]) -> Checkpoints:
        """A copy of each column at once, where a generic copy takes the values' list an
        item at a time (1,667 checkpoints: 9.5 against 435 us, a script); their bytes are
        never changed, so the list is copied, not they."""
        clone = memo[id(self)] = Checkpoints()
        clone._ticks, clone._values = array("Q", self._ticks), list(self._values)
        clone._digests = [bytearray(column) for column in self._digests]
        return clone

    def __len__(self) -> int:
        return len(self._ticks)

    @overload
    def __getitem__(self, index: int) -> Checkpoint: ...

    @overload
    def __getitem__(self, index: slice) -> list[Checkpoint]: ...

    def __getitem__(self, index: int | slice) -> Checkpoint | list[Checkpoint]:
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        if not -len(self) <= index < len(self):
            raise IndexError("checkpoint index out of range")
        i = index % len(self)
        score, ships, wave, *counts = map(int, self._values[i].split(b","))
        digest, *groups = self._digests
        return Checkpoint(self._ticks[i], digest[16 * i:16 * i + 16].hex(), score, ships, wave,
                          dict(zip(COUNT_NAMES, counts, strict=True)),
                          {name: column[8 * i:8 * i + 8].hex()
                           for name, column in zip(GROUPS, groups, strict=True)})

    def __iter__(self) -> Iterator[Checkpoint]:
        return (self[i] for i in range(len(self)))

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Checkpoints):
            return (self._ticks == other._ticks and self._values == other._values
                    and self._digests == other._digests)
        return isinstance(other, Sequence) and list(self) == list(other)

    def __repr__(self) -> str:
        return f"Checkpoints({list(self)!r})"
