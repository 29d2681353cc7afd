"""A formula consequent that reads other outputs (fuzzylite's chained ``Function``), as the
``.fll``, ``.fis`` and FCL readers read it: see :mod:`it2track.fuzzy.chain`. (jFuzzyLogic's
``FUNCTION`` reading an output is refused: its order of defuzzifying is not fuzzylite's.)

fuzzylite defuzzifies the outputs in the order they are declared, and a ``Function`` reads each
variable's value at that moment: an output declared before the formula's is this evaluation's
value; its own, or one declared after, is the *previous* evaluation's (NaN after a restart),
which makes the output depend on the order of evaluation. The first is read (the formula's names
are the inputs, then the outputs declared before its own); the second is refused, the message
naming the output.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..fuzzy.formula import Formula, FormulaError

__all__ = ["ChainRefused", "chained_formula"]


class ChainRefused(ValueError):
    """A formula reads its own output or one declared after it; ``token`` is that output."""

    def __init__(self, message: str, token: str, position: int) -> None:
        self.token = token
        self.position = position
        super().__init__(message)


def chained_formula(text: str, dialect: str, inputs: Sequence[str], outputs: Sequence[str],
                    own: str | None) -> Formula:
    """``text`` over the ``inputs``, or, where it reads outputs declared before ``own`` (in
    ``outputs``' order), over the inputs and those outputs. Raises :class:`FormulaError`
    (any output an unknown name where ``own`` is None), or :class:`ChainRefused` for a read of
    ``own`` or a later output."""
    inputs = tuple(inputs)
    try:
        return Formula(text, dialect, inputs)
    except FormulaError as exc:
        error = exc
    outputs = tuple(outputs)
    fuzzylite = dialect == "fuzzylite"
    before = outputs[:outputs.index(own)] if own in outputs and fuzzylite else ()
    if error.token in before:
        try:
            return Formula(text, dialect, inputs + before)
        except FormulaError as exc:
            error = exc
    if error.token not in outputs or own is None:  # own None: not an output's term
        raise error
    if not fuzzylite:
        raise ChainRefused(f"reads the output {error.token!r}: it2track reads a jFuzzyLogic "
                           "FUNCTION of the inputs only (fuzzylite's chained Function, in its "
                           "own grammar, reads the outputs declared before its own)",
                           error.token, error.position)
    if error.token == own:
        why = (f"reads its own output {error.token!r} (fuzzylite's value of the previous "
               "evaluation, NaN after a restart)")
    else:
        why = (f"reads the output {error.token!r}, which fuzzylite defuzzifies after "
               f"{own!r} (its value of the previous evaluation, NaN after a restart)")
    raise ChainRefused(f"{why}: it2track reads only the outputs declared before this one "
                       f"({', '.join(map(repr, before)) or 'none'})", error.token,
                       error.position)
