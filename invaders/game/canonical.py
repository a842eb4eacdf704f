"""Checkpoint lines in the shape this program writes them, read a block at a time.

Reading a replay near the size limit (145,000 checkpoint lines) through the JSON parser, a
check of every field and a Checkpoint object a line took 16 s and 520 MB. The lines this
program writes all have one shape, so a block of them (64 KB, some 140 lines) is read by
one regular expression and its fields taken a column at a time: about 8 microseconds a
line. Only the shape is read here, and the one fact that needs no limit: each hash is the
digest of its groups. The same shape with a little white space between its tokens (as
`json.dumps` writes by default, or Windows' line ends) is read the same way. A block of
which any line has another shape (fields in another order, a lab switch, a number of more
than 18 digits, a blank line, more white space) is read again by halves, down to the
lines of another shape, which the JSON parser reads (and says what is wrong with).

A line that matches is, as JSON, an object of exactly these fields in this order, its
numbers whole and below 2**63, its digests lower-case hex, no escapes.
"""

from __future__ import annotations

import json
import re
import sys
from binascii import unhexlify
from itertools import accumulate, repeat
from typing import NamedTuple

from invaders.game.checkpoint import COUNT_NAMES
from invaders.game.statehash import GROUPS, LISTED, digest_listed

_NUMBER = rb"(?:0|[1-9][0-9]{0,17})"
_RUN = rb"\[~%s~,~%s~\]" % (_NUMBER, _NUMBER)
# The line as the program writes it, `~` where JSON allows white space.
_SHAPE = (
    rb'^~\{~"inputs"~:~\[~((?:%s(?:~,~%s)*)?)~\]~,~"checkpoint"~:~\{~"tick"~:~(%s)~,~'
    % (_RUN, _RUN, _NUMBER)
    + rb'"hash"~:~"([0-9a-f]{32})"~,~'
    + rb'"(score"~:~%s~,~"ships"~:~%s~,~"wave"~:~%s~,~"counts"~:~\{~' % ((_NUMBER,) * 3)
    + b"~,~".join(b'"%s"~:~%s' % (name.encode(), _NUMBER) for name in COUNT_NAMES)
    + rb'~\})~,~"groups"~:~\{~'
    + b"~,~".join(b'"%s"~:~"([0-9a-f]{16})"' % name.encode() for name in GROUPS)
    + rb"~\}~\}~\}~$")
_LINE = re.compile(_SHAPE.replace(b"~", b""), re.MULTILINE)
# The same with a little white space anywhere JSON allows it (as `json.dumps` writes by
# default, or a line ending in \r\n): more than this, and the JSON parser reads the line.
# Tried only when a block is not all in the program's own shape (it is about twice as slow).
# (From Python 3.11 the gap's repeat is possessive: it never gives back white space it took,
# and nothing after a gap starts with white space, so the matches are the same, found
# sooner: 1.27x over the blocks of a spaced file, the median of 9 rounds in turn.)
_GAP = rb"[ \t\r]{0,8}" + (b"+" if sys.version_info >= (3, 11) else b"")
_SPACED = re.compile(_SHAPE.replace(b"~", _GAP), re.MULTILINE)
_NOT_DIGITS = bytes(set(range(128)) - set(b"0123456789,\n"))  # what a line's values lose
# More than a line holds besides its input runs (18-digit numbers and every gap included).
REST = 1024 + 8 * _SHAPE.count(b"~")


class Block(NamedTuple):
    """The lines of a block, as columns (nothing here is checked against a limit yet)."""
    bits: list[int]  # every input run's bits, in order
    counts: list[int]  # and its count
    ends: list[int]  # the input ticks the block covers up to each line's end
    most_runs: int  # the length of the longest line's input runs, as text
    ticks: list[int]  # each checkpoint's tick
    values: list[bytes]  # and its other numbers, as Checkpoints keeps them
    digests: list[bytes]  # each of Checkpoints' DIGESTS, a column each (bytes end to end)


def read_block(block: bytes) -> Block | None:
    """The block's lines (each ending in a newline) as columns, when every line has the
    shape this program writes and every hash is the digest of its groups; else None."""
    lines = block.count(b"\n")
    rows = _LINE.findall(block) if _LINE.match(block) else []  # (a match: a whole line)
    if len(rows) != lines:
        rows = _SPACED.findall(block) if _SPACED.match(block) else []
    if not rows or len(rows) != lines:  # a line of another shape
        return None
    runs, ticks, hashes, values, *groups = zip(*rows, strict=True)  # the columns
    digests = [unhexlify(b"".join(column)) for column in (hashes, *groups)]
    listed = map(LISTED.__mod__, zip(*groups, strict=True))  # each line's, as hashed
    if b"".join(map(digest_listed, listed)) != digests[0]:
        return None
    # Every run's bits and count in turn (each already read as a JSON number), then the
    # ticks they cover up to each line's end.
    flat = json.loads(b"[%s]" % b",".join(filter(None, runs)).translate(None, b"[]"))
    runs_ended = accumulate(map(bytes.count, runs, repeat(b"[")))
    covered = [0, *accumulate(flat[1::2])]
    return Block(flat[0::2], flat[1::2], [covered[end] for end in runs_ended],
                 max(map(len, runs)), [*map(int, ticks)],
                 b"\n".join(values).translate(None, _NOT_DIGITS).split(b"\n"), digests)
