"""
Build an IT2 Sugeno system from scratch
=======================================

Build an interval type-2 Sugeno system from scratch and evaluate it on a batch.

Run: ``python examples/build_it2_system_from_scratch.py``
"""

import numpy as np

from it2track.fuzzy import EIASC, KM, Input, IT2Set, IT2Sugeno, Rule, Triangle

# One input "temperature error" on [-5, 5] with three IT2 sets: a centre line widened by a
# footprint of uncertainty of width 1, and one set given by explicit upper/lower triangles.
cold = IT2Set.from_fou(Triangle(-5, -5, 0), 1.0, "cold")
ok = IT2Set.triangle(upper=[-3, 0, 3], lower=[-2, 0, 2, 0.8], name="ok")  # [a b c h]
hot = IT2Set.from_fou(Triangle(0, 5, 5), 1.0, "hot")
rate = Input("rate", (-1, 1), [IT2Set.gaussian_uncertain_std(0.0, 0.3, 0.5, "steady")])

fls = IT2Sugeno(
    inputs=[Input("error", (-5, 5), [cold, ok, hot]), rate],
    rules=[
        Rule(["cold", "steady"], (0.8, 1.0)),  # interval consequent [0.8, 1.0]
        Rule(["ok", None], 0.0),  # None: the rule ignores the input "rate"
        Rule(["hot", "steady"], -1.0),
    ],
    reducer=KM,
)

error = np.linspace(-6, 6, 7)  # outside [-5, 5] is clipped to the universe
rate_now = np.array([[0.0], [0.4]])  # broadcasts against error: output shape (2, 7)
u = fls(error, rate_now)
yl, yr = fls.interval(error, rate_now)
print("u =\n", u.round(4))
print("yl <= u <= yr:", bool(np.all((yl <= u) & (u <= yr))))

# Every exact type reducer gives the same interval (to rounding):
from dataclasses import replace  # noqa: E402

yl2, yr2 = replace(fls, reducer=EIASC).interval(error, rate_now)
print("KM vs EIASC max difference:", float(max(abs(yl - yl2).max(), abs(yr - yr2).max())))

lower, upper = fls.firing(1.0, 0.0)
intervals = list(zip(lower.round(3).tolist(), upper.round(3).tolist(), strict=True))
print("firing intervals at (1, 0):", intervals)
