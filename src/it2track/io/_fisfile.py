"""What MATLAB's ``.fis`` and the IT2FLS toolbox's ``.t2fis`` share above the text layer: one
reader skeleton and the writers' common blocks.

:class:`FisReader` reads ``[System]``, the ``[InputN]`` and ``[OutputN]`` sections and the
``[Rules]`` in the order both formats share; a dialect (:mod:`.matfis`, :mod:`.t2fis`)
subclasses it and supplies what differs: the ``[System]`` keys and methods, how a variable's MF
lines make its sets (one MF, or an ``U``/``L`` pair), what a Sugeno ``'constant'`` holds, and
which system class the result is. The writer helpers format numbers, strings and vectors
exactly (``repr``) and lay out the sections both formats write alike.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any, ClassVar, TypeVar

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Consequent,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    Output,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    TNorm,
    TypeReducer,
)
from ..fuzzy.formula import FormulaError
from ..fuzzy.mamdani import RESOLUTION
from ._chainread import ChainRefused, chained_formula
from ._common import build_input, build_rules, guard, linear_from
from ._matlab import Document, Entry, MFValue, Section
from ._writing import fmt_number, fmt_rule, fmt_string, fmt_vector
from .errors import UnsupportedFeatureError

__all__ = [
    "FisReader",
    "fis_name",
    "fmt_number",
    "fmt_string",
    "fmt_vector",
    "header_lines",
    "mamdani_methods",
    "reducer_name",
    "rules_lines",
    "variable_lines",
]

_MF_PATTERN = r"MF[1-9]\d{0,8}"
#: keys only fuzzylite writes (its 5.x exports have no header comment)
_FUZZYLITE_KEYS = re.compile(r"^\s*(LockPrevious|LockRange)\s*=", re.MULTILINE)
_E = TypeVar("_E", TNorm, SNorm, Implication, Aggregation)


def fis_name(member: TNorm | SNorm | Implication | Aggregation) -> str:
    """The ``.fis`` name of an operator: MATLAB's ``'prod'`` for the product, else its value
    (``'min'``, ``'probor'``, ``'sum'``, and the names Octave and fuzzylite write, e.g.
    ``'einstein_product'``)."""
    return "prod" if member.value == "product" else str(member.value)


# ---------------------------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------------------------


class FisReader:
    """Read a MATLAB-layout fuzzy-system file; subclasses supply the dialect.

    Parameters
    ----------
    text : str
        File content.
    path : str
        Named in error messages.
    """

    #: the suffix, for messages
    suffix: ClassVar[str] = ".fis"
    #: read as MATLAB's readfis does (MF lines in order, unknown keys warned about)
    lenient: ClassVar[bool] = False
    #: keys of ``[System]``
    system_keys: ClassVar[frozenset[str]] = frozenset()
    #: keys of an ``[InputN]`` (and a Mamdani ``[OutputN]``) besides its MF lines
    variable_keys: ClassVar[frozenset[str]] = frozenset({"Name", "Range", "NumMFs"})
    #: keys of a Sugeno ``[OutputN]`` besides its MF lines
    sugeno_output_keys: ClassVar[frozenset[str]] = frozenset({"Name", "Range", "NumMFs"})
    #: the MF key pattern of a variable section
    mf_pattern: ClassVar[str] = _MF_PATTERN
    #: whether ``'linear'`` outputs may have interval coefficients
    interval_linear: ClassVar[bool] = False

    def __init__(self, text: str, path: str) -> None:
        self.doc = Document(text, path, lenient=self.lenient)
        #: whose hedges a fractional rule index means (.fis only: fuzzylite's exports say so
        #: on line 1, or carry its LockPrevious/LockRange keys (fuzzylite 5), else Octave's);
        #: the IT2FLS toolbox's .t2fis has none
        self.hedges: str | None = None if not self.lenient else "fuzzylite" if (
            text.lstrip().startswith("#Code automatically generated with fuzzylite")
            or _FUZZYLITE_KEYS.search(text)) else "octave"
        self.type = "sugeno"

    @property
    def mamdani(self) -> bool:
        return self.type == "mamdani"

    # -- the skeleton --------------------------------------------------------------------------
    def read(self) -> AnySystem:
        doc = self.doc
        system = doc.section("System")
        doc.check_keys(system, set(self.system_keys))
        name = doc.string(system.entries["Name"]) if "Name" in system.entries else ""
        self.type = self.system_type(system)
        if "Version" in system.entries:
            doc.number(system.entries["Version"])
        options: dict[str, Any] = {"name": name, **self.header(system)}
        counts = doc.counts(system)
        inputs = [
            self.variable(doc.section(f"Input{k}", promised_by=counts.n_in_entry), Input)
            for k in range(1, counts.n_inputs + 1)
        ]
        outputs: list[Output | str] = []
        kinds: list[str] = []
        ranges: list[tuple[tuple[float, float], Section]] = []
        consequents: list[list[Consequent]] = []
        for k in range(1, counts.n_outputs + 1):
            section = doc.section(f"Output{k}", promised_by=counts.n_out_entry)
            kinds.append(self.output_kind(section))
            if kinds[-1] != "sugeno":  # an output with sets: Mamdani or Tsukamoto
                out = self.variable(section, Output)
                assert isinstance(out, Output)
                outputs.append(out)
                ranges.append((out.universe, section))
                consequents.append([s.name for s in out.sets])
                continue
            doc.check_keys(section, set(self.sugeno_output_keys), _MF_PATTERN)
            own = doc.string(doc.entry(section, "Name"))
            outputs.append(own)
            # a Sugeno output's Range only gives the zero-firing midpoint (MATLAB's juggler.fis
            # has [0 0])
            ranges.append((doc.universe(doc.entry(section, "Range"), point_ok=True), section))
            self.output_extras(section)
            count_entry = doc.entry(section, "NumMFs")
            n = doc.integer(count_entry, minimum=1)
            # outputs before this one that fuzzylite's hybrid puts in another system
            start = max((j + 1 for j, kind in enumerate(kinds) if kind != "sugeno"), default=0)
            apart = {o.name if isinstance(o, Output) else o: kinds[j]
                     for j, o in enumerate(outputs[:start])}
            consequents.append([
                self.consequent(doc.mf(entry), counts.n_inputs,
                                tuple(i.name for i in inputs), own, apart)
                for entry in self.mf_lines(section, n, count_entry)
            ])
        rules = build_rules(doc, doc.counted_rules(counts), inputs, consequents,
                            hedges=self.hedges)
        self.check_rules(rules)
        return self.finish(options, inputs, outputs, kinds, ranges, rules)

    def output_kind(self, section: Section) -> str:
        """``"mamdani"``, ``"sugeno"`` or ``"tsukamoto"``: how ``[OutputN]`` is read."""
        return "mamdani" if self.mamdani else "sugeno"

    def variable(self, section: Section, cls: type) -> Input:
        """An ``[InputN]`` (or a Mamdani ``[OutputN]``) as an :class:`Input` (or
        :class:`Output`)."""
        doc = self.doc
        keys = self.variable_keys | (self.sugeno_output_keys if cls is Output else frozenset())
        doc.check_keys(section, set(keys), self.mf_pattern)
        name_entry = doc.entry(section, "Name")
        universe = doc.universe(doc.entry(section, "Range"))
        if cls is Output:
            self.output_extras(section)
        else:
            self.input_extras(section)
        count_entry = doc.entry(section, "NumMFs")
        # an input without MFs feeds linear consequents only (MATLAB's slcp1.fis)
        n = doc.integer(count_entry, minimum=1 if cls is Output else 0)
        sets = self.sets(section, n, count_entry, universe)
        var = build_input(doc, doc.string(name_entry), universe, sets, name_entry.line)
        if cls is Output:
            with guard(doc, name_entry.line):
                return Output(var.name, var.universe, var.sets)
        return var

    def mf_lines(self, section: Section, n: int, count_entry: Entry) -> list[Entry]:
        """The ``n`` plain ``MFj`` lines of a section (in file order when lenient)."""
        if self.lenient:
            return self.doc.mf_entries(section, n, count_entry)
        self.doc.check_mf_keys(section, n, count_entry)
        return [section.entries[f"MF{j}"] for j in range(1, n + 1)]

    def consequent(self, mfv: MFValue, n_inputs: int, names: tuple[str, ...] = (),
                   own: str | None = None, apart: dict[str, str] | None = None
                   ) -> Consequent:
        """A Sugeno output MF: ``'linear'`` or ``'constant'`` (see :meth:`constant`), or
        fuzzylite's ``'function'``, a formula of the inputs ``names`` (and of the outputs
        declared before ``own``: fuzzylite's chained Function, :mod:`._chainread`; not of
        those ``apart``, output name -> kind, in another system of a hybrid)."""
        if mfv.type == "function":
            outputs = [self.doc.string(self.doc.sections[t].entries["Name"])
                       for t in sorted((t for t in self.doc.sections if t.startswith("Output")
                                        and "Name" in self.doc.sections[t].entries),
                                       key=lambda t: int(t[6:]) if t[6:].isdigit() else 0)]
            try:
                formula = chained_formula(mfv.formula, "fuzzylite", names, outputs, own)
            except (FormulaError, ChainRefused) as exc:
                sep = " " if isinstance(exc, ChainRefused) else ": "
                raise self.doc.error(mfv.line, f"MF {mfv.name!r}: function {mfv.formula!r}"
                                     f"{sep}{exc}") from None
            apart = apart or {}
            read = sorted(formula.used & set(apart))
            if read:
                raise self.doc.error(mfv.line, f"MF {mfv.name!r}: function {mfv.formula!r} "
                                     f"reads the output {read[0]!r} ({apart[read[0]]}), which "
                                     f"it2track evaluates apart from {own!r}: it chains "
                                     "formulas among Takagi-Sugeno outputs declared one after "
                                     "another")
            return formula
        if mfv.type == "linear":
            return linear_from(self.doc, mfv, n_inputs, interval=self.interval_linear)
        if mfv.type != "constant":
            raise self.doc.error(
                mfv.line, f"unknown output MF type {mfv.type!r} (expected 'constant' or "
                "'linear')"
            )
        return self.constant(mfv)

    def operator(self, system: Section, key: str, kind: type[_E], default: _E) -> _E:
        """An operator of ``[System]`` (``AndMethod='min'``) by its MATLAB, Octave or
        fuzzylite name (see :func:`fis_name`); ``default`` when absent."""
        entry = system.entries.get(key)
        if entry is None:
            return default
        value = self.doc.string(entry)
        try:
            return kind.from_name(value)
        except ValueError:
            choices = ", ".join(repr(fis_name(m)) for m in kind)
            raise self.doc.error(entry.line, f"{key}={value!r} is not supported ({choices})"
                                 ) from None

    def mamdani_options(self, system: Section) -> dict[str, Any]:
        """``implication`` and ``aggregation`` of a Mamdani ``[System]``."""
        return {
            "implication": self.operator(system, "ImpMethod", Implication, Implication.MINIMUM),
            "aggregation": self.operator(system, "AggMethod", Aggregation, Aggregation.MAXIMUM),
        }

    # -- the dialect's hooks -----------------------------------------------------------------
    def system_type(self, system: Section) -> str:
        """``Type``, lower case: ``'sugeno'`` or ``'mamdani'``."""
        entry = self.doc.entry(system, "Type")
        fis_type = self.doc.string(entry)
        if fis_type.lower() not in ("sugeno", "mamdani"):
            raise self.doc.error(
                entry.line, f"Type={fis_type!r} is not supported ('sugeno' or 'mamdani')"
            )
        return fis_type.lower()

    def header(self, system: Section) -> dict[str, Any]:
        """The system options ``[System]`` sets (norms, methods, reducer)."""
        raise NotImplementedError

    def input_extras(self, section: Section) -> None:
        """Check an ``[InputN]``'s keys beyond Name, Range, NumMFs and its MFs."""

    def output_extras(self, section: Section) -> None:
        """Check an ``[OutputN]``'s keys beyond Name, Range, NumMFs and its MFs."""

    def sets(self, section: Section, n: int, count_entry: Entry, universe: tuple[float, float]
             ) -> list[tuple[IT2Set, int, int]]:
        """The ``n`` sets of a variable, each with its upper and lower MF's lines."""
        raise NotImplementedError

    def constant(self, mfv: MFValue) -> Consequent:
        """A ``'constant'`` Sugeno output MF."""
        raise NotImplementedError

    def check_rules(self, rules: Sequence[Rule]) -> None:
        """Refuse rules the header cannot evaluate (e.g. AND with ``AndMethod=''``)."""

    def finish(
        self,
        options: dict[str, Any],
        inputs: list[Input],
        outputs: list[Output | str],
        kinds: list[str],
        ranges: list[tuple[tuple[float, float], Section]],
        rules: list[Rule],
    ) -> AnySystem:
        """The system, from everything read (``outputs``: an :class:`Output` with sets, or a
        Sugeno output's name, by output)."""
        raise NotImplementedError


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------


def mamdani_methods(system: IT2Mamdani | T1Mamdani, suffix: str) -> tuple[str, str]:
    """``(ImpMethod, AggMethod)`` of a Mamdani system, refusing a resolution other than
    MATLAB's 101 points."""
    if system.resolution != RESOLUTION or system.sampling is not Sampling.ENDPOINTS:
        raise UnsupportedFeatureError(
            f"the {suffix} format cannot carry resolution={system.resolution}, "
            f"sampling={system.sampling.value!r} (MATLAB evaluates {RESOLUTION} points, both "
            "ends included); save as .toml"
        )
    return fis_name(system.implication), fis_name(system.aggregation)


def reducer_name(reducer: TypeReducer, names: dict[str, str],
                 read: dict[str, TypeReducer], suffix: str) -> str:
    """The format's name of ``reducer`` (``names``: our name -> theirs; ``read``: theirs, lower
    case -> reducer), refusing a reducer without one or a ``max_iter`` other than its
    default."""
    if reducer.name not in names:
        raise UnsupportedFeatureError(f"reducer {reducer.name!r} has no {suffix} name")
    method = names[reducer.name]
    if reducer.max_iter != read[method.lower()].max_iter:
        raise UnsupportedFeatureError(
            f"the {suffix} format cannot carry max_iter={reducer.max_iter!r}; save as .toml"
        )
    return method


def header_lines(system: AnySystem, *, imp: str, agg: str, defuzz: str,
                 extra: Sequence[str] = ()) -> list[str]:
    """The ``[System]`` section (MATLAB's key order), then ``extra`` lines."""
    mamdani = isinstance(system, IT2Mamdani | T1Mamdani)
    return [
        "[System]",
        f"Name={fmt_string(system.name, 'system name')}",
        f"Type='{'mamdani' if mamdani else 'sugeno'}'",
        "Version=2.0",
        f"NumInputs={system.n_inputs}",
        f"NumOutputs={system.n_outputs}",
        f"NumRules={system.n_rules}",
        f"AndMethod='{fis_name(system.tnorm)}'",
        f"OrMethod='{fis_name(system.snorm)}'",
        f"ImpMethod='{imp}'",
        f"AggMethod='{agg}'",
        f"DefuzzMethod='{defuzz}'",
        *extra,
    ]


def variable_lines(title: str, name: str, universe: Sequence[float], n_mfs: int,
                   mf_lines: Sequence[str], *, extra: Sequence[str] = ()) -> list[str]:
    """One ``[InputN]``/``[OutputN]`` section, preceded by a blank line."""
    what = "input name" if title.startswith("Input") else "output name"
    return [
        "",
        f"[{title}]",
        f"Name={fmt_string(name, what)}",
        *extra,
        f"Range={fmt_vector(universe)}",
        f"NumMFs={n_mfs}",
        *mf_lines,
    ]


def rules_lines(system: AnySystem, which: Sequence[Sequence[int]]) -> list[str]:
    """The ``[Rules]`` section; ``which[r]`` are rule ``r``'s output indices."""
    lines = ["", "[Rules]"]
    for rule, outs in zip(system.rules, which, strict=True):
        lines.append(fmt_rule(system, rule, outs))
    return lines
