"""``it2track`` command line: a friendly outer layer over the strict library.

Strings from the command line are mapped to the library's strategy objects here (controller
kinds, reducers, trajectories); everything below works with dataclasses and arrays.
"""

from __future__ import annotations

import json
import shlex
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import click

from .. import __version__

__all__ = ["main"]

#: PD gains used by ``it2track simulate --controller pd`` unless given: close to the study's
#: effort-matched PD at sigma = 0.05 rad (the study re-tunes on every run; see its report).
DEFAULT_PD = {"kp": 6.0, "kd": 0.2}


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="it2track")
def main() -> None:
    """Interval type-2 fuzzy trajectory tracking: simulate, reproduce the paper, sweep, optimise."""


def _fail(message: str) -> None:
    raise click.ClickException(message)


# --------------------------------------------------------------------------------------------
# simulate
# --------------------------------------------------------------------------------------------


@main.command()
@click.option("--trajectory", default="straight", show_default=True,
              help="straight | curved | sinusoidal, or a waypoint CSV file (t,x,y).")
@click.option("--controller", "controller", default="it2", show_default=True,
              type=click.Choice(["flc", "it2", "t1-matched", "pd"]),
              help="Heading controller (t1-matched: type-1 FLC with the IT2FLC's dead zone).")
@click.option("--controller-file", type=click.Path(exists=True, dir_okay=False),
              help="Fuzzy controller file (.t2fis/.fis/.toml) instead of --controller.")
@click.option("--fou", default=0.2, show_default=True, type=float,
              help="FoU width for it2 / t1-matched.")
@click.option("--reducer", default="exhaustive", show_default=True,
              type=click.Choice(["km", "ekm", "eiasc", "exhaustive", "nie-tan", "wu-mendel"]))
@click.option("--ke", default=1.0, show_default=True, type=float, help="Error input gain.")
@click.option("--kde", default=1.0, show_default=True, type=float, help="Error-change gain.")
@click.option("--kp", default=DEFAULT_PD["kp"], show_default=True, type=float, help="PD gain.")
@click.option("--kd", default=DEFAULT_PD["kd"], show_default=True, type=float, help="PD gain.")
@click.option("--noise-std", default=0.05, show_default=True, type=float,
              help="Heading noise standard deviation, rad.")
@click.option("--noise-power", type=float, default=None,
              help="Simulink band-limited white noise power instead of --noise-std "
              "(sigma = sqrt(P / Ts_noise)).")
@click.option("--noise-rate", default=100.0, show_default=True,
              type=click.FloatRange(min=0.0, min_open=True), help="Hz.")
@click.option("--seed", default=0, show_default=True, type=int, help="Noise realisation index.")
@click.option("--base-seed", default=0, show_default=True, type=int, help="Base seed.")
@click.option("--duration", default=10.0, show_default=True,
              type=click.FloatRange(min=0.0, min_open=True, max=3600.0), help="s.")
@click.option("--ts", default=0.01, show_default=True,
              type=click.FloatRange(min=0.0, min_open=True), help="Control period, s.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as one JSON object.")
@click.option("--trace", type=click.Path(dir_okay=False, writable=True),
              help="Save the time series to this CSV file.")
def simulate(**opts: Any) -> None:
    """Simulate one scenario and print its metrics."""
    from ..atomicfile import atomic_write_text
    from ..experiments.specs import ControllerKind, ControllerSpec
    from ..plant import HeadingNoise
    from ..tracking import LoopConfig, RunTable, get_trajectory
    from ..tracking import simulate as run

    _reject_inapplicable(click.get_current_context(), opts)
    try:
        if opts["noise_power"] is not None:
            noise = HeadingNoise.from_band_limited_power(opts["noise_power"],
                                                         1.0 / opts["noise_rate"])
            sigma = noise.std
        else:
            sigma = opts["noise_std"]
        if opts["controller_file"]:
            spec = ControllerSpec(kind=ControllerKind.FILE, path=opts["controller_file"],
                                  ke=opts["ke"], kde=opts["kde"])
        else:
            kind = ControllerKind(opts["controller"])
            kw: dict[str, Any] = {"kind": kind}
            if kind is ControllerKind.PD:
                kw.update(kp=opts["kp"], kd=opts["kd"])
            else:
                kw.update(ke=opts["ke"], kde=opts["kde"])
            if kind in (ControllerKind.IT2, ControllerKind.T1_MATCHED):
                kw["fou"] = opts["fou"]
            if kind is ControllerKind.IT2:
                kw["reducer"] = opts["reducer"]
            spec = ControllerSpec(**kw)
        controller = spec.build()
        trajectory = get_trajectory(opts["trajectory"])
        config = LoopConfig(duration=opts["duration"], ts=opts["ts"],
                            noise_rate=opts["noise_rate"], seed=opts["base_seed"])
        runs = RunTable(0, 0, sigma, opts["seed"])
        trace = run([controller], [trajectory], runs, config)
    except ValueError as exc:
        _fail(str(exc))
        return
    metrics = {k: float(v[0]) for k, v in trace.metrics.items()}
    if opts["trace"]:
        import csv
        import io

        buf = io.StringIO()
        writer = csv.writer(buf, lineterminator="\n")
        names = list(trace.series)
        writer.writerow(["t", *names])
        run0 = trace.run(0)
        for k in range(trace.t.size):
            writer.writerow([repr(float(run0["t"][k]))] + [repr(float(run0[n][k]))
                                                           for n in names])
        try:
            atomic_write_text(Path(opts["trace"]), buf.getvalue())
        except OSError as exc:
            _fail(f"cannot write --trace {opts['trace']}: {exc.strerror}")
    if opts["as_json"]:
        click.echo(json.dumps(metrics))
        return
    click.echo(f"{spec.label} on {trajectory.name}, sigma = {sigma:g} rad, seed {opts['seed']}, "
               f"{opts['duration']:g} s")
    width = max(len(k) for k in metrics)
    for key, value in metrics.items():
        click.echo(f"  {key:<{width}}  {value:.6g}")


_APPLIES = {
    "fou": ("it2", "t1-matched"),
    "reducer": ("it2",),
    "ke": ("flc", "it2", "t1-matched", "file"),
    "kde": ("flc", "it2", "t1-matched", "file"),
    "kp": ("pd",),
    "kd": ("pd",),
}


def _reject_inapplicable(ctx: click.Context, opts: dict[str, Any]) -> None:
    """Options given on the command line that the chosen controller would silently ignore."""
    from click.core import ParameterSource

    def given(name: str) -> bool:
        return ctx.get_parameter_source(name) is ParameterSource.COMMANDLINE

    if opts["controller_file"] and given("controller"):
        _fail("give either --controller or --controller-file, not both")
    kind = "file" if opts["controller_file"] else opts["controller"]
    for name, kinds in _APPLIES.items():
        if given(name) and kind not in kinds:
            what = "--controller-file" if kind == "file" else f"--controller {kind}"
            _fail(f"--{name.replace('_', '-')} does not apply to {what}")
    if given("noise_power") and given("noise_std"):
        _fail("give either --noise-std or --noise-power, not both")


# --------------------------------------------------------------------------------------------
# reproduce
# --------------------------------------------------------------------------------------------


def _quick(config: Any) -> Any:
    from dataclasses import replace

    pd = config.pd
    if pd is not None and pd.kp is None:  # keep the user's PD settings, tune on a small grid
        pd = replace(pd, seeds=2, kp_grid=(2.0, 6.0, 20.0), kd_grid=(0.0, 0.2, 1.0))
    return replace(config, seeds=6, sweep_seeds=4, noise_levels=(0.0, 0.05, 0.2),
                   fou_sweep=(0.0, 0.1, 0.2, 0.3), pd=pd)


@main.command()
@click.option("--out", "out_dir", default="results", show_default=True,
              type=click.Path(file_okay=False), help="Output folder.")
@click.option("--config", "config_path", type=click.Path(exists=True, dir_okay=False),
              help="Study TOML file (default: the paper's defaults, configs/paper.toml).")
@click.option("--seeds", type=click.IntRange(min=1), help="Noise realisations per cell.")
@click.option("--sweep-seeds", type=click.IntRange(min=1),
              help="Noise realisations per cell of the noise and FoU sweeps.")
@click.option("--quick", is_flag=True, help="A seconds-long smoke version (few seeds/levels).")
@click.option("--workers", type=click.IntRange(min=0), default=0, show_default=True,
              help="Local worker processes for the experiments' runs (0: this process).")
@click.option("--scheduler", metavar="tcp://HOST:PORT",
              help="Run the experiments on this Dask cluster (needs it2track[dask]).")
@click.option("--no-progress", is_flag=True, help="No progress bar.")
def reproduce(out_dir: str, config_path: str | None, seeds: int | None,
              sweep_seeds: int | None, quick: bool, workers: int, scheduler: str | None,
              no_progress: bool) -> None:
    """Regenerate every result of the paper, with statistics and verdicts on its claims.

    Writes figures (PNG+SVG), metrics.csv, summary.csv, claims.md, report.html and
    manifest.json into OUT. Files appear only when complete.
    """
    from dataclasses import replace

    from tqdm import tqdm

    from ..experiments.analysis import evaluate_claims, summarise
    from ..experiments.specs import ConfigError
    from ..experiments.study import (
        ROW_KEYS,
        StudyConfig,
        load_study_config,
        run_study,
        study_run_count,
    )
    from ..report import outputs
    from ..tracking import METRIC_NAMES

    started = time.perf_counter()
    try:
        config = load_study_config(config_path) if config_path else StudyConfig()
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
    total = study_run_count(config)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".reproduce-", dir=out))
    try:
        with tqdm(total=total, unit="run", disable=no_progress, file=sys.stderr,
                  desc="simulating") as bar:
            try:
                if workers or scheduler:
                    with make_executor(workers=workers or None, scheduler=scheduler) as ex:
                        result = run_study(config, progress=bar.update, executor=ex)
                else:
                    result = run_study(config, progress=bar.update)
            except (ValueError, OSError, ExecutorError, BrokenExecutor) as exc:
                _fail(f"the study stopped: {type(exc).__name__}: {exc}; nothing was written")
                return
        summary = summarise(result.rows)
        claims = evaluate_claims(result.rows, fous=config.fous, main_fou=config.main_fou,
                                 trajectories=config.trajectories)
        outputs.write_metrics_csv(staging / "metrics.csv", result.rows,
                                  [*ROW_KEYS, *METRIC_NAMES])
        outputs.write_summary_csv(staging / "summary.csv", summary)
        preamble = _claims_preamble(config)
        outputs.write_claims_md(staging / "claims.md", claims, preamble=preamble)
        if not no_progress:
            click.echo("writing figures and report ...", err=True)
        from ..report.figures import write_figures
        from ..report.html import write_html

        figures = write_figures(result, summary, staging)
        command = _command_line(click.get_current_context())
        cfg = config.to_dict()
        cfg["pd_tuning"] = {k: v for k, v in result.pd_tuning.items() if k != "grid"}
        manifest = outputs.manifest(
            config=cfg, command=command.strip(), elapsed_s=time.perf_counter() - started,
            extra={"rows": len(result.rows["seed"]), "simulations": total,
                   "files": sorted(p.name for p in staging.iterdir())},
        )
        write_html(staging / "report.html", result=result, summary=summary, claims=claims,
                   manifest=manifest, figures=figures, elapsed_s=time.perf_counter() - started)
        manifest["elapsed_s"] = round(time.perf_counter() - started, 3)
        manifest["files"] = sorted([*(p.name for p in staging.iterdir()), "manifest.json"])
        outputs.write_json(staging / "manifest.json", manifest)
        _publish(staging, out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    elapsed = time.perf_counter() - started
    click.echo(f"{len(result.rows['seed'])} result rows from {total} simulations in "
               f"{elapsed:.1f} s -> {out}/")
    for c in claims:
        click.echo(f"  {c.id}: {c.verdict}")


def _publish(staging: Path, out: Path) -> None:
    """Move a finished run from ``staging`` into ``out``.

    Files a previous run listed in its manifest but this run did not write (e.g. figures of a
    trajectory no longer studied) are removed first, the old manifest before anything else and
    the new manifest last: an interrupted publish leaves no manifest rather than one that
    describes a mix of two runs.
    """
    new = {p.name for p in staging.iterdir()}
    old_manifest = out / "manifest.json"
    stale: set[str] = set()
    if old_manifest.is_file():
        try:
            stale = set(json.loads(old_manifest.read_text()).get("files", [])) - new
        except (ValueError, OSError):
            stale = set()
        old_manifest.unlink()
    for name in sorted(stale | new):
        if "/" in name or name in (".", ".."):
            continue
        target = out / name
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        elif name in stale:
            target.unlink(missing_ok=True)
    for name in sorted(new - {"manifest.json"}):
        (staging / name).replace(out / name)
    (staging / "manifest.json").replace(old_manifest)


def _command_line(ctx: click.Context) -> str:
    """The command that reproduces this run, from the parsed options (not ``sys.argv``)."""
    parts = [ctx.command_path]
    for param in ctx.command.params:
        value = ctx.params.get(param.name or "")
        if value is None or value == param.default or not isinstance(param, click.Option):
            continue
        flag = param.opts[0]
        parts.append(flag if param.is_flag else f"{flag} {shlex.quote(str(value))}")
    return " ".join(parts)


def _claims_preamble(config: Any) -> str:
    levels = ", ".join(f"{s:g}" for s in config.noise_levels)
    return (
        "# Claims of the paper, tested\n\n"
        "Computed by `it2track reproduce` from the `noise` experiment: "
        f"{config.sweep_seeds} noise realisations per cell (common random numbers across "
        f"controllers), noise levels sigma = {levels} rad, trajectories "
        f"{', '.join(config.trajectories)}, {config.loop.duration:g} s at "
        f"{1 / config.loop.ts:g} Hz. Intervals are 95 % Student-t intervals of paired "
        "per-seed differences. A comparison cell *supports* a claim when its interval lies on "
        "the claimed side of zero, *contradicts* it when it lies on the other side, and is "
        "*inconclusive* otherwise (an interval containing zero, e.g. exact ties); a noise level "
        "holds when every cell supports the claim, is contradicted when any cell contradicts "
        "it, and is *not shown* otherwise. Every verdict below is computed from the data in "
        "metrics.csv."
    )


def _register_subcommands() -> None:
    """Attach the commands that live in their own modules."""
    from .fis import fis, surface
    from .sweep import optimize, sweep

    for command in (sweep, optimize, fis, surface):
        main.add_command(command)


_register_subcommands()

if __name__ == "__main__":  # pragma: no cover
    main()
