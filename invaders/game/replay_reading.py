"""Reading a replay file: a block of lines at a time, each line bounded before it is read.

Only a regular file up to the size limit is read. The header (or a whole version-1 file) is
read first, bounded; the rest a block of whole lines at a time, so a file's text is never
held whole and a line too long is never kept. Each block is read whole by a regular
expression when its lines are checkpoints' lines in any order, spacing or escaping of
letters and digits (canonical.py), once any lab switches are cut out of them
(switches_cut.py), else by the JSON parser and checks a column at a time (json_block.py);
a block neither takes (a value out of place) again by halves, down to the lines that are
read one by one through the JSON parser and every field's check (replay_checks.py), which
name any problem: the same result by every way. The replay is kept packed (checkpoint.py,
runs.py): a replay at the size limit takes memory in proportion to what it means, not to
the file's size.
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, BinaryIO

from invaders.game import canonical, json_block
from invaders.game.actions import ALL_ACTIONS
from invaders.game.checkpoint import Checkpoints
from invaders.game.replay_checks import (
    add_runs,
    add_switches,
    checkpoint_from,
    decode,
    finished,
    header_fields,
    need,
    parse,
    players_of,
)
from invaders.game.replay_format import (
    LINE_FIELDS,
    MAX_FILE_BYTES,
    MAX_HEADER_BYTES,
    MAX_LINE_BYTES,
    MAX_RUNS,
    MAX_TICKS,
    MAX_V1_BYTES,
    Replay,
    ReplayError,
    Switch,
)
from invaders.game.runs import Runs
from invaders.game.switches_cut import cut_switches


def parse_lines(lines: list[str], numbers: list[int] | None = None) -> Replay:
    """A version-2 Replay from its lines (the header first), or ReplayError; `numbers`: each
    line's number in its file (blank lines left out between them), 1, 2, 3... by default."""
    numbered = list(zip(numbers or range(1, len(lines) + 1), lines, strict=True))
    return _parse_blocks(numbered[0][1], ((number, line.rstrip("\n").encode() + b"\n")
                                          for number, line in numbered[1:]))


def _parse_blocks(header_line: str, blocks: Iterable[tuple[int, bytes]]) -> Replay:
    """A version-2 Replay from its header line and the other lines in blocks of whole lines,
    each with its first line's number (a long replay is never held as text)."""
    need(len(header_line) <= MAX_HEADER_BYTES,
         f"the header line is {len(header_line):,} characters: at most {MAX_HEADER_BYTES:,}")
    header = decode(header_line, "the header line")
    _, seed, config, program = header_fields(header)
    players = players_of(header)
    runs, checkpoints, orders = Runs(), Checkpoints(), canonical.Orders()
    switches: list[Switch] = []
    total = 0
    for first, block in blocks:
        covered = _block(block, total, runs, checkpoints, switches, orders)
        total = covered if covered is not None else _by_halves(
            list(_block_lines(first, block)), total, runs, checkpoints, switches, orders)
    return finished(seed, config, runs, checkpoints, checkpoints.ticks(), program, total,
                   switches, players)


def _block_lines(number: int, block: bytes) -> Iterator[tuple[int, bytes]]:
    """A block's lines that hold something, each with its newline and its number (lines
    end at a newline alone: a carriage return is white space inside a line, as in JSON)."""
    for offset, line in enumerate(block.split(b"\n")[:-1]):
        if line.strip():
            yield number + offset, line + b"\n"


def _by_halves(lines: list[tuple[int, bytes]], total: int, runs: Runs,
               checkpoints: Checkpoints, switches: list[Switch], orders: canonical.Orders
               ) -> int:
    """Lines (numbered) that could not be taken as one block (one at least is bad): each
    half again as a block, down to the single lines neither block reader takes, read one
    by one; lines are taken in order, so the first bad one is the one named. The ticks
    covered so far."""
    if len(lines) == 1:
        number, line = lines[0]
        return _any_line(_text(line).rstrip("\n"), f"line {number}", total, runs,
                         checkpoints, switches)
    half = len(lines) // 2
    for part in (lines[:half], lines[half:]) if lines else ():
        covered = _block(b"".join(line for _, line in part), total, runs, checkpoints,
                         switches, orders)
        total = covered if covered is not None else _by_halves(part, total, runs,
                                                                checkpoints, switches, orders)
    return total


_UNKNOWN_BITS = ~ALL_ACTIONS


def _block(block: bytes, total: int, runs: Runs, checkpoints: Checkpoints,
           switches: list[Switch], orders: canonical.Orders) -> int | None:
    """Take a block of whole lines when either block reader takes it and every value in it
    is good: the ticks covered so far. None (having taken nothing) for any other block,
    whose lines are read again by halves."""
    read = _read_block(block, orders)
    if read is None:
        return None
    ends = [total + end for end in read.ends]
    good = (read.longest <= MAX_LINE_BYTES
            and len(runs) + len(read.bits) <= MAX_RUNS
            and ends == read.ticks and ends[-1] <= MAX_TICKS
            and not (read.counts <= 0).any()
            and not (read.bits & _UNKNOWN_BITS).any()
            and _switches_taken(read.switches, [total, *ends], switches))
    if not good:
        return None
    runs.extend(read.bits, read.counts)
    checkpoints.extend_columns(read.ticks, read.values, read.digests)
    return ends[-1]


def _read_block(block: bytes, orders: canonical.Orders) -> canonical.Block | None:
    """The block's lines as columns: by the regular expressions, with any lab switches cut
    out of their lines first, else by the JSON block reader; None if neither takes it. (A
    single line the regular expressions do not take is read on its own: for one line the
    JSON block reader's columns cost more than a line's field checks.)"""
    block = _without_blank_lines(block)
    if _LAB not in block:
        read = canonical.read_block(block, orders)
    elif (cut := cut_switches(block)) is not None:
        read = canonical.read_block(cut[0], orders)
        if read is not None:  # (its longest line: at most the block, as the others')
            read = read._replace(longest=len(block), switches=cut[1])
    else:
        read = None
    if read is None and block.count(b"\n") > 1:
        read = json_block.read_block(block)
    return read


_LAB = b'"lab"'


def _without_blank_lines(block: bytes) -> bytes:
    """The block without the lines that hold nothing, which every reader skips (a line of
    white space, as `bytes.strip` has it, alone): so a file with a blank line after each
    is read by the regular expressions as the same without them."""
    if _BLANK_LINES.search(block):
        block = _BLANK_LINES.sub(b"\n", block)
    first = _FIRST_BLANK_LINES.match(block)
    assert first is not None  # (it matches no line, too)
    return block[first.end():]  # (the same block, if none)


_BLANK_LINES = re.compile(rb"\n(?:[ \t\r\x0b\x0c]*\n)+")  # (a newline first: found fast)
_FIRST_BLANK_LINES = re.compile(rb"(?:[ \t\r\x0b\x0c]*\n)*")


def _switches_taken(listed: list[tuple[int, Any]], bounds: list[int],
                    switches: list[Switch]) -> bool:
    """Add a block's lab switches (each line's, by its index in the block) to `switches`,
    checked as a line read on its own has them; or add none and say so (line `i` spans the
    ticks from bounds[i] to bounds[i + 1])."""
    kept = len(switches)
    try:
        for line, choices in listed:
            add_switches(choices, "", bounds[line], bounds[line + 1], switches)
    except ReplayError:  # (its message made again when the line is read on its own)
        del switches[kept:]
        return False
    return True


_LINE_KEYS = frozenset(LINE_FIELDS)


def _any_line(line: str, where: str, total: int, runs: Runs, checkpoints: Checkpoints,
              switches: list[Switch]) -> int:
    """Take a checkpoint's line of any shape JSON allows, checking every field: the ticks
    covered so far, or ReplayError naming the first problem."""
    # (Each message is made only when it is needed: a long replay has 145,000 lines.)
    if len(line) > MAX_LINE_BYTES:
        raise ReplayError(f"{where} is {len(line):,} characters: a checkpoint's line is at "
                          f"most {MAX_LINE_BYTES:,}")
    data = decode(line, where)
    if not (isinstance(data, dict) and data.keys() - {"lab"} == _LINE_KEYS):
        raise ReplayError(f"{where} must hold exactly inputs and checkpoint (and lab switches)")
    covered = add_runs(data["inputs"], where, total, runs)
    if "lab" in data:
        add_switches(data["lab"], where, total, covered, switches)
    checkpoint = checkpoint_from(data["checkpoint"], f"{where} checkpoint", MAX_TICKS)
    if checkpoint.tick != covered:
        raise ReplayError(f"{where}: its checkpoint is at tick {checkpoint.tick}, its inputs "
                          f"end at {covered}")
    checkpoints.append(checkpoint)
    return covered


def _first_line_limit(size: int) -> int:
    """The first line is a header (16 KB at most) or a whole version-1 file (8 MB)."""
    return max(MAX_HEADER_BYTES, min(size, MAX_V1_BYTES))


def load(path: str | Path) -> Replay:
    """Read and validate a replay file of either version, a line at a time; ReplayError
    names the problem."""
    handle, size = _open(path)
    with handle:
        try:
            return _read(handle, size)
        except OSError as err:
            raise ReplayError(f"cannot read: {err.strerror}") from None


def _open(path: str | Path) -> tuple[BinaryIO, int]:
    """A replay file opened for reading, and its size: only a regular file, only up to the
    size limit."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise ReplayError("no such file") from None
    except OSError as err:
        raise ReplayError(f"cannot read: {err.strerror}") from None
    if stat.S_ISDIR(info.st_mode):
        raise ReplayError("is a folder, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise ReplayError("not a regular file (a pipe, a device, or a link to one)")
    if info.st_size > MAX_FILE_BYTES:
        raise ReplayError(f"{info.st_size} bytes: a replay may be at most {MAX_FILE_BYTES}")
    try:
        return open(path, "rb"), info.st_size  # (closed by load)
    except OSError as err:
        raise ReplayError(f"cannot read: {err.strerror}") from None


def _read(handle: BinaryIO, size: int) -> Replay:
    head = handle.read(4096).decode("utf-8", "replace")
    handle.seek(0)
    need(size <= MAX_V1_BYTES or not _V1_MARK.search(head),
         f"a version-1 replay may be at most {MAX_V1_BYTES:,} bytes (longer games are "
         "written in version 2)")
    number, text = _first_line(handle, size)
    try:
        data = decode(text, f"line {number}")
    except ReplayError:
        whole = _one_object(handle, size)  # a version-1 file spread over lines, as JSON allows
        if whole is None:
            raise
        return parse(whole)
    if _is_version_1(data):
        need(not any(line.strip() for _, block in _blocks(handle, number + 1)
                      for line in block.split(b"\n")),
             "a version-1 replay is one JSON object")
        return parse(data)
    return _parse_blocks(text, _blocks(handle, number + 1))


def _first_line(handle: BinaryIO, size: int) -> tuple[int, str]:
    """The first line that holds something, and its number, bounded before it is decoded
    (as a header or a whole version-1 file). A last line with no newline (a write that was
    interrupted) is left out, unless it is the file's first. A byte order mark before the
    file's first line is skipped, as JSON's standard lets a reader do (editors on Windows
    write one)."""
    limit, number = _first_line_limit(size), 0
    while raw := handle.readline(limit + 1):
        number += 1
        if number == 1:
            raw = raw.removeprefix(_BOM)
        whole = raw.endswith(b"\n")
        if not whole and len(raw) > limit:
            rest, whole = _skip_line(handle)
            need(not whole and number > 1, _too_long(number, len(raw) + rest, limit))
        if not whole and number > 1:
            need(not raw.strip(), "the file holds no complete line")
            break
        text = _text(raw[:-1] if whole else raw)
        if text.strip():
            return number, text
    raise ReplayError("the file is empty")


_BOM = "\ufeff".encode()

BLOCK_BYTES = 2**16  # some 140 of the program's lines


def _blocks(handle: BinaryIO, number: int) -> Iterator[tuple[int, bytes]]:
    """The rest of the file, from line `number`, in blocks of whole lines (64 KB or so),
    each with its first line's number. A last line with no newline (a
    write that was interrupted) is left out; a line longer than a checkpoint's may be is
    never kept whole."""
    pending = b""
    while chunk := handle.read(BLOCK_BYTES):
        need(handle.tell() <= MAX_FILE_BYTES, f"a replay may be at most {MAX_FILE_BYTES} bytes")
        pending += chunk
        end = pending.rfind(b"\n") + 1
        if end:
            yield number, pending[:end]
            number += pending.count(b"\n", 0, end)
            pending = pending[end:]
        if len(pending) > MAX_LINE_BYTES:
            rest, ended = _skip_line(handle)
            need(not ended, _too_long(number, len(pending) + rest, MAX_LINE_BYTES))
            return  # (the file ended inside it: a line cut short)


def _skip_line(handle: BinaryIO) -> tuple[int, bool]:
    """Read past the rest of a line too long to keep: its length, and whether a newline
    ended it (not: the file ended)."""
    length = 0
    while chunk := handle.readline(2**16):
        length += len(chunk)
        if chunk.endswith(b"\n"):
            return length - 1, True
    return length, False


def _too_long(number: int, length: int, limit: int) -> str:
    what = (f"a checkpoint's line is at most {MAX_LINE_BYTES:,}" if limit == MAX_LINE_BYTES
            else f"a header is at most {MAX_HEADER_BYTES:,} (and a version-1 file "
                 f"{MAX_V1_BYTES:,})")
    return f"line {number} is {length:,} characters: {what}"


def _text(raw: bytes) -> str:
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ReplayError("not a text file") from None


_V1_MARK = re.compile(r'"version"\s*:\s*1\b')


def _is_version_1(data: Any) -> bool:
    return isinstance(data, dict) and data.get("version") == 1 and type(data["version"]) is int


def _one_object(handle: BinaryIO, size: int) -> dict | None:
    """The file as one version-1 object over several lines, or None if it is not one."""
    if size > MAX_V1_BYTES:
        return None
    handle.seek(0)
    text = handle.read(MAX_V1_BYTES + 1).removeprefix(_BOM).decode("utf-8", "replace")
    if not text.lstrip().startswith("{"):
        return None
    try:
        whole = decode(text, "the file")
    except ReplayError:
        return None
    return whole if _is_version_1(whole) else None

