"""The study simulates each distinct run once; every row must still equal its own simulation."""

from dataclasses import replace

import numpy as np
import pytest

from it2track.experiments.sequential import SequentialDesign
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.study import (
    StudyConfig,
    experiment_sizes,
    run_study,
    study_run_count,
)
from it2track.tracking import METRIC_NAMES, LoopConfig, RunTable, get_trajectory, simulate


@pytest.fixture(scope="module")
def small():
    cfg = replace(StudyConfig(), loop=LoopConfig(duration=1.0), seeds=4, sweep_seeds=3,
                  noise_levels=(0.0, 0.05, 0.2), fou_sweep=(0.0, 0.2, 0.3), pd=None,
                  tuning=None, robustness=None)
    return cfg, run_study(cfg)


def test_every_row_equals_a_direct_simulation_of_it(small):
    cfg, result = small
    rows = result.rows
    rng = np.random.default_rng(0)
    picks = set(rng.choice(len(rows["seed"]), size=25, replace=False).tolist())
    # always include noise-free rows with a non-zero seed, which share one simulation
    picks |= set(np.flatnonzero((rows["noise_std"] == 0.0) & (rows["seed"] > 0))[:5].tolist())
    labels = {s.label: s for s in [
        ControllerSpec(kind=ControllerKind.FLC),
        *(ControllerSpec(kind=k, fou=w) for k in (ControllerKind.IT2, ControllerKind.T1_MATCHED,
                                                   ControllerKind.T1_SLOPE_MATCHED,
                                                   ControllerKind.T1_SURFACE)
          for w in (0.1, 0.2, 0.3)),
    ]}
    # The sequential design extended some cells beyond the first round: those rows too.
    assert result.extra_runs > 0 and rows["seed"].max() >= cfg.sweep_seeds
    picks |= set(np.flatnonzero(rows["seed"] >= cfg.sweep_seeds)[:5].tolist())
    for i in sorted(picks):
        spec = labels[rows["controller"][i]]
        trace = simulate([spec.build()], [get_trajectory(rows["trajectory"][i])],
                         RunTable(0, 0, rows["noise_std"][i], rows["seed"][i]), cfg.loop)
        for name in METRIC_NAMES:
            assert rows[name][i] == trace.metrics[name][0], (
                f"row {i} ({rows['experiment'][i]}, {rows['controller'][i]}, "
                f"{rows['trajectory'][i]}, sigma {rows['noise_std'][i]}, seed "
                f"{rows['seed'][i]}): {name}"
            )


def test_shared_runs_are_simulated_once(small):
    cfg, result = small
    rows = len(result.rows["seed"])
    sizes = experiment_sizes(cfg)
    # The noise sweep's first round, then the sequential design's extensions (all new runs).
    first = sizes["paper"] + sizes["noise"] + sizes["fou"]
    assert rows == first + result.extra_runs
    assert first < rows <= sizes["paper"] + sizes["noise_cap"] + sizes["fou"]
    assert study_run_count(cfg) < first  # overlaps and noise-free seeds are not re-run


def test_local_workers_give_the_same_rows(small):
    from it2track.experiments.executors import ProcessExecutor

    cfg, result = small
    chunked = replace(cfg, batch_size=97)  # many chunks, finishing in any order
    with ProcessExecutor(2) as ex:
        other = run_study(chunked, executor=ex)
    for name, values in result.rows.items():
        assert np.array_equal(values, other.rows[name]), name


def test_run_study_simulates_exactly_the_distinct_runs():
    cfg = replace(StudyConfig(), loop=LoopConfig(duration=0.5), seeds=3, sweep_seeds=2,
                  noise_levels=(0.0, 0.05), fou_sweep=(0.0, 0.2), pd=None, tuning=None,
                  robustness=None, verdicts=SequentialDesign(first=2, cap=2))
    done = []
    result = run_study(cfg, progress=done.append)
    # paper: 10 controllers (FLC, 3 IT2, 3 slope-matched, 3 dead-zone-matched) x 3
    # trajectories x seeds 0-2 = 90 rows, all distinct. noise: 7 controllers (those of the
    # paper's at FoU 0.2, and the surface copy) x 3 trajectories x (one noise-free run + seeds
    # 0-1 at sigma = 0.05) = 63 rows; the 21 noise-free runs and the copy's 6 noisy ones are
    # new, the others repeat paper runs. fou: FLC, IT2 0.2, matched 0.2 x 3 x seeds 0-1 = 18
    # rows, all repeats. The cap is the first round: no extension.
    assert len(result.rows["seed"]) == 90 + 63 + 18
    assert sum(done) == study_run_count(cfg) == 90 + 21 + 6
    assert result.extra_runs == 0 and result.rounds == []
    zero = result.rows["noise_std"] == 0.0
    assert set(result.rows["seed"][zero].tolist()) == {0}  # one row per noise-free cell


def test_early_figure_data_is_reused_and_must_be_of_the_same_config(small):
    from it2track.experiments.study import figure_data

    cfg, result = small
    early = figure_data(cfg)
    again = run_study(cfg, early=early)
    assert again.traces is early.traces and again.surfaces is early.surfaces  # not redone
    for name in result.rows:
        np.testing.assert_array_equal(again.rows[name], result.rows[name], name)
    other = replace(cfg, figure_seed=cfg.figure_seed + 1)
    with pytest.raises(ValueError, match="early= is figure_data of another config"):
        run_study(other, early=early)
    with pytest.raises(ValueError, match="early= must be figure_data"):
        run_study(cfg, early="traces")  # type: ignore[arg-type]
