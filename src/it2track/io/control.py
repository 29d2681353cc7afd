"""Fuzzy systems as python-control systems (DESIGN.md sec. 1, 10; needs ``it2track[control]``).

:func:`to_control` wraps any it2track fuzzy system (IT2/T1, Sugeno/Mamdani, any number of
inputs and outputs) as a discrete-time :class:`control.NonlinearIOSystem`: a static map, no
state, ``y_k = fls(u_k)``, sampled every ``dt``. Inputs and outputs carry the system's variable
names, so it can be connected by name with :func:`control.interconnect` and simulated with
:func:`control.input_output_response`. Inputs outside a universe are clipped to it, as
everywhere in it2track; NaN or infinite inputs raise ``ValueError``.

python-control is imported only inside :func:`to_control`.
"""

from __future__ import annotations

import math
from numbers import Real
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._extras import require
from ..fuzzy import AnySystem, IT2Mamdani, IT2Sugeno, T1Mamdani, T1Sugeno

__all__ = ["to_control"]


def to_control(
    fls: AnySystem,
    dt: float | bool = True,
    *,
    name: str | None = None,
    inputs: list[str] | None = None,
    outputs: list[str] | None = None,
) -> Any:
    """A fuzzy system as a discrete-time python-control nonlinear system (a static map).

    Parameters
    ----------
    fls : IT2Sugeno, T1Sugeno, IT2Mamdani or T1Mamdani
        The system; its crisp output (``(yl + yr) / 2`` for interval type-2) is the output.
    dt : float or True
        Sampling time, s (a finite number > 0), or ``True`` (discrete, any period), as in
        python-control.
    name : str, optional
        The system's name, without ``.`` (default: the fuzzy system's name with ``.`` replaced
        by ``_``, or ``"fls"``).
    inputs, outputs : list of str, optional
        Signal names (default: the fuzzy system's input and output names).

    Returns
    -------
    control.NonlinearIOSystem
        No states; ``ninputs == fls.n_inputs``, ``noutputs == fls.n_outputs``.

    Raises
    ------
    it2track._extras.MissingExtraError
        If python-control is not installed (an ``ImportError`` naming ``it2track[control]``).
    ValueError
        If ``fls`` is not a fuzzy system, ``dt`` is not ``True`` or a finite number > 0, or the
        names are not one distinct string per signal.

    Examples
    --------
    >>> import control as ct                                     # doctest: +SKIP
    >>> from it2track import heading_fls                         # doctest: +SKIP
    >>> flc = to_control(heading_fls(0.2), 0.01, name="flc")     # doctest: +SKIP
    >>> flc.input_labels, flc.output_labels                      # doctest: +SKIP
    (['e', 'de'], ['u'])
    """
    ct = require("control", "control", "a fuzzy system as a python-control system")
    if not isinstance(fls, IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani):
        raise ValueError(f"fls must be an it2track fuzzy system, got {type(fls).__name__}")
    if dt is not True and (isinstance(dt, bool) or not isinstance(dt, Real)
                           or not math.isfinite(dt) or dt <= 0):
        raise ValueError(f"dt={dt!r} must be a finite number > 0 (the sampling time, s) or True")
    in_names = _names(inputs, [inp.name for inp in fls.inputs], "inputs")
    out_names = _names(outputs, list(fls.output_names), "outputs")
    n_out = fls.n_outputs

    def output(t: float, x: Any, u: Any, params: Any) -> NDArray[np.float64]:
        values = np.asarray(u, dtype=np.float64).reshape(-1)
        if n_out == 1:
            return np.array([float(fls(*(float(v) for v in values)))])
        return np.asarray(fls.evaluate(values), dtype=np.float64).reshape(n_out)

    if name is None:  # python-control refuses '.' in system names
        name = (fls.name or "fls").replace(".", "_")
    elif not isinstance(name, str) or not name or "." in name:
        raise ValueError(f"name={name!r} must be a non-empty string without '.' (python-control "
                         "uses '.' to address subsystems)")
    return ct.nlsys(None, output, inputs=in_names, outputs=out_names, dt=dt, name=name)


def _names(given: list[str] | None, default: list[str], what: str) -> list[str]:
    if given is None:
        return list(default)
    names = list(given) if isinstance(given, list | tuple) else None
    if (names is None or len(names) != len(default)
            or not all(isinstance(s, str) and s for s in names) or len(set(names)) != len(names)):
        raise ValueError(f"{what}={given!r} must be {len(default)} distinct non-empty names")
    return names
