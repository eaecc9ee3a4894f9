"""A requirement spec as a differentiable model: static structure plus explicit inputs.

:class:`DesignModel` turns a validated :class:`~diffsense.design.spec.Spec` into pure JAX
functions whose only arguments are arrays:

* ``values`` — the input vector of every chain parameter (:mod:`diffsense.design.layout`);
* θ — :class:`~diffsense.design.inputs.DesignInputs` for an evaluation and
  :class:`~diffsense.design.inputs.SolveInputs` for a solve: the catalog cost, objective weights,
  requirement scales and limits, the interval requirements' boxes and slots, the chance
  constraints' sample, and the stage of the solve;
* ``x`` — the design variables in their own units, in the order of ``spec.variables``, written
  into the input vector together with a catalog row.

The model itself holds only what a compiled program depends on — the scenes, the layout of the
input vector, the variable set, the requirement kinds — and the spec's numbers as NumPy arrays
to build θ from (:meth:`DesignModel.inputs`, :meth:`DesignModel.solve_inputs`). It never changes
after construction, and its traced functions read no value from it, so a program compiled for
one spec serves every spec of the same structure (:mod:`diffsense.design.programs`).

Requirements come in three kinds behind one protocol (:mod:`diffsense.design.kinds`): a *point*
requirement is one output of one case (one constraint row), an *interval* requirement its worst
value over a box of parameters (one row per slot, :mod:`diffsense.design.intervals`), a *chance*
requirement a smoothed quantile over uncertain inputs (one row, :mod:`diffsense.design.chance`).
Each row is s·(v − b)/scale ≤ 0 (s = −1 for ``at_least``, +1 otherwise; = 0 for ``equals``),
``scale`` 1 for requirements in dB, degrees or plain numbers and |b| otherwise.

The functions the optimiser differentiates evaluate each case with ``wanted`` = the outputs
they read, so the chains leave out the root finds and detection series nobody asked for (see
:class:`diffsense.sensors.chain.Chain`); the values are those of the full evaluation.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Dict, FrozenSet, List, Mapping, Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.chance import ChanceRequirements
from diffsense.design.inputs import DesignInputs, SolveInputs, Stage
from diffsense.design.intervals import IntervalRequirements
from diffsense.design.kinds import RequirementKinds
from diffsense.design.layout import InputLayout
from diffsense.design.spec import Spec
from diffsense.design.spec.types import goal_status
from diffsense.scene import compute
from diffsense.sensors.chain import Evaluation

# units in which a difference of 1 is a natural step (no normalisation by the limit)
_ABSOLUTE_UNITS = {"dB", "deg", "1"}


@dataclass(frozen=True)
class Combination:
    """One choice of an option for every catalog: names and the parameter values it sets."""

    index: int
    options: Dict[str, str]  # catalog -> option name
    values: Dict[str, float]  # parameter -> value
    cost: float


def requirement_scales(requirements) -> np.ndarray:
    """Each requirement's scale: 1 in dB, degrees or plain numbers, else max(|limit|, 1e-300)."""
    return np.array([1.0 if r.unit in _ABSOLUTE_UNITS else max(abs(r.limit), 1e-300) for r in requirements],
                    dtype=float)


class DesignModel:
    """Pure functions of a spec's design (module docstring).

    Host-side data (NumPy): ``lower``/``upper``/``initial`` of the variables, ``combo_table``
    (one row per catalog combination: its parameter values, then its cost), ``limits`` and
    ``scales`` of the requirements, ``fixed`` (per case, every fixed parameter's value).
    Structure: ``variable_names``, ``log_scale``, ``integer``, ``combo_params``,
    ``requirements``, ``sign``, ``is_equality``, ``row_owner`` (the requirement of each
    constraint row), ``layout`` (the input vector), ``kinds`` (the requirement kinds).
    ``requirement_outputs`` and ``objective_outputs`` map each case to the frozenset of its
    outputs that the point requirements (resp. the objective terms) read.
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
        self.scales = requirement_scales(self.requirements)
        self.is_equality = np.array([r.sense == "equals" for r in self.requirements], dtype=bool)
        self.sign = np.array([-1.0 if r.sense == "at_least" else 1.0 for r in self.requirements], dtype=float)
        self.intervals = IntervalRequirements(spec, self.sign)
        self.chance = ChanceRequirements(spec, self.sign)
        self.kinds = RequirementKinds(self)
        #: the requirement each constraint row belongs to, and whether the row is an equality
        self.row_owner = self.kinds.row_owner
        self.row_is_equality = self.is_equality[self.row_owner]

        self.layout = InputLayout(spec, self.variable_names, self.combo_params)
        self.fixed: Dict[str, Dict[str, float]] = {c: {} for c in spec.scenes}
        for inp in self.layout.inputs:
            if inp.kind == "fixed":
                for c in inp.cases:
                    self.fixed[c][inp.param] = inp.value
        self.requirement_outputs: Dict[str, FrozenSet[str]] = self.kinds.point_outputs()
        # objective terms resolved once: (source, case, name), source one of "cost", "variable",
        # "combo", "output", "fixed"; their weights are inputs (DesignInputs.weights)
        self.objective_terms = [self.objective_term(name) for name, _ in spec.objective.terms]
        self.objective_weights = np.array([w for _, w in spec.objective.terms], dtype=float)
        self.objective_outputs: Dict[str, FrozenSet[str]] = self._outputs_by_case(
            (case, base) for source, case, base in self.objective_terms if source == "output")
        self._programs = None

    @staticmethod
    def _outputs_by_case(pairs) -> Dict[str, FrozenSet[str]]:
        """``{case: frozenset(outputs)}`` from ``(case, output)`` pairs."""
        out: Dict[str, set] = {}
        for case, name in pairs:
            out.setdefault(case, set()).add(name)
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

    # --- structure ---------------------------------------------------------------------------
    def structure(self) -> tuple:
        """Everything a compiled program of this model depends on, as a hashable tuple of plain
        values: scenes, input layout, variables, requirements (kinds, outputs, senses, boxes'
        parameters and grids, slots), objective terms, uncertain inputs. Numbers a user may edit
        (values, bounds, limits, weights, costs, boxes) are not in it: they are inputs."""
        spec = self.spec
        scenes = tuple((c, s.sensor, tuple(sorted(s.parts)), tuple((k, repr(v)) for k, v in s.options))
                       for c, s in spec.scenes.items())
        reqs = tuple((r.case, r.output, r.sense, tuple(iv.parameter for iv in r.over),
                      self.intervals.boxes[j].counts if r.over else (), r.over_worst if r.over else 0,
                      r.probability is not None) for j, r in enumerate(self.requirements))
        unc = spec.uncertain
        uncertain = () if unc is None else (tuple((d.parameter, d.kind) for d in unc.distributions), unc.samples)
        return ("design-model", scenes, self.layout.structure, tuple(self.variable_names),
                tuple(bool(b) for b in self.log_scale), tuple(bool(b) for b in self.integer),
                tuple(self.combo_params), reqs, tuple(self.objective_terms), float(spec.objective.sign), uncertain)

    # --- data ---------------------------------------------------------------------------------
    def inputs(self, combo_index: int = 0, values=None) -> DesignInputs:
        """θ of an evaluation at the spec's numbers (NumPy): the input vector ``values`` (default
        the spec's, with catalog combination ``combo_index`` written in), that combination's cost,
        and the slots of every interval requirement at its box's far corner (a search replaces
        them, :meth:`~diffsense.design.programs.Programs.search`)."""
        if values is None:
            values = np.asarray(self.layout.values, dtype=float).copy()
            values[self.layout.catalog_slots] = self.combo_table[combo_index, :-1]
        iv = self.intervals
        boxes = [iv.box_data(j) for j in iv.indices]
        return DesignInputs(
            values=np.asarray(values, dtype=float), cost=np.asarray(self.combo_table[combo_index, -1], dtype=float),
            weights=self.objective_weights.copy(), scales=self.scales.copy(),
            box=(tuple(b[0] for b in boxes), tuple(b[1] for b in boxes), tuple(b[2] for b in boxes)),
            points=tuple(iv.initial_points(j) for j in iv.indices),
            sample=self.chance.sample(), spreads=self.chance.spreads(), alpha=self.chance.alphas())

    def stage(self, canonical: bool = False, objective_cap: float = 0.0, inactive=None) -> Stage:
        """A :class:`Stage` (NumPy): the design problem by default."""
        m = int((~self.row_is_equality).sum())
        inactive = np.zeros(m, dtype=bool) if inactive is None else np.asarray(inactive, dtype=bool)
        return Stage(np.asarray(bool(canonical)), np.asarray(float(objective_cap)), inactive)

    def solve_inputs(self, design: DesignInputs, combo_index: int, limits, objective_scale: float,
                     stage: Optional[Stage] = None) -> SolveInputs:
        """θ of one solve (NumPy) for catalog combination ``combo_index``."""
        design = design._replace(cost=np.asarray(self.combo_table[combo_index, -1], dtype=float))
        return SolveInputs(design, np.asarray(self.combo_table[combo_index, :-1], dtype=float),
                           np.asarray(limits, dtype=float), np.asarray(objective_scale, dtype=float),
                           self.stage() if stage is None else stage)

    def design_values(self, x, combo_index: int) -> np.ndarray:
        """The input vector (NumPy) with design ``x`` and catalog combination ``combo_index``."""
        values = np.asarray(self.layout.values, dtype=float).copy()
        values[self.layout.variable_slots] = np.asarray(x, dtype=float)
        values[self.layout.catalog_slots] = self.combo_table[combo_index, :-1]
        return values

    # --- traced: evaluation -------------------------------------------------------------------
    def parameters(self, values) -> Dict[str, Dict[str, jnp.ndarray]]:
        """Per case, the full parameter dict read from the input vector ``values``."""
        return self.layout.case_parameters(values)

    def evaluate(self, values, wanted: Optional[Mapping[str, FrozenSet[str]]] = None) -> Dict[str, Evaluation]:
        """Each case's chain evaluation at input vector ``values``.

        ``wanted`` (static): ``None`` evaluates every case with every output; a mapping
        ``{case: frozenset of output names}`` evaluates only the cases it names, each with at
        least those outputs (the chain's ``wanted``, see :class:`diffsense.sensors.chain.Chain`).
        """
        res = {}
        for case, p in self.parameters(values).items():
            if wanted is not None and case not in wanted:
                continue
            res[case] = compute(self.spec.scenes[case], p, None if wanted is None else wanted[case])
        return res

    def evaluate_with_slots(self, values, inputs: DesignInputs, wanted=None):
        """``(evaluations, slot values)``: each case's chain evaluation at ``values`` and every
        interval requirement's output at each of its slots (j -> (K_j,)), from **one** batched
        chain evaluation per case — the case's parameters followed by one point per slot (the
        slot's ``over`` parameters replaced) — so that a compiled program holds one copy of each
        case's chain. ``wanted``: as :meth:`evaluate` (None: every output of every case); the
        interval requirements' outputs are added."""
        params = self.parameters(values)
        reqs = self.requirements
        evaluations, slots = {}, {}
        for case, p in params.items():
            ivs = [j for j in self.intervals.indices if reqs[j].case == case]
            want = None if wanted is None else wanted.get(case)
            if want is None and wanted is not None and not ivs:
                continue
            scene = self.spec.scenes[case]
            if not ivs:
                evaluations[case] = compute(scene, p, want)
                continue
            if wanted is not None:
                want = frozenset(want or ()) | frozenset(reqs[j].output for j in ivs)
            batch = self._slot_batch(p, ivs, inputs)

            def at(q, p=p, scene=scene, want=want):
                return compute(scene, {**p, **q}, want)

            # only the ``over`` parameters are batched: what does not depend on them (a required
            # SNR, a received pulse width, ...) is computed once, not once per slot
            ev = jax.vmap(at)(batch)
            if wanted is None or case in wanted:
                evaluations[case] = jax.tree_util.tree_map(lambda a: a[0], ev)
            start = 1
            for j in ivs:
                k = self.intervals.slots(j)
                slots[j] = jnp.asarray(ev.values[reqs[j].output], dtype=float)[start:start + k]
                start += k
        return evaluations, slots

    def _slot_batch(self, params: dict, ivs, inputs: DesignInputs) -> dict:
        """The ``over`` parameters of requirements ``ivs`` (all of one case) at the case's own
        values (row 0) and at each slot (one row per slot, the parameters a slot's requirement
        does not vary at the case's values)."""
        names = []
        for j in ivs:
            names += [iv.parameter for iv in self.requirements[j].over if iv.parameter not in names]
        columns = {name: [jnp.reshape(jnp.asarray(params[name], dtype=float), (1,))] for name in names}
        for j in ivs:
            pts = jnp.asarray(inputs.points[self.intervals.indices.index(j)], dtype=float)
            over = [iv.parameter for iv in self.requirements[j].over]
            for name in names:
                col = pts[:, over.index(name)] if name in over else jnp.broadcast_to(
                    jnp.asarray(params[name], dtype=float), (pts.shape[0],))
                columns[name].append(col)
        return {name: jnp.concatenate(parts) for name, parts in columns.items()}

    def row_values(self, values, inputs: DesignInputs, evaluations=None, slots=None) -> jnp.ndarray:
        """The value behind each constraint row in the requirement's unit (:attr:`row_owner`
        order): a point requirement's output, an interval requirement's output at each slot, a
        chance requirement's smoothed quantile. Without ``evaluations`` (and ``slots``) the cases
        are evaluated for :attr:`requirement_outputs` only (:meth:`evaluate_with_slots`)."""
        if evaluations is None:
            evaluations, slots = self.evaluate_with_slots(values, inputs, dict(self.requirement_outputs))
        return self.kinds.row_values(self.parameters(values), evaluations, slots or {}, inputs)

    def requirement_values(self, rows) -> jnp.ndarray:
        """Each requirement's value from its rows (:meth:`row_values`): the worst of them (the
        smallest for ``at_least``, the largest otherwise)."""
        return self.kinds.worst(rows)

    def objective_value(self, values, inputs: DesignInputs, evaluations=None) -> jnp.ndarray:
        """The objective as the spec states it: Σ weight · term (a maximised objective not
        negated). Without ``evaluations`` the cases are evaluated for :attr:`objective_outputs`."""
        if evaluations is None and self.objective_outputs:
            evaluations = self.evaluate(values, self.objective_outputs)
        return self.weighted_terms(self.objective_terms, inputs.weights, values, inputs.cost, evaluations)

    def weighted_terms(self, terms, weights, values, cost, evaluations) -> jnp.ndarray:
        """Σ weight · value over objective terms ``(source, case, base)``: the catalog cost, a
        design variable, a catalog parameter, a case's output (from ``evaluations``) or a fixed
        parameter (from the input vector)."""
        total = jnp.asarray(0.0)
        for k, (source, case, base) in enumerate(terms):
            if source == "cost":
                val = cost
            elif source == "output":
                val = evaluations[case].values[base]
            elif source in ("variable", "combo"):
                val = values[self.layout.index(base)]
            else:
                val = values[self.layout.slot(base, case)]
            total = total + weights[k] * val
        return total

    def evaluation(self, values, inputs: DesignInputs, full: bool = True):
        """``(evaluations, row values, requirement values, objective)``: with ``full`` every
        output of every case (what reports and the explorer show), else each case's budget and
        the outputs the requirements and the objective read (:attr:`requirement_outputs`,
        :attr:`objective_outputs`); the objective as the spec states it."""
        wanted = None if full else self.used_outputs()
        ev, slots = self.evaluate_with_slots(values, inputs, wanted)
        rows = self.row_values(values, inputs, ev, slots)
        return ev, rows, self.requirement_values(rows), self.objective_value(values, inputs, ev)

    def used_outputs(self) -> Dict[str, FrozenSet[str]]:
        """Per case, the outputs the requirements (of every kind: at the case's own values too)
        and the objective read (every case listed)."""
        wanted = {case: frozenset() for case in self.spec.scenes}
        every = self._outputs_by_case((r.case, r.output) for r in self.requirements)
        for source in (every, self.objective_outputs):
            for case, names in source.items():
                wanted[case] = wanted[case] | names
        return wanted

    def design_functions(self, values, inputs: DesignInputs):
        """``(row values, objective)`` for a solve, from one evaluation of the outputs the
        requirements and the objective read (:meth:`evaluate_with_slots`)."""
        wanted = {case: names for case, names in self.used_outputs().items() if names}
        ev, slots = self.evaluate_with_slots(values, inputs, wanted)
        return self.row_values(values, inputs, ev, slots), self.objective_value(values, inputs, ev)

    # --- traced: conveniences at the spec's numbers (notebooks, exploration) -------------------
    def design_vector(self, x, combo):
        """The input vector with design ``x`` and catalog row ``combo`` (its values, then its
        cost), every other entry at the spec's value (traceable in x and combo; the spec's numbers
        are constants of a function traced this way, unlike the compiled programs' inputs)."""
        return self.layout.with_design(self.layout.values, x, jnp.asarray(combo)[:-1])

    def evaluate_at(self, x, combo, wanted: Optional[Mapping[str, FrozenSet[str]]] = None) -> Dict[str, Evaluation]:
        """Each case's evaluation at design ``x`` with catalog row ``combo`` (:meth:`evaluate`)."""
        return self.evaluate(self.design_vector(x, combo), wanted)

    def requirement_values_at(self, x, combo) -> jnp.ndarray:
        """The requirement values at design ``x`` with catalog row ``combo``, each interval
        requirement at the worst points a search finds there (their derivatives by the envelope
        theorem: the points are held while differentiating). Traceable in x and combo."""
        values = self.design_vector(x, combo)
        inputs = self.inputs()._replace(cost=jnp.asarray(combo)[-1])
        if self.intervals.indices:
            found = self.intervals.search(jax.lax.stop_gradient(self.parameters(values)), inputs)
            pts = []
            for j in self.intervals.indices:
                worst = jax.lax.stop_gradient(found[j][1])
                extra = self.intervals.slots(j) - worst.shape[0]
                pts.append(jnp.concatenate([worst, jnp.repeat(worst[:1], extra, axis=0)]))
            inputs = inputs._replace(points=tuple(pts))
        return self.requirement_values(self.row_values(values, inputs))

    def objective_at(self, x, combo) -> jnp.ndarray:
        """The objective as the spec states it at design ``x`` with catalog row ``combo``."""
        inputs = self.inputs()._replace(cost=jnp.asarray(combo)[-1])
        return self.objective_value(self.design_vector(x, combo), inputs)

    # --- traced: the design problem -----------------------------------------------------------
    def solve_values(self, x, s: SolveInputs):
        """The input vector of a solve: ``s``'s vector with the design ``x`` and its catalog row."""
        return self.layout.with_design(s.design.values, x, s.catalog)

    def residuals_and_objective(self, x, s: SolveInputs):
        """(normalised residuals, normalised objective) of a solve at design ``x``: the rows
        s·(v − b)/scale (≤ 0 when an inequality is met, = 0 when an equality is met;
        :attr:`row_owner` order) and the spec's objective, maximisation negated, divided by
        ``s.objective_scale``; one evaluation of the chains."""
        rows, value = self.design_functions(self.solve_values(x, s), s.design)
        owner = self.row_owner
        residuals = jnp.asarray(self.sign[owner]) * (rows - s.limits[owner]) / s.design.scales[owner]
        return residuals, self.spec.objective.sign * value / s.objective_scale

    def residuals(self, x, s: SolveInputs) -> jnp.ndarray:
        """The normalised residuals of :meth:`residuals_and_objective`."""
        return self.residuals_and_objective(x, s)[0]

    def objective(self, x, s: SolveInputs) -> jnp.ndarray:
        """The normalised objective of :meth:`residuals_and_objective`."""
        value = self.objective_value(self.solve_values(x, s), s.design)
        return self.spec.objective.sign * value / s.objective_scale

    # --- host side ----------------------------------------------------------------------------
    @property
    def programs(self):
        """The compiled programs of this model (:class:`~diffsense.design.programs.Programs`)."""
        if self._programs is None:
            from diffsense.design.programs import Programs

            self._programs = Programs(self)
        return self._programs

    def row_multipliers(self, row_lam) -> np.ndarray:
        """Per requirement, the sum of the multipliers of its constraint rows."""
        out = np.zeros(len(self.requirements))
        np.add.at(out, self.row_owner, np.asarray(row_lam, dtype=float))
        return out

    def inequality_multipliers(self, lam) -> np.ndarray:
        """Per requirement, the multipliers of a solve's inequality rows (``lam``, the solver's
        order: the inequality rows of :attr:`row_owner`) summed over each requirement's rows."""
        row_lam = np.zeros(self.row_owner.size)
        ineq = ~self.row_is_equality
        row_lam[ineq] = np.asarray(lam, dtype=float)[: int(ineq.sum())]
        return self.row_multipliers(row_lam)

    def evaluate_all(self, x, combo):
        """``(evaluations, requirement_values, raw_objective)`` at design ``x`` with catalog row
        ``combo`` (its parameter values, then its cost), by the compiled programs: every output
        of every case, interval requirements at the worst points the search finds, and the
        objective in its minimised form (the spec's value times its sign). NumPy results."""
        return self.programs.evaluate_design(x, combo)[:3]

    def requirement_report(self, x, combo, tol: float = 1e-9) -> List[dict]:
        """Requirement rows {name, output, case, value, limit, unit, sense, met, slack}; an
        interval requirement's value is its worst value on the dense re-check."""
        values, checks = self.programs.checked_values(x, combo)
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
            if r.goal is not None:
                row["goal"] = r.goal
                row["goal_status"] = goal_status(r.sense, float(v), r.limit, r.goal, row["met"])
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
