"""The text layer shared by MATLAB's ``.fis`` and the IT2FLS toolbox's ``.t2fis`` formats.

Both are INI-like: ``[System]``, ``[Input1]`` ..., ``[Output1]`` ..., ``[Rules]`` sections of
``Key=value`` lines (``[Rules]`` holds one indexed rule per line); lines starting with ``%``
(MATLAB) or ``#`` (Octave, fuzzylite) are comments. Values are MATLAB literals: quoted strings
(``'it''s'``), numbers, row vectors (``[-1 0 1]``) and, for membership functions,
``'name':'type',[params]``.

This module parses that syntax into sections with line numbers and converts values strictly:
no ``Inf``, ``NaN`` or general expressions -- every number must match MATLAB's plain decimal
syntax and be finite. The one expression read is what MATLAB's own example files hold in vector
items: products and quotients of numbers and ``pi`` (``[-pi/4 pi/4]``), evaluated left to
right in double precision as MATLAB does. It knows nothing about fuzzy semantics beyond the
indexed rule syntax.

A *lenient* document (``.fis``, whose files come from MATLAB, Octave and fuzzylite) takes a
section's ``MF`` lines in file order, as MATLAB's ``readfis`` does, so a repeated key (MATLAB's
own ``slcp1.fis`` has two ``MF2`` lines) is the next MF, with a :class:`FisFormatWarning`; and
it warns about unknown keys instead of refusing them. A strict document (``.t2fis``) refuses
both.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

from ._matvalues import MAX_NUMBER_CHARS, NUMBER_RE, Entry, MFValue, ValueParser, show
from .errors import FisFormatError, FisFormatWarning

__all__ = [
    "Counts",
    "Document",
    "Entry",
    "MFValue",
    "ParsedRule",
    "Section",
    "decode",
]

_INT_RE = re.compile(r"[+-]?\d{1,9}")
_SECTION_RE = re.compile(r"\[\s*(System|Rules|Input[1-9]\d*|Output[1-9]\d*)\s*\]")
_ANY_SECTION_RE = re.compile(r"\[.*\]")
_KEY_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
_MF_KEY_RE = re.compile(r"MF([1-9]\d{0,8})")
_RULE_RE = re.compile(r"(?P<ant>[^,()]*),(?P<cons>[^,()]*)\((?P<w>[^()]*)\)\s*:\s*(?P<conn>.*)")


def decode(data: bytes) -> str:
    """Text of a MATLAB-style file: UTF-8 (a BOM is dropped), else Latin-1 (never fails)."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


@dataclass
class Section:
    """A ``[Title]`` section: its entries by key, its ``MF`` lines in file order (lenient
    documents), or (``[Rules]``) its rows in order."""

    title: str
    line: int
    entries: dict[str, Entry] = field(default_factory=dict)
    mfs: list[Entry] = field(default_factory=list)
    rows: list[tuple[str, int]] = field(default_factory=list)

    @property
    def kind(self) -> str:
        return self.title.rstrip("0123456789")

    @property
    def index(self) -> int:
        digits = self.title[len(self.kind) :]
        return int(digits) if digits else 0


@dataclass(frozen=True)
class ParsedRule:
    """An indexed rule line ``a1 a2 ..., c (w) : k``.

    Indices are kept as written numbers: MATLAB's are integers, Octave and fuzzylite write
    ``1.000`` and encode hedges in the fraction (``1.2``: "very" set 1); the rule builder
    decides what it reads.
    """

    antecedent: tuple[float, ...]
    consequent: tuple[float, ...]
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


class Document(ValueParser):
    """A parsed MATLAB-style fuzzy-system file.

    Parameters
    ----------
    text : str
        File content.
    path : str
        Used in error messages.
    lenient : bool
        Read as MATLAB's ``readfis`` does (``MF`` lines in order, unknown keys warned about);
        otherwise refuse repeated and unknown keys.
    """

    def __init__(self, text: str, path: str, *, lenient: bool = False) -> None:
        self.path = path
        self.lenient = lenient
        self.sections: dict[str, Section] = {}
        lines = text.split("\n")
        self.n_lines = len(lines)
        current: Section | None = None
        for number, raw in enumerate(lines, start=1):
            line = raw.strip()
            if not line or line[0] in "%#":
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
                    number, f"expected Key=value in [{current.title}], got {show(line)}"
                )
            entry = Entry(key, value.strip(), number)
            if lenient and _MF_KEY_RE.fullmatch(key):
                current.mfs.append(entry)
                current.entries.setdefault(key, entry)
                continue
            if key in current.entries:
                first = current.entries[key].line
                raise self.error(
                    number, f"duplicate key {key!r} in [{current.title}] (first at line {first})"
                )
            current.entries[key] = entry

    # -- errors ------------------------------------------------------------------------------
    def error(self, line: int | None, message: str) -> FisFormatError:
        return FisFormatError(self.path, line, message)

    def warn(self, line: int | None, message: str) -> None:
        warnings.warn(FisFormatWarning(self.path, line, message), stacklevel=2)

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

    def method(
        self, system: Section, key: str, allowed: Sequence[str], default: str
    ) -> tuple[str, int | None]:
        """A ``...Method`` string of ``[System]`` (lower case, one of ``allowed``) and its line
        (``None`` when absent, then ``default``)."""
        if key not in system.entries:
            return default, None
        entry = system.entries[key]
        value = self.string(entry)
        if value.lower() not in allowed:
            choices = ", ".join(repr(a) for a in allowed)
            raise self.error(entry.line, f"{key}={value!r} is not supported ({choices})")
        return value.lower(), entry.line

    def counts(self, system: Section, *, min_mfs: int = 1) -> Counts:
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

    def mf_entries(self, section: Section, n: int, count_entry: Entry) -> list[Entry]:
        """The ``n`` MF lines of a lenient section, in file order (MATLAB's reading).

        A key whose number is not its position (a repeated ``MF2``) is read by position, with a
        warning; more lines than ``NumMFs`` are all read, with a warning, as fuzzylite's
        importer reads them (fuzzylite's exports can undercount); fewer is an error.
        """
        found = section.mfs
        if len(found) > n:
            extra = found[n]
            self.warn(extra.line, f"{extra.key} is MF line {n + 1} but {count_entry.key}="
                      f"{count_entry.value}: all {len(found)} MF lines read, as fuzzylite "
                      "reads them")
        if len(found) < n:
            raise self.error(
                count_entry.line,
                f"[{section.title}] has {len(found)} MF lines but "
                f"{count_entry.key}={count_entry.value}",
            )
        for position, entry in enumerate(found, start=1):
            if entry.key != f"MF{position}":
                self.warn(entry.line, f"{entry.key} is MF line {position} of [{section.title}]; "
                          f"read as MF{position}, in file order, as MATLAB's readfis does")
        return found

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
        """The ``[Rules]``, as many as ``NumRules`` promised (a lenient document: at least as
        many; the others are read too, with a warning, as fuzzylite reads them)."""
        section = self.section("Rules", promised_by=counts.n_rules_entry)
        parsed = self.rules(section, counts.n_inputs, counts.n_outputs)
        if self.lenient and len(parsed) > counts.n_rules:
            self.warn(counts.n_rules_entry.line, f"NumRules={counts.n_rules} but [Rules] has "
                      f"{len(parsed)} rules: all read, as fuzzylite reads them")
        elif len(parsed) != counts.n_rules:
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
        """Every key of ``section`` is in ``allowed`` or matches ``pattern`` (a lenient
        document warns about the others and ignores them)."""
        regex = re.compile(pattern) if pattern else None
        for key, entry in section.entries.items():
            if key in allowed or (regex is not None and regex.fullmatch(key)):
                continue
            if self.lenient:
                self.warn(entry.line, f"unknown key {key!r} in [{section.title}] ignored")
                continue
            raise self.error(entry.line, f"unknown key {key!r} in [{section.title}]")

    def rules(self, section: Section, n_inputs: int, n_outputs: int) -> list[ParsedRule]:
        """The indexed rules of ``[Rules]``: ``a1 ... an, c1 ... cm (weight) : connection``."""
        parsed = []
        for text, line in section.rows:
            match = _RULE_RE.fullmatch(text)
            if match is None:
                raise self.error(
                    line, f"bad rule {show(text)}: expected e.g. '1 2, 3 (1) : 1' (indices, "
                    "output, (weight) : connection)"
                )
            ant = self._indices(match.group("ant"), line, "antecedent")
            cons = self._indices(match.group("cons"), line, "consequent")
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
                len(weight_text) > MAX_NUMBER_CHARS
                or not NUMBER_RE.fullmatch(weight_text)
                or not math.isfinite(float(weight_text))
            ):
                raise self.error(line, f"bad rule weight {show(weight_text)}")
            conn_text = match.group("conn").strip()
            if not _INT_RE.fullmatch(conn_text):
                raise self.error(line, f"bad rule connection {show(conn_text)} (1 = AND, 2 = OR)")
            parsed.append(
                ParsedRule(tuple(ant), tuple(cons), float(weight_text), int(conn_text), line)
            )
        return parsed

    def _indices(self, text: str, line: int, what: str) -> list[float]:
        items = text.split()
        values = []
        for item in items:
            if _INT_RE.fullmatch(item):
                values.append(float(int(item)))
            elif self.lenient and len(item) <= 20 and re.fullmatch(r"[+-]?\d{1,9}\.\d*", item):
                values.append(float(item))
            else:
                raise self.error(line, f"bad {what} index {show(item)} in rule")
        return values
