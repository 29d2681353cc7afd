"""Reading a sweep's TOML file (:func:`load_sweep_config`) and the axis parsers it shares with the
optimiser (:func:`expand_axes`, :func:`parse_seeds`, :func:`parse_noise_levels`,
:func:`parse_trajectories`).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..._limits import ResourceLimitError, check_memory
from ...plant import RobotParams
from ...plant.noise import MAX_NOISE_STD
from ...tracking import LoopConfig, Target, check_task, reference_from_dict
from ...tracking.simulate import MAX_INDEX
from ...tracking.trajectories import PAPER_TRAJECTORIES
from ..specs import (
    ConfigError,
    ControllerSpec,
    Table,
    loop_config_from_table,
    plant_from_root,
    read_toml,
    robot_from_table,
)
from .chunks import DEFAULT_BATCH_SIZE
from .plan import DEFAULT_CHUNK_SIZE, SweepPlan
from .refs import ControllerRef, TrajectoryRef, _file_sha256

__all__ = [
    "check_targets",
    "expand_axes",
    "load_sweep_config",
    "parse_noise_levels",
    "parse_seeds",
    "parse_trajectories",
]


def expand_axes(data: Mapping[str, Any], where: str) -> list[dict[str, Any]]:
    """Cartesian expansion of a table whose list values are axes.

    Keys keep their order; the first list-valued key varies slowest. Nested tables are returned
    untouched (expand them separately). An empty list is a :class:`ConfigError`.

    Examples
    --------
    >>> expand_axes({"kind": "it2", "fou": [0.1, 0.2], "ke": [1, 2]}, "f.toml")
    ... # doctest: +NORMALIZE_WHITESPACE
    [{'kind': 'it2', 'fou': 0.1, 'ke': 1}, {'kind': 'it2', 'fou': 0.1, 'ke': 2},
     {'kind': 'it2', 'fou': 0.2, 'ke': 1}, {'kind': 'it2', 'fou': 0.2, 'ke': 2}]
    """
    axes = {k: v for k, v in data.items() if isinstance(v, list)}
    for key, values in axes.items():
        if not values:
            raise ConfigError(f"{where}: {key}=[] is an empty axis (give at least one value)")
    out = []
    for combo in itertools.product(*axes.values()):  # (no axes: one empty combination)
        chosen = dict(zip(axes, combo, strict=True))
        out.append({k: chosen.get(k, v) for k, v in data.items()})
    return out


def parse_seeds(t: Table, key: str, default: Any = ...) -> tuple[int, ...]:
    """Seed indices: a count ``n`` (``0, 1, ..., n-1``), a list, or ``{start = s, count = n}``."""
    if key not in t:
        if default is ...:
            raise ConfigError(f"{t.where}: missing key {key!r}")
        return tuple(default)
    raw = t.data[key]
    what = f"{t.where}: {key}"
    if isinstance(raw, Mapping):
        sub = t.sub(key)
        start = sub.get("start", int, 0)
        count = sub.get("count", int)
        sub.done()
        if start < 0 or count < 1:
            raise ConfigError(f"{what}={dict(raw)!r} needs start >= 0 and count >= 1")
        if start + count - 1 > MAX_INDEX:
            raise ConfigError(
                f"{what}={dict(raw)!r}: seed indices must lie in [0, 2**63 - 1] (the last "
                f"would be {start + count - 1})"
            )
        _check_seed_count(count, what)
        return tuple(range(start, start + count))
    if isinstance(raw, list):
        seeds = t.get_list(key, int)
        if not seeds:
            raise ConfigError(f"{what}=[] is an empty axis (give at least one seed index)")
        bad = [s for s in seeds if s < 0]
        if bad:
            raise ConfigError(f"{what}={seeds!r}: seed indices must be >= 0 (got {bad[0]})")
        big = [s for s in seeds if s > MAX_INDEX]
        if big:
            raise ConfigError(
                f"{what}: seed index {big[0]!r} is larger than 2**63 - 1, the largest allowed"
            )
        if len(set(seeds)) != len(seeds):
            raise ConfigError(f"{what}={seeds!r}: seed indices must not repeat")
        return tuple(seeds)
    count = t.get(key, int)
    if count < 1:
        raise ConfigError(f"{what}={count!r} must be a seed count >= 1, a list or a table")
    if count - 1 > MAX_INDEX:
        raise ConfigError(f"{what}={count!r}: seed indices must lie in [0, 2**63 - 1]")
    _check_seed_count(count, what)
    return tuple(range(count))


def _check_seed_count(count: int, what: str) -> None:
    """The seed indices are held in memory several times (a tuple of ints, sets to compare
    them, the run tables: ~100 bytes per index): refuse counts that would not fit."""
    try:
        check_memory(100 * count, what=f"{what}: {count} seed indices",
                     hint="give fewer seeds")
    except ResourceLimitError as exc:
        raise ConfigError(str(exc)) from None


def parse_noise_levels(t: Table, key: str) -> tuple[float, ...]:
    """Heading-noise standard deviations (rad): a number or a non-empty list, each >= 0."""
    raw = t.data.get(key)
    values = t.get_list(key, float) if isinstance(raw, list) else [t.get(key, float)]
    if not values:
        raise ConfigError(f"{t.where}: {key}=[] is an empty axis (give at least one value)")
    for v in values:
        if v < 0:
            raise ConfigError(f"{t.where}: {key} value {v!r} must be >= 0")
        if v > MAX_NOISE_STD:
            raise ConfigError(
                f"{t.where}: {key} value {v!r} exceeds {MAX_NOISE_STD:g} rad, the largest "
                "heading-noise standard deviation allowed (beyond it theta + noise loses all "
                "precision, and far beyond it overflows)"
            )
    if len(set(values)) != len(values):
        raise ConfigError(f"{t.where}: {key}={values!r}: values must not repeat")
    return tuple(values)


def parse_trajectories(
    t: Table, key: str, base_dir: Path | None
) -> tuple[tuple[TrajectoryRef, ...], tuple[Target, ...]]:
    """Trajectory names or CSV paths (relative to ``base_dir``), or reference-signal tables
    (``{kind = "step", amplitude = ..., at = ..., initial = ..., name = ...}``, for a
    single-input ``[plant]``); returns refs and the loaded targets. Unknown names, unreadable
    files, repeats and a mix of trajectories and references are :class:`ConfigError`."""
    raw = t.data.get(key)
    if isinstance(raw, list) and raw and all(isinstance(v, Mapping) for v in raw):
        return _parse_references(t, key, raw)
    if isinstance(raw, list) and any(isinstance(v, Mapping) for v in raw):
        raise ConfigError(f"{t.where}: {key} mixes trajectory names and reference tables; a "
                          "robot follows trajectories, a single-input plant reference signals")
    names = t.get_list(key, str) if isinstance(raw, list) else [t.get(key, str)]
    if not names:
        raise ConfigError(f"{t.where}: {key}=[] is an empty axis (give at least one trajectory)")
    refs: list[TrajectoryRef] = []
    loaded: list[Target] = []
    for name in names:
        if name in PAPER_TRAJECTORIES:
            ref = TrajectoryRef(name)
        elif name.lower().endswith(".csv"):
            p = Path(name) if base_dir is None else base_dir / name  # (absolute: kept)
            try:
                digest = _file_sha256(p)
            except OSError as exc:
                raise ConfigError(
                    f"{t.where}: {key}: cannot read {str(p)!r}: {exc.strerror or exc}"
                ) from None
            except ValueError as exc:
                raise ConfigError(f"{t.where}: {key}: {exc}") from None
            ref = TrajectoryRef(p.stem, str(p), digest)
        else:
            raise ConfigError(
                f"{t.where}: {key}: unknown trajectory {name!r}; use one of "
                f"{sorted(PAPER_TRAJECTORIES)} or a .csv waypoint file"
            )
        refs.append(ref)
    refs = _unique_trajectory_names(refs, f"{t.where}: {key}")
    for ref in refs:
        try:
            loaded.append(ref.load())
        except ValueError as exc:
            raise ConfigError(f"{t.where}: {key}: {exc}") from None
    return tuple(refs), tuple(loaded)


def _parse_references(
    t: Table, key: str, raw: list[Mapping[str, Any]]
) -> tuple[tuple[TrajectoryRef, ...], tuple[Target, ...]]:
    t.used.add(key)
    refs: list[TrajectoryRef] = []
    for i, table in enumerate(raw):
        try:
            ref = reference_from_dict(dict(table), f"{t.where}: {key}[{i}]")
        except ValueError as exc:
            raise ConfigError(str(exc)) from None
        if any(r.name == ref.name for r in refs):
            raise ConfigError(f"{t.where}: {key}[{i}]: name={ref.name!r} repeats; every "
                              "reference needs a distinct name")
        refs.append(TrajectoryRef(ref.name, reference=ref))
    return tuple(refs), tuple(r.load() for r in refs)


def _unique_trajectory_names(refs: list[TrajectoryRef], where: str) -> list[TrajectoryRef]:
    """Give CSV trajectories that share a file name distinct names (the name is their identity
    in rows, figures and hashes): ``a/path.csv`` and ``b/path.csv`` become ``a-path`` and
    ``b-path``, with as many parent folders as it takes. The same file or built-in twice is a
    :class:`ConfigError`."""
    keys = [(r.path and str(Path(r.path).resolve())) or r.name for r in refs]
    for i, k in enumerate(keys):
        if k in keys[:i]:
            raise ConfigError(
                f"{where}: {refs[i].path or refs[i].name!r} is listed twice (trajectories must "
                "not repeat)"
            )
    names = [r.name for r in refs]
    for depth in range(1, 64):  # up to 63 folders (one stem twice in one folder: never)
        clash = {n for n in names if names.count(n) > 1}
        if not clash:
            break
        for i, r in enumerate(refs):
            if names[i] in clash and r.path:
                parts = Path(keys[i]).parent.parts[-depth:]
                names[i] = "-".join([*(p.strip("/") or "root" for p in parts), r.name])
    if len(set(names)) < len(names):
        raise ConfigError(f"{where}: cannot give the trajectories distinct names: {names}")
    return [replace(r, name=n) for r, n in zip(refs, names, strict=True)]


def check_targets(config: LoopConfig, targets: tuple[Target, ...], where: str) -> None:
    """The plant of ``config`` fits the targets (a robot for trajectories, a single-input plant
    for references), checked once at load time (:func:`~it2track.tracking.check_task`)."""
    try:
        check_task(targets, config)
    except ValueError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def _positive_int(t: Table, key: str, default: int) -> int:
    value = t.get(key, int, default)
    if value < 1:
        raise ConfigError(f"{t.where}: {key}={value!r} must be an integer >= 1")
    return int(value)


def _parse_controllers(
    entries: Any, file: str, base_dir: Path | None
) -> tuple[ControllerRef, ...]:
    """The ``[[controllers]]`` entries, expanded, each built once (errors name the entry)."""
    if not isinstance(entries, list) or not entries:
        raise ConfigError(f"{file}: [[controllers]] must list at least one controller table")
    refs: list[ControllerRef] = []
    origin: dict[str, str] = {}
    for i, entry in enumerate(entries):
        where = f"{file} [controllers][{i}]"
        if not isinstance(entry, Mapping):
            raise ConfigError(f"{where}: expected a table, got {entry!r}")
        expanded = expand_axes(entry, where)
        if "label" in entry and len(expanded) > 1:
            raise ConfigError(
                f"{where}: label={entry['label']!r} cannot name {len(expanded)} controllers; "
                "drop it (labels are derived from the values) or split the entry"
            )
        for values in expanded:
            if isinstance(values.get("path"), str) and base_dir is not None:
                values["path"] = str(base_dir / values["path"])  # (absolute: kept)
            spec = ControllerSpec.from_table(values, where=where)
            if spec.label in origin:
                raise ConfigError(
                    f"{where}: controller {spec.label!r} repeats one of {origin[spec.label]}; "
                    "every controller of a sweep needs a distinct label"
                )
            origin[spec.label] = where
            try:
                ref = ControllerRef.from_spec(spec)
            except OSError as exc:
                raise ConfigError(
                    f"{where}: controller {spec.label!r}: cannot read {spec.path!r}: "
                    f"{exc.strerror or exc}"
                ) from None
            except ValueError as exc:
                raise ConfigError(f"{where}: controller {spec.label!r}: {exc}") from None
            refs.append(ref)
    return tuple(refs)


def _parse_robots(
    t: Table,
) -> tuple[tuple[RobotParams, ...], dict[str, tuple[float, ...]]]:
    """Plant parameter sets from ``[robot]`` / ``[robot.motor]`` with list-valued axes."""
    raw = dict(t.data)
    motor = raw.pop("motor", {})
    if not isinstance(motor, Mapping):
        raise ConfigError(f"{t.where}: motor={motor!r} must be a table [robot.motor]")
    flat = {**raw, **{f"motor.{k}": v for k, v in motor.items()}}
    axis_keys = [k for k, v in flat.items() if isinstance(v, list)]
    robots: list[RobotParams] = []
    columns: dict[str, list[float]] = {k: [] for k in axis_keys}
    for values in expand_axes(flat, t.where):
        top = {k: v for k, v in values.items() if not k.startswith("motor.")}
        mot = {k[6:]: v for k, v in values.items() if k.startswith("motor.")}
        table = Table({**top, "motor": mot}, t.file, section="robot")
        robots.append(robot_from_table(table))
        for k in axis_keys:
            columns[k].append(values[k])
    return tuple(robots), {k: tuple(float(x) for x in v) for k, v in columns.items()}


def load_sweep_config(path: str | Path) -> SweepPlan:
    """Parse a sweep TOML file (see the packaged config ``sweep``, :mod:`it2track.configs`).

    Sections: ``[sweep]`` (``seed``, ``seeds``, ``noise_std``, ``trajectories``, ``chunk_size``,
    ``batch_size``), ``[simulation]`` (:class:`~it2track.tracking.LoopConfig` fields),
    ``[robot]`` / ``[robot.motor]`` (list values are axes), ``[[controllers]]`` (list values
    are axes).

    Raises
    ------
    ConfigError
        Naming the file, the section and the key of an unknown key, a bad value or an empty
        axis.
    """
    path = Path(path)
    file = str(path)
    data = read_toml(path)
    root = Table(data, file)
    st = root.sub("sweep")
    seed = st.get("seed", int, 0)
    if seed < 0:
        raise ConfigError(f"{st.where}: seed={seed!r} must be an integer >= 0")
    seeds = parse_seeds(st, "seeds")
    noise = parse_noise_levels(st, "noise_std")
    refs, trajectories = parse_trajectories(st, "trajectories", path.parent)
    chunk_size = _positive_int(st, "chunk_size", DEFAULT_CHUNK_SIZE)
    batch_size = _positive_int(st, "batch_size", DEFAULT_BATCH_SIZE)
    st.done()
    robots, robot_columns = _parse_robots(root.sub("robot"))
    plant = plant_from_root(root)
    config = loop_config_from_table(root.sub("simulation"), RobotParams(), seed=seed,
                                    plant=plant)  # fmt: skip
    check_targets(config, trajectories, st.where)
    if "controllers" not in data:
        raise ConfigError(f"{file}: missing [[controllers]] (at least one controller table)")
    root.used.add("controllers")
    controllers = _parse_controllers(data["controllers"], file, path.parent)
    root.done()
    try:
        return SweepPlan(
            config=config,
            robots=robots,
            robot_columns=robot_columns,
            controllers=controllers,
            trajectory_refs=refs,
            noise_std=noise,
            seeds=seeds,
            chunk_size=chunk_size,
            batch_size=batch_size,
            source=file,
            trajectories=trajectories,
        )
    except ValueError as exc:  # e.g. the plan would not fit in memory
        raise ConfigError(f"{file}: {exc}") from None
