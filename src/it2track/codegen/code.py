"""The generated code's types: the arithmetic (:class:`RealType`) and the files
(:class:`CCode`)."""

from __future__ import annotations

import enum
import hashlib
from dataclasses import dataclass

from .fixedpoint import FixedFormat

__all__ = ["CCode", "RealType"]


class RealType(enum.Enum):
    """The arithmetic of the generated code and the type of its values (``it2_real``):
    ``DOUBLE`` and ``FLOAT`` floating point, ``Q15`` integer-only fixed point with ``int16_t``
    values (see :mod:`it2track.codegen.fixedpoint`)."""

    DOUBLE = "double"
    FLOAT = "float"
    Q15 = "q15"

    @property
    def fixed(self) -> bool:
        """True for a fixed-point (integer) build."""
        return self is RealType.Q15

    @property
    def width(self) -> int:
        """Bits of ``it2_real``."""
        return {RealType.DOUBLE: 64, RealType.FLOAT: 32, RealType.Q15: 16}[self]

    @classmethod
    def from_name(cls, name: str) -> RealType:
        key = name.strip().lower()
        for member in cls:
            if key == member.value:
                return member
        raise ValueError(f"unknown real type {name!r}; choose "
                         f"{', '.join(repr(m.value) for m in cls)}")


@dataclass(frozen=True, kw_only=True)
class CCode:
    """Generated C for one controller.

    Attributes
    ----------
    prefix : str
        Prefix of every external name (``<prefix>_eval``, ``<prefix>_real``, ``<PREFIX>_OK``).
    real : RealType
    reducer : str
        Name of the type reducer compiled in (``"type-1"`` for a type-1 system).
    n_inputs, n_rules : int
    header_name, source_name : str
        File names, ``<prefix>.h`` and ``<prefix>.c``.
    header, source : str
        The text of the two files.
    fixed : FixedFormat or None
        For a fixed-point build, its scaling (how real values map to the integers of the
        interface); None for float and double.
    """

    prefix: str
    real: RealType
    reducer: str
    n_inputs: int
    n_rules: int
    header_name: str
    source_name: str
    header: str
    source: str
    fixed: FixedFormat | None = None

    def files(self) -> dict[str, str]:
        """File name -> text, header first."""
        return {self.header_name: self.header, self.source_name: self.source}

    def digest(self) -> str:
        """SHA-256 of both files (identifies a build)."""
        h = hashlib.sha256()
        for name, text in self.files().items():
            h.update(name.encode())
            h.update(b"\0")
            h.update(text.encode())
            h.update(b"\0")
        return h.hexdigest()
