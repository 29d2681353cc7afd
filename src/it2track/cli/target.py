"""``it2track simulate --target atmega328p``: the controller as the simulated MCU runs it.

The options (:data:`TARGET_OPTIONS`) are checked before anything runs; :func:`on_target` turns
the controller ``simulate`` built into a processor-in-the-loop controller
(:class:`~it2track.tracking.pil.PilHeadingController`), naming the option at fault when the
controller has no C form or a tool is missing.
"""

from __future__ import annotations

from typing import Any, NoReturn

import click

__all__ = ["TARGETS", "apply_target_options", "check_target_options", "on_target", "target_summary"]

#: ``--target`` values: the host (the controller in Python or its compiled engine) or the
#: simulated ATmega328P.
TARGETS = ("host", "atmega328p")
LATENCIES = ("none", "measured", "period")
REALS = ("float", "q15")


def apply_target_options(f: Any) -> Any:
    """Decorate ``simulate`` with ``--target``, ``--latency`` and ``--real``."""
    for option in reversed((
        click.option("--target", "target_mcu", type=click.Choice(TARGETS), default="host",
                     show_default=True,
                     help="Where the controller runs: host, or atmega328p -- its generated C "
                     "on the simulated ATmega328P at 16 MHz every period (processor in the "
                     "loop; needs libsimavr-dev, gcc-avr, avr-libc, binutils-avr, gcc)."),
        click.option("--latency", type=click.Choice(LATENCIES), default=None,
                     help="With --target atmega328p: when the output reaches the motors -- at "
                     "once (none), after the call's measured cycles (measured, the default), or "
                     "one period late (period)."),
        click.option("--real", "target_real", type=click.Choice(REALS), default=None,
                     help="With --target atmega328p: the C arithmetic, float (default) or q15 "
                     "fixed point."),
    )):
        f = option(f)
    return f


def _fail(message: str) -> NoReturn:
    raise click.ClickException(message)


def check_target_options(opts: dict[str, Any]) -> None:
    """``--latency`` and ``--real`` only with ``--target atmega328p``; the PD controller has
    no C form."""
    if opts["target_mcu"] == "host":
        for key, option in (("latency", "--latency"), ("target_real", "--real")):
            if opts[key] is not None:
                _fail(f"{option} applies to --target atmega328p only")
        return
    if not opts["controller_file"] and opts["controller"] == "pd":
        _fail("--target atmega328p runs the generated C of a fuzzy (Sugeno) controller; "
              "--controller pd has none")


def on_target(controller: Any, opts: dict[str, Any]) -> Any:
    """``controller`` itself for ``--target host``; else its processor-in-the-loop form."""
    if opts["target_mcu"] == "host":
        return controller
    from ..codegen import RealType, generate_c
    from ..codegen.tools import PIL_TOOLS, ToolMissingError, require
    from ..fuzzy import IT2Sugeno, T1Sugeno
    from ..tracking import FuzzyHeadingController
    from ..tracking.pil import PilHeadingController

    fls = getattr(controller, "fls", None)
    source = (f"--controller-file {opts['controller_file']}" if opts["controller_file"]
              else f"--controller {opts['controller']}")
    if not isinstance(controller, FuzzyHeadingController) or not isinstance(
            fls, IT2Sugeno | T1Sugeno):
        _fail(f"--target atmega328p: {source} is not a Sugeno fuzzy system, which is what the "
              "C generator compiles")
    real = RealType(opts["target_real"] or "float")
    try:
        code = generate_c(fls, real=real)
    except ValueError as exc:
        _fail(f"--target atmega328p --real {real.value}: {source}: {exc}")
    try:
        require(PIL_TOOLS)
    except ToolMissingError as exc:
        _fail(f"--target atmega328p {exc}")
    return PilHeadingController(code=code, ke=controller.ke, kde=controller.kde,
                                latency=opts["latency"] or "measured",  # type: ignore[arg-type]
                                name=f"{controller.name} on the ATmega328P ({real.value})")


def target_summary(trace: Any, opts: dict[str, Any]) -> dict[str, float]:
    """Cycle figures of a ``--target atmega328p`` run (empty for the host)."""
    if opts["target_mcu"] == "host":
        return {}
    from ..codegen.mcu import AVR_CLOCK_HZ

    cycles = trace["cycles"][0]
    return {"mcu_cycles_mean": float(cycles.mean()), "mcu_cycles_max": float(cycles.max()),
            "mcu_latency_max_ms": float(cycles.max() / AVR_CLOCK_HZ * 1e3)}
