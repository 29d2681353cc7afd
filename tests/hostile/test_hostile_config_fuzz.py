"""Every key of every configuration file, set to each of a list of hostile values (wrong
types, extremes, NaN, huge integers, nested tables, paths to nowhere): loading either succeeds
or raises ``ConfigError`` naming the file -- never another exception (a traceback for the
user), never a hang. About 2 000 files, a second or two."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from it2track.experiments.optimize import load_optimize_config
from it2track.experiments.specs import ConfigError
from it2track.experiments.study import load_study_config
from it2track.experiments.sweep import load_sweep_config

VALUES = (
    "0", "-1", "1e308", "-1e308", "nan", "inf", "-inf", "1e-300", '"abc"', '""',
    "12345678901234567890123", "[]", '[1, "a"]', "{}", "{ a = 1 }", "true", "0.5", "3",
    "[0.1, 0.1]", "[[1]]", "1979-05-27T07:32:00Z", '"on_path"', '"../../etc/passwd"',
    '"/dev/zero"', '"x.csv"', '"x.t2fis"', "{ start = -5, count = 2 }", "{ count = 1e3 }",
)  # fmt: skip

#: loader -> (valid base: section -> {key: value}, keys to fuzz: section -> keys)
FILES: dict[str, tuple[Callable[[Path], Any], dict[str, dict[str, str]], dict[str, list[str]]]] = {
    "sweep": (
        load_sweep_config,
        {"sweep": {"seeds": "2", "noise_std": "0.1", "trajectories": '"straight"'},
         "simulation": {"duration": "1.0"}, "robot": {}, "robot.motor": {},
         "controllers": {"kind": '"it2"', "fou": "0.2"}},
        {"sweep": ["seed", "seeds", "noise_std", "trajectories", "chunk_size", "batch_size"],
         "simulation": ["duration", "ts", "noise_rate", "start_pose", "quadrature_nodes",
                        "desired_heading_pose", "metric_start"],
         "robot": ["half_track", "wheel_radius"],
         "robot.motor": ["resistance", "inductance", "inertia", "friction", "torque_constant",
                         "voltage_limit"],
         "controllers": ["kind", "fou", "ke", "kde", "reducer", "tnorm", "kp", "kd", "tf",
                         "path", "label"]},
    ),
    "optimize": (
        load_optimize_config,
        {"optimize": {"objective": '"ISE"', "train_seeds": "2",
                      "holdout_seeds": "{ start = 100, count = 2 }", "noise_std": "0.05",
                      "trajectories": '["straight"]'},
         "optimize.symmetric": {}, "optimize.asymmetric": {}, "controller": {},
         "simulation": {"duration": "1.0"}},
        {"optimize": ["seed", "objective", "train_seeds", "holdout_seeds", "noise_std",
                      "trajectories", "bounds", "compare", "compare_flc", "batch_size"],
         "optimize.symmetric": ["grid", "xatol", "maxiter"],
         "optimize.asymmetric": ["enabled", "popsize", "maxiter", "tol", "seed", "mutation",
                                 "recombination", "init"],
         "controller": ["ke", "kde", "reducer", "tnorm"],
         "simulation": ["duration", "ts"]},
    ),
    "study": (
        load_study_config,
        {"study": {"seeds": "2"}, "pd": {}, "controllers": {"kind": '"flc"'}, "simulation": {},
         "verdicts": {}, "robustness": {}},
        {"study": ["seed", "trajectories", "fous", "main_fou", "noise_std", "noise_levels",
                   "fou_sweep", "seeds", "sweep_seeds", "figure_seed", "matched_baseline",
                   "pd_baseline", "batch_size"],
         "pd": ["seeds", "kp_grid", "kd_grid", "tf", "kp", "kd", "effort_limit",
                "match_effort"],
         "controllers": ["kind", "fou", "ke", "kde", "label", "path", "kp"],
         "simulation": ["metric_start", "start_pose", "noise_rate"],
         "verdicts": ["batch", "cap", "replication", "resamples", "seed"],
         "robustness": ["seeds", "baseline_batches", "factorial"]},
    ),
}  # fmt: skip

TARGETS = [(f, s, k) for f, (_, _, keys) in FILES.items() for s, ks in keys.items() for k in ks]


def _text(base: dict[str, dict[str, str]]) -> str:
    out = []
    for section, values in base.items():
        if not values:
            continue
        out.append("[[controllers]]" if section == "controllers" else f"[{section}]")
        out += [f"{k} = {v}" for k, v in values.items()]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize(("file", "section", "key"), TARGETS,
                         ids=[f"{f}-{s}-{k}" for f, s, k in TARGETS])
def test_every_value_of_every_key_loads_or_is_a_config_error(
    tmp_path: Path, file: str, section: str, key: str
) -> None:
    load, base, _ = FILES[file]
    for i, value in enumerate(VALUES):
        edited = {s: dict(kv) for s, kv in base.items()}
        edited[section][key] = value
        path = tmp_path / f"{i}.toml"
        path.write_text(_text(edited))
        try:
            load(path)
        except ConfigError as exc:
            assert str(path) in str(exc), f"{key} = {value}: {exc}"
        except Exception as exc:  # a traceback for the user
            pytest.fail(f"{section}.{key} = {value}: {type(exc).__name__}: {exc}")
