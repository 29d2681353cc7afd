"""The schema of it2track's TOML format: its name and version, the system kinds, the top-level
keys and the membership-function tables (type name -> class and fields), shared by the reader
(:mod:`._tomlread`) and the writer (:mod:`._tomlwrite`)."""

from __future__ import annotations

from ..fuzzy import (
    Gaussian,
    IT2Mamdani,
    IT2Sugeno,
    T1Mamdani,
    T1Sugeno,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)

__all__ = ["FORMAT", "KINDS", "MAX_DEPTH", "MF_TYPES", "TOP_KEYS", "VERSION"]

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
MAX_DEPTH = 8
TOP_KEYS = {
    "format", "version", "kind", "name", "tnorm", "reducer", "reducer_max_iter",
    "on_zero_firing", "inputs", "rules", "snorm", "outputs", "implication", "aggregation",
    "resolution", "type_reduction", "defuzzifier",
}
KINDS = {"it2": IT2Sugeno, "t1": T1Sugeno, "it2-mamdani": IT2Mamdani, "t1-mamdani": T1Mamdani}
