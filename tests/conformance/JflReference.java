// Evaluates an FCL file with jFuzzyLogic for the conformance references (see
// make_jfl_references.py, which compiles and runs it against jFuzzyLogic's own classes).
//
//   java JflReference FILE POINTS < inputs
//
// Prints "inputs NAME LO HI ..." and "outputs NAME LO HI ..." (sorted by name, universes as
// jFuzzyLogic estimates them), then, for every line of input values read in that order, the
// outputs. A continuous defuzzifier samples POINTS points over its universe, both ends included
// (it2track's grid); every evaluation starts from no output (NaN, or the DEFAULT), so the
// reference is stateless.
//
//   java JflReference FILE terms < queries
//
// The term mode, for files whose function blocks have no output with terms (jFuzzyLogic's
// membership-function files): prints "block NAME", then "input NAME LO HI TERM ..." for each of
// the block's variables with terms (sorted by name, the universe as jFuzzyLogic estimates it,
// the terms sorted by name), every block of the file sorted by name; then, for every query line
// "BLOCK VARIABLE X", the variable's value set to X and each of its terms' memberships in that
// order (Variable.getMembership, as jFuzzyLogic's own TestCaseJfuzzy reads them).

import java.io.BufferedReader;
import java.io.InputStreamReader;
import java.util.ArrayList;
import java.util.Iterator;
import java.util.List;
import java.util.TreeMap;

import net.sourceforge.jFuzzyLogic.FIS;
import net.sourceforge.jFuzzyLogic.FunctionBlock;
import net.sourceforge.jFuzzyLogic.defuzzifier.Defuzzifier;
import net.sourceforge.jFuzzyLogic.defuzzifier.DefuzzifierContinuous;
import net.sourceforge.jFuzzyLogic.rule.LinguisticTerm;
import net.sourceforge.jFuzzyLogic.rule.Variable;

public class JflReference {
    public static void main(String[] args) throws Exception {
        FIS fis = FIS.load(args[0], false);
        if (fis == null) {
            System.out.println("error: jFuzzyLogic cannot load the file");
            System.exit(2);
        }
        if (args[1].equals("terms")) {
            terms(fis);
            return;
        }
        FunctionBlock fb = fis.getFunctionBlock(null);
        int points = Integer.parseInt(args[1]);
        List<Variable> inputs = new ArrayList<>();
        List<Variable> outputs = new ArrayList<>();
        for (Variable v : fb.variablesSorted()) {
            v.estimateUniverse();
            (v.isOutput() ? outputs : inputs).add(v);
        }
        StringBuilder head = new StringBuilder("inputs");
        for (Variable v : inputs) {
            head.append(' ').append(v.getName()).append(' ').append(v.getUniverseMin())
                .append(' ').append(v.getUniverseMax());
        }
        head.append("\noutputs");
        for (Variable v : outputs) {
            head.append(' ').append(v.getName()).append(' ').append(v.getUniverseMin())
                .append(' ').append(v.getUniverseMax());
            Defuzzifier d = v.getDefuzzifier();
            if (d instanceof DefuzzifierContinuous) {
                DefuzzifierContinuous c = (DefuzzifierContinuous) d;
                double lo = v.getUniverseMin();
                double hi = v.getUniverseMax();
                c.setMin(lo);
                c.setMax(hi);
                c.setStepSize((hi - lo) / (points - 1));
                c.setValues(new double[points]);
            }
        }
        System.out.println(head);
        BufferedReader in = new BufferedReader(new InputStreamReader(System.in));
        String line;
        while ((line = in.readLine()) != null) {
            String[] values = line.trim().split("\\s+");
            for (int i = 0; i < inputs.size(); i++) {
                fb.setVariable(inputs.get(i).getName(), Double.parseDouble(values[i]));
            }
            for (Variable v : outputs) v.setValue(Double.NaN);
            fb.evaluate();
            StringBuilder out = new StringBuilder();
            for (Variable v : outputs) {
                if (out.length() > 0) out.append(' ');
                out.append(v.getValue());
            }
            System.out.println(out);
        }
    }

    static void terms(FIS fis) throws Exception {
        TreeMap<String, FunctionBlock> blocks = new TreeMap<>();
        for (Iterator<FunctionBlock> it = fis.iterator(); it.hasNext();) {
            FunctionBlock fb = it.next();
            blocks.put(fb.getName(), fb);
        }
        StringBuilder head = new StringBuilder();
        for (FunctionBlock fb : blocks.values()) {
            head.append("block ").append(fb.getName()).append('\n');
            for (Variable v : fb.variablesSorted()) {
                if (v.getLinguisticTerms().isEmpty()) continue;
                if (v.isOutput()) {
                    System.out.println("error: an output with terms: not a term library");
                    System.exit(3);
                }
                v.estimateUniverse();
                head.append("input ").append(v.getName()).append(' ').append(v.getUniverseMin())
                    .append(' ').append(v.getUniverseMax());
                for (LinguisticTerm t : v.linguisticTermsSorted()) {
                    head.append(' ').append(t.getTermName());
                }
                head.append('\n');
            }
        }
        System.out.print(head);
        BufferedReader in = new BufferedReader(new InputStreamReader(System.in));
        String line;
        while ((line = in.readLine()) != null) {
            String[] q = line.trim().split("\\s+");
            FunctionBlock fb = blocks.get(q[0]);
            Variable v = fb.getVariable(q[1]);
            v.setValue(Double.parseDouble(q[2]));
            StringBuilder out = new StringBuilder();
            for (LinguisticTerm t : v.linguisticTermsSorted()) {
                if (out.length() > 0) out.append(' ');
                out.append(v.getMembership(t.getTermName()));
            }
            System.out.println(out);
        }
    }
}
