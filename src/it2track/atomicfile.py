"""Atomic file writes: a temporary file in the target's directory, fsync, then ``os.replace``.

The one place the package writes files from: a reader (or a resumed run) sees either the old
file or the complete new one, never a torn write, and a failure leaves no temporary behind.

Safety rules, for every write:

- the temporary file is created with ``O_CREAT | O_EXCL | O_NOFOLLOW`` under an unpredictable
  name, so a file or a symbolic link planted under that name is never opened, followed or
  overwritten (the open fails instead);
- the temporary name is recognisable as ours -- ``.<target>.it2track-<pid>-<random>.tmp`` --
  so that :func:`remove_stale_temporaries` can clean up after a killed writer without ever
  touching a file this package did not create (a user's ``.notes.tmp`` stays);
- the target is replaced only if it is absent or a regular file: a directory, a device
  (``/dev/full``), a FIFO, a socket or a symbolic link is never replaced
  (:class:`NotRegularFileError`), checked before anything is written and again just before the
  rename;
- data are flushed and ``fsync``-ed before the rename, and the directory is ``fsync``-ed after
  it, so a crash leaves the old content or the new one.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import secrets
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import IO, Any

__all__ = [
    "NotRegularFileError",
    "atomic_open",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_can_create_in",
    "check_replaceable",
    "remove_stale_temporaries",
    "temporary_name",
]

#: Temporary names: ``.<target name>.it2track-<pid>-<12 hex digits>.tmp``.
_TEMP_RE = re.compile(r"^\.(?P<target>.+)\.it2track-(?P<pid>[0-9]+)-[0-9a-f]{12}\.tmp$")
_O_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_O_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


class NotRegularFileError(FileExistsError):
    """The target of a write exists and is not a regular file (nothing was written).

    A :class:`FileExistsError` (an ``OSError`` with ``errno.EEXIST``) whose ``strerror`` says
    what the path is, e.g. ``"exists and is a character device, not a regular file; refusing
    to replace it"``; ``filename`` is the path.
    """


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def check_replaceable(path: str | os.PathLike[str]) -> None:
    """Raise :class:`NotRegularFileError` unless ``path`` is absent or a regular file.

    A symbolic link is refused even if it points to a regular file: replacing it would
    destroy the link, writing through it would follow a link someone else may have planted.

    Raises
    ------
    NotRegularFileError
        Naming the path and what it is.
    ValueError
        If ``path`` is empty.
    """
    name = os.fspath(path)
    if not name:
        raise ValueError("the output path is empty; give a file name")
    try:
        st = os.lstat(name)
    except FileNotFoundError:
        return
    if not stat.S_ISREG(st.st_mode):
        what = _kind(st.st_mode)
        raise NotRegularFileError(
            errno.EEXIST,
            f"exists and is {what}, not a regular file; refusing to replace it",
            name,
        )


def temporary_name(target: str | os.PathLike[str]) -> Path:
    """A fresh temporary sibling of ``target`` in this package's recognisable form."""
    t = Path(target)
    return t.with_name(f".{t.name}.it2track-{os.getpid()}-{secrets.token_hex(6)}.tmp")


def check_can_create_in(directory: str | os.PathLike[str]) -> None:
    """Raise ``OSError`` unless a file can be created in ``directory`` right now.

    Creates one of this module's temporaries there (``O_EXCL | O_NOFOLLOW``) and removes it: a
    read-only filesystem, a folder without write permission, one where even root may not
    create files (``/sys``), a missing folder are all found before any work, with the
    folder as the error's ``filename`` (never the temporary's name).
    """
    tmp = temporary_name(Path(directory) / "probe")
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | _O_NOFOLLOW | _O_CLOEXEC
    try:
        fd = os.open(tmp, flags, 0o600)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror, os.fspath(directory)) from None
    os.close(fd)
    os.unlink(tmp)


@contextlib.contextmanager
def atomic_open(
    path: str | os.PathLike[str], mode: str = "w", **kwargs: Any
) -> Iterator[IO[Any]]:
    """Open a temporary sibling of ``path``; on success it replaces ``path`` atomically.

    On any exception inside the ``with`` block the temporary file is removed and ``path`` is
    left as it was (absent or with its old content). The file is created with the usual
    permissions (``0o666`` less the umask), flushed and fsync'ed before the rename; the
    directory is fsync'ed after it.

    Parameters
    ----------
    path : str or os.PathLike
        Destination: absent or a regular file (anything else raises
        :class:`NotRegularFileError` before a byte is written).
    mode : {"w", "wb"}
        Text or binary.
    **kwargs
        Passed to :func:`open` (e.g. ``encoding``, ``newline``).

    Raises
    ------
    NotRegularFileError
        If ``path`` exists and is not a regular file (a directory, device, FIFO, socket or
        symbolic link).
    ValueError
        For another ``mode`` or an empty ``path``.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"mode={mode!r} must be 'w' or 'wb'")
    check_replaceable(path)
    target = Path(path)
    tmp = temporary_name(target)
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | _O_NOFOLLOW | _O_CLOEXEC
    fd = os.open(tmp, flags, 0o666)
    try:
        with open(fd, mode, **kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        check_replaceable(target)  # again: something may have appeared meanwhile
        os.replace(tmp, target)
        _fsync_dir(target.parent)  # make the rename itself durable
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - platforms without directory descriptors
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) to ``path`` atomically; returns the path."""
    with atomic_open(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return Path(path)


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns the path."""
    with atomic_open(path, "wb") as fh:
        fh.write(data)
    return Path(path)


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    except OSError:  # pragma: no cover - e.g. pid out of range
        return False
    return True


def remove_stale_temporaries(
    directory: str | os.PathLike[str], targets: Iterable[str] | None = None
) -> list[Path]:
    """Remove temporaries that a killed :func:`atomic_open` left in ``directory``.

    Only regular files named ``.<target>.it2track-<pid>-<12 hex>.tmp`` whose writer process
    ``pid`` no longer runs are removed -- never a file of another name (a user's ``.x.tmp``),
    never a symbolic link, never the temporary of a live writer. ``targets``, when given,
    restricts the removal further to temporaries of those target names (the files the caller
    writes there).

    Returns
    -------
    list of Path
        The files removed.
    """
    d = Path(directory)
    allowed = None if targets is None else set(targets)
    removed: list[Path] = []
    try:
        entries = list(os.scandir(d))
    except FileNotFoundError:
        return removed
    for entry in entries:
        m = _TEMP_RE.match(entry.name)
        if m is None or (allowed is not None and m["target"] not in allowed):
            continue
        if not entry.is_file(follow_symlinks=False):
            continue
        if _pid_alive(int(m["pid"])):
            continue
        with contextlib.suppress(FileNotFoundError):
            os.unlink(entry.path)
            removed.append(Path(entry.path))
    return removed
