"""Tsukamoto fuzzy systems (type-1): monotonic consequent sets, each rule's output read off
its set's inverse at the rule's firing.

A rule ``if ... then y is Z`` names a set ``Z`` of an :class:`~it2track.fuzzy.rules.Output`
whose membership is monotonic and invertible on its rising (or falling) part: fuzzylite's
``Ramp``, ``Sigmoid``, ``SShape``, ``ZShape``, ``Concave``, ``Arc`` and MATLAB's
``linsmf``/``linzmf`` (every class with an ``inverse``). As in fuzzylite 8, the firing
strengths of the rules that name the same set are first combined with the output's
``aggregation`` (default: their plain sum, fuzzylite's ``none``) into one degree ``w_Z``; the
set contributes ``z_Z = Z.inverse(w_Z)`` and the output is the weighted average
``sum(w_Z z_Z) / sum(w_Z)`` (or the weighted sum ``sum(w_Z z_Z)``) over the sets that fire
(``w_Z > 0``), summed in the output's set order. Antecedents, AND/OR, NOT and weights are the
shared rule machinery (:mod:`.tables`).

Where no rule fires the output is undefined: :class:`~it2track.fuzzy.reducers.ZeroFiringError`
or ``on_zero_firing``. A degree outside the range of a set's membership (a sum of firings
above the set's height, say) has no inverse: the evaluation raises a ``ValueError`` naming
the set and the point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .norms import Aggregation, TNorm, WeightedDefuzzifier
from .rules import Output
from .system import BLOCK, _SystemBase
from .tables import SystemTables

__all__ = ["T1Tsukamoto"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, kw_only=True)
class T1Tsukamoto(_SystemBase):
    """Type-1 Tsukamoto system (see the module docstring).

    Parameters
    ----------
    inputs : sequence of Input
        Type-1 sets.
    outputs : sequence of Output
        Every set type-1 with a monotonic membership (a class with ``inverse``).
    rules : sequence of Rule
        Consequents are output set labels.
    tnorm, snorm : TNorm, SNorm
        AND / OR of the antecedents (default min / max).
    aggregation : Aggregation
        Combines the firing of rules naming the same set (default ``SUM``).
    defuzzifier : WeightedDefuzzifier
        ``AVERAGE`` (default) or ``SUM``.
    on_zero_firing : float, tuple of float or None
        Output where no rule fires; ``None`` (default) raises ``ZeroFiringError``.
    lock_previous : bool or tuple of bool
        fuzzylite's ``lock-previous`` (one per output, or one for all; default ``False``): in
        :meth:`evaluate_sequence` the output keeps its previous value where it has none of its
        own (no rule of it fires). ``__call__`` stays a function of its inputs: there it gives
        ``on_zero_firing`` (or raises), as fuzzylite's first evaluation after a restart does.
    name : str

    Examples
    --------
    >>> from it2track.fuzzy import Input, Output, Ramp, Rule, Triangle
    >>> x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    >>> y = Output("y", (0, 10), [("small", Ramp(10, 0)), ("big", Ramp(0, 10))])
    >>> fls = T1Tsukamoto(inputs=[x], outputs=[y], rules=[Rule(["lo"], "small"),
    ...                                                   Rule(["hi"], "big")])
    >>> float(fls(0.25))  # small at 0.75 -> z = 2.5, big at 0.25 -> z = 2.5
    2.5
    """

    outputs: tuple[Output, ...] = ()
    tnorm: TNorm = TNorm.MINIMUM
    aggregation: Aggregation = Aggregation.SUM
    defuzzifier: WeightedDefuzzifier = WeightedDefuzzifier.AVERAGE

    def _check_outputs(self) -> None:
        if not self.outputs:
            raise ValueError("T1Tsukamoto needs outputs=[Output(...), ...]")
        if not isinstance(self.aggregation, Aggregation):
            raise ValueError(f"aggregation={self.aggregation!r} must be an Aggregation member")
        if not isinstance(self.defuzzifier, WeightedDefuzzifier):
            raise ValueError(f"defuzzifier={self.defuzzifier!r} must be a WeightedDefuzzifier")
        for out in self.outputs:
            if not isinstance(out, Output):
                raise ValueError(f"outputs: {out!r} must be an Output (name, universe, sets)")
            for s in out.sets:
                if not s.is_type1 or not callable(getattr(s.upper, "inverse", None)):
                    raise ValueError(
                        f"T1Tsukamoto: output {out.name!r} set {s.name!r} ({s.upper!r}) must be "
                        "a type-1 monotonic term with an inverse (Ramp, Sigmoid, SShape, ZShape, "
                        "Concave, Arc, LinearSShape, LinearZShape)"
                    )
        names = [o.name for o in self.outputs]
        if len(set(names)) != len(names) or not all(names):
            raise ValueError(f"output names {names!r} must be distinct and non-empty")
        for k, rule in enumerate(self.rules):
            for out, label in zip(self.outputs, rule.consequents, strict=False):
                if label is None:
                    continue
                if not isinstance(label, str):
                    raise ValueError(f"rule {k}: a Tsukamoto consequent is an output set "
                                     f"label, got {label!r}")
                out.set_index(label)
        for inp in self.inputs:
            for s in inp.sets:
                if not s.is_type1:
                    raise ValueError(f"T1Tsukamoto: input {inp.name!r} set {s.name!r} has a "
                                     "footprint of uncertainty")

    def _lower(self) -> SystemTables:
        # Each consequent becomes its set's index: the tables sort the rules by it, so the
        # rules of one set are contiguous and in rule order.
        rules = tuple(
            r.with_consequents([
                None if label is None else float(out.set_index(str(label)))
                for out, label in zip(self.outputs, r.consequents, strict=True)
            ])
            for r in self.rules
        )
        return SystemTables(self.inputs, rules, snorm=self.snorm)

    def _interval_of(
        self, c: SystemTables, x: FloatArray, k: int
    ) -> tuple[FloatArray, FloatArray]:
        out = self.outputs[k]
        sets = c.y_lo_s.astype(np.intp)
        n = x.shape[1]
        u = np.empty(n)
        average = self.defuzzifier is WeightedDefuzzifier.AVERAGE
        for start in range(0, n, BLOCK):
            stop = min(start + BLOCK, n)
            _, f = c.firing_block(x[:, start:stop], self.tnorm)
            num = np.zeros(stop - start)
            den = np.zeros(stop - start)
            for s in np.unique(sets):
                rows = f[sets == s]
                w = rows[0].copy()
                for r in range(1, rows.shape[0]):
                    w = self.aggregation.snorm.pair(w, rows[r])
                fired = w > 0.0
                with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                    z = np.asarray(out.sets[s].upper.inverse(w), dtype=np.float64)
                bad = fired & ~np.isfinite(z)
                if bad.any():
                    j = start + int(np.argmax(bad))
                    point = ", ".join(f"{inp.name}={x[i, j]:.6g}"
                                      for i, inp in enumerate(self.inputs))
                    raise ValueError(
                        f"T1Tsukamoto {self.name!r}: output {out.name!r} set "
                        f"{out.sets[s].name!r} fires {float(w[j - start])!r} at ({point}), "
                        "which its membership never reaches (no inverse)"
                    )
                num += np.where(fired, w * np.where(fired, z, 0.0), 0.0)
                den += w
            with np.errstate(divide="ignore", invalid="ignore"):
                u[start:stop] = num / den if average else np.where(den > 0.0, num, np.nan)
        if math.isnan(float(np.add.reduce(u))):
            bad = np.isnan(u)
            zero = self.zero_firing_value(k)
            if zero is None:
                self._zero_firing(x, bad)
            u[bad] = zero
        return u, u.copy()
