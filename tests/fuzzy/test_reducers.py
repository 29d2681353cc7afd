"""Type reducers: exact ones agree with each other and with brute force; approximations match
their closed forms; shapes, errors, zero firing and iteration caps."""

from __future__ import annotations

import itertools

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
    ConvergenceError,
    Reducer,
    TypeReducer,
    ZeroFiringError,
)

EXACT = (KM, EKM, EIASC, EXHAUSTIVE)
ALL = (*EXACT, NIE_TAN, WU_MENDEL)
TOL = 1e-12


def brute_force(fl, fu, y_lo, y_hi):
    """Exact [yl, yr] by enumerating every switch point of the sorted rules (written here, not
    shared with the library): yl = min over L of (sum_{i<L} fu y + sum_{i>=L} fl y) / (...)."""
    out = []
    for y, left in ((y_lo, True), (y_hi, False)):
        order = np.argsort(y, kind="stable")
        ys, a, b = y[order], fl[..., order], fu[..., order]
        best = None
        for k in range(len(y) + 1):
            if left:
                theta = np.concatenate([b[..., :k], a[..., k:]], axis=-1)
            else:
                theta = np.concatenate([a[..., :k], b[..., k:]], axis=-1)
            with np.errstate(divide="ignore", invalid="ignore"):
                c = (theta * ys).sum(axis=-1) / theta.sum(axis=-1)
            best = c if best is None else (np.fmin(best, c) if left else np.fmax(best, c))
        out.append(best)
    return out[0], out[1]


def random_case(rng, n, r, mode):
    """Random firing intervals (n, r) and consequent intervals (r,), in several stress modes."""
    fu = rng.uniform(0, 1, (n, r))
    if mode == "skewed":  # firing ratios down to 1e-60: rounding ties, amplification
        fu = fu ** rng.uniform(1, 60, (n, 1))
    elif mode == "sparse":  # most rules not firing, many zero lower firings
        fu = np.where(rng.uniform(size=(n, r)) < 0.6, 0.0, fu)
    elif mode == "quantised":  # exact ties between centroids and consequents
        fu = rng.integers(0, 3, (n, r)) / 2
    if mode == "quantised":
        fl = np.minimum(fu, rng.integers(0, 3, (n, r)) / 2)
    else:
        fl = fu * rng.uniform(0, 1, (n, r)) ** rng.uniform(0.5, 20)
    if mode == "sparse":
        fl = np.where(rng.uniform(size=(n, r)) < 0.5, 0.0, fl)
    fires = fu.sum(axis=1) > 0
    fl, fu = fl[fires], fu[fires]
    if mode in ("quantised", "sparse"):
        y_lo = rng.integers(-3, 4, r).astype(float) * 4  # repeated consequents
        y_hi = y_lo + rng.integers(0, 2, r) * 4
    else:
        y_lo = rng.normal(0, 5, r)
        y_hi = y_lo + rng.uniform(0, 3, r)
    return fl, fu, y_lo, y_hi


@pytest.mark.parametrize("mode", ["uniform", "skewed", "sparse", "quantised"])
def test_exact_reducers_agree_pairwise_on_1e5_random_inputs(mode):
    rng = np.random.default_rng(["uniform", "skewed", "sparse", "quantised"].index(mode))
    fl, fu, y_lo, y_hi = random_case(rng, 110_000, 25, mode)
    assert fl.shape[0] >= 100_000
    results = {red.name: red(fl, fu, y_lo, y_hi) for red in EXACT}
    for (na, (al, ar)), (nb, (bl, br)) in itertools.combinations(results.items(), 2):
        dl, dr = np.abs(al - bl).max(), np.abs(ar - br).max()
        assert max(dl, dr) <= TOL, f"{mode}: {na} vs {nb} differ by yl {dl:.3g}, yr {dr:.3g}"


@pytest.mark.parametrize("seed", range(12))
def test_exact_reducers_equal_brute_force(seed):
    rng = np.random.default_rng(100 + seed)
    mode = ["uniform", "skewed", "sparse", "quantised"][seed % 4]
    r = int(rng.integers(1, 30))
    fl, fu, y_lo, y_hi = random_case(rng, 2000, r, mode)
    ref_l, ref_r = brute_force(fl, fu, y_lo, y_hi)
    for red in EXACT:
        yl, yr = red(fl, fu, y_lo, y_hi)
        err = max(np.abs(yl - ref_l).max(), np.abs(yr - ref_r).max())
        assert err <= TOL, f"{red.name}, mode {mode}, R={r}: off brute force by {err:.3g}"


# -- regressions: cases where KM/EKM used to fail ---------------------------------------------


def test_km_does_not_stop_at_a_rounding_tie():
    # The midpoint centroid (0 * 1e-17 + 1 * 0.5) / (0.5 + 1e-17) rounds to exactly y[1] = 1;
    # placing rule 1 at upper firing there is a false fixed point (centroid 1.0). The true
    # yl puts rule 1 at its lower firing 0: yl = 0.
    fl, fu, y = np.array([1e-17, 0.0]), np.array([1e-17, 1.0]), np.array([0.0, 1.0])
    for red in EXACT:
        yl, yr = red(fl, fu, y)
        assert (float(yl), float(yr)) == (0.0, 1.0), red.name


def test_km_zero_lower_firing_is_not_zero_firing():
    # All lower firings are 0 and the largest consequent fires only through its upper MF: the
    # yr configuration "y <= centroid at lower firing" has zero weight, yet the output is defined.
    fl = np.zeros(5)
    fu = np.array([0.0, 0.5, 1.0, 0.25, 0.75])
    y = np.array([-1.0, 0.0, 0.0, 1.0, 2.0])
    ref = brute_force(fl, fu, y, y)
    for red in EXACT:
        assert_allclose(red(fl, fu, y), ref, atol=TOL, err_msg=red.name)


def test_ekm_initial_switch_point_with_zero_weight():
    # EKM starts with round(R/2.4) = 2 rules at upper firing; here those two do not fire and all
    # lower firings are zero, so its first centroid is 0/0.
    fl = np.zeros(5)
    fu = np.array([0.0, 0.0, 0.5, 1.0, 0.25])
    y = np.arange(5.0)
    assert_allclose(EKM(fl, fu, y), brute_force(fl, fu, y, y), atol=TOL)


def test_eiasc_with_many_rules_needs_no_explicit_cap():
    # EIASC walks up to R rules; with R = 300 the default cap must not fire.
    rng = np.random.default_rng(7)
    fu = rng.uniform(0, 1, (500, 300))
    fl = fu * rng.uniform(0, 1, (500, 300))
    y = np.sort(rng.normal(size=300))
    ref = EXHAUSTIVE(fl, fu, y)
    for red in (KM, EKM, EIASC):
        assert_allclose(red(fl, fu, y), ref, atol=TOL, err_msg=red.name)


# -- closed forms -----------------------------------------------------------------------------


def test_crisp_type1_firing_gives_the_weighted_average():
    rng = np.random.default_rng(3)
    f = rng.uniform(0.01, 1, (1000, 7))
    y = rng.normal(size=7)
    expected = (f * y).sum(-1) / f.sum(-1)
    for red in ALL:
        yl, yr = red(f, f, y)
        assert_allclose(yl, expected, atol=TOL, err_msg=red.name)
        assert_allclose(yr, expected, atol=TOL, err_msg=red.name)


def test_single_rule():
    for red in (*EXACT, WU_MENDEL):
        yl, yr = red([0.2], [0.7], [1.5], [2.5])
        assert_allclose([yl, yr], [1.5, 2.5], rtol=1e-15, err_msg=red.name)
    # Nie-Tan reduces the consequent interval to its midpoint.
    assert_allclose(NIE_TAN([0.2], [0.7], [1.5], [2.5]), [2.0, 2.0], rtol=1e-15)


def test_hand_computed_interval():
    # Two rules, y = 0 and 8, both fired in [2/7, 4/9] (the paper controller at e=0.5, de=0):
    # yl = 8 (2/7) / (4/9 + 2/7) = 72/23, yr = 8 (4/9) / (2/7 + 4/9) = 112/23.
    fl, fu = np.array([2 / 7, 2 / 7]), np.array([4 / 9, 4 / 9])
    for red in EXACT:
        assert_allclose(red(fl, fu, [0.0, 8.0]), [72 / 23, 112 / 23], rtol=1e-15)


def test_nie_tan_is_its_closed_form():
    rng = np.random.default_rng(4)
    fl, fu, y_lo, y_hi = random_case(rng, 5000, 9, "uniform")
    y = (y_lo + y_hi) / 2
    expected = ((fl + fu) * y).sum(-1) / (fl + fu).sum(-1)
    a, b = NIE_TAN(fl, fu, y_lo, y_hi)
    assert_allclose(a, expected, rtol=1e-13, atol=1e-13)
    assert_array_equal(a, b)


def wu_mendel_bounds(fl, fu, y_lo, y_hi):
    """Wu & Mendel (2002) inner and outer bounds, from the paper's formulas (Mendel 2017,
    'Uncertain rule-based fuzzy systems', 2nd ed., eqs. for the uncertainty bounds)."""
    sl, su = fl.sum(-1), fu.sum(-1)
    inner_l = np.minimum((fl * y_lo).sum(-1) / sl, (fu * y_lo).sum(-1) / su)
    inner_r = np.maximum((fl * y_hi).sum(-1) / sl, (fu * y_hi).sum(-1) / su)
    k = (su - sl) / (su * sl)

    def term(w1, w2, y):
        a = (w1 * (y - y.min())).sum(-1)
        b = (w2 * (y.max() - y)).sum(-1)
        s = a + b
        return np.where(s > 0, a * b / np.where(s > 0, s, 1.0), 0.0)

    outer_l = inner_l - k * term(fl, fu, y_lo)
    outer_r = inner_r + k * term(fu, fl, y_hi)
    return outer_l, inner_l, inner_r, outer_r


@pytest.mark.parametrize("seed", range(5))
def test_wu_mendel_bounds_bracket_the_exact_interval(seed):
    rng = np.random.default_rng(200 + seed)
    r = int(rng.integers(2, 26))
    fu = rng.uniform(0, 1, (4000, r)) ** rng.uniform(1, 5)
    fl = fu * rng.uniform(0.01, 1, (4000, r))
    y_lo = rng.normal(0, 5, r)
    y_hi = y_lo + rng.uniform(0, 2, r)
    yl, yr = EXHAUSTIVE(fl, fu, y_lo, y_hi)
    outer_l, inner_l, inner_r, outer_r = wu_mendel_bounds(fl, fu, y_lo, y_hi)
    eps = 1e-12
    assert np.all(outer_l <= yl + eps) and np.all(yl <= inner_l + eps)
    assert np.all(inner_r <= yr + eps) and np.all(yr <= outer_r + eps)
    al, ar = WU_MENDEL(fl, fu, y_lo, y_hi)
    assert_allclose(al, (outer_l + inner_l) / 2, atol=1e-12)
    assert_allclose(ar, (inner_r + outer_r) / 2, atol=1e-12)


def test_wu_mendel_can_leave_the_consequent_range():
    # Not a defect of the implementation but of the approximation: the outer bound of yl can lie
    # below min(y), and so can the midpoint. y = [0, 1], lower firing [0.001, 0.3], upper
    # [1, 0.3]: inner bound min(0.3/0.301, 0.3/1.3) = 3/13; spread 0.999/(1.3 * 0.301); term
    # (0.3 * 1)/(0.3 + 1) = 3/13; outer = 3/13 (1 - 0.999/0.3913) = -0.3584; yl ~ -0.0638 < 0.
    yl, _ = WU_MENDEL([0.001, 0.3], [1.0, 0.3], [0.0, 1.0])
    assert_allclose(yl, (3 / 13) * (1 - 0.5 * 0.999 / (1.3 * 0.301)), rtol=1e-12)
    assert yl < 0.0
    exact_l, _ = EXHAUSTIVE([0.001, 0.3], [1.0, 0.3], [0.0, 1.0])
    assert_allclose(exact_l, 0.3 / 1.3, rtol=1e-15)


def test_approximations_stay_within_consequent_range():
    rng = np.random.default_rng(5)
    fl, fu, y_lo, y_hi = random_case(rng, 20000, 9, "uniform")
    fl = np.maximum(fl, 0.5 * fu)  # narrow footprints: where Wu-Mendel stays in range
    for red in (NIE_TAN, WU_MENDEL):
        a, b = red(fl, fu, y_lo, y_hi)
        assert np.all(a >= y_lo.min() - TOL) and np.all(b <= y_hi.max() + TOL), red.name
        assert np.all(a <= b + TOL), red.name
        assert not red.exact
    assert all(red.exact for red in EXACT)


# -- invariances ------------------------------------------------------------------------------


def test_rule_order_does_not_matter():
    rng = np.random.default_rng(6)
    fl, fu, y_lo, y_hi = random_case(rng, 3000, 11, "uniform")
    perm = rng.permutation(11)
    for red in ALL:
        a = red(fl, fu, y_lo, y_hi)
        b = red(fl[:, perm], fu[:, perm], y_lo[perm], y_hi[perm])
        assert_allclose(a, b, atol=TOL, err_msg=red.name)


def test_any_embedded_firing_lies_inside_the_interval():
    # Every firing vector theta with fl <= theta <= fu has its centroid in [yl, yr].
    rng = np.random.default_rng(8)
    fl, fu, y_lo, y_hi = random_case(rng, 5000, 9, "uniform")
    yl, yr = EXHAUSTIVE(fl, fu, y_lo, y_hi)
    for _ in range(5):
        t = rng.uniform(size=fl.shape)
        theta = fl + t * (fu - fl)
        lo = (theta * y_lo).sum(-1) / theta.sum(-1)
        hi = (theta * y_hi).sum(-1) / theta.sum(-1)
        assert np.all(yl <= lo + TOL) and np.all(hi <= yr + TOL)


# -- public call: shapes and errors -----------------------------------------------------------


@pytest.mark.parametrize("red", ALL, ids=lambda r: r.name)
def test_batch_shapes(red):
    rng = np.random.default_rng(9)
    y = np.array([-1.0, 0.0, 2.0])
    for batch in [(), (5,), (2, 3), (4, 1, 2)]:
        fu = rng.uniform(0.1, 1, (*batch, 3))
        fl = fu * 0.5
        yl, yr = red(fl, fu, y)
        assert yl.shape == batch and yr.shape == batch
        # the batch is elementwise: each sample reduces on its own
        flat = red(fl.reshape(-1, 3), fu.reshape(-1, 3), y)
        assert_array_equal(yl.reshape(-1), flat[0])


def test_y_upper_defaults_to_y_lower_and_lists_work():
    a = KM([[0.1, 0.2]], [[0.3, 0.4]], [1.0, 2.0])
    b = KM(np.array([[0.1, 0.2]]), np.array([[0.3, 0.4]]), [1.0, 2.0], [1.0, 2.0])
    assert_array_equal(a, b)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([0.1, 0.2], [0.3], [1.0, 2.0]), "f_lower shape"),
        ((0.1, 0.3, [1.0]), "f_lower shape"),
        (([0.1, 0.2], [0.3, 0.4], [1.0, 2.0, 3.0]), r"must be \(2,\)"),
        (([0.1, 0.2], [0.3, 0.4], [[1.0, 2.0]]), r"must be \(2,\)"),
        (([0.1, 0.2], [0.3, 0.4], [1.0, 2.0], [3.0]), r"must be \(2,\)"),
        (([np.nan, 0.2], [0.3, 0.4], [1.0, 2.0]), "f_lower contains NaN"),
        (([0.1, 0.2], [np.inf, 0.4], [1.0, 2.0]), "f_upper contains NaN or inf"),
        (([0.1, 0.2], [0.3, 0.4], [np.nan, 2.0]), "y_lower contains NaN"),
        (([0.1, 0.2], [0.3, 0.4], [1.0, 2.0], [1.0, np.inf]), "y_upper contains"),
        (([-0.1, 0.2], [0.3, 0.4], [1.0, 2.0]), "0 <= f_lower <= f_upper"),
        (([0.5, 0.2], [0.3, 0.4], [1.0, 2.0]), "0 <= f_lower <= f_upper"),
        (([0.1, 0.2], [0.3, 0.4], [1.0, 2.0], [0.0, 3.0]), "y_lower <= y_upper"),
        ((np.zeros((3, 0)), np.zeros((3, 0)), np.zeros(0)), "at least one rule"),
    ],
)
@pytest.mark.parametrize("red", ALL, ids=lambda r: r.name)
def test_bad_arguments_raise_value_error(red, args, match):
    with pytest.raises(ValueError, match=match):
        red(*args)


@pytest.mark.parametrize("red", ALL, ids=lambda r: r.name)
def test_zero_firing_raises(red):
    fl = np.array([[0.1, 0.0], [0.0, 0.0]])
    fu = np.array([[0.2, 0.3], [0.0, 0.0]])
    with pytest.raises(ZeroFiringError):
        red(fl, fu, [1.0, 2.0])
    assert issubclass(ZeroFiringError, ValueError)


def test_wu_mendel_needs_positive_lower_firing():
    with pytest.raises(ZeroFiringError, match="lower firing"):
        WU_MENDEL([0.0, 0.0], [0.5, 0.2], [1.0, 2.0])
    # the exact reducers are fine there
    for red in EXACT:
        assert_allclose(red([0.0, 0.0], [0.5, 0.2], [1.0, 2.0]), [1.0, 2.0])


# -- iteration caps ---------------------------------------------------------------------------

# y = [0, 1, 10], firing [0.1, 1] each. KM for yl starts at the midpoint centroid 11/3 (two
# rules below it at upper firing: centroid 2/2.1), needs a second iteration to move to one rule
# (centroid 1.1/1.2 = 11/12), and a third to confirm it.
SLOW_CASE = (np.full(3, 0.1), np.ones(3), np.array([0.0, 1.0, 10.0]))
# EIASC for yl starts from all-lower firing (centroid 1.1/0.3) and raises rules from the bottom
# while the centroid exceeds the next consequent: 1.1/0.4 = 2.75 > 1 needs a second step.
SLOW_EIASC = (np.full(3, 0.1), np.array([0.2, 1.0, 0.2]), np.array([0.0, 1.0, 10.0]))


def test_convergence_error_when_max_iter_too_small():
    with pytest.raises(ConvergenceError, match="KM did not converge in max_iter=1"):
        KM.with_max_iter(1)(*SLOW_CASE)
    with pytest.raises(ConvergenceError, match="EIASC did not converge in max_iter=1"):
        EIASC.with_max_iter(1)(*SLOW_EIASC)
    yl, _ = KM.with_max_iter(3)(*SLOW_CASE)
    assert_allclose(yl, 11 / 12, rtol=1e-15)
    yl, _ = EIASC.with_max_iter(2)(*SLOW_EIASC)
    assert_allclose(yl, 2.0 / 1.3, rtol=1e-15)
    assert issubclass(ConvergenceError, RuntimeError)


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "10"])
def test_max_iter_is_validated(bad):
    with pytest.raises(ValueError, match="max_iter"):
        KM.with_max_iter(bad)


def test_with_max_iter_keeps_the_strategy():
    km5 = KM.with_max_iter(5)
    assert km5.name == "km" and km5.max_iter == 5 and km5.exact
    assert km5 != KM and km5 == KM.with_max_iter(5)
    assert hash(km5) == hash(KM.with_max_iter(5))
    assert_array_equal(km5(*SLOW_CASE), KM(*SLOW_CASE))
    assert KM.with_max_iter(None) == KM


# -- naming -----------------------------------------------------------------------------------


def test_reducer_enum_lookup():
    for red in ALL:
        assert Reducer.from_name(red.name).value is red
        assert Reducer.from_name(red.name.upper().replace("-", "_")).value is red
    assert Reducer.from_name(" nie_tan ").value is NIE_TAN
    with pytest.raises(ValueError, match="unknown type reducer 'kmx'"):
        Reducer.from_name("kmx")
    assert repr(KM) == "TypeReducer('km')"
    assert isinstance(EXHAUSTIVE, TypeReducer)
