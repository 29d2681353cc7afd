"""The microcontroller cost figure draws from a CostTable (no toolchain needed) and is written
atomically as PNG or SVG."""

from __future__ import annotations

import pytest

from it2track.codegen.costs import CostRow, CostTable
from it2track.report.mcu import mcu_cost_figure, write_mcu_cost_figure


def _table(arm: bool = True) -> CostTable:
    rows = tuple(
        CostRow(label=label, reducer=red, arithmetic="float", exact=exact, cycles_max=cmax,
                cycles_mean=cmax * 0.8, flash=flash, program_flash=flash + 1100, ram=0,
                stack=300, error=2e-6, bound=1.2e-4, equals_host=True,
                arm_text=flash // 2 if arm else None)
        for label, red, exact, cmax, flash in [
            ("type-1 FLC (FoU 0)", "type-1", True, 6075, 1654),
            ("IT2 exhaustive", "exhaustive", True, 15655, 3040),
            ("IT2 nie-tan (approx.)", "nie-tan", False, 9352, 2002),
        ])
    return CostTable(rows=rows, n_points=100, fou=0.2, tools={})


def test_figure_has_one_bar_per_controller_in_microseconds():
    fig = mcu_cost_figure(_table())
    time_ax, size_ax = fig.axes[:2]
    widths = sorted(p.get_width() for p in time_ax.patches)
    assert widths == pytest.approx(sorted([6075 / 16, 15655 / 16, 9352 / 16]))
    ticks = sorted((t.get_position()[1], t.get_text()) for t in time_ax.get_yticklabels())
    # the table's first row at the top
    assert [text for _, text in ticks] == ["IT2 nie-tan (approx.)", "IT2 exhaustive",
                                           "type-1 FLC (FoU 0)"]
    assert len(size_ax.patches) == 6  # AVR and Cortex-M4F per controller
    assert len(mcu_cost_figure(_table(arm=False)).axes[1].patches) == 3


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG"), (".svg", b"<?xml")])
def test_written_atomically(tmp_path, suffix, magic):
    path = write_mcu_cost_figure(_table(), tmp_path / f"cost{suffix}")
    assert path.read_bytes().startswith(magic)
    assert [p.name for p in tmp_path.iterdir()] == [f"cost{suffix}"]
