"""Fuzzy-aware helpers shared by the readers of MATLAB-syntax files (and used by the others).

Membership-function conversion between MATLAB's parameter vectors and our classes, rule
building with line-accurate errors, and a guard that turns numeric trouble and the fuzzy core's
``ValueError`` into :class:`~it2track.io.errors.FisFormatError`. The writers' helpers are in
:mod:`._writing`.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from collections.abc import Iterator, Sequence

import numpy as np

from ..fuzzy import (
    AnySystem,
    Consequent,
    FootedTrapezoid,
    Hedge,
    Input,
    IT2Set,
    Linear,
    MembershipFunction,
    PiecewiseLinear,
    Rule,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianUpper,
)
from ..fuzzy.terms import MATLAB_MFS, from_fuzzylite, to_matlab
from ._matlab import Document, MFValue, ParsedRule
from ._writing import fmt_string, fmt_vector
from .errors import FisFormatError, UnsupportedFeatureError

__all__ = [
    "FUZZYLITE_FIS_NAMES",
    "build_input",
    "build_rules",
    "footed",
    "guard",
    "linear_from",
    "mf_from_matlab",
    "mf_line",
    "mf_to_matlab",
    "set_name",
    "shoulder_problem",
    "system_of",
    "widened",
]

#: fuzzylite's ``.fis`` names of its own terms (parameters in fuzzylite's order)
FUZZYLITE_FIS_NAMES = {
    "rampmf": "Ramp", "rectmf": "Rectangle", "cosinemf": "Cosine", "spikemf": "Spike",
    "concavemf": "Concave", "discretemf": "Discrete", "binarymf": "Binary",
}


@contextlib.contextmanager
def guard(doc: Document, line: int | None, what: str = "") -> Iterator[None]:
    """Turn the fuzzy core's ``ValueError`` and numeric overflow into ``FisFormatError``."""
    prefix = f"{what}: " if what else ""
    try:
        with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
            yield
    except FisFormatError:
        raise
    except FloatingPointError as exc:
        raise doc.error(line, f"{prefix}numeric overflow ({exc}); check the magnitudes") from None
    except (ValueError, TypeError, OverflowError) as exc:
        raise doc.error(line, f"{prefix}{exc}") from None


# ---------------------------------------------------------------------------------------------
# Membership functions
# ---------------------------------------------------------------------------------------------


def mf_from_matlab(doc: Document, mfv: MFValue, *, with_height: bool) -> MembershipFunction:
    """Our MF for ``'type',[params]`` (toolbox convention: ``with_height`` appends ``h``).

    MATLAB's functions go through :func:`~it2track.fuzzy.terms.from_matlab`'s table; a lenient
    document also reads fuzzylite's names of its own terms (``'rampmf'``, ``'cosinemf'``, ...,
    parameters in fuzzylite's order) and MATLAB's extra parameters (ignored, with a warning).
    A ``gauss2mf`` with equal sigmas and ``c1 <= c2`` is our uncertain-mean Gaussian upper MF
    (the same function).
    """
    kind = mfv.type
    spec = MATLAB_MFS.get(kind)
    if kind == "function":
        raise doc.error(mfv.line, f"MF {mfv.name!r}: fuzzylite's 'function' (a formula) is read "
                        "in a .fis as a Takagi-Sugeno output's consequent only (a membership "
                        "Function is read from fuzzylite's .fll)")
    if spec is None:
        if doc.lenient and kind in FUZZYLITE_FIS_NAMES:
            with guard(doc, mfv.line, f"MF {mfv.name!r}"):
                return from_fuzzylite(FUZZYLITE_FIS_NAMES[kind], mfv.params)
        known = ", ".join([*MATLAB_MFS, *(FUZZYLITE_FIS_NAMES if doc.lenient else ())])
        raise doc.error(mfv.line, f"unknown MF type {kind!r} (known: {known})")
    n = spec.count + (1 if with_height else 0)
    p = list(mfv.params)
    if len(p) > n and doc.lenient:
        doc.warn(mfv.line, f"{kind} {fmt_vector(p)} has {len(p)} parameters; read as "
                 f"{fmt_vector(p[:n])}, as MATLAB's {kind} uses the first {n}")
        p = p[:n]
    if len(p) != n:
        form = spec.params[:-1] + (" h]" if with_height else "]")
        raise doc.error(
            mfv.line, f"{kind} needs {n} parameters {form}, got {len(mfv.params)}"
        )
    h = p.pop() if with_height else 1.0
    with guard(doc, mfv.line, f"MF {mfv.name!r}"):
        if kind == "gauss2mf" and p[0] == p[2] and p[1] <= p[3]:
            return UncertainMeanGaussianUpper(p[1], p[3], p[0], h)
        return spec.build(p, h)


def mf_to_matlab(
    mf: MembershipFunction, *, with_height: bool, what: str
) -> tuple[str, tuple[float, ...]]:
    """``(type, params)`` of one of our MFs (``with_height``: the height appended); ``what``
    names it in errors."""
    h = float(getattr(mf, "h", 1.0))
    try:
        kind, params = to_matlab(mf if h == 1.0 else dataclasses.replace(mf, h=1.0))  # type: ignore[type-var]
    except (ValueError, TypeError):
        raise UnsupportedFeatureError(
            f"{what} is a {type(mf).__name__}, which has no MATLAB MF type (these formats carry "
            f"{', '.join(MATLAB_MFS)}); save as .toml"
        ) from None
    values = tuple(float(v) for v in params)
    if with_height:
        return kind, (*values, h)
    if h != 1.0:
        raise UnsupportedFeatureError(
            f"{what} has height h={h!r}; MATLAB's {kind} has no height parameter (only 1)"
        )
    return kind, values


def shoulder_problem(mf: MembershipFunction, universe: tuple[float, float], label: str,
                     tool: str) -> str | None:
    """Why a triangle/trapezoid ``mf`` read from a tool cannot be ours, or ``None``.

    MATLAB's, fuzzylite's and jFuzzyLogic's triangles and trapezoids are 0 outside their feet,
    even next to a shoulder (``a == b``), while ours keep their height beyond the peak side
    (DESIGN.md sec. 2); they agree on the universe when each shoulder's foot is at or beyond
    its end. ``label`` names the MF as written, ``tool`` the tool's function.
    """
    if not isinstance(mf, PiecewiseLinear):
        return None
    a, b, c, d, _ = mf.as_trapezoid()
    lo, hi = universe
    for shoulder, foot, inside, side in ((a == b, a, a > lo, "left"), (c == d, d, d < hi, "right")):
        if shoulder and inside:
            return (f"{label} has a {side} shoulder at x={foot:g} inside the range "
                    f"[{lo:g} {hi:g}]: {tool} drops to 0 beyond it, which it2track's shoulders "
                    "(constant beyond the peak) cannot represent; move the shoulder to the range "
                    "end")
    return None


def footed(mf: MembershipFunction, universe: tuple[float, float]) -> MembershipFunction:
    """``mf`` as the tools read it: a triangle/trapezoid with a shoulder inside the universe
    (:func:`shoulder_problem`) is 0 beyond its foot there, a :class:`FootedTrapezoid`."""
    if isinstance(mf, PiecewiseLinear) and shoulder_problem(mf, universe, "", "") is not None:
        return FootedTrapezoid(*mf.as_trapezoid())
    return mf


def widened(mf: MembershipFunction, universe: tuple[float, float]) -> MembershipFunction:
    """``mf`` with a shoulder inside the universe moved out to its end: the same values on the
    universe, and the same for tools whose triangles and trapezoids are 0 beyond their feet
    (:func:`shoulder_problem`)."""
    if type(mf) not in (Triangle, Trapezoid):
        return mf
    assert isinstance(mf, PiecewiseLinear)
    a, b, c, d, h = mf.as_trapezoid()
    lo, hi = universe
    left, right = a == b and a > lo, c == d and d < hi
    if not (left or right):
        return mf
    if left:
        a = b = lo
    if right:
        c = d = hi
    return Trapezoid(a, b, c, d, h)


def mf_line(key: str, name: str, kind: str, params: Sequence[float], what: str) -> str:
    """``key='name':'kind',[params]``."""
    return f"{key}={fmt_string(name, what)}:'{kind}',{fmt_vector(params)}"


def set_name(upper: str, lower: str) -> str:
    """One name for a toolbox ``U``/``L`` pair: ``'NU'``/``'NL'`` -> ``'N'``, else the upper's."""
    if (
        len(upper) > 1
        and upper[-1] == "U"
        and lower[-1:] == "L"
        and upper[:-1] == lower[:-1]
    ):
        return upper[:-1]
    return upper


# ---------------------------------------------------------------------------------------------
# Inputs, rules, systems
# ---------------------------------------------------------------------------------------------


def build_input(
    doc: Document,
    name: str,
    universe: tuple[float, float],
    sets: Sequence[tuple[IT2Set, int, int]],
    line: int,
) -> Input:
    """An :class:`Input`; ``sets`` are ``(set, upper_line, lower_line)``.

    Each set is checked on the universe first, so that an error names the line of the MF at
    fault (``lower MF ... exceeds upper MF`` names the lower MF's line).
    """
    seen: dict[str, int] = {}
    for s, up_line, _ in sets:
        if not s.name:
            raise doc.error(up_line, "empty MF name")
        if s.name in seen:
            raise doc.error(
                up_line, f"duplicate MF name {s.name!r} in input {name!r} (first at line "
                f"{seen[s.name]})"
            )
        seen[s.name] = up_line
    for s, up_line, low_line in sets:
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                s.check_on(universe, owner=f"input {name!r}")
        except FloatingPointError as exc:
            raise doc.error(up_line, f"numeric overflow evaluating MF {s.name!r} ({exc})") from None
        except ValueError as exc:
            text = str(exc)
            at_upper = ": upper MF" in text
            raise doc.error(up_line if at_upper else low_line, text) from None
    with guard(doc, line, f"input {name!r}"):
        return Input(name, universe, [s for s, _, _ in sets])


def build_rules(
    doc: Document,
    parsed: Sequence[ParsedRule],
    inputs: Sequence[Input],
    consequents: Sequence[Sequence[Consequent]],
    *,
    hedges: str | None = None,
) -> list[Rule]:
    """Our rules from indexed rules.

    ``consequents[k][j - 1]`` is what output ``k``'s index ``j`` means (an interval, a
    :class:`Linear` or an output set label). Index 0 leaves an output out of the rule; a
    negative antecedent index ``-j`` is ``NOT`` set ``j``; connection 1 is AND, 2 is OR; the
    weight must be in ``[0, 1]``. A fractional index is a hedge: with ``hedges="fuzzylite"``
    fuzzylite's (``.01`` seldom, ``.05`` somewhat, ``.2`` very, ``.3`` extremely, ``.4`` very
    very, ``.99`` any; a hedged Sugeno conclusion hands its degree on, as fuzzylite does);
    with ``"octave"`` Octave's powers (the fraction in hundredths over 10: ``2.3`` is set 2
    to the power 3 on an antecedent, the rule's firing to the power 1/3 on a Sugeno
    conclusion; fuzzy-logic-toolkit's ``get_mf_index_and_hedge``, ``evalmf``,
    ``eval_rules_sugeno``); ``None`` refuses them. Hedged Mamdani conclusions are refused.
    """
    rules = []
    for pr in parsed:
        antecedent: list[str | None] = []
        negated: list[bool] = []
        hedged: list[tuple[Hedge, ...]] = []
        for inp, code in zip(inputs, pr.antecedent, strict=True):
            index, words = _index(doc, pr.line, code, hedges)
            hedged.append(words)
            if abs(index) > len(inp.sets):
                raise doc.error(
                    pr.line,
                    f"rule names MF {index} of input {inp.name!r}, which has only "
                    f"{len(inp.sets)}",
                )
            antecedent.append(None if index == 0 else inp.sets[abs(index) - 1].name)
            negated.append(index < 0)
        if all(a is None for a in antecedent):
            raise doc.error(pr.line, "rule mentions no input (all antecedent indices are 0)")
        cons: list[Consequent] = []
        cons_hedges: list[tuple[Hedge, ...]] = []
        carried: tuple[Hedge, ...] = ()
        for k, (code, table) in enumerate(zip(pr.consequent, consequents, strict=True)):
            out, words = _index(doc, pr.line, code, hedges)
            if (words or out < 0) and not isinstance(table[0] if table else None,
                                                     tuple | Linear):
                raise doc.error(pr.line, f"a hedge or NOT on the conclusion of a Mamdani output "
                                f"({code:g}) is not supported")
            if hedges == "octave":  # Octave: the firing to the power 1 / p, this output only
                words = tuple(Hedge.power(1.0 / h.exponent) for h in words)
                cons_hedges.append(words)
                if out < 0:
                    cons_hedges[-1] = (Hedge("not"), *words)
                    out = -out
            else:
                if words or carried:
                    carried = words + carried
                cons_hedges.append(carried if out != 0 else ())
            if out < 0:
                raise doc.error(pr.line, f"negated consequent ({out}) is not supported")
            if out > len(table):
                raise doc.error(
                    pr.line, f"rule names output MF {out}, but output {k + 1} has only "
                    f"{len(table)}"
                )
            cons.append(None if out == 0 else table[out - 1])
        if all(c is None for c in cons):
            raise doc.error(pr.line, "rule has no consequent (every output index is 0)")
        if not 0.0 <= pr.weight <= 1.0:
            raise doc.error(pr.line, f"rule weight {pr.weight:g} must be in [0, 1]")
        if pr.connection not in (1, 2):
            raise doc.error(
                pr.line, f"rule connection {pr.connection} must be 1 (AND) or 2 (OR)"
            )
        with guard(doc, pr.line, "rule"):
            rules.append(Rule(antecedent, consequents=cons, weight=pr.weight,
                              connective="or" if pr.connection == 2 else "and",
                              negated=negated, hedges=hedged,
                              consequent_hedges=cons_hedges))
    return rules


#: Octave's and fuzzylite's hedges, by the fraction of a rule index (in hundredths)
_HEDGES = {1: "seldom", 5: "somewhat", 20: "very", 30: "extremely", 40: "very very", 99: "any"}


def _index(doc: Document, line: int, code: float, hedges: str | None
           ) -> tuple[int, tuple[Hedge, ...]]:
    """A rule index as an integer and its hedges (see :func:`build_rules`)."""
    whole = math.trunc(code)
    if code == whole:
        return int(whole), ()
    hundredths = round(100 * (abs(code) - abs(whole)))
    hedge = _HEDGES.get(hundredths)
    if hedges == "fuzzylite" and hedge is not None and whole != 0:
        return int(whole), tuple(Hedge(w) for w in hedge.split())
    if hedges == "fuzzylite" and hedge == "any" and whole == 0 and code > 0:
        return 1, (Hedge("any"),)  # fuzzylite's 'x is any' (no term): any term's hedge is 1
    if hedges == "octave" and whole != 0 and hundredths > 0:
        return int(whole), (Hedge.power(hundredths / 10),)
    meaning = f" (the hedge {hedge!r} of Octave and fuzzylite)" if hedge else ""
    raise doc.error(line, f"rule index {code:g} has a fraction{meaning}: hedges are not "
                    "supported")


def linear_from(doc: Document, mfv: MFValue, n_inputs: int, *, interval: bool) -> Linear:
    """A ``'linear',[c1 ... cn c0]`` output MF (with ``interval``, also
    ``[c1_lo ... cn_lo c0_lo c1_hi ... cn_hi c0_hi]``)."""
    n = n_inputs + 1
    p = list(mfv.params)
    if len(p) == n:
        lo = hi = p
    elif interval and len(p) == 2 * n:
        lo, hi = p[:n], p[n:]
    else:
        form = f"{n} numbers [c1 ... c{n_inputs} c0]" + (
            f" or {2 * n} (lower then upper coefficients)" if interval else "")
        raise doc.error(mfv.line, f"'linear' needs {form}, got {len(p)}")
    for a, b in zip(lo, hi, strict=True):
        if a > b:
            raise doc.error(mfv.line, f"linear coefficient interval [{a:g} {b:g}] must "
                            "satisfy lower <= upper")
    with guard(doc, mfv.line, f"MF {mfv.name!r}"):
        return Linear(list(zip(lo[:-1], hi[:-1], strict=True)), (lo[-1], hi[-1]))


def system_of(
    doc: Document,
    line: int | None,
    cls: type,
    **options: object,
) -> AnySystem:
    """Construct the system, turning the core's ``ValueError`` into ``FisFormatError``."""
    with guard(doc, line):
        system: AnySystem = cls(**options)
        return system
