"""What each claim compares: the claims as data, and their cells cut from a metrics table.

A claim (:class:`ClaimDef`) names the controllers it compares, on which paths and metrics,
and the side of a statistic it claims. Its evidence at a noise level is a family of *cells*
(:class:`CellData`): per noise level, path, metric and compared pair, the per-seed values
the judgement needs, aligned by seed. Three kinds of cell:

``below``
    ``values`` holds the two compared controllers' metrics (rows ``a``, ``b``); the claim is
    that the paired difference ``a - b`` has a mean below 0 (C1, C2, D1, D2).
``band``
    ``values`` holds the candidates' metrics; the claim is that the candidate with the
    smallest mean lies inside ``band`` (C3: the smallest straight-line ISE is "of order
    0.003").
``equal``
    ``values`` holds ``a`` and ``b``; the claim is that ``a - b`` lies inside
    ``band = [-delta, delta]``, ``delta`` a fraction of ``b``'s mean (D3: a type-1 copy of the
    IT2FLC's control surface scores the same as the IT2FLC).

Both the judgement of the observed data (:func:`~.analysis.evaluate_claims`) and its
bootstrap replicates (:mod:`.replication`) are computed from the same cells, so they cannot
disagree about what a claim compares.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "BAND",
    "BELOW",
    "C3_FACTOR",
    "C3_TARGET",
    "EQUAL",
    "EQUAL_MARGIN",
    "INTEGRALS",
    "MEASURED_INTEGRALS",
    "CellData",
    "ClaimDef",
    "claim_cells",
    "claim_definitions",
    "group_index",
]

INTEGRALS = ("IAE", "ITAE", "ISE", "ITSE")
#: The same integrals on the measured heading error (the open choice "integrals on the true
#: or the measured heading", docs/model.md).
MEASURED_INTEGRALS = tuple(f"{m}_meas" for m in INTEGRALS)
C3_TARGET = 0.003
C3_FACTOR = math.sqrt(10.0)
#: D3's margin: the copy "scores the same" when the paired difference lies within this
#: fraction of the IT2FLC's mean.
EQUAL_MARGIN = 0.01

BELOW, BAND, EQUAL = "below", "band", "equal"

Rows = Mapping[str, np.ndarray]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ClaimDef:
    """One claim as data.

    Attributes
    ----------
    id, statement, criterion : str
    kind : str
        :data:`BELOW`, :data:`BAND` or :data:`EQUAL` (module docstring).
    pairs : tuple of (str, str)
        ``below``/``equal``: the compared controllers ``(a, b)``, judged on ``a - b``.
    candidates : tuple of str
        ``band``: the controllers whose smallest mean is judged.
    trajectories : tuple of str
        The paths the claim covers.
    metrics : tuple of str
        The metrics compared (``band``: one).
    band : tuple of float
        ``band``: the claimed interval.
    margin : float
        ``equal``: the relative margin (``delta = margin * |mean(b)|``).
    missing : str
        Why the claim cannot be evaluated on these controllers (empty: it can).
    """

    id: str
    statement: str
    criterion: str
    kind: str
    pairs: tuple[tuple[str, str], ...] = ()
    candidates: tuple[str, ...] = ()
    trajectories: tuple[str, ...] = ()
    metrics: tuple[str, ...] = ()
    band: tuple[float, float] = (0.0, 0.0)
    margin: float = 0.0
    missing: str = ""

    @property
    def controllers(self) -> tuple[str, ...]:
        """Every controller label the claim compares, in first-use order."""
        labels = [x for pair in self.pairs for x in pair] + list(self.candidates)
        return tuple(dict.fromkeys(labels))


@dataclass(frozen=True, eq=False)
class CellData:
    """The per-seed values of one cell (see the module docstring).

    Attributes
    ----------
    sigma : float
    trajectory, metric, comparison : str
    kind : str
    values : ndarray, shape (k, n)
        One row per controller of ``labels``, columns in seed order.
    labels : tuple of str
    band : tuple of float
        ``band``/``equal``: the claimed interval of the statistic.
    """

    sigma: float
    trajectory: str
    metric: str
    comparison: str
    kind: str
    values: FloatArray
    labels: tuple[str, ...]
    band: tuple[float, float] = (0.0, 0.0)

    @property
    def n(self) -> int:
        return int(self.values.shape[1])

    def sample(self) -> FloatArray:
        """The values the cell's statistic is the mean of: ``a - b`` (``below``, ``equal``)
        or the candidate with the smallest mean (``band``; the first of equal means)."""
        if self.kind == BAND:
            return self.values[self.best]
        return self.values[0] - self.values[1]

    @property
    def best(self) -> int:
        """``band``: row of the candidate with the smallest mean."""
        means = [float(np.mean(v)) for v in self.values]
        return int(min(range(len(means)), key=lambda i: (means[i], i)))


def group_index(rows: Rows, keys: Sequence[str]) -> dict[tuple[Any, ...], np.ndarray]:
    """Row indices of each distinct combination of ``keys`` (in first-seen order), each sorted
    by seed so that groups sharing seeds align for paired comparisons (rows of one seed keep
    their order). A noise-free group (``noise_std == 0``) keeps only its lowest seed: every
    seed is the same run."""
    n = len(rows["seed"])
    if n == 0:
        return {}
    codes = []
    uniques = []
    for k in keys:
        u, inv = np.unique(np.asarray(rows[k]), return_inverse=True)
        uniques.append(u)
        codes.append(inv.reshape(-1))
    combined = np.zeros(n, dtype=np.int64)
    for inv, u in zip(codes, uniques, strict=True):
        combined = combined * len(u) + inv
    seed = np.asarray(rows["seed"])
    order = np.lexsort((np.arange(n), seed, combined))
    sorted_key = combined[order]
    starts = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1]])
    ends = np.r_[starts[1:], n]
    first_row = np.minimum.reduceat(order, starts)
    sigma = np.asarray(rows["noise_std"])
    cols = [np.asarray(rows[k]) for k in keys]
    out = {}
    for g in np.argsort(first_row, kind="stable"):
        idx = order[starts[g]:ends[g]].astype(np.intp)
        if sigma[idx[0]] == 0.0:
            idx = idx[:1]
        i0 = int(first_row[g])
        out[tuple(c[i0] for c in cols)] = idx
    return out


def _common(seed: np.ndarray, groups: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Each group's rows restricted to the seeds every group has (groups are sorted by seed,
    one row per seed): compared controllers are paired on their common realisations."""
    seeds = [np.asarray(seed)[g] for g in groups]
    if all(np.array_equal(seeds[0], x) for x in seeds[1:]):
        return list(groups)
    common = seeds[0]
    for x in seeds[1:]:
        common = np.intersect1d(common, x)
    return [g[np.isin(x, common)] for g, x in zip(groups, seeds, strict=True)]


def it2_label(w: float) -> str:
    return f"IT2FLC FoU {w:g}"


def claim_definitions(*, fous: Sequence[float], main_fou: float, trajectories: Sequence[str],
                      metrics: Sequence[str] = INTEGRALS,
                      available: Sequence[str] | None = None) -> list[ClaimDef]:
    """The study's claims C1, C2, C3, D1, D2 and D3 on these controllers.

    Controllers are found by their labels: ``"FLC"``, ``"IT2FLC FoU {w:g}"``,
    ``"T1 slope-matched {w:g}"``, ``"T1 dead-zone-matched {w:g}"`` and
    ``"T1 surface copy {w:g}"``. A claim whose baseline is not in ``available`` (``None``:
    every label is) gets ``missing`` set. ``metrics`` are the four integrals compared; C3
    uses the third (ISE).
    """
    if len(metrics) != len(INTEGRALS):
        raise ValueError(f"metrics={tuple(metrics)!r} must name the four integrals "
                         "(IAE, ITAE, ISE, ITSE forms)")
    have = None if available is None else set(available)
    trajectories = tuple(trajectories)
    metrics = tuple(metrics)
    it2 = {w: it2_label(w) for w in fous}
    main = it2[main_fou]
    heading = "measured" if metrics[0].endswith("_meas") else "true"
    names = ", ".join(metrics)
    out = [ClaimDef(
        id="C1",
        statement=(f"The IT2FLC (FoU {main_fou:g}) beats the FLC on IAE, ITAE, ISE and ITSE on "
                   f"all {len(trajectories)} trajectories"),
        criterion=(f"for every trajectory and metric ({names}, on the {heading} heading "
                   "error), the 95 % interval of the paired mean difference IT2FLC - FLC (same "
                   "noise realisations) lies below 0"),
        kind=BELOW, pairs=((main, "FLC"),), trajectories=trajectories, metrics=metrics,
    )]
    ordered = sorted(fous)
    pairs = tuple((it2[b], it2[a]) for a, b in itertools.pairwise(ordered))
    out.append(ClaimDef(
        id="C2",
        statement="The integral errors fall as the FoU grows " + " -> ".join(
            f"{w:g}" for w in ordered),
        criterion=("for every trajectory, metric and consecutive pair of widths, the 95 % "
                   "interval of the paired difference (wider - narrower) lies below 0"),
        kind=BELOW, pairs=pairs, trajectories=trajectories, metrics=metrics,
        missing="" if pairs else "needs at least two FoU widths",
    ))
    lo, hi = C3_TARGET / C3_FACTOR, C3_TARGET * C3_FACTOR
    ise = metrics[2]
    out.append(ClaimDef(
        id="C3",
        statement="The smallest straight-line ISE is of order 0.003",
        criterion=(f"the 95 % interval of the smallest mean straight-line {ise} over the FLC "
                   f"and the IT2FLCs lies inside [{lo:.2g}, {hi:.2g}] (within a factor "
                   "sqrt(10) of 0.003); it contradicts the claim when the test of lying "
                   "outside the band (below or above) rejects"),
        kind=BAND, candidates=("FLC", *it2.values()), trajectories=("straight",),
        metrics=(ise,), band=(lo, hi),
        missing="" if "straight" in trajectories else "the study has no straight trajectory",
    ))
    for id_, label, what in (
        ("D1", f"T1 slope-matched {main_fou:g}",
         "the same dead zone and the same slope just outside it"),
        ("D2", f"T1 dead-zone-matched {main_fou:g}", "the same dead zone only"),
    ):
        out.append(ClaimDef(
            id=id_,
            statement=(f"(beyond the paper) The IT2FLC (FoU {main_fou:g}) beats the type-1 FLC "
                       f"with {what}"),
            criterion=f"as C1, against the type-1 FLC with {what} instead of the FLC",
            kind=BELOW, pairs=((main, label),), trajectories=trajectories, metrics=metrics,
            missing="" if have is None or label in have
            else f"the study has no {label!r} baseline",
        ))
    copy = f"T1 surface copy {main_fou:g}"
    out.append(ClaimDef(
        id="D3",
        statement=(f"(beyond the paper) A type-1 lookup table of the IT2FLC's (FoU "
                   f"{main_fou:g}) own control surface scores the same as the IT2FLC"),
        criterion=("for every trajectory and metric, the 95 % interval of the paired "
                   f"difference copy - IT2FLC lies within +-{EQUAL_MARGIN:.0%} of the IT2FLC's "
                   "mean (an equivalence test); it contradicts the claim when the test of "
                   "lying outside that margin rejects"),
        kind=EQUAL, pairs=((copy, main),), trajectories=trajectories, metrics=metrics,
        margin=EQUAL_MARGIN,
        missing="" if have is None or copy in have else f"the study has no {copy!r} baseline",
    ))
    return out


def claim_cells(rows: Rows, claim: ClaimDef, *, experiment: str,
                groups: dict[tuple[Any, ...], np.ndarray] | None = None,
                levels: Sequence[float] | None = None) -> list[CellData]:
    """The cells of ``claim`` at every noise level of ``experiment``'s rows (ordered level,
    trajectory, metric, pair as the evidence tables list them).

    Compared controllers are paired on the seeds they share (a controller may have more
    realisations than another: seeds by need, :mod:`.sequential`).

    Raises
    ------
    ValueError
        If a compared pair lacks rows at some level and path, or shares no seed there (a
        paired comparison needs common random numbers).
    """
    if groups is None:
        groups = group_index(rows, ("experiment", "trajectory", "controller", "noise_std"))
    if levels is None:
        mask = rows["experiment"] == experiment
        levels = tuple(sorted({float(s) for s in rows["noise_std"][mask]}))
    cells: list[CellData] = []
    if claim.kind == BAND:
        metric = claim.metrics[0]
        traj = claim.trajectories[0]
        for sigma in levels:
            found = [(label, groups.get((experiment, traj, label, sigma)))
                     for label in claim.candidates]
            have = [(label, idx) for label, idx in found if idx is not None]
            if not have:
                raise ValueError(f"no {traj}-line {metric} at sigma {sigma:g}")
            have = list(zip([lb for lb, _ in have],
                            _common(rows["seed"], [idx for _, idx in have]), strict=True))
            if not have[0][1].size:
                raise ValueError(f"{claim.id}: the candidates share no seed at sigma {sigma:g}")
            cells.append(CellData(
                sigma=sigma, trajectory=traj, metric=metric,
                comparison=f"smallest mean of {len(have)} vs band", kind=BAND,
                values=np.stack([rows[metric][idx] for _, idx in have]),
                labels=tuple(label for label, _ in have), band=claim.band))
        return cells
    for sigma in levels:
        for traj in claim.trajectories:
            for metric in claim.metrics:
                for a, b in claim.pairs:
                    ia = groups.get((experiment, traj, a, sigma))
                    ib = groups.get((experiment, traj, b, sigma))
                    if ia is not None and ib is not None:
                        ia, ib = _common(rows["seed"], [ia, ib])
                    if ia is None or ib is None or not ia.size:
                        raise ValueError(
                            f"no paired data for {a!r} vs {b!r} on {traj!r} at sigma "
                            f"{sigma:g}")
                    values = np.stack([rows[metric][ia], rows[metric][ib]])
                    band = (0.0, 0.0)
                    if claim.kind == EQUAL:
                        delta = claim.margin * abs(float(np.mean(values[1])))
                        band = (-delta, delta)
                    cells.append(CellData(
                        sigma=sigma, trajectory=traj, metric=metric, comparison=f"{a} - {b}",
                        kind=claim.kind, values=values, labels=(a, b), band=band))
    return cells
