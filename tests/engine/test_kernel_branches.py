"""Every branch of the compiled fuzzy kernels (``it2track.fuzzy._jit``) on tiny batches, bit
for bit against the numpy reference.

The tests of ``test_compiled_fuzzy.py`` compare thousands of random points; these compare a few
dozen chosen ones (corners, shoulders, ties, the midpoint of an uncertain mean) per reducer,
membership shape, t-norm and status, so that they also run in seconds with the kernels as plain
Python (``NUMBA_DISABLE_JIT=1``), as the mutation testing of the kernels runs them
(``tools/mutation.py it2track.fuzzy._jit --no-jit``).
"""

import dataclasses
import math

import numpy as np
import pytest

from it2track.fuzzy import (
    Bell,
    Cosine,
    Gaussian,
    GaussianProduct,
    Input,
    IT2Set,
    IT2Sugeno,
    LinearSShape,
    MFKind,
    PiShape,
    Ramp,
    Rectangle,
    Reducer,
    Rule,
    Sigmoid,
    SigmoidDifference,
    SShape,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    WeightedDefuzzifier,
    ZeroFiringError,
    _jit,
    kernels,
)
from it2track.fuzzy.reducers import ConvergenceError
from it2track.paper import heading_fls

REDUCERS = [m.value for m in Reducer]
GRID = np.array([-1.0, -0.75, -0.5, -0.3, -0.1, 0.0, 0.1, 0.25, 0.5, 0.8, 1.0])


def reference(fls, *xs):
    x, shape = fls._prepare(xs)
    yl, yr = fls._interval_blocks(x)
    return yl.reshape(shape), yr.reshape(shape)


def bits(a):
    return np.asarray(a, dtype=np.float64).view(np.int64)


def same(a, b):
    """The same 64 bits (signed zeros and NaN payloads told apart)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and bool(np.all(bits(a) == bits(b)))


def grid(n_inputs, values=GRID):
    """Every combination of ``values`` (a full grid for two inputs, a diagonal band for
    three): the corners and shoulders of the sets land exactly."""
    if n_inputs == 1:
        return values[None, :].copy()
    if n_inputs == 2:
        a, b = np.meshgrid(values, values[::-1])
        return np.stack([a.ravel(), b.ravel()])
    v = values
    return np.stack([v, np.roll(v, 3), np.roll(v[::-1], 5)])


def expected(fls, x):
    """The reference's ``yl``, ``yr`` per point (NaN where it raises) and the kernels' status
    for it: OK, or the code of the error the reference raises there."""
    try:
        rl, rr = reference(fls, *x)
        return rl, rr, np.full(x.shape[1], _jit.OK, dtype=np.int8)
    except (ZeroFiringError, ConvergenceError):
        pass
    n = x.shape[1]
    rl, rr, st = np.full(n, np.nan), np.full(n, np.nan), np.zeros(n, dtype=np.int8)
    for j in range(n):
        try:
            (rl[j],), (rr[j],) = reference(fls, *x[:, j : j + 1])
        except ZeroFiringError as exc:
            lower = "total lower firing" in str(exc)
            st[j] = _jit.WM_ZERO_LOWER if lower else _jit.ZERO_FIRING
        except ConvergenceError:
            st[j] = _jit.NOT_CONVERGED
    return rl, rr, st


def direct(fls, x):
    """The kernels called directly on the clipped points (the public calls hand a point whose
    status is not OK to the reference, which would hide a kernel's NaN): ``yl``, ``yr`` and
    the status of two ranges, and the crisp output of all the points at once."""
    packed = kernels._entry(fls)
    assert packed is not None, kernels.supported(fls)
    ext = (True,) if fls.__dict__["_kernel_ext"] else ()
    xc, _ = fls._prepare(tuple(x))
    n = xc.shape[1]
    yl, yr, u = np.full(n, -7.0), np.full(n, -7.0), np.full(n, -7.0)
    st, st_u = np.full(n, 9, dtype=np.int8), np.full(n, 9, dtype=np.int8)
    cut = n // 3
    for a, b in ((0, cut), (cut, n)):
        _jit.batch(packed, xc, yl, yr, st, False, a, b, *ext)
    _jit.batch(packed, xc, u, u, st_u, True, 0, n, *ext)
    return xc, ext, yl, yr, st, u, st_u


def check(fls, x, *, scalar=True):
    """The kernels' interval, crisp output and status of every point, their scalar call (two
    inputs) and the public calls against the reference, bit for bit."""
    rl, rr, want = expected(fls, x)
    _, ext, yl, yr, st, u, st_u = direct(fls, x)
    assert (st == want).all() and (st_u == want).all(), (st, st_u, want)
    ok = want == _jit.OK
    assert same(yl[ok], rl[ok]) and same(yr[ok], rr[ok]), (x, yl, rl, yr, rr)
    assert same(u[ok], (rl[ok] + rr[ok]) * 0.5)
    if fls.n_inputs == 2:
        for j in range(x.shape[1]) if scalar else range(0, x.shape[1], 7):
            got = _jit.scalar2(kernels._entry(fls), float(x[0, j]), float(x[1, j]), *ext)
            assert same(got, (rl[j] + rr[j]) * 0.5 if ok[j] else math.nan), (x[:, j], got)
    # the public calls: the kernels where every point is OK, else the reference's error
    if ok.all():
        pl, pr = fls.interval(*x)
        assert same(pl, rl) and same(pr, rr)
        assert same(fls(*x), (rl + rr) * 0.5)
    if scalar and fls.n_inputs == 2:
        for j in np.flatnonzero(ok)[:5]:
            assert same(fls(float(x[0, j]), float(x[1, j])), (rl[j] + rr[j]) * 0.5)


def gaussian_system(reducer, tnorm=TNorm.PRODUCT, zero=None):
    """Uncertain-mean (upper and lower kinds) and uncertain-std Gaussians, interval
    consequents in an order that differs from the lower ends'."""
    sets = [
        IT2Set.gaussian_uncertain_mean(-1.0, -0.6, 0.3, "N"),
        IT2Set.gaussian_uncertain_std(0.0, 0.2, 0.35, "Z", h=0.9),
        IT2Set.gaussian_uncertain_mean(0.5, 0.8, 0.25, "P"),
    ]
    inputs = [Input("a", (-1, 1), sets), Input("b", (-2, 2), sets)]
    rules = [Rule((p, q), (i - j - 0.5, i - j + 0.25 * (i % 2) + 0.6 * (j == 1)))
             for i, p in enumerate("NZP") for j, q in enumerate("NZP")]  # fmt: skip
    return IT2Sugeno(inputs=inputs, rules=rules, reducer=reducer, tnorm=tnorm,
                     on_zero_firing=zero)  # fmt: skip


def tie_system(reducer, tnorm=TNorm.PRODUCT):
    """Integer consequents, a rule on one input only (the row of ones) and symmetric sets: the
    centroid lands on a consequent (KM/EKM's ties) at the symmetric points."""
    sets = [IT2Set.from_fou(Trapezoid(-1, -1, -0.4, 0.0), 0.2, "N"),
            IT2Set.from_fou(Triangle(-0.5, 0.0, 0.5), 0.3, "Z"),
            IT2Set.from_fou(Trapezoid(0.0, 0.4, 1, 1), 0.2, "P")]
    inputs = [Input("a", (-1, 1), sets), Input("b", (-1, 1), sets)]
    rules = [Rule(("N", "N"), -2.0), Rule(("N", "Z"), -1.0), Rule(("Z", None), 0.0),
             Rule(("P", "Z"), 1.0), Rule(("P", "P"), (2.0, 3.0)), Rule((None, "N"), (-1.0, 1.0)),
             Rule(("Z", "P"), (1.0, 1.0))]
    return IT2Sugeno(inputs=inputs, rules=rules, reducer=reducer, tnorm=tnorm,
                     on_zero_firing=0.5)


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_every_reducer_on_the_paper_grid(reducer):
    check(heading_fls(0.3, reducer=reducer), grid(2))


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_every_reducer_on_gaussians(reducer):
    """Gaussian kinds, the uncertain mean's midpoint exactly (lower MF: ``v <= mid``), and
    interval consequents sorted differently at their two ends."""
    mids = np.array([-1.0, -0.8, -0.79, -0.5, -0.2, 0.0, 0.3, 0.65, 0.7, 1.0, 1.6])
    check(gaussian_system(reducer), grid(2, mids))
    check(gaussian_system(reducer, TNorm.MINIMUM), grid(2, mids[::2]), scalar=False)


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_every_reducer_with_ties_and_rules_on_one_input(reducer):
    check(tie_system(reducer), grid(2))
    check(tie_system(reducer, TNorm.MINIMUM), grid(2), scalar=False)


def test_type1_average_and_sum():
    sets = [("L", Trapezoid(-3, -3, -1, 0.5, h=0.8)), ("H", Triangle(-1, 1, 1))]
    t1 = T1Sugeno(inputs=[Input("x", (-3, 1), sets)], rules=[Rule(["L"], -2.0),
                  Rule(["H"], 3.0)])  # fmt: skip
    x = grid(1, np.array([-3.5, -3.0, -1.0, -0.5, 0.0, 0.5, 0.75, 1.0, 2.0]))
    check(t1, x)
    check(heading_fls(0.0), grid(2))
    check(heading_fls(0.0, tnorm=TNorm.MINIMUM), grid(2), scalar=False)
    wsum = dataclasses.replace(t1, defuzzifier=WeightedDefuzzifier.SUM, on_zero_firing=-4.0)
    check(wsum, x)
    assert wsum(np.array([0.0, 0.75]))[1] == 0.875 * 3.0  # (H 0.875, L 0)
    gap = T1Sugeno(inputs=[Input("x", (-3, 1), [("L", Triangle(-3, -2, -1)),
                                                ("H", Triangle(0, 0.5, 1))])],
                   rules=[Rule(["L"], -2.0), Rule(["H"], 3.0)],
                   defuzzifier=WeightedDefuzzifier.SUM, on_zero_firing=-4.0)
    check(gap, x)
    assert list(gap(np.array([-2.0, -0.5, 0.25]))) == [-2.0, -4.0, 1.5]


#: One term of each compiled family (the kinds of curves/shapes, through _jit_lib._curve).
TERMS = [Bell(0.0, 0.5, 2.0), Sigmoid(0.2, 6.0), SShape(-1.0, 0.2), Cosine(0.0, 1.2),
         Rectangle(-0.4, 0.4), Ramp(-1.0, 1.0), LinearSShape(-0.5, 0.5), Gaussian(0.5, 0.3, h=0.9),
         SigmoidDifference(-0.5, 8.0, 8.0, 0.5, h=0.8), PiShape(-1.0, -0.3, 0.3, 1.0, h=0.9),
         GaussianProduct(-0.3, 0.2, 0.3, 0.25, h=0.7)]  # (the last three: a height parameter)


def term_system(a, b, *, it2, tnorm=TNorm.PRODUCT, reducer=None):
    if it2:  # MATLAB's type-2: lower MF scaled and lagged from the upper one (kind 19)
        sets = [IT2Set.from_scale_lag(a, scale=0.8, lag=0.2, name="A"),
                IT2Set.from_scale_lag(b, scale=0.9, lag=0.1, name="B")]
    else:
        sets = [IT2Set.type1(a, "A"), IT2Set.type1(b, "B")]
    inputs = [Input("x", (-1, 1), sets), Input("y", (-1, 1), sets)]
    rules = [Rule(["A", "A"], -1.0), Rule(["A", "B"], 0.5), Rule(["B", "A"], 1.0),
             Rule(["B", "B"], 2.0), Rule(["A", None], 0.0), Rule([None, "B"], 1.5)]
    if it2:
        return IT2Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, on_zero_firing=0.25,
                         reducer=reducer or Reducer.EXHAUSTIVE.value)
    return T1Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, on_zero_firing=0.25)


@pytest.mark.parametrize("k", range(len(TERMS)), ids=lambda k: type(TERMS[k]).__name__)
def test_every_membership_family(k):
    a, b = TERMS[k], TERMS[(k + 3) % len(TERMS)]
    x = grid(2, GRID[::2])
    check(term_system(a, b, it2=False), x, scalar=k == 0)
    fls = term_system(a, b, it2=True)
    assert MFKind.SCALED_LAGGED in {MFKind(int(v)) for v in fls.tables.mf_kind}
    check(fls, x, scalar=k == 1)  # (the scalar call of the extended kernels, once each)


@pytest.mark.parametrize("tnorm", list(TNorm), ids=lambda t: t.name)
def test_every_tnorm(tnorm):
    """The t-norms fold over the inputs a rule mentions (the rule on "A" alone skips the row of
    ones), in the kernels as in numpy."""
    x = grid(2, GRID[1::2])
    check(term_system(TERMS[0], TERMS[5], it2=False, tnorm=tnorm), x, scalar=False)
    check(term_system(TERMS[0], TERMS[5], it2=True, tnorm=tnorm, reducer=Reducer.KM.value), x,
          scalar=False)
    check(dataclasses.replace(heading_fls(0.2, tnorm=tnorm), on_zero_firing=0.0), x,
          scalar=False)


def three_input_system(reducer, max_iter=None):
    sets = [IT2Set.from_fou(Trapezoid(-1, -1, -0.4, 0.0), 0.2, "S0"),
            IT2Set.from_fou(Triangle(-0.6, 0.1, 0.7), 0.25, "S1"),
            IT2Set.from_fou(Trapezoid(0.0, 0.4, 1, 1), 0.2, "S2")]
    inputs = [Input(f"x{i}", (-1, 1), sets) for i in range(3)]
    ante = [("S0", "S1", None), ("S1", None, "S2"), (None, "S2", "S0"), ("S2", "S2", "S2"),
            ("S1", "S1", "S1"), ("S0", None, None), ("S2", "S0", "S1")]
    cons = [(-3.0, -2.0), (1.0, 1.5), (0.0, 2.0), (3.0, 3.0), (0.0, 0.5), (-1.0, 1.0), (2.0, 2.5)]
    rules = [Rule(a, c) for a, c in zip(ante, cons, strict=True)]
    return IT2Sugeno(inputs=inputs, rules=rules, on_zero_firing=0.25,
                     reducer=reducer.with_max_iter(max_iter))


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_every_reducer_with_three_inputs(reducer):
    check(three_input_system(reducer), grid(3))


@pytest.mark.parametrize("reducer", [Reducer.KM, Reducer.EKM, Reducer.EIASC],
                         ids=lambda r: r.value.name)
def test_no_convergence_is_the_references(reducer):
    """A cap on the iterations: the points that need more are NOT_CONVERGED in the kernels and
    raise in numpy, the others keep their values, up to the cap that is enough everywhere."""
    x = grid(3)
    for cap in range(1, 12):
        fls = three_input_system(reducer.value, cap)
        want = expected(fls, x)[2]
        check(fls, x)
        if (want == _jit.OK).all():
            break
        assert set(want) <= {_jit.OK, _jit.NOT_CONVERGED}
        with pytest.raises(ConvergenceError, match="did not converge"):
            fls.interval(*x)
    assert cap > 1 and (want == _jit.OK).all()


def test_zero_firing_value_status_and_errors():
    sets = [IT2Set.from_fou(Triangle(-1, -0.5, 0), 0.1, "A")]
    x = grid(1)
    for reducer in REDUCERS:
        fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)], rules=[Rule(["A"], 2.0)],
                        reducer=reducer, on_zero_firing=-0.75)  # fmt: skip
        assert fls(0.6) == -0.75
        if reducer.name != "wu-mendel":  # (its zero lower firing raises near the feet)
            check(fls, x)
            assert list(fls.interval(x[0])[0][-4:]) == [-0.75] * 4
        strict = dataclasses.replace(fls, on_zero_firing=None)
        with pytest.raises(ZeroFiringError, match="no rule"):
            strict(np.array([-0.5, 0.6]))
        assert strict(np.array([-0.5]))[0] == 2.0
    two = IT2Sugeno(inputs=[Input("x", (-1, 1), sets), Input("y", (-1, 1), sets)],
                    rules=[Rule(["A", "A"], 2.0)])
    assert two(-0.5, -0.5) == 2.0  # the scalar call
    with pytest.raises(ZeroFiringError, match="no rule"):
        two(-0.5, 0.5)
    t1 = T1Sugeno(inputs=[Input("x", (-1, 1), [("A", Triangle(-1, -0.5, 0))])],
                  rules=[Rule(["A"], 2.0)])  # fmt: skip
    with pytest.raises(ZeroFiringError, match="no rule"):
        t1(np.array([-0.5, 0.5]))
    assert t1(np.array([-0.5, -0.25]))[1] == 2.0


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_upper_firing_only(reducer):
    """Points where a rule fires on its upper MF only, alone or with others: zero lower sums,
    switch points at the ends, ties at the lowest and highest consequent."""
    sets = [IT2Set(Triangle(-1, -0.5, 0.0), Triangle(-0.9, -0.5, -0.1), "A"),
            IT2Set(Triangle(-0.2, 0.5, 1), Triangle(0.1, 0.5, 0.9), "B")]  # fmt: skip
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)],
                    rules=[Rule(["A"], -1.0), Rule(["B"], (1.0, 2.0))], reducer=reducer,
                    on_zero_firing=0.125)
    check(fls, grid(1, np.array([-1.0, -0.95, -0.5, -0.15, -0.05, 0.0, 0.05, 0.5, 0.95, 1.0])))


def test_wu_mendel_zero_lower_firing():
    sets = [IT2Set(Triangle(-1, -0.5, 0.0), Triangle(-0.9, -0.5, -0.1), "A"),
            IT2Set(Triangle(0.0, 0.5, 1), Triangle(0.1, 0.5, 0.9), "B")]  # fmt: skip
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)],
                    rules=[Rule(["A"], -1.0), Rule(["B"], 1.0)], reducer=Reducer.WU_MENDEL.value,
                    on_zero_firing=0.125)
    with pytest.raises(ZeroFiringError, match="total lower firing"):
        fls(np.array([0.3, -0.05]))
    with pytest.raises(ZeroFiringError, match="total lower firing"):
        fls(0.05)
    assert fls(0.0) == 0.125  # no upper firing either: the zero-firing value
    check(fls, grid(1, np.array([-0.9, -0.5, -0.3, 0.0, 0.3, 0.5, 0.9])))


def test_non_finite_inputs_are_the_references():
    fls = heading_fls(0.2)
    with pytest.raises(ValueError, match="NaN or inf"):
        fls(math.nan, 0.0)
    with pytest.raises(ValueError, match="NaN or inf"):
        fls(0.0, math.inf)
    assert fls(2.0, -3.0) == fls(1.0, -1.0)  # clipped to the universe
    assert fls(-5.0, 0.25) == fls(-1.0, 0.25)
    packed = kernels._entry(fls)  # the scalar kernel: NaN (the reference then raises)
    for a, b in ((math.nan, 0.0), (0.0, math.nan), (math.inf, 0.0), (0.0, -math.inf)):
        assert math.isnan(_jit.scalar2(packed, a, b))
    for a, b in ((2.0, -3.0), (-5.0, 0.25), (0.3, 7.0)):
        clipped = np.array([[min(max(a, -1.0), 1.0)], [min(max(b, -1.0), 1.0)]])
        rl, rr = reference(fls, *clipped)
        assert same(_jit.scalar2(packed, a, b), (rl[0] + rr[0]) * 0.5)


def test_batches_across_blocks_interval_and_crisp():
    """More points than a kernel block (256): every block's points, in order."""
    from it2track.fuzzy import _jit

    sets = [("L", Trapezoid(-3, -3, -1, 0.5, h=0.8)), ("H", Triangle(-1, 1, 1))]
    t1 = T1Sugeno(inputs=[Input("x", (-3, 1), sets)], rules=[Rule(["L"], -2.0),
                  Rule(["H"], 3.0)])  # fmt: skip
    n = _jit.BLOCK + 45
    x = np.linspace(-3.0, 1.0, n)[None, :]
    check(t1, x)
    fls = heading_fls(0.2)
    x2 = np.stack([np.linspace(-1, 1, n), np.linspace(1, -1, n) ** 3])
    check(fls, x2, scalar=False)


@pytest.mark.parametrize("reducer", [Reducer.KM, Reducer.EKM, Reducer.EIASC],
                         ids=lambda r: r.value.name)
@pytest.mark.parametrize("cap", [1, 2, 3])
def test_iteration_counts_on_two_inputs(reducer, cap):
    """Each point converges within the same number of iterations as in numpy: the iterative
    reducers' starting points (KM's midpoint centroid, EKM's switch points) and steps, seen
    through which points a small cap stops."""
    for fls in (heading_fls(0.3), gaussian_system(reducer.value), tie_system(reducer.value)):
        check(dataclasses.replace(fls, reducer=reducer.value.with_max_iter(cap)), grid(2),
              scalar=False)



@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_interval_consequents_in_another_order_at_their_upper_ends(reducer):
    """The rule with the lowest lower end (-3) has the highest upper end (5): the right side's
    first rule is not the left side's (the order of y_hi, not the identity)."""
    sets = [IT2Set.from_fou(Triangle(-1, -1, 0), 0.2, "A"),
            IT2Set.from_fou(Triangle(-1, 0, 1), 0.3, "B"),
            IT2Set.from_fou(Triangle(0, 1, 1), 0.2, "C")]
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)], reducer=reducer,
                    rules=[Rule(["A"], (-3.0, 5.0)), Rule(["B"], (-2.0, -1.0)),
                           Rule(["C"], (0.0, 0.5))])
    assert list(fls.tables.order_hi_s) != sorted(fls.tables.order_hi_s)
    x = np.linspace(-1.0, 1.0, 41)[None, :]  # (upper-only firing near the feet too)
    check(fls, x)
    if reducer.name in ("km", "ekm", "eiasc"):  # the start and each step, through the caps
        for cap in (1, 2, 3):
            check(dataclasses.replace(fls, reducer=reducer.with_max_iter(cap)), x)


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_equal_consequent_ends(reducer):
    """All lower ends equal and all upper ends equal: Wu-Mendel's p + q is 0 on both sides
    (its correction term is then 0, not 0 / 0)."""
    sets = [IT2Set.from_fou(Triangle(-1, -0.5, 0.5), 0.3, "A"),
            IT2Set.from_fou(Triangle(-0.5, 0.5, 1), 0.3, "B")]
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)], reducer=reducer,
                    rules=[Rule(["A"], (1.0, 2.0)), Rule(["B"], (1.0, 2.0))])
    check(fls, grid(1, np.array([-0.5, -0.2, 0.0, 0.1, 0.3, 0.5])))
    yl, yr = fls.interval(np.array([-0.2, 0.0, 0.3]))
    if reducer is Reducer.NIE_TAN.value:  # (the midpoints' centroid)
        assert list(yl) == list(yr) == [1.5] * 3
    else:
        assert list(yl) == [1.0] * 3 and list(yr) == [2.0] * 3


@pytest.mark.parametrize("reducer", REDUCERS, ids=lambda r: r.name)
def test_signed_zero_centroids(reducer):
    """Centroids that are zeros of either sign (subnormal consequents): the exhaustive
    reducer keeps the first of equal candidates (np.fmin / np.fmax), -0.0 over a later +0.0."""
    a = IT2Set.type1(Rectangle(-1.0, 1.0), "A")
    b = IT2Set(Rectangle(-1.0, 1.0), Rectangle(0.5, 1.0), "B")
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), [a, b])], reducer=reducer,
                    rules=[Rule(["A"], -5e-324), Rule(["A"], -0.0), Rule(["B"], 1e-323)])
    check(fls, grid(1, np.array([0.0, 0.75])))
    if reducer is Reducer.EXHAUSTIVE.value:
        yl, yr = fls.interval(np.array([0.0]))
        assert bits(yl)[0] == bits(-0.0) and bits(yr)[0] == bits(-0.0)


@pytest.mark.parametrize("cap", [1, 2])
def test_one_rule_ekm_starts_at_switch_point_zero(cap):
    """With one rule EKM's left switch point starts at round(1 / 2.4) = 0: where the rule
    fires on its upper MF only, both sides need a second iteration, elsewhere one is enough."""
    sets = [IT2Set(Triangle(-1, 0, 1), Triangle(-0.5, 0, 0.5), "Z")]
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), sets)], rules=[Rule(["Z"], (0.5, 1.0))],
                    reducer=Reducer.EKM.value.with_max_iter(cap), on_zero_firing=0.0)
    x = grid(1, np.array([0.0, 0.75]))
    check(fls, x)
    assert list(expected(fls, x)[2]) == [_jit.OK, _jit.NOT_CONVERGED if cap == 1 else _jit.OK]
