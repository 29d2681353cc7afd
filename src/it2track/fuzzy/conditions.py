"""General rule conditions: any nesting of AND, OR, NOT and hedges over the inputs' sets.

A :class:`~it2track.fuzzy.rules.Rule` joins its propositions with one connective; a rule whose
condition needs a tree -- ``A and (B or C)`` (FCL, fuzzylite), or a fuzzylite *chained* rule
whose proposition names an output (``if Power is LOW``: the aggregated degree of the rules
before it that conclude ``Power is LOW``, which a reader rewrites as their OR over the inputs)
-- carries a :data:`Condition` instead:

- :class:`Is`: ``input i is [hedges] set`` (the set's membership, hedged);
- :class:`Not`: ``1 - operand``;
- :class:`Join`: the t-norm (``"and"``) or s-norm (``"or"``) folded over the operands left to
  right; ``norm`` names it, or ``None`` for the system's t-norm / s-norm;
- :class:`Modified`: ``hedges(weight * operand)`` (an earlier rule's activation degree, as
  fuzzylite's chained propositions read it).

Interval type-2 sets: every operation is monotone in each operand (``Not`` and a ``not``
hedge decreasing), so the lower / upper firing is the condition evaluated on the lower / upper
memberships, with the bounds swapped under each negation.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from .hedges import Hedge
from .norms import SNorm, TNorm

__all__ = ["Condition", "Is", "Join", "Modified", "Not", "inputs_of"]


@dataclass(frozen=True)
class Is:
    """``input is [hedges] label`` (``input``: the input's index; hedges outermost first)."""

    input: int
    label: str
    hedges: tuple[Hedge, ...] = ()


@dataclass(frozen=True)
class Not:
    """``1 - operand``."""

    operand: Condition


@dataclass(frozen=True)
class Join:
    """``op`` (``"and"`` or ``"or"``) of two or more operands, with ``norm`` (a TNorm for
    ``"and"``, an SNorm for ``"or"``) or the system's when ``None``."""

    op: str
    operands: tuple[Condition, ...]
    norm: TNorm | SNorm | None = None

    def __post_init__(self) -> None:
        if self.op not in ("and", "or"):
            raise ValueError(f"Join op={self.op!r} must be 'and' or 'or'")
        if len(self.operands) < 2:
            raise ValueError("a Join needs two or more operands")
        want = TNorm if self.op == "and" else SNorm
        if self.norm is not None and not isinstance(self.norm, want):
            raise ValueError(f"Join {self.op!r}: norm={self.norm!r} must be a {want.__name__}")


@dataclass(frozen=True)
class Modified:
    """``hedges(weight * operand)``: ``0 <= weight <= 1``, hedges outermost first."""

    operand: Condition
    weight: float = 1.0
    hedges: tuple[Hedge, ...] = ()

    def __post_init__(self) -> None:
        if not 0.0 <= float(self.weight) <= 1.0:
            raise ValueError(f"Modified weight={self.weight!r} must be in [0, 1]")


Condition = Is | Not | Join | Modified


def inputs_of(condition: Condition) -> Iterator[Is]:
    """Every proposition of ``condition``, in order."""
    if isinstance(condition, Is):
        yield condition
    elif isinstance(condition, Not | Modified):
        yield from inputs_of(condition.operand)
    else:
        for operand in condition.operands:
            yield from inputs_of(operand)
