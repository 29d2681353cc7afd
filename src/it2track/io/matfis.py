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

import itertools
import math
from collections.abc import Sequence
from typing import Any, TypeVar

from ..fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Aggregation,
    AnySystem,
    Connective,
    Consequent,
    Defuzzifier,
    HybridSystem,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    TypeReducer,
    TypeReduction,
    WeightedDefuzzifier,
)
from ._common import (
    check_writable,
    consequent_tables,
    fmt_number,
    fmt_string,
    fmt_vector,
    mamdani_indices,
    mf_from_matlab,
    mf_to_matlab,
    output_range,
    shoulder_problem,
    sugeno_span,
    system_of,
)
from ._fisfile import (
    FisReader,
    header_lines,
    mamdani_methods,
    reducer_name,
    rules_lines,
    variable_lines,
)
from ._lowerlag import LOWER_KEYS, lag_foot, lower_from, scale_lag
from ._matlab import Document, Entry, MFValue, Section
from .errors import UnsupportedFeatureError

__all__ = ["dumps", "lag_foot", "loads"]

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
_SYSTEM_KEYS = frozenset({
    "Name", "Type", "Version", "NumInputs", "NumOutputs", "NumRules", "AndMethod", "OrMethod",
    "ImpMethod", "AggMethod", "DefuzzMethod", "TypeReductionMethod",
})
#: fuzzylite's keys: harmless at these values, refused at others
_FUZZYLITE_FLAGS = {"Enabled": 1.0, "LockPrevious": 0.0, "LockRange": 0.0}
_FLAG_MEANING = {
    "Enabled": "a disabled variable",
    "LockPrevious": "keeping the previous output where no rule fires (state)",
    "LockRange": "clipping the output to its Range",
}
_N = TypeVar("_N", TNorm, SNorm)


class _Reader(FisReader):
    suffix = ".fis"
    lenient = True
    system_keys = _SYSTEM_KEYS
    variable_keys = frozenset({"Name", "Range", "NumMFs", "Enabled"})
    sugeno_output_keys = frozenset({"Name", "Range", "NumMFs", *_FUZZYLITE_FLAGS, "Default"})

    def __init__(self, text: str, path: str) -> None:
        super().__init__(text, path)
        self.type2 = False
        self.defaults: list[float | None] = []
        self.missing: dict[str, int] = {}

    def system_type(self, system: Section) -> str:
        """MATLAB's ``'sugeno'``/``'mamdani'``, and fuzzylite's ``'tsukamoto'``/``'hybrid'``."""
        entry = self.doc.entry(system, "Type")
        fis_type = self.doc.string(entry).lower()
        if fis_type not in ("sugeno", "mamdani", "tsukamoto", "hybrid"):
            raise self.doc.error(entry.line, f"Type={fis_type!r} is not supported ('sugeno', "
                                 "'mamdani', and fuzzylite's 'tsukamoto' and 'hybrid')")
        if fis_type in ("tsukamoto", "hybrid") and "TypeReductionMethod" in system.entries:
            raise self.doc.error(entry.line, f"a type-2 system of Type={fis_type!r}")
        return fis_type

    def output_kind(self, section: Section) -> str:
        if self.type != "hybrid":
            return self.type
        # fuzzylite's hybrid: an output of 'constant'/'linear' MFs is Takagi-Sugeno
        kinds = {self.doc.mf(entry).type in ("constant", "linear") for entry in section.mfs}
        return "sugeno" if kinds == {True} else "mamdani"

    def header(self, system: Section) -> dict[str, Any]:
        doc = self.doc
        self.type2 = "TypeReductionMethod" in system.entries
        options: dict[str, Any] = {
            "tnorm": self._norm(system, "AndMethod", TNorm,
                                TNorm.PRODUCT if self.type == "sugeno" else TNorm.MINIMUM),
            "snorm": self._norm(system, "OrMethod", SNorm, SNorm.MAXIMUM),
        }
        if self.type in ("mamdani", "hybrid"):
            options.update(self.mamdani_options(system))
            allowed = ("centroid",) if self.type2 else tuple(d.value for d in Defuzzifier)
            defuzz, _ = doc.method(system, "DefuzzMethod", allowed, "centroid")
            if not self.type2:
                options["defuzzifier"] = Defuzzifier.from_name(defuzz)
        else:
            if self.type == "tsukamoto":  # fuzzylite 8 aggregates the firing of a set with it
                options["aggregation"] = self.operator(system, "AggMethod", Aggregation,
                                                       Aggregation.SUM)
            else:
                for key in ("ImpMethod", "AggMethod"):  # MATLAB's Sugeno systems ignore them
                    if key in system.entries:
                        doc.string(system.entries[key])
            allowed = ("wtaver",) if self.type2 else ("wtaver", "wtsum")
            defuzz, _ = doc.method(system, "DefuzzMethod", allowed, "wtaver")
            if defuzz == "wtsum":
                options["defuzzifier"] = WeightedDefuzzifier.SUM
        if self.type2:
            entry = system.entries["TypeReductionMethod"]
            method = doc.string(entry)
            if method.strip().lower() not in _READ_REDUCERS:
                known = ", ".join(_READ_REDUCERS)
                raise doc.error(
                    entry.line, f"unknown TypeReductionMethod {method!r} (known: {known})"
                )
            options["reducer"] = _READ_REDUCERS[method.strip().lower()]
        return options

    def _norm(self, system: Section, key: str, kind: type[_N], default: _N) -> _N:
        """A norm method; fuzzylite writes ``''`` for "none" (one-input systems): the default,
        with the line kept to refuse a rule that needs it."""
        entry = system.entries.get(key)
        if entry is not None and self.doc.string(entry) == "":
            self.missing[key] = entry.line
            return default
        return self.operator(system, key, kind, default)

    def input_extras(self, section: Section) -> None:
        self._flags(section)

    def output_extras(self, section: Section) -> None:
        self._flags(section)
        default = section.entries.get("Default")
        value: float | None = None
        if default is None:
            lo, hi = self.doc.universe(self.doc.entry(section, "Range"), point_ok=not self.mamdani)
            value = (lo + hi) / 2
            if not math.isfinite(value):
                raise self.doc.error(section.entries["Range"].line, "output Range is too wide")
        elif default.value.strip().lower() != "nan":
            value = self.doc.number(default)
        self.defaults.append(value)

    def _flags(self, section: Section) -> None:
        for key, harmless in _FUZZYLITE_FLAGS.items():
            entry = section.entries.get(key)
            if entry is not None and self.doc.number(entry) != harmless:
                raise self.doc.error(
                    entry.line, f"{key}={entry.value} ({_FLAG_MEANING[key]}) is not supported"
                )

    def sets(self, section: Section, n: int, count_entry: Entry, universe: tuple[float, float]
             ) -> list[tuple[IT2Set, int, int]]:
        sets = []
        for entry in self.mf_lines(section, n, count_entry):
            mfv = self.doc.mf(entry, extras=LOWER_KEYS if self.type2 else ())
            upper = mf_from_matlab(self.doc, mfv, with_height=False)
            _check_shoulders(self.doc, mfv, upper, universe)
            lower = lower_from(self.doc, mfv, upper) if self.type2 else upper
            sets.append((IT2Set(upper, lower, mfv.name), mfv.line, mfv.line))
        return sets

    def constant(self, mfv: MFValue) -> Consequent:
        if len(mfv.params) != 1:
            raise self.doc.error(
                mfv.line, f"'constant' needs one number, got {len(mfv.params)}"
            )
        return (mfv.params[0], mfv.params[0])

    def check_rules(self, rules: Sequence[Rule]) -> None:
        for rule, parsed in zip(rules, self.doc.sections["Rules"].rows, strict=True):
            used = sum(label is not None for label in rule.antecedent)
            key = "OrMethod" if rule.connective is Connective.OR else "AndMethod"
            missing = self.missing.get(key)
            if used > 1 and missing is not None:
                raise self.doc.error(
                    parsed[1], f"this rule joins {used} inputs with "
                    f"{rule.connective.value.upper()}, but {key}='' (line {missing}) names no "
                    "operator",
                )

    def finish(self, options: dict[str, Any], inputs: list[Input], outputs: list[Output | str],
               kinds: list[str], ranges: list[tuple[tuple[float, float], Section]],
               rules: list[Rule]) -> AnySystem:
        defaults = self.defaults
        if any(d is None for d in defaults) and any(d is not None for d in defaults):
            section = ranges[[d is None for d in defaults].index(True)][1]
            raise self.doc.error(section.entries["Default"].line,
                                 "Default=nan for some outputs and not others")
        line = self.doc.sections["System"].line
        parts = []
        start = 0
        for kind, run in itertools.groupby(kinds):  # fuzzylite's hybrid: a system per run
            n = len(list(run))
            cut = range(start, start + n)
            mine = [Rule(r.antecedent, consequents=[r.consequents[k] for k in cut],
                         weight=r.weight, connective=r.connective, negated=r.negated)
                    for r in rules if any(r.consequents[k] is not None for k in cut)]
            if not mine:
                raise self.doc.error(line, f"no rule acts on output {start + 1}")
            part = dict(options)
            zero = [defaults[k] for k in cut]
            if zero[0] is not None:
                part["on_zero_firing"] = zero[0] if n == 1 else tuple(zero)
            names = [outputs[k] for k in cut]
            if kind == "sugeno":
                cls: type = IT2Sugeno if self.type2 else T1Sugeno
                for key in ("implication", "aggregation"):
                    part.pop(key, None)
                if isinstance(part.get("defuzzifier"), Defuzzifier):
                    part["defuzzifier"] = WeightedDefuzzifier.AVERAGE
                if n > 1 or names != ["output1"]:
                    part["outputs"] = tuple(names)
            else:
                cls = T1Tsukamoto if kind == "tsukamoto" else (
                    IT2Mamdani if self.type2 else T1Mamdani)
                part["outputs"] = tuple(names)
            parts.append(system_of(self.doc, line, cls, inputs=tuple(inputs), rules=tuple(mine),
                                   **part))
            start += n
        if len(parts) == 1:
            return parts[0]
        return system_of(self.doc, line, HybridSystem, systems=tuple(parts),
                         name=options["name"])


def loads(text: str, path: str = "<string>") -> AnySystem:
    """Parse ``.fis`` text (type-1 or type-2, Sugeno or Mamdani) into a system.

    Raises
    ------
    FisFormatError
        On any malformed or unsupported content, naming ``path``, the line and the problem.

    Warns
    -----
    FisFormatWarning
        For what is read as MATLAB's ``readfis`` reads it but may not be what was meant
        (an unknown key, extra MF parameters, a misnumbered ``MF`` line).
    """
    return _Reader(text, path).read()


def _check_shoulders(
    doc: Document, mfv: MFValue, mf: MembershipFunction, universe: tuple[float, float]
) -> None:
    problem = shoulder_problem(mf, universe, f"{mfv.type} {fmt_vector(mfv.params)}",
                               f"MATLAB's {mfv.type}")
    if problem:
        raise doc.error(mfv.line, problem)


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
        method = reducer_name(system.reducer, _WRITE_REDUCERS, _READ_REDUCERS, ".fis")
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


