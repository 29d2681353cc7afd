"""Where it2track's output differs from a file's reference, which is right and why.

Every file the harness finds differing must have a note here, and every note must belong to a
file that differs (the conformance test checks both). Each note names the evidence; the
claims about pyfuzzylite are re-checked by ``test_conformance.py`` where pyfuzzylite is
installed.
"""

from __future__ import annotations

_SUM = (
    "The file's AggMethod='sum' is MATLAB's and Octave's sum of the implied output sets; "
    "fuzzylite's .fll of it says `aggregation: AlgebraicSum` (probabilistic OR), how "
    "fuzzylite's importer read 'sum' when it wrote the file. it2track follows MATLAB and "
    "Octave; with UnboundedSum instead, pyfuzzylite agrees with it2track to 1e-15. "
    "The reference is wrong."
)
_JUGGLER = (
    "fuzzylite's .fll of MATLAB's juggler.fis names all nine output terms out1mf, so every "
    "rule names one term (pyfuzzylite 8 binds the last, as it2track reads the .fll, with a "
    "warning; fuzzylite 6 bound the first). MATLAB's rules index the nine planes; it2track "
    "reads the .fis so, and with the terms renamed apart pyfuzzylite agrees with it to 1e-16. "
    "The reference is wrong."
)
_ROBOT = (
    "jFuzzyLogic steps along the output range by repeated addition, so its last grid point "
    "is 1.0000000000000007, just beyond the range end 1, where the right shoulder "
    "TRIAN 0.75 1 1 is 0 for it (and 1 at 1, for it2track's linspace grid). The two "
    "aggregated sets differ at that one point; elsewhere they agree. it2track samples the "
    "range end itself, as the term and the range say."
)

NOTES: dict[str, str] = {
    "fuzzylite/examples/original/mamdani/octave/mamdani_tip_calculator.fis": _SUM,
    "fuzzylite/examples/original/takagi-sugeno/matlab/juggler.fis": _JUGGLER,
    "fuzzylite/examples/takagi-sugeno/matlab/juggler.fis": _JUGGLER,
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
