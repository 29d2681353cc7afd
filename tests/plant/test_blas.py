"""it2track._blas: the robot's small matrix exponentials run without OpenBLAS's helper threads
(a wait for a busy core at every 5x5 solve), with the same bits."""

from __future__ import annotations

import contextlib
import dataclasses

import numpy as np
import pytest
import scipy.linalg

import it2track._blas as blas
from it2track.plant import DifferentialDrive, MotorParams, RobotParams, drive

MAPS = """\
55d0c8a00000-55d0c8a01000 r--p 00000000 08:01 1 /usr/bin/python3.11
7f0000000000-7f0000100000 r-xp 00000000 08:01 2 /venv/scipy.libs/libscipy_openblas-6cdc3b4a.so
7f0000100000-7f0000200000 r--p 00100000 08:01 2 /venv/scipy.libs/libscipy_openblas-6cdc3b4a.so
7f0000200000-7f0000300000 rw-p 00000000 00:00 0
7f0000300000-7f0000400000 r-xp 00000000 08:01 3 /my libs/libopenblas.so.0
7f0000400000-7f0000500000 r-xp 00000000 08:01 4 /venv/openblas_tools/libfoo.so
7f0000500000-7f0000600000 rw-p 00000000 00:00 0 [heap]
"""


def test_openblas_paths_from_the_memory_map():
    """Each OpenBLAS once, spaces in a path kept; lines without a path, folders named
    openblas and other libraries left out."""
    assert blas._openblas_paths(MAPS) == [
        "/venv/scipy.libs/libscipy_openblas-6cdc3b4a.so", "/my libs/libopenblas.so.0"]
    assert blas._openblas_paths("") == []


def _openblas() -> list[tuple]:
    libs = blas._libraries()
    if not libs:  # pragma: no cover - numpy and scipy wheels bundle OpenBLAS
        pytest.skip("no OpenBLAS in this process")
    return list(libs)


def test_both_wheels_openblas_are_found():
    """numpy's and scipy's wheels each bundle an OpenBLAS; both are found (scipy.linalg's is
    the one expm uses)."""
    _openblas()
    with open("/proc/self/maps", encoding="utf-8") as fh:
        names = " ".join(blas._openblas_paths(fh.read()))
    assert "scipy.libs" in names and "numpy.libs" in names
    assert len(blas._libraries()) == 2


@pytest.fixture
def two_threads():
    """Every OpenBLAS on two threads for the test (whatever the machine's cores), then back."""
    libs = _openblas()
    before = [setter(2) for setter, _ in libs]
    yield
    for (setter, _), count in zip(libs, before, strict=True):
        setter(count)


def test_one_thread_inside_and_the_counts_back_after(two_threads):
    assert blas.blas_thread_counts() == [2, 2]
    with blas.single_threaded_blas():
        assert blas.blas_thread_counts() == [1, 1]
        with blas.single_threaded_blas():  # nested: still one, and the outer's count kept
            assert blas.blas_thread_counts() == [1, 1]
        assert blas.blas_thread_counts() == [1, 1]
    assert blas.blas_thread_counts() == [2, 2]
    with pytest.raises(ZeroDivisionError), blas.single_threaded_blas():
        _ = 1 / 0
    assert blas.blas_thread_counts() == [2, 2]


def test_the_robot_is_built_without_blas_threads(two_threads, monkeypatch):
    """Every matrix exponential of a robot build runs with OpenBLAS on one thread."""
    seen = []
    real = scipy.linalg.expm

    def expm(a):
        seen.append(tuple(blas.blas_thread_counts()))
        return real(a)

    monkeypatch.setattr(drive.scipy.linalg, "expm", expm)
    drive._product_weights_cached.cache_clear()
    DifferentialDrive(RobotParams(), 0.01)
    assert len(seen) > 20 and set(seen) == {(1, 1)}
    assert blas.blas_thread_counts() == [2, 2]


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
