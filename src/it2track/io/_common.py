"""Fuzzy-aware helpers shared by the ``.t2fis`` and ``.fis`` readers and writers.

Membership-function conversion between MATLAB's parameter vectors and our classes, rule
building with line-accurate errors, and a guard that turns numeric trouble and the fuzzy core's
``ValueError`` into :class:`~it2track.io.errors.FisFormatError`.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from collections.abc import Iterator, Sequence

import numpy as np

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Connective,
    Consequent,
    Defuzzifier,
    HybridSystem,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    PiecewiseLinear,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianUpper,
    WeightedDefuzzifier,
)
from ..fuzzy.terms import MATLAB_MFS, from_fuzzylite, to_matlab
from ._matlab import Document, MFValue, ParsedRule
from .errors import FisFormatError, UnsupportedFeatureError

__all__ = [
    "FUZZYLITE_FIS_NAMES",
    "build_input",
    "build_rules",
    "check_writable",
    "consequent_tables",
    "fmt_number",
    "fmt_rule",
    "fmt_string",
    "fmt_vector",
    "guard",
    "linear_from",
    "mamdani_indices",
    "mf_from_matlab",
    "mf_line",
    "mf_to_matlab",
    "output_range",
    "set_name",
    "shoulder_problem",
    "sugeno_span",
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
) -> list[Rule]:
    """Our rules from indexed rules.

    ``consequents[k][j - 1]`` is what output ``k``'s index ``j`` means (an interval, a
    :class:`Linear` or an output set label). Index 0 leaves an output out of the rule; a
    negative antecedent index ``-j`` is ``NOT`` set ``j``; connection 1 is AND, 2 is OR; the
    weight must be in ``[0, 1]``.
    """
    rules = []
    for pr in parsed:
        antecedent: list[str | None] = []
        negated: list[bool] = []
        for inp, code in zip(inputs, pr.antecedent, strict=True):
            index = _whole(doc, pr.line, code)
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
        for k, (code, table) in enumerate(zip(pr.consequent, consequents, strict=True)):
            out = _whole(doc, pr.line, code)
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
                              negated=negated))
    return rules


#: Octave's and fuzzylite's hedges, by the fraction of a rule index (in hundredths)
_HEDGES = {1: "seldom", 5: "somewhat", 20: "very", 30: "extremely", 40: "very very", 99: "any"}


def _whole(doc: Document, line: int, code: float) -> int:
    """A rule index as an integer; a fraction is Octave's and fuzzylite's hedge, refused."""
    whole = math.trunc(code)
    if code == whole:
        return int(whole)
    hundredths = round(100 * (abs(code) - abs(whole)))
    hedge = _HEDGES.get(hundredths)
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


# ---------------------------------------------------------------------------------------------
# Writers
# ---------------------------------------------------------------------------------------------


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


def check_writable(system: object, fmt: str) -> None:
    if isinstance(system, T1Tsukamoto | HybridSystem):
        raise UnsupportedFeatureError(
            f"the {fmt} format cannot carry a {type(system).__name__}; save as .fll")
    if not isinstance(system, IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani):
        raise TypeError(f"can only write IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani systems "
                        f"to {fmt}, got {type(system).__name__}")
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
        ("aggregation", getattr(system, "aggregation", Aggregation.MAXIMUM),
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

