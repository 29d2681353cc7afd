"""Mamdani fuzzy systems, interval type-2 and type-1, evaluated batch-first.

A Mamdani system shares everything up to the rule firing with the Sugeno systems of
:mod:`.sugeno` (inputs, sets, :class:`~it2track.fuzzy.rules.Rule` with AND/OR, NOT and weights,
the t-norm and s-norm, :meth:`~it2track.fuzzy.tables.SystemTables.firing_block`); only the
consequent and the type reduction differ. A rule's consequent is the label of a set of an
:class:`~it2track.fuzzy.rules.Output`.

Centroid type reduction (the default)
-------------------------------------
Each output's universe is sampled at ``resolution`` points ``y_1 < ... < y_J`` (MATLAB's
``NumSamplePoints``, default 101). A rule of firing interval ``[fl, fu]`` whose output set has
lower / upper MFs ``L, U`` implies ``[I(fl, L(y_j)), I(fu, U(y_j))]`` (:class:`Implication`:
``min`` clips, ``product`` scales), and the rules are aggregated pointwise
(:class:`Aggregation`: ``max``, ``sum`` or probabilistic OR) into the lower and upper MF of
one IT2 set sampled on the grid. Its centroid is a centre-of-sets problem with ``J`` "rules":
consequent ``y_j`` (crisp) and firing interval ``[lower aggregate, upper aggregate]`` at
``y_j``. So the very same type reducers -- KM, EKM, EIASC, exhaustive (exact, agreeing to about
1e-12) and the Nie-Tan and Wu-Mendel approximations -- apply unchanged, through the same
interface (:meth:`~it2track.fuzzy.reducers.TypeReducer.reduce_rules_first`), and return
``[yl, yr]``; the output is ``(yl + yr) / 2``.

Centre-of-sets type reduction
-----------------------------
``type_reduction=TypeReduction.CENTRE_OF_SETS``: each output set is replaced by its centroid
interval (computed once, on the same grid, by the system's reducer -- or the exhaustive one
when that reducer is an approximation) and the system is evaluated exactly as an
:class:`~it2track.fuzzy.sugeno.IT2Sugeno` with those intervals as consequents (Mendel 2017,
sec. 9.5). Implication and aggregation do not enter.

Type-1 systems (:class:`T1Mamdani`) aggregate the same way and defuzzify the sampled set with a
:class:`~it2track.fuzzy.norms.Defuzzifier` (centroid by default), as MATLAB's ``mamfis``.

Where no rule fires the output is undefined: :class:`~it2track.fuzzy.reducers.ZeroFiringError`
by default, or ``on_zero_firing`` (MATLAB returns the middle of the output range).

Shapes as for the Sugeno systems: ``system(x1, ..., xn)`` broadcasts the inputs to ``S`` and
returns ``S`` (``S + (m,)`` for ``m > 1`` outputs).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .defuzz import Sampling, defuzzify, output_grid
from .norms import Aggregation, Defuzzifier, Implication, TNorm
from .reducers import EXHAUSTIVE, TypeReducer, _exhaustive_left, exhaustive_many_rows
from .rules import Output
from .sugeno import IT2Sugeno, T1Sugeno
from .system import BLOCK, _SystemBase
from .tables import SystemTables

__all__ = [
    "AnySystem",
    "IT2Mamdani",
    "MamdaniSystem",
    "MamdaniTables",
    "Sampling",
    "T1Mamdani",
    "TypeReduction",
    "defuzzify",
    "set_centroid",
]

FloatArray = NDArray[np.float64]

#: Default number of output grid points (MATLAB's ``NumSamplePoints``).
RESOLUTION = 101


class TypeReduction(enum.Enum):
    """Type reduction of an :class:`IT2Mamdani` system (see the module docstring)."""

    CENTROID = "centroid"
    CENTRE_OF_SETS = "centre-of-sets"

    @classmethod
    def from_name(cls, name: str) -> TypeReduction:
        """Look up by value or name; ``"cos"`` and ``"center-of-sets"`` also work."""
        key = str(name).strip().lower().replace("_", "-")
        key = {"cos": "centre-of-sets", "center-of-sets": "centre-of-sets"}.get(key, key)
        for member in cls:
            if key == member.value:
                return member
        raise ValueError(
            f"unknown type reduction {name!r}; choose 'centroid' or 'centre-of-sets'"
        )


def set_centroid(
    lower: FloatArray, upper: FloatArray, y: FloatArray, reducer: TypeReducer = EXHAUSTIVE
) -> tuple[float, float]:
    """Centroid interval ``[cl, cr]`` of an IT2 set sampled on a grid.

    Parameters
    ----------
    lower, upper : ndarray, shape (J,)
        Lower and upper MF at the grid points, ``0 <= lower <= upper``.
    y : ndarray, shape (J,)
        Grid points, ascending.
    reducer : TypeReducer
        An exact reducer gives the exact centroid of the sampled set.

    Examples
    --------
    A type-1 triangle's centroid is its centre of gravity on the grid:

    >>> y = np.linspace(0.0, 4.0, 5)
    >>> set_centroid(np.array([0, 1, 2, 1, 0.0]), np.array([0, 1, 2, 1, 0.0]), y)
    (2.0, 2.0)
    """
    yl, yr = reducer.reduce_rules_first(
        lower[:, None], upper[:, None], y, y, np.arange(y.size), np.arange(y.size)
    )
    return float(yl[0]), float(yr[0])


class MamdaniTables:
    """A Mamdani system lowered to arrays: its antecedents plus its sampled output sets.

    Compiled kernels of Sugeno systems do not cover Mamdani systems: ``features`` always holds
    ``"mamdani"`` (besides the antecedents' features), and a ``MamdaniTables`` is not a
    :class:`~it2track.fuzzy.tables.SystemTables`.

    Parameters
    ----------
    system : IT2Mamdani or T1Mamdani
        The system to lower.
    centroid_reducer : TypeReducer
        Exact reducer for the output sets' centroid intervals.

    Attributes
    ----------
    antecedents : SystemTables
        The rules' lowering (memberships, firing, NOT/OR/weights, several outputs), with each
        rule's consequent interval ``[y_lo, y_hi]`` the centroid interval of its output set:
        exactly the tables of the equivalent centre-of-sets Sugeno system.
    features : frozenset of str
        ``antecedents.features | {"mamdani"}``.
    grids : tuple of ndarray, shape (J,)
        Per output, the ``J = resolution`` grid points (:func:`~.defuzz.output_grid`:
        ``linspace(lo, hi, J)``, or the midpoints of ``J`` equal cells).
    upper_mf, lower_mf : tuple of ndarray, shape (S, J)
        Per output, its ``S`` sets' upper / lower MFs on the grid.
    rule_set : tuple of ndarray of int, shape (R_k,)
        Per output ``k``, the set of each rule of ``antecedents.outputs[k]`` (rule order, not
        sorted).
    set_centroids : tuple of ndarray, shape (S, 2)
        Per output, each set's centroid interval on the grid.
    type1_output : tuple of bool
        Per output, whether its sets' lower and upper MFs are equal on the grid.
    implication : Implication
    aggregation : Aggregation
    """

    def __init__(
        self,
        system: _MamdaniBase,
        centroid_reducer: TypeReducer,
    ) -> None:
        outputs: tuple[Output, ...] = system.outputs
        self.implication = system.implication
        self.aggregation = system.aggregation
        grids, uppers, lowers, centroids = [], [], [], []
        for out in outputs:
            y = output_grid(out.universe, system.resolution, system.sampling)
            up = np.array([np.broadcast_to(s.upper(y), y.shape) for s in out.sets], dtype=float)
            lo = np.array([np.broadcast_to(s.lower(y), y.shape) for s in out.sets], dtype=float)
            lo = np.minimum(lo, up)  # rounding of MFs checked lower <= upper to 1e-12
            cents = []
            for s in range(len(out.sets)):
                if not up[s].any():
                    raise ValueError(
                        f"output {out.name!r} set {out.sets[s].name!r} is zero at every one of "
                        f"the {system.resolution} grid points; raise the resolution"
                    )
                cents.append(set_centroid(lo[s], up[s], y, centroid_reducer))
            grids.append(y)
            uppers.append(up)
            lowers.append(lo)
            centroids.append(np.array(cents))
        self.grids = tuple(grids)
        self.upper_mf = tuple(uppers)
        self.lower_mf = tuple(lowers)
        self.type1_output = tuple(bool(np.array_equal(lo, up))
                                  for lo, up in zip(lowers, uppers, strict=True))
        self.set_centroids = tuple(centroids)
        interval_rules = []
        for rule in system.rules:
            cons: list[object] = []
            for k, label in enumerate(rule.consequents):
                if label is None:
                    cons.append(None)
                else:
                    assert isinstance(label, str)
                    lo_c, hi_c = centroids[k][outputs[k].set_index(label)]
                    cons.append((float(lo_c), float(hi_c)))
            interval_rules.append(
                rule.with_consequents(cons)
            )
        self.antecedents = SystemTables(system.inputs, tuple(interval_rules), snorm=system.snorm)
        self.features: frozenset[str] = self.antecedents.features | {"mamdani"}
        rule_set = []
        for k, tables in enumerate(self.antecedents.outputs):
            labels = [system.rules[r].consequents[k] for r in tables.rule_index]
            rule_set.append(np.array([outputs[k].set_index(str(lab)) for lab in labels],
                                     dtype=np.intp))
        self.rule_set = tuple(rule_set)
        # Sorted-order set index of each rule (the order firing_block returns).
        self.rule_set_s = tuple(
            rs[t.perm] for rs, t in zip(self.rule_set, self.antecedents.outputs, strict=True)
        )

    def aggregate(
        self, k: int, f: FloatArray, *, lower: bool
    ) -> FloatArray:
        """The aggregated output set of output ``k`` on its grid, ``(J, N)``.

        ``f`` is the (lower or upper) firing ``(R_k, N)`` in sorted order; ``lower`` picks the
        sets' lower MFs.
        """
        mf = (self.lower_mf if lower else self.upper_mf)[k]
        sets = self.rule_set_s[k]
        n = f.shape[1]
        out = np.zeros((mf.shape[1], n))
        clip = self.implication is Implication.MINIMUM
        scale = self.implication is Implication.PRODUCT
        if self.aggregation is Aggregation.MAXIMUM and (clip or scale):
            # max_r I(f_r, mu_s) = I(max_r f_r, mu_s) for the rules r of set s: I is monotone
            # in f and rounding is monotone, so this is exact (for min and product; a rounded
            # Einstein product, say, need not be monotone to the last bit).
            for s in np.unique(sets):
                strongest = f[sets == s].max(axis=0)
                term = (np.minimum(strongest[None, :], mf[s][:, None]) if clip
                        else mf[s][:, None] * strongest[None, :])
                np.maximum(out, term, out=out)
            return out
        tnorm = self.implication.tnorm
        for r in range(f.shape[0]):
            mu = mf[sets[r]][:, None]
            if clip:
                term = np.minimum(f[r][None, :], mu)
            elif scale:
                term = mu * f[r][None, :]
            else:
                term = tnorm.pair(f[r][None, :], mu)
            if self.aggregation is Aggregation.SUM:
                out += term
            elif self.aggregation is Aggregation.PROBOR:
                out += term - out * term
            else:
                out = self.aggregation.snorm.pair(out, term)
        return out


@dataclass(frozen=True, kw_only=True)
class _MamdaniBase(_SystemBase):
    outputs: tuple[Output, ...] = ()
    tnorm: TNorm = TNorm.MINIMUM
    implication: Implication = Implication.MINIMUM
    aggregation: Aggregation = Aggregation.MAXIMUM
    resolution: int = RESOLUTION
    sampling: Sampling = Sampling.ENDPOINTS
    _m: MamdaniTables = field(init=False, repr=False, compare=False)

    def _check_outputs(self) -> None:
        if not self.outputs:
            raise ValueError(f"{type(self).__name__} needs outputs=[Output(...), ...]")
        for out in self.outputs:
            if not isinstance(out, Output):
                raise ValueError(f"outputs: {out!r} must be an Output (name, universe, sets)")
        names = [o.name for o in self.outputs]
        if len(set(names)) != len(names) or not all(names):
            raise ValueError(f"output names {names!r} must be distinct and non-empty")
        if not isinstance(self.implication, Implication):
            raise ValueError(f"implication={self.implication!r} must be an Implication member")
        if not isinstance(self.aggregation, Aggregation):
            raise ValueError(f"aggregation={self.aggregation!r} must be an Aggregation member")
        if not isinstance(self.sampling, Sampling):
            raise ValueError(f"sampling={self.sampling!r} must be a Sampling member")
        if (isinstance(self.resolution, bool) or not isinstance(self.resolution, int)
                or not 3 <= self.resolution <= 100_000):
            raise ValueError(f"resolution={self.resolution!r} must be an int in [3, 100000]")
        for k, rule in enumerate(self.rules):
            for out, label in zip(self.outputs, rule.consequents, strict=False):
                if label is None:
                    continue
                if not isinstance(label, str):
                    raise ValueError(
                        f"rule {k}: a Mamdani consequent is an output set label, got {label!r}"
                    )
                out.set_index(label)

    def _centroid_reducer(self) -> TypeReducer:
        return EXHAUSTIVE

    def _lower(self) -> SystemTables:
        tables = MamdaniTables(self, self._centroid_reducer())
        object.__setattr__(self, "_m", tables)
        return tables.antecedents

    @property
    def tables(self) -> Any:
        """The system lowered to arrays (:class:`MamdaniTables`)."""
        return self._m

    def select_output(self, output: int | str) -> Any:
        """The same system with one output (its index or name); rules without a consequent
        for it are left out."""
        names = self.output_names
        k = names.index(output) if isinstance(output, str) and output in names else output
        if not isinstance(k, int) or isinstance(k, bool) or not 0 <= k < len(names):
            raise ValueError(f"output={output!r} must be an output name {list(names)} or an "
                             f"index 0..{len(names) - 1}")
        if len(names) == 1:
            return self
        from dataclasses import replace

        rules = tuple(
            r.with_consequents([r.consequents[k]], [k])
            for r in self.rules if r.consequents[k] is not None
        )
        return replace(self, rules=rules, outputs=(self.outputs[k],),
                       on_zero_firing=self.zero_firing_value(k),
                       lock_previous=self.keeps_previous(k))

    def _scalar_output(self, x: list[float]) -> float | None:
        return None

    def aggregated(self, *xs: Any) -> tuple[FloatArray, FloatArray]:
        """The aggregated output set of a one-output system on its grid.

        Returns
        -------
        lower, upper : ndarray, shape ``S + (J,)``
            Lower and upper MF of the aggregated IT2 set (equal for a type-1 system) at the
            grid points ``tables.grids[0]``.
        """
        if self.n_outputs != 1:
            raise ValueError("aggregated() needs a one-output system; use select_output()")
        x, shape = self._prepare(xs)
        c = self._c
        fl, fu = c.firing_block(x, self.tnorm)
        lower = self._m.aggregate(0, fl, lower=True)
        upper = self._m.aggregate(0, fu, lower=False)
        j = lower.shape[0]
        return lower.T.reshape((*shape, j)), upper.T.reshape((*shape, j))


@dataclass(frozen=True, kw_only=True)
class IT2Mamdani(_MamdaniBase):
    """Interval type-2 Mamdani system (see the module docstring).

    Parameters
    ----------
    inputs : sequence of Input
    outputs : sequence of Output
        Output variables with their IT2 (or type-1) sets; rules name these sets.
    rules : sequence of Rule
        Consequents are output set labels (one per output; ``None`` where a rule does not act
        on an output).
    tnorm : TNorm
        AND of the antecedents; default ``TNorm.MINIMUM`` (MATLAB's Mamdani default).
    snorm : SNorm
        OR of the antecedents; default ``SNorm.MAXIMUM``.
    implication : Implication
        Default ``Implication.MINIMUM``.
    aggregation : Aggregation
        Default ``Aggregation.MAXIMUM``.
    reducer : TypeReducer
        Default :data:`~it2track.fuzzy.reducers.EXHAUSTIVE` (exact).
    type_reduction : TypeReduction
        ``CENTROID`` (default) or ``CENTRE_OF_SETS``.
    resolution : int
        Output grid points (default 101).
    sampling : Sampling
        ``Sampling.ENDPOINTS`` (default: MATLAB's ``linspace``) or ``MIDPOINTS`` (fuzzylite's
        midpoint rule); see :func:`~it2track.fuzzy.defuzz.output_grid`.
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
    >>> from it2track.fuzzy import Input, IT2Set, Output, Rule, Triangle
    >>> e = Input("e", (-1, 1), [IT2Set.from_fou(Triangle(-1, -1, 1), 0.2, "N"),
    ...                          IT2Set.from_fou(Triangle(-1, 1, 1), 0.2, "P")])
    >>> u = Output("u", (-10, 10), [IT2Set.from_fou(Triangle(-10, -5, 0), 1.0, "neg"),
    ...                             IT2Set.from_fou(Triangle(0, 5, 10), 1.0, "pos")])
    >>> fls = IT2Mamdani(inputs=[e], outputs=[u],
    ...                  rules=[Rule(["N"], "neg"), Rule(["P"], "pos")])
    >>> fls([-1.0, 0.0, 1.0]).round(6).tolist()  # at -1, P still fires 0.048 (upper MF)
    [-4.572289, 0.0, 4.572289]
    """

    reducer: TypeReducer = EXHAUSTIVE
    type_reduction: TypeReduction = TypeReduction.CENTROID

    def __post_init__(self) -> None:
        if not isinstance(self.reducer, TypeReducer):
            raise ValueError(f"reducer={self.reducer!r} must be a TypeReducer")
        if not isinstance(self.type_reduction, TypeReduction):
            raise ValueError(f"type_reduction={self.type_reduction!r} must be a TypeReduction")
        super().__post_init__()

    def _centroid_reducer(self) -> TypeReducer:
        return self.reducer if self.reducer.exact else EXHAUSTIVE

    def _interval_of(
        self, c: SystemTables, x: FloatArray, k: int
    ) -> tuple[FloatArray, FloatArray]:
        n = x.shape[1]
        yl = np.empty(n)
        yr = np.empty(n)
        if self.type_reduction is TypeReduction.CENTRE_OF_SETS:
            for start in range(0, n, BLOCK):
                stop = min(start + BLOCK, n)
                fl, fu = c.firing_block(x[:, start:stop], self.tnorm)
                yl[start:stop], yr[start:stop] = self.reducer.reduce_rules_first(
                    fl, fu, c.y_lo_s, c.y_hi_s, c.order_ident, c.order_hi_s
                )
            return self._undefined(c, x, k, yl, yr)
        y = self._m.grids[k]
        ident = np.arange(y.size)
        block = max(1, BLOCK // 8)  # (J, N) aggregates: keep a block's working set small
        for start in range(0, n, block):
            stop = min(start + block, n)
            fl, fu = c.firing_block(x[:, start:stop], self.tnorm)
            agg_u = self._m.aggregate(k, fu, lower=False)
            # (the same firing, fl is fu, comes from type-1 antecedents; the output's sets may
            # still have a footprint, so only a type-1 output reuses the upper aggregate)
            agg_l = (agg_u if fl is fu and self._m.type1_output[k]
                     else self._m.aggregate(k, fl, lower=True))
            if self.reducer._left is _exhaustive_left and stop - start <= 64:
                # few samples, many grid rows: the vectorised form (same bits) is faster
                yl[start:stop], yr[start:stop] = exhaustive_many_rows(agg_l, agg_u, y)
                continue
            yl[start:stop], yr[start:stop] = self.reducer.reduce_rules_first(
                agg_l, agg_u, y, y, ident, ident
            )
        return self._undefined(c, x, k, yl, yr)

    def _no_output_message(self, point: str) -> str:
        if self.reducer.exact or self.type_reduction is TypeReduction.CENTROID:
            return (
                f"{type(self).__name__} {self.name!r} has no output at ({point}): rules fire "
                "there, but the aggregated output set is zero on the grid (or, for Wu-Mendel, "
                "its lower MF is); raise the resolution or use an exact reducer"
            )
        return super()._no_output_message(point)


@dataclass(frozen=True, kw_only=True)
class T1Mamdani(_MamdaniBase):
    """Type-1 Mamdani system: aggregated output set on a grid, then a defuzzifier.

    The defaults (min, max, min, max, centroid, 101 points) are MATLAB's ``mamfis``.

    Parameters
    ----------
    inputs : sequence of Input
        Every set type-1.
    outputs : sequence of Output
        Every set type-1.
    rules : sequence of Rule
        Consequents are output set labels.
    tnorm, snorm : TNorm, SNorm
        AND / OR of the antecedents (default min / max).
    implication, aggregation : Implication, Aggregation
        Default min / max.
    defuzzifier : Defuzzifier
        Default ``Defuzzifier.CENTROID``.
    resolution : int
        Output grid points (default 101).
    sampling : Sampling
        ``Sampling.ENDPOINTS`` (default: MATLAB's ``linspace``) or ``MIDPOINTS`` (fuzzylite's
        midpoint rule); see :func:`~it2track.fuzzy.defuzz.output_grid`.
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
    >>> from it2track.fuzzy import Input, Output, Rule, Triangle
    >>> x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    >>> y = Output("y", (0, 10), [("small", Triangle(0, 0, 5)), ("big", Triangle(5, 10, 10))])
    >>> fls = T1Mamdani(inputs=[x], outputs=[y], rules=[Rule(["lo"], "small"),
    ...                                                   Rule(["hi"], "big")])
    >>> round(float(fls(0.0)), 6)  # [0 0 5] sampled every 0.1: 41.65 / 25.5
    1.633333
    """

    defuzzifier: Defuzzifier = Defuzzifier.CENTROID

    def __post_init__(self) -> None:
        if not isinstance(self.defuzzifier, Defuzzifier):
            raise ValueError(f"defuzzifier={self.defuzzifier!r} must be a Defuzzifier")
        super().__post_init__()
        for var in (*self.inputs, *self.outputs):
            for s in var.sets:
                if not s.is_type1:
                    raise ValueError(
                        f"T1Mamdani: {type(var).__name__.lower()} {var.name!r} set {s.name!r} "
                        "has a footprint of uncertainty; use IT2Mamdani"
                    )

    def _interval_of(
        self, c: SystemTables, x: FloatArray, k: int
    ) -> tuple[FloatArray, FloatArray]:
        n = x.shape[1]
        u = np.empty(n)
        y = self._m.grids[k]
        block = max(1, BLOCK // 8)
        for start in range(0, n, block):
            stop = min(start + block, n)
            _, f = c.firing_block(x[:, start:stop], self.tnorm)
            u[start:stop] = defuzzify(self._m.aggregate(k, f, lower=False), y, self.defuzzifier)
        return self._undefined(c, x, k, u, u.copy())


MamdaniSystem = IT2Mamdani | T1Mamdani

#: Every kind of system: Sugeno/TSK and Mamdani, type-1 and interval type-2.
AnySystem = IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani
