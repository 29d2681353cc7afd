"""Global sensitivity of the key paired differences: Morris elementary effects (SALib) over
the paper's continuous open choices (docs/model.md#robustness).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .choices import PATHS

__all__ = ["SensitivityConfig", "SensitivityFactor", "morris_analysis", "morris_design"]


@dataclass(frozen=True, kw_only=True)
class SensitivityFactor:
    """A continuous choice varied by the Morris screening: a path and its grid of levels
    (as many as the screening's ``num_levels``, in increasing order)."""

    name: str
    path: str
    levels: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.path not in PATHS:
            raise ValueError(f"factor {self.name!r}: path {self.path!r} is not a known path")
        if self.path in ("metrics.heading", "controllers.tuned", "simulation.start_pose",
                         "simulation.desired_heading_pose"):
            raise ValueError(f"factor {self.name!r}: {self.path!r} is not continuous")
        for v in self.levels:
            PATHS[self.path](v, f"factor {self.name!r} levels")
        if len(self.levels) < 2 or list(self.levels) != sorted(set(self.levels)):
            raise ValueError(f"factor {self.name!r}: levels={list(self.levels)!r} must be >= 2 "
                             "distinct values in increasing order")


@dataclass(frozen=True, kw_only=True)
class SensitivityConfig:
    """Morris screening (SALib) of the key paired differences over continuous choices.

    Parameters
    ----------
    factors : tuple of SensitivityFactor
        The choices varied, each on the same number of grid levels (SALib's ``num_levels``,
        even).
    trajectories : int
        Morris trajectories ``r``: the screening simulates ``r (k + 1)`` design points for
        ``k`` factors.
    seeds : int
        Noise realisations per design point (common random numbers across points).
    seed : int
        Seed of SALib's sampling and of its bootstrap intervals.
    """

    factors: tuple[SensitivityFactor, ...] = (
        SensitivityFactor(name="half_track", path="robot.half_track",
                          levels=(0.056, 0.26, 1.2, 5.6)),
        SensitivityFactor(name="ts", path="simulation.ts", levels=(0.001, 0.0025, 0.005, 0.01)),
        SensitivityFactor(name="sigma", path="noise.sigma", levels=(0.05, 0.1, 0.2, 0.32)),
        SensitivityFactor(name="ke", path="controllers.ke", levels=(0.5, 0.8, 1.25, 2.0)),
        SensitivityFactor(name="kde", path="controllers.kde", levels=(0.5, 0.8, 1.25, 2.0)),
        SensitivityFactor(name="metric_start", path="simulation.metric_start",
                          levels=(0.0, 0.5, 1.0, 2.0)),
    )
    trajectories: int = 6
    seeds: int = 8
    seed: int = 0

    def __post_init__(self) -> None:
        if not self.factors:
            raise ValueError("sensitivity factors: needs at least one factor")
        names = [f.name for f in self.factors]
        if len(set(names)) != len(names):
            raise ValueError(f"sensitivity factors: names {names} must be unique")
        if len({len(f.levels) for f in self.factors}) != 1 or len(self.factors[0].levels) % 2:
            raise ValueError("sensitivity factors: every factor needs the same, even number of "
                             "levels (Morris num_levels)")
        for key in ("trajectories", "seeds"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int) or v < 2:
                raise ValueError(f"sensitivity {key}={v!r} must be an integer >= 2")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"sensitivity seed={self.seed!r} must be an integer >= 0")

    @property
    def num_levels(self) -> int:
        return len(self.factors[0].levels)

    def to_dict(self) -> dict[str, Any]:
        return {"trajectories": self.trajectories, "seeds": self.seeds, "seed": self.seed,
                "factors": [{"name": f.name, "path": f.path, "levels": list(f.levels)}
                            for f in self.factors]}


def morris_design(sens: SensitivityConfig) -> tuple[np.ndarray, list[dict[str, Any]]]:
    """SALib's Morris sample on the unit grid and the path values of each design point.

    Returns ``(X, points)``: ``X`` of shape ``(r (k + 1), k)`` in ``[0, 1]`` (grid
    ``i / (num_levels - 1)``), ``points[j] = {path: value}``. A fresh copy each call: the
    sample is drawn once per configuration (the study sizes its progress bar with it, then
    runs it).
    """
    x, points = _morris_design(sens)
    return x.copy(), [dict(p) for p in points]


@functools.lru_cache(maxsize=8)
def _morris_design(sens: SensitivityConfig) -> tuple[np.ndarray, list[dict[str, Any]]]:
    from SALib.sample import morris as morris_sample

    problem = _problem(sens)
    x = morris_sample.sample(problem, sens.trajectories, num_levels=sens.num_levels,
                             seed=sens.seed)
    p = sens.num_levels - 1
    points = []
    for row in x:
        idx = np.rint(row * p).astype(int)
        points.append({f.path: f.levels[i] for f, i in zip(sens.factors, idx, strict=True)})
    return x, points


def _problem(sens: SensitivityConfig) -> dict[str, Any]:
    return {"num_vars": len(sens.factors), "names": [f.name for f in sens.factors],
            "bounds": [[0.0, 1.0]] * len(sens.factors)}


def morris_analysis(sens: SensitivityConfig, x: np.ndarray,
                    outputs: Mapping[tuple[str, str], np.ndarray]
                    ) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """Morris indices of every output (``(name, trajectory) -> y``, one value per design
    point) and the overall ranking (mean over outputs of ``mu_star / max mu_star``).

    ``mu_star`` is in the output's unit per unit of the normalised grid (the full range of a
    factor's levels is 1).
    """
    from SALib.analyze import morris as morris_analyze

    problem = _problem(sens)
    rows = []
    scores = dict.fromkeys(problem["names"], 0.0)
    for (name, traj), y in outputs.items():
        res = morris_analyze.analyze(problem, x, np.asarray(y, dtype=np.float64),
                                     num_levels=sens.num_levels, seed=sens.seed)
        top = float(np.max(res["mu_star"])) or 1.0
        for i, factor in enumerate(problem["names"]):
            rows.append({"output": name, "trajectory": traj, "factor": factor,
                         "mu_star": float(res["mu_star"][i]),
                         "mu_star_conf": float(res["mu_star_conf"][i]),
                         "mu": float(res["mu"][i]), "sigma": float(res["sigma"][i])})
            scores[factor] += float(res["mu_star"][i]) / top / len(outputs)
    ranked = sorted(scores.items(), key=lambda kv: -kv[1])
    ranking = [{"factor": f, "score": s, "rank": i + 1} for i, (f, s) in enumerate(ranked)]
    return rows, ranking
