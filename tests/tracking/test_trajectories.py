"""Reference trajectories: built-ins, waypoints, CSV loading, user callables."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from it2track.paper import heading_fls
from it2track.tracking import (
    PAPER_TRAJECTORIES,
    FunctionTrajectory,
    FuzzyHeadingController,
    LoopConfig,
    RunTable,
    Trajectory,
    WaypointTrajectory,
    curved,
    get_trajectory,
    load_waypoints_csv,
    simulate,
    sinusoidal,
    straight,
)


@pytest.mark.parametrize("name", sorted(PAPER_TRAJECTORIES))
def test_builtin_velocity_is_derivative_of_position(name):
    traj = PAPER_TRAJECTORIES[name]()
    assert traj.name == name
    t = np.linspace(0.0, 10.0, 201)
    h = 1e-5
    out = traj.sample(t)
    assert out.shape == (t.size, 4)
    fd = (traj.sample(t + h)[:, :2] - traj.sample(t - h)[:, :2]) / (2 * h)
    err = np.abs(out[:, 2:] - fd).max()
    assert err < 1e-6, f"{name}: velocity differs from central differences by {err:.2g}"


def test_builtins_match_the_paper():
    t = np.array([0.0, 1.0, 2.5])
    assert np.allclose(straight().sample(t)[:, :2], np.c_[2 * t, 0 * t])
    assert np.allclose(curved().sample(t)[:, :2], np.c_[2 * t, 0.2 * t**2 - 4])
    assert np.allclose(sinusoidal().sample(t)[:, :2], np.c_[2 * t, 0.2 - 0.2 * np.cos(2 * t)])


def test_sample_checks_user_output():
    bad_shape = FunctionTrajectory("bad", lambda t: np.zeros((t.size, 3)))
    with pytest.raises(ValueError, match=r"'bad' returned shape"):
        bad_shape.sample([0.0, 1.0])
    nan = FunctionTrajectory("nan", lambda t: np.full((t.size, 4), np.nan))
    with pytest.raises(ValueError, match="'nan' returned NaN"):
        nan.sample([0.0])
    # ... and the loop does the same check up front
    with pytest.raises(ValueError, match="'nan' returned NaN"):
        simulate(
            [FuzzyHeadingController(fls=heading_fls(0.0))], [nan], RunTable(0, 0, 0.0, 0),
            LoopConfig(duration=0.1),
        )  # fmt: skip


@pytest.mark.parametrize("kind", ["cubic", "linear"])
def test_waypoints_interpolate_and_give_velocity(kind):
    times = np.array([0.0, 1.0, 2.5, 4.0, 5.0])
    pts = np.c_[2.0 * times + 1.0, -0.5 * times]  # points on a line, 2 and -0.5 m/s
    traj = WaypointTrajectory("line", times, pts, kind)
    at = traj.sample(times)
    assert np.allclose(at[:, :2], pts, atol=1e-12), f"{kind}: does not pass its waypoints"
    mid = np.linspace(0.0, 5.0, 37)
    out = traj.sample(mid)
    # a line is reproduced exactly by both interpolants, velocity included
    assert np.allclose(out[:, :2], np.c_[2.0 * mid + 1.0, -0.5 * mid], atol=1e-12), kind
    assert np.allclose(out[:, 2:], [2.0, -0.5], atol=1e-12), f"{kind}: velocity"
    # outside the time span: hold the end point, zero velocity
    after = traj.sample([6.0, 100.0])
    assert np.allclose(after, [[11.0, -2.5, 0.0, 0.0]] * 2), f"{kind}: after the end"
    before = traj.sample([-1.0])
    assert np.allclose(before, [[1.0, 0.0, 0.0, 0.0]]), f"{kind}: before the start"


def test_linear_waypoints_velocity_is_piecewise_constant():
    traj = WaypointTrajectory("zigzag", [0.0, 1.0, 3.0], [[0, 0], [1, 1], [3, 0]], "linear")
    out = traj.sample([0.5, 1.5, 2.9])
    assert np.allclose(out, [[0.5, 0.5, 1, 1], [1.5, 0.75, 1, -0.5], [2.9, 0.05, 1, -0.5]])


def test_cubic_waypoints_velocity_is_spline_derivative():
    t = np.linspace(0.0, 6.0, 13)
    traj = WaypointTrajectory("sine", t, np.c_[t, np.sin(t)])
    s = np.linspace(0.1, 5.9, 50)
    h = 1e-6
    fd = (traj.sample(s + h)[:, :2] - traj.sample(s - h)[:, :2]) / (2 * h)
    assert np.allclose(traj.sample(s)[:, 2:], fd, atol=1e-7)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([0.0, 1.0], [[0, 0]]), "must be"),
        (([0.0, 1.0, 2.0, 3.0], [[0, 0]] * 4, "quadratic"), "kind="),
        (([0.0, 1.0, 2.0], [[0, 0]] * 3), "at least 4"),
        (([0.0], [[0, 0]], "linear"), "at least 2"),
        (([0.0, 1.0, 1.0, 2.0], [[0, 0]] * 4), r"increase strictly"),
        (([0.0, 1.0, np.nan, 2.0], [[0, 0]] * 4), "finite"),
    ],
)
def test_waypoint_validation(args, match):
    with pytest.raises(ValueError, match=match):
        WaypointTrajectory("w", *args)


def _write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_load_waypoints_csv_good_file(tmp_path):
    # Any column order, extra columns, spaces, upper case and blank lines are fine.
    path = _write(
        tmp_path, "route.csv",
        "note, Y ,T,x\na,0,0,0\n\nb, 1.0, 1, 2\nc,0,2,4\n , , , \nd,-1,3,6\n",
    )  # fmt: skip
    traj = load_waypoints_csv(path)
    assert traj.name == "route"
    assert traj.times == (0.0, 1.0, 2.0, 3.0)
    assert traj.points == ((0.0, 0.0), (2.0, 1.0), (4.0, 0.0), (6.0, -1.0))
    assert traj.kind == "cubic"
    lin = load_waypoints_csv(path, kind="linear")
    assert np.allclose(lin.sample([0.5]), [[1.0, 0.5, 2.0, 1.0]])
    assert isinstance(get_trajectory(str(path)), WaypointTrajectory)


@pytest.mark.parametrize(
    ("text", "line", "match"),
    [
        ("t,x\n0,0\n", 1, r"lacks column\(s\) \['y'\]"),
        ("t,x,y\n0,0,0\n1,1,zero\n", 3, "expected numbers"),
        ("t,x,y\n0,0,0\n1,1\n", 3, "expected numbers"),
        ("t,x,y\n0,0,0\n1,1,inf\n", 3, "non-finite"),
        ("t,x,y\n0,0,0\n1,1,0\n\n1,2,0\n3,3,0\n", 5, "does not increase"),
        ("t,x,y\n0,0,0\n2,1,0\n1,2,0\n3,3,0\n", 4, "does not increase"),
    ],
    ids=["missing-column", "bad-number", "short-row", "inf", "repeated-time", "time-back"],
)
def test_load_waypoints_csv_bad_file_names_file_and_line(tmp_path, text, line, match):
    path = _write(tmp_path, "bad.csv", text)
    with pytest.raises(ValueError, match=match) as info:
        load_waypoints_csv(path)
    assert str(info.value).startswith(f"{path}:{line}:"), str(info.value)


def test_load_waypoints_csv_unreadable_or_empty(tmp_path):
    with pytest.raises(ValueError, match="cannot read"):
        load_waypoints_csv(tmp_path / "missing.csv")
    with pytest.raises(ValueError, match="empty"):
        load_waypoints_csv(_write(tmp_path, "empty.csv", ""))
    with pytest.raises(ValueError, match=r"header.csv: .*at least 4"):
        load_waypoints_csv(_write(tmp_path, "header.csv", "t,x,y\n0,0,0\n"))


def test_get_trajectory():
    assert get_trajectory("curved").name == "curved"
    traj = straight()
    assert get_trajectory(traj) is traj
    with pytest.raises(ValueError, match="unknown trajectory 'spiral'"):
        get_trajectory("spiral")


def test_csv_trajectory_runs_through_the_loop(tmp_path):
    # The straight line as waypoints: the loop gives the same run as the built-in, up to the
    # spline's reproduction of a line (~1e-15) -- here compared to 1e-9.
    rows = "\n".join(f"{t:g},{2 * t:g},0" for t in range(11))
    path = _write(tmp_path, "line.csv", "t,x,y\n" + rows + "\n")
    ctrl = [FuzzyHeadingController(fls=heading_fls(0.2))]
    trajs: list[Trajectory] = [straight(), get_trajectory(str(path))]
    trace = simulate(ctrl, trajs, RunTable(0, [0, 1], 0.05, 1), LoopConfig(duration=3.0))
    for name in ("x", "y", "theta", "u"):
        assert np.allclose(trace[name][0], trace[name][1], rtol=0, atol=1e-9), name
