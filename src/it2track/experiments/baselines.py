"""Fair baselines for the paper's IT2FLC (docs/model.md, "Fair baselines").

Two questions need baselines the paper does not have:

- *Is the footprint itself worth anything?* The IT2FLC of FoU width ``w`` has a dead zone
  ``|e| < d = 0.2 - w/2`` and, just outside it, a slope ``s(w)`` of ``u(e, 0)`` (about
  5.2 V/rad for ``w = 0.2``). :func:`~it2track.paper.dead_zone_matched_fls` matches the dead
  zone only (its upper MFs): it is about twice as steep there (10 V/rad), so comparing with it
  mixes a dead-zone effect with a gain effect. :func:`slope_matched_fls` matches both: the same
  dead zone, the same slope just outside it along each input axis, and the same output for
  large errors; what remains between it and the IT2FLC is the shape the footprint gives.
- *Is "PD is best" a tuning advantage?* :func:`tune_fuzzy` tunes the fuzzy controllers (input
  gains ``Ke``, ``Kde`` and an output gain) with the PD's budget, tuning seeds and effort
  limit (:class:`FuzzyTuning`). The output gain scales the rule consequents
  (:func:`scaled_consequents`), which gives a new system of the same kind: nothing in the
  closed loop changes.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..fuzzy import Input, IT2Set, IT2Sugeno, T1Sugeno, TNorm, Triangle, rules_from_table
from ..paper import LABELS, RULE_TABLE, heading_fls

__all__ = [
    "FuzzyTuning",
    "edge_slope",
    "scaled_consequents",
    "slope_matched_fls",
    "tuned_label",
]

#: Largest FoU width with a dead zone (``0.2 - w/2 >= 0``).
MAX_SLOPE_MATCHED_FOU = 0.4


def scaled_consequents(fls: IT2Sugeno | T1Sugeno, gain: float) -> IT2Sugeno | T1Sugeno:
    """The same system with every rule consequent (and ``on_zero_firing``) times ``gain``.

    For a zero-order Sugeno system (type-1, or interval type-2 with any exact or approximate
    type reducer) the output scales exactly: ``scaled(x) == gain * fls(x)`` up to rounding,
    because the firing strengths and the switch points do not depend on the consequents' scale
    (``gain > 0`` keeps their order).

    Raises
    ------
    ValueError
        If ``gain`` is not finite and > 0.
    """
    if isinstance(gain, bool) or not isinstance(gain, int | float) or not (
            math.isfinite(gain) and gain > 0):
        raise ValueError(f"output gain={gain!r} must be finite and > 0")
    if gain == 1.0:
        return fls

    def scale(c: object) -> object:
        if c is None:
            return None
        if isinstance(c, tuple) and len(c) == 2 and all(isinstance(v, float) for v in c):
            return (c[0] * gain, c[1] * gain)
        raise ValueError(f"output gain: consequent {c!r} is not a zero-order Sugeno "
                         "consequent (a number or an interval)")

    rules = tuple(r.with_consequents([scale(c) for c in r.consequents]) for r in fls.rules)
    zero = fls.on_zero_firing
    if isinstance(zero, tuple):
        zero = tuple(v * gain for v in zero)
    elif zero is not None:
        zero = zero * gain
    return dataclasses.replace(fls, rules=rules, on_zero_firing=zero,
                               name=f"{fls.name} x {gain:g}".strip())


def edge_slope(fls: Callable[[float, float], Any], edge: float) -> float:
    """Right derivative of ``u(e, 0)`` at ``e = edge`` where ``u(edge, 0) = 0`` (the dead-zone
    edge), by Richardson extrapolation of ``u(edge + h, 0) / h`` (error ~1e-10 for the
    piecewise-rational outputs of these systems)."""
    h = 1e-5
    s1 = float(fls(edge + h, 0.0)) / h
    s2 = float(fls(edge + h / 2, 0.0)) / (h / 2)
    return 2.0 * s2 - s1


def slope_matched_fls(fou: float, *, tnorm: TNorm = TNorm.PRODUCT) -> T1Sugeno:
    """Type-1 FLC with the dead zone *and* the edge slope of the IT2FLC of width ``fou``.

    Both inputs get the sets ``N = [-b, -b, -d]``, ``Z = [-z, 0, z]``, ``P = [d, b, b]`` with
    ``d = 0.2 - fou/2`` (the IT2FLC's dead zone), ``z = 0.8 + fou/2`` (its upper Z) and the
    shoulder ``b`` (beyond the universe, ``b > 1``) chosen so that the slope of ``u(e, 0)``
    just outside the dead zone equals the IT2FLC's: near the edge only the rules (Z, Z) -> 0
    and (P, Z) -> y (Table 2: 8 V) fire, so ``u = y mu_P / (mu_P + mu_Z)`` with slope
    ``y / ((b - d) (1 - d / z))``. Matched, therefore: the dead zone (``u = 0`` for
    ``|e| <= d`` and ``|de| <= d``), the right slope at the edge along either input axis, and
    the output once the error leaves Z (``|e| >= z``: ``y``, as for the FLC and the IT2FLC).
    Not matched: the curvature in between (the IT2FLC's output bends up between ``d`` and
    about 0.5; this one bends down), which is what the footprint adds.
    The rules are Table 2's.

    Raises
    ------
    ValueError
        Unless ``0 < fou <= 0.4`` (a dead zone to match).

    Examples
    --------
    >>> from it2track.paper import heading_fls
    >>> t1 = slope_matched_fls(0.2)
    >>> round(float(t1(0.1, 0.0)), 12), round(edge_slope(t1, 0.1), 6)
    (0.0, 5.185185)
    >>> round(edge_slope(heading_fls(0.2), 0.1), 6)
    5.185185
    """
    fou = float(fou)
    if not 0.0 < fou <= MAX_SLOPE_MATCHED_FOU:
        raise ValueError(f"slope-matched fou={fou!r} must satisfy 0 < fou <= "
                         f"{MAX_SLOPE_MATCHED_FOU} (a dead zone to match)")
    d = 0.2 - fou / 2.0
    z = 0.8 + fou / 2.0
    y = RULE_TABLE[2][1]  # (P, Z) -> 8 V
    target = edge_slope(heading_fls(fou, tnorm=tnorm), d)
    b = d + y / (target * (1.0 - d / z))
    sets = {
        "N": Triangle(-b, -b, -d),
        "Z": Triangle(-z, 0.0, z),
        "P": Triangle(d, b, b),
    }
    named = [IT2Set.type1(sets[k], k) for k in LABELS]
    inputs = (Input("e", (-1.0, 1.0), named), Input("de", (-1.0, 1.0), named))
    return T1Sugeno(inputs=inputs, rules=rules_from_table(LABELS, LABELS, RULE_TABLE),
                    tnorm=tnorm, name=f"type-1 FLC, dead zone and slope of FoU {fou:g}")


def tuned_label(label: str) -> str:
    """Label of the tuned version of a controller."""
    return f"{label} (tuned)"


def _grid(values: Sequence[float], key: str, *, positive: bool) -> tuple[float, ...]:
    out = tuple(float(v) for v in values)
    if not out or not all(math.isfinite(v) and (v > 0 if positive else v >= 0) for v in out):
        raise ValueError(f"tuning {key}={values!r} must be a non-empty list of finite gains "
                         + ("> 0" if positive else ">= 0"))
    if len(set(out)) != len(out):
        raise ValueError(f"tuning {key}={values!r} lists a gain twice")
    return out


@dataclass(frozen=True, kw_only=True)
class FuzzyTuning:
    """How the fuzzy controllers are tuned (beside the untuned paper controllers).

    The same procedure as the PD's (:class:`~it2track.experiments.study.config.PDTuning`): every
    candidate ``(ke, kde, gain)`` of the grid is simulated on the PD's tuning realisations
    (seed indices ``1_000_000 + i``, ``i < pd.seeds``) at the study's noise level over the
    study's trajectories, and the candidate with the smallest mean ISE whose mean control
    effort stays within the PD's limit (the largest mean effort of the paper's fuzzy
    controllers on the same runs) is chosen. The default grid has the PD grid's size
    (5 x 11 x 3 = 15 x 11 = 165 candidates): the same budget.

    Parameters
    ----------
    controllers : tuple of str
        Which fuzzy controllers to tune: ``"flc"`` (the FLC) and/or ``"it2"`` (the IT2FLC of
        every width in ``fous``).
    ke_grid, kde_grid : tuple of float
        Input gains (``ke > 0``, ``kde >= 0``; ``kde = 0`` ignores the change of error).
    gain_grid : tuple of float
        Output gains (> 0), applied by scaling the consequents.
    """

    controllers: tuple[str, ...] = ("flc", "it2")
    ke_grid: tuple[float, ...] = (0.5, 1.0, 2.0, 4.0, 8.0)
    kde_grid: tuple[float, ...] = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0)
    gain_grid: tuple[float, ...] = (0.25, 0.5, 1.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "ke_grid", _grid(self.ke_grid, "ke_grid", positive=True))
        object.__setattr__(self, "kde_grid", _grid(self.kde_grid, "kde_grid", positive=False))
        object.__setattr__(self, "gain_grid", _grid(self.gain_grid, "gain_grid", positive=True))
        known = ("flc", "it2")
        if not self.controllers or any(c not in known for c in self.controllers) or len(
                set(self.controllers)) != len(self.controllers):
            raise ValueError(f"tuning controllers={self.controllers!r} must be distinct names "
                             f"among {list(known)}")

    @property
    def candidates(self) -> list[tuple[float, float, float]]:
        """Every ``(ke, kde, gain)`` of the grid, ``ke`` slowest."""
        return list(itertools.product(self.ke_grid, self.kde_grid, self.gain_grid))

    def on_edge(self, ke: float, kde: float, gain: float) -> bool:
        """Whether a chosen candidate lies on the outer edge of the grid (where a wider grid
        might do better; ``kde = 0`` is a natural bound, not an edge)."""
        return (ke in (self.ke_grid[0], self.ke_grid[-1]) or kde == self.kde_grid[-1]
                or gain in (self.gain_grid[0], self.gain_grid[-1]))

    def to_dict(self) -> dict[str, Any]:
        return {"controllers": list(self.controllers), "ke_grid": list(self.ke_grid),
                "kde_grid": list(self.kde_grid), "gain_grid": list(self.gain_grid)}


def choose(ise: np.ndarray, effort: np.ndarray, limit: float) -> int | None:
    """Index of the smallest mean ISE among the candidates within the effort limit."""
    feasible = effort <= limit
    if not feasible.any():
        return None
    return int(np.argmin(np.where(feasible, ise, np.inf)))
