"""The IT2FLS MATLAB toolbox's ``.t2fis`` format (Taskin & Kumbasar), read and written.

A ``.t2fis`` file is MATLAB's ``.fis`` layout with paired upper/lower MFs::

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
    TypeRedMethod='KM'

    [Input1]
    Name='e'
    Range=[-1 1]
    NumMFs=3
    MF1U='NU':'trimf',[-1 -1 -0.1 1]
    MF1L='NL':'trimf',[-1 -1 -0.3 1]
    ...

    [Output1]
    Name='u'
    CrispInterval='crisp'
    Range=[-12 12]
    NumMFs=5
    MF1='mf1':'constant',[-12 -12]
    ...

    [Rules]
    1 1, 1 (1) : 1
    ...

What is read
------------
- Every MF's **last parameter is its height** ``h`` (the toolbox evaluates
  ``params(end) * mf(x, params(1:end-1))``): ``trimf [a b c h]``, ``trapmf [a b c d h]``,
  ``gaussmf [sigma mean h]``, ``gauss2mf [sigma c1 sigma c2 h]`` (only with equal sigmas and
  ``c1 <= c2``: our uncertain-mean Gaussian upper MF). Other toolbox types (``gbellmf``,
  ``sigmf`` ...) are rejected by name. Shoulders (``a == b`` or ``b == c``) follow DESIGN.md
  sec. 2: value ``h`` at and beyond the peak side.
- A set's name is the common stem of ``'NU'``/``'NL'`` (else the upper MF's name).
- ``Type='sugeno'`` outputs: ``'constant',[y_lower y_upper]`` interval consequents (one
  number: crisp) and ``'linear',[c1 ... cn c0]`` first-order consequents (crisp), or
  ``'linear',[c1_lo ... cn_lo c0_lo c1_hi ... cn_hi c0_hi]`` with interval coefficients (our
  layout: the toolbox's own text for interval linear outputs is not published).
- ``Type='mamdani'`` outputs: ``MF1U``/``MF1L`` pairs like the inputs; ``ImpMethod``
  ``'min'``/``'prod'``, ``AggMethod`` ``'max'``/``'sum'``/``'probor'``, and ``DefuzzMethod``
  ``'centroid'`` (centroid type reduction on 101 points) or ``'cos'`` (centre of sets; our
  name).
- Several outputs (``NumOutputs``, ``[Output2]`` ...).
- Rules ``a1 ... an, c1 ... cm (w) : k``: index 0 skips an input (or an output); ``-j`` is
  NOT set ``j``; ``w`` in ``[0, 1]`` is the rule weight; ``k = 1`` AND, ``k = 2`` OR.
- ``AndMethod`` (required) ``'prod'`` or ``'min'`` selects our t-norm, ``OrMethod`` ``'max'``
  (default) or ``'probor'`` our s-norm. (The toolbox's own ``evalt2`` always multiplies,
  whatever ``AndMethod`` says.) For Sugeno files ``ImpMethod``, ``AggMethod``,
  ``DefuzzMethod``, and everywhere ``Version``, ``outputType`` and ``CrispInterval`` are checked
  for form and otherwise ignored, as ``evalt2`` ignores them.
- ``TypeRedMethod``: ``'Karnik-Mendel'``/``'KM'`` -> :data:`KM`, ``'EKM'`` -> :data:`EKM`,
  ``'IASC'`` and ``'EIASC'`` -> :data:`EIASC` (both exact), ``'EODS'`` -> :data:`EXHAUSTIVE`
  (both exact, non-iterative), ``'NT'`` -> :data:`NIE_TAN`, ``'WM'`` -> :data:`WU_MENDEL`
  (case-insensitive). ``'BMM'`` and custom function names are rejected. Note: the toolbox's
  ``t2f_TR_WM`` departs from the published Wu-Mendel bounds (it takes ``min`` for the lower
  bound of ``yr`` and divides by ``sum(f_upper)`` only), so its 'WM' outputs differ from ours.
- A file whose every lower MF equals its upper MF and whose consequents are all crisp is loaded
  as a :class:`T1Sugeno` (or :class:`T1Mamdani`; the outputs are the same, the reducer is then
  irrelevant).

What is written
---------------
The same layout (the toolbox writer's key order), with every rule feature and system kind
above. Reducers map back as above, with :data:`EXHAUSTIVE` written as ``'EODS'`` (exact in
the toolbox too). Cannot be written (raise :class:`UnsupportedFeatureError`): MFs other than
Triangle, Trapezoid, Gaussian and UncertainMeanGaussianUpper (e.g. the uncertain-mean Gaussian
*lower* MF, ``ScaledLagged``), ``on_zero_firing``, reducer ``max_iter`` other than the
default, a Mamdani ``resolution`` other than 101, and a type-1 Mamdani defuzzifier other than
the centroid.
"""

from __future__ import annotations

from typing import Any

from ..fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    AnySystem,
    Consequent,
    Defuzzifier,
    Gaussian,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Linear,
    MembershipFunction,
    Output,
    Rule,
    ScaledLagged,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    TypeReducer,
    TypeReduction,
    WeightedDefuzzifier,
)
from ._common import mf_from_matlab, mf_line, mf_to_matlab, set_name, system_of
from ._fisfile import (
    FisReader,
    header_lines,
    mamdani_methods,
    reducer_name,
    rules_lines,
    variable_lines,
)
from ._matlab import Entry, MFValue, Section
from ._writing import (
    check_writable,
    consequent_tables,
    fmt_number,
    fmt_vector,
    mamdani_indices,
    output_range,
    sugeno_span,
)
from .errors import UnsupportedFeatureError

__all__ = ["dumps", "loads"]

_READ_REDUCERS: dict[str, TypeReducer] = {
    "karnik-mendel": KM,
    "km": KM,
    "ekm": EKM,
    "iasc": EIASC,
    "eiasc": EIASC,
    "eods": EXHAUSTIVE,
    "nt": NIE_TAN,
    "wm": WU_MENDEL,
}
_WRITE_REDUCERS = {
    "km": "KM",
    "ekm": "EKM",
    "eiasc": "EIASC",
    "exhaustive": "EODS",
    "nie-tan": "NT",
    "wu-mendel": "WM",
}
_SYSTEM_KEYS = frozenset({
    "Name", "Type", "Version", "NumInputs", "NumOutputs", "NumRules", "AndMethod", "OrMethod",
    "ImpMethod", "AggMethod", "DefuzzMethod", "TypeRedMethod", "outputType",
})
_TYPE_REDUCTIONS = {"centroid": TypeReduction.CENTROID, "cos": TypeReduction.CENTRE_OF_SETS}


class _Reader(FisReader):
    suffix = ".t2fis"
    system_keys = _SYSTEM_KEYS
    sugeno_output_keys = frozenset({"Name", "Range", "NumMFs", "CrispInterval"})
    mf_pattern = r"MF[1-9]\d{0,8}[UL]"
    interval_linear = True

    def header(self, system: Section) -> dict[str, Any]:
        doc = self.doc
        for key in ("ImpMethod", "AggMethod", "DefuzzMethod", "outputType"):
            if key in system.entries:
                doc.string(system.entries[key])
        doc.entry(system, "AndMethod")  # required
        options: dict[str, Any] = {
            "tnorm": self.operator(system, "AndMethod", TNorm, TNorm.PRODUCT),
            "snorm": self.operator(system, "OrMethod", SNorm, SNorm.MAXIMUM),
        }
        if self.mamdani:
            options.update(self.mamdani_options(system))
            options["type_reduction"] = _TYPE_REDUCTIONS[
                doc.method(system, "DefuzzMethod", tuple(_TYPE_REDUCTIONS), "centroid")[0]]
        self.reducer = KM
        if "TypeRedMethod" in system.entries:
            entry = system.entries["TypeRedMethod"]
            method = doc.string(entry)
            key = method.strip().lower()
            if key not in _READ_REDUCERS:
                problem = (
                    "the BMM reducer is not supported" if key.startswith("bmm")
                    else f"unknown TypeRedMethod {method!r}"
                )
                raise doc.error(
                    entry.line,
                    f"{problem} (known: Karnik-Mendel, KM, EKM, IASC, EIASC, EODS, NT, WM)",
                )
            self.reducer = _READ_REDUCERS[key]
        return options

    def output_extras(self, section: Section) -> None:
        if not self.mamdani and "CrispInterval" in section.entries:
            self.doc.string(section.entries["CrispInterval"])

    def sets(self, section: Section, n: int, count_entry: Entry, universe: tuple[float, float]
             ) -> list[tuple[IT2Set, int, int]]:
        doc = self.doc
        doc.check_mf_keys(section, n, count_entry, suffixes=("U", "L"))
        sets = []
        for j in range(1, n + 1):
            up_v = doc.mf(doc.entry(section, f"MF{j}U"))
            low_v = doc.mf(doc.entry(section, f"MF{j}L"))
            upper = mf_from_matlab(doc, up_v, with_height=True)
            lower = mf_from_matlab(doc, low_v, with_height=True)
            if lower == upper:
                lower = upper
            label = set_name(up_v.name, low_v.name)
            sets.append((IT2Set(upper, lower, label), up_v.line, low_v.line))
        return sets

    def constant(self, mfv: MFValue) -> Consequent:
        if len(mfv.params) not in (1, 2):
            raise self.doc.error(
                mfv.line, f"'constant' needs [y_lower y_upper] (or one number), got "
                f"{len(mfv.params)} numbers"
            )
        lo, hi = mfv.params[0], mfv.params[-1]
        if lo > hi:
            raise self.doc.error(mfv.line,
                                 f"consequent [{lo:g} {hi:g}] must satisfy lower <= upper")
        return (lo, hi)

    def finish(self, options: dict[str, Any], inputs: list[Input], outputs: list[Output | str],
               kinds: list[str], ranges: list[tuple[tuple[float, float], Section]],
               rules: list[Rule]) -> AnySystem:
        names = [o for o in outputs if isinstance(o, str)]
        sets_of = [o for o in outputs if isinstance(o, Output)]
        all_type1 = all(s.is_type1 for var in (*inputs, *sets_of) for s in var.sets)
        if self.mamdani:
            options["outputs"] = tuple(sets_of)
            cls: type = T1Mamdani if all_type1 else IT2Mamdani
            if cls is T1Mamdani:
                del options["type_reduction"]
            else:
                options["reducer"] = self.reducer
        else:
            crisp = all(
                (c[0] == c[1]) if isinstance(c, tuple) else (not isinstance(c, Linear) or c.crisp)
                for rule in rules for c in rule.consequents if c is not None
            )
            cls = T1Sugeno if all_type1 and crisp else IT2Sugeno
            if cls is IT2Sugeno:
                options["reducer"] = self.reducer
            if len(names) > 1 or names != ["output1"]:
                options["outputs"] = tuple(names)
        return system_of(self.doc, self.doc.sections["System"].line, cls, inputs=tuple(inputs),
                         rules=tuple(rules), **options)


def loads(text: str, path: str = "<string>") -> AnySystem:
    """Parse ``.t2fis`` text into a system.

    Parameters
    ----------
    text : str
        The file content.
    path : str
        Named in error messages.

    Raises
    ------
    FisFormatError
        On any malformed or unsupported content, naming ``path``, the line and the problem.
    """
    return _Reader(text, path).read()


def _mf_lines(var: Input, key_what: str) -> list[str]:
    lines = []
    for j, s in enumerate(var.sets, start=1):
        for suffix, mf in (("U", s.upper), ("L", s.lower)):
            side = "upper" if suffix == "U" else "lower"
            what = f"{key_what} {var.name!r} set {s.name!r} {side} MF"
            kind, params = mf_to_matlab(_plain(mf), with_height=True, what=what)
            lines.append(mf_line(f"MF{j}{suffix}", s.name + suffix, kind, params, what))
    return lines


def _consequent_mf(j: int, cons: Consequent) -> str:
    if isinstance(cons, Linear):
        lo = [*cons.lo, cons.constant_lo]
        hi = [*cons.hi, cons.constant_hi]
        params = lo if cons.crisp else lo + hi
        return f"MF{j}='mf{j}':'linear',{fmt_vector(params)}"
    assert isinstance(cons, tuple)
    return f"MF{j}='mf{j}':'constant',[{fmt_number(cons[0])} {fmt_number(cons[1])}]"


def dumps(system: AnySystem) -> str:
    """``.t2fis`` text for ``system``.

    Raises
    ------
    UnsupportedFeatureError
        If the system uses something the format cannot carry (see the module docstring).
    """
    check_writable(system, ".t2fis")
    if system.on_zero_firing is not None:
        raise UnsupportedFeatureError(
            f"the .t2fis format cannot carry on_zero_firing={system.on_zero_firing!r}; save as "
            ".toml or use dataclasses.replace(system, on_zero_firing=None)"
        )
    method = "KM"
    if isinstance(system, IT2Sugeno | IT2Mamdani):
        method = reducer_name(system.reducer, _WRITE_REDUCERS, _READ_REDUCERS, ".t2fis")
    if isinstance(system, IT2Mamdani | T1Mamdani):
        imp, agg = mamdani_methods(system, ".t2fis")
        if isinstance(system, T1Mamdani) and system.defuzzifier is not Defuzzifier.CENTROID:
            raise UnsupportedFeatureError(
                f"the .t2fis format cannot carry defuzzifier={system.defuzzifier.value!r} "
                "(only centroid type reduction); save as .fis or .toml"
            )
        defuzz = ("cos" if isinstance(system, IT2Mamdani)
                  and system.type_reduction is TypeReduction.CENTRE_OF_SETS else "centroid")
    else:
        if isinstance(system, T1Sugeno) and system.defuzzifier is not WeightedDefuzzifier.AVERAGE:
            raise UnsupportedFeatureError(
                f"the .t2fis format cannot carry defuzzifier={system.defuzzifier.value!r} "
                "(the toolbox averages); save as .fis or .toml"
            )
        imp, agg, defuzz = "prod", "sum", "wtaver"
    lines = header_lines(system, imp=imp, agg=agg, defuzz=defuzz,
                         extra=[f"TypeRedMethod='{method}'"])
    for k, inp in enumerate(system.inputs, start=1):
        lines += variable_lines(f"Input{k}", inp.name, inp.universe, len(inp.sets),
                                _mf_lines(inp, "input"))
    if isinstance(system, IT2Mamdani | T1Mamdani):
        which = mamdani_indices(system)
        for k, out in enumerate(system.outputs, start=1):
            lines += variable_lines(f"Output{k}", out.name, out.universe, len(out.sets),
                                    _mf_lines(out, "output"))
    else:
        tables, which = consequent_tables(system)
        for k, (out_name, table) in enumerate(zip(system.output_names, tables, strict=True),
                                              start=1):
            spans = sugeno_span(table)
            interval = any(lo != hi for lo, hi in spans) or any(
                isinstance(c, Linear) and not c.crisp for c in table)
            lines += variable_lines(
                f"Output{k}", out_name, output_range(spans, None), len(table),
                [_consequent_mf(j, c) for j, c in enumerate(table, start=1)],
                extra=[f"CrispInterval='{'interval' if interval else 'crisp'}'"])
    return "\n".join(lines + rules_lines(system, which)) + "\n"


def _plain(mf: MembershipFunction) -> MembershipFunction:
    """A ``ScaledLagged`` Gaussian with no lag is the Gaussian of height ``scale``."""
    if (
        type(mf) is ScaledLagged
        and isinstance(mf, ScaledLagged)
        and mf.lag == 0.0
        and type(mf.upper) is Gaussian
        and isinstance(mf.upper, Gaussian)
        and mf.upper.h == 1.0
    ):
        return Gaussian(mf.upper.mean, mf.upper.sigma, mf.scale)
    return mf
