"""Writing fuzzylite's FuzzyLite Language (the layout and what it carries: :mod:`.fll`)."""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import Any

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Consequent,
    Defuzzifier,
    Implication,
    Input,
    IT2Mamdani,
    IT2Sugeno,
    Linear,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    WeightedDefuzzifier,
)
from ..fuzzy.terms import to_fuzzylite
from ._common import consequent_tables, mamdani_indices, output_range, sugeno_span
from .errors import UnsupportedFeatureError

__all__ = ["dumps", "fuzzylite_name"]

_SPECIAL = {"PRODUCT": "AlgebraicProduct", "MINIMUM": "Minimum", "MAXIMUM": "Maximum",
            "PROBOR": "AlgebraicSum", "SUM": "UnboundedSum"}
_DEFUZZIFIERS = {Defuzzifier.CENTROID: "Centroid", Defuzzifier.BISECTOR: "Bisector",
                 Defuzzifier.MOM: "MeanOfMaximum", Defuzzifier.SOM: "SmallestOfMaximum",
                 Defuzzifier.LOM: "LargestOfMaximum"}
_WEIGHTED = {WeightedDefuzzifier.AVERAGE: "WeightedAverage", WeightedDefuzzifier.SUM: "WeightedSum"}
_NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*")
_KEYWORDS = {"if", "is", "then", "and", "or", "with", "not", "very", "somewhat", "extremely",
             "seldom", "any", "none"}


def fuzzylite_name(member: TNorm | SNorm | Implication | Aggregation) -> str:
    """fuzzylite's class name of an operator (``TNorm.PRODUCT`` -> ``"AlgebraicProduct"``)."""
    if member.name in _SPECIAL:
        return _SPECIAL[member.name]
    return "".join(part.capitalize() for part in member.name.split("_"))


def _number(x: float) -> str:
    value = float(x)
    if math.isnan(value):
        raise UnsupportedFeatureError("cannot write NaN to .fll")
    return repr(value)


def _numbers(values: Sequence[float]) -> str:
    return " ".join(_number(v) for v in values)


def _name(text: str, what: str) -> str:
    if not _NAME_RE.fullmatch(text) or text in _KEYWORDS:
        raise UnsupportedFeatureError(
            f"{what} {text!r} is not a fuzzylite identifier (letters, digits, '_' and '.', not "
            "a keyword of its rules); rename it or save as .toml"
        )
    return text


def _variable(header: str, var: Input, extra: Sequence[str], terms: Sequence[str]) -> list[str]:
    kind = "input" if header == "InputVariable" else "output"
    return [f"{header}: {_name(var.name, kind)}", "  enabled: true",
            f"  range: {_numbers(var.universe)}", *extra, *terms]


def _mf_terms(var: Input, kind: str) -> list[str]:
    lines = []
    for s in var.sets:
        what = f"{kind} {var.name!r} set {s.name!r}"
        if not s.is_type1:
            raise UnsupportedFeatureError(f"{what} has a footprint; fuzzylite is type-1 only")
        try:
            name, params = to_fuzzylite(s.upper)
        except ValueError:
            raise UnsupportedFeatureError(
                f"{what} is a {type(s.upper).__name__}, which fuzzylite has no term for; save "
                "as .toml") from None
        lines.append(f"  term: {_name(s.name, 'set')} {name} {_numbers(params)}")
    return lines


def _consequent_term(j: int, cons: Consequent) -> str:
    if isinstance(cons, Linear):
        return f"  term: c{j} Linear {_numbers([*cons.lo, cons.constant_lo])}"
    assert isinstance(cons, tuple)
    return f"  term: c{j} Constant {_number(cons[0])}"


def _default(system: AnySystem, k: int) -> str:
    zero = system.zero_firing_value(k)
    return "  default: nan" if zero is None else f"  default: {_number(zero)}"


def dumps(system: AnySystem) -> str:
    """``.fll`` text for a type-1 system.

    Raises
    ------
    UnsupportedFeatureError
        For a type-2 system, interval consequents, MFs without a fuzzylite term and names that
        are not fuzzylite identifiers.
    """
    if isinstance(system, IT2Sugeno | IT2Mamdani):
        raise UnsupportedFeatureError(
            "fuzzylite has no type-2 systems; save as .t2fis, .fis or .toml")
    if not isinstance(system, T1Sugeno | T1Mamdani):
        raise TypeError(f"can only write T1Sugeno or T1Mamdani systems to .fll, got "
                        f"{type(system).__name__}")
    if any(ch in system.name for ch in "#\n\r"):
        raise UnsupportedFeatureError(f"system name {system.name!r} holds '#' or a line break")
    lines = [f"Engine: {system.name}".rstrip()]
    for inp in system.inputs:
        lines += _variable("InputVariable", inp, ["  lock-range: true"],
                           _mf_terms(inp, "input"))
    which: list[list[int]]
    implication: Any = None
    if isinstance(system, T1Mamdani):
        defuzz = f"{_DEFUZZIFIERS[system.defuzzifier]} {system.resolution - 1}"
        for k, out in enumerate(system.outputs):
            extra = ["  lock-range: false",
                     f"  aggregation: {fuzzylite_name(system.aggregation)}",
                     f"  defuzzifier: {defuzz}", _default(system, k), "  lock-previous: false"]
            lines += _variable("OutputVariable", out, extra, _mf_terms(out, "output"))
        which = mamdani_indices(system)
        implication = fuzzylite_name(system.implication)
        term_names = [[s.name for s in out.sets] for out in system.outputs]
    else:
        tables, which = consequent_tables(system)
        defuzz = f"{_WEIGHTED[system.defuzzifier]} TakagiSugeno"
        for k, (name, table) in enumerate(zip(system.output_names, tables, strict=True)):
            for cons in table:
                if (isinstance(cons, Linear) and not cons.crisp) or (
                        isinstance(cons, tuple) and cons[0] != cons[1]):
                    raise UnsupportedFeatureError(
                        "fuzzylite's consequents are crisp; this system has intervals")
            lo, hi = output_range(sugeno_span(table), None)
            lines += [f"OutputVariable: {_name(name, 'output')}", "  enabled: true",
                      f"  range: {_number(lo)} {_number(hi)}", "  lock-range: false",
                      "  aggregation: none", f"  defuzzifier: {defuzz}", _default(system, k),
                      "  lock-previous: false"]
            lines += [_consequent_term(j, c) for j, c in enumerate(table, start=1)]
        term_names = [[f"c{j}" for j in range(1, len(t) + 1)] for t in tables]
    lines += ["RuleBlock: rules", "  enabled: true",
              f"  conjunction: {fuzzylite_name(system.tnorm)}",
              f"  disjunction: {fuzzylite_name(system.snorm)}",
              f"  implication: {implication or 'none'}", "  activation: General"]
    names = system.output_names
    for rule, outs in zip(system.rules, which, strict=True):
        props = [f"{inp.name} is {'not ' if neg else ''}{label}"
                 for inp, label, neg in zip(system.inputs, rule.antecedent, rule.negated,
                                            strict=True) if label is not None]
        then = [f"{names[k]} is {term_names[k][j - 1]}" for k, j in enumerate(outs) if j]
        text = f"  rule: if {f' {rule.connective.value} '.join(props)} then {' and '.join(then)}"
        if rule.weight != 1.0:
            text += f" with {_number(rule.weight)}"
        lines.append(text)
    return "\n".join(lines) + "\n"
