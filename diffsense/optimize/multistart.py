"""Multistart: seeded space-filling starts, one compiled solve of them all, clustering of the optima.

The local solver returns the KKT point reached from its start. For nonconvex design problems
several starts are solved at once (each start a lane of one compiled program,
:mod:`diffsense.optimize.lanes`) and the optima are clustered:

* Starts are drawn in the solver's scaled coordinates (so log-scaled variables are sampled
  log-uniformly) from a scrambled Sobol sequence or a Latin hypercube, both written here in
  NumPy and seeded (reproducible).
* Sobol points: Bratley & Fox's Gray-code construction (ACM TOMS 14 (1988) 88–100) with the
  direction numbers of S. Joe & F. Y. Kuo, "Constructing Sobol sequences with better
  two-dimensional projections", SIAM J. Sci. Comput. 30 (2008) 2635–2654 (their table
  new-joe-kuo-6.21201, dimensions 1–32 transcribed below). Scrambling is Matoušek's random
  linear matrix scramble plus a random digital shift (J. Matoušek, "On the L2-discrepancy for
  anchored boxes", J. Complexity 14 (1998) 527–556), which keeps the (t, m, s)-net property:
  every base-2 elementary interval of the right volume holds the same number of points.
* Latin hypercube: each coordinate's n strata hold exactly one point (McKay, Beckman &
  Conover, Technometrics 21 (1979) 239–245).
* Clustering: starts that converged to a feasible KKT point are visited in increasing f;
  each joins the nearest existing cluster leader within ``x_tol`` (∞-norm in scaled
  coordinates, relative to max(1, ‖z‖∞)) or becomes a leader. Fixed shapes, jit-able.
* ``success_rate`` is the fraction of *all* starts (failed ones included) that converged,
  are feasible and reach the best objective within ``f_rtol``·max(1, |f_best|).
"""

from __future__ import annotations

from typing import NamedTuple, Optional, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_choice, check_range
from diffsense.optimize.lanes import best_per_group, lane_grid, make_lane_solver, solve_lanes, take
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.result import Result
from diffsense.optimize.problem import Problem

# Joe & Kuo (2008), new-joe-kuo-6.21201: (s, a, m_1..m_s) for dimensions 2..32; dimension 1
# is the van der Corput sequence (all m_i = 1).
_JOE_KUO = (
    (1, 0, (1,)),
    (2, 1, (1, 3)),
    (3, 1, (1, 3, 1)),
    (3, 2, (1, 1, 1)),
    (4, 1, (1, 1, 3, 3)),
    (4, 4, (1, 3, 5, 13)),
    (5, 2, (1, 1, 5, 5, 17)),
    (5, 4, (1, 1, 5, 5, 5)),
    (5, 7, (1, 1, 7, 11, 19)),
    (5, 11, (1, 1, 5, 1, 1)),
    (5, 13, (1, 1, 1, 3, 11)),
    (5, 14, (1, 3, 5, 5, 31)),
    (6, 1, (1, 3, 3, 9, 7, 49)),
    (6, 13, (1, 1, 1, 15, 21, 21)),
    (6, 16, (1, 3, 1, 13, 27, 49)),
    (6, 19, (1, 1, 1, 15, 7, 5)),
    (6, 22, (1, 3, 1, 15, 13, 25)),
    (6, 25, (1, 1, 5, 5, 19, 61)),
    (7, 1, (1, 3, 7, 11, 23, 15, 103)),
    (7, 4, (1, 3, 7, 13, 13, 15, 69)),
    (7, 7, (1, 1, 3, 13, 7, 35, 63)),
    (7, 8, (1, 3, 5, 9, 1, 25, 53)),
    (7, 14, (1, 3, 1, 13, 9, 35, 107)),
    (7, 19, (1, 3, 1, 5, 27, 61, 31)),
    (7, 21, (1, 1, 5, 11, 19, 41, 61)),
    (7, 28, (1, 3, 5, 3, 3, 13, 69)),
    (7, 31, (1, 1, 7, 13, 1, 19, 1)),
    (7, 32, (1, 3, 7, 5, 13, 19, 59)),
    (7, 37, (1, 1, 3, 9, 25, 29, 41)),
    (7, 41, (1, 3, 5, 13, 23, 1, 55)),
    (7, 42, (1, 3, 7, 3, 13, 59, 17)),
)
SOBOL_MAX_DIM = 1 + len(_JOE_KUO)
_BITS = 32


def _direction_numbers(dim: int) -> np.ndarray:
    """(dim, 32) direction integers V[j, i] = v_{j,i+1}·2^32 (Bratley & Fox recurrence)."""
    V = np.zeros((dim, _BITS), dtype=np.uint64)
    for i in range(_BITS):
        V[0, i] = np.uint64(1) << np.uint64(_BITS - 1 - i)
    for j in range(1, dim):
        s, a, m = _JOE_KUO[j - 1]
        v = [0] * _BITS
        for i in range(min(s, _BITS)):
            v[i] = m[i] << (_BITS - 1 - i)
        for i in range(s, _BITS):
            val = v[i - s] ^ (v[i - s] >> s)
            for k in range(1, s):
                if (a >> (s - 1 - k)) & 1:
                    val ^= v[i - k]
            v[i] = val
        V[j] = np.asarray(v, dtype=np.uint64)
    return V


def _parity(x: np.ndarray) -> np.ndarray:
    x = x ^ (x >> np.uint64(32))
    x = x ^ (x >> np.uint64(16))
    x = x ^ (x >> np.uint64(8))
    x = x ^ (x >> np.uint64(4))
    x = x ^ (x >> np.uint64(2))
    x = x ^ (x >> np.uint64(1))
    return x & np.uint64(1)


def _scramble_directions(V: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Matoušek linear matrix scramble: V' = L·V over GF(2), L random unit lower triangular."""
    dim = V.shape[0]
    out = np.zeros_like(V)
    for j in range(dim):
        # row r of L as a 32-bit mask over digit positions (bit 31 is the first digit)
        rows = np.zeros(_BITS, dtype=np.uint64)
        for r in range(_BITS):
            below = rng.integers(0, 2, size=r) if r > 0 else np.zeros(0, dtype=int)
            mask = np.uint64(1) << np.uint64(_BITS - 1 - r)
            for c in range(r):
                if below[c]:
                    mask |= np.uint64(1) << np.uint64(_BITS - 1 - c)
            rows[r] = mask
        for i in range(_BITS):
            acc = np.uint64(0)
            bits = _parity(rows & V[j, i])
            for r in range(_BITS):
                if bits[r]:
                    acc |= np.uint64(1) << np.uint64(_BITS - 1 - r)
            out[j, i] = acc
    return out


def sobol_points(n_points: int, dim: int, *, seed: Optional[int] = 0, scramble: bool = True) -> np.ndarray:
    """First ``n_points`` Sobol points in [0, 1)^dim (Gray-code order), optionally scrambled.

    Unscrambled, the first point is the origin and the sequence equals the Joe–Kuo
    reference generator. With ``scramble`` the points are a random linear scramble plus
    digital shift drawn from ``numpy.random.default_rng(seed)``. Balance properties hold for
    n_points a power of two. dim ≤ 32."""
    check_range("n_points", n_points, 1, 2 ** 31, where="sobol_points")
    check_range("dim", dim, 1, SOBOL_MAX_DIM, where="sobol_points")
    V = _direction_numbers(dim)
    shift = np.zeros(dim, dtype=np.uint64)
    if scramble:
        rng = np.random.default_rng(seed)
        V = _scramble_directions(V, rng)
        shift = rng.integers(0, 2 ** _BITS, size=dim, dtype=np.uint64)
    idx = np.arange(n_points, dtype=np.uint64)
    gray = idx ^ (idx >> np.uint64(1))
    X = np.zeros((n_points, dim), dtype=np.uint64)
    for i in range(_BITS):
        bit = ((gray >> np.uint64(i)) & np.uint64(1)).astype(bool)
        X[bit] ^= V[:, i][None, :]
    X ^= shift[None, :]
    return X.astype(np.float64) / float(2 ** _BITS)


def latin_hypercube(n_points: int, dim: int, *, seed: Optional[int] = 0) -> np.ndarray:
    """Latin hypercube sample in [0, 1)^dim: one point per stratum [k/n, (k+1)/n) per axis."""
    check_range("n_points", n_points, 1, None, where="latin_hypercube")
    check_range("dim", dim, 1, None, where="latin_hypercube")
    rng = np.random.default_rng(seed)
    u = rng.random((n_points, dim))
    perms = np.stack([rng.permutation(n_points) for _ in range(dim)], axis=1)
    return (perms + u) / n_points


def start_points(problem: Problem, n_starts: int, *, seed: Optional[int] = 0, method: str = "sobol",
                 box=None) -> np.ndarray:
    """``n_starts`` starting points (units of the variables), space-filling in scaled coordinates.

    ``box``: optional (lower, upper) physical sampling box replacing infinite bounds (and
    narrowing finite ones); every variable needs a finite sampling range."""
    check_choice("method", method, ("sobol", "lhs"), where="start_points")
    lo = np.asarray(problem.lower, float)
    hi = np.asarray(problem.upper, float)
    if box is not None:
        blo = np.broadcast_to(np.asarray(box[0], float), lo.shape)
        bhi = np.broadcast_to(np.asarray(box[1], float), hi.shape)
        lo = np.maximum(lo, blo)
        hi = np.minimum(hi, bhi)
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise DomainError("start_points: every variable needs a finite sampling range; pass box=(lower, upper)")
    if np.any(lo > hi):
        raise DomainError("start_points: the sampling box does not intersect the bounds")
    # the problem's scaled coordinates, in NumPy (no eager JAX)
    zlo, zhi = problem.to_scaled_host(lo), problem.to_scaled_host(hi)
    if method == "sobol":
        u = sobol_points(n_starts, problem.n, seed=seed, scramble=True)
    else:
        u = latin_hypercube(n_starts, problem.n, seed=seed)
    z = zlo + u * (zhi - zlo)
    x = problem.from_scaled_host(z)
    return np.clip(x, lo, hi)


class Clusters(NamedTuple):
    """Clusters of optima (fixed size N = number of starts; unused slots padded).

    ``labels``: (N,) index of each start's cluster leader, −1 for starts that failed;
    ``is_leader``: (N,); ``size``: (N,) members per leader (0 elsewhere); ``count``: clusters."""

    labels: jax.Array
    is_leader: jax.Array
    size: jax.Array
    count: jax.Array


def cluster_optima(z, f, ok, x_tol: float = 1e-4) -> Clusters:
    """Leader clustering of points ``z`` (N, n) with values ``f`` (N,) over the mask ``ok``."""
    N = z.shape[0]
    order = jnp.argsort(jnp.where(ok, f, jnp.inf))

    def body(t, carry):
        labels, leaders = carry
        i = order[t]
        zi = z[i]
        d = jnp.max(jnp.abs(z - zi[None, :]), axis=1)
        tol = x_tol * jnp.maximum(1.0, jnp.max(jnp.abs(zi)))
        close = leaders & (d <= tol)
        has = jnp.any(close)
        j = jnp.argmin(jnp.where(close, d, jnp.inf))
        labels = labels.at[i].set(jnp.where(ok[i], jnp.where(has, j, i), -1))
        leaders = leaders.at[i].set(ok[i] & ~has)
        return labels, leaders

    labels, leaders = jax.lax.fori_loop(0, N, body, (-jnp.ones(N, dtype=int), jnp.zeros(N, dtype=bool)))
    size = jnp.sum(labels[None, :] == jnp.arange(N)[:, None], axis=1)
    return Clusters(labels, leaders, jnp.where(leaders, size, 0), jnp.sum(leaders))


class MultistartResult(NamedTuple):
    """``best``: best feasible converged solve (least infeasible if none); ``best_index``;
    ``results``: every start's solve (batched); ``starts``: (N, n);
    ``success``: (N,) converged, feasible and within f_rtol of the best;
    ``success_rate``: success count / N; ``converged_rate``, ``feasible_rate``: likewise;
    ``clusters``: :class:`Clusters` of the distinct optima found."""

    best: Result
    best_index: jax.Array
    results: Result
    starts: jax.Array
    success: jax.Array
    success_rate: jax.Array
    converged_rate: jax.Array
    feasible_rate: jax.Array
    clusters: Clusters


def summarize_starts(problem: Problem, starts, results: Result, *, f_rtol: float = 1e-6,
                     x_tol: float = 1e-4) -> MultistartResult:
    """The :class:`MultistartResult` of per-start solves ``results`` (NumPy, one row per start):
    the best converged feasible start (the least infeasible when none is), success and rates,
    and the clusters of the optima (module doc)."""
    starts = np.asarray(starts, dtype=float)
    N = starts.shape[0]
    ok = np.asarray(results.converged) & np.asarray(results.feasible)
    rows, _ = best_per_group(results, np.zeros(N, dtype=int), 1, ok=ok)
    best_index = int(rows[0])
    f = np.asarray(results.f)
    f_best = f[best_index]
    success = ok & (f <= f_best + f_rtol * max(1.0, abs(float(f_best))))
    z = problem.to_scaled(jnp.asarray(results.x))
    clusters = jax.tree_util.tree_map(np.asarray, jax.jit(cluster_optima)(z, jnp.asarray(f), jnp.asarray(ok), x_tol))
    return MultistartResult(take(results, best_index), best_index, results, starts, success, np.sum(success) / N,
                            np.mean(np.asarray(results.converged)), np.mean(np.asarray(results.feasible)), clusters)


def make_multistart(problem: Problem, options: SolverOptions = SolverOptions(), *, f_rtol: float = 1e-6,
                    x_tol: float = 1e-4, compile: str = "optimized", lockstep: Union[int, str, None] = "auto"):
    """``fn(starts, theta=None) -> MultistartResult``: every row of ``starts`` (N, n) a lane of
    one compiled program (:func:`diffsense.optimize.lanes.make_lane_solver`, compiled once per
    N), then :func:`summarize_starts`."""
    solver = make_lane_solver(problem, options, lockstep=lockstep, compile=compile)

    def run(starts, theta=None):
        group_theta = None if theta is None else jax.tree_util.tree_map(lambda a: np.asarray(a)[None], theta)
        lanes = lane_grid(starts, group_theta, lower=problem.lower, upper=problem.upper)
        results = solve_lanes(solver, lanes)
        return summarize_starts(problem, starts, results, f_rtol=f_rtol, x_tol=x_tol)

    return run


def multistart(problem: Problem, starts, theta=None, options: SolverOptions = SolverOptions(), *,
               f_rtol: float = 1e-6, x_tol: float = 1e-4, compile: str = "optimized",
               lockstep: Union[int, str, None] = "auto") -> MultistartResult:
    """Solve from every row of ``starts`` (N, n), then cluster (module doc): one use of
    :func:`make_multistart`."""
    return make_multistart(problem, options, f_rtol=f_rtol, x_tol=x_tol, compile=compile,
                           lockstep=lockstep)(starts, theta)


def run_multistart(problem: Problem, theta=None, *, n_starts: int = 32, seed: Optional[int] = 0,
                   method: str = "sobol", box=None, options: SolverOptions = SolverOptions(),
                   f_rtol: float = 1e-6, x_tol: float = 1e-4, compile: str = "optimized") -> MultistartResult:
    """Convenience: seeded starts (:func:`start_points`) then :func:`make_multistart`."""
    starts = start_points(problem, n_starts, seed=seed, method=method, box=box)
    return make_multistart(problem, options, f_rtol=f_rtol, x_tol=x_tol, compile=compile)(starts, theta)


__all__ = ["sobol_points", "latin_hypercube", "start_points", "cluster_optima", "Clusters", "MultistartResult",
           "summarize_starts", "multistart", "make_multistart", "run_multistart", "SOBOL_MAX_DIM"]
