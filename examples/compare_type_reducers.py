"""
Compare the type reducers
=========================

The exact type reducers agree; the closed-form approximations do not. Time them too.

Run: ``python examples/compare_type_reducers.py``
"""

import time
from dataclasses import replace

import numpy as np

from it2track import heading_fls
from it2track.fuzzy import Reducer

rng = np.random.default_rng(0)
e, de = rng.uniform(-1, 1, (2, 200_000))
reference = heading_fls(0.2)  # default reducer: exhaustive (exact, non-iterative)
yl0, yr0 = reference.interval(e, de)
for member in Reducer:
    fls = replace(reference, reducer=member.value)
    start = time.perf_counter()
    yl, yr = fls.interval(e, de)
    elapsed = time.perf_counter() - start
    gap = max(np.abs(yl - yl0).max(), np.abs(yr - yr0).max())
    kind = "exact" if member.value.exact else "approximation"
    print(f"{member.value.name:11s} {kind:13s} max |diff| {gap:9.2e}   "
          f"{e.size / elapsed / 1e6:6.1f} M samples/s")
