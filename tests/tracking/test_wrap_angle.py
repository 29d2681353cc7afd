"""wrap_angle: range (-pi, pi], identity inside it, equivalence modulo 2 pi."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from it2track.tracking import wrap_angle

PI = math.pi


def test_end_points_and_known_values():
    a = np.array([PI, -PI, 3 * PI, -3 * PI, 2 * PI, -2 * PI, 0.0, -0.0, PI / 2, -PI / 2,
                  3 * PI / 2, 7.0, -7.0])  # fmt: skip
    expect = [PI, PI, PI, PI, 0.0, 0.0, 0.0, 0.0, PI / 2, -PI / 2, -PI / 2, 7 - 2 * PI,
              -7 + 2 * PI]  # fmt: skip
    assert np.allclose(wrap_angle(a), expect, rtol=0, atol=4e-15)
    assert wrap_angle(PI) == PI and wrap_angle(-PI) == PI  # exactly: pi is in, -pi is out


def test_just_outside_pi_stays_in_range():
    # pi + 1 ulp: the float modulo rounds up to 2 pi; the result must still not be -pi.
    for a in (np.nextafter(PI, 4.0), np.nextafter(-PI, -4.0), np.nextafter(3 * PI, 10.0),
              np.nextafter(-3 * PI, -10.0)):  # fmt: skip
        w = float(wrap_angle(a))
        assert -PI < w <= PI, f"wrap_angle({a!r}) = {w!r}"
        assert abs(math.remainder(w - a, 2 * PI)) < 1e-14, f"wrap_angle({a!r}) = {w!r}"


def test_shapes_and_no_mutation():
    a = np.array([[4.0, -4.0], [0.5, 10.0]])
    before = a.copy()
    w = wrap_angle(a)
    assert w.shape == (2, 2) and w is not a
    assert np.array_equal(a, before), "the input was modified"
    assert wrap_angle(1.0).shape == ()
    assert wrap_angle([1.0, 2.0]).tolist() == [1.0, 2.0]
    assert np.isnan(wrap_angle(np.nan))


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_property_range_and_equivalence(a):
    w = float(wrap_angle(a))
    assert -PI < w <= PI
    # a - w is a whole number of turns, up to the rounding of a (|a| eps) and of 2 pi
    turns = (a - w) / (2 * PI)
    assert abs(turns - round(turns)) * 2 * PI <= 8e-16 * (abs(a) + 4.0)
    assert float(wrap_angle(w)) == w, "not idempotent"


@given(st.floats(min_value=-PI, max_value=PI, exclude_min=True))
def test_property_identity_inside_the_range(a):
    assert float(wrap_angle(a)) == a


@given(arrays(np.float64, st.integers(0, 50), elements=st.floats(-100.0, 100.0)))
def test_property_elementwise(a):
    w = wrap_angle(a)
    assert np.array_equal(w, [float(wrap_angle(v)) for v in a])
