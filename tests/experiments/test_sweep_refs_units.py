"""What identifies a sweep's trajectories and controllers (sweep/refs.py), called directly on
tiny inputs: the digest of a file's bytes (not its path), what a ref refuses and why, to the
letter. Fast: no sweep runs here (the sweeps that use these refs: test_sweep_store.py)."""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from it2track import heading_fls, save
from it2track._files import InputFileError
from it2track.experiments.specs import ControllerKind, ControllerSpec
from it2track.experiments.sweep import ControllerRef, TrajectoryRef
from it2track.experiments.sweep import refs as sweep_refs
from it2track.tracking import FuzzyHeadingController, PDHeadingController, StepReference
from it2track.tracking.trajectories import PAPER_TRAJECTORIES, WaypointTrajectory

# Five waypoints (a cubic spline needs four), times and points chosen by hand.
WAYPOINTS = "t,x,y\n0,0,0\n1,1,0\n2,2,0.5\n3,3,0\n4,4,1\n"


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


# -- the file digest ------------------------------------------------------------------------


def test_file_sha256_is_the_digest_of_the_files_bytes(tmp_path: Path) -> None:
    path = tmp_path / "a.bin"
    path.write_bytes(b"abc")
    # FIPS 180-2's example: SHA-256("abc").
    expected = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    assert sweep_refs._file_sha256(path) == expected
    assert sweep_refs._file_sha256(str(path)) == expected


def test_file_sha256_refuses_what_is_not_a_regular_file_naming_it_an_input_file(
    tmp_path: Path,
) -> None:
    with pytest.raises(InputFileError) as info:
        sweep_refs._file_sha256(tmp_path)
    assert str(info.value) == (
        f"{tmp_path}: is a directory, not a regular file; give a regular input file"
    )
    with pytest.raises(FileNotFoundError):
        sweep_refs._file_sha256(tmp_path / "missing.t2fis")


# -- TrajectoryRef --------------------------------------------------------------------------


def test_trajectory_ref_defaults_and_identity() -> None:
    ref = TrajectoryRef("straight")
    assert (ref.path, ref.sha256, ref.reference) == ("", "", None)
    assert ref == TrajectoryRef("straight", "", "", None)
    assert ref.to_dict() == {"name": "straight", "source": "builtin"}
    # The reference signal is part of the identity: two steps of one name differ.
    a = TrajectoryRef("step", reference=StepReference(amplitude=1.0))
    b = TrajectoryRef("step", reference=StepReference(amplitude=2.0))
    assert a != b
    assert a == TrajectoryRef("step", reference=StepReference(amplitude=1.0))


def test_builtin_trajectory_loads_the_papers_trajectory() -> None:
    for name in ("straight", "curved", "sinusoidal"):
        assert TrajectoryRef(name).load() == PAPER_TRAJECTORIES[name]()


def test_a_builtin_named_by_path_is_not_renamed() -> None:
    # Only a waypoint trajectory takes the ref's name; a built-in keeps its own.
    traj = TrajectoryRef("mine", path="curved").load()
    assert traj == PAPER_TRAJECTORIES["curved"]()
    assert traj.name == "curved"


def test_reference_signal_is_loaded_as_is_and_identified_by_its_values() -> None:
    step = StepReference(amplitude=2.0, at=0.5, initial=-1.0, name="jump")
    ref = TrajectoryRef("jump", reference=step)
    assert ref.load() is step
    assert ref.to_dict() == {
        "name": "jump", "source": "reference", **step.to_dict(),
    }  # fmt: skip
    assert ref.to_dict()["source"] == "reference"  # (the step's own dict does not override it)


def test_waypoint_file_takes_the_refs_name_and_keeps_the_files_values(tmp_path: Path) -> None:
    path = tmp_path / "wp.csv"
    path.write_text(WAYPOINTS)
    digest = _sha(path.read_bytes())
    ref = TrajectoryRef("mine", path=str(path), sha256=digest)
    traj = ref.load()
    assert isinstance(traj, WaypointTrajectory)
    assert traj.name == "mine"
    assert traj.times == (0.0, 1.0, 2.0, 3.0, 4.0)
    assert traj.points == ((0.0, 0.0), (1.0, 0.0), (2.0, 0.5), (3.0, 0.0), (4.0, 1.0))
    assert traj.kind == "cubic"
    # A ref named like the file (its stem) loads the file's trajectory unchanged.
    assert TrajectoryRef("wp", path=str(path), sha256=digest).load() == WaypointTrajectory(
        "wp", traj.times, traj.points, "cubic")
    # The identity is the content, not where the file lives.
    assert ref.to_dict() == {"name": "mine", "source": "csv", "sha256": digest}
    assert TrajectoryRef("mine", path="/elsewhere/wp.csv", sha256=digest).to_dict() == (
        ref.to_dict())


def test_a_linear_waypoint_trajectory_keeps_its_kind_when_renamed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "wp.csv"
    linear = WaypointTrajectory("wp", [0.0, 1.0, 2.0], [[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]],
                                "linear")
    seen: list[object] = []

    def fake_get_trajectory(spec: object) -> WaypointTrajectory:
        seen.append(spec)
        return linear

    monkeypatch.setattr(sweep_refs, "get_trajectory", fake_get_trajectory)
    traj = TrajectoryRef("mine", path=str(path), sha256="0" * 64).load()
    assert seen == [str(path)]  # the path, not the name, when there is one
    assert traj == WaypointTrajectory("mine", linear.times, linear.points, "linear")
    # No path: the name is what is loaded; a trajectory of the ref's own name is returned as is.
    assert TrajectoryRef("wp").load() is linear and seen[-1] == "wp"


# -- ControllerRef --------------------------------------------------------------------------


def _file_spec(tmp_path: Path, fou: float = 0.3) -> ControllerSpec:
    save(heading_fls(fou), tmp_path / "ctrl.t2fis")
    return ControllerSpec(kind=ControllerKind.FILE, path=str(tmp_path / "ctrl.t2fis"))


def test_controller_ref_of_a_built_in_kind_has_no_digest_and_no_path() -> None:
    spec = ControllerSpec(kind=ControllerKind.PD, kp=20.0, kd=0.5)
    ref = ControllerRef.from_spec(spec)
    assert ref == ControllerRef(spec)
    assert (ref.sha256, ref.path, ref.label) == ("", "", "PD kp 20 kd 0.5")
    assert ref.to_dict() == spec.to_dict() == {
        "kind": "pd", "kp": 20.0, "kd": 0.5, "tf": 0.02, "label": "PD kp 20 kd 0.5",
    }  # fmt: skip
    controller = ref.build()
    assert isinstance(controller, PDHeadingController)
    assert (controller.kp, controller.kd, controller.tf) == (20.0, 0.5, 0.02)


def test_controller_ref_of_a_file_is_its_digest_not_its_path(tmp_path: Path) -> None:
    spec = _file_spec(tmp_path)
    digest = _sha((tmp_path / "ctrl.t2fis").read_bytes())
    ref = ControllerRef.from_spec(spec)
    assert ref.sha256 == digest
    assert ref.path == str(tmp_path / "ctrl.t2fis")
    assert ref.label == "ctrl.t2fis"
    assert ref.to_dict() == {
        "kind": "file", "ke": 1.0, "kde": 1.0, "tnorm": "product", "label": "ctrl.t2fis",
        "file_sha256": digest,
    }  # fmt: skip
    assert spec.to_dict()["path"] == str(tmp_path / "ctrl.t2fis")  # (the spec keeps it)
    assert isinstance(ref.build(), FuzzyHeadingController)
    # The same bytes under another name and path: the same identity.
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "ctrl.t2fis").write_bytes((tmp_path / "ctrl.t2fis").read_bytes())
    moved = ControllerRef.from_spec(ControllerSpec(
        kind=ControllerKind.FILE, path=str(tmp_path / "sub" / "ctrl.t2fis")))
    assert moved.to_dict() == ref.to_dict()


def test_controller_ref_refuses_a_digest_that_does_not_fit_its_kind(tmp_path: Path) -> None:
    pd = ControllerSpec(kind=ControllerKind.PD, kp=1.0)
    with pytest.raises(ValueError) as info:
        ControllerRef(pd, "ab" * 32)
    assert str(info.value) == (
        "ControllerRef.sha256 is the digest of a 'file' controller's file (and empty for other "
        f"kinds); got kind 'pd', sha256='{'ab' * 32}'"
    )
    spec = _file_spec(tmp_path)
    with pytest.raises(ValueError) as info:
        ControllerRef(spec)
    assert str(info.value) == (
        "ControllerRef.sha256 is the digest of a 'file' controller's file (and empty for other "
        "kinds); got kind 'file', sha256=''"
    )


def test_from_spec_builds_the_controller_once_so_a_bad_file_fails_there(tmp_path: Path) -> None:
    bad = tmp_path / "bad.t2fis"
    bad.write_text("not a fuzzy system\n")
    spec = ControllerSpec(kind=ControllerKind.FILE, path=str(bad))
    with pytest.raises(ValueError, match=r"bad\.t2fis"):
        ControllerRef.from_spec(spec)
    # Constructed with its digest (no build), the same ref fails only when built.
    ref = ControllerRef(spec, _sha(bad.read_bytes()))
    with pytest.raises(ValueError, match=r"bad\.t2fis"):
        ref.build()


def test_from_spec_refuses_an_unreadable_controller_file(tmp_path: Path) -> None:
    spec = ControllerSpec(kind=ControllerKind.FILE, path=str(tmp_path / "gone.t2fis"))
    with pytest.raises(FileNotFoundError):
        ControllerRef.from_spec(spec)


def test_build_refuses_a_file_edited_after_planning_naming_both_digests(tmp_path: Path) -> None:
    spec = _file_spec(tmp_path, 0.3)
    ref = ControllerRef.from_spec(spec)
    before = ref.sha256
    save(heading_fls(0.5), tmp_path / "ctrl.t2fis")
    now = _sha((tmp_path / "ctrl.t2fis").read_bytes())
    assert now != before
    with pytest.raises(ValueError) as info:
        ref.build()
    assert str(info.value) == (
        f"controller file {str(tmp_path / 'ctrl.t2fis')!r} changed since the sweep was planned "
        f"(sha256 {before[:12]}, now {now[:12]}); results of the old and the new controller "
        "must not be mixed: restore the file or start a new sweep"
    )
    # Restored, it builds again.
    save(heading_fls(0.3), tmp_path / "ctrl.t2fis")
    assert _sha((tmp_path / "ctrl.t2fis").read_bytes()) == before
    assert isinstance(ref.build(), FuzzyHeadingController)
