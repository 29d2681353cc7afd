"""Zero-order Sugeno fuzzy systems, type-1 and interval type-2, evaluated batch-first.

Definition is apart from evaluation: an :class:`IT2Sugeno` or :class:`T1Sugeno` is an immutable
description (inputs with their sets, rules, t-norm, type reducer) that compiles itself once into
arrays; calling it evaluates any number of input points in one vectorised pass.

Shapes
------
``system(x1, x2, ..., xn)`` takes one array per input; they broadcast together to a batch shape
``S`` and the output has shape ``S`` (a scalar call returns a 0-d array / float-like).
``system.evaluate(X)`` takes the inputs stacked on the last axis, ``X.shape == S + (n,)``.
Firing strengths have the rules on the last axis: ``S + (R,)``.

Inputs are clipped to their universe before evaluation; NaN or inf raises ``ValueError`` naming
the input.
"""

from __future__ import annotations

import enum
import math
import threading
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .membership import MembershipFunction, PiecewiseLinear
from .reducers import EXHAUSTIVE, TypeReducer, ZeroFiringError
from .sets import IT2Set

__all__ = [
    "IT2Sugeno",
    "Input",
    "Rule",
    "T1Sugeno",
    "TNorm",
    "control_surface",
    "rules_from_table",
]

FloatArray = NDArray[np.float64]

#: Samples per internal block: keeps the working set of one block in the CPU cache.
BLOCK = 4096


class TNorm(enum.Enum):
    """Conjunction of the antecedents (eqs. 13-14 use the product)."""

    PRODUCT = "product"
    MINIMUM = "min"

    @classmethod
    def from_name(cls, name: str) -> TNorm:
        key = name.strip().lower()
        for member in cls:
            if key in (member.value, member.name.lower()):
                return member
        raise ValueError(f"unknown t-norm {name!r}; choose 'product' or 'min'")


@dataclass(frozen=True)
class Input:
    """An input variable: a name, a universe ``(lo, hi)`` and its fuzzy sets.

    Sets may be :class:`IT2Set` or, for type-1 systems, ``(name, mf)`` pairs. Each set is
    checked on the universe (``0 <= lower <= upper <= 1``).
    """

    name: str
    universe: tuple[float, float]
    sets: tuple[IT2Set, ...]

    def __init__(
        self,
        name: str,
        universe: Sequence[float],
        sets: Iterable[IT2Set | tuple[str, MembershipFunction]],
    ) -> None:
        lo, hi = (float(v) for v in universe)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(
                f"input {name!r}: universe={tuple(universe)!r} must be finite, lo < hi"
            )
        converted = []
        for s in sets:
            if isinstance(s, IT2Set):
                converted.append(s)
            else:
                label, mf = s
                converted.append(IT2Set.type1(mf, label))
        names = [s.name for s in converted]
        if not converted:
            raise ValueError(f"input {name!r}: needs at least one set")
        if len(set(names)) != len(names) or any(not n for n in names):
            raise ValueError(f"input {name!r}: set names {names!r} must be non-empty and unique")
        for s in converted:
            s.check_on((lo, hi), owner=f"input {name!r}")
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "universe", (lo, hi))
        object.__setattr__(self, "sets", tuple(converted))

    def set_index(self, label: str) -> int:
        for i, s in enumerate(self.sets):
            if s.name == label:
                return i
        raise ValueError(
            f"input {self.name!r} has no set {label!r}; its sets are {[s.name for s in self.sets]}"
        )


@dataclass(frozen=True)
class Rule:
    """``if x1 is A1 and ... then y = [lo, hi]`` (zero-order Sugeno).

    Parameters
    ----------
    antecedent : sequence of str or None
        One set label per input; ``None`` means the input does not appear in the rule.
    consequent : float or (float, float)
        Crisp output, or an interval ``(lo, hi)`` with ``lo <= hi``.
    """

    antecedent: tuple[str | None, ...]
    consequent: tuple[float, float]

    def __init__(
        self, antecedent: Sequence[str | None], consequent: float | Sequence[float]
    ) -> None:
        if isinstance(consequent, int | float | np.floating | np.integer):
            lo = hi = float(consequent)
        else:
            values = [float(v) for v in consequent]
            if len(values) != 2:
                raise ValueError(f"rule {list(antecedent)!r}: consequent {consequent!r} must be a "
                                 "number or an interval (lo, hi)")
            lo, hi = values
        if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
            raise ValueError(
                f"rule {list(antecedent)!r}: consequent ({lo}, {hi}) must be finite, lo <= hi"
            )
        object.__setattr__(self, "antecedent", tuple(antecedent))
        object.__setattr__(self, "consequent", (lo, hi))


def rules_from_table(
    row_sets: Sequence[str], col_sets: Sequence[str], table: Sequence[Sequence[float]]
) -> tuple[Rule, ...]:
    """Two-input rule grid: ``table[i][j]`` is the consequent of ``(row_sets[i], col_sets[j])``.

    Examples
    --------
    >>> [r.antecedent for r in rules_from_table(["N", "P"], ["Z"], [[-1], [1]])]
    [('N', 'Z'), ('P', 'Z')]
    """
    if len(table) != len(row_sets) or any(len(row) != len(col_sets) for row in table):
        raise ValueError(
            f"rule table must be {len(row_sets)} x {len(col_sets)} to match the set labels"
        )
    return tuple(
        Rule((r, c), table[i][j]) for i, r in enumerate(row_sets) for j, c in enumerate(col_sets)
    )


class _Compiled:
    """Arrays derived from a system's definition, built once."""

    def __init__(self, inputs: tuple[Input, ...], rules: tuple[Rule, ...]) -> None:
        self.lo = np.array([inp.universe[0] for inp in inputs])
        self.hi = np.array([inp.universe[1] for inp in inputs])
        mfs: list[MembershipFunction] = []
        mf_input: list[int] = []

        def row_of(mf: MembershipFunction, i: int) -> int:
            for k, (other, j) in enumerate(zip(mfs, mf_input, strict=True)):
                if j == i and (other is mf or other == mf):
                    return k
            mfs.append(mf)
            mf_input.append(i)
            return len(mfs) - 1

        n_in = len(inputs)
        upper_rows = np.empty((len(rules), n_in), dtype=np.intp)
        lower_rows = np.empty((len(rules), n_in), dtype=np.intp)
        for r, rule in enumerate(rules):
            for i, label in enumerate(rule.antecedent):
                if label is None:
                    upper_rows[r, i] = lower_rows[r, i] = -1
                    continue
                s = inputs[i].sets[inputs[i].set_index(label)]
                upper_rows[r, i] = row_of(s.upper, i)
                lower_rows[r, i] = row_of(s.lower, i)
        n_rows = len(mfs)
        # Row n_rows is the constant 1 used for inputs a rule does not mention.
        upper_rows[upper_rows < 0] = n_rows
        lower_rows[lower_rows < 0] = n_rows
        self.n_rows = n_rows
        self.upper_rows = upper_rows
        self.lower_rows = lower_rows
        self.type1 = bool(np.array_equal(upper_rows, lower_rows))
        # Piecewise-linear rows are evaluated together as one trapezoid bank.
        pl = [k for k, mf in enumerate(mfs) if isinstance(mf, PiecewiseLinear)]
        self.pl_rows = np.array(pl, dtype=np.intp)
        self.pl_input = np.array([mf_input[k] for k in pl], dtype=np.intp)
        a, wl, d, wr, h = [], [], [], [], []
        for k in pl:
            mf = mfs[k]
            assert isinstance(mf, PiecewiseLinear)
            pa, pb, pc, pd, ph = mf.as_trapezoid()
            a.append(-math.inf if pa == pb else pa)
            wl.append(1.0 if pa == pb else pb - pa)
            d.append(math.inf if pc == pd else pd)
            wr.append(1.0 if pc == pd else pd - pc)
            h.append(ph)
        self.pl_params = [np.array(v)[:, None] for v in (a, wl, d, wr, h)]
        self.pl_scalar = list(zip(pl, [mf_input[k] for k in pl], a, wl, d, wr, h, strict=True))
        self.other = [(k, mfs[k], mf_input[k]) for k in range(n_rows) if k not in set(pl)]
        self.all_pl = not self.other
        self.identity_pl = self.all_pl and np.array_equal(self.pl_rows, np.arange(n_rows))
        y_lo = np.array([rule.consequent[0] for rule in rules])
        y_hi = np.array([rule.consequent[1] for rule in rules])
        self.y_lo, self.y_hi = y_lo, y_hi
        self.crisp = bool(np.array_equal(y_lo, y_hi))
        # Rules are evaluated sorted by their lower consequent, so the type reducers need no
        # gather; `perm` maps sorted position -> original rule index.
        self.perm = np.argsort(y_lo, kind="stable")
        self.inv_perm = np.argsort(self.perm)
        self.upper_rows_s = np.ascontiguousarray(upper_rows[self.perm])
        self.lower_rows_s = np.ascontiguousarray(lower_rows[self.perm])
        self.y_lo_s = y_lo[self.perm]
        self.y_hi_s = y_hi[self.perm]
        self.order_ident = np.arange(len(rules))
        self.order_hi_s = np.argsort(self.y_hi_s, kind="stable")
        self.upper_rows_s_list = self.upper_rows_s.tolist()
        self.lower_rows_s_list = self.lower_rows_s.tolist()
        self.all_h1 = all(v == 1.0 for v in h)
        self._local = threading.local()

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        del state["_local"]  # per-thread scratch arrays: not picklable, rebuilt on demand
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._local = threading.local()

    def workspace(self, n: int) -> dict[str, FloatArray]:
        """Scratch arrays for blocks of up to ``n`` samples, reused across calls (per thread).

        Reuse matters: fresh multi-megabyte temporaries cost page faults that take longer than
        the arithmetic itself.
        """
        ws: dict[str, FloatArray] | None = getattr(self._local, "ws", None)
        if ws is None or ws["m"].shape[1] < n:
            r = len(self.upper_rows)
            p = max(len(self.pl_rows), 1)
            ws = {
                "m": np.empty((self.n_rows + 1, n)),
                "xr": np.empty((p, n)),
                "right": np.empty((p, n)),
                "fu": np.empty((r, n)),
                "fl": np.empty((r, n)),
                "tmp": np.empty((r, n)),
            }
            ws["m"][self.n_rows] = 1.0
            self._local.ws = ws
        return ws

    def memberships(self, x: FloatArray, out: FloatArray | None = None) -> FloatArray:
        """All membership rows for a block ``x`` of shape ``(n_inputs, N)``: ``(n_rows+1, N)``.

        The last row is the constant 1 used for inputs a rule does not mention.
        """
        n = x.shape[1]
        ws = self.workspace(n)
        if out is None:
            out = np.empty((self.n_rows + 1, n))
            out[self.n_rows] = 1.0
        if self.pl_rows.size:
            a, wl, d, wr, h = self.pl_params
            xr = np.take(x, self.pl_input, axis=0, out=ws["xr"][:, :n])
            left = out[: self.n_rows] if self.identity_pl else np.empty_like(xr)
            right = ws["right"][:, :n]
            np.subtract(xr, a, out=left)
            np.divide(left, wl, out=left)
            np.subtract(d, xr, out=right)
            np.divide(right, wr, out=right)
            np.minimum(left, right, out=left)
            np.minimum(left, 1.0, out=left)
            np.maximum(left, 0.0, out=left)
            if not self.all_h1:
                np.multiply(left, h, out=left)
            if not self.identity_pl:
                out[self.pl_rows] = left
        for k, mf, i in self.other:
            out[k] = mf(x[i])
        return out

    def memberships_scalar(self, x: Sequence[float]) -> list[float]:
        out = [1.0] * (self.n_rows + 1)
        for k, i, a, wl, d, wr, h in self.pl_scalar:
            v = min((x[i] - a) / wl, (d - x[i]) / wr)
            out[k] = h * (0.0 if v < 0.0 else 1.0 if v > 1.0 else v)
        for k, mf, i in self.other:
            out[k] = float(mf(np.float64(x[i])))
        return out


@dataclass(frozen=True, kw_only=True)
class _SugenoBase:
    inputs: tuple[Input, ...]
    rules: tuple[Rule, ...]
    tnorm: TNorm = TNorm.PRODUCT
    on_zero_firing: float | None = None
    name: str = ""
    _c: _Compiled = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "inputs", tuple(self.inputs))
        object.__setattr__(self, "rules", tuple(self.rules))
        if not self.inputs:
            raise ValueError("a fuzzy system needs at least one input")
        if not self.rules:
            raise ValueError("a fuzzy system needs at least one rule")
        if not isinstance(self.tnorm, TNorm):
            raise ValueError(f"tnorm={self.tnorm!r} must be a TNorm member")
        names = [inp.name for inp in self.inputs]
        if len(set(names)) != len(names):
            raise ValueError(f"input names {names!r} must be unique")
        for k, rule in enumerate(self.rules):
            if len(rule.antecedent) != len(self.inputs):
                raise ValueError(
                    f"rule {k} {rule.antecedent!r} has {len(rule.antecedent)} antecedents for "
                    f"{len(self.inputs)} inputs"
                )
            if all(label is None for label in rule.antecedent):
                raise ValueError(f"rule {k} mentions no input")
        if self.on_zero_firing is not None and not math.isfinite(self.on_zero_firing):
            raise ValueError(f"on_zero_firing={self.on_zero_firing!r} must be finite or None")
        object.__setattr__(self, "_c", _Compiled(self.inputs, self.rules))

    # -- shapes and checks --------------------------------------------------------------------
    @property
    def n_inputs(self) -> int:
        return len(self.inputs)

    @property
    def n_rules(self) -> int:
        return len(self.rules)

    def _prepare(self, xs: tuple[ArrayLike, ...]) -> tuple[FloatArray, tuple[int, ...]]:
        if len(xs) != self.n_inputs:
            raise ValueError(
                f"{type(self).__name__} {self.name!r} takes {self.n_inputs} inputs "
                f"({', '.join(i.name for i in self.inputs)}), got {len(xs)}"
            )
        arrays = [np.asarray(x, dtype=np.float64) for x in xs]
        for inp, arr in zip(self.inputs, arrays, strict=True):
            # One cheap reduction first; the exact elementwise check only if it is not finite
            # (it can overflow to inf on finite but huge values, which must not warn).
            with np.errstate(over="ignore", invalid="ignore"):
                total = float(np.add.reduce(arr, axis=None))
            if not math.isfinite(total) and not bool(np.isfinite(arr).all()):
                raise ValueError(f"input {inp.name!r} contains NaN or inf")
        try:
            shape = np.broadcast_shapes(*(a.shape for a in arrays))
        except ValueError:
            shapes = ", ".join(
                f"{i.name}: {a.shape}" for i, a in zip(self.inputs, arrays, strict=True)
            )
            raise ValueError(f"input shapes do not broadcast together ({shapes})") from None
        n = math.prod(shape)
        x = np.empty((self.n_inputs, n))
        c = self._c
        for i, arr in enumerate(arrays):
            row = x[i].reshape(shape)
            np.maximum(arr, c.lo[i], out=row)
            np.minimum(row, c.hi[i], out=row)
        return x, shape

    def _stacked(self, x: ArrayLike) -> tuple[FloatArray, ...]:
        arr = np.asarray(x, dtype=np.float64)
        if arr.ndim == 0 or arr.shape[-1] != self.n_inputs:
            raise ValueError(
                f"stacked inputs must have shape (..., {self.n_inputs}), got {arr.shape}"
            )
        return tuple(arr[..., i] for i in range(self.n_inputs))

    def _scalar_inputs(self, xs: tuple[ArrayLike, ...]) -> list[float] | None:
        """Plain floats (clipped) if every input is a finite scalar, else None."""
        if len(xs) != self.n_inputs:
            return None
        out = []
        for i, x in enumerate(xs):
            if type(x) is float or type(x) is int or isinstance(x, np.floating):
                v = float(x)
                if not math.isfinite(v):
                    return None
                lo, hi = self.inputs[i].universe
                out.append(lo if v < lo else hi if v > hi else v)
            else:
                return None
        return out

    # -- firing -------------------------------------------------------------------------------
    def _firing_block(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Firing of a block ``x`` (n_inputs, N) -> ``(fl, fu)`` (R, N), rules in sorted order.

        The returned arrays are workspace views, valid until the next block.
        """
        c = self._c
        n = x.shape[1]
        ws = c.workspace(n)
        m = c.memberships(x, out=ws["m"][:, :n])
        tmp = ws["tmp"][:, :n]
        result = []
        for rows, name in ((c.upper_rows_s, "fu"), (c.lower_rows_s, "fl")):
            f = np.take(m, rows[:, 0], axis=0, out=ws[name][:, :n])
            for i in range(1, self.n_inputs):
                np.take(m, rows[:, i], axis=0, out=tmp)
                if self.tnorm is TNorm.PRODUCT:
                    np.multiply(f, tmp, out=f)
                else:
                    np.minimum(f, tmp, out=f)
            result.append(f)
            if c.type1:
                return f, f
        fu, fl = result
        return fl, fu

    def _firing_scalar(self, x: list[float]) -> tuple[list[float], list[float]]:
        c = self._c
        m = c.memberships_scalar(x)
        prod = self.tnorm is TNorm.PRODUCT
        fu, fl = [], []
        ur, lr = c.upper_rows_s_list, c.lower_rows_s_list
        for r in range(self.n_rules):
            u = m[ur[r][0]]
            lw = m[lr[r][0]]
            for i in range(1, self.n_inputs):
                if prod:
                    u *= m[ur[r][i]]
                    lw *= m[lr[r][i]]
                else:
                    u = min(u, m[ur[r][i]])
                    lw = min(lw, m[lr[r][i]])
            fu.append(u)
            fl.append(lw)
        return fl, fu

    def firing(self, *xs: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Rule firing intervals.

        Returns
        -------
        lower, upper : ndarray, shape ``S + (R,)``
            Lower and upper firing strength of every rule (equal for a type-1 system).
        """
        x, shape = self._prepare(xs)
        n = x.shape[1]
        lower = np.empty((n, self.n_rules))
        upper = np.empty((n, self.n_rules))
        inv = self._c.inv_perm
        for start in range(0, n, BLOCK):
            stop = min(start + BLOCK, n)
            fl, fu = self._firing_block(x[:, start:stop])
            lower[start:stop] = fl[inv].T
            upper[start:stop] = fu[inv].T
        return lower.reshape((*shape, self.n_rules)), upper.reshape((*shape, self.n_rules))

    def _zero_firing(self, x: FloatArray, bad: NDArray[np.bool_]) -> None:
        j = int(np.argmax(bad))
        point = ", ".join(f"{inp.name}={x[i, j]:.6g}" for i, inp in enumerate(self.inputs))
        raise ZeroFiringError(
            f"no rule of {type(self).__name__} {self.name!r} fires at ({point}); pass "
            "on_zero_firing=<value> to define the output there"
        )

    def _interval_blocks(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        raise NotImplementedError

    def interval(self, *xs: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Type-reduced interval ``(yl, yr)``, each of the broadcast input shape."""
        x, shape = self._prepare(xs)
        yl, yr = self._interval_blocks(x)
        return yl.reshape(shape), yr.reshape(shape)

    def __call__(self, *xs: ArrayLike) -> Any:
        """Crisp output ``u = (yl + yr) / 2`` (eq. 18), shape of the broadcast inputs.

        A call with Python/NumPy float scalars returns a Python float through a fast path
        (bit-for-bit equal to the array path) meant for real-time loops.
        """
        scalars = self._scalar_inputs(xs)
        if scalars is not None:
            fast = self._scalar_output(scalars)
            if fast is not None:
                return fast
        x, shape = self._prepare(xs)
        yl, yr = self._interval_blocks(x)
        np.add(yl, yr, out=yl)
        yl *= 0.5
        return yl.reshape(shape)

    def evaluate(self, x: ArrayLike) -> FloatArray:
        """Crisp output for inputs stacked on the last axis, shape ``(..., n_inputs)``."""
        result: FloatArray = np.asarray(self(*self._stacked(x)))
        return result

    def _scalar_output(self, x: list[float]) -> float | None:
        return None


@dataclass(frozen=True, kw_only=True)
class IT2Sugeno(_SugenoBase):
    """Interval type-2 zero-order Sugeno system.

    Parameters
    ----------
    inputs : sequence of Input
    rules : sequence of Rule
    tnorm : TNorm
        ``TNorm.PRODUCT`` (eqs. 13-14, default) or ``TNorm.MINIMUM``.
    reducer : TypeReducer
        Type reducer; default :data:`~it2track.fuzzy.reducers.EXHAUSTIVE` (exact).
    on_zero_firing : float or None
        Output where no rule fires. ``None`` (default) raises
        :class:`~it2track.fuzzy.reducers.ZeroFiringError` instead. (Wu-Mendel where rules fire
        but their total lower firing is zero always raises ``ZeroFiringError``.)
    name : str

    Examples
    --------
    >>> from it2track.fuzzy import IT2Set, Triangle
    >>> sets = [IT2Set.from_fou(Triangle(-1, -1, 1), 0.2, "N"),
    ...         IT2Set.from_fou(Triangle(-1, 1, 1), 0.2, "P")]
    >>> fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)],
    ...                 rules=[Rule(["N"], -1.0), Rule(["P"], 1.0)])
    >>> fls([-1.0, 0.0, 0.5]).round(6).tolist()
    [-1.0, 0.0, 0.5]
    """

    reducer: TypeReducer = EXHAUSTIVE

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.reducer, TypeReducer):
            raise ValueError(f"reducer={self.reducer!r} must be a TypeReducer")

    def _interval_blocks(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        c = self._c
        n = x.shape[1]
        yl = np.empty(n)
        yr = np.empty(n)
        for start in range(0, n, BLOCK):
            stop = min(start + BLOCK, n)
            fl, fu = self._firing_block(x[:, start:stop])
            yl[start:stop], yr[start:stop] = self.reducer.reduce_rules_first(
                fl, fu, c.y_lo_s, c.y_hi_s, c.order_ident, c.order_hi_s
            )
        if math.isnan(float(np.add.reduce(yl)) + float(np.add.reduce(yr))):
            bad = np.isnan(yl) | np.isnan(yr)
            where = np.flatnonzero(bad)
            for start in range(0, where.size, BLOCK):
                j = where[start : start + BLOCK]
                _, fu = self._firing_block(np.ascontiguousarray(x[:, j]))
                fires = fu.sum(axis=0) > 0
                if fires.any():  # undefined although rules fire: Wu-Mendel, zero lower firing
                    i = int(j[np.argmax(fires)])
                    point = ", ".join(
                        f"{inp.name}={x[n, i]:.6g}" for n, inp in enumerate(self.inputs)
                    )
                    raise ZeroFiringError(
                        f"type reducer {self.reducer.name!r} of {type(self).__name__} "
                        f"{self.name!r} has no output at ({point}): rules fire there, but their "
                        "total lower firing strength is zero; use an exact reducer"
                    )
            if self.on_zero_firing is None:
                self._zero_firing(x, bad)
            yl[bad] = yr[bad] = self.on_zero_firing
        return yl, yr

    def _scalar_output(self, x: list[float]) -> float | None:
        if self.reducer is not EXHAUSTIVE:
            return None
        c = self._c
        fl, fu = self._firing_scalar(x)
        yl = _exhaustive_scalar(fl, fu, c.y_lo_s.tolist(), left=True)
        yr = _exhaustive_scalar([fl[k] for k in c.order_hi_s], [fu[k] for k in c.order_hi_s],
                                c.y_hi_s[c.order_hi_s].tolist(), left=False)
        if yl is None or yr is None:
            if self.on_zero_firing is None:
                return None  # the array path raises the descriptive error
            return float(self.on_zero_firing)
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
class T1Sugeno(_SugenoBase):
    """Type-1 zero-order Sugeno system: ``u = sum(f y) / sum(f)`` with crisp consequents.

    Every set must be type-1 (an :class:`IT2Set` whose lower MF is its upper MF, or a
    ``(name, mf)`` pair given to :class:`Input`).

    Parameters
    ----------
    inputs : sequence of Input
    rules : sequence of Rule
        Crisp consequents only.
    tnorm : TNorm
        ``TNorm.PRODUCT`` (default) or ``TNorm.MINIMUM``.
    on_zero_firing : float or None
        Output where no rule fires; ``None`` (default) raises
        :class:`~it2track.fuzzy.reducers.ZeroFiringError` instead.
    name : str
    """

    def __post_init__(self) -> None:
        super().__post_init__()
        for inp in self.inputs:
            for s in inp.sets:
                if not s.is_type1:
                    raise ValueError(
                        f"T1Sugeno: input {inp.name!r} set {s.name!r} has a footprint of "
                        "uncertainty; use IT2Sugeno"
                    )
        if not self._c.crisp:
            raise ValueError("T1Sugeno: rule consequents must be crisp (lo == hi)")

    def _interval_blocks(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        y = self._c.y_lo_s
        n = x.shape[1]
        u = np.empty(n)
        with np.errstate(divide="ignore", invalid="ignore"):
            for start in range(0, n, BLOCK):
                stop = min(start + BLOCK, n)
                _, f = self._firing_block(x[:, start:stop])
                num = f[0] * y[0]
                den = f[0].copy()
                for r in range(1, f.shape[0]):
                    num += f[r] * y[r]
                    den += f[r]
                u[start:stop] = num / den
        if math.isnan(float(np.add.reduce(u))):
            bad = np.isnan(u)
            if self.on_zero_firing is None:
                self._zero_firing(x, bad)
            u[bad] = self.on_zero_firing
        return u, u.copy()

    def _scalar_output(self, x: list[float]) -> float | None:
        _, f = self._firing_scalar(x)
        y = self._c.y_lo_s
        num = f[0] * float(y[0])
        den = f[0]
        for r in range(1, len(f)):
            num += f[r] * float(y[r])
            den += f[r]
        if den == 0.0:
            return None if self.on_zero_firing is None else float(self.on_zero_firing)
        return num / den


FuzzySystem = IT2Sugeno | T1Sugeno


def control_surface(
    system: _SugenoBase,
    *,
    points: int = 101,
    ranges: Mapping[str, tuple[float, float]] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Output of a two-input system on a grid.

    Parameters
    ----------
    system : IT2Sugeno or T1Sugeno
        A system with exactly two inputs.
    points : int
        Grid points per axis.
    ranges : mapping, optional
        Input name -> (lo, hi); defaults to each input's universe.

    Returns
    -------
    x1, x2, u : ndarray, shape (points, points)
        Meshgrid (``indexing="ij"``: ``x1`` varies along axis 0) and the output on it.
    """
    if system.n_inputs != 2:
        raise ValueError(f"control_surface needs a two-input system, got {system.n_inputs}")
    if points < 2:
        raise ValueError(f"points={points!r} must be >= 2")
    ranges = dict(ranges or {})
    axes = []
    for inp in system.inputs:
        lo, hi = ranges.pop(inp.name, inp.universe)
        axes.append(np.linspace(lo, hi, points))
    if ranges:
        raise ValueError(f"ranges names unknown inputs {sorted(ranges)}")
    x1, x2 = np.meshgrid(axes[0], axes[1], indexing="ij")
    return x1, x2, np.asarray(system(x1, x2))
