"""Antecedents and rules: input variables with their sets, rules, and the t-norm joining them.

Shared by every kind of fuzzy system (the Sugeno systems of :mod:`.sugeno`); a system's
definition is apart from its evaluation (see :mod:`.tables` for how rules become arrays).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from .membership import MembershipFunction
from .sets import IT2Set

__all__ = ["Input", "Rule", "TNorm", "rules_from_table"]


class TNorm(enum.Enum):
    """Conjunction of the antecedents (eqs. 13-14 use the product)."""

    PRODUCT = "product"
    MINIMUM = "min"

    @classmethod
    def from_name(cls, name: str) -> TNorm:
        key = name.strip().lower()
        for member in cls:
            if key in (member.value, member.name.lower()):
                return member
        raise ValueError(f"unknown t-norm {name!r}; choose 'product' or 'min'")


@dataclass(frozen=True)
class Input:
    """An input variable: a name, a universe ``(lo, hi)`` and its fuzzy sets.

    Sets may be :class:`IT2Set` or, for type-1 systems, ``(name, mf)`` pairs. Each set is
    checked on the universe (``0 <= lower <= upper <= 1``).
    """

    name: str
    universe: tuple[float, float]
    sets: tuple[IT2Set, ...]

    def __init__(
        self,
        name: str,
        universe: Sequence[float],
        sets: Iterable[IT2Set | tuple[str, MembershipFunction]],
    ) -> None:
        lo, hi = (float(v) for v in universe)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(
                f"input {name!r}: universe={tuple(universe)!r} must be finite, lo < hi"
            )
        converted = []
        for s in sets:
            if isinstance(s, IT2Set):
                converted.append(s)
            else:
                label, mf = s
                converted.append(IT2Set.type1(mf, label))
        names = [s.name for s in converted]
        if not converted:
            raise ValueError(f"input {name!r}: needs at least one set")
        if len(set(names)) != len(names) or any(not n for n in names):
            raise ValueError(f"input {name!r}: set names {names!r} must be non-empty and unique")
        for s in converted:
            s.check_on((lo, hi), owner=f"input {name!r}")
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "universe", (lo, hi))
        object.__setattr__(self, "sets", tuple(converted))

    def set_index(self, label: str) -> int:
        for i, s in enumerate(self.sets):
            if s.name == label:
                return i
        raise ValueError(
            f"input {self.name!r} has no set {label!r}; its sets are {[s.name for s in self.sets]}"
        )


@dataclass(frozen=True)
class Rule:
    """``if x1 is A1 and x2 is A2 then y = [lo, hi]`` (zero-order Sugeno; any number of inputs).

    Parameters
    ----------
    antecedent : sequence of str or None
        One set label per input; ``None`` means the input does not appear in the rule.
    consequent : float or (float, float)
        Crisp output, or an interval ``(lo, hi)`` with ``lo <= hi``.
    """

    antecedent: tuple[str | None, ...]
    consequent: tuple[float, float]

    def __init__(
        self, antecedent: Sequence[str | None], consequent: float | Sequence[float]
    ) -> None:
        if isinstance(consequent, int | float | np.floating | np.integer):
            lo = hi = float(consequent)
        else:
            values = [float(v) for v in consequent]
            if len(values) != 2:
                raise ValueError(f"rule {list(antecedent)!r}: consequent {consequent!r} must be a "
                                 "number or an interval (lo, hi)")
            lo, hi = values
        if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
            raise ValueError(
                f"rule {list(antecedent)!r}: consequent ({lo}, {hi}) must be finite, lo <= hi"
            )
        object.__setattr__(self, "antecedent", tuple(antecedent))
        object.__setattr__(self, "consequent", (lo, hi))


def rules_from_table(
    row_sets: Sequence[str], col_sets: Sequence[str], table: Sequence[Sequence[float]]
) -> tuple[Rule, ...]:
    """Two-input rule grid: ``table[i][j]`` is the consequent of ``(row_sets[i], col_sets[j])``.

    Examples
    --------
    >>> [r.antecedent for r in rules_from_table(["N", "P"], ["Z"], [[-1], [1]])]
    [('N', 'Z'), ('P', 'Z')]
    """
    if len(table) != len(row_sets) or any(len(row) != len(col_sets) for row in table):
        raise ValueError(
            f"rule table must be {len(row_sets)} x {len(col_sets)} to match the set labels"
        )
    return tuple(
        Rule((r, c), table[i][j]) for i, r in enumerate(row_sets) for j, c in enumerate(col_sets)
    )
