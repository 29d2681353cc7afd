"""Type-1 membership functions: values from their formulas, shoulders, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from it2track.fuzzy import (
    Gaussian,
    MembershipFunction,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
    gaussmf,
    trapmf,
    trimf,
)


def test_trimf_values_from_formula():
    # [a b c] = [-0.8 0 0.8]: (x - a)/(b - a) on the left, (c - x)/(c - b) on the right.
    x = np.array([-1.0, -0.8, -0.4, 0.0, 0.2, 0.8, 1.0])
    assert_allclose(trimf(x, -0.8, 0.0, 0.8), [0, 0, 0.5, 1, 0.75, 0, 0], rtol=0, atol=1e-15)


def test_trimf_height_scales():
    assert_allclose(trimf([-0.4, 0.0], -0.8, 0.0, 0.8, h=0.6), [0.3, 0.6], atol=1e-15)


def test_left_shoulder_is_height_beyond_the_peak():
    # a == b: value h for every x <= b, even left of a (IT2FLS-toolbox convention).
    x = np.array([-5.0, -1.0, -0.6, -0.2, 0.5])
    assert_allclose(trimf(x, -1, -1, -0.2), [1, 1, 0.5, 0, 0], atol=1e-15)
    assert_allclose(Triangle(-1, -1, -0.2, h=0.5)(x), [0.5, 0.5, 0.25, 0, 0], atol=1e-15)


def test_right_shoulder_is_height_beyond_the_peak():
    x = np.array([-0.5, 0.2, 0.6, 1.0, 5.0])
    assert_allclose(trimf(x, 0.2, 1, 1), [0, 0, 0.5, 1, 1], atol=1e-15)


def test_trapmf_plateau_and_sides():
    x = np.array([-1.0, -0.5, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0])
    assert_allclose(trapmf(x, -1, 0, 1, 2), [0, 0.5, 1, 1, 1, 0.5, 0, 0], atol=1e-15)


def test_trapezoid_shoulders_both_sides_is_constant():
    # a == b and c == d: both sides are shoulders, so the value is h everywhere.
    assert_allclose(Trapezoid(0, 0, 1, 1, h=0.7)([-3.0, 0.5, 4.0]), [0.7, 0.7, 0.7])


def test_triangle_is_trapezoid_with_equal_shoulders():
    x = np.linspace(-2, 2, 401)
    assert_array_equal(Triangle(-0.5, 0.25, 1.5, 0.9)(x), Trapezoid(-0.5, 0.25, 0.25, 1.5, 0.9)(x))


def test_mf_shape_is_preserved():
    x = np.zeros((3, 1, 4))
    for mf in (Triangle(-1, 0, 1), Trapezoid(-1, 0, 0.5, 1), Gaussian(0, 1),
               UncertainMeanGaussianUpper(-0.1, 0.1, 0.3),
               UncertainMeanGaussianLower(-0.1, 0.1, 0.3)):
        assert mf(x).shape == (3, 1, 4)
        assert isinstance(mf, MembershipFunction)
    assert np.ndim(trimf(0.5, -1, 0, 1)) == 0


def test_gaussmf_formula():
    x = np.array([-1.0, 0.0, 0.5, 2.0])
    expected = 0.8 * np.exp(-((x - 0.5) ** 2) / (2 * 0.25**2))
    assert_allclose(gaussmf(x, 0.5, 0.25, 0.8), expected, rtol=1e-15)
    assert gaussmf(0.5, 0.5, 0.25) == 1.0


def test_uncertain_mean_gaussian_upper_and_lower():
    m1, m2, s = -0.2, 0.3, 0.4
    up = UncertainMeanGaussianUpper(m1, m2, s)
    lo = UncertainMeanGaussianLower(m1, m2, s)
    x = np.array([-1.0, -0.2, 0.0, 0.05, 0.3, 1.2])

    def g(x, m):
        return math.exp(-0.5 * ((x - m) / s) ** 2)

    # Upper: the nearer mean's Gaussian outside [m1, m2], 1 between them.
    exp_up = [g(-1.0, m1), 1.0, 1.0, 1.0, 1.0, g(1.2, m2)]
    # Lower: the farther mean's Gaussian (the smaller of the two).
    exp_lo = [min(g(v, m1), g(v, m2)) for v in x]
    assert_allclose(up(x), exp_up, rtol=1e-15)
    assert_allclose(lo(x), exp_lo, rtol=1e-15)
    assert np.all(lo(x) <= up(x))


def test_breakpoints():
    assert Triangle(-1, 0, 2).breakpoints() == (-1.0, 0.0, 0.0, 2.0)
    assert Trapezoid(-1, 0, 1, 2).breakpoints() == (-1.0, 0.0, 1.0, 2.0)


@pytest.mark.parametrize(
    ("factory", "match"),
    [
        (lambda: Triangle(1, 0, 2), "a <= b <= c"),
        (lambda: Triangle(0, 2, 1), "a <= b <= c"),
        (lambda: Triangle(1, 1, 1), "a < c"),
        (lambda: Triangle(0, 0.5, 1, h=0), "height"),
        (lambda: Triangle(0, 0.5, 1, h=1.5), "height"),
        (lambda: Triangle(math.nan, 0.5, 1), "finite"),
        (lambda: Triangle(0, 0.5, math.inf), "finite"),
        (lambda: Triangle("0", 0.5, 1), "finite"),
        (lambda: Trapezoid(0, 2, 1, 3), "a <= b <= c <= d"),
        (lambda: Trapezoid(1, 1, 1, 1), "a < d"),
        (lambda: Trapezoid(0, 1, 2, 3, h=-0.1), "height"),
        (lambda: Gaussian(0, 0), "sigma"),
        (lambda: Gaussian(0, -1), "sigma"),
        (lambda: Gaussian(math.nan, 1), "finite"),
        (lambda: UncertainMeanGaussianUpper(0.3, 0.1, 1), "m1 <= m2"),
        (lambda: UncertainMeanGaussianLower(0.0, 0.1, 0), "sigma"),
    ],
)
def test_malformed_membership_functions_raise(factory, match):
    with pytest.raises(ValueError, match=match):
        factory()


def test_mfs_are_frozen_and_hashable():
    t = Triangle(-1, 0, 1)
    assert t == Triangle(-1.0, 0.0, 1.0)
    assert hash(t) == hash(Triangle(-1.0, 0.0, 1.0))
    with pytest.raises(AttributeError):
        t.a = 0.5  # type: ignore[misc]


def test_footed_trapezoid_is_zero_beyond_a_vertical_side() -> None:
    from it2track.fuzzy import FootedTrapezoid, Trapezoid

    f = FootedTrapezoid(1.0, 1.0, 2.0, 3.0, 0.5)
    x = np.array([0.999, 1.0, 1.5, 2.5, 3.0, 3.001])
    np.testing.assert_allclose(f(x), [0.0, 0.5, 0.5, 0.25, 0.0, 0.0], rtol=0, atol=1e-15)
    g = FootedTrapezoid(0.0, 1.0, 2.0, 2.0)  # right side vertical: h at d, 0 just after
    assert g(np.array([2.0, 2.0 + 1e-12])).tolist() == [1.0, 0.0]
    inside = np.linspace(1.0, 3.0, 21)
    np.testing.assert_array_equal(f(inside), Trapezoid(1.0, 1.0, 2.0, 3.0, 0.5)(inside))
    with pytest.raises(ValueError, match="a <= b <= c <= d"):
        FootedTrapezoid(2.0, 1.0, 3.0, 4.0)
