"""The two searches: the symmetric width by a grid and bounded Brent, the six asymmetric widths
by differential evolution; and the optima that sit on a bound of the search range
(:data:`BOUND_TOLERANCE`).
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping
from typing import Any

import numpy as np
import scipy.optimize
from numpy.typing import NDArray
from tqdm import tqdm

from ...paper import MAX_FOU
from .config import WIDTH_NAMES, OptimizeConfig
from .evaluation import _Evaluator

__all__ = ["BOUND_TOLERANCE"]

FloatArray = NDArray[np.float64]


#: An optimal width closer than this fraction of the search range to a bound is "on the bound".
BOUND_TOLERANCE = 0.01


def _bar(progress: bool, total: int | None, desc: str) -> Any:
    return tqdm(total=total, desc=desc, unit="cand", disable=not progress, dynamic_ncols=True)


def _optimise_symmetric(cfg: OptimizeConfig, ev: _Evaluator, progress: bool) -> dict[str, Any]:
    s = cfg.symmetric
    lo, hi = cfg.bounds
    grid = np.linspace(lo, hi, s.grid).tolist()
    cache: dict[float, float] = {}
    with _bar(progress, s.grid, "symmetric grid") as bar:
        values = ev([cfg.symmetric_spec(w) for w in grid], [[w] for w in grid], "symmetric-grid")
        bar.update(s.grid)
    cache.update(zip(grid, values.tolist(), strict=True))
    i = int(np.argmin(values))
    bracket = (grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)])

    with _bar(progress, None, "symmetric refine") as bar:

        def f(w: float) -> float:
            w = float(w)
            if w not in cache:
                cache[w] = float(ev([cfg.symmetric_spec(w)], [[w]], "symmetric-refine")[0])
                bar.update(1)
            return cache[w]

        res = scipy.optimize.minimize_scalar(
            f, bounds=bracket, method="bounded",
            options={"xatol": s.xatol, "maxiter": s.maxiter},
        )  # fmt: skip
    best_w = min(cache, key=lambda w: (cache[w], w))
    side = _bound_side(best_w, cfg.bounds)
    return {
        "width": best_w,
        "train_objective": cache[best_w],
        "on_bound": side is not None,
        "bound": side,
        "grid": grid,
        "grid_objective": values.tolist(),
        "bracket": list(bracket),
        "brent": {"x": float(res.x), "fun": float(res.fun), "nfev": int(res.nfev),
                  "success": bool(res.success), "message": str(res.message)},
        "n_evaluations": len(cache),
    }  # fmt: skip


def _optimise_asymmetric(
    cfg: OptimizeConfig, ev: _Evaluator, start: float, progress: bool
) -> dict[str, Any]:
    a = cfg.asymmetric
    lo, hi = cfg.bounds
    n_pop = a.popsize * len(WIDTH_NAMES)

    with _bar(progress, (a.maxiter + 1) * n_pop, "asymmetric DE") as bar:

        def f(x: FloatArray) -> FloatArray:
            cols = np.atleast_2d(np.asarray(x, dtype=np.float64).T)  # (S, 6)
            widths = [[float(v) for v in row] for row in cols]
            out = ev([cfg.asymmetric_spec(w) for w in widths], widths, "asymmetric")
            bar.update(len(widths))
            return out

        res = scipy.optimize.differential_evolution(
            f,
            bounds=[(lo, hi)] * len(WIDTH_NAMES),
            maxiter=a.maxiter,
            popsize=a.popsize,
            tol=a.tol,
            mutation=a.mutation,
            recombination=a.recombination,
            **_de_rng(np.random.default_rng(a.seed)),
            init=a.init,
            polish=False,
            updating="deferred",
            vectorized=True,
            x0=np.full(len(WIDTH_NAMES), min(max(start, lo), hi)),
        )
        # DE stops early once the population converges: the bar ends at the real count
        # (100 %), not at the budget's fraction.
        bar.total = bar.n
        bar.refresh()
    asym = [h for h in ev.history if h["phase"] == "asymmetric"]
    best = min(asym, key=lambda h: h["objective"])
    widths = dict(zip(WIDTH_NAMES, best["widths"], strict=True))
    sides = {name: _bound_side(w, cfg.bounds) for name, w in widths.items()}
    return {
        "widths": widths,
        "train_objective": best["objective"],
        "on_bound": {n: side is not None for n, side in sides.items()},
        "bound": sides,
        "de": {"x": [float(v) for v in res.x], "fun": float(res.fun),
               "batches": int(res.nfev), "generations": int(res.nit),
               "success": bool(res.success), "message": str(res.message),
               "population": n_pop},
        "n_evaluations": len(asym),
    }  # fmt: skip


def _de_rng(rng: np.random.Generator) -> dict[str, np.random.Generator]:
    """The generator as ``differential_evolution``'s keyword: ``rng`` (SciPy >= 1.15) or
    ``seed`` (older SciPy). Both use the generator as given: the same population either way."""
    params = inspect.signature(scipy.optimize.differential_evolution).parameters
    return {"rng": rng} if "rng" in params else {"seed": rng}


def _bound_side(width: float, bounds: tuple[float, float]) -> str | None:
    """``"lower"`` / ``"upper"`` if ``width`` is within :data:`BOUND_TOLERANCE` of the search
    range of that bound, else ``None``."""
    lo, hi = bounds
    tol = BOUND_TOLERANCE * (hi - lo)
    if width - lo <= tol:
        return "lower"
    if hi - width <= tol:
        return "upper"
    return None


def _bound_warnings(
    bounds: tuple[float, float], sym: Mapping[str, Any], asym: Mapping[str, Any] | None
) -> list[str]:
    """One sentence per optimal width that sits on a bound of the search range."""
    lo, hi = bounds

    def advice(side: str) -> str:
        if side == "lower" and lo == 0.0:
            return "0 is the smallest width (a type-1 set), so the optimum is at the edge"
        if side == "upper" and hi >= MAX_FOU - BOUND_TOLERANCE * (hi - lo):
            return f"widths must stay below {MAX_FOU}, so the optimum is at the edge"
        limit = f"0 <= lo < hi < {MAX_FOU}"
        return f"the objective may keep falling beyond it: widen bounds ({limit}) and rerun"

    out = []
    if sym.get("bound"):
        side = sym["bound"]
        value = lo if side == "lower" else hi
        out.append(
            f"The symmetric optimum FoU {sym['width']:.4g} lies on the {side} bound {value:g} "
            f"of the search range [{lo:g}, {hi:g}]; {advice(side)}."
        )
    if asym is not None:
        for name, side in asym["bound"].items():
            if side:
                value = lo if side == "lower" else hi
                out.append(
                    f"The asymmetric optimum width {name} = {asym['widths'][name]:.4g} lies on "
                    f"the {side} bound {value:g} of the search range [{lo:g}, {hi:g}]; "
                    f"{advice(side)}."
                )
    return out
