"""Tracking metrics, accumulated on the fly over the control grid (paper eqs. 24-27 and more).

Integrals use the trapezoid rule over the samples ``k = 0 ... N`` of the control grid
``t_k = k ts`` (ITAE and ITSE weight sample ``k`` by ``t_k``). The accumulator keeps O(B)
memory whatever the duration, so metrics of huge batches never need the time series.

Metric names (all arrays of shape ``(B,)``):

========== ================================================================== ==========
name       definition                                                         unit
========== ================================================================== ==========
IAE        integral of ``|e|`` (``e = wrap(theta_d - theta)``, true heading)   rad s
ITAE       integral of ``t |e|``                                              rad s^2
ISE        integral of ``e^2``                                                rad^2 s
ITSE       integral of ``t e^2``                                              rad^2 s^2
``*_meas`` the same four on the measured error ``wrap(theta_d - theta_hat)``
pos_rms    RMS over the samples of the distance to the reference point        m
pos_max    largest distance to the reference point                            m
pos_final  distance at ``t_N``                                                m
effort     integral of ``u^2``                                                V^2 s
u_tv       total variation ``sum |u_k - u_(k-1)|``                            V
sat_time   time during which a requested wheel voltage exceeds the limit      s
========== ================================================================== ==========

``sat_time`` counts the control periods ``k = 0 ... N-1`` (the ones applied to the plant).

Tracking a reference signal ``r`` with a single-input plant (:mod:`.siso`), the same names
hold with ``e = r - y`` (the plant's first output, true and measured) in place of the heading
error, ``|r - y|`` as the distance (so ``pos_final`` is the final tracking error), ``u`` the
controller's output and ``sat_time`` the time the requested plant input lies outside the
plant's input limits.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["METRIC_NAMES", "MetricAccumulator", "integral_errors"]

FloatArray = NDArray[np.float64]

INTEGRAL_NAMES = ("IAE", "ITAE", "ISE", "ITSE")
METRIC_NAMES: tuple[str, ...] = (
    *INTEGRAL_NAMES,
    *(f"{n}_meas" for n in INTEGRAL_NAMES),
    "pos_rms",
    "pos_max",
    "pos_final",
    "effort",
    "u_tv",
    "sat_time",
)


class _IntegralErrors:
    """Running trapezoid sums of |e|, t|e|, e^2, t e^2 on a uniform grid, over the samples
    ``k = start ... n_steps``."""

    def __init__(self, n: int, ts: float, n_steps: int, start: int = 0) -> None:
        self.ts = ts
        self.n_steps = n_steps
        self.start = start
        self.sums = np.zeros((4, n))
        self.ends = np.zeros((4, n))
        self._abs = np.empty(n)
        self._sq = np.empty(n)

    def update(self, k: int, e: FloatArray) -> None:
        if k < self.start:
            return
        t = k * self.ts
        end = k == self.start or k == self.n_steps
        sums, ends = self.sums, self.ends
        a = np.abs(e, out=self._abs)
        s = np.multiply(e, e, out=self._sq)
        sums[0] += a
        sums[2] += s
        if end:
            ends[0] += a
            ends[2] += s
        a *= t  # t |e| and t e^2, in place (no temporaries)
        s *= t
        sums[1] += a
        sums[3] += s
        if end:
            ends[1] += a
            ends[3] += s

    def result(self) -> FloatArray:
        return self.ts * (self.sums - 0.5 * self.ends)


class MetricAccumulator:
    """Accumulate every metric of :data:`METRIC_NAMES` for ``n`` runs, one sample at a time.

    Call :meth:`update` for ``k = 0 ... n_steps`` in order, then :meth:`result`. ``ts`` is the
    sampling period (s) and ``voltage_limit`` the wheel-voltage limit (V) that ``sat_time``
    compares the requested voltages with. The heading-error integrals (IAE ... ITSE, true and
    measured) cover the samples ``k >= start_index`` only (the other metrics every sample).
    ``limits``: an input range ``(low, high)`` instead of ``+-voltage_limit`` (a requested
    value saturates when outside it).
    """

    def __init__(self, n: int, ts: float, n_steps: int, voltage_limit: float, *,
                 start_index: int = 0, limits: tuple[float, float] | None = None) -> None:
        if not 0 <= start_index < n_steps:
            raise ValueError(f"start_index={start_index!r} must be in [0, n_steps={n_steps})")
        self.n = n
        self.ts = ts
        self.n_steps = n_steps
        self.voltage_limit = voltage_limit
        self.limits = limits
        self.true = _IntegralErrors(n, ts, n_steps, start_index)
        self.meas = _IntegralErrors(n, ts, n_steps, start_index)
        self.dist_sq = np.zeros(n)
        self.dist_max = np.zeros(n)
        self.dist_final = np.zeros(n)
        self.effort_sum = np.zeros(n)  # trapezoid sums of u^2, as in _IntegralErrors
        self.effort_ends = np.zeros(n)
        self.u_prev = np.zeros(n)
        self.u_tv = np.zeros(n)
        self.sat_steps = np.zeros(n)
        self._tmp = np.empty(n)
        self._over = np.empty(n, dtype=bool)
        self._over2 = np.empty(n, dtype=bool)
        self._k = 0

    def update(
        self,
        k: int,
        *,
        e_true: FloatArray,
        e_meas: FloatArray,
        distance: FloatArray,
        u: FloatArray,
        v_requested: tuple[FloatArray, ...],
    ) -> None:
        if k != self._k:
            raise RuntimeError(f"metric samples out of order: got k={k}, expected {self._k}")
        self._k += 1
        self.true.update(k, e_true)
        self.meas.update(k, e_meas)
        tmp = self._tmp
        self.dist_sq += np.multiply(distance, distance, out=tmp)
        np.maximum(self.dist_max, distance, out=self.dist_max)
        if k == self.n_steps:
            self.dist_final[:] = distance
        np.multiply(u, u, out=tmp)
        self.effort_sum += tmp
        if k == 0 or k == self.n_steps:
            self.effort_ends += tmp
        if k > 0:
            self.u_tv += np.abs(np.subtract(u, self.u_prev, out=tmp), out=tmp)
        self.u_prev[:] = u
        if k < self.n_steps:
            if self.limits is None:
                lim = self.voltage_limit
                vr, vl = v_requested
                over = np.greater(np.abs(vr, out=tmp), lim, out=self._over)
                over |= np.greater(np.abs(vl, out=tmp), lim, out=self._over2)
            else:
                low, high = self.limits
                over = self._over
                over[:] = False
                for v in v_requested:
                    over |= np.less(v, low, out=self._over2)
                    over |= np.greater(v, high, out=self._over2)
            self.sat_steps += over

    def result(self) -> dict[str, FloatArray]:
        if self._k != self.n_steps + 1:
            raise RuntimeError(f"metrics incomplete: {self._k} of {self.n_steps + 1} samples")
        true = self.true.result()
        meas = self.meas.result()
        out: dict[str, FloatArray] = {}
        for i, name in enumerate(INTEGRAL_NAMES):
            out[name] = true[i]
            out[f"{name}_meas"] = meas[i]
        out["pos_rms"] = np.sqrt(self.dist_sq / (self.n_steps + 1))
        out["pos_max"] = self.dist_max.copy()
        out["pos_final"] = self.dist_final.copy()
        out["effort"] = self.ts * (self.effort_sum - 0.5 * self.effort_ends)
        out["u_tv"] = self.u_tv.copy()
        out["sat_time"] = self.sat_steps * self.ts
        return out


def integral_errors(e: FloatArray, ts: float) -> dict[str, FloatArray]:
    """IAE, ITAE, ISE, ITSE of error series ``e`` of shape ``(..., N+1)`` sampled every ``ts``.

    Examples
    --------
    >>> import numpy as np
    >>> m = integral_errors(np.full(1001, 0.5), 0.01)   # constant error 0.5 over 10 s
    >>> [round(float(m[k]), 9) for k in ("IAE", "ITAE", "ISE", "ITSE")]
    [5.0, 25.0, 2.5, 12.5]
    """
    e = np.asarray(e, dtype=np.float64)
    batch = e.shape[:-1]
    flat = e.reshape(-1, e.shape[-1])
    acc = _IntegralErrors(flat.shape[0], ts, flat.shape[1] - 1)
    for k in range(flat.shape[1]):
        acc.update(k, np.ascontiguousarray(flat[:, k]))
    res = acc.result()
    return {name: res[i].reshape(batch) for i, name in enumerate(INTEGRAL_NAMES)}
