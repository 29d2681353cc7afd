"""Type-1 defuzzification of an output set sampled on a grid, and the grids.

An output's universe ``[lo, hi]`` is sampled at ``J`` points (:func:`output_grid`): MATLAB's
``linspace(lo, hi, J)`` (``NumSamplePoints``, default 101; :attr:`Sampling.ENDPOINTS`) or
fuzzylite's midpoint rule, the centres ``lo + (i + 1/2)(hi - lo)/J`` of ``J`` equal cells
(``resolution``, default 1000 there; :attr:`Sampling.MIDPOINTS`). :func:`defuzzify` reduces a
sampled set with a :class:`~.norms.Defuzzifier` (MATLAB's ``defuzz`` definitions on the grid).
"""

from __future__ import annotations

import enum

import numpy as np
from numpy.typing import NDArray

from .norms import Defuzzifier

__all__ = ["Sampling", "defuzzify", "output_grid"]

FloatArray = NDArray[np.float64]


class Sampling(enum.Enum):
    """Where an output's universe is sampled (see the module docstring)."""

    ENDPOINTS = "endpoints"
    MIDPOINTS = "midpoints"

    @classmethod
    def from_name(cls, name: str) -> Sampling:
        """Look up by value or name; ``"matlab"`` is ``ENDPOINTS``, ``"fuzzylite"``
        ``MIDPOINTS``."""
        key = str(name).strip().lower()
        key = {"matlab": "endpoints", "fuzzylite": "midpoints"}.get(key, key)
        for member in cls:
            if key in (member.value, member.name.lower()):
                return member
        raise ValueError(f"unknown sampling {name!r}; choose 'endpoints' (MATLAB) or "
                         "'midpoints' (fuzzylite)")


def output_grid(universe: tuple[float, float], n: int, sampling: Sampling) -> FloatArray:
    """The ``n`` grid points of ``universe`` (ascending).

    Parameters
    ----------
    universe : (float, float)
        ``(lo, hi)``.
    n : int
        Number of points.
    sampling : Sampling
        ``ENDPOINTS``: ``linspace(lo, hi, n)``; ``MIDPOINTS``:
        ``lo + (arange(n) + 0.5) * ((hi - lo) / n)`` (fuzzylite's expression).

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> output_grid((0.0, 1.0), 4, Sampling.MIDPOINTS).tolist()
    [0.125, 0.375, 0.625, 0.875]
    """
    lo, hi = universe
    if sampling is Sampling.MIDPOINTS:
        out: FloatArray = lo + (np.arange(n, dtype=np.float64) + 0.5) * ((hi - lo) / n)
        return out
    return np.linspace(lo, hi, n)


def defuzzify(mu: FloatArray, y: FloatArray, method: Defuzzifier) -> FloatArray:
    """Defuzzify sets sampled on a grid: ``mu`` ``(J, N)``, ``y`` ``(J,)`` -> ``(N,)``.

    NaN where a set is zero everywhere (no output). ``method`` is a :class:`Defuzzifier`.

    Examples
    --------
    >>> mu = np.array([[0.0], [1.0], [1.0], [0.5]])
    >>> y = np.array([0.0, 1.0, 2.0, 3.0])
    >>> [float(defuzzify(mu, y, d)[0]) for d in Defuzzifier]
    [1.8, 2.0, 1.5, 1.0, 2.0, 1.6666666666666667]
    """
    total = mu.sum(axis=0)
    empty = total <= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        if method is Defuzzifier.CENTROID:
            out = (mu * y[:, None]).sum(axis=0) / total
        elif method is Defuzzifier.CENTROID_INTEGRAL:
            # Octave's trapz(y, v): sum(diff(y) .* (v(1:end-1) + v(2:end))) / 2
            step = np.diff(y)[:, None]
            moment = mu * y[:, None]
            out = ((step * (moment[1:] + moment[:-1])).sum(axis=0)
                   / (step * (mu[1:] + mu[:-1])).sum(axis=0))
        elif method is Defuzzifier.BISECTOR:
            # The first grid point where the running sum reaches half the total.
            idx = np.argmax(np.cumsum(mu, axis=0) >= 0.5 * total, axis=0)
            out = y[idx].astype(np.float64)
        else:
            top = mu == mu.max(axis=0)
            if method is Defuzzifier.MOM:
                out = (top * y[:, None]).sum(axis=0) / top.sum(axis=0)
            elif method is Defuzzifier.SOM:
                out = y[np.argmax(top, axis=0)].astype(np.float64)
            else:
                out = y[y.size - 1 - np.argmax(top[::-1], axis=0)].astype(np.float64)
    out = np.asarray(out, dtype=np.float64)
    out[empty] = np.nan
    return out
