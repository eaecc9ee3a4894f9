"""Optimise a requirement spec: catalog choices, integer relaxation and multi-start.

Steps (every solve a lane of one compiled program, :meth:`Programs.lanes`):

1. **Continuous relaxation.** For every catalog combination and every start (the spec's
   initial design plus seeded Latin-hypercube points in the scaled box), minimise the
   normalised objective subject to the requirements with the augmented Lagrangian (bounds
   never violated). The requirements are tightened by a small ``margin`` (scaled units) so
   that the answer meets them when re-evaluated, not only to the solver's tolerance. The best
   start of each combination goes on (:func:`diffsense.optimize.lanes.best_per_group`).
2. **Integers.** Integer variables of the best relaxed answer of each combination are rounded
   to their floor/ceil neighbours and the continuous rest is re-solved with the integers
   pinned (:func:`diffsense.optimize.integer.integer_neighbours`); the best feasible
   neighbour is kept (neighbour verification), or the rounded relaxed answer when none is
   feasible.
3. **Near misses.** Each answer is re-evaluated exactly. The solver's feasibility tolerance
   applies to its internally scaled constraints, so an answer may miss a requirement by
   slightly more than ``margin``; such near misses are re-solved from where they stand with
   those limits tightened by ten times the miss, up to three times. An answer that meets every
   requirement but stopped short of a tightened limit (by more than :data:`FINISH_TOL`, within
   the solver's feasibility tolerance) is re-solved from where it stands too when the solver
   polishes (``SolverOptions.polish``), so that the margin it reports is the one asked for.
4. **Choice.** The feasible combination with the lowest objective wins. When no combination is
   feasible the least-infeasible answer is returned with ``feasible`` False and the
   requirements it leaves unmet.
5. **Canonical point.** When the optimum is not unique (flat directions of the optimal set),
   the most robust design of the optimal set is returned instead of an arbitrary one
   (:mod:`diffsense.design.canonical`), and ``canonical`` says so.

Requirements over intervals (:mod:`diffsense.design.intervals`) are solved by the exchange
method: every lane starts with the worst points a search finds at its start; after each solve
the search looks again at the answer, and a lane whose answer misses a worse point than its
slots hold is solved again from there with the new points (up to :data:`SEARCH_ROUNDS` times).
Step 3b: a worse point found by the dense re-check joins the slots and the answers are re-solved.

**One program.** Every step's lanes — relaxation, neighbours, near misses, exchange rounds,
the canonical stage and the linearisations it needs — go through the same compiled lane
program, in calls of a fixed number of lanes (:func:`lane_batch`; the last call padded), with
everything that differs between steps (catalog row, limits, slots, boxes, the stage) passed as
data (:class:`~diffsense.design.inputs.SolveInputs`). The programs compile in background
threads while this one traces the next.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, NamedTuple, Optional, Union

import numpy as np

from diffsense.design.canonical import canonical_optimum
from diffsense.design.model import DesignModel
from diffsense.design.programs import rows_of, stack, with_extra_point
from diffsense.design.runner import Lanes, Runner, bounds_problem, objective_scale
from diffsense.optimize import SolverOptions
from diffsense.optimize.integer import integer_neighbours
from diffsense.optimize.lanes import best_per_group, pin_variables
from diffsense.optimize.multistart import start_points


@dataclass
class DesignOptimum:
    """Outcome of :func:`optimize_design`."""

    x: np.ndarray  # design variables (their units)
    combo_index: int
    objective: float  # spec's own objective value (minimised or maximised as stated)
    converged: bool
    feasible: bool
    multipliers: np.ndarray  # per requirement (normalised objective per scaled residual)
    starts: int
    starts_converged: int
    starts_at_best: int
    unmet: List[str]
    candidates: List[dict]  # per combination: options, objective, feasible
    canonical: Optional[dict] = None  # the second stage's choice when the optimum is not unique


def tight_limits(model: DesignModel, margin: float) -> np.ndarray:
    """The requirement limits with each inequality moved inward by ``margin`` (scaled units:
    ``margin`` × the requirement's scale): an at_least limit up, an at_most limit down, an
    equality unchanged; the limits the solver is given so that a converged design meets the
    requirements with that margin to spare."""
    return model.limits - model.sign * margin * model.scales * (~model.is_equality)


_tight_limits = tight_limits  # former private name

#: an answer meeting every requirement is finished (re-solved from where it stands) when it
#: misses a tightened limit by more than this (scaled units)
FINISH_TOL = 1e-10


class _Answers(NamedTuple):
    """The current answer of each catalog combination (rows: combinations) and its θ."""

    x: np.ndarray
    converged: np.ndarray
    lam: np.ndarray
    theta: object


def _starts(model: DesignModel, n_starts: int, seed: int) -> np.ndarray:
    """The spec's initial design and n_starts − 1 seeded Latin-hypercube points."""
    starts = model.initial[None, :]
    if n_starts > 1:
        starts = np.vstack([starts, start_points(bounds_problem(model), n_starts - 1, seed=seed, method="lhs")])
    return starts


def _thetas(model: DesignModel, base, combos, limits, objective_scale: float):
    """θ of lanes of catalog combinations ``combos`` (a batch of :class:`SolveInputs`)."""
    limits = np.broadcast_to(limits, (len(combos), len(model.requirements)))
    return stack([model.solve_inputs(base, int(c), limits[i], objective_scale) for i, c in enumerate(combos)])


def _relax(model: DesignModel, run: Runner, starts, base, limits, objective_scale):
    """Step 1: every (start, combination) lane, start-major; returns (lanes, results, answers)."""
    C = len(model.combinations)
    x0 = np.repeat(starts, C, axis=0)
    combos = np.tile(np.arange(C), starts.shape[0])
    lower, upper = run.boxes(n=x0.shape[0])
    theta = _thetas(model, base, combos, limits, objective_scale)
    theta, _ = run.search_points(x0, theta, combos)
    lanes, res = run.settle(Lanes(x0, theta, lower, upper, combos))
    rows, _ = best_per_group(res, combos, C)
    return lanes, res, _Answers(res.x[rows].copy(), res.converged[rows].copy(), res.lam[rows].copy(),
                                rows_of(lanes.theta, rows))


def _round_integers(model: DesignModel, run: Runner, best: _Answers) -> _Answers:
    """Step 2: the best feasible integer neighbour of each combination's answer, or the answer
    with its integers rounded when no neighbour is feasible."""
    if not model.integer.any():
        return best
    cand = integer_neighbours(bounds_problem(model), best.x)
    lower, upper = run.boxes(cand.lower, cand.upper, n=cand.x0.shape[0])
    lanes = Lanes(cand.x0, rows_of(best.theta, cand.group), lower, upper, cand.group)
    lanes, res = run.settle(lanes)
    rows, found = best_per_group(res, cand.group, len(model.combinations))
    x, conv, lam = best.x.copy(), best.converged.copy(), best.lam.copy()
    x[found], conv[found], lam[found] = res.x[rows[found]], res.converged[rows[found]], res.lam[rows[found]]
    x[~found] = np.where(model.integer, np.round(x[~found]), x[~found])
    theta = stack([rows_of(lanes.theta, rows[c]) if found[c] else rows_of(best.theta, c)
                   for c in range(len(model.combinations))])
    return _Answers(x, conv, lam, theta)


def _scaled_misses(model: DesignModel, report) -> np.ndarray:
    """Per requirement, by how much (scaled units) a requirement report misses it; 0 when met."""
    return np.array([max(-r["slack"], 0.0) / scale for r, scale in zip(report, model.scales)])


def _tight_misses(model: DesignModel, limits, report) -> np.ndarray:
    """Per inequality requirement, by how much (scaled units) a report misses its tightened
    limit (``limits``, :func:`tight_limits`); 0 when met or an equality."""
    values = np.array([r["value"] for r in report], dtype=float)
    miss = model.sign * (values - limits) / model.scales
    return np.where(model.is_equality, 0.0, np.maximum(miss, 0.0))


def _resolve_near_misses(model: DesignModel, run: Runner, limits, best: _Answers, reports):
    """Step 3: re-solve, from where they stand with integers pinned, answers that miss a
    requirement by at most 1e-3 (scaled; the missed limits tightened by ten times the miss) or
    that meet every requirement but miss a tightened limit by more than :data:`FINISH_TOL`
    (same limits, with the polish on: the solver stopped at its feasibility tolerance; from
    there it polishes onto the limit); keep a re-solve that misses less — the requirements first, then the tightened
    limits. Returns the answers and their requirement reports."""
    x, conv, lam = best.x.copy(), best.converged.copy(), best.lam.copy()
    thetas = [rows_of(best.theta, c) for c in range(x.shape[0])]

    def misses(rep):
        return _scaled_misses(model, rep).sum(), _tight_misses(model, limits, rep).sum()

    for _ in range(3):
        miss = np.array([_scaled_misses(model, rep) for rep in reports])
        tight = np.array([_tight_misses(model, limits, rep).max(initial=0.0) for rep in reports])
        worst = miss.max(axis=1, initial=0.0)
        unfinished = (worst == 0) & (tight > FINISH_TOL) & run.options.polish
        near = np.flatnonzero(((worst > 0) & (worst <= 1e-3)) | unfinished)
        if near.size == 0:
            break
        tighter = limits[None, :] - model.sign * (10.0 * miss[near]) * model.scales * (~model.is_equality)
        lo, hi = pin_variables(model.lower, model.upper, x[near], model.integer)
        lower, upper = run.boxes(lo, hi, n=near.size)
        th = stack([thetas[c] for c in near])._replace(limits=tighter)
        lanes, res = run.settle(Lanes(x[near], th, lower, upper, near))
        new_reports = model.programs.reports(res.x, near)
        for k, c in enumerate(near):
            if misses(new_reports[k]) < misses(reports[c]):
                x[c], reports[c], conv[c], lam[c] = res.x[k], new_reports[k], res.converged[k], res.lam[k]
                thetas[c] = rows_of(lanes.theta, k)._replace(limits=np.asarray(limits))
    return _Answers(x, conv, lam, stack(thetas)), reports


def _missed_points(model: DesignModel, reports) -> dict:
    """Exchange candidates: per (combination, interval requirement) whose dense re-check found a
    value worse than the search's by more than 1e-9 (scaled), the point where it lies."""
    found = {}
    for c, rep in enumerate(reports):
        for j, row in enumerate(rep):
            if "search_value" not in row:
                continue
            worse = model.sign[j] * (row["value"] - row["search_value"]) / model.scales[j]
            if worse > 1e-9:
                found[(c, j)] = np.array([row["worst_at"][iv.parameter] for iv in model.requirements[j].over])
    return found


def _exchange(model: DesignModel, run: Runner, limits, best: _Answers, reports, rounds: int = 2):
    """Step 3b (exchange method for the interval requirements; Hettich & Kortanek 1993 §7): a
    point the dense re-check finds worse than the search's joins that combination's slots and
    every combination with one is re-solved from its answer, integers pinned; a re-solve is
    kept if it misses less."""
    for _ in range(rounds):
        missed = _missed_points(model, reports)
        if not missed:
            break
        theta = best.theta
        designs = [rows_of(theta.design, c) for c in range(best.x.shape[0])]
        for (c, j), point in missed.items():
            designs[c] = with_extra_point(model, designs[c], j, point)
        theta = theta._replace(design=stack(designs))
        redo = np.array(sorted({c for c, _ in missed}))
        lo, hi = pin_variables(model.lower, model.upper, best.x[redo], model.integer)
        lower, upper = run.boxes(lo, hi, n=redo.size)
        lanes, res = run.settle(Lanes(best.x[redo], rows_of(theta, redo), lower, upper, redo))
        new_reports = model.programs.reports(res.x, redo)
        x, conv, lam = best.x.copy(), best.converged.copy(), best.lam.copy()
        kept = [rows_of(theta, c) for c in range(best.x.shape[0])]
        for k, c in enumerate(redo):
            kept[c] = rows_of(lanes.theta, k)
            if _scaled_misses(model, new_reports[k]).sum() <= _scaled_misses(model, reports[c]).sum():
                x[c], reports[c], conv[c], lam[c] = res.x[k], new_reports[k], res.converged[k], res.lam[k]
        best = _Answers(x, conv, lam, stack(kept))
        best, reports = _resolve_near_misses(model, run, limits, best, reports)
    return best, reports


def _start_statistics(relaxed, combos, combo: int):
    """(starts converged, starts at the best objective) of one combination's relaxed lanes."""
    mine = combos == combo
    f = relaxed.f[mine]
    ok = relaxed.feasible[mine] & relaxed.converged[mine]
    best_f = np.min(np.where(ok, f, np.inf)) if ok.any() else np.inf
    at_best = int(np.sum(ok & (np.abs(f - best_f) <= 1e-6 * max(abs(best_f), 1e-12)))) if np.isfinite(best_f) else 0
    return int(ok.sum()), at_best


def _choose(model: DesignModel, best: _Answers, reports, relaxed, combos, n_starts: int) -> DesignOptimum:
    """Step 4: the combination that meets every requirement at the lowest objective (the one
    that misses least when none does), with its multi-start statistics."""
    n_combo = best.x.shape[0]
    met = np.array([all(r["met"] for r in rep) for rep in reports])
    V = np.stack([model.design_values(best.x[c], c) for c in range(n_combo)])
    inputs = stack([model.inputs(c) for c in range(n_combo)])
    values = model.programs.values_rows(V, per_row_inputs=inputs)
    sign = model.spec.objective.sign
    raw_obj = np.asarray(values[3], dtype=float) * sign  # minimised form
    score = np.where(met, raw_obj, np.inf)
    if np.isfinite(score).any():
        k = int(np.argmin(score))
    else:
        k = int(np.argmin([_scaled_misses(model, rep).sum() for rep in reports]))
    converged, at_best = _start_statistics(relaxed, combos, k)
    full_lam = model.inequality_multipliers(best.lam[k])
    candidates = [{"options": model.combinations[c].options, "objective": float(raw_obj[c] * sign),
                   "feasible": bool(met[c])} for c in range(n_combo)]
    return DesignOptimum(
        x=best.x[k], combo_index=k, objective=float(raw_obj[k] * sign),
        converged=bool(best.converged[k] and met[k]), feasible=bool(met[k]), multipliers=full_lam,
        starts=n_starts, starts_converged=converged, starts_at_best=at_best,
        unmet=[r["name"] for r in reports[k] if not r["met"]], candidates=candidates)


def prepare(model: DesignModel, *, n_starts: int = 8, options: Optional[SolverOptions] = None,
            lockstep: Union[int, str, None] = "auto") -> Runner:
    """The lane runner :func:`optimize_design` will use with these settings, its program begun
    (traced or loaded, compiling in the background): call it early to overlap compilation."""
    options = options or SolverOptions(polish=False)
    run = Runner(model, options, lockstep, n_starts * len(model.combinations))
    run.program.start()
    return run


def optimize_design(model: DesignModel, *, n_starts: int = 8, seed: int = 0, margin: float = 1e-7,
                    options: Optional[SolverOptions] = None,
                    lockstep: Union[int, str, None] = "auto", canonical: bool = True) -> DesignOptimum:
    """Optimise ``model`` (see the module docstring). Deterministic for a given ``seed``.

    ``canonical``: when the optimum is not unique, move to the most robust point of the optimal
    set (:mod:`diffsense.design.canonical`; step 5) and record the rule in ``canonical``.

    ``lockstep``: lanes per vmap (module docstring of :mod:`diffsense.optimize.lanes`): "auto"
    picks by backend, None puts every lane of a step in one vmap, a positive count must divide
    the number of lanes."""
    starts = _starts(model, n_starts, seed)
    model.programs.start("check")  # compiles while the solver's program is traced
    run = prepare(model, n_starts=starts.shape[0], options=options, lockstep=lockstep)
    model.programs.start("search", "dense")
    limits = tight_limits(model, margin)
    base = model.inputs()
    scale = objective_scale(model)
    lanes, relaxed, best = _relax(model, run, starts, base, limits, scale)
    best = _round_integers(model, run, best)
    reports = model.programs.reports(best.x, np.arange(best.x.shape[0]))
    best, reports = _resolve_near_misses(model, run, limits, best, reports)
    if model.intervals.indices:
        best, reports = _exchange(model, run, limits, best, reports)
    optimum = _choose(model, best, reports, relaxed, lanes.combo, starts.shape[0])
    if canonical and optimum.feasible:
        chosen = canonical_optimum(model, optimum.x, optimum.combo_index, run=run,
                                   theta=rows_of(best.theta, optimum.combo_index))
        if chosen is not None:
            optimum.x = chosen.x
            optimum.canonical = {"rule": chosen.rule, "flat_directions": chosen.flat_directions,
                                 "smallest_slack_before": chosen.smallest_slack_before,
                                 "smallest_slack_after": chosen.smallest_slack_after}
    return optimum


__all__ = ["optimize_design", "prepare", "DesignOptimum", "tight_limits"]
