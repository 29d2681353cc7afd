"""The loop kernel's lane helpers (atan2, wrap, sine/cosine) give the numpy forms' bits for
every lane, including the rare lanes their fix-up passes handle (non-finite atan2 arguments,
angles outside (-pi, pi], sine/cosine arguments beyond the kernels' range) wherever they sit
in a block."""

import math

import numpy as np
import pytest
from _lane_kernels import _atan2, _sc, _wrap, bits

from it2track.plant._sincos import _sincos, _sincos_small
from it2track.tracking.libm import atan2
from it2track.tracking.simulate import _wrap_inplace


def blocks(values, rng):
    """``values`` cut into blocks of up to 64 lanes, shuffled so rare ones land anywhere."""
    v = rng.permutation(values)
    return [v[a:a + n] for a, n in ((0, 64), (64, 13), (77, 1), (78, 64))]


RNG = np.random.default_rng(5)
ODD = [np.inf, -np.inf, np.nan, 0.0, -0.0]


@pytest.mark.parametrize("rare", [0, 1, 9])
def test_atan2_lanes(rare):
    n = 142
    y = RNG.normal(size=n) * RNG.choice([1e-300, 1.0, 1e20], n)
    x = RNG.normal(size=n) * RNG.choice([1e-300, 1.0, 1e20], n)
    y[:rare] = RNG.choice(ODD, rare)
    x[rare:2 * rare] = RNG.choice(ODD, rare)
    for idx in blocks(np.arange(n), RNG):
        L = idx.size
        W = np.zeros((3, 64))
        W[0, :L], W[1, :L] = x[idx], y[idx]
        _atan2(W, L)
        assert (bits(W[2, :L]) == bits(atan2(y[idx], x[idx]))).all()


@pytest.mark.parametrize("rare", [0, 1, 9])
def test_wrap_lanes(rare):
    a = RNG.uniform(-math.pi, math.pi, 142)
    a[:rare] = RNG.choice([-math.pi, 7.0, -20.0, 1e9, math.pi + 1e-15], rare)
    for idx in blocks(np.arange(a.size), RNG):
        L = idx.size
        W = np.zeros((1, 64))
        W[0, :L] = a[idx]
        _wrap(W, L)
        assert (bits(W[0, :L]) == bits(_wrap_inplace(a[idx].copy()))).all()


@pytest.mark.parametrize("small", [False, True])
@pytest.mark.parametrize("rare", [0, 1, 9])
def test_sincos_lanes(small, rare):
    x = RNG.uniform(-0.7, 0.7, 142) if small else RNG.normal(size=142) * 30.0
    x[:rare] = RNG.choice([1.0, -2.5, 1e7, -3e9], rare)
    ref = _sincos_small if small else _sincos
    for idx in blocks(np.arange(x.size), RNG):
        L = idx.size
        W = np.zeros((3, 64))
        W[0, :L] = x[idx]
        _sc(W, L, small)
        s, c = np.empty(L), np.empty(L)
        ref(x[idx], s, c, [np.empty(L) for _ in range(7)])
        assert (bits(W[1, :L]) == bits(s)).all() and (bits(W[2, :L]) == bits(c)).all()
