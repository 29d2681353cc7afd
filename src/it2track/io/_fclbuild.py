"""The meaning of a parsed FCL function block (:mod:`._fclparse`): an it2track system, or a
:class:`~it2track.io.FisFormatError` naming the line and the feature (the rules are in
:mod:`.fcl`'s docstring)."""

from __future__ import annotations

import itertools
import math
import sys
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from ..fuzzy import (
    Aggregation,
    Bell,
    Consequent,
    Cosine,
    Defuzzifier,
    Discrete,
    Gaussian,
    GaussianProduct,
    Linear,
    MembershipFunction,
    Sigmoid,
    SigmoidDifference,
    SNorm,
    TNorm,
    Trapezoid,
    Triangle,
    WeightedDefuzzifier,
)
from ..fuzzy.formula import Formula, FormulaError
from ..fuzzy.terms import FUZZYLITE_TERMS, from_fuzzylite, fuzzylite_consequent
from ._chainread import ChainRefused, chained_formula
from ._common import footed
from ._fclparse import FclTerm, FclVar, Parser
from ._ruletree import DUALS
from .errors import FisFormatError

__all__ = ["ACCU", "AND", "MAMDANI", "OR", "PARTNER_OF_OR", "SUGENO", "Builder"]

AND = {"MIN": TNorm.MINIMUM, "PROD": TNorm.PRODUCT, "BDIF": TNorm.BOUNDED_DIFFERENCE,
        "DPROD": TNorm.DRASTIC_PRODUCT, "EPROD": TNorm.EINSTEIN_PRODUCT,
        "EINSTEIN": TNorm.EINSTEIN_PRODUCT, "HPROD": TNorm.HAMACHER_PRODUCT,
        "HAMACHER": TNorm.HAMACHER_PRODUCT, "NMIN": TNorm.NILPOTENT_MINIMUM,
        "NIPMIN": TNorm.NILPOTENT_MINIMUM, "DMIN": TNorm.DRASTIC_PRODUCT}
OR = {"MAX": SNorm.MAXIMUM, "ASUM": SNorm.PROBOR, "BSUM": SNorm.BOUNDED_SUM,
       "DSUM": SNorm.DRASTIC_SUM, "ESUM": SNorm.EINSTEIN_SUM, "EINSTEIN": SNorm.EINSTEIN_SUM,
       "HSUM": SNorm.HAMACHER_SUM, "HAMACHER": SNorm.HAMACHER_SUM,
       "NMAX": SNorm.NILPOTENT_MAXIMUM, "NIPMAX": SNorm.NILPOTENT_MAXIMUM,
       "DMAX": SNorm.DRASTIC_SUM, "SUM": SNorm.UNBOUNDED_SUM}
ACCU = {**{k: Aggregation.from_name(v.value) for k, v in OR.items()},
         "NSUM": Aggregation.SUM, "PROBOR": Aggregation.PROBOR}
PARTNER_OF_OR = {s: t for t, s in DUALS.items()}
MAMDANI = {"COG": Defuzzifier.CENTROID, "COA": Defuzzifier.BISECTOR, "LM": Defuzzifier.SOM,
            "RM": Defuzzifier.LOM, "MM": Defuzzifier.MOM}
SUGENO = {"COGS": WeightedDefuzzifier.AVERAGE, "COGF": WeightedDefuzzifier.AVERAGE,
           "COGSS": WeightedDefuzzifier.SUM}
#: jFuzzyLogic's named shapes: parameter count
_JFL = {"TRIAN": 3, "TRAPE": 4, "GAUSS": 2, "GAUSS2": 4, "GBELL": 3, "SIGM": 2, "DSIGM": 4,
        "COSINE": 2}


class _NotLinear(Exception):
    """A FUNCTION that is not linear in the inputs (read as a formula instead)."""


class Builder:
    def __init__(self, parser: Parser) -> None:
        self.error = parser.error
        #: rule line -> its condition as a tree, where the flat form cannot hold it (_chain)
        self.trees: dict[int, Any] = {}

    def guarded(self, line: int | None, make: Callable[[], Any], what: str = "") -> Any:
        prefix = f"{what}: " if what else ""
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                return make()
        except FisFormatError:
            raise
        except FloatingPointError as exc:
            raise self.error(line, f"{prefix}numeric overflow ({exc})") from None
        except (ValueError, TypeError, OverflowError, ZeroDivisionError) as exc:
            raise self.error(line, f"{prefix}{exc}") from None

    # -- terms ---------------------------------------------------------------------------------
    def numbers(self, term: FclTerm) -> list[float]:
        values, tokens, k = [], term.params, 0
        while k < len(tokens):
            sign = 1.0
            if tokens[k].text in ("-", "+") and k + 1 < len(tokens):
                sign, k = (-1.0 if tokens[k].text == "-" else 1.0), k + 1
            tok = tokens[k]
            if tok.kind != "num":  # a variable's name is _fclvars' (NaN and inf are no number)
                raise self.error(tok.line, f"term {term.name!r}: unexpected {tok.text!r} in the "
                                 "parameters")
            values.append(sign * float(tok.text))
            k += 1
        return values

    def points(self, term: FclTerm) -> MembershipFunction:
        pts = term.points
        xs = [x for x, _ in pts]
        ms = [m for _, m in pts]
        if any(b < a for a, b in itertools.pairwise(xs)):
            raise self.error(term.line, f"term {term.name!r}: the points {pts} must have "
                             "increasing x")
        if any(not 0.0 <= m <= 1.0 for m in ms):
            raise self.error(term.line, f"term {term.name!r}: memberships must lie in [0, 1]")
        for a, b in itertools.pairwise(xs):
            if 0.0 < b - a < sys.float_info.min:  # 1 / (b - a), the slope's factor, overflows
                raise self.error(term.line, f"term {term.name!r}: the points at x = {a!r} and "
                                 f"x = {b!r} are closer than the smallest normal float "
                                 f"({sys.float_info.min!r}): the slope between them overflows")
        h = max(ms)
        if len(set(xs)) == len(xs) and set(ms) <= {0.0, h}:  # h = 0: no pattern below
            pattern = tuple("h" if m == h else "0" for m in ms)
            shapes = {
                ("h", "0"): lambda: Triangle(xs[0], xs[0], xs[1], h),
                ("0", "h"): lambda: Triangle(xs[0], xs[1], xs[1], h),
                ("0", "h", "0"): lambda: Triangle(xs[0], xs[1], xs[2], h),
                ("h", "h", "0"): lambda: Triangle(xs[1], xs[1], xs[2], h),
                ("0", "h", "h"): lambda: Triangle(xs[0], xs[1], xs[1], h),
                ("0", "h", "h", "0"): lambda: Trapezoid(xs[0], xs[1], xs[2], xs[3], h),
            }
            if pattern in shapes:
                return self.guarded(term.line, shapes[pattern], f"term {term.name!r}")
        return self.guarded(term.line, lambda: Discrete(pts), f"term {term.name!r}")

    def shape(self, term: FclTerm, universe: tuple[float, float] | None) -> MembershipFunction:
        name = term.shape.upper()
        if name == "SINGLETONS":
            raise self.error(term.line, f"term {term.name!r}: jFuzzyLogic's generalized "
                             "singletons are not supported")
        p = self.numbers(term)
        what = f"term {term.name!r}"
        if term.shape in FUZZYLITE_TERMS:
            mf = self.guarded(term.line, lambda: from_fuzzylite(term.shape, p), what)
        elif name in _JFL:
            if len(p) != _JFL[name]:
                raise self.error(term.line, f"{what}: {name} needs {_JFL[name]} parameters, got "
                                 f"{len(p)}")
            mf = self.guarded(term.line, lambda: self._jfl(name, p), what)
        else:
            known = ", ".join([*_JFL, *FUZZYLITE_TERMS])
            raise self.error(term.line, f"{what}: unknown shape {term.shape!r} (known: {known})")
        if universe is not None:
            mf = footed(mf, universe)  # 0 beyond a foot inside the range, as the tools
        return mf

    def _jfl(self, name: str, p: list[float]) -> MembershipFunction:
        if name == "TRIAN":
            return Triangle(p[0], p[1], p[2])
        if name == "TRAPE":
            return Trapezoid(p[0], p[1], p[2], p[3])
        if name == "GAUSS":
            return Gaussian(p[0], p[1])
        if name == "GAUSS2":
            if p[0] > p[2]:
                raise ValueError(f"GAUSS2 with mean1 > mean2 ({p[0]:g} > {p[2]:g}) is not "
                                 "MATLAB's gauss2mf in jFuzzyLogic; not supported")
            return GaussianProduct(p[0], p[1], p[2], p[3])
        if name == "GBELL":
            return Bell(p[2], p[0], p[1])
        if name == "SIGM":
            return Sigmoid(p[1], p[0])
        if name == "DSIGM":
            a1, c1, a2, c2 = p
            if a1 != a2 or not ((a1 > 0 and c1 <= c2) or (a1 < 0 and c1 >= c2)):
                raise ValueError("jFuzzyLogic's DSIGM is max(s1 - s2, 0), MATLAB's dsigmf "
                                 "|s1 - s2|: they agree (and it2track reads it) for equal gains "
                                 "and a plateau only")
            return SigmoidDifference(c1, a1, a2, c2)
        if p[0] <= 0:  # COSINE half_width center
            raise ValueError(f"COSINE half width {p[0]:g} must be > 0")
        return Cosine(p[1], 2.0 * p[0])

    def mf(self, term: FclTerm, universe: tuple[float, float] | None) -> MembershipFunction:
        if term.kind == "points":  # the parser reads at least one point
            return self.points(term)
        if term.kind == "shape":
            return self.shape(term, universe)
        if term.kind == "singleton":
            raise self.error(term.line, f"term {term.name!r}: a singleton is the value of a "
                             "COGS output (or an input's Point), not a membership function of "
                             "an output without METHOD : COGS as here")
        raise self.error(term.line, f"term {term.name!r}: FUNCTION is a COGF output term")

    def consequent(self, term: FclTerm, inputs: list[str], outputs: Iterable[str] = (),
                   own: str | None = None, apart: Iterable[str] = ()) -> Consequent:
        """An output term's value; a Function reading an output (before ``own``) that is
        ``apart`` (in another system of a hybrid) is refused."""
        if term.kind == "singleton":
            return (term.value, term.value)
        if term.kind == "shape":
            p = self.numbers(term)
            value = self.guarded(term.line, lambda: fuzzylite_consequent(term.shape, p,
                                                                         len(inputs)),
                                 f"term {term.name!r}")
            return (value, value) if isinstance(value, float) else value
        # a FUNCTION (_kind reads an output as Sugeno only when every term is a value,
        # Constant/Linear or FUNCTION); fuzzylite's FCL export spells it Function, in its grammar
        dialect = "fuzzylite" if term.shape == "Function" else "jfuzzylogic"
        formula = self.formula(term, inputs, dialect, outputs, own)
        read = sorted(formula.used & set(apart))
        if read:
            raise self.error(term.line, f"term {term.name!r}: Function {formula.text!r} "
                             f"reads the output {read[0]!r}, of another kind, which "
                             f"it2track evaluates apart from {own!r}: it chains formulas "
                             "among Takagi-Sugeno outputs declared one after another")
        try:  # linear in the inputs: a Linear (compiled, written), refused if not finite
            return self.linear(term, inputs)
        except _NotLinear:
            return formula

    def formula(self, term: FclTerm, inputs: list[str], dialect: str = "jfuzzylogic",
                outputs: Iterable[str] = (), own: str | None = None) -> Formula:
        """A FUNCTION's formula of the inputs (its tokens, rejoined), and of the ``outputs``
        declared before ``own`` (fuzzylite's chained Function, :mod:`._chainread`); one
        reading ``own`` or a later output is refused as such."""
        text, starts = "", []
        for tok in term.params:
            starts.append(len(text))
            text += tok.text + " "
        text = text.rstrip()
        try:
            return chained_formula(text, dialect, inputs, list(outputs), own)
        except (FormulaError, ChainRefused) as exc:
            k = max([0, *(k for k, start in enumerate(starts) if start <= exc.position)])
            line = term.params[k].line if term.params else term.line
            where = f"FUNCTION {text!r}" if dialect == "jfuzzylogic" else f"Function {text!r}"
            sep = " " if isinstance(exc, ChainRefused) else ": "
            raise self.error(line, f"term {term.name!r}: {where}{sep}{exc}") from None

    def linear(self, term: FclTerm, inputs: list[str]) -> Linear:
        """A FUNCTION that is linear in the inputs as a :class:`Linear`, else
        :class:`_NotLinear`. :meth:`formula` has parsed it: its tokens are well formed (an
        operand after every operator, every '(' closed)."""
        tokens = term.params
        pos = 0

        def atom() -> dict[str, float]:
            nonlocal pos
            tok = tokens[pos]
            pos += 1
            if tok.text in ("-", "+"):
                inner = atom()
                return {k: -v for k, v in inner.items()} if tok.text == "-" else inner
            if tok.text == "(":
                inner = expr()
                if tokens[pos].text != ")":  # ( x ^ 2 )
                    raise _NotLinear
                pos += 1
                return inner
            if tok.kind == "num":
                return {"": float(tok.text)}
            if tok.kind == "ident" and tok.text in inputs:
                return {tok.text: 1.0}
            raise _NotLinear  # a function, a constant, an output

        def product() -> dict[str, float]:
            nonlocal pos
            left = atom()
            while pos < len(tokens) and tokens[pos].text in ("*", "/"):
                op = tokens[pos].text
                pos += 1
                right = atom()
                if op == "/":
                    if set(right) != {""} or right[""] == 0.0:  # by an input, by zero
                        raise _NotLinear
                    left = {k: v / right[""] for k, v in left.items()}
                elif set(left) == {""}:
                    left = {k: left[""] * v for k, v in right.items()}
                elif set(right) == {""}:
                    left = {k: v * right[""] for k, v in left.items()}
                else:  # input times input
                    raise _NotLinear
            return left

        def expr() -> dict[str, float]:
            nonlocal pos
            total = product()
            while pos < len(tokens) and tokens[pos].text in ("+", "-"):
                sign = 1.0 if tokens[pos].text == "+" else -1.0
                pos += 1
                for k, v in product().items():
                    total[k] = total.get(k, 0.0) + sign * v
            return total

        form = expr()
        if pos != len(tokens):  # x ^ 2
            raise _NotLinear
        coefs = [form.get(name, 0.0) for name in inputs]
        return self.guarded(term.line, lambda: Linear(coefs, form.get("", 0.0)),
                            f"term {term.name!r}")

    # -- universes -----------------------------------------------------------------------------
    def universe(self, var: FclVar) -> tuple[float, float]:
        """The RANGE, else jFuzzyLogic's estimate from the terms."""
        if var.range is not None:
            return var.range
        lo, hi = math.inf, -math.inf
        for term in var.terms.values():
            a, b = self._term_span(term)
            lo, hi = min(lo, a), max(hi, b)
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise self.error(var.block_line, f"{var.name!r}: give a RANGE")
        if lo > hi:  # only a malformed term has its feet reversed: its own check names it
            for term in var.terms.values():
                self.mf(term, None)
        return (lo, hi) if lo < hi else (lo - 1.0, hi + 1.0)

    def _term_span(self, term: FclTerm) -> tuple[float, float]:
        if term.kind == "points":
            return term.points[0][0], term.points[-1][0]
        if term.kind == "singleton":
            return term.value, term.value
        name = term.shape.upper()
        if term.kind == "shape" and name not in _JFL and term.shape not in FUZZYLITE_TERMS:
            self.shape(term, None)  # raises: unknown shape
        if term.kind != "shape" or name not in _JFL:
            raise self.error(term.line, f"term {term.name!r}: its variable needs a RANGE "
                             f"(it2track estimates one from jFuzzyLogic's shapes and points "
                             f"only)")
        p = self.numbers(term)
        if len(p) != _JFL[name]:
            raise self.error(term.line, f"term {term.name!r}: {name} needs {_JFL[name]} "
                             f"parameters, got {len(p)}")
        if name in ("TRIAN", "TRAPE"):
            return p[0], p[-1]
        if name == "GAUSS":
            return p[0] - 4.0 * p[1], p[0] + 4.0 * p[1]
        if name == "GAUSS2":
            return p[0] - 4.0 * p[1], p[2] + 4.0 * p[3]
        if name == "GBELL":
            delta = 999.0 ** (1.0 / (2.0 * p[1])) * p[0] if p[1] != 0 else math.inf
            return p[2] - delta, p[2] + delta
        if name == "COSINE":
            return p[1] - p[0], p[1] + p[0]
        spans = [(c - 9.0 / abs(g), c + 9.0 / abs(g)) if g else (-math.inf, math.inf)
                 for g, c in zip(p[0::2], p[1::2], strict=True)]
        return min(s[0] for s in spans), max(s[1] for s in spans)
