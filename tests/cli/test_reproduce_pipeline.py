"""The reproduce pipeline: figures drawn by worker processes are the same files as drawn here,
in report order, each reported once; a failing figure is named; stages are reported; labels
are checked before simulating without importing matplotlib here."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from click import ClickException
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.cli.reproduce import _preflight_study
from it2track.experiments.analysis import summarise
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.study import PDTuning, StudyConfig, StudyResult, run_study
from it2track.report.figures import figure_keys, write_figures
from it2track.report.render import FigureError, FigureRenderer
from it2track.tracking import LoopConfig


@pytest.fixture(scope="module")
def study() -> StudyResult:
    return run_study(StudyConfig(
        seeds=3, sweep_seeds=3, fou_sweep=(0.0, 0.2), noise_levels=(0.0, 0.1),
        loop=LoopConfig(duration=2.0),
        pd=PDTuning(seeds=2, kp_grid=(5.0, 20.0), kd_grid=(0.0, 0.1)),
        tuning=None, robustness=None,  # their figures and sections have their own tests
    ))


@pytest.fixture(scope="module")
def here(study, tmp_path_factory):
    out = tmp_path_factory.mktemp("here")
    return out, write_figures(study, summarise(study.rows), out)


@pytest.mark.parametrize("workers", [0, 2])
def test_workers_write_the_same_files_in_report_order(study, here, tmp_path, workers):
    ref_dir, ref = here
    done: list[str] = []
    early = replace(study, rows={k: v[:0] for k, v in study.rows.items()}, pd=None,
                    pd_tuning={})
    with FigureRenderer(tmp_path, workers=workers,
                        on_done=lambda key, cpu: done.append(key)) as renderer:
        first = renderer.submit(early, [])  # what needs no Monte Carlo, submitted early
        second = renderer.submit(study, summarise(study.rows))
        figures = renderer.results(study)
    assert set(first).isdisjoint(second), "no figure is submitted twice"
    assert {"control_surfaces", "paper_straight"} <= set(first)
    assert "integral_errors" in second
    assert list(figures) == [k for k in figure_keys(study) if k in ref] == list(ref)
    assert sorted(done) == sorted(ref), "every figure reported once"
    for key, png in figures.items():
        assert png == tmp_path / f"{key}.png"
        for suffix in (".png", ".svg"):
            assert png.with_suffix(suffix).read_bytes() == (ref_dir / key).with_suffix(
                suffix).read_bytes(), f"{key}{suffix} differs from the one drawn here"


@pytest.mark.parametrize("workers", [0, 1])
def test_a_failing_figure_is_named(study, tmp_path, workers):
    e, de, u = study.surfaces["FLC"]
    broken = replace(study, surfaces={**study.surfaces, "FLC": (e, de, u[:3])})
    with pytest.raises(FigureError, match="'control_surfaces' failed"):
        with FigureRenderer(tmp_path, workers=workers, svg=False) as renderer:
            renderer.submit(broken, summarise(study.rows))
            renderer.results(broken)


def test_mathtext_labels_are_checked_before_simulating():
    """A label with broken mathtext is refused before any simulation (naming it); valid
    mathtext and plain labels pass."""
    def config(label: str) -> StudyConfig:
        return StudyConfig(extra_controllers=(
            ControllerSpec(kind=ControllerKind.PD, kp=5.0, kd=0.1, label=label),))

    with pytest.raises(ClickException, match=r"undefinedmacro.*cannot be drawn"):
        _preflight_study(config("$\\undefinedmacro{x}$ PD"), None)
    _preflight_study(config("$\\alpha$ PD"), None)
    _preflight_study(config("my PD"), None)


def test_the_main_process_does_not_import_matplotlib():
    """The figures are drawn by workers: checking the default study and planning its figures
    imports no matplotlib here (a plain label needs no test drawing)."""
    code = ("import sys\n"
            "from it2track.cli.reproduce import _preflight_study\n"
            "from it2track.experiments.study import StudyConfig\n"
            "import it2track.report.render, it2track.report.plan, it2track.report.html\n"
            "_preflight_study(StudyConfig(), None)\n"
            "print('matplotlib' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=300)
    assert out.stdout.strip() == "False"


def test_the_figure_server_starts_before_the_study_is_imported():
    """``reproduce`` starts the figure workers' fork server first thing: the module that starts
    it imports none of the study (0.2 s that delayed the workers' imports)."""
    code = ("import sys\n"
            "import it2track.cli.main\n"
            "before = set(sys.modules)\n"
            "from it2track.report.render import default_figure_workers, start_figure_server\n"
            "print(sorted(m for m in set(sys.modules) - before if m.startswith('it2track')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=300)
    assert out.stdout.strip() == "['it2track.report', 'it2track.report.render']"


def test_quick_reports_its_stages_and_writes_svg_on_request(tmp_path):
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--svg", "--out",
                                       str(tmp_path)])
    assert result.exit_code == 0, result.output
    for stage in ("statistics and verdicts ...", "figures ...", "report.html ...", "times: "):
        assert stage in result.stderr, f"no progress for {stage!r}"
    pngs = sorted(tmp_path.glob("*.png"))
    assert pngs and all(p.with_suffix(".svg").is_file() for p in pngs)
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    stages = manifest["stage_s"]
    assert {"simulating", "figures", "report.html"} <= set(stages)
    assert all(np.isfinite(v) and v >= 0 for v in stages.values())
    assert "--svg" in manifest["command"]


def test_figure_data_is_what_the_study_returns(study, tmp_path):
    """The early figures are drawn from figure_data(config): its traces and surfaces are the
    study's own, bit for bit, and so are the figures drawn from it."""
    from it2track.experiments.study import figure_data

    early = figure_data(study.config)
    assert len(early.rows["seed"]) == 0 and early.pd is None
    assert early.trace_specs == study.trace_specs
    assert early.surface_specs == study.surface_specs
    for traj, trace in study.traces.items():
        for name, series in trace.series.items():
            np.testing.assert_array_equal(early.traces[traj].series[name], series, name)
    for label, (_, _, u) in study.surfaces.items():
        np.testing.assert_array_equal(early.surfaces[label][2], u, label)
    with FigureRenderer(tmp_path / "early", workers=0, svg=False) as renderer:
        keys = renderer.submit(early, [])
    late = write_figures(study, summarise(study.rows), tmp_path / "late", svg=False)
    assert keys and set(keys) < set(late)
    for key in keys:
        assert (tmp_path / "early" / f"{key}.png").read_bytes() == late[key].read_bytes(), key


def test_figures_submitted_while_the_workers_start_are_not_lost(study, tmp_path):
    """Submitting right after entering (the workers still importing) defers the figures to the
    start-up thread; every one is written."""
    with FigureRenderer(tmp_path, workers=2, svg=False) as renderer:
        first = renderer.submit(study, summarise(study.rows))
        assert renderer.submitted == first
        figures = renderer.results(study)
    assert list(figures) == first and all(p.is_file() for p in figures.values())


def test_the_figure_workers_draw_on_the_numpy_engine_unless_told(study, tmp_path, monkeypatch):
    """The dead zone's slices are evaluated in the figure worker on the numpy engine: no numba
    imported there (about 0.5 s of CPU at the end of a run); the files are the same bits as
    the compiled engine's (test_workers_write_the_same_files_in_report_order). An engine the
    user names is kept."""
    from it2track.fuzzy.kernels import ENGINE_ENV
    from it2track.report import render

    monkeypatch.setenv(ENGINE_ENV, "auto")
    monkeypatch.delenv(ENGINE_ENV)  # (restored as it was after the test)
    with FigureRenderer(tmp_path, workers=1, svg=False) as renderer:
        assert "dead_zone" in renderer.submit(study, summarise(study.rows))
        renderer.results(study)
        pool = renderer._pool
        assert pool is not None
        assert pool.submit(eval, f"__import__('os').environ[{ENGINE_ENV!r}]").result() == "numpy"
        assert pool.submit(eval, "'numba' in __import__('sys').modules").result() is False
    assert ENGINE_ENV not in os.environ, "this process's engine is untouched"
    monkeypatch.setenv(ENGINE_ENV, "compiled")
    render._init_worker()
    assert os.environ[ENGINE_ENV] == "compiled"
    monkeypatch.delenv(ENGINE_ENV)
    render._init_worker()
    assert os.environ[ENGINE_ENV] == "numpy"


def test_the_fork_server_ends_at_once_when_its_clients_have_gone():
    """The fork server preloads report._fork_server before the figures; once its loop ends
    (SystemExit: no client left) that module ends the process on the spot, status 0, with its
    output flushed: no teardown of what the server imported (0.3 s quiet, 1-2 s busy, during
    which the command's stdout and stderr stayed open for whoever reads them). Earlier exit
    handlers, the interpreter's teardown, do not run."""
    from it2track.report import render

    render._context()
    import multiprocessing.forkserver as forkserver

    assert forkserver._forkserver._preload_modules == [render._SERVER, render._PRELOAD]
    code = ("import atexit, sys\n"
            "atexit.register(print, 'teardown ran')\n"
            "import it2track.report._fork_server\n"
            "print('flushed', end='')\n"
            "sys.stderr.write('also flushed')\n"
            "raise SystemExit(3)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)
    assert (out.returncode, out.stdout, out.stderr) == (0, "flushed", "also flushed")


def test_the_rows_figures_start_before_the_verdicts_and_are_the_same(tmp_path):
    """run_study hands the result so far to rows_ready once its rows are final (reproduce draws
    their figures while the verdicts are judged): the same rows object, no verdicts yet, and
    every figure its rows give -- all but the robustness ones -- byte-identical to the one
    drawn from the whole result."""
    from it2track.cli.reproduce import _quick
    from it2track.report.figures import figure_plan, write_figure

    seen: list[StudyResult] = []
    result = run_study(_quick(StudyConfig()), rows_ready=seen.append)
    assert len(seen) == 1
    so_far = seen[0]
    assert so_far.rows is result.rows
    assert (so_far.pd, so_far.tuned, so_far.pd_tuning) == (result.pd, result.tuned,
                                                           result.pd_tuning)
    assert so_far.robustness is None and so_far.claims == [] and so_far.verdict_rows == []
    summary = summarise(result.rows)
    early = figure_plan(so_far, summarise(so_far.rows))
    assert early == [k for k in figure_plan(result, summary)
                     if k not in ("robustness", "sensitivity")]
    assert {"integral_errors", "noise_sweep", "fou_sweep", "win_rates"} <= set(early)
    for key in early:
        a = write_figure(key, so_far, summary, tmp_path / "so_far", svg=False, draft=True)
        b = write_figure(key, result, summary, tmp_path / "whole", svg=False, draft=True)
        assert a.read_bytes() == b.read_bytes(), key
