"""Hypothesis properties of every membership term of fuzzy.curves / fuzzy.shapes: degrees in
[0, h], the documented monotonicity and symmetry, MATLAB's type-2 lower MF between 0 and the
upper MF; and every bad parameter refused with a message naming it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from it2track.fuzzy import (
    Arc,
    Bell,
    Binary,
    Concave,
    Cosine,
    Discrete,
    GaussianProduct,
    Input,
    IT2Set,
    LinearSShape,
    LinearZShape,
    PiShape,
    Ramp,
    Rectangle,
    SemiEllipse,
    Sigmoid,
    SigmoidDifference,
    SigmoidProduct,
    Spike,
    SShape,
    ZShape,
)

SETTINGS = settings(max_examples=120, deadline=None)
coord = st.floats(-5, 5, allow_nan=False).map(lambda v: round(v, 3))
width = st.floats(0.01, 5).map(lambda v: round(v, 3) or 0.01)
slope = st.floats(0.1, 10).map(lambda v: round(v, 2) or 0.1)
height = st.sampled_from([1.0, 0.8, 0.5, 0.25])
X = np.linspace(-12, 12, 2401)


@st.composite
def ordered(draw, n, strict=True):
    values = sorted(draw(st.lists(coord, min_size=n, max_size=n)))
    for k in range(1, n):
        if strict and values[k] <= values[k - 1]:
            values[k] = values[k - 1] + 0.01
    return values


@st.composite
def terms(draw):
    """Any term, from every class, with valid parameters."""
    kind = draw(st.sampled_from(list(MAKERS)))
    return MAKERS[kind](draw)


MAKERS = {
    "bell": lambda d: Bell(d(coord), d(width) * d(st.sampled_from([1, -1])), d(slope),
                           d(height)),
    "sigmoid": lambda d: Sigmoid(d(coord), d(slope) * d(st.sampled_from([1, -1])), d(height)),
    "dsig": lambda d: SigmoidDifference(*d(ordered(2))[:1], d(slope), d(slope),
                                        d(coord), d(height)),
    "psig": lambda d: SigmoidProduct(d(coord), d(slope), -d(slope), d(coord), d(height)),
    "s": lambda d: SShape(*d(ordered(2)), d(height)),
    "z": lambda d: ZShape(*d(ordered(2)), d(height)),
    "pi": lambda d: PiShape(*_pi(d(ordered(4, strict=False))), d(height)),
    "g2": lambda d: GaussianProduct(d(coord), d(width), d(coord), d(width), d(height)),
    "cos": lambda d: Cosine(d(coord), d(width), d(height)),
    "spike": lambda d: Spike(d(coord), d(width), d(height)),
    "concave": lambda d: Concave(*_distinct(d(coord), d(coord)), d(height)),
    "ramp": lambda d: Ramp(*_distinct(d(coord), d(coord)), d(height)),
    "rect": lambda d: Rectangle(*d(ordered(2)), d(height)),
    "binary": lambda d: Binary(d(coord), d(st.sampled_from([math.inf, -math.inf])), d(height)),
    "arc": lambda d: Arc(*_distinct(d(coord), d(coord)), d(height)),
    "ellipse": lambda d: SemiEllipse(*d(ordered(2)), d(height)),
    "lins": lambda d: LinearSShape(*d(ordered(2, strict=False)), d(height)),
    "linz": lambda d: LinearZShape(*d(ordered(2, strict=False)), d(height)),
    "discrete": lambda d: Discrete(list(zip(d(ordered(4, strict=False)),
                                            d(st.lists(st.floats(0, 1), min_size=4,
                                                       max_size=4)), strict=True)), d(height)),
}


def _pi(v):
    a, b, c, d = v
    b = max(b, a + 0.01)
    return a, b, max(c, b), max(d, max(c, b) + 0.01)


def _distinct(a, b):
    return (a, b) if a != b else (a, b + 0.5)


@SETTINGS
@given(terms())
def test_degrees_between_zero_and_height(term):
    y = term(X)
    assert y.shape == X.shape and y.dtype == np.float64
    assert ((y >= 0) & (y <= term.h)).all(), term
    k = int(np.searchsorted(X, 0.5))
    assert np.ndim(term(0.5)) == 0 and float(term(X[k])) == y[k]  # scalar call: same value


MONOTONIC = {  # +1 non-decreasing, -1 non-increasing
    "sigmoid": lambda t: 1 if t.slope > 0 else -1, "s": lambda t: 1, "z": lambda t: -1,
    "ramp": lambda t: 1 if t.start < t.end else -1,
    "concave": lambda t: 1 if t.inflection < t.end else -1,
    "arc": lambda t: 1 if t.start < t.end else -1, "lins": lambda t: 1, "linz": lambda t: -1,
    "binary": lambda t: 1 if t.direction > t.start else -1,
}


@SETTINGS
@given(st.sampled_from(sorted(MONOTONIC)), st.data())
def test_edge_terms_are_monotonic_and_invertible(kind, data):
    term = MAKERS[kind](data.draw)
    y = term(X)
    sign = MONOTONIC[kind](term)
    assert (sign * np.diff(y) >= -4.5e-16 * term.h).all(), term
    if hasattr(term, "inverse") and not (kind in ("lins", "linz") and term.a == term.b):
        w = np.linspace(0.05, 0.95, 19) * term.h
        np.testing.assert_allclose(term(term.inverse(w)), w, rtol=1e-9, atol=1e-12)


@SETTINGS
@given(st.data(), st.sampled_from(["bell", "cos", "spike", "ellipse", "g2", "pi", "dsig"]))
def test_symmetric_terms_are_symmetric_about_their_centre(data, kind):
    d = data.draw
    h = d(height)
    a, b = d(width), d(width)
    term = {"bell": lambda: Bell(0.0, a, d(slope), h), "cos": lambda: Cosine(0.0, a, h),
            "spike": lambda: Spike(0.0, a, h), "ellipse": lambda: SemiEllipse(-a, a, h),
            "g2": lambda: GaussianProduct(-a, b, a, b, h),
            "pi": lambda: PiShape(-a - b, -a, a, a + b, h),
            "dsig": lambda: SigmoidDifference(-a, 3.0, 3.0, a, h)}[kind]()
    y, mirrored = term(X), term(-X)
    if kind in ("bell", "cos", "spike", "ellipse", "g2"):
        assert (y == mirrored).all(), term  # to the bit: |x - 0| is exact
    else:
        np.testing.assert_allclose(y, mirrored, rtol=0, atol=1e-15)
    assert y.max() <= h and float(term(0.0)) == pytest.approx(y.max(), abs=1e-15)


@SETTINGS
@given(terms(), st.floats(0.05, 1.0), st.floats(0.0, 0.95))
def test_matlab_type2_lower_mf_stays_under_the_upper(term, scale, lag):
    s = IT2Set.from_scale_lag(term, scale=scale, lag=lag, name="A")
    lower, upper = s(X)
    assert ((lower >= 0) & (lower <= upper) & (upper <= 1)).all(), (term, scale, lag)
    assert lower.max() <= scale * term.h + 1e-15
    Input("x", (-12, 12), [s])  # the universe check agrees


BAD = [
    (lambda: Bell(0, 0, 2), r"Bell\(center=0, width=0, slope=2, h=1\.0\): width=0 must be != 0"),
    (lambda: Bell(0, 1, 0), r"slope=0 must be > 0"),
    (lambda: Bell(0, 1, -2), r"slope=-2 must be > 0"),
    (lambda: Bell(math.nan, 1, 2), r"parameter center=nan must be a finite number"),
    (lambda: Bell(0, 1, 2, h=0), r"height h=0 must satisfy 0 < h <= 1"),
    (lambda: Sigmoid(0, 0), r"slope=0 must be != 0"),
    (lambda: Sigmoid(math.inf, 1), r"parameter inflection=inf must be a finite number"),
    (lambda: SigmoidDifference(0, 0, 1, 1), r"rising=0 must be != 0"),
    (lambda: SigmoidProduct(0, 1, 0, 1), r"falling=0 must be != 0"),
    (lambda: SShape(1, 1), r"start=1 must be < end=1"),
    (lambda: ZShape(2, 1), r"start=2 must be < end=1"),
    (lambda: PiShape(0, 2, 1, 3), r"bottom_left < top_left <= top_right < bottom_right"),
    (lambda: PiShape(0, 0, 1, 3), r"bottom_left < top_left"),
    (lambda: GaussianProduct(0, 0, 1, 1), r"sigma_a=0 must be > 0"),
    (lambda: GaussianProduct(0, 1, 1, -1), r"sigma_b=-1 must be > 0"),
    (lambda: Cosine(0, 0), r"width=0 must be > 0"),
    (lambda: Spike(0, 0), r"width=0 must be != 0"),
    (lambda: Concave(1, 1), r"inflection=1 must differ from end"),
    (lambda: Ramp(1, 1), r"start=1 must differ from end"),
    (lambda: Rectangle(1, 1), r"start=1 must be < end=1"),
    (lambda: Binary(1, 1), r"direction=1 must differ from start"),
    (lambda: Binary(1, math.nan), r"parameter direction=nan must be a number"),
    (lambda: Binary(math.inf, 1), r"parameter start=inf must be a finite number"),
    (lambda: Arc(1, 1), r"start=1 must differ from end"),
    (lambda: SemiEllipse(2, 1), r"start=2 must be < end=1"),
    (lambda: LinearSShape(2, 1), r"a=2 must be <= b=1"),
    (lambda: LinearZShape(2, 1), r"a=2 must be <= b=1"),
    (lambda: Discrete([]), r"must be one or more \(x, y\) pairs"),
    (lambda: Discrete([(0, 0), (1,)]), r"must be one or more \(x, y\) pairs"),
    (lambda: Discrete([(1, 0), (0, 1)]), r"x2=0\.0 is below x1=1\.0; the points must be sorted"),
    (lambda: Discrete([(0, 0), (1, 1.5)]), r"y2=1\.5 must be in \[0, 1\]"),
    (lambda: Discrete([(0, math.nan)]), r"parameter y1=nan must be a finite number"),
    (lambda: Discrete([(0, 1)], h=2), r"height h=2 must satisfy 0 < h <= 1"),
]


@pytest.mark.parametrize(("make", "message"), BAD, ids=[m for _, m in BAD])
def test_bad_parameters_are_refused_naming_them(make, message):
    with pytest.raises(ValueError, match=message):
        make()
