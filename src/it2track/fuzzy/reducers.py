"""Type reducers for interval type-2 Sugeno systems with interval (or crisp) consequents.

A type reducer maps the rule firing intervals ``[f_lower, f_upper]`` and the consequent
intervals ``[y_lower, y_upper]`` of ``R`` rules to the centroid interval ``[yl, yr]`` of the
centre-of-sets type reduction (paper eqs. 15-17)::

    yl = min over f in [f_lower, f_upper] of  sum(y_lower f) / sum(f)
    yr = max over f in [f_lower, f_upper] of  sum(y_upper f) / sum(f)

All reducers share one signature, so they are interchangeable strategies::

    yl, yr = reducer(f_lower, f_upper, y_lower, y_upper)

with ``f_lower, f_upper`` of shape ``(..., R)`` (rules on the last axis), ``y_lower, y_upper`` of
shape ``(R,)``, and ``yl, yr`` of shape ``(...)``.

Exact reducers (agree with each other to ~1e-12):

- :data:`KM` -- Karnik-Mendel iterations (Karnik & Mendel 2001), as in the paper's toolbox.
- :data:`EKM` -- enhanced KM (Wu & Mendel 2009): better initial switch points.
- :data:`EIASC` -- enhanced iterative algorithm with stop condition (Wu & Nie 2011).
- :data:`EXHAUSTIVE` -- non-iterative: evaluates every switch point with running sums and takes
  the min / max. It vectorises best and is the default.

Closed-form approximations (not exact, named as such):

- :data:`NIE_TAN` -- Nie & Tan (2008): ``y = sum(ym (fl + fu)) / sum(fl + fu)``; returns
  ``(y, y)`` with ``ym = (y_lower + y_upper) / 2``.
- :data:`WU_MENDEL` -- the Wu-Mendel (2002) uncertainty bounds; returns the midpoints of the
  inner and outer bounds of ``yl`` and of ``yr``. Needs a positive total lower firing.

Zero firing: where every rule's upper firing is zero the centroid is undefined. The public call
raises :class:`ZeroFiringError`; a fuzzy system may instead substitute a value its user chose
(``on_zero_firing``). Iterative reducers stop after ``max_iter`` iterations and raise
:class:`ConvergenceError` if they have not converged. The exact algorithms converge in at most
``R`` iterations, so the default cap, ``max(100, 2 R)``, only guards against a defect.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "EIASC",
    "EKM",
    "EXHAUSTIVE",
    "KM",
    "NIE_TAN",
    "WU_MENDEL",
    "ConvergenceError",
    "Reducer",
    "TypeReducer",
    "ZeroFiringError",
]

FloatArray = NDArray[np.float64]
# A kernel works on rules-first arrays, rows sorted by y ascending:
#   kernel(f_lower (R, N), f_upper (R, N), y (R,), max_iter) -> (N,)
Kernel = Callable[[FloatArray, FloatArray, FloatArray, int], FloatArray]


class ZeroFiringError(ValueError):
    """No rule fires (total upper firing strength is zero), so the output is undefined."""


class ConvergenceError(RuntimeError):
    """An iterative type reducer did not converge within ``max_iter`` iterations."""


# --------------------------------------------------------------------------------------------
# Exact kernels. Rows are sorted by their consequent ascending; N is the flattened batch.
# ``y`` is (R,) -- the same consequents for every sample -- or (R, N), sorted per column (the
# consequents of first-order rules, which depend on the input). The (R,) branches are the
# original code, so their results are unchanged.
# --------------------------------------------------------------------------------------------


def _count(y: FloatArray, c: FloatArray, side: str) -> NDArray[np.intp]:
    """``searchsorted(y, c, side)`` per column (``y`` sorted ascending along axis 0)."""
    if y.ndim == 1:
        return np.searchsorted(y, c, side=side)  # type: ignore[call-overload]
    below = (y <= c) if side == "right" else (y < c)
    return below.sum(axis=0).astype(np.intp)


def _exhaustive_both(
    fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int
) -> tuple[FloatArray, FloatArray]:
    """``(yl, yr)`` by enumerating every switch point (rows sorted by ``y`` ascending).

    Candidate ``L`` for ``yl`` (``L = 0..R``): rules below ``L`` at upper firing, the rest at
    lower; ``yr`` mirrors it. Both start from the all-lower configuration and add ``fu - fl``
    one rule at a time (``yl`` bottom up, ``yr`` top down), so the denominators are sums of
    non-negative terms and never suffer cancellation. Zero total firing gives NaN.
    """
    del max_iter
    r = fl.shape[0]
    d = fu - fl
    yd = d * y[:, None] if y.ndim == 1 else d * y
    num0 = fl[0] * y[0]
    den0 = fl[0].copy()
    tmp = np.empty_like(den0)
    # (the temporaries here are (R, N) for one block of N samples: small enough to be reused
    # from the heap instead of faulting in fresh pages)
    for n in range(1, r):
        np.multiply(fl[n], y[n], out=tmp)
        num0 += tmp
        den0 += fl[n]
    with np.errstate(divide="ignore", invalid="ignore"):
        first = num0 / den0
        yl = first
        yr = first.copy()
        num, den = num0.copy(), den0.copy()
        for n in range(r):
            num += yd[n]
            den += d[n]
            np.divide(num, den, out=tmp)
            np.fmin(yl, tmp, out=yl)
        num, den = num0, den0
        for n in range(r - 1, -1, -1):
            num += yd[n]
            den += d[n]
            np.divide(num, den, out=tmp)
            np.fmax(yr, tmp, out=yr)
    return yl, yr


def exhaustive_many_rows(
    fl: FloatArray, fu: FloatArray, y: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """:func:`_exhaustive_both` for many rows and few samples (a Mamdani output grid).

    The same recurrences -- the same sums in the same order, each running sum a strict
    left-to-right ``np.add.accumulate`` -- hence the same candidates, without a Python loop
    over the rows. ``fl, fu`` are ``(R, N)``, ``y`` is ``(R,)`` ascending.
    """
    d = fu - fl
    yd = d * y[:, None]
    num0 = np.add.accumulate(fl * y[:, None], axis=0)[-1]
    den0 = np.add.accumulate(fl, axis=0)[-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        num = np.add.accumulate(np.concatenate((num0[None], yd)), axis=0)
        den = np.add.accumulate(np.concatenate((den0[None], d)), axis=0)
        yl = np.fmin.reduce(num / den, axis=0)
        num = np.add.accumulate(np.concatenate((num0[None], yd[::-1])), axis=0)
        den = np.add.accumulate(np.concatenate((den0[None], d[::-1])), axis=0)
        yr = np.fmax.reduce(num / den, axis=0)
    return yl, yr


def _exhaustive_left(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    return _exhaustive_both(fl, fu, y, max_iter)[0]


def _exhaustive_right(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    return _exhaustive_both(fl, fu, y, max_iter)[1]


def _sum_rows(a: FloatArray) -> FloatArray:
    """``a[0] + a[1] + ...`` (rows added in order), shape ``(N,)``.

    ``a.sum(axis=0)`` and ``einsum`` reduce in an order that depends on the batch (a single
    column is summed pairwise), so a sample's bits would depend on its batch; here every
    column is summed in the same order, as compiled kernels do.
    """
    out = a[0].copy()
    for r in range(1, a.shape[0]):
        out += a[r]
    return out


def _dot_rows(a: FloatArray, y: FloatArray) -> FloatArray:
    """``a[0] y[0] + a[1] y[1] + ...`` (rows added in order), shape ``(N,)``."""
    out = a[0] * y[0]
    tmp = np.empty_like(out)
    for r in range(1, a.shape[0]):
        np.multiply(a[r], y[r], out=tmp)
        out += tmp
    return out


def _centroid(theta: FloatArray, y: FloatArray) -> FloatArray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return _dot_rows(theta, y) / _sum_rows(theta)


def _switch_iterations(
    fl: FloatArray,
    fu: FloatArray,
    y: FloatArray,
    max_iter: int,
    *,
    left: bool,
    initial_k: FloatArray | None,
    name: str,
) -> FloatArray:
    """KM-style iterations on a whole batch: ``k`` = number of rules (from the bottom) at upper
    firing for ``yl`` (at lower firing for ``yr``); iterate until ``k`` stops changing.

    Consequents within rounding of the centroid ("ties") cannot be placed from the rounded
    centroid alone: when the other firing strengths are tiny, the wrong side can stall KM at a
    far-off false fixed point or make it oscillate. For such columns both placements are
    evaluated and the better one is kept. A switch point whose firing sums to zero (possible
    when lower firings are zero) moves to all-upper firing; a column with no upper firing at all
    gives NaN.
    """
    r = fl.shape[0]
    rows = np.arange(r)[:, None]
    tol = (8.0 + 2.0 * r) * np.finfo(np.float64).eps * max(1.0, float(np.abs(y).max()))
    all_upper = r if left else 0
    # With k = searchsorted(y, c, side="right"), below[k] <= c < above[k] are the consequents
    # around a centroid c.
    per_sample = y.ndim == 2
    if per_sample:
        cols = np.arange(fl.shape[1])
        below = np.concatenate((np.full((1, y.shape[1]), -np.inf), y))
        above = np.concatenate((y, np.full((1, y.shape[1]), np.inf)))
    else:
        below = np.concatenate(([-np.inf], y))
        above = np.concatenate((y, [np.inf]))

    def ycols(j: NDArray[np.intp]) -> FloatArray:
        return y[:, j] if per_sample else y

    def theta(k: NDArray[np.intp], lo: FloatArray, up: FloatArray) -> FloatArray:
        bottom = rows < k  # (R, N): rules below the switch point
        return np.where(bottom, up, lo) if left else np.where(bottom, lo, up)

    if initial_k is None:  # KM: start from the centroid of the interval midpoints
        c = _centroid(0.5 * (fl + fu), y)
        k = _count(y, c, "right")
        if not left:
            k[np.isnan(c)] = all_upper
    else:
        k = np.broadcast_to(initial_k, fl.shape[1:]).astype(np.intp)
    # The consequent value and the switch point of the last tie resolved in each column: the
    # same tie met again at that switch point needs no second resolution.
    tie_y = np.full(fl.shape[1:], np.nan)
    tie_k = np.full(fl.shape[1:], -1, dtype=np.intp)
    for _ in range(max_iter):
        c_new = _centroid(theta(k, fl, fu), y)
        k_new = _count(y, c_new, "right")
        nan = np.isnan(c_new)
        undefined = None
        if nan.any():
            undefined = nan & (k == all_upper)  # not even the upper firing has a positive sum
            k_new[nan] = all_upper
        if per_sample:
            gap = np.minimum(c_new - below[k_new, cols], above[k_new, cols] - c_new)
        else:
            gap = np.minimum(c_new - below[k_new], above[k_new] - c_new)
        j = np.flatnonzero(gap <= tol)
        if j.size:
            settled = (k[j] == tie_k[j]) & (np.abs(c_new[j] - tie_y[j]) <= tol)
            k_new[j[settled]] = k[j[settled]]
            j = j[~settled]
        if j.size:
            yj = ycols(j)
            ka = _count(yj, c_new[j] - tol, "left")
            kb = _count(yj, c_new[j] + tol, "right")
            sub_l, sub_u = fl[:, j], fu[:, j]
            ca = _centroid(theta(ka, sub_l, sub_u), yj)
            cb = _centroid(theta(kb, sub_l, sub_u), yj)
            a_better = ((ca < cb) if left else (ca > cb)) | np.isnan(cb)
            take_a = a_better | ((ca == cb) & (k[j] == ka))
            k_new[j] = tie_k[j] = np.where(take_a, ka, kb)
            tie_y[j] = y[kb - 1, j] if per_sample else y[kb - 1]
        done = k_new == k
        if undefined is not None:
            done |= undefined
        if done.all():
            return c_new
        k = k_new
    raise ConvergenceError(f"{name} did not converge in max_iter={max_iter} iterations")


def _km_left(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    return _switch_iterations(fl, fu, y, max_iter, left=True, initial_k=None, name="KM")


def _km_right(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    return _switch_iterations(fl, fu, y, max_iter, left=False, initial_k=None, name="KM")


def _ekm_left(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    # Wu & Mendel (2009): initial switch point k = round(R / 2.4) for yl.
    k0 = np.asarray(round(fl.shape[0] / 2.4))
    return _switch_iterations(fl, fu, y, max_iter, left=True, initial_k=k0, name="EKM")


def _ekm_right(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    # Wu & Mendel (2009): initial switch point k = round(R / 1.7) for yr.
    k0 = np.asarray(round(fl.shape[0] / 1.7))
    return _switch_iterations(fl, fu, y, max_iter, left=False, initial_k=k0, name="EKM")


def _eiasc_left(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    # Wu & Nie (2011): start from all-lower firing, raise rules to upper firing from the bottom
    # while the centroid still lies above the next consequent.
    r = fl.shape[0]
    a = _dot_rows(fl, y)
    b = _sum_rows(fl)
    c = np.full(fl.shape[1:], np.nan)
    done = np.zeros(fl.shape[1:], dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for it, n in enumerate(range(r)):
            if it >= max_iter:
                raise ConvergenceError(f"EIASC did not converge in max_iter={max_iter} iterations")
            step = np.where(done, 0.0, fu[n] - fl[n])
            a += y[n] * step
            b += step
            c = np.where(done, c, a / b)
            stop = c <= y[n + 1] if n + 1 < r else np.ones_like(done)
            done |= stop
            if done.all():
                break
    return c


def _eiasc_right(fl: FloatArray, fu: FloatArray, y: FloatArray, max_iter: int) -> FloatArray:
    r = fl.shape[0]
    a = _dot_rows(fl, y)
    b = _sum_rows(fl)
    c = np.full(fl.shape[1:], np.nan)
    done = np.zeros(fl.shape[1:], dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for it, n in enumerate(range(r - 1, -1, -1)):
            if it >= max_iter:
                raise ConvergenceError(f"EIASC did not converge in max_iter={max_iter} iterations")
            step = np.where(done, 0.0, fu[n] - fl[n])
            a += y[n] * step
            b += step
            c = np.where(done, c, a / b)
            stop = c >= y[n - 1] if n > 0 else np.ones_like(done)
            done |= stop
            if done.all():
                break
    return c


# --------------------------------------------------------------------------------------------
# Approximations (computed on the unsorted rules; they need no ordering).
# --------------------------------------------------------------------------------------------


def _nie_tan(
    fl: FloatArray, fu: FloatArray, y_lo: FloatArray, y_hi: FloatArray
) -> tuple[FloatArray, FloatArray]:
    w = fl + fu
    y = _centroid(w, 0.5 * (y_lo + y_hi))
    return y, y.copy()


def _wu_mendel(
    fl: FloatArray, fu: FloatArray, y_lo: FloatArray, y_hi: FloatArray
) -> tuple[FloatArray, FloatArray]:
    # Wu & Mendel (2002) uncertainty bounds, Mendel (2017) "Uncertain rule-based fuzzy
    # systems", 2nd ed., sec. 9.5. Requires sum(fl) > 0.
    sl, su = _sum_rows(fl), _sum_rows(fu)
    with np.errstate(divide="ignore", invalid="ignore"):
        yl0 = _dot_rows(fl, y_lo) / sl
        ylm = _dot_rows(fu, y_lo) / su
        yr0 = _dot_rows(fl, y_hi) / sl
        yrm = _dot_rows(fu, y_hi) / su
        yl_outer_hi = np.minimum(yl0, ylm)  # upper bound of yl
        yr_outer_lo = np.maximum(yr0, yrm)  # lower bound of yr
        spread = (su - sl) / (su * sl)
        y1l, yml = y_lo.min(axis=0), y_lo.max(axis=0)
        y1r, ymr = y_hi.min(axis=0), y_hi.max(axis=0)
        pl = _dot_rows(fl, y_lo - y1l)
        ql = _dot_rows(fu, yml - y_lo)
        yl_lo = yl_outer_hi - spread * np.where(pl + ql > 0, pl * ql / (pl + ql), 0.0)
        pr = _dot_rows(fu, y_hi - y1r)
        qr = _dot_rows(fl, ymr - y_hi)
        yr_hi = yr_outer_lo + spread * np.where(pr + qr > 0, pr * qr / (pr + qr), 0.0)
    return 0.5 * (yl_lo + yl_outer_hi), 0.5 * (yr_outer_lo + yr_hi)


# --------------------------------------------------------------------------------------------
# The strategy objects.
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class TypeReducer:
    """A type-reduction strategy: ``yl, yr = reducer(f_lower, f_upper, y_lower, y_upper)``.

    Attributes
    ----------
    name : str
        Short name (``"km"``, ``"ekm"``, ``"eiasc"``, ``"exhaustive"``, ``"nie-tan"``,
        ``"wu-mendel"``).
    exact : bool
        True for reducers that compute the exact centroid interval.
    max_iter : int or None
        Iteration cap for the iterative reducers (ignored by the others); ``None`` (default)
        means ``max(100, 2 R)`` for ``R`` rules.
    """

    name: str
    exact: bool
    _left: Kernel | None = None
    _right: Kernel | None = None
    _approx: (
        Callable[
            [FloatArray, FloatArray, FloatArray, FloatArray],
            tuple[FloatArray, FloatArray],
        ]
        | None
    ) = None
    max_iter: int | None = None

    def __post_init__(self) -> None:
        if self.max_iter is not None and (
            not isinstance(self.max_iter, int) or isinstance(self.max_iter, bool)
            or self.max_iter < 1
        ):
            raise ValueError(f"{self.name}: max_iter={self.max_iter!r} must be a positive int")

    def _cap(self, r: int) -> int:
        return max(100, 2 * r) if self.max_iter is None else self.max_iter

    def with_max_iter(self, max_iter: int | None) -> TypeReducer:
        """A copy of this reducer with another iteration cap."""
        return TypeReducer(
            name=self.name,
            exact=self.exact,
            _left=self._left,
            _right=self._right,
            _approx=self._approx,
            max_iter=max_iter,
        )

    def __repr__(self) -> str:
        return f"TypeReducer({self.name!r})"

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, TypeReducer)
            and other.name == self.name
            and other.max_iter == self.max_iter
        )

    def __hash__(self) -> int:
        return hash((self.name, self.max_iter))

    # -- rules-first entry used by the fuzzy systems ------------------------------------------
    def reduce_rules_first(
        self,
        fl: FloatArray,
        fu: FloatArray,
        y_lo: FloatArray,
        y_hi: FloatArray,
        order_lo: NDArray[np.intp],
        order_hi: NDArray[np.intp],
    ) -> tuple[FloatArray, FloatArray]:
        """Reduce rules-first firing arrays ``(R, N)``; NaN marks zero total firing.

        ``order_lo`` / ``order_hi`` sort the rules by ``y_lo`` / ``y_hi`` ascending. When the
        rows are already sorted (identity orders) no gather happens.
        """
        if self._approx is not None:
            return self._approx(fl, fu, y_lo, y_hi)
        assert self._left is not None and self._right is not None
        if self._left is _exhaustive_left and np.array_equal(order_lo, order_hi):
            if np.array_equal(y_lo, y_hi):
                return _exhaustive_both(*_sorted_rows(fl, fu, y_lo, order_lo), 0)
        cap = self._cap(fl.shape[0])
        yl = self._left(*_sorted_rows(fl, fu, y_lo, order_lo), cap)
        yr = self._right(*_sorted_rows(fl, fu, y_hi, order_hi), cap)
        return yl, yr

    def reduce_per_sample(
        self, fl: FloatArray, fu: FloatArray, y_lo: FloatArray, y_hi: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Like :meth:`reduce_rules_first` for consequents that differ per sample.

        ``fl, fu, y_lo, y_hi`` are all ``(R, N)`` in any rule order (first-order rules: the
        consequents depend on the input). Each column is sorted by its own ``y_lo`` (for
        ``yl``) and ``y_hi`` (for ``yr``) and the same kernels run on the sorted columns.
        """
        if self._approx is not None:
            return self._approx(fl, fu, y_lo, y_hi)
        assert self._left is not None and self._right is not None
        cap = self._cap(fl.shape[0])
        out = []
        for y, kernel in ((y_lo, self._left), (y_hi, self._right)):
            order = np.argsort(y, axis=0, kind="stable")
            out.append(kernel(np.take_along_axis(fl, order, 0), np.take_along_axis(fu, order, 0),
                              np.take_along_axis(y, order, 0), cap))
        return out[0], out[1]

    def __call__(
        self,
        f_lower: ArrayLike,
        f_upper: ArrayLike,
        y_lower: ArrayLike,
        y_upper: ArrayLike | None = None,
    ) -> tuple[FloatArray, FloatArray]:
        """Type-reduce firing intervals.

        Parameters
        ----------
        f_lower, f_upper : array_like, shape (..., R)
            Lower and upper firing strengths, ``0 <= f_lower <= f_upper``.
        y_lower, y_upper : array_like, shape (R,)
            Consequent interval ends; ``y_upper`` defaults to ``y_lower`` (crisp consequents).

        Returns
        -------
        yl, yr : ndarray, shape (...)

        Raises
        ------
        ValueError
            On mismatched shapes, non-finite values or ``f_lower > f_upper``.
        ZeroFiringError
            Where no rule fires (or, for Wu-Mendel, where the total lower firing is zero).
        """
        fl = np.asarray(f_lower, dtype=np.float64)
        fu = np.asarray(f_upper, dtype=np.float64)
        y_lo = np.asarray(y_lower, dtype=np.float64)
        y_hi = y_lo if y_upper is None else np.asarray(y_upper, dtype=np.float64)
        if fl.ndim == 0 or fl.shape != fu.shape:
            raise ValueError(
                f"f_lower shape {fl.shape} and f_upper shape {fu.shape} must be equal, (..., R)"
            )
        r = fl.shape[-1]
        if r == 0:
            raise ValueError("f_lower and f_upper need at least one rule on their last axis")
        if y_lo.shape != (r,) or y_hi.shape != (r,):
            raise ValueError(
                f"y_lower shape {y_lo.shape} and y_upper shape {y_hi.shape} must be ({r},)"
            )
        for name, arr in (("f_lower", fl), ("f_upper", fu), ("y_lower", y_lo), ("y_upper", y_hi)):
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"{name} contains NaN or inf")
        if np.any(fl < 0) or np.any(fl > fu):
            raise ValueError("firing strengths must satisfy 0 <= f_lower <= f_upper")
        if np.any(y_lo > y_hi):
            raise ValueError("consequents must satisfy y_lower <= y_upper")
        batch = fl.shape[:-1]
        fl2 = np.ascontiguousarray(np.moveaxis(fl, -1, 0).reshape(r, -1))
        fu2 = np.ascontiguousarray(np.moveaxis(fu, -1, 0).reshape(r, -1))
        if self._approx is _wu_mendel and np.any(fl2.sum(axis=0) <= 0):
            raise ZeroFiringError("Wu-Mendel bounds need a positive total lower firing strength")
        yl, yr = self.reduce_rules_first(
            fl2, fu2, y_lo, y_hi, np.argsort(y_lo, kind="stable"), np.argsort(y_hi, kind="stable")
        )
        if np.any(np.isnan(yl)) or np.any(np.isnan(yr)):
            raise ZeroFiringError("no rule fires for at least one input: the output is undefined")
        return yl.reshape(batch), yr.reshape(batch)


def _sorted_rows(
    fl: FloatArray, fu: FloatArray, y: FloatArray, order: NDArray[np.intp]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    if np.array_equal(order, np.arange(order.size)):
        return fl, fu, y
    return fl[order], fu[order], y[order]


KM = TypeReducer(name="km", exact=True, _left=_km_left, _right=_km_right)
EKM = TypeReducer(name="ekm", exact=True, _left=_ekm_left, _right=_ekm_right)
EIASC = TypeReducer(name="eiasc", exact=True, _left=_eiasc_left, _right=_eiasc_right)
EXHAUSTIVE = TypeReducer(
    name="exhaustive", exact=True, _left=_exhaustive_left, _right=_exhaustive_right
)
NIE_TAN = TypeReducer(name="nie-tan", exact=False, _approx=_nie_tan)
WU_MENDEL = TypeReducer(name="wu-mendel", exact=False, _approx=_wu_mendel)


class Reducer(enum.Enum):
    """Name -> type reducer, for command lines and configuration files.

    Examples
    --------
    >>> Reducer.from_name("EIASC").value is EIASC
    True
    """

    KM = KM
    EKM = EKM
    EIASC = EIASC
    EXHAUSTIVE = EXHAUSTIVE
    NIE_TAN = NIE_TAN
    WU_MENDEL = WU_MENDEL

    @classmethod
    def from_name(cls, name: str) -> Reducer:
        """Look a reducer up by its name (case-insensitive; ``-`` and ``_`` equivalent)."""
        key = name.strip().upper().replace("-", "_")
        try:
            return cls[key]
        except KeyError:
            known = ", ".join(m.value.name for m in cls)
            raise ValueError(f"unknown type reducer {name!r}; choose one of: {known}") from None
