"""Mamdani systems: centroid type reduction against an independent brute force, a hand-computed
example in exact fractions, MATLAB's documented tipper values, centre-of-sets, defuzzifiers,
zero firing and several outputs.

The brute force here shares no code with it2track's evaluation: firing, implication and
aggregation are plain Python loops over the documented formulas, and the centroid enumerates
every switch point over the discretised output."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Aggregation,
    Defuzzifier,
    Gaussian,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    IT2Sugeno,
    Output,
    Rule,
    SNorm,
    T1Mamdani,
    TNorm,
    Trapezoid,
    Triangle,
    TypeReduction,
    ZeroFiringError,
    set_centroid,
)

EXACT = [KM, EKM, EIASC, EXHAUSTIVE]


# -- the independent brute force -----------------------------------------------------------------


def _firing(system: IT2Mamdani, x: list[float], rule: Rule) -> tuple[float, float]:
    los, ups = [], []
    for inp, label, neg, xi in zip(system.inputs, rule.antecedent, rule.negated, x, strict=True):
        if label is None:
            continue
        s = inp.sets[[t.name for t in inp.sets].index(label)]
        xc = min(max(xi, inp.universe[0]), inp.universe[1])
        lo, up = float(s.lower(xc)), float(s.upper(xc))
        if neg:
            lo, up = 1.0 - up, 1.0 - lo
        los.append(lo)
        ups.append(up)
    if rule.connective.value == "or" and len(los) > 1:
        def s_norm(vals: list[float]) -> float:
            acc = vals[0]
            for v in vals[1:]:
                acc = max(acc, v) if system.snorm is SNorm.MAXIMUM else acc + v - acc * v
            return acc
        lo, up = s_norm(los), s_norm(ups)
    else:
        lo, up = 1.0, 1.0
        for a, b in zip(los, ups, strict=True):
            lo = lo * a if system.tnorm is TNorm.PRODUCT else min(lo, a)
            up = up * b if system.tnorm is TNorm.PRODUCT else min(up, b)
    return lo * rule.weight, up * rule.weight


def _aggregate(system: IT2Mamdani, x: list[float]) -> tuple[list[float], list[float], np.ndarray]:
    out = system.outputs[0]
    y = np.linspace(out.universe[0], out.universe[1], system.resolution)
    agg_lo = [0.0] * y.size
    agg_up = [0.0] * y.size
    for rule in system.rules:
        fl, fu = _firing(system, x, rule)
        s = out.sets[[t.name for t in out.sets].index(rule.consequent)]
        for j, yj in enumerate(y):
            ml, mu = float(s.lower(yj)), float(s.upper(yj))
            if system.implication is Implication.MINIMUM:
                a, b = min(fl, ml), min(fu, mu)
            else:
                a, b = fl * ml, fu * mu
            if system.aggregation is Aggregation.MAXIMUM:
                agg_lo[j], agg_up[j] = max(agg_lo[j], a), max(agg_up[j], b)
            elif system.aggregation is Aggregation.SUM:
                agg_lo[j], agg_up[j] = agg_lo[j] + a, agg_up[j] + b
            else:
                agg_lo[j] = agg_lo[j] + a - agg_lo[j] * a
                agg_up[j] = agg_up[j] + b - agg_up[j] * b
    return agg_lo, agg_up, y


def _switch_point_centroid(lo: list, up: list, y: list) -> tuple:
    """min / max over every switch point k of the centroid (upper below k for yl, above for yr).

    Works on floats or Fractions alike."""
    left, right = None, None
    for k in range(len(y) + 1):
        th_l = [up[j] if j < k else lo[j] for j in range(len(y))]
        th_r = [lo[j] if j < k else up[j] for j in range(len(y))]
        for th, is_left in ((th_l, True), (th_r, False)):
            den = sum(th)
            if den == 0:
                continue
            c = sum(t * v for t, v in zip(th, y, strict=True)) / den
            if is_left:
                left = c if left is None else min(left, c)
            else:
                right = c if right is None else max(right, c)
    return left, right


def _random_system(seed: int) -> IT2Mamdani:
    rng = np.random.default_rng(seed)

    def it2_sets(lo: float, hi: float, n: int) -> list[IT2Set]:
        centres = np.linspace(lo, hi, n)
        step = (hi - lo) / (n - 1)
        sets = []
        for k, c in enumerate(centres):
            if rng.random() < 0.25:
                s1, s2 = sorted(rng.uniform(0.3, 0.8, size=2) * step)
                sets.append(IT2Set.gaussian_uncertain_std(float(c), s1, s2, f"S{k}"))
            else:
                w = float(rng.uniform(0.0, 0.8) * step)
                tri = Triangle(c - 1.3 * step, c, c + 1.3 * step)
                sets.append(IT2Set.from_fou(tri, w, f"S{k}"))
        return sets

    inputs = [Input(f"x{i}", (-1, 1), it2_sets(-1, 1, 3)) for i in range(2)]
    n_out = int(rng.integers(2, 5))
    out = Output("y", (-5, 5), it2_sets(-4, 4, n_out))
    rules = []
    for a, b in itertools.product(range(3), repeat=2):
        if rng.random() < 0.15:
            continue
        ant: list[str | None] = [f"S{a}", f"S{b}"]
        if rng.random() < 0.15:
            ant[int(rng.integers(2))] = None
        neg = [bool(rng.random() < 0.15) and lab is not None for lab in ant]
        rules.append(Rule(ant, f"S{int(rng.integers(n_out))}",
                          connective="or" if rng.random() < 0.3 else "and", negated=neg,
                          weight=float(rng.choice([1.0, rng.uniform(0.2, 1.0)]))))
    return IT2Mamdani(
        inputs=inputs, outputs=[out], rules=rules,
        tnorm=TNorm.PRODUCT if rng.random() < 0.5 else TNorm.MINIMUM,
        snorm=SNorm.MAXIMUM if rng.random() < 0.5 else SNorm.PROBOR,
        implication=Implication.MINIMUM if rng.random() < 0.5 else Implication.PRODUCT,
        aggregation=[Aggregation.MAXIMUM, Aggregation.SUM, Aggregation.PROBOR][
            int(rng.integers(3))],
        resolution=int(rng.integers(5, 60)),
        on_zero_firing=0.0,
    )


@pytest.mark.parametrize("seed", range(12))
def test_centroid_equals_switch_point_brute_force(seed: int) -> None:
    system = _random_system(seed)
    rng = np.random.default_rng(100 + seed)
    x = rng.uniform(-1.1, 1.1, size=(15, 2))
    refs = []
    for p in x:
        lo, up, y = _aggregate(system, list(p))
        refs.append(_switch_point_centroid(lo, up, list(y)))
    for reducer in EXACT:
        sys_r = IT2Mamdani(**{**_fields(system), "reducer": reducer})
        yl, yr = sys_r.interval(x[:, 0], x[:, 1])
        for n, (left, right) in enumerate(refs):
            if left is None:  # nothing fires: on_zero_firing
                assert yl[n] == yr[n] == 0.0
                continue
            assert yl[n] == pytest.approx(left, abs=1e-12), (seed, reducer.name, n)
            assert yr[n] == pytest.approx(right, abs=1e-12), (seed, reducer.name, n)
        # the aggregated set itself
        agg_lo, agg_up = sys_r.aggregated(x[:, 0], x[:, 1])
        lo, up, _ = _aggregate(system, list(x[0]))
        np.testing.assert_allclose(agg_lo[0], lo, rtol=0, atol=1e-14)
        np.testing.assert_allclose(agg_up[0], up, rtol=0, atol=1e-14)


def _fields(system: IT2Mamdani) -> dict:
    keys = ("inputs", "outputs", "rules", "tnorm", "snorm", "implication", "aggregation",
            "resolution", "on_zero_firing", "reducer", "type_reduction", "name")
    return {k: getattr(system, k) for k in keys}


def _hand_system(**kwargs: object) -> IT2Mamdani:
    x = Input("x", (0, 1), [IT2Set(Triangle(0, 0, 1), Triangle(0, 0, 0.5), "lo"),
                            IT2Set(Triangle(0, 1, 1), Triangle(0.5, 1, 1), "hi")])
    y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                             IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    return IT2Mamdani(inputs=[x], outputs=[y], rules=[Rule(["lo"], "small"), Rule(["hi"], "big")],
                      resolution=5, **kwargs)  # type: ignore[arg-type]


def test_type1_antecedents_keep_the_output_sets_footprint() -> None:
    """Type-1 input sets fire an interval of zero width, but the IT2 output sets still give the
    aggregated set a lower MF below its upper one: the interval is the brute force's, not the
    upper MF's type-1 centroid (yl == yr, what the evaluation once returned)."""
    x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    y = Output("y", (0, 10), [IT2Set.from_fou(Triangle(0, 0, 5), 2.0, "small"),
                              IT2Set.from_fou(Triangle(5, 10, 10), 2.0, "big")])
    system = IT2Mamdani(inputs=[x], outputs=[y], rules=[Rule(["lo"], "small"),
                                                        Rule(["hi"], "big")])
    for reducer in EXACT:
        sys_r = IT2Mamdani(**{**_fields(system), "reducer": reducer})
        for p in (0.3, 0.5, 0.9):
            left, right = _switch_point_centroid(*_aggregate(sys_r, [p])[:2],
                                                 list(_aggregate(sys_r, [p])[2]))
            yl, yr = sys_r.interval(p)
            assert right - left > 0.1
            assert (float(yl), float(yr)) == pytest.approx((left, right), abs=1e-12)


def test_hand_computed_example_in_exact_fractions() -> None:
    """x = 1/4: rule lo fires [1/2, 3/4], rule hi [0, 1/4]; grid y = 0..4. With min implication
    and max aggregation the aggregated set is lower [1/2, 1/2, 0, 0, 0], upper
    [3/4, 3/4, 1/2, 1/4, 1/4]. yl = (1 * 1/2) / (3/4 + 1/2) = 2/5 (switch after y = 0);
    yr = (1 * 1/2 + 2 * 1/2 + 3/4 + 4/4) / (1/2 + 1/2 + 1/2 + 1/4 + 1/4) = 13/8."""
    q = Fraction
    lo = [q(1, 2), q(1, 2), q(0), q(0), q(0)]
    up = [q(3, 4), q(3, 4), q(1, 2), q(1, 4), q(1, 4)]
    assert _switch_point_centroid(lo, up, [q(k) for k in range(5)]) == (q(2, 5), q(13, 8))
    for reducer in EXACT:
        yl, yr = _hand_system(reducer=reducer).interval(0.25)
        assert (float(yl), float(yr)) == pytest.approx((0.4, 1.625), abs=1e-15), reducer.name
    assert float(_hand_system()(0.25)) == pytest.approx(81 / 80, abs=1e-15)
    # Nie-Tan: lo + up = [5/4, 5/4, 1/2, 1/4, 1/4]; sum((lo + up) y) / sum(lo + up) = 4 / (7/2)
    assert float(_hand_system(reducer=NIE_TAN)(0.25)) == pytest.approx(8 / 7, abs=1e-15)


def test_product_implication_and_sum_aggregation_by_hand() -> None:
    """Same example, product implication, sum aggregation: upper = 3/4 [1, 3/4, 1/2, 1/4, 0]
    + 1/4 [0, 1/4, 1/2, 3/4, 1]; lower = 1/2 [1, 1/2, 0, 0, 0]."""
    system = _hand_system(implication=Implication.PRODUCT, aggregation=Aggregation.SUM)
    up = [Fraction(3, 4) * a + Fraction(1, 4) * b for a, b in
          zip([1, Fraction(3, 4), Fraction(1, 2), Fraction(1, 4), 0],
              [0, Fraction(1, 4), Fraction(1, 2), Fraction(3, 4), 1], strict=True)]
    lo = [Fraction(1, 2) * a for a in [1, Fraction(1, 2), 0, 0, 0]]
    left, right = _switch_point_centroid(lo, up, [Fraction(k) for k in range(5)])
    yl, yr = system.interval(0.25)
    assert (float(yl), float(yr)) == pytest.approx((float(left), float(right)), abs=1e-15)


def test_centre_of_sets_is_sugeno_with_the_set_centroids() -> None:
    system = _random_system(3)
    cos = IT2Mamdani(**{**_fields(system), "type_reduction": TypeReduction.CENTRE_OF_SETS})
    out = system.outputs[0]
    y = np.linspace(-5, 5, system.resolution)
    cents = {}
    for s in out.sets:
        lo, up = np.minimum(s.lower(y), s.upper(y)), np.asarray(s.upper(y), dtype=float)
        left, right = _switch_point_centroid(list(lo), list(up), list(y))
        assert set_centroid(lo, up, y) == pytest.approx((left, right), abs=1e-12)
        cents[s.name] = (left, right)
    sugeno = IT2Sugeno(
        inputs=system.inputs, tnorm=system.tnorm, snorm=system.snorm, on_zero_firing=0.0,
        rules=[Rule(r.antecedent, cents[str(r.consequent)], weight=r.weight,
                    connective=r.connective, negated=r.negated) for r in system.rules])
    x = np.random.default_rng(0).uniform(-1, 1, size=(2, 300))
    np.testing.assert_allclose(cos(*x), sugeno(*x), rtol=0, atol=1e-12)
    assert "mamdani" in cos.tables.features


def test_matlab_tipper_documented_values() -> None:
    """MATLAB's tipper.fis (Mamdani: min, max, min, max, centroid, 101 points) evaluated at the
    three inputs printed in the evalfis documentation,
    https://www.mathworks.com/help/fuzzy/mamfis.evalfis.html : 7.0169, 14.4585, 20.3414."""
    svc = Input("service", (0, 10), [("poor", Gaussian(0, 1.5)), ("good", Gaussian(5, 1.5)),
                                     ("excellent", Gaussian(10, 1.5))])
    food = Input("food", (0, 10), [("rancid", Trapezoid(0, 0, 1, 3)),
                                   ("delicious", Trapezoid(7, 9, 10, 10))])
    tip = Output("tip", (0, 30), [("cheap", Triangle(0, 5, 10)),
                                  ("average", Triangle(10, 15, 20)),
                                  ("generous", Triangle(20, 25, 30))])
    rules = [Rule(["poor", "rancid"], "cheap", connective="or"), Rule(["good", None], "average"),
             Rule(["excellent", "delicious"], "generous", connective="or")]
    t1 = T1Mamdani(inputs=[svc, food], outputs=[tip], rules=rules)
    got = t1(np.array([2.0, 4.0, 7.0]), np.array([1.0, 5.0, 8.0]))
    assert np.round(got, 4).tolist() == [7.0169, 14.4585, 20.3414]
    # An IT2 system whose sets have no footprint gives the type-1 centroid for every reducer.
    for reducer in [*EXACT, NIE_TAN, WU_MENDEL]:
        it2 = IT2Mamdani(inputs=[svc, food], outputs=[tip], rules=rules, reducer=reducer)
        np.testing.assert_allclose(it2(np.array([2.0, 4.0, 7.0]), np.array([1.0, 5.0, 8.0])),
                                   got, rtol=0, atol=1e-12)


def test_zero_firing_policy() -> None:
    system = _hand_system()
    # Rule "hi" is the only one with support near 1 ... make nothing fire with a narrow input.
    x = Input("x", (0, 1), [IT2Set(Triangle(0, 0, 0.2), Triangle(0, 0, 0.1), "lo")])
    narrow = IT2Mamdani(inputs=[x], outputs=system.outputs, rules=[Rule(["lo"], "small")])
    with pytest.raises(ZeroFiringError, match="no rule"):
        narrow(0.5)
    assert float(IT2Mamdani(**{**_fields(narrow), "on_zero_firing": 2.0})(0.5)) == 2.0
    t1 = T1Mamdani(inputs=[Input("x", (0, 1), [("lo", Triangle(0, 0, 0.2))])],
                   outputs=[Output("y", (0, 1), [("a", Triangle(0, 0.5, 1))])],
                   rules=[Rule(["lo"], "a")], on_zero_firing=0.5)
    assert float(t1(0.9)) == 0.5


def test_several_outputs_and_select_output() -> None:
    base = _hand_system()
    y2 = Output("z", (-1, 1), [("neg", Triangle(-1, -1, 0)), ("pos", Triangle(0, 1, 1))])
    multi = IT2Mamdani(inputs=base.inputs, outputs=[*base.outputs, y2],
                       rules=[Rule(["lo"], consequents=["small", "neg"]),
                              Rule(["hi"], consequents=["big", None])], resolution=5)
    x = np.linspace(0, 0.9, 7)  # (at x = 1 no rule acts on z: ZeroFiringError)
    out = multi(x)
    assert out.shape == (7, 2)
    np.testing.assert_array_equal(out[:, 0], base(x))
    np.testing.assert_array_equal(out[:, 1], multi.select_output("z")(x))
    assert multi.select_output(1).outputs == (y2,)


def test_defuzzifiers_by_hand() -> None:
    x = Input("x", (0, 1), [("a", Trapezoid(0, 0, 1, 1))])
    y = Output("y", (0, 4), [("plateau", Trapezoid(0, 1, 2, 4))])
    expected = {  # mu on y = 0..4: [0, 1, 1, 0.5, 0]
        Defuzzifier.CENTROID: (1 + 2 + 1.5) / 2.5,
        Defuzzifier.BISECTOR: 2.0,  # running sum 0, 1, 2 >= 1.25 first at y = 2
        Defuzzifier.MOM: 1.5,
        Defuzzifier.SOM: 1.0,
        Defuzzifier.LOM: 2.0,
    }
    for method, value in expected.items():
        fls = T1Mamdani(inputs=[x], outputs=[y], rules=[Rule(["a"], "plateau")], resolution=5,
                        defuzzifier=method)
        assert float(fls(0.5)) == pytest.approx(value, abs=1e-15), method


def test_bad_mamdani_definitions() -> None:
    base = _hand_system()
    with pytest.raises(ValueError, match="needs outputs"):
        IT2Mamdani(inputs=base.inputs, rules=base.rules)
    with pytest.raises(ValueError, match="has no set 'huge'"):
        IT2Mamdani(inputs=base.inputs, outputs=base.outputs, rules=[Rule(["lo"], "huge")])
    with pytest.raises(ValueError, match="output set label"):
        IT2Mamdani(inputs=base.inputs, outputs=base.outputs, rules=[Rule(["lo"], 1.0)])
    with pytest.raises(ValueError, match="resolution"):
        IT2Mamdani(**{**_fields(base), "resolution": 2})
    with pytest.raises(ValueError, match="footprint"):
        T1Mamdani(inputs=base.inputs, outputs=base.outputs, rules=base.rules)
    with pytest.raises(ValueError, match="zero at every one"):
        IT2Mamdani(inputs=base.inputs, rules=base.rules, resolution=3, outputs=[
            Output("y", (0, 4), [IT2Set.type1(Triangle(0.5, 1, 1.5), "small"),
                                 IT2Set.type1(Triangle(0, 4, 4), "big")])])


def test_batch_shapes_and_bit_identical_blocks() -> None:
    system = _random_system(5)
    x = np.random.default_rng(1).uniform(-1, 1, size=(2, 3, 700))
    full = system(x[0], x[1])
    assert full.shape == (3, 700)
    np.testing.assert_array_equal(full[1, 200:260], system(x[0, 1, 200:260], x[1, 1, 200:260]))


def test_vectorised_exhaustive_kernel_gives_the_loop_kernels_bits() -> None:
    from it2track.fuzzy.reducers import _exhaustive_both, exhaustive_many_rows

    rng = np.random.default_rng(11)
    for rows, n in [(101, 1), (101, 64), (7, 300), (2, 5)]:
        fl = rng.uniform(0, 1, (rows, n)) * (rng.random((rows, n)) < 0.6)
        fu = fl + rng.uniform(0, 1, (rows, n)) * (rng.random((rows, n)) < 0.7)
        fu[:, :1] = fl[:, :1] = 0.0  # a column with no firing: NaN in both
        y = np.sort(rng.normal(size=rows))
        for a, b in zip(_exhaustive_both(fl, fu, y, 0), exhaustive_many_rows(fl, fu, y),
                        strict=True):
            np.testing.assert_array_equal(a, b)


def test_one_sample_calls_give_the_batch_bits() -> None:
    system = _random_system(6)
    x = np.random.default_rng(2).uniform(-1, 1, size=(2, 150))
    batch = system(x[0], x[1])
    one = [float(system(float(a), float(b))) for a, b in x.T]
    np.testing.assert_array_equal(batch, one)
