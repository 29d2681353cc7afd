"""Figure: what one IT2FLC step costs on a microcontroller (from a
:class:`~it2track.codegen.costs.CostTable`).

Left: the worst and mean time of one controller step on the ATmega328P at 16 MHz (simavr cycle
counts) per type reducer and arithmetic (float plain, q15 fixed point hatched), against the
1 ms aim and the paper's 10 ms control period. Right: the code size on the ATmega328P
(controller object, tables included) and on the Cortex-M4F.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

from matplotlib.figure import Figure

from ..atomicfile import atomic_open
from ..codegen.costs import CostTable
from ..codegen.mcu import CONTROL_PERIOD_S

__all__ = ["mcu_cost_figure", "write_mcu_cost_figure"]


def mcu_cost_figure(table: CostTable) -> Figure:
    """The cost figure of ``table`` (a :class:`matplotlib.figure.Figure`, no pyplot)."""
    rows = list(table.rows)
    labels = [r.label for r in rows]
    ypos = list(range(len(rows)))[::-1]
    fig = Figure(figsize=(9.0, 0.42 * len(rows) + 2.2), layout="constrained")
    ax, bx = fig.subplots(1, 2, width_ratios=[1.6, 1.0], sharey=True)
    colors = ["#4c72b0" if r.exact else "#dd8452" for r in rows]
    bars = ax.barh(ypos, [r.us_max for r in rows], color=colors, height=0.62,
                   label="worst step")
    for bar, r in zip(bars.patches, rows, strict=True):
        if r.arithmetic != "float":
            bar.set_hatch("///")
            bar.set_edgecolor("white")
    ax.scatter([r.us_mean for r in rows], ypos, color="black", marker="|", s=160, zorder=3,
               label="mean step")
    for y, r in zip(ypos, rows, strict=True):
        ax.text(r.us_max, y, f" {r.us_max:,.0f} µs ({100 * r.period_share:.1f} %)",
                va="center", fontsize=8)
    ax.axvline(1000.0, color="0.35", linestyle="--", linewidth=1)
    ax.text(1000.0, max(ypos) + 0.55, "1 ms", ha="center", va="bottom", fontsize=8,
            color="0.35")
    ax.set_yticks(ypos, labels)
    top = max(r.us_max for r in rows)
    ax.set_xlim(0, max(top * 1.45, 1100.0))
    ax.set_xlabel(f"µs per step, ATmega328P @ 16 MHz (period {CONTROL_PERIOD_S * 1e3:g} ms "
                  f"= {CONTROL_PERIOD_S * 1e6:,.0f} µs)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8,
              frameon=False)
    ax.set_title("time of one controller step (simavr cycle counts)", fontsize=10)
    h = 0.38
    bx.barh([y + h / 2 for y in ypos], [r.flash for r in rows], height=h, color="#55a868",
            label="ATmega328P (object)")
    arm = [r.arm_text for r in rows]
    if all(v is not None for v in arm):
        bx.barh([y - h / 2 for y in ypos], [float(v or 0) for v in arm], height=h,
                color="#8172b2", label="Cortex-M4F (object)")
    bx.set_xlabel("flash bytes (code + tables)")
    bx.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1, fontsize=8,
              frameon=False)
    bx.set_title("code size", fontsize=10)
    for a in (ax, bx):
        a.spines[["top", "right"]].set_visible(False)
    fig.suptitle(f"What the IT2FLC costs on a microcontroller (paper controller, FoU "
                 f"{table.fou:g}; {table.n_points:,} inputs)\nblue: exact reducers, orange: "
                 "approximate; hatched: q15 fixed point", fontsize=10)
    return fig


def _palette_png(data: bytes) -> bytes:
    """Re-encode a PNG with a 256-colour palette (a third of the size for this bar chart)."""
    import PIL.Image

    with PIL.Image.open(io.BytesIO(data)) as im:
        pal = im.convert("RGB").quantize(colors=256, method=PIL.Image.Quantize.MEDIANCUT,
                                         dither=PIL.Image.Dither.NONE)
    out = io.BytesIO()
    pal.save(out, format="PNG", compress_level=9)
    return out.getvalue()


def write_mcu_cost_figure(table: CostTable, path: str | os.PathLike[str], *,
                          dpi: int = 90) -> Path:
    """Draw :func:`mcu_cost_figure` for ``table`` and write it atomically to ``path`` (PNG at
    ``dpi`` dots per inch, or SVG by suffix); returns the path."""
    target = Path(path)
    fmt = target.suffix.lstrip(".").lower() or "png"
    fig = mcu_cost_figure(table)
    buf = io.BytesIO()
    if fmt == "svg":
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None})
    else:
        fig.savefig(buf, format=fmt, dpi=dpi)
        if fmt == "png":
            buf = io.BytesIO(_palette_png(buf.getvalue()))
    with atomic_open(target, "wb") as fh:
        fh.write(buf.getvalue())
    return target
