"""MATLAB Fuzzy Logic Toolbox ``.fis`` files: Sugeno and Mamdani, type-1, and type-2 as far as
known.

Type-1 (``sugfis``), as written by MATLAB's ``writeFIS``::

    [System]
    Name='heading'
    Type='sugeno'
    Version=2.0
    NumInputs=2
    NumOutputs=1
    NumRules=9
    AndMethod='prod'
    OrMethod='probor'
    ImpMethod='prod'
    AggMethod='sum'
    DefuzzMethod='wtaver'

    [Input1]
    Name='e'
    Range=[-1 1]
    NumMFs=3
    MF1='N':'trimf',[-1 -1 -0.2]
    ...

    [Output1]
    Name='u'
    Range=[-12 12]
    NumMFs=5
    MF1='mf1':'constant',[-12]
    ...

    [Rules]
    1 1, 1 (1) : 1

Read: ``trimf [a b c]``, ``trapmf [a b c d]``, ``gaussmf [sigma c]``, ``gauss2mf [sigma c1 sigma
c2]`` (equal sigmas, ``c1 <= c2`` only); ``AndMethod`` ``'prod'`` or ``'min'``, ``OrMethod``
``'max'`` or ``'probor'``; several outputs; rules ``a1 ... an, c1 ... cm (w) : k`` with NOT
(``-j``), weights in ``[0, 1]``, AND (``k = 1``) and OR (``k = 2``), output index 0 for an
output a rule leaves out.

- ``Type='sugeno'``: ``'constant',[c]`` and ``'linear',[c1 ... cn c0]`` outputs;
  ``DefuzzMethod='wtaver'`` (``'wtsum'`` is rejected); missing ``AndMethod``/``DefuzzMethod``
  mean MATLAB's Sugeno defaults ``'prod'``/``'wtaver'``.
- ``Type='mamdani'``: output sets like the input sets (evaluated on MATLAB's 101 points);
  ``ImpMethod`` ``'min'``/``'prod'``, ``AggMethod`` ``'max'``/``'sum'``/``'probor'``,
  ``DefuzzMethod`` ``'centroid'``, ``'bisector'``, ``'mom'``, ``'som'``, ``'lom'`` (type-2:
  ``'centroid'``, reduced by ``TypeReductionMethod``); defaults are ``mamfis``'s (min, max,
  min, max, centroid).

Where no rule fires MATLAB returns the middle of the output ``Range``: the loaded system's
``on_zero_firing`` is that midpoint (one per output), and for Sugeno systems the writer chooses
the output ``Range`` so that its midpoint is the system's ``on_zero_firing`` (covering the
constant consequents where floating point allows, else ``[0, 2 c]``); with
``on_zero_firing=None`` the range spans the consequents, so the file loads back with its
midpoint as ``on_zero_firing``. A Mamdani output's ``Range`` is its universe, so its
``on_zero_firing`` must be ``None`` or that midpoint.

MATLAB's ``trimf``/``trapmf`` are 0 outside ``[a, d]``, even next to a shoulder (``a == b``),
while our shoulders (DESIGN.md sec. 2) keep their height beyond the peak side. The two agree
wherever a shoulder's foot is at or beyond the end of the input ``Range``; a file with a
shoulder inside the range (a jump from 0 to 1 in MATLAB) is rejected, and the writer widens
such shoulders of ours to the range end (``trapmf [lo lo b c]``), which MATLAB evaluates as we
do.

Type-2 (``sugfistype2``). MATLAB documents the *objects* (``fismftype2``: an upper MF plus
``LowerScale`` and ``LowerLag``; ``sugfistype2.TypeReductionMethod``) but not the text layout
of a type-2 ``.fis`` file (its documentation asks not to edit ``.fis`` files by hand), so the
layout here is ours, built from the documented property names and MATLAB's own name-value
syntax, and untested against MATLAB itself::

    [System]
    ...
    DefuzzMethod='wtaver'
    TypeReductionMethod='karnikmendel'

    [Input1]
    ...
    MF1='N':'trimf',[-1.1 -1 -0.1],'LowerScale',1,'LowerLag',[0 0.25]

A ``TypeReductionMethod`` line makes the file type-2; every input MF then needs ``LowerScale``
(in ``(0, 1]``) and ``LowerLag`` (one number, or two for the left/right sides of a
``trimf``/``trapmf``, each in ``[0, 1)``). The lower MF is read as in
:meth:`IT2Set.from_scale_lag <it2track.fuzzy.IT2Set.from_scale_lag>` (zero until the upper MF
reaches the lag, peaking at ``LowerScale``): for a ``trimf``/``trapmf`` a triangle/trapezoid
with feet ``a + lag (b - a)`` and ``d - lag (d - c)``, evaluated exactly from the lag's decimal
text and rounded once (not rounded to 15 decimals as ``from_scale_lag`` does); for a Gaussian a
:class:`~it2track.fuzzy.ScaledLagged`. The writer gives each lag the fewest digits that
reproduce our lower MF's feet exactly, so a lag may carry up to ~20 significant digits
(MATLAB reads it as a double: its feet then agree with ours to about one ulp).
``TypeReductionMethod``: ``'karnikmendel'``, ``'ekm'``, ``'iasc'`` (read as :data:`EIASC`),
``'eiasc'``, and -- names MATLAB would take for custom functions, written for our reducers
MATLAB lacks -- ``'exhaustive'``, ``'nietan'``, ``'wumendel'``. Consequents are crisp (MATLAB's
type-2 Sugeno outputs are type-1).

Written: a :class:`T1Sugeno`/:class:`T1Mamdani` as a type-1 file, an
:class:`IT2Sugeno`/:class:`IT2Mamdani` as a type-2 file. Cannot be written
(:class:`UnsupportedFeatureError`): heights other than 1 (type-1 MATLAB MFs have none; a type-2
lower MF's height is its ``LowerScale``), lower MFs that are not a ``LowerScale``/``LowerLag``
image of their upper MF (e.g. uncertain-std or uncertain-mean Gaussians), interval consequents
and interval linear coefficients, MF classes without a MATLAB type, reducer ``max_iter``, a
Mamdani ``resolution`` other than 101, centre-of-sets type reduction, and a Mamdani
``on_zero_firing`` other than the middle of the output range.
"""

from __future__ import annotations

import math
from decimal import Decimal, localcontext
from fractions import Fraction

from ..fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Aggregation,
    AnySystem,
    Consequent,
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
    PiecewiseLinear,
    ScaledLagged,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    TypeReducer,
    TypeReduction,
)
from ..fuzzy.mamdani import RESOLUTION
from ._common import (
    build_input,
    build_rules,
    check_writable,
    consequent_tables,
    fmt_rule,
    guard,
    linear_from,
    mamdani_indices,
    mf_from_matlab,
    mf_to_matlab,
    output_range,
    sugeno_span,
    system_of,
)
from ._matlab import (
    Document,
    MFValue,
    Section,
    fmt_number,
    fmt_string,
    fmt_vector,
)
from .errors import UnsupportedFeatureError

__all__ = ["dumps", "loads"]

_READ_REDUCERS: dict[str, TypeReducer] = {
    "karnikmendel": KM,
    "ekm": EKM,
    "iasc": EIASC,
    "eiasc": EIASC,
    "exhaustive": EXHAUSTIVE,
    "nietan": NIE_TAN,
    "wumendel": WU_MENDEL,
}
_WRITE_REDUCERS = {
    "km": "karnikmendel",
    "ekm": "ekm",
    "eiasc": "eiasc",
    "exhaustive": "exhaustive",
    "nie-tan": "nietan",
    "wu-mendel": "wumendel",
}
_SYSTEM_KEYS = {
    "Name", "Type", "Version", "NumInputs", "NumOutputs", "NumRules", "AndMethod", "OrMethod",
    "ImpMethod", "AggMethod", "DefuzzMethod", "TypeReductionMethod",
}
_TNORMS = {"prod": TNorm.PRODUCT, "min": TNorm.MINIMUM}
_SNORMS = {"max": SNorm.MAXIMUM, "probor": SNorm.PROBOR}
_IMPLICATIONS = {"min": Implication.MINIMUM, "prod": Implication.PRODUCT}
_LOWER_KEYS = ("LowerScale", "LowerLag")


def _variable(doc: Document, section: Section, *, type2: bool, cls: type) -> Input:
    doc.check_keys(section, {"Name", "Range", "NumMFs"}, r"MF[1-9]\d{0,8}")
    name_entry = doc.entry(section, "Name")
    universe = doc.universe(doc.entry(section, "Range"))
    n_mfs_entry = doc.entry(section, "NumMFs")
    n_mfs = doc.integer(n_mfs_entry, minimum=1)
    doc.check_mf_keys(section, n_mfs, n_mfs_entry)
    sets = []
    for j in range(1, n_mfs + 1):
        mfv = doc.mf(doc.entry(section, f"MF{j}"), extras=_LOWER_KEYS if type2 else ())
        upper = mf_from_matlab(doc, mfv, with_height=False)
        _check_shoulders(doc, mfv, upper, universe)
        lower = _lower_from(doc, mfv, upper) if type2 else upper
        sets.append((IT2Set(upper, lower, mfv.name), mfv.line, mfv.line))
    var = build_input(doc, doc.string(name_entry), universe, sets, name_entry.line)
    if cls is Output:
        with guard(doc, name_entry.line):
            return Output(var.name, var.universe, var.sets)
    return var


def loads(text: str, path: str = "<string>") -> AnySystem:
    """Parse ``.fis`` text (type-1 or type-2, Sugeno or Mamdani) into a system.

    Raises
    ------
    FisFormatError
        On any malformed or unsupported content, naming ``path``, the line and the problem.
    """
    doc = Document(text, path)
    system = doc.section("System")
    doc.check_keys(system, _SYSTEM_KEYS)
    name, fis_type = doc.system_type(system)
    mamdani = fis_type == "mamdani"
    if "Version" in system.entries:
        doc.number(system.entries["Version"])
    type2 = "TypeReductionMethod" in system.entries
    options: dict[str, object] = {
        "name": name,
        "tnorm": _TNORMS[doc.method(system, "AndMethod", tuple(_TNORMS),
                                    "min" if mamdani else "prod")],
        "snorm": _SNORMS[doc.method(system, "OrMethod", tuple(_SNORMS), "max")],
    }
    if mamdani:
        options["implication"] = _IMPLICATIONS[
            doc.method(system, "ImpMethod", tuple(_IMPLICATIONS), "min")]
        options["aggregation"] = Aggregation.from_name(
            doc.method(system, "AggMethod", ("max", "sum", "probor"), "max"))
        allowed = ("centroid",) if type2 else tuple(d.value for d in Defuzzifier)
        defuzz = doc.method(system, "DefuzzMethod", allowed, "centroid")
        if not type2:
            options["defuzzifier"] = Defuzzifier.from_name(defuzz)
    else:
        for key in ("ImpMethod", "AggMethod"):
            if key in system.entries:
                doc.string(system.entries[key])
        doc.method(system, "DefuzzMethod", ("wtaver",), "wtaver")
    if type2:
        entry = system.entries["TypeReductionMethod"]
        method = doc.string(entry)
        if method.strip().lower() not in _READ_REDUCERS:
            known = ", ".join(_READ_REDUCERS)
            raise doc.error(
                entry.line, f"unknown TypeReductionMethod {method!r} (known: {known})"
            )
        options["reducer"] = _READ_REDUCERS[method.strip().lower()]
    counts = doc.counts(system)
    inputs = [
        _variable(doc, doc.section(f"Input{k}", promised_by=counts.n_in_entry), type2=type2,
                  cls=Input)
        for k in range(1, counts.n_inputs + 1)
    ]
    outputs: list[Output] = []
    names: list[str] = []
    midpoints: list[float] = []
    consequents: list[list[Consequent]] = []
    for k in range(1, counts.n_outputs + 1):
        output = doc.section(f"Output{k}", promised_by=counts.n_out_entry)
        range_entry = doc.entry(output, "Range")
        out_lo, out_hi = doc.universe(range_entry)
        midpoint = (out_lo + out_hi) / 2
        if not math.isfinite(midpoint):
            raise doc.error(range_entry.line, "output Range is too wide")
        midpoints.append(midpoint)
        if mamdani:
            out = _variable(doc, output, type2=type2, cls=Output)
            assert isinstance(out, Output)
            outputs.append(out)
            consequents.append([s.name for s in out.sets])
            continue
        doc.check_keys(output, {"Name", "Range", "NumMFs"}, r"MF[1-9]\d{0,8}")
        names.append(doc.string(doc.entry(output, "Name")))
        n_out_mfs_entry = doc.entry(output, "NumMFs")
        n_out_mfs = doc.integer(n_out_mfs_entry, minimum=1)
        doc.check_mf_keys(output, n_out_mfs, n_out_mfs_entry)
        table: list[Consequent] = []
        for j in range(1, n_out_mfs + 1):
            mfv = doc.mf(doc.entry(output, f"MF{j}"))
            if mfv.type == "linear":
                table.append(linear_from(doc, mfv, counts.n_inputs, interval=False))
                continue
            if mfv.type != "constant":
                raise doc.error(
                    mfv.line, f"unknown output MF type {mfv.type!r} (expected 'constant' or "
                    "'linear')"
                )
            if len(mfv.params) != 1:
                raise doc.error(
                    mfv.line, f"'constant' needs one number, got {len(mfv.params)}"
                )
            table.append((mfv.params[0], mfv.params[0]))
        consequents.append(table)

    parsed = doc.counted_rules(counts)
    rules = build_rules(doc, parsed, inputs, consequents)
    options["on_zero_firing"] = midpoints[0] if len(midpoints) == 1 else tuple(midpoints)
    if mamdani:
        options["outputs"] = tuple(outputs)
        cls: type = IT2Mamdani if type2 else T1Mamdani
    else:
        cls = IT2Sugeno if type2 else T1Sugeno
        if len(names) > 1 or names != ["output1"]:
            options["outputs"] = tuple(names)
    return system_of(doc, system.line, cls, inputs=tuple(inputs), rules=tuple(rules), **options)


def _check_shoulders(
    doc: Document, mfv: MFValue, mf: MembershipFunction, universe: tuple[float, float]
) -> None:
    if not isinstance(mf, PiecewiseLinear):
        return
    a, b, c, d, _ = mf.as_trapezoid()
    lo, hi = universe
    for shoulder, foot, inside, side in ((a == b, a, a > lo, "left"), (c == d, d, d < hi, "right")):
        if shoulder and inside:
            raise doc.error(
                mfv.line,
                f"{mfv.type} {fmt_vector(mfv.params)} has a {side} shoulder at x={foot:g} inside "
                f"the Range [{lo:g} {hi:g}]: MATLAB's {mfv.type} drops to 0 beyond it, which "
                "it2track's shoulders (constant beyond the peak) cannot represent; move the "
                "shoulder to the range end",
            )


def _lower_from(doc: Document, mfv: MFValue, upper: MembershipFunction) -> MembershipFunction:
    """The lower MF of a type-2 ``.fis`` MF line (``LowerScale``, ``LowerLag``)."""
    for key in _LOWER_KEYS:
        if key not in mfv.extras:
            raise doc.error(
                mfv.line,
                f"type-2 MF needs 'LowerScale',s,'LowerLag',l after its parameters "
                f"(missing {key!r})",
            )
    scale_v = mfv.extras["LowerScale"]
    lag_v = mfv.extras["LowerLag"]
    if len(scale_v) != 1:
        raise doc.error(mfv.line, "LowerScale must be one number")
    scale = float(scale_v[0])
    if not 0.0 < scale <= 1.0:
        raise doc.error(mfv.line, f"LowerScale={scale:g} must satisfy 0 < scale <= 1")
    if len(lag_v) not in (1, 2):
        raise doc.error(mfv.line, "LowerLag must be one number or two (left, right)")
    lags = (Fraction(lag_v[0]), Fraction(lag_v[-1]))
    for lag in lags:
        if not 0 <= lag < 1:
            raise doc.error(mfv.line, f"LowerLag={float(lag):g} must satisfy 0 <= lag < 1")
    if scale == 1.0 and lags == (0, 0):
        return upper
    with guard(doc, mfv.line, f"MF {mfv.name!r}"):
        if isinstance(upper, PiecewiseLinear):
            a, b, c, d, _ = upper.as_trapezoid()
            la = lag_foot(a, b, lags[0])
            ld = lag_foot(d, c, lags[1])
            if isinstance(upper, Triangle):
                return Triangle(la, b, ld, scale)
            return Trapezoid(la, b, c, ld, scale)
        if lags[0] != lags[1]:
            raise doc.error(
                mfv.line, f"a two-sided LowerLag needs a trimf or trapmf, not {mfv.type}"
            )
        return ScaledLagged(upper, scale, float(lags[0]))


def lag_foot(foot: float, peak: float, lag: Fraction) -> float:
    """Where a lower MF side starts: ``foot + lag * (peak - foot)``, rounded once.

    The upper MF side rises from ``foot`` (value 0) to ``peak`` (value 1), so it reaches the
    value ``lag`` there. The expression is evaluated exactly (rational arithmetic) and rounded
    to the nearest float, so that a lag written with enough digits reproduces any foot.
    """
    if foot == peak or lag == 0:
        return foot
    return float(Fraction(foot) + lag * (Fraction(peak) - Fraction(foot)))


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------


def _mf_lines(var: Input, *, type2: bool, what_kind: str) -> list[str]:
    lines = []
    for j, s in enumerate(var.sets, start=1):
        what = f"{what_kind} {var.name!r} set {s.name!r}"
        kind, params = mf_to_matlab(s.upper, with_height=False, what=f"{what} upper MF")
        kind, params = _widen_shoulders(kind, params, var.universe)
        line = f"MF{j}={fmt_string(s.name, 'set name')}:'{kind}',{fmt_vector(params)}"
        if type2:
            scale, lags = _scale_lag(s, what)
            lag_text = f"[{lags[0]} {lags[1]}]" if len(lags) == 2 else lags[0]
            line += f",'LowerScale',{fmt_number(scale)},'LowerLag',{lag_text}"
        elif not s.is_type1:
            raise UnsupportedFeatureError(f"{what} has a footprint in a type-1 system")
        lines.append(line)
    return lines


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
    mamdani = isinstance(system, IT2Mamdani | T1Mamdani)
    extra: list[str] = []
    if isinstance(system, IT2Mamdani | T1Mamdani):
        if system.resolution != RESOLUTION:
            raise UnsupportedFeatureError(
                f"the .fis format cannot carry resolution={system.resolution} (MATLAB "
                f"evaluates {RESOLUTION} points); save as .toml"
            )
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
        imp = "min" if system.implication is Implication.MINIMUM else "prod"
        agg = system.aggregation.value
        defuzz = (system.defuzzifier.value if isinstance(system, T1Mamdani) else "centroid")
        which = mamdani_indices(system)
    else:
        imp, agg, defuzz = "prod", "sum", "wtaver"
        tables, which = consequent_tables(system)
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
    lines = [
        "[System]",
        f"Name={fmt_string(system.name, 'system name')}",
        f"Type='{'mamdani' if mamdani else 'sugeno'}'",
        "Version=2.0",
        f"NumInputs={system.n_inputs}",
        f"NumOutputs={system.n_outputs}",
        f"NumRules={system.n_rules}",
        f"AndMethod='{'prod' if system.tnorm is TNorm.PRODUCT else 'min'}'",
        f"OrMethod='{system.snorm.value}'",
        f"ImpMethod='{imp}'",
        f"AggMethod='{agg}'",
        f"DefuzzMethod='{defuzz}'",
        *extra,
    ]
    if isinstance(system, IT2Sugeno | IT2Mamdani):
        reducer = system.reducer
        if reducer.name not in _WRITE_REDUCERS:
            raise UnsupportedFeatureError(f"reducer {reducer.name!r} has no .fis name")
        method = _WRITE_REDUCERS[reducer.name]
        if reducer.max_iter != _READ_REDUCERS[method].max_iter:
            raise UnsupportedFeatureError(
                f"the .fis format cannot carry max_iter={reducer.max_iter!r}; save as .toml"
            )
        lines.append(f"TypeReductionMethod='{method}'")
    for k, inp in enumerate(system.inputs, start=1):
        lines += [
            "",
            f"[Input{k}]",
            f"Name={fmt_string(inp.name, 'input name')}",
            f"Range={fmt_vector(inp.universe)}",
            f"NumMFs={len(inp.sets)}",
        ]
        lines += _mf_lines(inp, type2=type2, what_kind="input")
    if isinstance(system, IT2Mamdani | T1Mamdani):
        for k, out in enumerate(system.outputs, start=1):
            lines += [
                "",
                f"[Output{k}]",
                f"Name={fmt_string(out.name, 'output name')}",
                f"Range={fmt_vector(out.universe)}",
                f"NumMFs={len(out.sets)}",
            ]
            lines += _mf_lines(out, type2=type2, what_kind="output")
    else:
        for k, (out_name, table) in enumerate(zip(system.output_names, tables, strict=True)):
            lo, hi = output_range(sugeno_span(table), system.zero_firing_value(k))
            lines += [
                "",
                f"[Output{k + 1}]",
                f"Name={fmt_string(out_name, 'output name')}",
                f"Range={fmt_vector((lo, hi))}",
                f"NumMFs={len(table)}",
            ]
            for j, cons in enumerate(table, start=1):
                if isinstance(cons, Linear):
                    params = fmt_vector([*cons.lo, cons.constant_lo])
                    lines.append(f"MF{j}='mf{j}':'linear',{params}")
                else:
                    assert isinstance(cons, tuple)
                    lines.append(f"MF{j}='mf{j}':'constant',[{fmt_number(cons[0])}]")
    lines += ["", "[Rules]"]
    for rule, outs in zip(system.rules, which, strict=True):
        lines.append(fmt_rule(system, rule, outs))
    return "\n".join(lines) + "\n"


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


def _scale_lag(s: IT2Set, what: str) -> tuple[float, tuple[str, ...]]:
    """``(LowerScale, LowerLag)`` such that the reader rebuilds ``s.lower`` exactly."""
    upper, lower = s.upper, s.lower
    piecewise = isinstance(upper, PiecewiseLinear)
    if lower is upper or lower == upper:
        return 1.0, ("0", "0") if piecewise else ("0",)
    if isinstance(lower, ScaledLagged) and (lower.upper is upper or lower.upper == upper):
        if piecewise:
            raise UnsupportedFeatureError(
                f"{what}: a ScaledLagged lower MF of a triangle/trapezoid is not the MATLAB "
                "lower MF (use IT2Set.from_scale_lag, which builds a trapezoid)"
            )
        return float(lower.scale), (fmt_number(lower.lag),)
    if type(upper) is Gaussian and type(lower) is Gaussian:
        assert isinstance(upper, Gaussian) and isinstance(lower, Gaussian)
        if lower.mean == upper.mean and lower.sigma == upper.sigma and upper.h == 1.0:
            return float(lower.h), ("0",)
    if piecewise and isinstance(lower, PiecewiseLinear) and type(lower) in (Triangle, Trapezoid):
        assert isinstance(upper, PiecewiseLinear)
        a, b, c, d, h = upper.as_trapezoid()
        la, lb, lc, ld, lh = lower.as_trapezoid()
        if lb == b and lc == c and h == 1.0 and a <= la and ld <= d:
            left = _solve_lag(a, b, la)
            right = _solve_lag(d, c, ld)
            if left is not None and right is not None:
                return lh, (left, right)
    raise UnsupportedFeatureError(
        f"{what}: its lower MF {lower!r} is not a LowerScale/LowerLag image of its upper MF "
        f"{upper!r}, the only lower MFs MATLAB's type-2 .fis can describe; save as .t2fis or "
        ".toml"
    )


def _solve_lag(foot: float, peak: float, target: float) -> str | None:
    """The shortest decimal lag in ``[0, 1)`` for which :func:`lag_foot` gives ``target``."""
    if foot == peak:
        return "0" if target == foot else None
    exact = (Fraction(target) - Fraction(foot)) / (Fraction(peak) - Fraction(foot))
    if not 0 <= exact < 1:
        return None
    if exact == 0:
        return "0"
    for digits in range(1, 60):
        with localcontext() as ctx:
            ctx.prec = digits
            text = str(Decimal(exact.numerator) / Decimal(exact.denominator))
        lag = Fraction(text)
        if 0 <= lag < 1 and lag_foot(foot, peak, lag) == target:
            return text
    return None  # pragma: no cover - 60 digits always suffice for doubles
