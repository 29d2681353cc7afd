"""Reading it2track's TOML format: typed access to the parsed tables with errors that name
the key path and (where it can be found) the line, and the pieces of a system (MFs, sets,
inputs, consequents, rules). :mod:`.tomlfmt` assembles the system."""


from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from ..fuzzy import (
    Discrete,
    Input,
    IT2Set,
    Linear,
    MembershipFunction,
    Output,
    Rule,
    ScaledLagged,
)
from ._tomlschema import INFINITE_OK, MAX_DEPTH, MF_TYPES
from .errors import FisFormatError

__all__ = ["Reader", "kind_of"]


# ---------------------------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------------------------

_HEADER_RE = re.compile(r"^\s*\[")


class _Locator:
    """Best-effort line numbers for paths like ``("inputs", 1, "sets", 0, "upper")``.

    It follows the layout the writer produces (``[[inputs]]``, ``[[inputs.sets]]``,
    ``[[rules]]`` headers); for other layouts it falls back to the nearest table it finds.
    """

    def __init__(self, text: str) -> None:
        self.lines = text.split("\n")

    def _headers(self, name: str, start: int, end: int) -> list[int]:
        pattern = re.compile(r"^\s*\[\[\s*" + re.escape(name).replace(r"\.", r"\s*\.\s*")
                             + r"\s*\]\]")
        return [i for i in range(start, end) if pattern.match(self.lines[i])]

    def _next_header(self, after: int, end: int, pattern: str | None = None) -> int:
        for i in range(after + 1, end):
            line = self.lines[i]
            if pattern is None and _HEADER_RE.match(line):
                return i
            if pattern is not None and re.match(pattern, line):
                return i
        return end

    def _key_line(self, key: str, start: int, end: int) -> int | None:
        pattern = re.compile(r"^\s*(" + re.escape(key) + r'|"' + re.escape(key) + r'")\s*=')
        for i in range(start, end):
            if pattern.match(self.lines[i]):
                return i
        return None

    def line(self, path: Sequence[str | int]) -> int | None:
        n = len(self.lines)
        first_header = self._next_header(-1, n)
        start, end = 0, first_header
        rest = list(path)
        found: int | None = None
        if rest and rest[0] in ("inputs", "rules") and len(rest) >= 2 and isinstance(rest[1], int):
            table = str(rest[0])
            headers = self._headers(table, 0, n)
            index = rest[1]
            if index >= len(headers):
                return None
            start = headers[index]
            end = self._next_header(start, n, r"^\s*\[\[\s*" + table + r"\s*\]\]")
            found = start
            rest = rest[2:]
            if table == "inputs" and len(rest) >= 2 and rest[0] == "sets" and isinstance(
                rest[1], int
            ):
                set_headers = self._headers("inputs.sets", start, end)
                if rest[1] < len(set_headers):
                    start = set_headers[rest[1]]
                    end = self._next_header(start, end)
                    found = start
                    rest = rest[2:]
            else:
                end = self._next_header(start, end)
        if rest and isinstance(rest[0], str):
            key_line = self._key_line(rest[0], found + 1 if found is not None else start, end)
            if key_line is not None:
                found = key_line
        return None if found is None else found + 1


class Reader:
    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.locator = _Locator(text)

    def error(self, where: Sequence[str | int], message: str) -> FisFormatError:
        dotted = ""
        for part in where:
            dotted += f"[{part}]" if isinstance(part, int) else (f".{part}" if dotted else part)
        prefix = f"{dotted}: " if dotted else ""
        return FisFormatError(self.path, self.locator.line(where), prefix + message)

    # -- typed access --------------------------------------------------------------------------
    def table(self, value: object, where: Sequence[str | int]) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.error(where, f"expected a table, got {kind_of(value)}")
        return value

    def keys(self, table: Mapping[str, Any], allowed: set[str], required: set[str],
             where: Sequence[str | int]) -> None:
        for key in table:
            if key not in allowed:
                raise self.error((*where, key), f"unknown key {key!r}")
        for key in sorted(required):
            if key not in table:
                raise self.error(where, f"missing key {key!r}")

    def string(self, value: object, where: Sequence[str | int]) -> str:
        if not isinstance(value, str):
            raise self.error(where, f"expected a string, got {kind_of(value)}")
        return value

    def number(self, value: object, where: Sequence[str | int], *,
               infinite_ok: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(where, f"expected a number, got {kind_of(value)}")
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        if math.isinf(number) and infinite_ok:
            return number
        if not math.isfinite(number):
            raise self.error(where, f"number {value!r} must be finite")
        return number

    def array(self, value: object, where: Sequence[str | int]) -> list[Any]:
        if not isinstance(value, list):
            raise self.error(where, f"expected an array, got {kind_of(value)}")
        return value

    def guarded(self, where: Sequence[str | int], build: Callable[[], Any]) -> Any:
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                return build()
        except FloatingPointError as exc:
            raise self.error(where, f"numeric overflow ({exc}); check the magnitudes") from None
        except (ValueError, TypeError, OverflowError) as exc:
            if isinstance(exc, FisFormatError):
                raise
            raise self.error(where, str(exc)) from None

    # -- pieces --------------------------------------------------------------------------------
    def mf(self, value: object, where: Sequence[str | int], of: MembershipFunction | None,
           depth: int = 0) -> MembershipFunction:
        table = self.table(value, where)
        if "type" not in table:
            raise self.error(where, "missing key 'type'")
        kind = self.string(table["type"], (*where, "type"))
        if depth > MAX_DEPTH:
            raise self.error(where, "MFs nested too deeply")
        if kind in MF_TYPES:
            cls, fields = MF_TYPES[kind]
            self.keys(table, {"type", *fields}, {f for f in fields if f != "h"}, where)
            args = [self.number(table[f], (*where, f), infinite_ok=(kind, f) in INFINITE_OK)
                    if f in table else 1.0 for f in fields]
            return self.guarded(where, lambda: cls(*args))
        if kind == "discrete":
            self.keys(table, {"type", "points", "h"}, {"points"}, where)
            points = []
            for item in self.array(table["points"], (*where, "points")):
                pair = self.array(item, (*where, "points"))
                if len(pair) != 2:
                    raise self.error((*where, "points"), "expected [x, y] pairs")
                points.append((self.number(pair[0], (*where, "points")),
                               self.number(pair[1], (*where, "points"))))
            h = self.number(table["h"], (*where, "h")) if "h" in table else 1.0
            return self.guarded(where, lambda: Discrete(points, h))
        if kind == "scaled-lagged":
            self.keys(table, {"type", "scale", "lag", "upper"}, {"scale", "lag"}, where)
            scale = self.number(table["scale"], (*where, "scale"))
            lag = self.number(table["lag"], (*where, "lag"))
            if "upper" in table:
                upper = self.mf(table["upper"], (*where, "upper"), None, depth + 1)
            elif of is not None:
                upper = of
            else:
                raise self.error(where, "a scaled-lagged MF needs 'upper' here")
            return self.guarded(where, lambda: ScaledLagged(upper, scale, lag))
        known = ", ".join([*MF_TYPES, "discrete", "scaled-lagged"])
        raise self.error((*where, "type"), f"unknown MF type {kind!r} (known: {known})")

    def set(self, value: object, where: Sequence[str | int]) -> IT2Set:
        table = self.table(value, where)
        self.keys(table, {"name", "mf", "upper", "lower"}, {"name"}, where)
        name = self.string(table["name"], (*where, "name"))
        if "mf" in table:
            if "upper" in table or "lower" in table:
                raise self.error((*where, "mf"), "give either 'mf' (type-1) or 'upper' and 'lower'")
            mf = self.mf(table["mf"], (*where, "mf"), None)
            return IT2Set.type1(mf, name)
        if "upper" not in table or "lower" not in table:
            raise self.error(where, "a set needs 'mf' (type-1) or both 'upper' and 'lower'")
        upper = self.mf(table["upper"], (*where, "upper"), None)
        lower = self.mf(table["lower"], (*where, "lower"), upper)
        return self.guarded(where, lambda: IT2Set(upper, lower, name))

    def input(self, value: object, where: Sequence[str | int]) -> Input:
        table = self.table(value, where)
        self.keys(table, {"name", "universe", "sets"}, {"name", "universe", "sets"}, where)
        name = self.string(table["name"], (*where, "name"))
        universe_v = self.array(table["universe"], (*where, "universe"))
        if len(universe_v) != 2:
            raise self.error((*where, "universe"), "expected [lo, hi]")
        universe = (
            self.number(universe_v[0], (*where, "universe")),
            self.number(universe_v[1], (*where, "universe")),
        )
        if not universe[0] < universe[1]:
            raise self.error((*where, "universe"), f"{list(universe)} must satisfy lo < hi")
        sets_v = self.array(table["sets"], (*where, "sets"))
        sets = [self.set(s, (*where, "sets", j)) for j, s in enumerate(sets_v)]
        seen: set[str] = set()
        for j, s in enumerate(sets):
            if not s.name or s.name in seen:
                raise self.error(
                    (*where, "sets", j, "name"), f"set name {s.name!r} must be non-empty and unique"
                )
            seen.add(s.name)
            set_where: tuple[str | int, ...] = (*where, "sets", j)
            try:
                with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                    s.check_on(universe, owner=f"input {name!r}")
            except FloatingPointError as exc:
                raise self.error(set_where, f"numeric overflow ({exc})") from None
            except ValueError as exc:
                text = str(exc)
                key = "mf" if s.is_type1 else ("upper" if ": upper MF" in text else "lower")
                raise self.error((*set_where, key), text) from None
        return self.guarded(where, lambda: Input(name, universe, sets))

    def output(self, value: object, where: Sequence[str | int]) -> Output:
        inp = self.input(value, where)
        return self.guarded(where, lambda: Output(inp.name, inp.universe, inp.sets))

    def pair(self, value: object, where: Sequence[str | int]) -> float | tuple[float, float]:
        if isinstance(value, list):
            if len(value) != 2:
                raise self.error(where, "expected a number or an interval [lo, hi]")
            lo, hi = self.number(value[0], where), self.number(value[1], where)
            if lo > hi:
                raise self.error(where, f"interval [{lo}, {hi}] must satisfy lo <= hi")
            return lo, hi
        return self.number(value, where)

    def consequent(self, value: object, where: Sequence[str | int], *, mamdani: bool,
                   n_inputs: int) -> object:
        if mamdani:
            return self.string(value, where)
        if isinstance(value, dict):
            self.keys(value, {"linear", "constant"}, {"linear", "constant"}, where)
            coef_v = self.array(value["linear"], (*where, "linear"))
            if len(coef_v) != n_inputs:
                raise self.error((*where, "linear"),
                                 f"needs {n_inputs} coefficients (one per input), got "
                                 f"{len(coef_v)}")
            coefs = [self.pair(c, (*where, "linear")) for c in coef_v]
            const = self.pair(value["constant"], (*where, "constant"))
            return self.guarded(where, lambda: Linear(coefs, const))
        return self.pair(value, where)

    def rule(self, value: object, where: Sequence[str | int], inputs: Sequence[Input], *,
             outputs: Sequence[str], mamdani: bool) -> Rule:
        table = self.table(value, where)
        self.keys(table, {"if", "then", "not", "connective", "weight"}, {"if", "then"}, where)
        antecedent_v = self.table(table["if"], (*where, "if"))
        by_name = {inp.name: inp for inp in inputs}
        for input_name, label in antecedent_v.items():
            if input_name not in by_name:
                raise self.error(
                    (*where, "if"), f"rule names unknown input {input_name!r} (inputs: "
                    f"{[inp.name for inp in inputs]})"
                )
            label_s = self.string(label, (*where, "if"))
            names = [s.name for s in by_name[input_name].sets]
            if label_s not in names:
                raise self.error(
                    (*where, "if"),
                    f"rule names set {label_s!r} of input {input_name!r}, which has sets {names}",
                )
        if not antecedent_v:
            raise self.error((*where, "if"), "a rule needs at least one antecedent")
        antecedent = [antecedent_v.get(inp.name) for inp in inputs]
        negated = [False] * len(inputs)
        if "not" in table:
            for item in self.array(table["not"], (*where, "not")):
                name = self.string(item, (*where, "not"))
                if name not in antecedent_v:
                    raise self.error((*where, "not"),
                                     f"{name!r} is not an input this rule mentions")
                negated[[inp.name for inp in inputs].index(name)] = True
        connective = "and"
        if "connective" in table:
            connective = self.string(table["connective"], (*where, "connective"))
        weight = 1.0
        if "weight" in table:
            weight = self.number(table["weight"], (*where, "weight"))
        then = table["then"]
        n_in = len(inputs)
        if len(outputs) == 1:
            cons = [self.consequent(then, (*where, "then"), mamdani=mamdani, n_inputs=n_in)]
        else:
            then_t = self.table(then, (*where, "then"))
            for key in then_t:
                if key not in outputs:
                    raise self.error((*where, "then"),
                                     f"unknown output {key!r} (outputs: {list(outputs)})")
            cons = [None if name not in then_t else
                    self.consequent(then_t[name], (*where, "then"), mamdani=mamdani, n_inputs=n_in)
                    for name in outputs]
        return self.guarded(where, lambda: Rule(antecedent, consequents=cons, weight=weight,
                                                connective=connective, negated=negated))


def kind_of(value: object) -> str:
    return {dict: "a table", list: "an array", str: "a string", bool: "a boolean",
            int: "an integer", float: "a float"}.get(type(value), type(value).__name__)


