"""The loop kernel's lane helpers compiled on their own for the lane tests
(``test_lanes.py``, ``test_loop_kernel_branches.py``): each runs one helper over the first
``L`` lanes of a work array ``W``."""

import numpy as np
from numba import njit

from it2track.tracking import _jit


@njit(error_model="numpy")
def _atan2(W, L):
    _jit._atan2_lanes(W, 1, 0, 2, L)


@njit(error_model="numpy")
def _wrap(W, L):
    _jit._wrap_lanes(W, 0, L)


@njit(error_model="numpy")
def _sc(W, L, small):
    if small:
        _jit._sincos_lanes(W, 0, 1, 2, L, True)
    else:
        _jit._sincos_lanes(W, 0, 1, 2, L, False)


def bits(a):
    return np.asarray(a, dtype=np.float64).view(np.int64)
