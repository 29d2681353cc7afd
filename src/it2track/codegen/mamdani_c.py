"""A Mamdani system's output in the float and double C: the output grid, the output sets' MFs
on it and each rule's set, for the template's implication, aggregation and centroid.

The generated code follows :class:`~it2track.fuzzy.mamdani.MamdaniTables` step for step: the
firing intervals as for a Sugeno system; per grid point ``y_j`` the implication (``min``
clips, ``product`` scales) of each rule's firing with its set's MF at ``y_j``, aggregated over
the rules (``max``: through the strongest firing of each set, ``sum``, probabilistic OR) into
the lower and upper MF of one IT2 set; its centroid by the system's type reducer over the grid
points where the upper MF is positive (a centre-of-sets problem whose "rules" are the grid
points, consequent ``y_j``, firing ``[lower, upper]``), or for a type-1 system its
defuzzification (centroid, bisector, MOM, SOM, LOM). The grid and the MFs on it are tables of
the values Python computed (in double), rounded once to float for a float build.

A centre-of-sets Mamdani system (``TypeReduction.CENTRE_OF_SETS``) is its centre-of-sets
Sugeno system, and is generated as one (no grid in the C).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..fuzzy import IT2Mamdani, T1Mamdani
from ..fuzzy.mamdani import TypeReduction

__all__ = ["is_centroid_mamdani", "mamdani_context"]


def is_centroid_mamdani(system: object) -> bool:
    """True for a Mamdani system whose output is computed on its grid (a type-1 Mamdani
    system, or an interval type-2 one with centroid type reduction)."""
    if type(system) is T1Mamdani:
        return True
    return type(system) is IT2Mamdani and system.type_reduction is TypeReduction.CENTROID


def mamdani_context(system: Any, lit: Callable[[float], str]) -> dict[str, Any]:
    """The template context of a Mamdani system's output (one output; see the module
    docstring). ``lit`` writes a constant as a C literal."""
    m = system.tables
    out = system.outputs[0]
    grid = np.asarray(m.grids[0], dtype=np.float64)
    upper = np.asarray(m.upper_mf[0], dtype=np.float64)
    lower = np.asarray(m.lower_mf[0], dtype=np.float64)
    t1 = type(system) is T1Mamdani
    sets = [int(v) for v in m.rule_set_s[0]]
    tables = [("MU", [[lit(v) for v in row] for row in upper.tolist()])]
    if not t1:
        tables.append(("ML", [[lit(v) for v in row] for row in lower.tolist()]))
    return {
        "mam_t1": t1, "out_name": out.name, "out_lo": repr(float(out.universe[0])),
        "out_hi": repr(float(out.universe[1])), "n_grid": int(grid.size),
        "grid": [lit(v) for v in grid.tolist()], "n_sets": len(out.sets),
        "set_names": [s.name for s in out.sets], "mf_tables": tables, "rule_set": sets,
        "used_sets": sorted(set(sets)), "implication": system.implication.value,
        "aggregation": system.aggregation.value,
        "defuzzifier": system.defuzzifier.value if t1 else None,
    }
