"""Reading and writing fuzzy systems: one entry point for every format, chosen by suffix.

==========  ===================================================================================
suffix      format
==========  ===================================================================================
``.toml``   it2track's own TOML (:mod:`.tomlfmt`): readable, exact for every system we build
``.t2fis``  the IT2FLS MATLAB toolbox of Taskin & Kumbasar (:mod:`.t2fis`)
``.fis``    MATLAB's Fuzzy Logic Toolbox: Sugeno and Mamdani; type-2 in our layout
            (:mod:`.matfis`)
``.fll``    fuzzylite's FuzzyLite Language (:mod:`.fll`): type-1 Mamdani and Sugeno
``.fml``    IEEE 1855 Fuzzy Markup Language (:mod:`.fml`): type-1 Mamdani and Sugeno
``.fcl``    Fuzzy Control Language, IEC 61131-7 (:mod:`.fcl`): type-1, read only
==========  ===================================================================================

>>> import it2track
>>> from it2track.io import dumps, loads
>>> fls = it2track.heading_fls(0.2)
>>> again = loads(dumps(fls, "t2fis"), "t2fis")
>>> float(again(0.5, 0.0)) == float(fls(0.5, 0.0))
True

Every float is written with ``repr`` precision, so a system read back gives bit-for-bit the
outputs of the one written, in every format that can carry it. What each format can carry is
listed in its module; a writer raises :class:`UnsupportedFeatureError` (a ``ValueError``) for
the rest, and readers raise :class:`FisFormatError` (a ``ValueError``) for anything malformed or
unsupported, naming the file, the line and the problem. Writes are atomic: the text is
rendered first, written to a temporary file beside the target and moved into place, so an error
never leaves a half-written file.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from pathlib import Path

from .._files import InputFileError, decode_text, read_bytes, refuse_binary
from ..atomicfile import atomic_write_text
from ..fuzzy import AnySystem, Input
from . import fcl, fll, fml, matfis, t2fis, tomlfmt
from ._matlab import decode
from ._writing import refuse_formulas
from .errors import FisFormatError, FisFormatWarning, UnsupportedFeatureError

__all__ = [
    "FORMATS",
    "READ_ONLY",
    "TYPE2",
    "FisFormatError",
    "FisFormatWarning",
    "UnsupportedFeatureError",
    "dumps",
    "format_of",
    "load",
    "load_terms",
    "loads",
    "loads_terms",
    "save",
]

_Loader = Callable[[str, str], AnySystem]
_Dumper = Callable[[AnySystem], str]


def _no_formulas(dumper: _Dumper, fmt: str) -> _Dumper:
    """``dumper``, refusing a system with a formula (:mod:`it2track.fuzzy.formula`) first."""
    @functools.wraps(dumper)
    def dumps(system: AnySystem) -> str:
        refuse_formulas(system, fmt)
        return dumper(system)
    return dumps


#: format name -> (file suffix, loads, dumps): the formats it2track reads and writes
FORMATS: dict[str, tuple[str, _Loader, _Dumper]] = {
    "toml": (".toml", tomlfmt.loads, _no_formulas(tomlfmt.dumps, ".toml")),
    "t2fis": (".t2fis", t2fis.loads, _no_formulas(t2fis.dumps, ".t2fis")),
    "fis": (".fis", matfis.loads, _no_formulas(matfis.dumps, ".fis")),
    "fll": (".fll", fll.loads, _no_formulas(fll.dumps, ".fll")),
    "fml": (".fml", fml.loads, _no_formulas(fml.dumps, ".fml")),
}
#: the formats that carry interval type-2 systems (the others are type-1 only)
TYPE2 = frozenset({"toml", "t2fis", "fis"})
#: format name -> (file suffix, loads): the formats it2track only reads
READ_ONLY: dict[str, tuple[str, _Loader]] = {
    "fcl": (".fcl", fcl.loads),
}


def _loader(name: str) -> _Loader:
    return READ_ONLY[name][1] if name in READ_ONLY else FORMATS[name][1]


def _dumper(name: str) -> _Dumper:
    if name in READ_ONLY:
        def refuse(system: AnySystem) -> str:
            raise UnsupportedFeatureError(
                f"it2track reads {name.upper()} but does not write it; save as .toml, .fis or "
                ".t2fis"
            )
        return refuse
    return FORMATS[name][2]


def format_of(path: str | os.PathLike[str]) -> str:
    """The format name (``"toml"``, ``"t2fis"``, ``"fis"``, ``"fll"``, ``"fml"``, ``"fcl"``)
    for a path's suffix.

    Raises
    ------
    ValueError
        For any other suffix.
    """
    suffix = Path(path).suffix.lower()
    for name, (fmt_suffix, *_) in (*FORMATS.items(), *READ_ONLY.items()):
        if suffix == fmt_suffix:
            return name
    known = ", ".join([v[0] for v in FORMATS.values()] + [v[0] for v in READ_ONLY.values()])
    raise ValueError(f"{os.fspath(path)}: unknown fuzzy-system file suffix {suffix!r} ({known})")


def _format(fmt: str) -> tuple[str, _Loader, _Dumper]:
    name = fmt.lower().lstrip(".")
    if name in READ_ONLY:
        return READ_ONLY[name][0], _loader(name), _dumper(name)
    try:
        return FORMATS[name]
    except KeyError:
        known = sorted([*FORMATS, *READ_ONLY])
        raise ValueError(f"unknown format {fmt!r}; choose one of {known}") from None


def loads(text: str, fmt: str, *, path: str = "<string>", block: str | None = None,
          dialect: str | None = None) -> AnySystem:
    """Parse ``text`` in format ``fmt`` (``"toml"``, ``"t2fis"``, ``"fis"``, ``"fll"``,
    ``"fml"`` or ``"fcl"``).

    ``path`` only labels error messages; ``block`` names the FCL ``FUNCTION_BLOCK`` to read
    (``None``: the first; other formats take no ``block``); ``dialect`` reads a ``.fis`` as
    ``"matlab"`` (``None``: the default) or ``"octave"`` evaluates it (the Octave
    fuzzy-logic-toolkit's semantics where they differ: :mod:`.matfis`; other formats take no
    ``dialect``).
    """
    _, loader, _ = _format(fmt)
    if dialect is not None:
        if loader is not matfis.loads:
            raise ValueError(f"dialect= names a reading of a .fis; format {fmt!r} has none")
        return matfis.loads(text, path, dialect=dialect)
    if block is None:
        return loader(text, path)
    if loader is not fcl.loads:
        raise ValueError(f"block= names an FCL FUNCTION_BLOCK; format {fmt!r} has none")
    return fcl.loads(text, path, block=block)


def loads_terms(text: str, fmt: str, *, path: str = "<string>", block: str | None = None
                ) -> dict[str, Input]:
    """The input variables of ``text`` in format ``fmt`` and their terms, by name in the
    file's order (each an :class:`~it2track.fuzzy.Input`; ``inputs["x"].sets`` are the terms).

    FCL is read for its inputs alone (:func:`.fcl.loads_terms`): a function block with no
    outputs, an output without terms, or no rules -- jFuzzyLogic's membership-function files
    -- gives its terms. The other formats describe whole systems, so their file is read as
    :func:`loads` reads it and its system's inputs are returned (a file that does not load
    is refused so). ``path`` and ``block`` as for :func:`loads`.
    """
    name = _format(fmt)[0].lstrip(".")
    if name == "fcl":
        return fcl.loads_terms(text, path, block=block)
    system = loads(text, name, path=path, block=block)
    return {var.name: var for var in system.inputs}


def dumps(system: AnySystem, fmt: str) -> str:
    """Text of ``system`` in format ``fmt`` (``"toml"``, ``"t2fis"``, ``"fis"``, ``"fll"`` or
    ``"fml"``).

    Raises
    ------
    UnsupportedFeatureError
        If the format cannot carry something the system uses.
    """
    return _format(fmt)[2](system)


def load(path: str | os.PathLike[str], *, block: str | None = None,
         dialect: str | None = None) -> AnySystem:
    """Read a fuzzy system from ``path``; the format follows the suffix (``block``: the FCL
    ``FUNCTION_BLOCK`` to read; ``dialect``: ``"matlab"`` or ``"octave"``'s reading of a
    ``.fis``; as :func:`loads`).

    Returns
    -------
    IT2Sugeno, T1Sugeno, IT2Mamdani, T1Mamdani, T1Tsukamoto or HybridSystem
        Evaluate as ``system(x1, x2, ...)``.

    Raises
    ------
    FisFormatError
        If the file is malformed or uses something it2track cannot represent, is not a regular
        file (a FIFO, a device, a directory), is larger than 64 MiB, holds binary data or (for
        ``.toml``) is not UTF-8; ``str(err)`` is ``"path:line: problem"`` (or ``"path:
        problem"``).
    ValueError
        For an unknown suffix, ``block`` with a format other than FCL, or ``dialect`` with
        a format other than ``.fis`` or other than ``"matlab"``/``"octave"``.
    OSError
        If the file does not exist or cannot be read.
    """
    name = format_of(path)
    label = os.fspath(path)
    return loads(_read(path, name, label), name, path=label, block=block, dialect=dialect)


def _read(path: str | os.PathLike[str], name: str, label: str) -> str:
    """The text of the file at ``path`` in format ``name`` (refused as :func:`load` says)."""
    try:
        data = read_bytes(path, what="fuzzy-system file")
        if name == "toml":
            return decode_text(data, label, what="fuzzy-system file")
        refuse_binary(data, label, what="fuzzy-system file")
        return decode(data)  # UTF-8, else Latin-1 (MATLAB files)
    except InputFileError as exc:
        raise FisFormatError(label, exc.line, exc.problem) from None


def load_terms(path: str | os.PathLike[str], *, block: str | None = None
               ) -> dict[str, Input]:
    """The input variables of the file at ``path`` and their terms, by name (as
    :func:`loads_terms`; the format follows the suffix, the file is read as :func:`load`
    reads it). ``block``: the FCL function block to read (``None``: the first, with a warning
    when the file has several), as for :func:`load`.

    >>> import tempfile, pathlib
    >>> text = "FUNCTION_BLOCK f VAR_INPUT x : REAL; END_VAR " \\
    ...        "FUZZIFY x TERM low := TRIAN 0 2 4; END_FUZZIFY END_FUNCTION_BLOCK"
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = pathlib.Path(d) / "terms.fcl"
    ...     _ = path.write_text(text)
    ...     x = load_terms(path)["x"]
    >>> x.universe, [s.name for s in x.sets], float(x.sets[0].upper(1.0))
    ((0.0, 4.0), ['low'], 0.5)

    Raises
    ------
    FisFormatError, ValueError, OSError
        As :func:`load`.
    """
    name = format_of(path)
    label = os.fspath(path)
    return loads_terms(_read(path, name, label), name, path=label, block=block)


def save(system: AnySystem, path: str | os.PathLike[str]) -> None:
    """Write ``system`` to ``path`` atomically; the format follows the suffix.

    Raises
    ------
    UnsupportedFeatureError
        If the format cannot carry something the system uses (nothing is written).
    ValueError
        For an unknown suffix.
    """
    text = _dumper(format_of(path))(system)
    atomic_write_text(path, text)
