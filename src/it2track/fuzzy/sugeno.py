"""Sugeno fuzzy systems -- zero-order and first-order (TSK), type-1 and interval type-2 --
evaluated batch-first.

Definition is apart from evaluation: an :class:`IT2Sugeno` or :class:`T1Sugeno` is an immutable
description (inputs with their sets, rules, t-norm, s-norm, type reducer) that lowers itself
once into arrays (:class:`~it2track.fuzzy.tables.SystemTables`); calling it evaluates any number
of input points in one vectorised pass.

Rules (:class:`~it2track.fuzzy.rules.Rule`) may use AND or OR, NOT, weights, interval or
:class:`~it2track.fuzzy.rules.Linear` (first-order) consequents, and one consequent per output.
A first-order rule's consequent depends on the input, so the type reducers sort the rules per
sample; the paper's rule form (zero-order AND rules of weight 1) pays nothing for this.

Shapes
------
``system(x1, x2, ..., xn)`` takes one array per input; they broadcast together to a batch shape
``S`` and the output has shape ``S`` (a scalar call returns a 0-d array / float-like); a system
with ``m > 1`` outputs returns ``S + (m,)`` (use :meth:`~IT2Sugeno.select_output` for one).
``system.evaluate(X)`` takes the inputs stacked on the last axis, ``X.shape == S + (n,)``.
Firing strengths have the rules on the last axis: ``S + (R,)``.

Inputs are clipped to their universe before evaluation; NaN or inf raises ``ValueError`` naming
the input.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from .chain import chain_values
from .norms import Aggregation, WeightedDefuzzifier
from .reducers import EXHAUSTIVE, TypeReducer
from .system import BLOCK, _SystemBase
from .tables import EXACT_IDENTITY, SystemTables

__all__ = ["FuzzySystem", "IT2Sugeno", "T1Sugeno"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, kw_only=True)
class IT2Sugeno(_SystemBase):
    """Interval type-2 Sugeno system: zero-order (interval consequents) or first-order (TSK).

    Parameters
    ----------
    inputs : sequence of Input
    rules : sequence of Rule
    tnorm : TNorm
        ``TNorm.PRODUCT`` (eqs. 13-14, default) or ``TNorm.MINIMUM``.
    reducer : TypeReducer
        Type reducer; default :data:`~it2track.fuzzy.reducers.EXHAUSTIVE` (exact).
    on_zero_firing : float, tuple of float or None
        Output where no rule fires (one per output, or one for all). ``None`` (default) raises
        :class:`~it2track.fuzzy.reducers.ZeroFiringError` instead. (Wu-Mendel where rules fire
        but their total lower firing is zero always raises ``ZeroFiringError``.)
    lock_previous : bool or tuple of bool
        fuzzylite's ``lock-previous`` (one per output, or one for all; default ``False``): in
        :meth:`evaluate_sequence` the output keeps its previous value where it has none of its
        own (no rule of it fires). ``__call__`` stays a function of its inputs: there it gives
        ``on_zero_firing`` (or raises), as fuzzylite's first evaluation after a restart does.
    name : str
    snorm : SNorm
        S-norm of OR rules: ``SNorm.MAXIMUM`` (default) or ``SNorm.PROBOR``.
    outputs : tuple of str
        Output names, one per consequent of each rule (default: one unnamed output).

    Examples
    --------
    >>> from it2track.fuzzy import Input, IT2Set, Rule, Triangle
    >>> sets = [IT2Set.from_fou(Triangle(-1, -1, 1), 0.2, "N"),
    ...         IT2Set.from_fou(Triangle(-1, 1, 1), 0.2, "P")]
    >>> fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)],
    ...                 rules=[Rule(["N"], -1.0), Rule(["P"], 1.0)])
    >>> fls([-1.0, 0.0, 0.5]).round(6).tolist()
    [-0.954545, 0.0, 0.504093]

    At ``x = -1`` the FoU widens P's upper foot to -1.1, so P fires in ``[0, 1/21]`` beside N's
    ``[1, 1]``: ``yl = -1``, ``yr = (-1 + 1/21) / (1 + 1/21) = -10/11`` and
    ``u = -21/22 = -0.954545...``.
    """

    reducer: TypeReducer = EXHAUSTIVE
    #: How :mod:`.kernels` compiles this class (this class only: not inherited, see there).
    _compiled_as: ClassVar[str] = "it2"

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.reducer, TypeReducer):
            raise ValueError(f"reducer={self.reducer!r} must be a TypeReducer")

    def _interval_of(
        self, c: SystemTables, x: FloatArray, k: int
    ) -> tuple[FloatArray, FloatArray]:
        n = x.shape[1]
        yl = np.empty(n)
        yr = np.empty(n)
        linear = "linear" in c.features
        for start in range(0, n, BLOCK):
            stop = min(start + BLOCK, n)
            fl, fu = c.firing_block(x[:, start:stop], self.tnorm)
            if linear:
                y_lo, y_hi = c.consequents_block(x[:, start:stop])
                yl[start:stop], yr[start:stop] = self.reducer.reduce_per_sample(
                    fl, fu, y_lo, y_hi
                )
            else:
                yl[start:stop], yr[start:stop] = self.reducer.reduce_rules_first(
                    fl, fu, c.y_lo_s, c.y_hi_s, c.order_ident, c.order_hi_s
                )
        return self._undefined(c, x, k, yl, yr)

    def _no_output_message(self, point: str) -> str:
        return (
            f"type reducer {self.reducer.name!r} of {type(self).__name__} {self.name!r} has no "
            f"output at ({point}): rules fire there, but their total lower firing strength is "
            "zero; use an exact reducer"
        )

    def _scalar_output(self, x: list[float]) -> float | None:
        if self.reducer is not EXHAUSTIVE or self._c.features or (
                self.tnorm not in EXACT_IDENTITY):
            return None
        c = self._c
        fl, fu = self._firing_scalar(x)
        yl = _exhaustive_scalar(fl, fu, c.y_lo_s.tolist(), left=True)
        yr = _exhaustive_scalar([fl[k] for k in c.order_hi_s], [fu[k] for k in c.order_hi_s],
                                c.y_hi_s[c.order_hi_s].tolist(), left=False)
        if yl is None or yr is None:
            zero = self.zero_firing_value(0)
            if zero is None:
                return None  # the array path raises the descriptive error
            return float(zero)
        return (yl + yr) * 0.5


def _exhaustive_scalar(fl: list[float], fu: list[float], y: list[float], *, left: bool
                       ) -> float | None:
    """Scalar mirror of the exhaustive kernels (same operations in the same order)."""
    num = fl[0] * y[0]
    den = fl[0]
    for n in range(1, len(fl)):
        num += fl[n] * y[n]
        den += fl[n]
    best = num / den if den != 0.0 else None
    order = range(len(fl)) if left else range(len(fl) - 1, -1, -1)
    for n in order:
        d = fu[n] - fl[n]
        num += d * y[n]
        den += d
        if den != 0.0:
            cand = num / den
            if best is None or (cand < best if left else cand > best):
                best = cand
    return best


@dataclass(frozen=True, kw_only=True)
class T1Sugeno(_SystemBase):
    """Type-1 Sugeno system: ``u = sum(f y) / sum(f)`` (MATLAB's ``wtaver``) or ``sum(f y)``
    (``wtsum``).

    Every set must be type-1 (an :class:`IT2Set` whose lower MF is its upper MF, or a
    ``(name, mf)`` pair given to :class:`Input`).

    Parameters
    ----------
    inputs : sequence of Input
    rules : sequence of Rule
        Crisp consequents only: numbers (zero-order) or :class:`~it2track.fuzzy.rules.Linear`
        with crisp coefficients (first-order, ``y = c0 + sum ci xi``).
    tnorm : TNorm
        AND of the antecedents: ``TNorm.PRODUCT`` (default) or any other t-norm.
    on_zero_firing : float, tuple of float or None
        Output where no rule fires (one per output, or one for all); ``None`` (default) raises
        :class:`~it2track.fuzzy.reducers.ZeroFiringError` instead (also for ``wtsum``).
    lock_previous : bool or tuple of bool
        fuzzylite's ``lock-previous`` (one per output, or one for all; default ``False``): in
        :meth:`evaluate_sequence` the output keeps its previous value where it has none of its
        own (no rule of it fires). ``__call__`` stays a function of its inputs: there it gives
        ``on_zero_firing`` (or raises), as fuzzylite's first evaluation after a restart does.
    name : str
    snorm : SNorm
        S-norm of OR rules: ``SNorm.MAXIMUM`` (default) or any other s-norm.
    outputs : tuple of str
        Output names, one per consequent of each rule (default: one unnamed output).
    defuzzifier : WeightedDefuzzifier
        ``WeightedDefuzzifier.AVERAGE`` (default, ``wtaver``) or ``SUM`` (``wtsum``: the sum
        of the rules' firing times consequent, in rule order).
    aggregation : Aggregation or None
        ``None`` (default, MATLAB): every rule is a term of the weighted average. Otherwise
        rules with equal consequents are one term, whose degree is this s-norm
        of their firings folded in rule order: jFuzzyLogic's ``ACCU`` of singletons, which
        it groups by value (``Aggregation.MAXIMUM``: ``u = sum_v v max_{r: y_r = v} f_r /
        sum_v max_{r: y_r = v} f_r``). First-order consequents are grouped where their
        values at the input are equal, as jFuzzyLogic does. Evaluated by numpy.

    Examples
    --------
    A first-order rule ``y = 2 x + 1`` and a zero-order one, joined by OR/NOT:

    >>> from it2track.fuzzy import Input, Linear, Rule, Triangle
    >>> x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    >>> fls = T1Sugeno(inputs=[x], rules=[Rule(["lo"], Linear([2.0], 1.0)),
    ...                                    Rule(["lo"], 0.0, negated=[True])])
    >>> float(fls(0.25))  # (0.75 * 1.5 + 0.25 * 0) / (0.75 + 0.25)
    1.125
    """

    defuzzifier: WeightedDefuzzifier = WeightedDefuzzifier.AVERAGE
    aggregation: Aggregation | None = None
    #: How :mod:`.kernels` compiles this class (this class only: not inherited, see there).
    _compiled_as: ClassVar[str] = "t1"
    #: A formula consequent may read the outputs before its own (:mod:`.chain`).
    _chains: ClassVar[bool] = True

    def __post_init__(self) -> None:
        if not isinstance(self.defuzzifier, WeightedDefuzzifier):
            raise ValueError(f"defuzzifier={self.defuzzifier!r} must be a WeightedDefuzzifier")
        super().__post_init__()
        for inp in self.inputs:
            for s in inp.sets:
                if not s.is_type1:
                    raise ValueError(
                        f"T1Sugeno: input {inp.name!r} set {s.name!r} has a footprint of "
                        "uncertainty; use IT2Sugeno"
                    )
        if not all(c.crisp for c in self._c.outputs):
            raise ValueError("T1Sugeno: rule consequents must be crisp (lo == hi)")
        if self.aggregation is not None and not isinstance(self.aggregation, Aggregation):
            raise ValueError(f"aggregation={self.aggregation!r} must be an Aggregation or None")

    def _interval_of(
        self, c: SystemTables, x: FloatArray, k: int
    ) -> tuple[FloatArray, FloatArray]:
        u = self._values_of(c, x, k)
        if math.isnan(float(np.add.reduce(u))):
            bad = np.isnan(u)
            zero = self.zero_firing_value(k)
            if zero is None:
                self._zero_firing(x, bad)
            u[bad] = zero
        return u, u.copy()

    def _values_of(self, c: SystemTables, x: FloatArray, k: int) -> FloatArray:
        """Output ``k`` at the block ``x``, NaN where it has none (no rule fires, 0/0); with
        ``"chain"`` the rows of ``x`` after the inputs' are the outputs before ``k``."""
        y = c.y_lo_s
        n = x.shape[1]
        n_in = self.n_inputs
        u = np.empty(n)
        linear = "linear" in c.features
        average = self.defuzzifier is WeightedDefuzzifier.AVERAGE
        with np.errstate(divide="ignore", invalid="ignore"):
            for start in range(0, n, BLOCK):
                stop = min(start + BLOCK, n)
                _, f = c.firing_block(x[:n_in, start:stop], self.tnorm)
                if self.aggregation is not None:
                    yb = (c.consequents_block(x[:, start:stop])[0] if linear
                          else np.broadcast_to(y[:, None], f.shape))
                    num, den = self._aggregated(f, yb)
                elif linear:
                    yb = c.consequents_block(x[:, start:stop])[0]
                    num, den = (f * yb).sum(axis=0), f.sum(axis=0)
                else:
                    num = f[0] * y[0]
                    den = f[0].copy()
                    for r in range(1, f.shape[0]):
                        num += f[r] * y[r]
                        den += f[r]
                u[start:stop] = num / den if average else np.where(den != 0.0, num, np.nan)
        return u

    def _interval_blocks(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        if not self._chained:
            return super()._interval_blocks(x)
        y = chain_values(self, x)
        bad = np.isnan(y)
        if bad.any():  # the first output without a value (and no on_zero_firing)
            self._zero_firing(x, bad[:, int(np.argmax(bad.any(axis=0)))])
        y = y[:, 0] if y.shape[1] == 1 else y
        return y, y.copy()

    @property
    def _chained(self) -> bool:
        """A formula consequent reads an output before its own (see :mod:`.chain`)."""
        return any("chain" in c.features for c in self._c.outputs)

    def _aggregated(self, f: FloatArray, yb: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(sum_v v F_v, sum_v F_v)`` per sample, ``F_v`` the aggregation of the firings
        ``f`` (R, N) of the rules whose consequent ``yb`` (R, N) equals ``v`` there."""
        assert self.aggregation is not None
        snorm = self.aggregation.snorm
        deg = f.copy()
        merged = np.zeros(f.shape, dtype=bool)  # rule r joined an earlier rule's term there
        for r in range(1, f.shape[0]):
            for q in range(r):
                same = ~merged[q] & ~merged[r] & (yb[q] == yb[r])
                if same.any():
                    deg[q, same] = snorm.pair(deg[q, same], f[r, same])
                    merged[r, same] = True
        deg[merged] = 0.0
        return (deg * yb).sum(axis=0), deg.sum(axis=0)

    def _scalar_output(self, x: list[float]) -> float | None:
        if self._c.features or self.tnorm not in EXACT_IDENTITY or self.aggregation:
            return None
        _, f = self._firing_scalar(x)
        y = self._c.y_lo_s
        num = f[0] * float(y[0])
        den = f[0]
        for r in range(1, len(f)):
            num += f[r] * float(y[r])
            den += f[r]
        if den == 0.0:
            zero = self.zero_firing_value(0)
            return None if zero is None else float(zero)
        return num / den if self.defuzzifier is WeightedDefuzzifier.AVERAGE else num


FuzzySystem = IT2Sugeno | T1Sugeno
