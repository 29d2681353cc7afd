"""MATLAB's type-2 lower membership functions: ``LowerScale`` and ``LowerLag``, read exactly
and written with the fewest digits that reproduce our lower MF.

MATLAB documents a type-2 MF (``fismftype2``) as an upper MF plus ``LowerScale`` (the lower
MF's height) and ``LowerLag`` (where the lower MF starts: zero until the upper MF reaches the
lag). For a ``trimf``/``trapmf`` the lower MF is then a triangle/trapezoid whose feet are
``a + lag (b - a)`` and ``d - lag (d - c)`` (one lag, or one per side); for a smooth MF it is a
:class:`~it2track.fuzzy.ScaledLagged`. The feet are evaluated exactly from the lag's decimal
text (rational arithmetic) and rounded once, so that a lag written with enough digits
reproduces any foot.
"""

from __future__ import annotations

from decimal import Decimal, localcontext
from fractions import Fraction

from ..fuzzy import (
    Gaussian,
    IT2Set,
    MembershipFunction,
    PiecewiseLinear,
    ScaledLagged,
    Trapezoid,
    Triangle,
)
from ._common import guard
from ._matlab import Document, MFValue
from ._writing import fmt_number
from .errors import UnsupportedFeatureError

__all__ = ["LOWER_KEYS", "lag_foot", "lower_from", "scale_lag"]

#: the MF properties of a type-2 ``.fis`` MF line
LOWER_KEYS = ("LowerScale", "LowerLag")


def lower_from(doc: Document, mfv: MFValue, upper: MembershipFunction) -> MembershipFunction:
    """The lower MF of a type-2 ``.fis`` MF line (``LowerScale``, ``LowerLag``)."""
    for key in LOWER_KEYS:
        if key not in mfv.extras:
            raise doc.error(
                mfv.line,
                f"type-2 MF needs 'LowerScale',s,'LowerLag',l after its parameters "
                f"(missing {key!r})",
            )
    scale_v = mfv.extras["LowerScale"]
    lag_v = mfv.extras["LowerLag"]
    if len(scale_v) != 1:
        raise doc.error(mfv.line, "LowerScale must be one number")
    scale = float(scale_v[0])
    if not 0.0 < scale <= 1.0:
        raise doc.error(mfv.line, f"LowerScale={scale:g} must satisfy 0 < scale <= 1")
    if len(lag_v) not in (1, 2):
        raise doc.error(mfv.line, "LowerLag must be one number or two (left, right)")
    lags = (Fraction(lag_v[0]), Fraction(lag_v[-1]))
    for lag in lags:
        if not 0 <= lag < 1:
            raise doc.error(mfv.line, f"LowerLag={float(lag):g} must satisfy 0 <= lag < 1")
    if scale == 1.0 and lags == (0, 0):
        return upper
    with guard(doc, mfv.line, f"MF {mfv.name!r}"):
        if isinstance(upper, PiecewiseLinear):
            a, b, c, d, _ = upper.as_trapezoid()
            la = lag_foot(a, b, lags[0])
            ld = lag_foot(d, c, lags[1])
            if isinstance(upper, Triangle):
                return Triangle(la, b, ld, scale)
            return Trapezoid(la, b, c, ld, scale)
        if lags[0] != lags[1]:
            raise doc.error(
                mfv.line, f"a two-sided LowerLag needs a trimf or trapmf, not {mfv.type}"
            )
        return ScaledLagged(upper, scale, float(lags[0]))


def lag_foot(foot: float, peak: float, lag: Fraction) -> float:
    """Where a lower MF side starts: ``foot + lag * (peak - foot)``, rounded once.

    The upper MF side rises from ``foot`` (value 0) to ``peak`` (value 1), so it reaches the
    value ``lag`` there. The expression is evaluated exactly (rational arithmetic) and rounded
    to the nearest float, so that a lag written with enough digits reproduces any foot.
    """
    if foot == peak or lag == 0:
        return foot
    return float(Fraction(foot) + lag * (Fraction(peak) - Fraction(foot)))


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------


def scale_lag(s: IT2Set, what: str) -> tuple[float, tuple[str, ...]]:
    """``(LowerScale, LowerLag)`` such that the reader rebuilds ``s.lower`` exactly."""
    upper, lower = s.upper, s.lower
    piecewise = isinstance(upper, PiecewiseLinear)
    if lower is upper or lower == upper:
        return 1.0, ("0", "0") if piecewise else ("0",)
    if isinstance(lower, ScaledLagged) and (lower.upper is upper or lower.upper == upper):
        if piecewise:
            raise UnsupportedFeatureError(
                f"{what}: a ScaledLagged lower MF of a triangle/trapezoid is not the MATLAB "
                "lower MF (use IT2Set.from_scale_lag, which builds a trapezoid)"
            )
        return float(lower.scale), (fmt_number(lower.lag),)
    if type(upper) is Gaussian and type(lower) is Gaussian:
        assert isinstance(upper, Gaussian) and isinstance(lower, Gaussian)
        if lower.mean == upper.mean and lower.sigma == upper.sigma and upper.h == 1.0:
            return float(lower.h), ("0",)
    if piecewise and isinstance(lower, PiecewiseLinear) and type(lower) in (Triangle, Trapezoid):
        assert isinstance(upper, PiecewiseLinear)
        a, b, c, d, h = upper.as_trapezoid()
        la, lb, lc, ld, lh = lower.as_trapezoid()
        if lb == b and lc == c and h == 1.0 and a <= la and ld <= d:
            left = _solve_lag(a, b, la)
            right = _solve_lag(d, c, ld)
            if left is not None and right is not None:
                return lh, (left, right)
    raise UnsupportedFeatureError(
        f"{what}: its lower MF {lower!r} is not a LowerScale/LowerLag image of its upper MF "
        f"{upper!r}, the only lower MFs MATLAB's type-2 .fis can describe; save as .t2fis or "
        ".toml"
    )


def _solve_lag(foot: float, peak: float, target: float) -> str | None:
    """The shortest decimal lag in ``[0, 1)`` for which :func:`lag_foot` gives ``target``."""
    if foot == peak:
        return "0" if target == foot else None
    exact = (Fraction(target) - Fraction(foot)) / (Fraction(peak) - Fraction(foot))
    if not 0 <= exact < 1:
        return None
    if exact == 0:
        return "0"
    for digits in range(1, 60):
        with localcontext() as ctx:
            ctx.prec = digits
            text = str(Decimal(exact.numerator) / Decimal(exact.denominator))
        lag = Fraction(text)
        if 0 <= lag < 1 and lag_foot(foot, peak, lag) == target:
            return text
    return None  # pragma: no cover - 60 digits always suffice for doubles
