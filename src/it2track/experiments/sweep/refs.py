"""What identifies a sweep's controllers and trajectories: :class:`ControllerRef` and
:class:`TrajectoryRef`, a spec or a name plus the SHA-256 of the file behind it (the digest, not
the path, enters the configuration hash).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..._files import read_bytes
from ...tracking import HeadingController, StepReference, Target, get_trajectory
from ...tracking.trajectories import WaypointTrajectory
from ..specs import ControllerKind, ControllerSpec

__all__ = ["ControllerRef", "TrajectoryRef"]


def _file_sha256(path: str | Path) -> str:
    """SHA-256 of a regular file's bytes (hex); ``OSError`` if it cannot be read,
    :class:`~it2track._files.InputFileError` (a ``ValueError``) if it is not a regular file or
    too big."""
    return hashlib.sha256(read_bytes(path, what="input file")).hexdigest()


@dataclass(frozen=True)
class TrajectoryRef:
    """A trajectory named in a config: a built-in name or a CSV waypoint file; or, for a
    single-input plant, a reference signal (``reference``, from a ``{kind = "step", ...}``
    table).

    ``sha256`` (of the file's bytes) makes the configuration hash follow the file's content.
    """

    name: str
    path: str = ""
    sha256: str = ""
    reference: StepReference | None = field(default=None, compare=True)

    def load(self) -> Target:
        if self.reference is not None:
            return self.reference
        traj = get_trajectory(self.path or self.name)
        if isinstance(traj, WaypointTrajectory) and traj.name != self.name:
            traj = WaypointTrajectory(self.name, traj.times, traj.points, traj.kind)
        return traj

    def to_dict(self) -> dict[str, Any]:
        """What identifies the trajectory (not where the file lives)."""
        if self.reference is not None:
            return {"name": self.name, "source": "reference", **self.reference.to_dict()}
        if not self.path:
            return {"name": self.name, "source": "builtin"}
        return {"name": self.name, "source": "csv", "sha256": self.sha256}


@dataclass(frozen=True)
class ControllerRef:
    """A controller of a sweep: its spec and, for kind ``file``, the SHA-256 of the file's bytes.

    The digest, not the path, identifies a file controller: the same file reached by another
    path (a relative or an absolute one, a moved checkout) is the same controller, an edited
    file is another. Small and picklable; :meth:`build` re-reads the file and refuses content
    that no longer matches the digest (a file edited while the sweep runs).

    Build with :meth:`from_spec`, which reads, hashes and builds the controller once.
    """

    spec: ControllerSpec
    sha256: str = ""

    def __post_init__(self) -> None:
        is_file = self.spec.kind is ControllerKind.FILE
        if is_file != bool(self.sha256):
            raise ValueError(
                "ControllerRef.sha256 is the digest of a 'file' controller's file "
                f"(and empty for other kinds); got kind {self.spec.kind.value!r}, "
                f"sha256={self.sha256!r}"
            )

    @classmethod
    def from_spec(cls, spec: ControllerSpec) -> ControllerRef:
        """Hash the controller's file (kind ``file``) and build the controller once.

        Raises
        ------
        ValueError
            If the controller cannot be built (a value its class rejects, a malformed file:
            :class:`~it2track.io.FisFormatError`, an unknown file suffix).
        OSError
            If the file cannot be read.
        """
        digest = _file_sha256(spec.path) if spec.kind is ControllerKind.FILE else ""
        ref = cls(spec, digest)
        ref.build()
        return ref

    @property
    def label(self) -> str:
        return self.spec.label

    @property
    def path(self) -> str:
        """The controller's file (kind ``file``), else ``""``."""
        return self.spec.path if self.sha256 else ""

    def build(self) -> HeadingController:
        """The controller; for a file, only if the file still has the planned content."""
        controller = self.spec.build()
        if self.sha256:
            now = _file_sha256(self.spec.path)
            if now != self.sha256:
                raise ValueError(
                    f"controller file {self.spec.path!r} changed since the sweep was planned "
                    f"(sha256 {self.sha256[:12]}, now {now[:12]}); results of the old and the "
                    "new controller must not be mixed: restore the file or start a new sweep"
                )
        return controller

    def to_dict(self) -> dict[str, Any]:
        """What identifies the controller: the spec's values, a file's digest for its path."""
        out = self.spec.to_dict()
        if self.sha256:
            del out["path"]
            out["file_sha256"] = self.sha256
        return out
