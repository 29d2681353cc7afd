"""Helpers of the bad-input suite (imported by its test modules): build hostile inputs
(FIFOs, binary files, device links) and check that an error is clean -- the right type, a
message naming the culprit and its value, no traceback, nothing written."""

from __future__ import annotations

import os
from pathlib import Path

#: Bytes that are neither UTF-8 nor text.
BINARY = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe\x00\x01"
#: A Latin-1 (not UTF-8) byte in otherwise valid TOML.
LATIN1_TOML = b'# caf\xe9\n[sweep]\nseeds = 1\n'


def make_fifo(path: Path) -> Path:
    """A named pipe nobody writes to: reading it would block forever."""
    os.mkfifo(path)
    return path


def make_device_link(path: Path, device: str = "/dev/zero") -> Path:
    """A symbolic link named like an input file to an endless device."""
    path.symlink_to(device)
    return path


def make_sparse(path: Path, size: int) -> Path:
    """A file of ``size`` bytes that takes no disk space (for size caps)."""
    with open(path, "wb") as fh:
        fh.truncate(size)
    return path


def snapshot(folder: Path) -> dict[str, tuple[str, bytes | None]]:
    """Every entry under ``folder``: kind and, for regular files, the bytes."""
    out: dict[str, tuple[str, bytes | None]] = {}
    for p in sorted(folder.rglob("*")):
        rel = str(p.relative_to(folder))
        if p.is_symlink():
            out[rel] = ("link", os.readlink(p).encode())
        elif p.is_fifo():
            out[rel] = ("fifo", None)
        elif p.is_dir():
            out[rel] = ("dir", None)
        elif p.is_file():
            out[rel] = ("file", p.read_bytes())
        else:  # pragma: no cover
            out[rel] = ("other", None)
    return out


def assert_clean_error(exc: BaseException, expected: type[BaseException], *needles: str) -> None:
    """``exc`` is an ``expected`` whose message holds every needle."""
    assert isinstance(exc, expected), f"{type(exc).__name__}: {exc}"
    message = str(exc)
    for needle in needles:
        assert needle in message, f"{needle!r} not in {message!r}"


def unwritable_folder(root: Path) -> Path | None:
    """A folder in which this process cannot create files: ``root/read-only`` (mode 0555) for
    an ordinary user; for root, whom modes do not stop, a kernel folder (``/sys/kernel``)
    where nobody may create files; None if there is none (the case is skipped)."""
    folder = root / "read-only"
    if not folder.exists():
        folder.mkdir()
        folder.chmod(0o555)
    for candidate in (folder, Path("/sys/kernel")):
        probe = candidate / ".it2track-hostile-probe"
        try:
            fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL)
        except OSError:
            return candidate
        os.close(fd)
        os.unlink(probe)
    return None
