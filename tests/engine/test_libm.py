"""exp, log, cos(pi u) and atan2 of fuzzy.libm / tracking.libm: the numpy and scalar forms give
the same bits (what makes the numpy and compiled engines agree), within 1 ulp of the C library."""

import math

import numpy as np

from it2track.fuzzy.libm import cospi, cospi_scalar, exp, exp_scalar, log, log_scalar
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


def test_log():
    rng = np.random.default_rng(2)
    x = np.concatenate([rng.uniform(0, 4, 20000), np.exp(rng.uniform(-700, 700, 20000)),
                        1 + rng.uniform(-1e-6, 1e-6, 5000), [1.0, 2.0, 0.5, 1e-310, 5e-324,
                                                            np.sqrt(0.5), np.sqrt(2), 1e308]])
    got = log(x)
    assert same_bits(got, [log_scalar(v) for v in x.tolist()]).all()
    ref = np.array([math.log(v) for v in x.tolist()])
    ok = ref != 0
    assert ulps(got[ok], ref[ok]).max() <= 1.0
    assert log(1.0) == 0.0 and log(2.0**10) == 10 * log(2.0)  # exact powers of two
    special = np.array([0.0, -0.0, -1.0, np.inf, -np.inf, np.nan])
    assert same_bits(log(special), [-np.inf, -np.inf, np.nan, np.inf, np.nan, np.nan]).all()
    assert same_bits(log(special), [log_scalar(v) for v in special.tolist()]).all()


def test_cospi():
    rng = np.random.default_rng(3)
    u = np.concatenate([rng.uniform(-1, 1, 40000), np.linspace(-1, 1, 4001),
                        [0.25, 0.75, -0.25, -0.75, 2.0**-60]])
    got = cospi(u)
    assert same_bits(got, [cospi_scalar(v) for v in u.tolist()]).all()
    # against the C library's cos of the same argument pi |u| where no reduction is needed
    near = np.abs(u) <= 0.25
    ref = np.array([math.cos(math.pi * abs(v)) for v in u[near].tolist()])
    assert ulps(got[near], ref).max() <= 1.0
    np.testing.assert_allclose(got, np.cos(np.pi * u), rtol=0, atol=4.5e-16)
    assert cospi([0.0, 0.5, -0.5, 1.0, -1.0]).tolist() == [1.0, 0.0, 0.0, -1.0, -1.0]
    assert (np.abs(cospi(np.linspace(-1, 1, 2001))) <= 1.0).all()
