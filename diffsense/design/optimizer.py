"""Optimise a requirement spec: catalog choices, integer relaxation and multi-start.

Steps (all catalog combinations and all starts run in one compiled call each):

1. **Continuous relaxation.** For every catalog combination and every start (the spec's
   initial design plus seeded Latin-hypercube points in the scaled box), minimise the
   normalised objective subject to the requirements with
   :func:`diffsense.optimize.solve` (augmented Lagrangian, bounds never violated). The
   requirements are tightened by a small ``margin`` (scaled units) so that the answer meets
   them when re-evaluated, not only to the solver's tolerance. The best start of each
   combination goes on (:func:`diffsense.optimize.lanes.best_per_group`).
2. **Integers.** Integer variables of the best relaxed answer of each combination are rounded
   to their floor/ceil neighbours and the continuous rest is re-solved with the integers
   pinned (:func:`diffsense.optimize.integer.integer_neighbours`); the best feasible
   neighbour is kept (neighbour verification), or the rounded relaxed answer when none is
   feasible.
3. **Near misses.** Each answer is re-evaluated exactly. The solver's feasibility tolerance
   applies to its internally scaled constraints, so an answer may miss a requirement by
   slightly more than ``margin``; such near misses are re-solved from where they stand with
   those limits tightened by ten times the miss, up to three times.
4. **Choice.** The feasible combination with the lowest objective wins. When no combination is
   feasible the least-infeasible answer is returned with ``feasible`` False and the
   requirements it leaves unmet.
5. **Canonical point.** When the optimum is not unique (flat directions of the optimal set),
   the most robust design of the optimal set is returned instead of an arbitrary one
   (:mod:`diffsense.design.canonical`), and ``canonical`` says so.

Requirements over intervals (:mod:`diffsense.design.intervals`) add step 3b, the exchange
method: a worse point found by the dense re-check joins the search and the answers are re-solved.

**Lanes.** Every (start, combination) pair is one lane of :mod:`diffsense.optimize.lanes`: θ
carries the catalog row and the requirement limits, the box pins the integers in step 2, and
every step's lanes go through the first step's compiled program, in calls of as many lanes as
the first step has. ``lockstep`` sets how many lanes run in one ``jax.vmap`` (module
docstring of :mod:`diffsense.optimize.lanes`): "auto" (default) one after another on CPU and
all in one vmap on an accelerator; a value equal to the number of combinations solves each
start's catalog options in one vmap.

**Compilation.** The first step's solve is traced, then compiled in a background thread
while the model's evaluation program (the requirement reports of step 3) is traced and
compiled in this one (:func:`diffsense.optimize.compile.call_compiling_alongside`): XLA
compiles without holding Python's global interpreter lock, so the two compilations share the
cores.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, NamedTuple, Optional, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.canonical import canonical_optimum
from diffsense.design.model import DesignModel
from diffsense.optimize import Problem, SolverOptions
from diffsense.optimize.compile import jit_with_options
from diffsense.optimize.distributed import solve_across_processes
from diffsense.optimize.integer import integer_neighbours
from diffsense.optimize.lanes import Lanes, best_per_group, lane_program, pin_variables, solve_in_batches
from diffsense.optimize.lanes import lane_grid as grid_of_lanes
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


def build_problem(model: DesignModel) -> Problem:
    """The optimiser's :class:`Problem` for ``model``.

    θ = (catalog row, requirement limits, design vector, pinned mask). Variables whose mask is
    True keep their value from θ's design vector whatever the solver's iterate says (the
    objective and constraints do not depend on them, so the solver leaves them alone): a way to
    hold variables in a single solve without changing the box. :func:`optimize_design` pins
    its integers through the box instead (its lanes take the box as an argument) and leaves the
    mask False.
    """
    ineq = ~model.row_is_equality
    eq = model.row_is_equality
    # jitted once: the solver calls these from several places (the inner solve, the outer
    # linearisation, the problem's size check); JAX traces a jitted function once per signature
    # and reuses it at every call site, which shortens the time to trace the solve
    # (fresh closures, not the bound methods: JAX caches traces by function, and a model's
    # interval search gains candidates between solves, see _exchange)
    residuals = jax.jit(lambda x, combo, limits: model.residuals(x, combo, limits))
    objective_fn = jax.jit(lambda x, combo: model.objective(x, combo))

    def full(x, theta):
        return jnp.where(theta[3], theta[2], x)

    def objective(x, theta):
        return objective_fn(full(x, theta), theta[0])

    def inequality(x, theta):
        return residuals(full(x, theta), theta[0], theta[1])[ineq]

    def equality(x, theta):
        return residuals(full(x, theta), theta[0], theta[1])[eq]

    return Problem(objective, model.lower, model.upper, inequality=inequality if ineq.any() else None,
                   equality=equality if eq.any() else None, log_scale=model.log_scale, integer=model.integer,
                   names=list(model.variable_names))


def tight_limits(model: DesignModel, margin: float) -> np.ndarray:
    """The requirement limits with each inequality moved inward by ``margin`` (scaled units:
    ``margin`` × the requirement's scale): an at_least limit up, an at_most limit down, an
    equality unchanged; the limits the solver is given so that a converged design meets the
    requirements with that margin to spare."""
    return model.limits - model.sign * margin * model.scales * (~model.is_equality)


_tight_limits = tight_limits  # former private name


def _scaled_misses(model: DesignModel, report) -> np.ndarray:
    """Per requirement, by how much (scaled units) a requirement report misses it; 0 when met."""
    return np.array([max(-r["slack"], 0.0) / scale for r, scale in zip(report, model.scales)])


def lane_solver(problem: Problem, options: SolverOptions, lockstep: Union[int, str, None]):
    """One jitted call ``fn(x0, catalog rows, limits, lower, upper)`` solving rows of lanes:
    :func:`diffsense.optimize.lanes.lane_program` with θ = (catalog row, limits, x0, nothing
    pinned) per row and the row's box, ``lockstep`` rows per vmap. The row count must be a
    multiple of a lockstep count."""
    program = lane_program(problem, options, lockstep)

    def run(x0, combos, limits, lower, upper):
        return program(x0, (combos, limits, x0, jnp.zeros(x0.shape, dtype=bool)), lower, upper)

    return jit_with_options(run, "optimized")


def _lanes(model: DesignModel, x0, combo_index, limits, lower=None, upper=None) -> Lanes:
    """Lanes from starts ``x0`` (L, n), the catalog combination of each, limits (L, r) or (r,)
    and boxes (default the model's), θ = (catalog row, limits) as :func:`lane_solver` takes it."""
    x0 = np.asarray(x0, dtype=float)
    combo_index = np.asarray(combo_index, dtype=int)
    limits = np.broadcast_to(limits, (x0.shape[0], np.shape(limits)[-1]))
    lower = np.broadcast_to(model.lower if lower is None else lower, x0.shape)
    upper = np.broadcast_to(model.upper if upper is None else upper, x0.shape)
    return Lanes(x0, (model.combo_table[combo_index], limits), lower, upper, combo_index)


def _columns(lanes: Lanes):
    """The arguments of :func:`lane_solver` for ``lanes``."""
    return lanes.x0, lanes.theta[0], lanes.theta[1], lanes.lower, lanes.upper


def _grid(model: DesignModel, starts, limits) -> Lanes:
    """Every (start, combination) lane, start-major, each combination a group."""
    grid = grid_of_lanes(starts, None, lower=model.lower, upper=model.upper, n_groups=len(model.combinations))
    return _lanes(model, grid.x0, grid.group, limits)


def lane_grid(model: DesignModel, starts: np.ndarray, limits: np.ndarray):
    """Columns (x0, catalog row, limits, lower, upper) of every (start, combination) lane,
    start-major: lanes k·n_combo … (k+1)·n_combo − 1 are start k's catalog options."""
    return _columns(_grid(model, starts, limits))


class _Answers(NamedTuple):
    """The current answer of each catalog combination (rows: combinations)."""

    x: np.ndarray
    converged: np.ndarray
    lam: np.ndarray


def _starts(model: DesignModel, problem: Problem, n_starts: int, seed: int) -> np.ndarray:
    """The spec's initial design and n_starts − 1 seeded Latin-hypercube points."""
    starts = model.initial[None, :]
    if n_starts > 1:
        starts = np.vstack([starts, start_points(problem, n_starts - 1, seed=seed, method="lhs")])
    return starts


def _relax(model: DesignModel, solver, starts, limits):
    """Step 1: every (start, combination) lane; returns (lanes, results, answers per combination)."""
    lanes = _grid(model, starts, limits)
    # split across processes when jax.distributed is initialised (diffsense.optimize.distributed);
    # with one process this is solve_in_batches in one call of every lane
    res = solve_across_processes(solver, None, *_columns(lanes), alongside=model.compile_evaluation)
    rows, _ = best_per_group(res, lanes.group, len(model.combinations))
    return lanes, res, _Answers(res.x[rows].copy(), res.converged[rows].copy(), res.lam[rows].copy())


def _round_integers(model: DesignModel, problem: Problem, solver, batch: int, limits, best: _Answers) -> _Answers:
    """Step 2: the best feasible integer neighbour of each combination's answer, or the answer
    with its integers rounded when no neighbour is feasible."""
    if not model.integer.any():
        return best
    cand = integer_neighbours(problem, best.x)
    res = solve_in_batches(solver, batch, *_columns(_lanes(model, cand.x0, cand.group, limits, cand.lower,
                                                           cand.upper)))
    rows, found = best_per_group(res, cand.group, len(model.combinations))
    x, conv, lam = best.x.copy(), best.converged.copy(), best.lam.copy()
    x[found], conv[found], lam[found] = res.x[rows[found]], res.converged[rows[found]], res.lam[rows[found]]
    x[~found] = np.where(model.integer, np.round(x[~found]), x[~found])
    return _Answers(x, conv, lam)


def _resolve_near_misses(model: DesignModel, solver, batch: int, limits, best: _Answers):
    """Step 3: re-solve answers that miss a requirement by at most 1e-3 (scaled) from where they
    stand, integers pinned, with the missed limits tightened by ten times the miss; keep a
    re-solve that misses less. Returns the answers and their requirement reports."""
    x, conv, lam = best.x.copy(), best.converged.copy(), best.lam.copy()
    reports = [model.requirement_report(x[c], model.combo_table[c]) for c in range(x.shape[0])]
    for _ in range(3):
        miss = np.array([_scaled_misses(model, rep) for rep in reports])
        near = np.flatnonzero((miss.max(axis=1) > 0) & (miss.max(axis=1) <= 1e-3))
        if near.size == 0:
            break
        tighter = limits[None, :] - model.sign * (10.0 * miss[near]) * model.scales * (~model.is_equality)
        lower, upper = pin_variables(model.lower, model.upper, x[near], model.integer)
        res = solve_in_batches(solver, batch, *_columns(_lanes(model, x[near], near, tighter, lower, upper)))
        for j, c in enumerate(near):
            rep = model.requirement_report(res.x[j], model.combo_table[c])
            if _scaled_misses(model, rep).sum() < miss[c].sum():
                x[c], reports[c], conv[c], lam[c] = res.x[j], rep, res.converged[j], res.lam[j]
    return _Answers(x, conv, lam), reports


def _missed_points(model: DesignModel, reports) -> dict:
    """Exchange candidates: per interval requirement whose dense re-check (in any combination's
    report) found a value worse than the solver's own search by more than 1e-9 (scaled), the
    point where it lies."""
    found = {}
    for rep in reports:
        for j, row in enumerate(rep):
            if "search_value" not in row:
                continue
            worse = model.sign[j] * (row["value"] - row["search_value"]) / model.scales[j]
            if worse > 1e-9:
                found.setdefault(j, []).append([row["worst_at"][iv.parameter] for iv in model.requirements[j].over])
    return {j: np.asarray(pts) for j, pts in found.items()}


def _exchange(model: DesignModel, options, lockstep, batch: int, limits, best: _Answers, reports, rounds: int = 2):
    """Step 3b (exchange method for the interval requirements; Hettich & Kortanek 1993 §7): when
    the dense re-check finds a worse point than the solver's search, that point joins the search's
    candidates and every combination is re-solved from its answer, integers pinned; a re-solve is
    kept if it misses less."""
    for _ in range(rounds):
        missed = _missed_points(model, reports)
        if not missed:
            break
        for j, pts in missed.items():
            for q in pts:
                model.intervals.add_candidates({j: q})
        model.forget_compiled()
        solver = lane_solver(build_problem(model), options, lockstep)
        n = best.x.shape[0]
        lower, upper = pin_variables(model.lower, model.upper, best.x, model.integer)
        res = solve_in_batches(solver, batch, *_columns(_lanes(model, best.x, np.arange(n), limits, lower, upper)))
        x, conv, lam = best.x.copy(), best.converged.copy(), best.lam.copy()
        for c in range(n):
            rep = model.requirement_report(res.x[c], model.combo_table[c])
            if _scaled_misses(model, rep).sum() <= _scaled_misses(model, reports[c]).sum():
                x[c], reports[c], conv[c], lam[c] = res.x[c], rep, res.converged[c], res.lam[c]
            else:
                reports[c] = model.requirement_report(x[c], model.combo_table[c])
        best = _Answers(x, conv, lam)
        best, reports = _resolve_near_misses(model, solver, batch, limits, best)
    return best, reports


def _start_statistics(relaxed, lanes: Lanes, combo: int):
    """(starts converged, starts at the best objective) of one combination's relaxed lanes."""
    mine = lanes.group == combo
    f = relaxed.f[mine]
    ok = relaxed.feasible[mine] & relaxed.converged[mine]
    best_f = np.min(np.where(ok, f, np.inf)) if ok.any() else np.inf
    at_best = int(np.sum(ok & (np.abs(f - best_f) <= 1e-6 * max(abs(best_f), 1e-12)))) if np.isfinite(best_f) else 0
    return int(ok.sum()), at_best


def _choose(model: DesignModel, best: _Answers, reports, relaxed, lanes: Lanes, n_starts: int) -> DesignOptimum:
    """Step 4: the combination that meets every requirement at the lowest objective (the one
    that misses least when none does), with its multi-start statistics."""
    n_combo = best.x.shape[0]
    met = np.array([all(r["met"] for r in rep) for rep in reports])
    raw_obj = np.array([float(model.evaluate_all(best.x[c], model.combo_table[c])[2]) for c in range(n_combo)])
    score = np.where(met, raw_obj, np.inf)
    if np.isfinite(score).any():
        k = int(np.argmin(score))
    else:
        k = int(np.argmin([_scaled_misses(model, rep).sum() for rep in reports]))
    converged, at_best = _start_statistics(relaxed, lanes, k)
    row_lam = np.zeros(model.row_owner.size)
    row_lam[~model.row_is_equality] = best.lam[k][: int((~model.row_is_equality).sum())]
    full_lam = model.row_multipliers(row_lam)
    sign = model.spec.objective.sign
    candidates = [{"options": model.combinations[c].options, "objective": float(raw_obj[c] * sign),
                   "feasible": bool(met[c])} for c in range(n_combo)]
    return DesignOptimum(
        x=best.x[k], combo_index=k, objective=float(raw_obj[k] * sign),
        converged=bool(best.converged[k] and met[k]), feasible=bool(met[k]), multipliers=full_lam,
        starts=n_starts, starts_converged=converged, starts_at_best=at_best,
        unmet=[r["name"] for r in reports[k] if not r["met"]], candidates=candidates)


def optimize_design(model: DesignModel, *, n_starts: int = 8, seed: int = 0, margin: float = 1e-7,
                    options: Optional[SolverOptions] = None,
                    lockstep: Union[int, str, None] = "auto", canonical: bool = True) -> DesignOptimum:
    """Optimise ``model`` (see the module docstring). Deterministic for a given ``seed``.

    ``canonical``: when the optimum is not unique, move to the most robust point of the optimal
    set (:mod:`diffsense.design.canonical`; step 5) and record the rule in ``canonical``.

    ``lockstep``: lanes per vmap (module docstring): "auto" picks by backend, None puts every
    lane of a step in one vmap, a positive count must divide the number of lanes."""
    problem = build_problem(model)
    solver = lane_solver(problem, options or SolverOptions(polish=False), lockstep)
    limits = _tight_limits(model, margin)
    starts = _starts(model, problem, n_starts, seed)
    lanes, relaxed, best = _relax(model, solver, starts, limits)
    batch = lanes.x0.shape[0]
    best = _round_integers(model, problem, solver, batch, limits, best)
    best, reports = _resolve_near_misses(model, solver, batch, limits, best)
    if model.intervals.indices:
        best, reports = _exchange(model, options or SolverOptions(polish=False), lockstep, batch, limits, best, reports)
    optimum = _choose(model, best, reports, relaxed, lanes, starts.shape[0])
    if canonical and optimum.feasible:
        chosen = canonical_optimum(model, optimum.x, optimum.combo_index, options)
        if chosen is not None:
            optimum.x = chosen.x
            optimum.canonical = {"rule": chosen.rule, "flat_directions": chosen.flat_directions,
                                 "smallest_slack_before": chosen.smallest_slack_before,
                                 "smallest_slack_after": chosen.smallest_slack_after}
    return optimum
