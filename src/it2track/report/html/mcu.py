"""The page's microcontroller section: what one step of the study's controller costs on the
simulated ATmega328P and its Cortex-M4F code size, per type reducer (from
:class:`~it2track.report.mcu_job.McuCosts`); or why it was not measured and how to measure it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from markupsafe import Markup

from ...codegen.mcu import (
    ARM_FLAGS,
    AVR_CLOCK_HZ,
    AVR_FLAGS,
    CONTROL_PERIOD_S,
)
from ...codegen.tools import MCU_PACKAGES
from ..mcu_job import (
    TABLE_NAME,
    McuCosts,
    McuStatus,
    install_command,
    remeasure_commands,
)
from .env import render

__all__ = ["mcu_section"]

#: The reducer the study simulates (:func:`it2track.paper.heading_fls`'s default).
STUDY_REDUCER = "exhaustive"


def _rows(costs: McuCosts) -> list[dict[str, Any]]:
    assert costs.table is not None
    return [{
        "controller": r.label,
        "study": r.reducer in (STUDY_REDUCER, "type-1") and r.arithmetic == "float",
        "cycles_max": f"{r.cycles_max:,}", "cycles_mean": f"{r.cycles_mean:,.0f}",
        "us_max": f"{r.us_max:,.0f}", "us_mean": f"{r.us_mean:,.0f}",
        "share": f"{100 * r.period_share:.1f} %", "flash": f"{r.flash:,}",
        "program": f"{r.program_flash:,}", "ram": f"{r.ram:,}", "stack": f"{r.stack:,}",
        "arm": "—" if r.arm_text is None else f"{r.arm_text:,}",
        "error": f"{r.error:.1e}", "bound": f"{r.bound:.1e}",
    } for r in costs.table.rows]


def mcu_section(costs: McuCosts, figure: Mapping[str, Any] | None = None) -> Markup:
    """The section for ``costs``.

    Parameters
    ----------
    costs : McuCosts
        The measurement's outcome; a skipped, failed or toolless one gives the reason and the
        way to measure.
    figure : dict, optional
        The cost figure's ``number, src, name`` on the page (see
        :func:`~it2track.report.html.results.figure_refs`); its title and caption are set here.
    """
    table = costs.table
    fig = None
    if figure is not None and table is not None:
        fig = {**figure, "title": "What one controller step costs on a microcontroller",
               "caption": (
                   f"Left: worst (bar) and mean (tick) time of one step of the paper's controller "
                   f"(FoU {table.fou:g}) on the ATmega328P at {AVR_CLOCK_HZ / 1e6:g} MHz, per "
                   f"type reducer, over the {table.n_points:,} measured inputs; the dashed line "
                   "marks 1 ms. Rows marked q15 are the integer-only fixed-point build. Right: "
                   "flash of the controller object (code and tables) on the ATmega328P and the "
                   "Cortex-M4F. Blue: exact reducers; orange: approximate.")}
    exact = None if table is None else all(r.equals_host for r in table.rows)
    return render(
        "sections/mcu.html.j2",
        status=costs.status.value,
        measured=costs.status is McuStatus.MEASURED,
        fou=f"{costs.fou:g}",
        grid=costs.grid,
        inputs=f"{costs.grid ** 2:,}",
        rows=_rows(costs) if table is not None else [],
        tools=sorted(table.tools.items()) if table is not None else [],
        exact=exact,
        seconds=f"{costs.seconds:.1f}",
        figure=fig,
        missing=", ".join(costs.missing),
        install=install_command(costs.missing) if costs.missing else "",
        reason=costs.reason,
        avr_flags=" ".join(AVR_FLAGS),
        arm_flags=" ".join(ARM_FLAGS),
        clock=f"{AVR_CLOCK_HZ / 1e6:g}",
        period=f"{CONTROL_PERIOD_S * 1e3:g}",
        table_name=TABLE_NAME,
        commands=remeasure_commands(costs.fou),
        reducer=STUDY_REDUCER,
        packages=", ".join(MCU_PACKAGES),
    )
