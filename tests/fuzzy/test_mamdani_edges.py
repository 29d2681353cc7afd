"""Mamdani systems at their edges: defuzzifier ties and empty sets, the probabilistic-OR
aggregation by hand in exact fractions, the resolution's bounds, every refusal's message, the
type-reduction names and output selection.

Written from the cases a mutation test of ``fuzzy/mamdani.py`` found unpinned
(docs/guide/mutation.md). The centroid reference is a brute force over switch points in exact
fractions, sharing no code with it2track.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction as Q

import numpy as np
import pytest

from it2track.fuzzy import (
    EXHAUSTIVE,
    NIE_TAN,
    WU_MENDEL,
    Aggregation,
    Defuzzifier,
    Implication,
    Input,
    IT2Mamdani,
    IT2Set,
    Output,
    Rule,
    T1Mamdani,
    TNorm,
    Trapezoid,
    Triangle,
    TypeReduction,
    ZeroFiringError,
)
from it2track.fuzzy.mamdani import defuzzify, set_centroid


def exactly(message: str) -> str:
    return f"^{re.escape(message)}$"


def centroid_interval(lo: list[Q], up: list[Q], y: list[Q]) -> tuple[Q, Q]:
    """[min, max] of sum(w y) / sum(w) over the switch-point weightings (Karnik-Mendel: for
    ascending y the extremes put the upper MF on one side of a switch and the lower on the
    other)."""
    n = len(y)
    cands_l, cands_r = [], []
    for k in range(n + 1):
        wl = up[:k] + lo[k:]
        wr = lo[:k] + up[k:]
        for w, cands in ((wl, cands_l), (wr, cands_r)):
            if sum(w) > 0:
                cands.append(sum(a * b for a, b in zip(w, y, strict=True)) / sum(w))
    return min(cands_l), max(cands_r)


def hand_system(**kwargs: object) -> IT2Mamdani:
    """At x = 1/4 rule lo fires [1/2, 3/4] and rule hi [0, 1/4]; grid y = 0..4."""
    x = Input("x", (0, 1), [IT2Set(Triangle(0, 0, 1), Triangle(0, 0, 0.5), "lo"),
                            IT2Set(Triangle(0, 1, 1), Triangle(0.5, 1, 1), "hi")])
    y = Output("y", (0, 4), [IT2Set(Triangle(0, 0, 4), Triangle(0, 0, 2), "small"),
                             IT2Set(Triangle(0, 4, 4), Triangle(2, 4, 4), "big")])
    args: dict[str, object] = {"inputs": [x], "outputs": [y], "resolution": 5,
                               "rules": [Rule(["lo"], "small"), Rule(["hi"], "big")]}
    return IT2Mamdani(**{**args, **kwargs})  # type: ignore[arg-type]


SMALL_UP = [Q(1), Q(3, 4), Q(1, 2), Q(1, 4), Q(0)]
SMALL_LO = [Q(1), Q(1, 2), Q(0), Q(0), Q(0)]
BIG_UP = [Q(0), Q(1, 4), Q(1, 2), Q(3, 4), Q(1)]
GRID = [Q(k) for k in range(5)]


def probor(a: Q, b: Q) -> Q:
    return a + b - a * b


@pytest.mark.parametrize("implication", [Implication.MINIMUM, Implication.PRODUCT])
def test_probabilistic_or_aggregation_by_hand(implication: Implication) -> None:
    imp = min if implication is Implication.MINIMUM else (lambda f, m: f * m)
    up = [probor(imp(Q(3, 4), a), imp(Q(1, 4), b)) for a, b in zip(SMALL_UP, BIG_UP, strict=True)]
    lo = [probor(imp(Q(1, 2), a), imp(Q(0), Q(0))) for a in SMALL_LO]
    system = hand_system(implication=implication, aggregation=Aggregation.PROBOR)
    lower, upper = system.aggregated(0.25)
    np.testing.assert_allclose(upper, [float(v) for v in up], rtol=0, atol=1e-15)
    np.testing.assert_allclose(lower, [float(v) for v in lo], rtol=0, atol=1e-15)
    left, right = centroid_interval(lo, up, GRID)
    assert system.interval(0.25) == pytest.approx((float(left), float(right)), abs=1e-15)


def test_max_aggregation_keeps_the_strongest_rule_of_a_shared_set() -> None:
    # both rules conclude "small": upper firing max(3/4, 1/4) = 3/4, lower max(1/2, 0) = 1/2
    system = hand_system(rules=[Rule(["lo"], "small"), Rule(["hi"], "small")])
    lower, upper = system.aggregated(0.25)
    assert upper.tolist() == [0.75, 0.75, 0.5, 0.25, 0.0]
    assert lower.tolist() == [0.5, 0.5, 0.0, 0.0, 0.0]
    # x = 0.9: lo fires [0, 0.1], hi fires [0.8, 0.9] -> "small" upper clipped at 0.9
    lower, upper = system.aggregated(0.9)
    assert upper == pytest.approx([0.9, 0.75, 0.5, 0.25, 0.0], abs=1e-15)
    assert lower == pytest.approx([0.8, 0.5, 0.0, 0.0, 0.0], abs=1e-15)


def test_aggregated_needs_one_output() -> None:
    base = hand_system()
    two = hand_system(outputs=[*base.outputs, Output("z", (0, 1), [("a", Triangle(0, 0.5, 1))])],
                      rules=[Rule(["lo"], consequents=["small", "a"]),
                             Rule(["hi"], consequents=["big", None])])
    with pytest.raises(ValueError, match=exactly(
            "aggregated() needs a one-output system; use select_output()")):
        two.aggregated(0.5)
    lower, upper = base.aggregated([[0.25, 0.5], [0.75, 0.9]])
    assert lower.shape == upper.shape == (2, 2, 5)


def test_bisector_takes_the_first_point_reaching_half_the_area() -> None:
    y = np.array([0.0, 1.0, 2.0])
    mu = np.array([[0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]])  # three sets, columns
    # running sums: [0, 1, 2] reaches 2/2 = 1 at y = 1; [1, 2, 2] reaches 1 at y = 0 (a tie
    # with the half is reached, not passed); [0, 0, 1] reaches 1/2 at y = 2
    assert defuzzify(mu, y, Defuzzifier.BISECTOR).tolist() == [1.0, 0.0, 2.0]


def test_maxima_defuzzifiers_on_two_separate_peaks() -> None:
    y = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    mu = np.array([[0.0], [1.0], [0.5], [1.0], [0.0]])
    assert defuzzify(mu, y, Defuzzifier.SOM).tolist() == [1.0]
    assert defuzzify(mu, y, Defuzzifier.LOM).tolist() == [3.0]
    assert defuzzify(mu, y, Defuzzifier.MOM).tolist() == [2.0]
    assert defuzzify(mu, y, Defuzzifier.CENTROID).tolist() == [5.0 / 2.5]


@pytest.mark.parametrize("method", list(Defuzzifier))
def test_an_empty_set_has_no_output_whatever_the_method(method: Defuzzifier) -> None:
    y = np.array([0.0, 1.0, 2.0])
    mu = np.array([[0.0, 0.0], [0.0, 1.0], [0.0, 0.0]])  # column 0 empty, column 1 a spike
    out = defuzzify(mu, y, method)
    assert math.isnan(out[0]) and out[1] == 1.0


def test_set_centroid_of_an_interval_box_is_its_ends() -> None:
    # lower 0, upper 1 on y = 0, 1, 2: the extremes weight only y = 0 or only y = 2
    y = np.array([0.0, 1.0, 2.0])
    assert set_centroid(np.zeros(3), np.ones(3), y) == (0.0, 2.0)
    lo = [Q(0), Q(1, 2), Q(0)]
    up = [Q(1), Q(1), Q(1, 2)]
    ref = centroid_interval(lo, up, [Q(0), Q(1), Q(2)])
    got = set_centroid(np.array([0.0, 0.5, 0.0]), np.array([1.0, 1.0, 0.5]), y)
    assert got == pytest.approx((float(ref[0]), float(ref[1])), abs=1e-15)


@pytest.mark.parametrize(("name", "member"), [
    ("centroid", TypeReduction.CENTROID), (" CENTROID ", TypeReduction.CENTROID),
    ("centre-of-sets", TypeReduction.CENTRE_OF_SETS),
    ("Centre_Of_Sets", TypeReduction.CENTRE_OF_SETS),
    ("cos", TypeReduction.CENTRE_OF_SETS), ("COS", TypeReduction.CENTRE_OF_SETS),
    ("center-of-sets", TypeReduction.CENTRE_OF_SETS),
    ("center_of_sets", TypeReduction.CENTRE_OF_SETS)])
def test_type_reduction_names(name: str, member: TypeReduction) -> None:
    assert TypeReduction.from_name(name) is member


def test_an_unknown_type_reduction_is_named() -> None:
    with pytest.raises(ValueError, match=exactly(
            "unknown type reduction 'nie-tan'; choose 'centroid' or 'centre-of-sets'")):
        TypeReduction.from_name("nie-tan")


def test_resolution_bounds_are_accepted() -> None:
    x = Input("x", (0, 1), [("a", Trapezoid(0, 0, 1, 1))])
    y = Output("y", (0, 2), [("s", Triangle(0, 1, 2))])
    fls = T1Mamdani(inputs=[x], outputs=[y], rules=[Rule(["a"], "s")], resolution=3)
    assert fls.tables.grids[0].tolist() == [0.0, 1.0, 2.0]
    assert float(fls(0.5)) == 1.0  # a symmetric triangle
    # 100000 passes the check and goes on to sample the sets (the narrow one, between the
    # first two of the 100000 grid points, then stops the construction: a fast way to see it)
    narrow = Output("y", (0, 2), [("s", Triangle(0.5e-5, 1e-5, 1.5e-5))])
    with pytest.raises(ValueError, match=exactly(
            "output 'y' set 's' is zero at every one of the 100000 grid points; raise the "
            "resolution")):
        T1Mamdani(inputs=[x], outputs=[narrow], rules=[Rule(["a"], "s")], resolution=100_000)


@pytest.mark.parametrize("resolution", [2, 100_001, True, 5.0, "5"])
def test_resolution_out_of_bounds_is_refused(resolution: object) -> None:
    with pytest.raises(ValueError, match=exactly(
            f"resolution={resolution!r} must be an int in [3, 100000]")):
        hand_system(resolution=resolution)


def test_bad_definitions_say_what_is_wrong_word_for_word() -> None:
    base = hand_system()
    with pytest.raises(ValueError, match=exactly("IT2Mamdani needs outputs=[Output(...), ...]")):
        hand_system(outputs=[])
    with pytest.raises(ValueError, match=exactly("outputs: 'y' must be an Output (name, "
                                                 "universe, sets)")):
        hand_system(outputs=["y"])
    dup = [base.outputs[0], base.outputs[0]]
    with pytest.raises(ValueError, match=exactly(
            "output names ['y', 'y'] must be distinct and non-empty")):
        hand_system(outputs=dup, rules=[Rule(["lo"], consequents=["small", "big"])])
    with pytest.raises(ValueError, match=exactly("implication='min' must be an Implication "
                                                 "member")):
        hand_system(implication="min")
    with pytest.raises(ValueError, match=exactly("aggregation='max' must be an Aggregation "
                                                 "member")):
        hand_system(aggregation="max")
    with pytest.raises(ValueError, match=exactly(
            "rule 1: a Mamdani consequent is an output set label, got (2.0, 2.0)")):
        hand_system(rules=[Rule(["lo"], "small"), Rule(["hi"], 2.0)])
    with pytest.raises(ValueError, match=exactly("reducer='km' must be a TypeReducer")):
        hand_system(reducer="km")
    with pytest.raises(ValueError, match=exactly(
            "type_reduction='cos' must be a TypeReduction")):
        hand_system(type_reduction="cos")
    with pytest.raises(ValueError, match=exactly(
            "defuzzifier='centroid' must be a Defuzzifier")):
        T1Mamdani(inputs=[Input("x", (0, 1), [("a", Trapezoid(0, 0, 1, 1))])],
                  outputs=[Output("y", (0, 2), [("s", Triangle(0, 1, 2))])],
                  rules=[Rule(["a"], "s")], defuzzifier="centroid")


def test_a_set_zero_on_the_grid_is_refused_naming_it() -> None:
    with pytest.raises(ValueError, match=exactly(
            "output 'y' set 'small' is zero at every one of the 3 grid points; raise the "
            "resolution")):
        hand_system(resolution=3, outputs=[
            Output("y", (0, 4), [IT2Set.type1(Triangle(0.5, 1, 1.5), "small"),
                                 IT2Set.type1(Triangle(0, 4, 4), "big")])])


def test_a_type2_set_in_a_type1_system_is_named() -> None:
    base = hand_system()
    with pytest.raises(ValueError, match=exactly(
            "T1Mamdani: input 'x' set 'lo' has a footprint of uncertainty; use IT2Mamdani")):
        T1Mamdani(inputs=base.inputs, outputs=base.outputs, rules=base.rules)
    x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
    with pytest.raises(ValueError, match=exactly(
            "T1Mamdani: output 'y' set 'small' has a footprint of uncertainty; use "
            "IT2Mamdani")):
        T1Mamdani(inputs=[x], outputs=base.outputs, rules=base.rules)


def test_select_output_by_name_or_index_and_its_bounds() -> None:
    base = hand_system()
    z = Output("z", (0, 1), [("a", Triangle(0, 0.5, 1))])
    two = hand_system(outputs=[*base.outputs, z],
                      rules=[Rule(["lo"], consequents=["small", "a"]),
                             Rule(["hi"], consequents=["big", None])], on_zero_firing=(1.5, 0.25))
    assert base.select_output(0) is base and base.select_output("y") is base
    only_z = two.select_output("z")
    assert only_z.outputs == (z,) and len(only_z.rules) == 1
    assert only_z.on_zero_firing == 0.25
    assert two.select_output(1).outputs == (z,)
    assert two.select_output(0).outputs == base.outputs
    for bad in (2, -1, True, "w", 1.0):
        with pytest.raises(ValueError, match=exactly(
                f"output={bad!r} must be an output name ['y', 'z'] or an index 0..1")):
            two.select_output(bad)


def test_set_centroids_are_the_exact_centroid_intervals_whatever_the_reducer() -> None:
    small = centroid_interval(SMALL_LO, SMALL_UP, GRID)  # = (1/3, 1)
    assert small == (Q(1, 3), Q(1))
    for reducer in (EXHAUSTIVE, NIE_TAN, WU_MENDEL):  # inexact reducers: the exact one
        cents = hand_system(reducer=reducer).tables.set_centroids[0]
        assert cents[0].tolist() == pytest.approx([1 / 3, 1.0], abs=1e-15), reducer.name


def test_wu_mendel_with_a_lower_mf_zero_on_the_grid_says_so() -> None:
    x = Input("x", (0, 1), [IT2Set(Triangle(0, 0, 1), Triangle(0, 0, 0.5), "lo")])
    y = Output("y", (0, 4), [IT2Set(Trapezoid(0, 1, 3, 4), Triangle(2.2, 2.5, 2.8, h=0.5), "s")])
    s = IT2Mamdani(inputs=[x], outputs=[y], rules=[Rule(["lo"], "s")], resolution=5,
                   reducer=WU_MENDEL, name="w")
    with pytest.raises(ZeroFiringError, match=exactly(
            "IT2Mamdani 'w' has no output at (x=0.25): rules fire there, but the aggregated "
            "output set is zero on the grid (or, for Wu-Mendel, its lower MF is); raise the "
            "resolution or use an exact reducer")):
        s(0.25)


def two_outputs(cls: type, **kw: object) -> IT2Mamdani | T1Mamdani:
    """Rule "lo" (zero above x = 0.2) acts on both outputs; nothing fires at x = 0.5."""
    x = Input("x", (0, 1), [("lo", Triangle(0, 0, 0.2))])
    y = Output("y", (0, 4), [("s", Triangle(0, 0, 4))])
    z = Output("z", (0, 1), [("a", Triangle(0, 0.5, 1))])
    return cls(inputs=[x], outputs=[y, z], rules=[Rule(["lo"], consequents=["s", "a"])],
               resolution=5, on_zero_firing=(1.5, 0.25), **kw)  # type: ignore[operator]


@pytest.mark.parametrize("kw", [{"type_reduction": TypeReduction.CENTROID},
                                {"type_reduction": TypeReduction.CENTRE_OF_SETS}])
def test_each_output_takes_its_own_zero_firing_value(kw: dict) -> None:
    out = two_outputs(IT2Mamdani, **kw)([0.5, 0.9])
    assert out.tolist() == [[1.5, 0.25], [1.5, 0.25]]
    assert two_outputs(T1Mamdani)([0.5]).tolist() == [[1.5, 0.25]]


def test_centre_of_sets_zero_firing_policy() -> None:
    x = Input("x", (0, 1), [IT2Set.type1(Triangle(0, 0, 0.2), "lo")])
    base = hand_system()
    cos = IT2Mamdani(inputs=[x], outputs=base.outputs, rules=[Rule(["lo"], "small")],
                     resolution=5, type_reduction=TypeReduction.CENTRE_OF_SETS,
                     on_zero_firing=2.0)
    assert cos([0.5, 0.7]).tolist() == [2.0, 2.0]
    with pytest.raises(ZeroFiringError, match="no rule"):
        IT2Mamdani(inputs=[x], outputs=base.outputs, rules=[Rule(["lo"], "small")],
                   resolution=5, type_reduction=TypeReduction.CENTRE_OF_SETS)(0.5)


def test_select_output_keeps_each_rules_weight_negation_and_connective() -> None:
    x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1))])
    w = Input("w", (0, 1), [("p", Triangle(0, 1, 1))])
    y = Output("y", (0, 4), [("s", Triangle(0, 0, 4))])
    z = Output("z", (0, 1), [("a", Triangle(0, 0.5, 1))])
    rule = Rule(["lo", "p"], consequents=["s", "a"], weight=0.5, negated=[True, False],
                connective="or")
    fls = T1Mamdani(inputs=[x, w], outputs=[y, z], rules=[rule])
    (kept,) = fls.select_output("z").rules
    assert (kept.weight, kept.negated, kept.connective.value, kept.consequents) == (
        0.5, (True, False), "or", ("a",))


@pytest.mark.parametrize(("tnorm", "f"), [(TNorm.PRODUCT, Q(3, 10)), (TNorm.MINIMUM, Q(1, 2))])
def test_a_type1_system_uses_its_tnorm(tnorm: TNorm, f: Q) -> None:
    # mu = 1/2 and 3/5 -> f = 3/10 (product) or 1/2 (min); the output [1, 3/4, 1/2, 1/4, 0]
    # on y = 0, 1/2, ..., 2 clipped at f, then the centroid
    x1 = Input("x1", (0, 1), [("a", Triangle(0, 0, 1))])
    x2 = Input("x2", (0, 1), [("a", Triangle(0, 0, 1))])
    y = Output("y", (0, 2), [("s", Triangle(0, 0, 2))])
    fls = T1Mamdani(inputs=[x1, x2], outputs=[y], rules=[Rule(["a", "a"], "s")], tnorm=tnorm,
                    resolution=5)
    grid = [Q(k, 2) for k in range(5)]
    mu = [min(f, 1 - g / 2) for g in grid]
    want = sum(m * g for m, g in zip(mu, grid, strict=True)) / sum(mu)
    assert float(fls(0.5, 0.4)) == pytest.approx(float(want), abs=1e-15)


def test_maxima_defuzzifiers_per_column() -> None:
    y = np.array([0.0, 1.0, 2.0])
    mu = np.array([[0.0, 1.0], [0.5, 0.0], [0.5, 0.0]])  # maxima 0.5 (a plateau) and 1
    assert defuzzify(mu, y, Defuzzifier.SOM).tolist() == [1.0, 0.0]
    assert defuzzify(mu, y, Defuzzifier.LOM).tolist() == [2.0, 0.0]
    assert defuzzify(mu, y, Defuzzifier.MOM).tolist() == [1.5, 0.0]
    assert defuzzify(mu, y, Defuzzifier.CENTROID).tolist() == [1.5, 0.0]


def test_type1_inputs_with_interval_output_sets_keep_the_outputs_footprint() -> None:
    # Type-1 antecedents fire a point (fl is fu), but the output sets still have a footprint:
    # x = 1/4 fires lo 3/4 and hi 1/4; min implication, max aggregation on y = 0..4 give
    # lower max([3/4, 1/2, 0, 0, 0], [0, 0, 0, 1/4, 1/4]), upper max([3/4, 3/4, 1/2, 1/4, 0],
    # [0, 1/4, 1/4, 1/4, 1/4]). (A regression: the upper aggregate was used for both.)
    x = Input("x", (0, 1), [IT2Set.type1(Triangle(0, 0, 1), "lo"),
                            IT2Set.type1(Triangle(0, 1, 1), "hi")])
    system = hand_system(inputs=[x])
    lo = [Q(3, 4), Q(1, 2), Q(0), Q(1, 4), Q(1, 4)]
    up = [Q(3, 4), Q(3, 4), Q(1, 2), Q(1, 4), Q(1, 4)]
    lower, upper = system.aggregated(0.25)
    assert lower.tolist() == [float(v) for v in lo] and upper.tolist() == [float(v) for v in up]
    left, right = centroid_interval(lo, up, GRID)
    assert left < right
    assert system.interval(0.25) == pytest.approx((float(left), float(right)), abs=1e-15)
    assert system.tables.type1_output == (False,)
    t1_out = hand_system(inputs=[x], outputs=[Output("y", (0, 4), [
        IT2Set.type1(Triangle(0, 0, 4), "small"), IT2Set.type1(Triangle(0, 4, 4), "big")])])
    assert t1_out.tables.type1_output == (True,)
    yl, yr = t1_out.interval(0.25)
    assert yl == yr


@pytest.mark.parametrize(("kind", "n"), [("centroid", 1100), ("cos", 8300), ("t1", 1100)])
def test_every_block_of_a_long_batch_is_evaluated(kind: str, n: int) -> None:
    # batches are cut in blocks (512 points for the aggregates, 4096 for centre-of-sets):
    # the last points of a batch longer than two blocks equal the same points alone
    if kind == "t1":
        x = Input("x", (0, 1), [("lo", Triangle(0, 0, 1)), ("hi", Triangle(0, 1, 1))])
        y = Output("y", (0, 4), [("small", Triangle(0, 0, 4)), ("big", Triangle(0, 4, 4))])
        fls: IT2Mamdani | T1Mamdani = T1Mamdani(
            inputs=[x], outputs=[y], rules=[Rule(["lo"], "small"), Rule(["hi"], "big")],
            resolution=5)
    else:
        tr = TypeReduction.CENTROID if kind == "centroid" else TypeReduction.CENTRE_OF_SETS
        fls = hand_system(type_reduction=tr)
    xs = np.linspace(0.0, 1.0, n)
    whole = fls(xs)
    tail = fls(xs[-5:])
    np.testing.assert_array_equal(whole[-5:], tail)
    assert np.isfinite(whole).all()


def test_interval_inputs_with_type1_output_sets_keep_the_firing_interval() -> None:
    # x = 1/4 fires lo [1/2, 3/4] and hi [0, 1/4] on type-1 output sets: the lower aggregate
    # comes from the lower firing, max(min(1/2, small), min(0, big))
    y = Output("y", (0, 4), [IT2Set.type1(Triangle(0, 0, 4), "small"),
                             IT2Set.type1(Triangle(0, 4, 4), "big")])
    system = hand_system(outputs=[y])
    lo = [Q(1, 2), Q(1, 2), Q(1, 2), Q(1, 4), Q(0)]
    up = [Q(3, 4), Q(3, 4), Q(1, 2), Q(1, 4), Q(1, 4)]
    left, right = centroid_interval(lo, up, GRID)
    assert system.tables.type1_output == (True,)
    assert system.interval(0.25) == pytest.approx((float(left), float(right)), abs=1e-15)
