"""A requirement spec as a differentiable model of its design vector.

:class:`DesignModel` turns a validated :class:`~diffsense.design.spec.Spec` into pure JAX functions of

* ``x`` — the continuous and integer design variables in their own units (a vector, in the
  order of ``spec.variables``), and
* ``combo`` — one row of the catalog table: the values of every parameter set by a catalog
  choice (a vector; the model enumerates all combinations of catalog options),

returning each case's chain evaluation, the requirement outputs, normalised constraint
residuals (≤ 0 when met) and the objective. The requirement limits are a separate argument
(``limits``) so that an optimum can be differentiated with respect to them.

The functions the optimiser differentiates (:meth:`DesignModel.residuals`,
:meth:`DesignModel.objective`) evaluate each case with ``wanted`` = the outputs they read
(:attr:`DesignModel.requirement_outputs`, :attr:`DesignModel.objective_outputs`), so the chains
leave out the root finds and detection series nobody asked for (see
:class:`diffsense.sensors.chain.Chain`); the values are those of the full evaluation. Reports
(:meth:`DesignModel.evaluate_all`) evaluate every output.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Dict, FrozenSet, List, Mapping, Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.sensors.chain import Evaluation
from diffsense.scene import complete_parameters, chain_for
from diffsense.design.chance import ChanceRequirements
from diffsense.design.intervals import IntervalRequirements
from diffsense.design.spec import Spec

# units in which a difference of 1 is a natural step (no normalisation by the limit)
_ABSOLUTE_UNITS = {"dB", "deg", "1"}


@dataclass(frozen=True)
class Combination:
    """One choice of an option for every catalog: names and the parameter values it sets."""

    index: int
    options: Dict[str, str]  # catalog -> option name
    values: Dict[str, float]  # parameter -> value
    cost: float


class DesignModel:
    """Pure functions of the design for one spec (see the module docstring).

    ``requirement_outputs`` and ``objective_outputs`` map each case to the frozenset of its
    outputs that the requirements (resp. the objective terms) read; a case whose outputs are
    not read is absent.
    """

    def __init__(self, spec: Spec):
        self.spec = spec
        self.variable_names: List[str] = list(spec.variables)
        vs = [spec.variables[n] for n in self.variable_names]
        self.lower = np.array([v.lower for v in vs], dtype=float)
        self.upper = np.array([v.upper for v in vs], dtype=float)
        self.initial = np.array([v.initial for v in vs], dtype=float)
        self.log_scale = np.array([v.log_scale for v in vs], dtype=bool)
        self.integer = np.array([v.integer for v in vs], dtype=bool)

        # catalog combinations (cartesian product of every catalog's options)
        self.choice_names = list(spec.choices)
        self.combo_params: List[str] = []
        for c in self.choice_names:
            self.combo_params.extend(spec.choices[c].settings[0])
        combos = []
        per_choice = [range(len(spec.choices[c].option_names)) for c in self.choice_names]
        for idx, pick in enumerate(itertools.product(*per_choice)):
            opts, vals, cost = {}, {}, 0.0
            for c, k in zip(self.choice_names, pick):
                ch = spec.choices[c]
                opts[c] = ch.option_names[k]
                vals.update(ch.settings[k])
                cost += ch.costs[k]
            combos.append(Combination(idx, opts, vals, cost))
        self.combinations = combos
        self.combo_table = np.array([[c.values[p] for p in self.combo_params] + [c.cost] for c in combos],
                                    dtype=float).reshape(len(combos), len(self.combo_params) + 1)

        self.requirements = list(spec.requirements)
        self.limits = np.array([r.limit for r in self.requirements], dtype=float)
        self.scales = np.array([1.0 if r.unit in _ABSOLUTE_UNITS else max(abs(r.limit), 1e-300)
                                for r in self.requirements], dtype=float)
        self.is_equality = np.array([r.sense == "equals" for r in self.requirements], dtype=bool)
        self.sign = np.array([-1.0 if r.sense == "at_least" else 1.0 for r in self.requirements], dtype=float)
        # requirements over intervals (semi-infinite): one constraint row per worst point kept
        self.intervals = IntervalRequirements(spec, self.parameters, self.sign, self.scales)
        # requirements with a probability (chance constraints): one row each, a smoothed quantile
        self.chance = ChanceRequirements(spec, self.parameters, self.sign, self.scales)
        #: the requirement each constraint row of :meth:`residuals` belongs to
        self.row_owner = np.concatenate([np.full(r.over_worst if r.over else 1, j, dtype=int)
                                         for j, r in enumerate(self.requirements)]) if self.requirements \
            else np.zeros((0,), dtype=int)
        self.row_is_equality = self.is_equality[self.row_owner]

        # fixed parameters per case, completed with defaults (validated once, concretely)
        self.fixed = {}
        for case, scene in spec.scenes.items():
            chain = chain_for(scene)
            table = chain.parameters(scene)
            sample = dict(spec.fixed[case])
            for i, n in enumerate(self.variable_names):
                if n in table:
                    sample[n] = float(self.initial[i])
            for j, n in enumerate(self.combo_params):
                if n in table:
                    sample[n] = float(self.combo_table[0, j])
            complete = complete_parameters(scene, sample)
            self.fixed[case] = {k: v for k, v in complete.items()
                                if k not in self.variable_names and k not in self.combo_params}
        # outputs read per case (case -> frozenset of output names): by the requirements, by the objective
        self.requirement_outputs: Dict[str, FrozenSet[str]] = self._outputs_by_case(
            (r.case, r.output) for r in self.requirements if not r.over)
        # objective terms resolved once: (source, case, name, weight), source one of "cost",
        # "variable", "combo", "output", "fixed"
        self._objective_terms = [self._objective_term(name) + (weight,) for name, weight in spec.objective.terms]
        self.objective_outputs: Dict[str, FrozenSet[str]] = self._outputs_by_case(
            (case, base) for source, case, base, _ in self._objective_terms if source == "output")
        # objective normalisation: its magnitude at the initial design of the first combination
        self._objective_scale = 1.0
        self._evaluate_all = None
        f0 = float(jax.jit(self.raw_objective)(jnp.asarray(self.initial), jnp.asarray(self.combo_table[0])))
        self._objective_scale = max(abs(f0), 1e-300) if np.isfinite(f0) and f0 != 0 else 1.0

    @staticmethod
    def _outputs_by_case(pairs) -> Dict[str, FrozenSet[str]]:
        """``{case: frozenset(outputs)}`` from ``(case, output)`` pairs (``None`` pairs skipped)."""
        out: Dict[str, set] = {}
        for pair in pairs:
            if pair is not None:
                out.setdefault(pair[0], set()).add(pair[1])
        return {case: frozenset(names) for case, names in out.items()}

    def objective_term(self, name):
        """``(source, case, base)`` of the objective term ``name``: the catalog "cost", a design
        "variable", a catalog ("combo") parameter, a chain "output" or a "fixed" parameter of
        ``case`` (the first case when ``name`` names none)."""
        if name == "cost":
            return "cost", None, None
        case, base = name.split(".", 1) if "." in name else (next(iter(self.spec.scenes)), name)
        if base in self.variable_names:
            return "variable", case, base
        if base in self.combo_params:
            return "combo", case, base
        if base in self.spec.outputs[case]:
            return "output", case, base
        return "fixed", case, base

    _objective_term = objective_term  # former private name

    # --- evaluation --------------------------------------------------------------------------
    def parameters(self, x, combo) -> Dict[str, Dict[str, jnp.ndarray]]:
        """Per case, the full parameter dict for design ``x`` and catalog row ``combo``."""
        out = {}
        for case, scene in self.spec.scenes.items():
            table = self.spec.parameters[case]
            p = dict(self.fixed[case])
            for i, n in enumerate(self.variable_names):
                if n in table:
                    p[n] = x[i]
            for j, n in enumerate(self.combo_params):
                if n in table:
                    p[n] = combo[j]
            out[case] = p
        return out

    def evaluate(self, x, combo, wanted: Optional[Mapping[str, FrozenSet[str]]] = None) -> Dict[str, Evaluation]:
        """Each case's chain evaluation at design ``x`` and catalog row ``combo``.

        ``wanted`` (static): ``None`` evaluates every case with every output; a mapping
        ``{case: frozenset of output names}`` evaluates only the cases it names, each with at
        least those outputs (the chain's ``wanted``, see :class:`diffsense.sensors.chain.Chain`).
        """
        res = {}
        for case, p in self.parameters(x, combo).items():
            if wanted is not None and case not in wanted:
                continue
            scene = self.spec.scenes[case]
            chain = chain_for(scene)
            res[case] = chain.compute(scene, p) if wanted is None else chain.compute(scene, p, wanted=wanted[case])
        return res

    def requirement_values(self, x, combo, evaluations=None, parameters=None) -> jnp.ndarray:
        """The requirement outputs (their own units), in spec order; without ``evaluations`` the
        cases are evaluated for :attr:`requirement_outputs` only. A requirement over an interval
        gives its worst value found by the search (:mod:`diffsense.design.intervals`);
        ``parameters`` (per case) replaces :meth:`parameters` for that search."""
        ev = self.evaluate(x, combo, self.requirement_outputs) if evaluations is None else evaluations
        worst = self.intervals.worst_values(x, combo, parameters) if self.intervals.indices else {}
        chance = self.chance.values(x, combo, parameters) if self.chance.indices else {}
        return jnp.stack([worst[j] if r.over else chance[j] if j in chance
                          else jnp.asarray(ev[r.case].values[r.output], dtype=float)
                          for j, r in enumerate(self.requirements)])

    def residuals(self, x, combo, limits) -> jnp.ndarray:
        """Normalised residuals, one row per point requirement and ``over_worst`` rows per
        interval requirement (:attr:`row_owner`): ≤ 0 when an inequality is met, = 0 when an
        equality is met."""
        ev = self.evaluate(x, combo, self.requirement_outputs) if self.requirement_outputs else {}
        rows = self.intervals.rows(x, combo, limits) if self.intervals.indices else {}
        chance = self.chance.rows(x, combo, limits) if self.chance.indices else {}
        out = []
        for j, r in enumerate(self.requirements):
            if r.over:
                out.append(rows[j])
            elif j in chance:
                out.append(chance[j])
            else:
                v = jnp.asarray(ev[r.case].values[r.output], dtype=float)
                out.append(jnp.reshape(self.sign[j] * (v - limits[j]) / self.scales[j], (1,)))
        return jnp.concatenate(out)

    def row_multipliers(self, row_lam) -> np.ndarray:
        """Per requirement, the sum of the multipliers of its constraint rows."""
        out = np.zeros(len(self.requirements))
        np.add.at(out, self.row_owner, np.asarray(row_lam, dtype=float))
        return out

    def raw_objective(self, x, combo, evaluations=None) -> jnp.ndarray:
        """Objective in the spec's own terms (weighted sum; maximisation negated); without
        ``evaluations`` the cases are evaluated for :attr:`objective_outputs` only."""
        ev = evaluations
        if ev is None and any(t[0] == "output" for t in self._objective_terms):
            ev = self.evaluate(x, combo, self.objective_outputs)
        return self.spec.objective.sign * self.weighted_terms(self._objective_terms, x, combo, ev)

    def weighted_terms(self, terms, x, combo, evaluations) -> jnp.ndarray:
        """Σ weight · value over objective terms ``(source, case, base, weight)``: the catalog
        cost, a design variable, a catalog parameter, a case's output (from ``evaluations``) or
        a fixed parameter."""
        total = jnp.asarray(0.0)
        for source, case, base, weight in terms:
            if source == "cost":
                val = combo[-1]
            elif source == "variable":
                val = x[self.variable_names.index(base)]
            elif source == "combo":
                val = combo[self.combo_params.index(base)]
            elif source == "output":
                val = evaluations[case].values[base]
            else:
                val = self.fixed[case][base]
            total = total + weight * val
        return total

    def objective(self, x, combo) -> jnp.ndarray:
        """Normalised objective (≈ ±1 at the initial design) to be minimised."""
        return self.raw_objective(x, combo) / self._objective_scale

    def _evaluate_all_jit(self):
        if self._evaluate_all is None:
            def run(x, combo):
                ev = self.evaluate(x, combo)
                return ev, self.requirement_values(x, combo, ev), self.raw_objective(x, combo, ev)
            self._evaluate_all = jax.jit(run)
        return self._evaluate_all

    def forget_compiled(self) -> None:
        """Drop the compiled evaluation (after the interval search's candidates changed)."""
        self._evaluate_all = None

    def compile_evaluation(self) -> None:
        """Trace and compile :meth:`evaluate_all` now (later calls reuse the program); lets a
        caller compile it while another thread compiles something else."""
        dtype = jnp.result_type(float)
        self._evaluate_all_jit().lower(jax.ShapeDtypeStruct((len(self.variable_names),), dtype),
                                       jax.ShapeDtypeStruct((self.combo_table.shape[1],), dtype)).compile()

    def evaluate_all(self, x, combo):
        """``(evaluations, requirement_values, raw_objective)`` at one design, compiled once per
        model. Re-evaluating designs through this is far cheaper than eager evaluation, whose
        root-finding and series loops would each be compiled again on every call."""
        return self._evaluate_all_jit()(jnp.asarray(x, dtype=float), jnp.asarray(combo, dtype=float))

    def requirement_report(self, x, combo, tol: float = 1e-9) -> List[dict]:
        """Requirement rows {name, output, case, value, limit, unit, sense, met, slack}; an
        interval requirement's value is its worst value on the dense re-check."""
        values = self.evaluate_all(x, combo)[1]
        checks = self.intervals.check(x, combo, np.asarray(values)) if self.intervals.indices else {}
        return self.requirement_rows(values, tol, checks)

    def requirement_rows(self, values, tol: float = 1e-9, checks=None) -> List[dict]:
        """Requirement rows for given requirement output ``values`` (spec order, their units):
        slack ≥ 0 when met; "met" allows ``tol`` in scaled units. ``checks``: the dense re-checks
        of the interval requirements (:meth:`IntervalRequirements.check`): their worst value
        replaces the search's, and the row gains ``over``, ``worst_at``, ``dense_points``,
        ``search_value`` and (one parameter) ``curve``."""
        rows = []
        values = np.asarray(values, dtype=float).copy()
        checks = checks or {}
        for j, chk in checks.items():
            values[j] = chk.worst_value
        for j, (r, v, scale) in enumerate(zip(self.requirements, values, self.scales)):
            if r.sense == "at_least":
                slack = v - r.limit
            elif r.sense == "at_most":
                slack = r.limit - v
            else:
                slack = -abs(v - r.limit)
            row = {"name": r.name, "case": r.case, "output": r.output, "value": float(v),
                   "limit": r.limit, "unit": r.unit, "sense": r.sense,
                   "met": bool(slack >= -tol * scale), "slack": float(slack)}
            if r.over:
                row["over"] = {iv.parameter: [iv.lower, iv.upper, iv.unit] for iv in r.over}
                if j in checks:
                    chk = checks[j]
                    row.update(worst_at=chk.worst_point, dense_points=chk.n_points,
                               search_value=chk.solver_worst_value, curve=chk.curve)
            rows.append(row)
        return rows

    def combo_index(self, options: Dict[str, str]) -> int:
        """Index of the combination with the given catalog option names."""
        for c in self.combinations:
            if all(c.options[k] == v for k, v in options.items()):
                return c.index
        raise KeyError(options)
