"""Figures about the paper's claims: paired win rates against the FLC.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from ...experiments.analysis import INTEGRALS
from ...experiments.study import StudyResult
from ..identity import _Ctrl, _info, _num, _order_key, _Summary

# ---------------------------------------------------------------------------------------------
# Win rates
# ---------------------------------------------------------------------------------------------


def _fig_win_rates(result: StudyResult, summ: _Summary, ctrls: Mapping[str, _Ctrl],
                   trajs: Sequence[str] | None = None) -> Figure:
    cfg = result.config
    trajs = list(cfg.trajectories if trajs is None else trajs)
    sigma = summ.levels("paper")[0] if summ.levels("paper") else cfg.noise_std
    labels = sorted((lb for lb in summ.controllers("paper") if lb != "FLC"),
                    key=lambda lb: _order_key(_info(ctrls, lb)))
    n = len(trajs)
    fig = Figure(figsize=(max(3.3 * n + 2.5, 6.0), 0.5 * max(len(labels), 1) + 1.9),
                 layout="constrained")
    ax = np.asarray(fig.subplots(1, n, squeeze=False, sharey=True))[0]
    image = None
    any_ties = False
    for j, traj in enumerate(trajs):
        a = ax[j]
        m = np.full((len(labels), len(INTEGRALS)), np.nan)
        ties = np.zeros_like(m)
        for i, label in enumerate(labels):
            for k, metric in enumerate(INTEGRALS):
                r = summ.get("paper", traj, label, sigma, metric)
                if r is not None:
                    m[i, k] = _num(r["win_rate"])
                    t = _num(r.get("ties"))
                    ties[i, k] = t if math.isfinite(t) else 0.0
        image = a.imshow(m, cmap="RdBu", vmin=0.0, vmax=1.0, aspect="auto")
        for i in range(m.shape[0]):
            for k in range(m.shape[1]):
                if not math.isfinite(m[i, k]):
                    continue
                color = "white" if abs(m[i, k] - 0.5) > 0.3 else "black"
                if ties[i, k] > 0:  # a tie is no loss: say how much of the 0.5 is ties
                    any_ties = True
                    a.text(k, i - 0.12, f"{m[i, k]:.2f}", ha="center", va="center",
                           fontsize=7.5, color=color)
                    a.text(k, i + 0.22, f"ties {ties[i, k]:.0%}", ha="center", va="center",
                           fontsize=6, color=color)
                else:
                    a.text(k, i, f"{m[i, k]:.2f}", ha="center", va="center", fontsize=7.5,
                           color=color)
        a.set_xticks(range(len(INTEGRALS)), INTEGRALS)
        a.set_yticks(range(len(labels)), labels)
        a.tick_params(axis="y", labelleft=(j == 0))
        a.grid(False)
        a.set_title(traj)
    if image is not None:
        cb = fig.colorbar(image, ax=ax.tolist(), shrink=0.9, pad=0.02)
        cb.set_label("win rate vs FLC (ties count ½)")
        cb.set_ticks([0.0, 0.25, 0.5, 0.75, 1.0],
                     labels=["0 worse", "0.25", "0.5 no diff.", "0.75", "1 better"])
    tie_note = "; 'ties': share of exact ties" if any_ties else ""
    fig.suptitle(f"Paired win rate vs the FLC at σ = {sigma:g} rad: P(smaller error than the "
                 f"FLC) + ½ P(equal error), over the noise realisations (0.5: no difference; "
                 f"blue: better{tie_note})", fontsize=10)
    return fig
