"""Hedges: functions of a membership degree that modify a proposition (``x is very A``).

A hedge ``h`` maps a degree ``mu`` in ``[0, 1]`` to ``h(mu)`` in ``[0, 1]``. fuzzylite defines
six by name (its documentation, and jFuzzyLogic's where it has the name):

=============  ==============================================================
``any``        ``1`` (whatever ``mu``)
``not``        ``1 - mu``
``very``       ``mu ** 2``
``somewhat``   ``sqrt(mu)``
``extremely``  ``2 mu**2`` for ``mu <= 0.5``, else ``1 - 2 (1 - mu)**2``
``seldom``     ``sqrt(mu / 2)`` for ``mu <= 0.5``, else ``1 - sqrt((1 - mu) / 2)``
=============  ==============================================================

Octave's fuzzy-logic-toolkit writes hedges into a ``.fis`` rule index as its fraction
(``2.3``: set 2, hedge 3) and means a power: ``mu ** p`` on an antecedent (``p = 0.5, 2, 3, 4``
for ``.05, .2, .3, .4``: its "somewhat", "very", "extremely", "very very"), which
:meth:`Hedge.power` gives. Note that Octave's "extremely" (``mu ** 3``) is not fuzzylite's.

A proposition's hedges are written outermost first, as in the text: ``("not", "extremely")``
is ``not (extremely mu)``. :class:`Hedged` applies them to a membership function. Every hedge
but ``not`` is non-decreasing, so it maps the bounds of an interval degree to the bounds of the
hedged interval; ``not`` swaps them (as :class:`~it2track.fuzzy.rules.Rule` negation does).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .membership import MembershipFunction

__all__ = ["NAMES", "Hedge", "Hedged", "apply_hedges"]

FloatArray = NDArray[np.float64]

#: fuzzylite's hedges by name
NAMES = ("any", "not", "very", "somewhat", "extremely", "seldom")


@dataclass(frozen=True)
class Hedge:
    """One hedge: one of fuzzylite's :data:`NAMES`, or ``"power"`` with its ``exponent``.

    Parameters
    ----------
    name : str
        ``"any"``, ``"not"``, ``"very"``, ``"somewhat"``, ``"extremely"``, ``"seldom"`` or
        ``"power"``.
    exponent : float
        The power ``p > 0`` of ``"power"`` (``mu ** p``); 0 for the named hedges.

    Examples
    --------
    >>> Hedge("extremely")(np.array([0.25, 0.75])).tolist()
    [0.125, 0.875]
    >>> Hedge.power(3.0)(np.array([0.5])).tolist()
    [0.125]
    """

    name: str
    exponent: float = 0.0

    def __post_init__(self) -> None:
        if self.name == "power":
            p = self.exponent
            if isinstance(p, bool) or not isinstance(p, int | float) or not (
                    math.isfinite(p) and p > 0):
                raise ValueError(f"hedge power exponent={p!r} must be a finite number > 0")
            object.__setattr__(self, "exponent", float(p))
        elif self.name not in NAMES:
            raise ValueError(f"hedge {self.name!r} is not one of {list(NAMES)} or 'power'")
        elif self.exponent != 0.0:
            raise ValueError(f"hedge {self.name!r} takes no exponent (got {self.exponent!r})")

    @classmethod
    def power(cls, exponent: float) -> Hedge:
        """``mu ** exponent`` (Octave's hedges)."""
        return cls("power", exponent)

    @property
    def increasing(self) -> bool:
        """True unless the hedge is ``not`` (every other hedge is non-decreasing)."""
        return self.name != "not"

    def __call__(self, mu: ArrayLike) -> FloatArray:
        m = np.asarray(mu, dtype=np.float64)
        if self.name == "any":
            return np.ones_like(m)
        if self.name == "not":
            return 1.0 - m
        if self.name == "very":
            return m * m
        if self.name == "somewhat":
            return np.sqrt(m)
        if self.name == "extremely":
            return np.where(m <= 0.5, 2.0 * (m * m), 1.0 - 2.0 * ((1.0 - m) * (1.0 - m)))
        if self.name == "seldom":
            return np.where(m <= 0.5, np.sqrt(0.5 * m), 1.0 - np.sqrt(0.5 * (1.0 - m)))
        return np.power(m, self.exponent)

    def __str__(self) -> str:
        return self.name if self.name != "power" else f"power {self.exponent:g}"


def apply_hedges(hedges: Sequence[Hedge], mu: ArrayLike) -> FloatArray:
    """``hedges`` (outermost first) applied to the degrees ``mu``.

    Examples
    --------
    >>> apply_hedges([Hedge("not"), Hedge("very")], np.array([0.5])).tolist()
    [0.75]
    """
    m = np.asarray(mu, dtype=np.float64)
    for hedge in reversed(hedges):
        m = hedge(m)
    return m


@dataclass(frozen=True)
class Hedged:
    """A membership function with hedges applied, the last one first:
    ``hedges[0](hedges[1](mf(x)))`` for two.

    Parameters
    ----------
    mf : MembershipFunction
        The set's membership function (for an interval type-2 set, the bound the hedges map
        to the wanted bound: see the module docstring).
    hedges : tuple of Hedge
        Outermost first; at least one.

    Examples
    --------
    >>> from it2track.fuzzy import Triangle
    >>> Hedged(Triangle(0, 1, 2), (Hedge("very"),))(np.array([0.5])).tolist()
    [0.25]
    """

    mf: MembershipFunction
    hedges: tuple[Hedge, ...]

    def __post_init__(self) -> None:
        if not self.hedges or not all(isinstance(h, Hedge) for h in self.hedges):
            raise ValueError(f"Hedged needs one or more Hedge, got {self.hedges!r}")

    def __call__(self, x: ArrayLike) -> FloatArray:
        return apply_hedges(self.hedges, self.mf(x))
