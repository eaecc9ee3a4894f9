"""Optimise a requirement spec: catalog choices, integer relaxation and multi-start.

Steps (all catalog combinations and all starts run in one compiled call each):

1. **Continuous relaxation.** For every catalog combination and every start (the spec's
   initial design plus seeded Latin-hypercube points in the scaled box), minimise the
   normalised objective subject to the requirements with
   :func:`diffsense.optimize.solve` (augmented Lagrangian, bounds never violated). The
   requirements are tightened by a small ``margin`` (scaled units) so that the answer meets
   them when re-evaluated, not only to the solver's tolerance.
2. **Integers.** Integer variables of the best relaxed answer of each combination are rounded
   to their floor/ceil neighbours (:func:`diffsense.optimize.integer.rounding_candidates`);
   the continuous rest is re-solved with the integers fixed, and the best feasible neighbour
   is kept (neighbour verification).
3. **Choice.** The feasible combination with the lowest objective wins. When no combination is
   feasible the least-infeasible answer is returned with ``feasible`` False and the
   requirements it leaves unmet.

**Compilation.** The first step's solve is traced, then compiled in a background thread
while the model's evaluation program (the requirement reports at the end) is traced and
compiled in this one: XLA compiles without holding Python's global interpreter lock, so the two
compilations share the cores (see :func:`_first_solve`).

**Lanes.** Every (start, combination) pair is one *lane*, and all lanes of a step are solved by
one compiled call. ``lockstep`` sets how many lanes run in one ``jax.vmap``: a vmapped batch
advances in lockstep, so each loop of the solve (outer and inner iterations, the line search,
the series and root finders of the model) runs for as many trips as its slowest lane needs,
on every lane. Groups of ``lockstep`` lanes are run one after another by ``jax.lax.map``
inside the same program. ``lockstep="auto"`` (default) picks 1 on CPU (lanes one after
another: the work is the sum of the lanes' own work) and None on an accelerator (every lane in
one vmap: the device is wide and lanes run side by side). A value equal to the number of
combinations solves each start's catalog options in one vmap. Measured on ``ore_pass.toml``
(80 lanes, 2-core CPU, ``benchmarks/bench_design.py`` section 5): 0.68 s with ``lockstep=1``
against 3.8 s with 10 lanes per vmap and 7.0 s with all 80 in one vmap.
"""

from __future__ import annotations

import concurrent.futures

from dataclasses import dataclass
from typing import List, Optional, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.optimize import Problem, SolverOptions, solve_batch
from diffsense.optimize.batch import resolve_lockstep
from diffsense.optimize.constrained import jit_with_options
from diffsense.optimize.integer import rounding_candidates
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


def build_problem(model: DesignModel) -> Problem:
    """The optimiser's :class:`Problem` for ``model``.

    θ = (catalog row, requirement limits, design vector, pinned mask). Variables whose mask is
    True keep their value from θ's design vector whatever the solver's iterate says: the
    objective and constraints do not depend on them, so their gradient is zero and the solver
    leaves them alone. One compiled solve thus serves the relaxed problem (nothing pinned) and
    the re-solve of the continuous variables with the integers pinned at a rounding candidate.
    """
    ineq = ~model.is_equality
    eq = model.is_equality
    # jitted once: the solver calls these from several places (the inner solve, the outer
    # linearisation, the problem's size check); JAX traces a jitted function once per signature
    # and reuses it at every call site, which shortens the time to trace the solve
    residuals = jax.jit(model.residuals)
    objective_fn = jax.jit(model.objective)

    def full(x, theta):
        return jnp.where(theta[3], theta[2], x)

    def objective(x, theta):
        return objective_fn(full(x, theta), theta[0])

    def inequality(x, theta):
        return residuals(full(x, theta), theta[0], theta[1])[ineq]

    def equality(x, theta):
        return residuals(full(x, theta), theta[0], theta[1])[eq]

    return Problem(objective, model.lower, model.upper, inequality=inequality if ineq.any() else None,
                   equality=equality if eq.any() else None, log_scale=model.log_scale,
                   names=list(model.variable_names))


def _tight_limits(model: DesignModel, margin: float) -> np.ndarray:
    # move each inequality limit inward by margin (in scaled units): at_least up, at_most down
    return model.limits - model.sign * margin * model.scales * (~model.is_equality)


def _scaled_misses(model: DesignModel, report) -> np.ndarray:
    """Per requirement, by how much (scaled units) a requirement report misses it; 0 when met."""
    return np.array([max(-r["slack"], 0.0) / scale for r, scale in zip(report, model.scales)])


def lane_solver(problem: Problem, options: SolverOptions, lockstep: Optional[int]):
    """One jitted call solving rows of (x0, catalog row, limits, pinned mask), θ = (catalog row,
    limits, x0, pinned mask) per row: :func:`diffsense.optimize.solve_batch` with ``lockstep``
    rows per vmap (see :func:`diffsense.optimize.batch.map_in_lockstep`). The row count must be
    a multiple of ``lockstep``."""

    def run(x, c, l, pin):
        return solve_batch(problem, x, (c, l, x, pin), options, lockstep)

    return jit_with_options(run, "optimized")


def lane_grid(model: DesignModel, starts: np.ndarray, limits: np.ndarray):
    """Columns (x0, catalog row, limits, pinned mask) of every (start, combination) lane,
    start-major: lanes k·n_combo … (k+1)·n_combo − 1 are start k's catalog options."""
    n_s, n_var = starts.shape
    n_combo = model.combo_table.shape[0]
    x0 = np.repeat(starts[:, None, :], n_combo, axis=1).reshape(-1, n_var)
    combos = np.tile(model.combo_table, (n_s, 1))
    return x0, combos, np.broadcast_to(limits, (x0.shape[0], limits.size)), np.zeros(x0.shape, dtype=bool)


def _first_solve(solver, args, model: DesignModel):
    """``solver(*args)``, its compilation overlapped with that of the model's evaluation program
    (needed for the requirement reports at the end): the solve is traced here, compiled in a
    background thread (XLA compiles without holding Python's lock) while this thread traces and
    compiles the evaluation, so the two compilations share the machine's cores. The programs
    are the ones plain calls would compile; later calls reuse them."""
    lowered = solver.lower(*args)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        compiling = pool.submit(lowered.compile)
        model.compile_evaluation()
        executable = compiling.result()
    return executable(*args)


def _solve_in_batches(solver, batch: int, *columns):
    """``solver`` over rows of ``columns`` in batches of exactly ``batch`` rows (the last one
    padded by repeating its final row), so the compiled program of the first call is reused."""
    n = columns[0].shape[0]
    outs = []
    for start in range(0, n, batch):
        rows = np.arange(start, min(start + batch, n))
        padded = np.concatenate([rows, np.full(batch - rows.size, rows[-1])])
        res = solver(*(jnp.asarray(np.asarray(c)[padded]) for c in columns))
        outs.append(jax.tree_util.tree_map(lambda a, k=rows.size: np.asarray(a)[:k], res))
    return jax.tree_util.tree_map(lambda *a: np.concatenate(a), *outs)


def optimize_design(model: DesignModel, *, n_starts: int = 8, seed: int = 0, margin: float = 1e-7,
                    options: Optional[SolverOptions] = None,
                    lockstep: Union[int, str, None] = "auto") -> DesignOptimum:
    """Optimise ``model`` (see the module docstring). Deterministic for a given ``seed``.

    ``lockstep``: lanes per vmap (module docstring): "auto" picks by backend, None puts every
    lane of a step in one vmap, a positive count must divide the number of lanes."""
    options = options or SolverOptions(polish=False)
    lockstep = resolve_lockstep(lockstep)
    n_combo = len(model.combinations)
    limits = _tight_limits(model, margin)
    problem = build_problem(model)

    starts = model.initial[None, :]
    if n_starts > 1:
        starts = np.vstack([starts, start_points(problem, n_starts - 1, seed=seed, method="lhs")])
    n_s = starts.shape[0]
    columns = lane_grid(model, starts, limits)
    n_lanes = columns[0].shape[0]
    solver = lane_solver(problem, options, lockstep)
    res = _first_solve(solver, tuple(jnp.asarray(c) for c in columns), model)

    def by_combo(a):  # (n_s * n_combo, ...) -> (n_combo, n_s, ...)
        a = np.asarray(a)
        return np.swapaxes(a.reshape((n_s, n_combo) + a.shape[1:]), 0, 1)

    f = by_combo(res.f)
    feas = by_combo(res.feasible)
    conv = by_combo(res.converged)
    xs = by_combo(res.x)
    lam_all = by_combo(res.lam)
    feas_measure = by_combo(res.kkt.feasibility)

    best_rows = []
    for c in range(n_combo):
        score = np.where(feas[c], f[c], np.inf)
        k = int(np.argmin(score)) if np.isfinite(score).any() else int(np.argmin(feas_measure[c]))
        best_rows.append(k)

    # integer rounding with neighbour verification
    final_x = np.array([xs[c, best_rows[c]] for c in range(n_combo)])
    final_f = np.array([f[c, best_rows[c]] for c in range(n_combo)])
    final_feas = np.array([feas[c, best_rows[c]] for c in range(n_combo)])
    final_conv = np.array([conv[c, best_rows[c]] for c in range(n_combo)])
    final_lam = np.array([lam_all[c, best_rows[c]] for c in range(n_combo)])
    int_idx = np.flatnonzero(model.integer)
    if int_idx.size:
        int_lo, int_hi = np.ceil(model.lower[int_idx]), np.floor(model.upper[int_idx])
        cand_x, cand_c = [], []
        for c in range(n_combo):
            picks = np.asarray(rounding_candidates(jnp.asarray(final_x[c, int_idx]), int_lo, int_hi))
            x = np.repeat(final_x[c][None, :], picks.shape[0], axis=0)
            x[:, int_idx] = picks
            cand_x.append(x)
            cand_c.extend([c] * picks.shape[0])
        cand_x = np.clip(np.concatenate(cand_x), model.lower, model.upper)
        cand_c = np.array(cand_c)
        # the same compiled solve, integers pinned at each candidate
        pins = np.broadcast_to(model.integer, cand_x.shape)
        r2 = _solve_in_batches(solver, n_lanes, cand_x, model.combo_table[cand_c],
                               np.broadcast_to(limits, (cand_x.shape[0], limits.size)), pins)
        r2_x = np.where(pins, cand_x, np.asarray(r2.x))
        f2 = np.asarray(r2.f)
        feas2 = np.asarray(r2.feasible)
        for c in range(n_combo):
            rows = np.flatnonzero(cand_c == c)
            score = np.where(feas2[rows], f2[rows], np.inf)
            if np.isfinite(score).any():
                k = rows[int(np.argmin(score))]
                final_x[c] = r2_x[k]
                final_f[c] = f2[k]
                final_feas[c] = True
                final_conv[c] = bool(np.asarray(r2.converged)[k])
                final_lam[c] = np.asarray(r2.lam)[k]
            else:
                final_feas[c] = False
                final_x[c, int_idx] = np.round(final_x[c, int_idx])

    # exact re-evaluation decides feasibility
    reports = [model.requirement_report(final_x[c], model.combo_table[c]) for c in range(n_combo)]
    # The solver's feasibility tolerance applies to its internally scaled constraints, so an
    # answer may miss a requirement by slightly more than ``margin``. Such near misses are
    # re-solved from where they stand with those limits tightened by ten times the miss (the
    # same compiled program: limits are arguments), up to three times.
    pins_all = np.broadcast_to(model.integer, final_x.shape)
    for _ in range(3):
        miss = np.array([_scaled_misses(model, rep) for rep in reports])
        near = np.flatnonzero((miss.max(axis=1) > 0) & (miss.max(axis=1) <= 1e-3))
        if near.size == 0:
            break
        tighter = limits[None, :] - model.sign * (10.0 * miss[near]) * model.scales * (~model.is_equality)
        r3 = _solve_in_batches(solver, n_lanes, final_x[near], model.combo_table[near], tighter, pins_all[near])
        for j, c in enumerate(near):
            x_new = np.where(pins_all[c], final_x[c], np.asarray(r3.x)[j])
            rep = model.requirement_report(x_new, model.combo_table[c])
            if _scaled_misses(model, rep).sum() < miss[c].sum():
                final_x[c], reports[c] = x_new, rep
                final_conv[c] = bool(np.asarray(r3.converged)[j])
                final_lam[c] = np.asarray(r3.lam)[j]
    met = np.array([all(r["met"] for r in rep) for rep in reports])
    raw_obj = np.array([float(model.evaluate_all(final_x[c], model.combo_table[c])[2]) for c in range(n_combo)])
    score = np.where(met, raw_obj, np.inf)
    if np.isfinite(score).any():
        best = int(np.argmin(score))
    else:
        viol = [_scaled_misses(model, rep).sum() for rep in reports]
        best = int(np.argmin(viol))
    # multi-start statistics of the winning combination's relaxed solve
    fb = f[best]
    ok = feas[best] & conv[best]
    best_f = np.min(np.where(ok, fb, np.inf)) if ok.any() else np.inf
    at_best = int(np.sum(ok & (np.abs(fb - best_f) <= 1e-6 * max(abs(best_f), 1e-12)))) if np.isfinite(best_f) else 0
    full_lam = np.zeros(len(model.requirements))
    full_lam[~model.is_equality] = final_lam[best][: int((~model.is_equality).sum())]
    candidates = [{"options": model.combinations[c].options, "objective": float(raw_obj[c] * model.spec.objective.sign),
                   "feasible": bool(met[c])} for c in range(n_combo)]
    return DesignOptimum(
        x=final_x[best], combo_index=best, objective=float(raw_obj[best] * model.spec.objective.sign),
        converged=bool(final_conv[best] and met[best]), feasible=bool(met[best]), multipliers=full_lam,
        starts=n_s, starts_converged=int(ok.sum()), starts_at_best=at_best,
        unmet=[r["name"] for r in reports[best] if not r["met"]], candidates=candidates)
