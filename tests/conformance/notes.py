"""Where it2track's output differs from a file's reference, which is right and why.

Every file the harness finds differing must have a note here, and every note must belong to a
file that differs (the conformance test checks both). A file compared with a corrected
reference has its note in :data:`CORRECTIONS` instead: the original reference's defect and
the correction. Every refused file's reason matches one
of :data:`REFUSALS`, which says why it stays refused. Each note names the evidence; the
claims about pyfuzzylite are re-checked by ``test_conformance.py`` where pyfuzzylite is
installed.
"""

from __future__ import annotations

_SUM = (
    "The file's AggMethod='sum' is MATLAB's and Octave's sum of the implied output sets; "
    "fuzzylite's .fll of it, the original reference, says `aggregation: AlgebraicSum` "
    "(probabilistic OR), how fuzzylite's importer read 'sum' when it wrote the file. The "
    "corrected reference is pyfuzzylite with UnboundedSum (the sum) in its place."
)
_JUGGLER = (
    "fuzzylite's .fll of MATLAB's juggler.fis, the original reference, names all nine output "
    "terms out1mf, so every rule names one term (pyfuzzylite 8 binds the last, as it2track "
    "reads the .fll, with a warning; fuzzylite 6 bound the first). The .fis's rules index "
    "the terms: the corrected reference is pyfuzzylite with the terms renamed apart "
    "(out1mf1..out1mf9) and each rule naming the term its .fis rule indexes (MATLAB's "
    "original: rule k the k-th plane; fuzzylite 6's export of it: the first for every rule, "
    "as fuzzylite 6 bound them)."
)
_OCTAVE_HEDGES = (
    "Octave writes a hedge as a rule index's fraction and means a power (fuzzy-logic-toolkit's "
    "get_mf_index_and_hedge, evalmf, eval_rules_sugeno): 2.3 is set 2 to the power 3 on an "
    "antecedent and the rule's firing to the power 1/3 on a Sugeno conclusion, each "
    "conclusion on its own. fuzzylite read .3 as its own 'extremely' (2 mu^2 below 1/2) when "
    "it wrote the .fll, the original reference, and hands a hedged conclusion's degree on to "
    "the next. The corrected reference is pyfuzzylite given Octave's powers (and one rule per "
    "conclusion)."
)
_ROBOT = (
    "jFuzzyLogic steps along the output range by repeated addition, so its last grid point "
    "is 1.0000000000000007, just beyond the range end 1, where the right shoulder "
    "TRIAN 0.75 1 1 is 0 for it (and 1 at 1, for it2track's linspace grid). The two "
    "aggregated sets differ at that one point; elsewhere they agree. it2track samples the "
    "range end itself, as the term and the range say."
)

_OCTAVE_CENTROID = (
    "fuzzylite's .fll of this example is of the toolkit's 2012 file (AndMethod 'prod', "
    "AggMethod 'sum'), not of this one ('min', 'max'), so the reference is the publisher's "
    "engine: Octave's evalfis with the toolkit at the commit the file was copied from, at its "
    "default 101 points (tests/conformance/make_octave_references.py). The toolkit's version "
    "matters for this file. From 0.6.2 (May 2025; the file says 2011-2025) "
    "DefuzzMethod='centroid' is defuzz.m's weighted average of the 101 points (wtaver: "
    "MATLAB's centroid, it2track's). Up to 0.6.1 (September 2024), Debian's 0.4.6 "
    "included, it was trapz(x, x.*y) / trapz(x, y), the trapezoid rule, which weights the "
    "two end points by half (0.6.2 keeps it as 'centroid_integral'); this file's Gaussian "
    "output sets are not 0 at the range ends, so with 0.4.6 the reference would move by "
    "{older} of the range (it2track's aggregated set defuzzified so; "
    "make_octave_references.py --installed --check measures the same with Debian's toolkit). "
    "The file is 0.6.2's, and agrees with 0.6.2."
)

#: the files whose reference is the publisher's own engine (no independent twin): where the
#: reference comes from and what a reader re-running it should know; ``{older}`` is filled in
#: by ``make_table.py`` (the difference of the toolkit's older centroid)
PUBLISHER: dict[str, str] = {
    "octave/inst/mamdani_tip_calculator.fis": _OCTAVE_CENTROID,
}

_MATLAB_DEFAULT = (
    "fuzzylite 6 wrote this .fis without its Default/LockPrevious keys, so it2track reads "
    "MATLAB's meaning: an output with no value (outputFx where no NEAR_k fires, at 0 and 10; "
    "trueFx's sin(x)/x at 0) is the middle of its range, 0. The twin .fll, the original "
    "reference, says default: nan, so there it has none -- and neither has diffFx, "
    "Function fabs(outputFx-trueFx), which fuzzylite evaluates with the values committed "
    "before it (default applied). The corrected reference is pyfuzzylite with each output's "
    "default the middle of its range: diffFx then reads the 0 too."
)

#: the files compared with a corrected reference (``catalog.CORRECTED``): the original
#: reference's defect and what the correction changes (the table's header says it too)
CORRECTIONS: dict[str, str] = {
    "fuzzylite/examples/original/mamdani/octave/mamdani_tip_calculator.fis": _SUM,
    "fuzzylite/examples/original/takagi-sugeno/matlab/juggler.fis": _JUGGLER,
    "fuzzylite/examples/original/mamdani/octave/investment_portfolio.fis": _OCTAVE_HEDGES,
    "fuzzylite/examples/original/takagi-sugeno/octave/sugeno_tip_calculator.fis":
        _OCTAVE_HEDGES,
    "octave/inst/sugeno_tip_calculator.fis": _OCTAVE_HEDGES,
    "fuzzylite/examples/takagi-sugeno/matlab/juggler.fis": _JUGGLER,
    "fuzzylite/examples/takagi-sugeno/approximation.fis": _MATLAB_DEFAULT,
}

NOTES: dict[str, str] = {
    "fuzzylite/examples/original/takagi-sugeno/matlab/sltbu.fis": (
        "MATLAB's file gives its ranges as [-pi/4 pi/4]; fuzzylite's copy of it (sltbu_fl, "
        "the reference) rounds them to +-0.7853982, 3.7e-8 beyond pi/4. The reference grid's "
        "end points lie outside it2track's range and are clipped to it, so the linear "
        "consequents see inputs 3.7e-8 apart. Both are right for their ranges; the file's "
        "own, pi/4, is it2track's."
    ),
    "pyfuzzylite/fuzzylite/examples/mamdani/laundry.fll": (
        "MeanOfMaximum on a tie. At Load = Dirt = 3.75 the chained rule 'if Detergent is "
        "more_than_usual then Cycle is long' fires 0.725 (Dirt's Discrete 'high' interpolated "
        "to 0.7250000000000001 by both engines), and Cycle's 'long' (Discrete 10 0 20 1) is "
        "0.725 exactly at the midpoint 17.25, so in exact arithmetic 17.25 is in the plateau "
        "of maxima and the mean is the reference's 18.62. it2track evaluates 'long' as a ramp, "
        "(17.25 - 10) / 10 = 0.725 correctly rounded, one ulp below the firing, and starts "
        "the plateau one cell later: 18.63. The reference is right; the difference is one "
        "cell of the 1000-point grid, from rounding a discontinuous defuzzifier (the same "
        "file at resolution 500, fuzzylite/examples/mamdani/Laundry.fll, agrees)."
    ),
    "jfuzzylogic/fcl/robot.fcl": _ROBOT,
    "jfuzzylogic/fcl/robot_optimized.fcl": _ROBOT,
}


#: (a fragment of the refusal message, the cause, why it2track leaves it refused)
REFUSALS: list[tuple[str, str, str]] = [
    ("no VAR_OUTPUT", "not a fuzzy system: a function block without outputs",
     "jFuzzyLogic's membership-function unit tests (junit_gauss.fcl, ..., "
     "on_line_variable.fcl) and scarledOLD.fcl declare inputs only; jFuzzyLogic's tests read "
     "the terms' memberships directly. Nothing maps inputs to an output, so there is no "
     "system to evaluate or compare; those whose terms it2track reads (load_terms) agree "
     "as term libraries (above) and are not counted here. These stay refused: a term it2track "
     "does not read (a DSIGM with unequal gains, jFuzzyLogic's max(s1 - s2, 0), which no term "
     "of it2track is), the reason after 'its terms:'; or terms given by other inputs, which "
     "jFuzzyLogic gives no value until they are set, so its term table has none "
     "(on_line_variable.fcl's terms reproduce the memberships jFuzzyLogic records for it, "
     "on_line_variable_4/5/6.txt: tests/io/test_io_fcl_variables.py)."),
    ("has no DEFUZZIFY block", "not a fuzzy system: an output without terms",
     "The file declares an output it never defines (jFuzzyLogic fills it from a Java test). "
     "There is no output set or value to evaluate; its input terms agree as a term library "
     "(above)."),
    ("no TERM", "not a fuzzy system: no rules, no terms",
     "noRules.fcl has an output with no term and no rule, a parser test of jFuzzyLogic."),
    ("no rule has a consequent for output 1", "a first output no rule concludes",
     "An output no rule concludes is its default (jFuzzyLogic's DEFAULT, as arm.fcl's "
     "torque2 reads); it2track's system tables are built from the first output's rules, so "
     "a first output without rules is refused."),
    ("which fuzzylite defuzzifies after", "a formula reading a later output",
     "fuzzylite defuzzifies the outputs in the order they are declared; a Function reading "
     "an output declared after its own reads that output's value of the previous evaluation "
     "(NaN after a restart), so the output depends on the order of evaluation. it2track "
     "reads formulas of the inputs and of the outputs declared before (fuzzylite's chained "
     "Function, it2track.fuzzy.chain)."),
    ("reads its own output", "a formula reading a later output", ""),
    ("rule mentions no input", "a chained rule lost in a .fis export",
     "fuzzylite wrote the chained rules of Laundry/SimpleDimmerChained/SimpleDimmerInverse "
     "to .fis with antecedent index 0 (a .fis cannot name an output in a condition): the "
     ".fis rule says nothing about when it fires, so it cannot be read as its .fll/.fcl twin "
     "(which it2track reads and agrees with)."),
    ("an output term with values given by variables", "output terms given by variables",
     "membershipWithVariables.fcl's output terms have points given by its inputs (TERM "
     "middle := (low, 0) (mid, 1) (high, 0)). jFuzzyLogic reads such a value at each "
     "evaluation (Value.getValue), as it2track reads input terms so (cinthia.fcl's GAUSS "
     "meanGood stdGood, evaluated per sample: it agrees), but samples an output's terms on a "
     "defuzzification grid it fixes once, at the first evaluation whose values give the "
     "output a finite universe (Defuzzifier.reset calls init only while the grid is NaN, as "
     "it is at loading, the variables being NaN then): its outputs depend on the order of "
     "evaluations. it2track's output sets are fixed when the system is built. The file also "
     "has no rules, so jFuzzyLogic's output, its reference, is the DEFAULT 4 everywhere "
     "(jFuzzyLogic's own test of it checks only the universe it re-estimates); it2track "
     "refuses a file without rules."),
    ("a singleton is the value of a COGS output", "a singleton set in a centroid output",
     "junit1/junit2.fcl conclude singletons (TERM closed := 0) in an output without METHOD : "
     "COGS. jFuzzyLogic itself evaluates neither: a singleton is its discrete membership "
     "function and only a discrete defuzzifier takes one (RuleActivationMethod.imply throws "
     "'neither both discrete nor both continuous'), so there is no reference to agree with. "
     "it2track takes singletons as COGS values."),
    ("centroid_integral", "Octave's centroid_integral defuzzifier",
     "The toolkit's (0.6.2) trapz(x, x.*y) / trapz(x, y) over the same 101 points: the "
     "trapezoid rule, the two end points weighted by half, not MATLAB's centroid (the "
     "weighted average). MATLAB's format has no such method, and reading it as the centroid "
     "would be a different number, so load(path) refuses it; load(path, dialect='octave') "
     "reads it (Defuzzifier.CENTROID_INTEGRAL) and agrees with Octave's own evalfis (the "
     "Octave toolkit's files under each reading, above)."),
    ("feet and peak must satisfy", "a zero-width triangle",
     "junit_shashankrao.fcl's TRIAN 0 0 0 is 1 at 0 and 0 elsewhere (jFuzzyLogic's "
     "MembershipFunctionTriangular). On a centroid's grid it counts only at a grid point "
     "equal to 0: jFuzzyLogic's reference grid, -1 plus 0.002 added 500 times, reaches "
     "8.7e-16, not 0, so there the term never counts; on it2track's grid (linspace, which "
     "has 0) it would. Its weight is an accident of rounding, and it2track reads neither "
     "rounding into the file."),
]


def refusal_cause(detail: str) -> tuple[str, str] | None:
    """``(cause, why)`` of a refusal message, or None."""
    why_of = {cause: why for _, cause, why in REFUSALS if why}
    for fragment, cause, _ in REFUSALS:
        if fragment in detail:
            return cause, why_of[cause]
    return None


#: why the default (MATLAB's) reading of an Octave toolkit file differs from Octave's own
#: evalfis, by what ``make_table.octave_readings`` finds: ``{agg}`` is the file's AggMethod
OCTAVE_READINGS: dict[str, str] = {
    "merge": (
        "The toolkit merges the Sugeno rules that conclude the same value with the file's "
        "AggMethod ('{agg}'): aggregate_output_sugeno sorts the rules' (value, firing) "
        "pairs by value and folds equal neighbours with it, in rule order, before the "
        "weighted average over the distinct values. MATLAB, whose format a .fis is, counts "
        "every rule (fuzzylite's reading, the twin reference, agrees with MATLAB's); "
        "dialect='octave' reads AggMethod as T1Sugeno(aggregation=...), the same merge."
    ),
    "centroid_integral": (
        "DefuzzMethod='centroid_integral' is the toolkit's trapz(x, x.*y) / trapz(x, y) "
        "over the 101 points (defuzz.m): the trapezoid rule, the two end points weighted by "
        "half. MATLAB has no such method, so the default reading refuses it naming the "
        "line; dialect='octave' reads it as Defuzzifier.CENTROID_INTEGRAL."
    ),
    "same-mamdani": (
        "None here: a Mamdani system whose DefuzzMethod is the toolkit's 0.6.2 'centroid' "
        "(MATLAB's weighted average of the 101 points)."
    ),
    "same-sum": (
        "None here: AggMethod='sum', and merging equal conclusions by their sum is counting "
        "every rule, as MATLAB does."
    ),
    "same-apart": (
        "None here: the toolkit would merge with AggMethod ('{agg}'), but at no point of "
        "the table do two firing rules conclude the same value."
    ),
}
