"""The held-out verdict on the optima (:func:`_verdict`) and what the optimisation returns,
:class:`OptimizeResult` (JSON and Markdown).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...tracking import METRIC_NAMES
from ..stats import Interval, mean_interval, paired_comparison
from ..sweep import BuildableSpec
from .config import OptimizeConfig
from .evaluation import _Evaluator, evaluate_metrics

__all__ = ["OptimizeResult"]

FloatArray = NDArray[np.float64]


def _interval(iv: Interval) -> dict[str, float]:
    """An :class:`~.stats.Interval` as JSON-ready values."""
    return {"n": iv.n, "mean": iv.mean, "lo": iv.low, "hi": iv.high}


@dataclass(frozen=True)
class OptimizeResult:
    """Everything :func:`.run_optimization` found; JSON-ready via :meth:`to_dict`."""

    config: dict[str, Any]
    objective: str
    symmetric: dict[str, Any]
    asymmetric: dict[str, Any] | None
    verdict: dict[str, Any]
    history: list[dict[str, Any]]
    timing: dict[str, float]
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "objective": self.objective, "config": self.config, "symmetric": self.symmetric,
            "asymmetric": self.asymmetric, "warnings": list(self.warnings),
            "holdout": self.verdict, "timing": self.timing, "history": self.history,
        }  # fmt: skip

    def to_markdown(self) -> str:
        """The held-out verdict as Markdown tables."""
        v = self.verdict
        lines = [
            f"# FoU optimisation: minimise {self.objective}",
            "",
            f"Objective averaged over {v['n_noise']} noise level(s) x {v['n_trajectories']} "
            f"trajectory(ies) per seed; training on {v['n_train_seeds']} seed(s), verdict on "
            f"{v['n_holdout_seeds']} held-out seed(s) (disjoint, seed indices "
            f"{v['holdout_seed_range']}). Intervals: 95 % Student-t over seeds.",
            "",
        ]
        if self.warnings:
            lines += ["**Optimum on a bound of the search range:**", ""]
            lines += [f"- {w}" for w in self.warnings]
            lines.append("")
        lines += [
            "| controller | FoU widths | train objective | held-out mean | 95 % interval |",
            "|---|---|---:|---:|---|",
        ]
        for c in v["controllers"]:
            h = c["holdout"]
            lines.append(
                f"| {c['name']} | {c['widths']} | {c['train']:.5g} | {h['mean']:.5g} | "
                f"[{h['lo']:.5g}, {h['hi']:.5g}] |"
            )
        lines += [
            "",
            "Paired differences on the held-out seeds (optimum minus baseline; negative = the "
            "optimum is better; wins: share of seeds on which the optimum is better, ties "
            "counting half):",
            "",
            "| optimum | baseline | mean difference | 95 % interval | optimum wins | verdict |",
            "|---|---|---:|---|---:|---|",
        ]
        for d in v["paired"]:
            lines.append(
                f"| {d['optimum']} | {d['baseline']} | {d['mean']:.4g} | "
                f"[{d['lo']:.4g}, {d['hi']:.4g}] | {100 * d['win_rate']:.0f} % | {d['verdict']} |"
            )
        shown = ("IAE", "ITAE", "ISE", "ITSE", "pos_rms", "effort", "sat_time")
        lines += [
            "",
            "Held-out means of the metrics (over seeds, noise levels and trajectories), to see "
            "what the objective trades away:",
            "",
            "| controller | " + " | ".join(shown) + " |",
            "|---|" + "---:|" * len(shown),
        ]
        for c in v["controllers"]:
            cells = " | ".join(f"{c['holdout_metrics'][m]:.4g}" for m in shown)
            lines.append(f"| {c['name']} | {cells} |")
        t = self.timing
        lines += [
            "",
            f"Evaluations: {len(self.history)} candidates "
            f"({self.symmetric['n_evaluations']} symmetric"
            + (f", {self.asymmetric['n_evaluations']} asymmetric" if self.asymmetric else "")
            + f"); {t['total_s']:.1f} s in all.",
            "",
        ]
        return "\n".join(lines)


def _verdict(cfg: OptimizeConfig, ev: _Evaluator, sym: dict[str, Any],
             asym: dict[str, Any] | None) -> dict[str, Any]:  # fmt: skip
    entries: list[tuple[str, BuildableSpec, str, bool]] = []
    w = sym["width"]
    entries.append((f"symmetric optimum (FoU {w:.4g})", cfg.symmetric_spec(w), f"{w:.4g}", True))
    if asym is not None:
        ws = list(asym["widths"].values())
        text = "e " + "/".join(f"{x:.3g}" for x in ws[:3]) + ", de " + "/".join(
            f"{x:.3g}" for x in ws[3:]
        )
        entries.append(("asymmetric optimum", cfg.asymmetric_spec(ws), text, True))
    for c in cfg.compare:
        entries.append((f"IT2FLC FoU {c:g}", cfg.symmetric_spec(c), f"{c:g}", False))
    if cfg.compare_flc:
        entries.append(("FLC (type-1)", cfg.symmetric_spec(0.0), "0", False))
    specs = [e[1] for e in entries]

    def metrics(seeds: Sequence[int]) -> dict[str, FloatArray]:
        return evaluate_metrics(
            specs, config=cfg.config, trajectories=cfg.trajectories, noise_std=cfg.noise_std,
            seeds=seeds, executor=ev.executor, batch_size=cfg.batch_size,
        )  # fmt: skip

    train_m = metrics(cfg.train_seeds)
    hold_m = metrics(cfg.holdout_seeds)
    train = cfg.objective.per_run(train_m).reshape(len(specs), -1).mean(axis=1)
    # Per seed: mean over trajectories and noise levels -> (n_specs, n_holdout_seeds).
    per_seed = cfg.objective.per_run(hold_m).mean(axis=(1, 2))
    controllers = []
    for k, (name, spec, widths, is_opt) in enumerate(entries):
        controllers.append({
            "name": name, "optimum": is_opt, "widths": widths, "spec": spec.to_dict(),
            "train": float(train[k]),
            "holdout": _interval(mean_interval(per_seed[k])),
            "holdout_metrics": {m: float(hold_m[m][k].mean()) for m in METRIC_NAMES},
        })  # fmt: skip
    optima = [k for k, e in enumerate(entries) if e[3]]
    baselines = [k for k, e in enumerate(entries) if not e[3]]
    pairs = [(i, j) for i in optima for j in baselines]
    if len(optima) == 2:
        pairs.insert(len(baselines), (optima[1], optima[0]))  # asymmetric vs symmetric
    paired = []
    for i, j in pairs:
        cmp = paired_comparison(per_seed[i], per_seed[j])  # optimum minus baseline
        if cmp.diff.high < 0:
            verdict = "optimum better"
        elif cmp.diff.low > 0:
            verdict = "optimum worse"
        else:
            verdict = "no significant difference"
        paired.append({
            "optimum": entries[i][0], "baseline": entries[j][0], **_interval(cmp.diff),
            "win_rate": cmp.win_rate, "ties": cmp.ties, "verdict": verdict,
        })  # fmt: skip
    hs = cfg.holdout_seeds
    return {
        "n_train_seeds": len(cfg.train_seeds),
        "n_holdout_seeds": len(hs),
        "holdout_seed_range": f"{min(hs)}-{max(hs)}",
        "n_noise": len(cfg.noise_std),
        "n_trajectories": len(cfg.trajectories),
        "controllers": controllers,
        "paired": paired,
    }
