"""Formulas in text -- fuzzylite's ``Function`` term and jFuzzyLogic's ``FUNCTION`` -- read by a
small recursive-descent parser over a fixed grammar and evaluated with numpy over batches.

Nothing here runs text as code: a formula is tokenised, parsed into a tree of numbers, variable
names, whitelisted operators and whitelisted functions, and the tree is evaluated by numpy. A
name the formula may not read, a function or operator outside the dialect's list, a malformed
expression, or a formula longer than :data:`MAX_CHARS` characters, :data:`MAX_TOKENS` tokens or
nested deeper than :data:`MAX_DEPTH` raises :class:`FormulaError` naming the offending token and
its position.

Dialects
--------
``"fuzzylite"`` (fuzzylite 6/8's ``Function``, ``FunctionFactory``), loosest binding first:

==================================  ==========================================================
``or``, ``and``                     logical (1 or 0), left-associative
``+`` ``-``                         left-associative
``*`` ``/`` ``%``                   left-associative; ``%`` is numpy's ``remainder`` (the
                                    divisor's sign)
unary ``-`` ``+`` ``.-`` ``.+``     ``-x^2`` is ``-(x^2)`` (fuzzylite's ``.-``; fuzzylite itself
                                    reads a bare leading ``-`` as a binary minus and refuses it)
``^`` ``**``                        power, *right*-associative: ``2^3^2`` is ``2^9``
                                    (fuzzylite's associativity 1)
``!`` ``~``                         logical not, negate: bind tightest, ``~x^2`` is ``(~x)^2``
==================================  ==========================================================

Functions (fuzzylite's ``FunctionFactory``): ``gt ge eq neq le lt`` (1 or 0; ``ge``, ``le``,
``eq``, ``neq`` take two NaNs as equal), ``min max`` (Python's: ``min(a, b)`` is ``b`` where
``b < a``, else ``a``), ``pow atan2 fmod``; ``acos asin atan ceil cos cosh exp abs fabs floor
log`` (natural) ``log10 round`` (half to even, numpy's) ``sin sinh sqrt tan tanh log1p acosh
asinh atanh``; ``pi`` (no argument, with or without ``()``). Names and functions are
case-sensitive.

``"jfuzzylogic"`` (jFuzzyLogic's ``Fcl.g``: ``fun_pm``, ``fun_md``, ``fun_mp``, ``fun_atom``):
``+ -`` below ``* /`` below ``^ %`` (power and Java's ``%``, numpy's ``fmod``: the dividend's
sign), all left-associative (``2^3^2`` is ``8^2``); functions ``EXP LN LOG`` (base 10)
``SIN COS TAN ABS`` in any case. A unary minus binds tighter than ``^``: jFuzzyLogic reads a
sign as part of the number (``-2^2`` is ``(-2)^2 = 4``). jFuzzyLogic's evaluator skips NaN
operands of ``+ - /`` (``MffSum``); here NaN propagates as IEEE arithmetic says.

Examples
--------
>>> import numpy as np
>>> from it2track.fuzzy.formula import Formula
>>> f = Formula("2 * x ^ 2 - 1", "fuzzylite", ("x",))
>>> f(np.array([0.0, 0.5, 1.0])).tolist()
[-1.0, -0.5, 1.0]
>>> Formula("2 ^ 3 ^ 2", "fuzzylite", ()).value()
512.0
>>> Formula("2 ^ 3 ^ 2", "jfuzzylogic", ()).value()
64.0
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["DIALECTS", "MAX_CHARS", "MAX_DEPTH", "MAX_TOKENS", "Formula", "FormulaError",
           "FormulaMembership"]

FloatArray = NDArray[np.float64]

#: the longest formula read, in characters
MAX_CHARS = 2000
#: the most tokens a formula may have
MAX_TOKENS = 400
#: the deepest a formula's tree may nest (parentheses, calls, operators)
MAX_DEPTH = 64


class FormulaError(ValueError):
    """A formula that is not in its dialect's grammar; ``token`` is the offending token (``""``
    at the end) and ``position`` its 0-based character offset."""

    def __init__(self, message: str, token: str, position: int) -> None:
        self.token = token
        self.position = position
        where = "at the end" if not token else f"at character {position + 1}"
        super().__init__(f"{message} ({where})")


def _f(a: Any) -> FloatArray:
    return np.asarray(a, dtype=np.float64)


def _equal(a: FloatArray, b: FloatArray) -> FloatArray:
    return _f((a == b) | (np.isnan(a) & np.isnan(b)))


def _minimum(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.where(b < a, b, a)  # Python's min(a, b): a unless b < a (NaN: the first)


def _maximum(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.where(b > a, b, a)


_Fn = Callable[..., Any]
_FUZZYLITE_FUNCTIONS: dict[str, tuple[int, _Fn]] = {
    "gt": (2, lambda a, b: _f(a > b)),
    "ge": (2, lambda a, b: _f((a >= b) | (np.isnan(a) & np.isnan(b)))),
    "eq": (2, _equal),
    "neq": (2, lambda a, b: 1.0 - _equal(a, b)),
    "le": (2, lambda a, b: _f((a <= b) | (np.isnan(a) & np.isnan(b)))),
    "lt": (2, lambda a, b: _f(a < b)),
    "min": (2, _minimum),
    "max": (2, _maximum),
    "acos": (1, np.arccos), "asin": (1, np.arcsin), "atan": (1, np.arctan),
    "ceil": (1, np.ceil), "cos": (1, np.cos), "cosh": (1, np.cosh), "exp": (1, np.exp),
    "abs": (1, np.fabs), "fabs": (1, np.fabs), "floor": (1, np.floor), "log": (1, np.log),
    "log10": (1, np.log10), "round": (1, np.round), "sin": (1, np.sin), "sinh": (1, np.sinh),
    "sqrt": (1, np.sqrt), "tan": (1, np.tan), "tanh": (1, np.tanh), "log1p": (1, np.log1p),
    "acosh": (1, np.arccosh), "asinh": (1, np.arcsinh), "atanh": (1, np.arctanh),
    "pow": (2, np.float_power), "atan2": (2, np.arctan2), "fmod": (2, np.fmod),
    "pi": (0, lambda: np.float64(math.pi)),
}
_JFL_FUNCTIONS: dict[str, tuple[int, _Fn]] = {
    "EXP": (1, np.exp), "LN": (1, np.log), "LOG": (1, np.log10), "SIN": (1, np.sin),
    "COS": (1, np.cos), "TAN": (1, np.tan), "ABS": (1, np.fabs),
}
_BINARY: dict[str, _Fn] = {
    "+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide,
    "^": np.float_power, "**": np.float_power,
    "and": lambda a, b: _f(np.logical_and(a, b)), "or": lambda a, b: _f(np.logical_or(a, b)),
}
_UNARY: dict[str, _Fn] = {
    "-": np.negative, ".-": np.negative, "~": np.negative, "+": np.positive,
    ".+": np.positive, "!": lambda a: _f(np.logical_not(a)),
}


@dataclass(frozen=True)
class _Dialect:
    name: str
    functions: dict[str, tuple[int, _Fn]]
    #: binary operator levels, loosest first; the last is the power level
    levels: tuple[tuple[str, ...], ...]
    modulo: _Fn
    power_right: bool  # fuzzylite: ^ right-associative
    unary: tuple[str, ...]
    tight: tuple[str, ...]  # prefix operators binding tighter than ^
    fold_case: bool  # function names in any case
    symbols: tuple[str, ...] = field(default=())


DIALECTS: dict[str, _Dialect] = {
    "fuzzylite": _Dialect(
        "fuzzylite", _FUZZYLITE_FUNCTIONS,
        (("or",), ("and",), ("+", "-"), ("*", "/", "%"), ("^", "**")),
        np.remainder, True, ("-", "+", ".-", ".+"), ("!", "~"), False,
        ("**", ".-", ".+", "+", "-", "*", "/", "%", "^", "!", "~", "(", ")", ",")),
    "jfuzzylogic": _Dialect(
        "jfuzzylogic", _JFL_FUNCTIONS, (("+", "-"), ("*", "/"), ("^", "%")),
        np.fmod, False, (), ("-", "+"), True,
        ("+", "-", "*", "/", "%", "^", "(", ")")),
}

_NUMBER = re.compile(r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_SPACE = re.compile(r"\s+")

# A tree node, its depth last: ("num", value, 0) | ("var", index, 0) | ("call", fn, args, depth)
# | ("op", fn, args, depth); fn is one of the whitelisted numpy functions above
_Node = tuple[Any, ...]


@dataclass(frozen=True)
class _Tok:
    kind: str  # "num", "name", "sym", "end"
    text: str
    pos: int


def _tokens(text: str, dialect: _Dialect) -> list[_Tok]:
    if len(text) > MAX_CHARS:
        raise FormulaError(f"is {len(text)} characters long; at most {MAX_CHARS} are read",
                           text[MAX_CHARS], MAX_CHARS)
    out: list[_Tok] = []
    pos = 0
    while pos < len(text):
        if m := _SPACE.match(text, pos):
            pos = m.end()
            continue
        if m := _NUMBER.match(text, pos):
            out.append(_Tok("num", m.group(), pos))
        elif m := _NAME.match(text, pos):
            out.append(_Tok("name", m.group(), pos))
        else:
            sym = next((s for s in dialect.symbols if text.startswith(s, pos)), None)
            if sym is None:
                allowed = " ".join(s for s in dialect.symbols if s != ",")
                raise FormulaError(f"unexpected character {text[pos]!r} ({dialect.name}'s "
                                   f"formulas use numbers, names and {allowed})", text[pos], pos)
            out.append(_Tok("sym", sym, pos))
            pos += len(sym)
            if len(out) > MAX_TOKENS:
                break
            continue
        pos = m.end()
        if len(out) > MAX_TOKENS:
            break
    if len(out) > MAX_TOKENS:
        tok = out[MAX_TOKENS]
        raise FormulaError(f"has more than {MAX_TOKENS} tokens", tok.text, tok.pos)
    out.append(_Tok("end", "", len(text)))
    return out


class _Parser:
    def __init__(self, text: str, dialect: _Dialect, names: Sequence[str]) -> None:
        self.d = dialect
        self.names = {n: k for k, n in enumerate(names)}
        self.toks = _tokens(text, dialect)
        self.k = 0
        self.depth = 0

    @property
    def tok(self) -> _Tok:
        return self.toks[self.k]

    def fail(self, message: str, tok: _Tok | None = None) -> FormulaError:
        tok = tok or self.tok
        return FormulaError(message, tok.text, tok.pos)

    def enter(self, tok: _Tok) -> None:
        """One level deeper, at ``tok`` (named if it is one too many)."""
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise self.fail(f"nests deeper than {MAX_DEPTH}", tok)

    def at(self, *texts: str) -> bool:
        return self.tok.kind in ("sym", "name") and self.tok.text in texts

    def parse(self) -> _Node:
        if self.tok.kind == "end":
            raise self.fail("is empty")
        tree = self.level(0)
        if self.tok.kind != "end":
            raise self.fail(f"unexpected {self.tok.text!r} where the formula should end")
        return tree

    def level(self, i: int) -> _Node:
        levels = self.d.levels
        if i == len(levels) - 1:
            return self.power()
        left = self.level(i + 1)
        while self.at(*levels[i]):
            op = self.tok
            self.k += 1
            left = self.op(op, left, self.level(i + 1))
        return left

    def op(self, tok: _Tok, left: _Node, right: _Node) -> _Node:
        fn = self.d.modulo if tok.text == "%" else _BINARY[tok.text]
        node = ("op", fn, (left, right), 1 + max(_depth(left), _depth(right)))
        if node[3] > MAX_DEPTH:
            raise self.fail(f"nests deeper than {MAX_DEPTH}", tok)
        return node

    def power(self) -> _Node:
        ops = self.d.levels[-1]
        if self.d.power_right:  # fuzzylite: unary minus below ^, right-associative ^
            if self.at(*self.d.unary):
                tok = self.tok
                self.k += 1
                self.enter(tok)
                operand = self.power()
                self.depth -= 1
                return ("op", _UNARY[tok.text], (operand,), 1 + _depth(operand))
            base = self.prefix()
            if self.at(*ops):
                tok = self.tok
                self.k += 1
                self.enter(tok)
                exponent = self.power()
                self.depth -= 1
                return self.op(tok, base, exponent)
            return base
        left = self.prefix()
        while self.at(*ops):
            tok = self.tok
            self.k += 1
            left = self.op(tok, left, self.prefix())
        return left

    def prefix(self) -> _Node:
        if self.at(*self.d.tight):
            tok = self.tok
            self.k += 1
            nxt = self.tok
            if self.d.name == "jfuzzylogic" and nxt.kind == "num":  # a signed number
                self.k += 1
                value = float(nxt.text)
                return ("num", -value if tok.text == "-" else value, 0)
            self.enter(tok)
            operand = self.prefix()
            self.depth -= 1
            return ("op", _UNARY[tok.text], (operand,), 1 + _depth(operand))
        return self.atom()

    def atom(self) -> _Node:
        tok = self.tok
        if tok.kind == "num":
            self.k += 1
            value = float(tok.text)
            if not math.isfinite(value):
                raise self.fail(f"number {tok.text!r} is out of range", tok)
            return ("num", value, 0)
        if tok.kind == "sym" and tok.text == "(":
            self.k += 1
            self.enter(tok)
            inner = self.level(0)
            self.depth -= 1
            self.close(tok)
            return inner
        if tok.kind == "name":
            self.k += 1
            key = tok.text.upper() if self.d.fold_case else tok.text
            if key in self.d.functions:
                return self.call(tok, key)
            if tok.text in self.names:
                return ("var", self.names[tok.text], 0)
            known = ", ".join(self.names) or "none"
            raise self.fail(f"unknown name {tok.text!r} (the formula may read: {known}; "
                            f"{self.d.name}'s functions: {', '.join(self.d.functions)})", tok)
        if tok.kind == "end":
            raise self.fail("ends where a number, name or '(' should follow")
        raise self.fail(f"unexpected {tok.text!r} where a number, name or '(' should be", tok)

    def close(self, opener: _Tok) -> None:
        if not self.at(")"):
            raise self.fail(f"'(' at character {opener.pos + 1} is not closed"
                            if self.tok.kind == "end" else
                            f"unexpected {self.tok.text!r} where ')' should close the '(' at "
                            f"character {opener.pos + 1}")
        self.k += 1

    def call(self, name: _Tok, key: str) -> _Node:
        arity, fn = self.d.functions[key]
        if arity == 0:
            if self.at("("):
                opener = self.tok
                self.k += 1
                self.close(opener)
            return ("call", fn, (), 0)
        if not self.at("("):
            raise self.fail(f"function {name.text!r} needs '(' and {arity} argument"
                            f"{'s' if arity > 1 else ''}")
        opener = self.tok
        self.k += 1
        self.enter(name)
        args = [self.level(0)]
        while len(args) < arity and self.at(","):
            self.k += 1
            args.append(self.level(0))
        self.depth -= 1
        if len(args) < arity or self.at(","):
            raise self.fail(f"function {name.text!r} takes {arity} argument"
                            f"{'s' if arity > 1 else ''}", self.tok)
        self.close(opener)
        depth = 1 + max(_depth(a) for a in args)
        if depth > MAX_DEPTH:
            raise self.fail(f"nests deeper than {MAX_DEPTH}", name)
        return ("call", fn, tuple(args), depth)


def _depth(node: _Node) -> int:
    return int(node[-1])


def _evaluate(node: _Node, values: Sequence[FloatArray]) -> FloatArray:
    kind = node[0]
    if kind == "num":
        return np.float64(node[1])  # type: ignore[return-value]
    if kind == "var":
        return values[node[1]]
    return _f(node[1](*(_evaluate(a, values) for a in node[2])))


def _used(node: _Node) -> set[int]:
    if node[0] == "var":
        return {node[1]}
    if node[0] == "num":
        return set()
    return set().union(*(_used(a) for a in node[2])) if node[2] else set()


@dataclass(frozen=True, init=False)
class Formula:
    """A formula of named variables, parsed once (see the module docstring).

    Parameters
    ----------
    text : str
        The formula as the file writes it.
    dialect : {"fuzzylite", "jfuzzylogic"}
        Its grammar and functions.
    names : sequence of str
        The variables it may read, in the order :meth:`__call__` takes their values.

    Attributes
    ----------
    used : frozenset of str
        The names the formula reads.

    Raises
    ------
    FormulaError
        The text is not a formula of the dialect over ``names``.
    """

    text: str
    dialect: str
    names: tuple[str, ...]
    _tree: _Node = field(init=False, repr=False, compare=False, hash=False)
    used: frozenset[str] = field(init=False, compare=False, hash=False, repr=False)

    def __init__(self, text: str, dialect: str, names: Sequence[str] = ()) -> None:
        if dialect not in DIALECTS:
            raise ValueError(f"dialect={dialect!r} must be one of {sorted(DIALECTS)}")
        if not isinstance(text, str):
            raise TypeError(f"a formula is text, got {type(text).__name__}")
        object.__setattr__(self, "text", text)
        object.__setattr__(self, "dialect", dialect)
        object.__setattr__(self, "names", tuple(str(n) for n in names))
        tree = _Parser(text, DIALECTS[dialect], self.names).parse()
        object.__setattr__(self, "_tree", tree)
        object.__setattr__(self, "used", frozenset(self.names[k] for k in _used(tree)))

    def __reduce__(self) -> tuple[Any, ...]:
        return (Formula, (self.text, self.dialect, self.names))

    def __call__(self, *values: ArrayLike) -> FloatArray:
        """The formula at ``values`` (one array per name, broadcast together): an array of the
        broadcast shape. Floating-point exceptions give NaN or inf silently, as the tools'."""
        if len(values) != len(self.names):
            raise ValueError(f"formula {self.text!r} takes {len(self.names)} values "
                             f"({', '.join(self.names)}), got {len(values)}")
        arrays = np.broadcast_arrays(*(_f(v) for v in values)) if values else []
        shape = arrays[0].shape if arrays else ()
        with np.errstate(all="ignore"):
            out = _evaluate(self._tree, arrays)
        return np.array(np.broadcast_to(out, shape), dtype=np.float64)

    def value(self) -> float:
        """The value of a formula that reads no variable."""
        if self.used:
            raise ValueError(f"formula {self.text!r} reads {sorted(self.used)}")
        with np.errstate(all="ignore"):
            zeros = [np.zeros(())] * len(self.names)
            return float(_evaluate(self._tree, zeros))


@dataclass(frozen=True)
class FormulaMembership:
    """fuzzylite's ``Function`` term ``f(x)`` as a Mamdani output set: ``max(f(x), 0)``.

    fuzzylite neither clips nor checks a ``Function``'s values, but its ``Aggregated`` term
    starts from 0 (``y = aggregation(0, ...)``), so under ``Maximum`` aggregation with a
    ``Minimum`` or ``AlgebraicProduct`` implication (``I(a, f) <= 0`` where ``f <= 0``) the
    aggregated set is the same with ``f`` floored at 0: the readers use this only there. Values
    above 1 are not changed (a set's check refuses them). NaN stays NaN, as in fuzzylite.
    """

    formula: Formula

    def __post_init__(self) -> None:
        if self.formula.names != ("x",):
            raise ValueError(f"a membership formula reads x only, not {self.formula.names}")

    def __call__(self, x: ArrayLike) -> FloatArray:
        return np.maximum(self.formula(x), 0.0)
