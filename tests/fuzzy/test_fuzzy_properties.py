"""Hypothesis property tests: 0 <= lower <= upper <= 1 for memberships and firing,
min(y) <= yl <= u <= yr <= max(y), odd symmetry of the paper controller, scalar == array path."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    IT2Set,
    TNorm,
    Trapezoid,
    Triangle,
    ZeroFiringError,
)
from it2track.paper import heading_fls

EXACT = (KM, EKM, EIASC, EXHAUSTIVE)
SETTINGS = settings(max_examples=150, deadline=None)

inputs = st.floats(-1.5, 1.5, allow_nan=False, allow_infinity=False)
fous = st.floats(0.0, 1.55, allow_nan=False)
unit = st.floats(0.0, 1.0, allow_nan=False)


#: t-norms positive wherever both arguments are: the paper's sets (every input in some set's
#: support on both inputs) then always fire a rule. Bounded difference, the drastic product and
#: the nilpotent minimum can be 0 for positive arguments (see test_zero_firing_norms).
POSITIVE_TNORMS = (TNorm.PRODUCT, TNorm.MINIMUM, TNorm.EINSTEIN_PRODUCT, TNorm.HAMACHER_PRODUCT)


@functools.cache
def paper(w: float, reducer=EXHAUSTIVE, tnorm=TNorm.PRODUCT):
    return heading_fls(w, reducer=reducer, tnorm=tnorm)


@st.composite
def it2_sets(draw):
    """Random IT2 sets from every constructor."""
    kind = draw(st.sampled_from(["tri", "trap", "scale_lag", "gauss_mean", "gauss_std"]))
    if kind in ("tri", "trap", "scale_lag"):
        n = 3 if kind != "trap" else 4
        # parameters on a 1e-3 grid (coinciding ones make shoulders)
        pts = sorted(v / 1000 for v in draw(st.lists(st.integers(-2000, 2000), min_size=n,
                                                        max_size=n)))
        if pts[-1] == pts[0]:
            pts[-1] = pts[0] + 1e-3
        h = draw(st.floats(0.05, 1.0))
        mf = Triangle(*pts, h=h) if n == 3 else Trapezoid(*pts, h=h)
        if kind == "scale_lag":
            return IT2Set.from_scale_lag(mf, scale=draw(st.floats(0.01, 1.0)),
                                         lag=draw(st.floats(0.0, 0.99)))
        a, b, c, d, _ = mf.as_trapezoid()
        widths = [v for v in (b - a, d - c) if v > 0]
        limit = 2 * min(widths) if widths else 1.0
        return IT2Set.from_fou(mf, draw(st.floats(0.0, 0.999)) * limit)
    m = draw(st.floats(-1, 1))
    s = draw(st.floats(0.01, 1))
    if kind == "gauss_mean":
        return IT2Set.gaussian_uncertain_mean(m, m + draw(st.floats(0, 0.5)), s)
    return IT2Set.gaussian_uncertain_std(m, s, s * draw(st.floats(1, 3)))


@SETTINGS
@given(s=it2_sets(), x=hnp.arrays(np.float64, 20, elements=st.floats(-3, 3)))
def test_memberships_are_ordered_in_unit_interval(s, x):
    lower, upper = s(x)
    assert np.all(lower >= 0.0)
    assert np.all(lower <= upper + 1e-12)
    assert np.all(upper <= 1.0)


@SETTINGS
@given(w=fous, e=inputs, de=inputs, tnorm=st.sampled_from(list(TNorm)))
def test_firing_is_ordered_in_unit_interval(w, e, de, tnorm):
    lower, upper = paper(w, tnorm=tnorm).firing(e, de)
    assert lower.shape == upper.shape == (9,)
    assert np.all(lower >= 0.0) and np.all(lower <= upper) and np.all(upper <= 1.0)
    if tnorm in POSITIVE_TNORMS:
        assert upper.sum() > 0.0  # the paper's sets cover the universe


def test_zero_firing_norms():
    """At e = de = 0.5 the type-1 paper sets give Z = P = 0.375 on each input: every rule's
    bounded difference is max(0, 0.375 + 0.375 - 1) = 0 and the nilpotent minimum (0 where
    a + b <= 1) is 0, so no rule fires; the drastic product is 0 unless an argument is 1. The
    product fires the four rules on Z, P at 0.375**2."""
    for tnorm in (TNorm.BOUNDED_DIFFERENCE, TNorm.NILPOTENT_MINIMUM, TNorm.DRASTIC_PRODUCT):
        lower, upper = paper(0.0, tnorm=tnorm).firing(0.5, 0.5)
        assert upper.tolist() == [0.0] * 9 and lower.tolist() == [0.0] * 9, tnorm
        with pytest.raises(ZeroFiringError, match="no rule"):
            paper(0.0, tnorm=tnorm)(0.5, 0.5)
    _, upper = paper(0.0).firing(0.5, 0.5)
    assert sorted(upper.tolist())[-4:] == pytest.approx([0.375 ** 2] * 4, rel=1e-15)
    assert sorted(upper.tolist())[:5] == [0.0] * 5


@SETTINGS
@given(w=fous, e=inputs, de=inputs, red=st.sampled_from(EXACT))
def test_output_inside_interval_inside_consequent_range(w, e, de, red):
    fls = paper(w, red)
    yl, yr = (float(v) for v in fls.interval(e, de))
    u = float(fls(e, de))
    tol = 1e-12
    assert -12.0 - tol <= yl <= u + tol
    assert u <= yr + tol <= 12.0 + 2 * tol
    assert abs(u - (yl + yr) / 2) <= tol
    # every exact reducer gives the same interval
    ref = [float(v) for v in paper(w, EXHAUSTIVE).interval(e, de)]
    assert abs(yl - ref[0]) <= tol and abs(yr - ref[1]) <= tol


@SETTINGS
@given(w=fous, e=inputs, de=inputs)
def test_type1_output_inside_the_it2_interval_of_its_centre_sets(w, e, de):
    # With the type-1 centre sets between the lower and upper MFs, the type-1 output is one of
    # the embedded centroids, so it lies inside [yl, yr].
    t1 = float(paper(0.0)(e, de))
    yl, yr = (float(v) for v in paper(w).interval(e, de))
    assert yl - 1e-12 <= t1 <= yr + 1e-12


@SETTINGS
@given(w=fous, e=inputs, de=inputs, red=st.sampled_from((*EXACT, NIE_TAN)),
       tnorm=st.sampled_from(list(TNorm)))
def test_paper_controller_is_odd(w, e, de, red, tnorm):
    fls = paper(w, red, tnorm)
    try:
        u = float(fls(e, de))
    except ZeroFiringError:  # only a norm that can vanish; then at (-e, -de) as well
        assert tnorm not in POSITIVE_TNORMS
        with pytest.raises(ZeroFiringError):
            fls(-e, -de)
        return
    assert abs(u + float(fls(-e, -de))) <= 1e-12


@SETTINGS
@given(w=st.sampled_from([0.0, 0.1, 0.2, 0.3]) | fous, e=inputs, de=inputs,
       tnorm=st.sampled_from(list(TNorm)))
def test_scalar_path_equals_array_path(w, e, de, tnorm):
    fls = paper(w, tnorm=tnorm)
    try:
        fast = fls(e, de)
    except ZeroFiringError:  # the array path refuses the same point
        assert tnorm not in POSITIVE_TNORMS
        with pytest.raises(ZeroFiringError):
            fls(np.array([e]), np.array([de]))
        return
    assert type(fast) is float
    assert fast == float(fls(np.array([e]), np.array([de]))[0])


@st.composite
def reducer_inputs(draw):
    r = draw(st.integers(1, 12))
    fu = draw(hnp.arrays(np.float64, (8, r), elements=unit))
    t = draw(hnp.arrays(np.float64, (8, r), elements=unit))
    fl = fu * t
    # Subnormal firing strengths lose precision (see test_subnormal_firing_...): keep them out.
    tiny = np.finfo(np.float64).tiny
    fl[fl < tiny] = 0.0
    fu[fu < tiny] = 0.0
    fu[:, 0] = np.maximum(fu[:, 0], 1e-3)  # something fires
    y_lo = draw(hnp.arrays(np.float64, r, elements=st.floats(-100, 100)))
    dy = draw(hnp.arrays(np.float64, r, elements=st.floats(0, 10)))
    return fl, fu, y_lo, y_lo + dy


@SETTINGS
@given(args=reducer_inputs())
def test_reducers_stay_in_consequent_range_and_agree(args):
    fl, fu, y_lo, y_hi = args
    tol = 1e-12 * max(1.0, np.abs(y_hi).max(), np.abs(y_lo).max())
    ref_l, ref_r = EXHAUSTIVE(fl, fu, y_lo, y_hi)
    for red in EXACT:
        yl, yr = red(fl, fu, y_lo, y_hi)
        assert np.all(y_lo.min() - tol <= yl) and np.all(yl <= yr + tol)
        assert np.all(yr <= y_hi.max() + tol)
        assert np.all(np.abs(yl - ref_l) <= 8 * tol) and np.all(np.abs(yr - ref_r) <= 8 * tol)
    y, _ = NIE_TAN(fl, fu, y_lo, y_hi)
    assert np.all(y_lo.min() - tol <= y) and np.all(y <= y_hi.max() + tol)


@pytest.mark.xfail(
    strict=True,
    reason="known limitation: with only subnormal (< 2.2e-308) lower firing the all-lower "
    "centroid fl*y/fl is computed with a few significant bits and can exceed max(y) by ~1e-4",
)
def test_subnormal_firing_keeps_the_consequent_range():
    fl, fu = np.array([[1.1126e-320]]), np.array([[0.001]])
    _, yr = EXHAUSTIVE(fl, fu, [0.0], [1.625])
    assert float(yr) <= 1.625
