"""Seeds by need: a sequential design that adds noise realisations where a verdict needs them.

Every (path, sigma) *unit* of an experiment starts with ``first`` realisations (seed indices
``0 .. first-1``) for every controller. After each round, every claim is judged
(:func:`~.analysis.evaluate_claims`) and the replication probability of every level -- claim x
path (and all paths together) x sigma -- is estimated by the bootstrap
(:mod:`.replication`). A level is *settled* when its replication probability reaches
``target``. Every unit behind an unsettled level (its path, or every path of the claim for a
level over all paths) gets ``batch`` more realisations, up to ``cap``, for every controller
(so all controllers of a unit keep sharing their seeds: the comparisons stay paired); rounds
continue until every level is settled or every unit behind an unsettled one is at the cap.
Levels still unsettled at the cap are reported as such, never as a verdict.

The design is reused by every experiment that judges claims (the study's noise sweep, and any
plant or controller implementation that can simulate a batch of seeds): :func:`settle` takes a
callable that simulates :class:`SeedBatch` requests and returns metrics rows.

Stopping when the estimate first reaches the target looks at the data up to
``1 + (cap - first) / batch`` times; the check of two independent runs
(``benchmarks/check_verdict_replication.py``) measures how often a settled level changes status
under a fresh seed set.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .analysis import evaluate_claims
from .claimcells import BAND, ClaimDef
from .judgement import ALL, DETERMINISTIC, ClaimResult
from .replication import replicate_claims

__all__ = ["SeedBatch", "SequentialDesign", "SettledResult", "concat_rows", "settle"]

Rows = Mapping[str, np.ndarray]


def _int(v: Any, key: str, least: int) -> None:
    if isinstance(v, bool) or not isinstance(v, int) or v < least:
        raise ValueError(f"verdicts {key}={v!r} must be an integer >= {least}")


@dataclass(frozen=True, kw_only=True)
class SequentialDesign:
    """How many noise realisations a level gets (module docstring).

    Parameters
    ----------
    first : int
        Realisations of every (path, sigma) unit in the first round (>= 2).
    batch : int
        Realisations added to a unit behind an unsettled level, per round (>= 1).
    cap : int
        Most realisations per unit (>= first).
    target : float
        Replication probability that settles a level, in (0, 1].
    resamples : int
        Bootstrap resamples per estimate (>= 100).
    seed : int
        Seed of the bootstrap's draws (>= 0).
    """

    first: int = 100
    batch: int = 100
    cap: int = 400
    target: float = 0.95
    resamples: int = 1000
    seed: int = 0

    def __post_init__(self) -> None:
        _int(self.first, "first", 2)
        _int(self.batch, "batch", 1)
        _int(self.resamples, "resamples", 100)
        _int(self.seed, "seed", 0)
        _int(self.cap, "cap", 2)
        if self.cap < self.first:
            raise ValueError(f"verdicts cap={self.cap!r} must be >= the first round's "
                             f"{self.first} realisations")
        t = self.target
        if isinstance(t, bool) or not isinstance(t, int | float) or not (
                math.isfinite(t) and 0.0 < t <= 1.0):
            raise ValueError(f"verdicts replication={t!r} must lie in (0, 1]")

    def to_dict(self) -> dict[str, Any]:
        return {"first": self.first, "batch": self.batch, "cap": self.cap,
                "replication": self.target, "resamples": self.resamples, "seed": self.seed}


@dataclass(frozen=True)
class SeedBatch:
    """Realisations to simulate: seed indices ``start .. stop-1`` of every ``(controller,
    path, sigma)`` cell of ``cells``."""

    cells: tuple[tuple[str, str, float], ...]
    start: int
    stop: int

    @property
    def seeds(self) -> np.ndarray:
        return np.arange(self.start, self.stop, dtype=np.int64)


#: ``simulate(batches)`` -> metrics rows (columns ``experiment, trajectory, controller,
#: noise_std, seed`` and the metrics) of every requested cell and seed.
Simulate = Callable[[Sequence[SeedBatch]], Rows]


@dataclass
class SettledResult:
    """What :func:`settle` found.

    Attributes
    ----------
    rows : dict of str -> ndarray
        Every row simulated (the first round's and each extension's).
    claims : list of ClaimResult
        The claims judged on all rows, with replication probabilities and verdicts over the
        settled levels.
    n : dict of (str, float) -> int
        Realisations per (path, sigma) unit at the end.
    rounds : list of dict
        Per extension round: ``{"round": k, "units": [(path, sigma, n_before, n_after),
        ...]}``.
    design : SequentialDesign
    """

    rows: dict[str, np.ndarray]
    claims: list[ClaimResult]
    n: dict[tuple[str, float], int]
    design: SequentialDesign
    rounds: list[dict[str, Any]] = field(default_factory=list)

    def n_of(self, claim: ClaimDef | None, path: str, sigma: float,
             trajectories: Sequence[str]) -> int:
        """Realisations behind a level: the unit's, or the fewest of the claim's paths for a
        level over all paths (1 without noise)."""
        if sigma == 0.0:
            return 1
        if path != ALL:
            return self.n[(path, sigma)]
        paths = claim.trajectories if claim is not None else trajectories
        return min(self.n[(p, sigma)] for p in paths)


def concat_rows(parts: Sequence[Rows]) -> dict[str, np.ndarray]:
    """Row tables with the same columns, one after the other."""
    parts = [p for p in parts if len(p["seed"])]
    if not parts:
        raise ValueError("no rows")
    keys = list(parts[0])
    for p in parts[1:]:
        if list(p) != keys:
            raise ValueError(f"rows with other columns: {sorted(p)} vs {sorted(keys)}")
    return {k: np.concatenate([np.asarray(p[k]) for p in parts]) for k in keys}


def _unsettled_units(claims: Sequence[ClaimDef], results: Sequence[ClaimResult],
                     target: float) -> set[tuple[str, float]]:
    units: set[tuple[str, float]] = set()
    for d, r in zip(claims, results, strict=True):
        if d.missing or not r.level_status:
            continue
        for (path, sigma), p in r.replication.items():
            if sigma == 0.0 or p >= target:
                continue
            status = (r.level_status.get(sigma) if path == ALL
                      else r.per_trajectory.get(path, {}).get("status", {}).get(sigma))
            if status == DETERMINISTIC:
                continue
            paths = d.trajectories if (path == ALL or d.kind == BAND) else (path,)
            units.update((p_, sigma) for p_ in paths)
    return units


def settle(
    simulate: Simulate,
    *,
    claims: Sequence[ClaimDef],
    controllers: Sequence[str],
    trajectories: Sequence[str],
    levels: Sequence[float],
    design: SequentialDesign,
    experiment: str = "noise",
    rows: Rows | None = None,
    fous: Sequence[float] = (),
    main_fou: float = 0.0,
    progress: Callable[[dict[str, Any]], object] | None = None,
) -> SettledResult:
    """Run the sequential design (module docstring) and judge the claims.

    Parameters
    ----------
    simulate : callable
        ``simulate(batches) -> rows`` for a list of :class:`SeedBatch` (one call per round).
    claims : sequence of ClaimDef
        What is judged (:func:`~.claimcells.claim_definitions`).
    controllers : sequence of str
        Every controller of the experiment (each gets the same seeds in a unit, also those
        no claim compares: their summaries stay paired).
    trajectories, levels : sequence
        The experiment's paths and noise levels (a level 0 is one noise-free run per cell).
    design : SequentialDesign
    experiment : str
        The rows' ``experiment`` value.
    rows : mapping, optional
        The first round's rows, already simulated (``first`` realisations of every noisy
        unit, one run per noise-free cell); otherwise the first round is simulated here.
    fous, main_fou
        Passed to :func:`~.analysis.evaluate_claims` (the claims' statements only).
    progress : callable, optional
        Called with each extension round's record before it is simulated.

    Raises
    ------
    ValueError
        If ``rows`` lack a unit or have another number of realisations than ``first``.
    """
    units = {(p, float(s)): (design.first if s > 0 else 1) for p in trajectories for s in levels}
    if rows is None:
        first = [SeedBatch(tuple((c, p, s) for c in controllers), 0, n)
                 for (p, s), n in units.items()]
        rows = simulate(first)
    table = dict(rows)
    mask = table["experiment"] == experiment
    for (p, s), n in units.items():
        sel = mask & (table["trajectory"] == p) & (table["noise_std"] == s)
        have = {int(x) for x in np.asarray(table["seed"])[sel]}
        if have != set(range(n)):
            raise ValueError(f"settle: the first round's rows of {p!r} at sigma {s:g} have "
                             f"{len(have)} realisations, not {n}")
    rounds: list[dict[str, Any]] = []
    while True:
        sub = {k: np.asarray(v)[table["experiment"] == experiment] for k, v in table.items()}
        results = evaluate_claims(sub, fous=fous, main_fou=main_fou,
                                  trajectories=trajectories, experiment=experiment,
                                  claims=claims)
        results = replicate_claims(sub, claims, results, experiment=experiment,
                                   resamples=design.resamples, seed=design.seed,
                                   target=design.target)
        wanted = sorted(_unsettled_units(claims, results, design.target))
        grow = [(p, s, units[(p, s)], min(design.cap, units[(p, s)] + design.batch))
                for p, s in wanted if units[(p, s)] < design.cap]
        if not grow:
            return SettledResult(rows=table, claims=results, n=units, design=design,
                                 rounds=rounds)
        record = {"round": len(rounds) + 1, "units": grow}
        rounds.append(record)
        if progress is not None:
            progress(record)
        batches = [SeedBatch(tuple((c, p, s) for c in controllers), a, b)
                   for p, s, a, b in grow]
        new = simulate(batches)
        table = concat_rows([table, new])
        for p, s, _a, b in grow:
            units[(p, s)] = b
