"""Integer and catalog (categorical) design variables.

Integer variables (``Problem(..., integer=...)``, e.g. a number of pulses or array elements)
are handled by continuous relaxation and rounding with neighbour verification:

1. solve the continuous relaxation (integers treated as reals);
2. build candidate integer assignments around the relaxed values r: every floor/ceil
   combination (2^k candidates) when there are k ≤ ``max_enumerated`` integer variables,
   otherwise the nearest rounding plus each single variable moved one step down and up
   (1 + 2k candidates); values are clipped to the integers inside the bounds;
3. re-solve the continuous rest with the integers fixed (bounds lower = upper = value,
   :func:`integer_neighbours`), warm-started from the relaxed solution, every candidate a lane
   of the relaxation's compiled program (:mod:`diffsense.optimize.lanes`);
4. keep the best feasible candidate (lowest f); if none is feasible, the least infeasible.

This is a heuristic, not branch and bound: it is exact when the integer optimum lies in the
floor/ceil box of the relaxed solution, which holds for problems whose objective is
separable-convex in the integers near the relaxed point but is not guaranteed in general (a
nonconvex problem can have its integer optimum far from the relaxation). ``gap`` reports
f(best) − f(relaxed); for a convex problem the relaxed value is a lower bound, so the gap
bounds the suboptimality of the answer.

Catalog choices (a radar from a list of transmitters, an antenna from a product line) are
discrete options that change the parameters θ and/or fix some variables. ``solve_catalog``
solves every option as a lane of one compiled program and returns the best feasible one.

Both run on the host around one jitted lane program (compiled once per call; ``compile`` and
``lockstep`` as in :func:`diffsense.optimize.lanes.make_lane_solver`) and return NumPy arrays;
:func:`diffsense.design.optimizer.optimize_design` combines the same steps for every catalog
combination and start of a design.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range
from diffsense.optimize.lanes import Lanes, best_per_group, make_lane_solver, pin_variables, solve_lanes, take
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem, check_start
from diffsense.optimize.result import Result


class MixedIntegerResult(NamedTuple):
    """``best``: the chosen solve (integers fixed); ``relaxed``: the continuous relaxation;
    ``candidates``: (K, k) integer assignments tried (columns in ``problem.integer_indices``
    order); ``candidate_f``, ``candidate_feasible``: their objective values and feasibility;
    ``index``: the chosen row; ``found``: some candidate is feasible; ``gap``:
    f(best) − f(relaxed) (a suboptimality bound for convex problems)."""

    best: Result
    relaxed: Result
    candidates: jax.Array
    candidate_f: jax.Array
    candidate_feasible: jax.Array
    index: jax.Array
    found: jax.Array
    gap: jax.Array


def rounding_candidates(relaxed_values, int_lower, int_upper, max_enumerated: int = 8):
    """Integer candidates around relaxed values r (shape (k,)), clipped to [int_lower, int_upper].

    k ≤ max_enumerated: all 2^k floor/ceil combinations; otherwise round(r) and round(r) ± eᵢ
    (1 + 2k rows). Shapes are static (k is known at trace time)."""
    xp = np if isinstance(relaxed_values, np.ndarray) else jnp  # NumPy in, NumPy out: no eager JAX
    k = relaxed_values.shape[0]
    r = xp.clip(relaxed_values, int_lower, int_upper)
    if k <= max_enumerated:
        bits = np.array(list(itertools.product((0.0, 1.0), repeat=k)), dtype=float).reshape(-1, k)
        cand = xp.floor(r)[None, :] + bits
    else:
        base = xp.round(r)
        eye = np.eye(k)
        cand = xp.concatenate([base[None, :], base[None, :] - eye, base[None, :] + eye], axis=0)
    return xp.clip(cand, int_lower, int_upper)


def candidate_count(k: int, max_enumerated: int = 8) -> int:
    """Number of rows :func:`rounding_candidates` gives for k integer variables."""
    return 2 ** k if k <= max_enumerated else 1 + 2 * k


def integer_neighbours(problem: Problem, x, max_enumerated: int = 8) -> Lanes:
    """Lanes re-solving the continuous rest of each row of ``x`` (G, n) at the integer
    candidates around it (:func:`rounding_candidates` of its integer variables, inside the
    integers of the bounds): each lane starts at the row with its integers replaced by a
    candidate, in ``problem``'s box with those integers pinned (lower = upper = value);
    ``group`` is the row of ``x`` it came from, ``theta`` is None (the caller's θ of that row
    goes there). The integer variables are ``problem.integer_indices``."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    idx = np.asarray(problem.integer_indices, dtype=int)
    lower, upper = np.asarray(problem.lower), np.asarray(problem.upper)
    int_lo, int_hi = np.ceil(lower[idx]), np.floor(upper[idx])
    starts, source = [], []
    for g, row in enumerate(x):
        picks = rounding_candidates(np.asarray(row[idx], dtype=float), int_lo, int_hi, max_enumerated)
        cand = np.repeat(row[None, :], picks.shape[0], axis=0)
        cand[:, idx] = picks
        starts.append(cand)
        source.extend([g] * picks.shape[0])
    x0 = np.clip(np.concatenate(starts), lower, upper)
    mask = np.zeros(problem.n, dtype=bool)
    mask[idx] = True
    lo, hi = pin_variables(lower, upper, x0, mask)
    return Lanes(x0, None, lo, hi, np.asarray(source, dtype=int))


def _one_row(tree):
    """``tree`` with a leading axis of one row (None stays None)."""
    return jax.tree_util.tree_map(lambda a: np.asarray(a)[None], tree)


def solve_mixed_integer(problem: Problem, x0, theta=None, options: SolverOptions = SolverOptions(), *,
                        max_enumerated: int = 8, lockstep: Union[int, str, None] = "auto",
                        compile: str = "optimized") -> MixedIntegerResult:
    """Relax, round with neighbour verification, re-solve the continuous rest (module doc).

    ``problem.integer_indices`` names the integer variables (bounds of integer variables are
    rounded inwards to integers). The relaxation and the 2^k (or 1 + 2k) candidates are lanes
    of one compiled program, in calls of as many lanes as there are candidates."""
    check_start(problem, x0, where="solve_mixed_integer")
    idx = np.asarray(problem.integer_indices, dtype=int)
    if idx.size == 0:
        raise DomainError("solve_mixed_integer: the problem has no integer variables (Problem(integer=...))")
    check_range("max_enumerated", max_enumerated, 0, 20, where="solve_mixed_integer")
    batch = candidate_count(idx.size, max_enumerated)
    solver = make_lane_solver(problem, options, lockstep=lockstep, compile=compile)
    theta_row = _one_row(theta)
    start = np.asarray(x0, dtype=float)[None, :]
    relaxed_lane = Lanes(start, theta_row, np.asarray(problem.lower)[None, :], np.asarray(problem.upper)[None, :],
                         np.zeros(1, dtype=int))
    relaxed = take(solve_lanes(solver, relaxed_lane, batch), 0)
    lanes = integer_neighbours(problem, relaxed.x[None, :], max_enumerated)
    lanes = lanes._replace(theta=take(theta_row, lanes.group))
    results = solve_lanes(solver, lanes, batch)
    rows, found = best_per_group(results, lanes.group, 1)
    i = int(rows[0])
    best = take(results, i)
    return MixedIntegerResult(best, relaxed, lanes.x0[:, idx], results.f, results.feasible, i, bool(found[0]),
                              best.f - relaxed.f)


class CatalogResult(NamedTuple):
    """``best``: the chosen option's solve; ``index``: its row; ``results``: every option's
    solve (batched); ``feasible``: (K,) flags; ``found``: some option is feasible."""

    best: Result
    index: jax.Array
    results: Result
    feasible: jax.Array
    found: jax.Array


def solve_catalog(problem: Problem, x0, option_thetas, options: SolverOptions = SolverOptions(), *,
                  option_lower=None, option_upper=None, lockstep: Union[int, str, None] = "auto",
                  compile: str = "optimized") -> CatalogResult:
    """Solve every catalog option as a lane of one compiled program and pick the best feasible one.

    ``option_thetas``: pytree of parameters with a leading axis of K options (each option's θ).
    ``option_lower``/``option_upper``: optional (K, n) bounds per option (e.g. fixing the
    variables an item determines, lower = upper). ``x0``: shared start (n,) or (K, n)."""
    check_start(problem, x0, where="solve_catalog")
    leaves = jax.tree_util.tree_leaves(option_thetas)
    if not leaves:
        raise DomainError("solve_catalog: option_thetas must hold at least one array with a leading option axis")
    k = int(np.shape(leaves[0])[0])
    shape = (k, problem.n)
    lo = np.broadcast_to(problem.lower if option_lower is None else np.asarray(option_lower, float), shape)
    hi = np.broadcast_to(problem.upper if option_upper is None else np.asarray(option_upper, float), shape)
    lanes = Lanes(np.broadcast_to(np.asarray(x0, float), shape), option_thetas, lo, hi, np.zeros(k, dtype=int))
    results = solve_lanes(make_lane_solver(problem, options, lockstep=lockstep, compile=compile), lanes)
    rows, found = best_per_group(results, lanes.group, 1)
    i = int(rows[0])
    return CatalogResult(take(results, i), i, results, results.feasible, bool(found[0]))


__all__ = ["MixedIntegerResult", "CatalogResult", "solve_mixed_integer", "solve_catalog", "rounding_candidates",
           "integer_neighbours", "candidate_count"]
