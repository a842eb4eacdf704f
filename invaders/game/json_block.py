"""Checkpoint lines in any shape JSON allows, read a block at a time.

The regular expressions (canonical.py) read checkpoint lines in any order of fields, with
any white space, with JSON's escapes of letters and digits, fields and objects written
twice, once lab switches are cut out of their lines (switches_cut.py). What they leave:
lines with lab switches no cut takes (their name escaped or written twice, say), an earlier
object written twice that is not one of a checkpoint line's own, any other escape. A block
of such lines is parsed a line at a time by the JSON parser alone, then checked and taken a
column at a time, each step a single call over the block's lines (map, itemgetter, join, a
regular expression), as canonical.py takes its columns. Nothing is taken here that reading
the lines one by one (replay_reading.py) would refuse: a block with any line that is not a
checkpoint's line with every field in place, every number whole and every digest of the
right length gives None, and its lines are read again, down to the one that names the
problem. The caller bounds the numbers, checks the limits (as for canonical.py's blocks)
and checks the lab switches with the function that checks a line's.
"""

from __future__ import annotations

import json
import re
from itertools import accumulate, chain, repeat
from operator import itemgetter
from typing import Any

import numpy as np

from invaders.game.canonical import Block, hashed
from invaders.game.checkpoint import COUNT_NAMES, VALUES_TEXT
from invaders.game.replay_checks import no_constant, no_fraction, overfull
from invaders.game.replay_format import CHECKPOINT_FIELDS, LINE_FIELDS, MAX_DIGITS
from invaders.game.statehash import GROUPS

_HASHES = re.compile(r"(?:[0-9a-f]{32},)*[0-9a-f]{32}")  # joined by commas
_GROUP_DIGESTS = re.compile(r"(?:[0-9a-f]{16},)*[0-9a-f]{16}")


class _NotTaken(Exception):
    """A line of the block is not one this reader takes."""


def read_block(block: bytes) -> Block | None:
    """The block's lines that hold something (each ending in a newline) as columns, when
    each is a checkpoint's line with every value in place and every hash the digest of its
    groups; else None. Lab switches are given as the JSON parser gives them, for the
    caller to check as it checks a line's."""
    try:  # (the lines that hold something, as the line-by-line reader has them)
        texts = [line.decode() for line in block.split(b"\n") if line.strip()]
        lines = _parsed(block, texts)
        switches = [(index, line.pop("lab")) for index, line in enumerate(lines)
                    if type(line) is dict and "lab" in line]
        inputs, checkpoints = _fields(lines, LINE_FIELDS)
        return Block(*_runs(inputs), max(map(len, texts)), *_checkpoints(checkpoints),
                     switches)
    except (_NotTaken, UnicodeDecodeError, ValueError, RecursionError):
        return None  # (a ValueError: the JSON parser's)


def _parsed(block: bytes, texts: list[str]) -> list[Any]:
    """The lines as the line-by-line reader parses them (replay_checks.decode: a line not
    overfull, no fraction, constant or number of over MAX_DIGITS digits anywhere, even in a
    value JSON drops for a field written again), by the JSON parser alone: it refuses the
    fractions and constants itself; a block with a longer run of digits anywhere, or with
    an overfull line, is not taken (neither can be where the lines hold no more fields
    than checkpoints' lines: every value they hold is checked below)."""
    if block.count(b":") != _FIELDS * len(texts) and (
            _TOO_LONG in block.translate(_DIGITS_AS_0) or any(map(overfull, texts))):
        raise _NotTaken
    return [*map(_PARSER.decode, texts)]


_PARSER = json.JSONDecoder(parse_float=no_fraction, parse_constant=no_constant)
_FIELDS = len(LINE_FIELDS) + len(CHECKPOINT_FIELDS) + len(COUNT_NAMES) + len(GROUPS)
_DIGITS_AS_0 = bytes.maketrans(b"123456789", b"000000000")
_TOO_LONG = b"0" * (MAX_DIGITS + 1)


def _fields(objects: list[Any], names: tuple[str, ...]) -> list[tuple[Any, ...]]:
    """The objects' values of each of `names` (two or more), a column a name, when there
    are objects and every one has exactly those fields."""
    if {*map(type, objects)} != {dict} or {*map(len, objects)} != {len(names)}:
        raise _NotTaken  # (no objects, too)
    try:
        return [*zip(*map(itemgetter(*names), objects), strict=True)]
    except KeyError:
        raise _NotTaken from None


def _whole(numbers: list[Any]) -> list[int]:
    """The numbers, when every one is whole, from 0 to 2**63 - 1 (the most a field holds)."""
    if numbers and ({*map(type, numbers)} != {int} or min(numbers) < 0
                    or max(numbers) >= 2**63):
        raise _NotTaken
    return numbers


def _runs(inputs: tuple[Any, ...]) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Every input run's bits and count in order (64-bit integers, as canonical.py gives
    them), and the ticks they cover up to each line's end, when each line's inputs are
    [bits, count] pairs of whole numbers that fit 64 bits."""
    if {*map(type, inputs)} != {list}:
        raise _NotTaken
    runs = [*chain.from_iterable(inputs)]
    if runs and ({*map(type, runs)} != {list} or {*map(len, runs)} != {2}):
        raise _NotTaken
    bits, counts = _whole([*map(itemgetter(0), runs)]), _whole([*map(itemgetter(1), runs)])
    covered = [0, *accumulate(counts)]
    try:
        columns = np.array(bits, np.int64), np.array(counts, np.int64)
    except OverflowError:
        raise _NotTaken from None
    return *columns, [covered[end] for end in accumulate(map(len, inputs))]


def _checkpoints(checkpoints: tuple[Any, ...]) -> tuple[list[int], list[bytes], list[bytes]]:
    """Each checkpoint's tick, its other numbers and its digests, as Checkpoints keeps them,
    when each has exactly its fields, its numbers whole and its digests lower-case hex."""
    ticks, hashes, score, ships, wave, counts, groups = _fields([*checkpoints], CHECKPOINT_FIELDS)
    numbers = [score, ships, wave, *_fields([*counts], COUNT_NAMES)]  # a column a field
    _whole([*chain(ticks, *numbers)])
    digests = hashed(_hex(hashes, _HASHES), [*map(_hex, _fields([*groups], GROUPS),
                                                   repeat(_GROUP_DIGESTS))])
    if digests is None:
        raise _NotTaken
    return [*ticks], [*map(VALUES_TEXT.__mod__, zip(*numbers, strict=True))], digests


def _hex(digests: tuple[Any, ...], form: re.Pattern[str]) -> list[bytes]:
    """Digests as bytes of hex, when each is a string of lower-case hex digits of the
    length `form` (joined by commas) has them."""
    try:
        joined = ",".join(digests)
    except TypeError:  # (one is no string)
        raise _NotTaken from None
    if not form.fullmatch(joined):
        raise _NotTaken
    return joined.encode().split(b",")
