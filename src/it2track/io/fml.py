"""IEEE 1855-2016 Fuzzy Markup Language (``.fml``; JFML names its files ``.xml``, read those
with ``loads(text, "fml")``), read and written::

    <fuzzySystem xmlns="http://www.ieee1855.org" name="tipper">
      <knowledgeBase>
        <fuzzyVariable name="food" domainleft="0.0" domainright="10.0" type="input">
          <fuzzyTerm name="rancid" complement="false">
            <triangularShape param1="0.0" param2="2.0" param3="5.5"/>
          </fuzzyTerm>
        </fuzzyVariable>
        <fuzzyVariable name="tip" domainleft="0.0" domainright="20.0" type="output"
                       accumulation="MAX" defuzzifier="COG" defaultValue="0.0">
          ...
        </fuzzyVariable>
      </knowledgeBase>
      <mamdaniRuleBase name="rulebase1" activationMethod="MIN" andMethod="MIN" orMethod="MAX">
        <rule name="rule1" connector="or" weight="1.0">
          <antecedent><clause><variable>food</variable><term>rancid</term></clause></antecedent>
          <consequent><then><clause><variable>tip</variable><term>cheap</term></clause></then>
          </consequent>
        </rule>
      </mamdaniRuleBase>
    </fuzzySystem>

What is read
------------
- XML with defusedxml's care (:mod:`._xml`): no document type declaration, so no entity is ever
  expanded and nothing is fetched; bounded depth and size (the file itself is at most 64 MiB).
- Variables: ``fuzzyVariable`` (``type`` input or output, ``domainleft``/``domainright``) and
  ``tskVariable`` (``combination="WA"``, the weighted average); ``defaultValue`` (0 when absent,
  as the schema says; ``NaN``: none) is ``on_zero_firing``.
- Shapes: ``triangularShape``, ``trapezoidShape``, ``rightLinearShape``/``leftLinearShape``
  (:class:`~it2track.fuzzy.Ramp`), ``gaussianShape``, ``leftGaussianShape``/``rightGaussianShape``
  (1 below / above the mean: a :class:`~it2track.fuzzy.GaussianProduct` flat to the end of the
  domain), ``piShape``, ``sShape``, ``zShape``, ``rectangularShape``; ``complement="true"`` on an
  input term negates the clauses that name it. Triangles and trapezoids are 0 beyond their feet
  in IEEE 1855, so a shoulder inside the domain is refused as in the other formats.
- ``tskTerm``: ``order="0"`` one ``tskValue``; ``order="1"`` the constant, then one coefficient
  per input, as JFML (the standard's reference implementation) reads it (FuzzyLogic.jl reads the
  constant last).
- Rule bases ``mamdaniRuleBase`` and ``tskRuleBase`` (both: a
  :class:`~it2track.fuzzy.HybridSystem`), their ``andMethod``, ``orMethod`` and
  ``activationMethod`` (``MIN``, ``PROD``, ``BDIF``/``BSUM``, ``DRP``/``DRS``, ``EPROD``,
  ``HPROD``, ``NILMIN``; ``MAX``, ``PROBOR``, ``BSUM``, ``DRS``, ``ESUM``, ``HSUM``, ``NILMAX``),
  the outputs' ``accumulation`` and ``defuzzifier`` (``COG``, ``COA``, ``MOM``, ``LM``, ``RM``;
  Mamdani outputs sampled at MATLAB's 101 points: FML carries no resolution). Rules:
  ``connector`` and/or, ``weight``; a rule's own ``andMethod``/``orMethod`` must be its rule
  base's. Refused with the line: modifiers (hedges), ``else`` parts, other shapes, Tsukamoto and
  AnYa rule bases.

What is written
---------------
The same, every number with ``repr`` precision: a file read back evaluates bit for bit like the
system written. Type-1 Mamdani and Sugeno systems (and hybrids of them); names must be XML
names; ``on_zero_firing=None`` is written ``defaultValue="NaN"``. Refused: type-2 and Tsukamoto
systems, NOT in a rule (IEEE 1855 complements terms, not propositions), heights, MFs without an
IEEE 1855 shape, a Mamdani sampling other than 101 points with both ends.
"""

from __future__ import annotations

from ..fuzzy import AnySystem
from ._fmlread import build
from ._fmlwrite import dumps

__all__ = ["dumps", "loads"]


def loads(text: str, path: str = "<string>") -> AnySystem:
    """Parse IEEE 1855 FML text into a system (see the module docstring).

    Parameters
    ----------
    text : str
        The document.
    path : str
        Named in error messages.

    Raises
    ------
    FisFormatError
        For malformed or hostile XML and anything it2track cannot evaluate as the standard
        says, naming ``path``, the line and the problem.
    """
    return build(text, path)
