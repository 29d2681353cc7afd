"""Error types of :mod:`it2track.io`."""

from __future__ import annotations

import os

__all__ = ["FisFormatError", "FisFormatWarning", "UnsupportedFeatureError"]


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


class FisFormatWarning(UserWarning):
    """A file holds something harmless that it2track ignores or reads as its tool does.

    For example an unknown key in a ``.fis`` section, MATLAB's extra membership-function
    parameters (``trimf [a b c 0]``) or a misnumbered ``MF2`` line. The file still loads; the
    warning says what was read and how. Silence one kind with :mod:`warnings` filters
    (``warnings.simplefilter("ignore", FisFormatWarning)``) or turn it into an error with
    ``"error"``.

    Parameters
    ----------
    path : str or os.PathLike
        The file (or a label such as ``"<string>"``).
    line : int or None
        1-based line number, or ``None``.
    message : str
        What was found and how it was read.

    Examples
    --------
    >>> str(FisFormatWarning("tank.fis", 3, "unknown key 'Colour' in [System] ignored"))
    "tank.fis:3: unknown key 'Colour' in [System] ignored"
    """

    def __init__(self, path: str | os.PathLike[str], line: int | None, message: str) -> None:
        self.path = os.fspath(path)
        self.line = line
        self.message = message
        where = self.path if line is None else f"{self.path}:{line}"
        super().__init__(f"{where}: {message}")

    def __reduce__(self) -> tuple[type[FisFormatWarning], tuple[str, int | None, str]]:
        return (type(self), (self.path, self.line, self.message))
