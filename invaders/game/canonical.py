"""Checkpoint lines read a block at a time by regular expressions, however JSON spells them.

Reading a replay near the size limit (145,000 checkpoint lines) through the JSON parser, a
check of every field and a Checkpoint object a line took 16 s and 520 MB. The lines this
program writes all have one shape, so a block of them (64 KB, some 140 lines) is read by
one regular expression and its fields taken a column at a time: about 9 microseconds a
line (ending in a newline, or in a carriage return and a newline as Windows ends lines).
Only the shape is read here, and the one fact that needs no limit: each hash is the digest
of its groups. The same lines with every object's fields sorted (as tools that sort
them write them) or in an order learnt from the file (Orders: as written, a name written
again included), with white space between tokens or not, are read by a pattern of their
order; lines whose fields are in any order (a
hostile file may change it every line), by one pattern that takes each object's fields in
any order, about two thirds as fast. JSON's escapes of the letters and digits that names
and digests hold, and -0, are read as what they stand for (Plain). A field or an object
written twice is read as JSON reads it (the last kept). A block of which any line has
another shape (a lab switch not cut out of its line by switches_cut.py, a field missing) is
left to the JSON block reader (json_block.py).

A line that matches is, as JSON, an object of exactly these fields, its numbers whole (and
of at most 19 digits: read_block bounds them), its digests lower-case hex.
"""

from __future__ import annotations

import codecs
import functools
import json
import re
import sys
from binascii import unhexlify
from collections.abc import Iterator, Sequence
from itertools import repeat
from typing import Any, NamedTuple

import numpy as np

from invaders.game.checkpoint import COUNT_NAMES
from invaders.game.replay_format import CHECKPOINT_FIELDS, LINE_FIELDS, MAX_TICKS
from invaders.game.statehash import GROUPS, LISTED, digest_listed

_NUMBER = rb"(?:0|[1-9][0-9]{0,18})"  # (19 digits may pass 2**63 - 1: bounded after)
_LARGEST = b"%d" % (2**63 - 1)
_HEX = rb"[0-9a-f\x80-\x89]"  # (from 0x80: an escaped digit, as Plain leaves it)
_RUN = rb"\[~%s~,~%s~\]" % (_NUMBER, _NUMBER)
# Each value of a line, in the order its columns are taken (counts and groups share names).
COLUMNS = ("runs", "inputs", "tick", "hash", "score", "ships", "wave",
           *[f"count_{name}" for name in COUNT_NAMES], *[f"group_{name}" for name in GROUPS])


# From Python 3.11 the repeats of white space and of an object's fields are possessive:
# they never give back what they took. Nothing after a gap starts with white space, and
# nothing after an object's last field but its brace, so the matches are the same, found
# sooner: 1.27x over the blocks of a spaced file, 1.45x over those of a file with an order
# of fields a line read by ANY (medians of 9 and 7 rounds in turn, a script).
_POSSESSIVE = b"+" if sys.version_info >= (3, 11) else b""
# White space anywhere JSON allows it (as `json.dumps` writes by default).
_GAP = rb"[ \t\r]*" + _POSSESSIVE


def _value(column: str, pattern: bytes) -> bytes:
    return rb"(?P<%s>%s)" % (column.encode(), pattern)


# The order of each object's fields in a line: the line's, its checkpoint's, the
# checkpoint's counts' and its groups'.
Order = tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...], tuple[str, ...]]
OWN: Order = (LINE_FIELDS, CHECKPOINT_FIELDS, COUNT_NAMES, GROUPS)
SORTED: Order = tuple(tuple(sorted(names)) for names in OWN)  # type: ignore[assignment]
ANY = None  # (in place of an order: each object's fields in any order)


def _object(fields: dict[str, bytes], names: tuple[str, ...] | None, at: str = "",
            earlier: dict[str, bytes] | None = None) -> bytes:
    """A JSON object's pattern from its fields' patterns, in the order `names` gives (None:
    in any order), `~` where JSON allows white space. A name that `names` gives again (as
    a file wrote it: JSON keeps the last) is matched before its last by its pattern in
    `earlier`, without groups."""
    if names is not None:
        pairs = [b'"%s"~:~%s' % (name.encode(), fields[name] if name not in names[i + 1:]
                                 else _NAMED.sub(b"(?:", (earlier or fields)[name]))
                 for i, name in enumerate(names)]
        return rb"\{~%s~\}" % b"~,~".join(pairs)
    pairs = [b'"%s"~:~%s' % (name.encode(), fields[name]) for name in fields]
    # Fields, each any of them, each followed by a comma or the brace, and no comma just
    # before the brace (looked at once, at the brace, not after each comma). A field
    # written again: its group keeps the last, as JSON does. The empty group `at` marks
    # where the object starts (its last start, if it is written again; see
    # _whole_objects). (Possessive, as the gap.)
    return rb"%s\{(?:~(?:%s)~(?:,|(?=\})))+%s(?<!,)\}" % (
        _value(at, b"") if at else b"", b"|".join(pairs), _POSSESSIVE)


_NAMED = re.compile(rb"\(\?P<\w+>")  # (a named group's start: made a plain one)


def _shape(order: Order | None) -> bytes:
    """A checkpoint's line with its objects' fields in `order` (or ANY), a named group a
    value; an object written before its last (in an order learnt) takes any order."""
    line, checkpoint, counts, groups = order or (None,) * 4
    count_fields = {name: _value(f"count_{name}", _NUMBER) for name in COUNT_NAMES}
    group_fields = {name: b'"%s"' % _value(f"group_{name}", _HEX + b"{16}") for name in GROUPS}
    numbers = {"tick": _value("tick", _NUMBER), "hash": b'"%s"' % _value("hash", _HEX + b"{32}"),
               **{name: _value(name, _NUMBER) for name in ("score", "ships", "wave")}}
    inputs = {"inputs": _value("inputs", rb"\[~%s~\]" % _value("runs", rb"(?:%s(?:~,~%s)*)?" % (
        _RUN, _RUN)))}  # (the runs, maybe none; the inputs never empty, if there)
    any_checkpoint = {**numbers, "counts": _object(count_fields, None, "counts_at"),
                      "groups": _object(group_fields, None, "groups_at")}
    checkpoint_fields = {
        **numbers, "counts": _object(count_fields, counts, "counts_at"),
        "groups": _object(group_fields, groups, "groups_at")}
    line_fields = {**inputs, "checkpoint": _object(checkpoint_fields, checkpoint,
                                                   "checkpoint_at", any_checkpoint)}
    return rb"^~%s~\r?$" % _object(line_fields, line, "", {  # (\r\n: as Windows ends lines)
        **inputs, "checkpoint": _object(any_checkpoint, None, "checkpoint_at")})


# In ANY's pattern, each object a line may write again: its name, the mark of where it
# starts and its fields' groups.
NESTED = (("checkpoint", "checkpoint_at",
           ("tick", "hash", "score", "ships", "wave", "counts_at", "groups_at")),
          ("counts", "counts_at", tuple(f"count_{name}" for name in COUNT_NAMES)),
          ("groups", "groups_at", tuple(f"group_{name}" for name in GROUPS)))
Nesting = tuple[tuple[bytes, int, tuple[int, ...]], ...]  # (the name as a JSON string)


@functools.lru_cache(maxsize=64)  # (kept for the files read after: a few milliseconds each)
def _compiled(order: Order | None, gap: bytes
              ) -> tuple[re.Pattern[bytes], list[int], Nesting]:
    """A shape's pattern (`gap` where JSON allows white space), where each of COLUMNS is in
    its matches' groups, and (for ANY) NESTED as group numbers."""
    pattern = re.compile(_shape(order).replace(b"~", gap), re.MULTILINE)
    number = pattern.groupindex.__getitem__
    nesting = tuple((b'"%s"' % name.encode(), number(at), tuple(map(number, fields)))
                    for name, at, fields in NESTED) if order is ANY else ()
    return pattern, [number(column) - 1 for column in COLUMNS], nesting


class Orders:
    """The orders of fields a file's blocks are tried in: the program's and sorted (as
    `sort_keys=True`, `jq -S` and Go's maps write them), then the orders of up to LEARNED
    blocks that only ANY took, as their first lines wrote them (a tool of any other order
    writes them all in one, a name written again too; a block's own order reads it about
    1.5 times as fast as ANY, 1.7 times where the counts are written twice): each order a
    pattern to compile, so a file cannot make many; ANY last."""

    LEARNED = 4

    def __init__(self) -> None:
        self.orders: list[Order] = [OWN, SORTED]

    def __iter__(self) -> Iterator[Order | None]:
        return iter([*self.orders, ANY])

    def learn(self, block: bytes) -> None:
        """Try the order of the block's first line on the blocks after it (while fewer
        than LEARNED have been learnt, and if it is a checkpoint's line in a new order)."""
        if len(self.orders) < 2 + self.LEARNED:
            order = order_of(block[:block.find(b"\n") + 1])
            if order is not None and order not in self.orders:
                self.orders.append(order)


def order_of(line: bytes) -> Order | None:
    """The order of a checkpoint line's fields as written (a name written again named
    again; the objects inside, the last of their name's, as JSON keeps it); None for any
    other line, and for one with more names than twice its fields in an object (a line of
    256 KB could name thousands: a pattern that takes seconds to compile)."""
    try:
        data = json.loads(line, object_pairs_hook=_Written)
        checkpoint = data.last("checkpoint")
        order = (data.names(), checkpoint.names(), checkpoint.last("counts").names(),
                 checkpoint.last("groups").names())
    except (ValueError, TypeError, AttributeError, KeyError, RecursionError):
        return None
    if tuple(map(sorted, map(set, order))) != tuple(map(list, SORTED)) or any(
            len(names) > 2 * len(set(names)) for names in order):
        return None  # (no name more than twice on average: each order's pattern stays small)
    return order


class _Written(list):
    """A JSON object as written: its (name, value) pairs in order, names written again
    kept."""

    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self)

    def last(self, name: str) -> _Written:
        """The last value of that name (KeyError: none), if an object (TypeError: not)."""
        value = dict(self)[name]
        if not isinstance(value, _Written):
            raise TypeError(name)
        return value


class Plain(NamedTuple):
    """A block with what JSON lets a valid line spell two ways spelt one way: each escape
    of a letter as the letter, of a digit as a byte from 0x80 (which _HEX takes, and no
    number: in a number an escape is no JSON), and -0 as 0 where a number starts (after a
    colon, a bracket, a comma or white space: in a string, that character is left, so the
    string is still no name or digest)."""
    text: bytes
    escaped: bool  # (the digests' escaped digits are turned back by `digits`)

    @classmethod
    def of(cls, block: bytes) -> Plain | None:
        """The block spelt plainly; None if it is not ASCII (no valid line's values are)
        or has a backslash that is not such an escape (an escaped backslash, too)."""
        if not block.isascii():
            return None
        text = _MINUS_ZERO.sub(b"0", block) if b"-" in block else block
        if b"\\" not in text:
            return cls(text, False)
        if _OTHER_BACKSLASH.search(text):
            return None
        # (Python's own escapes are JSON's where every backslash is \u00 and a code
        # below 0x80; a digit's code moved up by 0x50.)
        decoded = codecs.decode(text.replace(b"\\u003", b"\\u008"), "unicode_escape")
        return cls(decoded.encode("latin-1"), True)

    def digits(self, digests: tuple[bytes, ...]) -> tuple[bytes, ...]:
        """A digest column's values with their escaped digits turned back."""
        if not self.escaped:
            return digests
        return tuple(b",".join(digests).translate(_DIGITS_BACK).split(b","))


_MINUS_ZERO = re.compile(rb"(?<=[:\[,\s])-0")
# A backslash that does not start the escape of a digit or a letter.
_OTHER_BACKSLASH = re.compile(rb"\\(?!u00(?:3[0-9]|6[1-9a-fA-F]|7[0-9aA]))")
_DIGITS_BACK = bytes.maketrans(bytes(range(0x80, 0x8a)), b"0123456789")


class Block(NamedTuple):
    """The lines of a block, as columns (nothing here is checked against a limit yet)."""
    bits: np.ndarray  # every input run's bits, in order (64-bit integers)
    counts: np.ndarray  # and its count
    ends: list[int]  # the input ticks the block covers up to each line's end
    longest: int  # at least the length of its longest line
    ticks: list[int]  # each checkpoint's tick
    values: list[bytes]  # and its other numbers, as Checkpoints keeps them
    digests: list[bytes]  # each of Checkpoints' DIGESTS, a column each (bytes end to end)
    switches: list[tuple[int, Any]]  # each line's lab switches as JSON gives them, by index


def read_block(block: bytes, orders: Orders | None = None) -> Block | None:
    """The block's lines (each ending in a newline) as columns, when every line has one of
    the shapes (the orders', with white space or not) and every hash is the digest of its
    groups; else None. A block only ANY took teaches `orders` its order."""
    plain = Plain.of(block)
    shaped = None if plain is None else _columns(plain.text, orders or Orders())
    if plain is None or shaped is None:  # a line of another shape
        return None
    order, (runs, _, ticks, hashes, *columns) = shaped
    numbers, groups = columns[:-len(GROUPS)], columns[-len(GROUPS):]
    digests = hashed(plain.digits(hashes), [*map(plain.digits, groups)])
    values = [*map(b",".join, zip(*numbers, strict=True))]
    if digests is None or not _bounded(values):
        return None
    if order is ANY and orders is not None:
        orders.learn(block)
    runs_read = _runs(runs)
    if runs_read is None:
        return None
    return Block(*runs_read, len(block), [*map(int, ticks)], values, digests, [])


def _runs(runs: tuple[bytes, ...]) -> tuple[np.ndarray, np.ndarray, list[int]] | None:
    """Every run's bits and count in turn, read at once by numpy from the runs' text (each
    already matched as a JSON number of at most 19 digits), and the ticks they cover up to
    each line's end; None if a number passes MAX_TICKS, more than a run's bits or count
    may be. Numpy reads a number past its 64 bits as their largest, and sums past them
    wrap around: refused first, no number can pass the bound, nor a block's sum 64 bits (a
    test breaks when counts past 64 bits, summed around to a line's ticks, are taken).
    About 1.4 times as fast as the JSON parser and lists over a block of a replay with the
    most input runs (medians of 25 rounds in turn, in one process, a script)."""
    text = b",".join(filter(None, runs)).translate(None, b"[]")
    # (typed as an array of any shape: numpy 2.5's stubs give np.zeros(0)'s, and then no
    # `max()` without arguments)
    numbers: np.ndarray = (np.fromstring(text, np.int64, sep=",") if text
                           else np.zeros(0, np.int64))
    each_line = np.cumsum([*map(bytes.count, runs, repeat(b"["))])  # (runs up to its end)
    if len(numbers) != 2 * (each_line[-1] if len(each_line) else 0) or (
            len(numbers) and numbers.max() > MAX_TICKS):
        return None
    counts = numbers[1::2]
    covered = np.concatenate(([0], np.cumsum(counts)))  # (no sum passes 64 bits: see above)
    return numbers[0::2], counts, covered[each_line].tolist()


def _bounded(values: list[bytes]) -> bool:
    """Whether every number in the lines' values (each line's joined by commas) is at most
    2**63 - 1, the most a field holds. (Values too short to hold a number of 19 digits, as
    every line's of a game are, are not split.)"""
    if max(map(len, values)) < _SHORTEST_WITH_19:
        return True
    return all(len(number) < len(_LARGEST) or number <= _LARGEST
               for number in b",".join(values).split(b","))


_SHORTEST_WITH_19 = len(_LARGEST) + 2 * (3 + len(COUNT_NAMES) - 1)  # (the others 1 digit)


def _columns(block: bytes, orders: Orders
             ) -> tuple[Order | None, list[tuple[bytes, ...]]] | None:
    """The order that read the lines, and their values, a column each in COLUMNS' order,
    when all have one of the shapes (the shapes with white space tried only on a block that
    holds some: on a block of lines of the program's shape but one, each would read all but
    that one again). Where ANY reads lines of more than four objects (braces: no value
    holds one), some object is written again: see _whole_objects."""
    lines, spaced = block.count(b"\n"), any(map(block.__contains__, (b" ", b"\t", b"\r")))
    for order, gap in ((order, gap) for order in orders for gap in (b"", _GAP)):
        if gap and not spaced:
            continue
        pattern, taken, nesting = _compiled(order, gap)
        if order is ANY and block.count(b"{") != _OBJECTS * lines:
            rows = _whole_objects(pattern, nesting, block, lines)
        else:
            rows = pattern.findall(block) if pattern.match(block) else []  # (a match: a line)
        if rows and len(rows) == lines:
            matched = [*zip(*rows, strict=True)]
            columns = [matched[index] for index in taken]
            if order is ANY and not all(map(all, columns[1:])):
                return None  # (a field missing: its values empty; only the runs, first,
                # may be empty, their inputs never)
            return order, columns
    return None


_OBJECTS = 4  # (the line, its checkpoint, the counts and the groups)


def _whole_objects(pattern: re.Pattern[bytes], nesting: Nesting, block: bytes,
                   lines: int) -> list[tuple[bytes, ...]]:
    """The lines' matches' groups, as `findall` gives them, when the last of each object
    written again holds every field: JSON keeps only the last, and a group keeps its last
    value, so each field's must lie after the object's last start (a field the last object
    lacks keeps an earlier one's value, or none: -1); else none. Only the objects whose
    names the block holds more than once a line are looked at (no value holds a name: each
    is a key; and each line that matches with every value in place has each once at
    least, which the caller checks)."""
    matches = [*pattern.finditer(block)] if pattern.match(block) else []
    for _, at, fields in (nested for nested in nesting if block.count(nested[0]) != lines):
        for match in matches:
            if min(map(match.start, fields)) < match.start(at):
                return []
    return [match.groups(b"") for match in matches]


def hashed(hashes: Sequence[bytes], groups: Sequence[Sequence[bytes]]) -> list[bytes] | None:
    """The digests' bytes, a column each (the hash's, then each group's in GROUPS' order),
    from their hex (lower case, of the right lengths): None unless every hash is the digest
    of its groups."""
    digests = [unhexlify(b"".join(column)) for column in (hashes, *groups)]
    listed = map(LISTED.__mod__, zip(*groups, strict=True))  # each line's, as hashed
    return digests if b"".join(map(digest_listed, listed)) == digests[0] else None
