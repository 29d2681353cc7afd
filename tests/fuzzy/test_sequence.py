"""Sequence evaluation with fuzzylite's lock-previous (``evaluate_sequence``): hand-made
sequences with known fills, a fresh start, the state passed between chunks (bit-identical
whatever the chunking), outputs with and without the flag side by side, each output filled from
its own rules' firing, ``__call__`` unchanged, and the checks on the arguments."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from it2track.fuzzy import (
    HybridSystem,
    Input,
    IT2Set,
    IT2Sugeno,
    Linear,
    Output,
    Rule,
    T1Mamdani,
    T1Sugeno,
    Triangle,
    ZeroFiringError,
)

# two triangles with gaps between and around them: nothing fires on [2, 4] and [6, 10]
X = Input("x", (0, 10), [("a", Triangle(0, 1, 2)), ("b", Triangle(4, 5, 6))])


def _sugeno(**kw) -> T1Sugeno:
    return T1Sugeno(inputs=[X], rules=[Rule(["a"], 1.0), Rule(["b"], 5.0)], **kw)


def _col(values) -> np.ndarray:
    return np.asarray(values, dtype=float)[:, None]


def test_known_fills_from_a_fresh_start_and_from_a_given_previous() -> None:
    fls = _sugeno(lock_previous=True)
    y, state = fls.evaluate_sequence(_col([1.0, 3.0, 5.0, 8.0, 0.5, 2.0]))
    # 3 keeps a's 1, 8 keeps b's 5, 2 (a's foot: a is 0) keeps the 1 of 0.5
    assert y.tolist() == [1.0, 1.0, 5.0, 5.0, 1.0, 1.0]
    assert state.tolist() == [1.0]
    y, state = fls.evaluate_sequence(_col([3.0, 9.0, 5.0]), previous=[7.0])
    assert y.tolist() == [7.0, 7.0, 5.0] and state.tolist() == [5.0]
    y, state = fls.evaluate_sequence(_col([3.0]), previous=7.0)  # a scalar for one output
    assert y.tolist() == [7.0] and state.tolist() == [7.0]


def test_a_fresh_start_where_nothing_fires_is_what_call_gives_there() -> None:
    fls = _sugeno(lock_previous=True)
    with pytest.raises(ZeroFiringError, match=r"row 0 \(x=9\) and there is no previous"):
        fls.evaluate_sequence(_col([9.0, 3.0]))
    with pytest.raises(ZeroFiringError, match=r"row 0 \(x=0\)"):  # a's foot: nothing fires
        fls.evaluate_sequence(_col([0.0, 3.0]), previous=[np.nan])
    with pytest.raises(ZeroFiringError, match="row 0"):  # NaN: no previous output
        fls.evaluate_sequence(_col([3.0, 1.0]), previous=[np.nan])
    assert fls.evaluate_sequence(_col([1.0, 0.0, 3.0]))[0].tolist() == [1.0, 1.0, 1.0]
    default = _sugeno(lock_previous=True, on_zero_firing=-2.0)
    y, _ = default.evaluate_sequence(_col([3.0, 9.0, 1.0, 8.0]))
    assert y.tolist() == [-2.0, -2.0, 1.0, 1.0]  # the default until something fires
    y, _ = default.evaluate_sequence(_col([3.0, 1.0]), previous=[4.0])
    assert y.tolist() == [4.0, 1.0]  # a previous output comes before the default


def test_without_the_flag_the_sequence_is_evaluate() -> None:
    fls = _sugeno(on_zero_firing=-2.0)
    x = _col([1.0, 3.0, 5.0, 8.0])
    y, state = fls.evaluate_sequence(x, previous=[7.0])
    assert y.tolist() == [1.0, -2.0, 5.0, -2.0] and state.tolist() == [-2.0]
    assert_array_equal(y, fls.evaluate(x))
    with pytest.raises(ZeroFiringError):
        _sugeno().evaluate_sequence(x, previous=[7.0])


def test_call_stays_a_function_of_its_inputs() -> None:
    fls = _sugeno(lock_previous=True, on_zero_firing=-2.0)
    assert fls(3.0) == -2.0 and fls(1.0) == 1.0
    assert fls(np.array([1.0, 3.0])).tolist() == [1.0, -2.0]
    with pytest.raises(ZeroFiringError):
        _sugeno(lock_previous=True)(3.0)


def _random_system() -> T1Sugeno:
    sets = [(f"s{k}", Triangle(c - 0.6, c, c + 0.6)) for k, c in enumerate([1.0, 3.0, 5.0])]
    inputs = [Input("u", (0, 6), sets), Input("v", (0, 6), sets)]
    rules = [Rule([f"s{i}", f"s{j}"], consequents=[float(3 * i + j), float(i - j)])
             for i in range(3) for j in range(3) if (i + j) % 2 == 0]
    return T1Sugeno(inputs=inputs, rules=rules, outputs=("p", "q"),
                    lock_previous=(True, False), on_zero_firing=(0.5, -0.5))


def test_chunks_with_the_state_passed_on_are_bit_identical_to_the_whole() -> None:
    fls = _random_system()
    x = np.random.default_rng(7).uniform(0, 6, size=(400, 2))
    whole, last = fls.evaluate_sequence(x)
    _, upper = fls.firing(*x.T)
    assert (upper.sum(axis=1) == 0).sum() > 50  # the sequence has many gaps to fill
    for cuts in ([1], [7, 8, 9], [100, 250, 399], list(range(0, 400, 13))):
        state, parts = None, []
        for a, b in zip([0, *cuts], [*cuts, 400], strict=True):
            y, state = fls.evaluate_sequence(x[a:b], state)
            parts.append(y)
        assert_array_equal(np.concatenate(parts), whole)
        assert_array_equal(state, last)
    # one row at a time, as a control loop calls it
    state, rows = None, []
    for row in x:
        y, state = fls.evaluate_sequence(row[None], state)
        rows.append(y[0])
    assert_array_equal(np.array(rows), whole)


def test_each_output_fills_where_its_own_rules_do_not_fire() -> None:
    fls = _random_system()
    x = np.random.default_rng(3).uniform(0, 6, size=(300, 2))
    y, _ = fls.evaluate_sequence(x, previous=[9.0, 9.0])
    _, upper = fls.firing(*x.T)
    fires = upper.sum(axis=1) > 0
    assert_array_equal(y[fires], fls.evaluate(x[fires]))  # __call__'s bits where rules fire
    assert (y[~fires, 1] == -0.5).all()  # q has no lock: its default
    last, expected = 9.0, []
    for i in range(len(x)):  # p: the previous value of p, by a plain loop
        last = y[i, 0] if fires[i] else last
        expected.append(last)
    assert_array_equal(y[:, 0], expected)
    # an output whose rules do not fire is filled though another output's rules fire
    two = T1Sugeno(inputs=[X], rules=[Rule(["a"], consequents=[1.0, None]),
                                        Rule(["b"], consequents=[None, 5.0])],
                   outputs=("m", "n"), lock_previous=True)
    y, state = two.evaluate_sequence(_col([1.0, 5.0, 1.0]), previous=[3.0, 4.0])
    assert y.tolist() == [[1.0, 4.0], [1.0, 5.0], [1.0, 5.0]] and state.tolist() == [1.0, 5.0]


def test_mamdani_type2_and_hybrid_systems() -> None:
    out = Output("o", (0, 10), [("lo", Triangle(0, 2, 4)), ("hi", Triangle(6, 8, 10))])
    mam = T1Mamdani(inputs=[X], outputs=[out], rules=[Rule(["a"], "lo"), Rule(["b"], "hi")],
                    lock_previous=True)
    x = _col([1.0, 3.0, 5.0, 9.0])
    y, _ = mam.evaluate_sequence(x)
    at = mam.evaluate(x[[0, 2]])
    assert y.tolist() == [at[0], at[0], at[1], at[1]]
    sets = [IT2Set.from_fou(Triangle(0, 1, 2), 0.2, "a"),
            IT2Set.from_fou(Triangle(4, 5, 6), 0.2, "b")]
    it2 = IT2Sugeno(inputs=[Input("x", (0, 10), sets)], rules=[Rule(["a"], -1.0),
                    Rule(["b"], 2.0)], outputs=("t",), lock_previous=True)
    y2, _ = it2.evaluate_sequence(x)
    assert y2.tolist() == [-1.0, -1.0, 2.0, 2.0]
    hyb = HybridSystem((dataclasses.replace(mam, lock_previous=False, on_zero_firing=-1.0),
                        _sugeno(lock_previous=True, outputs=("s",))))
    assert hyb.lock_previous == (False, True) and hyb.keeps_previous(1)
    y, state = hyb.evaluate_sequence(x, previous=[0.0, 3.0])
    assert y[:, 0].tolist() == [at[0], -1.0, at[1], -1.0]
    assert y[:, 1].tolist() == [1.0, 1.0, 5.0, 5.0] and state.tolist() == [-1.0, 5.0]
    assert hyb.select_output("s").lock_previous is True


def test_the_flag_is_canonical_and_kept_by_select_output() -> None:
    fls = _random_system()
    assert fls.lock_previous == (True, False)
    assert fls.select_output("p").lock_previous is True
    assert fls.select_output("q").lock_previous is False
    both = dataclasses.replace(fls, lock_previous=(True, True))
    assert both.lock_previous is True and both == dataclasses.replace(fls, lock_previous=True)
    assert _sugeno().lock_previous is False


@pytest.mark.parametrize(("value", "fragment"), [
    ("yes", "lock_previous='yes'"), (1, "lock_previous=1"), ((True,), "one bool per output (2)"),
    ((True, False, True), "one bool per output"),
])
def test_bad_flags_are_refused(value, fragment: str) -> None:
    with pytest.raises(ValueError, match=fragment.replace("(", r"\(").replace(")", r"\)")):
        dataclasses.replace(_random_system(), lock_previous=value)


def test_bad_sequences_and_states_are_refused() -> None:
    fls = _random_system()
    good = np.ones((3, 2))
    for x, fragment in [(np.ones(2), r"shape \(N, 2\)"), (np.ones((3, 3)), r"shape \(N, 2\)"),
                        (np.array([[1.0, np.nan]]), "NaN or inf")]:
        with pytest.raises(ValueError, match=fragment):
            fls.evaluate_sequence(x)
    for previous, fragment in [([1.0], r"shape \(2,\)"), ([1.0, np.inf], "finite"),
                               (["a", "b"], "real numbers"), (1.0, r"shape \(2,\)")]:
        with pytest.raises(ValueError, match=fragment):
            fls.evaluate_sequence(good, previous)
    y, state = fls.evaluate_sequence(np.empty((0, 2)), [1.0, np.nan])
    assert y.shape == (0, 2) and state[0] == 1.0 and np.isnan(state[1])


def test_a_value_undefined_where_rules_fire_is_filled_as_fuzzylite_fills_nan() -> None:
    # at x = 10 both 'w' rules fire fully, their consequents +-1e309 overflow: inf - inf, NaN
    w = Input("x", (0, 10), [("a", Triangle(0, 1, 2)), ("w", Triangle(4, 10, 16))])
    fls = T1Sugeno(inputs=[w], rules=[Rule(["a"], 1.0), Rule(["w"], Linear([1e308], 0.0)),
                                      Rule(["w"], Linear([-1e308], 0.0))], lock_previous=True)
    with np.errstate(over="ignore"):
        y, state = fls.evaluate_sequence(_col([1.0, 10.0, 3.0]))
        assert y.tolist() == [1.0, 1.0, 1.0] and state.tolist() == [1.0]
        with pytest.raises(ZeroFiringError, match=r"has no output 'output1' at row 0 \(x=10\), "
                           "where its rules fire"):
            fls.evaluate_sequence(_col([10.0, 1.0]))
        default = dataclasses.replace(fls, on_zero_firing=-3.0)
        assert default.evaluate_sequence(_col([10.0, 1.0, 10.0]))[0].tolist() == [-3.0, 1.0, 1.0]
