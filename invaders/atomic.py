"""Write files so a reader never sees a torn one: a temporary file beside, then rename; and
grow one by whole lines only, held by its writer (`GrowingFile`)."""

from __future__ import annotations

import contextlib
import itertools
import os
import tempfile
import time
import weakref
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
    _permissions(fd, target)
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


def _permissions(fd: int, replacing: Path | None) -> None:
    """Give the file being written what a plain open() would: the permissions of the file
    it replaces, kept (a private replay stays private), and its owner where we may (root:
    `sudo` leaves a user's file theirs), or for a new one 0666 less the umask (mkstemp
    makes files private, 0600). Windows before Python 3.13 has no os.fchmod."""
    if not hasattr(os, "fchmod"):
        return
    try:
        old = os.stat(replacing) if replacing else None
    except OSError:  # (nothing there yet)
        old = None
    if old is None:
        os.fchmod(fd, 0o666 & ~_umask())
        return
    if hasattr(os, "fchown") and (old.st_uid, old.st_gid) != (os.geteuid(), os.getegid()):
        with contextlib.suppress(PermissionError):  # (only root gives a file away)
            os.fchown(fd, old.st_uid, old.st_gid)
    os.fchmod(fd, old.st_mode & 0o777)  # (its read, write and run bits)


def _umask() -> int:
    """The process's umask, read where the system says it (Linux: /proc/self/status);
    elsewhere by setting it and setting it back, which for that instant gives a file
    another thread makes every permission."""
    with (contextlib.suppress(OSError, ValueError),
          open("/proc/self/status", encoding="ascii", errors="replace") as status):
        for line in status:
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    umask = os.umask(0)
    os.umask(umask)
    return umask


def write_atomic(path: str | os.PathLike[str], text: str) -> tuple[int, int]:
    """Replace `path` with `text` atomically; the file written's identity (device, inode)."""
    with atomic_writer(path) as handle:
        handle.write(text)
        written = os.fstat(handle.fileno())
    return written.st_dev, written.st_ino


def write_new(path: str | os.PathLike[str], text: str) -> Path:
    """Write `text` atomically as `path`, or, where a file already has that name, as the
    first free one of `stem-2.suffix`, `stem-3.suffix`...: never over another file, even
    one a writer in another process names at the same moment. The path written."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=temporary_prefix(target), suffix=TEMPORARY_SUFFIX,
                               dir=target.parent if str(target.parent) else Path("."))
    _permissions(fd, None)  # (never over another file)
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
    _permissions(fd, target)
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


class GrowingFile:
    """A file written whole under its name (atomically), then grown by appends through a
    descriptor kept open, so that no other program's file at that name takes its lines
    and none of its own is lost: where an append finds the name gone or another file under
    it (a second recording of the same name, started meanwhile, or the file removed), it
    first writes this file whole under the first free name beside (`write_new`) and goes
    on there (`path` says where)."""

    def __init__(self, path: str | os.PathLike[str], text: str) -> None:
        self.path = Path(path)
        self._held = [-1]  # the descriptor (in a list: the finalizer closes the current one)
        weakref.finalize(self, _close_held, self._held)
        self._hold(write_atomic(self.path, text), text)

    def append(self, text: str) -> None:
        """Append `text` whole, or leave the file as it was (`append_whole`)."""
        if self._identity(self.path) != self._identity(self._held[0]):
            self._hold(None, _read_all(self._held[0]))
        append_whole(self._held[0], text)

    def _hold(self, written: tuple[int, int] | None, text: str) -> None:
        """Hold the file at `path` if it is the one `written` (its identity); else write
        `text` under the first free name and hold that."""
        if written is None or self._identity(self.path) != written:
            self.path = write_new(self.path, text)
        _close_held(self._held)
        self._held[0] = os.open(self.path, os.O_RDWR | os.O_APPEND | getattr(os, "O_BINARY", 0))

    @staticmethod
    def _identity(file: Path | int) -> tuple[int, int] | None:
        """A file's device and inode, by name or descriptor (None for a name gone)."""
        try:
            found = os.stat(file) if isinstance(file, Path) else os.fstat(file)
        except FileNotFoundError:
            return None
        return found.st_dev, found.st_ino


def _close_held(held: list[int]) -> None:
    if held[0] >= 0:
        os.close(held[0])
        held[0] = -1


def _read_all(fd: int) -> str:
    """The whole file an open descriptor holds (appends go to its end whatever the offset)."""
    os.lseek(fd, 0, os.SEEK_SET)
    chunks = []
    while chunk := os.read(fd, 1 << 20):
        chunks.append(chunk)
    return b"".join(chunks).decode("utf-8")


def append_whole(fd: int, text: str) -> None:
    """Append `text` (UTF-8, as it is: no newline made another) to the file open as `fd`
    (for appending) and fsync it, or leave the file as it was: a write cut short (the disk
    full midway) is cut off again, so that a later append follows the file's last whole
    line, where it would follow a torn one and the file would no longer read. Unbuffered,
    so nothing is left to be flushed after the cut."""
    size = os.fstat(fd).st_size
    try:
        left = memoryview(text.encode("utf-8"))
        while left:
            left = left[os.write(fd, left):]
        os.fsync(fd)
    except OSError:
        os.ftruncate(fd, size)
        raise


STALE_AFTER = 60  # s since a temporary file was last written: past it, no writer has it


def clean_stale(path: str | os.PathLike[str]) -> None:
    """Remove temporary files an interrupted atomic write of `path` left beside it: those
    untouched for STALE_AFTER seconds. A newer one may be another writer's, mid-write (a
    second recording of the same name, saving): removing it failed that save."""
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    for stale in folder.glob(glob_escape(temporary_prefix(target)) + "*" + TEMPORARY_SUFFIX):
        with contextlib.suppress(OSError):
            if time.time() - stale.stat().st_mtime > STALE_AFTER:
                stale.unlink()


def glob_escape(name: str) -> str:
    """A file name with glob's special characters taken literally."""
    return "".join(f"[{ch}]" if ch in "*?[" else ch for ch in name)
