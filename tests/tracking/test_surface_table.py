"""The surface-table controller: bilinear interpolation (closed forms), its exact type-1 Sugeno
equivalent, and the IT2FLC's copy used as the D3 baseline."""

import numpy as np
import pytest

from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.paper import heading_fls
from it2track.tracking import (
    LoopConfig,
    SurfaceTableController,
    get_trajectory,
    run_grid,
    simulate_metrics,
)


def test_bilinear_functions_are_reproduced_exactly_and_inputs_clipped():
    # A bilinear function a + b x + c y + d x y is its own bilinear interpolant on any grid.
    e = np.array([-1.0, -0.3, 0.2, 1.0])
    de = np.array([-1.0, 0.5, 1.0])
    f = lambda x, y: 1.5 - 2.0 * x + 0.5 * y + 3.0 * x * y  # noqa: E731
    table = f(*np.meshgrid(e, de, indexing="ij"))
    c = SurfaceTableController(e_nodes=e, de_nodes=de, table=table, ke=2.0, kde=0.5)
    rng = np.random.default_rng(0)
    x, y = rng.uniform(-0.5, 0.5, 50), rng.uniform(-2.0, 2.0, 50)
    u = c.output(x, y, c.initial_state(50, 0.01))
    np.testing.assert_allclose(u, f(np.clip(2.0 * x, -1, 1), np.clip(0.5 * y, -1, 1)),
                               rtol=0, atol=1e-12)
    # At the nodes the table itself; beyond the grid the edge values.
    assert c.lookup(np.array([0.2]), np.array([0.5]))[0] == table[2, 1]
    assert c.lookup(np.array([7.0]), np.array([-7.0]))[0] == table[3, 0]


def test_a_table_is_exactly_a_type1_sugeno_system():
    # One triangle per node (a partition of unity), product t-norm, one rule per node pair:
    # the weighted average is the bilinear interpolant.
    fls = heading_fls(0.2)
    c = SurfaceTableController.from_system(fls, points=9)
    t1 = c.as_sugeno()
    assert len(t1.rules) == 81
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-1, 1, 200), rng.uniform(-1, 1, 200)
    np.testing.assert_allclose(np.asarray(t1(x, y)), c.lookup(x, y), rtol=0, atol=1e-12)


def test_the_it2flc_copy_matches_its_surface_and_its_closed_loop():
    fls = heading_fls(0.2)
    spec = ControllerSpec(kind=ControllerKind.T1_SURFACE, fou=0.2)
    assert spec.label == "T1 surface copy 0.2"
    copy = spec.build()
    assert isinstance(copy, SurfaceTableController)
    err = copy.surface_error(fls, points=301)
    # Between nodes 0.005 apart: piecewise-smooth surface, kinks where the type reducer's
    # switch point moves; the interpolation error is a few mV at worst.
    assert err["max"] < 0.01 and err["rms"] < 5e-4
    assert err["max"] > 0.0  # not trivially equal: the grid is offset from the nodes
    coarse = SurfaceTableController.from_system(fls, points=41)
    assert coarse.surface_error(fls, points=301)["max"] > 3 * err["max"]
    trajs = [get_trajectory(t) for t in ("straight", "curved", "sinusoidal")]
    runs = run_grid(2, 3, [0.05], 4)
    ctrls = [ControllerSpec(kind=ControllerKind.IT2, fou=0.2).build(), copy]
    m = simulate_metrics(ctrls, trajs, runs, LoopConfig())
    ise = m["ISE"].reshape(2, 3, 4)
    np.testing.assert_allclose(ise[1], ise[0], rtol=1e-3)


def test_scaled_and_gained_copies_follow_their_it2flc():
    spec = ControllerSpec(kind=ControllerKind.T1_SURFACE, fou=0.2, output_gain=0.5, ke=2.0)
    assert spec.label == "T1 surface copy 0.2 Ke 2 Kde 1 G 0.5"
    it2 = ControllerSpec(kind=ControllerKind.IT2, fou=0.2, output_gain=0.5, ke=2.0).build()
    copy = spec.build()
    e = np.linspace(-0.6, 0.6, 13)
    de = np.linspace(0.3, -0.3, 13)
    np.testing.assert_allclose(copy.output(e, de, copy.initial_state(13, 0.01)),
                               it2.output(e, de, it2.initial_state(13, 0.01)), atol=5e-3)
    assert spec.to_dict()["kind"] == "t1-surface"
    with pytest.raises(ValueError, match="needs fou > 0"):
        ControllerSpec(kind=ControllerKind.T1_SURFACE)


@pytest.mark.parametrize(("kw", "match"), [
    ({"e_nodes": [0.0, 0.0, 1.0]}, "strictly increasing"),
    ({"e_nodes": [0.0]}, "e_nodes must be >= 2"),
    ({"table": np.zeros((2, 2))}, "shape"),
    ({"table": np.full((3, 3), np.nan)}, "finite"),
    ({"ke": float("inf")}, "ke=inf"),
])
def test_bad_tables_are_refused(kw, match):
    args = {"e_nodes": np.array([-1.0, 0.0, 1.0]), "de_nodes": np.array([-1.0, 0.0, 1.0]),
            "table": np.zeros((3, 3))}
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        SurfaceTableController(**args)
    with pytest.raises(ValueError, match="points=1"):
        SurfaceTableController.from_system(heading_fls(0.2), points=1)
