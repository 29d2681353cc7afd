"""The value syntax of MATLAB-style fuzzy-system files: quoted strings, numbers, row vectors
(with MATLAB's ``pi`` expressions in items) and membership-function lines
``'name':'type',[params]`` with optional ``,'Name',value`` pairs.

:class:`ValueParser` is the half of :class:`~._matlab.Document` that converts one
``Key=value`` entry; every error names the entry's line and key.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from .errors import FisFormatError

__all__ = ["MAX_NUMBER_CHARS", "NUMBER_RE", "Entry", "MFValue", "ValueParser", "show"]

_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?"
MAX_NUMBER_CHARS = 80
NUMBER_RE = re.compile(_NUMBER)
_INT_RE = re.compile(r"[+-]?\d{1,9}")
_FACTOR = r"(?:(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?|pi)"
_EXPR_RE = re.compile(rf"[+-]?{_FACTOR}(?:[*/]{_FACTOR})*")
_EXPR_TOKEN_RE = re.compile(rf"[*/]|{_FACTOR}")
_TOKEN_RE = re.compile(
    r"""\s*(?:
        (?P<sq>'(?:[^']|'')*')
      | (?P<dq>"(?:[^"]|"")*")
      | (?P<vec>\[[^\[\]'"]*\])
      | (?P<punct>[:,])
      | (?P<atom>[^\s,:'"\[\]]+)
    )""",
    re.VERBOSE,
)


def show(text: str, limit: int = 60) -> str:
    """``repr`` of user text for an error message, shortened to about ``limit`` characters."""
    return repr(text) if len(text) <= limit else repr(text[:limit]) + "..."


@dataclass(frozen=True)
class Entry:
    """One ``Key=value`` line."""

    key: str
    value: str
    line: int


@dataclass(frozen=True)
class MFValue:
    """``'name':'type',[params]`` plus optional ``,'Name',value`` pairs.

    ``extras`` keeps the values' number texts (checked finite numbers), so that a reader can
    evaluate them exactly.
    """

    name: str
    type: str
    params: tuple[float, ...]
    extras: dict[str, tuple[str, ...]]
    line: int
    #: fuzzylite's ``'function',[formula]``: the formula's text (``params`` is empty)
    formula: str = ""


class ValueParser:
    """Convert the value of an :class:`Entry`; subclasses supply :meth:`error`."""

    def error(self, line: int | None, message: str) -> FisFormatError:
        raise NotImplementedError

    def _tokens(self, entry: Entry) -> list[tuple[str, str]]:
        text = entry.value
        tokens: list[tuple[str, str]] = []
        pos = 0
        while pos < len(text):
            if text[pos:].strip() == "":
                break
            match = _TOKEN_RE.match(text, pos)
            if match is None or match.end() == pos:
                rest = text[pos:].strip()
                if rest[:1] in ("'", '"'):
                    problem = "unterminated string"
                elif rest[:1] == "[":
                    problem = "unterminated or malformed vector"
                else:
                    problem = f"unexpected text {show(rest)}"
                raise self.error(entry.line, f"{problem} in {entry.key}")
            kind = match.lastgroup
            assert kind is not None
            tokens.append((kind, match.group(kind)))
            pos = match.end()
        return tokens

    def _number(self, text: str, entry: Entry) -> float:
        if len(text) > MAX_NUMBER_CHARS or not NUMBER_RE.fullmatch(text):
            raise self.error(entry.line, f"bad number {show(text)} in {entry.key}")
        value = float(text)
        if not math.isfinite(value):
            raise self.error(entry.line, f"number {show(text)} in {entry.key} is out of range")
        return value

    def _item(self, text: str, entry: Entry) -> float:
        """A vector item: a number, or MATLAB's ``pi`` expressions (``-pi/4``)."""
        if len(text) <= MAX_NUMBER_CHARS and NUMBER_RE.fullmatch(text):
            return self._number(text, entry)
        if len(text) > MAX_NUMBER_CHARS or not _EXPR_RE.fullmatch(text):
            raise self.error(entry.line, f"bad number {show(text)} in {entry.key}")
        sign = -1.0 if text[0] == "-" else 1.0
        parts = _EXPR_TOKEN_RE.findall(text.lstrip("+-"))
        value = sign * (math.pi if parts[0] == "pi" else float(parts[0]))
        for op, operand in zip(parts[1::2], parts[2::2], strict=True):
            x = math.pi if operand == "pi" else float(operand)
            if op == "*":
                value *= x
            elif x == 0.0:
                raise self.error(entry.line, f"division by zero in {show(text)} in {entry.key}")
            else:
                value /= x
        if not math.isfinite(value):
            raise self.error(entry.line, f"number {show(text)} in {entry.key} is out of range")
        return value

    def _vector_items(self, text: str, entry: Entry) -> tuple[str, ...]:
        inner = text[1:-1].strip()
        if ";" in inner:
            raise self.error(
                entry.line, f"matrix {show(text)} in {entry.key}: expected a row vector"
            )
        return tuple(item for item in re.split(r"[\s,]+", inner) if item)

    def _vector_texts(self, text: str, entry: Entry) -> tuple[str, ...]:
        """The number texts of a vector literal, each checked to be a finite number."""
        items = self._vector_items(text, entry)
        for item in items:
            self._number(item, entry)
        return items

    def _vector(self, text: str, entry: Entry) -> tuple[float, ...]:
        return tuple(self._item(item, entry) for item in self._vector_items(text, entry))

    @staticmethod
    def _unquote(token: str) -> str:
        quote = token[0]
        return token[1:-1].replace(quote * 2, quote)

    def string(self, entry: Entry) -> str:
        """A quoted string value (single or double quotes)."""
        tokens = self._tokens(entry)
        if len(tokens) != 1 or tokens[0][0] not in ("sq", "dq"):
            raise self.error(
                entry.line,
                f"{entry.key} must be a quoted string, e.g. 'text'; got {show(entry.value)}",
            )
        return self._unquote(tokens[0][1])

    def number(self, entry: Entry) -> float:
        tokens = self._tokens(entry)
        if len(tokens) != 1 or tokens[0][0] != "atom":
            raise self.error(entry.line, f"{entry.key} must be a number, got {show(entry.value)}")
        return self._number(tokens[0][1], entry)

    def integer(self, entry: Entry, *, minimum: int = 0) -> int:
        value = entry.value.strip()
        if not _INT_RE.fullmatch(value):
            raise self.error(
                entry.line, f"{entry.key} must be an integer, got {show(entry.value)}"
            )
        number = int(value)
        if number < minimum:
            raise self.error(entry.line, f"{entry.key}={number} must be at least {minimum}")
        return number

    def vector(self, entry: Entry, *, size: int | None = None) -> tuple[float, ...]:
        tokens = self._tokens(entry)
        if len(tokens) != 1 or tokens[0][0] != "vec":
            raise self.error(
                entry.line, f"{entry.key} must be a vector like [0 1], got {show(entry.value)}"
            )
        values = self._vector(tokens[0][1], entry)
        if size is not None and len(values) != size:
            raise self.error(
                entry.line, f"{entry.key} must have {size} numbers, got {len(values)}"
            )
        return values

    def universe(self, entry: Entry, *, point_ok: bool = False) -> tuple[float, float]:
        """A ``Range=[lo hi]`` with ``lo < hi`` (``lo <= hi`` with ``point_ok``)."""
        lo, hi = self.vector(entry, size=2)
        if not (lo < hi or (point_ok and lo == hi)):
            raise self.error(entry.line, f"{entry.key}={entry.value} must satisfy lo < hi")
        return lo, hi

    def mf(self, entry: Entry, *, extras: Sequence[str] = ()) -> MFValue:
        """``'name':'type',[params]`` optionally followed by ``,'Key',value`` pairs."""
        tokens = self._tokens(entry)
        quoted = ("sq", "dq")
        if not (
            len(tokens) >= 5
            and tokens[0][0] in quoted
            and tokens[1] == ("punct", ":")
            and tokens[2][0] in quoted
            and tokens[3] == ("punct", ",")
            and tokens[4][0] == "vec"
        ):
            raise self.error(
                entry.line,
                f"{entry.key} must look like 'name':'type',[params]; got {show(entry.value)}",
            )
        name = self._unquote(tokens[0][1])
        kind = self._unquote(tokens[2][1])
        if kind == "function":  # fuzzylite's formula: the text between the brackets
            if tokens[5:]:
                raise self.error(entry.line, f"unexpected text after the formula of {entry.key}")
            return MFValue(name, kind, (), {}, entry.line, formula=tokens[4][1][1:-1].strip())
        params = self._vector(tokens[4][1], entry)
        found: dict[str, tuple[str, ...]] = {}
        rest = tokens[5:]
        while rest:
            if (
                len(rest) < 4
                or rest[0] != ("punct", ",")
                or rest[1][0] not in quoted
                or rest[2] != ("punct", ",")
                or rest[3][0] not in ("atom", "vec")
            ):
                raise self.error(
                    entry.line,
                    f"unexpected text after the parameters of {entry.key}: expected "
                    f",'Name',value pairs",
                )
            key = self._unquote(rest[1][1])
            if key not in extras:
                known = ", ".join(repr(e) for e in extras) or "none"
                raise self.error(
                    entry.line, f"unknown MF property {show(key)} in {entry.key} (known: {known})"
                )
            if key in found:
                raise self.error(entry.line, f"duplicate MF property {key!r} in {entry.key}")
            kind_v, text_v = rest[3]
            if kind_v == "atom":
                self._number(text_v, entry)
                found[key] = (text_v,)
            else:
                found[key] = self._vector_texts(text_v, entry)
            rest = rest[4:]
        return MFValue(name, kind, params, found, entry.line)

