"""The lowering of a system to arrays (SystemTables): the contract compiled kernels and code
generators read. Checked by re-evaluating the documented formulas independently."""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track import heading_fls
from it2track.fuzzy import (
    Gaussian,
    Input,
    IT2Set,
    IT2Sugeno,
    MFKind,
    Rule,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)


def _row_value(kind: int, p: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The documented meaning of an MFKind row, written out independently."""
    if kind == MFKind.TRAPEZOID:
        a, wl, d, wr, h = p
        left = np.ones_like(x) if math.isinf(a) else (x - a) / wl
        right = np.ones_like(x) if math.isinf(d) else (d - x) / wr
        return h * np.clip(np.minimum(left, right), 0.0, 1.0)
    if kind == MFKind.GAUSSIAN:
        mean, sigma, h = p[:3]
        return h * np.exp(-0.5 * ((x - mean) / sigma) ** 2)
    m1, m2, sigma, h = p[:4]
    if kind == MFKind.UM_GAUSSIAN_UPPER:
        centre = np.clip(x, m1, m2)
    else:
        centre = np.where(x <= 0.5 * (m1 + m2), m2, m1)
    return h * np.exp(-0.5 * ((x - centre) / sigma) ** 2)


def _firing_from_tables(fls: IT2Sugeno, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    t = fls.tables
    xc = np.clip(x, t.lo, t.hi)
    rows = np.ones((t.n_rows + 1, x.shape[0]))
    for k in range(t.n_rows):
        rows[k] = _row_value(int(t.mf_kind[k]), t.mf_params[k], xc[:, t.mf_input[k]])
    fl = np.prod(rows[t.lower_rows], axis=1)  # (R, n_in, N) -> (R, N)
    fu = np.prod(rows[t.upper_rows], axis=1)
    return fl.T, fu.T


def _mixed_system() -> IT2Sugeno:
    x_sets = [
        IT2Set(Trapezoid(-2, -1, 0, 1), Trapezoid(-1.5, -1, 0, 0.5, 0.8), "A"),
        IT2Set.from_fou(Triangle(0, 1, 1), 0.3, "B"),
        IT2Set.from_fou(Triangle(-2, -2, 0), 0.2, "C"),
    ]
    y_sets = [
        IT2Set(Gaussian(0.0, 1.0), Gaussian(0.0, 0.6, 0.9), "G"),
        IT2Set(UncertainMeanGaussianUpper(0.5, 1.0, 0.4),
               UncertainMeanGaussianLower(0.5, 1.0, 0.4, 0.7), "U"),
    ]
    return IT2Sugeno(
        inputs=[Input("x", (-2, 2), x_sets), Input("y", (-2, 2), y_sets)],
        rules=[Rule(["A", "G"], (-1, -0.5)), Rule(["B", None], 2.0), Rule(["C", "U"], (0, 1)),
               Rule([None, "U"], 0.25), Rule(["A", "U"], (1, 3))],
    )


def test_paper_controller_rows_are_trapezoids_with_shoulders_at_infinity() -> None:
    t = heading_fls(0.2).tables
    assert t.n_inputs == 2 and t.n_rules == 9
    # Both inputs share the same three sets, one row per distinct MF and input.
    assert t.n_rows == 12
    assert set(t.mf_kind.tolist()) == {int(MFKind.TRAPEZOID)}
    n_upper = t.mfs.index(heading_fls(0.2).inputs[0].sets[0].upper)
    a, wl, d, wr, h = t.mf_params[n_upper]
    assert a == -math.inf and wl == 1.0 and d == pytest.approx(-0.1) and h == 1.0
    assert wr == pytest.approx(0.9)  # from the peak -1 to the foot -0.1
    assert t.features == frozenset()
    assert not t.type1 and t.crisp
    assert heading_fls(0.0).tables.type1


@pytest.mark.parametrize("make", [lambda: heading_fls(0.3), _mixed_system],
                         ids=["paper", "mixed-shapes"])
def test_tables_reproduce_the_firing_strengths(make) -> None:
    fls = make()
    x = np.random.default_rng(3).uniform(-2.5, 2.5, (500, fls.n_inputs))
    fl, fu = _firing_from_tables(fls, x)
    lower, upper = fls.firing(*x.T)
    np.testing.assert_allclose(fl, lower, rtol=0, atol=1e-15)
    np.testing.assert_allclose(fu, upper, rtol=0, atol=1e-15)


def test_sorted_views_are_consistent() -> None:
    t = _mixed_system().tables
    np.testing.assert_array_equal(t.y_lo_s, t.y_lo[t.perm])
    np.testing.assert_array_equal(t.upper_rows_s, t.upper_rows[t.perm])
    assert np.all(np.diff(t.y_lo_s) >= 0)
    assert np.all(np.diff(t.y_hi_s[t.order_hi_s]) >= 0)


def test_an_arbitrary_callable_is_encoded_as_other() -> None:
    def bump(x):
        return np.exp(-np.asarray(x, float) ** 2)

    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), [IT2Set.type1(bump, "B")])],
                    rules=[Rule(["B"], 1.0)])
    assert fls.tables.mf_kind.tolist() == [int(MFKind.OTHER)]
