"""The text layer shared by MATLAB's ``.fis`` and the IT2FLS toolbox's ``.t2fis`` formats.

Both are INI-like: ``[System]``, ``[Input1]`` ..., ``[Output1]`` ..., ``[Rules]`` sections of
``Key=value`` lines (``[Rules]`` holds one indexed rule per line); lines starting with ``%`` are
comments. Values are MATLAB literals: quoted strings (``'it''s'``), numbers, row vectors
(``[-1 0 1]``) and, for membership functions, ``'name':'type',[params]``.

This module parses that syntax into sections with line numbers, converts values strictly (no
``Inf``, ``NaN`` or expressions: every number must match MATLAB's plain decimal syntax and be
finite), and formats values for the writers. It knows nothing about fuzzy semantics beyond the
indexed rule syntax.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from .errors import FisFormatError, UnsupportedFeatureError

__all__ = [
    "Document",
    "Entry",
    "MFValue",
    "ParsedRule",
    "Section",
    "decode",
    "fmt_number",
    "fmt_string",
    "fmt_vector",
]

_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?"
_MAX_NUMBER_CHARS = 80
_NUMBER_RE = re.compile(_NUMBER)
_INT_RE = re.compile(r"[+-]?\d{1,9}")
_SECTION_RE = re.compile(r"\[\s*(System|Rules|Input[1-9]\d*|Output[1-9]\d*)\s*\]")
_ANY_SECTION_RE = re.compile(r"\[.*\]")
_KEY_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
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
_RULE_RE = re.compile(r"(?P<ant>[^,()]*),(?P<cons>[^,()]*)\((?P<w>[^()]*)\)\s*:\s*(?P<conn>.*)")


def _show(text: str, limit: int = 60) -> str:
    """``repr`` of user text for an error message, shortened to about ``limit`` characters."""
    return repr(text) if len(text) <= limit else repr(text[:limit]) + "..."


def decode(data: bytes) -> str:
    """Text of a MATLAB-style file: UTF-8 (a BOM is dropped), else Latin-1 (never fails)."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


# ---------------------------------------------------------------------------------------------
# Formatting (writers)
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


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Entry:
    """One ``Key=value`` line."""

    key: str
    value: str
    line: int


@dataclass
class Section:
    """A ``[Title]`` section: its entries by key, or (``[Rules]``) its rows in order."""

    title: str
    line: int
    entries: dict[str, Entry] = field(default_factory=dict)
    rows: list[tuple[str, int]] = field(default_factory=list)

    @property
    def kind(self) -> str:
        return self.title.rstrip("0123456789")

    @property
    def index(self) -> int:
        digits = self.title[len(self.kind) :]
        return int(digits) if digits else 0


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


@dataclass(frozen=True)
class ParsedRule:
    """An indexed rule line ``a1 a2 ..., c (w) : k``."""

    antecedent: tuple[int, ...]
    consequent: tuple[int, ...]
    weight: float
    connection: int
    line: int


@dataclass(frozen=True)
class Counts:
    """Sizes declared in ``[System]``, with the entries that declared them (for messages)."""

    n_inputs: int
    n_in_entry: Entry
    n_out_entry: Entry
    n_rules: int
    n_rules_entry: Entry
    n_outputs: int = 1


class Document:
    """A parsed MATLAB-style fuzzy-system file.

    Parameters
    ----------
    text : str
        File content.
    path : str
        Used in error messages.
    """

    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.sections: dict[str, Section] = {}
        lines = text.split("\n")
        self.n_lines = len(lines)
        current: Section | None = None
        for number, raw in enumerate(lines, start=1):
            line = raw.strip()
            if not line or line.startswith("%"):
                continue
            match = _SECTION_RE.fullmatch(line)
            if match:
                title = match.group(1)
                if title in self.sections:
                    raise self.error(
                        number,
                        f"duplicate section [{title}] (first at line {self.sections[title].line})",
                    )
                current = Section(title, number)
                self.sections[title] = current
                continue
            if _ANY_SECTION_RE.fullmatch(line):
                raise self.error(number, f"unknown section {line}")
            if current is None:
                raise self.error(number, "text before the first section (expected [System])")
            if current.title == "Rules":
                current.rows.append((line, number))
                continue
            key, sep, value = line.partition("=")
            key = key.strip()
            if not sep or not _KEY_RE.fullmatch(key):
                raise self.error(
                    number, f"expected Key=value in [{current.title}], got {_show(line)}"
                )
            if key in current.entries:
                first = current.entries[key].line
                raise self.error(
                    number, f"duplicate key {key!r} in [{current.title}] (first at line {first})"
                )
            current.entries[key] = Entry(key, value.strip(), number)

    # -- errors ------------------------------------------------------------------------------
    def error(self, line: int | None, message: str) -> FisFormatError:
        return FisFormatError(self.path, line, message)

    # -- sections ----------------------------------------------------------------------------
    def section(self, title: str, *, promised_by: Entry | None = None) -> Section:
        """The section ``[title]``; a missing one is an error at the line that promised it."""
        try:
            return self.sections[title]
        except KeyError:
            if promised_by is not None:
                raise self.error(
                    promised_by.line,
                    f"missing section [{title}] ({promised_by.key}={promised_by.value})",
                ) from None
            raise self.error(None, f"missing section [{title}]") from None

    def system_type(self, system: Section) -> tuple[str, str]:
        """``(Name, Type)`` of a ``[System]`` (Name ``""`` if absent; Type ``'sugeno'`` or
        ``'mamdani'``, lower case)."""
        name = self.string(system.entries["Name"]) if "Name" in system.entries else ""
        type_entry = self.entry(system, "Type")
        fis_type = self.string(type_entry)
        if fis_type.lower() not in ("sugeno", "mamdani"):
            raise self.error(
                type_entry.line, f"Type={fis_type!r} is not supported ('sugeno' or 'mamdani')"
            )
        return name, fis_type.lower()

    def method(self, system: Section, key: str, allowed: Sequence[str], default: str) -> str:
        """A ``...Method`` string of ``[System]``, lower case, one of ``allowed``."""
        if key not in system.entries:
            return default
        entry = system.entries[key]
        value = self.string(entry)
        if value.lower() not in allowed:
            choices = ", ".join(repr(a) for a in allowed)
            raise self.error(entry.line, f"{key}={value!r} is not supported ({choices})")
        return value.lower()

    def counts(self, system: Section) -> Counts:
        """``NumInputs``, ``NumOutputs`` and ``NumRules`` of a ``[System]``, with no
        ``[InputN]``/``[OutputN]`` sections beyond them."""
        n_in_entry = self.entry(system, "NumInputs")
        n_inputs = self.integer(n_in_entry, minimum=1)
        n_out_entry = self.entry(system, "NumOutputs")
        n_outputs = self.integer(n_out_entry, minimum=1)
        n_rules_entry = self.entry(system, "NumRules")
        n_rules = self.integer(n_rules_entry, minimum=1)
        self.check_no_extra_sections("Input", n_inputs, n_in_entry)
        self.check_no_extra_sections("Output", n_outputs, n_out_entry)
        return Counts(n_inputs, n_in_entry, n_out_entry, n_rules, n_rules_entry, n_outputs)

    def check_mf_keys(
        self, section: Section, n: int, count_entry: Entry, *, suffixes: tuple[str, ...] = ("",)
    ) -> None:
        """``MF1`` ... ``MFn`` (with each suffix, e.g. ``U``/``L``) present, none beyond ``n``."""
        for key, entry in section.entries.items():
            if key.startswith("MF") and int(key[2:].rstrip("UL")) > n:
                raise self.error(entry.line, f"{key} but {count_entry.key}={count_entry.value}")
        for j in range(1, n + 1):
            for suffix in suffixes:
                if f"MF{j}{suffix}" not in section.entries:
                    raise self.error(
                        count_entry.line,
                        f"missing MF{j}{suffix} in [{section.title}] "
                        f"({count_entry.key}={count_entry.value})",
                    )

    def counted_rules(self, counts: Counts) -> list[ParsedRule]:
        """The ``[Rules]``, as many as ``NumRules`` promised."""
        section = self.section("Rules", promised_by=counts.n_rules_entry)
        parsed = self.rules(section, counts.n_inputs, counts.n_outputs)
        if len(parsed) != counts.n_rules:
            raise self.error(
                counts.n_rules_entry.line,
                f"NumRules={counts.n_rules} but [Rules] has {len(parsed)} rules",
            )
        return parsed

    def check_no_extra_sections(self, kind: str, count: int, promised_by: Entry) -> None:
        for section in self.sections.values():
            if section.kind == kind and section.index > count:
                raise self.error(
                    section.line,
                    f"unexpected section [{section.title}] ({promised_by.key}={promised_by.value})",
                )

    def entry(self, section: Section, key: str) -> Entry:
        try:
            return section.entries[key]
        except KeyError:
            raise self.error(section.line, f"missing key {key!r} in [{section.title}]") from None

    def check_keys(self, section: Section, allowed: set[str], pattern: str | None = None) -> None:
        """Every key of ``section`` is in ``allowed`` or matches ``pattern``."""
        regex = re.compile(pattern) if pattern else None
        for key, entry in section.entries.items():
            if key in allowed or (regex is not None and regex.fullmatch(key)):
                continue
            raise self.error(entry.line, f"unknown key {key!r} in [{section.title}]")

    # -- values ------------------------------------------------------------------------------
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
                    problem = f"unexpected text {_show(rest)}"
                raise self.error(entry.line, f"{problem} in {entry.key}")
            kind = match.lastgroup
            assert kind is not None
            tokens.append((kind, match.group(kind)))
            pos = match.end()
        return tokens

    def _number(self, text: str, entry: Entry) -> float:
        if len(text) > _MAX_NUMBER_CHARS or not _NUMBER_RE.fullmatch(text):
            raise self.error(entry.line, f"bad number {_show(text)} in {entry.key}")
        value = float(text)
        if not math.isfinite(value):
            raise self.error(entry.line, f"number {_show(text)} in {entry.key} is out of range")
        return value

    def _vector_texts(self, text: str, entry: Entry) -> tuple[str, ...]:
        """The number texts of a vector literal, each checked to be a finite number."""
        inner = text[1:-1].strip()
        if ";" in inner:
            raise self.error(
                entry.line, f"matrix {_show(text)} in {entry.key}: expected a row vector"
            )
        items = tuple(item for item in re.split(r"[\s,]+", inner) if item)
        for item in items:
            self._number(item, entry)
        return items

    def _vector(self, text: str, entry: Entry) -> tuple[float, ...]:
        return tuple(float(item) for item in self._vector_texts(text, entry))

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
                f"{entry.key} must be a quoted string, e.g. 'text'; got {_show(entry.value)}",
            )
        return self._unquote(tokens[0][1])

    def number(self, entry: Entry) -> float:
        tokens = self._tokens(entry)
        if len(tokens) != 1 or tokens[0][0] != "atom":
            raise self.error(entry.line, f"{entry.key} must be a number, got {_show(entry.value)}")
        return self._number(tokens[0][1], entry)

    def integer(self, entry: Entry, *, minimum: int = 0) -> int:
        value = entry.value.strip()
        if not _INT_RE.fullmatch(value):
            raise self.error(
                entry.line, f"{entry.key} must be an integer, got {_show(entry.value)}"
            )
        number = int(value)
        if number < minimum:
            raise self.error(entry.line, f"{entry.key}={number} must be at least {minimum}")
        return number

    def vector(self, entry: Entry, *, size: int | None = None) -> tuple[float, ...]:
        tokens = self._tokens(entry)
        if len(tokens) != 1 or tokens[0][0] != "vec":
            raise self.error(
                entry.line, f"{entry.key} must be a vector like [0 1], got {_show(entry.value)}"
            )
        values = self._vector(tokens[0][1], entry)
        if size is not None and len(values) != size:
            raise self.error(
                entry.line, f"{entry.key} must have {size} numbers, got {len(values)}"
            )
        return values

    def universe(self, entry: Entry) -> tuple[float, float]:
        """A ``Range=[lo hi]`` with ``lo < hi``."""
        lo, hi = self.vector(entry, size=2)
        if not lo < hi:
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
                f"{entry.key} must look like 'name':'type',[params]; got {_show(entry.value)}",
            )
        name = self._unquote(tokens[0][1])
        kind = self._unquote(tokens[2][1])
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
                    entry.line, f"unknown MF property {_show(key)} in {entry.key} (known: {known})"
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

    def rules(self, section: Section, n_inputs: int, n_outputs: int) -> list[ParsedRule]:
        """The indexed rules of ``[Rules]``: ``a1 ... an, c1 ... cm (weight) : connection``."""
        parsed = []
        for text, line in section.rows:
            match = _RULE_RE.fullmatch(text)
            if match is None:
                raise self.error(
                    line, f"bad rule {_show(text)}: expected e.g. '1 2, 3 (1) : 1' (indices, "
                    "output, (weight) : connection)"
                )
            ant = self._ints(match.group("ant"), line, "antecedent")
            cons = self._ints(match.group("cons"), line, "consequent")
            if len(ant) != n_inputs:
                raise self.error(
                    line, f"rule has {len(ant)} antecedent indices for {n_inputs} inputs"
                )
            if len(cons) != n_outputs:
                raise self.error(
                    line, f"rule has {len(cons)} consequent indices for {n_outputs} output(s)"
                )
            weight_text = match.group("w").strip()
            if (
                len(weight_text) > _MAX_NUMBER_CHARS
                or not _NUMBER_RE.fullmatch(weight_text)
                or not math.isfinite(float(weight_text))
            ):
                raise self.error(line, f"bad rule weight {_show(weight_text)}")
            conn_text = match.group("conn").strip()
            if not _INT_RE.fullmatch(conn_text):
                raise self.error(line, f"bad rule connection {_show(conn_text)} (1 = AND, 2 = OR)")
            parsed.append(
                ParsedRule(tuple(ant), tuple(cons), float(weight_text), int(conn_text), line)
            )
        return parsed

    def _ints(self, text: str, line: int, what: str) -> list[int]:
        items = text.split()
        for item in items:
            if not _INT_RE.fullmatch(item):
                raise self.error(line, f"bad {what} index {_show(item)} in rule")
        return [int(item) for item in items]
