"""``it2track reproduce``: the whole study, its files, figures and report, in one command.

Moved from :mod:`it2track.cli.main`; the output folder's safety (staging, publishing) lives in
:mod:`it2track.cli.outdir`.
"""

from __future__ import annotations

import shlex
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from .config import ConfigFile
from .kernels import kernel_stage, start_kernels
from .outdir import _discard_staging, _drop_cache, _fail, _make_staging, _publish
from .reproduce_chip import _chip_lines, _chip_provenance, _ChipJob
from .sweep import check_dask_options as _check_dask_options
from .sweep import check_scheduler as _check_scheduler
from .sweep import dask_options as _dask_options
from .sweep import dask_settings as _dask_settings

if TYPE_CHECKING:
    from ..report.render import FigureRenderer

__all__ = ["MAX_MCU_GRID", "reproduce"]

#: The largest ``--mcu-grid``: the benchmark's grid (benchmarks/bench_mcu.py); the time grows
#: with its square (~3 s at 21), so a larger one would run for many minutes.
MAX_MCU_GRID = 61


def _quick(config: Any) -> Any:
    from ..experiments.study import quick_config

    return quick_config(config)


@click.command()
@click.option("--out", "out_dir", default="results", show_default=True,
              type=click.Path(file_okay=False), help="Output folder.")
@click.option("--config", "config_path", type=ConfigFile(),
              help="Study TOML file, or the name of a packaged config (default: paper, the "
              "paper's defaults; `it2track config show paper --out FILE` writes it out).")
@click.option("--seeds", type=click.IntRange(min=1), help="Noise realisations per cell.")
@click.option("--sweep-seeds", type=click.IntRange(min=1),
              help="Noise realisations per cell of the noise and FoU sweeps.")
@click.option("--quick", is_flag=True,
              help="A seconds-long smoke version (few seeds/levels, draft figures).")
@click.option("--workers", type=click.IntRange(min=0), default=0, show_default=True,
              help="Local worker processes for the experiments' runs (0: this process).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", callback=_check_scheduler,
              help="Run the experiments on this Dask cluster (needs it2track[dask]; only on a "
              "trusted network or with TLS: see README).")
@_dask_options
@click.option("--svg/--no-svg", default=None,
              help="Also write every figure as SVG (default: yes, except with --quick).")
@click.option("--mcu/--no-mcu", default=None,
              help="Measure the controller's cost on the simulated ATmega328P (cycles, bytes) "
              "and its Cortex-M4F code size, in the background (default: yes, except with "
              "--quick; needs the Debian packages gcc-avr, binutils-avr, avr-libc, simavr, "
              "gcc-arm-none-eabi, binutils-arm-none-eabi, libnewlib-arm-none-eabi, else the "
              "report names what to install).")
@click.option("--mcu-grid", type=click.IntRange(min=2, max=MAX_MCU_GRID), default=21,
              show_default=True,
              help="Inputs per axis of the microcontroller measurement's grid on [-1, 1]^2, "
              f"2 to {MAX_MCU_GRID} (the benchmark's grid); the time grows with its square: "
              "~3 s at 21. Refused with --no-mcu, and with --quick unless --mcu is given.")
@click.option("--physics/--no-physics", default=None,
              help="Re-judge the claims with the robot simulated in MuJoCo on dry, wet and "
              "icy ground (default: yes when MuJoCo is installed, except with --quick; needs "
              "it2track[mujoco]). Much slower than the kinematic study (manifest.json's "
              "stage_s has its time); an interrupted check resumes from OUT/.physics-cache "
              "when rerun with the same --out.")
@click.option("--chip/--no-chip", default=None,
              help="Judge C1, C2 and D1 again with the controllers as the simulated ATmega328P "
              "runs them (float32, measured latency), per reducer, into chip_verdicts.csv, "
              "claims.md and the report (default: yes, except with --quick, where --chip runs "
              "a tiny smoke version; needs the Debian packages gcc, gcc-avr, binutils-avr, "
              "avr-libc, libsimavr-dev, else the report names what to install).")
@click.option("--no-progress", is_flag=True, help="No progress bar or stage messages.")
@click.option("--force", is_flag=True,
              help="Replace files in OUT of the names this run writes that it2track cannot "
              "prove it wrote (not listed with their SHA-256 in OUT's manifest.json).")
def reproduce(out_dir: str, config_path: str | None, seeds: int | None,
              sweep_seeds: int | None, quick: bool, workers: int, scheduler: str | None,
              svg: bool | None, mcu: bool | None, mcu_grid: int, physics: bool | None,
              chip: bool | None, no_progress: bool, force: bool, **dask: Any) -> None:
    """Regenerate every result of the paper, with statistics and verdicts on its claims.

    Writes figures (PNG, and SVG unless --quick or --no-svg), metrics.csv, summary.csv,
    verdicts.csv, robustness.csv, sensitivity.csv, claims.md, mcu_costs.csv,
    chip_verdicts.csv, report.html and manifest.json into OUT, and with the physics check
    physics_verdicts.csv, physics_metrics.csv and physics_tracking.gif. Files appear only when
    complete. --quick is a smoke run: every verdict it prints is marked "smoke run — not
    evidence". A file of those names already in OUT is replaced only if OUT's manifest.json
    (sealed by the run that wrote it) lists it with its SHA-256, or with --force; otherwise
    nothing runs.
    Figures are drawn by worker processes while the study runs; the microcontroller costs are
    measured by another process meanwhile.
    """
    from ..report.render import default_figure_workers, start_figure_server

    if default_figure_workers():  # the figure workers boot while this process goes on
        start_figure_server()
    from dataclasses import replace
    from functools import partial

    from tqdm import tqdm

    from ..experiments.analysis import summarise
    from ..experiments.specs import ConfigError
    from ..experiments.study import (
        ROW_KEYS,
        figure_data,
        load_study_config,
        run_study,
        study_run_count,
    )
    from ..report import outputs
    from ..report.chip import CHIP_CSV, chip_markdown, write_chip_csv
    from ..report.html import write_html
    from ..report.mcu_job import TABLE_NAME, McuJob, McuStatus, write_cost_csv
    from ..report.physics import physics_markdown
    from ..report.plan import possible_figure_keys
    from ..report.render import FigureError, FigureRenderer
    from ..tracking import METRIC_NAMES

    started = time.perf_counter()
    ctx = click.get_current_context()
    _check_dask_options(ctx, scheduler)
    mcu = (not quick) if mcu is None else mcu
    if not mcu and _given(ctx, "mcu_grid"):
        _fail(f"--mcu-grid {mcu_grid} has no effect without the microcontroller measurement "
              f"({'--no-mcu' if _given(ctx, 'mcu') else '--quick'} turns it off): drop it or "
              "add --mcu")
    try:
        config = load_study_config(config_path) if config_path else _default_study_config()
        if quick:
            config = _quick(config)
        if seeds is not None:
            config = replace(config, seeds=seeds)
        if sweep_seeds is not None:
            config = replace(config, sweep_seeds=sweep_seeds)
    except (ConfigError, ValueError) as exc:
        _fail(str(exc))
        return
    from concurrent.futures import BrokenExecutor

    from ..experiments.executors import ExecutorError, make_executor

    if workers and scheduler:
        _fail("give either --workers or --scheduler, not both")
    _preflight_study(config, config_path)
    kernels_started = start_kernels()  # (a first run's compile overlaps the preparation)
    total = study_run_count(config)
    out = Path(out_dir)
    svg = (not quick) if svg is None else svg
    stages = _Stages(enabled=not no_progress)
    also = []  # the other files this run writes, checked up front like the fixed ones
    if config.robustness is not None:
        also.append("robustness.csv")
        if config.robustness.sensitivity is not None:
            also.append("sensitivity.csv")
    if mcu:
        also += ["mcu_costs.csv", "mcu_costs.png", *(["mcu_costs.svg"] if svg else [])]
    also += [f"{key}.{ext}" for key in possible_figure_keys(config)
             for ext in ("png", *(["svg"] if svg else []))]
    check, physics_outcome = _physics_plan(ctx, physics, quick)
    if check is not None:
        from ..report.physics import GIF_NAME, METRICS_NAME, VERDICTS_NAME

        also += [VERDICTS_NAME, METRICS_NAME, GIF_NAME]
    chip_on = (not quick and _default_chip()) if chip is None else chip
    if chip_on:
        also.append("chip_verdicts.csv")
    staging = _make_staging(out_dir, also, force=force)
    skipped = "--quick" if quick and not _given(ctx, "mcu") else "--no-mcu"
    mcu_job = McuJob.skipped(f"skipped with {skipped}", fou=config.main_fou, grid=mcu_grid)
    chip_job = _ChipJob()
    try:
        # The chip's runs go to another process while the study runs.
        chip_job = _ChipJob.start(config, chip, quick=quick)
        if mcu:
            # The cross-compilers and simavr run in another process while the study runs.
            mcu_job = McuJob.start(out_dir=staging, fou=config.main_fou, grid=mcu_grid,
                                   svg=svg)
        # Figure workers start now and import matplotlib while the study runs; each figure is
        # drawn as soon as its data exist (report.render), so both cores stay busy.
        # (The kernels first: on a first run their compile starts before the workers do.)
        with kernel_stage(progress=not no_progress, run_steps=total * config.loop.n_steps,
                          started=kernels_started) as kernels, FigureRenderer(
                staging, workers=default_figure_workers(), svg=svg,
                on_done=stages.figure_done, draft=quick) as renderer:
            with stages.stage("simulating"), tqdm(
                    total=total, unit="run", disable=no_progress, file=sys.stderr,
                    desc="simulating", leave=False) as bar:
                kernels.watch(bar)
                try:
                    # The time series and control surfaces need no Monte Carlo: their
                    # figures are drawn while the experiments run.
                    early = figure_data(config)
                    renderer.submit(early, [])

                    def grow(n: int) -> None:  # a sequential round adds runs
                        bar.total += n
                        bar.refresh()

                    rows: list[Any] = []  # the rows' figures start while the verdicts are judged

                    def rows_ready(so_far: Any) -> None:
                        rows[:] = [so_far.rows, summarise(so_far.rows)]
                        renderer.submit(so_far, rows[1])

                    run = partial(run_study, config, progress=bar.update, early=early,
                                  grow=grow, rows_ready=rows_ready)
                    if workers or scheduler:
                        with make_executor(workers=workers or None, scheduler=scheduler,
                                           **_dask_settings(**dask)) as ex:
                            result = run(executor=ex)
                    else:
                        result = run()
                except (ValueError, OSError, ExecutorError, BrokenExecutor) as exc:
                    _fail(f"the study stopped: {type(exc).__name__}: {exc}; nothing was "
                          "written")
            with stages.stage("statistics and verdicts"):
                summary = rows[1] if rows and rows[0] is result.rows else summarise(result.rows)
                if quick:  # every verdict a smoke run prints says what it is
                    result = _mark_smoke(result)
                claims = result.claims
            with stages.stage("the verdicts on the chip (waiting for them)"):
                chip_outcome = chip_job.result(result.verdict_rows)
            renderer.submit(result, summary)
            if check is not None:
                physics_outcome = _run_physics(config, check, result, staging, out,
                                               stages, no_progress, quick)
            with stages.stage("metrics.csv, summary.csv, verdicts.csv, claims.md"):
                outputs.write_metrics_csv(staging / "metrics.csv", result.rows,
                                          [*ROW_KEYS, *METRIC_NAMES])
                outputs.write_summary_csv(staging / "summary.csv", summary)
                outputs.write_verdicts_csv(staging / "verdicts.csv", result.verdict_rows)
                if result.robustness is not None:
                    outputs.write_robustness_csv(staging / "robustness.csv", result.robustness)
                    if result.robustness.sensitivity:
                        outputs.write_sensitivity_csv(staging / "sensitivity.csv",
                                                      result.robustness)
                outputs.write_claims_md(
                    staging / "claims.md", claims,
                    preamble=outputs.claims_preamble(config, seeds=result.seeds_by_level,
                                                     smoke=quick),
                    levels=outputs.levels_markdown(claims, result.verdict_rows),
                    sections=outputs.study_sections(result, claims)
                    + "\n" + physics_markdown(physics_outcome)
                    + ("\n" + chip_markdown(chip_outcome) if chip_outcome else ""),
                    smoke=quick)
                if chip_outcome is not None and chip_outcome.result is not None:
                    write_chip_csv(staging / CHIP_CSV, chip_outcome.result)
            with stages.stage("figures"), stages.figure_bar(renderer):
                try:
                    figures = renderer.results(result)
                except FigureError as exc:
                    _fail(f"{exc}; nothing was written")
        with stages.stage("microcontroller costs"):
            mcu_costs = mcu_job.result()
            if mcu_costs.table is not None:
                write_cost_csv(staging / TABLE_NAME, mcu_costs.table)
            if mcu_costs.figure is not None:
                figures = {**figures, "mcu_costs": mcu_costs.figure}
            if mcu_costs.status in (McuStatus.FAILED, McuStatus.TOOLS_MISSING):
                why = mcu_costs.reason or f"install {', '.join(mcu_costs.missing)}"
                click.echo(f"note: the microcontroller costs were not measured ({why}); the "
                           "report says so", err=True)
        command = _command_line(click.get_current_context())
        cfg = config.to_dict()
        cfg["pd_tuning"] = {k: v for k, v in result.pd_tuning.items() if k != "grid"}
        cfg["fuzzy_tuning"] = {label: {k: v for k, v in rec.items() if k != "grid"}
                               for label, rec in result.tuning.items()}
        manifest = outputs.manifest(
            config=cfg, command=command.strip(), elapsed_s=time.perf_counter() - started,
            extra={"rows": len(result.rows["seed"]), "simulations": total + result.extra_runs,
                   "mcu": mcu_costs.provenance(),
                   "physics": physics_outcome.provenance(),
                   "chip": _chip_provenance(chip_outcome),
                   "files": sorted(p.name for p in staging.iterdir())},
        )
        with stages.stage("report.html"):
            write_html(staging / "report.html", result=result, summary=summary,
                       claims=claims, manifest=manifest, figures=figures,
                       elapsed_s=time.perf_counter() - started, mcu=mcu_costs, smoke=quick,
                       physics=physics_outcome, chip=chip_outcome)
        manifest["elapsed_s"] = round(time.perf_counter() - started, 3)
        manifest["stage_s"] = stages.record()
        manifest["files"] = sorted([*(p.name for p in staging.iterdir()), "manifest.json"])
        outputs.write_json(staging / "manifest.json", manifest)
        _publish(staging, out, force=force)
        if check is not None:
            _drop_cache(out / PHYSICS_CACHE)
    finally:
        try:
            chip_job.cancel()
            mcu_job.cancel()
        finally:  # the staging folder goes even if stopping the measurement fails
            _discard_staging(staging)
    elapsed = time.perf_counter() - started
    stages.summary(elapsed)
    runs = total + result.extra_runs
    if physics_outcome.result is None:
        click.echo(f"note: the physics check was skipped ({physics_outcome.reason})", err=True)
    click.echo(f"{len(result.rows['seed'])} result rows from {runs} simulations in "
               f"{elapsed:.1f} s -> {out}/")
    if quick:
        click.echo(f"  {_SMOKE_NOTE}")
    for c in claims:
        click.echo(f"  {c.id}: {c.verdict}")
    for line in _chip_lines(chip_outcome):
        click.echo(f"  {line}")


PHYSICS_CACHE = ".physics-cache"
#: Frames of the physics check's animation.
PHYSICS_GIF_FRAMES = 60


def _physics_plan(ctx: click.Context, physics: bool | None, quick: bool) -> tuple[Any, Any]:
    """The physics check to run (or None) and the outcome to report if it does not run:
    on by default when MuJoCo is installed, off with --quick unless --physics is given;
    --physics without MuJoCo is an error naming the extra."""
    from dataclasses import replace

    from ..experiments.physics import PhysicsCheck, mujoco_missing
    from ..report.physics import INSTALL, PhysicsOutcome

    if physics is False:
        return None, PhysicsOutcome.skipped("skipped with --no-physics")
    if physics is None and quick:
        return None, PhysicsOutcome.skipped("skipped with --quick; add --physics for a "
                                            "smoke run of it")
    missing = mujoco_missing()
    if missing is not None:
        if physics:
            _fail(f"--physics needs MuJoCo: {INSTALL} (or drop --physics); nothing was "
                  "simulated")
        return None, PhysicsOutcome.skipped(f"MuJoCo is not installed: {INSTALL}")
    check = _default_physics_check()
    if check is None:
        if physics:
            check = PhysicsCheck()
        else:
            return None, PhysicsOutcome.skipped("off by default here; add --physics")
    if quick:  # a smoke run of the check: the quick study's 3 s runs, two realisations
        return replace(check, first=2, batch=1, cap=2), None
    return check, None


def _default_chip() -> bool:
    """Whether ``reproduce`` judges the verdicts on the chip without ``--chip``/``--no-chip``
    (yes, outside ``--quick``; a hook the tests replace, as the chip takes minutes)."""
    return True


def _default_physics_check() -> Any:
    """The physics check ``reproduce`` runs by default when MuJoCo is installed, or None
    for none unless --physics is given (a hook the tests replace)."""
    from ..experiments.physics import PhysicsCheck

    return PhysicsCheck()


def _run_physics(config: Any, check: Any, result: Any, staging: Path, out: Path,
                 stages: _Stages, no_progress: bool, quick: bool) -> Any:
    """Run the physics check (its rounds cached in OUT/.physics-cache, so an interrupted
    run resumes) and write its files into ``staging``."""
    from tqdm import tqdm

    from ..experiments.physics import RowCache, run_physics
    from ..plant.mujoco_robot import PhysicsDivergedError
    from ..report.physics import PhysicsOutcome, write_physics_files

    started = time.perf_counter()
    with stages.stage("physics check (MuJoCo)"), tqdm(
            total=0, unit="run", disable=no_progress, file=sys.stderr, desc="physics",
            leave=False) as bar:
        def grow(n: int) -> None:
            bar.total += n
            bar.refresh()

        try:
            cache = RowCache(out / PHYSICS_CACHE)
            physics = run_physics(config, check, cache=cache, progress=bar.update, grow=grow,
                                  on_surface=lambda s: bar.set_description(f"physics {s}"))
        except (ValueError, OSError, PhysicsDivergedError) as exc:
            _fail(f"the physics check stopped: {type(exc).__name__}: {exc}; nothing was "
                  f"written (finished rounds are kept in {out / PHYSICS_CACHE})")
    outcome = PhysicsOutcome(result=physics, seconds=time.perf_counter() - started,
                             smoke=quick, cached=cache.hits)
    with stages.stage("physics check: files and animation"):
        write_physics_files(staging, outcome, config, result.verdict_rows,
                            frames=PHYSICS_GIF_FRAMES)
    return outcome


#: The terminal's line above a --quick run's verdicts.
_SMOKE_NOTE = ("smoke run — not evidence: --quick runs every part of the study on a few "
               "short realisations; run without --quick for verdicts")


def _mark_smoke(result: Any) -> Any:
    """The result with every verdict it prints (headline, per path, tuned, robustness)
    marked as a smoke run's."""
    from dataclasses import replace

    from ..report.outputs import SMOKE

    def mark(c: Any) -> Any:
        per = {t: {**v, "verdict": f"{v['verdict']} ({SMOKE})"}
               for t, v in c.per_trajectory.items()}
        return replace(c, verdict=f"{c.verdict} ({SMOKE})", per_trajectory=per)

    rob = result.robustness
    if rob is not None:
        rob = replace(rob, verdicts=[{**v, "verdict": f"{v['verdict']} ({SMOKE})"}
                                     for v in rob.verdicts])
    return replace(result, claims=[mark(c) for c in result.claims],
                   tuned_claims=[mark(c) for c in result.tuned_claims], robustness=rob)


class _Stages:
    """Progress of the pipeline on stderr: a line when a stage starts, its time when it ends,
    a bar for the figures; the stage times for the manifest."""

    def __init__(self, *, enabled: bool) -> None:
        self.enabled = enabled
        self.seconds: dict[str, float] = {}
        self.figure_cpu: dict[str, float] = {}
        self._bar: Any = None

    @contextmanager
    def stage(self, name: str) -> Iterator[None]:
        if self.enabled and name != "simulating":  # the simulation has its own bar
            click.echo(f"{name} ...", err=True)
        started = time.perf_counter()
        yield
        self.seconds[name] = time.perf_counter() - started

    def figure_done(self, key: str, cpu_seconds: float) -> None:
        self.figure_cpu[key] = cpu_seconds
        if self._bar is not None:
            self._bar.set_postfix_str(key, refresh=False)
            self._bar.update(1)

    @contextmanager
    def figure_bar(self, renderer: FigureRenderer) -> Iterator[None]:
        from tqdm import tqdm

        renderer.poll()  # figures finished during the simulation count as done
        with tqdm(total=len(renderer.submitted), initial=len(self.figure_cpu), unit="figure",
                  disable=not self.enabled, file=sys.stderr, desc="figures",
                  leave=False) as bar:
            self._bar = bar
            try:
                yield
            finally:
                self._bar = None

    def record(self) -> dict[str, float]:
        """Stage -> wall seconds, and the figures' CPU seconds (summed over the workers)."""
        out = {k: round(v, 3) for k, v in self.seconds.items()}
        out["figures (CPU, all workers)"] = round(sum(self.figure_cpu.values()), 3)
        return out

    def summary(self, elapsed: float) -> None:
        if not self.enabled:
            return
        parts = ", ".join(f"{k} {v:.1f} s" for k, v in self.seconds.items())
        cpu = sum(self.figure_cpu.values())
        click.echo(f"times: {parts} (figures: {cpu:.1f} s CPU in {len(self.figure_cpu)} "
                   f"figures); total {elapsed:.1f} s", err=True)


def _preflight_study(config: Any, config_path: str | None) -> None:
    """What would fail only after minutes of simulation, checked before any: the memory the
    results need, noise levels beyond the allowed range, trajectories whose figures or rows
    would overwrite each other, and labels matplotlib cannot draw (mathtext)."""
    from .._limits import ResourceLimitError, check_memory, loop_bytes
    from ..experiments.study import experiment_sizes
    from ..plant.noise import MAX_NOISE_STD
    from ..tracking import get_trajectory

    source = config_path or "the default study"
    for key, values in (("noise_std", [config.noise_std]),
                        ("noise_levels", list(config.noise_levels))):
        big = [v for v in values if v > MAX_NOISE_STD]
        if big:
            _fail(f"{source} [study] {key}: {big[0]!r} exceeds {MAX_NOISE_STD:g} rad, the largest "
                  "heading-noise standard deviation allowed")
    sizes = experiment_sizes(config)
    rows = sizes["paper"] + sizes["noise_cap"] + sizes["fou"]  # the noise sweep at its cap
    loop = config.loop
    n_traced = 1 + len(config.fous)
    try:
        check_memory(
            700 * rows + 100 * sizes["pd_tuning"]
            + loop_bytes(n_steps=loop.n_steps, runs=n_traced, record=True,
                         noise_samples=int(loop.duration * loop.noise_rate) + 1)
            + loop_bytes(n_steps=loop.n_steps, runs=config.batch_size,
                         trajectories=len(config.trajectories),
                         noise_samples=int(loop.duration * loop.noise_rate) + 1),
            what=(f"{source}: the study's {rows} result rows (seeds={config.seeds}, "
                  f"sweep_seeds={config.sweep_seeds}, batch_size={config.batch_size})"),
            hint="use fewer seeds (--seeds, --sweep-seeds) or a smaller batch_size",
        )
    except ResourceLimitError as exc:
        _fail(str(exc))
    seen: dict[str, str] = {}
    names = []
    for t in config.trajectories:
        try:
            names.append(get_trajectory(t).name)
        except (ValueError, OSError) as exc:
            _fail(f"{source} [study] trajectories: {exc}")
    if len(config.trajectories) > 1 and any(t.lower().endswith(".csv")
                                            for t in config.trajectories):
        from ..report.identity import slug

        for t, name in zip(config.trajectories, names, strict=True):
            for key in (f"figure {slug(t)!r}", f"name {name!r}"):
                if key in seen and seen[key] != t:
                    _fail(f"{source} [study] trajectories {seen[key]!r} and {t!r} would share "
                          f"the {key} (one's figures and rows would overwrite the other's): "
                          "rename one of the files")
                seen[key] = t
    labels = [s.label for s in config.extra_controllers] + names
    for label in labels:
        if "$" not in label:
            continue  # only $...$ (mathtext) can fail to draw
        problem = _undrawable(label)
        if problem:
            _fail(f"{source}: the label {label!r} cannot be drawn in the figures ({problem}); "
                  "escape '$' as '\\$' or fix the mathtext")


def _undrawable(text: str) -> str | None:
    """Why matplotlib cannot draw ``text`` (a mathtext parse error), or None."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(2, 1))
    FigureCanvasAgg(fig)
    fig.text(0, 0, text)
    try:
        fig.canvas.draw()
    except Exception as exc:  # any drawing failure means a bad label
        return " ".join(str(exc).split())[:200] or type(exc).__name__
    return None


def _given(ctx: click.Context, name: str) -> bool:
    """Whether option ``name`` was given (command line or environment), not defaulted."""
    from click.core import ParameterSource

    return ctx.get_parameter_source(name) in (ParameterSource.COMMANDLINE,
                                              ParameterSource.ENVIRONMENT)


def _command_line(ctx: click.Context) -> str:
    """The command that reproduces this run: the options given on the command line (or from
    the environment), in the command's declaration order, with their parsed values.

    Options left at their defaults are not recorded, whatever their value: click's parameter
    source says which were given (comparing values with ``param.default`` fails for flags,
    whose default is a sentinel in recent click releases).
    """
    parts = [ctx.command_path]
    for param in ctx.command.params:
        if not isinstance(param, click.Option) or not _given(ctx, param.name or ""):
            continue
        value = ctx.params.get(param.name or "")
        flag = param.opts[0]
        if param.is_flag:
            if value:
                parts.append(flag)
            elif param.secondary_opts:
                parts.append(param.secondary_opts[0])
            continue
        parts.append(f"{flag} {shlex.quote(str(value))}")
    return " ".join(parts)


def _default_study_config() -> Any:
    """The study ``reproduce`` runs without ``--config`` (a hook the tests replace)."""
    from ..experiments.study import StudyConfig

    return StudyConfig()
