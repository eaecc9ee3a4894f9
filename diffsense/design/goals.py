"""Buying requirement goals in order of cost (``[objective] reach_goals = true``).

A requirement may carry a goal beyond its threshold (``goal = "..."``; PASS / WARN / FAIL,
:func:`diffsense.design.spec.types.goal_status`). With ``reach_goals`` the optimiser first meets
every threshold (:func:`~diffsense.design.optimizer.optimize_design`), then, greedily:

1. every goal not yet met at the current optimum is tried on its own: the requirement's limit
   becomes its goal (the goals bought so far kept), and the design problem is solved again;
2. of the tries that are feasible (every requirement met on the dense re-check), the one whose
   objective is least worse (in the minimised sense) is bought: its goal becomes a limit of the
   problem, its optimum the current one; goals that the new optimum meets on its way are reached
   for free;
3. a goal whose try is infeasible stays out: adding limits only shrinks the feasible set, so it
   cannot become reachable later. Repeat until no goal is left.

With G goals this is at most G (G + 1) / 2 solves; each re-uses the spec's compiled programs (the
limits are inputs of the programs, not part of their structure), so a try costs a warm solve.
The greedy order is the cheapest-first rule of a trade-off that buys objectives one at a time; it
is not the cheapest subset (which would take 2^G solves) — the record lists each goal's price at
the moment it was bought.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Callable, List, Optional

import numpy as np

from diffsense.design.activity import design_findings
from diffsense.design.model import DesignModel
from diffsense.design.record import design_record
from diffsense.design.spec.types import goal_status

__all__ = ["GoalPlan", "with_goals", "goal_statuses", "buy_goals", "optimize_with_goals", "plan_record", "plan_lines",
           "solved_findings"]


@dataclass
class GoalPlan:
    """The outcome of :func:`buy_goals`: the final model (limits raised to the goals bought) and its
    optimum, and per goal what happened, in order."""

    model: DesignModel
    optimum: object  # DesignOptimum
    #: goals bought, cheapest first: {name, goal, unit, objective_before, objective_after}
    bought: List[dict] = field(default_factory=list)
    #: goals met by the optimum without being asked for (at the thresholds, or on the way)
    free: List[str] = field(default_factory=list)
    #: goals no feasible design reaches together with those bought before them
    unreachable: List[str] = field(default_factory=list)
    #: design problems solved after the thresholds' optimum
    solves: int = 0


def with_goals(model: DesignModel, indices) -> DesignModel:
    """A model of the same spec with the limits of requirements ``indices`` raised to their goals
    (the same structure: it shares the spec's compiled programs)."""
    reqs = [dataclasses.replace(r, limit=r.goal) if j in indices else r for j, r in enumerate(model.spec.requirements)]
    return DesignModel(dataclasses.replace(model.spec, requirements=reqs))


def goal_statuses(model: DesignModel, optimum) -> List[Optional[str]]:
    """PASS / WARN / FAIL of each requirement's goal at ``optimum`` (None without a goal), from the
    requirement report (dense re-check of interval requirements included) against the spec's own
    thresholds and goals."""
    rows = model.programs.reports(np.asarray(optimum.x)[None, :], np.array([optimum.combo_index]))[0]
    out = []
    for r, row in zip(model.spec.requirements, rows):
        out.append(None if r.goal is None else goal_status(r.sense, row["value"], r.limit, r.goal, row["met"]))
    return out


def buy_goals(model: DesignModel, optimum, solve: Callable[[DesignModel], object]) -> GoalPlan:
    """Raise the requirements of ``model`` to their goals, cheapest first (module docstring).

    ``optimum``: the thresholds' optimum of ``model`` (feasible); ``solve(model) -> optimum``: the
    optimiser, called once per try."""
    spec = model.spec
    sign = spec.objective.sign  # +1 minimise, -1 maximise: sign * objective is minimised
    statuses = goal_statuses(model, optimum)
    plan = GoalPlan(model, optimum)
    plan.free = [spec.requirements[j].name for j, s in enumerate(statuses) if s == "PASS"]
    pending = [j for j, s in enumerate(statuses) if s is not None and s != "PASS"]
    chosen: List[int] = []
    while pending:
        tries = {}
        for j in pending:
            trial = with_goals(model, set(chosen) | {j})
            result = solve(trial)
            plan.solves += 1
            if result.feasible:
                tries[j] = (trial, result)
        for j in pending:
            if j not in tries:
                plan.unreachable.append(spec.requirements[j].name)
        if not tries:
            break
        j_best = min(tries, key=lambda j: sign * tries[j][1].objective)
        trial, result = tries[j_best]
        r = spec.requirements[j_best]
        plan.bought.append({"name": r.name, "goal": r.goal, "unit": r.unit,
                            "objective_before": plan.optimum.objective, "objective_after": result.objective})
        chosen.append(j_best)
        plan.model, plan.optimum = trial, result
        now = goal_statuses(model, result)  # against the spec's own thresholds and goals
        for j in tries:
            if j != j_best and now[j] == "PASS":
                plan.free.append(spec.requirements[j].name)
        pending = [j for j in tries if j != j_best and now[j] != "PASS"]
    return plan


def optimize_with_goals(model: DesignModel, *, n_starts: int = 8, seed: int = 0):
    """``(optimum, plan)``: :func:`~diffsense.design.optimizer.optimize_design`, then, when the spec
    asks for ``reach_goals`` and the thresholds can be met, :func:`buy_goals` with the same
    settings (``plan`` None otherwise). The optimum is that of the last goal bought."""
    from diffsense.design.optimizer import optimize_design

    result = optimize_design(model, n_starts=n_starts, seed=seed)
    if not model.spec.objective.reach_goals or not result.feasible:
        return result, None
    plan = buy_goals(model, result, lambda m: optimize_design(m, n_starts=n_starts, seed=seed))
    return plan.optimum, plan


def plan_record(plan: GoalPlan) -> dict:
    """The plan as plain data (the JSON record's and the report's ``goals``)."""
    return {"bought": plan.bought, "free": plan.free, "unreachable": plan.unreachable, "solves": plan.solves}


def plan_lines(plan: dict, objective_text: str) -> List[str]:
    """One sentence per goal: bought (with the objective before and after), met without being
    asked for, or not reachable."""
    lines = []
    for k, b in enumerate(plan["bought"], 1):
        lines.append(f"goal {k} bought: {b['name']!r} to {b['goal']:.6g} {b['unit']}: {objective_text} "
                     f"{b['objective_before']:.6g} -> {b['objective_after']:.6g}")
    lines += [f"goal met without asking: {name!r}" for name in plan["free"]]
    lines += [f"goal not reachable with those bought before it: {name!r}" for name in plan["unreachable"]]
    return lines


def solved_findings(model: DesignModel, plan: Optional[GoalPlan], x, combo_index: int, rows, multipliers) -> dict:
    """What sets the design at ``x``, against the limits it was solved for: ``model``'s with its
    requirement ``rows``, or with goals bought (``plan``) the goals, whose rows are evaluated here."""
    if plan is None:
        return design_findings(model, x, combo_index, rows, multipliers)
    solved_rows = design_record(plan.model, x, combo_index)["requirements"]
    return design_findings(plan.model, x, combo_index, solved_rows, multipliers)
