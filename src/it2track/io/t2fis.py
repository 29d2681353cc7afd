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
- Outputs: ``'constant',[y_lower y_upper]`` interval consequents (one number: crisp). One output
  only. ``'linear'`` (first-order) consequents are rejected.
- Rules ``a1 ... an, c (w) : k``: index 0 skips an input; negative indices (NOT), weights other
  than 1 and OR rules (``k = 2``, more than one antecedent) are rejected with the line.
- ``AndMethod`` (required) ``'prod'`` or ``'min'`` selects our t-norm. (The toolbox's own
  ``evalt2`` always multiplies, whatever this says.) ``OrMethod``, ``ImpMethod``, ``AggMethod``,
  ``DefuzzMethod``, ``Version``, ``outputType`` and ``CrispInterval`` are checked for form and
  otherwise ignored, as ``evalt2`` ignores them.
- ``TypeRedMethod``: ``'Karnik-Mendel'``/``'KM'`` -> :data:`KM`, ``'EKM'`` -> :data:`EKM`,
  ``'IASC'`` and ``'EIASC'`` -> :data:`EIASC` (both exact), ``'EODS'`` -> :data:`EXHAUSTIVE`
  (both exact, non-iterative), ``'NT'`` -> :data:`NIE_TAN`, ``'WM'`` -> :data:`WU_MENDEL`
  (case-insensitive). ``'BMM'`` and custom function names are rejected. Note: the toolbox's
  ``t2f_TR_WM`` departs from the published Wu-Mendel bounds (it takes ``min`` for the lower
  bound of ``yr`` and divides by ``sum(f_upper)`` only), so its 'WM' outputs differ from ours.
- A file whose every lower MF equals its upper MF and whose consequents are all crisp is loaded
  as a :class:`T1Sugeno` (the outputs are the same; the reducer is then irrelevant).

What is written
---------------
The same layout (the toolbox writer's key order). Reducers map back as above, with
:data:`EXHAUSTIVE` written as ``'EODS'`` (exact in the toolbox too). Cannot be written (raise
:class:`UnsupportedFeatureError`): MFs other than Triangle, Trapezoid, Gaussian and
UncertainMeanGaussianUpper (e.g. the uncertain-mean Gaussian *lower* MF, ``ScaledLagged``),
``on_zero_firing``, and reducer ``max_iter`` other than the default.
"""

from __future__ import annotations

from ..fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Gaussian,
    IT2Set,
    IT2Sugeno,
    MembershipFunction,
    ScaledLagged,
    T1Sugeno,
    TNorm,
    TypeReducer,
)
from ._common import (
    build_input,
    build_rules,
    check_writable,
    consequent_table,
    fmt_rule,
    mf_from_matlab,
    mf_line,
    mf_to_matlab,
    output_range,
    set_name,
    system_of,
)
from ._matlab import Document, fmt_number, fmt_string, fmt_vector
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
_SYSTEM_KEYS = {
    "Name", "Type", "Version", "NumInputs", "NumOutputs", "NumRules", "AndMethod", "OrMethod",
    "ImpMethod", "AggMethod", "DefuzzMethod", "TypeRedMethod", "outputType",
}
_TNORMS = {"prod": TNorm.PRODUCT, "min": TNorm.MINIMUM}


def loads(text: str, path: str = "<string>") -> IT2Sugeno | T1Sugeno:
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
    doc = Document(text, path)
    system = doc.section("System")
    doc.check_keys(system, _SYSTEM_KEYS)
    name = doc.sugeno_name(system)
    for key in ("OrMethod", "ImpMethod", "AggMethod", "DefuzzMethod", "outputType"):
        if key in system.entries:
            doc.string(system.entries[key])
    if "Version" in system.entries:
        doc.number(system.entries["Version"])
    and_entry = doc.entry(system, "AndMethod")
    and_method = doc.string(and_entry)
    if and_method.lower() not in _TNORMS:
        raise doc.error(
            and_entry.line, f"AndMethod={and_method!r} is not supported ('prod' or 'min')"
        )
    tnorm = _TNORMS[and_method.lower()]
    reducer = KM
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
        reducer = _READ_REDUCERS[key]
    counts = doc.counts(system)
    n_inputs, n_in_entry, n_out_entry = counts.n_inputs, counts.n_in_entry, counts.n_out_entry

    inputs = []
    all_type1 = True
    for k in range(1, n_inputs + 1):
        section = doc.section(f"Input{k}", promised_by=n_in_entry)
        doc.check_keys(section, {"Name", "Range", "NumMFs"}, r"MF[1-9]\d{0,8}[UL]")
        name_entry = doc.entry(section, "Name")
        inp_name = doc.string(name_entry)
        universe = doc.universe(doc.entry(section, "Range"))
        n_mfs_entry = doc.entry(section, "NumMFs")
        n_mfs = doc.integer(n_mfs_entry, minimum=1)
        doc.check_mf_keys(section, n_mfs, n_mfs_entry, suffixes=("U", "L"))
        sets = []
        for j in range(1, n_mfs + 1):
            up_v = doc.mf(doc.entry(section, f"MF{j}U"))
            low_v = doc.mf(doc.entry(section, f"MF{j}L"))
            upper = mf_from_matlab(doc, up_v, with_height=True)
            lower = mf_from_matlab(doc, low_v, with_height=True)
            if lower == upper:
                lower = upper
            else:
                all_type1 = False
            label = set_name(up_v.name, low_v.name)
            sets.append((IT2Set(upper, lower, label), up_v.line, low_v.line))
        inputs.append(build_input(doc, inp_name, universe, sets, name_entry.line))

    output = doc.section("Output1", promised_by=n_out_entry)
    doc.check_keys(output, {"Name", "Range", "NumMFs", "CrispInterval"}, r"MF[1-9]\d{0,8}")
    doc.string(doc.entry(output, "Name"))
    if "CrispInterval" in output.entries:
        doc.string(output.entries["CrispInterval"])
    doc.universe(doc.entry(output, "Range"))
    n_out_mfs_entry = doc.entry(output, "NumMFs")
    n_out_mfs = doc.integer(n_out_mfs_entry, minimum=1)
    doc.check_mf_keys(output, n_out_mfs, n_out_mfs_entry, suffixes=("",))
    consequents = []
    for j in range(1, n_out_mfs + 1):
        mfv = doc.mf(doc.entry(output, f"MF{j}"))
        if mfv.type != "constant":
            if mfv.type == "linear":
                raise doc.error(mfv.line, "'linear' (first-order) consequents are not supported")
            raise doc.error(mfv.line, f"unknown output MF type {mfv.type!r} (expected 'constant')")
        if len(mfv.params) not in (1, 2):
            raise doc.error(
                mfv.line, f"'constant' needs [y_lower y_upper] (or one number), got "
                f"{len(mfv.params)} numbers"
            )
        lo, hi = mfv.params[0], mfv.params[-1]
        if lo > hi:
            raise doc.error(mfv.line, f"consequent [{lo:g} {hi:g}] must satisfy lower <= upper")
        consequents.append((lo, hi))

    parsed = doc.counted_rules(counts)
    rules = build_rules(doc, parsed, inputs, consequents)
    type1 = all_type1 and all(lo == hi for lo, hi in consequents)
    return system_of(
        doc, system.line, type1=type1, inputs=inputs, rules=rules, tnorm=tnorm,
        reducer=reducer, name=name,
    )


def dumps(system: IT2Sugeno | T1Sugeno) -> str:
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
    if isinstance(system, IT2Sugeno):
        reducer = system.reducer
        if reducer.name not in _WRITE_REDUCERS:
            raise UnsupportedFeatureError(f"reducer {reducer.name!r} has no .t2fis name")
        default = _READ_REDUCERS[_WRITE_REDUCERS[reducer.name].lower()]
        if reducer.max_iter != default.max_iter:
            raise UnsupportedFeatureError(
                f"the .t2fis format cannot carry max_iter={reducer.max_iter!r}; save as .toml"
            )
        method = _WRITE_REDUCERS[reducer.name]
    else:
        method = "KM"
    table, which = consequent_table(system.rules)
    interval = any(lo != hi for lo, hi in table)
    lines = [
        "[System]",
        f"Name={fmt_string(system.name, 'system name')}",
        "Type='sugeno'",
        "Version=2.0",
        f"NumInputs={system.n_inputs}",
        "NumOutputs=1",
        f"NumRules={system.n_rules}",
        f"AndMethod='{'prod' if system.tnorm is TNorm.PRODUCT else 'min'}'",
        "OrMethod='probor'",
        "ImpMethod='prod'",
        "AggMethod='sum'",
        "DefuzzMethod='wtaver'",
        f"TypeRedMethod='{method}'",
    ]
    for k, inp in enumerate(system.inputs, start=1):
        lines += [
            "",
            f"[Input{k}]",
            f"Name={fmt_string(inp.name, 'input name')}",
            f"Range={fmt_vector(inp.universe)}",
            f"NumMFs={len(inp.sets)}",
        ]
        for j, s in enumerate(inp.sets, start=1):
            for suffix, mf in (("U", s.upper), ("L", s.lower)):
                side = "upper" if suffix == "U" else "lower"
                what = f"input {inp.name!r} set {s.name!r} {side} MF"
                kind, params = mf_to_matlab(_plain(mf), with_height=True, what=what)
                lines.append(mf_line(f"MF{j}{suffix}", s.name + suffix, kind, params, what))
    lo, hi = output_range(table, None)
    lines += [
        "",
        "[Output1]",
        "Name='output1'",
        f"CrispInterval='{'interval' if interval else 'crisp'}'",
        f"Range={fmt_vector((lo, hi))}",
        f"NumMFs={len(table)}",
    ]
    for j, (y_lo, y_hi) in enumerate(table, start=1):
        lines.append(f"MF{j}='mf{j}':'constant',[{fmt_number(y_lo)} {fmt_number(y_hi)}]")
    lines += ["", "[Rules]"]
    for rule, out in zip(system.rules, which, strict=True):
        lines.append(fmt_rule(system, rule, out))
    return "\n".join(lines) + "\n"


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
