"""The robot's small matrix exponentials run without OpenBLAS's helper threads (a wait for a
busy core at every 5x5 solve; ``drive.single_threaded_blas``, threadpoolctl), with the same
bits."""

from __future__ import annotations

import contextlib
import dataclasses

import numpy as np
import pytest
import scipy.linalg
from threadpoolctl import ThreadpoolController

from it2track.plant import DifferentialDrive, MotorParams, RobotParams, drive


def _counts() -> list[int]:
    return [i["num_threads"] for i in ThreadpoolController().info() if i["user_api"] == "blas"]


@pytest.fixture
def two_threads():
    """Every BLAS on two threads for the test (whatever the machine's cores), then back."""
    if not _counts():  # pragma: no cover - numpy's and scipy's wheels bundle OpenBLAS
        pytest.skip("no BLAS library threadpoolctl can set in this process")
    with ThreadpoolController().limit(limits=2, user_api="blas"):
        yield


def test_one_thread_inside_and_the_counts_back_after(two_threads):
    assert set(_counts()) == {2}
    with drive.single_threaded_blas():
        assert set(_counts()) == {1}
    assert set(_counts()) == {2}
    with pytest.raises(ZeroDivisionError), drive.single_threaded_blas():
        _ = 1 / 0
    assert set(_counts()) == {2}


def test_the_robot_is_built_without_blas_threads(two_threads, monkeypatch):
    """Every matrix exponential of a robot build runs with BLAS on one thread."""
    seen = []
    real = scipy.linalg.expm

    def expm(a):
        seen.append(tuple(_counts()))
        return real(a)

    monkeypatch.setattr(drive.scipy.linalg, "expm", expm)
    drive._product_weights_cached.cache_clear()
    DifferentialDrive(RobotParams(), 0.01)
    assert len(seen) > 20 and {set(s) == {1} for s in seen} == {True}
    assert set(_counts()) == {2}


ROBOTS = [RobotParams(),
          RobotParams(half_track=0.21, motor=MotorParams(resistance=1.3, inductance=0.004)),
          dataclasses.replace(RobotParams(), wheel_radius=0.06)]


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("nodes", [1, 4, 9])
def test_a_robot_built_without_blas_threads_is_the_same_bits(two_threads, monkeypatch, robot,
                                                             nodes):
    """The build's every coefficient equals a build with OpenBLAS's threads, bit for bit."""
    drive._product_weights_cached.cache_clear()
    single = DifferentialDrive(robot, 0.01, quadrature_nodes=nodes)
    drive._product_weights_cached.cache_clear()
    monkeypatch.setattr(drive, "single_threaded_blas", contextlib.nullcontext)
    threaded = DifferentialDrive(robot, 0.01, quadrature_nodes=nodes)
    for name in ("_wheel", "_heading", "_node_speed", "_node_heading"):
        a, b = np.array(getattr(single, name)), np.array(getattr(threaded, name))
        assert a.tobytes() == b.tobytes(), name
    np.testing.assert_array_equal(single.nodes, threaded.nodes)
