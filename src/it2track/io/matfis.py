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

Read as MATLAB, Octave and fuzzylite write it: every MATLAB membership function
(:data:`~it2track.fuzzy.terms.MATLAB_MFS`) and fuzzylite's names; ``AndMethod``/``OrMethod``
by MATLAB's, Octave's or fuzzylite's norm names (``''``: none, refused where a rule needs
one); several outputs; rules ``a1 ... an, c1 ... cm (w) : k`` with NOT (``-j``), weights in
``[0, 1]``, AND (``k = 1``) and OR (``k = 2``), index 0 for a variable a rule leaves out,
indices written ``1.000``. ``%``/``#`` comment lines, ``pi`` expressions, fuzzylite's
``Enabled``/``LockRange``/``Default`` at harmless values and its ``LockPrevious`` of an output
(the system's ``lock_previous``: see ``evaluate_sequence``); an unknown key, extra
MF parameters, a repeated ``MF`` key and undercounted ``NumMFs``/``NumRules`` are read as
MATLAB or fuzzylite reads them, with a :class:`~it2track.io.FisFormatWarning`.

- ``Type='sugeno'``: ``'constant',[c]`` and ``'linear',[c1 ... cn c0]`` outputs, and
  fuzzylite's ``'function',[formula]`` (a formula of the inputs, parsed by
  :mod:`it2track.fuzzy.formula`, never run as code) (an output of
  monotonic MFs: fuzzylite's Tsukamoto); ``DefuzzMethod`` ``'wtaver'`` or ``'wtsum'``; missing
  ``AndMethod``/``DefuzzMethod`` mean MATLAB's Sugeno defaults ``'prod'``/``'wtaver'``.
- ``Type='mamdani'``: output sets like the input sets (evaluated on MATLAB's 101 points);
  ``ImpMethod`` and ``AggMethod`` (``'max'``/``'sum'``/``'probor'``, any norm by name),
  ``DefuzzMethod`` ``'centroid'``, ``'bisector'``, ``'mom'``, ``'som'``, ``'lom'`` (type-2:
  ``'centroid'``, reduced by ``TypeReductionMethod``); defaults are ``mamfis``'s (min, max,
  min, max, centroid).
- fuzzylite's ``Type='tsukamoto'`` and ``'hybrid'`` (a :class:`~it2track.fuzzy.HybridSystem`
  of the runs of Mamdani and Takagi-Sugeno outputs).

``dialect="octave"`` reads a file as the Octave fuzzy-logic-toolkit (0.6.2) evaluates it, where
that differs from MATLAB: a Sugeno output merges the rules that conclude the same value with
``AggMethod`` (``aggregate_output_sugeno``: :class:`T1Sugeno` ``aggregation``; ``'max'`` if
absent, ``newfis``'s), where MATLAB counts every rule; and a Mamdani ``DefuzzMethod`` may be
``'centroid_integral'`` (:attr:`Defuzzifier.CENTROID_INTEGRAL`, the trapezoid rule). Only the
toolkit's ``Type='mamdani'``/``'sugeno'`` type-1 systems of constant/linear Sugeno outputs.

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
    MembershipFunction,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    WeightedDefuzzifier,
)
from ._common import mf_from_matlab, shoulder_problem, system_of
from ._fisfile import (
    FisReader,
)
from ._fiswrite import READ_REDUCERS, dumps
from ._lowerlag import LOWER_KEYS, lag_foot, lower_from
from ._matlab import Document, Entry, MFValue, Section
from ._writing import fmt_vector

__all__ = ["DIALECTS", "dumps", "lag_foot", "loads"]

_SYSTEM_KEYS = frozenset({
    "Name", "Type", "Version", "NumInputs", "NumOutputs", "NumRules", "AndMethod", "OrMethod",
    "ImpMethod", "AggMethod", "DefuzzMethod", "TypeReductionMethod",
})
#: fuzzylite's keys: harmless at these values, refused at others
_FUZZYLITE_FLAGS = {"Enabled": 1.0, "LockPrevious": 0.0, "LockRange": 0.0}
_FLAG_MEANING = {
    "Enabled": "a disabled variable",
    "LockPrevious": "keeping the previous output where no rule fires, on an input",
    "LockRange": "clipping the output to its Range",
}
_N = TypeVar("_N", TNorm, SNorm)


class _Reader(FisReader):
    suffix = ".fis"
    lenient = True
    system_keys = _SYSTEM_KEYS
    variable_keys = frozenset({"Name", "Range", "NumMFs", "Enabled"})
    sugeno_output_keys = frozenset({"Name", "Range", "NumMFs", *_FUZZYLITE_FLAGS, "Default"})

    def __init__(self, text: str, path: str, octave: bool = False) -> None:
        super().__init__(text, path)
        self.octave = octave
        self.type2 = False
        self.defaults: list[float | None] = []
        self.locks: list[bool] = []
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
        if self.octave and fis_type in ("tsukamoto", "hybrid"):
            raise self.doc.error(entry.line, f"Type={fis_type!r} is fuzzylite's; the Octave "
                                 "toolkit (dialect='octave') has 'mamdani' and 'sugeno'")
        if self.octave and "TypeReductionMethod" in system.entries:
            raise self.doc.error(system.entries["TypeReductionMethod"].line, "a type-2 system: "
                                 "the Octave toolkit (dialect='octave') has type-1 only")
        return fis_type

    def output_kind(self, section: Section) -> str:
        if self.type not in ("hybrid", "sugeno") or self.type2:
            return self.type
        constant = {self.doc.mf(entry).type in ("constant", "linear", "function")
                    for entry in section.mfs}
        if self.type == "hybrid":  # fuzzylite's: an output of 'constant'/'linear' MFs is TSK
            return "sugeno" if constant == {True} else "mamdani"
        if constant == {False} and self.octave:
            raise self.doc.error(section.line, f"[{section.title}] of a Type='sugeno' system "
                                 "has membership functions: the Octave toolkit (dialect="
                                 "'octave') calls them as functions of the inputs")
        if constant == {False}:
            # fuzzylite's importer takes any term; its weighted average of monotonic terms is
            # Tsukamoto's (MATLAB refuses such a file)
            self.doc.warn(section.line, f"[{section.title}] of a Type='sugeno' system has "
                          "membership functions, not 'constant'/'linear' ones: read as "
                          "fuzzylite reads it, a Tsukamoto output")
            return "tsukamoto"
        return "sugeno"

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
            allowed = ("centroid",) if self.type2 else tuple(
                d.value for d in Defuzzifier
                if self.octave or d is not Defuzzifier.CENTROID_INTEGRAL)
            entry = system.entries.get("DefuzzMethod")
            if (entry is not None and not self.octave
                    and doc.string(entry).lower() == Defuzzifier.CENTROID_INTEGRAL.value):
                raise doc.error(entry.line, "DefuzzMethod='centroid_integral' is the Octave "
                                "toolkit's trapezoid-rule centroid; MATLAB has none (read "
                                "the file with dialect='octave', CLI --dialect octave)")
            defuzz, _ = doc.method(system, "DefuzzMethod", allowed, "centroid")
            if not self.type2:
                options["defuzzifier"] = Defuzzifier.from_name(defuzz)
        else:
            if self.type == "tsukamoto":  # fuzzylite 8 aggregates the firing of a set with it
                options["aggregation"] = self.operator(system, "AggMethod", Aggregation,
                                                       Aggregation.SUM)
            elif self.octave:  # aggregate_output_sugeno: equal conclusions merged
                options["aggregation"] = self.operator(system, "AggMethod", Aggregation,
                                                       Aggregation.MAXIMUM)
                if "ImpMethod" in system.entries:
                    doc.string(system.entries["ImpMethod"])
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
            if method.strip().lower() not in READ_REDUCERS:
                known = ", ".join(READ_REDUCERS)
                raise doc.error(
                    entry.line, f"unknown TypeReductionMethod {method!r} (known: {known})"
                )
            options["reducer"] = READ_REDUCERS[method.strip().lower()]
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
        self._flags(section, output=True)
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

    def _flags(self, section: Section, *, output: bool = False) -> None:
        for key, harmless in _FUZZYLITE_FLAGS.items():
            entry = section.entries.get(key)
            if output and key == "LockPrevious":  # fuzzylite's: the system's evaluate_sequence
                value = 0.0 if entry is None else self.doc.number(entry)
                if value not in (0.0, 1.0):
                    assert entry is not None  # absent, it is 0
                    raise self.doc.error(entry.line, f"LockPrevious={entry.value} must be 0 "
                                         "or 1")
                self.locks.append(value == 1.0)
                continue
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
            mine = [r.with_consequents([r.consequents[k] for k in cut], cut)
                    for r in rules if any(r.consequents[k] is not None for k in cut)]
            if not mine:
                raise self.doc.error(line, f"no rule acts on output {start + 1}")
            part = dict(options)
            zero = [defaults[k] for k in cut]
            if zero[0] is not None:
                part["on_zero_firing"] = zero[0] if n == 1 else tuple(zero)
            part["lock_previous"] = tuple(self.locks[k] for k in cut)
            names = [outputs[k] for k in cut]
            if kind == "sugeno":
                cls: type = IT2Sugeno if self.type2 else T1Sugeno
                for key in ("implication",) if self.octave else ("implication", "aggregation"):
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


#: the readings of a ``.fis`` file: ``dialect=`` of :func:`loads`
DIALECTS = ("matlab", "octave")


def loads(text: str, path: str = "<string>", *, dialect: str = "matlab") -> AnySystem:
    """Parse ``.fis`` text (type-1 or type-2, Sugeno or Mamdani) into a system.

    ``dialect``: ``"matlab"`` (MATLAB's reading, the default) or ``"octave"`` (the Octave
    fuzzy-logic-toolkit's, where it differs: see the module).

    Raises
    ------
    FisFormatError
        On any malformed or unsupported content, naming ``path``, the line and the problem.

    Warns
    -----
    FisFormatWarning
        For what is read as MATLAB's ``readfis`` or fuzzylite reads it but may not be what
        was meant (an unknown key, extra MF parameters, a misnumbered ``MF`` line, more MF
        lines or rules than ``NumMFs``/``NumRules`` say, a ``Type='sugeno'`` output of
        monotonic membership functions, read as Tsukamoto's).
    """
    if dialect not in DIALECTS:
        raise ValueError(f"dialect={dialect!r}: a .fis is read as one of {DIALECTS}")
    return _Reader(text, path, octave=dialect == "octave").read()


def _check_shoulders(
    doc: Document, mfv: MFValue, mf: MembershipFunction, universe: tuple[float, float]
) -> None:
    problem = shoulder_problem(mf, universe, f"{mfv.type} {fmt_vector(mfv.params)}",
                               f"MATLAB's {mfv.type}")
    if problem:
        raise doc.error(mfv.line, problem)
