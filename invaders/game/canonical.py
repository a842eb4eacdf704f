"""Checkpoint lines in the shapes tools write them, read a block at a time.

Reading a replay near the size limit (145,000 checkpoint lines) through the JSON parser, a
check of every field and a Checkpoint object a line took 16 s and 520 MB. The lines this
program writes all have one shape, so a block of them (64 KB, some 140 lines) is read by
one regular expression and its fields taken a column at a time: about 9 microseconds a
line. Only the shape is read here, and the one fact that needs no limit: each hash is the
digest of its groups. The same lines with every object's fields sorted (as tools that sort
them write them), in an order learnt from the file (Orders), or with a little white space
between tokens (as `json.dumps` writes by default, or Windows' line ends), are read the
same way, by a pattern of their own. A block of which any line has another shape is left
to the JSON block reader (json_block.py).

A line that matches is, as JSON, an object of exactly these fields in one of these orders,
its numbers whole and below 2**63, its digests lower-case hex, no escapes.
"""

from __future__ import annotations

import functools
import json
import re
import sys
from binascii import unhexlify
from collections.abc import Sequence
from itertools import accumulate, repeat
from typing import Any, NamedTuple

from invaders.game.checkpoint import COUNT_NAMES
from invaders.game.replay_format import CHECKPOINT_FIELDS, LINE_FIELDS
from invaders.game.statehash import GROUPS, LISTED, digest_listed

_NUMBER = rb"(?:0|[1-9][0-9]{0,17})"
_RUN = rb"\[~%s~,~%s~\]" % (_NUMBER, _NUMBER)
# Each value of a line, in the order its columns are taken (counts and groups share names).
COLUMNS = ("inputs", "tick", "hash", "score", "ships", "wave",
           *[f"count_{name}" for name in COUNT_NAMES], *[f"group_{name}" for name in GROUPS])


def _value(column: str, pattern: bytes) -> bytes:
    return rb"(?P<%s>%s)" % (column.encode(), pattern)


# The order of each object's fields in a line: the line's, its checkpoint's, the
# checkpoint's counts' and its groups'.
Order = tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...], tuple[str, ...]]
OWN: Order = (LINE_FIELDS, CHECKPOINT_FIELDS, COUNT_NAMES, GROUPS)
SORTED: Order = tuple(tuple(sorted(names)) for names in OWN)  # type: ignore[assignment]


def _object(fields: dict[str, bytes], names: tuple[str, ...]) -> bytes:
    """A JSON object's pattern from its fields' patterns, in the order `names` gives,
    `~` where JSON allows white space."""
    return rb"\{~%s~\}" % b"~,~".join(b'"%s"~:~%s' % (name.encode(), fields[name])
                                        for name in names)


def _shape(order: Order) -> bytes:
    """A checkpoint's line with its objects' fields in `order`, a named group a value."""
    line, checkpoint, counts, groups = order
    count_fields = {name: _value(f"count_{name}", _NUMBER) for name in COUNT_NAMES}
    group_fields = {name: b'"%s"' % _value(f"group_{name}", rb"[0-9a-f]{16}")
                    for name in GROUPS}
    checkpoint_fields = {
        "tick": _value("tick", _NUMBER), "hash": b'"%s"' % _value("hash", rb"[0-9a-f]{32}"),
        **{name: _value(name, _NUMBER) for name in ("score", "ships", "wave")},
        "counts": _object(count_fields, counts), "groups": _object(group_fields, groups)}
    line_fields = {
        "inputs": rb"\[~%s~\]" % _value("inputs", rb"(?:%s(?:~,~%s)*)?" % (_RUN, _RUN)),
        "checkpoint": _object(checkpoint_fields, checkpoint)}
    return rb"^~%s~$" % _object(line_fields, line)


# A little white space anywhere JSON allows it (as `json.dumps` writes by default, or a line
# ending in \r\n): more than this, and the JSON block reader reads the line.
# (From Python 3.11 the gap's repeat is possessive: it never gives back white space it took,
# and nothing after a gap starts with white space, so the matches are the same, found
# sooner: 1.27x over the blocks of a spaced file, the median of 9 rounds in turn.)
_GAP = rb"[ \t\r]{0,8}" + (b"+" if sys.version_info >= (3, 11) else b"")


@functools.lru_cache(maxsize=64)  # (kept for the files read after: a few milliseconds each)
def _compiled(order: Order, gap: bytes) -> tuple[re.Pattern[bytes], list[int]]:
    """A shape's pattern (`gap` where JSON allows white space), and where each of COLUMNS
    is in its matches' groups."""
    pattern = re.compile(_shape(order).replace(b"~", gap), re.MULTILINE)
    return pattern, [pattern.groupindex[column] - 1 for column in COLUMNS]


# More than a line holds besides its input runs (18-digit numbers and every gap included).
REST = 1024 + 8 * _shape(OWN).count(b"~")


class Orders:
    """The orders of fields a file's blocks are tried in: the program's and sorted (as
    `sort_keys=True`, `jq -S` and Go's maps write them), then the orders of up to LEARNED
    blocks the JSON block reader took (a tool of any other order writes them all in one):
    each order a pattern to compile, so a file cannot make many."""

    LEARNED = 4

    def __init__(self) -> None:
        self.orders: list[Order] = [OWN, SORTED]

    def learn(self, block: bytes) -> None:
        """Try the order of the block's first line on the blocks after it (while fewer
        than LEARNED have been learnt, and if it is a checkpoint's line in a new order)."""
        if len(self.orders) < 2 + self.LEARNED:
            order = order_of(block[:block.find(b"\n") + 1])
            if order is not None and order not in self.orders:
                self.orders.append(order)


def order_of(line: bytes) -> Order | None:
    """The order of a checkpoint line's fields (None for any other line)."""
    try:
        data = json.loads(line)
        checkpoint = data["checkpoint"]
        order = (tuple(data), tuple(checkpoint), tuple(checkpoint["counts"]),
                 tuple(checkpoint["groups"]))
    except (ValueError, TypeError, KeyError, RecursionError):
        return None
    return order if tuple(map(sorted, order)) == tuple(map(sorted, SORTED)) else None


class Block(NamedTuple):
    """The lines of a block, as columns (nothing here is checked against a limit yet)."""
    bits: list[int]  # every input run's bits, in order
    counts: list[int]  # and its count
    ends: list[int]  # the input ticks the block covers up to each line's end
    longest: int  # at least the length of its longest line
    ticks: list[int]  # each checkpoint's tick
    values: list[bytes]  # and its other numbers, as Checkpoints keeps them
    digests: list[bytes]  # each of Checkpoints' DIGESTS, a column each (bytes end to end)
    switches: list[tuple[int, Any]]  # each line's lab switches as JSON gives them, by index


def read_block(block: bytes, orders: Sequence[Order] = (OWN, SORTED)) -> Block | None:
    """The block's lines (each ending in a newline) as columns, when every line has one of
    the shapes (the orders, each plain or with a little white space) and every hash is the
    digest of its groups; else None."""
    columns = _columns(block, orders)
    if columns is None:  # a line of another shape
        return None
    runs, ticks, hashes, *columns = columns
    numbers, groups = columns[:-len(GROUPS)], columns[-len(GROUPS):]
    digests = hashed(hashes, groups)
    if digests is None:
        return None
    # Every run's bits and count in turn (each already read as a JSON number), then the
    # ticks they cover up to each line's end.
    flat = json.loads(b"[%s]" % b",".join(filter(None, runs)).translate(None, b"[]"))
    runs_ended = accumulate(map(bytes.count, runs, repeat(b"[")))
    covered = [0, *accumulate(flat[1::2])]
    return Block(flat[0::2], flat[1::2], [covered[end] for end in runs_ended],
                 max(map(len, runs)) + REST, [*map(int, ticks)],
                 [*map(b",".join, zip(*numbers, strict=True))], digests, [])


def _columns(block: bytes, orders: Sequence[Order]) -> list[tuple[bytes, ...]] | None:
    """The lines' values, a column each in COLUMNS' order, when all have one of the shapes
    (the shapes with white space tried only on a block that holds some: on a block of
    lines of the program's shape but one, each would read all but that one again)."""
    lines, spaced = block.count(b"\n"), any(map(block.__contains__, (b" ", b"\t", b"\r")))
    for order, gap in ((order, gap) for order in orders for gap in (b"", _GAP)):
        if gap and not spaced:
            continue
        pattern, taken = _compiled(order, gap)
        rows = pattern.findall(block) if pattern.match(block) else []  # (a match: a line)
        if rows and len(rows) == lines:
            matched = [*zip(*rows, strict=True)]
            return [matched[index] for index in taken]
    return None


def hashed(hashes: Sequence[bytes], groups: Sequence[Sequence[bytes]]) -> list[bytes] | None:
    """The digests' bytes, a column each (the hash's, then each group's in GROUPS' order),
    from their hex (lower case, of the right lengths): None unless every hash is the digest
    of its groups."""
    digests = [unhexlify(b"".join(column)) for column in (hashes, *groups)]
    listed = map(LISTED.__mod__, zip(*groups, strict=True))  # each line's, as hashed
    return digests if b"".join(map(digest_listed, listed)) == digests[0] else None
