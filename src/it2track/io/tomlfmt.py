"""it2track's own TOML format for fuzzy systems: readable, and exact for every system we build.

Every float is written with ``repr`` precision, so a system read back evaluates bit for bit like
the one written. Layout (the paper's IT2 controller, abridged)::

    # it2track fuzzy system; load with it2track.io.load(path)
    format = "it2track-fuzzy-system"
    version = 1
    kind = "it2"                  # "it2" / "t1" (IT2Sugeno / T1Sugeno),
                                  # "it2-mamdani" / "t1-mamdani" (IT2Mamdani / T1Mamdani),
                                  # "t1-tsukamoto" (T1Tsukamoto: aggregation, defuzzifier)
    name = "paper IT2FLC (FoU 0.2)"
    tnorm = "product"             # or "min"
    # snorm = "probor"            # optional, OR rules: "max" (default) or "probor"
    reducer = "exhaustive"        # it2 only: km, ekm, eiasc, exhaustive, nie-tan, wu-mendel
    # reducer_max_iter = 50       # optional, it2 only
    # on_zero_firing = 0.0        # optional: output where no rule fires (default: error);
                                  # one number per output for several outputs
    # outputs = ["u", "v"]        # Sugeno: output names (several outputs)
    # Mamdani only: implication = "min" | "product", aggregation = "max" | "sum" | "probor",
    # resolution = 101, sampling = "endpoints" (MATLAB's, default) | "midpoints" (fuzzylite's),
    # type_reduction = "centroid" | "centre-of-sets" (it2),
    # defuzzifier = "centroid" | "bisector" | "mom" | "som" | "lom" (t1)
    # Sugeno t1 only: defuzzifier = "wtaver" (default) | "wtsum"

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

import re
import tomllib
from collections.abc import Callable
from typing import Any

from ..fuzzy import (
    Aggregation,
    Defuzzifier,
    Implication,
    Reducer,
    Sampling,
    SNorm,
    TNorm,
    TypeReducer,
    TypeReduction,
    WeightedDefuzzifier,
)
from ..fuzzy import AnySystem as System
from ._tomlread import Reader
from ._tomlschema import FORMAT, KINDS, TOP_KEYS, VERSION, WITH_SETS
from ._tomlwrite import dumps
from .errors import FisFormatError

__all__ = ["FORMAT", "VERSION", "dumps", "loads"]


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
    reader = Reader(text, path)
    reader.keys(data, TOP_KEYS, {"format", "version", "kind", "inputs", "rules"}, ())
    fmt = reader.string(data["format"], ("format",))
    if fmt != FORMAT:
        raise reader.error(("format",), f"format={fmt!r}, expected {FORMAT!r}")
    version = data["version"]
    if isinstance(version, bool) or version != VERSION:
        raise reader.error(("version",), f"version={version!r} is not supported (only {VERSION})")
    kind = reader.string(data["kind"], ("kind",))
    if kind not in KINDS:
        raise reader.error(("kind",), f"kind={kind!r} must be 'it2' or 't1' (Sugeno), "
                           "'it2-mamdani', 't1-mamdani' or 't1-tsukamoto'")
    mamdani = kind in WITH_SETS
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
    proper_mamdani = kind.endswith("mamdani")
    enum_key("implication", Implication.from_name, proper_mamdani)
    enum_key("aggregation", Aggregation.from_name, mamdani)
    enum_key("type_reduction", TypeReduction.from_name, kind == "it2-mamdani")
    enum_key("defuzzifier", Defuzzifier.from_name if proper_mamdani
             else WeightedDefuzzifier.from_name, kind in ("t1-mamdani", "t1", "t1-tsukamoto"))
    enum_key("sampling", Sampling.from_name, proper_mamdani)
    if "resolution" in data:
        if not proper_mamdani:
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
        system: System = KINDS[kind](inputs=tuple(inputs), rules=tuple(rules), **options)
        return system

    return reader.guarded((), build)
