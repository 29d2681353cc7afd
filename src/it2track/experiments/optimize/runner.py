"""Running the optimisation, :func:`run_optimization`: the symmetric search, the asymmetric one,
then the held-out verdict.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from ..executors import Executor, InProcessExecutor
from .config import OptimizeConfig
from .evaluation import _Evaluator
from .result import OptimizeResult, _verdict
from .search import _bound_warnings, _optimise_asymmetric, _optimise_symmetric

__all__ = ["run_optimization"]


def run_optimization(
    cfg: OptimizeConfig,
    *,
    executor: Executor | None = None,
    progress: bool = True,
    log: Callable[[str], object] | None = None,
) -> OptimizeResult:
    """Optimise the FoU widths of ``cfg`` and verify the optima on the held-out seeds.

    Parameters
    ----------
    cfg : OptimizeConfig
    executor : Executor, optional
        Where candidate batches run (default: this process). Results do not depend on it.
    progress : bool
        tqdm bars on stderr.
    log : callable, optional
        Receives one line per finished phase.
    """
    executor = executor or InProcessExecutor()
    t0 = time.perf_counter()
    ev = _Evaluator(cfg, executor)
    sym = _optimise_symmetric(cfg, ev, progress)
    t_sym = time.perf_counter() - t0
    if log:
        log(f"symmetric optimum: FoU {sym['width']:.4g}, train objective "
            f"{sym['train_objective']:.5g} ({sym['n_evaluations']} evaluations, {t_sym:.1f} s)")
    asym = None
    if cfg.asymmetric.enabled:
        asym = _optimise_asymmetric(cfg, ev, sym["width"], progress)
        if log:
            ws = ", ".join(f"{k} {v:.3g}" for k, v in asym["widths"].items())
            log(f"asymmetric optimum: {ws}; train objective {asym['train_objective']:.5g} "
                f"({asym['n_evaluations']} evaluations, {time.perf_counter() - t0 - t_sym:.1f} s)")
    t_opt = time.perf_counter() - t0
    verdict = _verdict(cfg, ev, sym, asym)
    total = time.perf_counter() - t0
    warnings = _bound_warnings(cfg.bounds, sym, asym)
    if log:
        for w in warnings:
            log(f"warning: {w}")
    return OptimizeResult(
        config=cfg.normalised(),
        objective=str(cfg.objective),
        symmetric=sym,
        asymmetric=asym,
        verdict=verdict,
        history=ev.history,
        warnings=tuple(warnings),
        timing={"symmetric_s": t_sym, "optimisation_s": t_opt, "holdout_s": total - t_opt,
                "total_s": total, "simulation_s": ev.seconds, "train_runs": ev.runs},
    )  # fmt: skip
