"""Printed intervals: the printed mean always lies inside the printed interval."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from it2track.experiments.stats import interval_text


def _parse(text):
    mean, rest = text.split(" [")
    low, high = rest.rstrip("]").split(", ")
    return float(mean), float(low), float(high)


def test_the_reported_case_gets_the_digits_it_needs():
    # The review's case: 2.748 printed with a 3-digit interval [2.75, 2.75] put the mean
    # outside its own interval.
    text = interval_text(2.7483, 2.7480, 2.7486)
    m, lo, hi = _parse(text)
    assert lo < m < hi
    assert text == "2.7483 [2.748, 2.7486]"
    assert interval_text(0.5, 0.25, 0.75) == "0.5 [0.25, 0.75]"  # no needless digits
    assert interval_text(1.0, 1.0, 1.0) == "1 [1, 1]"  # a collapsed interval stays collapsed
    assert interval_text(3.0, 3.0, 4.0) == "3 [3, 4]"  # a mean on its bound may print equal


@given(st.floats(-1e6, 1e6, allow_nan=False), st.floats(0, 1e3), st.floats(0, 1e3),
       st.integers(1, 6))
def test_printed_mean_lies_inside_and_off_the_bounds(mean, below, above, digits):
    low, high = mean - below, mean + above
    if not (low <= mean <= high):  # rounding of mean +- x
        return
    m, lo, hi = _parse(interval_text(mean, low, high, digits))
    assert lo <= m <= hi
    if low < mean:
        assert lo < m
    if mean < high:
        assert m < hi
    assert math.isclose(m, mean, rel_tol=10.0 ** (1 - digits), abs_tol=1e-300)


@pytest.mark.parametrize("bad", [(1.0, 2.0, 3.0), (1.0, 0.0, 0.5), (math.nan, 0.0, 1.0),
                                 (0.0, -math.inf, 1.0)])
def test_inconsistent_intervals_are_refused(bad):
    with pytest.raises(ValueError, match="low <= mean <= high"):
        interval_text(*bad)


def test_evidence_tables_print_the_estimate_inside_its_interval():
    from it2track.experiments.judgement import evidence_texts

    row = {"sigma": 0.1, "metric": "ISE", "n": 100, "diff_mean": 2.74831,
           "ci_low": 2.74802, "ci_high": 2.74867, "p_holm": 0.5, "outcome": "inconclusive"}
    text = evidence_texts(row)
    m, lo, hi = float(text["diff_mean"]), float(text["ci_low"]), float(text["ci_high"])
    assert lo < m < hi  # at 4 digits all three would print 2.748
    assert text["n"] == "100" and text["p_holm"] == "0.5" and text["sigma"] == "0.1"
    c3 = {"sigma": 0.05, "best controller": "FLC", "n": 4, "mean ISE": 0.0031234,
          "ci_low": 0.0031230, "ci_high": 0.003124}
    shown = evidence_texts(c3)
    assert float(shown["ci_low"]) < float(shown["mean ISE"]) < float(shown["ci_high"])
    noise_free = {"sigma": 0.0, "diff_mean": 1.0, "ci_low": "", "ci_high": ""}
    assert evidence_texts(noise_free) == {"sigma": "0", "diff_mean": "1", "ci_low": "",
                                          "ci_high": ""}
