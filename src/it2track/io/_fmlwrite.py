"""Writing IEEE 1855 FML (the layout and what it carries: :mod:`.fml`)."""

from __future__ import annotations

import math
from typing import Any
from xml.sax.saxutils import quoteattr

from ..fuzzy import (
    AnySystem,
    Discrete,
    Gaussian,
    GaussianProduct,
    HybridSystem,
    Input,
    IT2Mamdani,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    PiShape,
    Ramp,
    Rectangle,
    Sampling,
    SShape,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    ZShape,
)
from ..fuzzy.mamdani import RESOLUTION
from ._common import widened
from ._fmlread import ACCUMULATIONS, AND, DEFUZZIFIERS, NAMESPACE, OR
from ._writing import consequent_tables, mamdani_indices, refuse_hedges
from .errors import UnsupportedFeatureError

__all__ = ["dumps"]

# the schema's spellings (bounded difference BSUM, drastic product DRS among the t-norms)
_AND = {v: k for k, v in AND.items() if k not in ("BDIF", "DRP")}
_OR = {v: k for k, v in OR.items()}
_ACCU = {v: k for k, v in ACCUMULATIONS.items()}
_DEFUZZ = {v: k for k, v in DEFUZZIFIERS.items()}


def _number(x: float) -> str:
    value = float(x)
    if not math.isfinite(value):
        raise UnsupportedFeatureError(f"cannot write the non-finite number {value!r} to FML")
    return repr(value)


def _name(text: str, what: str) -> str:
    """A name as a quoted attribute. The schema makes names xs:ID (XML names, unique), which
    JFML's own examples do not keep ("tipper - TSK"); it2track writes any printable name."""
    if not text.strip() or any(ord(ch) < 32 for ch in text):
        raise UnsupportedFeatureError(f"{what} {text!r} is empty or holds control characters")
    return quoteattr(text)


def _shape(mf: MembershipFunction, universe: tuple[float, float], what: str) -> str:
    mf = widened(mf, universe)
    if float(getattr(mf, "h", 1.0)) != 1.0:
        raise UnsupportedFeatureError(f"{what} has a height; IEEE 1855's shapes have none")
    lo, hi = universe
    kind = type(mf)
    p: tuple[float, ...]
    if kind is Triangle:
        assert isinstance(mf, Triangle)
        tag, p = "triangularShape", (mf.a, mf.b, mf.c)
    elif kind is Trapezoid:
        assert isinstance(mf, Trapezoid)
        tag, p = "trapezoidShape", (mf.a, mf.b, mf.c, mf.d)
    elif kind is Ramp:
        assert isinstance(mf, Ramp)
        rising = mf.start < mf.end
        tag = "rightLinearShape" if rising else "leftLinearShape"
        p = (mf.start, mf.end) if rising else (mf.end, mf.start)
    elif kind is Gaussian:
        assert isinstance(mf, Gaussian)
        tag, p = "gaussianShape", (mf.mean, mf.sigma)
    elif kind is GaussianProduct and isinstance(mf, GaussianProduct) and (
            mf.mean_a <= lo and mf.sigma_a == mf.sigma_b):
        tag, p = "leftGaussianShape", (mf.mean_b, mf.sigma_b)
    elif kind is GaussianProduct and isinstance(mf, GaussianProduct) and (
            mf.mean_b >= hi and mf.sigma_a == mf.sigma_b):
        tag, p = "rightGaussianShape", (mf.mean_a, mf.sigma_a)
    elif kind in (SShape, ZShape):
        tag = "sShape" if kind is SShape else "zShape"
        p = (mf.start, mf.end)  # type: ignore[attr-defined]
    elif kind is PiShape:
        assert isinstance(mf, PiShape)
        tag, p = "piShape", (mf.bottom_left, mf.top_left, mf.top_right, mf.bottom_right)
    elif kind is Discrete:
        assert isinstance(mf, Discrete)
        points = "".join(f'<point x="{_number(x)}" y="{_number(y)}"/>' for x, y in mf.points)
        return f'<pointSetShape interpolationMethod="linear">{points}</pointSetShape>'
    elif kind is Rectangle:
        assert isinstance(mf, Rectangle)
        tag, p = "rectangularShape", (mf.start, mf.end)
    else:
        raise UnsupportedFeatureError(
            f"{what} is a {kind.__name__}, which IEEE 1855 has no shape for (it has triangles, "
            "trapezoids, linear, Gaussian, S, Z, Pi and rectangular shapes); save as .toml")
    params = " ".join(f"param{k}={quoteattr(_number(v))}" for k, v in enumerate(p, start=1))
    return f"<{tag} {params}/>"


def _terms(var: Input, kind: str) -> list[str]:
    lines = []
    for s in var.sets:
        what = f"{kind} {var.name!r} term {s.name!r}"
        if not s.is_type1:
            raise UnsupportedFeatureError(f"{what} has a footprint; IEEE 1855 is type-1")
        lines += [f'      <fuzzyTerm name={_name(s.name, "term")} complement="false">',
                  f"        {_shape(s.upper, var.universe, what)}", "      </fuzzyTerm>"]
    return lines


def _default(system: Any, k: int) -> str:
    zero = system.zero_firing_value(k)
    return "NaN" if zero is None else _number(zero)


def _clauses(tag: str, pairs: list[tuple[str, str]], indent: str) -> list[str]:
    lines = []
    for variable, term in pairs:
        lines += [f"{indent}<{tag}>", f"{indent}  <variable>{_escape(variable)}</variable>",
                  f"{indent}  <term>{_escape(term)}</term>", f"{indent}</{tag}>"]
    return lines


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _part(system: Any, k: int) -> tuple[list[str], list[str]]:
    """The knowledge-base lines of one part's outputs and its rule base."""
    variables: list[str] = []
    mamdani = isinstance(system, T1Mamdani)
    names = system.output_names
    if mamdani:
        if system.defuzzifier not in _DEFUZZ:
            raise UnsupportedFeatureError(
                f"IEEE 1855 has no defuzzifier {system.defuzzifier.value!r} (Octave's "
                "trapezoid-rule centroid); save as .fis or .toml")
        if system.resolution != RESOLUTION or system.sampling is not Sampling.ENDPOINTS:
            raise UnsupportedFeatureError(
                f"IEEE 1855 carries no sampling: it2track reads FML Mamdani outputs at MATLAB's "
                f"{RESOLUTION} points; this system samples {system.resolution} "
                f"({system.sampling.value}); save as .toml")
        for j, out in enumerate(system.outputs):
            variables += [
                f"    <fuzzyVariable name={_name(out.name, 'output')} "
                f'domainleft="{_number(out.universe[0])}" '
                f'domainright="{_number(out.universe[1])}" type="output" '
                f'accumulation="{_ACCU[system.aggregation]}" '
                f'defuzzifier="{_DEFUZZ[system.defuzzifier]}" '
                f'defaultValue="{_default(system, j)}">',
                *_terms(out, "output"), "    </fuzzyVariable>"]
        which = mamdani_indices(system)
        terms = [[s.name for s in out.sets] for out in system.outputs]
    else:
        tables, which = consequent_tables(system)
        for j, (name, table) in enumerate(zip(names, tables, strict=True)):
            variables.append(f"    <tskVariable name={_name(name, 'output')} type=\"output\" "
                             f'combination="WA" defaultValue="{_default(system, j)}">')
            for t, cons in enumerate(table, start=1):
                if isinstance(cons, Linear):
                    order, values = 1, [cons.constant_lo, *cons.lo]
                else:
                    assert isinstance(cons, tuple)
                    order, values = 0, [cons[0]]
                variables.append(f'      <tskTerm name="{name}_c{t}" order="{order}">')
                variables += [f"        <tskValue>{_number(v)}</tskValue>" for v in values]
                variables.append("      </tskTerm>")
            variables.append("    </tskVariable>")
        terms = [[f"{name}_c{t}" for t in range(1, len(table) + 1)]
                 for name, table in zip(names, tables, strict=True)]
    base = "mamdaniRuleBase" if mamdani else "tskRuleBase"
    implication = _AND[TNorm.from_name(system.implication.value)] if mamdani else "PROD"
    rules = [f'  <{base} name="rulebase{k}" activationMethod="{implication}" '
             f'andMethod="{_AND[system.tnorm]}" orMethod="{_OR[system.snorm]}">']
    rule_tag, cons_tags = (("rule", ("consequent", "then", "clause")) if mamdani
                           else ("tskRule", ("tskConsequent", "tskThen", "tskClause")))
    for r, (rule, outs) in enumerate(zip(system.rules, which, strict=True), start=1):
        if any(rule.negated):
            raise UnsupportedFeatureError(
                "IEEE 1855 complements terms, not a rule's propositions: a rule with NOT cannot "
                "be written; save as .toml")
        rules.append(f'    <{rule_tag} name="rule{k}_{r}" connector="{rule.connective.value}" '
                     f'weight="{_number(rule.weight)}">')
        ante = [(inp.name, label) for inp, label in zip(system.inputs, rule.antecedent,
                                                         strict=True) if label is not None]
        then = [(names[o], terms[o][j - 1]) for o, j in enumerate(outs) if j]
        rules += ["      <antecedent>", *_clauses("clause", ante, "        "),
                  "      </antecedent>", f"      <{cons_tags[0]}>", f"        <{cons_tags[1]}>",
                  *_clauses(cons_tags[2], then, "          "), f"        </{cons_tags[1]}>",
                  f"      </{cons_tags[0]}>", f"    </{rule_tag}>"]
    rules.append(f"  </{base}>")
    return variables, rules


def dumps(system: AnySystem) -> str:
    """IEEE 1855 FML text for a type-1 Mamdani or Sugeno system (or a
    :class:`~it2track.fuzzy.HybridSystem` of them).

    Raises
    ------
    UnsupportedFeatureError
        For type-2 and Tsukamoto systems, MFs without an IEEE 1855 shape, heights, NOT in a
        rule, hedges, a Mamdani sampling other than MATLAB's 101 points and names that are
        not XML names.
    """
    refuse_hedges(system, "FML")
    parts = system.systems if isinstance(system, HybridSystem) else (system,)
    for part in parts:
        if isinstance(part, IT2Sugeno | IT2Mamdani):
            raise UnsupportedFeatureError("IEEE 1855 FML is type-1; save as .t2fis, .fis or "
                                          ".toml")
        if not isinstance(part, T1Sugeno | T1Mamdani):
            raise UnsupportedFeatureError(f"FML cannot carry a {type(part).__name__} here; save "
                                          "as .fll or .toml")
    if any(ord(ch) < 32 for ch in system.name):
        raise UnsupportedFeatureError(f"system name {system.name!r} holds control characters")
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<fuzzySystem xmlns="{NAMESPACE}" name={quoteattr(system.name)}>',
             "  <knowledgeBase>"]
    for inp in parts[0].inputs:
        lines += [f"    <fuzzyVariable name={_name(inp.name, 'input')} "
                  f'domainleft="{_number(inp.universe[0])}" '
                  f'domainright="{_number(inp.universe[1])}" type="input">',
                  *_terms(inp, "input"), "    </fuzzyVariable>"]
    bases = []
    for k, part in enumerate(parts, start=1):
        variables, rules = _part(part, k)
        lines += variables
        bases += rules
    lines += ["  </knowledgeBase>", *bases, "</fuzzySystem>"]
    return "\n".join(lines) + "\n"
