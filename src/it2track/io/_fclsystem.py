"""Assembling an FCL function block into an it2track system: methods, operators (per rule
block, agreeing), rules and defaults (see :mod:`.fcl` for what is read)."""

from __future__ import annotations

import dataclasses
import itertools
import math
from typing import Any

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Consequent,
    Hedge,
    HybridSystem,
    Implication,
    Input,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    TNorm,
)
from . import _fclvars
from ._chain import Chain
from ._fclbuild import ACCU, AND, MAMDANI, OR, PARTNER_OF_OR, SUGENO, Builder
from ._fclparse import Block, FclVar, FunctionBlock, Parser, RuleNode, Tok
from ._ruletree import DUALS, flatten, propositions

__all__ = ["POINTS", "build", "input_terms"]

#: Mamdani outputs are sampled at jFuzzyLogic's 1000 intervals: 1001 points, both ends
POINTS = 1001

_ACT = {k: Implication.from_name(v.value) for k, v in AND.items()}


class _Setting:
    """One operator the whole system must agree on: its value and where it was set -- by a
    token, or by default where a block or an output leaves it out."""

    def __init__(self, what: str, default: Any) -> None:
        self.what = what
        self.value = default
        self.source: tuple[str, int | None] | None = None  # (the text, its line) set it first

    def set(self, b: Builder, value: Any, tok: Tok | None, line: int | None = None) -> None:
        """``value`` as ``tok`` gives it, or the default (``tok`` None) of the block or output
        at ``line``."""
        text, where = (tok.text, tok.line) if tok is not None else ("the default", line)
        if self.source is None:
            self.value, self.source = value, (text, where)
        elif value is not self.value:
            raise b.error(where, f"{self.what} : {text} differs from the earlier {self.what} : "
                          f"{self.source[0]} (line {self.source[1]}); one setting per system")


def _op(b: Builder, block: Block, key: str, table: dict[str, Any]) -> Any:
    tok = block.ops.get(key)
    if tok is None:
        return None
    if tok.upper not in table:
        raise b.error(tok.line, f"{key} : {tok.text} is not supported ({', '.join(table)})")
    return table[tok.upper]


def _method(b: Builder, var: FclVar) -> str:
    tok = var.method
    name = tok.upper if tok is not None else "COG"
    if name not in MAMDANI and name not in SUGENO:
        known = ", ".join([*MAMDANI, *SUGENO])
        assert tok is not None
        raise b.error(tok.line, f"METHOD {tok.text} is not supported ({known})")
    return name


def _variable(b: Builder, cls: type[Input], var: FclVar, universe: tuple[float, float],
              sets: list[tuple[str, Any]]) -> Input:
    made: Input = b.guarded(var.block_line, lambda: cls(var.name, universe, sets))
    return made


def _rule(b: Builder, rule: RuleNode, antecedent: list[str | None], cons: list[Consequent],
          op: str, negated: list[bool], hedges: list[tuple[Hedge, ...]],
          cons_hedges: list[tuple[Hedge, ...]]) -> Rule:
    made: Rule = b.guarded(rule.line, lambda: Rule(antecedent, consequents=cons,
                                                   weight=rule.weight, connective=op,
                                                   negated=negated, hedges=hedges,
                                                   consequent_hedges=cons_hedges,
                                                   condition=b.trees.get(rule.line)))
    return made


def _kind(b: Builder, var: FclVar) -> str:
    """``"mamdani"``, ``"sugeno"`` or ``"tsukamoto"`` (a singleton method on MF terms, as
    fuzzylite exports its Tsukamoto engines)."""
    if _method(b, var) in MAMDANI:
        return "mamdani"
    mfs = [t.kind in ("points", "shape") and t.shape not in ("Constant", "Linear")
           for t in var.terms.values()]
    if all(mfs):
        return "tsukamoto"
    if any(mfs):
        raise b.error(var.block_line, f"the terms of {var.name!r} mix values and membership "
                      "functions")
    return "sugeno"


def build(parser: Parser, fb: FunctionBlock) -> AnySystem:
    """The system of one parsed function block: one system, or a
    :class:`~it2track.fuzzy.HybridSystem` of one per run of outputs of the same kind."""
    b = Builder(parser)
    if not fb.inputs:
        raise b.error(fb.line, "no VAR_INPUT variables")
    if not fb.outputs:
        raise b.error(fb.line, "no VAR_OUTPUT variables (a function block without outputs is "
                      "not a fuzzy system)")
    inputs = _inputs(b, fb, with_outputs=True)
    parsed: list[tuple[RuleNode, str, list, Block, TNorm, SNorm]] = []
    accus = {name: ACCU.get(var.accu.upper) if var.accu is not None else next(
        (_op(b, blk, "ACCU", ACCU) for blk in fb.blocks if blk.ops.get("ACCU")), None)
        for name, var in fb.outputs.items()}
    chain = Chain(list(fb.inputs), accus)
    for block in fb.blocks:
        and_, or_ = _op(b, block, "AND", AND), _op(b, block, "OR", OR)
        and_ = and_ or PARTNER_OF_OR.get(or_) or TNorm.MINIMUM
        or_ = or_ or DUALS.get(and_) or SNorm.MAXIMUM
        for rule in block.rules:
            for vname, _, _ in rule.conclusions:
                if vname not in fb.outputs:
                    raise b.error(rule.line, f"rule concludes {vname!r}, which is not an output")
            chained = False
            for prop in propositions(rule.condition):
                if prop.variable in fb.outputs:
                    chained = True  # fuzzylite's chained engine: see _chain
                elif prop.variable not in fb.inputs:
                    raise b.error(rule.line, f"rule names {prop.variable!r}, which is not an "
                                  "input")
            try:
                if chained:
                    raise ValueError("chained")
                op, props = flatten(rule.condition, tnorm=and_, snorm=or_)
            except ValueError:  # nested AND/OR, an input named twice, a chained output
                op, props = "and", []
                try:
                    b.trees[rule.line] = chain.condition(rule.condition, and_, or_)
                except ValueError as exc:
                    raise b.error(rule.line, str(exc)) from None
            if not 0.0 <= rule.weight <= 1.0:
                raise b.error(rule.line, f"rule weight {rule.weight:g} must be in [0, 1]")
            chain.concludes(b.trees.get(rule.line) or chain.condition(rule.condition, and_, or_),
                            rule.weight, rule.conclusions)
            parsed.append((rule, op, props, block, and_, or_))
    if not parsed:
        raise b.error(fb.line, f"FUNCTION_BLOCK {fb.name}: no RULE")
    kinds = [(name, _kind(b, var)) for name, var in fb.outputs.items()]
    parts = []
    for kind, run in itertools.groupby(kinds, key=lambda item: item[1]):
        names = [name for name, _ in run]
        mine = [p for p in parsed if any(c[0] in names for c in p[0].conclusions)]
        if not mine:
            raise b.error(fb.outputs[names[0]].block_line, f"no rule concludes {names}")
        parts.append(_part(b, fb, inputs, names, kind, mine))
    if len(parts) == 1:
        return parts[0]
    # cannot fail: the parts share the inputs, and the outputs' names are distinct declarations
    hybrid: Any = HybridSystem(tuple(parts), name=fb.name)  # evaluated as any AnySystem
    return hybrid


def input_terms(parser: Parser, fb: FunctionBlock) -> dict[str, Input]:
    """The input variables of one parsed function block, with their terms, by name (in the
    declared order), read as :func:`build` reads them; the outputs and rules are not read
    (a block may have none)."""
    b = Builder(parser)
    if not fb.inputs:
        raise b.error(fb.line, "no VAR_INPUT variables")
    return {var.name: var for var in _inputs(b, fb, with_outputs=False)}


def _inputs(b: Builder, fb: FunctionBlock, *, with_outputs: bool) -> list[Input]:
    """The inputs, each checked to have its FUZZIFY block (or to be read as a term's
    parameter); ``with_outputs``: the outputs' terms and blocks are checked too."""
    read = _fclvars.check(b, fb, with_outputs=with_outputs)  # terms given by variables
    for var in (*fb.inputs.values(), *(fb.outputs.values() if with_outputs else ())):
        if var.block_line is None and var.name not in read:
            kind = "FUZZIFY" if var.name in fb.inputs else "DEFUZZIFY"
            raise b.error(var.line, f"variable {var.name!r} has no {kind} block")
    inputs = []
    for var in fb.inputs.values():
        universe = _fclvars.universe(b, fb, var)
        if universe[0] == universe[1]:
            raise b.error(var.range_line, f"RANGE of {var.name!r} is a point; an input needs "
                          "lo < hi")
        sets = _fclvars.sets(b, fb, var, universe)
        inputs.append(_variable(b, Input, var, universe, sets))
    return inputs


def _part(b: Builder, fb: FunctionBlock, inputs: list[Input], names: list[str], kind: str,
          parsed: list[tuple[RuleNode, str, list, Block, TNorm, SNorm]]) -> AnySystem:
    """The system of one run of outputs: the operators its rules' blocks agree on."""
    outputs = {name: fb.outputs[name] for name in names}
    tnorm = _Setting("AND", TNorm.MINIMUM)
    snorm = _Setting("OR", SNorm.MAXIMUM)
    act = _Setting("ACT", Implication.MINIMUM)
    accu = _Setting("ACCU", Aggregation.SUM)  # jFuzzyLogic's default; fuzzylite's none
    methods = _Setting("METHOD", None)
    for var in outputs.values():
        method = _method(b, var)
        assert var.block_line is not None  # build checked every output has its block
        methods.set(b, MAMDANI.get(method) or SUGENO[method], var.method, var.block_line)
        if var.accu is not None:
            if var.accu.upper not in ACCU:
                raise b.error(var.accu.line, f"ACCU : {var.accu.text} is not supported "
                              f"({', '.join(ACCU)})")
            accu.set(b, ACCU[var.accu.upper], var.accu)
    rules = []
    for rule, op, props, block, and_, or_ in parsed:
        if block.ops.get("ACCU") is not None:
            accu.set(b, _op(b, block, "ACCU", ACCU), block.ops["ACCU"])
        if len(props) > 1:
            setting, value, key = (tnorm, and_, "AND") if op == "and" else (snorm, or_, "OR")
            setting.set(b, value, block.ops.get(key) or block.ops.get(
                "OR" if key == "AND" else "AND"), block.line)
        if kind == "mamdani":
            act.set(b, _op(b, block, "ACT", _ACT) or Implication.MINIMUM, block.ops.get("ACT"),
                    block.line)
        conclusions = [c for c in rule.conclusions if c[0] in outputs]
        rules.append((dataclasses.replace(rule, conclusions=conclusions), op, props))
    return _assemble(b, fb, outputs, inputs, rules, kind, methods.value,
                     (tnorm.value, snorm.value, act.value, accu))


def _assemble(b: Builder, fb: FunctionBlock, outputs: dict[str, FclVar], inputs: list[Input],
              rules: list[tuple[RuleNode, str, list]], kind: str, defuzzifier: Any,
              ops: tuple[TNorm, SNorm, Implication, _Setting]) -> AnySystem:
    tnorm, snorm, implication, accu = ops
    in_names = list(fb.inputs)
    out_names = list(outputs)
    sugeno = kind == "sugeno"
    values: dict[str, dict[str, Consequent]] = {}
    if sugeno:
        for name, var in outputs.items():
            values[name] = {t.name: b.consequent(t, in_names, fb.outputs, name,
                                                 [o for o in fb.outputs if o not in outputs])
                            for t in var.terms.values()}
    built: list[Rule] = []
    concluded: set[tuple[str, str]] = set()  # (output, value) of the rules so far
    shared = False
    queue = list(rules)
    while queue:
        rule, op, props = queue.pop(0)
        antecedent: list[str | None] = [None] * len(in_names)
        negated = [False] * len(in_names)
        hedges: list[tuple[Hedge, ...]] = [()] * len(in_names)
        for prop in props:
            terms = fb.inputs[prop.variable].terms
            term = prop.term or next(iter(terms), "")  # 'x is any': any term's hedge is 1
            if term not in terms:
                missing = repr(prop.term) if prop.term else f"(for '{prop.variable} is any')"
                raise b.error(rule.line, f"input {prop.variable!r} has no term {missing}")
            k = in_names.index(prop.variable)
            antecedent[k], negated[k] = term, prop.negated
            hedges[k] = tuple(Hedge(h) for h in prop.hedges)
        cons: list[Consequent] = [None] * len(out_names)
        cons_hedges: list[tuple[Hedge, ...]] = [()] * len(out_names)
        again = []  # a second conclusion on one output: the same rule again (jFuzzyLogic)
        for vname, term, written in rule.conclusions:
            if term not in outputs[vname].terms:
                raise b.error(rule.line, f"output {vname!r} has no term {term!r}")
            k = out_names.index(vname)
            if cons[k] is not None:
                again.append((vname, term, written))
                continue
            cons[k] = values[vname][term] if sugeno else term
            cons_hedges[k] = tuple(Hedge(h) for h in written)
            # jFuzzyLogic accumulates singletons by their value (x): equal values are one
            # term, its degree the ACCU of the rules' (T1Sugeno's aggregation)
            key = (vname, repr(cons[k]))
            shared = shared or key in concluded
            concluded.add(key)
        if again:
            queue.insert(0, (dataclasses.replace(rule, conclusions=again), op, props))
        built.append(_rule(b, rule, antecedent, cons, op, negated, hedges, cons_hedges))
    defaults = [var.default for var in outputs.values()]
    numbers = [None if d is None or math.isnan(d[0]) else d[0] for d in defaults]
    if any(v is None for v in numbers) and any(v is not None for v in numbers):
        var = next(v for v, n in zip(outputs.values(), numbers, strict=True) if n is None)
        raise b.error(var.block_line, "give DEFAULT for every output or for none")
    options: dict[str, Any] = {
        "inputs": tuple(inputs), "rules": tuple(built), "name": fb.name, "tnorm": tnorm,
        "snorm": snorm, "defuzzifier": defuzzifier,
        "on_zero_firing": None if numbers[0] is None else (
            numbers[0] if len(numbers) == 1 else tuple(numbers)),
        "lock_previous": tuple(var.nc for var in outputs.values()),
    }
    if sugeno:
        if out_names != ["output1"]:  # one output, named as MATLAB names it: plain
            options["outputs"] = tuple(out_names)
        if shared and accu.value is not Aggregation.SUM:
            options["aggregation"] = accu.value
        made: AnySystem = b.guarded(None, lambda: T1Sugeno(**options))
        return made
    sets_of = []
    for var in outputs.values():
        universe = b.universe(var)
        if universe[0] == universe[1]:
            raise b.error(var.range_line, f"RANGE of {var.name!r} is a point; an output with "
                          "sets needs lo < hi")
        sets = [(t.name, b.mf(t, universe)) for t in var.terms.values()]
        sets_of.append(_variable(b, Output, var, universe, sets))
    options["outputs"] = tuple(sets_of)
    if kind == "tsukamoto":  # fuzzylite 8 combines the firing of a set with the ACCU
        options["aggregation"] = accu.value
        system: AnySystem = b.guarded(None, lambda: T1Tsukamoto(**options))
        return system
    options.update(implication=implication, aggregation=accu.value, resolution=POINTS)
    mamdani: AnySystem = b.guarded(None, lambda: T1Mamdani(**options))
    return mamdani
