"""Fuzzy Control Language (FCL) files as IEC 61131-7, jFuzzyLogic and fuzzylite write them,
read (type-1 systems)::

    FUNCTION_BLOCK tipper
    VAR_INPUT
        service : REAL;
    END_VAR
    VAR_OUTPUT
        tip : REAL;
    END_VAR
    FUZZIFY service
        TERM poor := (0, 1) (4, 0);
        TERM good := TRIAN 1 4 9;
        RANGE := (0 .. 10);
    END_FUZZIFY
    DEFUZZIFY tip
        TERM cheap := (0, 0) (5, 1) (10, 0);
        METHOD : COG;
        DEFAULT := 0;
        RANGE := (0 .. 30);
    END_DEFUZZIFY
    RULEBLOCK No1
        AND : MIN;
        ACT : MIN;
        ACCU : MAX;
        RULE 1 : IF service IS poor OR NOT (food IS rancid) THEN tip IS cheap WITH 0.5;
    END_RULEBLOCK
    END_FUNCTION_BLOCK

What is read
------------
- Comments ``(* ... *)``, ``/* ... */`` (both may span lines) and ``// ...``; keywords in
  any case. Several ``FUNCTION_BLOCK``\\ s: ``block=`` names one; without it the first is read
  with a :class:`~it2track.io.FisFormatWarning` naming the others (jFuzzyLogic asks for a
  name).
- Terms: point lists ``(x, mu) ...`` (the standard: linear between the points, the first and
  last degree beyond them -- triangles, trapezoids and shoulders become
  :class:`~it2track.fuzzy.Triangle`/:class:`~it2track.fuzzy.Trapezoid`, other polylines a
  :class:`~it2track.fuzzy.Discrete`); jFuzzyLogic's named shapes ``TRIAN a b c``,
  ``TRAPE a b c d``, ``GAUSS mean sigma``, ``GAUSS2 m1 s1 m2 s2`` (``m1 <= m2``),
  ``GBELL a b mean``, ``SIGM gain center``, ``DSIGM`` (equal gains, a plateau: jFuzzyLogic's
  ``max(s1 - s2, 0)`` is then MATLAB's ``dsigmf``), ``COSINE half_width center``; fuzzylite's
  term names (``Triangle``, ``Bell``, ..., with its parameter order); output singletons
  ``TERM t := value`` (an input singleton is a :class:`~it2track.fuzzy.Point`:
  jFuzzyLogic's 1 at the value, 0 elsewhere), fuzzylite's ``Constant``/``Linear``, and jFuzzyLogic's
  ``FUNCTION``: linear in the inputs (``(a * 0.6) + 1.2``) a ``Linear``, else a formula of
  the inputs parsed (never run as code) by :mod:`it2track.fuzzy.formula` in jFuzzyLogic's
  grammar (``SIN``, ``EXP``, ``^``, ...); fuzzylite's ``Function`` (so spelt) in fuzzylite's.
  jFuzzyLogic's parameters given by variables (``GAUSS meanGood stdGood``, ``(lo, 0)
  (mid, 1)``) are read on input terms, point lists and ``GAUSS``: each evaluation takes the
  inputs' values there (a :class:`~it2track.fuzzy.Parametric` term; an input read so needs
  no FUZZIFY block; see :mod:`._fclvars`); on output terms they are refused.
- ``RANGE := (lo .. hi)`` in a FUZZIFY/DEFUZZIFY block or after a VAR_INPUT declaration
  (jFuzzyLogic) gives the universe; without it, jFuzzyLogic's estimate from the terms (the
  points' span, triangle and trapezoid feet, ``mean +- 4 sigma``, a bell's 0.001 level,
  ``center +- 9 / |gain|``, a cosine's support).
- ``METHOD``: ``COG`` (centroid), ``COA`` (bisector), ``LM``/``RM``/``MM`` (leftmost /
  rightmost / mean of maxima) give a :class:`~it2track.fuzzy.T1Mamdani` (101 points);
  ``COGS`` (singletons, fuzzylite's constant and linear terms), ``COGF`` (jFuzzyLogic's
  functions) and fuzzylite's ``COGSS`` (weighted sum) a :class:`~it2track.fuzzy.T1Sugeno`.
  ``DEFAULT := v`` is ``on_zero_firing`` (``nan``: none; jFuzzyLogic's lenient
  ``DEFAULT = v`` without ``;`` is read as it reads it, with a warning); ``NC`` ("no change":
  keep the last output), alone or as fuzzylite writes it (``DEFAULT := nan | NC``), is the
  system's ``lock_previous``, which ``evaluate_sequence`` follows (``__call__`` is stateless).
- Operators by the standard's, jFuzzyLogic's and fuzzylite's names: ``AND`` ``MIN``,
  ``PROD``, ``BDIF``, ``DPROD``, ``EPROD``/``EINSTEIN``, ``HPROD``/``HAMACHER``,
  ``NMIN``/``NIPMIN``; ``OR`` ``MAX``, ``ASUM``, ``BSUM``, ``DSUM``, ``ESUM``, ``HSUM``,
  ``NMAX``/``NIPMAX``, ``SUM``; an ``AND`` alone implies its De Morgan partner and the other
  way round, as the standard pairs them; ``ACT`` any t-norm; ``ACCU`` (in the RULEBLOCK or,
  as jFuzzyLogic and fuzzylite write it, the DEFUZZIFY block) any s-norm, and ``NSUM``
  (the standard's normalised sum: the centroid, bisector and maxima of the plain sum;
  jFuzzyLogic and fuzzylite fold it pairwise, ``(a + b) / max(1, a + b)``, which differs once
  the sum passes 1). Without ``ACCU`` the sum, jFuzzyLogic's default (fuzzylite's "none").
  Several rule blocks are merged when their operators agree; outputs of different kinds
  (Mamdani, singletons, Tsukamoto's monotonic terms) make a
  :class:`~it2track.fuzzy.HybridSystem`.
- Rules ``RULE n : IF cond THEN y IS t [, z IS u] [WITH w] [;]`` (fuzzylite ends them at the
  line, in lower case) with ``AND``, ``OR``, ``NOT``, ``IS NOT`` and parentheses, reduced as
  :mod:`._ruletree` explains. With ``COGS`` and ``ACCU : MAX`` the standard takes, for each
  singleton, the *largest* activation of the rules concluding it; that equals the per-rule
  weighted average of a Sugeno system only when no two rules share a singleton, so a shared
  one is refused.

Errors raise :class:`~it2track.io.FisFormatError` with ``file:line``. Writing FCL is not
supported.

A file's input variables and their terms alone: :func:`loads_terms` (``it2track.io.load_terms``),
also for a function block with no outputs or rules, as jFuzzyLogic's membership-function
files are.
"""

from __future__ import annotations

import warnings

from ..fuzzy import AnySystem, Input
from ._fclparse import FunctionBlock, Parser
from ._fclsystem import build, input_terms
from .errors import FisFormatError, FisFormatWarning

__all__ = ["loads", "loads_terms"]


def loads(text: str, path: str = "<string>", *, block: str | None = None) -> AnySystem:
    """Parse FCL text into a :class:`~it2track.fuzzy.T1Mamdani` or
    :class:`~it2track.fuzzy.T1Sugeno` (see the module docstring).

    Parameters
    ----------
    text : str
        The file content.
    path : str
        Named in error messages.
    block : str or None
        The ``FUNCTION_BLOCK`` to read; ``None``: the first.

    Raises
    ------
    FisFormatError
        On anything malformed or unsupported, naming ``path``, the line and the problem.

    Warns
    -----
    FisFormatWarning
        When the file has several function blocks and ``block`` is ``None``, a term defined
        twice, or ``DEFAULT = v`` (jFuzzyLogic's lenient form).
    """
    parser = Parser(text, path)
    return build(parser, _chosen(parser, path, block))


def loads_terms(text: str, path: str = "<string>", *, block: str | None = None
                ) -> dict[str, Input]:
    """The input variables of FCL text and their terms, by name in the declared order: each
    an :class:`~it2track.fuzzy.Input` whose sets are its terms, read as :func:`loads` reads
    them (universes, named shapes, terms given by variables), for a function block with or
    without outputs and rules (jFuzzyLogic's membership-function files declare inputs only).
    The outputs and rules are not read.

    Raises
    ------
    FisFormatError
        As :func:`loads`, for the function block's inputs and their terms (naming ``path``,
        the line and the term); for a block without ``VAR_INPUT``.
    """
    parser = Parser(text, path)
    return input_terms(parser, _chosen(parser, path, block))


def _chosen(parser: Parser, path: str, block: str | None) -> FunctionBlock:
    """The function block ``block`` names (``None``: the first, warning when there are
    several)."""
    blocks = parser.function_blocks()
    for warning in parser.warnings:  # attributed to the caller, as the one below
        warnings.warn(warning, stacklevel=3)
    names = [fb.name for fb in blocks]
    if block is not None:
        if block not in names:
            raise FisFormatError(path, None, f"no FUNCTION_BLOCK {block!r} (the file has "
                                 f"{', '.join(repr(n) for n in names)})")
        return blocks[names.index(block)]
    chosen = blocks[0]
    if len(blocks) > 1:
        warnings.warn(FisFormatWarning(
            path, chosen.line, f"{len(blocks)} FUNCTION_BLOCKs ({', '.join(map(repr, names))})"
            f"; read the first, {chosen.name!r} (block= selects another)"), stacklevel=3)
    return chosen
