"""The paper's open modelling choices as data (docs/model.md; DESIGN.md sec. 8).

A :class:`Choice` names something the paper leaves open or misprints, the configuration paths
it sets, the paper-faithful default and the plausible alternatives. The study config lists
them as ``[[choices]]`` tables::

    [[choices]]
    name = "half_track"
    sets = "robot.half_track"            # or a list of paths, e.g. ["simulation.ts", ...]
    default = 5.6                        # one value per path (a list for several paths)
    alternatives = [0.28, 0.056]
    doc = "half-track"                   # section anchor in docs/model.md

Paths (:data:`PATHS`) and what a value means:

``robot.half_track``               half the wheel track l, m (> 0)
``simulation.ts``                  control period, s
``simulation.noise_rate``          rate the heading noise is held at, Hz
``simulation.start_pose``          ``[x, y, theta]`` or ``"on_path"``
``simulation.desired_heading_pose`` ``"current"`` or ``"previous"`` (the paper's y(k-1))
``simulation.metric_start``        start of the error-integral window, s
``noise.sigma``                    ``"sweep"`` (the robustness noise levels) or one sigma, rad
``metrics.heading``                integrals on the ``"true"`` or the ``"measured"`` heading
``controllers.ke``, ``controllers.kde``  input gains of every fuzzy controller
``controllers.output_gain``        output gain g of every untuned fuzzy controller (V0 +- g u)
``controllers.tuned``              ``true``: the tuned fuzzy controllers instead of the paper's

Applying a set of path values to the study's loop gives a :class:`Variant`: the loop, the
fuzzy controllers' gains, the noise levels and the heading the integrals use.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..tracking import ON_PATH, LoopConfig, PoseTiming
from .specs import ConfigError, Table

__all__ = [
    "DEFAULT_CHOICES",
    "PATHS",
    "Choice",
    "Variant",
    "apply_settings",
    "baseline_value",
    "choices_from_list",
    "describe_settings",
    "describe_value",
    "format_value",
]

SWEEP = "sweep"


def _number(positive: bool) -> Callable[[Any, str], float]:
    def parse(value: Any, where: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(
                value) or (value <= 0 if positive else value < 0):
            raise ConfigError(f"{where}={value!r} must be a finite number "
                              + ("> 0" if positive else ">= 0"))
        return float(value)
    return parse


def _word(allowed: Sequence[str]) -> Callable[[Any, str], str]:
    def parse(value: Any, where: str) -> str:
        if not isinstance(value, str) or value not in allowed:
            raise ConfigError(f"{where}={value!r} must be one of {list(allowed)}")
        return value
    return parse


def _pose(value: Any, where: str) -> Any:
    if value == ON_PATH:
        return ON_PATH
    if (isinstance(value, list | tuple) and len(value) == 3
            and all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                    for v in value)):
        return tuple(float(v) for v in value)
    raise ConfigError(f"{where}={value!r} must be [x, y, theta] or {ON_PATH!r}")


def _sigma(value: Any, where: str) -> Any:
    if value == SWEEP:
        return SWEEP
    try:
        return _number(False)(value, where)
    except ConfigError:
        raise ConfigError(f"{where}={value!r} must be {SWEEP!r} or a noise level >= 0, "
                          "rad") from None


def _flag(value: Any, where: str) -> bool:
    if not isinstance(value, bool):
        raise ConfigError(f"{where}={value!r} must be true or false")
    return value


#: Every configuration path a choice may set, with the parser of its values.
PATHS: dict[str, Callable[[Any, str], Any]] = {
    "robot.half_track": _number(True),
    "simulation.ts": _number(True),
    "simulation.noise_rate": _number(True),
    "simulation.start_pose": _pose,
    "simulation.desired_heading_pose": _word([t.value for t in PoseTiming]),
    "simulation.metric_start": _number(False),
    "noise.sigma": _sigma,
    "metrics.heading": _word(["true", "measured"]),
    "controllers.ke": _number(True),
    "controllers.kde": _number(False),
    "controllers.output_gain": _number(True),
    "controllers.tuned": _flag,
}


def format_value(value: Any) -> str:
    """A path value as written in tables: ``0.056``, ``on_path``, ``[0, 0, 0]``, ``true``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple | list):
        return "[" + ", ".join(format_value(v) for v in value) + "]"
    return str(value)


@dataclass(frozen=True, kw_only=True)
class Choice:
    """One open modelling choice.

    Parameters
    ----------
    name : str
        Identifier (letters, digits, ``_``), unique in a study.
    sets : tuple of str
        Configuration paths (keys of :data:`PATHS`) the choice sets together.
    default : tuple
        The paper-faithful value of each path (the study's own setting).
    alternatives : tuple of tuple
        The plausible alternatives, each one value per path.
    description : str
        One line: what the paper says and why it is open.
    doc : str
        Section anchor in ``docs/model.md``.
    """

    name: str
    sets: tuple[str, ...]
    default: tuple[Any, ...]
    alternatives: tuple[tuple[Any, ...], ...]
    description: str = ""
    doc: str = ""

    def __post_init__(self) -> None:
        where = f"choice {self.name!r}"
        if not self.name or not self.name.replace("_", "").isalnum():
            raise ValueError(f"choice name={self.name!r} must be letters, digits and _")
        if not self.sets or len(set(self.sets)) != len(self.sets):
            raise ValueError(f"{where}: sets={list(self.sets)!r} must be distinct paths")
        for path in self.sets:
            if path not in PATHS:
                raise ValueError(f"{where}: sets {path!r} is not a known path; known: "
                                 f"{sorted(PATHS)}")
        if not self.alternatives:
            raise ValueError(f"{where}: needs at least one alternative")
        values = [self.default, *self.alternatives]
        for value in values:
            if len(value) != len(self.sets):
                raise ValueError(f"{where}: value {list(value)!r} needs one entry per path "
                                 f"{list(self.sets)}")
            for path, v in zip(self.sets, value, strict=True):
                PATHS[path](v, f"{where}: {path}")
        if len({tuple(map(repr, v)) for v in values}) != len(values):
            raise ValueError(f"{where}: the default and the alternatives must all differ")

    def settings(self, value: tuple[Any, ...]) -> dict[str, Any]:
        """``{path: value}`` of one of the choice's values."""
        return dict(zip(self.sets, value, strict=True))

    def describe(self, value: tuple[Any, ...]) -> str:
        """A value in the reader's words, e.g. ``"Ts = 5 ms, noise at 200 Hz"``."""
        return describe_settings(self.settings(value))

    def label(self, value: tuple[Any, ...]) -> str:
        """``0.056`` for one path, ``ts=0.001 noise_rate=1000`` for several."""
        if len(self.sets) == 1:
            return format_value(value[0])
        return " ".join(f"{p.split('.')[-1]}={format_value(v)}"
                        for p, v in zip(self.sets, value, strict=True))

    def to_dict(self) -> dict[str, Any]:
        def plain(v: tuple[Any, ...]) -> Any:
            items = [list(x) if isinstance(x, tuple) else x for x in v]
            return items[0] if len(items) == 1 else items
        return {"name": self.name, "sets": list(self.sets), "default": plain(self.default),
                "alternatives": [plain(a) for a in self.alternatives],
                "description": self.description, "doc": self.doc}


def _parse_value(choice_sets: Sequence[str], value: Any, where: str) -> tuple[Any, ...]:
    if len(choice_sets) == 1:
        return (PATHS[choice_sets[0]](value, f"{where} ({choice_sets[0]})"),)
    if not isinstance(value, list) or len(value) != len(choice_sets):
        raise ConfigError(f"{where}={value!r} must be a list of {len(choice_sets)} values, one "
                          f"per path {list(choice_sets)}")
    return tuple(PATHS[p](v, f"{where} ({p})") for p, v in zip(choice_sets, value, strict=True))


def choices_from_list(entries: Any, file: str) -> tuple[Choice, ...]:
    """``[[choices]]`` tables onto :class:`Choice` objects.

    Raises
    ------
    ConfigError
        Naming the file, the entry (``[[choices]] #i 'name'``), the key and the value.
    """
    if not isinstance(entries, list):
        raise ConfigError(f"{file} [[choices]]: must be an array of tables, got {entries!r}")
    out = []
    for i, entry in enumerate(entries):
        t = Table(entry, f"{file} [[choices]] #{i + 1}")
        name = t.get("name", str)
        t.where = f"{file} [[choices]] #{i + 1} {name!r}"
        if "sets" in t and isinstance(t.data["sets"], str):
            sets: list[str] = [t.get("sets", str)]
        else:
            sets = t.get_list("sets", str)
        for path in sets:
            if path not in PATHS:
                raise ConfigError(f"{t.where}: sets={path!r} is not a known path; known: "
                                  f"{sorted(PATHS)}")
        default = _parse_value(sets, t.get("default", lambda v: v), f"{t.where}: default")
        alt_raw = t.get("alternatives", list)
        alternatives = tuple(_parse_value(sets, v, f"{t.where}: alternatives[{k}]")
                             for k, v in enumerate(alt_raw))
        description = t.get("description", str, "")
        doc = t.get("doc", str, "")
        t.done()
        try:
            out.append(Choice(name=name, sets=tuple(sets), default=default,
                              alternatives=alternatives, description=description, doc=doc))
        except ValueError as exc:
            raise ConfigError(f"{t.where}: {exc}") from None
    names = [c.name for c in out]
    if len(set(names)) != len(names):
        dup = next(n for n in names if names.count(n) > 1)
        raise ConfigError(f"{file} [[choices]]: name {dup!r} is used twice")
    return tuple(out)


def baseline_value(path: str, loop: LoopConfig) -> Any:
    """The study's own setting of ``path`` (what a choice's ``default`` must equal)."""
    return {
        "robot.half_track": loop.robot.half_track,
        "simulation.ts": loop.ts,
        "simulation.noise_rate": loop.noise_rate,
        "simulation.start_pose": loop.start_pose,
        "simulation.desired_heading_pose": loop.desired_heading_pose.value,
        "simulation.metric_start": loop.metric_start,
        "noise.sigma": SWEEP,
        "metrics.heading": "true",
        "controllers.ke": 1.0,
        "controllers.kde": 1.0,
        "controllers.output_gain": 1.0,
        "controllers.tuned": False,
    }[path]


@dataclass(frozen=True, kw_only=True)
class Variant:
    """The study under one combination of choice values.

    Attributes
    ----------
    choice : str
        ``"baseline"``, a choice's name, or ``"a x b"`` for a factorial cell.
    value : str
        The value's label (``"paper"`` for the baseline).
    settings : tuple of (str, value)
        The paths set away from the study's own values.
    loop : LoopConfig
    ke, kde : float
        Input gains of every fuzzy controller.
    output_gain : float
        Output gain of every untuned fuzzy controller.
    tuned : bool
        The tuned fuzzy controllers instead of the paper's.
    noise_levels : tuple of float
        Levels at which the variant is judged.
    heading : str
        ``"true"`` or ``"measured"``: which heading error the integrals use.
    """

    choice: str
    value: str
    settings: tuple[tuple[str, Any], ...]
    loop: LoopConfig
    ke: float = 1.0
    kde: float = 1.0
    output_gain: float = 1.0
    tuned: bool = False
    noise_levels: tuple[float, ...]
    heading: str = "true"
    label: str = ""


def apply_settings(loop: LoopConfig, noise_levels: Sequence[float],
                   settings: Mapping[str, Any], *, choice: str, value: str,
                   label: str = "") -> Variant:
    """The :class:`Variant` of the study's ``loop`` and robustness ``noise_levels`` with the
    path values ``settings`` (validated by :data:`PATHS`' parsers beforehand); ``label``: the
    values in the reader's words (default: those of the paths that differ from the loop's).

    Raises
    ------
    ValueError
        If the combination is not a valid loop (e.g. a duration or integral window that is not
        a whole number of periods), naming the choice and value.
    """
    loop_kw: dict[str, Any] = {}
    robot_kw: dict[str, Any] = {}
    out: dict[str, Any] = {"noise_levels": tuple(noise_levels)}
    for path, v in settings.items():
        section, key = path.split(".")
        if section == "robot":
            robot_kw[key] = v
        elif section == "simulation":
            loop_kw[key] = v
        elif path == "noise.sigma":
            if v != SWEEP:
                out["noise_levels"] = (v,)
        elif path == "metrics.heading":
            out["heading"] = v
        elif path in ("controllers.ke", "controllers.kde", "controllers.output_gain"):
            out[key] = v
        elif path == "controllers.tuned":
            out["tuned"] = v
        else:  # pragma: no cover - PATHS and this function list the same paths
            raise ValueError(f"unknown path {path!r}")
    try:
        robot = dataclasses.replace(loop.robot, **robot_kw)
        new_loop = dataclasses.replace(loop, robot=robot, **loop_kw)
    except ValueError as exc:
        raise ValueError(f"choice {choice} = {value}: {exc}") from None
    changed = tuple((p, v) for p, v in settings.items() if v != baseline_value(p, loop))
    label = label or (describe_settings(dict(changed)) if changed else "the paper's choices")
    return Variant(choice=choice, value=value, settings=changed, loop=new_loop, label=label,
                   **out)


def _seconds(v: float) -> str:
    return f"{v * 1000:g} ms" if v < 1.0 else f"{v:g} s"


def _hertz(v: float) -> str:
    return f"{v / 1000:g} kHz" if v >= 1000.0 else f"{v:g} Hz"


def describe_value(path: str, value: Any) -> str:
    """One path value in the reader's words, e.g. ``"l = 0.28 m"``, ``"Ts = 5 ms"``,
    ``"noise at 200 Hz"``, ``"start on the path"``.

    Examples
    --------
    >>> describe_value("simulation.noise_rate", 1000.0)
    'noise at 1 kHz'
    """
    if path == "robot.half_track":
        return f"l = {value:g} m"
    if path == "simulation.ts":
        return f"Ts = {_seconds(value)}"
    if path == "simulation.noise_rate":
        return f"noise at {_hertz(value)}"
    if path == "simulation.start_pose":
        return ("start on the path" if value == ON_PATH
                else "start at (" + ", ".join(f"{v:g}" for v in value) + ")")
    if path == "simulation.desired_heading_pose":
        return f"θd from the {value} pose"
    if path == "simulation.metric_start":
        return f"integrals from t = {value:g} s"
    if path == "noise.sigma":
        return "σ swept" if value == SWEEP else f"σ = {value:.3g} rad"
    if path == "metrics.heading":
        return f"integrals on the {value} heading"
    if path == "controllers.ke":
        return f"Ke = {value:g}"
    if path == "controllers.kde":
        return f"Kde = {value:g}"
    if path == "controllers.output_gain":
        return f"output gain {value:g}"
    if path == "controllers.tuned":
        return "tuned controllers" if value else "untuned controllers"
    raise ValueError(f"unknown path {path!r}")


def describe_settings(settings: Mapping[str, Any]) -> str:
    """Several path values in the reader's words, ``", "``-joined (``"Ts = 5 ms, noise at
    200 Hz"``)."""
    return ", ".join(describe_value(p, v) for p, v in settings.items())


def _c(name: str, sets: Sequence[str], default: Sequence[Any],
       alternatives: Sequence[Sequence[Any]], description: str, doc: str) -> Choice:
    return Choice(name=name, sets=tuple(sets), default=tuple(default),
                  alternatives=tuple(tuple(a) for a in alternatives), description=description,
                  doc=doc)


#: The open choices ``configs/paper.toml`` lists (a test keeps the two identical).
DEFAULT_CHOICES: tuple[Choice, ...] = (
    _c("half_track", ["robot.half_track"], [5.6], [[0.28], [0.056]],
       "Table 3 prints l = 5.6 m, implausible for a small robot; 0.28 m and 0.056 m are the "
       "same digits at other scales", "half-track"),
    _c("control_period", ["simulation.ts", "simulation.noise_rate"], [0.01, 100.0],
       [[0.005, 100.0], [0.001, 100.0], [0.005, 200.0], [0.001, 1000.0]],
       "the paper gives no control period; de is a per-period difference, so Ts is a hidden "
       "gain on de; the noise is held at 100 Hz or resampled every period", "control-period"),
    _c("noise_reading", ["noise.sigma"], [SWEEP],
       [[math.sqrt(0.1)], [math.sqrt(0.1 / 0.01)]],
       "'0.1 W, 100 Hz': a sweep of sigma (our reading), mean-square power sigma = sqrt(0.1), "
       "or Simulink band-limited power sigma = sqrt(P / Ts) = sqrt(0.1 / 0.01)",
       "noise-reading"),
    _c("heading_integrals", ["metrics.heading"], ["true"], [["measured"]],
       "the error integrals of eqs. 24-27 on the true heading error or on the measured "
       "(noisy) one the controller sees", "heading-integrals"),
    _c("start_pose", ["simulation.start_pose"], [(0.0, 0.0, 0.0)], [[ON_PATH]],
       "the robot starts at the origin heading along x, or on the reference with its tangent "
       "heading (the curved path starts 4 m away)", "start-pose"),
    _c("heading_timing", ["simulation.desired_heading_pose"], ["current"], [["previous"]],
       "theta_d from the pose of this period, or of the previous one as eqs. 20-21 write "
       "y(k-1)", "heading-timing"),
    _c("input_gains", ["controllers.ke", "controllers.kde"], [1.0, 1.0],
       [[0.5, 1.0], [2.0, 1.0], [1.0, 0.5], [1.0, 2.0]],
       "input scaling gains Ke, Kde: the paper shows none (1, 1)", "input-gains"),
    _c("output_gain", ["controllers.output_gain"], [1.0], [[0.5], [2.0]],
       "the motor mixing (the paper's Fig. 5) is missing: V_R,L = V0 +- g u with g = 1 (ours), "
       "0.5 or 2 on every untuned fuzzy controller; g scales the turning rate as l / g does (g = "
       "0.5 is l = 11.2 m, g = 2 is l = 2.8 m, exactly while no wheel voltage saturates)",
       "output-gain"),
    _c("tuning", ["controllers.tuned"], [False], [[True]],
       "the paper's untuned controllers, or each tuned like the PD baseline (Ke, Kde and an "
       "output gain, effort-matched)", "tuning"),
    _c("integral_window", ["simulation.metric_start"], [0.0], [[2.0]],
       "integrals over the whole run, or after the initial transient (t >= 2 s)",
       "integral-window"),
)
