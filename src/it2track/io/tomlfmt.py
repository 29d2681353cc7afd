"""it2track's own TOML format for fuzzy systems: readable, and exact for every system we build.

Every float is written with ``repr`` precision, so a system read back evaluates bit for bit like
the one written. Layout (the paper's IT2 controller, abridged)::

    # it2track fuzzy system; load with it2track.io.load(path)
    format = "it2track-fuzzy-system"
    version = 1
    kind = "it2"                  # "it2" / "t1" (IT2Sugeno / T1Sugeno),
                                  # "it2-mamdani" / "t1-mamdani" (IT2Mamdani / T1Mamdani)
    name = "paper IT2FLC (FoU 0.2)"
    tnorm = "product"             # or "min"
    # snorm = "probor"            # optional, OR rules: "max" (default) or "probor"
    reducer = "exhaustive"        # it2 only: km, ekm, eiasc, exhaustive, nie-tan, wu-mendel
    # reducer_max_iter = 50       # optional, it2 only
    # on_zero_firing = 0.0        # optional: output where no rule fires (default: error);
                                  # one number per output for several outputs
    # outputs = ["u", "v"]        # Sugeno: output names (several outputs)
    # Mamdani only: implication = "min" | "product", aggregation = "max" | "sum" | "probor",
    # resolution = 101, type_reduction = "centroid" | "centre-of-sets" (it2),
    # defuzzifier = "centroid" | "bisector" | "mom" | "som" | "lom" (t1)

    [[inputs]]
    name = "e"
    universe = [-1.0, 1.0]

    [[inputs.sets]]
    name = "N"
    upper = { type = "triangle", a = -1.0, b = -1.0, c = -0.1 }
    lower = { type = "triangle", a = -1.0, b = -1.0, c = -0.3 }
    # a type-1 set has one MF instead:  mf = { type = "triangle", ... }

    [[rules]]
    if = { e = "N", de = "N" }    # inputs not named are not used by the rule
    then = -12.0                  # or an interval [lo, hi]
    # not = ["de"]                # optional: negated antecedents (x is not A)
    # connective = "or"           # optional: "and" (default) or "or"
    # weight = 0.5                # optional, in [0, 1] (default 1)

A first-order consequent is ``then = { linear = [c1, ..., cn], constant = c0 }`` (each
coefficient a number or an interval ``[lo, hi]``); a Mamdani consequent is an output set name,
``then = "NB"``. With several outputs ``then`` is a table by output name,
``then = { u = -12.0, v = "low" }`` (an output left out: the rule does not act on it).
A Mamdani system lists its outputs like its inputs, ``[[outputs]]`` with ``name``,
``universe`` and ``[[outputs.sets]]``.

Membership functions (``h``, the height, may be omitted when 1)::

    { type = "triangle", a, b, c, h }            Triangle
    { type = "trapezoid", a, b, c, d, h }        Trapezoid
    { type = "gaussian", mean, sigma, h }        Gaussian
    { type = "uncertain-mean-gaussian-upper", m1, m2, sigma, h }
    { type = "uncertain-mean-gaussian-lower", m1, m2, sigma, h }
    { type = "scaled-lagged", scale, lag }       ScaledLagged of the set's upper MF
    { type = "scaled-lagged", scale, lag, upper = {...} }   ... of another MF

Unknown keys are errors. Membership functions of other classes (user-defined callables) cannot
be written (:class:`UnsupportedFeatureError`).
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from ..fuzzy import (
    Aggregation,
    Connective,
    Defuzzifier,
    Gaussian,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    Output,
    Reducer,
    Rule,
    ScaledLagged,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    TypeReducer,
    TypeReduction,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)
from ..fuzzy import AnySystem as System
from .errors import FisFormatError, UnsupportedFeatureError

__all__ = ["FORMAT", "VERSION", "dumps", "loads"]

FORMAT = "it2track-fuzzy-system"
VERSION = 1

# type name -> (class, parameter names in constructor order)
_MF_TYPES: dict[str, tuple[type, tuple[str, ...]]] = {
    "triangle": (Triangle, ("a", "b", "c", "h")),
    "trapezoid": (Trapezoid, ("a", "b", "c", "d", "h")),
    "gaussian": (Gaussian, ("mean", "sigma", "h")),
    "uncertain-mean-gaussian-upper": (UncertainMeanGaussianUpper, ("m1", "m2", "sigma", "h")),
    "uncertain-mean-gaussian-lower": (UncertainMeanGaussianLower, ("m1", "m2", "sigma", "h")),
}
_MAX_DEPTH = 8
_TOP_KEYS = {
    "format", "version", "kind", "name", "tnorm", "reducer", "reducer_max_iter",
    "on_zero_firing", "inputs", "rules", "snorm", "outputs", "implication", "aggregation",
    "resolution", "type_reduction", "defuzzifier",
}
_KINDS = {"it2": IT2Sugeno, "t1": T1Sugeno, "it2-mamdani": IT2Mamdani, "t1-mamdani": T1Mamdani}


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------


def _toml_string(text: str) -> str:
    out = ['"']
    for ch in text:
        code = ord(ch)
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch in "\b\t\n\f\r":
            out.append({"\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}[ch])
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04X}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def _toml_key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else _toml_string(key)


def _toml_value(value: object) -> str:
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise UnsupportedFeatureError(f"cannot write the non-finite number {value!r}")
        return repr(value)
    if isinstance(value, Mapping):
        items = ", ".join(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items())
        return "{ " + items + " }" if items else "{}"
    if isinstance(value, Sequence):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} to TOML")


def _mf_table(mf: MembershipFunction, *, of: MembershipFunction | None, what: str,
              depth: int = 0) -> dict[str, object]:
    if depth > _MAX_DEPTH:
        raise UnsupportedFeatureError(f"{what}: MFs nested too deeply")
    kind = type(mf)
    for name, (cls, fields) in _MF_TYPES.items():
        if kind is cls:
            table: dict[str, object] = {"type": name}
            for field in fields:
                value = float(getattr(mf, field))
                if field == "h" and value == 1.0:
                    continue
                table[field] = value
            return table
    if kind is ScaledLagged:
        assert isinstance(mf, ScaledLagged)
        table = {"type": "scaled-lagged", "scale": float(mf.scale), "lag": float(mf.lag)}
        if of is None or not (mf.upper is of or mf.upper == of):
            table["upper"] = _mf_table(mf.upper, of=None, what=what, depth=depth + 1)
        return table
    raise UnsupportedFeatureError(
        f"{what} is a {kind.__name__}, which the TOML format cannot carry (it carries "
        f"{', '.join(c.__name__ for c, _ in _MF_TYPES.values())} and ScaledLagged)"
    )


def _known_reducer(reducer: TypeReducer) -> TypeReducer:
    try:
        known: TypeReducer = Reducer.from_name(reducer.name).value
    except ValueError:
        raise UnsupportedFeatureError(f"unknown type reducer {reducer.name!r}") from None
    return known


def _sets_lines(var: Input, header: str) -> list[str]:
    lines = []
    kind = type(var).__name__.lower()
    for s in var.sets:
        what = f"{kind} {var.name!r} set {s.name!r}"
        lines += ["", f"[[{header}.sets]]", f"name = {_toml_string(s.name)}"]
        if s.lower is s.upper or s.lower == s.upper:
            table = _mf_table(s.upper, of=None, what=f"{what} MF")
            lines.append(f"mf = {_toml_value(table)}")
        else:
            upper = _mf_table(s.upper, of=None, what=f"{what} upper MF")
            lower = _mf_table(s.lower, of=s.upper, what=f"{what} lower MF")
            lines += [f"upper = {_toml_value(upper)}", f"lower = {_toml_value(lower)}"]
    return lines


def _pair(lo: float, hi: float) -> object:
    return float(lo) if _same(lo, hi) else [float(lo), float(hi)]


def _then_value(cons: object) -> object:
    if isinstance(cons, str):
        return cons
    if isinstance(cons, Linear):
        return {
            "linear": [_pair(a, b) for a, b in zip(cons.lo, cons.hi, strict=True)],
            "constant": _pair(cons.constant_lo, cons.constant_hi),
        }
    assert isinstance(cons, tuple)
    return _pair(*cons)


def dumps(system: System) -> str:
    """TOML text for ``system`` (see the module docstring for the layout).

    Raises
    ------
    UnsupportedFeatureError
        For membership functions of classes the format does not know, or an unknown reducer.
    """
    kind = next((k for k, cls in _KINDS.items() if type(system) is cls), None)
    if kind is None:
        raise TypeError(f"can only write IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani systems, "
                        f"got {type(system)}")
    mamdani = isinstance(system, IT2Mamdani | T1Mamdani)
    lines = [
        "# it2track fuzzy system; load with it2track.io.load(path)",
        f"format = {_toml_string(FORMAT)}",
        f"version = {VERSION}",
        f'kind = "{kind}"',
        f"name = {_toml_string(system.name)}",
        f"tnorm = {_toml_string(system.tnorm.value)}",
    ]
    if system.snorm is not SNorm.MAXIMUM:
        lines.append(f"snorm = {_toml_string(system.snorm.value)}")
    if isinstance(system, IT2Sugeno | IT2Mamdani):
        known = _known_reducer(system.reducer)
        lines.append(f"reducer = {_toml_string(known.name)}")
        if system.reducer.max_iter != known.max_iter:
            lines.append(f"reducer_max_iter = {int(system.reducer.max_iter)}")  # type: ignore[arg-type]
    if isinstance(system, IT2Mamdani | T1Mamdani):
        lines += [
            f"implication = {_toml_string(system.implication.value)}",
            f"aggregation = {_toml_string(system.aggregation.value)}",
            f"resolution = {int(system.resolution)}",
        ]
    if isinstance(system, IT2Mamdani):
        lines.append(f"type_reduction = {_toml_string(system.type_reduction.value)}")
    if isinstance(system, T1Mamdani):
        lines.append(f"defuzzifier = {_toml_string(system.defuzzifier.value)}")
    if system.on_zero_firing is not None:
        zero = system.on_zero_firing
        value = float(zero) if isinstance(zero, int | float) else [float(v) for v in zero]
        lines.append(f"on_zero_firing = {_toml_value(value)}")
    if not mamdani and system.outputs:
        lines.append(f"outputs = {_toml_value(list(system.outputs))}")
    for inp in system.inputs:
        lines += [
            "",
            "[[inputs]]",
            f"name = {_toml_string(inp.name)}",
            f"universe = {_toml_value([float(v) for v in inp.universe])}",
        ]
        lines += _sets_lines(inp, "inputs")
    if isinstance(system, IT2Mamdani | T1Mamdani):
        for out in system.outputs:
            lines += [
                "",
                "[[outputs]]",
                f"name = {_toml_string(out.name)}",
                f"universe = {_toml_value([float(v) for v in out.universe])}",
            ]
            lines += _sets_lines(out, "outputs")
    names = system.output_names
    for rule in system.rules:
        antecedent = {
            inp.name: label
            for inp, label in zip(system.inputs, rule.antecedent, strict=True)
            if label is not None
        }
        if system.n_outputs == 1:
            then = _toml_value(_then_value(rule.consequent))
        else:
            then = _toml_value({
                name: _then_value(c)
                for name, c in zip(names, rule.consequents, strict=True) if c is not None
            })
        lines += ["", "[[rules]]", f"if = {_toml_value(antecedent)}"]
        negated = [inp.name for inp, neg in zip(system.inputs, rule.negated, strict=True) if neg]
        if negated:
            lines.append(f"not = {_toml_value(negated)}")
        if rule.connective is not Connective.AND:
            lines.append(f"connective = {_toml_string(rule.connective.value)}")
        if rule.weight != 1.0:
            lines.append(f"weight = {_toml_value(rule.weight)}")
        lines.append(f"then = {then}")
    return "\n".join(lines) + "\n"


def _same(a: float, b: float) -> bool:
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


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


class _Reader:
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
            raise self.error(where, f"expected a table, got {_kind(value)}")
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
            raise self.error(where, f"expected a string, got {_kind(value)}")
        return value

    def number(self, value: object, where: Sequence[str | int]) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(where, f"expected a number, got {_kind(value)}")
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        if not math.isfinite(number):
            raise self.error(where, f"number {value!r} must be finite")
        return number

    def array(self, value: object, where: Sequence[str | int]) -> list[Any]:
        if not isinstance(value, list):
            raise self.error(where, f"expected an array, got {_kind(value)}")
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
        if depth > _MAX_DEPTH:
            raise self.error(where, "MFs nested too deeply")
        if kind in _MF_TYPES:
            cls, fields = _MF_TYPES[kind]
            self.keys(table, {"type", *fields}, {f for f in fields if f != "h"}, where)
            args = [self.number(table[f], (*where, f)) if f in table else 1.0 for f in fields]
            return self.guarded(where, lambda: cls(*args))
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
        known = ", ".join([*_MF_TYPES, "scaled-lagged"])
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
        if not sets_v:
            raise self.error((*where, "sets"), "an input needs at least one set")
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


def _kind(value: object) -> str:
    return {dict: "a table", list: "an array", str: "a string", bool: "a boolean",
            int: "an integer", float: "a float"}.get(type(value), type(value).__name__)


_DECODE_LINE_RE = re.compile(r"\(at line (\d+), column \d+\)")


def loads(text: str, path: str = "<string>") -> System:
    """Parse it2track TOML text into a system.

    Raises
    ------
    FisFormatError
        On invalid TOML or content, naming ``path``, the line (where it can be found) and the
        problem.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = _DECODE_LINE_RE.search(str(exc))
        message = _DECODE_LINE_RE.sub("", str(exc)).strip()
        raise FisFormatError(
            path, int(match.group(1)) if match else None, f"invalid TOML: {message}"
        ) from None
    reader = _Reader(text, path)
    reader.keys(data, _TOP_KEYS, {"format", "version", "kind", "inputs", "rules"}, ())
    fmt = reader.string(data["format"], ("format",))
    if fmt != FORMAT:
        raise reader.error(("format",), f"format={fmt!r}, expected {FORMAT!r}")
    version = data["version"]
    if isinstance(version, bool) or version != VERSION:
        raise reader.error(("version",), f"version={version!r} is not supported (only {VERSION})")
    kind = reader.string(data["kind"], ("kind",))
    if kind not in _KINDS:
        raise reader.error(("kind",), f"kind={kind!r} must be 'it2' or 't1' (Sugeno), "
                           "'it2-mamdani' or 't1-mamdani'")
    mamdani = kind.endswith("mamdani")
    it2 = kind.startswith("it2")
    name = reader.string(data.get("name", ""), ("name",))
    options: dict[str, Any] = {"name": name}

    def enum_key(key: str, lookup: Callable[[str], Any], allowed: bool) -> None:
        if key not in data:
            return
        if not allowed:
            raise reader.error((key,), f"{key!r} does not apply to kind = {kind!r}")
        text = reader.string(data[key], (key,))
        options[key] = reader.guarded((key,), lambda: lookup(text))

    enum_key("tnorm", TNorm.from_name, True)
    enum_key("snorm", SNorm.from_name, True)
    enum_key("implication", Implication.from_name, mamdani)
    enum_key("aggregation", Aggregation.from_name, mamdani)
    enum_key("type_reduction", TypeReduction.from_name, kind == "it2-mamdani")
    enum_key("defuzzifier", Defuzzifier.from_name, kind == "t1-mamdani")
    if "resolution" in data:
        if not mamdani:
            raise reader.error(("resolution",), f"'resolution' does not apply to kind = {kind!r}")
        resolution = data["resolution"]
        if isinstance(resolution, bool) or not isinstance(resolution, int):
            raise reader.error(("resolution",), f"{resolution!r} must be an integer")
        options["resolution"] = resolution
    if "on_zero_firing" in data:
        zero = data["on_zero_firing"]
        if isinstance(zero, list):
            options["on_zero_firing"] = tuple(
                reader.number(v, ("on_zero_firing",)) for v in zero)
        else:
            options["on_zero_firing"] = reader.number(zero, ("on_zero_firing",))
    if not it2:
        for key in ("reducer", "reducer_max_iter"):
            if key in data:
                raise reader.error((key,), f"{key!r} applies only to kind = 'it2' or "
                                   "'it2-mamdani'")
    else:
        reducer_name = reader.string(data.get("reducer", "exhaustive"), ("reducer",))
        reducer: TypeReducer = reader.guarded(
            ("reducer",), lambda: Reducer.from_name(reducer_name).value)
        if "reducer_max_iter" in data:
            max_iter = data["reducer_max_iter"]
            if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
                raise reader.error(("reducer_max_iter",),
                                   f"{max_iter!r} must be a positive integer")
            reducer = reducer.with_max_iter(max_iter)
        options["reducer"] = reducer
    inputs_v = reader.array(data["inputs"], ("inputs",))
    if not inputs_v:
        raise reader.error(("inputs",), "a system needs at least one input")
    inputs = [reader.input(v, ("inputs", i)) for i, v in enumerate(inputs_v)]
    names = [inp.name for inp in inputs]
    for i, inp_name in enumerate(names):
        if names.index(inp_name) != i:
            raise reader.error(("inputs", i, "name"), f"duplicate input name {inp_name!r}")
    output_names: list[str] = []
    if mamdani:
        if "outputs" not in data:
            raise reader.error((), "a Mamdani system needs [[outputs]]")
        outputs_v = reader.array(data["outputs"], ("outputs",))
        if not outputs_v:
            raise reader.error(("outputs",), "a Mamdani system needs at least one output")
        outputs = [reader.output(v, ("outputs", i)) for i, v in enumerate(outputs_v)]
        options["outputs"] = tuple(outputs)
        output_names = [o.name for o in outputs]
    elif "outputs" in data:
        output_names = [reader.string(v, ("outputs",))
                        for v in reader.array(data["outputs"], ("outputs",))]
        options["outputs"] = tuple(output_names)
    if not output_names:
        output_names = ["output1"]
    rules_v = reader.array(data["rules"], ("rules",))
    if not rules_v:
        raise reader.error(("rules",), "a system needs at least one rule")
    rules = [reader.rule(v, ("rules", k), inputs, outputs=output_names, mamdani=mamdani)
             for k, v in enumerate(rules_v)]

    def build() -> System:
        system: System = _KINDS[kind](inputs=tuple(inputs), rules=tuple(rules), **options)
        return system

    return reader.guarded((), build)
