"""Summary statistics for Monte Carlo results: means, 95 % intervals, paired comparisons.

Runs of different controllers that share a seed index saw the same noise (common random
numbers), so comparisons are *paired*: the interval of a difference is computed from the
per-seed differences, which is much tighter than comparing two independent means.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

# Student's t quantile and tail from scipy.special, the functions scipy.stats.t calls (same
# numbers, bit for bit: tests/experiments/test_analysis.py) without scipy.stats' per-call
# argument handling (~0.3 ms a call; the robustness experiment judges thousands of cells).
from scipy import special as _sc

__all__ = [
    "Interval",
    "binomial_interval",
    "holm_adjust",
    "interval_text",
    "mean_interval",
    "paired_comparison",
    "t_tail",
]


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
    half = float(_sc.stdtrit(n - 1, 0.5 + level / 2.0)) * sem
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


def t_tail(values: ArrayLike, threshold: float = 0.0, *, side: str = "greater") -> float:
    """One-sided p-value of Student's t test of the mean of ``values`` against ``threshold``.

    ``side = "greater"``: evidence that the mean exceeds ``threshold`` (H0: mean <= threshold);
    ``"less"``: that it lies below. Consistent with :func:`mean_interval`: the two-sided
    ``1 - 2 a`` interval lies wholly above ``threshold`` exactly when the ``"greater"`` p-value
    is below ``a``. Zero spread gives 0 (the mean is on the tested side) or 1; fewer than two
    values give 1 (no test).

    Examples
    --------
    >>> round(t_tail([1.0, 2.0, 3.0], 0.0), 4)   # t = 2 sqrt(3) on 2 d.o.f.
    0.0371
    """
    x = np.asarray(values, dtype=np.float64).ravel()
    if side not in ("greater", "less"):
        raise ValueError(f"side={side!r} must be 'greater' or 'less'")
    if not np.isfinite(x).all():
        raise ValueError("t_tail: values contain NaN or inf")
    n = int(x.size)
    if n < 2:
        return 1.0
    excess = float(np.mean(x)) - threshold
    if side == "less":
        excess = -excess
    sd = float(np.std(x, ddof=1))
    if sd == 0.0:
        return 0.0 if excess > 0.0 else 1.0
    return float(_sc.stdtr(n - 1, -(excess / (sd / math.sqrt(n)))))


def holm_adjust(pvalues: ArrayLike) -> NDArray[np.float64]:
    """Holm-Bonferroni adjusted p-values (step-down; family-wise error control).

    Rejecting every hypothesis whose adjusted p-value is at most ``a`` keeps the probability of
    any false rejection in the family at most ``a``, whatever the dependence between the tests.
    ``adj_(i) = max_{j <= i} min(1, (m - j) p_(j))`` over the p-values sorted ascending
    (``j = 0 ... m-1``), returned in the input order.

    Examples
    --------
    >>> holm_adjust([0.01, 0.04, 0.03]).tolist()
    [0.03, 0.06, 0.06]
    """
    p = np.asarray(pvalues, dtype=np.float64).ravel()
    if p.size and (not np.isfinite(p).all() or p.min() < 0.0 or p.max() > 1.0):
        raise ValueError("holm_adjust: p-values must lie in [0, 1]")
    m = p.size
    order = np.argsort(p, kind="stable")
    scaled = np.minimum(1.0, (m - np.arange(m)) * p[order])
    adjusted = np.empty(m)
    adjusted[order] = np.maximum.accumulate(scaled)
    return adjusted


def binomial_interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact (Clopper-Pearson) interval of a binomial proportion ``k / n``.

    Its coverage is at least ``level`` for every true proportion.

    Examples
    --------
    >>> lo, hi = binomial_interval(0, 10)
    >>> lo, round(hi, 4)     # 1 - 0.025 ** (1 / 10)
    (0.0, 0.3085)
    """
    if isinstance(k, bool) or isinstance(n, bool) or n < 1 or not 0 <= k <= n:
        raise ValueError(f"binomial_interval: need 0 <= k <= n and n >= 1, got k={k}, n={n}")
    a = 1.0 - level
    # scipy.stats' beta quantile, not scipy.special's betaincinv: they differ in the last bits,
    # and the published intervals are scipy.stats'. A few calls per study.
    from scipy.stats import beta

    low = 0.0 if k == 0 else float(beta.ppf(a / 2.0, k, n - k + 1))
    high = 1.0 if k == n else float(beta.ppf(1.0 - a / 2.0, k + 1, n - k))
    return low, high


def interval_text(mean: float, low: float, high: float, digits: int = 3) -> str:
    """``"mean [low, high]"`` with enough significant digits (at least ``digits``) that the
    printed mean lies inside the printed interval and differs from a printed bound unless the
    numbers themselves are equal -- never ``2.748 [2.75, 2.75]``.

    Raises
    ------
    ValueError
        If a value is not finite, ``low > high``, or ``mean`` lies outside ``[low, high]``.

    Examples
    --------
    >>> interval_text(2.7483, 2.7480, 2.7486)
    '2.7483 [2.748, 2.7486]'
    >>> interval_text(0.5, 0.25, 0.75)
    '0.5 [0.25, 0.75]'
    """
    values = (float(mean), float(low), float(high))
    if not all(math.isfinite(v) for v in values) or not values[1] <= values[0] <= values[2]:
        raise ValueError(f"interval_text: need finite low <= mean <= high, got {values}")
    m, lo, hi = values
    for d in range(max(1, int(digits)), 18):
        tm, tl, th = (f"{v:.{d}g}" for v in values)
        inside = float(tl) <= float(tm) <= float(th)
        distinct = (tl != tm or lo == m) and (th != tm or hi == m)
        if inside and distinct:
            return f"{tm} [{tl}, {th}]"
    return f"{m!r} [{lo!r}, {hi!r}]"  # pragma: no cover - 17 digits always separate doubles
