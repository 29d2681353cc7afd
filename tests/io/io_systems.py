"""Shared builders for the io tests: random fuzzy systems that exercise every format.

A plain module (not conftest.py), imported by the test modules of this directory.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Gaussian,
    Input,
    IT2Set,
    IT2Sugeno,
    Rule,
    ScaledLagged,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)

DATA = Path(__file__).parent / "data"
REDUCERS = (KM, EKM, EIASC, EXHAUSTIVE, NIE_TAN, WU_MENDEL)


def _piecewise_set(rng: np.random.Generator, lo: float, hi: float, name: str) -> IT2Set:
    """A random triangle/trapezoid IT2 set whose lower MF is a LowerScale/LowerLag image."""
    width = hi - lo
    pts = np.sort(rng.uniform(lo - 0.2 * width, hi + 0.2 * width, 4))
    a, b, c, d = (float(v) for v in pts)
    shape = rng.integers(4)
    if shape == 0:  # left shoulder, possibly inside the universe
        b = a
    elif shape == 1:  # right shoulder
        c = d
    upper = Triangle(a, b, d) if rng.random() < 0.5 and shape != 1 else Trapezoid(a, b, c, d)
    ua, ub, uc, ud, _ = upper.as_trapezoid()
    lag_l, lag_r = (float(v) for v in rng.uniform(0.0, 0.9, 2))
    la = ua if ua == ub else ua + lag_l * (ub - ua)
    ld = ud if uc == ud else ud - lag_r * (ud - uc)
    scale = float(rng.uniform(0.3, 1.0))
    if isinstance(upper, Triangle):
        lower = Triangle(la, ub, ld, scale)
    else:
        lower = Trapezoid(la, ub, uc, ld, scale)
    return IT2Set(upper, lower, name)


def _gaussian_set(rng: np.random.Generator, lo: float, hi: float, name: str) -> IT2Set:
    """A Gaussian covering the whole universe, lower MF scaled: every point fires."""
    width = hi - lo
    upper = Gaussian(float(rng.uniform(lo, hi)), float(rng.uniform(0.4, 1.0) * width))
    return IT2Set(upper, Gaussian(upper.mean, upper.sigma, float(rng.uniform(0.3, 1.0))), name)


def random_system(seed: int, *, interval: bool = False, rich: bool = False,
                  type1: bool = False, identifiers: bool = False) -> IT2Sugeno | T1Sugeno:
    """A random three-input system (27 rules, full grid) with no zero-firing point.

    ``interval``: interval consequents; ``rich``: MFs only TOML can carry (uncertain-mean
    Gaussians, uncertain std, ScaledLagged with lag); ``type1``: a T1Sugeno; ``identifiers``:
    names without spaces or quotes (fuzzylite's, FML's).
    """
    rng = np.random.default_rng(seed)
    inputs = []
    for i in range(3):
        lo = float(rng.uniform(-3.0, 1.0))
        hi = lo + float(rng.uniform(0.5, 5.0))
        sets = [_gaussian_set(rng, lo, hi, "G"), _piecewise_set(rng, lo, hi, "P1"),
                _piecewise_set(rng, lo, hi, "P2" if identifiers else "P2 'quoted'")]
        if rich:
            m1 = float(rng.uniform(lo, hi))
            m2 = m1 + float(rng.uniform(0.0, 0.3)) * (hi - lo)
            sigma = float(rng.uniform(0.1, 0.5)) * (hi - lo)
            sets[1] = IT2Set(UncertainMeanGaussianUpper(m1, m2, sigma),
                             UncertainMeanGaussianLower(m1, m2, sigma), "UM")
            g = Gaussian(float(rng.uniform(lo, hi)), sigma * 2)
            sets[2] = IT2Set.gaussian_uncertain_std(g.mean, sigma, 2 * sigma, name="US")
            sets.append(IT2Set(g, ScaledLagged(g, 0.7, float(rng.uniform(0, 0.5))), "SL"))
        if type1:
            sets = [IT2Set.type1(s.upper, s.name) for s in sets]
        inputs.append(Input(f"x{i}", (lo, hi), sets))
    rules = []
    names = [[s.name for s in inp.sets] for inp in inputs]
    for a in names[0]:
        for b in names[1]:
            for c in names[2]:
                y = float(rng.normal(0.0, 5.0))
                consequent = (y, y + float(rng.uniform(0.0, 2.0))) if interval else y
                rules.append(Rule((a, b, c), consequent))
    rules.append(Rule((None, names[1][0], None), float(rng.normal())))  # a partial rule
    tnorm = TNorm.PRODUCT if rng.random() < 0.5 else TNorm.MINIMUM
    name = f"random_system_{seed}" if identifiers else f"random system {seed}"
    if type1:
        return T1Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, name=name)
    reducer = REDUCERS[int(rng.integers(len(REDUCERS)))]
    return IT2Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, reducer=reducer, name=name)


def random_points(system: IT2Sugeno | T1Sugeno, n: int = 10_000, seed: int = 0) -> list:
    """``n`` random points per input, 10 % beyond each universe (clipping is exercised)."""
    rng = np.random.default_rng(seed)
    out = []
    for inp in system.inputs:
        lo, hi = inp.universe
        pad = 0.1 * (hi - lo)
        out.append(rng.uniform(lo - pad, hi + pad, n))
    return out
