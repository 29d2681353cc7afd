"""The compiled fuzzy evaluation (it2track.fuzzy.kernels) equals the numpy reference bit for bit.

Each test evaluates a system through its public calls (which use the kernels when they apply)
and through the numpy reference (``_prepare`` + ``_interval_blocks``), and compares the bits.
Errors (zero firing, no convergence, NaN input) must come from the reference, unchanged.
"""

import dataclasses
import math

import numpy as np
import pytest

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
    IT2Sugeno,
    LinearSShape,
    LinearZShape,
    MFKind,
    PiShape,
    Point,
    Ramp,
    Rectangle,
    Reducer,
    Rule,
    ScaledLagged,
    SemiEllipse,
    Sigmoid,
    SigmoidDifference,
    SigmoidProduct,
    Spike,
    SShape,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    WeightedDefuzzifier,
    ZeroFiringError,
    ZShape,
    kernels,
)
from it2track.fuzzy.reducers import ConvergenceError, TypeReducer
from it2track.paper import dead_zone_matched_fls, heading_fls

REDUCERS = [m.value for m in Reducer]


def reference(fls, *xs):
    x, shape = fls._prepare(xs)
    yl, yr = fls._interval_blocks(x)
    return yl.reshape(shape), yr.reshape(shape)


def same(a, b):
    """The same 64 bits (signed zeros told apart)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and bool(np.all(a.view(np.int64) == b.view(np.int64)))


def points(n, seed, n_inputs=2, spread=1.4):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-spread, spread, (n_inputs, n))
    x[:, :40] = np.round(x[:, :40], 1)  # set corners and shoulders exactly
    return x


def check(fls, x):
    assert kernels._entry(fls) is not None, kernels.supported(fls)
    try:
        rl, rr = reference(fls, *x)
    except ZeroFiringError as exc:  # (Wu-Mendel with zero lower firing): same error
        with pytest.raises(ZeroFiringError, match=str(exc)[:30]):
            fls.interval(*x)
        keep = np.ones(x.shape[1], dtype=bool)
        for j in range(x.shape[1]):
            try:
                reference(fls, *x[:, j : j + 1])
            except ZeroFiringError:
                keep[j] = False
        x = x[:, keep]
        rl, rr = reference(fls, *x)
    yl, yr = fls.interval(*x)
    assert same(yl, rl) and same(yr, rr)
    u = fls(*x)
    assert same(u, (rl + rr) * 0.5)
    for j in range(0, x.shape[1], max(1, x.shape[1] // 50)):
        xs = [float(v) for v in x[:, j]]
        got = fls(*xs)
        if fls.n_inputs == 2:
            assert isinstance(got, float)  # the compiled scalar call
        assert float(got) == float((rl[j] + rr[j]) * 0.5), (xs, got)


def gaussian_system(reducer, tnorm=TNorm.PRODUCT, zero=None):
    sets = [
        IT2Set.gaussian_uncertain_mean(-1.0, -0.6, 0.3, "N"),
        IT2Set.gaussian_uncertain_std(0.0, 0.2, 0.35, "Z", h=0.9),
        IT2Set.gaussian_uncertain_mean(0.5, 0.8, 0.25, "P"),
    ]
    inputs = [Input("a", (-1, 1), sets), Input("b", (-2, 2), sets)]
    rules = [Rule((p, q), (i - j - 0.5, i - j + 0.25 * (i % 2)))
             for i, p in enumerate("NZP") for j, q in enumerate("NZP")]  # fmt: skip
    return IT2Sugeno(inputs=inputs, rules=rules, reducer=reducer, tnorm=tnorm,
                     on_zero_firing=zero)  # fmt: skip


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
@pytest.mark.parametrize("tnorm", list(TNorm), ids=lambda t: t.name)
@pytest.mark.parametrize("fou", [0.0, 0.1, 0.2, 0.3])
def test_paper_controllers(reducer, tnorm, fou):
    fls = heading_fls(fou, reducer=reducer, tnorm=tnorm)
    check(fls, points(3000, 1))


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_gaussian_sets_interval_consequents(reducer):
    check(gaussian_system(reducer), points(3000, 2, spread=2.5))
    check(gaussian_system(reducer, TNorm.MINIMUM), points(500, 3, spread=2.5))


def test_type1_systems():
    check(dead_zone_matched_fls(0.2), points(2000, 4))
    check(dead_zone_matched_fls(0.3, tnorm=TNorm.MINIMUM), points(2000, 5))
    sets = [("L", Trapezoid(-3, -3, -1, 0.5, h=0.8)), ("H", Triangle(-1, 1, 1))]
    t1 = T1Sugeno(inputs=[Input("x", (-3, 1), sets)], rules=[Rule(["L"], -2.0),
                  Rule(["H"], 3.0)])  # fmt: skip
    check(t1, points(2000, 6, n_inputs=1, spread=3.5))


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_random_three_input_systems(reducer):
    """Random triangle/trapezoid IT2 sets, rules missing inputs, tied and interval consequents:
    the KM tie handling and every reducer's branch get exercised."""
    rng = np.random.default_rng(7)
    for trial in range(4):
        inputs = []
        for i in range(3):
            sets = []
            for s in range(3):
                c = np.sort(rng.uniform(-1, 1, 3))
                width = float(rng.uniform(0, 0.3))
                centre = Triangle(*(float(v) for v in c)) if c[0] < c[2] else Triangle(-1, 0, 1)
                try:
                    sets.append(IT2Set.from_fou(centre, width, f"S{s}"))
                except ValueError:
                    sets.append(IT2Set.from_fou(Triangle(-1, 0, 1), 0.1, f"S{s}"))
            sets[0] = IT2Set.from_fou(Trapezoid(-1, -1, -0.4, 0.0), 0.2, "S0")
            sets[2] = IT2Set.from_fou(Trapezoid(0.0, 0.4, 1, 1), 0.2, "S2")
            inputs.append(Input(f"x{i}", (-1, 1), sets))
        rules = []
        for _ in range(12):
            ante = [f"S{rng.integers(3)}" if rng.random() < 0.8 else None for _ in range(3)]
            if all(a is None for a in ante):
                ante[0] = "S1"
            lo = float(rng.integers(-3, 4))  # integer consequents: many ties
            rules.append(Rule(ante, (lo, lo + float(rng.choice([0.0, 0.5, 1.0])))))
        fls = IT2Sugeno(inputs=inputs, rules=rules, reducer=reducer, on_zero_firing=0.25)
        check(fls, points(2000, 10 + trial, n_inputs=3, spread=1.2))


def test_zero_firing_value_and_errors():
    sets = [IT2Set.from_fou(Triangle(-1, -0.5, 0), 0.1, "A")]
    for reducer in REDUCERS:
        fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)], rules=[Rule(["A"], 2.0)],
                        reducer=reducer, on_zero_firing=-0.75)  # fmt: skip
        if reducer.name != "wu-mendel":  # (its zero lower firing raises near the feet)
            check(fls, points(500, 8, n_inputs=1))
        assert fls(0.6) == -0.75
        strict = dataclasses.replace(fls, on_zero_firing=None)
        with pytest.raises(ZeroFiringError, match="no rule"):
            strict(np.array([-0.5, 0.6]))
        with pytest.raises(ZeroFiringError, match="no rule"):
            strict(0.6)
    t1 = T1Sugeno(inputs=[Input("x", (-1, 1), [("A", Triangle(-1, -0.5, 0))])],
                  rules=[Rule(["A"], 2.0)])  # fmt: skip
    with pytest.raises(ZeroFiringError):
        t1(0.5)


def test_wu_mendel_zero_lower_firing_raises_as_reference():
    # At x = -0.05 the upper MF fires, the lower one does not.
    sets = [IT2Set(Triangle(-1, -0.5, 0.0), Triangle(-0.9, -0.5, -0.1), "A"),
            IT2Set(Triangle(0.0, 0.5, 1), Triangle(0.1, 0.5, 0.9), "B")]  # fmt: skip
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)],
                    rules=[Rule(["A"], -1.0), Rule(["B"], 1.0)], reducer=Reducer.WU_MENDEL.value)
    with pytest.raises(ZeroFiringError, match="total lower firing"):
        fls(np.array([0.3, -0.05]))
    with pytest.raises(ZeroFiringError, match="total lower firing"):
        fls(-0.05)


def test_no_convergence_raises_as_reference():
    fls = heading_fls(0.3, reducer=Reducer.KM.value.with_max_iter(1))
    with pytest.raises(ConvergenceError):
        fls(*points(200, 9))


def test_nan_input_raises_as_reference():
    fls = heading_fls(0.2)
    with pytest.raises(ValueError, match="NaN or inf"):
        fls(math.nan, 0.0)
    with pytest.raises(ValueError, match="NaN or inf"):
        fls(np.array([0.1, math.inf]), 0.0)


def test_unsupported_systems_use_numpy():
    """Anything outside the allow-list is evaluated by numpy, correctly."""
    discrete = IT2Set.type1(Discrete([(-1, 0), (0, 1), (1, 0)]), "Z")
    other = IT2Sugeno(inputs=[Input("x", (-1, 1), [discrete])], rules=[Rule(["Z"], 1.0)],
                      on_zero_firing=0.0)
    assert "OTHER" in kernels.supported(other)

    class Sub(IT2Sugeno):
        pass

    sub = Sub(inputs=heading_fls(0.2).inputs, rules=heading_fls(0.2).rules)
    assert "not IT2Sugeno" in kernels.supported(sub)
    custom = TypeReducer(name="mine", exact=False, _approx=lambda fl, fu, a, b: (fl[0], fu[0]))
    odd = dataclasses.replace(heading_fls(0.2), reducer=custom)
    assert "built-in" in kernels.supported(odd)
    for fls in (other, sub, odd):
        x = points(100, 11, n_inputs=fls.n_inputs)
        assert kernels._entry(fls) is None
        assert same(fls.interval(*x)[0], reference(fls, *x)[0])
    with_feature = heading_fls(0.2)
    object.__setattr__(with_feature.tables, "features", frozenset({"or"}))
    assert "features" in kernels.supported(with_feature)


def test_engine_variable(monkeypatch):
    monkeypatch.setenv(kernels.ENGINE_ENV, "numpy")
    assert kernels.engine() == "numpy"
    monkeypatch.setenv(kernels.ENGINE_ENV, "fast")
    with pytest.raises(ValueError, match="IT2TRACK_ENGINE='fast'"):
        kernels.engine()


def test_empty_and_threaded_batches():
    fls = heading_fls(0.2)
    assert fls(np.empty(0), np.empty(0)).shape == (0,)
    assert fls.interval(np.empty((3, 0)), np.empty((3, 0)))[0].shape == (3, 0)
    x = points(3 * kernels._PARALLEL_MIN + 5, 12)  # split across threads
    import numba

    before = numba.get_num_threads()
    try:
        got = []
        for n in (1, 2):
            numba.set_num_threads(n)
            got.append(fls(*x))
    finally:
        numba.set_num_threads(before)
    assert same(got[0], got[1]) and same(got[0], sum(reference(fls, *x)) * 0.5)


#: Every term class the kernels compile, with parameters that exercise its branches on [-1, 1]:
#: integer and fractional bell exponents, both directions of the edge terms, crisp ramps.
TERMS = [Bell(0.0, 0.5, 2.0), Bell(0.3, 0.4, 1.3), Sigmoid(0.2, 6.0),
         SigmoidDifference(-0.5, 8.0, 8.0, 0.5), SigmoidProduct(-0.5, 8.0, -8.0, 0.5),
         SShape(-1.0, 0.2), ZShape(-0.2, 1.0), PiShape(-1.0, -0.3, 0.3, 1.0, h=0.9),
         GaussianProduct(-0.3, 0.2, 0.3, 0.25), Cosine(0.0, 1.2), Spike(0.1, 2.0),
         Concave(0.2, 0.8), Concave(-0.2, -0.8), Rectangle(-0.4, 0.4), Binary(0.0, math.inf),
         Binary(0.1, -math.inf), Arc(-1.0, 0.5), Arc(1.0, -0.5), SemiEllipse(-0.7, 0.7),
         Ramp(-1.0, 1.0), Ramp(1.0, -1.0), LinearSShape(-0.5, 0.5), LinearZShape(-0.5, 0.5),
         LinearSShape(0.2, 0.2), LinearZShape(0.2, 0.2), Point(0.1), Point(-0.4, 0.6)]


def two_term_system(k, *, it2, tnorm=TNorm.PRODUCT, reducer=None):
    a, b = TERMS[k], TERMS[(k + 7) % len(TERMS)]
    if it2:  # MATLAB's type-2: lower MF scaled and lagged from the upper one
        sets = [IT2Set.from_scale_lag(a, scale=0.8, lag=0.2, name="A"),
                IT2Set.from_scale_lag(b, scale=0.9, lag=0.1, name="B")]
    else:
        sets = [IT2Set.type1(a, "A"), IT2Set.type1(b, "B")]
    inputs = [Input("x", (-1, 1), sets), Input("y", (-1, 1), sets)]
    rules = [Rule(["A", "A"], -1.0), Rule(["A", "B"], 0.5), Rule(["B", "A"], 1.0),
             Rule(["B", "B"], 2.0), Rule(["A", None], 0.0)]
    if it2:
        return IT2Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, on_zero_firing=0.25,
                         reducer=reducer or Reducer.EXHAUSTIVE.value)
    return T1Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, on_zero_firing=0.25)


def test_every_membership_kind_is_compiled():
    kinds = set()
    for k in range(len(TERMS)):
        for it2 in (False, True):
            fls = two_term_system(k, it2=it2)
            kinds |= {MFKind(int(v)) for v in fls.tables.mf_kind}
    assert kinds == set(MFKind) - {MFKind.OTHER} - {
        MFKind.GAUSSIAN, MFKind.UM_GAUSSIAN_UPPER, MFKind.UM_GAUSSIAN_LOWER}  # (tested above)


@pytest.mark.parametrize("k", range(len(TERMS)), ids=lambda k: repr(TERMS[k]))
@pytest.mark.parametrize("it2", [False, True], ids=["t1", "it2"])
def test_new_kinds_equal_reference(k, it2):
    check(two_term_system(k, it2=it2), points(1500, 20 + k, spread=1.2))


@pytest.mark.parametrize("tnorm", list(TNorm), ids=lambda t: t.name)
def test_every_tnorm_equals_reference(tnorm):
    """The t-norms without an exact identity fold over the inputs a rule mentions only (the
    rule on "A" alone), in the kernels as in numpy."""
    for k in (0, 5, 13):
        check(two_term_system(k, it2=False, tnorm=tnorm), points(1000, 40 + k, spread=1.2))
        check(two_term_system(k, it2=True, tnorm=tnorm, reducer=Reducer.KM.value),
              points(1000, 50 + k, spread=1.2))


def test_weighted_sum_equals_reference():
    fls = dataclasses.replace(two_term_system(3, it2=False),
                              defuzzifier=WeightedDefuzzifier.SUM)
    check(fls, points(2000, 60, spread=1.2))
    strict = dataclasses.replace(fls, on_zero_firing=None,
                                 rules=(Rule(["A", "A"], 1.0),))  # (Sigmoid A: never 0)
    check(strict, points(500, 61, spread=1.2))
    lone = T1Sugeno(inputs=[Input("x", (-1, 1), [("R", Rectangle(-0.4, 0.4))])],
                    rules=[Rule(["R"], 3.0)], defuzzifier=WeightedDefuzzifier.SUM)
    assert kernels._entry(lone) is not None
    assert lone(0.0) == 3.0
    with pytest.raises(ZeroFiringError, match="no rule"):
        lone(np.array([0.0, 0.9]))


def test_scaled_lagged_of_existing_kinds_is_compiled():
    from it2track.fuzzy import Gaussian

    sets = [IT2Set(Triangle(-1, 0, 1), ScaledLagged(Triangle(-1, 0, 1), 0.8, 0.1), "Z"),
            IT2Set.from_scale_lag(Gaussian(0.5, 0.3, h=0.9), scale=0.7, lag=0.25, name="P")]
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)], rules=[Rule(["Z"], 1.0),
                    Rule(["P"], 2.0)], on_zero_firing=0.0)  # fmt: skip
    assert {MFKind(int(v)) for v in fls.tables.mf_kind} == {
        MFKind.TRAPEZOID, MFKind.GAUSSIAN, MFKind.SCALED_LAGGED}
    check(fls, points(2000, 70, n_inputs=1, spread=1.2))


def test_uncertain_parameter_sets_of_new_terms_are_compiled():
    """IT2 sets whose bounds are two terms of one family (uncertain width, inflection)."""
    sets = [IT2Set(Bell(0.0, 0.6, 2.0), Bell(0.0, 0.4, 2.0), "Z"),
            IT2Set(Sigmoid(0.3, 7.0), Sigmoid(0.5, 7.0), "P"),
            IT2Set(ZShape(-0.8, -0.1), ZShape(-0.9, -0.3, h=0.8), "N")]
    rules = [Rule([p, q], float(i - j)) for i, p in enumerate("NZP") for j, q in enumerate("NZP")]
    for reducer in REDUCERS:
        fls = IT2Sugeno(inputs=[Input("a", (-1, 1), sets), Input("b", (-1, 1), sets)],
                        rules=rules, reducer=reducer, on_zero_firing=0.0)
        check(fls, points(1500, 80, spread=1.2))


def test_extended_specialisation_is_chosen_per_system():
    """The paper's systems run the basic specialisation (the new kinds' code pruned before
    compiling); every new kind, t-norm and wtsum asks for the extended one, and the
    closed-loop kernel (basic only) leaves such controllers to the numpy loop."""
    from it2track.tracking import FuzzyHeadingController
    from it2track.tracking import compiled as loop_kernels

    assert not kernels.extended(heading_fls(0.2))
    assert not kernels.extended(heading_fls(0.0, tnorm=TNorm.MINIMUM))
    assert not kernels.extended(gaussian_system(Reducer.KM.value))
    assert all(kernels.extended(two_term_system(k, it2=False)) for k in range(len(TERMS))
               if {MFKind(int(v)) for v in two_term_system(k, it2=False).tables.mf_kind}
               != {MFKind.TRAPEZOID})
    assert kernels.extended(two_term_system(19, it2=True))  # a ramp's lagged lower MF
    tri = dataclasses.replace(heading_fls(0.0), tnorm=TNorm.EINSTEIN_PRODUCT)
    assert kernels.extended(tri)
    assert loop_kernels.supported(FuzzyHeadingController(fls=heading_fls(0.2))) is None
    assert "extended" in loop_kernels.supported(FuzzyHeadingController(fls=tri))
