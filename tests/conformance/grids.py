"""The inputs every reference table is evaluated at (numpy only: both reference scripts import
it)."""

from __future__ import annotations

import numpy as np

__all__ = ["grid"]

_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53)


def _halton(n_points: int, dims: int) -> np.ndarray:
    """The first ``n_points`` of the Halton sequence in ``[0, 1)^dims`` (deterministic)."""
    out = np.empty((n_points, dims))
    for d in range(dims):
        base = _PRIMES[d]
        for i in range(n_points):
            f, r, k = 1.0, 0.0, i + 1
            while k > 0:
                f /= base
                r += f * (k % base)
                k //= base
            out[i, d] = r
    return out


def grid(ranges: list[tuple[float, float]]) -> np.ndarray:
    """Inputs to evaluate: a full grid for up to three inputs (33, 9 x 9, 4 x 4 x 4 points,
    ends included; one point for a universe that is a point), else 64 Halton points."""
    n = len(ranges)
    if n <= 3:
        k = {1: 33, 2: 9, 3: 4}[n]
        # a point universe (jFuzzyLogic's estimate from degenerate terms) is sampled once
        axes = [np.linspace(lo, hi, k) if lo < hi else np.array([lo]) for lo, hi in ranges]
        return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, n)
    lo = np.array([r[0] for r in ranges])
    hi = np.array([r[1] for r in ranges])
    return lo + _halton(64, n) * (hi - lo)
