"""The paper's heading controller: hand-computed reference points, dead zones, saturation,
clipping, symmetry and the dead-zone-matched type-1 baseline.

Every reference below is derived in the comments from the MF formulas of DESIGN.md sec. 3
(upper/lower ``[a b c]`` per set and FoU ``w``) and the rule table (Table 2), and computed here
in exact rational arithmetic. For a set with feet ``a, c`` and peak ``b``: left side
``(x - a)/(b - a)``, right side ``(c - x)/(c - b)``, clipped to [0, 1]; shoulders stay 1.
Firing = product t-norm of the e-set and de-set degrees. The exact interval is
``yl = min_L (sum_{y_i below L} fu y + sum_rest fl y)/(...)`` and ``yr`` likewise with max,
enumerated by :func:`exact_interval` over all switch points.
"""

from __future__ import annotations

from fractions import Fraction as Fr

import numpy as np
import pytest
from numpy.testing import assert_allclose

from it2track.fuzzy import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    IT2Sugeno,
    T1Sugeno,
    TNorm,
)
from it2track.paper import (
    CENTRE_SETS,
    RULE_TABLE,
    dead_zone_matched_fls,
    heading_fls,
    heading_fls_widths,
)

EXACT = (KM, EKM, EIASC, EXHAUSTIVE)


def exact_interval(rules):
    """``rules``: (y, f_lower, f_upper) Fractions of the firing rules -> exact (yl, yr)."""
    rules = sorted(rules)
    out = []
    for left in (True, False):
        best = None
        for k in range(len(rules) + 1):
            theta = [((fu if i < k else fl) if left else (fl if i < k else fu))
                     for i, (_, fl, fu) in enumerate(rules)]
            if sum(theta) == 0:
                continue
            c = sum(t * y for t, (y, _, _) in zip(theta, rules, strict=True)) / sum(theta)
            if best is None or (c < best if left else c > best):
                best = c
        out.append(best)
    return out[0], out[1]


def check_it2(w, e, de, yl, yr, *, rel=1e-14):
    """Assert every exact reducer gives (yl, yr) and u = (yl + yr)/2 at (e, de)."""
    for red in EXACT:
        fls = heading_fls(w, reducer=red)
        got = [float(v) for v in fls.interval(e, de)]
        assert got == pytest.approx([float(yl), float(yr)], rel=rel, abs=1e-14), red.name
        assert float(fls(e, de)) == pytest.approx(float((yl + yr) / 2), rel=rel, abs=1e-14)


# -- hand-computed reference points -----------------------------------------------------------


def test_reference_e05_de0_fou02():
    # w = 0.2, e = 0.5, de = 0.
    # e: upper Z [-0.9 0 0.9] = 1 - 0.5/0.9 = 4/9, lower Z [-0.7 0 0.7] = 1 - 0.5/0.7 = 2/7;
    #    upper P [0.1 1 1] = (0.5 - 0.1)/0.9 = 4/9, lower P [0.3 1 1] = 0.2/0.7 = 2/7; N = 0.
    # de = 0: Z = 1 (both); upper N [-1 -1 -0.1] and upper P [0.1 1 1] are 0 at 0.
    # Firing: (Z,Z) -> 0 in [2/7, 4/9]; (P,Z) -> 8 in [2/7, 4/9].
    # yl = 8 f_lower(P)/(f_upper(Z) + f_lower(P)) = 8 (2/7)/(4/9 + 2/7) = 72/23
    # yr = 8 f_upper(P)/(f_lower(Z) + f_upper(P)) = 8 (4/9)/(2/7 + 4/9) = 112/23; u = 4.
    yl, yr = exact_interval([(0, Fr(2, 7), Fr(4, 9)), (8, Fr(2, 7), Fr(4, 9))])
    assert (yl, yr) == (Fr(72, 23), Fr(112, 23))
    check_it2(0.2, 0.5, 0.0, yl, yr)
    assert heading_fls(0.2)(0.5, 0.0) == 4.0


@pytest.mark.parametrize(("e", "de"), [(0.1, 0.0), (-0.19, 0.0), (0.15, 0.1), (-0.05, -0.19),
                                       (0.0, 0.0), (0.1999, 0.1999)])
def test_reference_type1_dead_zone(e, de):
    # w = 0: N [-1 -1 -0.2] and P [0.2 1 1] are 0 for |x| < 0.2, so only (Z,Z) -> 0 fires:
    # u = 0 * f / f = 0 exactly.
    assert heading_fls(0.0)(e, de) == 0.0
    assert float(heading_fls(0.0)(np.array(e), np.array(de))) == 0.0


def test_reference_fou_opens_the_dead_zone():
    # e = 0.15, de = 0: inside the type-1 dead zone (0.15 < 0.2), outside the IT2 one for
    # w = 0.2 (0.15 > 0.2 - 0.1).
    # e: upper Z = 1 - 0.15/0.9 = 5/6, lower Z = 1 - 0.15/0.7 = 11/14,
    #    upper P = (0.15 - 0.1)/0.9 = 1/18, lower P (foot 0.3) = 0.  de = 0: Z = 1.
    # Firing: (Z,Z) -> 0 in [11/14, 5/6]; (P,Z) -> 8 in [0, 1/18].
    # yl = 8 * 0 / (...) = 0; yr = 8 (1/18)/(11/14 + 1/18) = 28/53; u = 14/53 ~ 0.264 != 0.
    yl, yr = exact_interval([(0, Fr(11, 14), Fr(5, 6)), (8, Fr(0), Fr(1, 18))])
    assert (yl, yr) == (0, Fr(28, 53))
    check_it2(0.2, 0.15, 0.0, yl, yr)
    assert heading_fls(0.0)(0.15, 0.0) == 0.0
    assert heading_fls(0.2)(-0.15, 0.0) == pytest.approx(-14 / 53, rel=1e-14)


@pytest.mark.parametrize("w", [0.0, 0.1, 0.2, 0.3])
def test_reference_saturation_corners_and_clipping(w):
    fls = heading_fls(w)
    # e = de = 1: N = 0, Z = 0 (upper Z foot 0.8 + w/2 < 1), P = 1 (upper and lower shoulder),
    # so only (P,P) -> 12 fires: u = 12. Symmetrically (-1,-1) -> -12.
    assert fls(1.0, 1.0) == 12.0
    assert fls(-1.0, -1.0) == -12.0
    # e = 1, de = 0: only (P,Z) -> 8; e = 1, de = -1: only (P,N) -> 4; e = -1, de = 1: (N,P).
    assert fls(1.0, 0.0) == 8.0
    assert fls(1.0, -1.0) == 4.0
    assert fls(-1.0, 1.0) == -4.0
    # Inputs are clipped to [-1, 1]: e = 5 is e = 1.
    assert fls(5.0, 0.0) == fls(1.0, 0.0)
    assert fls(5.0, 5.0) == 12.0 and fls(-1e9, -3.0) == -12.0
    e = np.array([5.0, 1.0, 1.5, -7.0])
    assert_allclose(fls(e, 0.3), fls(np.clip(e, -1, 1), 0.3), rtol=0, atol=0)


def test_reference_off_grid_both_inputs_active_fou02():
    # w = 0.2, e = 0.3, de = -0.45.
    # e = 0.3: upper Z = 1 - 0.3/0.9 = 2/3, lower Z = 1 - 0.3/0.7 = 4/7,
    #          upper P = (0.3 - 0.1)/0.9 = 2/9, lower P (foot 0.3) = 0; N = 0.
    # de = -0.45: upper N [-1 -1 -0.1] = (-0.1 + 0.45)/0.9 = 7/18,
    #             lower N [-1 -1 -0.3] = (-0.3 + 0.45)/0.7 = 3/14,
    #             upper Z = 1 - 0.45/0.9 = 1/2, lower Z = 1 - 0.45/0.7 = 5/14; P = 0.
    # Firing (lower, upper): (Z,N) -> -8: [4/7 * 3/14, 2/3 * 7/18] = [6/49, 7/27]
    #                        (Z,Z) ->  0: [4/7 * 5/14, 2/3 * 1/2]  = [10/49, 1/3]
    #                        (P,N) -> +4: [0, 2/9 * 7/18] = [0, 7/81]
    #                        (P,Z) -> +8: [0, 2/9 * 1/2]  = [0, 1/9]
    # yl: only (Z,N) at upper firing: (-8 * 7/27)/(7/27 + 10/49) = -2744/613
    # yr: (P,N), (P,Z) at upper: (-8 * 6/49 + 4 * 7/81 + 8/9)/(16/49 + 7/81 + 1/9) = 253/520
    rules = [(-8, Fr(6, 49), Fr(7, 27)), (0, Fr(10, 49), Fr(1, 3)),
             (4, Fr(0), Fr(7, 81)), (8, Fr(0), Fr(1, 9))]
    yl, yr = exact_interval(rules)
    assert (yl, yr) == (Fr(-2744, 613), Fr(253, 520))
    check_it2(0.2, 0.3, -0.45, yl, yr)


def test_reference_off_grid_fou03():
    # w = 0.3, e = -0.6, de = 0.25.
    # e = -0.6: upper N [-1 -1 -0.05] = (-0.05 + 0.6)/0.95 = 11/19,
    #           lower N [-1 -1 -0.35] = (-0.35 + 0.6)/0.65 = 5/13,
    #           upper Z [-0.95 0 0.95] = 1 - 0.6/0.95 = 7/19,
    #           lower Z [-0.65 0 0.65] = 1 - 0.6/0.65 = 1/13; P = 0.
    # de = 0.25: upper Z = 1 - 0.25/0.95 = 14/19, lower Z = 1 - 0.25/0.65 = 8/13,
    #            upper P [0.05 1 1] = 0.2/0.95 = 4/19, lower P [0.35 1 1] = 0; N = 0.
    # Firing: (N,Z) -> -8: [40/169, 154/361]; (N,P) -> -4: [0, 44/361];
    #         (Z,Z) ->  0: [8/169, 98/361];   (Z,P) -> +8: [0, 28/361].
    # yl: (N,Z) at upper: (-8 * 154/361)/(154/361 + 8/169) = -104104/14457
    # yr: (Z,Z), (Z,P) at upper: (-8 * 40/169 + 8 * 28/361)/(40/169 + 98/361 + 28/361)
    #     = -38832/17867
    rules = [(-8, Fr(40, 169), Fr(154, 361)), (-4, Fr(0), Fr(44, 361)),
             (0, Fr(8, 169), Fr(98, 361)), (8, Fr(0), Fr(28, 361))]
    yl, yr = exact_interval(rules)
    assert (yl, yr) == (Fr(-104104, 14457), Fr(-38832, 17867))
    check_it2(0.3, -0.6, 0.25, yl, yr)


def test_reference_off_grid_type1_product_and_min():
    # w = 0, e = 0.3, de = -0.45.
    # e: Z [-0.8 0 0.8] = 1 - 0.3/0.8 = 5/8, P [0.2 1 1] = 0.1/0.8 = 1/8.
    # de: N [-1 -1 -0.2] = 0.25/0.8 = 5/16, Z = 1 - 0.45/0.8 = 7/16.
    # Product: (Z,N) 25/128 -> -8, (Z,Z) 35/128 -> 0, (P,N) 5/128 -> 4, (P,Z) 7/128 -> 8;
    #   u = (-200 + 20 + 56)/(25 + 35 + 5 + 7) = -124/72 = -31/18.
    # Minimum: 5/16, 7/16, 1/8, 1/8: u = (-8 * 5/16 + 4/8 + 8/8)/1 = -1.
    assert heading_fls(0.0)(0.3, -0.45) == pytest.approx(-31 / 18, rel=1e-15)
    assert heading_fls(0.0, tnorm=TNorm.MINIMUM)(0.3, -0.45) == pytest.approx(-1.0, rel=1e-15)


def test_reference_approximate_reducers_at_e05():
    # Same firing as test_reference_e05_de0_fou02. Nie-Tan: 8 (2/7 + 4/9)/(2 (2/7 + 4/9)) = 4.
    # Wu-Mendel: sum(fl) = 4/7, sum(fu) = 8/9; inner yl = min(4, 4) = 4, inner yr = 4;
    # spread (8/9 - 4/7)/((8/9)(4/7)) = 5/8. The bounds use the smallest and largest consequent
    # of ALL rules, y1 = -12, yM = 12:
    # yl: p = sum fl (y + 12) = (2/7)(12 + 20) = 64/7, q = sum fu (12 - y) = (4/9)(12 + 4) = 64/9,
    #     outer = 4 - (5/8) p q/(p + q) = 4 - (5/8) 4 = 3/2; yl ~ (3/2 + 4)/2 = 11/4.
    # yr: p = sum fu (y + 12) = (4/9)(12 + 20) = 128/9, q = sum fl (12 - y) = (2/7)(12 + 4) = 32/7,
    #     outer = 4 + (5/8) p q/(p + q) = 4 + (5/8)(128/37) = 228/37; yr ~ (4 + 228/37)/2 = 188/37.
    assert heading_fls(0.2, reducer=NIE_TAN)(0.5, 0.0) == pytest.approx(4.0, rel=1e-15)
    yl, yr = heading_fls(0.2, reducer=WU_MENDEL).interval(0.5, 0.0)
    assert (float(yl), float(yr)) == pytest.approx((11 / 4, 188 / 37), rel=1e-14)


# -- dead zones -------------------------------------------------------------------------------


@pytest.mark.parametrize("w", [0.0, 0.1, 0.2, 0.3])
def test_dead_zone_is_02_minus_half_fou(w):
    fls = heading_fls(w)
    edge = 0.2 - w / 2
    inside = np.linspace(-edge, edge, 2001)[1:-1]
    assert np.all(fls(inside, 0.0) == 0.0), f"w={w}: u != 0 inside |e| < {edge}"
    for s in (1.0, -1.0):
        assert fls(s * (edge - 1e-9), 0.0) == 0.0
        u = fls(s * (edge + 1e-9), 0.0)
        assert u != 0.0 and np.sign(u) == s, f"w={w}: u={u} just outside the dead zone"
        assert fls(s * (edge + 0.05), 0.0) * s > 0


@pytest.mark.parametrize("w", [0.1, 0.2, 0.3])
def test_dead_zone_matched_type1_has_the_it2_dead_zone(w):
    t1 = dead_zone_matched_fls(w)
    assert isinstance(t1, T1Sugeno)
    edge = 0.2 - w / 2
    assert t1(edge - 1e-9, 0.0) == 0.0 and t1(-(edge - 1e-9), 0.0) == 0.0
    assert t1(edge + 1e-9, 0.0) > 0.0 and t1(-(edge + 1e-9), 0.0) < 0.0
    # Its sets are the IT2 controller's upper MFs.
    it2 = heading_fls(w)
    for s_t1, s_it2 in zip(t1.inputs[0].sets, it2.inputs[0].sets, strict=True):
        assert s_t1.upper == s_it2.upper and s_t1.is_type1
    # Same dead zone, different footprint: the two controllers differ outside it.
    assert t1(0.3, -0.45) != pytest.approx(it2(0.3, -0.45), abs=0.1)
    assert dead_zone_matched_fls(0.0)(0.3, -0.45) == heading_fls(0.0)(0.3, -0.45)


def test_dead_zone_matched_type1_reference_point():
    # w = 0.2, e = 0.3, de = -0.45 with the upper MFs only (see the IT2 reference above):
    # (Z,N) 7/27 -> -8, (Z,Z) 1/3 -> 0, (P,N) 7/81 -> 4, (P,Z) 1/9 -> 8;
    # u = (-8 * 21 + 4 * 7 + 8 * 9)/(21 + 27 + 7 + 9) = -68/64 = -17/16.
    assert dead_zone_matched_fls(0.2)(0.3, -0.45) == pytest.approx(-17 / 16, rel=1e-15)


# -- structure, validation, symmetry ----------------------------------------------------------


def test_controller_structure():
    assert isinstance(heading_fls(0.0), T1Sugeno)
    for w in (0.1, 0.2, 0.3):
        fls = heading_fls(w, reducer=KM)
        assert isinstance(fls, IT2Sugeno) and fls.reducer is KM
        assert [i.name for i in fls.inputs] == ["e", "de"]
        assert [i.universe for i in fls.inputs] == [(-1.0, 1.0)] * 2
        assert fls.n_rules == 9
        assert [r.consequent[0] for r in fls.rules] == [v for row in RULE_TABLE for v in row]
    assert heading_fls(0.2).reducer is EXHAUSTIVE
    assert set(CENTRE_SETS) == {"N", "Z", "P"}


def test_names_say_type_2_or_type_1():
    # the paper's "FLC" is its type-1 controller: an IT2 system must not carry that name
    assert heading_fls(0.2).name == "paper IT2FLC (FoU 0.2)"
    assert heading_fls(0.05).name == "paper IT2FLC (FoU 0.05)"
    assert heading_fls(0.0).name == "paper FLC (type-1)"
    assert heading_fls_widths((0.1, 0.2, 0), (0, 0, 0.3)).name == (
        "paper IT2FLC (FoU e 0.1,0.2,0 de 0,0,0.3)")
    assert heading_fls_widths((0, 0, 0), (0, 0, 0)).name == "paper FLC (type-1)"
    assert heading_fls_widths((0, 0, 0), (0, 0, 0), name="mine").name == "mine"


@pytest.mark.parametrize("w", [-0.1, 1.6, 2.0, float("nan"), float("inf")])
def test_invalid_fou_is_rejected(w):
    with pytest.raises(ValueError, match="fou"):
        heading_fls(w)
    with pytest.raises(ValueError, match="fou"):
        dead_zone_matched_fls(w)


@pytest.mark.parametrize("w", [0.0, 0.1, 0.2, 0.3, 0.9])
def test_odd_symmetry_on_a_grid(w):
    g = np.linspace(-1, 1, 81)
    e, de = np.meshgrid(g, g, indexing="ij")
    # (Wu-Mendel is undefined where the total lower firing vanishes, which happens for w >= 0.6)
    for red in (*EXACT, NIE_TAN, *((WU_MENDEL,) if w < 0.6 else ())):
        fls = heading_fls(w, reducer=red)
        assert_allclose(fls(e, de), -fls(-e, -de), rtol=0, atol=1e-12, err_msg=red.name)
        yl, yr = fls.interval(e, de)
        yl_m, yr_m = fls.interval(-e, -de)
        assert_allclose(yl, -yr_m, atol=1e-12)
        assert_allclose(yr, -yl_m, atol=1e-12)
