"""Random systems and input points for the code-generation tests."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from it2track.codegen import RealType, generate_c
from it2track.codegen.host import HostLibrary, build_host_library
from it2track.codegen.tools import missing_tools
from it2track.fuzzy import (
    Gaussian,
    Input,
    IT2Set,
    IT2Sugeno,
    Reducer,
    Rule,
    SNorm,
    T1Sugeno,
    TNorm,
    Trapezoid,
    Triangle,
)


def skip_without(*tools: str) -> None:
    """Skip (never silently) when a tool is missing, naming its Debian package."""
    missing = missing_tools(tools)
    if missing:
        pytest.skip(f"needs {', '.join(tools)}: install the Debian package(s) "
                    f"{', '.join(missing)}")


def _random_set(rng, lo, hi, name, shape, *, type1):
    span = hi - lo
    if shape in ("triangle", "trapezoid", "left", "right"):
        c = rng.uniform(lo, hi)
        w1, w2 = rng.uniform(0.1, 0.6, size=2) * span
        if shape == "triangle":
            pts = [c - w1, c, c + w2]
        elif shape == "trapezoid":
            plateau = rng.uniform(0.0, 0.3) * span
            pts = [c - w1, c, c + plateau, c + plateau + w2]
        elif shape == "left":
            pts = [lo, lo, c + w2]
        else:
            pts = [c - w1, hi, hi]
        h = 1.0 if rng.random() < 0.6 else rng.uniform(0.5, 1.0)
        cls = Triangle if len(pts) == 3 else Trapezoid
        upper = cls(*pts, h=h)
        if type1:
            return IT2Set(upper, upper, name)
        fou = rng.uniform(0.0, 0.8) * min(w1, w2)
        s = IT2Set.from_fou(upper, fou, name)
        if rng.random() < 0.4:  # a lower MF lower than the upper one: height < upper's
            lower = dataclasses.replace(s.lower, h=s.lower.h * rng.uniform(0.4, 1.0))
            s = IT2Set(s.upper, lower, name)
        return s
    mean = rng.uniform(lo, hi)
    sigma = rng.uniform(0.08, 0.4) * span
    if type1:
        return IT2Set.type1(Gaussian(mean, sigma, rng.uniform(0.6, 1.0)), name)
    if shape == "gauss-std":
        return IT2Set.gaussian_uncertain_std(mean, sigma * rng.uniform(0.5, 0.95), sigma, name,
                                             h=rng.uniform(0.6, 1.0))
    half = rng.uniform(0.0, 0.2) * span
    return IT2Set.gaussian_uncertain_mean(mean - half, mean + half, sigma, name,
                                          h=rng.uniform(0.6, 1.0))


SHAPES = ("triangle", "trapezoid", "left", "right", "gauss-std", "gauss-mean")


def random_system(seed: int, *, type1: bool = False, on_zero_firing=None,
                  reducer: Reducer | None = None, shapes=SHAPES, features: bool = False):
    """A random multi-input Sugeno system covering every supported shape and option
    (``features``: also NOT antecedents, OR rules with either s-norm, and rule weights)."""
    rng = np.random.default_rng(seed)
    n_in = int(rng.integers(1, 4))
    inputs = []
    for i in range(n_in):
        lo = float(rng.uniform(-3.0, 0.0))
        hi = lo + float(rng.uniform(0.5, 4.0))
        n_sets = int(rng.integers(2, 5))
        sets = [_random_set(rng, lo, hi, f"s{j}", shapes[int(rng.integers(len(shapes)))],
                            type1=type1) for j in range(n_sets)]
        inputs.append(Input(f"x{i}", (lo, hi), sets))
    rules = []
    seen = set()
    for _ in range(int(rng.integers(3, 13))):
        ante = tuple(
            None if (n_in > 1 and rng.random() < 0.25) else
            f"s{int(rng.integers(len(inputs[i].sets)))}" for i in range(n_in))
        if all(a is None for a in ante) or ante in seen:
            continue
        seen.add(ante)
        y = float(rng.uniform(-10, 10))
        if type1 or rng.random() < 0.5:
            cons: float | tuple[float, float] = y
        else:
            cons = (y, y + float(rng.uniform(0.0, 4.0)))
        if not features:
            rules.append(Rule(list(ante), cons))
            continue
        mentioned = sum(a is not None for a in ante)
        rules.append(Rule(
            list(ante), cons,
            weight=float(rng.uniform(0.3, 1.0)) if rng.random() < 0.4 else 1.0,
            connective="or" if mentioned > 1 and rng.random() < 0.4 else "and",
            negated=[a is not None and bool(rng.random() < 0.25) for a in ante]))
    if not rules:
        rules.append(Rule(["s0"] + [None] * (n_in - 1), 1.0))
    tnorm = TNorm.PRODUCT if rng.random() < 0.6 else TNorm.MINIMUM
    extra = {"snorm": SNorm.PROBOR if rng.random() < 0.5 else SNorm.MAXIMUM} if features else {}
    if type1:
        return T1Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, on_zero_firing=on_zero_firing,
                        name=f"random-t1-{seed}", **extra)
    red = reducer if reducer is not None else list(Reducer)[int(rng.integers(len(Reducer)))]
    return IT2Sugeno(inputs=inputs, rules=rules, tnorm=tnorm, reducer=red.value,
                     on_zero_firing=on_zero_firing, name=f"random-{seed}", **extra)


def points(system, n_random: int, seed: int, *, grid: int = 21, margin: float = 0.3):
    """A grid over (and beyond) the universes plus uniform random points, shape (N, n_in)."""
    rng = np.random.default_rng(seed)
    lo = np.array([inp.universe[0] for inp in system.inputs])
    hi = np.array([inp.universe[1] for inp in system.inputs])
    pad = margin * (hi - lo)
    axes = [np.linspace(a - p, b + p, grid if system.n_inputs < 3 else 9)
            for a, b, p in zip(lo, hi, pad, strict=True)]
    g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, system.n_inputs)
    r = rng.uniform(lo - pad, hi + pad, size=(n_random, system.n_inputs))
    return np.concatenate([g, r])


def host_lib_factory(build_dir):
    """``make(system, real=..., prefix=...) -> HostLibrary``, each code compiled once."""
    skip_without("gcc")
    cache: dict[str, HostLibrary] = {}

    def make(system, real=RealType.DOUBLE, prefix="it2"):
        code = generate_c(system, real=real, prefix=prefix)
        key = code.digest()
        if key not in cache:
            cache[key] = HostLibrary(code, build_host_library(code, build_dir))
        return cache[key]

    return make


def paper_mamdani(*, reducer=None, type1: bool = False, **kwargs):
    """it2track.paper.heading_mamdani (FoU 0.2; the type-1 one from the type-1 FLC's sets)."""
    from it2track.paper import heading_mamdani

    extra = {} if reducer is None else {"reducer": reducer.value}
    return heading_mamdani(0.0 if type1 else 0.2, type1=type1, **extra, **kwargs)


def paper_tsk(*, reducer=None, type1: bool = False, interval: bool = True):
    """it2track.paper.heading_tsk: slopes 1.5 and [-0.5, 0.5] (or -2 for crisp coefficients)."""
    from it2track.paper import heading_tsk

    extra = {} if reducer is None else {"reducer": reducer.value}
    slopes = (1.5, (-0.5, 0.5) if (interval and not type1) else -2.0)
    return heading_tsk(0.0 if type1 else 0.2, slopes=slopes, **extra)


def random_mamdani(seed: int, *, type1: bool = False, shapes=SHAPES):
    """A random Mamdani system: 1-3 inputs, random output sets, rule-language features, every
    implication and aggregation, a random reducer and resolution."""
    from it2track.fuzzy import Aggregation, Implication, IT2Mamdani, Output, T1Mamdani

    base = random_system(seed, type1=type1, shapes=shapes, features=True)
    rng = np.random.default_rng(1000 + seed)
    lo = float(rng.uniform(-5.0, 0.0))
    hi = lo + float(rng.uniform(1.0, 10.0))
    n_sets = int(rng.integers(2, 6))
    sets = [_random_set(rng, lo, hi, f"o{j}", ("triangle", "trapezoid", "left", "right")[
        int(rng.integers(4))], type1=type1) for j in range(n_sets)]
    out = Output("y", (lo, hi), sets)
    rules = [Rule(r.antecedent, f"o{int(rng.integers(n_sets))}", weight=r.weight,
                  connective=r.connective, negated=r.negated) for r in base.rules]
    common = {
        "inputs": base.inputs, "outputs": [out], "rules": rules, "tnorm": base.tnorm,
        "snorm": base.tables.snorm,
        "implication": list(Implication)[(seed // 3) % 2],
        "aggregation": list(Aggregation)[seed % 3],
        "resolution": int(rng.integers(5, 80)), "name": f"random-mamdani-{seed}",
    }
    if type1:
        return T1Mamdani(**common)
    red = list(Reducer)[seed % len(Reducer)]
    return IT2Mamdani(reducer=red.value, **common)


def random_tsk(seed: int, *, type1: bool = False, shapes=SHAPES):
    """A random first-order system: random_system's antecedents with Linear consequents
    (interval coefficients unless type-1)."""
    from it2track.fuzzy import Linear

    base = random_system(seed, type1=type1, shapes=shapes, features=True)
    rng = np.random.default_rng(2000 + seed)
    rules = []
    for r in base.rules:
        coefs: list[float | tuple[float, float]] = []
        for _ in range(base.n_inputs):
            c = float(rng.uniform(-3.0, 3.0))
            coefs.append(c if (type1 or rng.random() < 0.5) else (c, c + float(rng.uniform(0, 2))))
        c0 = float(rng.uniform(-5.0, 5.0))
        rules.append(Rule(r.antecedent, Linear(coefs, c0), weight=r.weight,
                          connective=r.connective, negated=r.negated))
    return dataclasses.replace(base, rules=tuple(rules), name=f"random-tsk-{seed}")
