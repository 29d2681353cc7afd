"""Interval type-2 sets: the paper's Tables 1 and 4, MATLAB scale/lag, lower <= upper checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from it2track.fuzzy import (
    Gaussian,
    Input,
    IT2Set,
    ScaledLagged,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)
from it2track.paper import CENTRE_SETS

# The paper's Table 1 (w = 0.2) and Table 4 (w = 0.1, 0.3), as printed: set -> ([upper a b c],
# [lower a b c]). Exact decimal values; from_fou must give exactly these floats.
PAPER_TABLES = {
    0.1: {
        "N": ([-1, -1, -0.15], [-1, -1, -0.25]),
        "Z": ([-0.85, 0, 0.85], [-0.75, 0, 0.75]),
        "P": ([0.15, 1, 1], [0.25, 1, 1]),
    },
    0.2: {
        "N": ([-1, -1, -0.1], [-1, -1, -0.3]),
        "Z": ([-0.9, 0, 0.9], [-0.7, 0, 0.7]),
        "P": ([0.1, 1, 1], [0.3, 1, 1]),
    },
    0.3: {
        "N": ([-1, -1, -0.05], [-1, -1, -0.35]),
        "Z": ([-0.95, 0, 0.95], [-0.65, 0, 0.65]),
        "P": ([0.05, 1, 1], [0.35, 1, 1]),
    },
}


@pytest.mark.parametrize("w", sorted(PAPER_TABLES))
@pytest.mark.parametrize("label", ["N", "Z", "P"])
def test_from_fou_reproduces_paper_tables_exactly(w, label):
    s = IT2Set.from_fou(CENTRE_SETS[label], w, label)
    upper, lower = PAPER_TABLES[w][label]
    assert isinstance(s.upper, Triangle) and isinstance(s.lower, Triangle)
    got_upper = [s.upper.a, s.upper.b, s.upper.c, s.upper.h]
    got_lower = [s.lower.a, s.lower.b, s.lower.c, s.lower.h]
    assert got_upper == [*upper, 1.0], f"w={w} {label} upper {got_upper} != table {upper}"
    assert got_lower == [*lower, 1.0], f"w={w} {label} lower {got_lower} != table {lower}"
    assert s.name == label


def test_from_fou_equals_toolbox_triangle_constructor():
    s = IT2Set.from_fou(Triangle(-0.8, 0, 0.8), 0.2, "Z")
    t = IT2Set.triangle([-0.9, 0, 0.9, 1], [-0.7, 0, 0.7], "Z")
    assert (s.upper, s.lower) == (t.upper, t.lower)


def test_from_fou_zero_width_is_type1():
    s = IT2Set.from_fou(Triangle(-0.8, 0, 0.8), 0.0, "Z")
    assert s.is_type1
    assert s.upper == Triangle(-0.8, 0, 0.8)


def test_from_fou_trapezoid_moves_only_sloped_feet():
    s = IT2Set.from_fou(Trapezoid(-1, -1, 0.2, 0.6), 0.2)
    assert s.upper == Trapezoid(-1, -1, 0.2, 0.7)
    assert s.lower == Trapezoid(-1, -1, 0.2, 0.5)


@pytest.mark.parametrize("w", [-0.1, math.nan, math.inf, 1.6, 1.7])
def test_from_fou_rejects_bad_widths(w):
    # Z = [-0.8 0 0.8]: a width above 1.6 would push the lower feet past the peak.
    with pytest.raises(ValueError, match="FoU width"):
        IT2Set.from_fou(Triangle(-0.8, 0, 0.8), w, "Z")


def test_from_fou_width_limit_is_exclusive():
    # Triangle(-1, 0, 2): left side 1 wide, right side 2 wide, so w must stay below 2. At w = 2
    # the lower MF's left foot would reach the peak and the side become a shoulder (1 for every
    # x <= 0), far above the upper MF.
    assert IT2Set.from_fou(Triangle(-1, 0, 2), 1.999).lower.a == pytest.approx(-0.0005)
    with pytest.raises(ValueError, match="must be less than 2"):
        IT2Set.from_fou(Triangle(-1, 0, 2), 2.0)
    # a shoulder side does not limit the width
    assert IT2Set.from_fou(Triangle(-1, -1, 2), 5.9).lower == Triangle(-1, -1, -0.95)
    with pytest.raises(ValueError, match="must be less than 6"):
        IT2Set.from_fou(Triangle(-1, -1, 2), 6.0)


def test_from_scale_lag_matlab_example():
    # MATLAB fismftype2 "LowerScale 0.8, LowerLag 0.3" on trimf [5 7 9]: the lower MF is zero
    # where the upper MF is below 0.3 (x < 5.6 or x > 8.4) and peaks at 0.8 at x = 7.
    s = IT2Set.from_scale_lag(Triangle(5, 7, 9), scale=0.8, lag=0.3)
    assert s.lower == Trapezoid(5.6, 7, 7, 8.4, 0.8)
    x = np.linspace(3, 11, 8001)
    up, lo = s.upper(x), s.lower(x)
    assert np.all(lo[up < 0.3] == 0), "lower MF must be 0 where the upper MF is below the lag"
    assert np.all(lo[up > 0.3 + 1e-9] > 0)
    assert s.lower(7.0) == 0.8
    assert float(lo.max()) == 0.8
    assert np.all(lo <= up)
    # Between the lag point and the peak the lower MF is scale * (upper - lag) / (1 - lag).
    mid = (up >= 0.3)
    assert_allclose(lo[mid], 0.8 * (up[mid] - 0.3) / 0.7, atol=1e-12)


def test_from_scale_lag_two_sided_lag_and_non_linear_upper():
    s = IT2Set.from_scale_lag(Trapezoid(0, 1, 2, 4), scale=1.0, lag=[0.5, 0.25])
    assert s.lower == Trapezoid(0.5, 1, 2, 3.5, 1.0)
    g = IT2Set.from_scale_lag(Gaussian(0, 1), scale=0.5, lag=0.2)
    assert isinstance(g.lower, ScaledLagged)
    x = np.linspace(-4, 4, 101)
    assert_allclose(g.lower(x), 0.5 * np.clip((g.upper(x) - 0.2) / 0.8, 0, 1))
    assert g.lower(0.0) == 0.5


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"scale": 0.0}, "LowerScale"),
        ({"scale": 1.5}, "LowerScale"),
        ({"lag": 1.0}, "LowerLag"),
        ({"lag": -0.1}, "LowerLag"),
        ({"lag": [0.1, 0.2, 0.3]}, "LowerLag"),
    ],
)
def test_from_scale_lag_rejects_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        IT2Set.from_scale_lag(Triangle(5, 7, 9), **kwargs)


def test_from_scale_lag_two_sided_lag_needs_piecewise_linear():
    with pytest.raises(ValueError, match="two-sided"):
        IT2Set.from_scale_lag(Gaussian(0, 1), lag=[0.1, 0.2])


def test_gaussian_constructors():
    um = IT2Set.gaussian_uncertain_mean(-0.1, 0.2, 0.3, "G")
    assert isinstance(um.upper, UncertainMeanGaussianUpper)
    assert isinstance(um.lower, UncertainMeanGaussianLower)
    us = IT2Set.gaussian_uncertain_std(0.0, 0.2, 0.4, "G")
    assert us.upper == Gaussian(0.0, 0.4) and us.lower == Gaussian(0.0, 0.2)
    with pytest.raises(ValueError, match="sigma1"):
        IT2Set.gaussian_uncertain_std(0.0, 0.4, 0.2)


def test_call_returns_lower_then_upper():
    s = IT2Set.triangle([-0.9, 0, 0.9], [-0.7, 0, 0.7], "Z")
    lo, up = s(np.array([0.35]))
    assert_allclose(up, [1 - 0.35 / 0.9])
    assert_allclose(lo, [1 - 0.35 / 0.7])


def test_lower_above_upper_is_rejected_with_the_place():
    # Lower triangle wider than the upper one: lower > upper near the feet.
    bad = IT2Set.triangle([-0.7, 0, 0.7], [-0.9, 0, 0.9], "Z")
    with pytest.raises(ValueError, match=r"input 'e' set 'Z': lower MF .* exceeds upper MF"):
        Input("e", (-1, 1), [bad])
    with pytest.raises(ValueError, match="exceeds upper"):
        IT2Set(bad.upper, bad.lower, "Z", universe=(-1.0, 1.0))


def test_lower_taller_than_upper_is_rejected():
    with pytest.raises(ValueError, match="exceeds upper"):
        IT2Set(Triangle(-1, 0, 1, h=0.5), Triangle(-0.5, 0, 0.5, h=0.9), "Z", universe=(-1, 1))


def test_mf_outside_unit_interval_is_rejected():
    def too_high(x):
        return 1.5 * np.ones_like(np.asarray(x, dtype=float))

    with pytest.raises(ValueError, match=r"outside \[0, 1\]"):
        IT2Set(too_high, Triangle(-1, 0, 1), "X", universe=(-1, 1))

    def nan_mf(x):
        return np.full_like(np.asarray(x, dtype=float), np.nan)

    with pytest.raises(ValueError, match=r"outside \[0, 1\]"):
        IT2Set(nan_mf, nan_mf, "X", universe=(-1, 1))


def test_lower_above_upper_between_grid_points_is_found_at_breakpoints():
    # The violation is confined to [0.3, 0.3 + 1e-9]: a grid alone would miss it, the breakpoint
    # check cannot.
    upper = Trapezoid(-1, -1, 0.3, 0.3 + 2e-9)
    lower = Triangle(-1, 0.3 + 1e-9, 0.3 + 1e-9 + 1e-12, h=1.0)
    with pytest.raises(ValueError, match="exceeds upper"):
        IT2Set(upper, lower, "S", universe=(-1, 1))


@pytest.mark.parametrize(
    ("upper", "lower", "match"),
    [
        ([0, 1], [0, 0.5, 1], "must have 3 values"),
        ([0, 0.5, 1, 1, 1], [0, 0.5, 1], "must have 3 values"),
        ([1, 0.5, 0], [0, 0.5, 1], "upper MF"),
        ([0, 0.5, 1], [0, 0.5, 1, 2], "lower MF"),
    ],
)
def test_malformed_triangle_parameters(upper, lower, match):
    with pytest.raises(ValueError, match=match):
        IT2Set.triangle(upper, lower, "S")


def test_malformed_trapezoid_parameters():
    with pytest.raises(ValueError, match="must have 4 values"):
        IT2Set.trapezoid([0, 1, 2], [0, 1, 2, 3])
    with pytest.raises(ValueError, match="lower MF"):
        IT2Set.trapezoid([0, 1, 2, 3], [0, 2, 1, 3])


def test_non_callable_mf_is_rejected():
    with pytest.raises(ValueError, match="callable"):
        IT2Set(Triangle(-1, 0, 1), 0.5, "S")  # type: ignore[arg-type]


def test_type1_set():
    mf = Triangle(-1, 0, 1)
    s = IT2Set.type1(mf, "Z")
    assert s.is_type1
    lo, up = s(np.linspace(-1, 1, 5))
    assert_array_equal(lo, up)
    assert not IT2Set.from_fou(mf, 0.1).is_type1


@pytest.mark.parametrize("foot", [2 / 3, -0.1234567890123456, 1e-17])
def test_scale_lag_keeps_shoulders_with_awkward_floats(foot):
    # A left shoulder at a foot with no short decimal form stays a shoulder (value = scale
    # everywhere left of the peak), and the right foot moves to where upper == lag.
    s = IT2Set.from_scale_lag(Triangle(foot, foot, 0.9), scale=0.9, lag=0.2)
    assert s.lower.a == s.lower.b == foot
    assert s.lower(foot - 1.0) == pytest.approx(0.9)
    assert s.lower.d == pytest.approx(0.9 - 0.2 * (0.9 - foot))


def test_scale_lag_gaussian_matches_the_triangle_rule_for_lower_heights():
    # For an upper MF of height h the lower MF peaks at scale*h and starts where upper = lag*h,
    # whether it is built as a trapezoid (triangle upper) or as ScaledLagged (Gaussian upper).
    tri = IT2Set.from_scale_lag(Triangle(-1, 0, 1, 0.5), scale=0.8, lag=0.25)
    gau = IT2Set.from_scale_lag(Gaussian(0.0, 0.4, 0.5), scale=0.8, lag=0.25)
    assert float(tri.lower(0.0)) == pytest.approx(0.4)
    assert float(gau.lower(0.0)) == pytest.approx(0.4)
    x = np.linspace(-2, 2, 401)
    up = gau.upper(x)
    assert np.all(gau.lower(x)[up <= 0.25 * 0.5] == 0.0)
    assert np.all(gau.lower(x) <= up + 1e-15)
