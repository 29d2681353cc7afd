"""Reading IEEE 1855 FML (the layout and what it carries: :mod:`.fml`)."""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable
from typing import Any

import numpy as np

from ..fuzzy import (
    Aggregation,
    AnySystem,
    Consequent,
    Defuzzifier,
    Discrete,
    Gaussian,
    GaussianProduct,
    HybridSystem,
    Implication,
    Input,
    Linear,
    MembershipFunction,
    Output,
    PiShape,
    Ramp,
    Rectangle,
    Rule,
    SNorm,
    SShape,
    T1Mamdani,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    ZShape,
)
from ._common import shoulder_problem
from ._xml import Node, parse
from .errors import FisFormatError

__all__ = ["ACCUMULATIONS", "AND", "DEFUZZIFIERS", "NAMESPACE", "OR", "build"]

NAMESPACE = "http://www.ieee1855.org"
_NUMBER_RE = re.compile(r"\s*[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d{1,3})?\s*")
#: IEEE 1855 t-norm names (the schema spells bounded difference and drastic product BSUM and
#: DRS; the standard's text BDIF and DRP) -> ours
AND = {"MIN": TNorm.MINIMUM, "PROD": TNorm.PRODUCT, "BDIF": TNorm.BOUNDED_DIFFERENCE,
       "BSUM": TNorm.BOUNDED_DIFFERENCE, "DRP": TNorm.DRASTIC_PRODUCT,
       "DRS": TNorm.DRASTIC_PRODUCT, "EPROD": TNorm.EINSTEIN_PRODUCT,
       "HPROD": TNorm.HAMACHER_PRODUCT, "NILMIN": TNorm.NILPOTENT_MINIMUM}
OR = {"MAX": SNorm.MAXIMUM, "PROBOR": SNorm.PROBOR, "BSUM": SNorm.BOUNDED_SUM,
      "DRS": SNorm.DRASTIC_SUM, "ESUM": SNorm.EINSTEIN_SUM, "HSUM": SNorm.HAMACHER_SUM,
      "NILMAX": SNorm.NILPOTENT_MAXIMUM}
ACCUMULATIONS = {k: Aggregation.from_name(v.value) for k, v in OR.items()}
DEFUZZIFIERS = {"COG": Defuzzifier.CENTROID, "COA": Defuzzifier.BISECTOR,
                "MOM": Defuzzifier.MOM, "LM": Defuzzifier.SOM, "RM": Defuzzifier.LOM}
_IMPLICATIONS = {k: Implication.from_name(v.value) for k, v in AND.items()}
_SHAPES = {"triangularShape": 3, "trapezoidShape": 4, "rightLinearShape": 2,
           "leftLinearShape": 2, "gaussianShape": 2, "rightGaussianShape": 2,
           "leftGaussianShape": 2, "piShape": 4, "sShape": 2, "zShape": 2,
           "rectangularShape": 2}


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path

    def error(self, node: Node | None, message: str) -> FisFormatError:
        return FisFormatError(self.path, None if node is None else node.line, message)

    def guarded(self, node: Node, make: Callable[[], Any], what: str = "") -> Any:
        prefix = f"{what}: " if what else ""
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                return make()
        except FisFormatError:
            raise
        except FloatingPointError as exc:
            raise self.error(node, f"{prefix}numeric overflow ({exc})") from None
        except (ValueError, TypeError, OverflowError) as exc:
            raise self.error(node, f"{prefix}{exc}") from None

    def attr(self, node: Node, name: str, default: str | None = None) -> str:
        value = node.attrs.get(name, default)
        if value is None:
            raise self.error(node, f"<{node.tag}> needs the attribute {name!r}")
        return value

    def number(self, node: Node, text: str, what: str) -> float:
        if len(text) > 80 or not _NUMBER_RE.fullmatch(text):
            raise self.error(node, f"{what}: bad number {text[:60]!r}")
        value = float(text)
        if not math.isfinite(value):
            raise self.error(node, f"{what}: {text.strip()} is out of range")
        return value

    def choice(self, node: Node, name: str, table: dict[str, Any], default: str) -> Any:
        value = self.attr(node, name, default)
        if value not in table:
            raise self.error(node, f"{name}={value!r} is not supported ({', '.join(table)})")
        return table[value]

    # -- knowledge base ------------------------------------------------------------------------
    def universe(self, node: Node) -> tuple[float, float]:
        lo = self.number(node, self.attr(node, "domainleft"), "domainleft")
        hi = self.number(node, self.attr(node, "domainright"), "domainright")
        if not lo < hi:
            raise self.error(node, f"domainleft={lo:g} must be below domainright={hi:g}")
        return lo, hi

    def mf(self, term: Node, universe: tuple[float, float]) -> MembershipFunction:
        shapes = [c for c in term.children]
        if len(shapes) != 1:
            raise self.error(term, f"<fuzzyTerm name={term.attrs.get('name')!r}> needs one shape")
        shape = shapes[0]
        if shape.tag == "pointSetShape":
            return self.points(shape)
        if shape.tag not in _SHAPES:
            raise self.error(shape, f"<{shape.tag}> is not supported (it2track reads "
                             f"{', '.join(_SHAPES)}, pointSetShape)")
        p = [self.number(shape, self.attr(shape, f"param{k}"), f"param{k}")
             for k in range(1, _SHAPES[shape.tag] + 1)]
        lo, hi = universe
        makers: dict[str, Callable[[], MembershipFunction]] = {
            "triangularShape": lambda: Triangle(*p),
            "trapezoidShape": lambda: Trapezoid(*p),
            "rightLinearShape": lambda: Ramp(p[0], p[1]),
            "leftLinearShape": lambda: Ramp(p[1], p[0]),
            "gaussianShape": lambda: Gaussian(p[0], p[1]),
            # 1 below (above) the mean: on the universe, a Gaussian product flat to its end
            "leftGaussianShape": lambda: GaussianProduct(min(lo, p[0]), p[1], p[0], p[1]),
            "rightGaussianShape": lambda: GaussianProduct(p[0], p[1], max(hi, p[0]), p[1]),
            "piShape": lambda: PiShape(*p),
            "sShape": lambda: SShape(*p),
            "zShape": lambda: ZShape(*p),
            "rectangularShape": lambda: Rectangle(*p),
        }
        mf: MembershipFunction = self.guarded(shape, makers[shape.tag], f"<{shape.tag}>")
        problem = shoulder_problem(mf, universe, f"<{shape.tag}>", "IEEE 1855's shape")
        if problem:
            raise self.error(shape, problem)
        return mf

    def points(self, shape: Node) -> MembershipFunction:
        """A ``pointSetShape``: with linear interpolation, fuzzylite's ``Discrete`` (the first
        and last degree beyond the points, as JFML evaluates it)."""
        method = self.attr(shape, "interpolationMethod", "linear")
        if method != "linear":
            raise self.error(shape, f"<pointSetShape interpolationMethod={method!r}> is not "
                             "supported (linear)")
        points = sorted((self.number(p, self.attr(p, "x"), "x"),
                         self.number(p, self.attr(p, "y"), "y")) for p in shape.all("point"))
        made: MembershipFunction = self.guarded(shape, lambda: Discrete(points),
                                                "<pointSetShape>")
        return made

    def variable(self, node: Node, complements: set[tuple[str, str]]) -> Input:
        name = self.attr(node, "name")
        universe = self.universe(node)
        sets = []
        for term in node.all("fuzzyTerm"):
            label = self.attr(term, "name")
            if self.attr(term, "complement", "false").lower() == "true":
                complements.add((name, label))
            sets.append((label, self.mf(term, universe)))
        cls = Output if self.attr(node, "type", "input") == "output" else Input
        if cls is Output and any(v == name for v, _ in complements):
            raise self.error(node, f"a complemented output term of {name!r} is not supported")
        made: Input = self.guarded(node, lambda: cls(name, universe, sets))
        return made

    def linear(self, term: Node, values: list[float]) -> Linear:
        made: Linear = self.guarded(term, lambda: Linear(values[1:], values[0]))
        return made

    def tsk_terms(self, node: Node, n_inputs: int) -> dict[str, Consequent]:
        terms: dict[str, Consequent] = {}
        self.attr(node, "name")
        for term in node.all("tskTerm"):
            label = self.attr(term, "name")
            values = [self.number(v, v.text, "tskValue") for v in term.all("tskValue")]
            order = self.attr(term, "order")
            if order == "0" and len(values) == 1:
                terms[label] = (values[0], values[0])
            elif order == "1" and len(values) == n_inputs + 1:
                # the constant first, then one coefficient per input (JFML, the standard's
                # reference implementation)
                terms[label] = self.linear(term, values)
            else:
                raise self.error(term, f"<tskTerm name={label!r} order={order!r}> needs one "
                                 f"<tskValue> (order 0) or {n_inputs + 1} (order 1: the "
                                 f"constant, then one per input), got {len(values)}")
        if not terms:
            raise self.error(node, "<tskVariable> has no <tskTerm>")
        return terms


def _rule_bases(r: _Reader, root: Node) -> list[Node]:
    bases = [c for c in root.children if c.tag.endswith("RuleBase")]
    for base in bases:
        if base.tag not in ("mamdaniRuleBase", "tskRuleBase"):
            raise r.error(base, f"<{base.tag}> is not supported (mamdaniRuleBase, tskRuleBase)")
    if not bases:
        raise r.error(root, "<fuzzySystem> has no rule base")
    return bases


def _clauses(r: _Reader, parent: Node, tag: str) -> list[tuple[Node, str, str]]:
    found = []
    for clause in parent.all(tag):
        modifier = clause.attrs.get("modifier")
        if modifier:
            raise r.error(clause, f"the modifier {modifier!r} (a hedge) is not supported")
        variable, term = clause.one("variable", r.path), clause.one("term", r.path)
        if variable is None or term is None:
            raise r.error(clause, f"<{tag}> needs <variable> and <term>")
        found.append((clause, variable.text.strip(), term.text.strip()))
    return found


def _rule(r: _Reader, node: Node, labels: list[str | None], cons: list[Consequent],
          weight: float, connector: str, negated: list[bool]) -> Rule:
    made: Rule = r.guarded(node, lambda: Rule(labels, consequents=cons, weight=weight,
                                              connective=connector, negated=negated))
    return made


def _part(r: _Reader, root: Node, inputs: list[Input], run: list[tuple[str, Node, Any]],
          complements: set[tuple[str, str]]) -> AnySystem:
    """The system of a run of outputs of one kind, with the rules concluding them."""
    kind = run[0][0]
    names = [node.attrs["name"] for _, node, _ in run]
    base_tag, rule_tag, then_tags = (
        ("mamdaniRuleBase", "rule", ("consequent", "then", "clause")) if kind == "mamdani"
        else ("tskRuleBase", "tskRule", ("tskConsequent", "tskThen", "tskClause")))
    in_names = [i.name for i in inputs]
    rules: list[Rule] = []
    settings: dict[str, tuple[Any, Node]] = {}
    for base in root.all(base_tag):
        ops = {"andMethod": r.choice(base, "andMethod", AND, "MIN"),
               "orMethod": r.choice(base, "orMethod", OR, "MAX"),
               "activationMethod": r.choice(base, "activationMethod", _IMPLICATIONS, "MIN")}
        for key, value in ops.items():
            if settings.setdefault(key, (value, base))[0] is not value:
                raise r.error(base, f"{key} differs from the first {base_tag}'s: one setting "
                              "per system")
        for rule in base.all(rule_tag):
            for key in ("andMethod", "orMethod"):
                table = AND if key == "andMethod" else OR
                if key in rule.attrs and r.choice(rule, key, table, "MIN") is not ops[key]:
                    raise r.error(rule, f"the rule's {key} differs from its rule base's: "
                                  "it2track's rules share their operators")
            connector = r.attr(rule, "connector", "and").lower()
            if connector not in ("and", "or"):
                raise r.error(rule, f"connector={connector!r} must be 'and' or 'or'")
            weight = r.number(rule, r.attr(rule, "weight", "1.0"), "weight")
            antecedent = rule.one("antecedent", r.path)
            if antecedent is None:
                raise r.error(rule, "the rule has no <antecedent>")
            labels: list[str | None] = [None] * len(inputs)
            negated = [False] * len(inputs)
            for clause, variable, term in _clauses(r, antecedent, "clause"):
                if variable not in in_names:
                    raise r.error(clause, f"{variable!r} is not an input variable")
                k = in_names.index(variable)
                if term not in {t.name for t in inputs[k].sets}:
                    raise r.error(clause, f"input {variable!r} has no term {term!r}")
                if labels[k] is not None:
                    raise r.error(clause, f"input {variable!r} appears twice in the rule: "
                                  "it2track's rules name each input once")
                labels[k], negated[k] = term, (variable, term) in complements
            consequent = rule.one(then_tags[0], r.path)
            then = None if consequent is None else consequent.one(then_tags[1], r.path)
            if then is None:
                raise r.error(rule, f"the rule has no <{then_tags[0]}><{then_tags[1]}>")
            if consequent is not None and len(consequent.children) > 1:
                raise r.error(consequent, "an <else> part is not supported")
            cons: list[Consequent] = [None] * len(run)
            for clause, variable, term in _clauses(r, then, then_tags[2]):
                if variable not in names:
                    continue  # another part's output
                k = names.index(variable)
                table = run[k][2]
                known = [s.name for s in table.sets] if kind == "mamdani" else list(table)
                if term not in known:
                    raise r.error(clause, f"output {variable!r} has no term {term!r}")
                cons[k] = term if kind == "mamdani" else table[term]
            if all(c is None for c in cons):
                continue
            rules.append(_rule(r, rule, labels, cons, weight, connector, negated))
    if not rules:
        raise r.error(run[0][1], f"no rule concludes {names}")
    # xs:float's NaN: no value where no rule fires (ZeroFiringError; it2track writes it so)
    defaults = [None if r.attr(node, "defaultValue", "0").strip() == "NaN" else
                r.number(node, r.attr(node, "defaultValue", "0"), "defaultValue")
                for _, node, _ in run]
    if any(d is None for d in defaults) and any(d is not None for d in defaults):
        raise r.error(run[0][1], "defaultValue NaN for some outputs and not others")
    options: dict[str, Any] = {
        "inputs": tuple(inputs), "rules": tuple(rules), "name": root.attrs.get("name", ""),
        "tnorm": settings["andMethod"][0], "snorm": settings["orMethod"][0],
        "on_zero_firing": None if defaults[0] is None else (
            defaults[0] if len(defaults) == 1 else tuple(defaults)),
    }
    if kind == "sugeno":
        for _, node, _ in run:
            if r.attr(node, "combination", "WA") != "WA":
                raise r.error(node, "combination must be WA (the weighted average)")
        if len(names) > 1 or names != ["output1"]:
            options["outputs"] = tuple(names)
        sugeno: AnySystem = r.guarded(root, lambda: T1Sugeno(**options))
        return sugeno
    accumulations = {r.choice(node, "accumulation", ACCUMULATIONS, "MAX") for _, node, _ in run}
    defuzzifiers = {r.choice(node, "defuzzifier", DEFUZZIFIERS, "COG") for _, node, _ in run}
    if len(accumulations) > 1 or len(defuzzifiers) > 1:
        raise r.error(run[1][1], "the outputs' accumulation or defuzzifier differ: it2track "
                      "systems have one")
    options.update(outputs=tuple(out for _, _, out in run),
                   implication=settings["activationMethod"][0],
                   aggregation=accumulations.pop(), defuzzifier=defuzzifiers.pop())
    mamdani: AnySystem = r.guarded(root, lambda: T1Mamdani(**options))
    return mamdani


def build(text: str, path: str) -> AnySystem:
    """The system of an FML document."""
    r = _Reader(path)
    root = parse(text, path)
    if root.tag != "fuzzySystem" or root.namespace not in ("", NAMESPACE):
        raise r.error(root, f"the root element is <{root.tag}>, expected IEEE 1855's "
                      "<fuzzySystem>")
    kb = root.one("knowledgeBase", path)
    if kb is None:
        raise r.error(root, "<fuzzySystem> has no <knowledgeBase>")
    complements: set[tuple[str, str]] = set()
    inputs: list[Input] = []
    outputs: list[tuple[str, Node, Any]] = []  # (kind, node, Output or {term: consequent})
    for node in kb.children:
        if node.tag == "fuzzyVariable":
            var = r.variable(node, complements)
            if isinstance(var, Output):
                outputs.append(("mamdani", node, var))
            else:
                inputs.append(var)
        elif node.tag != "tskVariable":
            raise r.error(node, f"<{node.tag}> is not supported (fuzzyVariable, tskVariable)")
    for node in kb.all("tskVariable"):
        outputs.append(("sugeno", node, r.tsk_terms(node, len(inputs))))
    if not inputs or not outputs:
        raise r.error(kb, "the knowledge base needs input and output variables")
    seen: dict[str, int] = {}
    for node in kb.children:
        name = node.attrs.get("name", "")
        if name in seen:
            raise r.error(node, f"variable {name!r} declared twice (first at line {seen[name]})")
        seen[name] = node.line
    _rule_bases(r, root)
    runs = [list(group) for _, group in itertools.groupby(outputs, key=lambda o: o[0])]
    parts = [_part(r, root, inputs, run, complements) for run in runs]
    if len(parts) == 1:
        return parts[0]
    hybrid: AnySystem = r.guarded(root, lambda: HybridSystem(tuple(parts),
                                                             name=root.attrs.get("name", "")))
    return hybrid
