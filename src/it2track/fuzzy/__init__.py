"""General interval type-2 and type-1 Sugeno fuzzy logic (knows nothing about robots).

Imports numpy only. See :mod:`.membership`, :mod:`.sets`, :mod:`.reducers`, :mod:`.rules`,
:mod:`.tables`, :mod:`.sugeno`, :mod:`.surface`.
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
from .rules import Input, Rule, TNorm, rules_from_table
from .sets import IT2Set, ScaledLagged
from .sugeno import FuzzySystem, IT2Sugeno, T1Sugeno
from .surface import control_surface
from .tables import MFKind, SystemTables

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
    "MFKind",
    "MembershipFunction",
    "PiecewiseLinear",
    "Reducer",
    "Rule",
    "ScaledLagged",
    "SystemTables",
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
