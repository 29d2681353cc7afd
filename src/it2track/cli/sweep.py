"""``it2track sweep`` and ``it2track optimize``: resumable sweeps and FoU optimisation.

Both run in this process by default, on ``--workers N`` local processes, or on a Dask cluster
named by ``--scheduler tcp://HOST:PORT``; the numbers do not depend on the choice. They are
registered on the ``it2track`` group (:mod:`it2track.cli.main`). Errors -- a bad
configuration, a refused store, a run that fails -- end the command with a message naming
the cause, not a traceback.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable
from concurrent.futures import BrokenExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from .config import ConfigFile
from .kernels import kernel_stage
from .options import WORKER_TIMEOUT_TYPE
from .outdir import check_outputs

if TYPE_CHECKING:
    from ..experiments.executors import Executor

__all__ = ["DASK_OPTIONS", "check_dask_options", "check_scheduler", "dask_options",
           "dask_settings", "optimize", "sweep"]

def check_scheduler(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
    """Click callback: a malformed ``--scheduler`` is an error before anything starts."""
    if value is None:
        return None
    from ..experiments.executors import ExecutorError, check_scheduler_address

    try:
        return check_scheduler_address(value)
    except ExecutorError as exc:
        raise click.BadParameter(str(exc)) from None


_WORKERS = click.option(
    "--workers", type=click.IntRange(min=0), default=0, show_default=True,
    help="Local worker processes (0: run in this process).",
)  # fmt: skip
_SCHEDULER = click.option(
    "--scheduler", metavar="tcp://HOST:PORT", default=None, callback=check_scheduler,
    help="Run on this Dask cluster (needs it2track[dask]; workers need it2track installed). "
    "Only on a trusted network, or with TLS: see README, 'Dask: trust model'.",
)  # fmt: skip
_PROGRESS = click.option(
    "--progress/--no-progress", default=True, show_default=True,
    help="Progress bar with ETA on stderr.",
)  # fmt: skip
_FILE = click.Path(exists=True, dir_okay=False)
#: Dask connection options shared by ``sweep``, ``optimize`` and ``reproduce``.
DASK_OPTIONS = (
    click.option("--tls-ca-file", type=_FILE, default=None,
                 help="Dask TLS: CA certificate of the cluster (PEM); needs tls://HOST:PORT."),
    click.option("--tls-cert", type=_FILE, default=None,
                 help="Dask TLS: this client's certificate (PEM)."),
    click.option("--tls-key", type=_FILE, default=None,
                 help="Dask TLS: this client's private key (PEM), if not in --tls-cert."),
    click.option("--worker-timeout", type=WORKER_TIMEOUT_TYPE, default=60.0, show_default=True,
                 help="Dask: seconds to wait for a worker when the scheduler has none "
                 "(at most a week)."),
)


def dask_options(f: Any) -> Any:
    """Decorator adding :data:`DASK_OPTIONS` to a command."""
    for option in reversed(DASK_OPTIONS):
        f = option(f)
    return f


def check_dask_options(ctx: click.Context, scheduler: str | None) -> None:
    """The Dask options (TLS files, ``--worker-timeout``) given without ``--scheduler`` would be
    ignored: refuse them before any work, naming each (the policy of ``simulate``'s options
    that do not apply)."""
    from click.core import ParameterSource

    if scheduler is not None:
        return
    for name in ("tls_ca_file", "tls_cert", "tls_key", "worker_timeout"):
        if ctx.get_parameter_source(name) in (ParameterSource.COMMANDLINE,
                                              ParameterSource.ENVIRONMENT):
            value = ctx.params[name]
            raise click.UsageError(
                f"--{name.replace('_', '-')} {value if isinstance(value, str) else f'{value:g}'}"
                " applies only to a Dask cluster: add --scheduler tls://HOST:PORT (or "
                "tcp://) or drop it", ctx)


def dask_settings(
    tls_ca_file: str | None, tls_cert: str | None, tls_key: str | None, worker_timeout: float
) -> dict[str, Any]:
    """``make_executor`` keyword arguments for the Dask options (errors as ClickException)."""
    from ..experiments.executors import DaskSecurity, ExecutorError

    try:
        security = DaskSecurity(ca_file=tls_ca_file or "", cert=tls_cert or "",
                                key=tls_key or "")
    except ExecutorError as exc:
        raise click.ClickException(str(exc)) from None
    return {"security": security, "worker_timeout": worker_timeout}


def _executor(workers: int, scheduler: str | None, dask: dict[str, Any]) -> Executor:
    from ..experiments.executors import ExecutorError, make_executor

    try:
        return make_executor(workers=workers or None, scheduler=scheduler, **dask)
    except ExecutorError as exc:
        raise click.ClickException(str(exc)) from None


def _check_out_dir(out_dir: str, files: tuple[str, ...] = ()) -> None:
    """``--out`` must name a folder that exists or can be created, and the result ``files``
    in it must be absent or regular files -- checked before any work, not after it."""
    from ..atomicfile import NotRegularFileError, check_can_create_in, check_replaceable

    if not out_dir:
        raise click.ClickException("--out '' is empty: give an output folder")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise click.ClickException(f"--out {out_dir} exists and is not a folder")
    if os.path.islink(out) and not out.exists():
        raise click.ClickException(f"--out {out_dir} is a symbolic link to "
                                   f"{os.readlink(out)!r}, which does not exist")
    parent = next((p for p in (out, *out.parents) if p.exists()), Path("."))
    if not parent.is_dir():
        raise click.ClickException(f"--out {out_dir}: {parent} is not a folder")
    try:
        check_can_create_in(parent)
    except OSError as exc:
        where = "" if parent == out else f" (in {parent})"
        raise click.ClickException(f"--out {out_dir}: cannot write into the folder{where}: "
                                   f"{exc.strerror or type(exc).__name__}") from None
    for name in files:
        try:
            check_replaceable(out / name)
        except NotRegularFileError as exc:
            raise click.ClickException(f"--out {out_dir}: {out / name} {exc.strerror}") from None


@click.command("sweep")
@click.option("--config", "config_path", required=True, type=ConfigFile(),
              help="Sweep TOML file, or the name of a packaged config (sweep: an example).")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False),
              help="Results directory (sweep.json, chunks/, results.csv).")
@click.option("--resume", is_flag=True,
              help="Continue the sweep in OUT (same config), skipping finished chunks.")
@click.option("--force", is_flag=True,
              help="Replace an OUT/results.csv that it2track cannot prove it wrote (no "
              "matching results.csv.sha256).")
@_WORKERS
@_SCHEDULER
@dask_options
@_PROGRESS
@click.pass_context
def sweep(
    ctx: click.Context,
    config_path: str,
    out_dir: str,
    resume: bool,
    force: bool,
    workers: int,
    scheduler: str | None,
    progress: bool,
    **dask: Any,
) -> None:
    """Simulate the cartesian product of the config's axes into a resumable store.

    Every finished chunk is saved durably (DIR/chunks/chunk-NNNNNN.csv); kill the command at
    any moment and rerun it with --resume to finish: DIR/results.csv comes out identical to an
    uninterrupted run's. A results.csv already in DIR is replaced only if its results.csv.sha256
    matches (it2track wrote it), or with --force.
    """
    from ..authorship import proven_by_sidecar
    from ..experiments.specs import ConfigError
    from ..experiments.sweep import StoreError, load_sweep_config, run_sweep

    check_dask_options(ctx, scheduler)
    _check_out_dir(out_dir)
    check_outputs([Path(out_dir) / "results.csv"], option=f"--out {out_dir}", force=force,
                  proof=proven_by_sidecar, sidecars=True)
    try:
        plan = load_sweep_config(config_path)
    except ConfigError as exc:
        raise click.ClickException(str(exc)) from None
    out = Path(out_dir)
    executor = _executor(workers, scheduler, dask_settings(**dask))
    click.echo(
        f"sweep {plan.config_hash()[:12]}: {plan.n_runs} runs in {len(plan.chunks())} chunks "
        f"({len(plan.robots)} plant set(s) x {len(plan.controllers)} controller(s) x "
        f"{len(plan.trajectory_refs)} trajector(ies) x {len(plan.noise_std)} noise level(s) x "
        f"{len(plan.seeds)} seed(s)) on {executor!r}",
        err=True,
    )
    try:
        with kernel_stage(progress=progress,
                          run_steps=plan.n_runs * plan.config.n_steps), executor:
            summary = run_sweep(plan, out, executor=executor, resume=resume,
                                progress=progress, force=force)
    except (StoreError, ConfigError) as exc:
        raise click.ClickException(str(exc)) from None
    except BrokenExecutor as exc:
        saved = len(list((out / "chunks").glob("chunk-*.csv.sha256")))
        raise click.ClickException(
            f"a worker process died ({exc}); {saved} finished chunks are saved in {out}: "
            "rerun with --resume"
        ) from None
    except (ValueError, OSError) as exc:
        saved = len(list((out / "chunks").glob("chunk-*.csv.sha256")))
        raise click.ClickException(
            f"the sweep stopped: {type(exc).__name__}: {exc}; {saved} finished chunks are "
            f"saved in {out}: remove the cause and rerun with --resume"
        ) from None
    except KeyboardInterrupt:
        saved = len(list((out / "chunks").glob("chunk-*.csv.sha256")))
        click.echo(
            f"\ninterrupted: {saved} of {len(plan.chunks())} chunks saved in {out}; "
            "rerun with --resume to finish",
            err=True,
        )
        ctx.exit(130)
    click.echo(
        f"{summary.runs_computed} runs computed ({summary.chunks_computed} chunks, "
        f"{summary.chunks_skipped} already done) in {summary.seconds:.1f} s "
        f"({summary.runs_per_second:.0f} runs/s) -> {out / 'results.csv'}"
    )


#: The files ``optimize`` writes into ``--out``.
_OPTIMIZE_FILES = ("optimize.json", "optimize.md", "convergence.png")


def _optimize_proof(out: Path) -> Callable[[Path], bool]:
    """Proof of authorship in ``out``: the sealed ``optimize.json`` of a previous run lists the
    other files with their SHA-256 (and proves itself by its seal)."""
    from ..authorship import proven_by_digests, read_sealed_json

    old = read_sealed_json(out / "optimize.json")
    listed = proven_by_digests(old.get("sha256") if old is not None else None)
    return lambda p: old is not None if p.name == "optimize.json" else listed(p)


@click.command("optimize")
@click.option("--config", "config_path", required=True, type=ConfigFile(),
              help="Optimisation TOML file, or the name of a packaged config (optimize: the "
              "paper's controller).")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False),
              help="Output directory (optimize.json, optimize.md, convergence.png).")
@click.option("--force", is_flag=True,
              help="Replace files in OUT of the names this command writes that it2track cannot "
              "prove it wrote (not listed with their SHA-256 in OUT's optimize.json).")
@_WORKERS
@_SCHEDULER
@dask_options
@_PROGRESS
def optimize(
    config_path: str, out_dir: str, force: bool, workers: int, scheduler: str | None,
    progress: bool, **dask: Any,
) -> None:
    """Find the FoU widths minimising the config's objective; verify on held-out seeds.

    Symmetric (one width: grid + bounded Brent) and asymmetric (six widths: differential
    evolution with a fixed seed) optima are compared with FoU 0.1/0.2/0.3 and the FLC on
    disjoint held-out seeds (paired differences with 95 % intervals). Files of those names
    already in OUT are replaced only if OUT's optimize.json (sealed by the run that wrote it)
    lists them with their SHA-256, or with --force.
    """
    from ..atomicfile import atomic_write_bytes
    from ..authorship import seal_json, sha256_bytes, sha256_file
    from ..experiments.optimize import load_optimize_config, run_optimization
    from ..experiments.specs import ConfigError

    check_dask_options(click.get_current_context(), scheduler)
    _check_out_dir(out_dir, files=_OPTIMIZE_FILES)
    check_outputs([Path(out_dir) / name for name in _OPTIMIZE_FILES],
                  option=f"--out {out_dir}", force=force, proof=_optimize_proof(Path(out_dir)))
    try:
        cfg = load_optimize_config(config_path)
    except ConfigError as exc:
        raise click.ClickException(str(exc)) from None
    out = Path(out_dir)
    t0 = time.perf_counter()
    try:
        # (an optimisation's evaluations are open-ended: it waits for the compiled loop)
        with kernel_stage(progress=progress, run_steps=math.inf), _executor(
                workers, scheduler, dask_settings(**dask)) as executor:
            result = run_optimization(
                cfg, executor=executor, progress=progress, log=lambda s: click.echo(s, err=True)
            )
    except BrokenExecutor as exc:
        raise click.ClickException(f"a worker process died ({exc}); nothing was written") from None
    except (ValueError, OSError) as exc:
        raise click.ClickException(
            f"the optimisation stopped: {type(exc).__name__}: {exc}; nothing was written"
        ) from None
    data = result.to_dict()
    data["command"] = {"config": config_path, "workers": workers, "scheduler": scheduler}
    from ..report.optimize_plot import plot_convergence  # matplotlib: only once needed

    # Checked again: a file may have appeared or changed while the optimisation ran.
    check_outputs([out / name for name in _OPTIMIZE_FILES], option=f"--out {out_dir}",
                  force=force, proof=_optimize_proof(out))
    try:
        out.mkdir(parents=True, exist_ok=True)
        markdown = result.to_markdown().encode()
        atomic_write_bytes(out / "optimize.md", markdown)
        refs = {c["name"]: c["train"] for c in result.verdict["controllers"] if not c["optimum"]}
        plot_convergence(result.history, out / "convergence.png", objective=result.objective,
                         references=refs)
        # optimize.json last, sealed, with the SHA-256 of the other two: the proof that lets
        # the next run replace them.
        data["sha256"] = {"optimize.md": sha256_bytes(markdown),
                          "convergence.png": sha256_file(out / "convergence.png")}
        atomic_write_bytes(out / "optimize.json",
                           (json.dumps(seal_json(data), indent=1) + "\n").encode())
    except OSError as exc:
        raise click.ClickException(
            f"cannot write the results to --out {out}: {exc.strerror or exc}") from None
    click.echo(result.to_markdown())
    click.echo(f"wrote {out / 'optimize.json'}, {out / 'optimize.md'}, "
               f"{out / 'convergence.png'} in {time.perf_counter() - t0:.1f} s")

