"""Shape codes of membership rows: how a membership function is lowered to 5 numbers.

:class:`MFKind` is shared by the membership classes (each knows its own row, see
``kernel_row``), the lowering of a system to arrays (:mod:`.tables`) and the compiled kernels
(:mod:`._jit`), which evaluate a row from its kind and parameters with the same IEEE
operations, in the same order, as the class's numpy ``__call__``.
"""

from __future__ import annotations

import enum

__all__ = ["MFKind", "Row"]


class MFKind(enum.IntEnum):
    """Shape code of a membership row, with the meaning of its 5 parameters ``p``.

    ``TRAPEZOID``
        ``h clip(min((x - a) / wl, (d - x) / wr), 0, 1)`` with ``p = (a, wl, d, wr, h)``;
        a left shoulder has ``a = -inf, wl = 1``, a right shoulder ``d = +inf, wr = 1``
        (triangles are trapezoids with ``b == c``; ramps and ``linsmf``/``linzmf`` have one
        side at infinity).
    ``GAUSSIAN``
        ``h exp(-z^2 / 2)``, ``z = (x - mean) / sigma``; ``p = (mean, sigma, h, 0, 0)``.
    ``UM_GAUSSIAN_UPPER`` / ``UM_GAUSSIAN_LOWER``
        Bounds of a Gaussian with uncertain mean in ``[m1, m2]``; ``p = (m1, m2, sigma, h, 0)``
        (see :class:`~it2track.fuzzy.membership.UncertainMeanGaussianUpper` / ``Lower``).
    ``BELL`` ... ``SEMI_ELLIPSE``
        The classes of :mod:`.curves` and :mod:`.shapes`; each documents its ``p`` in its
        ``kernel_row``.
    ``SCALED_LAGGED``
        MATLAB's type-2 lower MF of another row ``k < this row``:
        ``p = (k, scale * peak, lag, peak, 0)`` (see :class:`~it2track.fuzzy.sets.ScaledLagged`).
    ``OTHER``
        Any other callable: only the numpy evaluation knows it (parameters 0).
    """

    TRAPEZOID = 0
    GAUSSIAN = 1
    UM_GAUSSIAN_UPPER = 2
    UM_GAUSSIAN_LOWER = 3
    BELL = 4
    SIGMOID = 5
    SIGMOID_DIFFERENCE = 6
    SIGMOID_PRODUCT = 7
    S_SHAPE = 8
    Z_SHAPE = 9
    PI_SHAPE = 10
    GAUSSIAN_PRODUCT = 11
    COSINE = 12
    SPIKE = 13
    CONCAVE = 14
    RECTANGLE = 15
    STEP = 16
    ARC = 17
    SEMI_ELLIPSE = 18
    SCALED_LAGGED = 19
    OTHER = 255


#: A lowered membership function: its kind and its 5 parameters.
Row = tuple[MFKind, tuple[float, float, float, float, float]]
