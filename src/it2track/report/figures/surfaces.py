"""Control surfaces u(e, de) of the fuzzy controllers and their dead zone: the slice u(e, 0),
with the dead-zone edges ``|e| < 0.2 - w/2`` that the FoU narrows.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from ...experiments.study import StudyResult
from ...tracking import FuzzyHeadingController
from ..identity import (
    _FLC,
    _IT2,
    _MATCHED,
    _PAPER_FUZZY,
    _T1S,
    _Ctrl,
    _dead_zone,
    _input_gains,
    _order_key,
    _surface_info,
    surface_limit,
)
from .style import _Palette

# ---------------------------------------------------------------------------------------------
# Control surfaces and dead zone
# ---------------------------------------------------------------------------------------------


def _surface_layout(result: StudyResult, ctrls: Mapping[str, _Ctrl]) -> list[list[str | None]]:
    """Columns by FoU width (0 = FLC); row 0 the IT2FLCs, then a row of dead-zone-matched and
    a row of slope-matched type-1 FLCs (when there are any); anything else in further rows."""
    infos = [_surface_info(result, ctrls, lb) for lb in result.surfaces]
    widths = sorted({round(c.fou, 12) for c in infos if c.kind in (_IT2, *_MATCHED)})
    cols = [0.0, *widths]
    top: list[str | None] = [None] * len(cols)
    matched: dict[Any, list[str | None]] = {kind: [None] * len(cols) for kind in _MATCHED}
    others: list[str] = []
    for c in infos:
        if c.kind is _FLC and top[0] is None:
            top[0] = c.label
        elif c.kind is _IT2:
            top[cols.index(round(c.fou, 12))] = c.label
        elif c.kind in matched:
            matched[c.kind][cols.index(round(c.fou, 12))] = c.label
        else:
            others.append(c.label)
    grid = [top]
    grid += [row for row in matched.values() if any(b is not None for b in row)]
    ncol = len(cols)
    for k in range(0, len(others), ncol):
        row: list[str | None] = list(others[k:k + ncol])
        grid.append(row + [None] * (ncol - len(row)))
    return grid


def _input_names(c: _Ctrl) -> tuple[str, str]:
    spec = c.spec
    if spec is None or (spec.ke, spec.kde) == (1.0, 1.0):
        return "e (rad)", "Δe (rad)"
    return f"Ke·e (Ke = {spec.ke:g})", f"Kde·Δe (Kde = {spec.kde:g})"


def _fig_control_surfaces(result: StudyResult, ctrls: Mapping[str, _Ctrl], *,
                          draft: bool = False) -> Figure:
    """The surfaces on :func:`_surface_layout`'s grid; a ``draft`` (``reproduce --quick``)
    draws its first row only (half the figure's CPU at the end of a smoke run) and says so."""
    grid = _surface_layout(result, ctrls)
    left_out = 0
    if draft:
        first = next(row for row in grid if any(lb is not None for lb in row))
        left_out = sum(lb is not None for row in grid for lb in row) - sum(
            lb is not None for lb in first)
        grid = [first]
    nrow, ncol = len(grid), len(grid[0])
    fig = Figure(figsize=(2.9 * ncol + 1.0, 2.8 * nrow + 0.6), layout="constrained")
    ax = np.asarray(fig.subplots(nrow, ncol, squeeze=False))
    image = None
    vlim = surface_limit(result) or 1.0
    step = vlim / 3.0
    levels = [k * step / 2.0 for k in (-5, -3, -1, 1, 3, 5)]
    for i, row in enumerate(grid):
        for j, label in enumerate(row):
            a = ax[i, j]
            if label is None:
                a.set_axis_off()
                continue
            e, de, u = result.surfaces[label]
            extent = (float(e.min()), float(e.max()), float(de.min()), float(de.max()))
            image = a.imshow(u.T, origin="lower", extent=extent, cmap="RdBu_r", vmin=-vlim,
                             vmax=vlim, interpolation="nearest", aspect="equal")
            cs = a.contour(e, de, u, levels=levels, colors="k", linewidths=0.5, alpha=0.6)
            a.clabel(cs, fontsize=6, fmt="%g")
            c = _surface_info(result, ctrls, label)
            d = _dead_zone(c)
            if d is not None and d > 0:
                a.add_patch(Rectangle((-d, -d), 2 * d, 2 * d, fill=False, ec="black", lw=1.0,
                                      ls="--"))
                a.set_title(f"{label}\ndead zone |e|, |Δe| < {d:g}", fontsize=8.5)
            else:
                a.set_title(label, fontsize=8.5)
            a.grid(False)
            x_name, y_name = _input_names(c)
            a.set_xlabel(x_name)
            a.set_ylabel(y_name)
    if image is not None:
        cb = fig.colorbar(image, ax=ax.ravel().tolist(), shrink=0.8, pad=0.02)
        cb.set_label("u (V)")
    gains = _input_gains(_surface_info(result, ctrls, lb).spec for lb in result.surfaces)
    gain_text = ("inputs Ke·e, Kde·Δe" if gains is None
                 else f"Ke = {gains[0]:g}, Kde = {gains[1]:g}")
    fig.suptitle(f"Control surfaces u(e, Δe) ({gain_text}; contours every {step:.3g} V; dashed "
                 "square: only the Z×Z rule fires, u = 0)", fontsize=10)
    if left_out:
        fig.text(0.995, 0.005, f"draft (reproduce --quick): the first row only; {left_out} more "
                 f"surface{'s' if left_out > 1 else ''} in the full run", ha="right",
                 va="bottom", fontsize=8, color="#b00000")
    return fig


def _zero_de_slice(result: StudyResult, c: _Ctrl) -> tuple[np.ndarray, np.ndarray]:
    """``(x, u(x, 0))`` of a fuzzy controller, ``x`` its first input (``Ke e``).

    The paper's controllers are rebuilt from their specs (with their reducer and t-norm) and
    evaluated on a fine grid, so that the zoomed dead-zone edges are exact; any other controller
    gets the ``de = 0`` column of its stored surface.
    """
    spec = c.spec
    if spec is not None and spec.kind in _PAPER_FUZZY:
        controller = spec.build()
        if isinstance(controller, FuzzyHeadingController):
            x = np.linspace(-1.0, 1.0, 2001)
            return x, np.asarray(controller.fls(x, np.zeros_like(x)), dtype=float)
    ge, gde, gu = result.surfaces[c.label]
    k = int(np.argmin(np.abs(gde[0, :])))
    return ge[:, k], gu[:, k]


def _fig_dead_zone(result: StudyResult, ctrls: Mapping[str, _Ctrl], pal: _Palette) -> Figure:
    infos = sorted((_surface_info(result, ctrls, lb) for lb in result.surfaces), key=_order_key)
    fig = Figure(figsize=(11.0, 4.3), layout="constrained")
    a_full, a_zoom = fig.subplots(1, 2)
    zoom = 0.35
    for c in infos:
        st = pal.style(c)
        x, u = _zero_de_slice(result, c)
        a_full.plot(x, u, color=st.color, ls=st.ls, label=c.label)
        a_zoom.plot(x, u, color=st.color, ls=st.ls, label=c.label)
        d = _dead_zone(c)
        if d is not None and c.kind not in _MATCHED:
            for sgn in (-1.0, 1.0):
                a_zoom.axvline(sgn * d, color=st.color, lw=0.8, ls=":")
            a_zoom.annotate(f"{d:g}", (d, 1.0), xycoords=("data", "axes fraction"),
                            xytext=(2, -2), textcoords="offset points", color=st.color,
                            fontsize=7.5, va="top", ha="left")
    gains = _input_gains(c.spec for c in infos)
    x_name = "heading error e (rad)" if gains is not None and gains[0] == 1.0 else "Ke·e"
    for a in (a_full, a_zoom):
        a.axhline(0.0, color="#999999", lw=0.6)
        a.set_xlabel(f"{x_name}, Δe = 0")
        a.set_ylabel("u (V)")
    a_full.set_title("u(e, Δe = 0) over the universe")
    a_zoom.set_xlim(-zoom, zoom)
    a_zoom.set_ylim(-3.0, 3.0)
    a_zoom.set_title("zoom: dead-zone edges ±(0.2 − w/2) dotted")
    a_full.legend(loc="upper left", fontsize=7.5)
    matched = ("dashed: type-1 FLC with the same dead zone"
               + ("; dotted: and the same slope outside it" if any(c.kind is _T1S for c in infos)
                  else ""))
    fig.suptitle("Dead zone: near e = 0 only the Z sets fire and u = 0; the FoU narrows the dead "
                 f"zone from 0.2 to 0.2 − w/2\n({matched})", fontsize=10)
    return fig
