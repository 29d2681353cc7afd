"""General interval type-2 and type-1 fuzzy logic: Sugeno, TSK, Mamdani and Tsukamoto (knows
nothing about robots).

Imports numpy only. One concept per module: :mod:`.membership` (type-1 MFs: triangles,
trapezoids, Gaussians), :mod:`.curves` (bell, two-sided Gaussian, cosine, spike),
:mod:`.sigmoids`, :mod:`.splines` (S/Z/Pi shapes), :mod:`.shapes` (ramps, rectangle,
binary, discrete, concave, arc, semi-ellipse), :mod:`.terms` (MATLAB's and fuzzylite's
names of them), :mod:`.kinds` (their compiled rows), :mod:`.sets`
(IT2 sets), :mod:`.parametric` (terms whose parameters are inputs), :mod:`.hedges` (very,
somewhat, ...), :mod:`.norms` (t-norms, s-norms, implication, aggregation, defuzzifiers),
:mod:`.rules` (variables and rules), :mod:`.tables` (the lowering to arrays and the rule
firing), :mod:`.reducers` (type reduction), :mod:`.sugeno` (Sugeno/TSK
systems), :mod:`.mamdani` (Mamdani systems, centroid and centre-of-sets type reduction),
:mod:`.system` (what every system shares: input checks, firing, outputs, zero firing),
:mod:`.tsukamoto` (Tsukamoto systems), :mod:`.hybrid` (systems side by side),
:mod:`.defuzz` (output grids and type-1 defuzzification), :mod:`.surface` (control surfaces).
"""

from .curves import Bell, Cosine, GaussianProduct, Spike, gauss2mf, gbellmf
from .defuzz import Sampling, output_grid
from .hedges import Hedge, Hedged
from .hybrid import HybridSystem
from .kinds import MFKind
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
    FootedTrapezoid,
    Gaussian,
    MembershipFunction,
    PiecewiseLinear,
    Term,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
    gaussmf,
    trapmf,
    trimf,
)
from .norms import (
    Aggregation,
    Connective,
    Defuzzifier,
    Implication,
    SNorm,
    TNorm,
    WeightedDefuzzifier,
)
from .parametric import Parametric, Ref
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
from .shapes import (
    Arc,
    Binary,
    Concave,
    Discrete,
    LinearSShape,
    LinearZShape,
    Ramp,
    Rectangle,
    SemiEllipse,
    linsmf,
    linzmf,
)
from .sigmoids import Sigmoid, SigmoidDifference, SigmoidProduct, dsigmf, psigmf, sigmf
from .splines import PiShape, SShape, ZShape, pimf, smf, zmf
from .sugeno import FuzzySystem, IT2Sugeno, T1Sugeno
from .surface import control_surface
from .tables import FEATURES, SystemTables
from .terms import (
    FUZZYLITE_TERMS,
    MATLAB_MFS,
    from_fuzzylite,
    from_matlab,
    fuzzylite_consequent,
    to_fuzzylite,
    to_matlab,
)
from .tsukamoto import T1Tsukamoto

__all__ = [
    "EIASC",
    "EKM",
    "EXHAUSTIVE",
    "FEATURES",
    "FUZZYLITE_TERMS",
    "KM",
    "MATLAB_MFS",
    "NIE_TAN",
    "WU_MENDEL",
    "Aggregation",
    "AnySystem",
    "Arc",
    "Bell",
    "Binary",
    "Concave",
    "Connective",
    "Consequent",
    "ConvergenceError",
    "Cosine",
    "Defuzzifier",
    "Discrete",
    "FootedTrapezoid",
    "FuzzySystem",
    "Gaussian",
    "GaussianProduct",
    "Hedge",
    "Hedged",
    "HybridSystem",
    "IT2Mamdani",
    "IT2Set",
    "IT2Sugeno",
    "Implication",
    "Input",
    "Linear",
    "LinearSShape",
    "LinearZShape",
    "MFKind",
    "MamdaniSystem",
    "MamdaniTables",
    "MembershipFunction",
    "Output",
    "Parametric",
    "PiShape",
    "PiecewiseLinear",
    "Ramp",
    "Rectangle",
    "Reducer",
    "Ref",
    "Rule",
    "SNorm",
    "SShape",
    "Sampling",
    "ScaledLagged",
    "SemiEllipse",
    "Sigmoid",
    "SigmoidDifference",
    "SigmoidProduct",
    "Spike",
    "SystemTables",
    "T1Mamdani",
    "T1Sugeno",
    "T1Tsukamoto",
    "TNorm",
    "Term",
    "Trapezoid",
    "Triangle",
    "TypeReducer",
    "TypeReduction",
    "UncertainMeanGaussianLower",
    "UncertainMeanGaussianUpper",
    "WeightedDefuzzifier",
    "ZShape",
    "ZeroFiringError",
    "control_surface",
    "defuzzify",
    "dsigmf",
    "from_fuzzylite",
    "from_matlab",
    "fuzzylite_consequent",
    "gauss2mf",
    "gaussmf",
    "gbellmf",
    "linsmf",
    "linzmf",
    "output_grid",
    "pimf",
    "psigmf",
    "rules_from_table",
    "set_centroid",
    "sigmf",
    "smf",
    "to_fuzzylite",
    "to_matlab",
    "trapmf",
    "trimf",
    "zmf",
]
