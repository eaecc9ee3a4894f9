"""Integer and catalog (categorical) design variables.

Integer variables (``Problem(..., integer=...)``, e.g. a number of pulses or array elements)
are handled by continuous relaxation and rounding with neighbour verification:

1. solve the continuous relaxation (integers treated as reals);
2. build candidate integer assignments around the relaxed values r: every floor/ceil
   combination (2^k candidates) when there are k ≤ ``max_enumerated`` integer variables,
   otherwise the nearest rounding plus each single variable moved one step down and up
   (1 + 2k candidates); values are clipped to the integers inside the bounds;
3. re-solve the continuous rest with the integers fixed (bounds lower = upper = value), all
   candidates in one vmap, warm-started from the relaxed solution;
4. keep the best feasible candidate (lowest f); if none is feasible, the least infeasible.

This is a heuristic, not branch and bound: it is exact when the integer optimum lies in the
floor/ceil box of the relaxed solution, which holds for problems whose objective is
separable-convex in the integers near the relaxed point but is not guaranteed in general (a
nonconvex problem can have its integer optimum far from the relaxation). ``gap`` reports
f(best) − f(relaxed); for a convex problem the relaxed value is a lower bound, so the gap
bounds the suboptimality of the answer.

Catalog choices (a radar from a list of transmitters, an antenna from a product line) are
discrete options that change the parameters θ and/or fix some variables. ``solve_catalog``
solves every option in one vmap and returns the best feasible one.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range
from diffsense.optimize.constrained import Result, SolverOptions, solve
from diffsense.optimize.problem import Problem, check_start


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


def _select(results: Result, i) -> Result:
    return jax.tree_util.tree_map(lambda a: a[i], results)


def _pick_best(results: Result):
    """Index of the feasible result with the lowest f; the least infeasible if none."""
    feasible = results.feasible
    score = jnp.where(feasible, results.f, jnp.inf)
    any_feasible = jnp.any(feasible)
    i_feas = jnp.argmin(score)
    i_infeas = jnp.argmin(results.kkt.feasibility)
    return jnp.where(any_feasible, i_feas, i_infeas), any_feasible


def rounding_candidates(relaxed_values, int_lower, int_upper, max_enumerated: int = 8):
    """Integer candidates around relaxed values r (shape (k,)), clipped to [int_lower, int_upper].

    k ≤ max_enumerated: all 2^k floor/ceil combinations; otherwise round(r) and round(r) ± eᵢ
    (1 + 2k rows). Shapes are static (k is known at trace time)."""
    k = relaxed_values.shape[0]
    r = jnp.clip(relaxed_values, int_lower, int_upper)
    if k <= max_enumerated:
        bits = np.array(list(itertools.product((0.0, 1.0), repeat=k)), dtype=float).reshape(-1, k)
        cand = jnp.floor(r)[None, :] + bits
    else:
        base = jnp.round(r)
        eye = np.eye(k)
        cand = jnp.concatenate([base[None, :], base[None, :] - eye, base[None, :] + eye], axis=0)
    return jnp.clip(cand, int_lower, int_upper)


def solve_mixed_integer(problem: Problem, x0, theta=None, options: SolverOptions = SolverOptions(), *,
                        max_enumerated: int = 8) -> MixedIntegerResult:
    """Relax, round with neighbour verification, re-solve the continuous rest (module doc).

    ``problem.integer_indices`` names the integer variables (bounds of integer variables are
    rounded inwards to integers). Jit/vmap-able; cost: one solve plus a vmapped solve over
    2^k (or 1 + 2k) candidates."""
    check_start(problem, x0, where="solve_mixed_integer")
    idx = np.asarray(problem.integer_indices, dtype=int)
    if idx.size == 0:
        raise DomainError("solve_mixed_integer: the problem has no integer variables (Problem(integer=...))")
    check_range("max_enumerated", max_enumerated, 0, 20, where="solve_mixed_integer")
    relaxed = solve(problem, x0, theta, options)
    int_lo = jnp.ceil(problem.lower[idx])
    int_hi = jnp.floor(problem.upper[idx])
    cand = rounding_candidates(relaxed.x[idx], int_lo, int_hi, max_enumerated)

    def one(values):
        lo = problem.lower.at[idx].set(values)
        hi = problem.upper.at[idx].set(values)
        start = relaxed.x.at[idx].set(values)
        return solve(problem.with_bounds(lo, hi), start, theta, options)

    results = jax.vmap(one)(cand)
    i, found = _pick_best(results)
    best = _select(results, i)
    return MixedIntegerResult(best, relaxed, cand, results.f, results.feasible, i, found, best.f - relaxed.f)


class CatalogResult(NamedTuple):
    """``best``: the chosen option's solve; ``index``: its row; ``results``: every option's
    solve (batched); ``feasible``: (K,) flags; ``found``: some option is feasible."""

    best: Result
    index: jax.Array
    results: Result
    feasible: jax.Array
    found: jax.Array


def solve_catalog(problem: Problem, x0, option_thetas, options: SolverOptions = SolverOptions(), *,
                  option_lower=None, option_upper=None) -> CatalogResult:
    """Solve every catalog option in one vmap and pick the best feasible one.

    ``option_thetas``: pytree of parameters with a leading axis of K options (each option's θ).
    ``option_lower``/``option_upper``: optional (K, n) bounds per option (e.g. fixing the
    variables an item determines, lower = upper). ``x0``: shared start (n,) or (K, n)."""
    check_start(problem, x0, where="solve_catalog")
    leaves = jax.tree_util.tree_leaves(option_thetas)
    if not leaves:
        raise DomainError("solve_catalog: option_thetas must hold at least one array with a leading option axis")
    k = leaves[0].shape[0]
    lo = jnp.broadcast_to(problem.lower if option_lower is None else jnp.asarray(option_lower, float), (k, problem.n))
    hi = jnp.broadcast_to(problem.upper if option_upper is None else jnp.asarray(option_upper, float), (k, problem.n))
    x0 = jnp.broadcast_to(jnp.asarray(x0, float), (k, problem.n))

    def one(start, th, l, u):
        return solve(problem.with_bounds(l, u), start, th, options)

    results = jax.vmap(one)(x0, option_thetas, lo, hi)
    i, found = _pick_best(results)
    return CatalogResult(_select(results, i), i, results, results.feasible, found)


__all__ = ["MixedIntegerResult", "CatalogResult", "solve_mixed_integer", "solve_catalog", "rounding_candidates"]
