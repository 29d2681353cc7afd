"""The schema of it2track's TOML format: its name and version, the system kinds, the top-level
keys and the membership-function tables (type name -> class and fields), shared by the reader
(:mod:`._tomlread`) and the writer (:mod:`._tomlwrite`)."""

from __future__ import annotations

import dataclasses
import re

from ..fuzzy import (
    Arc,
    Bell,
    Binary,
    Concave,
    Cosine,
    FootedTrapezoid,
    Gaussian,
    GaussianProduct,
    IT2Mamdani,
    IT2Sugeno,
    LinearSShape,
    LinearZShape,
    PiShape,
    Point,
    Ramp,
    Rectangle,
    SemiEllipse,
    Sigmoid,
    SigmoidDifference,
    SigmoidProduct,
    Spike,
    SShape,
    T1Mamdani,
    T1Sugeno,
    T1Tsukamoto,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
    ZShape,
)

__all__ = ["FORMAT", "INFINITE_OK", "KINDS", "MAX_DEPTH", "MF_TYPES", "TOP_KEYS", "VERSION",
           "WITH_SETS"]

FORMAT = "it2track-fuzzy-system"
VERSION = 1

# type name -> (class, parameter names in constructor order)
MF_TYPES: dict[str, tuple[type, tuple[str, ...]]] = {
    "triangle": (Triangle, ("a", "b", "c", "h")),
    "trapezoid": (Trapezoid, ("a", "b", "c", "d", "h")),
    "gaussian": (Gaussian, ("mean", "sigma", "h")),
    "uncertain-mean-gaussian-upper": (UncertainMeanGaussianUpper, ("m1", "m2", "sigma", "h")),
    "uncertain-mean-gaussian-lower": (UncertainMeanGaussianLower, ("m1", "m2", "sigma", "h")),
}
#: MATLAB's and fuzzylite's terms: the class name in kebab case (``SigmoidDifference`` ->
#: ``"sigmoid-difference"``), the dataclass fields as keys (``Discrete``: ``points``, an array
#: of ``[x, y]`` pairs, read apart)
TERMS = (Bell, Sigmoid, SigmoidDifference, SigmoidProduct, SShape, ZShape, PiShape,
         GaussianProduct, Cosine, Spike, LinearSShape, LinearZShape, Ramp, Rectangle, Point,
         Binary, Concave, Arc, SemiEllipse, FootedTrapezoid)
for _cls in TERMS:
    MF_TYPES[re.sub(r"(?<!^)(?=[A-Z])", "-", _cls.__name__).lower()] = (
        _cls, tuple(f.name for f in dataclasses.fields(_cls)))
#: (type, key) of MF fields that may be infinite (fuzzylite's ``Binary 0.5 inf``)
INFINITE_OK = {("binary", "direction")}
MAX_DEPTH = 8
TOP_KEYS = {
    "format", "version", "kind", "name", "tnorm", "reducer", "reducer_max_iter",
    "on_zero_firing", "inputs", "rules", "snorm", "outputs", "implication", "aggregation",
    "resolution", "type_reduction", "defuzzifier", "sampling",
}
KINDS = {"it2": IT2Sugeno, "t1": T1Sugeno, "it2-mamdani": IT2Mamdani, "t1-mamdani": T1Mamdani,
         "t1-tsukamoto": T1Tsukamoto}
#: the kinds whose outputs have sets (and whose consequents are set labels)
WITH_SETS = ("it2-mamdani", "t1-mamdani", "t1-tsukamoto")
