"""The rules table: which pairs of kinds are ever tested, how, and what answers a contact.

A pair of kinds with no entry is never tested: that is the first reduction, done as data.
In each entry side `a` probes: the grid looks up `a`'s cells in the layer of kind `b`, so
kinds that only ever probe are never binned at all. Each entry names, per side, whether the
box is the whole shape (BOX) or pixels matter (MASK); its motion model (DISCRETE: where
things are at the end of the tick; SWEPT: every pixel position along the tick's relative
motion; LANDING: where they land, whatever they passed); an optional zone outside which the
pair cannot meet; which sides a contact spends (a spent body takes part in no later contact
of that tick); and its response, called as `response(context, body_a, body_b, contact)`,
as a pair handler is in pymunk. The table also names the kinds whose masks change in place
(erode): those are never swept or cached, the other side of a pair is swept instead.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, fields, replace
from enum import Enum
from typing import Any

Box = tuple[int, int, int, int]  # x, y, w, h
Zone = tuple[Box, ...]  # a union of boxes
Response = Callable[[Any, Any, Any, Any], None]  # (context, body a, body b, contact)


class Shape(Enum):
    BOX = "box"  # the box is the shape
    MASK = "mask"  # pixels matter


class Motion(Enum):
    DISCRETE = "discrete"  # test where things are at the end of the tick
    SWEPT = "swept"  # test every pixel position along the tick's relative motion
    LANDING = "landing"  # the outcome is defined by where things land, not the path


MAX_KIND = 63  # kinds are 0 to 63: a set of them is one bit each of a machine word


@dataclass(frozen=True)
class PairRule:
    """One entry of the table: kinds a and b meet, tested and answered as it says."""

    a: int
    b: int
    a_shape: Shape = Shape.MASK
    b_shape: Shape = Shape.MASK
    motion: Motion = Motion.SWEPT
    zone: Zone | None = None
    spends_a: bool = False
    spends_b: bool = False
    response: Response | None = None
    reason: str = ""
    # Worked out from the above once, as plain fields, since the detector reads them for
    # every candidate pair: box against box is exact on its own, anything else goes on to
    # a pixel test; and the kinds whose side is tested by its mask.
    needs_pixels: bool = field(init=False, repr=False, compare=False)
    masked: frozenset[int] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for kind in (self.a, self.b):
            if not (isinstance(kind, int) and 0 <= kind <= MAX_KIND):
                raise ValueError(f"kind {kind!r}: a whole number from 0 to {MAX_KIND} (a "
                                 "store keeps the kinds it holds as one bit each)")
        _member("a_shape", self.a_shape, Shape)
        _member("b_shape", self.b_shape, Shape)
        _member("motion", self.motion, Motion)
        if self.zone is not None:
            object.__setattr__(self, "zone", zone_of(self.zone))
        masked = {kind for kind in (self.b, self.a) if self.shape_of(kind) is Shape.MASK}
        object.__setattr__(self, "masked", frozenset(masked))
        object.__setattr__(self, "needs_pixels", Shape.MASK in (self.a_shape, self.b_shape))

    def __deepcopy__(self, memo: dict[int, Any]) -> PairRule:
        """Itself: frozen, and copied with every world (a detector holds its entries)."""
        return self

    def __reduce__(self) -> tuple[type[PairRule], tuple[Any, ...]]:
        """Pickled as the call that makes it (compiled, a frozen class takes no fields
        set one by one, as pickle sets them)."""
        return PairRule, tuple(getattr(self, f.name) for f in fields(self) if f.init)

    def shape_of(self, kind: int) -> Shape:
        return self.a_shape if kind == self.a else self.b_shape


def _member(name: str, value: object, members: type[Enum]) -> None:
    """Refuse a field that is not of its enum, naming it: a string, its value's, would
    pass as the other member where a test asks `is Shape.MASK`."""
    if not isinstance(value, members):
        raise ValueError(f"{name} {value!r}: one of {', '.join(map(str, members))}")


def zone_of(boxes: Any) -> Zone:
    """A zone as the detector reads it, a tuple of boxes of four Python ints (boxes as
    lists, and NumPy integers, taken), or a ValueError naming the box that is not one. A
    box of no width or height holds no pixel, and is left out: it holds nothing, as a
    `Rect` of none meets nothing."""
    try:
        listed = list(boxes)
    except TypeError:
        raise ValueError(f"zone {boxes!r}: a tuple of boxes (x, y, width, height)") from None
    zone = []
    for box in listed:
        try:
            x, y, w, h = (operator.index(v) for v in box)
        except (TypeError, ValueError):
            raise ValueError(f"zone box {box!r}: four whole numbers, x, y, width and height "
                             "(a zone is a tuple of such boxes)") from None
        if w < 0 or h < 0:
            raise ValueError(f"zone box {box!r}: a width or height below 0")
        if w and h:
            zone.append((x, y, w, h))
    return tuple(zone)


@dataclass(frozen=True)
class RuleTable:
    """The entries, and the kinds whose masks change in place."""

    entries: tuple[PairRule, ...]
    eroding: frozenset[int] = frozenset()

    def __post_init__(self) -> None:
        seen: set[frozenset[int]] = set()
        for rule in self.entries:
            pair = frozenset({rule.a, rule.b})
            if pair in seen:
                raise ValueError(f"two entries for kinds {rule.a} and {rule.b}")
            seen.add(pair)
            if rule.motion is Motion.SWEPT and rule.a in self.eroding and rule.b in self.eroding:
                raise ValueError(f"entry {rule.a}-{rule.b}: both sides erode, nothing to sweep")

    def __reduce__(self) -> tuple[type[RuleTable], tuple[Any, ...]]:
        """Pickled as the call that makes it (see PairRule's)."""
        return RuleTable, (self.entries, self.eroding)

    def __iter__(self) -> Iterator[PairRule]:
        return iter(self.entries)

    def __len__(self) -> int:
        return len(self.entries)

    def rule_for(self, a: int, b: int) -> PairRule | None:
        """The entry for a pair of kinds in either order, or None: never tested."""
        for rule in self.entries:
            if (rule.a, rule.b) in ((a, b), (b, a)):
                return rule
        return None

    def probed_kinds(self) -> frozenset[int]:
        """Kinds some entry looks up in the broad phase: only these need cells."""
        return frozenset(r.b for r in self.entries)

    def swept_kinds(self) -> frozenset[int]:
        """Kinds in some swept entry: a grid bins them by their swept box."""
        return frozenset(k for r in self.entries if r.motion is Motion.SWEPT for k in (r.a, r.b))

    def kinds(self) -> frozenset[int]:
        return frozenset(k for r in self.entries for k in (r.a, r.b))

    def map(self, change: Callable[[PairRule], PairRule]) -> RuleTable:
        """The same table with every entry changed (a study's model, a zone moved)."""
        return replace(self, entries=tuple(change(rule) for rule in self.entries))
