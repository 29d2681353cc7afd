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
from typing import Any, NoReturn

import click

from .. import __version__
from .sweep import check_scheduler as _check_scheduler
from .sweep import dask_options as _dask_options
from .sweep import dask_settings as _dask_settings

__all__ = ["main"]

#: PD gains used by ``it2track simulate --controller pd`` unless given: close to the study's
#: effort-matched PD at sigma = 0.05 rad (the study re-tunes on every run; see its report).
DEFAULT_PD = {"kp": 6.0, "kd": 0.2}


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="it2track")
def main() -> None:
    """Interval type-2 fuzzy trajectory tracking: simulate, reproduce the paper, sweep, optimise."""


def _fail(message: str) -> NoReturn:
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
    # Everything that can fail is checked before the simulation starts, each error naming
    # the option(s) it comes from.
    if opts["trace"] is not None:
        _check_output_file(opts["trace"], "--trace")
    try:
        if opts["noise_power"] is not None:
            noise = HeadingNoise.from_band_limited_power(opts["noise_power"],
                                                         1.0 / opts["noise_rate"])
            sigma = noise.std
        else:
            sigma = opts["noise_std"]
    except ValueError as exc:
        _fail(f"--noise-power {opts['noise_power']:g} with --noise-rate "
              f"{opts['noise_rate']:g}: {exc}")
    try:
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
    except (ValueError, OSError) as exc:
        source = (f"--controller-file {opts['controller_file']}" if opts["controller_file"]
                  else f"--controller {opts['controller']}")
        _fail(f"{source}: {exc}")
    try:
        trajectory = get_trajectory(opts["trajectory"])
    except (ValueError, OSError) as exc:
        _fail(f"--trajectory {opts['trajectory']}: {exc}")
    try:
        config = LoopConfig(duration=opts["duration"], ts=opts["ts"],
                            noise_rate=opts["noise_rate"], seed=opts["base_seed"])
    except ValueError as exc:
        _fail(f"--duration {opts['duration']:g} / --ts {opts['ts']:g} / --noise-rate "
              f"{opts['noise_rate']:g} / --base-seed {opts['base_seed']}: {exc}")
    try:
        runs = RunTable(0, 0, sigma, opts["seed"])
    except ValueError as exc:
        noise_opt = "--noise-power" if opts["noise_power"] is not None else "--noise-std"
        _fail(f"--seed {opts['seed']} / {noise_opt}: {exc}")
    try:
        trace = run([controller], [trajectory], runs, config)
    except ValueError as exc:
        _fail(f"the simulation stopped: {exc}")
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
        except (OSError, ValueError) as exc:
            _fail(f"cannot write --trace {opts['trace']}: "
                  f"{getattr(exc, 'strerror', None) or exc}")
    if opts["as_json"]:
        click.echo(json.dumps(metrics))
        return
    click.echo(f"{spec.label} on {trajectory.name}, sigma = {sigma:g} rad, seed {opts['seed']}, "
               f"{opts['duration']:g} s")
    width = max(len(k) for k in metrics)
    for key, value in metrics.items():
        click.echo(f"  {key:<{width}}  {value:.6g}")


def _check_output_file(path: str, option: str) -> None:
    """An output file option must name a file we may create or replace: not empty, in an
    existing folder, absent or a regular file (never a device, FIFO, folder or link)."""
    from ..atomicfile import NotRegularFileError, check_replaceable

    if not path:
        _fail(f"{option} '' is empty: give a file name")
    try:
        check_replaceable(path)
    except NotRegularFileError as exc:
        _fail(f"{option} {path}: {exc.strerror}")
    parent = Path(path).parent
    if not parent.is_dir():
        _fail(f"{option} {path}: the folder {parent} does not exist")


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
@click.option("--scheduler", metavar="tcp://HOST:PORT", callback=_check_scheduler,
              help="Run the experiments on this Dask cluster (needs it2track[dask]; only on a "
              "trusted network or with TLS: see README).")
@_dask_options
@click.option("--no-progress", is_flag=True, help="No progress bar.")
def reproduce(out_dir: str, config_path: str | None, seeds: int | None,
              sweep_seeds: int | None, quick: bool, workers: int, scheduler: str | None,
              no_progress: bool, **dask: Any) -> None:
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
    _preflight_study(config, config_path)
    total = study_run_count(config)
    out = Path(out_dir)
    staging = _make_staging(out_dir)
    try:
        with tqdm(total=total, unit="run", disable=no_progress, file=sys.stderr,
                  desc="simulating") as bar:
            try:
                if workers or scheduler:
                    with make_executor(workers=workers or None, scheduler=scheduler,
                                       **_dask_settings(**dask)) as ex:
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
        _discard_staging(staging)
    elapsed = time.perf_counter() - started
    click.echo(f"{len(result.rows['seed'])} result rows from {total} simulations in "
               f"{elapsed:.1f} s -> {out}/")
    for c in claims:
        click.echo(f"  {c.id}: {c.verdict}")


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
    rows = sum(v for k, v in sizes.items() if k != "pd_tuning")
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
        from ..report.figures import slug  # (imports matplotlib: only when files could clash)

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


#: Results every run writes (figures vary with the config): checked before any work starts.
_FIXED_OUTPUTS = ("metrics.csv", "summary.csv", "claims.md", "report.html", "manifest.json")
_STAGING_PREFIX = ".reproduce-"
_OWNER_FILE = "owner.json"
_OWNER_PROGRAM = "it2track reproduce"


def _process_start(pid: int) -> int | None:
    """Start time of process ``pid`` (clock ticks since boot, Linux ``/proc``), else None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    try:
        return int(text.rsplit(")", 1)[1].split()[19])
    except (IndexError, ValueError):  # pragma: no cover - unexpected /proc format
        return None


def _owner_alive(owner: dict[str, Any]) -> bool:
    """Is the process that created a staging folder (``owner.json``) still running?"""
    import os
    import socket

    if owner.get("host") != socket.gethostname():
        return True  # another machine (shared filesystem): cannot tell, so never ours to remove
    pid = owner.get("pid")
    if isinstance(pid, bool) or not isinstance(pid, int) or pid <= 0:
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    start = owner.get("start")
    return start is None or _process_start(pid) in (None, start)  # a reused pid is not it


def _remove_stale_staging(out: Path) -> None:
    """Remove staging folders that killed runs of ``reproduce`` left in ``out``.

    A folder is removed only if it is provably ours and stale: a real directory named
    ``.reproduce-*`` holding our ``owner.json`` (program, host, pid, process start time) whose
    process is gone, and nothing but that file and a ``files/`` folder of regular files. Any
    other ``.reproduce-*`` entry (a user's, an older version's, a live run's) is left alone.
    """
    import os
    import stat

    try:
        entries = [e for e in os.scandir(out) if e.name.startswith(_STAGING_PREFIX)]
    except OSError:
        return
    for entry in entries:
        if not entry.is_dir(follow_symlinks=False):
            continue
        root = Path(entry.path)
        try:
            st = os.lstat(root / _OWNER_FILE)
            if not stat.S_ISREG(st.st_mode):
                continue
            owner = json.loads((root / _OWNER_FILE).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if not isinstance(owner, dict) or owner.get("program") != _OWNER_PROGRAM:
            continue
        if _owner_alive(owner):
            continue
        files = root / "files"
        try:
            names = set(os.listdir(root))
            inner = list(os.scandir(files)) if "files" in names else []
        except OSError:
            continue
        if names - {_OWNER_FILE, "files"} or not all(
            e.is_file(follow_symlinks=False) for e in inner
        ) or ("files" in names and not files.is_dir()) or files.is_symlink():
            click.echo(f"note: left {root} alone (holds more than a run's files)", err=True)
            continue
        try:
            for e in inner:
                os.unlink(e.path)
            if "files" in names:
                os.rmdir(files)
            os.unlink(root / _OWNER_FILE)
            os.rmdir(root)
        except OSError as exc:
            click.echo(f"note: could not remove the stale {root}: {exc.strerror}", err=True)


def _make_staging(out_dir: str) -> Path:
    """Create ``out_dir`` and a fresh staging folder in it; returns the folder results go to.

    Checked before any simulation: an empty ``--out``, a folder that cannot be created or
    written (read-only, a file in the way), a result name taken by something that is not a
    regular file. Stale staging folders of killed runs are removed (see
    :func:`_remove_stale_staging`). The staging root holds ``owner.json`` (this process's
    identity, the proof a later run needs to remove it) and ``files/``, which is returned.
    """
    import os
    import socket
    import stat

    if not out_dir:
        _fail("--out '' is empty: give an output folder")
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        _fail(f"cannot create the output folder --out {out_dir}: "
              f"{exc.strerror or exc}; nothing was simulated")
    for name in _FIXED_OUTPUTS:
        try:
            mode = os.lstat(out / name).st_mode
        except OSError:
            continue
        if not stat.S_ISREG(mode):
            _fail(f"{out / name} exists and is not a regular file; it2track never replaces "
                  "what it did not write: move it away or choose another --out "
                  "(nothing was simulated)")
    _remove_stale_staging(out)
    try:
        root = Path(tempfile.mkdtemp(prefix=_STAGING_PREFIX, dir=out))
    except OSError as exc:
        _fail(f"cannot write into the output folder --out {out_dir}: "
              f"{exc.strerror or exc}; nothing was simulated")
    try:
        owner = {"program": _OWNER_PROGRAM, "host": socket.gethostname(), "pid": os.getpid(),
                 "start": _process_start(os.getpid()), "created": time.time()}
        from ..atomicfile import atomic_write_text

        atomic_write_text(root / _OWNER_FILE, json.dumps(owner) + "\n")
        (root / "files").mkdir()
    except OSError as exc:
        shutil.rmtree(root, ignore_errors=True)
        _fail(f"cannot write into the output folder --out {out_dir}: "
              f"{exc.strerror or exc}; nothing was simulated")
    _terminate_cleanly()
    return root / "files"


def _terminate_cleanly() -> None:
    """Let SIGTERM unwind like Ctrl-C (``finally`` blocks run, the staging folder goes)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return

    def handler(signum: int, frame: Any) -> None:
        raise SystemExit(128 + signum)

    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, handler)
        _RESTORE_SIGTERM.append(signal.SIG_DFL)


_RESTORE_SIGTERM: list[Any] = []


def _discard_staging(staging: Path) -> None:
    """Remove this run's own staging folder (the parent of ``staging``)."""
    import signal

    shutil.rmtree(staging.parent, ignore_errors=True)
    while _RESTORE_SIGTERM:
        signal.signal(signal.SIGTERM, _RESTORE_SIGTERM.pop())


def _sha256_file(path: Path) -> str:
    import hashlib

    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while block := fh.read(1 << 20):
            h.update(block)
    return h.hexdigest()


def _publish(staging: Path, out: Path) -> None:
    """Move a finished run from ``staging`` into ``out``, never losing a file of the user's.

    Only two kinds of file in ``out`` are ever replaced or removed:

    - files this run is about to write (same names; only if they are regular files: a folder,
      link or device in the way stops the publish before anything moves);
    - files a previous run wrote and listed in its ``manifest.json`` *with their SHA-256*, and
      that still have exactly those bytes (e.g. figures of a trajectory no longer studied).
      Anything else -- a name the old manifest lists without a digest or with another one
      (a file edited since, a manifest this program did not write), a folder, a link, a path
      outside ``out`` -- is kept (and named on stderr).

    The new manifest records the SHA-256 of every file of this run, as that proof for the
    next run. The old manifest goes before anything else moves and the new one comes last:
    an interrupted publish leaves no manifest rather than one that describes a mix of runs.
    """
    import os
    import stat

    from ..report import outputs

    new = sorted(p.name for p in staging.iterdir())
    for name in new:
        try:
            mode = os.lstat(out / name).st_mode
        except FileNotFoundError:
            continue
        if not stat.S_ISREG(mode):
            _fail(f"{out / name} exists and is not a regular file; it2track never replaces "
                  "what it did not write: move it away and rerun (nothing was published)")
    staged_manifest = staging / "manifest.json"
    manifest = json.loads(staged_manifest.read_text(encoding="utf-8"))
    manifest["sha256"] = {n: _sha256_file(staging / n) for n in new if n != "manifest.json"}
    outputs.write_json(staged_manifest, manifest)

    old_path = out / "manifest.json"
    stale: dict[str, str] = {}
    try:
        old = json.loads(old_path.read_text(encoding="utf-8")) if old_path.is_file() else {}
    except (OSError, ValueError):
        old = {}
    listed = old.get("files", []) if isinstance(old, dict) else []
    digests = old.get("sha256", {}) if isinstance(old, dict) else {}
    if not isinstance(digests, dict):
        digests = {}
    kept: list[str] = []
    for name in listed if isinstance(listed, list) else []:
        if not isinstance(name, str) or name in new or name == "manifest.json":
            continue
        target = out / name
        plain = (name not in ("", ".", "..") and "/" not in name and "\\" not in name
                 and not name.startswith("."))
        if not plain or not os.path.lexists(target):
            continue
        digest = digests.get(name)
        try:
            ours = (isinstance(digest, str) and stat.S_ISREG(os.lstat(target).st_mode)
                    and _sha256_file(target) == digest)
        except OSError:
            ours = False
        if ours:
            stale[name] = str(digest)
        else:
            kept.append(name)
    if old_path.is_file() and not old_path.is_symlink():
        old_path.unlink()
    for name in sorted(stale):
        (out / name).unlink(missing_ok=True)
    for name in new:
        if name != "manifest.json":
            (staging / name).replace(out / name)
    staged_manifest.replace(old_path)
    if kept:
        click.echo(
            f"note: kept {len(kept)} file(s) in {out} that the previous manifest lists but that "
            f"this run cannot prove it wrote (changed since, or no checksum): "
            f"{', '.join(sorted(kept))}",
            err=True,
        )


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
    from .export import export
    from .fis import fis, surface
    from .sweep import optimize, sweep

    for command in (sweep, optimize, fis, surface, export):
        main.add_command(command)


_register_subcommands()

if __name__ == "__main__":  # pragma: no cover
    main()
