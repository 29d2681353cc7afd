"""Seeds by need: a sequential design that adds noise realisations where a verdict needs them.

Every (controller, path, sigma) *cell* of an experiment starts with ``first`` realisations
(seed indices ``0 .. first-1``). After each round, every claim is judged
(:func:`~.analysis.evaluate_claims`) and the replication probability of every level -- claim x
path (and all paths together) x sigma -- is estimated by the bootstrap
(:mod:`.replication`). A level is *settled* when its replication probability reaches
``target``. The cells behind an unsettled level -- the claim's controllers on its path (or on
every path of the claim, for a level over all paths) at its sigma -- get realisations up to
``batch`` more than the level has, at most ``cap``; seed indices continue where each cell
stopped, so compared controllers keep sharing their seeds (a comparison uses the seeds both
have). Rounds continue until every level is settled or every cell behind an unsettled one is
at the cap. Levels still unsettled at the cap are reported as such, never as a verdict.
Controllers that no claim compares keep the first round's realisations.

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


#: Most bootstrap resamples (memory: the draws are (resamples, seeds) arrays).
MAX_RESAMPLES = 20_000


def _int(v: Any, key: str, least: int, most: int | None = None) -> None:
    if isinstance(v, bool) or not isinstance(v, int) or v < least or (
            most is not None and v > most):
        bound = f">= {least}" if most is None else f"in [{least}, {most}]"
        raise ValueError(f"verdicts {key}={v!r} must be an integer {bound}")


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
        Bootstrap resamples per estimate (100 to 20 000).
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
        _int(self.resamples, "resamples", 100, MAX_RESAMPLES)
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
    """Realisations to simulate: the seed indices from ``start`` to ``stop - 1`` of every
    ``(controller, path, sigma)`` cell of ``cells``."""

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
    n : dict of (str, str, float) -> int
        Realisations per (controller, path, sigma) cell at the end.
    rounds : list of dict
        Per extension round: ``{"round": k, "units": [(path, sigma, n_before, n_after,
        controllers), ...]}``.
    design : SequentialDesign
    """

    rows: dict[str, np.ndarray]
    claims: list[ClaimResult]
    n: dict[tuple[str, str, float], int]
    design: SequentialDesign
    rounds: list[dict[str, Any]] = field(default_factory=list)


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


def _wanted(claims: Sequence[ClaimDef], results: Sequence[ClaimResult],
            n: Mapping[tuple[str, str, float], int], design: SequentialDesign
            ) -> dict[tuple[str, str, float], int]:
    """The realisations each cell behind an unsettled level should reach (only cells below
    it)."""
    want: dict[tuple[str, str, float], int] = {}
    for d, r in zip(claims, results, strict=True):
        if d.missing or not r.level_status:
            continue
        for (path, sigma), p in r.replication.items():
            if sigma == 0.0 or p >= design.target:
                continue
            status = (r.level_status.get(sigma) if path == ALL
                      else r.per_trajectory.get(path, {}).get("status", {}).get(sigma))
            if status == DETERMINISTIC:
                continue
            paths = d.trajectories if (path == ALL or d.kind == BAND) else (path,)
            cells = [(c, p_, sigma) for c in d.controllers for p_ in paths]
            have = min(n[cell] for cell in cells)
            if have >= design.cap:
                continue
            target = min(design.cap, have + design.batch)
            for cell in cells:
                if n[cell] < target:
                    want[cell] = max(want.get(cell, 0), target)
    return want


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
        Every controller of the experiment (the first round simulates them all; later rounds
        only the claims' controllers).
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
        If ``rows`` lack a cell or have another number of realisations than ``first``.
    """
    units = {(p, float(s)): (design.first if s > 0 else 1) for p in trajectories for s in levels}
    n = {(c, p, s): k for (p, s), k in units.items() for c in controllers}
    if rows is None:
        first = [SeedBatch(tuple((c, p, s) for c in controllers), 0, k)
                 for (p, s), k in units.items()]
        rows = simulate(first)
    table = dict(rows)
    mask = table["experiment"] == experiment
    for (p, s), k in units.items():
        sel = mask & (table["trajectory"] == p) & (table["noise_std"] == s)
        for c in controllers:
            have = {int(x) for x in np.asarray(table["seed"])[sel & (table["controller"] == c)]}
            if have != set(range(k)):
                raise ValueError(f"settle: the first round's rows of {c!r} on {p!r} at sigma "
                                 f"{s:g} have {len(have)} realisations, not {k}")
    rounds: list[dict[str, Any]] = []
    while True:
        sub = {k: np.asarray(v)[table["experiment"] == experiment] for k, v in table.items()}
        results = evaluate_claims(sub, fous=fous, main_fou=main_fou,
                                  trajectories=trajectories, experiment=experiment,
                                  claims=claims)
        results = replicate_claims(sub, claims, results, experiment=experiment,
                                   resamples=design.resamples, seed=design.seed,
                                   target=design.target)
        want = _wanted(claims, results, n, design)
        if not want:
            return SettledResult(rows=table, claims=results, n=n, design=design,
                                 rounds=rounds)
        groups: dict[tuple[str, float, int, int], list[str]] = {}
        for (c, p, s), b in sorted(want.items(), key=lambda kv: (kv[0][1], kv[0][2])):
            groups.setdefault((p, s, n[(c, p, s)], b), []).append(c)
        order = {c: i for i, c in enumerate(controllers)}
        batches = [SeedBatch(tuple((c, p, s) for c in sorted(cs, key=order.__getitem__)), a, b)
                   for (p, s, a, b), cs in groups.items()]
        record = {"round": len(rounds) + 1,
                  "units": [(b.cells[0][1], b.cells[0][2], b.start, b.stop,
                             tuple(c for c, _, _ in b.cells)) for b in batches]}
        rounds.append(record)
        if progress is not None:
            progress(record)
        new = simulate(batches)
        table = concat_rows([table, new])
        for cell, b in want.items():
            n[cell] = b
