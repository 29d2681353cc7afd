"""Fuzzy Control Language (FCL, IEC 61131-7) files, read (type-1 systems)::

    FUNCTION_BLOCK tipper
    VAR_INPUT
        service : REAL;
    END_VAR
    VAR_OUTPUT
        tip : REAL;
    END_VAR
    FUZZIFY service
        TERM poor := (0, 1) (4, 0);
        TERM good := (1, 0) (4, 1) (6, 1) (9, 0);
        RANGE := (0 .. 10);
    END_FUZZIFY
    DEFUZZIFY tip
        TERM cheap := (0, 0) (5, 1) (10, 0);
        METHOD : COG;
        DEFAULT := 0;
        RANGE := (0 .. 30);
    END_DEFUZZIFY
    RULEBLOCK No1
        AND : MIN;
        ACT : MIN;
        ACCU : MAX;
        RULE 1 : IF service IS poor OR food IS NOT rancid THEN tip IS cheap WITH 0.5;
    END_RULEBLOCK
    END_FUNCTION_BLOCK

What is read
------------
- Comments ``(* ... *)`` (may span lines) and ``// ...``; keywords are case-insensitive.
- ``TERM t := (x1, m1) (x2, m2) ...`` with the points in increasing ``x``: the shapes
  it2track has -- triangles ``(a,0)(b,h)(c,0)``, trapezoids ``(a,0)(b,h)(c,h)(d,0)`` and
  shoulders ``(a,h)(b,0)`` / ``(a,0)(b,h)`` / ``(a,h)(b,h)(c,0)`` / ``(a,0)(b,h)(c,h)`` (the
  standard extends the first and last values beyond the points, as our shoulders do).
  Other polylines are refused with the line. In ``DEFUZZIFY``, ``TERM t := value`` is a
  singleton.
- ``RANGE := (lo .. hi)`` gives a variable's universe; without it, the span of its terms'
  points (singletons: their values).
- ``DEFUZZIFY``: ``METHOD`` ``COG`` (centroid), ``COA`` (bisector), ``LM`` / ``RM`` (leftmost /
  rightmost maximum) give a :class:`~it2track.fuzzy.T1Mamdani` (output sampled on 101
  points); ``COGS`` (centre of gravity of singletons) gives a
  :class:`~it2track.fuzzy.T1Sugeno`. ``DEFAULT := v`` is ``on_zero_firing`` (``NC``, "keep the
  last output", needs state and is refused); without ``DEFAULT`` no firing raises
  ``ZeroFiringError``.
- ``RULEBLOCK``: ``AND`` ``MIN``/``PROD`` and ``OR`` ``MAX``/``ASUM`` (probabilistic OR; an
  ``AND`` alone implies its De Morgan partner, as the standard pairs them), ``ACT``
  ``MIN``/``PROD`` (implication), ``ACCU`` ``MAX`` or ``NSUM`` (normalised sum: the same
  centroid, bisector and maxima as a plain sum). ``BDIF``, ``BSUM`` (bounded operators) are
  refused. Several rule blocks are merged when their operators agree.
- ``RULE n : IF x IS [NOT] t AND|OR ... THEN y IS t [, z IS s] [WITH w];`` -- one
  connective per rule, no parentheses. With ``COGS`` and ``ACCU : MAX`` the standard takes,
  for each singleton, the *largest* activation of the rules concluding it; that equals the
  per-rule weighted average of a Sugeno system only when no two rules share a singleton, so a
  shared one is refused.

Errors raise :class:`~it2track.io.FisFormatError` with ``file:line``. Writing FCL is not
supported.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterator
from dataclasses import dataclass, field

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Defuzzifier,
    Implication,
    Input,
    MembershipFunction,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
)
from .errors import FisFormatError

__all__ = ["loads"]

_TOKEN = re.compile(
    r"""(?P<ws>[ \t\r\f\v]+)
      | (?P<nl>\n)
      | (?P<comment>\(\*.*?\*\)|//[^\n]*)
      | (?P<num>[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?(?![.\d]))
      | (?P<range>\.\.)
      | (?P<assign>:=)
      | (?P<punct>[:;(),])
      | (?P<ident>[A-Za-z_][A-Za-z0-9_]*)
    """,
    re.VERBOSE | re.DOTALL,
)
_DEFUZZ = {"COG": Defuzzifier.CENTROID, "COA": Defuzzifier.BISECTOR, "LM": Defuzzifier.SOM,
           "RM": Defuzzifier.LOM}
_AND = {"MIN": TNorm.MINIMUM, "PROD": TNorm.PRODUCT}
_OR = {"MAX": SNorm.MAXIMUM, "ASUM": SNorm.PROBOR}
_PARTNER = {"MIN": "MAX", "PROD": "ASUM", "MAX": "MIN", "ASUM": "PROD"}


#: (line, [(input, term, negated)], "AND" | "OR", [(output, term)], weight)
_RuleData = tuple[int, list[tuple[str, str, bool]], str, list[tuple[str, str]], float]


@dataclass(frozen=True)
class _Tok:
    kind: str
    text: str
    line: int

    @property
    def upper(self) -> str:
        return self.text.upper()


@dataclass
class _Var:
    name: str
    line: int
    terms: dict[str, tuple[object, int]] = field(default_factory=dict)  # name -> (value, line)
    range: tuple[float, float] | None = None
    method: tuple[str, int] | None = None
    default: tuple[float | None, int] | None = None
    block_line: int | None = None


class _Parser:
    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.toks = list(self._tokens(text))
        self.pos = 0

    # -- tokens -------------------------------------------------------------------------------
    def _tokens(self, text: str) -> Iterator[_Tok]:
        line, pos = 1, 0
        while pos < len(text):
            if text.startswith("(*", pos) and "*)" not in text[pos + 2 :]:
                raise self.error(line, "unterminated comment (* ... *)")
            m = _TOKEN.match(text, pos)
            if m is None:
                raise self.error(line, f"unexpected character {text[pos]!r}")
            kind = m.lastgroup
            assert kind is not None
            value = m.group(kind)
            if kind not in ("ws", "nl", "comment"):
                yield _Tok(kind, value, line)
            line += value.count("\n")
            pos = m.end()

    def error(self, line: int | None, message: str) -> FisFormatError:
        return FisFormatError(self.path, line, message)

    def peek(self) -> _Tok | None:
        return self.toks[self.pos] if self.pos < len(self.toks) else None

    def last_line(self) -> int:
        return self.toks[-1].line if self.toks else 1

    def next(self, what: str) -> _Tok:
        tok = self.peek()
        if tok is None:
            raise self.error(self.last_line(), f"unexpected end of file: expected {what}")
        self.pos += 1
        return tok

    def expect(self, text: str) -> _Tok:
        tok = self.next(repr(text))
        if tok.upper != text.upper():
            raise self.error(tok.line, f"expected {text!r}, got {tok.text!r}")
        return tok

    def ident(self, what: str) -> _Tok:
        tok = self.next(what)
        if tok.kind != "ident":
            raise self.error(tok.line, f"expected {what}, got {tok.text!r}")
        return tok

    def number(self, what: str) -> float:
        tok = self.next(what)
        if tok.kind != "num":
            raise self.error(tok.line, f"expected {what} (a number), got {tok.text!r}")
        value = float(tok.text)
        if not math.isfinite(value):
            raise self.error(tok.line, f"number {tok.text!r} is out of range")
        return value

    def at(self, *words: str) -> bool:
        tok = self.peek()
        return tok is not None and tok.upper in words


def _shape(points: list[tuple[float, float]], line: int, p: _Parser) -> MembershipFunction:
    xs = [x for x, _ in points]
    ms = [m for _, m in points]
    if any(b <= a for a, b in itertools.pairwise(xs)):
        raise p.error(line, f"term points {points} must have strictly increasing x")
    if any(not 0.0 <= m <= 1.0 for m in ms):
        raise p.error(line, f"term points {points}: memberships must lie in [0, 1]")
    h = max(ms)
    pattern = tuple("h" if m == h and h > 0 else "0" if m == 0 else "?" for m in ms)
    shapes = {
        ("h", "0"): lambda: Triangle(xs[0], xs[0], xs[1], h),
        ("0", "h"): lambda: Triangle(xs[0], xs[1], xs[1], h),
        ("0", "h", "0"): lambda: Triangle(xs[0], xs[1], xs[2], h),
        ("h", "h", "0"): lambda: Triangle(xs[1], xs[1], xs[2], h),
        ("0", "h", "h"): lambda: Triangle(xs[0], xs[1], xs[1], h),
        ("0", "h", "h", "0"): lambda: Trapezoid(xs[0], xs[1], xs[2], xs[3], h),
    }
    if pattern not in shapes:
        raise p.error(
            line, f"term shape {points} is not supported: it2track reads triangles "
            "(a,0)(b,h)(c,0), trapezoids (a,0)(b,h)(c,h)(d,0) and shoulders"
        )
    try:
        return shapes[pattern]()
    except ValueError as exc:
        raise p.error(line, str(exc)) from None


def loads(text: str, path: str = "<string>") -> AnySystem:
    """Parse FCL text into a :class:`~it2track.fuzzy.T1Mamdani` or
    :class:`~it2track.fuzzy.T1Sugeno` (see the module docstring).

    Raises
    ------
    FisFormatError
        On anything malformed or unsupported, naming ``path``, the line and the problem.
    """
    p = _Parser(text, path)
    p.expect("FUNCTION_BLOCK")
    name = ""
    if p.peek() is not None and p.peek().kind == "ident" and not p.at(  # type: ignore[union-attr]
        "VAR_INPUT", "VAR_OUTPUT", "FUZZIFY", "DEFUZZIFY", "RULEBLOCK", "END_FUNCTION_BLOCK"
    ):
        name = p.next("name").text
    inputs: dict[str, _Var] = {}
    outputs: dict[str, _Var] = {}
    ops: dict[str, tuple[str, int]] = {}
    rules: list[_RuleData] = []
    while True:
        tok = p.next("END_FUNCTION_BLOCK")
        word = tok.upper
        if word == "END_FUNCTION_BLOCK":
            break
        if word in ("VAR_INPUT", "VAR_OUTPUT"):
            target = inputs if word == "VAR_INPUT" else outputs
            while not p.at("END_VAR"):
                var = p.ident("a variable name")
                if var.text in inputs or var.text in outputs:
                    raise p.error(var.line, f"variable {var.text!r} declared twice")
                p.expect(":")
                kind = p.ident("a type")
                if kind.upper != "REAL":
                    raise p.error(kind.line, f"variable {var.text!r} has type {kind.text}: "
                                  "only REAL is supported")
                p.expect(";")
                target[var.text] = _Var(var.text, var.line)
            p.expect("END_VAR")
        elif word in ("FUZZIFY", "DEFUZZIFY"):
            _block(p, word, inputs if word == "FUZZIFY" else outputs)
        elif word == "RULEBLOCK":
            p.ident("a rule block name")
            _ruleblock(p, ops, rules)
        else:
            raise p.error(tok.line, f"unexpected {tok.text!r} (expected VAR_INPUT, VAR_OUTPUT, "
                          "FUZZIFY, DEFUZZIFY, RULEBLOCK or END_FUNCTION_BLOCK)")
    extra = p.peek()
    if extra is not None:
        raise p.error(extra.line, f"text after END_FUNCTION_BLOCK: {extra.text!r}")
    return _build(p, name, inputs, outputs, ops, rules)


def _block(p: _Parser, word: str, variables: dict[str, _Var]) -> None:
    tok = p.ident("a variable name")
    if tok.text not in variables:
        kind = "VAR_INPUT" if word == "FUZZIFY" else "VAR_OUTPUT"
        raise p.error(tok.line, f"{word} {tok.text}: not declared in {kind}")
    var = variables[tok.text]
    if var.block_line is not None:
        raise p.error(tok.line, f"second {word} block for {tok.text!r} (first at line "
                      f"{var.block_line})")
    var.block_line = tok.line
    end = "END_" + word
    while not p.at(end):
        key = p.next(end)
        if key.upper == "TERM":
            term = p.ident("a term name")
            if term.text in var.terms:
                raise p.error(term.line, f"duplicate term {term.text!r} of {var.name!r}")
            p.expect(":=")
            nxt = p.peek()
            if nxt is not None and nxt.kind == "num":
                if word == "FUZZIFY":
                    raise p.error(term.line, "a singleton input term is not supported")
                var.terms[term.text] = (p.number("a singleton value"), term.line)
            else:
                points = []
                while p.at("("):
                    p.expect("(")
                    x = p.number("x")
                    p.expect(",")
                    m = p.number("a membership degree")
                    p.expect(")")
                    points.append((x, m))
                if len(points) < 2:
                    raise p.error(term.line, f"term {term.text!r} needs at least two points "
                                  "(x, membership)")
                var.terms[term.text] = (_shape(points, term.line, p), term.line)
            p.expect(";")
        elif key.upper == "RANGE":
            p.expect(":=")
            p.expect("(")
            lo = p.number("the range start")
            p.expect("..")
            hi = p.number("the range end")
            p.expect(")")
            p.expect(";")
            if not lo < hi:
                raise p.error(key.line, f"RANGE ({lo} .. {hi}) must satisfy lo < hi")
            var.range = (lo, hi)
        elif key.upper == "METHOD" and word == "DEFUZZIFY":
            p.expect(":")
            method = p.ident("a defuzzification method")
            if method.upper not in (*_DEFUZZ, "COGS"):
                raise p.error(method.line, f"METHOD {method.text} is not supported (COG, COGS, "
                              "COA, LM, RM)")
            var.method = (method.upper, method.line)
            p.expect(";")
        elif key.upper == "DEFAULT" and word == "DEFUZZIFY":
            p.expect(":=")
            if p.at("NC"):
                nc = p.next("NC")
                raise p.error(nc.line, "DEFAULT := NC (keep the last output) needs state, "
                              "which it2track systems do not have; give a value")
            var.default = (p.number("a default value"), key.line)
            p.expect(";")
        elif key.upper == "ACCU" and word == "DEFUZZIFY":  # allowed here by some tools
            raise p.error(key.line, "put ACCU in the RULEBLOCK")
        else:
            raise p.error(key.line, f"unexpected {key.text!r} in {word} {var.name}")
    p.expect(end)
    if not var.terms:
        raise p.error(tok.line, f"{word} {var.name}: no TERM")


def _ruleblock(p: _Parser, ops: dict[str, tuple[str, int]], rules: list[_RuleData]) -> None:
    allowed = {"AND": ("MIN", "PROD"), "OR": ("MAX", "ASUM"), "ACT": ("MIN", "PROD"),
               "ACCU": ("MAX", "NSUM")}
    while not p.at("END_RULEBLOCK"):
        key = p.next("END_RULEBLOCK")
        word = key.upper
        if word in allowed:
            p.expect(":")
            value = p.ident(f"an {word} operator")
            if value.upper not in allowed[word]:
                raise p.error(value.line, f"{word} : {value.text} is not supported "
                              f"({', '.join(allowed[word])})")
            if word in ops and ops[word][0] != value.upper:
                raise p.error(value.line, f"{word} : {value.text} differs from the earlier "
                              f"{word} : {ops[word][0]} (line {ops[word][1]}); one setting "
                              "per system")
            ops[word] = (value.upper, value.line)
            p.expect(";")
        elif word == "RULE":
            number = p.next("a rule number")
            p.expect(":")
            p.expect("IF")
            terms: list[tuple[str, str, bool]] = []
            connective = ""
            while True:
                if p.at("("):
                    raise p.error(p.next("(").line, "parentheses in rule conditions are not "
                                  "supported")
                neg = False
                if p.at("NOT"):
                    p.next("NOT")
                    neg = True
                var = p.ident("an input variable")
                p.expect("IS")
                if p.at("NOT"):
                    p.next("NOT")
                    neg = not neg
                term = p.ident("a term")
                terms.append((var.text, term.text, neg))
                if p.at("AND", "OR"):
                    conn = p.next("AND or OR")
                    if connective and conn.upper != connective:
                        raise p.error(conn.line, "a rule mixing AND and OR needs parentheses, "
                                      "which are not supported")
                    connective = conn.upper
                    continue
                break
            p.expect("THEN")
            conclusions = []
            while True:
                var = p.ident("an output variable")
                p.expect("IS")
                term = p.ident("a term")
                conclusions.append((var.text, term.text))
                if p.at(","):
                    p.next(",")
                    continue
                break
            weight = 1.0
            if p.at("WITH"):
                p.next("WITH")
                weight = p.number("a weight")
            p.expect(";")
            rules.append((number.line, terms, connective or "AND", conclusions, weight))
        else:
            raise p.error(key.line, f"unexpected {key.text!r} in RULEBLOCK")
    p.expect("END_RULEBLOCK")


def _universe(var: _Var) -> tuple[float, float]:
    """RANGE, or the span of the terms' points (singletons have no universe to give: they
    occur only in the outputs of a COGS system, which has none; every point list spans
    lo < hi, its x strictly increasing)."""
    if var.range is not None:
        return var.range
    xs: list[float] = []
    for value, _ in var.terms.values():
        assert isinstance(value, Triangle | Trapezoid)
        a, _b, _c, d, _h = value.as_trapezoid()
        xs += [a, d]
    return min(xs), max(xs)


def _build(p: _Parser, name: str, inputs: dict[str, _Var], outputs: dict[str, _Var],
           ops: dict[str, tuple[str, int]], rules: list[_RuleData]) -> AnySystem:
    if not inputs:
        raise p.error(1, "no VAR_INPUT variables")
    if not outputs:
        raise p.error(1, "no VAR_OUTPUT variables")
    for var in (*inputs.values(), *outputs.values()):
        if var.block_line is None:
            block = "FUZZIFY" if var.name in inputs else "DEFUZZIFY"
            raise p.error(var.line, f"variable {var.name!r} has no {block} block")
    if not rules:
        raise p.error(p.last_line(), "no RULE")
    methods = {var.method[0] if var.method else "COG" for var in outputs.values()}
    if len(methods) > 1:
        raise p.error(next(iter(outputs.values())).line,
                      f"outputs use different METHODs {sorted(methods)}: one per system")
    method = methods.pop()
    sugeno = method == "COGS"
    for var in outputs.values():
        for term, (value, line) in var.terms.items():
            if sugeno != isinstance(value, float):
                raise p.error(line, f"term {term!r}: METHOD COGS needs singletons "
                              "(TERM t := value) and the other methods need point lists")

    def convert(cls: type, var: _Var) -> Input:
        universe = _universe(var)
        sets = [(t, mf) for t, (mf, _) in var.terms.items()]
        try:
            made: Input = cls(var.name, universe, sets)
            return made
        except ValueError as exc:
            raise p.error(var.block_line, str(exc)) from None

    in_vars = [convert(Input, v) for v in inputs.values()]
    in_names = list(inputs)
    out_names = list(outputs)
    built = []
    shared: dict[tuple[str, str], int] = {}
    for line, terms, connective, conclusions, weight in rules:
        antecedent: list[str | None] = [None] * len(in_names)
        negated = [False] * len(in_names)
        for vname, term, neg in terms:
            if vname not in inputs:
                raise p.error(line, f"rule names {vname!r}, which is not an input")
            if term not in inputs[vname].terms:
                raise p.error(line, f"input {vname!r} has no term {term!r}")
            i = in_names.index(vname)
            if antecedent[i] is not None:
                raise p.error(line, f"rule names input {vname!r} twice")
            antecedent[i], negated[i] = term, neg
        cons: list[object] = [None] * len(out_names)
        for vname, term in conclusions:
            if vname not in outputs:
                raise p.error(line, f"rule concludes {vname!r}, which is not an output")
            if term not in outputs[vname].terms:
                raise p.error(line, f"output {vname!r} has no term {term!r}")
            k = out_names.index(vname)
            cons[k] = outputs[vname].terms[term][0] if sugeno else term
            if sugeno and ops.get("ACCU", ("MAX", 0))[0] == "MAX":
                if (vname, term) in shared:
                    raise p.error(line, f"singleton {term!r} of {vname!r} is concluded by this "
                                  f"rule and the one at line {shared[(vname, term)]}: with "
                                  "COGS and ACCU : MAX that is not a weighted average of rules "
                                  "(use ACCU : NSUM, or one rule per singleton)")
                shared[(vname, term)] = line
        if not 0.0 <= weight <= 1.0:
            raise p.error(line, f"rule weight {weight:g} must be in [0, 1]")
        try:
            built.append(Rule(antecedent, consequents=cons, weight=weight,
                              connective="or" if connective == "OR" else "and",
                              negated=negated))
        except ValueError as exc:
            raise p.error(line, str(exc)) from None
    and_op = ops.get("AND", (_PARTNER[ops["OR"][0]], 0) if "OR" in ops else ("MIN", 0))[0]
    or_op = ops.get("OR", (_PARTNER[and_op], 0))[0]
    defaults = [v.default[0] if v.default else None for v in outputs.values()]
    if any(d is None for d in defaults) and any(d is not None for d in defaults):
        raise p.error(next(v.line for v in outputs.values() if v.default is None),
                      "give DEFAULT for every output or for none")
    zero: object = None
    if defaults[0] is not None:
        zero = defaults[0] if len(defaults) == 1 else tuple(defaults)
    options: dict[str, object] = {
        "inputs": tuple(in_vars), "rules": tuple(built), "name": name,
        "tnorm": _AND[and_op], "snorm": _OR[or_op], "on_zero_firing": zero,
    }
    try:
        if sugeno:
            if len(out_names) > 1:
                options["outputs"] = tuple(out_names)
            return T1Sugeno(**options)  # type: ignore[arg-type]
        options["outputs"] = tuple(convert(Output, v) for v in outputs.values())
        options["implication"] = (Implication.PRODUCT if ops.get("ACT", ("MIN", 0))[0] == "PROD"
                                  else Implication.MINIMUM)
        options["aggregation"] = (Aggregation.SUM if ops.get("ACCU", ("MAX", 0))[0] == "NSUM"
                                  else Aggregation.MAXIMUM)
        options["defuzzifier"] = _DEFUZZ[method]
        return T1Mamdani(**options)  # type: ignore[arg-type]
    except ValueError as exc:
        raise p.error(None, str(exc)) from None
