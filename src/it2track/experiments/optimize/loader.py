"""Reading an optimisation TOML file (``configs/optimize.toml``) into an
:class:`~.config.OptimizeConfig`.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ...tracking import METRIC_NAMES
from ..specs import (
    ConfigError,
    Table,
    loop_config_from_table,
    plant_from_root,
    read_toml,
    robot_from_table,
)
from ..sweep import (
    DEFAULT_BATCH_SIZE,
    check_targets,
    parse_noise_levels,
    parse_seeds,
    parse_trajectories,
)
from .config import AsymmetricSettings, Objective, OptimizeConfig, SymmetricSettings

__all__ = ["load_optimize_config"]


def _parse_objective(t: Table) -> Objective:
    key = "objective"
    raw = t.data.get(key, ...)
    if raw is ...:
        raise ConfigError(f"{t.where}: missing key 'objective' (a metric name or {{ISE = 1.0}})")
    if isinstance(raw, str):
        name = t.get(key, str)
        weights: list[tuple[str, float]] = [(name, 1.0)]
    elif isinstance(raw, Mapping):
        sub = t.sub(key)
        if not raw:
            raise ConfigError(f"{sub.where}: empty objective (give weights, e.g. ISE = 1.0)")
        weights = [(name, sub.get(name, float)) for name in raw]
        sub.done()
    else:
        raise ConfigError(f"{t.where}: objective={raw!r} must be a metric name or a table")
    for name, w in weights:
        if name not in METRIC_NAMES:
            raise ConfigError(
                f"{t.where}: objective metric {name!r} unknown; choose from {list(METRIC_NAMES)}"
            )
        if w <= 0:
            raise ConfigError(f"{t.where}: objective weight {name}={w!r} must be > 0")
    return Objective(tuple(weights))


def _settings(t: Table, cls: type, spec: dict[str, type]) -> Any:
    values = {}
    for key, kind in spec.items():
        if key in t:
            values[key] = tuple(t.get_list(key, float)) if kind is list else t.get(key, kind)
    t.done()
    try:
        return cls(**values)
    except ValueError as exc:
        raise ConfigError(f"{t.where}: {exc}") from None


def load_optimize_config(path: str | Path) -> OptimizeConfig:
    """Parse an optimisation TOML file (see ``configs/optimize.toml``).

    Sections: ``[optimize]`` (``seed``, ``objective``, ``train_seeds``, ``holdout_seeds``,
    ``noise_std``, ``trajectories``, ``bounds``, ``compare``, ``compare_flc``, ``batch_size``),
    ``[optimize.symmetric]``, ``[optimize.asymmetric]``, ``[controller]`` (``ke``, ``kde``,
    ``reducer``, ``tnorm``), ``[simulation]``, ``[robot]`` / ``[robot.motor]``.

    Raises
    ------
    ConfigError
        Naming the file, section, key and value of an unknown key, a bad value or an empty list.
    """
    path = Path(path)
    file = str(path)
    root = Table(read_toml(path), file, path.parent)
    ot = root.sub("optimize")
    seed = ot.get("seed", int, 0)
    if seed < 0:
        raise ConfigError(f"{ot.where}: seed={seed!r} must be an integer >= 0")
    objective = _parse_objective(ot)
    train = parse_seeds(ot, "train_seeds")
    holdout = parse_seeds(ot, "holdout_seeds")
    noise = parse_noise_levels(ot, "noise_std")
    refs, trajectories = parse_trajectories(ot, "trajectories", path.parent)
    bounds = tuple(ot.get_list("bounds", float, [0.0, 1.5]))
    if len(bounds) != 2:
        raise ConfigError(f"{ot.where}: bounds={list(bounds)!r} must be [lo, hi]")
    compare = tuple(ot.get_list("compare", float, [0.1, 0.2, 0.3]))
    compare_flc = ot.get("compare_flc", bool, True)
    batch_size = ot.get("batch_size", int, DEFAULT_BATCH_SIZE)
    if batch_size < 1:
        raise ConfigError(f"{ot.where}: batch_size={batch_size!r} must be an integer >= 1")
    symmetric = _settings(
        ot.sub("symmetric"), SymmetricSettings, {"grid": int, "xatol": float, "maxiter": int}
    )
    asymmetric = _settings(
        ot.sub("asymmetric"),
        AsymmetricSettings,
        {
            "enabled": bool, "popsize": int, "maxiter": int, "tol": float, "seed": int,
            "mutation": list, "recombination": float, "init": str,
        },
    )  # fmt: skip
    ot.done()
    ct = root.sub("controller")
    ctrl = {k: ct.get(k, float) for k in ("ke", "kde") if k in ct}
    ctrl.update({k: ct.get(k, str) for k in ("reducer", "tnorm") if k in ct})
    ct.done()
    robot = robot_from_table(root.sub("robot"))
    config = loop_config_from_table(root.sub("simulation"), robot, seed=seed,
                                    plant=plant_from_root(root))  # fmt: skip
    check_targets(config, trajectories, ot.where)
    root.done()
    try:
        return OptimizeConfig(
            config=config,
            trajectory_refs=refs,
            trajectories=trajectories,
            noise_std=noise,
            train_seeds=train,
            holdout_seeds=holdout,
            objective=objective,
            bounds=(bounds[0], bounds[1]),
            compare=compare,
            compare_flc=compare_flc,
            symmetric=symmetric,
            asymmetric=asymmetric,
            batch_size=batch_size,
            source=file,
            **ctrl,
        )
    except ValueError as exc:
        raise ConfigError(f"{ot.where}: {exc}") from None
