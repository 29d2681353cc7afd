"""A fuzzy system lowered to arrays: the one representation every evaluator works from.

:class:`SystemTables` is built once per system. It deduplicates the membership functions the
rules use into *rows* (one per distinct MF of an input), encodes each row's shape as an
:class:`MFKind` with a fixed-size parameter vector, and lists for every rule the row of its
upper and lower MF for each input (row ``n_rows`` is the constant 1 of an input the rule does
not mention). The numpy evaluation of the rows here is the reference semantics; compiled
kernels and code generators read the same arrays and must refuse (or fall back on) what they do
not implement: a row of kind :attr:`MFKind.OTHER` (an arbitrary Python callable), or a rule
feature listed in :attr:`SystemTables.features`.

The firing of the rules (:meth:`SystemTables.firing_block`) is here too: it is the antecedent
machinery every kind of system shares (Sugeno, TSK, and Mamdani through
:class:`~it2track.fuzzy.mamdani.MamdaniTables`, which holds a ``SystemTables`` for its
antecedents).
"""

from __future__ import annotations

import math
import threading
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .conditions import Condition, Is, Join, Modified, Not
from .formula import Formula
from .hedges import Hedge, Hedged, apply_hedges
from .kinds import MFKind, Row
from .membership import (
    Gaussian,
    MembershipFunction,
    PiecewiseLinear,
    Term,
    UncertainMeanGaussianLower,
    UncertainMeanGaussianUpper,
)
from .norms import Connective, SNorm, TNorm
from .parametric import Parametric
from .rules import Input, Linear, Rule
from .sets import ScaledLagged

__all__ = ["FEATURES", "MFKind", "SystemTables"]

#: Every name :attr:`SystemTables.features` can hold (see the class docstring).
FEATURES = frozenset({"not", "or", "weights", "linear", "formula", "chain", "outputs",
                      "hedges", "tree", "idle"})

FloatArray = NDArray[np.float64]


#: t-norms whose identity 1 is exact (``T(f, 1) == f`` in floating point): the rows of inputs
#: a rule does not mention may take part in the fold as the constant 1.
EXACT_IDENTITY = frozenset({TNorm.PRODUCT, TNorm.MINIMUM})


def _encode(mf: MembershipFunction) -> Row:
    if isinstance(mf, Term):
        return mf.kernel_row()
    if isinstance(mf, PiecewiseLinear):
        pa, pb, pc, pd, ph = mf.as_trapezoid()
        return MFKind.TRAPEZOID, (
            -math.inf if pa == pb else pa,
            1.0 if pa == pb else pb - pa,
            math.inf if pc == pd else pd,
            1.0 if pc == pd else pd - pc,
            ph,
        )
    if type(mf) is Gaussian:
        return MFKind.GAUSSIAN, (float(mf.mean), float(mf.sigma), float(mf.h), 0.0, 0.0)
    if type(mf) is UncertainMeanGaussianUpper:
        return MFKind.UM_GAUSSIAN_UPPER, (float(mf.m1), float(mf.m2), float(mf.sigma),
                                         float(mf.h), 0.0)
    if type(mf) is UncertainMeanGaussianLower:
        return MFKind.UM_GAUSSIAN_LOWER, (float(mf.m1), float(mf.m2), float(mf.sigma),
                                         float(mf.h), 0.0)
    return MFKind.OTHER, (0.0, 0.0, 0.0, 0.0, 0.0)


def _parametric(mf: MembershipFunction) -> bool:
    """A term whose parameters are inputs (:mod:`.parametric`), hedged or not."""
    return isinstance(mf, Parametric) or (isinstance(mf, Hedged)
                                          and isinstance(mf.mf, Parametric))


def _parametric_block(mf: Any, x: FloatArray, i: int) -> FloatArray:
    if isinstance(mf, Hedged):
        inner: Parametric = mf.mf  # type: ignore[assignment]  # (_parametric)
        return apply_hedges(mf.hedges, inner.evaluate(x, i))
    result: FloatArray = mf.evaluate(x, i)
    return result


class SystemTables:
    """A Sugeno system's inputs and rules as arrays, built once (see the module docstring).

    Parameters
    ----------
    inputs : tuple of Input
    rules : tuple of Rule
        Zero-order (interval) or first-order (:class:`~it2track.fuzzy.rules.Linear`)
        consequents; one per output.
    snorm : SNorm
        The s-norm of OR rules (default max); recorded in :attr:`snorm`.

    Attributes
    ----------
    n_inputs, n_rules, n_rows : int
        Inputs, rules, and distinct membership rows M.
    lo, hi : ndarray, shape (n_inputs,)
        Universe of each input (inputs are clipped to it before evaluation).
    mf_kind : ndarray of int, shape (M,)
        :class:`MFKind` of each row.
    mf_params : ndarray, shape (M, 5)
        Parameters of each row (meaning per :class:`MFKind`).
    mf_input : ndarray of int, shape (M,)
        The input each row reads.
    mfs : tuple of MembershipFunction
        The membership function objects behind the rows.
    upper_rows, lower_rows : ndarray of int, shape (R, n_inputs)
        Row of the upper / lower MF of rule r on input i; ``M`` where the rule does not
        mention the input (membership 1). For a negated antecedent these are still the rows of
        the set's own upper / lower MF (see ``negated``).
    y_lo, y_hi : ndarray, shape (R,)
        Consequent interval of each rule, in rule order. For a first-order rule (feature
        ``"linear"``) the interval of its constant term ``c0``.
    perm : ndarray of int, shape (R,)
        Rules sorted by ``y_lo`` (stable): sorted position -> rule index. The ``*_s`` arrays
        (``upper_rows_s``, ``lower_rows_s``, ``y_lo_s``, ``y_hi_s``, ``negated_s``,
        ``is_or_s``, ``weight_s``, ``coef_lo_s``, ``coef_hi_s``) are in that order, and
        ``order_hi_s`` sorts ``y_hi_s`` (stable). (With ``"linear"`` the consequents depend on
        the input, so an evaluator must sort them per sample; ``perm`` then only fixes the
        order of the rows.)
    type1 : bool
        Every rule uses the same rows for upper and lower MFs.
    crisp : bool
        Every consequent has ``y_lo == y_hi`` (and, with ``"linear"``, ``coef_lo == coef_hi``).
    negated : ndarray of bool, shape (R, n_inputs)
        True where rule r reads ``x_i is not A``: its lower / upper membership is
        ``1 - m[upper_rows]`` / ``1 - m[lower_rows]`` (the bounds of an interval swap under
        complement). All False unless ``"not"`` is a feature.
    is_or : ndarray of bool, shape (R,)
        True for an OR rule that mentions two or more inputs: its firing is the s-norm
        :attr:`snorm` of its (possibly negated) antecedent memberships, and inputs it does not
        mention (row ``M``) are left out (the s-norm's identity is 0). An OR rule with one
        antecedent equals an AND rule and is lowered as one. All False unless ``"or"``.
    snorm : SNorm
        Any :class:`~it2track.fuzzy.norms.SNorm` (default ``max(a, b)``), folded over
        the antecedents left to right.
    weight : ndarray, shape (R,)
        Rule weights in [0, 1]; both firing bounds are multiplied by them after the t-norm /
        s-norm. All 1 unless ``"weights"``.
    coef_lo, coef_hi : ndarray, shape (R, n_inputs)
        Interval coefficients of first-order consequents (zero for zero-order rules): the
        consequent at the clipped input ``x`` is
        ``[y_lo + sum_i min(coef_lo x_i, coef_hi x_i), y_hi + sum_i max(coef_lo x_i,
        coef_hi x_i)]``, summed over ``i`` in input order. All 0 unless ``"linear"``.
    n_outputs : int
        Outputs of the system. With ``"outputs"`` (``n_outputs > 1``) the attributes above
        describe output 1 and ``outputs[k]`` describes output ``k + 1``.
    outputs : tuple of SystemTables
        One single-output lowering per output, each holding only the rules with a consequent
        for that output; ``(self,)`` for a one-output system.
    rule_index : ndarray of int, shape (R,)
        The system's rule number of each rule here (``arange(R)`` unless rules were left out
        of an output).
    features : frozenset of str
        Rule-language features beyond zero-order AND rules of weight 1 with one output that
        these tables use, from :data:`FEATURES`: ``"not"`` (a negated antecedent),
        ``"or"`` (an OR rule over two or more inputs), ``"weights"`` (a weight other than 1),
        ``"linear"`` (a first-order consequent), ``"formula"`` (a
        :class:`~it2track.fuzzy.formula.Formula` consequent, evaluated per sample; with it
        ``"linear"`` too), ``"chain"`` (a formula reading the outputs before this one, as
        rows after the inputs': :mod:`~it2track.fuzzy.chain`), ``"outputs"`` (several),
        ``"idle"`` (an output other than the first that no rule concludes: its tables have
        no rules and it is the system's zero-firing value everywhere),
        ``"hedges"`` (a hedged proposition -- its rows are :class:`~it2track.fuzzy.hedges.Hedged`
        -- or a hedged conclusion, applied to the weighted firing of that rule). An
        evaluator that does not implement one of them must refuse the tables or fall back on
        the numpy evaluation. The empty set is exactly the paper's rule form.
    """

    def __init__(
        self,
        inputs: tuple[Input, ...],
        rules: tuple[Rule, ...],
        *,
        snorm: SNorm = SNorm.MAXIMUM,
        _output: int | None = None,
    ) -> None:
        n_outputs = len(rules[0].consequents) if rules else 1
        for k, rule in enumerate(rules):
            if len(rule.consequents) != n_outputs:
                raise ValueError(
                    f"rule {k} has {len(rule.consequents)} consequents, rule 0 has {n_outputs}: "
                    "every rule needs one per output"
                )
        self.n_outputs = n_outputs
        self.snorm = snorm
        output = 0 if _output is None else _output
        rules_all = rules
        index = [r for r, rule in enumerate(rules) if rule.consequents[output] is not None]
        if not index and _output is None:
            raise ValueError(f"no rule has a consequent for output {output + 1}")
        self.rule_index = np.array(index, dtype=np.intp)
        rules = tuple(rules[r] for r in index)
        self.n_inputs = len(inputs)
        self.n_rules = len(rules)
        self.lo = np.array([inp.universe[0] for inp in inputs])
        self.hi = np.array([inp.universe[1] for inp in inputs])
        mfs: list[MembershipFunction] = []
        mf_input: list[int] = []

        def row_of(mf: MembershipFunction, i: int) -> int:
            for k, (other, j) in enumerate(zip(mfs, mf_input, strict=True)):
                if j == i and (other is mf or other == mf):
                    return k
            if isinstance(mf, ScaledLagged):
                row_of(mf.upper, i)  # its upper MF is a row before it (the kernels read it)
            mfs.append(mf)
            mf_input.append(i)
            return len(mfs) - 1

        def hedged_rows(i: int, label: str, hedges: tuple[Hedge, ...]) -> tuple[int, int]:
            s = inputs[i].sets[inputs[i].set_index(label)]
            mf_up, mf_lo = s.upper, s.lower
            if hedges:  # hedged rows (a 'not' among the hedges swaps the bounds)
                if sum(not h.increasing for h in hedges) % 2:
                    mf_up, mf_lo = mf_lo, mf_up
                mf_up, mf_lo = Hedged(mf_up, hedges), Hedged(mf_lo, hedges)
            return row_of(mf_up, i), row_of(mf_lo, i)

        def compiled(node: Condition) -> tuple[Any, ...]:
            if isinstance(node, Is):
                return ("is", *hedged_rows(node.input, node.label, node.hedges))
            if isinstance(node, Not):
                return ("not", compiled(node.operand))
            if isinstance(node, Modified):
                flip = sum(not h.increasing for h in node.hedges) % 2 == 1
                return ("mod", float(node.weight), node.hedges, flip, compiled(node.operand))
            assert isinstance(node, Join)
            return (node.op, node.norm, tuple(compiled(c) for c in node.operands))

        n_in = len(inputs)
        trees: dict[int, tuple[Any, ...]] = {}
        upper_rows = np.empty((len(rules), n_in), dtype=np.intp)
        lower_rows = np.empty((len(rules), n_in), dtype=np.intp)
        for r, rule in enumerate(rules):
            if rule.condition is not None:
                trees[r] = compiled(rule.condition)
            for i, label in enumerate(rule.antecedent):
                if label is None:
                    upper_rows[r, i] = lower_rows[r, i] = -1
                    continue
                upper_rows[r, i], lower_rows[r, i] = hedged_rows(i, label, rule.hedges[i])
        n_rows = len(mfs)
        # Row n_rows is the constant 1 used for inputs a rule does not mention.
        upper_rows[upper_rows < 0] = n_rows
        lower_rows[lower_rows < 0] = n_rows
        self.n_rows = n_rows
        self.upper_rows = upper_rows
        self.lower_rows = lower_rows
        self.type1 = bool(np.array_equal(upper_rows, lower_rows))
        self.mfs = tuple(mfs)
        self.mf_input = np.array(mf_input, dtype=np.intp)
        encoded = [_encode(mf) for mf in mfs]
        for k, mf in enumerate(mfs):
            if isinstance(mf, ScaledLagged):
                up = next(j for j in range(k) if mf_input[j] == mf_input[k]
                          and (mfs[j] is mf.upper or mfs[j] == mf.upper))
                peak = float(getattr(mf.upper, "h", 1.0))
                encoded[k] = (MFKind.SCALED_LAGGED, (float(up), mf.scale * peak,
                                                     float(mf.lag), peak, 0.0))
        self.mf_kind = np.array([int(k) for k, _ in encoded], dtype=np.intp)
        self.mf_params = np.array([p for _, p in encoded], dtype=np.float64).reshape(n_rows, 5)
        # Piecewise-linear rows are evaluated together as one trapezoid bank.
        pl = [k for k in range(n_rows) if self.mf_kind[k] == MFKind.TRAPEZOID]
        self.pl_rows = np.array(pl, dtype=np.intp)
        self.pl_input = np.array([mf_input[k] for k in pl], dtype=np.intp)
        a, wl, d, wr, h = (self.mf_params[pl, j].tolist() for j in range(5))
        self.pl_params = [np.array(v)[:, None] for v in (a, wl, d, wr, h)]
        self.pl_scalar = list(zip(pl, [mf_input[k] for k in pl], a, wl, d, wr, h, strict=True))
        self.other = [(k, mfs[k], mf_input[k]) for k in range(n_rows)
                      if k not in set(pl) and not _parametric(mfs[k])]
        #: rows whose parameters are inputs (:mod:`.parametric`), evaluated on the whole block
        self.parametric = [(k, mf, mf_input[k]) for k, mf in enumerate(mfs) if _parametric(mf)]
        self.all_pl = not self.other and not self.parametric
        self.identity_pl = self.all_pl and np.array_equal(self.pl_rows, np.arange(n_rows))
        y_lo = np.empty(len(rules))
        y_hi = np.empty(len(rules))
        coef_lo = np.zeros((len(rules), n_in))
        coef_hi = np.zeros((len(rules), n_in))
        formulas: dict[int, Formula] = {}
        for r, rule in enumerate(rules):
            cons = rule.consequents[output]
            if isinstance(cons, Formula):
                if not n_in <= len(cons.names) <= n_in + output:
                    raise ValueError(
                        f"rule {int(self.rule_index[r])}: formula {cons.text!r} reads "
                        f"{len(cons.names)} names for {n_in} inputs"
                        + (f" and the {output} outputs before this one" if output else "")
                    )
                y_lo[r] = y_hi[r] = 0.0
                formulas[r] = cons
            elif isinstance(cons, Linear):
                if len(cons.lo) != n_in:
                    raise ValueError(
                        f"rule {int(self.rule_index[r])}: linear consequent has "
                        f"{len(cons.lo)} coefficients for {n_in} inputs"
                    )
                y_lo[r], y_hi[r] = cons.constant_lo, cons.constant_hi
                coef_lo[r], coef_hi[r] = cons.lo, cons.hi
            elif isinstance(cons, tuple):
                y_lo[r], y_hi[r] = cons
            else:
                raise ValueError(
                    f"rule {int(self.rule_index[r])}: consequent {cons!r} is not a number, "
                    "interval or Linear (a Mamdani output set label needs a Mamdani system)"
                )
        self.y_lo, self.y_hi = y_lo, y_hi
        self.coef_lo, self.coef_hi = coef_lo, coef_hi
        linear = bool(formulas) or any(isinstance(rule.consequents[output], Linear)
                                       for rule in rules)
        self.crisp = bool(np.array_equal(y_lo, y_hi)) and bool(np.array_equal(coef_lo, coef_hi))
        self.negated = np.array([rule.negated for rule in rules], dtype=bool).reshape(
            len(rules), n_in
        )
        self.is_or = np.array(
            [rule.connective is Connective.OR and sum(a is not None for a in rule.antecedent) > 1
             for rule in rules],
            dtype=bool,
        )
        self.weight = np.array([rule.weight for rule in rules], dtype=np.float64)
        self.consequent_hedges = tuple(rule.consequent_hedges[output] for rule in rules)
        features = set()
        if any(rule.hedges[i] for rule in rules for i in range(n_in)) or any(
                self.consequent_hedges):
            features.add("hedges")
        if trees:
            features.add("tree")
        if self.negated.any():
            features.add("not")
        if self.is_or.any():
            features.add("or")
        if np.any(self.weight != 1.0):
            features.add("weights")
        if linear:
            features.add("linear")
        if formulas:
            features.add("formula")
        if any(name in f.used for f in formulas.values() for name in f.names[n_in:]):
            features.add("chain")
        if n_outputs > 1:
            features.add("outputs")
        self.features: frozenset[str] = frozenset(features)
        # Rules are evaluated sorted by their lower consequent, so the type reducers need no
        # gather; `perm` maps sorted position -> original rule index.
        self.perm = np.argsort(y_lo, kind="stable")
        self.inv_perm = np.argsort(self.perm)
        self.upper_rows_s = np.ascontiguousarray(upper_rows[self.perm])
        self.lower_rows_s = np.ascontiguousarray(lower_rows[self.perm])
        self.y_lo_s = y_lo[self.perm]
        self.y_hi_s = y_hi[self.perm]
        self.order_ident = np.arange(len(rules))
        self.order_hi_s = np.argsort(self.y_hi_s, kind="stable")
        self.upper_rows_s_list = self.upper_rows_s.tolist()
        self.lower_rows_s_list = self.lower_rows_s.tolist()
        self.all_h1 = all(v == 1.0 for v in h)
        self.negated_s = np.ascontiguousarray(self.negated[self.perm])
        self.is_or_s = self.is_or[self.perm]
        self.weight_s = self.weight[self.perm]
        self.coef_lo_s = np.ascontiguousarray(coef_lo[self.perm])
        self.coef_hi_s = np.ascontiguousarray(coef_hi[self.perm])
        # The firing features: rows of an extended membership array [m, 1, 0, 1 - m] that each
        # (possibly negated) antecedent reads; unmentioned inputs of OR rules read the 0 row.
        self.general_firing = bool(self.features & {"not", "or", "weights", "hedges", "tree"})
        position = {r: s for s, r in enumerate(self.perm.tolist())}
        #: (sorted position, formula) of each Formula consequent
        self.formulas_s = [(position[r], f) for r, f in sorted(formulas.items())]
        self.trees_s = [(position[r], tree) for r, tree in sorted(trees.items())]
        self.consequent_hedges_s = [(s, self.consequent_hedges[r])
                                    for s, r in enumerate(self.perm.tolist())
                                    if self.consequent_hedges[r]]
        one, zero, comp = n_rows, n_rows + 1, n_rows + 2
        up_ext = np.where(self.negated_s, comp + self.lower_rows_s, self.upper_rows_s)
        lo_ext = np.where(self.negated_s, comp + self.upper_rows_s, self.lower_rows_s)
        unused = self.upper_rows_s == n_rows
        up_ext[unused] = one
        lo_ext[unused] = one
        up_ext[unused & self.is_or_s[:, None]] = zero
        lo_ext[unused & self.is_or_s[:, None]] = zero
        self.up_ext_s, self.lo_ext_s = up_ext, lo_ext
        self.type1_firing = bool(np.array_equal(up_ext, lo_ext)) and all(
            _tree_type1(tree) for _, tree in self.trees_s)
        # For t-norms without an exact identity: which inputs each (sorted) rule mentions,
        # and the first of them (where its AND fold starts).
        self.mentioned_s = ~unused
        self.first_s = np.argmax(self.mentioned_s, axis=1)
        self._local = threading.local()
        self.outputs: tuple[SystemTables, ...] = (self,)
        if _output is None and n_outputs > 1:
            others = [SystemTables(inputs, tuple(rules_all), snorm=snorm, _output=k)
                      for k in range(1, n_outputs)]
            self.outputs = (self, *others)
            if any(not t.n_rules for t in others):  # an output no rule concludes
                self.features = self.features | {"idle"}

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        del state["_local"]  # per-thread scratch arrays: not picklable, rebuilt on demand
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._local = threading.local()

    def workspace(self, n: int) -> dict[str, FloatArray]:
        """Scratch arrays for blocks of up to ``n`` samples, reused across calls (per thread).

        Reuse matters: fresh multi-megabyte temporaries cost page faults that take longer than
        the arithmetic itself.
        """
        ws: dict[str, FloatArray] | None = getattr(self._local, "ws", None)
        if ws is None or ws["m"].shape[1] < n:
            r = len(self.upper_rows)
            p = max(len(self.pl_rows), 1)
            ws = {
                "m": np.empty((self.n_rows + 1, n)),
                "xr": np.empty((p, n)),
                "right": np.empty((p, n)),
                "fu": np.empty((r, n)),
                "fl": np.empty((r, n)),
                "tmp": np.empty((r, n)),
            }
            ws["m"][self.n_rows] = 1.0
            self._local.ws = ws
        return ws

    def memberships(self, x: FloatArray, out: FloatArray | None = None) -> FloatArray:
        """All membership rows for a block ``x`` of shape ``(n_inputs, N)``: ``(n_rows+1, N)``.

        The last row is the constant 1 used for inputs a rule does not mention.
        """
        n = x.shape[1]
        ws = self.workspace(n)
        if out is None:
            out = np.empty((self.n_rows + 1, n))
            out[self.n_rows] = 1.0
        if self.pl_rows.size:
            a, wl, d, wr, h = self.pl_params
            xr = np.take(x, self.pl_input, axis=0, out=ws["xr"][:, :n])
            left = out[: self.n_rows] if self.identity_pl else np.empty_like(xr)
            right = ws["right"][:, :n]
            np.subtract(xr, a, out=left)
            np.divide(left, wl, out=left)
            np.subtract(d, xr, out=right)
            np.divide(right, wr, out=right)
            np.minimum(left, right, out=left)
            np.minimum(left, 1.0, out=left)
            np.maximum(left, 0.0, out=left)
            if not self.all_h1:
                np.multiply(left, h, out=left)
            if not self.identity_pl:
                out[self.pl_rows] = left
        for k, mf, i in self.other:
            out[k] = mf(x[i])
        for k, pmf, i in self.parametric:
            out[k] = _parametric_block(pmf, x, i)
        return out

    def memberships_scalar(self, x: Sequence[float]) -> list[float]:
        out = [1.0] * (self.n_rows + 1)
        for k, i, a, wl, d, wr, h in self.pl_scalar:
            v = min((x[i] - a) / wl, (d - x[i]) / wr)
            out[k] = h * (0.0 if v < 0.0 else 1.0 if v > 1.0 else v)
        for k, mf, i in self.other:
            out[k] = float(mf(np.float64(x[i])))
        if self.parametric:
            column = np.array(x, dtype=np.float64)[:, None]
            for k, pmf, i in self.parametric:
                out[k] = float(_parametric_block(pmf, column, i)[0])
        return out

    # -- firing (the antecedent machinery shared by every kind of system) ---------------------
    def firing_block(self, x: FloatArray, tnorm: TNorm) -> tuple[FloatArray, FloatArray]:
        """Firing of a block ``x`` (n_inputs, N) -> ``(fl, fu)`` (R, N), rules in sorted order.

        The returned arrays are workspace views, valid until the next block (per thread).
        """
        n = x.shape[1]
        ws = self.workspace(n)
        m = self.memberships(x, out=ws["m"][:, :n])
        if self.general_firing or tnorm not in EXACT_IDENTITY:
            return self._firing_general(m, tnorm, n)
        tmp = ws["tmp"][:, :n]
        result = []
        for rows, name in ((self.upper_rows_s, "fu"), (self.lower_rows_s, "fl")):
            f = np.take(m, rows[:, 0], axis=0, out=ws[name][:, :n])
            for i in range(1, self.n_inputs):
                np.take(m, rows[:, i], axis=0, out=tmp)
                if tnorm is TNorm.PRODUCT:
                    np.multiply(f, tmp, out=f)
                else:
                    np.minimum(f, tmp, out=f)
            result.append(f)
            if self.type1:
                return f, f
        fu, fl = result
        return fl, fu

    def _firing_general(
        self, m: FloatArray, tnorm: TNorm, n: int
    ) -> tuple[FloatArray, FloatArray]:
        """Firing with NOT, OR rules, weights and t-norms other than product and minimum (the
        meaning documented on the class)."""
        rows = self.n_rows
        ext = np.empty((2 * rows + 2, n))
        ext[:rows] = m[:rows]
        ext[rows] = 1.0
        ext[rows + 1] = 0.0
        np.subtract(1.0, m[:rows], out=ext[rows + 2 :])
        ws = self.workspace(n)
        result = []
        any_or = bool(self.is_or_s.any())
        for idx, name in ((self.up_ext_s, "fu"), (self.lo_ext_s, "fl")):
            f = np.take(ext, idx[:, 0], axis=0, out=ws[name][:, :n])
            g = f.copy() if any_or else f
            for i in range(1, self.n_inputs):
                col = ext[idx[:, i]]
                if tnorm is TNorm.PRODUCT:
                    np.multiply(f, col, out=f)
                elif tnorm is TNorm.MINIMUM:
                    np.minimum(f, col, out=f)
                else:  # fold over the mentioned inputs only (T(f, 1) may differ from f)
                    start = self.first_s == i
                    f[start] = col[start]
                    more = self.mentioned_s[:, i] & (self.first_s < i)
                    f[more] = tnorm.pair(f[more], col[more])
                if any_or:
                    g = self.snorm.pair(g, col)
            if any_or:
                np.copyto(f, g, where=self.is_or_s[:, None])
            for s, tree in self.trees_s:
                f[s] = _tree_value(tree, ext, name == "fu", tnorm, self.snorm)
            if "weights" in self.features:
                f *= self.weight_s[:, None]
            result.append(f)
            if self.type1_firing:
                result.append(f)
                break
        fu, fl = result
        for s, hedges in self.consequent_hedges_s:  # a 'not' among them swaps the bounds
            if fl is fu:
                fu[s] = apply_hedges(hedges, fu[s])
                continue
            up, lo = fu[s].copy(), fl[s].copy()
            if sum(not h.increasing for h in hedges) % 2:
                up, lo = lo, up
            fu[s] = apply_hedges(hedges, up)
            fl[s] = apply_hedges(hedges, lo)
        return fl, fu

    def consequents_block(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """First-order consequents at a block ``x`` (n_inputs, N): ``(y_lo, y_hi)`` (R, N),
        rules in sorted order (the formula of :attr:`coef_lo`; ``"chain"``: outputs after)."""
        y_lo = np.repeat(self.y_lo_s[:, None], x.shape[1], axis=1)
        y_hi = np.repeat(self.y_hi_s[:, None], x.shape[1], axis=1)
        for i in range(self.n_inputs):
            p = self.coef_lo_s[:, i : i + 1] * x[i]
            q = self.coef_hi_s[:, i : i + 1] * x[i]
            y_lo += np.minimum(p, q)
            y_hi += np.maximum(p, q)
        for s, formula in self.formulas_s:
            y_lo[s] = y_hi[s] = formula(*x[:len(formula.names)])
        return y_lo, y_hi


def _tree_type1(tree: tuple[Any, ...]) -> bool:
    """True if the compiled condition reads the same rows for both bounds."""
    if tree[0] == "is":
        return bool(tree[1] == tree[2])
    if tree[0] == "not":
        return _tree_type1(tree[1])
    if tree[0] == "mod":
        return _tree_type1(tree[4])
    return all(_tree_type1(t) for t in tree[2])


def _tree_value(tree: tuple[Any, ...], m: FloatArray, upper: bool, tnorm: TNorm,
                snorm: SNorm) -> FloatArray:
    """A compiled :mod:`.conditions` condition on the membership rows ``m`` (its upper bound
    if ``upper``, else its lower; each negation swaps them)."""
    kind = tree[0]
    if kind == "is":
        return m[tree[1] if upper else tree[2]]
    if kind == "not":
        return 1.0 - _tree_value(tree[1], m, not upper, tnorm, snorm)
    if kind == "mod":
        _, weight, hedges, flip, inner = tree
        value = weight * _tree_value(inner, m, upper != flip, tnorm, snorm)
        return apply_hedges(hedges, value) if hedges else value
    norm = tree[1] if tree[1] is not None else (tnorm if kind == "and" else snorm)
    values = [_tree_value(t, m, upper, tnorm, snorm) for t in tree[2]]
    out = values[0]
    for v in values[1:]:
        out = norm.pair(out, v)
    return out
