"""Helpers shared by the writers: numbers and strings as MATLAB-syntax text, the consequent
tables and rule lines of ``.t2fis``/``.fis``, and the checks of what a format can carry."""

from __future__ import annotations

import math
from collections.abc import Sequence

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Connective,
    Consequent,
    Defuzzifier,
    HybridSystem,
    Implication,
    IT2Mamdani,
    IT2Sugeno,
    Linear,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    WeightedDefuzzifier,
)
from ..fuzzy.formula import Formula, FormulaMembership
from .errors import UnsupportedFeatureError

__all__ = [
    "check_matlab_operators",
    "check_writable",
    "consequent_tables",
    "fmt_number",
    "fmt_rule",
    "fmt_string",
    "fmt_vector",
    "mamdani_indices",
    "output_range",
    "refuse_hedges",
    "sugeno_span",
]




def fmt_number(x: float) -> str:
    """Shortest text that reads back to exactly ``x`` (``repr``), ``-12.0`` written ``-12``."""
    value = float(x)
    if not math.isfinite(value):
        raise UnsupportedFeatureError(f"cannot write the non-finite number {value!r}")
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


def fmt_vector(values: Sequence[float]) -> str:
    """``[a b c]`` with every number written by :func:`fmt_number`."""
    return "[" + " ".join(fmt_number(v) for v in values) + "]"


def fmt_string(text: str, what: str) -> str:
    """A single-quoted MATLAB string (``'`` doubled); ``what`` names it in errors."""
    if any(ch in text for ch in "\n\r"):
        raise UnsupportedFeatureError(f"{what} {text!r} contains a line break")
    return "'" + text.replace("'", "''") + "'"


def _key(value: float) -> tuple[float, bool]:
    return (value, math.copysign(1.0, value) < 0)


def _cons_key(cons: Consequent) -> object:
    if isinstance(cons, Linear):
        return ("linear", tuple(_key(v) for v in (*cons.lo, cons.constant_lo, *cons.hi,
                                                   cons.constant_hi)))
    assert isinstance(cons, tuple)
    return (_key(float(cons[0])), _key(float(cons[1])))


def consequent_tables(
    system: AnySystem,
) -> tuple[list[list[Consequent]], list[list[int]]]:
    """Per output: the distinct Sugeno consequents in order of first use, and each rule's
    1-based index into them (0 where the rule does not act on the output)."""
    tables: list[list[Consequent]] = []
    which: list[list[int]] = [[] for _ in system.rules]
    for k in range(system.n_outputs):
        table: list[Consequent] = []
        index: dict[object, int] = {}
        for r, rule in enumerate(system.rules):
            cons = rule.consequents[k]
            if cons is None:
                which[r].append(0)
                continue
            key = _cons_key(cons)
            if key not in index:
                table.append(cons)
                index[key] = len(table)
            which[r].append(index[key])
        tables.append(table)
    return tables, which


def mamdani_indices(system: IT2Mamdani | T1Mamdani | T1Tsukamoto) -> list[list[int]]:
    """Each rule's 1-based output set index per output (0: not acting on it)."""
    return [
        [0 if c is None else out.set_index(str(c)) + 1
         for out, c in zip(system.outputs, rule.consequents, strict=True)]
        for rule in system.rules
    ]


def fmt_rule(system: AnySystem, rule: Rule, out_indices: Sequence[int]) -> str:
    """``a1 a2 ..., c1 c2 (w) : k`` for one of our rules (``-j`` for NOT set ``j``)."""
    indices = []
    for inp, label, neg in zip(system.inputs, rule.antecedent, rule.negated, strict=True):
        j = 0 if label is None else inp.set_index(label) + 1
        indices.append(-j if neg else j)
    conn = 2 if rule.connective is Connective.OR else 1
    outs = " ".join(str(i) for i in out_indices)
    return f"{' '.join(str(i) for i in indices)}, {outs} ({fmt_number(rule.weight)}) : {conn}"


def refuse_hedges(system: object, fmt: str, *, hedges: bool = True,
                  lock_previous: bool = True) -> None:
    """Refuse a system whose rules have hedges (with ``hedges``) or a general condition, a
    T1Sugeno that groups its rules by value (``aggregation``), or an output with
    ``lock_previous`` (with ``lock_previous``): ``fmt`` cannot carry them."""
    for part in getattr(system, "systems", (system,)):
        flags = getattr(part, "lock_previous", False) if lock_previous else False
        if flags is True or (isinstance(flags, tuple) and any(flags)):
            raise UnsupportedFeatureError(
                f"lock_previous (fuzzylite's lock-previous: keep the previous output where no "
                f"rule fires) cannot be written to {fmt}; save as .fll")
        if isinstance(part, T1Sugeno) and part.aggregation is not None:
            raise UnsupportedFeatureError(
                f"the T1Sugeno aggregation {part.aggregation.value!r} (rules grouped by "
                f"consequent value, jFuzzyLogic's ACCU) cannot be written to {fmt}")
        for r, rule in enumerate(getattr(part, "rules", ())):
            if rule.condition is not None:
                raise UnsupportedFeatureError(
                    f"rule {r + 1} has a general condition (nested AND/OR, or a chained "
                    f"output's degree), which it2track cannot write to {fmt}")
            if not hedges:
                continue
            if rule.hedged:
                raise UnsupportedFeatureError(
                    f"rule {r + 1} has hedges (very, somewhat, ...), which the {fmt} format "
                    "cannot carry; save as .fll")


def check_writable(system: object, fmt: str) -> None:
    if isinstance(system, T1Tsukamoto | HybridSystem):
        raise UnsupportedFeatureError(
            f"the {fmt} format cannot carry a {type(system).__name__}; save as .fll")
    if not isinstance(system, IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani):
        raise TypeError(f"can only write IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani systems "
                        f"to {fmt}, got {type(system).__name__}")
    refuse_hedges(system, fmt)
    if fmt == ".t2fis":  # .fis names every norm as Octave and fuzzylite write them
        check_matlab_operators(system, fmt)


def check_matlab_operators(system: object, fmt: str) -> None:
    """Refuse operators the IT2FLS toolbox's files cannot name (fuzzylite's other norms,
    ``wtsum``, fuzzylite's midpoint sampling) rather than write another one in their place."""
    for what, value, allowed in (
        ("t-norm", getattr(system, "tnorm", None), (TNorm.PRODUCT, TNorm.MINIMUM)),
        ("s-norm", getattr(system, "snorm", None), (SNorm.MAXIMUM, SNorm.PROBOR)),
        ("implication", getattr(system, "implication", Implication.MINIMUM),
         (Implication.MINIMUM, Implication.PRODUCT)),
        ("aggregation", getattr(system, "aggregation", None) or Aggregation.MAXIMUM,
         (Aggregation.MAXIMUM, Aggregation.SUM, Aggregation.PROBOR)),
        ("defuzzifier", getattr(system, "defuzzifier", None),
         (None, WeightedDefuzzifier.AVERAGE, *Defuzzifier)),
        ("sampling", getattr(system, "sampling", Sampling.ENDPOINTS), (Sampling.ENDPOINTS,)),
    ):
        if value not in allowed:
            raise UnsupportedFeatureError(
                f"{fmt} cannot carry the {what} {value!r} (only "
                f"{', '.join(repr(a) for a in allowed if a is not None)}); save as .toml")


def sugeno_span(table: Sequence[Consequent]) -> list[tuple[float, float]]:
    """The intervals an output range must cover: each constant consequent, and each linear
    consequent's constant term (its value at the origin)."""
    spans = []
    for cons in table:
        if isinstance(cons, Linear):
            spans.append((cons.constant_lo, cons.constant_hi))
        else:
            assert isinstance(cons, tuple)
            spans.append((float(cons[0]), float(cons[1])))
    return spans


def output_range(
    table: Sequence[tuple[float, float]], on_zero_firing: float | None
) -> tuple[float, float]:
    """An output ``Range`` covering the consequents (``lo < hi``).

    With ``on_zero_firing`` set, the range's midpoint (MATLAB's output where no rule fires) is
    exactly ``on_zero_firing``: a range symmetric about it that covers the consequents if one
    exists in floating point, else ``[0, 2 c]`` (or ``[2 c, 0]``; ``[-1, 1]`` for ``c == 0``).
    """
    lo = min(v[0] for v in table)
    hi = max(v[1] for v in table)
    if on_zero_firing is None:
        if lo == hi:
            pad = max(1.0, abs(lo))
            return lo - pad, hi + pad
        return lo, hi
    c = float(on_zero_firing)
    span = max(c - lo, hi - c, 0.0) or max(1.0, abs(c))
    candidates = [span]
    step = 2.0 ** math.ceil(math.log2(span))
    candidates += [step * 2.0**k for k in range(8)]
    for r in candidates:
        a, b = c - r, c + r
        if math.isfinite(a) and math.isfinite(b) and a <= lo and b >= hi and a < b:
            if (a + b) / 2 == c:
                return a, b
    if c == 0.0:
        return -1.0, 1.0
    a, b = sorted((0.0, 2.0 * c))
    if not math.isfinite(b - a) or (a + b) / 2 != c:
        raise UnsupportedFeatureError(
            f"on_zero_firing={c!r} cannot be written as the midpoint of an output range"
        )
    return a, b


def refuse_formulas(system: object, fmt: str) -> None:
    """Refuse a system with a formula (a :class:`~it2track.fuzzy.formula.Formula` consequent or
    membership function, read from a fuzzylite or jFuzzyLogic file): no writer carries one."""
    for part in getattr(system, "systems", None) or (system,):
        for rule in getattr(part, "rules", ()):
            for cons in rule.consequents:
                if isinstance(cons, Formula):
                    raise UnsupportedFeatureError(
                        f"the consequent formula {cons.text!r} cannot be written to {fmt}: "
                        "it2track writes numbers, not formulas")
        variables = [*getattr(part, "inputs", ()), *getattr(part, "outputs", ())]
        for var in variables:
            for s in getattr(var, "sets", ()):
                for mf in (s.upper, s.lower):
                    if isinstance(mf, Formula | FormulaMembership):
                        raise UnsupportedFeatureError(
                            f"set {s.name!r} of {var.name!r} is a formula, which it2track "
                            f"cannot write to {fmt}: it writes numbers, not formulas")
