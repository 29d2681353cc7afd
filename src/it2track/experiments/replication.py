"""Replication probability of a claim's status at each noise level (bootstrap).

A level's status (holds / contradicted / not shown, :mod:`.judgement`) is computed from a finite
set of noise realisations; another set of the same size could give another status. The
*replication probability* of a level is the probability that an independent seed set of the
same size gives the same status. It is estimated here by resampling the seeds:

1. Draw ``B`` replicate seed sets for every cell, of the cell's own size ``n``, by the
   *double* bootstrap: resample the seed positions with replacement (a plausible population
   the data could have come from), then resample those (a replicate seed set drawn from that
   population). The same draws serve every cell with the same ``n``: a noise realisation
   stays paired across controllers, metrics, paths and levels, as the common random numbers
   pair them in the data.
2. Re-judge the *whole* claim on each replicate, exactly as the data are judged: every cell's
   95 % interval and one-sided p-value, the Holm-Bonferroni step-down over all the claim's
   noisy cells (so a level's status depends on the other levels' p-values as in the data),
   then every level's status, per path and over all paths.
3. The replication probability of a level is the fraction of replicates whose status equals
   the observed one.

Why two stages: a replicate's mean differs from the observed one by the error of the observed
mean *and* the replicate's own error (about twice the variance; the predictive replication
probability of Killeen, 2005, or Goodman, 1992, for a z statistic ``Phi((|z| - z_c) /
sqrt 2)``). The single, plug-in bootstrap (``predictive=False``: Shao and Chow's
"reproducibility probability" ``Phi(|z| - z_c)``) takes the observed effect for the true one and
overstates how often a fresh seed set agrees -- two independent runs of the study disagreed on
levels it called settled. For one ``below`` cell with normal data the predictive estimate
approaches ``P(N(t, 2) < -t_(0.975, n-1))`` (``t`` the observed t statistic) and the plug-in one
the non-central t ``P(T' < -t_(0.975, n-1))`` (the tests compare both with scipy). A noise-free
level is one deterministic run: every seed set gives it again (probability 1). The Monte Carlo
error of the estimate is ``sqrt(p (1 - p) / B)`` (0.007 at p = 0.95 with ``B = 1000``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import special as _sc

from .claimcells import BAND, BELOW, CellData, ClaimDef
from .judgement import ALL, ALPHA, CONTRADICTED, DETERMINISTIC, HOLDS, NOT_SHOWN, ClaimResult

__all__ = [
    "STATUS_CODES",
    "Resampler",
    "cell_statistics",
    "judge_replicates",
    "replication_probabilities",
    "uniform_resampler",
]

#: Status -> integer code in :func:`judge_replicates`' output.
STATUS_CODES = {HOLDS: 0, CONTRADICTED: 1, NOT_SHOWN: 2}

FloatArray = NDArray[np.float64]
#: ``resampler(n)`` -> seed positions, shape ``(B, n)``, ints in ``[0, n)``.
Resampler = Callable[[int], NDArray[np.intp]]


def _uniforms(resamples: int, seed: tuple[int, ...], width: int) -> FloatArray:
    """``(resamples, width)`` uniforms drawn in column blocks of 64 from one stream: the first
    ``m`` columns are the same whatever the width."""
    blocks = -(-width // 64)
    rng = np.random.default_rng(seed)
    return rng.random((blocks, resamples, 64)).transpose(1, 0, 2).reshape(resamples, -1)


def uniform_resampler(resamples: int, seed: int, *, predictive: bool = True) -> Resampler:
    """Bootstrap draws sharing streams of uniforms, so cells with the same number of seeds get
    the same resample (their pairing is kept), whatever order the cells are asked for in.

    ``predictive`` (default): the *double* bootstrap of the predictive replication
    probability (module docstring) -- a plausible population is resampled from the seeds
    (positions ``floor(U1[:, :n] n)``), then a replicate seed set from it (positions
    ``p1[floor(U2[:, :n] n)]``), so a replicate's mean spreads by about twice the variance of
    the observed one: the uncertainty of the observed effect and of the replicate. Without it,
    the plug-in bootstrap: one resample, positions ``floor(U1[:, :n] n)``.

    Raises
    ------
    ValueError
        Unless ``resamples >= 1`` and ``seed >= 0`` are integers.
    """
    for key, v, least in (("resamples", resamples, 1), ("seed", seed, 0)):
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < least:
            raise ValueError(f"replication {key}={v!r} must be an integer >= {least}")
    rng_seed = int(seed)
    cache: dict[int, FloatArray] = {}

    def uniforms(stream: int, n: int) -> FloatArray:
        u = cache.get(stream)
        if u is None or u.shape[1] < n:
            u = _uniforms(resamples, (rng_seed, stream), max(n, 0 if u is None else u.shape[1]))
            cache[stream] = u
        return u[:, :n]

    def draw(n: int) -> NDArray[np.intp]:
        first = np.minimum((uniforms(0, n) * n).astype(np.intp), n - 1)
        if not predictive:
            return first
        second = np.minimum((uniforms(1, n) * n).astype(np.intp), n - 1)
        return np.take_along_axis(first, second, axis=1)

    return draw


@dataclass(frozen=True)
class _Stats:
    """Per-cell statistics over replicates: arrays of shape (B, cells)."""

    mean: FloatArray
    sd: FloatArray
    n: NDArray[np.int64]


def _counts(idx: NDArray[np.intp], n: int) -> FloatArray:
    """Multinomial counts (B, n) of the resampled positions."""
    b = idx.shape[0]
    flat = (idx + n * np.arange(b)[:, None]).ravel()
    return np.bincount(flat, minlength=b * n).reshape(b, n).astype(np.float64)


def cell_statistics(cells: Sequence[CellData], resampler: Resampler | None) -> _Stats:
    """Mean and standard deviation (``ddof = 1``) of every cell's statistic on every resample
    (``resampler=None``: the data themselves, one "resample"). A ``band`` cell's statistic is
    its candidate with the smallest resampled mean (the first of equal means), as in the
    data."""
    n_cells = len(cells)
    ns = np.array([c.n for c in cells], dtype=np.int64)
    b = 1
    weights: dict[int, FloatArray] = {}
    for n in sorted(set(ns.tolist())):
        if resampler is None:
            weights[n] = np.ones((1, n))
        else:
            idx = resampler(n)
            if idx.ndim != 2 or idx.shape[1] != n:
                raise ValueError(f"resampler({n}) must give shape (B, {n}), got {idx.shape}")
            weights[n] = _counts(idx, n)
    if weights:
        b = next(iter(weights.values())).shape[0]
    mean = np.zeros((b, n_cells))
    sd = np.zeros((b, n_cells))
    for n, w in weights.items():
        mine = [i for i, c in enumerate(cells) if c.n == n]
        blocks = [cells[i].values if cells[i].kind == BAND
                  else (cells[i].values[0] - cells[i].values[1])[None, :] for i in mine]
        x = np.concatenate(blocks, axis=0)  # (K, n)
        centre = x.mean(axis=1)
        xc = x - centre[:, None]
        m = w @ xc.T / n  # (B, K): resampled mean minus the centre
        ss = w @ (xc * xc).T - n * m * m
        var = np.maximum(ss, 0.0) / (n - 1) if n > 1 else np.zeros_like(ss)
        mu = m + centre[None, :]
        sizes = np.array([blk.shape[0] for blk in blocks])
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        single = sizes == 1
        cols, at = np.asarray(mine)[single], starts[single]
        mean[:, cols], sd[:, cols] = mu[:, at], np.sqrt(var[:, at])
        for i, k, rows in zip(np.asarray(mine)[~single], starts[~single], sizes[~single],
                              strict=True):
            # band: the candidate with the smallest mean on each resample
            best = np.argmin(mu[:, k:k + rows], axis=1)
            pick = np.arange(b)
            mean[:, i] = mu[:, k:k + rows][pick, best]
            sd[:, i] = np.sqrt(var[:, k:k + rows][pick, best])
    return _Stats(mean, sd, ns)


def _tail(excess: FloatArray, se: FloatArray, dof: FloatArray, q: FloatArray) -> FloatArray:
    """One-sided p of "the mean exceeds by ``excess``" (``t_tail``'s rules at zero spread),
    computed only where it can be at most :data:`ALPHA` -- where the t statistic reaches the
    95 % intervals' quantile; elsewhere 1. Any p-value above ``ALPHA`` can neither contradict
    nor change the Holm-adjusted p-value of a cell with a smaller p-value (those come first
    in the step-down), so every decision is the exact p-values' (module docstring). ``q``:
    the ``1 - ALPHA`` quantile of Student's t on ``dof`` degrees of freedom (broadcast)."""
    out = np.ones_like(excess)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = excess / se
    zero = se <= 0.0
    need = ~zero & (t >= q * (1.0 - 1e-12))
    if need.any():
        out[need] = _sc.stdtr(np.broadcast_to(dof, t.shape)[need], -t[need])
    out[zero & (excess > 0.0)] = 0.0
    return out


def _holm(p: FloatArray) -> FloatArray:
    """Holm-Bonferroni adjusted p-values along axis 1 (:func:`~.stats.holm_adjust` per row)."""
    m = p.shape[1]
    if m == 0:
        return p.copy()
    order = np.argsort(p, axis=1, kind="stable")
    scaled = np.minimum(1.0, (m - np.arange(m))[None, :] * np.take_along_axis(p, order, 1))
    out = np.empty_like(p)
    np.put_along_axis(out, order, np.maximum.accumulate(scaled, axis=1), axis=1)
    return out


def judge_replicates(cells: Sequence[CellData], levels: Sequence[tuple[str, float]],
                     resampler: Resampler | None) -> NDArray[np.int8]:
    """Status codes (:data:`STATUS_CODES`) of each ``(path, sigma)`` level on every resample:
    shape ``(B, len(levels))``. ``path`` is a trajectory or ``"all"`` (every cell at
    ``sigma``). The cells are one claim's whole family (every level and path), judged as
    :mod:`.judgement` judges the data; noise-free levels are not asked for here."""
    st = cell_statistics(cells, resampler)
    b = st.mean.shape[0]
    noisy = np.array([c.sigma != 0.0 for c in cells], dtype=bool)
    testable = noisy & (st.n >= 2)
    dof = np.maximum(st.n - 1, 1).astype(np.float64)[None, :]
    q = _sc.stdtrit(dof, 1.0 - ALPHA)  # the 95 % intervals' quantile (one per cell)
    se = st.sd / np.sqrt(st.n)[None, :]
    half = q * se
    mu = st.mean
    below = np.flatnonzero([c.kind == BELOW for c in cells])
    inside = np.flatnonzero([c.kind != BELOW for c in cells])
    support = np.zeros(mu.shape, dtype=bool)
    p = np.ones(mu.shape)
    if below.size:
        m, h, e = mu[:, below], half[:, below], se[:, below]
        d, qq = np.broadcast_to(dof[:, below], m.shape), np.broadcast_to(q[:, below], m.shape)
        support[:, below] = m + h < 0.0
        p[:, below] = _tail(m, e, d, qq)
    if inside.size:
        m, h, e = mu[:, inside], half[:, inside], se[:, inside]
        d, qq = np.broadcast_to(dof[:, inside], m.shape), np.broadcast_to(q[:, inside], m.shape)
        lo = np.array([cells[int(i)].band[0] for i in inside])[None, :]
        hi = np.array([cells[int(i)].band[1] for i in inside])[None, :]
        support[:, inside] = (m - h >= lo) & (m + h <= hi)
        p[:, inside] = np.minimum(1.0, np.minimum(_tail(lo - m, e, d, qq),
                                                  _tail(m - hi, e, d, qq)))
    support &= testable[None, :]
    family = np.flatnonzero(testable)
    contradicts = np.zeros_like(support)
    if family.size:
        adj = _holm(p[:, family])
        contradicts[:, family] = ~support[:, family] & (adj <= ALPHA)
    out = np.empty((b, len(levels)), dtype=np.int8)
    sigma = np.array([c.sigma for c in cells])
    traj = np.array([c.trajectory for c in cells], dtype=object)
    for j, (path, s) in enumerate(levels):
        mine = np.flatnonzero((sigma == s) & ((traj == path) if path != ALL else True))
        if not mine.size:
            raise ValueError(f"no cells at {path} sigma {s:g}")
        holds = support[:, mine].all(axis=1)
        contra = contradicts[:, mine].any(axis=1)
        out[:, j] = np.where(holds, STATUS_CODES[HOLDS],
                             np.where(contra, STATUS_CODES[CONTRADICTED],
                                      STATUS_CODES[NOT_SHOWN]))
    return out


def observed_levels(claim: ClaimDef, result: ClaimResult) -> dict[tuple[str, float], str]:
    """Every ``(path, sigma)`` level of a judged claim with its observed status: over all
    paths (``"all"``) and per trajectory (``band`` claims: all only)."""
    out = {(ALL, s): st for s, st in result.level_status.items()}
    if claim.kind != BAND:
        for traj, v in result.per_trajectory.items():
            out.update({(traj, s): st for s, st in v["status"].items()})
    return out


def replication_probabilities(claim: ClaimDef, cells: Sequence[CellData],
                              result: ClaimResult, resampler: Resampler
                              ) -> dict[tuple[str, float], float]:
    """Replication probability of every level of a judged claim (module docstring), by
    ``(path, sigma)``; 1 for a noise-free level."""
    observed = observed_levels(claim, result)
    noisy = [k for k, st in observed.items() if st != DETERMINISTIC]
    out = {k: 1.0 for k, st in observed.items() if st == DETERMINISTIC}
    if noisy:
        codes = judge_replicates(cells, noisy, resampler)
        want = np.array([STATUS_CODES[observed[k]] for k in noisy], dtype=np.int8)
        same = (codes == want[None, :]).mean(axis=0)
        out.update({k: float(v) for k, v in zip(noisy, same, strict=True)})
    return out


def replicate_claims(rows: Mapping[str, np.ndarray], claims: Sequence[ClaimDef],
                     results: Sequence[ClaimResult], *, experiment: str, resamples: int,
                     seed: int, target: float) -> list[ClaimResult]:
    """``results`` (from :func:`~.analysis.evaluate_claims` on the same ``rows`` and
    ``claims``) with the replication probability of every level, their verdicts restated over
    the settled levels (:func:`~.judgement.with_replication`)."""
    from .claimcells import claim_cells, group_index
    from .judgement import with_replication

    if not 0.0 < target <= 1.0:
        raise ValueError(f"replication target={target!r} must lie in (0, 1]")
    mask = rows["experiment"] == experiment
    sub = {k: v[mask] for k, v in rows.items()}
    groups = group_index(sub, ("experiment", "trajectory", "controller", "noise_std"))
    levels = tuple(sorted({float(s) for s in sub["noise_std"]}))
    resampler = uniform_resampler(resamples, seed)
    out = []
    for claim, result in zip(claims, results, strict=True):
        if claim.missing or not result.level_status:
            out.append(result)
            continue
        cells = claim_cells(sub, claim, experiment=experiment, groups=groups, levels=levels)
        probs = replication_probabilities(claim, cells, result, resampler)
        out.append(with_replication(result, probs, target))
    return out
