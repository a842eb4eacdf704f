"""Every file the program writes, checked in one place before any work starts, and every
write's failure reported the same way: one line naming the file and the reason (exit 2).

A target must be absent or a regular file (nothing ever replaces a device, a pipe, a folder
or a link), its folder must exist and be writable, and its name must end in a suffix its
format allows. Writes go through `atomic.py`, which flushes and fsyncs before the rename,
so whoever prints "saved" after a write has the bytes on disk.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

from invaders.atomic import TEMPORARY_EXTRA, TEMPORARY_SUFFIX, temporary_prefix

NAME_MAX = 255  # bytes in one file name on the file systems we write to


class OutputError(Exception):
    """A file that cannot be written where asked; the message names it and why."""


def check_output(path: str, what: str, suffixes: tuple[str, ...], named: str = "") -> Path:
    """The path, if a `what` (say "replay") can be written there; else OutputError, which
    names `named` if given (what the user gave: a folder to be made, say), else `path`."""
    named = named or path
    shown = named if len(named) <= 80 else named[:77] + "..."
    if not path:
        raise OutputError(f"{what}: an empty file name")
    target = Path(path)
    if len(os.fsencode(target.name)) + TEMPORARY_EXTRA > NAME_MAX:
        raise OutputError(f"{what} {shown!r}: the file name is longer than "
                          f"{NAME_MAX - TEMPORARY_EXTRA} bytes (it is written under a "
                          f"temporary name {TEMPORARY_EXTRA} bytes longer, at most {NAME_MAX})")
    folder = target.parent if str(target.parent) else Path(".")
    try:
        folder_info = os.stat(folder)
    except FileNotFoundError:
        raise OutputError(f"cannot write {what} {shown!r}: no such folder") from None
    except OSError as err:
        raise OutputError(f"cannot write {what} {shown!r}: {err.strerror}") from None
    if not stat.S_ISDIR(folder_info.st_mode):
        raise OutputError(f"cannot write {what} {shown!r}: {str(folder)!r} is not a folder")
    if hasattr(os, "statvfs") and os.statvfs(folder).f_flag & os.ST_RDONLY:  # (not Windows)
        raise OutputError(f"cannot write {what} {shown!r}: read-only file system")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write {what} {shown!r}: permission denied")
    try:
        info = os.lstat(target)
    except FileNotFoundError:
        info = None
    except OSError as err:
        raise OutputError(f"cannot write {what} {shown!r}: {err.strerror}") from None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise OutputError(f"cannot write {what} {shown!r}: it is a folder")
    if info is not None and not stat.S_ISREG(info.st_mode):
        raise OutputError(f"cannot write {what} {shown!r}: it is not a regular file "
                          "(a device, a pipe or a link), and will not be replaced")
    if info is not None and not os.access(target, os.W_OK):  # (as a plain write would be)
        raise OutputError(f"cannot write {what} {shown!r}: permission denied (the file is "
                          "read-only to you, and will not be replaced)")
    if target.suffix.lower() not in suffixes:
        raise OutputError(f"{what} {shown!r} must end in {' or '.join(suffixes)}")
    if info is not None and _sticky_and_not_ours(folder_info, info):
        raise OutputError(f"cannot write {what} {shown!r}: permission denied (another user's "
                          "file in a folder where only its owner may replace it)")
    _try_temporary(folder, target, f"cannot write {what} {shown!r}")
    return target


def _sticky_and_not_ours(folder: os.stat_result, file: os.stat_result) -> bool:
    """Whether a rename over the file would fail: a sticky folder (as /tmp) lets only the
    file's owner, the folder's owner or root replace it (Windows has neither)."""
    if not hasattr(os, "geteuid"):
        return False
    uid = os.geteuid()
    return bool(folder.st_mode & stat.S_ISVTX) and uid not in (0, file.st_uid, folder.st_uid)


def _try_temporary(folder: Path, target: Path, problem: str) -> None:
    """Make and remove the temporary file the write will use, before any work is done:
    whatever would stop it (a name too long, no space for an inode, a quota) stops it now."""
    try:
        fd, name = tempfile.mkstemp(prefix=temporary_prefix(target), suffix=TEMPORARY_SUFFIX,
                                    dir=folder)
    except OSError as err:
        raise OutputError(f"{problem}: {err.strerror or err}") from None
    os.close(fd)
    os.unlink(name)


@contextlib.contextmanager
def writing(path: str | os.PathLike[str], what: str, kept: str = "") -> Iterator[None]:
    """Turn a failed write (no space, permission, read-only) into an OutputError; `kept`
    says what the file still holds, when that is worth knowing."""
    try:
        yield
    except OSError as err:
        raise OutputError(f"cannot write {what} {str(path)!r}: {reason(err)}{kept}") from None


def reason(err: OSError) -> str:
    """Why a write failed, in words (a full disk's as every message here says it)."""
    if err.errno == errno.ENOSPC:
        return "no space left on the device"
    return err.strerror or str(err)


REPLAY_SUFFIXES = (".json",)  # `invaders replay FOLDER` reads *.json
REPORT_SUFFIXES = (".csv", ".jsonl")
PICTURE_SUFFIXES = (".png",)
