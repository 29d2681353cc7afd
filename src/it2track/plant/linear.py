"""Linear time-invariant plants, discretised exactly by zero-order hold (DESIGN.md sec. 10).

:class:`LinearSpec` describes a state-space system ``(A, B, C, D)``, continuous
(``dx/dt = A x + B u``) or discrete (``x+ = A x + B u``), as plain numbers, so it travels in a
TOML table or to worker processes and needs no other library. Its :meth:`~LinearSpec.build`
gives a :class:`LinearPlant` for a control period ``ts``: a continuous system is discretised
exactly with the input held over the period,

    expm([[A, B], [0, 0]] ts) = [[Ad, Bd], [0, I]],      x_(k+1) = Ad x_k + Bd u_k,

and a discrete one must have been sampled at ``ts`` (``dt == ts``) or leave its period open
(``dt = True``). The output at ``t_k`` is read just before the new input is applied:
``y_k = C x_k + D u_(k-1)`` (``u_(-1) = 0``), so a plant with direct feedthrough forms no
algebraic loop with the controller.

:func:`it2track.plant.control.from_control` turns any python-control LTI system (``ss``,
``tf``) into a :class:`LinearSpec`; a transfer function may also be given here directly
(:meth:`LinearSpec.from_tf`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import Any

import numpy as np
import scipy.linalg
import scipy.signal
from numpy.typing import ArrayLike, NDArray

__all__ = ["MAX_LTI_ORDER", "LinearPlant", "LinearSpec"]

FloatArray = NDArray[np.float64]
Matrix = tuple[tuple[float, ...], ...]

#: Most states, inputs or outputs of a :class:`LinearSpec` (the discretisation is a dense
#: matrix exponential, and every step visits each matrix entry once per run).
MAX_LTI_ORDER = 256
#: Relative tolerance between a discrete system's ``dt`` and the loop's period.
DT_RTOL = 1e-9


def _matrix(value: object, key: str, rows: int | None, cols: int | None) -> Matrix:
    """``value`` as a finite 2-D matrix of the given shape (``None``: any), as nested tuples."""
    if isinstance(value, str | bytes):
        raise ValueError(f"LinearSpec: {key}={value!r} must be a matrix of numbers")
    try:
        arr = np.array(value, dtype=object)
    except (TypeError, ValueError):
        raise ValueError(f"LinearSpec: {key}={value!r} must be a matrix of numbers") from None
    if arr.ndim != 2:
        raise ValueError(f"LinearSpec: {key} must be a 2-D matrix (list of rows), got "
                         f"{arr.ndim} dimension(s)")
    if any(isinstance(v, bool) or not isinstance(v, Real) for v in arr.reshape(-1).tolist()):
        raise ValueError(f"LinearSpec: {key}={value!r} must hold real numbers only")
    out = arr.astype(np.float64)
    if not np.isfinite(out).all():
        raise ValueError(f"LinearSpec: {key} must hold finite numbers, got {value!r}")
    if max(out.shape) > MAX_LTI_ORDER:
        raise ValueError(f"LinearSpec: {key} has shape {out.shape}; at most {MAX_LTI_ORDER} "
                         "states, inputs and outputs")
    want = (rows if rows is not None else out.shape[0], cols if cols is not None else out.shape[1])
    if out.shape != want:
        raise ValueError(f"LinearSpec: {key} has shape {out.shape}, expected {want}")
    return tuple(tuple(float(v) for v in row) for row in out)


#: How :meth:`LinearSpec.to_dict` writes an unbounded input limit (JSON has no infinity).
INFINITE_LIMITS = {"-inf": -math.inf, "inf": math.inf}


def limit_value(value: object) -> object:
    """An input limit as given, with the strings ``"inf"``/``"-inf"`` read as infinities."""
    return INFINITE_LIMITS.get(value, value) if isinstance(value, str) else value


def limit_text(value: float) -> float | str:
    """An input limit for a table: infinities as ``"inf"``/``"-inf"`` (JSON-safe)."""
    return value if math.isfinite(value) else ("inf" if value > 0 else "-inf")


def _names(value: object, key: str, n: int, default: str) -> tuple[str, ...]:
    if value is None or value == ():
        return tuple(f"{default}[{i}]" for i in range(n)) if n != 1 else (default,)
    if (not isinstance(value, list | tuple) or len(value) != n
            or not all(isinstance(s, str) and s for s in value)
            or len(set(value)) != len(value)):
        raise ValueError(f"LinearSpec: {key}={value!r} must be {n} distinct non-empty names")
    return tuple(value)


@dataclass(frozen=True, kw_only=True)
class LinearSpec:
    """A linear time-invariant plant ``(A, B, C, D)``, continuous or discrete.

    Parameters
    ----------
    a : array_like, shape (n, n)
        State matrix ``A`` (``n >= 1`` states).
    b : array_like, shape (n, m)
        Input matrix ``B`` (``m >= 1`` inputs).
    c : array_like, shape (p, n)
        Output matrix ``C`` (``p >= 1`` outputs).
    d : array_like, shape (p, m), optional
        Feedthrough ``D`` (default zeros).
    dt : float or True
        0 (default): continuous time. A number > 0: discrete time sampled every ``dt`` s
        (must equal the loop's period). ``True``: discrete at whatever period the loop uses.
    input_limits : sequence of (float, float), optional
        ``(low, high)`` per input (``-inf``/``inf``, or the strings ``"-inf"``/``"inf"``,
        allowed); default unbounded.
    x0 : array_like, shape (n,), optional
        Initial state (default zeros).
    input_names, output_names : sequence of str, optional
        Default ``("u",)``/``("y",)`` for one, ``("u[0]", ...)`` for several.
    name : str
        Label (default ``"lti"``).

    Raises
    ------
    ValueError
        Naming the field and value: non-numeric, non-finite or mis-shaped matrices, more than
        :data:`MAX_LTI_ORDER` states/inputs/outputs, ``dt`` < 0 or not finite, limits not one
        ``low < high`` pair per input, names not distinct.

    Examples
    --------
    >>> import numpy as np
    >>> lag = LinearSpec(a=[[-1.0]], b=[[1.0]], c=[[1.0]])   # 1 / (s + 1)
    >>> plant = lag.build(ts=0.5)
    >>> state = plant.initial_state(1)
    >>> state = plant.step(state, np.ones((1, 1)), 0.0)
    >>> bool(round(float(plant.outputs(state)[0, 0]), 12) == round(1 - np.exp(-0.5), 12))
    True
    """

    # Given as array_like; stored as nested tuples of floats (hashable, comparable).
    a: Any
    b: Any
    c: Any
    d: Any = None
    dt: float | bool = 0.0
    input_limits: Any = None
    x0: Any = None
    input_names: tuple[str, ...] = ()
    output_names: tuple[str, ...] = ()
    name: str = "lti"
    kind: str = field(default="lti", init=False)

    def __post_init__(self) -> None:
        a = _matrix(self.a, "a", None, None)
        n = len(a)
        if n < 1 or len(a[0]) != n:
            raise ValueError(f"LinearSpec: a must be square with >= 1 state, got shape "
                             f"{np.shape(a)}")
        b = _matrix(self.b, "b", n, None)
        m = len(b[0])
        c = _matrix(self.c, "c", None, n)
        p = len(c)
        if m < 1 or p < 1:
            raise ValueError(f"LinearSpec: the plant needs >= 1 input and >= 1 output, got "
                             f"b {n}x{m}, c {p}x{n}")
        d = _matrix(self.d, "d", p, m) if self.d is not None else ((0.0,) * m,) * p
        for key, value in (("a", a), ("b", b), ("c", c), ("d", d)):
            object.__setattr__(self, key, value)
        dt = self.dt
        if dt is not True:
            if (isinstance(dt, bool) or not isinstance(dt, Real) or not math.isfinite(dt)
                    or dt < 0):
                raise ValueError(f"LinearSpec: dt={dt!r} must be 0 (continuous), a finite "
                                 "number > 0 (discrete) or True (discrete, any period)")
            object.__setattr__(self, "dt", float(dt))
        limits = self.input_limits
        if limits is None:
            limits = ((-math.inf, math.inf),) * m
        try:
            given = [tuple(limit_value(v) for v in pair) for pair in limits]
            pairs = tuple((float(lo), float(hi)) for lo, hi in given)  # type: ignore[arg-type]
            ok = len(pairs) == m and all(
                not isinstance(v, bool) and isinstance(v, Real) for pair in given for v in pair
            )
        except (TypeError, ValueError):
            ok = False
        if not ok or not all(lo < hi for lo, hi in pairs):
            raise ValueError(f"LinearSpec: input_limits={self.input_limits!r} must be one "
                             f"(low, high) pair of numbers with low < high per input ({m})")
        object.__setattr__(self, "input_limits", pairs)
        x0 = (0.0,) * n if self.x0 is None else _matrix(
            [list(np.ravel(np.asarray(self.x0, dtype=object)))], "x0", 1, n)[0]
        object.__setattr__(self, "x0", x0)
        object.__setattr__(self, "input_names", _names(self.input_names, "input_names", m, "u"))
        object.__setattr__(self, "output_names",
                           _names(self.output_names, "output_names", p, "y"))
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"LinearSpec: name={self.name!r} must be a non-empty string")

    @property
    def n_states(self) -> int:
        """Number of states n."""
        return len(self.a)

    @classmethod
    def from_tf(cls, num: ArrayLike, den: ArrayLike, **kwargs: Any) -> LinearSpec:
        """A single-input single-output plant from its transfer function ``num(s) / den(s)``.

        Parameters
        ----------
        num, den : array_like
            Polynomial coefficients, highest power first; ``len(num) <= len(den)`` (proper),
            ``den[0] != 0``.
        **kwargs
            The other fields of :class:`LinearSpec` (``dt``, ``input_limits``, names...).

        Returns
        -------
        LinearSpec
            A state-space realisation (scipy's controller canonical form).

        Raises
        ------
        ValueError
            If the coefficients are not finite numbers, ``den`` is empty or starts with 0, or
            the transfer function is improper.

        Examples
        --------
        >>> LinearSpec.from_tf([2.0], [1.0, 3.0]).a
        ((-3.0,),)
        """
        rows = []
        for key, poly in (("num", num), ("den", den)):
            coeffs = _matrix([list(np.atleast_1d(np.asarray(poly, dtype=object)))], key, 1, None)
            rows.append(np.array(coeffs[0]))
        nu, de = rows
        if de.size == 0 or de[0] == 0.0:
            raise ValueError(f"LinearSpec: den={list(de)!r} must be non-empty with a non-zero "
                             "leading coefficient")
        nu = np.trim_zeros(nu, "f") if nu.any() else np.zeros(1)
        if nu.size > de.size:
            raise ValueError(f"LinearSpec: num={list(nu)!r} / den={list(de)!r} is improper "
                             "(numerator degree above the denominator's): no state-space form")
        a, b, c, d = scipy.signal.tf2ss(nu, de)
        n = a.shape[0]
        return cls(a=a.reshape(n, n), b=b.reshape(n, 1), c=c.reshape(1, n), d=d.reshape(1, 1),
                   **kwargs)

    def build(self, *, ts: float, robot: object = None) -> LinearPlant:
        """The plant for control period ``ts`` (``robot`` is ignored).

        Parameters
        ----------
        ts : float
            Control period, s.
        robot : RobotParams, optional
            Ignored (a linear plant has its own parameters).

        Returns
        -------
        LinearPlant

        Raises
        ------
        ValueError
            If ``ts`` is not a finite number > 0, a discrete ``dt`` differs from it, or the
            discretised matrices overflow (``A ts`` far too large for float64).
        """
        return LinearPlant(self, ts)

    def to_dict(self) -> dict[str, Any]:
        """The table :func:`it2track.plant.specs.plant_from_dict` reads back.

        Returns
        -------
        dict
            ``kind = "lti"``, the matrices as lists of rows and the other fields (infinite
            limits as the strings ``"inf"``/``"-inf"``, which JSON can hold).
        """
        return {
            "kind": self.kind, "name": self.name,
            "A": [list(r) for r in self.a], "B": [list(r) for r in self.b],
            "C": [list(r) for r in self.c], "D": [list(r) for r in self.d or ()],
            "dt": self.dt, "x0": list(self.x0 or ()),
            "input_limits": [[limit_text(v) for v in p] for p in self.input_limits or ()],
            "input_names": list(self.input_names), "output_names": list(self.output_names),
        }  # fmt: skip

    @classmethod
    def from_dict(cls, table: dict[str, Any], *, where: str = "[plant]") -> LinearSpec:
        """A spec from a TOML/JSON table: ``A, B, C[, D]`` or ``num, den`` (SISO), plus any of
        ``dt, x0, input_limits, input_names, output_names, name`` (``kind`` ignored).

        Parameters
        ----------
        table : dict
            The table (unknown keys are refused).
        where : str
            How error messages name the table (file and key).

        Returns
        -------
        LinearSpec

        Raises
        ------
        ValueError
            Naming ``where`` and the offending key and value.
        """
        common = {"kind", "dt", "x0", "input_limits", "input_names", "output_names", "name"}
        keys = set(table)
        if keys & {"num", "den"}:
            allowed = common | {"num", "den"}
            form = "num/den"
        else:
            allowed = common | {"A", "B", "C", "D"}
            form = "A/B/C/D"
        unknown = sorted(keys - allowed)
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {unknown} for a {form} plant; allowed: "
                             f"{sorted(allowed)}")
        kw = {k: v for k, v in table.items() if k in common - {"kind"}}
        try:
            if form == "num/den":
                missing = sorted({"num", "den"} - keys)
                if missing:
                    raise ValueError(f"missing key(s) {missing}")
                return cls.from_tf(table["num"], table["den"], **kw)
            missing = sorted({"A", "B", "C"} - keys)
            if missing:
                raise ValueError(f"missing key(s) {missing} (give A, B, C[, D] or num, den)")
            return cls(a=table["A"], b=table["B"], c=table["C"], d=table.get("D"), **kw)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"{where}: {exc}") from None


def _check_ts(ts: object) -> float:
    if isinstance(ts, bool) or not isinstance(ts, Real) or not math.isfinite(ts) or ts <= 0:
        raise ValueError(f"ts={ts!r} must be a finite number > 0")
    return float(ts)


class LinearPlant:
    """A :class:`LinearSpec` discretised for one control period (the runtime plant).

    Parameters
    ----------
    spec : LinearSpec
        The system.
    ts : float
        Control period, s.

    Attributes
    ----------
    ad, bd : ndarray
        The discrete-time state and input matrices ``x_(k+1) = ad x_k + bd u_k``.

    Raises
    ------
    ValueError
        As :meth:`LinearSpec.build`.

    Notes
    -----
    The state is ``(x (n, B), u_prev (m, B))``. Each step computes every state row as a sum
    over the matrix entries in a fixed order with elementwise numpy operations (no BLAS), so a
    run's numbers do not depend on the batch it is in.
    """

    def __init__(self, spec: LinearSpec, ts: float) -> None:
        if not isinstance(spec, LinearSpec):
            raise ValueError(f"spec must be a LinearSpec, got {spec!r}")
        ts = _check_ts(ts)
        a = np.array(spec.a, dtype=np.float64).reshape(spec.n_states, spec.n_states)
        b = np.array(spec.b, dtype=np.float64).reshape(spec.n_states, -1)
        m = len(spec.input_names)
        b = b.reshape(spec.n_states, m)
        if spec.dt == 0.0:
            n = spec.n_states
            aug = np.zeros((n + m, n + m))
            aug[:n, :n] = a * ts
            aug[:n, n:] = b * ts
            with np.errstate(over="ignore", invalid="ignore"):
                e = scipy.linalg.expm(aug)
            ad, bd = e[:n, :n], e[:n, n:]
            if not (np.isfinite(ad).all() and np.isfinite(bd).all()):
                raise ValueError(f"LinearSpec {spec.name!r}: expm(A ts) overflows at ts={ts!r} "
                                 "(a pole far in the right half-plane); shorten ts")
        else:
            if spec.dt is not True and abs(spec.dt - ts) > DT_RTOL * ts:
                raise ValueError(f"LinearSpec {spec.name!r} is discrete with dt={spec.dt!r}, "
                                 f"but the loop's period is ts={ts!r}: resample it at ts")
            ad, bd = a, b
        self.spec = spec
        self.ts = ts
        self.ad = np.ascontiguousarray(ad)
        self.bd = np.ascontiguousarray(bd)
        self.c = np.array(spec.c, dtype=np.float64).reshape(len(spec.output_names), -1)
        self.d = np.array(spec.d, dtype=np.float64).reshape(len(spec.output_names), m)
        self.input_names = spec.input_names
        self.output_names = spec.output_names
        self.input_limits = spec.input_limits or ()
        self._x0 = np.array(spec.x0 or (), dtype=np.float64)

    def __repr__(self) -> str:
        return f"LinearPlant({self.spec!r}, ts={self.ts!r})"

    def initial_state(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n`` runs at ``x0`` with no input applied yet.

        Parameters
        ----------
        n : int
            Number of runs (>= 0).

        Returns
        -------
        tuple of ndarray
            ``(x (n_states, n), u_prev (n_inputs, n))``.
        """
        if isinstance(n, bool) or not isinstance(n, Integral) or n < 0:
            raise ValueError(f"n={n!r} must be an integer >= 0")
        x = np.repeat(self._x0[:, None], int(n), axis=1)
        return x, np.zeros((len(self.input_names), int(n)))

    @staticmethod
    def _rows(mat: FloatArray, v: FloatArray, out: FloatArray, tmp: FloatArray) -> None:
        """``out[i] += sum_j mat[i, j] v[j]``, entries in order, elementwise over the batch."""
        for i in range(mat.shape[0]):
            for j in range(mat.shape[1]):
                coef = mat[i, j]
                if coef != 0.0:
                    np.multiply(v[j], coef, out=tmp)
                    out[i] += tmp

    def step(
        self, state: tuple[FloatArray, FloatArray], u: FloatArray, t: float
    ) -> tuple[FloatArray, FloatArray]:
        """One period with ``u`` ``(n_inputs, B)`` held: ``x+ = Ad x + Bd u``.

        Parameters
        ----------
        state : tuple of ndarray
            ``(x, u_prev)``.
        u : ndarray, shape (n_inputs, B)
            Inputs (the loop saturates them).
        t : float
            Start of the period, s (unused: time-invariant).

        Returns
        -------
        tuple of ndarray
            The new ``(x, u)`` (new arrays).
        """
        x, _ = state
        batch = x.shape[1:] if x.ndim > 1 else u.shape[1:]
        nxt = np.zeros((self.ad.shape[0], *batch))
        tmp = np.empty(batch)
        self._rows(self.ad, x, nxt, tmp)
        self._rows(self.bd, u, nxt, tmp)
        return nxt, np.array(u, dtype=np.float64, copy=True)

    def outputs(self, state: tuple[FloatArray, FloatArray]) -> FloatArray:
        """``y = C x + D u_prev``, shape ``(n_outputs, B)``.

        Parameters
        ----------
        state : tuple of ndarray
            ``(x, u_prev)``.

        Returns
        -------
        ndarray, shape (n_outputs, B)
        """
        x, u_prev = state
        batch = u_prev.shape[1:]
        y = np.zeros((self.c.shape[0], *batch))
        tmp = np.empty(batch)
        self._rows(self.c, x, y, tmp)
        self._rows(self.d, u_prev, y, tmp)
        return y
