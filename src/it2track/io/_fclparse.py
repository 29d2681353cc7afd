"""The syntax of the Fuzzy Control Language as IEC 61131-7, jFuzzyLogic and fuzzylite write it:
tokens (comments ``(* *)``, ``/* */`` and ``//``; keywords in any case) and a syntax tree of
function blocks, variables, terms, operator settings and rules, every node with its line.
:mod:`.fcl` gives the tree its meaning.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from dataclasses import dataclass, field

from ._ruletree import Compound, Condition, Negation, Proposition
from .errors import FisFormatError, FisFormatWarning

__all__ = ["Block", "FclTerm", "FclVar", "FunctionBlock", "Parser", "RuleNode", "Tok"]

_TOKEN = re.compile(
    r"""(?P<ws>[ \t\r\f\v]+)
      | (?P<nl>\n)
      | (?P<comment>\(\*.*?\*\)|/\*.*?\*/|//[^\n]*)
      | (?P<num>(?:\d+(?:\.(?!\.)\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?(?!\d)(?!\.\d))
      | (?P<range>\.\.)
      | (?P<assign>:=)
      | (?P<punct>[:;(),|*/+^%=-])
      | (?P<ident>[A-Za-z_][A-Za-z0-9_.]*)
    """,
    re.VERBOSE | re.DOTALL,
)
_MAX_NUMBER_CHARS = 80
_HEDGES = ("VERY", "SOMEWHAT", "EXTREMELY", "SELDOM", "ANY")
_AFTER_PROPOSITION = ("THEN", "AND", "OR", "WITH")
_BLOCK_WORDS = ("VAR_INPUT", "VAR_OUTPUT", "FUZZIFY", "DEFUZZIFY", "RULEBLOCK",
                "END_FUNCTION_BLOCK")


@dataclass(frozen=True)
class Tok:
    """A token: ``kind`` (num, range, assign, punct, ident), its text and line."""

    kind: str
    text: str
    line: int

    @property
    def upper(self) -> str:
        return self.text.upper()


@dataclass
class FclTerm:
    """``TERM name := ...``: points, a number (singleton), a named shape with parameters, or a
    ``FUNCTION`` (its tokens)."""

    name: str
    line: int
    kind: str  # "points", "singleton", "shape", "function"
    points: list[tuple[float, float]] = field(default_factory=list)
    value: float = 0.0
    shape: str = ""
    params: list[Tok] = field(default_factory=list)
    #: points given by variables (jFuzzyLogic): ``2k`` (point k's x) or ``2k + 1`` (its
    #: degree) -> the variable's name (the point holds NaN there)
    refs: dict[int, str] = field(default_factory=dict)


@dataclass
class FclVar:
    """A declared variable and what its FUZZIFY/DEFUZZIFY block says."""

    name: str
    line: int
    terms: dict[str, FclTerm] = field(default_factory=dict)
    range: tuple[float, float] | None = None
    range_line: int | None = None
    method: Tok | None = None
    default: tuple[float, int] | None = None
    nc: bool = False  # DEFAULT ... NC: keep the last output where no rule fires
    accu: Tok | None = None
    block_line: int | None = None


@dataclass
class RuleNode:
    """``RULE n : IF condition THEN y IS t [, z IS u] [WITH w]``."""

    line: int
    condition: Condition
    #: variable, term, hedges: fuzzylite hands a conclusion's hedged degree on to the
    #: conclusions after it (``Consequent.modify``), so each holds those before it too
    conclusions: list[tuple[str, str, tuple[str, ...]]]
    weight: float


@dataclass
class Block:
    """A RULEBLOCK: its operator settings (``AND``, ``OR``, ``ACT``, ``ACCU``) and rules."""

    name: str
    line: int
    ops: dict[str, Tok] = field(default_factory=dict)
    rules: list[RuleNode] = field(default_factory=list)


@dataclass
class FunctionBlock:
    """A FUNCTION_BLOCK."""

    name: str
    line: int
    inputs: dict[str, FclVar] = field(default_factory=dict)
    outputs: dict[str, FclVar] = field(default_factory=dict)
    blocks: list[Block] = field(default_factory=list)


class Parser:
    """Parse FCL text into :class:`FunctionBlock` trees (:meth:`function_blocks`)."""

    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.toks = list(self._tokens(text))
        self.pos = 0
        #: what is read but may not be what was meant; :func:`.fcl.loads` warns of each
        self.warnings: list[FisFormatWarning] = []

    # -- tokens -------------------------------------------------------------------------------
    def _tokens(self, text: str) -> Iterator[Tok]:
        line, pos = 1, 0
        while pos < len(text):
            for opener, closer in (("(*", "*)"), ("/*", "*/")):
                if text.startswith(opener, pos) and closer not in text[pos + 2:]:
                    raise self.error(line, f"unterminated comment {opener} ... {closer}")
            m = _TOKEN.match(text, pos)
            if m is None:
                raise self.error(line, f"unexpected character {text[pos]!r}")
            kind = m.lastgroup
            assert kind is not None
            value = m.group(kind)
            if kind not in ("ws", "nl", "comment"):
                yield Tok(kind, value, line)
            line += value.count("\n")
            pos = m.end()

    def error(self, line: int | None, message: str) -> FisFormatError:
        return FisFormatError(self.path, line, message)

    def peek(self, ahead: int = 0) -> Tok | None:
        k = self.pos + ahead
        return self.toks[k] if k < len(self.toks) else None

    def last_line(self) -> int:
        return self.toks[-1].line if self.toks else 1

    def next(self, what: str) -> Tok:
        tok = self.peek()
        if tok is None:
            raise self.error(self.last_line(), f"unexpected end of file: expected {what}")
        self.pos += 1
        return tok

    def take(self) -> Tok:
        """The next token, where the caller has seen that there is one."""
        tok = self.toks[self.pos]
        self.pos += 1
        return tok

    def expect(self, text: str) -> Tok:
        tok = self.next(repr(text))
        if tok.upper != text.upper():
            raise self.error(tok.line, f"expected {text!r}, got {tok.text!r}")
        return tok

    def ident(self, what: str) -> Tok:
        tok = self.next(what)
        if tok.kind != "ident":
            raise self.error(tok.line, f"expected {what}, got {tok.text!r}")
        return tok

    def at(self, *words: str) -> bool:
        tok = self.peek()
        return tok is not None and tok.upper in words

    def skip(self, text: str) -> bool:
        if self.at(text):
            self.pos += 1
            return True
        return False

    def number(self, what: str) -> float:
        sign = 1.0
        if self.at("-", "+"):
            sign = -1.0 if self.take().text == "-" else 1.0
        tok = self.next(what)
        if tok.kind == "ident" and tok.upper in ("NAN", "INF"):
            return math.nan if tok.upper == "NAN" else sign * math.inf
        if tok.kind == "ident":
            raise self.error(tok.line, f"expected {what} (a number), got {tok.text!r}: values "
                             "given by variables (jFuzzyLogic) are not supported")
        if tok.kind != "num" or len(tok.text) > _MAX_NUMBER_CHARS:
            raise self.error(tok.line, f"expected {what} (a number), got {tok.text!r}")
        value = sign * float(tok.text)
        if not math.isfinite(value):
            raise self.error(tok.line, f"number {tok.text!r} is out of range")
        return value

    # -- structure ----------------------------------------------------------------------------
    def function_blocks(self) -> list[FunctionBlock]:
        blocks = []
        while self.peek() is not None:
            blocks.append(self.function_block())
        if not blocks:
            raise self.error(1, "no FUNCTION_BLOCK")
        return blocks

    def function_block(self) -> FunctionBlock:
        start = self.take()  # function_blocks saw a token
        if start.upper != "FUNCTION_BLOCK":
            where = "text after END_FUNCTION_BLOCK" if self.pos > 1 else "expected FUNCTION_BLOCK"
            raise self.error(start.line, f"{where}: {start.text!r}")
        name = ""
        tok = self.peek()
        if tok is not None and tok.kind == "ident" and tok.upper not in _BLOCK_WORDS:
            name = self.take().text
        fb = FunctionBlock(name, start.line)
        while True:
            tok = self.next("END_FUNCTION_BLOCK")
            word = tok.upper
            if word == "END_FUNCTION_BLOCK":
                return fb
            if word in ("VAR_INPUT", "VAR_OUTPUT"):
                self.declarations(fb, fb.inputs if word == "VAR_INPUT" else fb.outputs)
            elif word in ("FUZZIFY", "DEFUZZIFY"):
                self.variable_block(word, fb.inputs if word == "FUZZIFY" else fb.outputs)
            elif word == "RULEBLOCK":
                fb.blocks.append(self.ruleblock(tok))
            elif word == "FUNCTION_BLOCK":
                raise self.error(tok.line, f"FUNCTION_BLOCK inside FUNCTION_BLOCK {fb.name} "
                                 f"(line {fb.line}): missing END_FUNCTION_BLOCK")
            else:
                raise self.error(tok.line, f"unexpected {tok.text!r} (expected VAR_INPUT, "
                                 "VAR_OUTPUT, FUZZIFY, DEFUZZIFY, RULEBLOCK or "
                                 "END_FUNCTION_BLOCK)")

    def declarations(self, fb: FunctionBlock, target: dict[str, FclVar]) -> None:
        while not self.at("END_VAR"):
            var = self.ident("a variable name")
            if var.text in fb.inputs or var.text in fb.outputs:
                raise self.error(var.line, f"variable {var.text!r} declared twice")
            self.expect(":")
            kind = self.ident("a type")
            if kind.upper != "REAL":
                raise self.error(kind.line, f"variable {var.text!r} has type {kind.text}: "
                                 "only REAL is supported")
            self.expect(";")
            target[var.text] = FclVar(var.text, var.line)
            if self.at("RANGE"):  # jFuzzyLogic: RANGE := (lo .. hi); after the declaration
                self.range(target[var.text], self.take())
        self.expect("END_VAR")

    def range(self, var: FclVar, key: Tok) -> None:
        self.expect(":=")
        self.expect("(")
        lo = self.number("the range start")
        self.expect("..")
        hi = self.number("the range end")
        self.expect(")")
        self.expect(";")
        if not lo <= hi:  # a point: a singleton output's (fuzzylite's juggler export)
            raise self.error(key.line, f"RANGE ({lo:g} .. {hi:g}) must satisfy lo < hi")
        if var.range is not None:
            raise self.error(key.line, f"a second RANGE for {var.name!r} (first at line "
                             f"{var.range_line})")
        var.range, var.range_line = (lo, hi), key.line

    def variable_block(self, word: str, variables: dict[str, FclVar]) -> None:
        tok = self.ident("a variable name")
        if tok.text not in variables:
            kind = "VAR_INPUT" if word == "FUZZIFY" else "VAR_OUTPUT"
            raise self.error(tok.line, f"{word} {tok.text}: not declared in {kind}")
        var = variables[tok.text]
        if var.block_line is not None:
            raise self.error(tok.line, f"second {word} block for {tok.text!r} (first at line "
                             f"{var.block_line})")
        var.block_line = tok.line
        end = "END_" + word
        while not self.at(end):
            key = self.next(end)
            if key.upper == "TERM":
                self.term(var)
            elif key.upper == "RANGE":
                self.range(var, key)
            elif key.upper == "METHOD" and word == "DEFUZZIFY":
                self.expect(":")
                var.method = self.ident("a defuzzification method")
                self.expect(";")
            elif key.upper == "ACCU" and word == "DEFUZZIFY":  # jFuzzyLogic, fuzzylite
                self.expect(":")
                var.accu = self.ident("an accumulation method")
                self.expect(";")
            elif key.upper == "DEFAULT" and word == "DEFUZZIFY":
                # jFuzzyLogic also reads 'DEFAULT = 0' without ';' (its lexer drops the '=',
                # its parser puts in the missing ':=' and ';'; junit_functions.fcl)
                lenient = self.skip("=")
                if not lenient:
                    self.expect(":=")
                # NC ("no change", IEC 61131-7): the last output where no rule fires, the
                # system's lock_previous (evaluate_sequence); fuzzylite: DEFAULT := nan | NC
                if self.at("NC"):
                    self.take()
                    var.nc = True
                else:
                    value = self.number("a default value")
                    var.default = (value, key.line)
                    if self.skip("|"):
                        self.expect("NC")
                        var.nc = True
                    if lenient:
                        self.warnings.append(FisFormatWarning(
                            self.path, key.line, f"DEFAULT = {value:g}: read as jFuzzyLogic "
                            f"reads it, DEFAULT := {value:g}; (the standard's form)"))
                if lenient:
                    self.skip(";")
                else:
                    self.expect(";")
            else:
                raise self.error(key.line, f"unexpected {key.text!r} in {word} {var.name}")
        self.expect(end)
        if not var.terms and word == "DEFUZZIFY":  # an input may feed linear FUNCTIONs only
            raise self.error(tok.line, f"{word} {var.name}: no TERM")

    def term(self, var: FclVar) -> None:
        name = self.ident("a term name")
        if name.text in var.terms:  # pyfuzzylite 8 binds the last (fuzzylite 6 the first)
            self.warnings.append(FisFormatWarning(
                self.path, name.line, f"duplicate term {name.text!r} of {var.name!r} (first at "
                f"line {var.terms[name.text].line}): rules naming it take this one"))
            del var.terms[name.text]
        self.expect(":=")
        term = FclTerm(name.text, name.line, "points")
        nxt = self.peek()
        if nxt is not None and (nxt.kind == "num" or nxt.text in ("-", "+")):
            term.kind, term.value = "singleton", self.number("a singleton value")
        elif nxt is not None and nxt.text == "(":
            while self.at("("):
                self.expect("(")
                x = self.point_value(term, 0, "x")
                self.expect(",")
                m = self.point_value(term, 1, "a membership degree")
                self.expect(")")
                term.points.append((x, m))
        elif nxt is not None and nxt.kind == "ident":
            shape = self.take()
            term.kind = "function" if shape.upper == "FUNCTION" else "shape"
            term.shape = shape.text
            while not self.at(";"):
                term.params.append(self.next("';'"))
        else:
            raise self.error(name.line, f"term {name.text!r}: expected points (x, m), a value or "
                             "a shape")
        self.expect(";")
        var.terms[name.text] = term

    def point_value(self, term: FclTerm, which: int, what: str) -> float:
        """A point's number, or NaN for a variable's name, recorded in ``term.refs``."""
        tok = self.peek()
        if tok is not None and tok.kind == "ident" and tok.upper not in ("NAN", "INF"):
            term.refs[2 * len(term.points) + which] = self.take().text
            return math.nan
        return self.number(what)

    # -- rules --------------------------------------------------------------------------------
    def ruleblock(self, start: Tok) -> Block:
        name = ""
        tok = self.peek()
        if tok is not None and tok.kind == "ident" and tok.upper not in (
                "AND", "OR", "ACT", "ACCU", "RULE", "END_RULEBLOCK"):
            name = self.take().text
        block = Block(name, start.line)
        while not self.at("END_RULEBLOCK"):
            key = self.next("END_RULEBLOCK")
            word = key.upper
            if word in ("AND", "OR", "ACT", "ACCU"):
                self.expect(":")
                value = self.ident(f"an {word} operator")
                first = block.ops.get(word)
                if first is not None and first.upper != value.upper:
                    raise self.error(value.line, f"{word} : {value.text} differs from the "
                                     f"earlier {word} : {first.text} (line {first.line}); one "
                                     "setting per system")
                block.ops.setdefault(word, value)
                self.expect(";")
            elif word == "RULE":
                block.rules.append(self.rule())
            else:
                raise self.error(key.line, f"unexpected {key.text!r} in RULEBLOCK")
        self.expect("END_RULEBLOCK")
        return block

    def rule(self) -> RuleNode:
        label = self.next("a rule number")
        if label.kind not in ("num", "ident"):
            raise self.error(label.line, f"expected a rule number, got {label.text!r}")
        self.expect(":")
        self.expect("IF")
        condition = self.disjunction()
        self.expect("THEN")
        conclusions = []
        carried: tuple[str, ...] = ()
        while True:
            parens = self.skip("(")
            var = self.ident("an output variable")
            self.expect("IS")
            hedges = []
            while self.at(*_HEDGES, "NOT") and (nxt := self.peek(1)) is not None and (
                    nxt.kind == "ident"):
                hedges.append(self.take().text.lower())
            term = self.ident("a term")
            if parens:
                self.expect(")")
            carried = tuple(hedges) + carried
            conclusions.append((var.text, term.text, carried))
            if not (self.skip(",") or self.skip("AND")):
                break
        weight = 1.0
        if self.skip("WITH"):
            weight = self.number("a weight")
        if not self.skip(";") and not self.at("RULE", "END_RULEBLOCK"):
            tok = self.peek()
            got = "the end of the file" if tok is None else repr(tok.text)
            raise self.error(label.line if tok is None else tok.line,
                             f"expected ';' after the rule, got {got}")
        return RuleNode(label.line, condition, conclusions, weight)

    def disjunction(self) -> Condition:
        parts = [self.conjunction()]
        while self.skip("OR"):
            parts.append(self.conjunction())
        return parts[0] if len(parts) == 1 else Compound("or", tuple(parts))

    def conjunction(self) -> Condition:
        parts = [self.operand()]
        while self.skip("AND"):
            parts.append(self.operand())
        return parts[0] if len(parts) == 1 else Compound("and", tuple(parts))

    def operand(self) -> Condition:
        if self.skip("NOT"):
            return Negation(self.operand())
        if self.skip("("):
            inner = self.disjunction()
            self.expect(")")
            return inner
        var = self.ident("an input variable")
        self.expect("IS")
        negated = self.skip("NOT")
        hedges = []
        while self.at(*_HEDGES) and (nxt := self.peek(1)) is not None and nxt.kind == "ident" and (
                nxt.upper not in _AFTER_PROPOSITION):
            hedges.append(self.take().text.lower())
        if self.at("ANY"):  # fuzzylite's 'x is any' names no term: the builder takes the first
            self.take()
            return Proposition(var.text, "", negated, (*hedges, "any"))
        term = self.ident("a term")
        return Proposition(var.text, term.text, negated, tuple(hedges))
