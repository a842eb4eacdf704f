"""Write files so a reader never sees a torn one: a temporary file beside, then rename."""

from __future__ import annotations

import contextlib
import itertools
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO

TEMPORARY_SUFFIX = ".tmp"
TEMPORARY_EXTRA = 14  # bytes a temporary name adds: a dot, a dot, 8 random, ".tmp"


def temporary_prefix(target: Path) -> str:
    """The start of the name a file is first written under, beside its final place."""
    return f".{target.name}."


@contextlib.contextmanager
def atomic_writer(path: str | os.PathLike[str], mode: str = "w") -> Iterator[IO]:
    """Yield a file to write; on success it replaces `path` in one rename, else it vanishes."""
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=temporary_prefix(target), suffix=TEMPORARY_SUFFIX,
                               dir=folder)
    _usual_permissions(fd)
    try:
        with os.fdopen(fd, mode, newline="" if "b" not in mode else None) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def _usual_permissions(fd: int) -> None:
    """mkstemp makes files private (0600); give them what a plain open() would (where
    files have such modes: Windows before Python 3.13 has no os.fchmod)."""
    if not hasattr(os, "fchmod"):
        return
    umask = os.umask(0)
    os.umask(umask)
    os.fchmod(fd, (stat.S_IRUSR | stat.S_IWUSR | stat.S_IRGRP | stat.S_IWGRP | stat.S_IROTH
                   | stat.S_IWOTH) & ~umask)


def write_atomic(path: str | os.PathLike[str], text: str) -> None:
    """Replace `path` with `text` atomically."""
    with atomic_writer(path) as handle:
        handle.write(text)


def write_new(path: str | os.PathLike[str], text: str) -> Path:
    """Write `text` atomically as `path`, or, where a file already has that name, as the
    first free one of `stem-2.suffix`, `stem-3.suffix`...: never over another file, even
    one a writer in another process names at the same moment. The path written."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=temporary_prefix(target), suffix=TEMPORARY_SUFFIX,
                               dir=target.parent if str(target.parent) else Path("."))
    _usual_permissions(fd)
    try:
        with os.fdopen(fd, "w", newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        names = (target.with_stem(f"{target.stem}-{number}") if number > 1 else target
                 for number in itertools.count(1))
        return next(name for name in names if _claim(tmp, name))
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def _claim(written: str, name: Path) -> bool:
    """Give the written file `name` too, if no file has it yet (False if one has). A hard
    link takes a name only if it is free; where the file system has none, the name is
    taken empty first, then filled by a rename over it."""
    try:
        os.link(written, name)
    except FileExistsError:
        return False
    except OSError:  # (no hard links here)
        try:
            os.close(os.open(name, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            return False
        os.replace(written, name)
    return True


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[str]:
    """Yield a temporary path with the same suffix (for writers that take a file name, such
    as pygame.image.save); on success it is renamed over `path`."""
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=folder)
    _usual_permissions(fd)
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def append_whole(path: str | os.PathLike[str], text: str) -> None:
    """Append `text` (UTF-8, as it is: no newline made another) and fsync it, or leave the
    file as it was: a write cut short (the disk full midway) is cut off again, so that a
    later append follows the file's last whole line, where it would follow a torn one and
    the file would no longer read. Unbuffered, so nothing is left to be flushed after the
    cut."""
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | getattr(os, "O_BINARY", 0))
    try:
        size = os.fstat(fd).st_size
        try:
            left = memoryview(text.encode("utf-8"))
            while left:
                left = left[os.write(fd, left):]
            os.fsync(fd)
        except OSError:
            os.ftruncate(fd, size)
            raise
    finally:
        os.close(fd)


def clean_stale(path: str | os.PathLike[str]) -> None:
    """Remove temporary files an interrupted atomic write of `path` left beside it."""
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    for stale in folder.glob(glob_escape(temporary_prefix(target)) + "*" + TEMPORARY_SUFFIX):
        with contextlib.suppress(OSError):
            stale.unlink()


def glob_escape(name: str) -> str:
    """A file name with glob's special characters taken literally."""
    return "".join(f"[{ch}]" if ch in "*?[" else ch for ch in name)
