"""A fuzzy system lowered to arrays: the one representation every evaluator works from.

:class:`SystemTables` is built once per system. It deduplicates the membership functions the
rules use into *rows* (one per distinct MF of an input), encodes each row's shape as an
:class:`MFKind` with a fixed-size parameter vector, and lists for every rule the row of its
upper and lower MF for each input (row ``n_rows`` is the constant 1 of an input the rule does
not mention). The numpy evaluation of the rows here is the reference semantics; compiled
kernels and code generators read the same arrays and must refuse (or fall back on) what they do
not implement: a row of kind :attr:`MFKind.OTHER` (an arbitrary Python callable), or a rule
feature listed in :attr:`SystemTables.features`.
"""

from __future__ import annotations

import enum
import math
import threading
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .membership import (
    Gaussian,
    MembershipFunction,
    PiecewiseLinear,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)
from .rules import Input, Rule

__all__ = ["MFKind", "SystemTables"]

FloatArray = NDArray[np.float64]


class MFKind(enum.IntEnum):
    """Shape code of a membership row, with the meaning of its 5 parameters ``p``.

    ``TRAPEZOID``
        ``h clip(min((x - a) / wl, (d - x) / wr), 0, 1)`` with ``p = (a, wl, d, wr, h)``;
        a left shoulder has ``a = -inf, wl = 1``, a right shoulder ``d = +inf, wr = 1``
        (triangles are trapezoids with ``b == c``).
    ``GAUSSIAN``
        ``h exp(-z^2 / 2)``, ``z = (x - mean) / sigma``; ``p = (mean, sigma, h, 0, 0)``.
    ``UM_GAUSSIAN_UPPER`` / ``UM_GAUSSIAN_LOWER``
        Bounds of a Gaussian with uncertain mean in ``[m1, m2]``; ``p = (m1, m2, sigma, h, 0)``
        (see :class:`~it2track.fuzzy.membership.UncertainMeanGaussianUpper` / ``Lower``).
    ``OTHER``
        Any other callable: only the numpy evaluation knows it (parameters 0).
    """

    TRAPEZOID = 0
    GAUSSIAN = 1
    UM_GAUSSIAN_UPPER = 2
    UM_GAUSSIAN_LOWER = 3
    OTHER = 255


def _encode(mf: MembershipFunction) -> tuple[MFKind, tuple[float, float, float, float, float]]:
    if isinstance(mf, PiecewiseLinear):
        pa, pb, pc, pd, ph = mf.as_trapezoid()
        return MFKind.TRAPEZOID, (
            -math.inf if pa == pb else pa,
            1.0 if pa == pb else pb - pa,
            math.inf if pc == pd else pd,
            1.0 if pc == pd else pd - pc,
            ph,
        )
    if type(mf) is Gaussian:
        return MFKind.GAUSSIAN, (float(mf.mean), float(mf.sigma), float(mf.h), 0.0, 0.0)
    if type(mf) is UncertainMeanGaussianUpper:
        return MFKind.UM_GAUSSIAN_UPPER, (float(mf.m1), float(mf.m2), float(mf.sigma),
                                         float(mf.h), 0.0)
    if type(mf) is UncertainMeanGaussianLower:
        return MFKind.UM_GAUSSIAN_LOWER, (float(mf.m1), float(mf.m2), float(mf.sigma),
                                         float(mf.h), 0.0)
    return MFKind.OTHER, (0.0, 0.0, 0.0, 0.0, 0.0)


class SystemTables:
    """A Sugeno system's inputs and rules as arrays, built once (see the module docstring).

    Parameters
    ----------
    inputs : tuple of Input
    rules : tuple of Rule

    Attributes
    ----------
    n_inputs, n_rules, n_rows : int
        Inputs, rules, and distinct membership rows M.
    lo, hi : ndarray, shape (n_inputs,)
        Universe of each input (inputs are clipped to it before evaluation).
    mf_kind : ndarray of int, shape (M,)
        :class:`MFKind` of each row.
    mf_params : ndarray, shape (M, 5)
        Parameters of each row (meaning per :class:`MFKind`).
    mf_input : ndarray of int, shape (M,)
        The input each row reads.
    mfs : tuple of MembershipFunction
        The membership function objects behind the rows.
    upper_rows, lower_rows : ndarray of int, shape (R, n_inputs)
        Row of the upper / lower MF of rule r on input i; ``M`` where the rule does not
        mention the input (membership 1).
    y_lo, y_hi : ndarray, shape (R,)
        Consequent interval of each rule, in rule order.
    perm : ndarray of int, shape (R,)
        Rules sorted by ``y_lo`` (stable): sorted position -> rule index. The ``*_s`` arrays
        (``upper_rows_s``, ``lower_rows_s``, ``y_lo_s``, ``y_hi_s``) are in that order, and
        ``order_hi_s`` sorts ``y_hi_s`` (stable).
    type1 : bool
        Every rule uses the same rows for upper and lower MFs.
    crisp : bool
        Every consequent has ``y_lo == y_hi``.
    features : frozenset of str
        Rule-language features beyond zero-order AND rules with weight 1 that these tables
        use (empty for now). An evaluator that does not implement one of them must refuse the
        tables or fall back on the numpy evaluation.
    """

    def __init__(self, inputs: tuple[Input, ...], rules: tuple[Rule, ...]) -> None:
        self.n_inputs = len(inputs)
        self.n_rules = len(rules)
        self.features: frozenset[str] = frozenset()
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
        self.mfs = tuple(mfs)
        self.mf_input = np.array(mf_input, dtype=np.intp)
        encoded = [_encode(mf) for mf in mfs]
        self.mf_kind = np.array([int(k) for k, _ in encoded], dtype=np.intp)
        self.mf_params = np.array([p for _, p in encoded], dtype=np.float64).reshape(n_rows, 5)
        # Piecewise-linear rows are evaluated together as one trapezoid bank.
        pl = [k for k in range(n_rows) if self.mf_kind[k] == MFKind.TRAPEZOID]
        self.pl_rows = np.array(pl, dtype=np.intp)
        self.pl_input = np.array([mf_input[k] for k in pl], dtype=np.intp)
        a, wl, d, wr, h = (self.mf_params[pl, j].tolist() for j in range(5))
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
