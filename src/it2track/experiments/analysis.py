"""From the study's metrics table to verdicts on the paper's claims.

Nothing here is written by hand: every verdict is computed from the rows it is given, so
feeding other data (synthetic rows in the tests, another robot, another controller) changes the
verdicts accordingly. The modelling choices behind the rows are documented in ``docs/model.md``.

Claims (DESIGN.md sec. 6; :func:`~.claimcells.claim_definitions`), evaluated at every noise
level of the ``noise`` experiment:

C1  The IT2FLC beats the FLC on all four integral errors on all trajectories: for every
    trajectory and metric, the paired mean difference IT2FLC - FLC is below 0.
C2  Errors fall as the FoU grows (0.1 -> 0.2 -> 0.3): every consecutive pair of the study's
    widths has its paired difference (wider - narrower) below 0, for every trajectory and metric.
C3  The smallest straight-line ISE (over the FLC and the IT2FLCs) is "of order 0.003": within a
    factor sqrt(10) of 0.003, i.e. in the band [0.00095, 0.0095].
D1  (Not a paper claim.) The IT2FLC beats the type-1 FLC with the same dead zone *and* the
    same slope just outside it (:mod:`it2track.experiments.baselines`). The two surfaces still
    differ away from the edge (the IT2FLC's output bends up between the dead zone and about
    0.5, this one bends down), so D1 compares surface shapes, not "the footprint" as such.
D2  (Not a paper claim.) The IT2FLC beats the type-1 FLC with the same dead zone only (its
    upper membership functions, about twice as steep outside the dead zone). Where C1 holds and
    D2 does not, the gain comes from the narrower dead zone, not from the FoU.
D3  (Not a paper claim.) A type-1 lookup table of the IT2FLC's own control surface scores the
    same as the IT2FLC (within 1 % of its mean): an IT2 Sugeno controller with crisp
    consequents is a static map u(e, de), so what the footprint does, it does through the
    shape of that surface.

How cells are judged and levels settled: :mod:`.judgement`; the replication probability of a
level's status: :mod:`.replication`. The summaries (summary.csv, C3's noise range, the
single-realisation probability of the paper's ordering) live in :mod:`.summaries`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .claimcells import (
    C3_FACTOR,
    C3_TARGET,
    INTEGRALS,
    MEASURED_INTEGRALS,
    ClaimDef,
    claim_cells,
    claim_definitions,
    group_index,
)
from .judgement import (
    ALPHA,
    CONTRADICTED,
    DETERMINISTIC,
    HOLDS,
    NOT_SHOWN,
    ClaimResult,
    judge_claim,
    levels_text,
    verdict_text,
)
from .summaries import SUMMARY_METRICS, c3_sigma_range, ordering_probability, summarise

__all__ = [
    "ALPHA",
    "C3_FACTOR",
    "C3_TARGET",
    "CONTRADICTED",
    "DETERMINISTIC",
    "HOLDS",
    "INTEGRALS",
    "MEASURED_INTEGRALS",
    "NOT_SHOWN",
    "SUMMARY_METRICS",
    "ClaimResult",
    "c3_sigma_range",
    "evaluate_claims",
    "levels_text",
    "ordering_probability",
    "summarise",
    "verdict_text",
]

Rows = Mapping[str, np.ndarray]


def evaluate_claims(
    rows: Rows,
    *,
    fous: Sequence[float],
    main_fou: float,
    trajectories: Sequence[str],
    experiment: str = "noise",
    metrics: Sequence[str] = INTEGRALS,
    claims: Sequence[ClaimDef] | None = None,
) -> list[ClaimResult]:
    """Verdicts on C1, C2, C3, D1, D2 and D3 from the rows of ``experiment`` (module
    docstring), every level counted as settled (see :func:`~.replication.replicate_claims`
    for the replication probabilities).

    Controllers are found by their labels: ``"FLC"``, ``"IT2FLC FoU {w:g}"``,
    ``"T1 slope-matched {w:g}"``, ``"T1 dead-zone-matched {w:g}"`` and
    ``"T1 surface copy {w:g}"``. ``metrics`` are the four integrals compared (default on the
    true heading error; :data:`MEASURED_INTEGRALS` for the measured one); C3 uses the third
    (ISE). ``claims``: the definitions to judge (default
    :func:`~.claimcells.claim_definitions` of these arguments).
    """
    mask = rows["experiment"] == experiment
    sub = {k: v[mask] for k, v in rows.items()}
    if not mask.any():
        raise ValueError(f"no rows of experiment {experiment!r} to evaluate the claims on")
    if claims is None:
        claims = claim_definitions(fous=fous, main_fou=main_fou, trajectories=trajectories,
                                   metrics=metrics, available=sorted(set(sub["controller"])))
    groups = group_index(sub, ("experiment", "trajectory", "controller", "noise_std"))
    levels = tuple(sorted({float(s) for s in sub["noise_std"]}))
    out = []
    for claim in claims:
        if claim.missing:
            out.append(ClaimResult(id=claim.id, statement=claim.statement,
                                   criterion=claim.criterion, levels=levels, holds_at=(),
                                   verdict=f"not evaluated: {claim.missing}"))
            continue
        cells = claim_cells(sub, claim, experiment=experiment, groups=groups, levels=levels)
        out.append(judge_claim(claim, cells, levels))
    return out
