"""Lab switches cut out of a block's lines, so the regular expressions read the rest.

A line whose ticks saw the lab switch methods holds a `"lab"` member besides its inputs and
checkpoint, a value of any shape JSON allows, which no regular expression reads. Cut out
(with one comma beside it), the line is a checkpoint's line like any other, and its block is
read whole by canonical.py: a replay with a switch every few lines reads about as fast as
one without. Each value cut out is parsed by the JSON parser with the checks the
line-by-line reader makes before it parses (replay_checks.decode: the line not overfull, no
fraction or constant) and is given back, by its line's index in the block, for the
caller to check as it checks a line's switches.

A member is cut out only where doing so cannot change what the line means: its name
written plainly, once in the line, at the line's top level, between a brace or a comma and
a comma or a brace. With such a member cut out, the line is valid JSON exactly when it was
before (whatever lies around it is left, and the value is parsed whole), so the regular
expressions refuse the rest of any line JSON refuses. Any other line gives None: its block
is read by the JSON block reader or a line at a time (replay_reading.py), as before.
"""

from __future__ import annotations

import json
import re
from typing import Any

from invaders.game.replay_checks import no_constant, no_fraction, overfull
from invaders.game.replay_format import ReplayError

_NAME = b'"lab"'
_COLON = re.compile(rb"[ \t\r]*:[ \t\r]*")
_GAP = b" \t\r"
# (A number too long for a field is refused by the checks of the switches after, each of
# whose numbers is bounded: a tick, or a choice's value.)
_PARSER = json.JSONDecoder(parse_float=no_fraction, parse_constant=no_constant)


def cut_switches(block: bytes) -> tuple[bytes, list[tuple[int, Any]]] | None:
    """The block (whole lines, each ending in a newline) with every line's lab switches
    cut out, and each cut line's switches as the JSON parser gives them, by the line's
    index in the block; None if some line's cannot be cut out (see above)."""
    kept, switches = [], []
    start = index = 0  # (the block's text not yet kept, and the index of the line there)
    while (at := block.find(_NAME, start)) >= 0:
        line = block.rfind(b"\n", 0, at) + 1
        end = block.find(b"\n", at) + 1
        cut = _member(block[line:end], at - line)
        if cut is None:
            return None
        cut_from, cut_to, value = cut
        index += block.count(b"\n", start, line)
        kept.append(block[start:line + cut_from])
        switches.append((index, value))
        start = line + cut_to
    kept.append(block[start:])
    return b"".join(kept), switches


def _member(line: bytes, at: int) -> tuple[int, int, Any] | None:
    """Where to cut the line's lab member, whose name starts at `at` (with a comma beside
    it), and its value parsed; None if it may not be cut out."""
    before, after = line[:at], line[at + len(_NAME):]
    if (_NAME in after or before.count(b"{") != 1 + before.count(b"}")
            or before.count(b"[") != before.count(b"]") or not line.isascii()):
        return None
    colon = _COLON.match(after)
    opened = before.rstrip(_GAP)[-1:]  # what the member follows: `{` or `,`
    if colon is None or opened not in (b"{", b","):
        return None
    text = line.decode("ascii")
    if overfull(text) is not None:
        return None
    try:
        value, end = _PARSER.raw_decode(text, at + len(_NAME) + colon.end())
    except (ValueError, ReplayError, RecursionError):
        return None
    rest = line[end:].lstrip(_GAP)
    closed = rest[:1]  # what follows it: `,` or `}`
    if closed not in (b",", b"}"):
        return None
    if opened == b",":  # (the comma before it goes with it)
        return len(before.rstrip(_GAP)) - 1, end, value
    if closed == b",":  # (the first member: the comma after it goes with it)
        return at, len(line) - len(rest) + 1, value
    return None  # (the only member: the line has no inputs or checkpoint)
