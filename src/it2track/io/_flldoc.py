"""The syntax of fuzzylite's FuzzyLite Language: sections (``Engine:``, ``InputVariable:``,
``OutputVariable:``, ``RuleBlock:``) of ``key: value`` lines with ``#`` comments, rules, numbers as
fuzzylite writes them (``nan``, ``inf``), kept with their line numbers. The meaning is
:mod:`._fllbuild`'s."""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field

from ._ruletree import Compound, Condition, Proposition
from .errors import FisFormatError, FisFormatWarning

__all__ = ["SECTIONS", "Document", "Item", "Section", "show"]

_NUMBER_RE = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?|[+-]?inf|nan")
_MAX_NUMBER_CHARS = 80
_KEY_RE = re.compile(r"([A-Za-z][A-Za-z-]*)\s*:(.*)")
SECTIONS = {
    "Engine": {"description"},
    "InputVariable": {"description", "enabled", "range", "lock-range", "term"},
    "OutputVariable": {"description", "enabled", "range", "lock-range", "aggregation",
                       "defuzzifier", "default", "lock-previous", "term"},
    "RuleBlock": {"description", "enabled", "conjunction", "disjunction", "implication",
                  "activation", "rule"},
}
_REPEATABLE = {"term", "rule"}
_HEDGES = ("not", "very", "somewhat", "extremely", "seldom", "any")
_TOKEN_RE = re.compile(r"\(|\)|[^\s()]+")


@dataclass(frozen=True)
class Item:
    """One ``key: value`` line."""

    key: str
    value: str
    line: int


@dataclass
class Section:
    """``Engine:``, ``InputVariable:``, ``OutputVariable:`` or ``RuleBlock:`` and its lines."""

    kind: str
    name: str
    line: int
    items: dict[str, Item] = field(default_factory=dict)
    terms: list[Item] = field(default_factory=list)
    rules: list[Item] = field(default_factory=list)


class Document:
    """A parsed ``.fll`` file: its sections in order, with line numbers."""

    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.sections: list[Section] = []
        current: Section | None = None
        for number, raw in enumerate(text.split("\n"), start=1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            match = _KEY_RE.fullmatch(line)
            if match is None:
                raise self.error(number, f"expected 'key: value', got {show(line)}")
            key, value = match.group(1), match.group(2).strip()
            if key in SECTIONS:
                if key == "Engine" and any(s.kind == "Engine" for s in self.sections):
                    raise self.error(number, "a second Engine")
                current = Section(key, value, number)
                self.sections.append(current)
                continue
            if current is None:
                raise self.error(number, f"{key!r} before the first section (expected Engine:, "
                                 "InputVariable:, OutputVariable: or RuleBlock:)")
            if key not in SECTIONS[current.kind]:
                known = ", ".join(sorted(SECTIONS[current.kind]))
                raise self.error(number, f"unknown key {key!r} in {current.kind} (known: {known})")
            item = Item(key, value, number)
            if key == "term":
                current.terms.append(item)
            elif key == "rule":
                current.rules.append(item)
            elif key in current.items:
                raise self.error(number, f"duplicate key {key!r} in {current.kind} "
                                 f"{current.name} (first at line {current.items[key].line})")
            else:
                current.items[key] = item

    def error(self, line: int | None, message: str) -> FisFormatError:
        return FisFormatError(self.path, line, message)

    def warn(self, line: int | None, message: str) -> None:
        warnings.warn(FisFormatWarning(self.path, line, message), stacklevel=3)

    def number(self, text: str, line: int, what: str, *, finite: bool = True) -> float:
        """A number as fuzzylite writes it (``nan``, ``inf`` only where ``finite=False``)."""
        if len(text) > _MAX_NUMBER_CHARS or not _NUMBER_RE.fullmatch(text):
            raise self.error(line, f"bad number {show(text)} in {what}")
        value = float(text)
        if finite and not math.isfinite(value):
            raise self.error(line, f"{what}: {text} must be a finite number")
        return value

    def rule(self, item: Item) -> tuple[Condition, list[tuple[str, str, tuple[str, ...]]], float]:
        """A ``rule:`` line: its condition, its conclusions (variable, term, hedges), its weight."""
        tokens = _TOKEN_RE.findall(item.value)
        pos = 0

        def peek() -> str | None:
            return tokens[pos] if pos < len(tokens) else None

        def take(what: str) -> str:
            nonlocal pos
            if pos >= len(tokens):
                raise self.error(item.line, f"rule ends where {what} was expected")
            pos += 1
            return tokens[pos - 1]

        def expect(word: str) -> None:
            got = take(repr(word))
            if got != word:
                raise self.error(item.line, f"expected {word!r} in the rule, got {got!r}")

        def proposition() -> Proposition:
            variable = take("a variable")
            expect("is")
            hedges = []
            while peek() in _HEDGES:
                hedges.append(take("a hedge"))
            if hedges and hedges[-1] == "any" and peek() in (None, "and", "or", "then", "with",
                                                             ")"):
                term = ""  # fuzzylite's 'x is any' names no term: the builder takes the first
            else:
                term = take("a term")
            if term in _HEDGES or term in ("and", "or", "then", "with", "(", ")"):
                raise self.error(item.line, f"expected a term after {variable!r} is, got "
                                 f"{term!r}")
            negated = False  # leading 'not's are the proposition's negation (outermost)
            while hedges and hedges[0] == "not":
                negated = not negated
                hedges.pop(0)
            return Proposition(variable, term, negated, tuple(hedges))

        def operand() -> Condition:
            if peek() == "(":
                take("(")
                inner = disjunction()
                expect(")")
                return inner
            return proposition()

        def conjunction() -> Condition:
            parts = [operand()]
            while peek() == "and":
                take("and")
                parts.append(operand())
            return parts[0] if len(parts) == 1 else Compound("and", tuple(parts))

        def disjunction() -> Condition:
            parts = [conjunction()]
            while peek() == "or":
                take("or")
                parts.append(conjunction())
            return parts[0] if len(parts) == 1 else Compound("or", tuple(parts))

        expect("if")
        condition = disjunction()
        expect("then")
        conclusions = []
        while True:
            prop = proposition()
            hedges = ("not",) * prop.negated + prop.hedges
            conclusions.append((prop.variable, prop.term, hedges))
            if peek() != "and":
                break
            take("and")
        weight = 1.0
        if peek() == "with":
            take("with")
            weight = self.number(take("a weight"), item.line, "the rule weight")
        if peek() is not None:
            raise self.error(item.line, f"unexpected {peek()!r} at the end of the rule")
        if not 0.0 <= weight <= 1.0:
            raise self.error(item.line, f"rule weight {weight:g} must be in [0, 1]")
        return condition, conclusions, weight

    def boolean(self, item: Item) -> bool:
        if item.value not in ("true", "false"):
            raise self.error(item.line, f"{item.key}: expected true or false, got "
                             f"{show(item.value)}")
        return item.value == "true"


def show(text: str, limit: int = 60) -> str:
    return repr(text) if len(text) <= limit else repr(text[:limit]) + "..."


