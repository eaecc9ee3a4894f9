"""Trade studies: the Pareto front of a spec's ``[trade]`` objectives.

:func:`trade_design` traces, for every catalog combination, the front of the objectives over
the designs that meet every requirement by ε-constraint continuation
(:func:`diffsense.optimize.continuation.trace_front`: anchors, then points evenly spaced in
the bounded objectives, each warm-started from its neighbour with the post-optimal tangent as
predictor; integer variables rounded to their best feasible neighbour as in
:func:`diffsense.design.optimizer.optimize_design`). The requirement limits are tightened by
``margin`` (scaled units) as ``optimize`` does. Each point is then re-evaluated exactly
(the model's evaluation program at the returned design, its interval requirements re-checked
densely): points the solver did not converge
on or that miss a requirement are dropped and counted, and so are the points another
combination's point dominates; the non-dominated union is the front.

Along the front (sorted by the first objective) each point lists the requirements that are
active (met with zero slack, or carrying a multiplier) and the variables on a bound; runs of
points with the same active set are the front's *stretches*.
"""

from __future__ import annotations

import dataclasses
import time
import weakref
from dataclasses import dataclass
from typing import Dict, List, Optional, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.activity import active_names
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import tight_limits
from diffsense.design.problem import requirement_problem
from diffsense.design.programs import rows_of, stack
from diffsense.design.record import design_table
from diffsense.design.runner import bounds_problem, objective_scale
from diffsense.design.spec import Objective, Spec
from diffsense.errors import SpecError
from diffsense.optimize import SolverOptions
from diffsense.optimize.bounds import variables_on_bounds
from diffsense.optimize.continuation import knee_index, pareto_mask, trace_front


def trade_spec(spec: Spec) -> Spec:
    """``spec`` with the parameters its ``[trade]`` section frees added to the variables; raise
    :class:`SpecError` when it has no ``[trade]`` section."""
    if spec.trade is None:
        raise SpecError(spec.path, "trade", "missing: add a [trade] table with objectives = [...]")
    return dataclasses.replace(spec, variables={**spec.variables, **spec.trade.variables})


def objective_label(objective: Objective) -> str:
    """A short name of a trade objective: its term for a single unweighted term, else its text."""
    if len(objective.terms) == 1 and objective.terms[0][1] == 1.0:
        return objective.terms[0][0]
    return objective.text


def objective_unit(model: DesignModel, objective: Objective) -> str:
    """The unit of a single-term objective ("1" for cost, "" for a weighted sum)."""
    if len(objective.terms) != 1 or objective.terms[0][1] != 1.0:
        return ""
    source, case, base = model.objective_term(objective.terms[0][0])
    return "1" if source == "cost" else model.spec.unit_of(case, base)


class TradeObjectives:
    """The trade objectives of a model as pure functions of (design x, θ of a solve)."""

    def __init__(self, model: DesignModel, objectives):
        self.model = model
        self.objectives = tuple(objectives)
        self.terms = [[model.objective_term(name) for name, _ in o.terms] for o in self.objectives]
        self.weights = [np.array([w for _, w in o.terms], dtype=float) for o in self.objectives]
        wanted: Dict[str, set] = {}
        for source, case, base in (t for ts in self.terms for t in ts):
            if source == "output":
                wanted.setdefault(case, set()).add(base)
        self.wanted = {case: frozenset(v) for case, v in wanted.items()}
        self.signs = np.array([o.sign for o in self.objectives])

    def values_at(self, values, cost, evaluations=None):
        """The objectives in their own sense (maximised ones not negated), shape (K,), at input
        vector ``values`` with catalog ``cost``."""
        m = self.model
        ev = evaluations
        if ev is None and self.wanted:
            ev = m.evaluate(values, self.wanted)
        return jnp.stack([m.weighted_terms(terms, w, values, cost, ev) for terms, w in zip(self.terms, self.weights)])

    def minimised(self, x, s):
        """The objectives as minimised (maximised ones negated), shape (K,), of a solve's θ."""
        return self.values_at(self.model.solve_values(x, s), s.design.cost) * jnp.asarray(self.signs)

    def host_values(self, values, cost, evaluation) -> np.ndarray:
        """The objectives (NumPy) from an evaluation already computed (its outputs, NumPy)."""
        m = self.model
        out = []
        for terms, w in zip(self.terms, self.weights):
            total = 0.0
            for k, (source, case, base) in enumerate(terms):
                if source == "cost":
                    val = cost
                elif source == "output":
                    val = evaluation[case].values[base]
                elif source in ("variable", "combo"):
                    val = values[m.layout.index(base)]
                else:
                    val = values[m.layout.slot(base, case)]
                total += w[k] * float(np.asarray(val))
            out.append(total)
        return np.array(out)


def check_trade_objectives(model: DesignModel, where, V, evaluations) -> None:
    """Raise :class:`SpecError` for a trade objective that is not finite, or has one value, at
    every point of :func:`diffsense.design.evaluable.check_evaluable` (the initial design and the
    box corners of every catalog combination checked; ``where``, ``V``, ``evaluations`` its
    return): a constant objective adds nothing to a front. Costs enter as 0: an objective with
    a catalog cost is never constant (:func:`diffsense.design.spec.trade.check_trade`)."""
    objectives = TradeObjectives(model, model.spec.trade.objectives)
    rows = [objectives.host_values(V[i], 0.0, jax.tree_util.tree_map(lambda a, i=i: np.asarray(a)[i], evaluations))
            for i in range(V.shape[0])]
    F = np.asarray(rows, dtype=float)
    for k, o in enumerate(objectives.objectives):
        key = f"trade.objectives[{k}]"
        bad = np.flatnonzero(~np.isfinite(F[:, k]))
        if bad.size:
            raise SpecError(model.spec.path, key, f"{o.text} is {F[bad[0], k]:g} at {where[bad[0]]}: "
                            "its weights overflow the numbers; rescale them")
        has_cost = any(name == "cost" for name, _ in o.terms)
        spread = np.ptp(F[:, k])
        if not has_cost and spread <= 1e-12 * max(1.0, float(np.max(np.abs(F[:, k])))):
            raise SpecError(model.spec.path, key, f"constant: {o.text} is {F[0, k]:g} at the initial design and at "
                            "every corner of the variables' box, so it adds nothing to a front")


@dataclass
class TradeResult:
    """Outcome of :func:`trade_design`: ``points`` are the front's records (sorted by the first
    objective), ``dropped`` counts the points left out, ``knee`` indexes ``points``."""

    model: DesignModel
    labels: List[str]
    units: List[str]
    objectives: List[Objective]
    points: List[dict]
    knee: Optional[int]
    dropped: Dict[str, int]
    stretches: List[dict]
    solves: int
    trips: int
    seconds: float


#: per model: the trade problem and objective functions, the same objects on every call so
#: that :func:`diffsense.optimize.continuation.step_program` compiles them once
_FUNCTIONS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _functions(model: DesignModel):
    """(problem, :class:`TradeObjectives`, minimised objectives of (x, θ)) of ``model``, built
    once per model."""
    hit = _FUNCTIONS.get(model)
    if hit is None or hit[1].objectives != tuple(model.spec.trade.objectives):
        objectives = TradeObjectives(model, model.spec.trade.objectives)
        hit = (requirement_problem(model), objectives, objectives.minimised)
        _FUNCTIONS[model] = hit
    return hit


def _points(model: DesignModel, objectives: TradeObjectives, front, limits) -> List[dict]:
    """The exact re-evaluation of every solved point as a record (one batched call of the
    model's evaluation program, then each point's dense re-check)."""
    assessed = model.programs.assess(front.x, front.group)
    out = []
    bounds_problem_ = bounds_problem(model)
    for i, (ev, rows, _) in enumerate(assessed):
        c = int(front.group[i])
        values = model.design_values(front.x[i], c)
        F = objectives.host_values(values, float(model.combo_table[c, -1]), ev)
        active = active_names(model, rows, model.inequality_multipliers(front.lam[i]))
        on_lo, on_hi = variables_on_bounds(bounds_problem_, front.x[i])
        bounds = [f"{n} at its lower bound" for n, b in zip(model.variable_names, on_lo) if b]
        bounds += [f"{n} at its upper bound" for n, b in zip(model.variable_names, on_hi) if b]
        out.append({"F": F, "x": np.asarray(front.x[i], float), "combo_index": c,
                    "met": all(r["met"] for r in rows),
                    "converged": bool(front.converged[i] and front.feasible[i]),
                    "kkt_residual": float(front.kkt_residual[i]), "active": active, "on_bounds": bounds,
                    "anchor": int(front.anchor[i]), "requirements": rows})
    return out


def _row(evaluation, i: int):
    """Row ``i`` of a batched evaluation (NumPy)."""
    import jax

    return jax.tree_util.tree_map(lambda a: np.asarray(a)[i], evaluation)


def stretches(points: List[dict], labels: List[str]) -> List[dict]:
    """Runs of consecutive points with the same active requirements and bounds."""
    out = []
    for i, p in enumerate(points):
        key = (tuple(p["active"]), tuple(p["on_bounds"]))
        if out and out[-1]["key"] == key:
            out[-1]["last"] = i
        else:
            out.append({"key": key, "first": i, "last": i})
    return [{"active": list(s["key"][0]), "on_bounds": list(s["key"][1]), "first": s["first"], "last": s["last"],
             "points": s["last"] - s["first"] + 1,
             "from": dict(zip(labels, map(float, points[s["first"]]["F"]))),
             "to": dict(zip(labels, map(float, points[s["last"]]["F"])))} for s in out]


def trade_design(model: DesignModel, *, points: Optional[int] = None, margin: float = 1e-7,
                 options: Optional[SolverOptions] = None,
                 lockstep: Union[int, str, None] = "auto") -> TradeResult:
    """The Pareto front of ``model.spec.trade`` (module docstring). ``model`` must be built
    from :func:`trade_spec` of the spec (so the freed parameters are variables); ``points``
    overrides the section's count."""
    t0 = time.perf_counter()
    trade = model.spec.trade
    if trade is None:
        raise SpecError(model.spec.path, "trade", "missing: add a [trade] table with objectives = [...]")
    problem, objectives, minimised = _functions(model)
    C = len(model.combinations)
    limits = tight_limits(model, margin)
    # each combination's θ, its interval slots at the worst points of its initial design
    _, designs = model.programs.design_inputs(np.tile(model.initial, (C, 1)), np.arange(C))
    thetas = stack([model.solve_inputs(rows_of(designs, c), c, limits, objective_scale(model)) for c in range(C)])

    def values(x, groups):
        """The objectives (minimised) at solved points, by the model's evaluation program."""
        x = np.atleast_2d(x)
        V = np.stack([model.design_values(xi, int(c)) for xi, c in zip(x, groups)])
        ev = model.programs.values_rows(V, per_row_inputs=stack([rows_of(designs, int(c)) for c in groups]))[0]
        return np.array([objectives.host_values(V[i], float(model.combo_table[int(c), -1]),
                                                {k: _row(e, i) for k, e in ev.items()}) * objectives.signs
                         for i, c in enumerate(groups)])

    # the step program depends on the model's structure and on the trade objectives (their
    # weights are constants of it): traced once per such structure, kept on disk
    structure = repr((model.structure(), [(t, list(w), o.sign) for t, w, o in
                                          zip(objectives.terms, objectives.weights, objectives.objectives)]))
    front = trace_front(problem, minimised, thetas,
                        np.tile(model.initial, (C, 1)), points=points or trade.points,
                        options=options or SolverOptions(), lockstep=lockstep, values=values, structure=structure)
    recs = _points(model, objectives, front, limits)
    good = [r for r in recs if r["converged"] and r["met"]]
    dropped = {"unconverged": sum(not r["converged"] for r in recs),
               "unmet": sum(r["converged"] and not r["met"] for r in recs)}
    if good:
        keep = pareto_mask(np.array([r["F"] * objectives.signs for r in good]))
        dropped["dominated"] = int((~keep).sum())
        good = sorted([r for r, k in zip(good, keep) if k], key=lambda r: tuple(r["F"] * objectives.signs))
    else:
        dropped["dominated"] = 0
    labels = [objective_label(o) for o in trade.objectives]
    knee = knee_index(np.array([r["F"] * objectives.signs for r in good])) if len(good) >= 3 else None
    return TradeResult(model, labels, [objective_unit(model, o) for o in trade.objectives], list(trade.objectives),
                       good, knee, dropped, stretches(good, labels), int(front.x.shape[0]), front.trips,
                       time.perf_counter() - t0)


def trade_record(result: TradeResult) -> dict:
    """JSON-ready record of a trade study: ``front`` (each point's objectives, design — as in
    ``optimize --json`` —, catalog options, convergence, KKT residual, active requirements),
    the anchors and knee, the dropped counts and the stretches."""
    model = result.model
    spec = model.spec
    front = []
    for i, p in enumerate(result.points):
        front.append({
            "objectives": dict(zip(result.labels, map(float, p["F"]))),
            "design": design_table(model, p["x"], p["combo_index"]),
            "choices": dict(model.combinations[p["combo_index"]].options),
            "converged": p["converged"], "kkt_residual": p["kkt_residual"],
            "active_requirements": p["active"], "on_bounds": p["on_bounds"],
            "anchor_of": result.labels[p["anchor"]] if p["anchor"] >= 0 else None,
            "knee": i == result.knee,
        })
    return {"name": spec.name, "title": spec.title, "sensor": spec.sensor,
            "objectives": [{"name": lab, "text": o.text, "unit": u, "sense": "minimize" if o.sign > 0 else "maximize"}
                           for lab, o, u in zip(result.labels, result.objectives, result.units)],
            "front": front, "knee": result.knee, "dropped": result.dropped,
            "stretches": result.stretches, "solves": result.solves, "solver_trips": result.trips,
            "time_s": result.seconds}


__all__ = ["trade_spec", "trade_design", "trade_record", "TradeObjectives", "TradeResult", "objective_label",
           "objective_unit", "stretches"]
