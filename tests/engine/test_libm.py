"""exp and atan2 of fuzzy.libm / tracking.libm: the numpy and scalar forms give the same bits
(what makes the numpy and compiled engines agree), within 1 ulp of the C library."""

import math

import numpy as np

from it2track.fuzzy.libm import exp, exp_scalar
from it2track.tracking.libm import atan2, atan2_scalar


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return (a == b) & (np.signbit(a) == np.signbit(b)) | (np.isnan(a) & np.isnan(b))


def ulps(a, ref):
    return np.abs(a - ref) / np.spacing(np.abs(ref))


def test_exp():
    rng = np.random.default_rng(0)
    x = np.concatenate([-0.5 * rng.uniform(0, 40, 20000) ** 2, rng.uniform(-745, 709, 20000),
                        rng.uniform(-1, 1, 20000), [0.0, -0.0, -745.2, -744.9, 709.7, 1e-300]])
    got = exp(x)
    assert same_bits(got, [exp_scalar(v) for v in x.tolist()]).all()
    ref = np.array([math.exp(v) for v in x.tolist()])
    ok = ref > 0
    assert ulps(got[ok], ref[ok]).max() <= 1.0
    assert exp(-np.inf) == 0.0 and exp(np.inf) == np.inf and np.isnan(exp(np.nan))


def test_atan2():
    rng = np.random.default_rng(1)
    n = 30000
    y = rng.normal(size=n) * rng.choice([1e-300, 1e-8, 1.0, 10.0, 1e3, 1e20], n)
    x = rng.normal(size=n) * rng.choice([1e-300, 1e-3, 1.0, 10.0, 1e20], n)
    special = np.array([0.0, -0.0, 1.0, -1.0, np.inf, -np.inf, np.nan, 1e-320])
    sy, sx = np.meshgrid(special, special)
    y = np.concatenate([y, sy.ravel()])
    x = np.concatenate([x, sx.ravel()])
    got = atan2(y, x)
    pairs = list(zip(y.tolist(), x.tolist(), strict=True))
    assert same_bits(got, [atan2_scalar(p, q) for p, q in pairs]).all()
    ref = np.array([math.atan2(p, q) for p, q in pairs])
    assert same_bits(got[-special.size**2:], ref[-special.size**2:]).all()  # C semantics
    ok = np.isfinite(ref) & (ref != 0)
    assert ulps(got[ok], ref[ok]).max() <= 1.0
