"""Chained outputs: a formula consequent that reads an output evaluated before its own --
fuzzylite's ``Function`` term reading another output variable (``diffFx: Function
fabs(outputFx - trueFx)`` in its ``approximation`` example).

Semantics (pyfuzzylite 8): ``Engine.process`` fires the rules, then defuzzifies the outputs in
the order they are declared, each committing its value (lock-previous, then ``default``, then
lock-range applied) before the next is defuzzified; a ``Function`` reads every variable's
``value`` at the time it is evaluated. So an output declared *before* the formula's is read at
this evaluation, as it was committed; one declared after it (or its own) would be read at the
*previous* evaluation (NaN after a restart). it2track keeps the first kind only -- the readers
refuse the second, naming the term and the output -- so the value is a function of this
evaluation's inputs (and, in :func:`chain_values` with a state, of ``lock_previous``'s kept
values, as fuzzylite's).

A formula consequent of output ``k`` (a :class:`~.formula.Formula`) reads the names ``inputs +
outputs[:j]``, ``j <= k``, in that order; output ``j`` is read as the system gives it there:
its own value, else its ``on_zero_firing`` value, else NaN (fuzzylite's ``default: nan``), which
the formula propagates as IEEE arithmetic does. Only :class:`~.sugeno.T1Sugeno` evaluates
chains (crisp outputs, by numpy: the compiled kernels and the C export refuse the tables'
``"chain"`` feature).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .formula import Formula

__all__ = ["chain_values", "chained_outputs", "check_chain"]

FloatArray = NDArray[np.float64]


def chained_outputs(system: Any, k: int) -> tuple[str, ...]:
    """The outputs before ``k`` that output ``k``'s formula consequents read."""
    names = system.output_names
    n_in = system.n_inputs
    read = {name for rule in system.rules if isinstance(f := rule.consequents[k], Formula)
            for name in f.names[n_in:] if name in f.used}
    return tuple(n for n in names[:k] if n in read)


def check_chain(system: Any) -> None:
    """Refuse a chained formula a system cannot evaluate: in a system other than T1Sugeno, or
    whose names after the inputs are not the outputs before its own, in order (checked before
    the system is lowered to tables)."""
    n_in = len(system.inputs)
    if not any(isinstance(f, Formula) and f.used.intersection(f.names[n_in:])
               for rule in system.rules for f in rule.consequents):
        return
    what = f"{type(system).__name__} {system.name!r}"
    if not getattr(type(system), "_chains", False):
        raise ValueError(f"{what}: a formula consequent reads an output; only T1Sugeno "
                         "evaluates formulas of outputs (fuzzylite's chained Function)")
    inputs = tuple(i.name for i in system.inputs)
    outputs = tuple(o if isinstance(o, str) else o.name for o in system.outputs) or tuple(
        f"output{k + 1}" for k in range(len(system.rules[0].consequents)))
    for r, rule in enumerate(system.rules):
        for k, f in enumerate(rule.consequents):
            if not isinstance(f, Formula) or len(f.names) == len(inputs):
                continue
            read = len(f.names) - len(inputs)
            if read > k or f.names != inputs + outputs[:read]:
                raise ValueError(
                    f"{what}: rule {r}: formula {f.text!r} of output {outputs[k]!r} reads "
                    f"{list(f.names)}; a formula reads the inputs, then the outputs before "
                    f"its own in order: {list(inputs + outputs[:k])}")


def chain_values(system: Any, x: FloatArray, state: FloatArray | None = None) -> FloatArray:
    """The outputs ``(N, m)`` at the clipped inputs ``x`` (n_inputs, N), in order, NaN where an
    output has no value (no rule fires, or its value is undefined, and no ``on_zero_firing``).

    With ``state`` (the output row before ``x``'s first, NaN for none) the rows are successive
    evaluations: an output with ``lock_previous`` keeps its previous value where it has none of
    its own before ``on_zero_firing`` applies, as fuzzylite's ``OutputVariable.defuzzify`` (see
    :mod:`.sequence`), and a later formula reads the value so kept.
    """
    n, m = x.shape[1], system.n_outputs
    out = np.empty((n, m))
    index = np.arange(n)
    for k, c in enumerate(system.tables.outputs):
        if not c.n_rules:
            u = np.full(n, np.nan)
        else:
            rows = x if "chain" not in c.features else np.vstack([x, out[:, :k].T])
            u = system._values_of(c, rows, k)
        if state is not None and system.keeps_previous(k):
            own = ~np.isnan(u)
            if not own.all():
                last = np.maximum.accumulate(np.where(own, index, -1))
                u = np.where(last >= 0, u[np.maximum(last, 0)], state[k])
        zero = system.zero_firing_value(k)
        if zero is not None:
            u[np.isnan(u)] = zero
        out[:, k] = u
    return out

