"""The operators of fuzzy inference, as Enums: t-norms, s-norms, implication, aggregation,
and type-1 defuzzification (Mamdani and weighted).

Each member is a strategy with a documented formula; command lines and files name them by the
member's value or name, case and ``_``/``-`` insensitive (``TNorm.from_name("prod")``,
``SNorm.from_name("EinsteinSum")``). Their numpy forms (:meth:`TNorm.pair` and friends) are
the reference semantics the fuzzy systems use. The t-norms and s-norms are fuzzylite's (its
documentation defines each; MATLAB has ``min``/``prod`` and ``max``/``probor``).

t-norms ``T(a, b)`` (member: formula):

- ``MINIMUM`` (``"min"``): ``min(a, b)``; ``PRODUCT`` (``"product"``): ``a b``;
- ``BOUNDED_DIFFERENCE``: ``max(0, a + b - 1)``;
- ``DRASTIC_PRODUCT``: ``min(a, b)`` if ``max(a, b) = 1``, else 0;
- ``EINSTEIN_PRODUCT``: ``a b / (2 - (a + b - a b))``;
- ``HAMACHER_PRODUCT``: ``a b / (a + b - a b)``, 0 if ``a + b = 0``;
- ``NILPOTENT_MINIMUM``: ``min(a, b)`` if ``a + b > 1``, else 0.

s-norms ``S(a, b)``:

- ``MAXIMUM`` (``"max"``): ``max(a, b)``; ``PROBOR`` (``"probor"``, algebraic sum):
  ``a + b - a b``;
- ``BOUNDED_SUM``: ``min(1, a + b)``;
- ``DRASTIC_SUM``: ``max(a, b)`` if ``min(a, b) = 0``, else 1;
- ``EINSTEIN_SUM``: ``(a + b) / (1 + a b)``;
- ``HAMACHER_SUM``: ``(a + b - 2 a b) / (1 - a b)``, 1 if ``a b = 1``;
- ``NILPOTENT_MAXIMUM``: ``max(a, b)`` if ``a + b < 1``, else 1;
- ``NORMALIZED_SUM``: ``(a + b) / max(1, a + b)``;
- ``UNBOUNDED_SUM`` (``"sum"``): ``a + b``.

- A rule's AND folds the t-norm over the antecedents it mentions, left to right in input
  order (an input it does not mention takes no part: ``T(a, 1)`` may differ from ``a`` in
  floating point); its OR folds the s-norm likewise.
- ``Implication``: Mamdani implication, any t-norm (``min`` clips, ``product`` scales);
- ``Aggregation``: combines the implied output sets, any s-norm (``sum`` is MATLAB's
  unbounded sum);
- ``Defuzzifier``: type-1 Mamdani centroid, bisector, mean / smallest / largest of maximum;
- ``WeightedDefuzzifier``: Sugeno/Tsukamoto weighted average (MATLAB ``wtaver``) or sum
  (``wtsum``).
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from typing import Self

import numpy as np
from numpy.typing import NDArray

__all__ = ["Aggregation", "Connective", "Defuzzifier", "Implication", "SNorm", "TNorm",
           "WeightedDefuzzifier"]

FloatArray = NDArray[np.float64]


def _squash(text: str) -> str:
    return text.strip().lower().replace("_", "").replace("-", "").replace(" ", "")


class _Named(enum.Enum):
    """An Enum looked up by its value or member name (case, ``_`` and ``-`` insensitive)."""

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {}

    @classmethod
    def _label(cls) -> str:
        return cls.__name__

    @classmethod
    def from_name(cls, name: str) -> Self:
        """The member whose value, name or alias is ``name`` (case, ``_``, ``-`` insensitive)."""
        key = _squash(str(name))
        key = {_squash(k): v for k, v in cls._aliases().items()}.get(key, key)
        for member in cls:
            if key in (_squash(member.value), _squash(member.name)):
                return member
        choices = ", ".join(repr(m.value) for m in cls)
        raise ValueError(f"unknown {cls._label()} {name!r}; choose one of {choices}")


def _where(cond: NDArray[np.bool_], a: FloatArray, b: FloatArray | float) -> FloatArray:
    out: FloatArray = np.where(cond, a, b)
    return out


def _t_einstein(a: FloatArray, b: FloatArray) -> FloatArray:
    ab = a * b
    result: FloatArray = ab / (2.0 - (a + b - ab))
    return result


def _t_hamacher(a: FloatArray, b: FloatArray) -> FloatArray:
    ab = a * b
    with np.errstate(divide="ignore", invalid="ignore"):
        return _where(a + b != 0.0, ab / (a + b - ab), 0.0)


def _s_hamacher(a: FloatArray, b: FloatArray) -> FloatArray:
    ab = a * b
    with np.errstate(divide="ignore", invalid="ignore"):
        return _where(ab != 1.0, (a + b - 2.0 * ab) / (1.0 - ab), 1.0)


_T: dict[str, Callable[[FloatArray, FloatArray], FloatArray]] = {
    "product": np.multiply,
    "min": np.minimum,
    "bounded_difference": lambda a, b: np.maximum(0.0, a + b - 1.0),
    "drastic_product": lambda a, b: _where(np.maximum(a, b) == 1.0, np.minimum(a, b), 0.0),
    "einstein_product": _t_einstein,
    "hamacher_product": _t_hamacher,
    "nilpotent_minimum": lambda a, b: _where(a + b > 1.0, np.minimum(a, b), 0.0),
}

_S: dict[str, Callable[[FloatArray, FloatArray], FloatArray]] = {
    "max": np.maximum,
    "probor": lambda a, b: a + b - a * b,
    "bounded_sum": lambda a, b: np.minimum(1.0, a + b),
    "drastic_sum": lambda a, b: _where(np.minimum(a, b) == 0.0, np.maximum(a, b), 1.0),
    "einstein_sum": lambda a, b: (a + b) / (1.0 + a * b),
    "hamacher_sum": _s_hamacher,
    "nilpotent_maximum": lambda a, b: _where(a + b < 1.0, np.maximum(a, b), 1.0),
    "normalized_sum": lambda a, b: (a + b) / np.maximum(1.0, a + b),
    "sum": np.add,
}


class TNorm(_Named):
    """Conjunction of the antecedents (eqs. 13-14 use the product); formulas in the module
    docstring.

    Examples
    --------
    >>> TNorm.from_name("prod") is TNorm.PRODUCT
    True
    >>> float(TNorm.from_name("EinsteinProduct").pair(np.float64(0.5), np.float64(0.5)))
    0.2
    """

    @classmethod
    def _label(cls) -> str:
        return "t-norm"

    PRODUCT = "product"
    MINIMUM = "min"
    BOUNDED_DIFFERENCE = "bounded_difference"
    DRASTIC_PRODUCT = "drastic_product"
    EINSTEIN_PRODUCT = "einstein_product"
    HAMACHER_PRODUCT = "hamacher_product"
    NILPOTENT_MINIMUM = "nilpotent_minimum"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"prod": "product", "minimum": "min", "algebraic_product": "product"}

    def pair(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """``T(a, b)`` elementwise."""
        return _T[self.value](a, b)


class SNorm(_Named):
    """Disjunction of the antecedents of an OR rule; formulas in the module docstring.

    Examples
    --------
    >>> float(SNorm.PROBOR.pair(np.float64(0.5), np.float64(0.5)))
    0.75
    >>> float(SNorm.from_name("einstein_sum").pair(np.float64(0.5), np.float64(0.5)))
    0.8
    """

    @classmethod
    def _label(cls) -> str:
        return "s-norm"

    MAXIMUM = "max"
    PROBOR = "probor"
    BOUNDED_SUM = "bounded_sum"
    DRASTIC_SUM = "drastic_sum"
    EINSTEIN_SUM = "einstein_sum"
    HAMACHER_SUM = "hamacher_sum"
    NILPOTENT_MAXIMUM = "nilpotent_maximum"
    NORMALIZED_SUM = "normalized_sum"
    UNBOUNDED_SUM = "sum"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"maximum": "max", "asum": "probor", "algebraic_sum": "probor"}

    def pair(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """``S(a, b)`` elementwise."""
        return _S[self.value](a, b)


class Connective(_Named):
    """How a rule joins its antecedents: AND (the system's t-norm) or OR (its s-norm)."""

    @classmethod
    def _label(cls) -> str:
        return "rule connective"

    AND = "and"
    OR = "or"


class Implication(_Named):
    """Mamdani implication: an output set's membership ``mu(y)`` under firing ``f`` is
    ``T(f, mu(y))`` for a t-norm ``T`` (same members and formulas as :class:`TNorm`).

    ``MINIMUM``: ``min(f, mu(y))`` (clipping); ``PRODUCT``: ``f mu(y)`` (scaling).
    """

    @classmethod
    def _label(cls) -> str:
        return "implication"

    MINIMUM = "min"
    PRODUCT = "product"
    BOUNDED_DIFFERENCE = "bounded_difference"
    DRASTIC_PRODUCT = "drastic_product"
    EINSTEIN_PRODUCT = "einstein_product"
    HAMACHER_PRODUCT = "hamacher_product"
    NILPOTENT_MINIMUM = "nilpotent_minimum"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return TNorm._aliases()

    @property
    def tnorm(self) -> TNorm:
        """The t-norm this implication applies."""
        return TNorm(self.value)


class Aggregation(_Named):
    """Mamdani aggregation of the implied output sets of all rules, pointwise on the grid:
    any s-norm (same formulas as :class:`SNorm`), folded over the rules in rule order.

    ``MAXIMUM``: ``max``; ``SUM``: the plain sum (MATLAB's ``sum``, fuzzylite's
    ``UnboundedSum``: may exceed 1; centroids are unaffected by the scale); ``PROBOR``:
    probabilistic OR ``a + b - a b`` (fuzzylite's ``AlgebraicSum``).
    """

    @classmethod
    def _label(cls) -> str:
        return "aggregation"

    MAXIMUM = "max"
    SUM = "sum"
    PROBOR = "probor"
    BOUNDED_SUM = "bounded_sum"
    DRASTIC_SUM = "drastic_sum"
    EINSTEIN_SUM = "einstein_sum"
    HAMACHER_SUM = "hamacher_sum"
    NILPOTENT_MAXIMUM = "nilpotent_maximum"
    NORMALIZED_SUM = "normalized_sum"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {**SNorm._aliases(), "unbounded_sum": "sum"}

    @property
    def snorm(self) -> SNorm:
        """The s-norm this aggregation folds."""
        return SNorm(self.value)


class Defuzzifier(_Named):
    """Type-1 Mamdani defuzzification of the aggregated set sampled on a grid ``y``.

    ``CENTROID``: ``sum(mu y) / sum(mu)``; ``BISECTOR``: the grid point where the cumulative
    area first reaches half the total; ``MOM`` / ``SOM`` / ``LOM``: mean / smallest / largest
    of the grid points where ``mu`` is maximal (MATLAB's ``defuzz`` definitions on the grid).
    ``CENTROID_INTEGRAL``: the Octave fuzzy-logic-toolkit's ``trapz(y, y.*mu) / trapz(y, mu)``
    (its ``'centroid_integral'``; its ``'centroid'`` up to 0.6.1): the trapezoid rule, the two
    end points weighted by half. Written to ``.fis`` (Octave's name) and ``.toml`` only.
    """

    @classmethod
    def _label(cls) -> str:
        return "defuzzifier"

    CENTROID = "centroid"
    BISECTOR = "bisector"
    MOM = "mom"
    SOM = "som"
    LOM = "lom"
    CENTROID_INTEGRAL = "centroid_integral"


class WeightedDefuzzifier(_Named):
    """Output of a type-1 Sugeno or Tsukamoto system from the rules' firing ``w_r`` and
    consequents ``z_r``.

    ``AVERAGE``: ``sum(w z) / sum(w)`` (MATLAB ``wtaver``, fuzzylite ``WeightedAverage``);
    ``SUM``: ``sum(w z)`` (MATLAB ``wtsum``, fuzzylite ``WeightedSum``).

    Examples
    --------
    >>> WeightedDefuzzifier.from_name("WeightedSum") is WeightedDefuzzifier.SUM
    True
    """

    @classmethod
    def _label(cls) -> str:
        return "weighted defuzzifier"

    AVERAGE = "wtaver"
    SUM = "wtsum"

    @classmethod
    def _aliases(cls) -> dict[str, str]:
        return {"weighted_average": "wtaver", "weighted_sum": "wtsum"}
