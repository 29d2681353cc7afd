"""``it2track`` command line: a friendly outer layer over the strict library.

Strings from the command line are mapped to the library's strategy objects here (controller
kinds, reducers, trajectories); everything below works with dataclasses and arrays.
"""

from __future__ import annotations

import atexit
import gc
import json
import re
from typing import Any, NoReturn

import click

from .. import __version__
from .options import DURATION_TYPE, FINITE, POSITIVE
from .outdir import check_output_file, write_output_file
from .target import apply_target_options

__all__ = ["main"]

#: PD gains used by ``it2track simulate --controller pd`` unless given: close to the study's
#: effort-matched PD at sigma = 0.05 rad (the study re-tunes on every run; see its report).
DEFAULT_PD = {"kp": 6.0, "kd": 0.2}


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="it2track")
def main() -> None:
    """Interval type-2 fuzzy trajectory tracking: simulate, reproduce the paper, sweep, optimise."""
    _skip_final_collection()


_EXIT_HOOK: list[bool] = []


def _skip_final_collection() -> None:
    """Spare the process the interpreter's cyclic garbage collections as it exits.

    After a command has finished, everything it allocated is about to go back to the system;
    tearing the interpreter down still traverses every object (a few hundred thousand after a
    study) several times, about 0.5 s of a 7 s ``reproduce --quick``. ``gc.freeze`` as an
    atexit hook moves them out of the collector's sight before that. Files are closed by the
    commands themselves; nothing is left for a collection to flush. Registered once per
    process, whatever the number of commands run in it.
    """
    if not _EXIT_HOOK:
        atexit.register(gc.freeze)
        _EXIT_HOOK.append(True)


def _fail(message: str) -> NoReturn:
    raise click.ClickException(message)


# --------------------------------------------------------------------------------------------
# simulate
# --------------------------------------------------------------------------------------------


@main.command()
@click.option("--trajectory", default="straight", show_default=True,
              help="straight | curved | sinusoidal, or a waypoint CSV file (t,x,y).")
@click.option("--plant", "plant", default="kinematic", show_default=True,
              help="kinematic (the paper's robot) | mujoco | a TOML file with a [plant] table "
              "(e.g. kind = \"lti\" with num/den or A/B/C/D: any linear plant).")
@click.option("--friction", default=None,
              help="Tyre-ground friction of --plant mujoco: dry | wet | icy (mu 0.8, 0.5, 0.1) "
              "or a friction coefficient (default dry; docs/guide/mujoco.md).")
@click.option("--step", "step", type=FINITE, default=None,
              help="Step reference for a single-input --plant (its first output follows it).")
@click.option("--controller", "controller", default="it2", show_default=True,
              type=click.Choice(["flc", "it2", "t1-matched", "pd"]),
              help="Heading controller (t1-matched: type-1 FLC with the IT2FLC's dead zone).")
@click.option("--controller-file", type=click.Path(exists=True, dir_okay=False),
              help="Fuzzy controller file (.toml/.t2fis/.fis/.fll/.fml/.fcl) instead of "
                   "--controller.")
@click.option("--fou", default=0.2, show_default=True, type=FINITE,
              help="FoU width for it2 / t1-matched.")
@click.option("--reducer", default="exhaustive", show_default=True,
              type=click.Choice(["km", "ekm", "eiasc", "exhaustive", "nie-tan", "wu-mendel"]))
@click.option("--ke", default=1.0, show_default=True, type=FINITE, help="Error input gain.")
@click.option("--kde", default=1.0, show_default=True, type=FINITE, help="Error-change gain.")
@click.option("--kp", default=DEFAULT_PD["kp"], show_default=True, type=FINITE, help="PD gain.")
@click.option("--kd", default=DEFAULT_PD["kd"], show_default=True, type=FINITE, help="PD gain.")
@click.option("--noise-std", default=0.05, show_default=True, type=FINITE,
              help="Heading noise standard deviation, rad.")
@click.option("--noise-power", type=FINITE, default=None,
              help="Simulink band-limited white noise power instead of --noise-std "
              "(sigma = sqrt(P / Ts_noise)).")
@click.option("--noise-rate", default=100.0, show_default=True, type=POSITIVE, help="Hz.")
@click.option("--seed", default=0, show_default=True, type=int, help="Noise realisation index.")
@click.option("--base-seed", default=0, show_default=True, type=int, help="Base seed.")
@click.option("--duration", default=10.0, show_default=True, type=DURATION_TYPE,
              help="s (at most 3600, as in every config).")
@click.option("--ts", default=0.01, show_default=True, type=POSITIVE,
              help="Control period, s.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as one JSON object.")
@click.option("--trace", type=click.Path(dir_okay=False),
              help="Save the time series to this CSV file (and its SHA-256 to FILE.sha256).")
@click.option("--force", is_flag=True,
              help="Replace an existing --trace file that it2track cannot prove it wrote.")
@apply_target_options
def simulate(**opts: Any) -> None:
    """Simulate one scenario and print its metrics.

    The robot follows --trajectory; a single-input --plant (a motor, a tank...) follows a --step
    reference instead, its measured output noisy by --noise-std.
    """
    from ..codegen.tools import BuildError
    from ..experiments.specs import ControllerKind, ControllerSpec
    from ..plant import HeadingNoise
    from ..tracking import LoopConfig, RunTable, StepReference, check_task, get_trajectory
    from ..tracking import simulate as run
    from ..tracking.metrics import METRIC_UNITS
    from .kernels import kernel_stage
    from .target import check_target_options, on_target, target_summary

    _reject_inapplicable(click.get_current_context(), opts)
    check_target_options(opts)
    # Everything that can fail is checked before the simulation starts, each error naming
    # the option(s) it comes from.
    if opts["trace"] is not None:
        check_output_file(opts["trace"], "--trace", force=opts["force"])
    elif opts["force"]:
        _fail("--force applies only with --trace FILE")
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
        field = re.search(r"\b(fou|ke|kde|kp|kd)\b", str(exc))
        if field is not None and not opts["controller_file"]:
            value = opts[field[1]]  # the option the message is about, first
            source = f"--{field[1]} {value:g} ({source})"
        _fail(f"{source}: {exc}")
    controller = on_target(controller, opts)
    plant = _plant_option(opts["plant"], opts["friction"])
    target: Any
    if opts["step"] is not None:
        try:
            target = StepReference(amplitude=opts["step"], name=f"step {opts['step']:g}")
        except ValueError as exc:
            _fail(f"--step {opts['step']}: {exc}")
    else:
        try:
            target = get_trajectory(opts["trajectory"])
        except (ValueError, OSError) as exc:
            _fail(f"--trajectory {opts['trajectory']}: {exc}")
    try:
        config = LoopConfig(duration=opts["duration"], ts=opts["ts"],
                            noise_rate=opts["noise_rate"], seed=opts["base_seed"], plant=plant)
    except ValueError as exc:
        _fail(f"--duration {opts['duration']:g} / --ts {opts['ts']:g} / --noise-rate "
              f"{opts['noise_rate']:g} / --base-seed {opts['base_seed']}: {exc}")
    try:
        check_task([target], config)
    except ValueError as exc:
        given = (f"--step {opts['step']:g}" if opts["step"] is not None
                 else f"--trajectory {opts['trajectory']}")
        hint = ("; a single-input plant follows --step" if opts["step"] is None
                else "; the robot follows --trajectory")
        _fail(f"--plant {opts['plant']} with {given}: {exc}{hint}")
    try:
        runs = RunTable(0, 0, sigma, opts["seed"])
    except ValueError as exc:
        noise_opt = "--noise-power" if opts["noise_power"] is not None else "--noise-std"
        _fail(f"--seed {opts['seed']} / {noise_opt}: {exc}")
    try:
        with kernel_stage(progress=True):
            trace = run([controller], [target], runs, config)
    except ValueError as exc:
        _fail(f"the simulation stopped: {exc}")
    except BuildError as exc:
        _fail(f"--target {opts['target_mcu']}: {exc}")
    metrics = {k: float(v[0]) for k, v in trace.metrics.items()}
    metrics.update(target_summary(trace, opts))
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
        write_output_file(opts["trace"], buf.getvalue().encode("utf-8"), "--trace")
    if opts["as_json"]:
        click.echo(json.dumps(metrics))
        return
    unit = "rad" if plant is None else "(output units)"
    label = controller.name if opts["target_mcu"] != "host" else spec.label
    click.echo(f"{label} on {target.name}, sigma = {sigma:g} {unit}, seed {opts['seed']}, "
               f"{opts['duration']:g} s" + ("" if plant is None else f", plant {opts['plant']}"))
    units = {**METRIC_UNITS, "mcu_cycles_mean": "cycles", "mcu_cycles_max": "cycles",
             "mcu_latency_max_ms": "ms"}  # (target_summary's, on the simulated MCU)
    width = max(len(k) for k in metrics)
    values = {k: f"{v:.6g}" for k, v in metrics.items()}
    vwidth = max(len(v) for v in values.values())
    for key, value in values.items():
        click.echo(f"  {key:<{width}}  {value:>{vwidth}}  {units[key]}")


def _plant_option(value: str, friction: str | None = None) -> Any:
    """The plant ``--plant`` names: ``kinematic`` (None), ``mujoco`` (on the ``--friction``
    surface), or a TOML plant file."""
    from ..plant.specs import load_plant, plant_from_dict

    if friction is not None and value != "mujoco":
        _fail(f"--friction applies only with --plant mujoco, not --plant {value} (the kinematic "
              "robot never slips; a plant file gives its own surface)")
    try:
        if value == "mujoco" and friction is not None:
            return plant_from_dict({"kind": "mujoco", "surface": _surface(friction)},
                                   where=f"--plant mujoco --friction {friction}")
        if value in ("kinematic", "mujoco"):
            return plant_from_dict({"kind": value}, where="--plant")
        if not value.lower().endswith(".toml"):
            _fail(f"--plant {value}: give kinematic, mujoco or a .toml plant file")
        return load_plant(value)
    except (ValueError, ImportError) as exc:
        _fail(f"--plant {value}: {exc}" if not str(exc).startswith("--plant") else str(exc))
    except OSError as exc:
        _fail(f"--plant {value}: cannot read: {exc.strerror or exc}")


def _surface(friction: str) -> str | float:
    """``--friction``'s value: a surface name, or the friction coefficient it spells."""
    from ..plant.mujoco_model import SURFACES

    if friction in SURFACES:
        return friction
    try:
        return float(friction)
    except ValueError:
        _fail(f"--friction {friction!r} must be one of {', '.join(SURFACES)} or a friction "
              "coefficient")


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
    if given("step") and given("trajectory"):
        _fail("give either --trajectory (the robot) or --step (a single-input --plant), not both")


def _register_subcommands() -> None:
    """Attach the commands that live in their own modules."""
    from .config import config
    from .export import export
    from .fis import fis, surface
    from .kernels import compile_kernels
    from .reproduce import reproduce
    from .sweep import optimize, sweep

    for command in (reproduce, sweep, optimize, config, fis, surface, export, compile_kernels):
        main.add_command(command)


_register_subcommands()

if __name__ == "__main__":  # pragma: no cover
    main()
