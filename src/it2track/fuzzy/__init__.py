"""General interval type-2 and type-1 Sugeno fuzzy logic (knows nothing about robots).

Imports numpy only. See :mod:`.membership`, :mod:`.sets`, :mod:`.reducers`, :mod:`.system`.
"""

from .membership import (
    Gaussian,
    MembershipFunction,
    PiecewiseLinear,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
    gaussmf,
    trapmf,
    trimf,
)
from .reducers import (
    EIASC,
    EKM,
    EXHAUSTIVE,
    KM,
    NIE_TAN,
    WU_MENDEL,
    ConvergenceError,
    Reducer,
    TypeReducer,
    ZeroFiringError,
)
from .sets import IT2Set, ScaledLagged
from .system import (
    FuzzySystem,
    Input,
    IT2Sugeno,
    Rule,
    T1Sugeno,
    TNorm,
    control_surface,
    rules_from_table,
)

__all__ = [
    "EIASC",
    "EKM",
    "EXHAUSTIVE",
    "KM",
    "NIE_TAN",
    "WU_MENDEL",
    "ConvergenceError",
    "FuzzySystem",
    "Gaussian",
    "IT2Set",
    "IT2Sugeno",
    "Input",
    "MembershipFunction",
    "PiecewiseLinear",
    "Reducer",
    "Rule",
    "ScaledLagged",
    "T1Sugeno",
    "TNorm",
    "Trapezoid",
    "Triangle",
    "TypeReducer",
    "UncertainMeanGaussianLower",
    "UncertainMeanGaussianUpper",
    "ZeroFiringError",
    "control_surface",
    "gaussmf",
    "rules_from_table",
    "trapmf",
    "trimf",
]
