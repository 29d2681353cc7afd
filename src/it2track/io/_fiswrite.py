"""The writer of MATLAB ``.fis`` files (:mod:`.matfis` says what is written and refused)."""

from __future__ import annotations

from ..fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    AnySystem,
    Consequent,
    Input,
    IT2Mamdani,
    IT2Sugeno,
    Linear,
    T1Mamdani,
    T1Sugeno,
    TypeReducer,
    TypeReduction,
)
from ._common import mf_to_matlab
from ._fisfile import header_lines, mamdani_methods, reducer_name, rules_lines, variable_lines
from ._lowerlag import scale_lag
from ._writing import (
    check_writable,
    consequent_tables,
    fmt_number,
    fmt_string,
    fmt_vector,
    mamdani_indices,
    output_range,
    sugeno_span,
)
from .errors import UnsupportedFeatureError

__all__ = ["READ_REDUCERS", "WRITE_REDUCERS", "dumps"]

#: ``TypeReductionMethod`` -> reducer
READ_REDUCERS: dict[str, TypeReducer] = {
    "karnikmendel": KM,
    "ekm": EKM,
    "iasc": EIASC,
    "eiasc": EIASC,
    "exhaustive": EXHAUSTIVE,
    "nietan": NIE_TAN,
    "wumendel": WU_MENDEL,
}
WRITE_REDUCERS = {
    "km": "karnikmendel",
    "ekm": "ekm",
    "eiasc": "eiasc",
    "exhaustive": "exhaustive",
    "nie-tan": "nietan",
    "wu-mendel": "wumendel",
}


def _mf_lines(var: Input, *, type2: bool, what_kind: str) -> list[str]:
    lines = []
    for j, s in enumerate(var.sets, start=1):
        what = f"{what_kind} {var.name!r} set {s.name!r}"
        kind, params = mf_to_matlab(s.upper, with_height=False, what=f"{what} upper MF")
        kind, params = _widen_shoulders(kind, params, var.universe)
        line = f"MF{j}={fmt_string(s.name, 'set name')}:'{kind}',{fmt_vector(params)}"
        if type2:
            scale, lags = scale_lag(s, what)
            lag_text = f"[{lags[0]} {lags[1]}]" if len(lags) == 2 else lags[0]
            line += f",'LowerScale',{fmt_number(scale)},'LowerLag',{lag_text}"
        elif not s.is_type1:
            raise UnsupportedFeatureError(f"{what} has a footprint in a type-1 system")
        lines.append(line)
    return lines


def _check_sugeno(tables: list[list[Consequent]]) -> None:
    for table in tables:
        for cons in table:
            if isinstance(cons, Linear):
                if not cons.crisp:
                    raise UnsupportedFeatureError(
                        "MATLAB's linear Sugeno outputs have crisp coefficients; this system "
                        "has interval coefficients (save as .t2fis or .toml)"
                    )
            elif isinstance(cons, tuple) and cons[0] != cons[1]:
                raise UnsupportedFeatureError(
                    "MATLAB's Sugeno systems have crisp consequents; this system has "
                    "interval consequents (save as .t2fis or .toml)"
                )


def _consequent_mf(j: int, cons: Consequent) -> str:
    if isinstance(cons, Linear):
        return f"MF{j}='mf{j}':'linear',{fmt_vector([*cons.lo, cons.constant_lo])}"
    assert isinstance(cons, tuple)
    return f"MF{j}='mf{j}':'constant',[{fmt_number(cons[0])}]"


def dumps(system: AnySystem) -> str:
    """``.fis`` text for ``system`` (type-1 for :class:`T1Sugeno`/:class:`T1Mamdani`, type-2
    for :class:`IT2Sugeno`/:class:`IT2Mamdani`).

    Raises
    ------
    UnsupportedFeatureError
        If the system uses something the format cannot carry (see the module docstring).
    """
    check_writable(system, ".fis")
    type2 = isinstance(system, IT2Sugeno | IT2Mamdani)
    if isinstance(system, IT2Mamdani | T1Mamdani):
        imp, agg = mamdani_methods(system, ".fis")
        if isinstance(system, IT2Mamdani) and (
            system.type_reduction is not TypeReduction.CENTROID
        ):
            raise UnsupportedFeatureError(
                "MATLAB's type-2 Mamdani systems use centroid type reduction; this system uses "
                "centre-of-sets (save as .t2fis or .toml)"
            )
        for k, out in enumerate(system.outputs):
            zero = system.zero_firing_value(k)
            middle = (out.universe[0] + out.universe[1]) / 2
            if zero is not None and zero != middle:
                raise UnsupportedFeatureError(
                    f"in a .fis Mamdani system the output where no rule fires is the middle of "
                    f"the output range ({middle!r} for {out.name!r}), not on_zero_firing="
                    f"{zero!r}; save as .toml"
                )
        defuzz = (system.defuzzifier.value if isinstance(system, T1Mamdani) else "centroid")
        which = mamdani_indices(system)
    else:
        imp, agg = "prod", "sum"
        defuzz = system.defuzzifier.value if isinstance(system, T1Sugeno) else "wtaver"
        tables, which = consequent_tables(system)
        _check_sugeno(tables)
    extra: list[str] = []
    if isinstance(system, IT2Sugeno | IT2Mamdani):
        method = reducer_name(system.reducer, WRITE_REDUCERS, READ_REDUCERS, ".fis")
        extra.append(f"TypeReductionMethod='{method}'")
    lines = header_lines(system, imp=imp, agg=agg, defuzz=defuzz, extra=extra)
    for k, inp in enumerate(system.inputs, start=1):
        lines += variable_lines(f"Input{k}", inp.name, inp.universe, len(inp.sets),
                                _mf_lines(inp, type2=type2, what_kind="input"))
    if isinstance(system, IT2Mamdani | T1Mamdani):
        for k, out in enumerate(system.outputs, start=1):
            lines += variable_lines(f"Output{k}", out.name, out.universe, len(out.sets),
                                    _mf_lines(out, type2=type2, what_kind="output"))
    else:
        for k, (out_name, table) in enumerate(zip(system.output_names, tables, strict=True)):
            mfs = [_consequent_mf(j, cons) for j, cons in enumerate(table, start=1)]
            universe = output_range(sugeno_span(table), system.zero_firing_value(k))
            lines += variable_lines(f"Output{k + 1}", out_name, universe, len(table), mfs)
    return "\n".join(lines + rules_lines(system, which)) + "\n"


def _widen_shoulders(
    kind: str, params: tuple[float, ...], universe: tuple[float, float]
) -> tuple[str, tuple[float, ...]]:
    """Move a shoulder inside the universe out to its end (same values on the universe)."""
    if kind not in ("trimf", "trapmf"):
        return kind, params
    a, b, c, d = (params[0], params[1], params[1], params[2]) if kind == "trimf" else params
    lo, hi = universe
    left = a == b and a > lo
    right = c == d and d < hi
    if not (left or right):
        return kind, params
    if left:
        a = b = lo
    if right:
        c = d = hi
    return "trapmf", (a, b, c, d)


