"""The robustness experiment's configuration: which open choices, which alternatives, the
factorial crossing, the seeds, the baseline's independent batches (docs/model.md#robustness);
and the variants of the study it runs (:func:`robustness_variants`).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from .choices import (
    DEFAULT_CHOICES,
    Choice,
    Variant,
    _parse_value,
    apply_settings,
    baseline_value,
    format_value,
)
from .sensitivity import SensitivityConfig, SensitivityFactor
from .specs import ConfigError, Table

__all__ = [
    "RobustnessConfig",
    "check_defaults",
    "check_factor_levels",
    "rebase",
    "robustness_config_from_table",
    "robustness_variants",
]


@dataclass(frozen=True, kw_only=True)
class RobustnessConfig:
    """The robustness experiment (see the module docstring).

    Parameters
    ----------
    choices : tuple of Choice
        The open choices (``[[choices]]``).
    noise_levels : tuple of float
        Levels (> 0) at which every variant is judged (a noise reading judges at its own).
    seeds : int
        Realisations per cell (>= 2).
    factorial : tuple of str
        Choices crossed in the factorial (none: no factorial).
    factorial_levels : tuple of (str, tuple of tuple)
        Per factorial choice, the alternatives it takes in the factorial (those of its
        alternatives that are listed; a choice not listed takes all of them; entries of
        choices not crossed are ignored). ``[robustness.factorial_levels]`` in a study file
        is checked against the choices: a name not crossed or a value that is not an
        alternative is an error there.
    baseline_batches : int
        Independent seed batches the baseline is judged on (>= 2): its spread, against which
        a variant's change is called.
    sensitivity : SensitivityConfig or None
        The Morris screening (None: none).
    """

    choices: tuple[Choice, ...] = DEFAULT_CHOICES
    noise_levels: tuple[float, ...] = (0.05, 0.1, 0.2)
    seeds: int = 40
    factorial: tuple[str, ...] = ("half_track", "control_period", "output_gain")
    factorial_levels: tuple[tuple[str, tuple[tuple[Any, ...], ...]], ...] = (
        ("half_track", ((0.28,),)),
        ("control_period", ((0.001, 1000.0),)),
    )
    baseline_batches: int = 10
    sensitivity: SensitivityConfig | None = field(default_factory=SensitivityConfig)

    def __post_init__(self) -> None:
        if not self.noise_levels or any(not math.isfinite(s) or s <= 0
                                        for s in self.noise_levels):
            raise ValueError(f"robustness noise_levels={list(self.noise_levels)!r} must be "
                             "noise levels > 0")
        if len(set(self.noise_levels)) != len(self.noise_levels):
            raise ValueError(f"robustness noise_levels={list(self.noise_levels)!r} lists a "
                             "level twice")
        if isinstance(self.seeds, bool) or not isinstance(self.seeds, int) or self.seeds < 2:
            raise ValueError(f"robustness seeds={self.seeds!r} must be an integer >= 2 (a "
                             "single realisation shows nothing)")
        names = [c.name for c in self.choices]
        for name in self.factorial:
            if name not in names:
                raise ValueError(f"robustness factorial names {name!r}, not a choice; "
                                 f"choices: {names}")
        if len(set(self.factorial)) != len(self.factorial) or len(self.factorial) == 1:
            raise ValueError(f"robustness factorial={list(self.factorial)!r} needs none or "
                             "at least two distinct choices")
        b = self.baseline_batches
        if isinstance(b, bool) or not isinstance(b, int) or b < 2:
            raise ValueError(f"robustness baseline_batches={b!r} must be an integer >= 2 (a "
                             "spread needs two independent batches)")
        seen = set()
        for name, alts in self.factorial_levels:
            if name in seen:
                raise ValueError(f"robustness factorial_levels names {name!r} twice")
            seen.add(name)
            if not alts or not all(isinstance(a, tuple) for a in alts):
                raise ValueError(f"robustness factorial_levels {name!r}: needs a non-empty "
                                 "tuple of alternatives (each a tuple of path values)")

    def factorial_values(self, choice: Choice) -> tuple[tuple[Any, ...], ...]:
        """The values ``choice`` takes in the factorial: its default, then its alternatives
        (those of ``factorial_levels`` when listed)."""
        given = dict(self.factorial_levels).get(choice.name)
        alts = tuple(a for a in choice.alternatives if given is None or a in given)
        return (choice.default, *alts)

    def to_dict(self) -> dict[str, Any]:
        return {"noise_levels": list(self.noise_levels), "seeds": self.seeds,
                "factorial": list(self.factorial),
                "factorial_levels": {n: [list(a) for a in alts]
                                     for n, alts in self.factorial_levels},
                "baseline_batches": self.baseline_batches,
                "sensitivity": None if self.sensitivity is None else self.sensitivity.to_dict(),
                "choices": [c.to_dict() for c in self.choices]}


def robustness_config_from_table(t: Table, choices: tuple[Choice, ...]) -> RobustnessConfig:
    """``[robustness]`` (+ ``[robustness.sensitivity]`` and its ``[[...factors]]``)."""
    values: dict[str, Any] = {"choices": choices}
    if "noise_levels" in t:
        values["noise_levels"] = tuple(t.get_list("noise_levels", float))
    if "seeds" in t:
        values["seeds"] = t.get("seeds", int)
    if "baseline_batches" in t:
        values["baseline_batches"] = t.get("baseline_batches", int)
    if "factorial" in t:
        values["factorial"] = tuple(t.get_list("factorial", str))
        values["factorial_levels"] = ()
    else:  # the default crossing, if the (possibly user-given) choices have it
        names = {c.name for c in choices}
        fields = RobustnessConfig.__dataclass_fields__
        default = fields["factorial"].default
        assert isinstance(default, tuple)
        ok = all(n in names for n in default)
        values["factorial"] = default if ok else ()
        levels_default = fields["factorial_levels"].default
        assert isinstance(levels_default, tuple)
        by_name = {c.name: c for c in choices}
        values["factorial_levels"] = tuple(
            (n, alts) for n, alts in levels_default
            if ok and all(a in by_name[n].alternatives for a in alts))
    lt = t.sub("factorial_levels")
    if lt.data:
        by_name = {c.name: c for c in choices}
        parsed = []
        for name in list(lt.data):
            if name not in values["factorial"] or name not in by_name:
                raise ConfigError(f"{lt.where}: {name!r} is not crossed in the factorial "
                                  f"{list(values['factorial'])}")
            raw = lt.get(name, list)
            if not raw:
                raise ConfigError(f"{lt.where}: {name} = [] needs at least one alternative")
            alts = tuple(_parse_value(by_name[name].sets, v, f"{lt.where}: {name}[{k}]")
                         for k, v in enumerate(raw))
            for k, a in enumerate(alts):
                if a not in by_name[name].alternatives:
                    raise ConfigError(
                        f"{lt.where}: {name}[{k}] = {format_value(list(a))} is not one of the "
                        f"choice's alternatives "
                        f"{[format_value(list(x)) for x in by_name[name].alternatives]}")
            parsed.append((name, alts))
        values["factorial_levels"] = tuple(parsed)
    lt.done()
    use_sens = t.get("sensitivity_analysis", bool, True)
    st = t.sub("sensitivity")
    if use_sens:
        sv: dict[str, Any] = {}
        for key in ("trajectories", "seeds", "seed"):
            if key in st:
                sv[key] = st.get(key, int)
        if "factors" in st:
            factors = []
            for i, entry in enumerate(st.get("factors", list)):
                ft = Table(entry, f"{st.where}.factors #{i + 1}")
                name = ft.get("name", str)
                path = ft.get("path", str)
                levels = tuple(ft.get_list("levels", float))
                ft.done()
                try:
                    factors.append(SensitivityFactor(name=name, path=path, levels=levels))
                except ValueError as exc:
                    raise ConfigError(f"{ft.where}: {exc}") from None
            sv["factors"] = tuple(factors)
        try:
            values["sensitivity"] = SensitivityConfig(**sv)
        except ValueError as exc:
            raise ConfigError(f"{st.where}: {exc}") from None
    else:
        values["sensitivity"] = None
    st.done()
    t.done()
    try:
        return RobustnessConfig(**values)
    except ValueError as exc:
        raise ConfigError(f"{t.where}: {exc}") from None


def check_defaults(choices: Sequence[Choice], loop: Any, where: str) -> None:
    """Every choice's default must be the study's own setting (the baseline of the robustness
    experiment), so that the table of choices cannot misstate what was run."""
    for c in choices:
        for path, value in zip(c.sets, c.default, strict=True):
            own = baseline_value(path, loop)
            if value != own:
                raise ConfigError(
                    f"{where} [[choices]] {c.name!r}: default {path} = {format_value(value)} "
                    f"but the study runs {format_value(own)}; the default must be the study's "
                    "own setting"
                )


def check_factor_levels(sens: SensitivityConfig, loop: Any) -> None:
    """Every combination of the screening's loop levels must be a valid loop (e.g. each
    integral window a whole number of every period)."""
    loop_factors = [f for f in sens.factors if f.path.split(".")[0] in ("robot", "simulation")]
    for combo in itertools.product(*(f.levels for f in loop_factors)):
        settings = {f.path: v for f, v in zip(loop_factors, combo, strict=True)}
        apply_settings(loop, (1.0,), settings, choice="sensitivity",
                       value=", ".join(f"{f.name}={v:g}"
                                       for f, v in zip(loop_factors, combo, strict=True)))


def rebase(choices: Sequence[Choice], loop: Any) -> tuple[Choice, ...]:
    """The choices with the study's own settings as defaults: a choice whose default differs
    (e.g. the study sets ``half_track = 0.3``) gets the study's value as its default and its
    former default among the alternatives. Used for the implied list (no ``[[choices]]``
    given); an explicit list must match (:func:`check_defaults`)."""
    out = []
    for c in choices:
        own = tuple(baseline_value(p, loop) for p in c.sets)
        if own == c.default:
            out.append(c)
            continue
        alternatives = tuple(a for a in (c.default, *c.alternatives) if a != own)
        out.append(dataclasses.replace(c, default=own, alternatives=alternatives))
    return tuple(out)


# --------------------------------------------------------------------------------------------
# Variants
# --------------------------------------------------------------------------------------------


def robustness_variants(config: RobustnessConfig, loop: Any) -> list[Variant]:
    """The baseline, then every one-at-a-time alternative, then the factorial cells."""
    levels = config.noise_levels
    out = [apply_settings(loop, levels, {}, choice="baseline", value="paper")]
    for c in config.choices:
        for alt in c.alternatives:
            out.append(apply_settings(loop, levels, c.settings(alt), label=c.describe(alt),
                                      choice=c.name,
                                      value=c.label(alt)))
    if config.factorial:
        chosen = [next(c for c in config.choices if c.name == n) for n in config.factorial]
        name = " x ".join(c.name for c in chosen)
        for combo in itertools.product(*(config.factorial_values(c) for c in chosen)):
            moved = sum(v != c.default for c, v in zip(chosen, combo, strict=True))
            if moved < 2:
                continue
            settings: dict[str, Any] = {}
            for c, v in zip(chosen, combo, strict=True):
                settings.update(c.settings(v))
            label = " x ".join(c.label(v) for c, v in zip(chosen, combo, strict=True))
            words = ", ".join(c.describe(v) for c, v in zip(chosen, combo, strict=True)
                              if v != c.default)
            out.append(apply_settings(loop, levels, settings, choice=name, value=label,
                                      label=words))
    return out
