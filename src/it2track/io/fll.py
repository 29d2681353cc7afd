"""fuzzylite's FuzzyLite Language (``.fll``), read and written::

    Engine: tipper
    InputVariable: service
      enabled: true
      range: 0.000 10.000
      lock-range: false
      term: poor Gaussian 0.000 1.500
      term: good Gaussian 5.000 1.500
    OutputVariable: tip
      enabled: true
      range: 0.000 30.000
      lock-range: false
      aggregation: Maximum
      defuzzifier: Centroid 100
      default: nan
      lock-previous: false
      term: cheap Triangle 0.000 5.000 10.000
      term: generous Triangle 20.000 25.000 30.000
    RuleBlock: mamdani
      enabled: true
      conjunction: Minimum
      disjunction: Maximum
      implication: Minimum
      activation: General
      rule: if service is poor then tip is cheap
      rule: if service is good and food is not rancid then tip is generous with 0.5

What is read
------------
- ``#`` starts a comment; keys and section names as fuzzylite 6 to 8 write them.
- Terms: every membership term of :data:`~it2track.fuzzy.terms.FUZZYLITE_TERMS` (parameters
  in fuzzylite's order, optional trailing height); Takagi-Sugeno outputs' ``Constant`` and
  ``Linear`` terms; ``Function`` terms, fuzzylite's formulas, parsed (never run as code) by
  :mod:`it2track.fuzzy.formula`: of ``x`` as a membership function (a Mamdani output's is
  read floored at 0, fuzzylite's aggregated set under Maximum aggregation with a Minimum or
  AlgebraicProduct implication, and refused under others), of the inputs as a Takagi-Sugeno
  consequent, and of the outputs declared before its own (fuzzylite's chained Function, as
  ``Engine.process`` defuzzifies them in order: :mod:`it2track.fuzzy.chain`); one reading its
  own output or a later one (fuzzylite's value of the previous evaluation) is refused.
- Operators: conjunction / disjunction, implication and aggregation by fuzzylite's class
  names (``AlgebraicProduct``, ``EinsteinSum``, ...; ``none`` where no rule needs one);
  ``activation: General`` (the others select or scale rules and are refused).
- ``defuzzifier``: ``Centroid``, ``Bisector``, ``MeanOfMaximum``, ``SmallestOfMaximum``,
  ``LargestOfMaximum`` give a :class:`~it2track.fuzzy.T1Mamdani`; ``WeightedAverage`` and
  ``WeightedSum`` a :class:`~it2track.fuzzy.T1Sugeno`. fuzzylite integrates ``Centroid N`` by
  the midpoint rule over ``N`` cells (default 1000 since fuzzylite 8); it2track samples
  ``N + 1`` points including both ends of the range (MATLAB's rule), so
  ``resolution = N + 1``: the same number of intervals, nodes at their ends.
- ``default: nan`` (no output where no rule fires: :class:`~it2track.fuzzy.ZeroFiringError`)
  or a number (``on_zero_firing``).
- Rules: ``if ... then y is t [and z is u] [with w]`` with ``and``, ``or``, ``not``
  (``x is not t``) and parentheses, reduced as :mod:`._ruletree` explains (nested conditions
  and chained outputs as :mod:`._chain` explains); hedges as :mod:`it2track.fuzzy.hedges`.
  Several rule blocks are merged when their operators agree.
- fuzzylite clips nothing unless ``lock-range: true``; it2track always clips inputs to their
  range (MATLAB's rule), so the two differ only outside it. ``lock-range: true`` on an output
  is read where it changes nothing (a Mamdani output, constant consequents inside the range).
  ``lock-previous: true`` (the previous output where no rule fires) is the system's
  ``lock_previous``, which ``evaluate_sequence`` follows (``__call__`` is stateless: it gives
  what fuzzylite's first evaluation after a restart gives). Disabled variables are refused,
  and so is a Takagi-Sugeno output whose ``aggregation`` (fuzzylite 8 aggregates the
  activations of one term with it) is not a sum while rules share a term.

What is written
---------------
Type-1 systems (fuzzylite has no type-2), every float with ``repr`` precision so that a file
read back evaluates bit for bit like the system written; Sugeno consequents become named
``Constant``/``Linear`` terms (``c1``, ``c2``, ...) in order of first use. Names must be single
words (fuzzylite's identifiers); a system's ``on_zero_firing`` is each output's ``default``,
its ``lock_previous`` each output's ``lock-previous``.
"""

from __future__ import annotations

from ..fuzzy import AnySystem
from ._fllbuild import build
from ._flldoc import Document
from ._fllwrite import dumps

__all__ = ["dumps", "loads"]

def loads(text: str, path: str = "<string>") -> AnySystem:
    """Parse ``.fll`` text into a :class:`~it2track.fuzzy.T1Mamdani` or
    :class:`~it2track.fuzzy.T1Sugeno` (see the module docstring).

    Parameters
    ----------
    text : str
        The file content.
    path : str
        Named in error messages.

    Raises
    ------
    FisFormatError
        On anything malformed or that it2track cannot evaluate as fuzzylite does, naming
        ``path``, the line and the problem.
    """
    return build(Document(text, path))
