"""FCL terms whose parameters are other variables (jFuzzyLogic's membership functions with
variables, ``TERM good := GAUSS meanGood stdGood;``, ``(inputZeroMin, 0) (mid, 1) ...``).

jFuzzyLogic (``membership/Value.java``) reads such a parameter when the membership is asked
for, so it is the variable's value at that evaluation: an input's value as set before
``evaluate()``. it2track reads them so (:class:`~it2track.fuzzy.Parametric`, on input terms):

- a parameter names an input (``VAR_INPUT``); one that names an output, or a variable not
  declared, is refused (an output's value there is its DEFAULT or the previous evaluation's);
- an input read as a parameter may have no FUZZIFY block (jFuzzyLogic's plain value); its
  universe, to which it is clipped as every input, is its RANGE, else the union of the
  universes of the inputs whose terms read it;
- an input's universe without RANGE is jFuzzyLogic's estimate (the span of the terms' ends)
  from its fixed terms and the ends of its point lists that are numbers (with a variable end
  jFuzzyLogic's own estimate is NaN when it loads the file, its variables being NaN then);
  without any, a RANGE is asked for;
- point lists and ``GAUSS`` take variables; other shapes with a variable, and output terms
  with one, are refused naming the term. (jFuzzyLogic samples an output's terms on a
  defuzzification grid it fixes once, at the first evaluation whose variables give the output
  a finite universe -- ``Defuzzifier.reset`` calls ``init`` only while the grid is NaN, as it
  is when the file is loaded -- so its outputs depend on the order of evaluations;
  it2track's output sets are fixed when the system is built.)
"""

from __future__ import annotations

import dataclasses
import itertools
import math

from ..fuzzy import MembershipFunction, Parametric, Point, Ref
from ._fclbuild import Builder
from ._fclparse import FclTerm, FclVar, FunctionBlock

__all__ = ["check", "sets", "universe"]

_SHAPES = ("GAUSS",)  # named shapes read with variable parameters (and point lists)


def names(term: FclTerm, declared: set[str]) -> list[str]:
    """The variables ``term``'s parameters name, in order (a singleton output term given by a
    variable, ``TERM t := mid;``, names ``mid``)."""
    found = list(term.refs.values())
    if term.kind == "shape":
        if term.shape in declared:
            found.append(term.shape)
        found += [t.text for t in term.params if t.kind == "ident"
                  and t.upper not in ("NAN", "INF")]
    return found


def check(b: Builder, fb: FunctionBlock, *, with_outputs: bool = True) -> set[str]:
    """Refuse what is not read (see the module docstring); the inputs read as parameters.
    ``with_outputs=False`` checks the inputs' terms only."""
    declared = {*fb.inputs, *fb.outputs}
    read: set[str] = set()
    for var in (*fb.inputs.values(), *(fb.outputs.values() if with_outputs else ())):
        for term in var.terms.values():
            used = names(term, declared)
            if not used:
                continue
            listed = ", ".join(dict.fromkeys(used))
            what = f"term {term.name!r} of {var.name!r}"
            if var.name in fb.outputs:
                raise b.error(term.line, f"{what}: an output term with values given by "
                              f"variables ({listed}); it2track reads variable parameters on "
                              "input terms only (an output's sets are fixed when the system "
                              "is built)")
            for name in used:
                if name in fb.outputs:
                    raise b.error(term.line, f"{what}: parameter {name!r} is an output; "
                                  "variable parameters read inputs only")
                if name not in fb.inputs:
                    raise b.error(term.line, f"{what}: parameter {name!r} is not a declared "
                                  "variable")
            if term.kind == "shape" and term.shape.upper() not in _SHAPES:
                raise b.error(term.line, f"{what}: {term.shape} with values given by variables "
                              f"({listed}); it2track reads variable parameters in point lists "
                              f"and {', '.join(_SHAPES)}")
            read.update(used)
    return read


def universe(b: Builder, fb: FunctionBlock, var: FclVar) -> tuple[float, float]:
    """The universe of input ``var`` (see the module docstring)."""
    if var.range is not None:
        return var.range
    declared = {*fb.inputs, *fb.outputs}
    if not var.terms:  # read as a parameter only (check() let it through)
        spans = [universe(b, fb, other) for other in fb.inputs.values()
                 if any(var.name in names(t, declared) for t in other.terms.values())]
        return min(s[0] for s in spans), max(s[1] for s in spans)
    fixed = {k: t for k, t in var.terms.items() if not names(t, declared)}
    if len(fixed) == len(var.terms):
        return b.universe(var)
    for t in var.terms.values():  # a point list's first and last x, where they are numbers
        if t.kind == "points" and names(t, declared):
            ends = {0: t.points[0][0], 2 * len(t.points) - 2: t.points[-1][0]}
            for j, x in ends.items():
                if j not in t.refs:
                    fixed[f"{t.name} {j}"] = FclTerm(t.name, t.line, "points", [(x, 0.0)])
    if not fixed:
        raise b.error(var.block_line, f"{var.name!r}: give a RANGE (its terms' ends are "
                      "given by variables, from which no universe can be estimated)")
    return b.universe(dataclasses.replace(var, terms=fixed))


def sets(b: Builder, fb: FunctionBlock, var: FclVar, span: tuple[float, float]
         ) -> list[tuple[str, MembershipFunction]]:
    """The ``(name, membership)`` of each term of input ``var``; an input singleton
    (``TERM t := 5;``) is a :class:`~it2track.fuzzy.Point` (jFuzzyLogic's
    ``MembershipFunctionSingleton``: 1 at the value, 0 elsewhere)."""
    declared = {*fb.inputs, *fb.outputs}
    order = list(fb.inputs)
    # (the parser refuses a number out of range: a singleton's value is finite, a Point)
    return [(t.name, _parametric(b, t, order) if names(t, declared) else Point(t.value)
             if t.kind == "singleton" else b.mf(t, span)) for t in var.terms.values()]


def _parametric(b: Builder, term: FclTerm, order: list[str]) -> Parametric:
    what = f"term {term.name!r}"
    params: list[float | Ref] = []
    if term.kind == "points":
        for k, (x, m) in enumerate(term.points):
            for j, value in ((2 * k, x), (2 * k + 1, m)):
                name = term.refs.get(j)
                params.append(value if name is None else Ref(order.index(name), name))
        ys = [p for p in params[1::2] if not isinstance(p, Ref)]
        if any(not 0.0 <= y <= 1.0 for y in ys):
            raise b.error(term.line, f"{what}: memberships must lie in [0, 1]")
        xs = params[0::2]
        for a, c in itertools.pairwise(xs):
            if not isinstance(a, Ref) and not isinstance(c, Ref) and c < a:
                raise b.error(term.line, f"{what}: the points must have increasing x")
        family = "points"
    else:
        tokens, k = term.params, 0
        while k < len(tokens):
            sign = 1.0
            if tokens[k].text in ("-", "+") and k + 1 < len(tokens):
                sign, k = (-1.0 if tokens[k].text == "-" else 1.0), k + 1
            tok = tokens[k]
            if tok.kind == "ident" and tok.text in order and sign == 1.0:
                params.append(Ref(order.index(tok.text), tok.text))
            elif tok.kind == "num":
                params.append(sign * float(tok.text))
            else:
                raise b.error(tok.line, f"{what}: unexpected {tok.text!r} in the parameters")
            k += 1
        if len(params) != 2:
            raise b.error(term.line, f"{what}: GAUSS needs 2 parameters, got {len(params)}")
        sigma = params[1]
        if not isinstance(sigma, Ref) and not sigma > 0.0:
            raise b.error(term.line, f"{what}: GAUSS sigma {sigma!r} must be > 0")
        if any(not isinstance(p, Ref) and not math.isfinite(p) for p in params):
            raise b.error(term.line, f"{what}: its parameters must be finite")
        family = "gauss"
    made: Parametric = b.guarded(term.line, lambda: Parametric(family, tuple(params),
                                                               term.name), what)
    return made
