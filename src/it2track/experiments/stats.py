"""Summary statistics for Monte Carlo results: means, 95 % intervals, paired comparisons.

Runs of different controllers that share a seed index saw the same noise (common random
numbers), so comparisons are *paired*: the interval of a difference is computed from the
per-seed differences, which is much tighter than comparing two independent means.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats as _st

__all__ = ["Interval", "mean_interval", "paired_comparison"]


@dataclass(frozen=True)
class Interval:
    """A mean with its two-sided confidence interval (Student t on ``n - 1`` d.o.f.)."""

    n: int
    mean: float
    low: float
    high: float

    @property
    def excludes_zero(self) -> bool:
        return self.low > 0.0 or self.high < 0.0


def mean_interval(values: ArrayLike, level: float = 0.95) -> Interval:
    """Mean of ``values`` with its ``level`` confidence interval.

    With one value (or zero spread) the interval collapses to the mean.

    Examples
    --------
    >>> iv = mean_interval([1.0, 2.0, 3.0])
    >>> round(iv.mean, 6), round(iv.high - iv.mean, 4)
    (2.0, 2.4841)
    """
    x = np.asarray(values, dtype=np.float64).ravel()
    n = int(x.size)
    if n == 0:
        raise ValueError("mean_interval needs at least one value")
    if not np.isfinite(x).all():
        raise ValueError("mean_interval: values contain NaN or inf")
    mean = float(np.mean(x))
    if n == 1:
        return Interval(1, mean, mean, mean)
    sem = float(np.std(x, ddof=1)) / math.sqrt(n)
    half = float(_st.t.ppf(0.5 + level / 2.0, n - 1)) * sem
    return Interval(n, mean, mean - half, mean + half)


@dataclass(frozen=True)
class PairedComparison:
    """``a - b`` over paired samples.

    Attributes
    ----------
    diff : Interval
        Mean per-pair difference with its confidence interval.
    win_rate : float
        ``P(a < b) + P(a == b) / 2`` over the pairs: the chance that ``a`` has the smaller error,
        ties counting half (0.5 = no difference).
    ties : float
        Fraction of pairs with ``a == b`` exactly (e.g. two controllers that never leave their
        dead zones).
    """

    diff: Interval
    win_rate: float
    ties: float


def paired_comparison(a: ArrayLike, b: ArrayLike, level: float = 0.95) -> PairedComparison:
    """Compare paired samples ``a`` and ``b`` (same length, same seed order)."""
    xa = np.asarray(a, dtype=np.float64).ravel()
    xb = np.asarray(b, dtype=np.float64).ravel()
    if xa.shape != xb.shape:
        raise ValueError(f"paired samples differ in length: {xa.size} vs {xb.size}")
    d = xa - xb
    ties = float(np.mean(xa == xb))
    return PairedComparison(mean_interval(d, level), float(np.mean(xa < xb)) + 0.5 * ties, ties)
