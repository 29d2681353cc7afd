"""Error types of :mod:`it2track.io`."""

from __future__ import annotations

import os

__all__ = ["FisFormatError", "UnsupportedFeatureError"]


class FisFormatError(ValueError):
    """A fuzzy-system file is malformed, or uses something it2track cannot represent.

    Parameters
    ----------
    path : str or os.PathLike
        The file (or a label such as ``"<string>"`` for text not read from a file).
    line : int or None
        1-based line number of the problem, or ``None`` where no single line is to blame.
    message : str
        What is wrong, e.g. ``"unknown MF type 'foo'"``.

    Examples
    --------
    >>> str(FisFormatError("ctrl.t2fis", 12, "unknown MF type 'foo'"))
    "ctrl.t2fis:12: unknown MF type 'foo'"
    """

    def __init__(self, path: str | os.PathLike[str], line: int | None, message: str) -> None:
        self.path = os.fspath(path)
        self.line = line
        self.message = message
        where = self.path if line is None else f"{self.path}:{line}"
        super().__init__(f"{where}: {message}")

    def __reduce__(self) -> tuple[type[FisFormatError], tuple[str, int | None, str]]:
        return (type(self), (self.path, self.line, self.message))


class UnsupportedFeatureError(ValueError):
    """A system uses something the chosen file format cannot carry (raised by writers).

    The message names the feature and, where one exists, a format that can carry it
    (``.toml`` carries everything).
    """
