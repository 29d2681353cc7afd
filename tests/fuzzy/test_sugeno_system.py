"""Sugeno systems: reducer agreement on random 5x5 IT2 systems and the paper controller,
broadcasting and shapes, firing vs a naive product / minimum, the scalar fast path, bad input,
zero firing, control surfaces."""

from __future__ import annotations

import dataclasses
import itertools
import threading

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    Gaussian,
    Input,
    IT2Set,
    IT2Sugeno,
    Output,
    Rule,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
    ZeroFiringError,
    control_surface,
    rules_from_table,
)
from it2track.paper import heading_fls

EXACT = (KM, EKM, EIASC, EXHAUSTIVE)
TOL = 1e-12
LABELS = ("N", "Z", "P")
TABLE = {("N", "N"): -12, ("N", "Z"): -8, ("N", "P"): -4, ("Z", "N"): -8, ("Z", "Z"): 0,
         ("Z", "P"): 8, ("P", "N"): 4, ("P", "Z"): 8, ("P", "P"): 12}


# -- random IT2 systems -----------------------------------------------------------------------


def random_it2_set(rng: np.random.Generator, name: str) -> IT2Set:
    """A random IT2 triangle, trapezoid, uncertain-mean or uncertain-std Gaussian."""
    kind = int(rng.integers(4))
    h = float(rng.uniform(0.2, 1.0))  # lower MF height
    if kind == 0:
        a, b, c = np.sort(rng.uniform(-1.2, 1.2, 3)).tolist()
        s = float(rng.uniform(0, 0.5))
        t1, t2 = rng.uniform(0, 0.9, 2).tolist()
        return IT2Set(Triangle(a - s, b, c + s), Triangle(a + t1 * (b - a), b, c - t2 * (c - b), h),
                      name)
    if kind == 1:
        a, b, c, d = np.sort(rng.uniform(-1.2, 1.2, 4)).tolist()
        s = float(rng.uniform(0, 0.5))
        t1, t2 = rng.uniform(0, 0.9, 2).tolist()
        return IT2Set(Trapezoid(a - s, b, c, d + s),
                      Trapezoid(a + t1 * (b - a), b, c, d - t2 * (d - c), h), name)
    m = float(rng.uniform(-1, 1))
    if kind == 2:
        return IT2Set.gaussian_uncertain_mean(m, m + float(rng.uniform(0, 0.3)),
                                              float(rng.uniform(0.05, 0.5)), name)
    s1 = float(rng.uniform(0.05, 0.4))
    return IT2Set.gaussian_uncertain_std(m, s1, s1 * float(rng.uniform(1, 2)), name)


def random_system(seed: int, reducer=EXHAUSTIVE, tnorm=TNorm.PRODUCT) -> IT2Sugeno:
    """Two inputs with 5 random IT2 sets each, 25 rules with random interval consequents."""
    rng = np.random.default_rng(seed)
    names = [f"A{i}" for i in range(5)]
    inputs = [Input(v, (-1, 1), [random_it2_set(rng, n) for n in names]) for v in ("x1", "x2")]
    rules = []
    for a, b in itertools.product(names, names):
        lo = float(rng.normal(0, 5))
        rules.append(Rule((a, b), (lo, lo + float(rng.uniform(0, 3)))))
    return IT2Sugeno(inputs=inputs, rules=rules, reducer=reducer, tnorm=tnorm,
                     on_zero_firing=0.0, name=f"random {seed}")


def special_points(step: float = 0.05) -> np.ndarray:
    """A grid through every breakpoint of the paper's sets (multiples of 0.05), plus outside."""
    g = np.round(np.arange(-1.1, 1.1 + step / 2, step), 10)
    e, de = np.meshgrid(g, g, indexing="ij")
    return np.stack([e.ravel(), de.ravel()], axis=-1)


def agreement(systems, x):
    results = {s.reducer.name: s.interval(x[:, 0], x[:, 1]) for s in systems}
    worst = 0.0
    for (na, (al, ar)), (nb, (bl, br)) in itertools.combinations(results.items(), 2):
        d = max(np.abs(al - bl).max(), np.abs(ar - br).max())
        worst = max(worst, d)
        assert d <= TOL, f"{na} vs {nb}: max difference {d:.3g}"
    return results


@pytest.mark.parametrize("w", [0.1, 0.2, 0.3])
def test_paper_controller_exact_reducers_agree_on_1e5_inputs(w):
    rng = np.random.default_rng(int(w * 10))
    x = np.concatenate([rng.uniform(-1.2, 1.2, (100_000, 2)), special_points()])
    systems = [heading_fls(w, reducer=red) for red in EXACT]
    agreement(systems, x)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_5x5_system_exact_reducers_agree_on_1e5_inputs(seed):
    rng = np.random.default_rng(1000 + seed)
    x = rng.uniform(-1.1, 1.1, (100_000, 2))
    systems = [random_system(seed, reducer=red) for red in EXACT]
    results = agreement(systems, x)
    # ... and they are the true centroid interval (brute force on a subset).
    s = systems[0]
    fl, fu = s.firing(x[:3000, 0], x[:3000, 1])
    y_lo = np.array([r.consequent[0] for r in s.rules])
    y_hi = np.array([r.consequent[1] for r in s.rules])
    ref_l, ref_r = brute_force(fl, fu, y_lo, y_hi)
    yl, yr = results["exhaustive"]
    ok = ~np.isnan(ref_l)  # on_zero_firing=0.0 where nothing fires
    assert_allclose(yl[:3000][ok], ref_l[ok], atol=TOL)
    assert_allclose(yr[:3000][ok], ref_r[ok], atol=TOL)
    assert np.all(yl[:3000][~ok] == 0.0)


def brute_force(fl, fu, y_lo, y_hi):
    out = []
    for y, left in ((y_lo, True), (y_hi, False)):
        order = np.argsort(y, kind="stable")
        ys, a, b = y[order], fl[..., order], fu[..., order]
        best = np.full(fl.shape[:-1], np.nan)
        for k in range(len(y) + 1):
            theta = (np.concatenate([b[..., :k], a[..., k:]], -1) if left
                     else np.concatenate([a[..., :k], b[..., k:]], -1))
            with np.errstate(divide="ignore", invalid="ignore"):
                c = (theta * ys).sum(-1) / theta.sum(-1)
            best = np.fmin(best, c) if left else np.fmax(best, c)
        out.append(best)
    return out[0], out[1]


def test_random_system_with_min_tnorm_reducers_agree():
    rng = np.random.default_rng(77)
    x = rng.uniform(-1.1, 1.1, (20_000, 2))
    agreement([random_system(5, reducer=red, tnorm=TNorm.MINIMUM) for red in EXACT], x)


# -- firing -----------------------------------------------------------------------------------


def naive_firing(fls, e, de, tnorm=np.multiply):
    """Per-rule t-norm of the input sets' MFs, in the order the rules were given."""
    e, de = np.broadcast_arrays(np.clip(e, -1, 1), np.clip(de, -1, 1))
    sets_e = {s.name: s for s in fls.inputs[0].sets}
    sets_d = {s.name: s for s in fls.inputs[1].sets}
    lower, upper = [], []
    for rule in fls.rules:
        a, b = rule.antecedent
        lower.append(tnorm(sets_e[a].lower(e), sets_d[b].lower(de)))
        upper.append(tnorm(sets_e[a].upper(e), sets_d[b].upper(de)))
    return np.stack(lower, -1), np.stack(upper, -1)


@pytest.mark.parametrize("w", [0.0, 0.2])
@pytest.mark.parametrize(("tnorm", "op"), [(TNorm.PRODUCT, np.multiply),
                                           (TNorm.MINIMUM, np.minimum)])
def test_firing_equals_naive_tnorm_in_rule_order(w, tnorm, op):
    fls = heading_fls(w, tnorm=tnorm)
    rng = np.random.default_rng(11)
    e = rng.uniform(-1.3, 1.3, (7, 1, 3))
    de = rng.uniform(-1.3, 1.3, (1, 5, 3))
    lower, upper = fls.firing(e, de)
    assert lower.shape == upper.shape == (7, 5, 3, 9)
    ref_l, ref_u = naive_firing(fls, e, de, op)
    assert_allclose(lower, ref_l, rtol=0, atol=1e-15)
    assert_allclose(upper, ref_u, rtol=0, atol=1e-15)
    assert [r.antecedent for r in fls.rules] == list(itertools.product(LABELS, LABELS))


def test_min_tnorm_output_against_naive_centroid():
    # Type-1 with the minimum t-norm: u = sum(min(mu_e, mu_de) y) / sum(min(...)).
    fls = heading_fls(0.0, tnorm=TNorm.MINIMUM)
    rng = np.random.default_rng(12)
    e, de = rng.uniform(-1, 1, (2, 5000))
    f, _ = naive_firing(fls, e, de, np.minimum)
    y = np.array([r.consequent[0] for r in fls.rules])
    assert_allclose(fls(e, de), (f * y).sum(-1) / f.sum(-1), atol=TOL)
    # IT2 with min: brute-force centroid interval of the naive firing.
    it2 = heading_fls(0.2, tnorm=TNorm.MINIMUM)
    fl, fu = naive_firing(it2, e, de, np.minimum)
    ref = brute_force(fl, fu, y, y)
    assert_allclose(it2.interval(e, de), ref, atol=TOL)


def test_rule_without_an_input_uses_constant_one():
    z = IT2Set.from_fou(Triangle(-1, 0, 1), 0.2, "Z")
    p = IT2Set.from_fou(Triangle(0, 1, 1), 0.2, "P")
    inputs = [Input("a", (-1, 1), [z, p]), Input("b", (-1, 1), [z, p])]
    s = IT2Sugeno(inputs=inputs, rules=[Rule(["Z", None], -1.0), Rule([None, "P"], 1.0)])
    lower, upper = s.firing(0.3, 0.6)
    assert_allclose(upper, [z.upper(0.3), p.upper(0.6)])
    assert_allclose(lower, [z.lower(0.3), p.lower(0.6)])


# -- shapes -----------------------------------------------------------------------------------


def test_broadcasting_shapes():
    fls = heading_fls(0.2)
    e = np.linspace(-1, 1, 3).reshape(3, 1)
    de = np.linspace(-1, 1, 4).reshape(1, 4)
    u = fls(e, de)
    assert u.shape == (3, 4)
    for i, j in itertools.product(range(3), range(4)):
        assert u[i, j] == fls(float(e[i, 0]), float(de[0, j]))
    yl, yr = fls.interval(e, de)
    assert yl.shape == yr.shape == (3, 4)
    assert_allclose((yl + yr) / 2, u, rtol=0, atol=0)
    assert fls(e, 0.0).shape == (3, 1)
    assert fls(np.zeros((2, 0)), 0.0).shape == (2, 0)


def test_scalar_calls():
    fls = heading_fls(0.2)
    u = fls(0.3, -0.1)
    assert type(u) is float
    assert type(fls(np.float64(0.3), -0.1)) is float
    assert fls(1, 0) == 8.0  # Python ints take the fast path too
    arr = fls(np.array(0.3), np.array(-0.1))
    assert isinstance(arr, np.ndarray) and arr.shape == ()
    assert float(arr) == u
    yl, yr = fls.interval(0.3, -0.1)
    assert type(yl) is float and type(yr) is float and (yl + yr) / 2 == u


def _scalar_interval_systems():
    """One system of every class (IT2/T1 Sugeno, IT2/T1 Mamdani), one output each."""
    from it2track.fuzzy import IT2Mamdani, Output, T1Mamdani

    x = Input("x", (0, 1), [IT2Set(Triangle(0, 0, 1), Triangle(0, 0, 0.5), "lo"),
                            IT2Set(Triangle(0, 1, 1), Triangle(0.5, 1, 1), "hi")])
    y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                             IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    x1 = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    y1 = Output("y", (0, 4), [("small", Triangle(0, 0, 4)), ("big", Triangle(0, 4, 4))])
    rules = [Rule(["lo"], "small"), Rule(["hi"], "big")]
    return {
        **{f"IT2Sugeno-{r.name}": dataclasses.replace(heading_fls(0.2), reducer=r)
           for r in (*EXACT, NIE_TAN, WU_MENDEL)},
        "T1Sugeno": heading_fls(0.0),
        "IT2Mamdani": IT2Mamdani(inputs=[x], outputs=[y], rules=rules, resolution=9),
        "T1Mamdani": T1Mamdani(inputs=[x1], outputs=[y1], rules=rules, resolution=9),
    }


@pytest.mark.parametrize("engine", ["auto", "numpy"])
@pytest.mark.parametrize("name", list(_scalar_interval_systems()))
def test_interval_of_scalars_is_two_python_floats_like_the_call(name, engine, monkeypatch):
    monkeypatch.setenv("IT2TRACK_ENGINE", engine)
    fls = _scalar_interval_systems()[name]  # built after the engine is chosen
    point = (0.3, -0.1)[:fls.n_inputs]
    for xs in (point, tuple(np.float64(v) for v in point), tuple(int(v > 0) for v in point)):
        u = fls(*xs)
        yl, yr = fls.interval(*xs)
        assert type(u) is float and type(yl) is float and type(yr) is float, (name, xs)
        assert (yl + yr) / 2 == u, (name, xs)
        # the same bits as an array evaluation at that point
        arr_l, arr_r = fls.interval(*(np.array([v], dtype=float) for v in xs))
        assert (yl, yr) == (arr_l[0], arr_r[0]), (name, xs)
    # arrays, 0-d arrays included, stay arrays of the broadcast shape
    yl, yr = fls.interval(*(np.array(v) for v in point))
    assert isinstance(yl, np.ndarray) and yl.shape == yr.shape == ()
    yl, yr = fls.interval(*(np.full((2, 3), v) for v in point))
    assert yl.shape == yr.shape == (2, 3)


def test_interval_of_scalars_with_several_outputs_is_arrays():
    a = Input("a", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    fls = T1Sugeno(inputs=[a], rules=[Rule(["lo"], consequents=[1.0, 2.0]),
                                      Rule(["hi"], consequents=[3.0, 5.0])], outputs=("u", "v"))
    yl, yr = fls.interval(0.25)
    assert yl.shape == yr.shape == (2,)
    assert_allclose(yl, [1.5, 2.75], rtol=0, atol=1e-15)


def test_evaluate_stacked_inputs():
    fls = heading_fls(0.2)
    rng = np.random.default_rng(13)
    x = rng.uniform(-1, 1, (4, 5, 2))
    assert_array_equal(fls.evaluate(x), fls(x[..., 0], x[..., 1]))
    assert fls.evaluate(x).shape == (4, 5)
    assert fls.evaluate([0.3, -0.1]).shape == ()
    assert float(fls.evaluate([0.3, -0.1])) == fls(0.3, -0.1)


def test_lists_ints_float32_and_non_contiguous_inputs():
    fls = heading_fls(0.2)
    rng = np.random.default_rng(14)
    x = rng.uniform(-1, 1, (50, 2))
    ref = fls(x[:, 0].copy(), x[:, 1].copy())
    assert_array_equal(fls(x[:, 0], x[:, 1]), ref)  # strided views
    assert_array_equal(fls(list(x[:, 0]), list(x[:, 1])), ref)
    assert_array_equal(fls(np.array([1, 0, -1]), 0), fls(np.array([1.0, 0.0, -1.0]), 0.0))
    x32 = x.astype(np.float32)
    assert_array_equal(fls(x32[:, 0], x32[:, 1]),
                       fls(x32[:, 0].astype(np.float64), x32[:, 1].astype(np.float64)))


def test_large_batches_cross_internal_blocks_consistently():
    # 10^4 samples span several internal blocks (4096); every sample is evaluated on its own.
    fls = heading_fls(0.2, reducer=KM)
    rng = np.random.default_rng(15)
    x = rng.uniform(-1, 1, (10_001, 2))
    whole = fls(x[:, 0], x[:, 1])
    parts = np.concatenate([fls(x[i:i + 999, 0], x[i:i + 999, 1])
                            for i in range(0, len(x), 999)])
    assert_allclose(whole, parts, atol=TOL)
    lower, _ = fls.firing(x[:, 0], x[:, 1])
    assert_array_equal(lower[5000], fls.firing(x[5000, 0], x[5000, 1])[0])


def test_threads_share_a_system_safely():
    fls = heading_fls(0.2)
    rng = np.random.default_rng(16)
    xs = [rng.uniform(-1, 1, (20_000, 2)) for _ in range(4)]
    expected = [fls(x[:, 0], x[:, 1]) for x in xs]
    got: list = [None] * 4

    def work(i):
        for _ in range(3):
            got[i] = fls(xs[i][:, 0], xs[i][:, 1])

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for g, e in zip(got, expected, strict=True):
        assert_array_equal(g, e)


# -- scalar fast path -------------------------------------------------------------------------


@pytest.mark.parametrize("w", [0.0, 0.2])
@pytest.mark.parametrize("tnorm", [TNorm.PRODUCT, TNorm.MINIMUM])
def test_scalar_fast_path_equals_array_path_bit_for_bit(w, tnorm):
    fls = heading_fls(w, tnorm=tnorm)
    rng = np.random.default_rng(17)
    pts = np.concatenate([rng.uniform(-1.3, 1.3, (3000, 2)), special_points()])
    arr = fls(pts[:, 0], pts[:, 1])
    for (e, de), ref in zip(pts.tolist(), arr.tolist(), strict=True):
        u = fls(e, de)
        assert u == ref, f"fast path {u!r} != array path {ref!r} at ({e!r}, {de!r})"


def test_scalar_fast_path_on_random_interval_system():
    fls = random_system(3)
    rng = np.random.default_rng(18)
    pts = rng.uniform(-1.1, 1.1, (2000, 2))
    arr = fls(pts[:, 0], pts[:, 1])
    assert [fls(e, de) for e, de in pts.tolist()] == arr.tolist()


# -- type-1 special case ----------------------------------------------------------------------


def test_it2_system_with_type1_sets_equals_t1_system():
    t1 = heading_fls(0.0)
    assert isinstance(t1, T1Sugeno)
    it2_sets = [IT2Set.from_fou(Triangle(*p), 0.0, k) for k, p in
                (("N", (-1, -1, -0.2)), ("Z", (-0.8, 0, 0.8)), ("P", (0.2, 1, 1)))]
    inputs = [Input("e", (-1, 1), it2_sets), Input("de", (-1, 1), it2_sets)]
    rules = rules_from_table(LABELS, LABELS, [[-12, -8, -4], [-8, 0, 8], [4, 8, 12]])
    rng = np.random.default_rng(19)
    e, de = rng.uniform(-1, 1, (2, 20_000))
    for red in (*EXACT, NIE_TAN, WU_MENDEL):
        it2 = IT2Sugeno(inputs=inputs, rules=rules, reducer=red)
        assert_allclose(it2(e, de), t1(e, de), atol=TOL, err_msg=red.name)


def test_t1_system_from_name_mf_pairs():
    # N = (1 - x)/2, P = (1 + x)/2 on [-1, 1]: u = -2 N + 2 P = 2 x.
    mfs = [("N", Triangle(-1, -1, 1)), ("P", Triangle(-1, 1, 1))]
    s = T1Sugeno(inputs=[Input("x", (-1, 1), mfs)], rules=[Rule(["N"], -2.0), Rule(["P"], 2.0)])
    assert_allclose(s(np.array([-1.0, -0.5, 0.0, 0.25])), [-2.0, -1.0, 0.0, 0.5], atol=1e-15)


# -- bad input --------------------------------------------------------------------------------


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_nan_or_inf_input_names_the_input(bad):
    fls = heading_fls(0.2)
    with pytest.raises(ValueError, match="input 'e' contains NaN or inf"):
        fls(bad, 0.0)
    with pytest.raises(ValueError, match="input 'de' contains NaN or inf"):
        fls(np.zeros(3), np.array([0.0, bad, 0.0]))
    with pytest.raises(ValueError, match="input 'de'"):
        fls.interval(0.0, bad)
    with pytest.raises(ValueError, match="input 'e'"):
        fls.firing(np.array([[bad]]), 0.0)
    with pytest.raises(ValueError, match="input 'de'"):
        fls.evaluate([[0.0, 0.1], [0.2, bad]])


def test_huge_finite_inputs_are_clipped_without_warnings():
    fls = heading_fls(0.2)
    big = np.finfo(np.float64).max
    assert_array_equal(fls(np.array([big, big, -big]), 0.0), fls(np.array([1.0, 1.0, -1.0]), 0.0))
    assert fls(1e308, 1e308) == 12.0


def test_wrong_number_of_inputs():
    fls = heading_fls(0.2)
    with pytest.raises(ValueError, match=r"takes 2 inputs \(e, de\), got 1"):
        fls(0.1)
    with pytest.raises(ValueError, match="got 3"):
        fls(0.1, 0.2, 0.3)
    with pytest.raises(ValueError, match="got 3"):
        fls.firing(0.1, 0.2, 0.3)


def test_non_broadcasting_shapes():
    fls = heading_fls(0.2)
    with pytest.raises(ValueError, match=r"do not broadcast.*e: \(3,\), de: \(4,\)"):
        fls(np.zeros(3), np.zeros(4))


@pytest.mark.parametrize("x", [0.5, [0.1, 0.2, 0.3], np.zeros((4, 3)), np.zeros((2, 1))])
def test_evaluate_wrong_last_axis(x):
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 2\)"):
        heading_fls(0.2).evaluate(x)


def _z(name="Z"):
    return IT2Set.from_fou(Triangle(-1, 0, 1), 0.2, name)


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: IT2Sugeno(inputs=[], rules=[Rule(["Z"], 0.0)]), "at least one input"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[]), "at least one rule"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Q"], 0.0)]),
         "input 'x' has no set 'Q'"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Z", "Z"], 0.0)]),
         "2 antecedents for 1 inputs"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule([None], 0.0)]),
         "mentions no input"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()]), Input("x", (-1, 1), [_z()])],
                           rules=[Rule(["Z", "Z"], 0.0)]), "input names"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Z"], 0.0)],
                           tnorm="product"), "TNorm"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Z"], 0.0)],
                           reducer="km"), "TypeReducer"),
        (lambda: IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Z"], 0.0)],
                           on_zero_firing=float("nan")), "on_zero_firing"),
        (lambda: T1Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Z"], 0.0)]),
         "footprint of uncertainty"),
        (lambda: T1Sugeno(inputs=[Input("x", (-1, 1), [("Z", Triangle(-1, 0, 1))])],
                          rules=[Rule(["Z"], (0.0, 1.0))]), "crisp"),
        (lambda: Input("x", (1, -1), [_z()]), "lo < hi"),
        (lambda: Input("x", (-1, np.inf), [_z()]), "finite"),
        (lambda: Output("x", (-1, 1), []), "at least one set"),
        (lambda: Input("x", (-1, 1), [_z(), _z()]), "unique"),
        (lambda: Input("x", (-1, 1), [_z("")]), "non-empty"),
        (lambda: Rule(["Z"], (1.0, 0.0)), "lo <= hi"),
        (lambda: Rule(["Z"], (0.0, 1.0, 2.0)), "number or an interval"),
        (lambda: Rule(["Z"], float("nan")), "finite"),
        (lambda: rules_from_table(["N", "P"], ["Z"], [[1.0]]), "2 x 1"),
        (lambda: TNorm.from_name("max"), "unknown t-norm"),
    ],
)
def test_malformed_systems_raise_value_error(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_tnorm_names():
    assert TNorm.from_name("Product") is TNorm.PRODUCT
    assert TNorm.from_name("min") is TNorm.MINIMUM
    assert TNorm.from_name(" minimum ") is TNorm.MINIMUM


# -- zero firing ------------------------------------------------------------------------------


def disjoint_system(cls=IT2Sugeno, **kw):
    """Two narrow sets at the ends of [-1, 1]: nothing fires in (-0.775, 0.775)."""
    a = IT2Set.from_fou(Triangle(-1, -0.9, -0.8), 0.05, "A")
    b = IT2Set.from_fou(Triangle(0.8, 0.9, 1), 0.05, "B")
    if cls is T1Sugeno:
        a, b = IT2Set.type1(a.upper, "A"), IT2Set.type1(b.upper, "B")
        rules = [Rule(["A"], -1.0), Rule(["B"], 1.0)]
    else:
        rules = [Rule(["A"], -1.0), Rule(["B"], (1.0, 2.0))]
    return cls(inputs=[Input("x", (-1, 1), [a, b])], rules=rules, name="disjoint", **kw)


@pytest.mark.parametrize("red", [*EXACT, NIE_TAN, WU_MENDEL], ids=lambda r: r.name)
def test_zero_firing_raises_naming_the_point(red):
    s = disjoint_system(reducer=red)
    with pytest.raises(ZeroFiringError, match=r"no rule of IT2Sugeno 'disjoint' fires at \(x=0\)"):
        s(0.0)
    with pytest.raises(ZeroFiringError, match=r"x=0.5"):
        s(np.array([-0.9, 0.5, 0.9]))
    with pytest.raises(ZeroFiringError):
        s.interval(0.0)


@pytest.mark.parametrize("red", [*EXACT, NIE_TAN, WU_MENDEL], ids=lambda r: r.name)
def test_on_zero_firing_value_is_used_only_where_nothing_fires(red):
    s = disjoint_system(reducer=red, on_zero_firing=0.0)
    assert s(0.0) == 0.0
    u = s(np.array([-0.9, 0.0, 0.5, 0.9]))
    assert_allclose(u, [-1.0, 0.0, 0.0, 1.5])
    yl, yr = s.interval(np.array([0.0, 0.9]))
    # only rule B, consequent [1, 2], fires at 0.9 (Nie-Tan takes the interval's midpoint)
    assert_allclose(yl, [0.0, 1.5 if red is NIE_TAN else 1.0])
    assert_allclose(yr, [0.0, 1.5 if red is NIE_TAN else 2.0])
    assert not np.isnan(u).any()
    s7 = disjoint_system(reducer=red, on_zero_firing=7.5)
    assert s7(0.1) == 7.5 and float(s7(np.array(0.1))) == 7.5


def test_t1_zero_firing():
    with pytest.raises(ZeroFiringError, match="no rule of T1Sugeno 'disjoint' fires"):
        disjoint_system(T1Sugeno)(0.0)
    with pytest.raises(ZeroFiringError):
        disjoint_system(T1Sugeno)(np.zeros(3))
    s = disjoint_system(T1Sugeno, on_zero_firing=0.0)
    assert s(0.0) == 0.0
    assert_array_equal(s(np.array([0.0, -0.9, 0.9])), [0.0, -1.0, 1.0])


def test_wu_mendel_zero_lower_firing_is_not_replaced_silently():
    # At x = 0.81 rule B fires through its upper MF only (lower foot 0.825): the exact reducers
    # give 1.5, Wu-Mendel is undefined there, and must say so rather than use on_zero_firing.
    s = disjoint_system(reducer=WU_MENDEL, on_zero_firing=-99.0)
    with pytest.raises(ZeroFiringError, match="total lower firing strength is zero"):
        s(np.array([0.81]))
    assert disjoint_system(reducer=EXHAUSTIVE, on_zero_firing=-99.0)(0.81) == 1.5


# -- control surfaces -------------------------------------------------------------------------


def test_control_surface_shape_and_values():
    fls = heading_fls(0.2)
    e, de, u = control_surface(fls, points=21)
    assert e.shape == de.shape == u.shape == (21, 21)
    assert_array_equal(e[:, 0], np.linspace(-1, 1, 21))  # indexing="ij": e along axis 0
    assert_array_equal(de[0, :], np.linspace(-1, 1, 21))
    assert_array_equal(u, fls(e, de))
    assert u[0, 0] == -12.0 and u[-1, -1] == 12.0 and u[10, 10] == 0.0
    e2, de2, u2 = control_surface(fls, points=5, ranges={"e": (-0.5, 0.5)})
    assert_array_equal(e2[:, 0], np.linspace(-0.5, 0.5, 5))
    assert_array_equal(de2[0], np.linspace(-1, 1, 5))
    assert_array_equal(u2, fls(e2, de2))


def test_control_surface_errors():
    fls = heading_fls(0.2)
    with pytest.raises(ValueError, match="points"):
        control_surface(fls, points=1)
    with pytest.raises(ValueError, match="unknown inputs"):
        control_surface(fls, ranges={"x": (0, 1)})
    one = IT2Sugeno(inputs=[Input("x", (-1, 1), [_z()])], rules=[Rule(["Z"], 0.0)])
    with pytest.raises(ValueError, match="two-input"):
        control_surface(one)


def test_gaussian_system_broadcasts_like_piecewise_linear():
    s = IT2Set.gaussian_uncertain_std(0.0, 0.2, 0.3, "G")
    t = IT2Set.from_fou(Triangle(0, 1, 1), 0.2, "P")
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), [s, t]), Input("y", (-1, 1), [s, t])],
                    rules=[Rule(["G", "G"], 0.0), Rule(["P", None], 1.0),
                           Rule([None, "P"], (1.0, 2.0))])
    x = np.linspace(-1, 1, 6)[:, None]
    y = np.linspace(-1, 1, 7)[None, :]
    u = fls(x, y)
    assert u.shape == (6, 7)
    assert u[3, 4] == fls(float(x[3, 0]), float(y[0, 4]))
    assert isinstance(s.upper, Gaussian)


def test_systems_pickle_and_evaluate_identically():
    # Systems travel to worker processes and Dask workers; their per-thread scratch buffers
    # must not stop them, and the copy must compute the same bits.
    import pickle

    from it2track import heading_fls

    rng = np.random.default_rng(3)
    e, de = rng.uniform(-1.2, 1.2, (2, 5000))
    for w in (0.0, 0.2):
        fls = heading_fls(w)
        fls(e, de)  # populate the scratch buffers first
        copy = pickle.loads(pickle.dumps(fls))
        assert np.array_equal(copy(e, de), fls(e, de))
        assert copy(0.3, -0.1) == fls(0.3, -0.1)


@pytest.mark.parametrize("engine", ["numpy", "auto"])
@pytest.mark.parametrize("reducer", ["km", "ekm", "eiasc", "exhaustive", "nie-tan", "wu-mendel"])
def test_a_scalar_call_returns_a_python_float_on_every_engine_and_reducer(
        monkeypatch, engine, reducer):
    # The engine is chosen when a system is first evaluated, so the system is built after
    # the environment is set.
    from it2track.fuzzy import Reducer

    monkeypatch.setenv("IT2TRACK_ENGINE", engine)
    fls = dataclasses.replace(heading_fls(0.2), reducer=Reducer.from_name(reducer).value)
    u = fls(0.3, -0.1)
    assert type(u) is float
    assert u == float(fls(np.array([0.3]), np.array([-0.1]))[0])
