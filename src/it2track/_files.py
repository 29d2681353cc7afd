"""Reading the user's input files safely: regular files only, bounded size, text checked.

Every file it2track reads on a user's behalf -- configurations (TOML), fuzzy-system files,
waypoint CSV files, files hashed for a sweep's identity -- goes through :func:`read_bytes` or
:func:`read_text`:

- the file is opened without blocking (``O_NONBLOCK``), then must be a regular file: a FIFO
  (which would block forever), a device such as ``/dev/zero`` (endless) or a directory is
  refused, naming the path and what it is;
- it must not be larger than ``max_bytes`` (default :data:`MAX_INPUT_BYTES`);
- :func:`read_text` refuses binary content (a NUL byte) and text that is not valid in the
  expected encoding, naming the file and the line.

Errors are :class:`InputFileError` (a ``ValueError``) with messages ``"path: problem"``;
a missing or unreadable file stays an ``OSError``. Standard library only.
"""

from __future__ import annotations

import os
import stat

from .atomicfile import _kind

__all__ = [
    "MAX_INPUT_BYTES",
    "InputFileError",
    "decode_text",
    "read_bytes",
    "read_text",
    "refuse_binary",
]

#: Largest input file read (64 MiB): far above any configuration, fuzzy system or waypoint
#: list, far below what would exhaust memory.
MAX_INPUT_BYTES = 64 << 20


class InputFileError(ValueError):
    """An input file is not a regular file, too big, binary or not decodable text."""

    def __init__(self, path: str | os.PathLike[str], message: str, line: int | None = None):
        self.path = os.fspath(path)
        self.line = line
        self.problem = message
        where = self.path if line is None else f"{self.path}:{line}"
        super().__init__(f"{where}: {message}")


def read_bytes(
    path: str | os.PathLike[str], *, what: str = "file", max_bytes: int = MAX_INPUT_BYTES
) -> bytes:
    """The bytes of the regular file ``path`` (at most ``max_bytes``).

    Parameters
    ----------
    path : str or os.PathLike
    what : str
        What the file is for, used in messages (``"configuration"``, ``"fuzzy-system file"``).
    max_bytes : int
        Size limit.

    Raises
    ------
    InputFileError
        If the path is empty, not a regular file, or larger than ``max_bytes``.
    OSError
        If it does not exist or cannot be opened.
    """
    name = os.fspath(path)
    if not name:
        raise InputFileError("''", f"empty path given for the {what}")
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    fd = os.open(name, flags)
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InputFileError(
                name, f"is {_kind(st.st_mode)}, not a regular file; give a regular {what}"
            )
        if st.st_size > max_bytes:
            raise InputFileError(
                name, f"{what} of {st.st_size} bytes is larger than the {max_bytes} allowed"
            )
        chunks: list[bytes] = []
        size = 0
        while True:
            block = os.read(fd, min(1 << 20, max_bytes + 1 - size))
            if not block:
                break
            chunks.append(block)
            size += len(block)
            if size > max_bytes:  # grew while being read
                raise InputFileError(name, f"{what} is larger than the {max_bytes} bytes allowed")
        return b"".join(chunks)
    finally:
        os.close(fd)


def refuse_binary(data: bytes, path: str | os.PathLike[str], *, what: str = "file") -> None:
    """Raise :class:`InputFileError` if ``data`` holds a NUL byte (no text format has one)."""
    nul = data.find(b"\x00")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        raise InputFileError(path, f"binary data (a NUL byte), not a text {what}", line=line)


def decode_text(data: bytes, path: str | os.PathLike[str], *, what: str = "file",
                encoding: str = "utf-8-sig") -> str:
    """``data`` decoded, refusing binary content and undecodable bytes (naming the line)."""
    refuse_binary(data, path, what=what)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise InputFileError(
            path,
            f"not valid {exc.encoding.upper().replace('-SIG', '')} text (byte "
            f"0x{data[exc.start]:02x}); a text {what} is expected",
            line=line,
        ) from None


def read_text(
    path: str | os.PathLike[str],
    *,
    what: str = "file",
    max_bytes: int = MAX_INPUT_BYTES,
    encoding: str = "utf-8-sig",
) -> str:
    """The text of the regular file ``path``: :func:`read_bytes` then :func:`decode_text`."""
    return decode_text(read_bytes(path, what=what, max_bytes=max_bytes), path, what=what,
                       encoding=encoding)
