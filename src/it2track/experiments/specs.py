"""Declarative pieces shared by the study, the sweeps and the optimiser.

- :class:`ControllerSpec`: a heading controller described by plain values (kind, FoU, gains,
  reducer, file), buildable into a :class:`~it2track.tracking.HeadingController` anywhere --
  in this process, a worker process or a Dask worker;
- :class:`ConfigError` and the TOML helpers used to map configuration files onto frozen
  dataclasses: unknown keys and bad values are errors naming the file, the key and the value.
"""

from __future__ import annotations

import enum
import functools
import math
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from .._files import InputFileError, read_text
from ..fuzzy import Reducer, TNorm
from ..paper import dead_zone_matched_fls, heading_fls
from ..plant import MotorParams, RobotParams
from ..plant.base import PlantSpec
from ..plant.specs import plant_from_dict
from ..tracking import (
    ON_PATH,
    FuzzyHeadingController,
    HeadingController,
    LoopConfig,
    PDHeadingController,
    SurfaceTableController,
)

__all__ = [
    "ConfigError",
    "ControllerKind",
    "ControllerSpec",
    "Table",
    "loop_config_from_table",
    "plant_from_root",
    "read_toml",
    "robot_from_table",
]


class ConfigError(ValueError):
    """A configuration file or table has an unknown key or a bad value."""


class ControllerKind(enum.Enum):
    """What a :class:`ControllerSpec` builds."""

    FLC = "flc"  # the paper's type-1 FLC (FoU 0)
    IT2 = "it2"  # the paper's IT2FLC with FoU width `fou`
    T1_MATCHED = "t1-matched"  # type-1 FLC with the dead zone of the IT2FLC of width `fou`
    T1_SLOPE_MATCHED = "t1-slope-matched"  # ... with its dead zone and its edge slope
    T1_SURFACE = "t1-surface"  # type-1 table of the IT2FLC of width `fou`'s control surface
    PD = "pd"  # PD heading controller with a filtered derivative
    FILE = "file"  # a fuzzy system loaded from a .t2fis / .fis / .toml file


@dataclass(frozen=True, kw_only=True)
class ControllerSpec:
    """A heading controller as plain data.

    Parameters
    ----------
    kind : ControllerKind
    fou : float
        FoU width for ``IT2``, ``T1_MATCHED``, ``T1_SLOPE_MATCHED`` and ``T1_SURFACE``
        (``0 <= fou < 1.6``; ``0 < fou <= 0.4`` for ``T1_SLOPE_MATCHED``; ``T1_SURFACE``
        tabulates the IT2FLC of that width with its ``reducer`` and ``tnorm``,
        :class:`~it2track.tracking.SurfaceTableController`).
    ke, kde : float
        Input gains of the fuzzy controllers (``ke > 0``, ``kde >= 0``).
    output_gain : float
        Output gain of the fuzzy controllers (> 0), applied by scaling the rule consequents
        (:func:`~it2track.experiments.baselines.scaled_consequents`): a new system, not a
        controller parameter.
    reducer : str
        Type-reducer name (``km``, ``ekm``, ``eiasc``, ``exhaustive``, ``nie-tan``,
        ``wu-mendel``) for IT2 systems.
    tnorm : str
        ``"product"`` or ``"min"``.
    kp, kd, tf : float
        PD gains (V/rad, V s/rad) and derivative filter time constant (s); ``PD`` needs
        ``kp > 0``, ``kd, tf >= 0``.

    A field that does not apply to the kind (e.g. ``fou`` for ``PD`` or ``FILE``, ``kp`` for
    a fuzzy kind, ``reducer``/``tnorm`` for ``FILE``) must keep its default: a value given
    for it is an error, never silently dropped.
    path : str
        Fuzzy-system file for ``FILE``.
    label : str
        Name used in results; derived from the other fields when empty.

    Examples
    --------
    >>> ControllerSpec(kind=ControllerKind.IT2, fou=0.2).label
    'IT2FLC FoU 0.2'
    """

    kind: ControllerKind
    fou: float = 0.0
    ke: float = 1.0
    kde: float = 1.0
    output_gain: float = 1.0
    reducer: str = "exhaustive"
    tnorm: str = "product"
    kp: float = 0.0
    kd: float = 0.0
    tf: float = 0.02
    path: str = ""
    label: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.kind, ControllerKind):
            raise ValueError(f"controller kind={self.kind!r} must be a ControllerKind")
        for key in ("fou", "ke", "kde", "output_gain", "kp", "kd", "tf"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"controller {key}={value!r} must be a number")
            if not math.isfinite(value):
                raise ValueError(f"controller {key}={value!r} must be finite")
            if key != "tf" and abs(value) > 1e6:
                raise ValueError(
                    f"controller {key}={value!r} exceeds 1e6 in magnitude (such a controller "
                    "is bang-bang, and its arithmetic could overflow)"
                )
        if not 0.0 <= self.fou < 1.6:
            raise ValueError(f"controller fou={self.fou!r} must satisfy 0 <= fou < 1.6")
        if self.kind is ControllerKind.FLC and self.fou != 0.0:
            raise ValueError("controller kind 'flc' is the FoU-0 FLC; use kind 'it2' with fou")
        if self.kind in (ControllerKind.IT2, ControllerKind.T1_SURFACE) and self.fou == 0.0:
            raise ValueError(f"controller kind {self.kind.value!r} needs fou > 0 (fou 0 is "
                             "kind 'flc')")
        if self.kind is ControllerKind.T1_SLOPE_MATCHED and not 0.0 < self.fou <= 0.4:
            raise ValueError(f"controller kind 't1-slope-matched' needs 0 < fou <= 0.4 (a dead "
                             f"zone to match), got fou={self.fou!r}")
        if self.output_gain <= 0.0:
            raise ValueError(f"controller output_gain={self.output_gain!r} must be > 0")
        # Canonical spellings, so that "KM" and "km" are one controller (labels, hashes).
        object.__setattr__(self, "reducer", Reducer.from_name(self.reducer).value.name)
        object.__setattr__(self, "tnorm", TNorm.from_name(self.tnorm).value)
        if self.kind is ControllerKind.FILE and not self.path:
            raise ValueError("controller kind 'file' needs a path")
        defaults = {f.name: f.default for f in fields(self)}
        for key, kinds in _APPLIES_TO.items():
            if self.kind not in kinds and getattr(self, key) != defaults[key]:
                allowed = ", ".join(repr(k.value) for k in kinds)
                raise ValueError(
                    f"controller {key}={getattr(self, key)!r} does not apply to kind "
                    f"{self.kind.value!r} (only to {allowed}); remove it"
                )
        if self.kind is ControllerKind.PD:
            if not self.kp > 0:
                raise ValueError(
                    f"controller kind 'pd' needs a gain kp > 0 (V/rad), got kp={self.kp!r}"
                )
            for key in ("kd", "tf"):
                if getattr(self, key) < 0:
                    raise ValueError(f"controller {key}={getattr(self, key)!r} must be >= 0")
        else:
            if not self.ke > 0:
                raise ValueError(f"controller ke={self.ke!r} must be > 0 (error input gain)")
            if self.kde < 0:
                raise ValueError(f"controller kde={self.kde!r} must be >= 0 (error-change gain)")
        for key in ("label", "path"):
            if not isinstance(getattr(self, key), str):
                raise ValueError(f"controller {key}={getattr(self, key)!r} must be a string")
        if not self.label:
            object.__setattr__(self, "label", self._default_label())

    def _default_label(self) -> str:
        k = self.kind
        gains = "" if (self.ke, self.kde) == (1.0, 1.0) else f" Ke {self.ke:g} Kde {self.kde:g}"
        if self.output_gain != 1.0:
            gains += f" G {self.output_gain:g}"
        if self.tnorm != "product" and k is not ControllerKind.PD:
            gains += f" {self.tnorm} t-norm"
        if self.reducer != "exhaustive" and k in (ControllerKind.IT2, ControllerKind.T1_SURFACE):
            gains += f" {self.reducer}"
        if k is ControllerKind.FLC:
            return "FLC" + gains
        if k is ControllerKind.IT2:
            return f"IT2FLC FoU {self.fou:g}" + gains
        if k is ControllerKind.T1_MATCHED:
            return f"T1 dead-zone-matched {self.fou:g}" + gains
        if k is ControllerKind.T1_SLOPE_MATCHED:
            return f"T1 slope-matched {self.fou:g}" + gains
        if k is ControllerKind.T1_SURFACE:
            return f"T1 surface copy {self.fou:g}" + gains
        if k is ControllerKind.PD:
            return f"PD kp {self.kp:.3g} kd {self.kd:.3g}"
        return Path(self.path).name + gains

    def build(self) -> HeadingController:
        """The controller this spec describes."""
        tnorm = TNorm.from_name(self.tnorm)
        k = self.kind
        if k is ControllerKind.PD:
            return PDHeadingController(kp=self.kp, kd=self.kd, tf=self.tf, name=self.label)
        if k is ControllerKind.T1_SURFACE:
            return SurfaceTableController(
                e_nodes=_SURFACE_AXIS, de_nodes=_SURFACE_AXIS,
                table=_surface_table(self.fou, self.reducer, self.tnorm, self.output_gain),
                ke=self.ke, kde=self.kde, name=self.label)
        if k is ControllerKind.FILE:
            from ..io import load

            fls: Any = load(self.path)
            if self.output_gain != 1.0:
                from .baselines import scaled_consequents

                fls = scaled_consequents(fls, self.output_gain)
        else:
            fls = _paper_system(k, self.fou, self.reducer, tnorm.value, self.output_gain)
        return FuzzyHeadingController(fls=fls, ke=self.ke, kde=self.kde, name=self.label)

    def to_dict(self) -> dict[str, Any]:
        """Plain values (TOML/JSON-ready), only the fields that matter for the kind."""
        keep = {"kind", "label"}
        k = self.kind
        if k in (ControllerKind.IT2, ControllerKind.T1_MATCHED, ControllerKind.T1_SLOPE_MATCHED,
                 ControllerKind.T1_SURFACE):
            keep |= {"fou"}
        if k in (ControllerKind.IT2, ControllerKind.T1_SURFACE):
            keep |= {"reducer"}
        if k is not ControllerKind.PD:
            keep |= {"ke", "kde", "tnorm"}
            if self.output_gain != 1.0:  # only when used: older records stay identical
                keep |= {"output_gain"}
        else:
            keep |= {"kp", "kd", "tf"}
        if k is ControllerKind.FILE:
            keep |= {"path"}
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name in keep}
        out["kind"] = k.value
        return out

    @classmethod
    def from_table(
        cls, table: Mapping[str, Any], *, where: str, base_dir: Path | None = None
    ) -> ControllerSpec:
        """Build from a TOML table, e.g. ``{kind = "it2", fou = 0.2}``; errors name ``where``.

        A relative ``path`` (kind ``file``) is taken relative to ``base_dir`` when given.
        """
        t = Table(table, where, base_dir)
        kind_name = t.get("kind", str)
        try:
            kind = ControllerKind(kind_name)
        except ValueError:
            known = ", ".join(m.value for m in ControllerKind)
            raise ConfigError(f"{where}: kind={kind_name!r} must be one of {known}") from None
        values: dict[str, Any] = {"kind": kind}
        for key, kinds in _APPLIES_TO.items():
            if key in t and kind not in kinds:
                allowed = ", ".join(repr(k.value) for k in kinds)
                raise ConfigError(
                    f"{where}: {key}={t.data[key]!r} does not apply to kind {kind.value!r} "
                    f"(only to {allowed}); remove it"
                )
        if kind is ControllerKind.PD and "kp" not in t:
            raise ConfigError(
                f"{where}: kind 'pd' needs its gains: kp (V/rad, > 0) and optionally kd "
                "(V s/rad, >= 0, default 0) and tf (s, default 0.02)"
            )
        for f in fields(cls):
            if f.name == "kind":
                continue
            if f.name in t:
                kind_type: type = str if f.name in ("reducer", "tnorm", "path", "label") else float
                values[f.name] = t.get(f.name, kind_type)
        t.done()
        if kind is ControllerKind.FILE and "path" in values and t.base_dir is not None:
            p = Path(values["path"])
            values["path"] = str(p if p.is_absolute() else t.base_dir / p)
        try:
            return cls(**values)
        except ValueError as exc:
            raise ConfigError(f"{where}: {exc}") from None


_FUZZY = (ControllerKind.FLC, ControllerKind.IT2, ControllerKind.T1_MATCHED,
          ControllerKind.T1_SLOPE_MATCHED, ControllerKind.T1_SURFACE)
#: Which fields apply to which kinds: any other kind must leave them at their defaults
#: (a configuration must not even give them): a value that would be silently ignored -- and
#: would still change a sweep's identity -- is an error.
_APPLIES_TO: dict[str, tuple[ControllerKind, ...]] = {
    "fou": (ControllerKind.IT2, ControllerKind.T1_MATCHED, ControllerKind.T1_SLOPE_MATCHED,
            ControllerKind.T1_SURFACE),
    "reducer": (ControllerKind.IT2, ControllerKind.T1_SURFACE),
    "tnorm": _FUZZY,
    "ke": (*_FUZZY, ControllerKind.FILE),
    "kde": (*_FUZZY, ControllerKind.FILE),
    "output_gain": (*_FUZZY, ControllerKind.FILE),
    "kp": (ControllerKind.PD,),
    "kd": (ControllerKind.PD,),
    "tf": (ControllerKind.PD,),
    "path": (ControllerKind.FILE,),
}


@functools.lru_cache(maxsize=256)
def _paper_system(kind: ControllerKind, fou: float, reducer: str, tnorm: str,
                  gain: float) -> Any:
    """The fuzzy system of a built-in kind (immutable, so one object serves every spec that
    asks for it: the study builds hundreds of specs over a handful of systems)."""
    t = TNorm.from_name(tnorm)
    if kind is ControllerKind.FLC:
        fls: Any = heading_fls(0.0, tnorm=t)
    elif kind is ControllerKind.IT2:
        fls = heading_fls(fou, reducer=Reducer.from_name(reducer).value, tnorm=t)
    elif kind is ControllerKind.T1_MATCHED:
        fls = dead_zone_matched_fls(fou, tnorm=t)
    else:
        from .baselines import slope_matched_fls

        fls = slope_matched_fls(fou, tnorm=t)
    if gain != 1.0:
        from .baselines import scaled_consequents

        fls = scaled_consequents(fls, gain)
    return fls


#: Grid of the surface tables (both inputs): 401 points on [-1, 1], step 0.005.
SURFACE_POINTS = 401
_SURFACE_AXIS = np.linspace(-1.0, 1.0, SURFACE_POINTS)


@functools.lru_cache(maxsize=16)
def _surface_table(fou: float, reducer: str, tnorm: str, gain: float) -> np.ndarray:
    """The IT2FLC's output on the surface grid (computed once per process; read-only)."""
    fls = _paper_system(ControllerKind.IT2, fou, reducer, tnorm, gain)
    return SurfaceTableController.from_system(fls, points=SURFACE_POINTS).table


class Table:
    """A TOML table being mapped onto Python values, tracking which keys were used.

    Every lookup checks the value's type; :meth:`done` raises on keys never looked up.
    Messages name ``where`` (``"configs/paper.toml [study]"``) and the key.
    """

    def __init__(
        self,
        data: Mapping[str, Any],
        where: str,
        base_dir: Path | None = None,
        *,
        section: str = "",
    ) -> None:
        self.file = where
        self.section = section
        self.where = f"{where} [{section}]" if section else where
        if not isinstance(data, Mapping):
            raise ConfigError(f"{self.where}: expected a table, got {data!r}")
        self.data = data
        self.base_dir = base_dir
        self.used: set[str] = set()

    def __contains__(self, key: str) -> bool:
        return key in self.data

    def get(self, key: str, kind: type | Callable[[Any], Any], default: Any = ...) -> Any:
        if key not in self.data:
            if default is ...:
                raise ConfigError(f"{self.where}: missing key {key!r}")
            return default
        self.used.add(key)
        value = self.data[key]
        return _convert(value, kind, f"{self.where}: {key}")

    def get_list(self, key: str, kind: type, default: Any = ...) -> Any:
        if key not in self.data:
            if default is ...:
                raise ConfigError(f"{self.where}: missing key {key!r}")
            return default
        self.used.add(key)
        value = self.data[key]
        if not isinstance(value, list):
            raise ConfigError(f"{self.where}: {key}={value!r} must be a list")
        return [_convert(v, kind, f"{self.where}: {key}[{i}]") for i, v in enumerate(value)]

    def sub(self, key: str) -> Table:
        """A nested table (empty if absent)."""
        value = self.data.get(key, {})
        if key in self.data:
            self.used.add(key)
        section = f"{self.section}.{key}" if self.section else key
        return Table(value, self.file, self.base_dir, section=section)

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise ConfigError(f"{self.where}: unknown key(s) {unknown}")


def _convert(value: Any, kind: type | Callable[[Any], Any], what: str) -> Any:
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{what}={value!r} must be a number")
        if not math.isfinite(value):
            raise ConfigError(f"{what}={value!r} must be finite")
        return float(value)
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{what}={value!r} must be an integer")
        return value
    if kind is str:
        if not isinstance(value, str):
            raise ConfigError(f"{what}={value!r} must be a string")
        return value
    if kind is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{what}={value!r} must be true or false")
        return value
    try:
        return kind(value)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"{what}={value!r}: {exc}") from None


def read_toml(path: str | Path) -> dict[str, Any]:
    """Parse a TOML file; syntax errors become :class:`ConfigError` naming the file.

    Only regular files of at most 64 MiB of UTF-8 text are read (a FIFO, a device, a binary
    or non-UTF-8 file is a :class:`ConfigError` naming the file; see :mod:`it2track._files`).
    """
    path = Path(path)
    try:
        text = read_text(path, what="TOML configuration")
    except InputFileError as exc:
        raise ConfigError(str(exc)) from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read: {exc.strerror or exc}") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: invalid TOML: {exc}") from None


def robot_from_table(t: Table) -> RobotParams:
    """``[robot]`` (``half_track``, ``wheel_radius``) with ``[robot.motor]`` (MotorParams
    fields) onto :class:`RobotParams`; absent keys keep the paper's Table 3 values."""
    base = RobotParams()
    motor_t = t.sub("motor")
    motor_values = {
        f.name: motor_t.get(f.name, float) for f in fields(MotorParams) if f.name in motor_t
    }
    motor_t.done()
    values: dict[str, Any] = {
        key: t.get(key, float) for key in ("half_track", "wheel_radius") if key in t
    }
    t.done()
    try:
        motor = replace(base.motor, **motor_values)
        return replace(base, motor=motor, **values)
    except ValueError as exc:
        raise ConfigError(f"{t.where}: {exc}") from None


def plant_from_root(root: Table) -> PlantSpec | None:
    """The top-level ``[plant]`` table (:func:`it2track.plant.specs.plant_from_dict`: ``kind =
    "kinematic" | "lti" | "mujoco"`` and that family's keys), or None (the paper's robot)."""
    if "plant" not in root:
        return None
    root.used.add("plant")
    try:
        return plant_from_dict(root.data["plant"], where=f"{root.file} [plant]")
    except ValueError as exc:
        raise ConfigError(str(exc)) from None


def loop_config_from_table(
    t: Table, robot: RobotParams, *, seed: int, plant: PlantSpec | None = None
) -> LoopConfig:
    """``[simulation]`` (``duration``, ``ts``, ``noise_rate``, ``start_pose``,
    ``quadrature_nodes``, ``desired_heading_pose``, ``metric_start``) onto
    :class:`LoopConfig`, with ``plant`` (from :func:`plant_from_root`)."""
    values: dict[str, Any] = {}
    for key in ("duration", "ts", "noise_rate", "metric_start"):
        if key in t:
            values[key] = t.get(key, float)
    if "start_pose" in t and isinstance(t.data["start_pose"], str):
        values["start_pose"] = t.get("start_pose", str)
        if values["start_pose"] != ON_PATH:
            raise ConfigError(f"{t.where}: start_pose={values['start_pose']!r} must be "
                              f"[x, y, theta] or {ON_PATH!r}")
    elif "start_pose" in t:
        pose = t.get_list("start_pose", float)
        if len(pose) != 3:
            raise ConfigError(f"{t.where}: start_pose={pose!r} must be [x, y, theta] or "
                              f"{ON_PATH!r}")
        values["start_pose"] = tuple(pose)
    if "desired_heading_pose" in t:
        values["desired_heading_pose"] = t.get("desired_heading_pose", str)
    if "quadrature_nodes" in t:
        values["quadrature_nodes"] = t.get("quadrature_nodes", int)
    t.done()
    try:
        return LoopConfig(robot=robot, seed=seed, plant=plant, **values)
    except ValueError as exc:
        raise ConfigError(f"{t.where}: {exc}") from None
