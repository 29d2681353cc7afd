"""FoU optimisation: the asymmetric spec, the search, the held-out verdict, outputs and errors."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import scipy.optimize
from click.testing import CliRunner

from it2track.cli.sweep import optimize as optimize_command
from it2track.experiments import optimize as optimize_module
from it2track.experiments.executors import InProcessExecutor, ProcessExecutor
from it2track.experiments.optimize import (
    WIDTH_NAMES,
    AsymmetricFouSpec,
    Objective,
    evaluate_metrics,
    load_optimize_config,
    run_optimization,
)
from it2track.experiments.optimize import search as optimize_search
from it2track.experiments.specs import ConfigError, ControllerKind, ControllerSpec
from it2track.report.optimize_plot import plot_convergence
from it2track.tracking import METRIC_NAMES, LoopConfig, get_trajectory

TINY = """
[optimize]
seed = 2
objective = { ISE = 1.0, IAE = 0.1 }
train_seeds = 3
holdout_seeds = { start = 100, count = 5 }
noise_std = 0.1
trajectories = ["sinusoidal"]
bounds = [0.0, 1.2]

[optimize.symmetric]
grid = 5
maxiter = 8

[optimize.asymmetric]
popsize = 2
maxiter = 2
seed = 4

[simulation]
duration = 1.0
"""


def write(tmp_path: Path, text: str, name: str = "optimize.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_asymmetric_spec_with_equal_widths_is_the_paper_controller() -> None:
    config = LoopConfig(duration=1.0, seed=9)
    kw = {"config": config, "trajectories": [get_trajectory("curved")],
          "noise_std": [0.05, 0.3], "seeds": [0, 1, 2]}  # fmt: skip
    for w in (0.2, 0.75):
        asym = evaluate_metrics([AsymmetricFouSpec.from_widths([w] * 6)], **kw)
        paper = evaluate_metrics([ControllerSpec(kind=ControllerKind.IT2, fou=w)], **kw)
        for name in METRIC_NAMES:
            np.testing.assert_array_equal(asym[name], paper[name], err_msg=f"{name}, w={w}")


def test_asymmetric_spec_values() -> None:
    spec = AsymmetricFouSpec(e=(0.1, 0.2, 0.3), de=(0.0, 0.5, 1.0), ke=2.0)
    assert spec.widths == (0.1, 0.2, 0.3, 0.0, 0.5, 1.0)
    assert spec.label == "IT2FLC FoU e(0.1,0.2,0.3) de(0,0.5,1) Ke 2 Kde 1"
    assert spec.to_dict()["fou_de"] == [0.0, 0.5, 1.0]
    fls = spec.build().fls
    assert [s.name for s in fls.inputs[1].sets] == ["N", "Z", "P"]
    assert fls.inputs[1].sets[0].upper is fls.inputs[1].sets[0].lower  # width 0: type-1 set
    assert WIDTH_NAMES == ("e.N", "e.Z", "e.P", "de.N", "de.Z", "de.P")
    with pytest.raises(ValueError, match=r"width of Z=1.6 must satisfy 0 <= w < 1.6"):
        AsymmetricFouSpec(e=(0.1, 1.6, 0.1), de=(0.1, 0.1, 0.1))
    with pytest.raises(ValueError, match="must be 3 widths"):
        AsymmetricFouSpec(e=(0.1, 0.1), de=(0.1, 0.1, 0.1))
    with pytest.raises(ValueError, match="must be 6 numbers"):
        AsymmetricFouSpec.from_widths([0.1] * 5)
    with pytest.raises(ValueError, match="unknown type reducer"):
        AsymmetricFouSpec(e=(0.1,) * 3, de=(0.1,) * 3, reducer="fast")


def test_evaluate_metrics_is_executor_independent() -> None:
    specs = [ControllerSpec(kind=ControllerKind.FLC),
             AsymmetricFouSpec.from_widths([0.1, 0.5, 0.2, 0.3, 0.3, 0.0]),
             ControllerSpec(kind=ControllerKind.IT2, fou=0.4)]  # fmt: skip
    kw = {"config": LoopConfig(duration=1.0), "trajectories": [get_trajectory("straight")],
          "noise_std": [0.2], "seeds": [3, 4]}  # fmt: skip
    local = evaluate_metrics(specs, executor=InProcessExecutor(), **kw)
    assert local["ISE"].shape == (3, 1, 1, 2)
    with ProcessExecutor(2) as ex:
        spread = evaluate_metrics(specs, executor=ex, **kw)
    for name in METRIC_NAMES:
        np.testing.assert_array_equal(local[name], spread[name], err_msg=name)


def test_optimisation_run_and_held_out_verdict(tmp_path: Path) -> None:
    cfg = load_optimize_config(write(tmp_path, TINY))
    assert cfg.train_seeds == (0, 1, 2) and cfg.holdout_seeds == tuple(range(100, 105))
    result = run_optimization(cfg, progress=False)
    hist = result.history
    assert [h["eval"] for h in hist] == list(range(len(hist)))
    sym_hist = [h for h in hist if h["phase"].startswith("symmetric")]
    asym_hist = [h for h in hist if h["phase"] == "asymmetric"]
    assert [h["widths"][0] for h in sym_hist[:5]] == pytest.approx([0.0, 0.3, 0.6, 0.9, 1.2])
    sym = result.symmetric
    assert sym["train_objective"] == min(h["objective"] for h in sym_hist)
    assert 0.0 <= sym["width"] <= 1.2
    asym = result.asymmetric
    assert asym is not None
    assert len(asym_hist) == asym["n_evaluations"] == 12 * 3  # popsize 2 x 6, 1 + 2 generations
    assert list(asym["widths"]) == list(WIDTH_NAMES)
    # The symmetric optimum seeds the population: the asymmetric one is no worse on training.
    assert asym["train_objective"] <= sym["train_objective"]
    assert asym_hist[0]["widths"] == pytest.approx([sym["width"]] * 6)

    verdict = result.verdict
    names = [c["name"] for c in verdict["controllers"]]
    assert names[1:] == ["asymmetric optimum", "IT2FLC FoU 0.1", "IT2FLC FoU 0.2",
                         "IT2FLC FoU 0.3", "FLC (type-1)"]  # fmt: skip
    first = verdict["controllers"][0]
    # Re-simulated on the training seeds, the optimum reproduces its search value exactly.
    assert first["train"] == sym["train_objective"]
    assert verdict["controllers"][1]["train"] == asym["train_objective"]
    for c in verdict["controllers"]:
        h = c["holdout"]
        assert h["n"] == 5 and h["lo"] <= h["mean"] <= h["hi"]
    pairs = {(d["optimum"], d["baseline"]) for d in verdict["paired"]}
    assert ("asymmetric optimum", first["name"]) in pairs
    assert (first["name"], "FLC (type-1)") in pairs and len(pairs) == 4 + 1 + 4
    for d in verdict["paired"]:
        assert d["lo"] <= d["mean"] <= d["hi"] and 0.0 <= d["win_rate"] <= 1.0
        assert d["verdict"] in ("optimum better", "optimum worse", "no significant difference")
    md = result.to_markdown()
    assert "| asymmetric optimum |" in md and "95 % interval" in md
    json.dumps(result.to_dict(), allow_nan=False)  # JSON-ready, no NaN


def test_held_out_statistics_are_paired_per_seed(tmp_path: Path) -> None:
    text = TINY.replace("[optimize.asymmetric]", "[optimize.asymmetric]\nenabled = false")
    cfg = load_optimize_config(write(tmp_path, text))
    result = run_optimization(cfg, progress=False)
    assert result.asymmetric is None
    # Recompute one paired difference by hand from per-seed objectives.
    best = cfg.symmetric_spec(result.symmetric["width"])
    flc = cfg.symmetric_spec(0.0)
    m = evaluate_metrics([best, flc], config=cfg.config, trajectories=cfg.trajectories,
                         noise_std=cfg.noise_std, seeds=cfg.holdout_seeds)  # fmt: skip
    per_seed = cfg.objective.per_run(m).mean(axis=(1, 2))
    diff = per_seed[0] - per_seed[1]
    (pair,) = [d for d in result.verdict["paired"] if d["baseline"] == "FLC (type-1)"]
    assert pair["mean"] == pytest.approx(diff.mean(), rel=1e-12)
    half = 2.7764451051977987 * diff.std(ddof=1) / math.sqrt(5)  # t(0.975, 4)
    assert pair["hi"] - pair["mean"] == pytest.approx(half, rel=1e-9)


def test_cli_optimize_writes_outputs(tmp_path: Path) -> None:
    text = TINY.replace("maxiter = 2\n", "maxiter = 1\n")
    config = write(tmp_path, text)
    out = tmp_path / "out"
    result = CliRunner().invoke(
        optimize_command, ["--config", str(config), "--out", str(out), "--no-progress"]
    )
    assert result.exit_code == 0, result.output
    data = json.loads((out / "optimize.json").read_text())
    assert data["objective"] == "ISE + 0.1 IAE"
    assert data["config"]["holdout_seeds"] == list(range(100, 105))
    assert {"symmetric", "asymmetric", "holdout", "history", "timing"} <= set(data)
    assert (out / "optimize.md").read_text().startswith("# FoU optimisation")
    assert (out / "convergence.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "| symmetric optimum" in result.output


def test_ties_count_half_and_optima_on_a_bound_are_flagged(tmp_path: Path) -> None:
    # No run of this tiny scenario saturates: every candidate's objective is exactly 0, so
    # every paired comparison is a tie on every seed and the optima sit on the lower bound
    # (the grid's first width wins ties; differential evolution keeps its first candidate,
    # the symmetric optimum).
    text = TINY.replace("{ ISE = 1.0, IAE = 0.1 }", '"sat_time"').replace("maxiter = 2\n",
                                                                          "maxiter = 1\n")
    config = write(tmp_path, text.replace("popsize = 2", "popsize = 1"))
    out = tmp_path / "out"
    result = CliRunner().invoke(
        optimize_command, ["--config", str(config), "--out", str(out), "--no-progress"]
    )
    assert result.exit_code == 0, result.output
    data = json.loads((out / "optimize.json").read_text())
    for d in data["holdout"]["paired"]:
        assert (d["mean"], d["ties"], d["win_rate"]) == (0.0, 1.0, 0.5), d
        assert d["verdict"] == "no significant difference"
    assert data["config"]["simulation"] == load_optimize_config(config).config.to_dict()

    sym, asym = data["symmetric"], data["asymmetric"]
    assert (sym["width"], sym["on_bound"], sym["bound"]) == (0.0, True, "lower")
    assert asym["on_bound"] == dict.fromkeys(WIDTH_NAMES, True)
    assert len(data["warnings"]) == 1 + 6
    assert data["warnings"][0].startswith(
        "The symmetric optimum FoU 0 lies on the lower bound 0 of the search range [0, 1.2]"
    )
    assert "width de.P = 0 lies on the lower bound 0" in data["warnings"][-1]
    md = (out / "optimize.md").read_text()
    assert "**Optimum on a bound of the search range:**" in md
    assert all(f"- {w}" in md for w in data["warnings"])


def test_bound_side_and_advice() -> None:
    assert optimize_search._bound_side(0.205, (0.2, 1.2)) == "lower"  # within 1 % of the range
    assert optimize_search._bound_side(0.215, (0.2, 1.2)) is None
    assert optimize_search._bound_side(1.195, (0.2, 1.2)) == "upper"
    sym = {"width": 1.2, "bound": "upper"}
    asym = {"widths": {"e.N": 0.7, "e.Z": 0.2}, "bound": {"e.N": None, "e.Z": "lower"}}
    warnings = optimize_search._bound_warnings((0.2, 1.2), sym, asym)
    assert len(warnings) == 2
    assert "upper bound 1.2" in warnings[0] and "widen bounds" in warnings[0]
    assert "width e.Z = 0.2 lies on the lower bound 0.2" in warnings[1]
    assert optimize_search._bound_warnings((0.2, 1.2), {"width": 0.5, "bound": None}, None) == []


def test_differential_evolution_on_scipy_without_rng_keyword(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """SciPy < 1.15 calls the generator ``seed``; the optimiser must run there, identically."""
    text = TINY.replace("popsize = 2", "popsize = 1").replace("maxiter = 2\n", "maxiter = 1\n")
    cfg = load_optimize_config(write(tmp_path, text))
    expected = run_optimization(cfg, progress=False).asymmetric
    real = scipy.optimize.differential_evolution
    seen: list[object] = []

    def legacy(func: Any, bounds: Any, *, seed: Any = None, **kwargs: Any) -> Any:
        seen.append(seed)
        return real(func, bounds, rng=seed, **kwargs)

    monkeypatch.setattr(scipy.optimize, "differential_evolution", legacy)
    got = run_optimization(cfg, progress=False).asymmetric
    assert len(seen) == 1 and isinstance(seen[0], np.random.Generator)
    assert got == expected


def test_cli_optimize_reports_a_failing_run_without_traceback(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(*args: object, **kwargs: object) -> None:
        raise ValueError("objective is NaN")

    monkeypatch.setattr(optimize_module, "run_optimization", broken)
    out = tmp_path / "out"
    result = CliRunner().invoke(
        optimize_command, ["--config", str(write(tmp_path, TINY)), "--out", str(out)]
    )
    assert result.exit_code == 1 and isinstance(result.exception, SystemExit), result.output
    assert "the optimisation stopped: ValueError: objective is NaN" in result.output
    assert not out.exists()


def test_convergence_plot(tmp_path: Path) -> None:
    history = [{"phase": "symmetric-grid", "objective": v} for v in (3.0, 1.0, 2.0)]
    history += [{"phase": "asymmetric", "objective": v} for v in (0.5, 4.0)]
    path = plot_convergence(history, tmp_path / "c.png", objective="ISE",
                            references={"FLC": 2.5})  # fmt: skip
    assert path.read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(ValueError, match="empty"):
        plot_convergence([], tmp_path / "d.png")


def test_objective() -> None:
    obj = Objective((("ISE", 2.0), ("effort", 0.5)))
    got = obj.per_run({"ISE": np.array([1.0, 2.0]), "effort": np.array([4.0, 0.0])})
    assert got.tolist() == [4.0, 4.0]
    assert str(obj) == "2 ISE + 0.5 effort"
    with pytest.raises(ValueError, match="not one of"):
        Objective((("ISEE", 1.0),))


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        ("seed = 2", "seed = 2\nseeds = 3", "[optimize]: unknown key(s) ['seeds']"),
        ("grid = 5", "grid = 5\nrefine = true", "[optimize.symmetric]: unknown key(s) ['refine']"),
        ("popsize = 2", "popsize = 2\npop = 3", "[optimize.asymmetric]: unknown key(s) ['pop']"),
        ("duration = 1.0", "duration = 1.0\nsteps = 3", "[simulation]: unknown key(s) ['steps']"),
        ("[simulation]", "[controller]\nfou = 0.2\n[simulation]",
         "[controller]: unknown key(s) ['fou']"),
        ("{ ISE = 1.0, IAE = 0.1 }", '"ISEE"', "objective metric 'ISEE' unknown"),
        ("{ ISE = 1.0, IAE = 0.1 }", "{ ISE = -1.0 }", "objective weight ISE=-1.0 must be > 0"),
        ("{ ISE = 1.0, IAE = 0.1 }", "{}", "empty objective"),
        ("{ ISE = 1.0, IAE = 0.1 }", "3", "objective=3 must be a metric name or a table"),
        ("holdout_seeds = { start = 100, count = 5 }", "holdout_seeds = [2, 50]",
         "disjoint from train_seeds; both hold [2]"),
        ("holdout_seeds = { start = 100, count = 5 }", "holdout_seeds = [50]",
         "at least 2 seeds"),
        ("holdout_seeds = { start = 100, count = 5 }", "holdout_seeds = []",
         "holdout_seeds=[] is an empty axis"),
        ("noise_std = 0.1", "noise_std = []", "noise_std=[] is an empty axis"),
        ('["sinusoidal"]', "[]", "trajectories=[] is an empty axis"),
        ("bounds = [0.0, 1.2]", "bounds = [0.0, 1.7]", "bounds=(0.0, 1.7) must satisfy"),
        ("bounds = [0.0, 1.2]", "bounds = [0.5]", "bounds=[0.5] must be [lo, hi]"),
        ("grid = 5", "grid = 2", "grid=2 must be an integer >= 3"),
        ("popsize = 2", "popsize = 0", "popsize=0 must be an integer >= 1"),
        ("seed = 4", 'seed = 4\ninit = "grid"', "init='grid' must be"),
        ("[simulation]", '[controller]\nreducer = "fast"\n[simulation]',
         "unknown type reducer 'fast'"),
        ("[simulation]", '[optimize.extra]\n[simulation]', "[optimize]: unknown key(s) ['extra']"),
    ],
)
def test_config_errors_name_file_key_value(
    tmp_path: Path, old: str, new: str, expected: str
) -> None:
    assert old in TINY
    path = write(tmp_path, TINY.replace(old, new, 1))
    with pytest.raises(ConfigError) as info:
        load_optimize_config(path)
    message = str(info.value)
    assert str(path) in message, message
    assert expected in message, message


def test_example_config_parses() -> None:
    root = Path(__file__).resolve().parents[2]
    cfg = load_optimize_config(root / "configs" / "optimize.toml")
    assert not set(cfg.train_seeds) & set(cfg.holdout_seeds)
    assert cfg.asymmetric.enabled and cfg.compare == (0.1, 0.2, 0.3)


def test_de_progress_bar_ends_at_the_real_count(tmp_path: Path, capsys) -> None:
    """Differential evolution that converges early: the bar ends at 100 %, count evaluated."""
    from it2track.experiments.optimize.search import _optimise_asymmetric

    text = TINY.replace("maxiter = 2\nseed = 4", "maxiter = 60\ntol = 1.0\nseed = 4")
    cfg = load_optimize_config(write(tmp_path, text))

    class Quadratic:  # stands in for the simulation-backed evaluator
        def __init__(self):
            self.history = []

        def __call__(self, specs, widths, phase):
            values = np.array([sum((x - 0.3) ** 2 for x in w) for w in widths])
            for w, v in zip(widths, values.tolist(), strict=True):
                self.history.append({"phase": phase, "widths": list(w), "objective": v})
            return values

    out = _optimise_asymmetric(cfg, Quadratic(), 0.3, True)
    n = out["n_evaluations"]
    assert n < 61 * out["de"]["population"]  # ended early
    last = capsys.readouterr().err.replace("\n", "\r").strip("\r").split("\r")[-1]
    assert "100%" in last and f"{n}/{n}" in last, last
