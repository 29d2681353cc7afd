"""Rule conditions as the text formats write them (``(A and not B) or C``), and their reduction
to it2track's rules: one connective over propositions on distinct inputs, each perhaps
negated.

FCL and fuzzylite's FLL allow any nesting of ``AND``, ``OR``, ``NOT`` and parentheses; the tools
evaluate the tree. :func:`flatten` rewrites a tree into the flat form when that changes no
value: nested parentheses of one connective (associativity), ``NOT`` of a proposition (our
negation ``1 - mu``) and ``NOT`` of a compound condition by De Morgan's laws, which hold when the
AND and OR operators are duals (``NOT (A OR B) = NOT A AND NOT B`` with ``min``/``max``,
``product``/``probor`` and fuzzylite's other pairs; equal up to rounding except for
``min``/``max``). Anything else -- ``A AND (B OR C)``, an input named twice -- raises
``ValueError`` with the reason, and the readers make it a general condition (:mod:`._chain`).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from ..fuzzy import SNorm, TNorm

__all__ = ["DUALS", "Compound", "Condition", "Negation", "Proposition", "flatten", "propositions"]

#: t-norm -> its De Morgan dual s-norm
DUALS = {
    TNorm.MINIMUM: SNorm.MAXIMUM,
    TNorm.PRODUCT: SNorm.PROBOR,
    TNorm.BOUNDED_DIFFERENCE: SNorm.BOUNDED_SUM,
    TNorm.DRASTIC_PRODUCT: SNorm.DRASTIC_SUM,
    TNorm.EINSTEIN_PRODUCT: SNorm.EINSTEIN_SUM,
    TNorm.HAMACHER_PRODUCT: SNorm.HAMACHER_SUM,
    TNorm.NILPOTENT_MINIMUM: SNorm.NILPOTENT_MAXIMUM,
}


@dataclass(frozen=True)
class Proposition:
    """``variable is [hedges] term`` (``negated``: ``is not``)."""

    variable: str
    term: str
    negated: bool = False
    hedges: tuple[str, ...] = ()


@dataclass(frozen=True)
class Negation:
    """``NOT (condition)``."""

    operand: Condition


@dataclass(frozen=True)
class Compound:
    """``a AND b AND ...`` or ``a OR b OR ...`` (``op`` is ``"and"`` or ``"or"``)."""

    op: str
    operands: tuple[Condition, ...]


Condition = Proposition | Negation | Compound


def _push(node: Condition, negate: bool, duals: bool) -> Condition:
    """``node`` with every NOT pushed onto its propositions (De Morgan needs ``duals``)."""
    if isinstance(node, Proposition):
        if not negate:
            return node
        return Proposition(node.variable, node.term, not node.negated, node.hedges)
    if isinstance(node, Negation):
        return _push(node.operand, not negate, duals)
    if negate and not duals:
        raise ValueError(
            "NOT of a compound condition needs De Morgan's laws, which hold only when the AND "
            "and OR operators are duals (min/max, product/probor, ...)"
        )
    op = node.op if not negate else ("or" if node.op == "and" else "and")
    return Compound(op, tuple(_push(c, negate, duals) for c in node.operands))


def _gather(node: Condition, op: str, out: list[Proposition]) -> None:
    if isinstance(node, Proposition):
        out.append(node)
        return
    assert isinstance(node, Compound)
    if node.op != op:
        raise ValueError(
            f"the condition mixes AND and OR ({op.upper()} of an {node.op.upper()}): "
            "it2track's rules join their propositions with one connective"
        )
    for operand in node.operands:
        _gather(operand, op, out)


def flatten(condition: Condition, *, tnorm: TNorm, snorm: SNorm
            ) -> tuple[str, list[Proposition]]:
    """``(connective, propositions)`` of a condition it2track can evaluate as the tool does.

    Raises
    ------
    ValueError
        With the reason, for conditions that need a tree (mixed connectives) or an input named
        twice.
    """
    pushed = _push(condition, False, DUALS.get(tnorm) is snorm)
    op = pushed.op if isinstance(pushed, Compound) else "and"
    props: list[Proposition] = []
    _gather(pushed, op, props)
    seen: set[str] = set()
    for prop in props:
        if prop.variable in seen:
            raise ValueError(f"input {prop.variable!r} appears twice in the condition: "
                             "it2track's rules name each input once")
        seen.add(prop.variable)
    return op, props


def propositions(condition: Condition) -> Iterator[Proposition]:
    """Every proposition of a condition, in order."""
    if isinstance(condition, Proposition):
        yield condition
    elif isinstance(condition, Negation):
        yield from propositions(condition.operand)
    else:
        for operand in condition.operands:
            yield from propositions(operand)
