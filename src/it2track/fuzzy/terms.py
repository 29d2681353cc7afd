"""Factories: MATLAB's and fuzzylite's names of membership functions mapped to our classes,
and back. Every reader and writer goes through them (fuzzylite's ``TermFactory``): adding a
term is one class plus one entry here.

- :func:`from_matlab` (``"gbellmf", [a b c]`` -> :class:`~.curves.Bell`) and
  :func:`to_matlab`, for MATLAB's ``.fis`` and the FCL/FML names that follow MATLAB;
- :func:`from_fuzzylite` (``"Bell", [center width slope (height)]``) and
  :func:`to_fuzzylite`, for fuzzylite's ``.fll`` (and its ``.fis``/``.fcl`` exports);
- :func:`fuzzylite_consequent`: fuzzylite's ``Constant`` and ``Linear`` output terms as our
  Sugeno consequents. fuzzylite's ``Function`` (a formula string) is refused: we never
  evaluate text from a file, and its grammar is not implemented.

Parameters come in each tool's documented order; the messages of a refusal name the tool's
function and its parameter vector (``"gbellmf [0 2 5]: Bell(center=5.0, width=0.0, ...):
width=0.0 must be != 0"``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType

from .curves import Bell, Cosine, GaussianProduct, Spike
from .membership import (
    Gaussian,
    MembershipFunction,
    Term,
    Trapezoid,
    Triangle,
    UncertainMeanGaussianUpper,
)
from .rules import Linear
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
)
from .sigmoids import Sigmoid, SigmoidDifference, SigmoidProduct
from .splines import PiShape, SShape, ZShape

__all__ = [
    "FUZZYLITE_TERMS",
    "MATLAB_MFS",
    "TermSpec",
    "from_fuzzylite",
    "from_matlab",
    "fuzzylite_consequent",
    "to_fuzzylite",
    "to_matlab",
]


@dataclass(frozen=True)
class TermSpec:
    """One entry of a factory: a tool's name of a membership function.

    Attributes
    ----------
    name : str
        The tool's name (``"gbellmf"``, ``"Bell"``).
    params : str
        Its parameter vector as the tool documents it (``"[a b c]"``).
    count : int
        Number of parameters (fuzzylite may add a height); ``-1``: pairs (``Discrete``).
    build : callable
        ``build(params, h)`` -> the membership function.
    """

    name: str
    params: str
    count: int
    build: Callable[[Sequence[float], float], MembershipFunction]


def _spec(name: str, params: str, build: Callable[..., MembershipFunction]) -> TermSpec:
    count = len(params.strip("[]").split())
    return TermSpec(name, params, count, lambda p, h: build(*p, h))


#: MATLAB's membership functions (``fismf`` types) by name; MATLAB's have no height.
MATLAB_MFS: Mapping[str, TermSpec] = MappingProxyType({s.name: s for s in (
    _spec("trimf", "[a b c]", lambda a, b, c, h: Triangle(a, b, c, h)),
    _spec("trapmf", "[a b c d]", lambda a, b, c, d, h: Trapezoid(a, b, c, d, h)),
    _spec("gaussmf", "[sigma c]", lambda s, c, h: Gaussian(c, s, h)),
    _spec("gauss2mf", "[sig1 c1 sig2 c2]",
          lambda s1, c1, s2, c2, h: GaussianProduct(c1, s1, c2, s2, h)),
    _spec("gbellmf", "[a b c]", lambda a, b, c, h: Bell(c, a, b, h)),
    _spec("sigmf", "[a c]", lambda a, c, h: Sigmoid(c, a, h)),
    _spec("dsigmf", "[a1 c1 a2 c2]",
          lambda a1, c1, a2, c2, h: SigmoidDifference(c1, a1, a2, c2, h)),
    _spec("psigmf", "[a1 c1 a2 c2]",
          lambda a1, c1, a2, c2, h: SigmoidProduct(c1, a1, a2, c2, h)),
    _spec("smf", "[a b]", lambda a, b, h: SShape(a, b, h)),
    _spec("zmf", "[a b]", lambda a, b, h: ZShape(a, b, h)),
    _spec("pimf", "[a b c d]", lambda a, b, c, d, h: PiShape(a, b, c, d, h)),
    _spec("linsmf", "[a b]", lambda a, b, h: LinearSShape(a, b, h)),
    _spec("linzmf", "[a b]", lambda a, b, h: LinearZShape(a, b, h)),
)})

#: fuzzylite's membership terms by name (each takes an optional trailing height).
FUZZYLITE_TERMS: Mapping[str, TermSpec] = MappingProxyType({s.name: s for s in (
    _spec("Triangle", "[vertexA vertexB vertexC]", lambda a, b, c, h: Triangle(a, b, c, h)),
    _spec("Trapezoid", "[vertexA vertexB vertexC vertexD]",
          lambda a, b, c, d, h: Trapezoid(a, b, c, d, h)),
    _spec("Gaussian", "[mean standardDeviation]", lambda m, s, h: Gaussian(m, s, h)),
    _spec("GaussianProduct", "[meanA standardDeviationA meanB standardDeviationB]",
          lambda ma, sa, mb, sb, h: GaussianProduct(ma, sa, mb, sb, h)),
    _spec("Bell", "[center width slope]", lambda c, w, s, h: Bell(c, w, s, h)),
    _spec("Sigmoid", "[inflection slope]", lambda i, s, h: Sigmoid(i, s, h)),
    _spec("SigmoidDifference", "[left rising falling right]",
          lambda le, r, f, ri, h: SigmoidDifference(le, r, f, ri, h)),
    _spec("SigmoidProduct", "[left rising falling right]",
          lambda le, r, f, ri, h: SigmoidProduct(le, r, f, ri, h)),
    _spec("SShape", "[start end]", lambda s, e, h: SShape(s, e, h)),
    _spec("ZShape", "[start end]", lambda s, e, h: ZShape(s, e, h)),
    _spec("PiShape", "[bottomLeft topLeft topRight bottomRight]",
          lambda a, b, c, d, h: PiShape(a, b, c, d, h)),
    _spec("Cosine", "[center width]", lambda c, w, h: Cosine(c, w, h)),
    _spec("Spike", "[center width]", lambda c, w, h: Spike(c, w, h)),
    _spec("Concave", "[inflection end]", lambda i, e, h: Concave(i, e, h)),
    _spec("Ramp", "[start end]", lambda s, e, h: Ramp(s, e, h)),
    _spec("Rectangle", "[start end]", lambda s, e, h: Rectangle(s, e, h)),
    _spec("Binary", "[start direction]", lambda s, d, h: Binary(s, d, h)),
    _spec("Arc", "[start end]", lambda s, e, h: Arc(s, e, h)),
    _spec("SemiEllipse", "[start end]", lambda s, e, h: SemiEllipse(s, e, h)),
    TermSpec("Discrete", "[x1 y1 ... xn yn]", -1,
             lambda p, h: Discrete(list(zip(p[0::2], p[1::2], strict=True)), h)),
)})

#: fuzzylite's output terms that are Sugeno consequents, not membership functions.
FUZZYLITE_CONSEQUENTS = ("Constant", "Linear", "Function")


def _numbers(kind: str, params: Sequence[float]) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in params)
    except (TypeError, ValueError):
        raise ValueError(f"{kind}: parameters {params!r} must be numbers") from None
    return values


def _fmt(values: Sequence[float]) -> str:
    return "[" + " ".join(f"{v:g}" for v in values) + "]"


def _build(spec: TermSpec, values: tuple[float, ...], h: float, label: str
           ) -> MembershipFunction:
    try:
        return spec.build(values, h)
    except ValueError as exc:
        raise ValueError(f"{label}: {exc}") from None


def from_matlab(kind: str, params: Sequence[float]) -> MembershipFunction:
    """The membership function of MATLAB's ``fismf(kind, params)``.

    Parameters
    ----------
    kind : str
        MATLAB's type name, one of :data:`MATLAB_MFS` (``"trimf"``, ``"gbellmf"``, ...).
    params : sequence of float
        MATLAB's parameter vector, in MATLAB's documented order.

    Returns
    -------
    MembershipFunction

    Raises
    ------
    ValueError
        For an unknown name, a wrong parameter count or parameters the shape refuses; the
        message names the function, its parameter vector and the offending parameter.

    Examples
    --------
    >>> from_matlab("gbellmf", [2, 4, 6])
    Bell(center=6.0, width=2.0, slope=4.0, h=1.0)
    """
    spec = MATLAB_MFS.get(kind)
    if spec is None:
        raise ValueError(f"unknown MATLAB membership function {kind!r}; it2track reads "
                         f"{', '.join(MATLAB_MFS)}")
    values = _numbers(kind, params)
    if len(values) != spec.count:
        raise ValueError(f"{kind} needs {spec.count} parameters {spec.params}, got "
                         f"{len(values)} {_fmt(values)}")
    return _build(spec, values, 1.0, f"{kind} {_fmt(values)}")


def from_fuzzylite(kind: str, params: Sequence[float]) -> MembershipFunction:
    """The membership function of fuzzylite's ``term: name kind params [height]``.

    Parameters
    ----------
    kind : str
        fuzzylite's class name, one of :data:`FUZZYLITE_TERMS` (``"Bell"``, ``"Ramp"``, ...).
        ``Constant``, ``Linear`` and ``Function`` are consequents: see
        :func:`fuzzylite_consequent`.
    params : sequence of float
        The parameters in fuzzylite's order, optionally followed by the height (``Discrete``:
        ``x1 y1 ... xn yn`` and an optional height, so an odd count ends with the height).

    Returns
    -------
    MembershipFunction

    Raises
    ------
    ValueError
        For an unknown name, a wrong parameter count or parameters the shape refuses, naming
        the term and its parameters.

    Examples
    --------
    >>> from_fuzzylite("Bell", [0, 5, 3, 0.5])
    Bell(center=0.0, width=5.0, slope=3.0, h=0.5)
    """
    if kind in FUZZYLITE_CONSEQUENTS:
        raise ValueError(f"fuzzylite's {kind} is an output term of a Takagi-Sugeno system, not "
                         "a membership function: use fuzzylite_consequent()")
    spec = FUZZYLITE_TERMS.get(kind)
    if spec is None:
        raise ValueError(f"unknown fuzzylite term {kind!r}; it2track reads "
                         f"{', '.join(FUZZYLITE_TERMS)}")
    values = _numbers(kind, params)
    label = f"{kind} {_fmt(values)}"
    if spec.count < 0:
        with_height = len(values) % 2 == 1
        if len(values) < 2:
            raise ValueError(f"{kind} needs pairs {spec.params} (and an optional height), got "
                             f"{_fmt(values)}")
    else:
        if len(values) not in (spec.count, spec.count + 1):
            raise ValueError(f"{kind} needs {spec.count} parameters {spec.params} (and an "
                             f"optional height), got {len(values)} {_fmt(values)}")
        with_height = len(values) == spec.count + 1
    h = values[-1] if with_height else 1.0
    return _build(spec, values[:-1] if with_height else values, h, label)


def fuzzylite_consequent(kind: str, params: Sequence[float], n_inputs: int
                         ) -> float | Linear:
    """A fuzzylite Takagi-Sugeno output term as a consequent of :class:`~.rules.Rule`.

    Parameters
    ----------
    kind : str
        ``"Constant"`` (one value) or ``"Linear"`` (``c1 ... cn`` and an optional constant
        ``k``: ``y = c1 x1 + ... + cn xn + k``).
    params : sequence of float
        The term's parameters.
    n_inputs : int
        Inputs of the engine (``Linear`` needs ``n_inputs`` or ``n_inputs + 1`` values).

    Returns
    -------
    float or Linear

    Raises
    ------
    ValueError
        For ``Function`` (a formula: never evaluated), other names or wrong counts.

    Examples
    --------
    >>> fuzzylite_consequent("Linear", [2, -1, 0.5], 2)
    Linear(lo=(2.0, -1.0), hi=(2.0, -1.0), constant_lo=0.5, constant_hi=0.5)
    """
    values = _numbers(kind, params)
    if kind == "Constant":
        if len(values) != 1 or not math.isfinite(values[0]):
            raise ValueError(f"Constant needs one finite value, got {_fmt(values)}")
        return values[0]
    if kind == "Linear":
        if len(values) not in (n_inputs, n_inputs + 1):
            raise ValueError(f"Linear needs {n_inputs} coefficients (one per input) and an "
                             f"optional constant, got {len(values)} {_fmt(values)}")
        constant = values[n_inputs] if len(values) > n_inputs else 0.0
        return Linear(values[:n_inputs], constant)
    if kind == "Function":
        raise ValueError("fuzzylite's Function term is a formula, not numbers: parse its "
                         "text with it2track.fuzzy.formula.Formula")
    raise ValueError(f"unknown fuzzylite output term {kind!r} for a Takagi-Sugeno output "
                     "(Constant, Linear)")


def to_matlab(mf: MembershipFunction) -> tuple[str, tuple[float, ...]]:
    """``(type, params)`` of MATLAB's function for ``mf`` (inverse of :func:`from_matlab`).

    Raises
    ------
    ValueError
        If MATLAB has no such function, or ``mf`` has a height other than 1.

    Examples
    --------
    >>> to_matlab(Bell(6, 2, 4))
    ('gbellmf', (2.0, 4.0, 6.0))
    """
    h = float(getattr(mf, "h", 1.0))
    if isinstance(mf, Term) and mf.MATLAB is not None:
        kind, params = mf.MATLAB, mf.matlab_params()
    elif type(mf) is Triangle:
        kind, params = "trimf", (float(mf.a), float(mf.b), float(mf.c))
    elif type(mf) is Trapezoid:
        kind, params = "trapmf", (float(mf.a), float(mf.b), float(mf.c), float(mf.d))
    elif type(mf) is Gaussian:
        kind, params = "gaussmf", (float(mf.sigma), float(mf.mean))
    elif type(mf) is UncertainMeanGaussianUpper:
        kind, params = "gauss2mf", (float(mf.sigma), float(mf.m1), float(mf.sigma),
                                    float(mf.m2))
    else:
        raise ValueError(f"{mf!r} has no MATLAB membership function")
    if h != 1.0:
        raise ValueError(f"{mf!r} has height h={h!r}; MATLAB's {kind} has none (only 1)")
    return kind, params


def to_fuzzylite(mf: MembershipFunction) -> tuple[str, tuple[float, ...]]:
    """``(term, params)`` of fuzzylite's term for ``mf``, the height appended when it is not 1
    (inverse of :func:`from_fuzzylite`).

    Raises
    ------
    ValueError
        If fuzzylite has no such term.

    Examples
    --------
    >>> to_fuzzylite(Bell(6, 2, 4, h=0.5))
    ('Bell', (6.0, 2.0, 4.0, 0.5))
    """
    h = float(getattr(mf, "h", 1.0))
    try:
        if isinstance(mf, Term) and mf.FUZZYLITE is not None:
            kind, params = mf.FUZZYLITE, mf.fuzzylite_params()
        elif type(mf) is Triangle:
            kind, params = "Triangle", (float(mf.a), float(mf.b), float(mf.c))
        elif type(mf) is Trapezoid:
            kind, params = "Trapezoid", (float(mf.a), float(mf.b), float(mf.c), float(mf.d))
        elif type(mf) is Gaussian:
            kind, params = "Gaussian", (float(mf.mean), float(mf.sigma))
        elif type(mf) is UncertainMeanGaussianUpper:
            kind, params = "GaussianProduct", (float(mf.m1), float(mf.sigma), float(mf.m2),
                                               float(mf.sigma))
        else:
            raise NotImplementedError
    except NotImplementedError:
        raise ValueError(f"{mf!r} has no fuzzylite term") from None
    return kind, (*params, h) if h != 1.0 else params
