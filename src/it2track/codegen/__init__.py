"""Generated C for microcontrollers: a fuzzy controller as self-contained C99.

:func:`generate_c` turns an :class:`~it2track.fuzzy.IT2Sugeno` or
:class:`~it2track.fuzzy.T1Sugeno` into a header and a source file (:class:`CCode`);
:func:`write_c` writes them. The generated code has no heap, no recursion, no static state,
``const`` tables (in flash on the AVR), and one entry point::

    int <prefix>_eval(const <prefix>_real in[N_IN], <prefix>_real *u, <prefix>_real *yl,
                      <prefix>_real *yr);

returning ``<PREFIX>_OK`` (0) or an error status (NaN/inf input, zero firing without a
configured ``on_zero_firing``, non-convergence of an iterative reducer within its fixed bound,
zero lower firing for the Wu-Mendel bounds); on an error the outputs are 0. Inputs are clipped
to their universes; the zero-firing value and every type reducer behave as in Python.
``<prefix>_real`` is ``double``, ``float`` or, for the integer-only fixed-point build
(``RealType.Q15``), ``int16_t`` in the Q formats the header defines and
:class:`FixedFormat` (``CCode.fixed``) converts to and from.

Submodules: :mod:`.generate` (the float generator), :mod:`.fixedpoint` (the fixed-point
scaling and integer tables), :mod:`.lowering` (what both share), :mod:`.host` (compile with the
system C compiler and call through ctypes), :mod:`.controller` (a heading controller backed by
the compiled C), :mod:`.errorbound` (the float and fixed-point builds' error bounds),
:mod:`.mcu` (cross-compile, run on the simulated ATmega328P, measure sizes), :mod:`.costs`
(the cost table of every reducer and arithmetic).
"""

from .controller import CHeadingController
from .fixedpoint import FixedFormat
from .generate import (
    SUPPORTED_FEATURES,
    CCode,
    RealType,
    check_prefix,
    check_supported,
    generate_c,
)
from .write import write_c

__all__ = [
    "SUPPORTED_FEATURES",
    "CCode",
    "CHeadingController",
    "FixedFormat",
    "RealType",
    "check_prefix",
    "check_supported",
    "generate_c",
    "write_c",
]
