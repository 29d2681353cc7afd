"""The operators of fuzzy inference, as Enums: t-norms, s-norms, implication, aggregation,
and type-1 defuzzification.

Each member is a strategy with a documented formula; command lines and files name them by the
member's value (``TNorm.from_name("prod")`` etc.). Their numpy forms (:meth:`TNorm.pair`
and friends) are the reference semantics the fuzzy systems use.

- ``TNorm.PRODUCT`` / ``TNorm.MINIMUM``: ``a b`` / ``min(a, b)`` (AND);
- ``SNorm.MAXIMUM`` / ``SNorm.PROBOR``: ``max(a, b)`` / ``a + b - a b`` (OR);
- ``Implication.MINIMUM`` / ``Implication.PRODUCT``: clip / scale an output set by the firing;
- ``Aggregation.MAXIMUM`` / ``SUM`` / ``PROBOR``: combine the implied output sets;
- ``Defuzzifier``: type-1 Mamdani centroid, bisector, mean / smallest / largest of maximum.
"""

from __future__ import annotations

import enum
from typing import Self

import numpy as np
from numpy.typing import NDArray

__all__ = ["Aggregation", "Connective", "Defuzzifier", "Implication", "SNorm", "TNorm"]

FloatArray = NDArray[np.float64]


class _Named(enum.Enum):
    """An Enum looked up by its value or member name (case-insensitive)."""

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {}

    @classmethod
    def _label(cls) -> str:
        return cls.__name__

    @classmethod
    def from_name(cls, name: str) -> Self:
        """The member whose value or name is ``name`` (case-insensitive)."""
        key = str(name).strip().lower()
        key = cls._aliases().get(key, key)
        for member in cls:
            if key in (member.value, member.name.lower()):
                return member
        choices = ", ".join(repr(m.value) for m in cls)
        raise ValueError(f"unknown {cls._label()} {name!r}; choose one of {choices}")


class TNorm(_Named):
    """Conjunction of the antecedents (eqs. 13-14 use the product): ``a b`` or ``min(a, b)``.

    Examples
    --------
    >>> TNorm.from_name("prod") is TNorm.PRODUCT
    True
    """

    @classmethod
    def _label(cls) -> str:
        return "t-norm"

    PRODUCT = "product"
    MINIMUM = "min"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"prod": "product", "minimum": "min"}

    def pair(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """``T(a, b)`` elementwise."""
        return np.multiply(a, b) if self is TNorm.PRODUCT else np.minimum(a, b)


class SNorm(_Named):
    """Disjunction of the antecedents of an OR rule: ``max(a, b)`` or ``a + b - a b``.

    Examples
    --------
    >>> float(SNorm.PROBOR.pair(np.float64(0.5), np.float64(0.5)))
    0.75
    """

    @classmethod
    def _label(cls) -> str:
        return "s-norm"

    MAXIMUM = "max"
    PROBOR = "probor"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"maximum": "max", "asum": "probor", "algebraic_sum": "probor"}

    def pair(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """``S(a, b)`` elementwise."""
        if self is SNorm.MAXIMUM:
            return np.maximum(a, b)
        return a + b - a * b


class Connective(_Named):
    """How a rule joins its antecedents: AND (the system's t-norm) or OR (its s-norm)."""

    @classmethod
    def _label(cls) -> str:
        return "rule connective"

    AND = "and"
    OR = "or"


class Implication(_Named):
    """Mamdani implication: an output set's membership ``mu(y)`` under firing ``f``.

    ``MINIMUM``: ``min(f, mu(y))`` (clipping); ``PRODUCT``: ``f mu(y)`` (scaling).
    """

    @classmethod
    def _label(cls) -> str:
        return "implication"

    MINIMUM = "min"
    PRODUCT = "product"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"prod": "product", "minimum": "min"}


class Aggregation(_Named):
    """Mamdani aggregation of the implied output sets of all rules, pointwise on the grid.

    ``MAXIMUM``: ``max``; ``SUM``: the plain sum (may exceed 1; centroids are unaffected by
    the scale); ``PROBOR``: probabilistic OR ``a + b - a b``.
    """

    @classmethod
    def _label(cls) -> str:
        return "aggregation"

    MAXIMUM = "max"
    SUM = "sum"
    PROBOR = "probor"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"maximum": "max"}


class Defuzzifier(_Named):
    """Type-1 Mamdani defuzzification of the aggregated set sampled on a grid ``y``.

    ``CENTROID``: ``sum(mu y) / sum(mu)``; ``BISECTOR``: the grid point where the cumulative
    area first reaches half the total; ``MOM`` / ``SOM`` / ``LOM``: mean / smallest / largest
    of the grid points where ``mu`` is maximal (MATLAB's ``defuzz`` definitions on the grid).
    """

    @classmethod
    def _label(cls) -> str:
        return "defuzzifier"

    CENTROID = "centroid"
    BISECTOR = "bisector"
    MOM = "mom"
    SOM = "som"
    LOM = "lom"
