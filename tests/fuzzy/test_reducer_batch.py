"""Every type reducer gives the same bits for a sample whatever batch it is reduced in.

Catches sums whose order depends on the batch (numpy's pairwise summation and einsum kernels
reduce a length-R column in a different order when the batch has one sample).
"""

import numpy as np
import pytest

from it2track.fuzzy.reducers import Reducer


@pytest.mark.parametrize("reducer", [m.value for m in Reducer], ids=lambda r: r.name)
@pytest.mark.parametrize("n_rules", [3, 9, 17])
def test_sample_alone_equals_sample_in_batch(reducer, n_rules):
    rng = np.random.default_rng(n_rules)
    n = 300
    fl = rng.uniform(0.05, 1.0, (n, n_rules))
    fu = fl + rng.uniform(0.0, 1.0, (n, n_rules))
    y_lo = np.sort(rng.normal(size=n_rules) * 5.0)
    y_hi = y_lo + rng.uniform(0.0, 1.0, n_rules)
    yl, yr = reducer(fl, fu, y_lo, y_hi)
    for i in range(n):
        a, b = reducer(fl[i : i + 1], fu[i : i + 1], y_lo, y_hi)
        assert a[0] == yl[i] and b[0] == yr[i], f"{reducer.name}: sample {i} differs alone"
