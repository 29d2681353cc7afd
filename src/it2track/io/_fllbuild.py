"""The meaning of a parsed ``.fll`` file (:mod:`._flldoc`): fuzzylite's engine as an it2track
system, or a :class:`~it2track.io.FisFormatError` naming the line and the feature it2track
cannot evaluate as fuzzylite does (the rules are in :mod:`.fll`'s docstring)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar, cast

import numpy as np

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Consequent,
    Defuzzifier,
    Hedge,
    HybridSystem,
    Implication,
    Input,
    MembershipFunction,
    Output,
    Rule,
    Sampling,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
    WeightedDefuzzifier,
)
from ..fuzzy.conditions import Condition as CoreCondition
from ..fuzzy.formula import Formula, FormulaError, FormulaMembership
from ..fuzzy.terms import from_fuzzylite, fuzzylite_consequent
from ._chain import Chain
from ._chainread import ChainRefused, chained_formula
from ._common import footed
from ._flldoc import Document, Item, Section, show
from ._ruletree import Condition, Proposition, flatten, propositions
from .errors import FisFormatError

__all__ = ["INTEGRAL", "WEIGHTED", "build"]

#: fuzzylite's integral defuzzifiers (Mamdani) -> ours
INTEGRAL = {"Centroid": Defuzzifier.CENTROID, "Bisector": Defuzzifier.BISECTOR,
            "MeanOfMaximum": Defuzzifier.MOM, "SmallestOfMaximum": Defuzzifier.SOM,
            "LargestOfMaximum": Defuzzifier.LOM}
#: fuzzylite's weighted defuzzifiers (Takagi-Sugeno) -> ours
WEIGHTED = {"WeightedAverage": WeightedDefuzzifier.AVERAGE, "WeightedSum": WeightedDefuzzifier.SUM}
_DEFAULT_RESOLUTION = 1000  # fuzzylite 8's IntegralDefuzzifier default
_MAX_RESOLUTION = 100_000
_CONSEQUENTS = ("Constant", "Linear", "Function")
_E = TypeVar("_E", TNorm, SNorm, Implication, Aggregation)


@dataclass
class _Output:
    section: Section
    universe: tuple[float, float]
    kind: str  # "mamdani", "sugeno" or "tsukamoto"
    terms: dict[str, tuple[Any, int]]  # name -> (MF, Consequent), line
    uses: dict[str, int] = field(default_factory=dict)  # term -> rules concluding it


class _Builder:
    def __init__(self, doc: Document) -> None:
        self.doc = doc
        self.error = doc.error

    # -- pieces --------------------------------------------------------------------------------
    def guarded(self, line: int | None, make: Callable[[], Any], what: str = "") -> Any:
        prefix = f"{what}: " if what else ""
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                return make()
        except FisFormatError:
            raise
        except FloatingPointError as exc:
            raise self.error(line, f"{prefix}numeric overflow ({exc})") from None
        except (ValueError, TypeError, OverflowError) as exc:
            raise self.error(line, f"{prefix}{exc}") from None

    def name(self, section: Section) -> str:
        if not section.name or len(section.name.split()) != 1:
            raise self.error(section.line, f"{section.kind} needs a one-word name, got "
                             f"{show(section.name)}")
        return section.name

    def flag(self, section: Section, key: str, harmless: bool, meaning: str) -> bool:
        item = section.items.get(key)
        if item is None:
            return harmless
        value = self.doc.boolean(item)
        if value != harmless and meaning:
            raise self.error(item.line, f"{key}: {item.value} ({meaning}) is not supported")
        return value

    def universe(self, section: Section, *, point_ok: bool = False) -> tuple[float, float]:
        item = section.items.get("range")
        if item is None:
            raise self.error(section.line, f"{section.kind} {section.name}: missing 'range'")
        parts = item.value.split()
        if len(parts) != 2:
            raise self.error(item.line, f"range: expected two numbers, got {show(item.value)}")
        lo, hi = (self.doc.number(p, item.line, "range") for p in parts)
        if not (lo < hi or (point_ok and lo == hi)):
            raise self.error(item.line, f"range {item.value} must satisfy lo < hi")
        return lo, hi

    def term(self, item: Item, universe: tuple[float, float]) -> tuple[str, str, list[float]]:
        parts = item.value.split()
        if len(parts) < 2:
            raise self.error(item.line, f"expected 'term: name Kind parameters', got "
                             f"{show(item.value)}")
        name, kind = parts[0], parts[1]
        if kind == "Function":  # the formula: the rest of the line
            return name, kind, []
        params = [self.doc.number(p, item.line, f"term {name!r}", finite=False)
                  for p in parts[2:]]
        return name, kind, params

    def formula(self, item: Item, name: str, names: tuple[str, ...], own: str | None = None
                ) -> Formula:
        """A ``Function`` term's formula over ``names`` (``x`` for a membership function), or,
        in the output ``own``, over the inputs ``names`` and the outputs declared before it
        (fuzzylite's chained Function, :mod:`._chainread`)."""
        text = item.value.split(None, 2)[2] if len(item.value.split(None, 2)) > 2 else ""
        outputs = [s.name for s in self.doc.sections if s.kind == "OutputVariable"]
        try:
            if own is None:
                return Formula(text, "fuzzylite", names)
            return chained_formula(text, "fuzzylite", names, outputs, own)
        except (FormulaError, ChainRefused) as exc:
            raise self.error(item.line, f"term {name!r}: Function {text!r}"
                             f"{' ' if isinstance(exc, ChainRefused) else ': '}{exc}") from None

    def mf(self, item: Item, universe: tuple[float, float]) -> tuple[str, MembershipFunction]:
        name, kind, params = self.term(item, universe)
        if kind == "Function":  # fuzzylite's f(x), neither clipped nor footed
            return name, cast(MembershipFunction, self.formula(item, name, ("x",)))
        mf = self.guarded(item.line, lambda: from_fuzzylite(kind, params), f"term {name!r}")
        return name, footed(mf, universe)  # 0 beyond a foot inside the range, as fuzzylite

    def consequent(self, line: int, name: str, kind: str, params: list[float], n_inputs: int
                   ) -> Consequent:
        try:
            value = fuzzylite_consequent(kind, params, n_inputs)
            return (value, value) if isinstance(value, float) else value
        except ValueError as exc:
            raise self.error(line, f"term {name!r}: {exc}") from None

    def operator(self, section: Section, key: str, kind: type[_E]) -> tuple[_E | None, int]:
        item = section.items.get(key)
        if item is None or item.value in ("", "none"):
            return None, section.line if item is None else item.line
        try:
            return kind.from_name(item.value), item.line
        except ValueError:
            raise self.error(item.line, f"{key}: {item.value!r} is not supported (fuzzylite's "
                             f"{kind.__name__} classes it2track has: "
                             f"{', '.join(_fuzzylite_name(m) for m in kind)})") from None

    # -- variables -----------------------------------------------------------------------------
    def input(self, section: Section) -> Input:
        self.flag(section, "enabled", True, "a disabled variable")
        self.flag(section, "lock-range", False, "")
        universe = self.universe(section)
        name = self.name(section)
        sets = [self.mf(item, universe) for item in section.terms]
        return self.guarded(section.line, lambda: Input(name, universe, sets))

    def output(self, section: Section, inputs: tuple[str, ...]) -> _Output:
        self.flag(section, "enabled", True, "a disabled variable")
        self.flag(section, "lock-previous", False, "")  # a boolean; read in _output_options
        self.name(section)
        item = section.items.get("defuzzifier")
        if item is None or not item.value or item.value.split()[0] == "none":
            raise self.error(section.line if item is None else item.line,
                             f"OutputVariable {section.name}: no defuzzifier")
        kind = item.value.split()[0]
        if kind not in INTEGRAL and kind not in WEIGHTED:
            known = ", ".join([*INTEGRAL, *WEIGHTED])
            raise self.error(item.line, f"defuzzifier {kind!r} is not supported ({known})")
        params = item.value.split()[1:]
        if kind in INTEGRAL:
            out_kind = "mamdani"
        elif params in (["TakagiSugeno"], ["Tsukamoto"]):
            out_kind = "sugeno" if params == ["TakagiSugeno"] else "tsukamoto"
        elif params in ([], ["Automatic"]):  # fuzzylite infers it from the terms
            kinds = {t.value.split()[1] in _CONSEQUENTS for t in section.terms
                     if len(t.value.split()) > 1}
            if len(kinds) > 1:
                raise self.error(item.line, f"{kind} Automatic: the terms of "
                                 f"{section.name} mix Takagi-Sugeno and Tsukamoto kinds")
            out_kind = "sugeno" if kinds != {False} else "tsukamoto"
        else:
            raise self.error(item.line, f"defuzzifier: {item.value} is not supported ({kind} "
                             "[TakagiSugeno|Tsukamoto|Automatic])")
        # a Takagi-Sugeno output's range only bounds lock-range (MATLAB's juggler has [0 0])
        universe = self.universe(section, point_ok=out_kind == "sugeno")
        terms: dict[str, tuple[Any, int]] = {}
        for t in section.terms:
            value: Any
            if out_kind == "sugeno":
                name, tkind, values = self.term(t, universe)
                value = (self.formula(t, name, inputs, section.name) if tkind == "Function" else
                         self.consequent(t.line, name, tkind, values, len(inputs)))
            else:
                name, value = self.mf(t, universe)
                if isinstance(value, Formula):  # see _formula_sets
                    value = FormulaMembership(value)
            if name in terms:
                self.doc.warn(t.line, f"duplicate term {name!r} (first at line "
                              f"{terms[name][1]}): rules naming it take this one")
                del terms[name]
            terms[name] = (value, t.line)
        if not terms:
            raise self.error(section.line, f"OutputVariable {section.name}: no term")
        if self.flag(section, "lock-range", False, "") and out_kind != "mamdani":
            for value, line in terms.values():
                if not isinstance(value, tuple) or not universe[0] <= value[0] <= universe[1]:
                    raise self.error(section.items["lock-range"].line,
                                     "lock-range: true clips this output to its range, which "
                                     f"it2track does not (the term at line {line} can leave it)")
        return _Output(section, universe, out_kind, terms)


def _fuzzylite_name(member: Any) -> str:
    if not hasattr(member, "name"):
        return str(member)
    return "".join(part.capitalize() for part in member.name.split("_"))


def _one(values: dict[Any, int], what: str, builder: _Builder) -> Any:
    """The one value the blocks or outputs agree on (``values``: value -> a line)."""
    if len(values) > 1:
        (first, line1), (second, line2) = list(values.items())[:2]
        raise builder.error(line2, f"{what} {_fuzzylite_name(second)} differs from "
                            f"{_fuzzylite_name(first)} (line {line1}): it2track systems have one")
    return next(iter(values)) if values else None


def _run_key(out: _Output) -> tuple[str, str | None]:
    item = out.section.items.get("defuzzifier")
    return out.kind, item.value if out.kind == "mamdani" and item is not None else None


def build(doc: Document) -> AnySystem:
    """The system of a parsed ``.fll`` document: one system, or a
    :class:`~it2track.fuzzy.HybridSystem` of one per run of outputs of the same kind."""
    b = _Builder(doc)
    engine = next((s for s in doc.sections if s.kind == "Engine"), None)
    inputs = [b.input(s) for s in doc.sections if s.kind == "InputVariable"]
    if not inputs:
        raise b.error(None, "no InputVariable")
    names = tuple(i.name for i in inputs)
    outputs = [b.output(s, names) for s in doc.sections if s.kind == "OutputVariable"]
    if not outputs:
        raise b.error(None, "no OutputVariable")
    seen: dict[str, int] = {}
    for section in (s for s in doc.sections if s.kind in ("InputVariable", "OutputVariable")):
        if section.name in seen:
            raise b.error(section.line, f"variable {section.name!r} declared twice (first at "
                          f"line {seen[section.name]})")
        seen[section.name] = section.line
    rules = _rules(b, doc, inputs, outputs)
    name = engine.name if engine is not None else ""
    # a run: outputs of one kind (and, for Mamdani, one defuzzifier and resolution)
    runs = [list(group) for _, group in itertools.groupby(outputs, key=_run_key)]
    if len(runs) > 1:
        _chains_within_runs(b, runs)
    parts = [_part(b, inputs, run, rules, name) for run in runs]
    if len(parts) == 1:
        return parts[0]
    return b.guarded(None, lambda: HybridSystem(tuple(parts), name=name))


def _chains_within_runs(b: _Builder, runs: list[list[_Output]]) -> None:
    """Refuse a Function reading an output of another part (fuzzylite evaluates it; it2track
    chains formulas within one system)."""
    kinds = {o.section.name: o.kind for run in runs for o in run}
    for run in runs:
        mine = {o.section.name for o in run}
        for out in run:
            for term, (value, line) in out.terms.items():
                if isinstance(value, Formula) and (read := sorted(value.used & set(kinds)
                                                                  - mine)):
                    raise b.error(line, f"term {term!r}: Function {value.text!r} reads the "
                                  f"output {read[0]!r} ({kinds[read[0]]}), which it2track "
                                  f"evaluates apart from {out.section.name!r}: it chains "
                                  "formulas among Takagi-Sugeno outputs declared one after "
                                  "another")


@dataclass(frozen=True)
class _ParsedRule:
    item: Item
    op: str
    props: list[Proposition]
    conclusions: list[tuple[str, str, tuple[str, ...]]]
    weight: float
    ops: tuple[tuple[Any, int], tuple[Any, int], tuple[Any, int]]  # conj, disj, imp: line
    tree: CoreCondition | None = None  # a condition the flat form cannot hold (_chain)


def _rules(b: _Builder, doc: Document, inputs: list[Input], outputs: list[_Output]
           ) -> list[_ParsedRule]:
    """Every rule of the enabled blocks (fuzzylite ignores disabled ones), its condition
    flattened with its block's operators."""
    parsed = []
    chain: Chain | None = None  # the rules so far, for chained propositions (_chain)
    for block in (s for s in doc.sections if s.kind == "RuleBlock"):
        if not b.flag(block, "enabled", True, ""):
            continue
        activation = block.items.get("activation")
        if activation is not None and activation.value not in ("", "none", "General"):
            raise b.error(activation.line, f"activation: {activation.value} is not supported "
                          "(General: every rule fires by its degree)")
        ops = (b.operator(block, "conjunction", TNorm), b.operator(block, "disjunction", SNorm),
               b.operator(block, "implication", Implication))
        (conj, conj_line), (disj, disj_line), _ = ops
        chain = chain or Chain([i.name for i in inputs], {
            o.section.name: b.operator(o.section, "aggregation", Aggregation)[0]
            for o in outputs})
        for item in block.rules:
            condition, written, weight = b.doc.rule(item)
            # A hedged conclusion is fuzzylite's: its hedges modify the rule's activation
            # degree, and fuzzylite hands the modified degree on to the conclusions after it
            # (Consequent.modify), so each conclusion's hedges are its own (outermost) and
            # those of the conclusions before it.
            conclusions: list[tuple[str, str, tuple[str, ...]]] = []
            carried: tuple[str, ...] = ()
            for variable, term, hedges in written:
                carried = hedges + carried
                conclusions.append((variable, term, carried))
            _check_names(b, item, condition, inputs, outputs)
            chained = any(p.variable not in chain.inputs for p in propositions(condition))
            tree = None
            try:
                if chained:  # a proposition on an output: a tree over the earlier rules
                    raise ValueError("chained")
                op, props = flatten(condition, tnorm=conj or TNorm.MINIMUM,
                                    snorm=disj or SNorm.MAXIMUM)
            except ValueError:  # nested AND/OR, an input named twice: a tree (_chain)
                op, props = "and", []
                try:
                    tree = chain.condition(condition, conj, disj)
                except ValueError as exc:
                    raise b.error(item.line, str(exc)) from None
            try:
                chain.concludes(tree or chain.condition(condition, conj, disj), weight,
                                conclusions)
            except ValueError:
                pass  # a one-proposition rule of a block without norms: flat, recorded below
            if len(props) > 1:
                used, line, key = (conj, conj_line, "conjunction") if op == "and" else (
                    disj, disj_line, "disjunction")
                if used is None:
                    raise b.error(item.line, f"the rule joins propositions with {op}, but its "
                                  f"block has {key}: none (line {line})")
            parsed.append(_ParsedRule(item, op, props, conclusions, weight, ops, tree))
    if not parsed:
        raise b.error(None, "no rule (in an enabled RuleBlock)")
    return parsed


def _part(b: _Builder, inputs: list[Input], outputs: list[_Output], rules: list[_ParsedRule],
          name: str) -> AnySystem:
    """The system of a run of outputs of one kind, with the rules concluding them."""
    names = {o.section.name for o in outputs}
    mine = [r for r in rules if any(c[0] in names for c in r.conclusions)]
    if not mine:
        raise b.error(outputs[0].section.line, f"no rule concludes {sorted(names)}")
    kind = outputs[0].kind
    tnorms: dict[Any, int] = {}
    snorms: dict[Any, int] = {}
    implications: dict[Any, int] = {}
    for r in mine:
        (conj, conj_line), (disj, disj_line), (imp, imp_line) = r.ops
        if len(r.props) > 1:
            if r.op == "and":
                tnorms.setdefault(conj, conj_line)
            else:
                snorms.setdefault(disj, disj_line)
        if kind == "mamdani":
            if imp is None:
                raise b.error(r.item.line, f"a Mamdani rule needs an implication; its block has "
                              f"implication: none (line {imp_line})")
            implications.setdefault(imp, imp_line)
    # a norm no rule uses is still the block's: keep it when the blocks agree (round trips)
    declared_t = {r.ops[0][0] for r in mine} - {None}
    declared_s = {r.ops[1][0] for r in mine} - {None}
    options: dict[str, Any] = {
        "name": name,
        "tnorm": _one(tnorms, "conjunction", b) or (
            declared_t.pop() if len(declared_t) == 1 else
            TNorm.PRODUCT if kind == "sugeno" else TNorm.MINIMUM),
        "snorm": _one(snorms, "disjunction", b) or (
            declared_s.pop() if len(declared_s) == 1 else SNorm.MAXIMUM),
    }
    built = [_rule(b, inputs, outputs, r.item, r.op, r.props,
                   [c for c in r.conclusions if c[0] in names], r.weight, r.tree) for r in mine]
    options.update(_output_options(b, outputs, implications))
    if kind == "mamdani":
        _formula_sets(b, outputs, options)
    if kind == "sugeno":
        cls: type = T1Sugeno
        if len(outputs) > 1 or outputs[0].section.name != "output1":
            options["outputs"] = tuple(o.section.name for o in outputs)
    else:
        cls = T1Mamdani if kind == "mamdani" else T1Tsukamoto
        options["outputs"] = tuple(_mf_output(b, o) for o in outputs)
    return b.guarded(None, lambda: cls(inputs=tuple(inputs), rules=tuple(built), **options))


def _formula_sets(b: _Builder, outputs: list[_Output], options: dict[str, Any]) -> None:
    """A ``Function`` output term is read floored at 0 (:class:`FormulaMembership`), which is
    fuzzylite's aggregated set only under Maximum aggregation and a Minimum or
    AlgebraicProduct implication."""
    exact = (options["aggregation"] is Aggregation.MAXIMUM
             and options["implication"] in (Implication.MINIMUM, Implication.PRODUCT))
    for out in outputs:
        for name, (mf, line) in out.terms.items():
            if isinstance(mf, FormulaMembership) and not exact:
                raise b.error(line, f"term {name!r}: a Function output term needs aggregation: "
                              "Maximum and implication: Minimum or AlgebraicProduct (fuzzylite "
                              "does not clip a Function's values; it2track's sets are degrees "
                              "in [0, 1], the same aggregated set only with those operators)")


def _check_names(b: _Builder, item: Item, condition: Condition, inputs: list[Input],
                 outputs: list[_Output]) -> None:
    for prop in propositions(condition):
        if prop.variable in {o.section.name for o in outputs}:
            continue  # a chained engine's proposition (see _chain)
        if prop.variable not in {i.name for i in inputs}:
            raise b.error(item.line, f"the rule names {prop.variable!r}, which is not an input")


def _mf_output(b: _Builder, out: _Output) -> Output:
    sets = [(t, mf) for t, (mf, _) in out.terms.items()]
    made: Output = b.guarded(out.section.line,
                             lambda: Output(out.section.name, out.universe, sets))
    return made


def _rule(b: _Builder, inputs: list[Input], outputs: list[_Output], item: Item, op: str,
          props: list[Proposition], conclusions: list[tuple[str, str, tuple[str, ...]]],
          weight: float, tree: CoreCondition | None = None) -> Rule:
    names = [i.name for i in inputs]
    antecedent: list[str | None] = [None] * len(inputs)
    negated = [False] * len(inputs)
    hedges: list[tuple[Hedge, ...]] = [()] * len(inputs)
    for prop in props:
        if prop.variable not in names:
            raise b.error(item.line, f"the rule names {prop.variable!r}, which is not an input")
        k = names.index(prop.variable)
        # 'x is any' names no term: the hedge 'any' makes any term's membership 1
        term = prop.term or (inputs[k].sets[0].name if inputs[k].sets else "")
        if term not in {s.name for s in inputs[k].sets}:
            raise b.error(item.line, f"input {prop.variable!r} has no term {prop.term!r}")
        antecedent[k], negated[k] = term, prop.negated
        hedges[k] = tuple(Hedge(h) for h in prop.hedges)
    out_names = [o.section.name for o in outputs]
    consequents: list[Consequent] = [None] * len(outputs)
    cons_hedges: list[tuple[Hedge, ...]] = [()] * len(outputs)
    for variable, term, written in conclusions:
        if variable not in out_names:
            raise b.error(item.line, f"the rule concludes {variable!r}, which is not an output")
        k = out_names.index(variable)
        if term not in outputs[k].terms:
            raise b.error(item.line, f"output {variable!r} has no term {term!r}")
        if consequents[k] is not None:
            raise b.error(item.line, f"the rule concludes {variable!r} twice")
        consequents[k] = outputs[k].terms[term][0] if outputs[k].kind == "sugeno" else term
        outputs[k].uses[term] = outputs[k].uses.get(term, 0) + 1
        cons_hedges[k] = tuple(Hedge(h) for h in written)
    return b.guarded(item.line, lambda: Rule(antecedent, consequents=consequents, weight=weight,
                                             connective=op, negated=negated, hedges=hedges,
                                             consequent_hedges=cons_hedges, condition=tree))


def _output_options(b: _Builder, outputs: list[_Output], implications: dict[Any, int]
                    ) -> dict[str, Any]:
    options: dict[str, Any] = {}
    defaults = []
    kinds: dict[Any, int] = {}
    resolutions: dict[int, int] = {}
    aggregations: dict[Any, int] = {}
    for out in outputs:
        section = out.section
        item = section.items["defuzzifier"]
        kind, *params = item.value.split()
        default = section.items.get("default")
        value = (math.nan if default is None
                 else b.doc.number(default.value, default.line, "default", finite=False))
        if math.isinf(value):
            raise b.error(default.line if default else section.line, "default must be nan or "
                          "a finite number")
        defaults.append((None if math.isnan(value) else value, section.line))
        agg, agg_line = b.operator(section, "aggregation", Aggregation)
        if out.kind == "mamdani":
            kinds.setdefault(INTEGRAL[kind], item.line)
            if len(params) > 1 or (params and not params[0].isdigit()):
                raise b.error(item.line, f"defuzzifier: expected {kind} [resolution], got "
                              f"{show(item.value)}")
            n = int(params[0]) if params else _DEFAULT_RESOLUTION
            if not 3 <= n <= _MAX_RESOLUTION:
                raise b.error(item.line, f"{kind} resolution {n} must be in [3, {_MAX_RESOLUTION}]")
            resolutions.setdefault(n, item.line)
            if agg is None:
                raise b.error(agg_line, f"a Mamdani output needs an aggregation; {section.name} "
                              "has none")
            aggregations.setdefault(agg, agg_line)
            continue
        kinds.setdefault(WEIGHTED[kind], item.line)
        if out.kind == "tsukamoto":  # fuzzylite 8 combines a term's activations with it
            aggregations.setdefault(agg or Aggregation.SUM, agg_line)
        elif agg is not None and agg is not Aggregation.SUM:
            shared = [t for t, n in out.uses.items() if n > 1]
            if shared:
                raise b.error(agg_line, f"aggregation: {section.items['aggregation'].value} "
                              f"combines the activations of term {shared[0]!r} (several rules "
                              "conclude it) before the weighted average, as fuzzylite 8 does; "
                              "it2track weighs each rule (use aggregation: none)")
    if outputs[0].kind == "mamdani":
        options["implication"] = _one(implications, "implication", b)
        options["resolution"] = _one(resolutions, "resolution", b)
        options["sampling"] = Sampling.MIDPOINTS
    if outputs[0].kind != "sugeno":
        options["aggregation"] = _one(aggregations, "aggregation", b)
    options["defuzzifier"] = _one(kinds, "defuzzifier", b)
    values = [d for d, _ in defaults]
    if any(v is None for v in values) and any(v is not None for v in values):
        line = defaults[[v is None for v in values].index(True)][1]
        raise b.error(line, "default: nan for some outputs and not others")
    if values[0] is not None:
        options["on_zero_firing"] = values[0] if len(values) == 1 else tuple(values)
    # fuzzylite's previous output where no rule fires: the system's evaluate_sequence
    options["lock_previous"] = tuple(b.flag(o.section, "lock-previous", False, "")
                                     for o in outputs)
    return options
