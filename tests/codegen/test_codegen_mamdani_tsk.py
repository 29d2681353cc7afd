"""C for Mamdani systems (type-1 and interval type-2, centroid on the output grid) and
first-order (TSK) systems: compiled on the host, the double build equals the Python system to
1e-12 and the float build stays within the bound derived in it2track.codegen.errorbound and
errorbound_mamdani, for the paper's controller in both forms with every reducer, every
implication and aggregation, and random systems with rule-language features; the statuses match
Python's errors; what is not carried is refused by name."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from codegen_helpers import (
    host_lib_factory,
    paper_mamdani,
    paper_tsk,
    points,
    random_mamdani,
    random_tsk,
)

from it2track.codegen import RealType, generate_c
from it2track.codegen.errorbound import float_error_bound
from it2track.codegen.generate import SUPPORTED_AGGREGATIONS, SUPPORTED_IMPLICATIONS
from it2track.fuzzy import (
    Aggregation,
    Defuzzifier,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    Output,
    Reducer,
    Rule,
    T1Mamdani,
    Triangle,
    TypeReduction,
    ZeroFiringError,
)
from it2track.io import UnsupportedFeatureError

OK, BAD_INPUT, ZERO_FIRING, NO_CONVERGENCE, ZERO_LOWER = range(5)


@pytest.fixture(scope="module")
def host_lib(tmp_path_factory):
    return host_lib_factory(tmp_path_factory.mktemp("c-builds"))


def reference(system, x):
    """Python's (u, yl, yr, status, ok) per point, with the C status convention: no rule fires
    -> ZERO_FIRING (or the configured value); Wu-Mendel with no lower firing (aggregated lower
    MF) -> ZERO_LOWER_FIRING."""
    fl, fu = system.firing(*x.T)
    zero = fu.sum(axis=1) == 0
    wm_bad = np.zeros_like(zero)
    if getattr(system, "reducer", None) is not None and system.reducer.name == "wu-mendel":
        if isinstance(system, IT2Mamdani) and system.type_reduction is TypeReduction.CENTROID:
            lower, _ = system.aggregated(*x.T)
            wm_bad = (lower.sum(axis=1) == 0) & ~zero
        else:
            wm_bad = (fl.sum(axis=1) == 0) & ~zero
    ok = ~zero & ~wm_bad
    u, yl, yr = np.zeros(len(x)), np.zeros(len(x)), np.zeros(len(x))
    status = np.full(len(x), OK, dtype=np.intc)
    if ok.any():
        yl[ok], yr[ok] = system.interval(*x[ok].T)
        u[ok] = system(*x[ok].T)
    zero_value = system.zero_firing_value(0)
    if zero_value is None:
        status[zero] = ZERO_FIRING
    else:
        u[zero] = yl[zero] = yr[zero] = zero_value
    status[wm_bad] = ZERO_LOWER
    return u, yl, yr, status, ok


def check(host_lib, system, x, *, float_too=True):
    lib = host_lib(system, real=RealType.DOUBLE)
    u, yl, yr, status = lib.evaluate(x)
    ru, ryl, ryr, rstatus, ok = reference(system, x)
    np.testing.assert_array_equal(status, rstatus, err_msg=f"{system.name}: status")
    for name, got, want in (("u", u, ru), ("yl", yl, ryl), ("yr", yr, ryr)):
        err = np.abs(got - want)
        j = int(np.argmax(err))
        assert err[j] <= 1e-12, (f"{system.name}: double {name} differs by {err[j]:.3g} at "
                                 f"x={x[j].tolist()}: C {got[j]!r}, Python {want[j]!r}")
    if not float_too:
        return ok
    xf = x.astype(np.float32).astype(np.float64)  # the points the float build sees
    lib = host_lib(system, real=RealType.FLOAT)
    u, yl, yr, status = lib.evaluate(xf)
    ru, ryl, ryr, rstatus, ok = reference(system, xf)
    np.testing.assert_array_equal(status, rstatus, err_msg=f"{system.name}: float status")
    bounds = float_error_bound(system, xf[ok])
    for name, got, want, bound in zip(("yl", "yr", "u"), (yl, yr, u), (ryl, ryr, ru), bounds,
                                      strict=True):
        err = np.abs(got[ok].astype(np.float64) - want[ok])
        finite = np.isfinite(bound)
        assert finite.mean() > 0.5, f"{system.name}: the bound is finite at too few points"
        bad = np.flatnonzero(finite & (err > bound))
        assert bad.size == 0, (f"{system.name}: float {name} error {err[bad[0]]:.3g} exceeds "
                               f"the bound {bound[bad[0]]:.3g} at x={xf[ok][bad[0]].tolist()}")
    return ok


REDUCERS = list(Reducer)


@pytest.mark.parametrize("red", REDUCERS, ids=lambda r: r.value.name)
def test_paper_mamdani_equals_python(red, host_lib):
    system = paper_mamdani(reducer=red)
    x = points(system, 3000, seed=1, grid=31, margin=0.3)
    assert check(host_lib, system, x).all()


_IMPS = sorted(SUPPORTED_IMPLICATIONS, key=lambda i: i.value)
_AGGS = sorted(SUPPORTED_AGGREGATIONS, key=lambda a: a.value)


@pytest.mark.parametrize("agg", _AGGS, ids=lambda a: a.value)
@pytest.mark.parametrize("imp", _IMPS, ids=lambda i: i.value)
def test_every_implication_and_aggregation(imp, agg, host_lib):
    system = paper_mamdani(implication=imp, aggregation=agg)
    x = points(system, 1500, seed=2, grid=21)
    check(host_lib, system, x)
    t1 = paper_mamdani(type1=True, implication=imp, aggregation=agg)
    check(host_lib, t1, x)


def test_the_other_operators_are_refused_naming_them():
    """The C carries min/product implication and max/sum/probor aggregation; every other
    operator of the library is refused by name, with what is supported."""
    assert {i.value for i in SUPPORTED_IMPLICATIONS} == {"min", "product"}
    assert {a.value for a in SUPPORTED_AGGREGATIONS} == {"max", "sum", "probor"}
    for imp in set(Implication) - SUPPORTED_IMPLICATIONS:
        with pytest.raises(UnsupportedFeatureError,
                           match=f"implication '{imp.value}' has no C implementation "
                                 r"\(supported: min, product\)"):
            generate_c(paper_mamdani(implication=imp))
    for agg in set(Aggregation) - SUPPORTED_AGGREGATIONS:
        with pytest.raises(UnsupportedFeatureError,
                           match=f"aggregation '{agg.value}' has no C implementation "
                                 r"\(supported: max, probor, sum\)"):
            generate_c(paper_mamdani(aggregation=agg))


@pytest.mark.parametrize("red", REDUCERS, ids=lambda r: r.value.name)
@pytest.mark.parametrize("interval", [True, False], ids=["interval-coef", "crisp-coef"])
def test_paper_tsk_equals_python(red, interval, host_lib):
    system = paper_tsk(reducer=red, interval=interval)
    x = points(system, 3000, seed=3, grid=31, margin=0.3)
    assert check(host_lib, system, x).all()


def test_type1_tsk_equals_python(host_lib):
    system = paper_tsk(type1=True)
    check(host_lib, system, points(system, 3000, seed=4, grid=31))


@pytest.mark.parametrize("seed", range(8))
def test_random_mamdani_systems(seed, host_lib):
    """Triangles, trapezoids, shoulders and Gaussians; NOT, OR (either s-norm) and weights;
    each implication, aggregation, reducer; grids of 5 to 80 points."""
    for system in (random_mamdani(seed), random_mamdani(seed, type1=True)):
        check(host_lib, system, points(system, 600, seed=seed))


@pytest.mark.parametrize("seed", range(8))
def test_random_tsk_systems(seed, host_lib):
    for system in (random_tsk(seed), random_tsk(seed, type1=True)):
        check(host_lib, system, points(system, 600, seed=seed))


def test_random_systems_cover_what_is_carried():
    """The random systems above meet every operator and reducer the tests claim."""
    mams = [random_mamdani(s) for s in range(8)]
    assert {m.implication for m in mams} == SUPPORTED_IMPLICATIONS
    assert {m.aggregation for m in mams} == SUPPORTED_AGGREGATIONS
    assert len({m.reducer.name for m in mams}) >= 4
    tsks = [random_tsk(s) for s in range(8)]
    assert any(not t.tables.crisp for t in tsks)
    feats = set().union(*(t.tables.features for t in tsks))
    assert {"linear", "not", "or", "weights"} <= feats


def test_type1_antecedents_with_it2_output_sets(host_lib):
    """The lower aggregate uses the output sets' lower MFs even where the firing is type-1."""
    system = dataclasses.replace(paper_mamdani(), inputs=paper_mamdani(type1=True).inputs)
    x = points(system, 500, seed=5)
    check(host_lib, system, x)
    _, yl, yr, _ = host_lib(system).evaluate(x)
    assert np.max(yr - yl) > 0.5


def test_zero_firing_and_no_lower_aggregate(host_lib):
    x_in = Input("x", (0.0, 1.0), [IT2Set(Triangle(0.0, 0.2, 0.4), Triangle(0.15, 0.2, 0.25),
                                          "a")])
    out = Output("y", (0.0, 4.0), [IT2Set(Triangle(0, 2, 4), Triangle(1, 2, 3), "m")])
    base = IT2Mamdani(inputs=[x_in], outputs=[out], rules=[Rule(["a"], "m")], resolution=9)
    x = np.array([[0.2], [0.1], [0.7], [0.3]])  # fires, upper only, nothing, upper only
    for red in REDUCERS:
        system = dataclasses.replace(base, reducer=red.value)
        _, _, _, status = host_lib(system).evaluate(x)
        _, _, _, rstatus, _ = reference(system, x)
        np.testing.assert_array_equal(status, rstatus)
        assert status[2] == ZERO_FIRING
        assert status[1] == (ZERO_LOWER if red.value.name == "wu-mendel" else OK)
    with pytest.raises(ZeroFiringError):
        base(0.7)
    valued = dataclasses.replace(base, on_zero_firing=1.25)
    u, yl, yr, status = host_lib(valued).evaluate(x)
    assert status[2] == OK and u[2] == yl[2] == yr[2] == 1.25


def test_centre_of_sets_mamdani_is_its_sugeno_system(host_lib):
    system = dataclasses.replace(paper_mamdani(), type_reduction=TypeReduction.CENTRE_OF_SETS)
    code = generate_c(system)
    assert "GRID" not in code.source and "_SET[" not in code.source
    check(host_lib, system, points(system, 1000, seed=6))


def test_refusals_name_the_feature():
    for d in (Defuzzifier.BISECTOR, Defuzzifier.MOM, Defuzzifier.SOM, Defuzzifier.LOM):
        with pytest.raises(UnsupportedFeatureError, match=f"defuzzifier '{d.value}'.*grid"):
            generate_c(paper_mamdani(type1=True, defuzzifier=d))
    for system in (paper_mamdani(), paper_tsk()):
        with pytest.raises(UnsupportedFeatureError, match="use --real float"):
            generate_c(system, real=RealType.Q15)


def test_the_c_holds_the_grid_and_the_sets_as_python(host_lib):
    """The tables are Python's values: the grid's ends and a set's peak appear exactly, and a
    101-point system writes 101 grid points and 7 x 101 values per MF table."""
    system = paper_mamdani()
    src = generate_c(system, real=RealType.DOUBLE).source
    assert "IT2_GRID[101]" in src and "IT2_MU[7][101]" in src and "IT2_ML[7][101]" in src
    t1 = generate_c(paper_mamdani(type1=True)).source
    assert "IT2_ML[" not in t1  # a type-1 output: one MF per set
    assert isinstance(paper_mamdani(type1=True), T1Mamdani)
