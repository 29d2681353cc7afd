"""Antecedents and rules: variables with their sets, and rules over them.

Shared by every kind of fuzzy system -- the Sugeno and TSK systems of :mod:`.sugeno` and the
Mamdani systems of :mod:`.mamdani` differ only in what a rule's consequent is:

- a number or an interval ``(lo, hi)``: zero-order Sugeno;
- a :class:`Linear` function of the inputs: first-order Sugeno (TSK);
- a :class:`~.formula.Formula` of the inputs (fuzzylite's ``Function``, jFuzzyLogic's
  ``FUNCTION``): a crisp consequent evaluated per sample, read from files;
- a set label (a string) of an :class:`Output`: Mamdani.

A rule joins its antecedents with AND (the system's t-norm) or OR (its s-norm, see
:mod:`.norms`), may negate any of them (NOT ``A``: ``1 - mu_A``; for an interval type-2 set the
lower and upper bounds swap roles, ``[1 - upper, 1 - lower]``), and carries a weight in
``[0, 1]`` that multiplies its firing strength (MATLAB's rule weight). A system with several
outputs gives each rule one consequent per output (``None``: the rule does not act on that
output). A system's definition is apart from its evaluation (see :mod:`.tables` for how rules
become arrays).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from .conditions import Condition, Is, Join, Modified, Not, inputs_of
from .formula import Formula
from .hedges import Hedge
from .membership import MembershipFunction
from .norms import Connective, TNorm
from .sets import IT2Set

__all__ = ["Consequent", "Input", "Linear", "Output", "Rule", "TNorm", "rules_from_table"]


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
        kind = type(self).__name__.lower()
        lo, hi = (float(v) for v in universe)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi
                and math.isfinite(hi - lo)):  # a width that overflows makes every grid NaN
            raise ValueError(
                f"{kind} {name!r}: universe={tuple(universe)!r} must be finite, lo < hi, "
                "with a finite width hi - lo"
            )
        converted = []
        for s in sets:
            if isinstance(s, IT2Set):
                converted.append(s)
            else:
                label, mf = s
                converted.append(IT2Set.type1(mf, label))
        names = [s.name for s in converted]
        if not converted and kind != "input":  # an input may feed linear consequents only
            raise ValueError(f"{kind} {name!r}: needs at least one set")
        if len(set(names)) != len(names) or any(not n for n in names):
            raise ValueError(f"{kind} {name!r}: set names {names!r} must be non-empty and unique")
        for s in converted:
            s.check_on((lo, hi), owner=f"{kind} {name!r}")
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "universe", (lo, hi))
        object.__setattr__(self, "sets", tuple(converted))

    def set_index(self, label: str) -> int:
        for i, s in enumerate(self.sets):
            if s.name == label:
                return i
        raise ValueError(
            f"{type(self).__name__.lower()} {self.name!r} has no set {label!r}; its sets are "
            f"{[s.name for s in self.sets]}"
        )


@dataclass(frozen=True, init=False)
class Output(Input):
    """An output variable of a Mamdani system: a name, a universe ``(lo, hi)`` and its sets.

    The universe is where the output sets are sampled for centroid type reduction.
    Constructed like :class:`Input`.

    Examples
    --------
    >>> from it2track.fuzzy import Triangle
    >>> out = Output("u", (-12, 12), [("low", Triangle(-12, -12, 0)),
    ...                               ("high", Triangle(0, 12, 12))])
    >>> [s.name for s in out.sets]
    ['low', 'high']
    """


def _float_pair(value: object, what: str) -> tuple[float, float]:
    if isinstance(value, int | float | np.floating | np.integer) and not isinstance(value, bool):
        lo = hi = float(value)
    else:
        try:
            values = [float(v) for v in value]  # type: ignore[attr-defined]
        except (TypeError, ValueError):
            raise ValueError(f"{what} {value!r} must be a number or an interval (lo, hi)") from None
        if len(values) != 2:
            raise ValueError(f"{what} {value!r} must be a number or an interval (lo, hi)")
        lo, hi = values
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
        raise ValueError(f"{what} ({lo}, {hi}) must be finite, lo <= hi")
    return lo, hi


@dataclass(frozen=True, init=False)
class Linear:
    """First-order (TSK) consequent ``y = c0 + sum_i ci xi``, crisp or interval.

    Each coefficient is a number or an interval ``(lo, hi)``. With interval coefficients the
    consequent is the interval of the linear function by interval arithmetic (on the clipped
    inputs)::

        y_lo = c0_lo + sum_i min(ci_lo xi, ci_hi xi)
        y_hi = c0_hi + sum_i max(ci_lo xi, ci_hi xi)

    Parameters
    ----------
    coefficients : sequence of (float or (float, float)), length n_inputs
        ``c1 ... cn``, in input order (MATLAB's ``[c1 ... cn c0]`` without the constant).
    constant : float or (float, float)
        ``c0``.

    Attributes
    ----------
    lo, hi : tuple of float
        Lower / upper ends of ``(c1, ..., cn)``.
    constant_lo, constant_hi : float

    Examples
    --------
    >>> f = Linear([2.0, (-1.0, 1.0)], 0.5)
    >>> f.interval([1.0, -3.0])
    (-0.5, 5.5)
    """

    lo: tuple[float, ...]
    hi: tuple[float, ...]
    constant_lo: float
    constant_hi: float

    def __init__(self, coefficients: Sequence[float | Sequence[float]],
                 constant: float | Sequence[float] = 0.0) -> None:
        pairs = [_float_pair(c, f"linear coefficient c{i + 1}")
                 for i, c in enumerate(coefficients)]
        if not pairs:
            raise ValueError("a Linear consequent needs one coefficient per input")
        c0 = _float_pair(constant, "linear constant c0")
        object.__setattr__(self, "lo", tuple(p[0] for p in pairs))
        object.__setattr__(self, "hi", tuple(p[1] for p in pairs))
        object.__setattr__(self, "constant_lo", c0[0])
        object.__setattr__(self, "constant_hi", c0[1])

    @property
    def crisp(self) -> bool:
        """True if every coefficient is a number (no interval)."""
        return self.lo == self.hi and self.constant_lo == self.constant_hi

    def interval(self, x: Sequence[float]) -> tuple[float, float]:
        """``(y_lo, y_hi)`` at one input point ``x`` (same operations as the systems)."""
        y_lo, y_hi = self.constant_lo, self.constant_hi
        for a, b, xi in zip(self.lo, self.hi, x, strict=True):
            p, q = a * xi, b * xi
            y_lo += min(p, q)
            y_hi += max(p, q)
        return y_lo, y_hi


#: What one output of a rule can be: an interval (zero-order), a :class:`Linear` function
#: (first-order), a :class:`~.formula.Formula` of the inputs, a set label (Mamdani), or
#: ``None`` (the rule does not act on this output).
Consequent = tuple[float, float] | Linear | Formula | str | None


def _consequent(value: object, what: str) -> Consequent:
    if value is None or isinstance(value, Linear | Formula):
        return value
    if isinstance(value, str):
        if not value:
            raise ValueError(f"{what}: an output set label must be non-empty")
        return value
    return _float_pair(value, what)


@dataclass(frozen=True, init=False)
class Rule:
    """A rule: ``if x1 is A1 and x2 is A2 then y = c``, with AND or OR, NOT and a weight.

    Parameters
    ----------
    antecedent : sequence of str or None
        One set label per input; ``None`` means the input does not appear in the rule.
    consequent : float, (float, float), Linear or str
        The consequent of a one-output system: a crisp number or an interval ``(lo, hi)``
        (zero-order Sugeno), a :class:`Linear` function (first-order TSK), or an output set
        label (Mamdani). Give either this or ``consequents``.
    consequents : sequence, optional
        One consequent per output (same forms, or ``None`` where the rule does not act on an
        output), for systems with several outputs.
    weight : float
        Multiplies the rule's firing strength; ``0 <= weight <= 1`` (default 1).
    connective : Connective or str
        ``"and"`` (default: the system's t-norm joins the antecedents) or ``"or"`` (its s-norm).
    negated : sequence of bool, optional
        Per input, True for ``x is not A`` (default: none negated). Only mentioned inputs can
        be negated.
    hedges : sequence of sequence of Hedge, optional
        Per input, the :class:`~it2track.fuzzy.hedges.Hedge` s of its proposition, outermost
        first, applied to the set's membership before ``negated`` (``x is not very A`` is
        ``1 - very(mu_A)``). Default: none. Only mentioned inputs can have hedges.
    consequent_hedges : sequence of sequence of Hedge, optional
        Per output, hedges (outermost first) applied to the rule's weighted firing strength
        for that output (fuzzylite's hedged conclusion ``then y is very B``; Octave's hedged
        Sugeno consequent). Default: none. Only outputs the rule acts on can have hedges.
    condition : Condition, optional
        A general condition (:mod:`.conditions`: nested AND/OR/NOT, hedges, explicit norms)
        in place of the one-connective antecedent; then ``antecedent`` is all ``None`` (one
        per input) and ``negated``/``hedges`` are not given. Evaluated by numpy.

    Attributes
    ----------
    consequents : tuple
        The normalised consequents, one per output (intervals as ``(lo, hi)`` tuples).

    Examples
    --------
    >>> r = Rule(["N", "P"], -4.0)
    >>> r.consequent, r.weight, r.connective.value
    ((-4.0, -4.0), 1.0, 'and')
    >>> Rule(["N", None], "low", negated=[True, False]).negated
    (True, False)
    """

    antecedent: tuple[str | None, ...]
    consequents: tuple[Consequent, ...]
    weight: float
    connective: Connective
    negated: tuple[bool, ...]
    hedges: tuple[tuple[Hedge, ...], ...]
    consequent_hedges: tuple[tuple[Hedge, ...], ...]
    condition: Condition | None

    def __init__(
        self,
        antecedent: Sequence[str | None],
        consequent: object = None,
        *,
        consequents: Sequence[object] | None = None,
        weight: float = 1.0,
        connective: Connective | str = Connective.AND,
        negated: Sequence[bool] | None = None,
        hedges: Sequence[Sequence[Hedge]] | None = None,
        consequent_hedges: Sequence[Sequence[Hedge]] | None = None,
        condition: Condition | None = None,
    ) -> None:
        ant = tuple(antecedent)
        where = f"rule {list(ant)!r}"
        if (consequent is None) == (consequents is None):
            raise ValueError(f"{where}: give either consequent= (one output) or consequents= "
                             "(one per output)")
        if consequents is None:
            cons: tuple[Consequent, ...] = (_consequent(consequent, f"{where}: consequent"),)
        else:
            cons = tuple(_consequent(c, f"{where}: consequent {k + 1}")
                         for k, c in enumerate(consequents))
            if not cons or all(c is None for c in cons):
                raise ValueError(f"{where}: needs a consequent for at least one output")
        if isinstance(weight, bool) or not isinstance(
            weight, int | float | np.floating | np.integer
        ) or not 0.0 <= float(weight) <= 1.0:
            raise ValueError(f"{where}: weight={weight!r} must be a number in [0, 1]")
        if not isinstance(connective, Connective):
            connective = Connective.from_name(str(connective))
        neg = (False,) * len(ant) if negated is None else tuple(negated)
        if len(neg) != len(ant) or not all(isinstance(v, bool | np.bool_) for v in neg):
            raise ValueError(f"{where}: negated={negated!r} must hold one bool per antecedent")
        for label, flag in zip(ant, neg, strict=True):
            if flag and label is None:
                raise ValueError(f"{where}: an input the rule does not mention cannot be negated")
        ant_hedges = _hedges(hedges, ant, f"{where}: hedges", "input")
        cons_hedges = _hedges(consequent_hedges, cons, f"{where}: consequent_hedges", "output")
        if condition is not None:
            _check_condition(condition, ant, neg, ant_hedges, where)
        object.__setattr__(self, "condition", condition)
        object.__setattr__(self, "antecedent", ant)
        object.__setattr__(self, "hedges", ant_hedges)
        object.__setattr__(self, "consequent_hedges", cons_hedges)
        object.__setattr__(self, "consequents", cons)
        object.__setattr__(self, "weight", float(weight))
        object.__setattr__(self, "connective", connective)
        object.__setattr__(self, "negated", tuple(bool(v) for v in neg))

    @property
    def consequent(self) -> Consequent:
        """The first output's consequent (the only one of a one-output system)."""
        return self.consequents[0]

    @property
    def plain(self) -> bool:
        """True for an AND rule of weight 1 with no negation or hedge (the paper's rule form)."""
        return (self.weight == 1.0 and self.connective is Connective.AND
                and not any(self.negated) and not self.hedged and self.condition is None)

    @property
    def hedged(self) -> bool:
        """True if any proposition or conclusion of the rule has a hedge."""
        return any(self.hedges) or any(self.consequent_hedges)

    def with_consequents(self, consequents: Sequence[object],
                         outputs: Sequence[int] | None = None) -> Rule:
        """This rule with other consequents: one per output, or one per output of
        ``outputs`` (indices into this rule's outputs, whose conclusion hedges it keeps)."""
        picked = range(len(self.consequents)) if outputs is None else outputs
        return Rule(self.antecedent, consequents=consequents, weight=self.weight,
                    connective=self.connective, negated=self.negated, hedges=self.hedges,
                    consequent_hedges=[self.consequent_hedges[k] for k in picked],
                    condition=self.condition)


def _check_condition(condition: object, ant: tuple[str | None, ...], neg: tuple[bool, ...],
                     hedges: tuple[tuple[Hedge, ...], ...], where: str) -> None:
    if not isinstance(condition, Is | Not | Join | Modified):
        raise ValueError(f"{where}: condition={condition!r} must be an Is, Not, Join or Modified")
    if any(a is not None for a in ant) or any(neg) or any(hedges):
        raise ValueError(f"{where}: with a condition, give the antecedent as None per input "
                         "and no negated= or hedges=")
    for prop in inputs_of(condition):
        if not (isinstance(prop.input, int) and 0 <= prop.input < len(ant)):
            raise ValueError(f"{where}: condition names input {prop.input!r}; the rule has "
                             f"{len(ant)} inputs")


def _hedges(value: Sequence[Sequence[Hedge]] | None, slots: tuple[object, ...], what: str,
            kind: str) -> tuple[tuple[Hedge, ...], ...]:
    if value is None:
        return ((),) * len(slots)
    try:
        out = tuple(tuple(h) for h in value)
    except TypeError:
        raise ValueError(f"{what}={value!r} must hold a sequence of Hedge per {kind}") from None
    if len(out) != len(slots) or not all(isinstance(h, Hedge) for hs in out for h in hs):
        raise ValueError(f"{what}={value!r} must hold a sequence of Hedge per {kind}")
    for slot, hs in zip(slots, out, strict=True):
        if hs and slot is None:
            raise ValueError(f"{what}: an {kind} the rule does not mention cannot have hedges")
    return out


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
