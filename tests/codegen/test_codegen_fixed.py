"""The q15 fixed-point build: compiled on the host it equals an independent integer model of
its specification bit for bit (tests/codegen/fixed_model.py), every exact reducer returns the
same bits, and its error against the double system stays within the derived bound -- each of
whose terms is shown necessary: for each, some input makes the observed error exceed the bound
without that term."""

from __future__ import annotations

import dataclasses

import fixed_model
import numpy as np
import pytest
from codegen_helpers import host_lib_factory, random_system

import it2track
from it2track.codegen import RealType, generate_c
from it2track.codegen.errorbound import FIXED_TERMS, fixed_error_bound
from it2track.codegen.fixedpoint import M_FRAC, fixed_plan
from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Reducer, Rule, T1Sugeno, Trapezoid, Triangle
from it2track.io import UnsupportedFeatureError

FIXED_REDUCERS = [r for r in Reducer if r.value.name != "wu-mendel"]
EXACT = [r for r in FIXED_REDUCERS if r.value.exact]
PL_SHAPES = ("triangle", "trapezoid", "left", "right")


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("c-builds")


@pytest.fixture(scope="module")
def host_lib(build_dir):
    return host_lib_factory(build_dir)


def q15(host_lib, system, prefix="it2"):
    return host_lib(system, real=RealType.Q15, prefix=prefix)


def lattice_points(fmt, n_random, seed, *, grid=33):
    """Integer inputs: a grid over the whole int16 range (the universe and beyond), its
    extremes, and uniform random integers."""
    rng = np.random.default_rng(seed)
    n_in = len(fmt.in_frac)
    axis = np.unique(np.concatenate([np.linspace(-32768, 32767, grid).round(),
                                     [-32768, 32767, 0, 1, -1]]))
    axes = [axis] * n_in if n_in < 3 else [axis[::4]] * n_in
    g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, n_in)
    lo = np.array(fmt.in_lo)
    hi = np.array(fmt.in_hi)
    r = rng.integers(lo - 200, hi + 200, size=(n_random, n_in), endpoint=True)
    return np.clip(np.concatenate([g, r]), -32768, 32767).astype(np.int16)


def check_model(lib, system, q):
    code = lib.code
    plan = fixed_plan(system, code.reducer)
    u, yl, yr, status = lib.evaluate_raw(q)
    mu, myl, myr, mstatus, _, _ = fixed_model.evaluate(system, plan, q)
    np.testing.assert_array_equal(status, mstatus, err_msg=f"{system.name}: status")
    for name, got, want in (("u", u, mu), ("yl", yl, myl), ("yr", yr, myr)):
        bad = np.flatnonzero(got.astype(np.int64) != want)
        assert bad.size == 0, (f"{system.name} ({code.reducer}): {name} differs at "
                               f"q={q[bad[:3]].tolist()}: C {got[bad[:3]]}, model "
                               f"{want[bad[:3]]}")


def paper(fou, red=None):
    base = it2track.heading_fls(fou)
    return base if red is None else dataclasses.replace(base, reducer=red.value)


PAPER = [pytest.param(paper(0.0), id="fou0-type1")] + [
    pytest.param(paper(fou, red), id=f"fou{fou}-{red.value.name}")
    for fou in (0.1, 0.2, 0.3) for red in FIXED_REDUCERS]


@pytest.mark.parametrize("system", PAPER)
def test_paper_controllers_equal_the_integer_model(system, host_lib):
    lib = q15(host_lib, system)
    check_model(lib, system, lattice_points(lib.code.fixed, 1500, seed=1))


@pytest.mark.parametrize("seed", range(16))
def test_random_systems_equal_the_integer_model(seed, host_lib):
    type1 = seed % 6 == 5
    red = None if type1 else FIXED_REDUCERS[seed % len(FIXED_REDUCERS)]
    system = random_system(500 + seed, type1=type1, reducer=red, shapes=PL_SHAPES,
                           on_zero_firing=None if seed % 3 else float(seed) - 7.25)
    lib = q15(host_lib, system)
    check_model(lib, system, lattice_points(lib.code.fixed, 1500, seed=seed))


def test_random_systems_cover_what_fixed_point_carries():
    """The family above exercises interval consequents, both t-norms, 1-3 inputs, every
    reducer, zero-firing values and lower heights (guards the generator)."""
    from it2track.fuzzy import TNorm
    seen = {"interval": False, "min": False, "prod": False, "low": False, "zero": False}
    n_in, reds = set(), set()
    for seed in range(16):
        type1 = seed % 6 == 5
        s = random_system(500 + seed, type1=type1, shapes=PL_SHAPES,
                          reducer=None if type1 else FIXED_REDUCERS[seed % 5],
                          on_zero_firing=None if seed % 3 else 1.0)
        t = s.tables
        seen["interval"] |= not t.crisp
        seen["min"] |= s.tnorm is TNorm.MINIMUM
        seen["prod"] |= s.tnorm is TNorm.PRODUCT
        seen["low"] |= any(float(p[4]) < 1 for p in t.mf_params)
        seen["zero"] |= s.on_zero_firing is not None
        n_in.add(s.n_inputs)
        reds.add(getattr(s, "reducer", None) and s.reducer.name)
    assert all(seen.values()), seen
    assert n_in == {1, 2, 3}
    assert {r.value.name for r in FIXED_REDUCERS} <= reds


@pytest.mark.parametrize("fou", [0.1, 0.2, 0.3])
def test_every_exact_reducer_returns_the_same_bits(fou, host_lib):
    """In exact integer arithmetic exhaustive, KM, EKM and EIASC all find the true extremes of
    the integer firings' centroid."""
    outs = []
    q = None
    for red in EXACT:
        lib = q15(host_lib, paper(fou, red))
        q = lattice_points(lib.code.fixed, 4000, seed=7, grid=65) if q is None else q
        outs.append(lib.evaluate_raw(q))
    for other in outs[1:]:
        for a, b in zip(outs[0], other, strict=True):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("seed", [600, 601, 602, 603])
def test_exact_reducers_agree_on_random_interval_systems(seed, host_lib):
    base = random_system(seed, shapes=PL_SHAPES, on_zero_firing=0.5)
    outs = []
    for red in EXACT:
        lib = q15(host_lib, dataclasses.replace(base, reducer=red.value))
        outs.append(lib.evaluate_raw(lattice_points(lib.code.fixed, 2000, seed=seed)))
    for other in outs[1:]:
        for a, b in zip(outs[0], other, strict=True):
            np.testing.assert_array_equal(a, b)


# -- the error bound --------------------------------------------------------------------------

def real_points(system, n, seed, margin=0.2):
    rng = np.random.default_rng(seed)
    lo = np.array([i.universe[0] for i in system.inputs])
    hi = np.array([i.universe[1] for i in system.inputs])
    pad = margin * (hi - lo)
    return rng.uniform(lo - pad, hi + pad, size=(n, system.n_inputs))


def errors(lib, system, x):
    u, yl, yr, status = lib.evaluate(x)
    ref_l, ref_r = system.interval(*x.T)
    ref_u = system(*x.T)
    assert np.all(status == 0)
    return (np.abs(yl - ref_l), np.abs(yr - ref_r), np.abs(u - ref_u))


@pytest.mark.parametrize("system", PAPER)
def test_paper_controllers_within_the_bound(system, host_lib):
    lib = q15(host_lib, system)
    fmt = lib.code.fixed
    x = real_points(system, 20_000, seed=3)
    for pts in (x, fmt.inputs_seen(fmt.to_int(x))):  # real inputs and the integer grid
        bound = fixed_error_bound(system, fmt, pts)
        for name, err, b in zip(("yl", "yr", "u"), errors(lib, system, pts),
                                (bound.yl, bound.yr, bound.u), strict=True):
            assert np.all(np.isfinite(b)), "the paper's lower firing never vanishes"
            j = int(np.argmax(err / b))
            assert err[j] <= b[j], f"{name}: error {err[j]:.3g} > bound {b[j]:.3g} at {pts[j]}"


@pytest.mark.parametrize("seed", range(10))
def test_random_systems_within_the_bound(seed, host_lib):
    type1 = seed % 4 == 3
    system = random_system(700 + seed, type1=type1, shapes=PL_SHAPES,
                           reducer=None if type1 else FIXED_REDUCERS[seed % 5],
                           on_zero_firing=None)
    lib = q15(host_lib, system)
    x = real_points(system, 8000, seed=seed)
    u, yl, yr, status = lib.evaluate(x)
    _, fu = system.firing(*x.T)
    fires = fu.sum(axis=1) > 0
    bound = fixed_error_bound(system, lib.code.fixed, x)
    finite = np.isfinite(bound.u)
    assert finite.sum() > 0.5 * fires.sum()
    ok = fires & finite & (status == 0)
    ref_l, ref_r = system.interval(*x[ok].T)
    for name, got, ref, b in (("yl", yl[ok], ref_l, bound.yl[ok]),
                              ("yr", yr[ok], ref_r, bound.yr[ok]),
                              ("u", u[ok], system(*x[ok].T), bound.u[ok])):
        err = np.abs(got - ref)
        j = int(np.argmax(err / b))
        assert err[j] <= b[j], f"{system.name}: {name} {err[j]:.3g} > {b[j]:.3g} at {x[ok][j]}"


def test_the_millivolt_target_over_the_input_square(host_lib):
    """The paper's controller (FoU 0.2, exhaustive): at every input the q15 function can be
    given on a 257 x 257 grid of the square (and 20,000 random ones) the bound -- and so the
    error -- is below 1e-3 V, and the measured error is half an output step (2^-12 V)."""
    system = paper(0.2, Reducer.EXHAUSTIVE)
    lib = q15(host_lib, system)
    fmt = lib.code.fixed
    axis = np.linspace(-32768, 32767, 257).round()
    g = np.stack(np.meshgrid(axis, axis, indexing="ij"), -1).reshape(-1, 2)
    r = np.random.default_rng(11).integers(-32768, 32767, size=(20_000, 2), endpoint=True)
    x = fmt.inputs_seen(np.concatenate([g, r]))
    bound = fixed_error_bound(system, fmt, x)
    err = errors(lib, system, x)
    assert bound.u.max() < 1e-3 and bound.yl.max() < 1e-3 and bound.yr.max() < 1e-3
    assert err[2].max() <= bound.u.max()
    assert 2.0**-12 * 0.99 < err[0].max() <= 2.0**-12 * 1.01


# -- each term of the bound is needed -----------------------------------------------------------

def awkward_system():
    """Slopes whose constants round badly (widths of thirds and sevenths over a universe that
    is not a power of two), a lower height, and consequents that are not on the output grid."""
    a = IT2Set(Trapezoid(-3.0, -1.0 / 3.0, 0.2, 2.0 / 7.0), Triangle(-1.0, -1.0 / 3.0, 0.1, h=0.6),
               "A")
    b = IT2Set(Triangle(-0.7, 1.3, 2.9), Triangle(0.1, 1.3, 2.2, h=0.85), "B")
    c = IT2Set.from_fou(Triangle(-2.9, -2.9, 0.4), 0.3, "C")
    x = Input("x", (-2.9, 2.9), [a, b, c])
    return IT2Sugeno(inputs=[x, Input("z", (-2.9, 2.9), [a, b, c])],
                     rules=[Rule(["A", "B"], -1.0 / 3.0), Rule(["B", "C"], 2.0 / 3.0),
                            Rule(["C", "A"], 1.1), Rule(["B", "B"], (0.2, 0.45)),
                            Rule(["A", None], -0.9)],
                     name="awkward")


def _row_errors_everywhere(system):
    """Every row at every integer input: model (Q24) minus the exact double row, in Q24 units,
    and each row's bound."""
    plan = fixed_plan(system, system.reducer.name)
    fmt = plan.fmt
    out = []
    for row in plan.rows:
        q = np.zeros((65536, system.n_inputs), dtype=np.int64)
        q[:, row.inp] = np.arange(-32768, 32768)
        m = fixed_model.memberships(plan, q)[row.row]
        exact = system.tables.memberships(fmt.inputs_seen(q).T.copy())[row.row]
        out.append((row, np.abs(m - exact * 2.0**M_FRAC)))
    return out


def test_rows_term_rounding_and_constants_are_both_needed():
    """Every row at all 65,536 integer inputs stays within its bound (in Q24 steps); the
    final rounding's 1/2 is reached, and some row goes past it by its constants' rounding."""
    worst = []
    for row, err in _row_errors_everywhere(awkward_system()) + _row_errors_everywhere(
            paper(0.2)):
        bound = row.error()
        assert err.max() <= bound + 1e-6, f"row {row.row}: {err.max()} > {bound}"
        worst.append(err.max())
    assert max(worst) > 0.5 + 0.05, "some row needs its constants' rounding beyond the 1/2"


def test_input_term_is_needed_and_covers_the_universe_edge(host_lib):
    system = paper(0.3, Reducer.EXHAUSTIVE)
    lib = q15(host_lib, system)
    fmt = lib.code.fixed
    x = real_points(system, 20_000, seed=5, margin=0.0)
    x[:50, 0] = 1.0  # +1 is clipped to 32767 / 2^15
    bound = fixed_error_bound(system, fmt, x)
    err = errors(lib, system, x)
    without = bound.u - bound.terms["input"][2]
    assert np.all(err[2] <= bound.u)
    assert np.any(err[2] > without), "input rounding must be in the bound"
    at_edge = fixed_error_bound(system, fmt, np.array([[1.0, 0.3]]))
    assert at_edge.terms["input"][2][0] > 0  # the universe's top end is not on the grid


def plateau_system(h1, h2):
    """Two inputs whose only sets are plateaus of heights h1, h2 over the whole universe, and
    a second rule that always fires fully: the firing error is the product's rounding plus the
    heights' rounding, nothing else."""
    s1 = IT2Set.type1(Trapezoid(-2.0, -1.0, 1.0, 2.0, h=h1), "A")
    s2 = IT2Set.type1(Trapezoid(-2.0, -1.0, 1.0, 2.0, h=h2), "B")
    one = IT2Set.type1(Trapezoid(-2.0, -1.0, 1.0, 2.0), "O")
    inputs = [Input("x", (-1.0, 1.0), [s1, one]), Input("z", (-1.0, 1.0), [s2, one])]
    return T1Sugeno(inputs=inputs, rules=[Rule(["A", "B"], 0.0), Rule(["O", "O"], 1.0)])


def test_products_term_is_needed():
    """Heights exactly on the Q24 grid (no row error at all) whose product is not: the firing
    is off by the product's rounding alone, up to half a Q24 step -- which only the products
    term covers."""
    step = 2.0**-M_FRAC
    for a, b in ((1, 2), (3, 8), (5, 6)):
        h1, h2 = 0.5 + a * step, 0.5 + b * step
        system = plateau_system(h1, h2)
        plan = fixed_plan(system, "type-1")
        assert all(r.error() == 0 for r in plan.rows)
        m = fixed_model.memberships(plan, np.zeros((1, 2), dtype=np.int64))
        _, fu = fixed_model.firings(system, m)
        observed = abs(int(fu[0, 0]) * step - h1 * h2)
        assert 0.4 * step < observed <= 0.5 * step
        bound = fixed_error_bound(system, plan.fmt, np.zeros((1, 2)), plan=plan)
        assert bound.terms["rows"][0][0] == 0 and bound.terms["input"][0][0] == 0
        assert bound.terms["products"][0][0] > 0


def test_sensitivity_and_consequent_terms_are_needed(host_lib):
    """Before the output rounding, the exact quotient of the integer firings differs from the
    double system by the firing errors carried through the reducer plus the consequents'
    rounding: each of the two is needed somewhere (the awkward system's consequents are not on
    the output grid; the paper's are, so there the firing term alone must cover it)."""
    for system, need_cons in ((awkward_system(), True), (paper(0.3, Reducer.EXHAUSTIVE), False)):
        plan = fixed_plan(system, system.reducer.name)
        fmt = plan.fmt
        x = real_points(system, 1500, seed=9, margin=0.0)
        xs = fmt.inputs_seen(fmt.to_int(x))  # on the grid: no input term
        _, _, _, status, ex_l, _ = fixed_model.evaluate(system, plan, fmt.to_int(xs))
        bound = fixed_error_bound(system, fmt, xs, plan=plan)
        ok = (status == 0) & np.isfinite(bound.yl)
        ref_l, _ = system.interval(*xs[ok].T)
        got = np.array([float(v) for v, k in zip(ex_l, ok, strict=True) if k]) \
            * 2.0**-fmt.out_frac
        err = np.abs(got - ref_l)
        t = bound.terms
        pre = sum(t[k][0][ok] for k in ("input", "rows", "products", "consequents"))
        assert np.all(err <= pre + 1e-12)
        firing = sum(t[k][0][ok] for k in ("rows", "products"))
        assert np.any(err > t["consequents"][0][ok] + 1e-15), "the firing term is needed"
        if need_cons:
            assert np.any(err > firing + 1e-15), "the consequents' term is needed"
        else:
            assert np.all(t["consequents"][0] == 0)


def test_output_term_is_needed(host_lib):
    system = paper(0.2, Reducer.EXHAUSTIVE)
    lib = q15(host_lib, system)
    fmt = lib.code.fixed
    x = fmt.inputs_seen(fmt.to_int(real_points(system, 5000, seed=4)))
    bound = fixed_error_bound(system, fmt, x)
    err = errors(lib, system, x)
    for k, (e, b) in enumerate(zip(err, (bound.yl, bound.yr, bound.u), strict=True)):
        assert np.all(e <= b)
        assert np.any(e > b - bound.terms["output"][k])
    # u carries 2^-4 of a step more than yl, yr (it is formed from the finer quotients)
    step = 2.0**-fmt.out_frac
    assert bound.terms["output"][2][0] == pytest.approx((0.5 + 2**-4) * step, rel=0, abs=0)
    assert bound.terms["output"][0][0] == 0.5 * step
    assert set(bound.terms) == set(FIXED_TERMS)


# -- what fixed point refuses, and the header ----------------------------------------------------

def test_fixed_point_refuses_what_it_does_not_carry():
    from it2track.fuzzy import WU_MENDEL, Gaussian
    with pytest.raises(UnsupportedFeatureError, match="Wu-Mendel"):
        generate_c(dataclasses.replace(paper(0.2), reducer=WU_MENDEL), real=RealType.Q15)
    g = IT2Sugeno(inputs=[Input("x", (-1, 1), [IT2Set.type1(Gaussian(0, 0.5), "G")])],
                  rules=[Rule(["G"], 1.0)])
    with pytest.raises(UnsupportedFeatureError, match="Gaussian"):
        generate_c(g, real=RealType.Q15)
    weighted = random_system(301, features=True, shapes=PL_SHAPES)
    with pytest.raises(UnsupportedFeatureError, match="rule-language"):
        generate_c(weighted, real=RealType.Q15)
    narrow = IT2Sugeno(inputs=[Input("x", (1000.0, 1000.01), [
        IT2Set.type1(Triangle(1000.0, 1000.005, 1000.01), "A")])], rules=[Rule(["A"], 1.0)])
    with pytest.raises(UnsupportedFeatureError, match="too narrow"):
        generate_c(narrow, real=RealType.Q15)
    many = IT2Sugeno(inputs=[Input("x", (-1, 1), [IT2Set.from_fou(Triangle(-1, 0, 1), 0.1, "A")])],
                     rules=[Rule(["A"], float(k)) for k in range(128)])
    with pytest.raises(UnsupportedFeatureError, match="127"):
        generate_c(many, real=RealType.Q15)


def test_header_documents_the_scaling():
    code = generate_c(paper(0.2), real=RealType.Q15, prefix="ctl")
    h = code.header
    for text in ("typedef int16_t ctl_real;", "#define CTL_IN_FRAC_0 15",
                 "#define CTL_OUT_FRAC 11", "#define CTL_IN_LO_1 (-32768)",
                 "#define CTL_IN_HI_1 (32767)", "#define CTL_FIXED 16",
                 "int ctl_eval(const ctl_real in[CTL_N_IN], ctl_real *u, ctl_real *yl,"):
        assert text in h, text
    assert "float" not in code.source and "double" not in code.source
    assert "did not converge in (not iterative)" not in h
    assert code.fixed is not None and code.fixed.out_frac == 11
    assert code.fixed.to_int(np.array([[1.0, -1.0]])).tolist() == [[32767, -32768]]
    np.testing.assert_array_equal(code.fixed.to_real(np.array([24576, -2048])), [12.0, -1.0])
    with pytest.raises(ValueError, match="input 1 is NaN"):
        code.fixed.to_int(np.array([[0.0, np.nan]]))
