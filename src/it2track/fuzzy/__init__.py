"""General interval type-2 and type-1 fuzzy logic: Sugeno, TSK and Mamdani (knows nothing
about robots).

Imports numpy only. One concept per module: :mod:`.membership` (type-1 MFs), :mod:`.sets`
(IT2 sets), :mod:`.norms` (t-norms, s-norms, implication, aggregation, defuzzifiers),
:mod:`.rules` (variables and rules), :mod:`.tables` (the lowering to arrays and the rule
firing), :mod:`.reducers` (type reduction), :mod:`.sugeno` (Sugeno/TSK
systems), :mod:`.mamdani` (Mamdani systems, centroid and centre-of-sets type reduction),
:mod:`.system` (what every system shares: input checks, firing, outputs, zero firing),
:mod:`.surface` (control surfaces).
"""

from .mamdani import (
    AnySystem,
    IT2Mamdani,
    MamdaniSystem,
    MamdaniTables,
    T1Mamdani,
    TypeReduction,
    defuzzify,
    set_centroid,
)
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
from .norms import Aggregation, Connective, Defuzzifier, Implication, SNorm, TNorm
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
from .rules import Consequent, Input, Linear, Output, Rule, rules_from_table
from .sets import IT2Set, ScaledLagged
from .sugeno import FuzzySystem, IT2Sugeno, T1Sugeno
from .surface import control_surface
from .tables import FEATURES, MFKind, SystemTables

__all__ = [
    "EIASC",
    "EKM",
    "EXHAUSTIVE",
    "FEATURES",
    "KM",
    "NIE_TAN",
    "WU_MENDEL",
    "Aggregation",
    "AnySystem",
    "Connective",
    "Consequent",
    "ConvergenceError",
    "Defuzzifier",
    "FuzzySystem",
    "Gaussian",
    "IT2Mamdani",
    "IT2Set",
    "IT2Sugeno",
    "Implication",
    "Input",
    "Linear",
    "MFKind",
    "MamdaniSystem",
    "MamdaniTables",
    "MembershipFunction",
    "Output",
    "PiecewiseLinear",
    "Reducer",
    "Rule",
    "SNorm",
    "ScaledLagged",
    "SystemTables",
    "T1Mamdani",
    "T1Sugeno",
    "TNorm",
    "Trapezoid",
    "Triangle",
    "TypeReducer",
    "TypeReduction",
    "UncertainMeanGaussianLower",
    "UncertainMeanGaussianUpper",
    "ZeroFiringError",
    "control_surface",
    "defuzzify",
    "gaussmf",
    "rules_from_table",
    "set_centroid",
    "trapmf",
    "trimf",
]
