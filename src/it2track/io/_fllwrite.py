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
    Hedge,
    HybridSystem,
    Implication,
    Input,
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
from ..fuzzy.terms import to_fuzzylite
from ._common import widened
from ._writing import (
    consequent_tables,
    mamdani_indices,
    output_range,
    refuse_hedges,
    sugeno_span,
)
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
            name, params = to_fuzzylite(widened(s.upper, var.universe))
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


def _default(system: Any, k: int) -> str:
    zero = system.zero_firing_value(k)
    return "  default: nan" if zero is None else f"  default: {_number(zero)}"


def _lock(system: Any, k: int) -> str:
    return f"  lock-previous: {'true' if system.keeps_previous(k) else 'false'}"


def _part(system: Any) -> tuple[list[str], list[list[str]], list[list[int]], str]:
    """One part's output sections, each output's term names, each rule's term indices and the
    implication (``none`` unless Mamdani)."""
    lines: list[str] = []
    if isinstance(system, T1Mamdani | T1Tsukamoto):
        if isinstance(system, T1Mamdani):
            if system.defuzzifier not in _DEFUZZIFIERS:
                raise UnsupportedFeatureError(
                    f"fuzzylite has no defuzzifier {system.defuzzifier.value!r} (Octave's "
                    "trapezoid-rule centroid); save as .fis or .toml")
            if system.sampling is not Sampling.MIDPOINTS:
                raise UnsupportedFeatureError(
                    "fuzzylite samples a Mamdani output at the midpoints of N cells; this "
                    f"system samples {system.resolution} points including the ends (MATLAB's); "
                    "use dataclasses.replace(system, sampling=Sampling.MIDPOINTS, "
                    "resolution=N) or save as .fis or .toml")
            defuzz = f"{_DEFUZZIFIERS[system.defuzzifier]} {system.resolution}"
        else:
            defuzz = f"{_WEIGHTED[system.defuzzifier]} Tsukamoto"
        for k, out in enumerate(system.outputs):
            extra = ["  lock-range: false",
                     f"  aggregation: {fuzzylite_name(system.aggregation)}",
                     f"  defuzzifier: {defuzz}", _default(system, k), _lock(system, k)]
            lines += _variable("OutputVariable", out, extra, _mf_terms(out, "output"))
        implication = (fuzzylite_name(system.implication) if isinstance(system, T1Mamdani)
                       else "none")
        return (lines, [[s.name for s in out.sets] for out in system.outputs],
                mamdani_indices(system), implication)
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
                  _lock(system, k)]
        lines += [_consequent_term(j, c) for j, c in enumerate(table, start=1)]
    return lines, [[f"c{j}" for j in range(1, len(t) + 1)] for t in tables], which, "none"


def _rule_block(system: Any, name: str, term_names: list[list[str]], which: list[list[int]],
                implication: str) -> list[str]:
    lines = [f"RuleBlock: {name}", "  enabled: true",
             f"  conjunction: {fuzzylite_name(system.tnorm)}",
             f"  disjunction: {fuzzylite_name(system.snorm)}",
             f"  implication: {implication}", "  activation: General"]
    names = system.output_names
    for r, (rule, outs) in enumerate(zip(system.rules, which, strict=True)):
        props = [f"{inp.name} is {'not ' if neg else ''}{_hedge_words(hedges, r)}{label}"
                 for inp, label, neg, hedges in zip(system.inputs, rule.antecedent, rule.negated,
                                                    rule.hedges, strict=True) if label is not None]
        written = _conclusion_hedges(rule, [k for k, j in enumerate(outs) if j], r)
        then = [f"{names[k]} is {written[k]}{term_names[k][j - 1]}"
                for k, j in enumerate(outs) if j]
        text = f"  rule: if {f' {rule.connective.value} '.join(props)} then {' and '.join(then)}"
        if rule.weight != 1.0:
            text += f" with {_number(rule.weight)}"
        lines.append(text)
    return lines


def _hedge_words(hedges: Sequence[Hedge], r: int) -> str:
    """``"very extremely "`` (fuzzylite's named hedges only)."""
    for h in hedges:
        if h.name == "power":
            raise UnsupportedFeatureError(f"rule {r + 1}: the hedge {str(h)!r} (Octave's power) "
                                          "has no fuzzylite name")
    return "".join(f"{h.name} " for h in hedges)


def _conclusion_hedges(rule: Rule, acting: list[int], r: int) -> dict[int, str]:
    """The hedges to write on each conclusion: fuzzylite hands a conclusion's hedged degree
    on to the conclusions after it, so each writes what its hedges add to those before."""
    out: dict[int, str] = {}
    before: tuple[Hedge, ...] = ()
    for k in acting:
        mine = rule.consequent_hedges[k]
        if mine[len(mine) - len(before):] != before:
            raise UnsupportedFeatureError(
                f"rule {r + 1}: the hedges of its conclusions are not fuzzylite's (each "
                "conclusion's degree is the one before it, hedged further)")
        out[k] = _hedge_words(mine[: len(mine) - len(before)], r)
        before = mine
    return out


def dumps(system: AnySystem) -> str:
    """``.fll`` text for a type-1 system (a :class:`~it2track.fuzzy.HybridSystem` of them: one
    rule block per part).

    Raises
    ------
    UnsupportedFeatureError
        For a type-2 system, interval consequents, MFs without a fuzzylite term, Mamdani
        outputs sampled at MATLAB's points, names that are not fuzzylite identifiers, Octave's
        power hedges, and a T1Sugeno aggregation (fuzzylite groups terms by name, not value).
    """
    refuse_hedges(system, ".fll", hedges=False, lock_previous=False)
    parts = system.systems if isinstance(system, HybridSystem) else (system,)
    for part in parts:
        if isinstance(part, IT2Sugeno | IT2Mamdani):
            raise UnsupportedFeatureError(
                "fuzzylite has no type-2 systems; save as .t2fis, .fis or .toml")
        if not isinstance(part, T1Sugeno | T1Mamdani | T1Tsukamoto):
            raise TypeError(f"can only write type-1 systems to .fll, got "
                            f"{type(part).__name__}")
    if any(ch in system.name for ch in "#\n\r"):
        raise UnsupportedFeatureError(f"system name {system.name!r} holds '#' or a line break")
    lines = [f"Engine: {system.name}".rstrip()]
    for inp in parts[0].inputs:
        lines += _variable("InputVariable", inp, ["  lock-range: true"],
                           _mf_terms(inp, "input"))
    blocks = []
    for k, part in enumerate(parts, start=1):
        out_lines, term_names, which, implication = _part(part)
        lines += out_lines
        blocks += _rule_block(part, f"rules{k}" if len(parts) > 1 else "rules", term_names,
                              which, implication)
    return "\n".join(lines + blocks) + "\n"
