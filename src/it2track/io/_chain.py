"""Rule conditions the one-connective form cannot hold, as :mod:`it2track.fuzzy.conditions`
trees: nested AND/OR (``A and (B or C)``), an input named twice, and fuzzylite's *chained*
propositions on an output.

fuzzylite evaluates its rules in order and a proposition ``Power is LOW`` on an output reads
the degree its fuzzy output holds for ``LOW`` at that moment: the rules *before* it that
conclude ``Power is LOW``, each with its activation degree (its weight times its condition,
hedged by its conclusion's hedges), folded by ``Power``'s aggregation (none: their sum)
(pyfuzzylite 8 ``Antecedent.activation_degree``, ``Aggregated.activation_degree``). That is
stateless: :class:`Chain` rewrites the proposition as that fold of the earlier rules'
conditions, so the rule reads the inputs only. An output term no earlier rule concludes has
degree 0 in fuzzylite; such a rule is refused (it never fires).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..fuzzy import Aggregation, Hedge, SNorm, TNorm
from ..fuzzy.conditions import Condition as CoreCondition
from ..fuzzy.conditions import Is, Join, Modified, Not
from ._ruletree import Compound, Condition, Negation, Proposition

__all__ = ["Chain"]


class Chain:
    """The rules read so far (in file order), to rewrite conditions naming outputs.

    Parameters
    ----------
    inputs : sequence of str
        Input names, in input order.
    aggregations : dict
        Output name -> its aggregation (``None``: fuzzylite's unbounded sum).
    """

    def __init__(self, inputs: Sequence[str], aggregations: dict[str, Aggregation | None]) -> None:
        self.inputs = list(inputs)
        self.aggregations = aggregations
        self.concluded: dict[tuple[str, str], list[CoreCondition]] = {}

    def condition(self, node: Condition, tnorm: TNorm | None, snorm: SNorm | None
                  ) -> CoreCondition:
        """``node`` as a core condition over the inputs, with the block's norms.

        Raises
        ------
        ValueError
            For a connective whose norm the block lacks, or an output term no earlier rule
            concludes.
        """
        if isinstance(node, Proposition):
            hedges = tuple(Hedge(h) for h in node.hedges)
            core: CoreCondition
            if node.variable in self.inputs:
                core = Is(self.inputs.index(node.variable), node.term, hedges)
            else:
                core = self._degree(node.variable, node.term)
                if hedges:
                    core = Modified(core, 1.0, hedges)
            return Not(core) if node.negated else core
        if isinstance(node, Negation):
            return Not(self.condition(node.operand, tnorm, snorm))
        assert isinstance(node, Compound)
        norm = tnorm if node.op == "and" else snorm
        if norm is None:
            raise ValueError(f"the condition joins with {node.op}, but the block has no "
                             f"{'conjunction' if node.op == 'and' else 'disjunction'}")
        return Join(node.op, tuple(self.condition(c, tnorm, snorm) for c in node.operands),
                    norm)

    def _degree(self, output: str, term: str) -> CoreCondition:
        earlier = self.concluded.get((output, term), [])
        if not earlier:
            raise ValueError(f"the condition reads {output} is {term}, which no rule before it "
                             "concludes (its degree is always 0)")
        if len(earlier) == 1:
            return earlier[0]
        aggregation = self.aggregations.get(output)
        snorm = SNorm.UNBOUNDED_SUM if aggregation is None else aggregation.snorm
        return Join("or", tuple(earlier), snorm)

    def concludes(self, condition: CoreCondition, weight: float,
                  conclusions: Sequence[tuple[str, str, tuple[str, ...]]]) -> None:
        """Record a rule's conclusions (``(output, term, hedges)``: its effective hedges, see
        the readers) for the rules after it."""
        for output, term, hedges in conclusions:
            degree = Modified(condition, float(weight), tuple(Hedge(h) for h in hedges))
            self.concluded.setdefault((output, term), []).append(degree)
