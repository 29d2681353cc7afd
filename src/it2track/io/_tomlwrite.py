"""Writing it2track's TOML format (the layout is described in :mod:`.tomlfmt`): every float
with ``repr`` precision, MFs as inline tables, one ``[[rules]]`` table per rule."""


from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence

from ..fuzzy import AnySystem as System
from ..fuzzy import (
    Connective,
    Discrete,
    Input,
    IT2Mamdani,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    Reducer,
    Sampling,
    ScaledLagged,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TypeReducer,
    WeightedDefuzzifier,
)
from ._tomlschema import FORMAT, KINDS, MAX_DEPTH, MF_TYPES, VERSION, WITH_SETS
from ._writing import refuse_hedges
from .errors import UnsupportedFeatureError

__all__ = ["dumps"]


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


class _Infinite(float):
    """An infinity the schema allows (``Binary``'s direction), written ``inf``/``-inf``."""


def _toml_value(value: object) -> str:
    if isinstance(value, _Infinite):
        return "inf" if value > 0 else "-inf"
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
    if depth > MAX_DEPTH:
        raise UnsupportedFeatureError(f"{what}: MFs nested too deeply")
    kind = type(mf)
    for name, (cls, fields) in MF_TYPES.items():
        if kind is cls:
            table: dict[str, object] = {"type": name}
            for field in fields:
                value = float(getattr(mf, field))
                if field == "h" and value == 1.0:
                    continue
                table[field] = _Infinite(value) if math.isinf(value) else value
            return table
    if kind is Discrete:
        assert isinstance(mf, Discrete)
        table = {"type": "discrete", "points": [[x, y] for x, y in mf.points]}
        if mf.h != 1.0:
            table["h"] = float(mf.h)
        return table
    if kind is ScaledLagged:
        assert isinstance(mf, ScaledLagged)
        table = {"type": "scaled-lagged", "scale": float(mf.scale), "lag": float(mf.lag)}
        if of is None or not (mf.upper is of or mf.upper == of):
            table["upper"] = _mf_table(mf.upper, of=None, what=what, depth=depth + 1)
        return table
    raise UnsupportedFeatureError(
        f"{what} is a {kind.__name__}, which the TOML format cannot carry (it carries "
        f"{', '.join(c.__name__ for c, _ in MF_TYPES.values())}, Discrete and ScaledLagged)"
    )


def _known_reducer(reducer: TypeReducer) -> TypeReducer:
    try:
        known: TypeReducer = Reducer.from_name(reducer.name).value
    except ValueError:
        raise UnsupportedFeatureError(f"unknown type reducer {reducer.name!r}") from None
    return known


def _sets_lines(var: Input, header: str) -> list[str]:
    if not var.sets:  # an input feeding linear consequents only
        return ["sets = []"]
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
        For membership functions of classes the format does not know, an unknown reducer, or
        hedges.
    """
    refuse_hedges(system, "TOML")
    kind = next((k for k, cls in KINDS.items() if type(system) is cls), None)
    if kind is None:
        if type(system).__name__ == "HybridSystem":
            raise UnsupportedFeatureError("the TOML format does not carry a HybridSystem yet; "
                                          "save as .fll or save each of its systems")
        raise TypeError(f"can only write IT2Sugeno, T1Sugeno, IT2Mamdani, T1Mamdani or "
                        f"T1Tsukamoto systems, got {type(system)}")
    mamdani = kind in WITH_SETS
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
        if system.sampling is not Sampling.ENDPOINTS:
            lines.append(f"sampling = {_toml_string(system.sampling.value)}")
    if isinstance(system, T1Tsukamoto):
        lines.append(f"aggregation = {_toml_string(system.aggregation.value)}")
    if isinstance(system, IT2Mamdani):
        lines.append(f"type_reduction = {_toml_string(system.type_reduction.value)}")
    if isinstance(system, T1Mamdani) or (
            isinstance(system, T1Sugeno | T1Tsukamoto)
            and system.defuzzifier is not WeightedDefuzzifier.AVERAGE):
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
    if mamdani:
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


