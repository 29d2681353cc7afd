"""Tuning the study's baselines: the PD (:func:`tune_pd`) and the fuzzy controllers with the PD's
budget (:func:`tune_fuzzy`), on seed indices disjoint from the evaluation seeds
(:data:`TUNING_SEED_OFFSET`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...tracking import (
    HeadingController,
    PDHeadingController,
    get_trajectory,
    run_grid,
    simulate_metrics,
)
from ..baselines import choose, tuned_label
from ..specs import ControllerKind, ControllerSpec
from .config import StudyConfig

__all__ = ["TUNING_SEED_OFFSET", "tune_fuzzy", "tune_pd"]

FloatArray = NDArray[np.float64]


#: Offset of the seed indices used to tune the PD baseline (disjoint from evaluation seeds).
TUNING_SEED_OFFSET = 1_000_000


def _tuning_evaluate(config: StudyConfig, ctrls: Sequence[HeadingController],
                     progress: Callable[[int], object] | None) -> tuple[FloatArray, FloatArray]:
    """Mean ISE and mean effort of each controller over the tuning runs."""
    assert config.pd is not None
    trajs = [get_trajectory(t) for t in config.trajectories]
    seeds = TUNING_SEED_OFFSET + np.arange(config.pd.seeds)
    runs = run_grid(len(ctrls), len(trajs), [config.noise_std], seeds.tolist())
    m = simulate_metrics(ctrls, trajs, runs, config.loop, batch_size=config.batch_size,
                         progress=progress)
    shape = (len(ctrls), -1)
    return m["ISE"].reshape(shape).mean(axis=1), m["effort"].reshape(shape).mean(axis=1)


def tune_pd(
    config: StudyConfig, progress: Callable[[int], object] | None = None
) -> tuple[ControllerSpec, dict[str, Any]]:
    """Tune the PD baseline by the procedure of :class:`.PDTuning`.

    Returns the PD spec and a record: ``grid`` (rows ``[kp, kd, mean ISE, mean effort]``, see
    ``grid_columns``), the chosen ``kp``, ``kd``, its ``objective`` (mean ISE) and ``effort``,
    the ``effort_limit`` applied and the rule behind it (``effort_limit_rule``),
    ``on_grid_edge``, and ``fuzzy_effort`` (label -> mean effort of each paper fuzzy
    controller on the tuning runs, also their ``fuzzy_ise``) when they were simulated.
    """
    tuning = config.pd
    assert tuning is not None
    if tuning.kp is not None:
        spec = ControllerSpec(kind=ControllerKind.PD, kp=tuning.kp, kd=tuning.kd or 0.0,
                              tf=tuning.tf, label="PD (given)")
        return spec, {"grid": [], "kp": spec.kp, "kd": spec.kd, "objective": None,
                      "on_grid_edge": False}
    seeds = TUNING_SEED_OFFSET + np.arange(tuning.seeds)
    grid = [(kp, kd) for kp in tuning.kp_grid for kd in tuning.kd_grid]
    ise, effort = _tuning_evaluate(
        config, [PDHeadingController(kp=kp, kd=kd, tf=tuning.tf) for kp, kd in grid], progress)
    record_extra: dict[str, Any] = {}
    if tuning.match_effort or config.tuning is not None:
        fuzzy = config.paper_fuzzy()
        fuzzy_ise, fuzzy_effort = _tuning_evaluate(config, [s.build() for s in fuzzy], progress)
        record_extra = {
            "fuzzy_effort": {s.label: float(v) for s, v in zip(fuzzy, fuzzy_effort,
                                                               strict=True)},
            "fuzzy_ise": {s.label: float(v) for s, v in zip(fuzzy, fuzzy_ise, strict=True)},
        }
    if tuning.match_effort:
        limit = float(max(record_extra["fuzzy_effort"].values()))
        rule = "largest mean effort of the FLC and the IT2FLCs on the tuning runs"
    else:
        limit = math.inf if tuning.effort_limit is None else tuning.effort_limit
        rule = "fixed" if tuning.effort_limit is not None else "none"
    best = choose(ise, effort, limit)
    if best is None:
        raise ValueError(
            f"PD tuning: no gains on the grid keep the mean effort within "
            f"{limit:.3g} V^2 s (smallest {effort.min():.3g}); "
            "raise the limit or extend the grid towards smaller gains"
        )
    kp, kd = grid[best]
    best_value = float(ise[best])
    edge = bool(kp in (tuning.kp_grid[0], tuning.kp_grid[-1]) or kd == tuning.kd_grid[-1])
    spec = ControllerSpec(kind=ControllerKind.PD, kp=kp, kd=kd,
                          tf=tuning.tf, label="PD (tuned)")
    record = {
        "grid": [[g[0], g[1], float(v), float(f)]
                 for g, v, f in zip(grid, ise, effort, strict=True)],
        "grid_columns": ["kp", "kd", "mean ISE", "mean effort"],
        "kp": spec.kp, "kd": spec.kd, "objective": best_value, "on_grid_edge": edge,
        "effort": float(effort[best]),
        "effort_limit": None if math.isinf(limit) else limit, "effort_limit_rule": rule,
        "seed_indices": [int(seeds[0]), int(seeds[-1])],
        "noise_std": config.noise_std, "criterion": "mean ISE over trajectories",
        **record_extra,
    }
    return spec, record


def tune_fuzzy(
    config: StudyConfig, pd_record: Mapping[str, Any],
    progress: Callable[[int], object] | None = None,
) -> tuple[dict[str, ControllerSpec], dict[str, dict[str, Any]]]:
    """Tune the fuzzy controllers of :meth:`.StudyConfig.tuned_roles` by :class:`FuzzyTuning`:
    the PD's tuning runs, the PD's budget and the PD's effort limit (``pd_record``, from
    :func:`tune_pd`; without a limit there, the largest mean effort of the paper's fuzzy
    controllers on the same runs).

    Returns ``(tuned, records)``, both keyed by the paper controller's label (see
    :class:`.StudyResult`).
    """
    tuning = config.tuning
    if tuning is None or config.pd is None:
        return {}, {}
    limit = pd_record.get("effort_limit")
    if limit is None:
        limit = float(max(pd_record["fuzzy_effort"].values()))
    candidates = tuning.candidates
    tuned: dict[str, ControllerSpec] = {}
    records: dict[str, dict[str, Any]] = {}
    seeds = TUNING_SEED_OFFSET + np.arange(config.pd.seeds)
    for role in config.tuned_roles():
        specs = [replace(role, ke=ke, kde=kde, output_gain=g, label="")
                 for ke, kde, g in candidates]
        ise, effort = _tuning_evaluate(config, [s.build() for s in specs], progress)
        best = choose(ise, effort, limit)
        if best is None:
            raise ValueError(
                f"tuning {role.label}: no candidate keeps the mean effort within the PD's "
                f"limit {limit:.3g} V^2 s (smallest {effort.min():.3g}); extend the grid "
                "towards smaller gains"
            )
        ke, kde, gain = candidates[best]
        spec = replace(role, ke=ke, kde=kde, output_gain=gain, label=tuned_label(role.label))
        tuned[role.label] = spec
        records[role.label] = {
            "grid": [[c[0], c[1], c[2], float(v), float(f)]
                     for c, v, f in zip(candidates, ise, effort, strict=True)],
            "grid_columns": ["ke", "kde", "gain", "mean ISE", "mean effort"],
            "ke": ke, "kde": kde, "gain": gain, "objective": float(ise[best]),
            "effort": float(effort[best]), "effort_limit": limit,
            "on_grid_edge": tuning.on_edge(ke, kde, gain),
            "untuned": {"ise": pd_record.get("fuzzy_ise", {}).get(role.label),
                        "effort": pd_record.get("fuzzy_effort", {}).get(role.label)},
            "seed_indices": [int(seeds[0]), int(seeds[-1])],
            "noise_std": config.noise_std, "criterion": "mean ISE over trajectories",
        }
    return tuned, records
