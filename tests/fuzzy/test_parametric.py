"""Terms whose parameters are inputs (it2track.fuzzy.parametric): jFuzzyLogic's piecewise
linear formula and the Gaussian, per sample, in closed form; a system with one evaluates each
sample with that sample's parameters (the bits of the fixed term there), in the batch and the
scalar path; fixed systems are untouched and the compiled engine leaves it to numpy."""

from __future__ import annotations

import math

import numpy as np
import pytest

from it2track.fuzzy import (
    Gaussian,
    Input,
    Parametric,
    Ref,
    Rule,
    T1Sugeno,
    Trapezoid,
    gaussmf,
)
from it2track.fuzzy import kernels as _kernels

TRIANGLE = Parametric("points", (Ref(1, "lo"), 0.0, Ref(2, "mid"), 1.0, Ref(3, "hi"), 0.0),
                      "middle")


def block(*rows: list[float]) -> np.ndarray:
    return np.array(rows, dtype=np.float64)


def test_points_triangle_per_sample_in_closed_form() -> None:
    # v, lo, mid, hi per sample; jFuzzyLogic: y0 at or below x0, yn above xn, else
    # y_{k-1} + (y_k - y_{k-1}) * ((v - x_{k-1}) / (x_k - x_{k-1})) on the first x_k >= v
    v = [1.0, 6.0, 5.0, -1.0, 9.0, 0.0, 4.0, 8.0, 3.0]
    lo = [0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0]
    mid = [4.0, 4.0, 3.0, 4.0, 4.0, 4.0, 4.0, 4.0, 3.0]
    hi = [8.0, 8.0, 7.0, 8.0, 8.0, 8.0, 8.0, 8.0, 7.0]
    got = TRIANGLE.evaluate(block(v, lo, mid, hi), 0)
    assert got.tolist() == [0.25, 0.5, 0.5, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0]


def test_points_outside_take_the_end_degrees_and_a_repeated_x_takes_the_left_segment() -> None:
    shoulder = Parametric("points", (Ref(1, "a"), 1.0, Ref(2, "b"), 0.0), "cold")
    x = block([-5.0, 20.0, 3.0], [0.0, 0.0, 2.0], [10.0, 10.0, 6.0])
    assert shoulder.evaluate(x, 0).tolist() == [1.0, 0.0, 0.75]
    # a vertical step at x = 1: v = 1 is on the first segment (v <= x_1), degree 1
    step = Parametric("points", (0.0, 0.0, Ref(1, "s"), 1.0, Ref(1, "s"), 0.0, 2.0, 0.0))
    assert step.evaluate(block([1.0, 1.5, 0.5], [1.0, 1.0, 1.0]), 0).tolist() == [1.0, 0.0, 0.5]
    # degrees given by an input
    level = Parametric("points", (0.0, Ref(1, "h"), 10.0, Ref(1, "h")))
    assert level.evaluate(block([3.0, 12.0], [0.25, 0.75]), 0).tolist() == [0.25, 0.75]


def test_gauss_per_sample_is_the_fixed_gaussian_bit_for_bit() -> None:
    mf = Parametric("gauss", (Ref(1, "m"), Ref(2, "s")), "good")
    rng = np.random.default_rng(7)
    x = np.stack([rng.uniform(-3, 3, 50), rng.uniform(-1, 1, 50), rng.uniform(0.1, 2, 50)])
    got = mf.evaluate(x, 0)
    want = [float(Gaussian(m, s)(v)) for v, m, s in x.T]
    assert got.tolist() == want
    # at one sigma from the mean: exp(-1/2)
    one = mf.evaluate(block([3.0], [1.0], [2.0]), 0)
    assert one.tolist() == [float(gaussmf(3.0, 1.0, 2.0))]
    assert math.isclose(float(one[0]), math.exp(-0.5), rel_tol=1e-15)
    fixed_mean = Parametric("gauss", (2.0, Ref(1, "s")))
    assert fixed_mean.evaluate(block([2.0, 4.0], [1.0, 2.0]), 0).tolist() == [
        1.0, float(gaussmf(4.0, 2.0, 2.0))]


def test_parameters_that_make_no_membership_function_are_named_with_the_sample() -> None:
    mf = Parametric("gauss", (Ref(1, "m"), Ref(2, "stdGood")), "good")
    with pytest.raises(ValueError, match=r"'good': stdGood = 0\.0 at sample 1 must be > 0"):
        mf.evaluate(block([1.0, 1.0], [0.0, 0.0], [1.0, 0.0]), 0)
    with pytest.raises(ValueError, match=r"'middle': mid = 1\.0 at sample 0 is below the x of "
                       r"point 1"):
        TRIANGLE.evaluate(block([1.0], [2.0], [1.0], [3.0]), 0)
    level = Parametric("points", (0.0, Ref(1, "h"), 10.0, 0.0), "t")
    with pytest.raises(ValueError, match=r"h = 1\.5 at sample 0 must lie in \[0, 1\]"):
        level.evaluate(block([3.0], [1.5]), 0)
    with pytest.raises(ValueError, match="is not among the 2 inputs"):
        TRIANGLE.evaluate(block([1.0], [2.0]), 0)


def test_construction_checks() -> None:
    with pytest.raises(ValueError, match="family 'bell'"):
        Parametric("bell", (Ref(0, "a"),))
    with pytest.raises(ValueError, match=r"gauss takes \[mean sigma\], got 3"):
        Parametric("gauss", (Ref(0, "a"), 1.0, 2.0))
    with pytest.raises(ValueError, match=r"points takes .* got 3"):
        Parametric("points", (Ref(0, "a"), 1.0, 2.0))
    with pytest.raises(ValueError, match="no parameter is an input"):
        Parametric("gauss", (0.0, 1.0))
    with pytest.raises(ValueError, match="parameter 2 = nan must be a finite number"):
        Parametric("gauss", (Ref(0, "a"), math.nan))
    with pytest.raises(ValueError, match="input index -1"):
        Ref(-1, "a")
    with pytest.raises(TypeError, match=r"its parameters are the inputs \['lo', 'mid', 'hi'\]"):
        TRIANGLE(np.zeros(3))
    assert TRIANGLE.reads == (1, 2, 3)


def _systems() -> tuple[T1Sugeno, np.ndarray]:
    variable = Parametric("gauss", (Ref(1, "m"), Ref(2, "s")), "near")
    fixed_term = ("far", Trapezoid(-11.0, -10.0, 10.0, 11.0))
    inputs = (Input("v", (-10, 10), [("near", variable), fixed_term]),
              Input("m", (-5, 5), []), Input("s", (0.25, 4), []))
    rules = (Rule(["near", None, None], consequents=[(10.0, 10.0)]),
             Rule(["far", None, None], consequents=[(-2.0, -2.0)]))
    rng = np.random.default_rng(3)
    x = np.stack([rng.uniform(-10, 10, 12), rng.uniform(-5, 5, 12), rng.uniform(0.25, 4, 12)],
                 axis=1)
    return T1Sugeno(inputs=inputs, rules=rules, name="parametric"), x


def test_a_system_evaluates_each_sample_with_its_parameters() -> None:
    system, x = _systems()
    batch = system.evaluate(x)
    far = ("far", Trapezoid(-11, -10, 10, 11))
    for j, (_, m, s) in enumerate(x):
        v = Input("v", (-10, 10), [("near", Gaussian(m, s)), far])
        fixed = T1Sugeno(inputs=(v, Input("m", (-5, 5), []), Input("s", (0.25, 4), [])),
                         rules=system.rules, name="fixed")
        assert batch[j] == fixed.evaluate(x[j])  # the fixed term's bits at that sample
        assert system(*x[j].tolist()) == batch[j]  # the scalar path
    # parameters are inputs, clipped to their universes as every input: s below 0.25 is 0.25
    assert system(1.0, 0.0, 0.01) == system(1.0, 0.0, 0.25)
    # closed form: g = exp(-1/2) at one sigma, far = 1: (10 g - 2) / (g + 1)
    g = math.exp(-0.5)
    assert math.isclose(system(2.0, 0.0, 2.0), (10 * g - 2) / (g + 1), rel_tol=1e-15)


def test_the_compiled_engine_leaves_it_to_numpy_and_fixed_rows_are_unchanged() -> None:
    from it2track.codegen.generate import check_supported
    from it2track.io import UnsupportedFeatureError

    system, _ = _systems()
    assert "OTHER" in (_kernels.supported(system) or "")
    with pytest.raises(UnsupportedFeatureError, match=r"input 'v': membership function "
                       r"Parametric\(family='gauss'.* has no C implementation"):
        check_supported(system)
    t = system.tables
    assert [k for k, _, _ in t.parametric] == [0] and t.other == []
    assert t.pl_rows.tolist() == [1] and not t.all_pl
