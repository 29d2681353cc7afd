"""experiments/stats.py at its boundaries: exact messages, caps, sizes, precision of the inputs.

The references are closed forms (Clopper-Pearson with k = 0 or k = n, Holm's cap at 1) and
scipy.stats on float64 copies of the data; the cases are the ones a mutation test of the module
found unpinned (docs/guide/mutation.md).
"""

import math
import re

import numpy as np
import pytest
from scipy import stats

from it2track.experiments.stats import (
    binomial_interval,
    holm_adjust,
    mean_interval,
    paired_comparison,
    t_tail,
)

# float32 cannot hold 1e8 + 1 (its spacing there is 8): summed in float32 the 1 is lost and the
# mean is 0; summed in float64 it is exactly 1 / 3.
LOSSY32 = np.array([1e8, 1.0, -1e8], dtype=np.float32)


def test_mean_interval_sums_float32_data_in_float64():
    iv = mean_interval(LOSSY32)
    assert iv.mean == 1.0 / 3.0
    ref = stats.t.interval(0.95, 2, loc=1.0 / 3.0,
                           scale=stats.sem(LOSSY32.astype(np.float64)))
    assert (iv.low, iv.high) == pytest.approx(ref, rel=1e-12)


def test_t_tail_sums_float32_data_in_float64():
    ref = stats.ttest_1samp(LOSSY32.astype(np.float64), 0.0, alternative="greater").pvalue
    assert ref < 0.5  # the float64 mean (1/3) is above 0; a float32 mean (0) would give 0.5
    assert t_tail(LOSSY32) == pytest.approx(ref, rel=1e-12)


def test_t_tail_tests_against_zero_by_default():
    # t = mean / (sd / sqrt(n)) = 2 / (1 / sqrt(3)) on 2 d.o.f.
    assert t_tail([1.0, 2.0, 3.0]) == pytest.approx(stats.t.sf(2.0 * math.sqrt(3.0), 2),
                                                    rel=1e-12)


@pytest.mark.parametrize(("call", "message"), [
    (lambda: mean_interval([]), "mean_interval needs at least one value"),
    (lambda: mean_interval([1.0, math.nan]), "mean_interval: values contain NaN or inf"),
    (lambda: paired_comparison([1.0, 2.0], [1.0, 2.0, 3.0]),
     "paired samples differ in length: 2 vs 3"),
    (lambda: t_tail([1.0, 2.0], side="both"), "side='both' must be 'greater' or 'less'"),
    (lambda: t_tail([1.0, math.inf]), "t_tail: values contain NaN or inf"),
    (lambda: holm_adjust([0.5, 1.5]), "holm_adjust: p-values must lie in [0, 1]"),
    (lambda: binomial_interval(3, 2),
     "binomial_interval: need 0 <= k <= n and n >= 1, got k=3, n=2"),
])
def test_errors_say_what_is_wrong_word_for_word(call, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        call()


def test_paired_comparison_uses_the_level_it_is_given():
    a = np.array([1.0, 2.5, 2.0, 4.0, 3.5])
    b = np.array([0.5, 2.0, 2.5, 3.0, 2.0])
    d = a - b
    ref = stats.t.interval(0.80, d.size - 1, loc=d.mean(), scale=stats.sem(d))
    iv = paired_comparison(a, b, level=0.80).diff
    assert (iv.low, iv.high) == pytest.approx(ref, rel=1e-12)


@pytest.mark.parametrize("bad", [[math.nan, 0.5], [0.5, math.nan], [-0.1, 0.5], [0.5, 1.5],
                                 [1.0 + 2**-52], [-1e-300]])
def test_holm_refuses_each_kind_of_bad_p_value_alone(bad):
    with pytest.raises(ValueError, match="must lie in"):
        holm_adjust(bad)


def test_holm_accepts_the_ends_of_the_unit_interval_and_an_empty_family():
    assert holm_adjust([0.0, 1.0]).tolist() == [0.0, 1.0]
    assert holm_adjust([]).tolist() == []


def test_holm_caps_adjusted_p_values_at_one():
    # 2 * 0.6 = 1.2 and 1 * 0.7 = 0.7 -> running max 1.2 -> capped at 1 (Holm 1979)
    assert holm_adjust([0.6, 0.7]).tolist() == [1.0, 1.0]
    assert holm_adjust([0.7, 0.45]).tolist() == [0.9, 0.9]  # 2 * 0.45, below the cap


@pytest.mark.parametrize(("k", "n"), [(True, 5), (1, True), (0, 0), (0, -1), (-1, 4)])
def test_binomial_interval_refuses_bools_and_empty_samples(k, n):
    with pytest.raises(ValueError, match="need 0 <= k <= n and n >= 1"):
        binomial_interval(k, n)


def test_binomial_interval_of_a_single_trial_is_the_closed_form():
    # Clopper-Pearson: k = 0 -> [0, 1 - (a/2)^(1/n)], k = n -> [(a/2)^(1/n), 1]; n = 1, a = 0.05
    assert binomial_interval(0, 1) == pytest.approx((0.0, 0.975), abs=1e-12)
    assert binomial_interval(1, 1) == pytest.approx((0.025, 1.0), abs=1e-12)
