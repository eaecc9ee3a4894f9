"""Trade studies: the Pareto front of a spec's ``[trade]`` objectives.

:func:`trade_design` traces, for every catalog combination, the front of the objectives over
the designs that meet every requirement by ε-constraint continuation
(:func:`diffsense.optimize.continuation.trace_front`: anchors, then points evenly spaced in
the bounded objectives, each warm-started from its neighbour with the post-optimal tangent as
predictor; integer variables rounded to their best feasible neighbour as in
:func:`diffsense.design.optimizer.optimize_design`). The requirement limits are tightened by
``margin`` (scaled units) as ``optimize`` does. Each point is then re-evaluated exactly
(:meth:`DesignModel.evaluate_all` at the returned design): points the solver did not converge
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

import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.design.optimizer import build_problem, tight_limits
from diffsense.design.record import design_table
from diffsense.design.spec import Objective, Spec
from diffsense.errors import SpecError
from diffsense.optimize import Problem, SolverOptions
from diffsense.optimize.bounds import variables_on_bounds
from diffsense.optimize.continuation import knee_index, pareto_mask, trace_front

#: a requirement whose slack is within this (scaled units) of zero is active
ACTIVE_SLACK = 1e-6


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
    """The trade objectives of a model as pure functions of (design x, catalog row)."""

    def __init__(self, model: DesignModel, objectives):
        self.model = model
        self.objectives = tuple(objectives)
        self.terms = [[model.objective_term(name) + (weight,) for name, weight in o.terms] for o in self.objectives]
        wanted: Dict[str, set] = {}
        for source, case, base, _ in (t for ts in self.terms for t in ts):
            if source == "output":
                wanted.setdefault(case, set()).add(base)
        self.wanted = {case: frozenset(v) for case, v in wanted.items()}
        self.signs = np.array([o.sign for o in self.objectives])

    def values(self, x, combo, evaluations=None):
        """The objectives in their own sense (maximised ones not negated), shape (K,)."""
        m = self.model
        ev = evaluations
        if ev is None and self.wanted:
            ev = m.evaluate(x, combo, self.wanted)
        return jnp.stack([m.weighted_terms(terms, x, combo, ev) for terms in self.terms])

    def minimised(self, x, combo):
        """The objectives as minimised (maximised ones negated), shape (K,)."""
        return self.values(x, combo) * jnp.asarray(self.signs)


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


def _problem(model: DesignModel) -> Problem:
    """The design problem with θ = (catalog row, limits) (floating leaves only)."""
    base = build_problem(model)
    pin = jnp.zeros(len(model.variable_names), dtype=bool)

    def wrap(fn):
        return None if fn is None else (lambda x, th: fn(x, (th[0], th[1], x, pin)))

    return Problem(wrap(base.objective), model.lower, model.upper, inequality=wrap(base.inequality),
                   equality=wrap(base.equality), log_scale=model.log_scale, integer=model.integer,
                   names=list(model.variable_names))


#: per model: the trade problem and objective functions, the same objects on every call so
#: that :func:`diffsense.optimize.continuation.step_program` compiles them once
_FUNCTIONS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _functions(model: DesignModel):
    """(problem, :class:`TradeObjectives`, minimised objectives of (x, θ)) of ``model``, built
    once per model."""
    hit = _FUNCTIONS.get(model)
    if hit is None or hit[1].objectives != tuple(model.spec.trade.objectives):
        objectives = TradeObjectives(model, model.spec.trade.objectives)
        hit = (_problem(model), objectives, lambda x, th: objectives.minimised(x, th[0]))
        _FUNCTIONS[model] = hit
    return hit


def _point(model: DesignModel, objectives: TradeObjectives, x, combo_index: int, lam, kkt: float,
           converged: bool, anchor: int) -> dict:
    """The exact re-evaluation of one solved point as a record."""
    combo = model.combo_table[combo_index]
    ev, req_values, _ = model.evaluate_all(x, combo)
    F = np.asarray(objectives.values(jnp.asarray(x), jnp.asarray(combo), ev), dtype=float)
    rows = model.requirement_rows(req_values)
    full_lam = np.zeros(len(model.requirements))
    full_lam[~model.is_equality] = lam[: int((~model.is_equality).sum())]
    active = [r["name"] for r, lm, s, eq in zip(rows, full_lam, model.scales, model.is_equality)
              if eq or lm > 0.0 or abs(r["slack"]) <= ACTIVE_SLACK * s]
    on_lo, on_hi = variables_on_bounds(_problem_bounds(model), x)
    bounds = [f"{n} at its lower bound" for n, b in zip(model.variable_names, on_lo) if b]
    bounds += [f"{n} at its upper bound" for n, b in zip(model.variable_names, on_hi) if b]
    return {"F": F, "x": np.asarray(x, float), "combo_index": int(combo_index), "met": all(r["met"] for r in rows),
            "converged": bool(converged), "kkt_residual": float(kkt), "active": active, "on_bounds": bounds,
            "anchor": int(anchor), "requirements": rows}


def _problem_bounds(model: DesignModel) -> Problem:
    return Problem(lambda x, _: x[0], model.lower, model.upper, log_scale=model.log_scale)


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
    limits = np.broadcast_to(tight_limits(model, margin), (C, len(model.requirements))).copy()
    thetas = (model.combo_table.copy(), limits)
    front = trace_front(problem, minimised, thetas,
                        np.tile(model.initial, (C, 1)), points=points or trade.points,
                        options=options or SolverOptions(), lockstep=lockstep)
    recs = [_point(model, objectives, front.x[i], int(front.group[i]), front.lam[i], front.kkt_residual[i],
                   bool(front.converged[i] and front.feasible[i]), int(front.anchor[i]))
            for i in range(front.x.shape[0])]
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
           "objective_unit", "stretches", "ACTIVE_SLACK"]
