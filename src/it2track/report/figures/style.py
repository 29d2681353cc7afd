"""Look and output of every study figure: rcParams, colours by controller identity, and the
atomic PNG + SVG writer.

Figures are :class:`matplotlib.figure.Figure` objects created directly (no pyplot, so no global
figure registry and no backend state leaks into the caller). Styles are applied with
:func:`matplotlib.rc_context`, so the caller's rcParams are untouched; SVG ids and metadata are
fixed so that reruns are byte-identical.
"""

from __future__ import annotations

import io
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
import PIL.Image
from matplotlib.figure import Figure
from matplotlib.gridspec import GridSpec

from ...atomicfile import atomic_open
from ..identity import _FLC, _IT2, _PD, _T1M, _T1S, INTEGRAL_UNITS, _Ctrl, _order_key

__all__ = ["DRAFT_DPI", "FIGURE_DPI"]

#: Resolution of the PNG files, dots per inch.
FIGURE_DPI = 110
#: Resolution of the draft PNGs of a smoke run (``reproduce --quick``), written without the
#: palette quantisation and with unhinted text: about a third less CPU per figure.
DRAFT_DPI = 80

_RC: dict[str, Any] = {
    "font.size": 9,
    "axes.titlesize": 9.5,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "svg.hashsalt": "it2track",
    "svg.fonttype": "path",
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
}

#: What a draft changes in :data:`_RC`: FreeType hinting costs more than drawing the glyphs.
_DRAFT_RC: dict[str, Any] = {"text.hinting": "no_hinting"}
#: A draft's subplot spacing (fractions of the figure, and of an axes for the gaps), in place
#: of the constrained layout of the full figures.
_DRAFT_SPACING: dict[str, float] = {"left": 0.08, "right": 0.96, "bottom": 0.12, "top": 0.88,
                                    "wspace": 0.4, "hspace": 0.6}

_FLC_COLOR = "#d62728"
_PD_COLOR = "#7f7f7f"
_REF_COLOR = "#222222"
_EXTRA_COLORS = ("#ff7f0e", "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#1f77b4")


@dataclass(frozen=True)
class _Style:
    color: str
    ls: str | tuple[float, tuple[float, ...]]
    hatch: str | None
    marker: str


class _Palette:
    """Consistent colours: FLC red, IT2FLC(w) along viridis by width (the type-1 baselines of
    the same width share the colour: dead-zone-matched dashed / hatched ``///``, slope-matched
    dotted / ``xx``; a tuned controller its untuned colour, dash-dotted / ``++``), PD grey,
    other controllers tab colours.

    The other controllers' colours are fixed up front from ``controllers`` (in
    :func:`~it2track.report.identity._order_key` order), so that a controller has one colour in
    every figure, whichever figure is drawn first and in whichever process.
    """

    def __init__(self, fous: Iterable[float], controllers: Iterable[_Ctrl] = ()) -> None:
        self.fous = sorted({float(w) for w in fous if w > 0})
        self.extra: dict[str, str] = {}
        for c in sorted(controllers, key=_order_key):
            if c.kind not in (_FLC, _IT2, _T1M, _T1S, _PD):
                self.style(c)

    def fou_color(self, w: float) -> str:
        cmap = matplotlib.colormaps["viridis"]
        if not self.fous or len(self.fous) == 1:
            pos = 0.35
        else:
            lo, hi = self.fous[0], self.fous[-1]
            pos = 0.05 + 0.7 * (min(max(w, lo), hi) - lo) / (hi - lo)
        r, g, b, _ = cmap(pos)
        return f"#{round(r * 255):02x}{round(g * 255):02x}{round(b * 255):02x}"

    def style(self, c: _Ctrl) -> _Style:
        if c.tuned and c.kind in (_FLC, _IT2):
            color = _FLC_COLOR if c.kind is _FLC else self.fou_color(c.fou)
            return _Style(color, (0, (5, 1.5, 1, 1.5)), "++", "P")
        if c.kind is _FLC:
            return _Style(_FLC_COLOR, "-", None, "o")
        if c.kind is _IT2:
            return _Style(self.fou_color(c.fou), "-", None, "s")
        if c.kind is _T1M:
            return _Style(self.fou_color(c.fou), "--", "///", "^")
        if c.kind is _T1S:
            return _Style(self.fou_color(c.fou), ":", "xx", "v")
        if c.kind is _PD:
            return _Style(_PD_COLOR, "-.", "..", "D")
        if c.label not in self.extra:
            self.extra[c.label] = _EXTRA_COLORS[len(self.extra) % len(_EXTRA_COLORS)]
        return _Style(self.extra[c.label], ":", "xx", "v")


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------


def _save(fig: Figure, out_dir: Path, stem: str, *, svg: bool = True,
          draft: bool = False) -> Path:
    png = out_dir / f"{stem}.png"
    buf = io.BytesIO()
    if draft:  # straight from matplotlib, fast zlib, no quantisation
        # and no constrained layout, which measures every label twice (a fifth of a figure's
        # CPU): the grid's fixed spacing, widened so that titles clear the row above.
        fig.set_layout_engine("none")
        # (a title wider than the figure wraps rather than running off both edges)
        title = getattr(fig, "_suptitle", None)
        if title is not None:
            title.set_wrap(True)
        grids = set()
        for ax in fig.axes:
            spec = ax.get_subplotspec()
            if spec is not None:
                grids.add(spec.get_topmost_subplotspec().get_gridspec())
        for grid in grids:
            if isinstance(grid, GridSpec):  # a figure's own grid (not a nested one)
                grid.update(**_DRAFT_SPACING)
        fig.savefig(buf, format="png", dpi=DRAFT_DPI, pil_kwargs={"compress_level": 1})
        data = buf.getvalue()
    else:
        fig.savefig(buf, format="png", dpi=FIGURE_DPI, pil_kwargs={"compress_level": 0})
        data = _compact_png(buf.getvalue())
    with atomic_open(png, "wb") as fh:
        fh.write(data)
    if svg:
        # The constrained layout has been computed by the PNG draw; freeze it for the SVG (the
        # layout is in figure fractions, so it does not depend on the dpi).
        fig.set_layout_engine("none")
        with atomic_open(out_dir / f"{stem}.svg", "wb") as fh:
            fig.savefig(fh, format="svg", metadata={"Date": None, "Creator": None})
    # (no fig.clear(): it resets every axes to a fresh one, about 5 % of a figure's CPU, for
    # a figure that nothing refers to any more)
    return png


def _compact_png(data: bytes) -> bytes:
    """Re-encode as a 256-colour palette PNG (about a third of the size, visually identical for
    these line and surface plots; the HTML report embeds the PNGs).

    Median cut, not the 7x faster octree: octree quantisation bands the control surfaces'
    diverging colour map (the light colours near u = 0 all became white, widening the dead zone
    to the eye). zlib level 6, not 9: level 9 took 3-6x as long for files about 5 % smaller.
    """
    with PIL.Image.open(io.BytesIO(data)) as im:
        pal = im.convert("RGB").quantize(
            colors=256, method=PIL.Image.Quantize.MEDIANCUT, dither=PIL.Image.Dither.NONE
        )
    out = io.BytesIO()
    pal.save(out, format="PNG", compress_level=6)
    return out.getvalue()


def _metric_label(metric: str) -> str:
    unit = INTEGRAL_UNITS.get(metric)
    return f"{metric} ({unit})" if unit else metric
