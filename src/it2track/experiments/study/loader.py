"""Reading a study TOML file (``configs/paper.toml``) into a :class:`~.config.StudyConfig`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...tracking import check_task, get_trajectory
from ..baselines import FuzzyTuning
from ..choices import choices_from_list
from ..robustness import RobustnessConfig, check_defaults, robustness_config_from_table
from ..sequential import SequentialDesign
from ..specs import (
    ConfigError,
    ControllerSpec,
    Table,
    loop_config_from_table,
    plant_from_root,
    read_toml,
    robot_from_table,
)
from .config import PDTuning, StudyConfig

__all__ = ["load_study_config"]


def load_study_config(path: str | Path, **overrides: Any) -> StudyConfig:
    """Read a study TOML file (see ``configs/paper.toml``).

    Sections: ``[simulation]``, ``[robot]`` (+ ``[robot.motor]``), ``[study]``, ``[pd]`` (or
    ``pd_baseline = false`` in ``[study]``), ``[tuning]`` (or ``tuning = false``),
    ``[[choices]]`` (the open modelling choices), ``[robustness]`` (+
    ``[robustness.sensitivity]``; or ``robustness = false``), ``[verdicts]`` (seeds by need and
    the replication probability: ``batch``, ``cap``, ``replication``, ``resamples``, ``seed``),
    ``[[controllers]]`` (extra controllers).
    ``overrides`` replace ``[study]`` values (e.g. ``seeds`` from the command line).

    Raises
    ------
    ConfigError
        Naming the file, section, key and value of anything unknown or invalid.
    """
    path = Path(path)
    data = read_toml(path)
    root = Table(data, str(path), path.parent)
    study_t = root.sub("study")
    seed = study_t.get("seed", int, 0)
    if seed < 0:
        raise ConfigError(f"{study_t.where}: seed={seed!r} must be >= 0")
    robot = robot_from_table(root.sub("robot"))
    loop = loop_config_from_table(root.sub("simulation"), robot, seed=seed,
                                  plant=plant_from_root(root))  # fmt: skip
    if loop.plant is not None:  # the study tracks the paper's paths: a robot plant only
        try:
            check_task([get_trajectory("straight")], loop)
        except ValueError as exc:
            raise ConfigError(f"{root.file} [plant]: {exc}") from None
    values: dict[str, Any] = {"loop": loop}
    for key in ("trajectories",):
        if key in study_t:
            values[key] = tuple(study_t.get_list(key, str))
    for key in ("fous", "noise_levels", "fou_sweep"):
        if key in study_t:
            values[key] = tuple(study_t.get_list(key, float))
    for key in ("main_fou", "noise_std"):
        if key in study_t:
            values[key] = study_t.get(key, float)
    for key in ("seeds", "sweep_seeds", "figure_seed", "batch_size"):
        if key in study_t:
            values[key] = study_t.get(key, int)
    if "matched_baseline" in study_t:
        values["matched_baseline"] = study_t.get("matched_baseline", bool)
    use_pd = study_t.get("pd_baseline", bool, True)
    use_tuning = study_t.get("tuning", bool, True)
    use_robustness = study_t.get("robustness", bool, True)
    study_t.done()
    verdicts_t = root.sub("verdicts")
    vv: dict[str, Any] = {}
    for key, name in (("batch", "batch"), ("cap", "cap"), ("resamples", "resamples"),
                      ("seed", "seed")):
        if key in verdicts_t:
            vv[name] = verdicts_t.get(key, int)
    if "replication" in verdicts_t:
        vv["target"] = verdicts_t.get("replication", float)
    verdicts_t.done()
    try:
        values["verdicts"] = SequentialDesign(
            first=min(values.get("sweep_seeds", StudyConfig.sweep_seeds),
                      vv.get("cap", SequentialDesign.cap)), **vv)
    except ValueError as exc:
        raise ConfigError(f"{verdicts_t.where}: {exc}") from None
    tuning_t = root.sub("tuning")
    pd_tuned = use_pd and "kp" not in root.sub("pd")
    if not pd_tuned and use_tuning:
        if "tuning" in study_t or "tuning" in root:
            raise ConfigError(f"{study_t.where}: tuning needs the PD tuning (its seeds and "
                              "effort limit): set [pd] without kp/kd and pd_baseline = true, "
                              "or tuning = false")
        use_tuning = False  # the fuzzy tuning needs the PD's: off with it unless asked for
    if use_tuning:
        tv: dict[str, Any] = {}
        if "controllers" in tuning_t:
            tv["controllers"] = tuple(tuning_t.get_list("controllers", str))
        for key in ("ke_grid", "kde_grid", "gain_grid"):
            if key in tuning_t:
                tv[key] = tuple(tuning_t.get_list(key, float))
        try:
            values["tuning"] = FuzzyTuning(**tv)
        except ValueError as exc:
            raise ConfigError(f"{tuning_t.where}: {exc}") from None
    else:
        values["tuning"] = None
    tuning_t.done()
    choices = (choices_from_list(root.get("choices", list), str(path)) if "choices" in root
               else RobustnessConfig().choices)
    rob_t = root.sub("robustness")
    if use_robustness:
        values["robustness"] = robustness_config_from_table(rob_t, choices)
        if "choices" in root:
            check_defaults(choices, loop, str(path))
    else:
        values["robustness"] = None
        rob_t.done()
    pd_t = root.sub("pd")
    if use_pd:
        pd_values: dict[str, Any] = {}
        for key in ("seeds",):
            if key in pd_t:
                pd_values[key] = pd_t.get(key, int)
        for key in ("kp_grid", "kd_grid"):
            if key in pd_t:
                pd_values[key] = tuple(pd_t.get_list(key, float))
        for key in ("tf", "kp", "kd", "effort_limit"):
            if key in pd_t:
                pd_values[key] = pd_t.get(key, float)
        if "match_effort" in pd_t:
            pd_values["match_effort"] = pd_t.get("match_effort", bool)
        try:
            values["pd"] = PDTuning(**pd_values)
        except ValueError as exc:
            raise ConfigError(f"{pd_t.where}: {exc}") from None
    else:
        values["pd"] = None
    pd_t.done()
    extra = []
    if "controllers" in root:
        ctrl_list = root.get("controllers", list)
        for i, entry in enumerate(ctrl_list):
            where = f"{path} [[controllers]] #{i + 1}"
            spec = ControllerSpec.from_table(entry, where=where, base_dir=path.parent)
            try:  # build once now: a bad file or value fails here, not after minutes of runs
                spec.build()
            except (ValueError, OSError) as exc:
                raise ConfigError(f"{where}: {exc}") from None
            extra.append(spec)
    values["extra_controllers"] = tuple(extra)
    root.done()
    values.update(overrides)
    if "trajectories" in values:
        values["trajectories"] = tuple(
            _resolve_trajectory(name, path) for name in values["trajectories"]
        )
    try:
        return StudyConfig(**values)
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc}") from None


def _resolve_trajectory(name: str, path: Path) -> str:
    """A built-in name as is; a CSV file relative to the config file's folder, checked."""
    if name.lower().endswith(".csv") and not Path(name).is_absolute():
        name = str(path.parent / name)
    try:
        get_trajectory(name)
    except ValueError as exc:
        raise ConfigError(f"{path} [study] trajectories: {exc}") from None
    return name
