"""The plotting functions of ``it2track.report.surface``: clean functions returning Figures."""

from __future__ import annotations

import numpy as np
import pytest
from io_systems import random_system
from matplotlib.figure import Figure

from it2track import heading_fls
from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Rule, T1Sugeno, Triangle, control_surface
from it2track.report.surface import (
    plot_control_surface,
    plot_footprints,
    plot_system,
    surface_grid,
)


def test_surface_grid_matches_control_surface() -> None:
    fls = heading_fls(0.2)
    x, y, u = surface_grid(fls, points=11)
    cx, cy, cu = control_surface(fls, points=11)
    assert np.array_equal(x, cx) and np.array_equal(y, cy) and np.array_equal(u, cu)
    _, _, swapped = surface_grid(fls, inputs=("de", "e"), points=11)
    assert np.array_equal(swapped, u.T)


def test_surface_grid_fixes_other_inputs() -> None:
    system = random_system(2)
    names = [i.name for i in system.inputs]
    x, y, u = surface_grid(system, inputs=(names[2], names[0]), fixed={names[1]: 0.3},
                           points=5)
    lo, hi = system.inputs[1].universe
    value = min(max(0.3, lo), hi)
    expect = system(y, np.full_like(x, value), x)
    assert np.array_equal(u, expect)
    with pytest.raises(ValueError, match="fixed"):
        surface_grid(system, fixed={"nope": 1.0})
    with pytest.raises(ValueError, match="two different inputs"):
        surface_grid(system, inputs=(names[0], names[0]))


def test_zero_firing_regions_are_nan() -> None:
    sets = [IT2Set.from_fou(Triangle(-1, -0.5, 0), 0.1, "A"), IT2Set.from_fou(
        Triangle(0.4, 0.7, 1), 0.1, "B")]
    system = IT2Sugeno(inputs=[Input("x", (-1, 1), sets), Input("y", (-1, 1), sets)],
                       rules=[Rule(["A", "A"], -1.0), Rule(["B", "B"], 1.0)])
    _, _, u = surface_grid(system, points=21)
    assert np.isnan(u).any() and np.isfinite(u).any()
    fig = plot_control_surface(system, style="contour", points=21)
    assert isinstance(fig, Figure)


def test_plot_control_surface_to_file_and_into_axes(tmp_path) -> None:
    fls = heading_fls(0.2)
    path = tmp_path / "s.png"
    fig = plot_control_surface(fls, path, points=11)
    assert isinstance(fig, Figure) and path.read_bytes()[:4] == b"\x89PNG"
    host = Figure()
    ax = host.add_subplot(projection="3d")
    assert plot_control_surface(fls, ax, points=11) is host
    flat = Figure().add_subplot()
    with pytest.raises(ValueError, match="projection='3d'"):
        plot_control_surface(fls, flat, points=11)
    assert plot_control_surface(fls, flat, points=11, style="contour") is flat.figure
    with pytest.raises(ValueError, match="style"):
        plot_control_surface(fls, style="wire")
    svg = tmp_path / "s.svg"
    plot_control_surface(fls, svg, points=5, title="custom")
    assert svg.read_text().lstrip().startswith("<?xml")


def test_plot_footprints() -> None:
    fig = plot_footprints(heading_fls(0.2))
    axes = fig.get_axes()
    assert len(axes) == 2
    assert axes[0].get_title() == "footprints of uncertainty"
    assert len(axes[0].collections) == 3  # one FoU per set
    t1 = plot_footprints(heading_fls(0.0), inputs=["de"])
    assert len(t1.get_axes()) == 1
    assert t1.get_axes()[0].get_title() == "membership functions"
    host = Figure()
    axes = host.subplots(1, 2)
    assert plot_footprints(heading_fls(0.1), list(axes)) is host
    with pytest.raises(ValueError, match="Axes"):
        plot_footprints(heading_fls(0.1), [axes[0]])
    with pytest.raises(ValueError, match="inputs"):
        plot_footprints(heading_fls(0.1), inputs=["q"])


def test_plot_system_one_and_three_inputs(tmp_path) -> None:
    one = T1Sugeno(inputs=[Input("x", (0, 1), [("lo", Triangle(0, 0, 1)),
                                               ("hi", Triangle(0, 1, 1))])],
                   rules=[Rule(["lo"], 0.0), Rule(["hi"], 1.0)])
    fig = plot_system(one, tmp_path / "one.png")
    assert len(fig.get_axes()) == 2
    three = plot_system(random_system(3), tmp_path / "three.png", points=9)
    assert len(three.get_axes()) == 4
    assert (tmp_path / "three.png").stat().st_size > 0
