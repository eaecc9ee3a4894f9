"""Pareto fronts of several objectives by epsilon-constraint continuation.

Objectives F(x, θ) ∈ Rᴷ (all minimised) over the feasible set of a :class:`Problem` are traded
by the ε-constraint scalarisation (Y. Haimes, L. Lasdon, D. Wismer, "On a bicriterion
formulation of the problems of integrated system identification and system optimization",
IEEE Trans. SMC 1 (1971) 296):

    minimise  Σₖ wₖ Fₖ(x, θ)/sₖ   s.t.  Fⱼ(x, θ) ≤ εⱼ  (j with bounded[j]),   g ≤ 0,  h = 0,  box,

with sₖ > 0 fixed objective scales. A grid point minimises F₀/s₀ + δ Σⱼ Fⱼ/sⱼ (δ =
``AUGMENTATION``, the augmented ε-constraint method of G. Mavrotas, Appl. Math. Comput. 213
(2009) 455, in its weighted-sum form): where the bound εⱼ leaves Fⱼ free to improve (a tie in
F₀, e.g. with an integer F₀), the answer still does not sit at a weakly dominated point. Its θ is ``(problem θ, Scalarization(w, ε, bounded))``
(:func:`scalarized_problem`), so every point of a front is a lane of one compiled program
(:mod:`diffsense.optimize.lanes`).

Steps of :func:`trace_front` (each lane a group: e.g. a catalog option; its own front):

1. **Anchors** (each objective's own optimum, the rows of the payoff table): w = eₖ, nothing
   bounded; then lexicographically, Fₖ held at its optimum (ε = Fₖ*·(1 + 1e-9)) while the sum
   of the other scaled objectives is minimised, so that an anchor is not weakly dominated.
2. **Grid.** Objective 0 is minimised; objectives 1 … K−1 are bounded by ε on a grid between
   their best and worst anchor values (``points`` values for K = 2, ⌈points^(1/(K−1))⌉ per
   axis for K ≥ 3, walked boustrophedon so that each point neighbours the last), evenly spaced
   in ln F for an objective that stays positive and spans more than a decade (and at most
   ``LOG_GRID_MAX_RATIO``: a wider span means a numerical zero at the low end) over the
   anchors, linearly otherwise.
3. **Continuation** (predictor–corrector, E. Allgower and K. Georg, *Numerical Continuation
   Methods*, Springer 1990, ch. 2) along K walks per group (:func:`walks`; K = 2: from both
   anchors towards the middle of the grid): each grid point is solved from a predicted start
   x̂ = x* + (dx*/dε)·Δε, the tangent dx*/dε of the walk's last solution by the active-set
   KKT derivative (:mod:`diffsense.optimize.sensitivity`), computed in the same compiled call
   as the solve; after an infeasible grid point (below the front) the last feasible answer is
   the start. The G·K walks are independent: one call advances every one of them by a grid
   point (lanes of one program, ``lockstep`` of them per vmap), so a front of N points takes
   about N/K calls after the two anchor calls, every call of the same shape (one compilation).

Then :func:`pareto_mask` keeps the non-dominated points and :func:`knee_index` picks the knee:
the point farthest from the hyperplane through the anchors in objectives normalised to the
ideal–nadir box (I. Das, "On characterizing the 'knee' of the Pareto curve based on Normal-
Boundary Intersection", Struct. Optim. 18 (1999) 107). The normal-boundary intersection
itself (Das & Dennis, SIAM J. Optim. 8 (1998) 631) is not used: its equality constraints
are harder for the solver than ε bounds and may return dominated points.
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from dataclasses import dataclass
from typing import Callable, List, NamedTuple, Optional, Union

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.optimize.batch import map_in_lockstep, resolve_lockstep
from diffsense.optimize.compile import jit_with_options
from diffsense.optimize.entry import solve
from diffsense.optimize.integer import integer_neighbours
from diffsense.optimize.kkt import kkt_max
from diffsense.optimize.lanes import solve_in_batches, take
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.programs import LazyProgram, register_serializable
from diffsense.optimize.sensitivity import linearised_kkt

#: relative slack of an anchor's own objective in its lexicographic second solve
ANCHOR_SLACK = 1e-9
#: largest ratio of an objective's anchor values spaced in ln F (above: linear spacing)
LOG_GRID_MAX_RATIO = 1e6
#: weight δ of each bounded (scaled) objective in a grid point's minimised sum
AUGMENTATION = 1e-6


class Scalarization(NamedTuple):
    """ε-constraint scalarisation of K objectives (arrays of shape (K,)): ``weights`` of the
    scaled objectives in the minimised sum, ``bounds`` ε (units of the objectives),
    ``bounded`` (1.0 where Fⱼ ≤ εⱼ is imposed, 0.0 where not; a float so that θ can be
    differentiated) and ``scales`` sₖ > 0 (None: the scales given to
    :func:`scalarized_problem`). Every field is a traced argument of the compiled program, so
    one compilation serves every point, anchor and scaling of a problem."""

    weights: jax.Array
    bounds: jax.Array
    bounded: jax.Array
    scales: Optional[jax.Array] = None


register_serializable(Scalarization)


def scalarized_problem(problem: Problem, objectives: Callable, scales=None) -> Problem:
    """The ε-constraint problem (module docstring) of ``objectives(x, θ) -> (K,)`` over the
    feasible set of ``problem``; its θ is ``(problem θ, Scalarization)``; its inequalities are
    ``problem``'s followed by the K scaled bounds (Fⱼ − εⱼ)/sⱼ (−1 where not bounded). The
    scales sₖ are ``scales`` when given, else the θ's ``Scalarization.scales``."""
    fixed = None if scales is None else jnp.asarray(np.asarray(scales, dtype=float))
    integer = np.zeros(problem.n, dtype=bool)
    integer[list(problem.integer_indices)] = True

    def scale_of(sc):
        return fixed if sc.scales is None else sc.scales

    def scaled(x, theta):
        return jnp.reshape(objectives(x, theta[0]), (-1,)) / scale_of(theta[1])

    def objective(x, theta):
        return jnp.dot(theta[1].weights, scaled(x, theta))

    def inequality(x, theta):
        sc = theta[1]
        eps = jnp.where(sc.bounded > 0.5, scaled(x, theta) - sc.bounds / scale_of(sc), -1.0)
        return jnp.concatenate([problem.g(x, theta[0]), eps])

    equality = None if problem.equality is None else (lambda x, theta: problem.h(x, theta[0]))
    return Problem(objective, np.asarray(problem.lower), np.asarray(problem.upper), inequality=inequality,
                   equality=equality, scale=np.asarray(problem.scale), log_scale=np.asarray(problem.log_scale),
                   integer=integer, names=problem.names)


def _build_step(problem: Problem, objectives: Callable, options: SolverOptions, lockstep: Optional[int],
                tangent: bool, structure: Optional[str] = None):
    sproblem = scalarized_problem(problem, objectives)

    def one(x0, theta, lower, upper, next_bounds):
        p = sproblem.with_bounds(lower, upper)
        res = solve(p, x0, theta, options)
        if not tangent:
            return res, res.x
        parts, z, derivative, unpack = linearised_kkt(p, res, theta, options)
        base, sc = theta
        delta = next_bounds - sc.bounds
        _, (r_dot, c_dot) = jax.jvp(lambda b: parts(z, (base, sc._replace(bounds=b))), (sc.bounds,), (delta,))
        dz, dmu = derivative(r_dot, c_dot)
        dx = unpack(dz, dmu)[0]
        x_hat = jnp.clip(res.x + dx, lower, upper)
        return res, jnp.where(jnp.all(jnp.isfinite(x_hat)), x_hat, res.x)

    def run(x0, theta, lower, upper, next_bounds):
        return map_in_lockstep(one, (x0, theta, lower, upper, next_bounds), lockstep)

    if structure is not None:
        return LazyProgram("front", run, f"{structure}\n{options!r}\n{lockstep!r}\n{tangent!r}")
    return jit_with_options(run, "optimized")


#: compiled step programs by (problem, objectives, options, lockstep, tangent), most recent last
_PROGRAMS: "OrderedDict[tuple, tuple]" = OrderedDict()
#: how many step programs :func:`step_program` keeps
PROGRAM_CACHE_SIZE = 16


def step_program(problem: Problem, objectives: Callable, options: SolverOptions,
                 lockstep: Union[int, str, None] = "auto", tangent: bool = True, structure: Optional[str] = None):
    """Jitted ``fn(x0, theta, lower, upper, next_bounds) -> (Result, x̂)`` over lanes (leading
    axis of every argument) of the ε-constraint problem of ``objectives`` over ``problem``
    (:func:`scalarized_problem`, scales traced in θ): each lane's solve and the predicted start
    x̂ = x* + (dx*/dε)·(next_bounds − ε) of its next point, clipped to the box (x* where the
    tangent is not finite, or everywhere with ``tangent`` False).

    The program is built once per (``problem``, ``objectives`` — the same objects —,
    ``options``, ``lockstep``, ``tangent``) and kept (the last :data:`PROGRAM_CACHE_SIZE`):
    starts, θ (the ε values, weights, scales), boxes and predictions are its arguments, so a
    second front of the same problem compiles nothing. ``structure``: a description of
    everything the two functions compute besides their arguments (e.g. a design model's
    structure and the objectives' terms and weights); given, the program is traced once per
    structure and kept on disk (:mod:`diffsense.optimize.programs`)."""
    k = resolve_lockstep(lockstep)
    key = (id(problem), id(objectives), options, k, bool(tangent), structure)
    hit = _PROGRAMS.get(key)
    if hit is not None and hit[0] is problem and hit[1] is objectives:
        _PROGRAMS.move_to_end(key)
        return hit[2]
    program = _build_step(problem, objectives, options, k, bool(tangent), structure)
    _PROGRAMS[key] = (problem, objectives, program)
    while len(_PROGRAMS) > PROGRAM_CACHE_SIZE:
        _PROGRAMS.popitem(last=False)
    return program


@dataclass
class Front:
    """Every point :func:`trace_front` solved (NumPy; leading axis: the point).

    ``x`` (N, n); ``objectives`` (N, K) at x; ``group`` (N,); ``anchor`` (N,) the objective a
    point anchors, −1 for grid points; ``bounds`` (N, K) the ε of each point (NaN where not
    bounded); ``converged``, ``feasible`` (N,); ``kkt_residual`` (N,) the largest scaled KKT
    residual; ``lam`` (N, m) multipliers of ``problem``'s own inequalities; ``calls`` compiled
    calls made; ``trips`` the solver's inner iterations summed over every solve (each one
    evaluation of the problem's functions and gradients)."""

    x: np.ndarray
    objectives: np.ndarray
    group: np.ndarray
    anchor: np.ndarray
    bounds: np.ndarray
    converged: np.ndarray
    feasible: np.ndarray
    kkt_residual: np.ndarray
    lam: np.ndarray
    calls: int
    trips: int


class _Solved(NamedTuple):
    x: np.ndarray
    converged: np.ndarray
    feasible: np.ndarray
    kkt: np.ndarray
    lam: np.ndarray


def _record(res, m: int) -> _Solved:
    return _Solved(np.asarray(res.x), np.asarray(res.converged, bool), np.asarray(res.feasible, bool),
                   np.asarray(kkt_max(res.kkt)), np.asarray(res.lam)[:, :m])


def grid_axes(low, high, points: int) -> List[np.ndarray]:
    """ε values per bounded objective (1 … K−1) between ``low`` and ``high`` (K,) (module
    docstring, step 2); ``points`` per axis.

    >>> [a.round(6).tolist() for a in grid_axes(np.array([0.0, 1.0]), np.array([5.0, 100.0]), 3)]
    [[1.0, 10.0, 100.0]]
    """
    axes = []
    for lo, hi in zip(np.asarray(low)[1:], np.asarray(high)[1:]):
        if lo > 0 and 10.0 * lo < hi <= LOG_GRID_MAX_RATIO * lo:
            axes.append(np.exp(np.linspace(np.log(lo), np.log(hi), points)))
        else:
            axes.append(np.linspace(lo, hi, points))
    return axes


def snake(axes: List[np.ndarray]) -> np.ndarray:
    """Grid points of ``axes`` (rows of ε values), boustrophedon: consecutive rows differ in
    one axis by one step.

    >>> snake([np.array([1.0, 2.0]), np.array([5.0, 6.0])]).tolist()
    [[1.0, 5.0], [1.0, 6.0], [2.0, 6.0], [2.0, 5.0]]
    """
    if len(axes) == 1:
        return axes[0][:, None]
    rest = snake(axes[1:])
    rows = []
    for i, v in enumerate(axes[0]):
        block = rest if i % 2 == 0 else rest[::-1]
        rows.extend([[v, *r] for r in block])
    return np.array(rows)


class _Sweep:
    """State of :func:`trace_front`: the compiled step, the lanes' θ and boxes, and counters;
    every call solves ``batch`` lanes (one compiled shape)."""

    def __init__(self, problem, objectives, options, lockstep, thetas, scales, lower, upper, K, m, batch,
                 structure=None, tangent=True):
        self.tangent = bool(tangent)
        self.step = step_program(problem, objectives, options, lockstep, tangent=self.tangent, structure=structure)
        self._fallback = lambda: step_program(problem, objectives, dataclasses.replace(options, polish=False),
                                              lockstep, tangent=False, structure=structure)
        self.thetas, self.scales, self.lower, self.upper = thetas, np.asarray(scales, float), lower, upper
        self.K, self.m, self.batch = K, m, batch
        self.calls = self.trips = 0

    def theta(self, rows, weights, bounds, bounded):
        n = len(rows)
        sc = Scalarization(np.asarray(weights, float), np.asarray(bounds, float), np.asarray(bounded, float),
                           np.tile(self.scales, (n, 1)))
        return (take(self.thetas, rows), sc)

    def run(self, rows, x0, weights, bounds, bounded, next_bounds=None, lower=None, upper=None):
        """Solve lanes ``rows`` (group indices; boxes: the groups' unless given) in calls of
        ``batch`` lanes; returns (solved, x̂)."""
        next_bounds = bounds if next_bounds is None else next_bounds
        lower = self.lower[rows] if lower is None else lower
        upper = self.upper[rows] if upper is None else upper
        args = (np.asarray(x0, float), self.theta(rows, weights, bounds, bounded), lower, upper,
                np.asarray(next_bounds, float))
        try:
            res, x_hat = solve_in_batches(self.step, self.batch, *args)
        except NotImplementedError:
            # a model without second derivatives (e.g. the regularised incomplete gamma
            # function's order derivative): no Newton polish, no tangent; the caller predicts by secant
            if not self.tangent:
                raise
            self.tangent, self.step = False, self._fallback()
            res, x_hat = solve_in_batches(self.step, self.batch, *args)
        self.calls += -(-len(rows) // self.batch)
        self.trips += int(np.sum(res.inner_iterations))
        return _record(res, self.m), x_hat


def _anchors(sweep: _Sweep, x0, values):
    """Lexicographic anchors of every group: (solved, F (G·K, K)), group-major."""
    G, K = x0.shape[0], sweep.K
    rows = np.repeat(np.arange(G), K)
    eye = np.tile(np.eye(K), (G, 1))
    zeros = np.zeros((G * K, K))
    first, _ = sweep.run(rows, np.repeat(x0, K, axis=0), eye, zeros, zeros)
    F = values(first.x, rows)
    own = F[np.arange(G * K), np.tile(np.arange(K), G)]
    eps = zeros.copy()
    eps[np.arange(G * K), np.tile(np.arange(K), G)] = own + ANCHOR_SLACK * np.maximum(np.abs(own), 1e-300)
    second, _ = sweep.run(rows, first.x, 1.0 - eye, eps, eye)
    use = second.feasible & (second.converged | ~first.converged)
    best = _Solved(*[np.where(use.reshape((-1,) + (1,) * (a.ndim - 1)), b, a) for a, b in zip(first, second)])
    return best, values(best.x, rows)


def walks(FA, per_axis: int):
    """The grid of one group cut into K walks, each ``(ε rows (·, K−1), anchor it starts from)``
    (module docstring, steps 2–3). ``FA`` (K, K): the anchors' objectives. K = 2: the grid
    without its ends (the anchors) walked from both anchors towards the middle; K ≥ 3: the
    boustrophedon path cut into K consecutive pieces, each started from the anchor nearest
    its first point in the ideal–nadir box.

    >>> [(w.ravel().tolist(), a) for w, a in walks(np.array([[0.0, 4.0], [4.0, 0.0]]), 5)]
    [([1.0, 2.0], 1), ([3.0], 0)]
    """
    K = FA.shape[0]
    low, high = FA.min(axis=0), FA.max(axis=0)
    grid = snake(grid_axes(low, high, per_axis))
    if K == 2:
        inner = grid[1:-1]
        half = -(-len(inner) // 2)
        return [(inner[:half], 1), (inner[half:][::-1], 0)]
    span = np.where(high > low, high - low, 1.0)[1:]
    out = []
    for piece in np.array_split(grid, K):
        if len(piece) == 0:
            out.append((piece, 0))
            continue
        dist = np.linalg.norm((FA[:, 1:] - piece[0]) / span, axis=1)
        out.append((piece, int(np.argmin(dist))))
    return out


def _values_program(objectives: Callable):
    """Jitted ``(x (N, n), θ rows) -> F (N, K)`` of ``objectives``, kept per function object."""
    hit = _VALUES.get(id(objectives))
    if hit is not None and hit[0] is objectives:
        return hit[1]
    program = jax.jit(jax.vmap(lambda x, th: jnp.reshape(objectives(x, th), (-1,))))
    _VALUES[id(objectives)] = (objectives, program)
    while len(_VALUES) > PROGRAM_CACHE_SIZE:
        _VALUES.pop(next(iter(_VALUES)))
    return program


_VALUES: dict = {}


def trace_front(problem: Problem, objectives: Callable, thetas, x0, *, points: int = 30, scales=None,
                options: Optional[SolverOptions] = None, lockstep: Union[int, str, None] = "auto",
                values: Optional[Callable] = None, structure: Optional[str] = None,
                tangent: bool = True) -> Front:
    """Trace the Pareto front of ``objectives(x, θ) -> (K,)`` (minimised, K ≥ 2) over
    ``problem``'s feasible set for every group (module docstring).

    ``thetas``: pytree whose leaves have a leading axis of G groups (each group's θ, floating
    leaves); ``x0`` (G, n) the start of each group's anchors; ``points``: grid values (K = 2:
    points on the front, anchors included; K ≥ 3: per axis ⌈points^(1/(K−1))⌉); ``scales``
    (K,) the objectives' scales sₖ (default |F| at the first group's start, 1 where 0).
    Every call solves G·K lanes (the anchors; then the K walks of every group side by side)
    through one program compiled per (``problem``, ``objectives``) (:func:`step_program`):
    pass the same function objects to reuse it. ``values``: ``fn(x (N, n), groups (N,)) -> F
    (N, K)``, the objectives at solved points (by a program the caller has already compiled;
    default: a vmapped ``objectives``, compiled here). ``structure``: see :func:`step_program`.
    ``tangent`` False predicts each next point by the secant of the last two (K = 2) instead of
    the KKT tangent (no second derivatives in the program: a much smaller one)."""
    x0 = np.atleast_2d(np.asarray(x0, dtype=float))
    G = x0.shape[0]
    if values is None:
        obj = _values_program(objectives)

        def values(x, rows):
            return np.asarray(obj(jnp.asarray(x), jax.tree_util.tree_map(jnp.asarray, take(thetas, rows))))

    F0 = values(x0[:1], np.array([0]))[0]
    K = F0.shape[0]
    if K < 2 or points < 2:
        raise DomainError(f"trace_front: needs at least 2 objectives and 2 points; got {K} and {points}")
    if scales is None:
        scales = np.where(np.isfinite(F0) & (np.abs(F0) > 0), np.abs(F0), 1.0)
    m = problem.constraint_sizes(take(thetas, 0))[0]
    lower = np.broadcast_to(np.asarray(problem.lower), x0.shape).copy()
    upper = np.broadcast_to(np.asarray(problem.upper), x0.shape).copy()
    sweep = _Sweep(problem, objectives, options or SolverOptions(polish=True), lockstep, thetas, scales, lower,
                   upper, K, m, G * K, structure=structure, tangent=tangent)
    anchors, FA = _anchors(sweep, x0, values)
    FA = FA.reshape(G, K, K)
    ax_x = anchors.x.reshape(G, K, -1)
    per_axis = points if K == 2 else int(np.ceil(points ** (1.0 / (K - 1)) - 1e-9))
    lane_walks, x_start = [], []
    for g in range(G):
        for path, a in walks(FA[g], per_axis):
            lane_walks.append(path)
            x_start.append(ax_x[g, a])
    out = _walk(sweep, lane_walks, np.array(x_start), np.repeat(np.arange(G), K))
    grid_solved = _Solved(*[np.concatenate(a) for a in zip(*out["solved"])]) if out["solved"] else None
    front = _repair(sweep, _assemble(anchors, FA, grid_solved, out, values, K, sweep), values, scales)
    return _round_integers(sweep, problem, front, values, scales) if problem.integer_indices else front


def _walk(sweep: _Sweep, lane_walks, x_start, lane_group) -> dict:
    """Continuation along every lane's walk at once (module docstring, step 3); a lane whose
    walk is over re-solves its last point from its answer (a converged start: a few trips)."""
    K = sweep.K
    L = len(lane_walks)
    lengths = np.array([len(w) for w in lane_walks])
    weights = np.tile(np.r_[1.0, np.full(K - 1, AUGMENTATION)], (L, 1))
    bounded = np.tile(np.r_[0.0, np.ones(K - 1)], (L, 1))
    bounded[lengths == 0] = 0.0  # an empty walk's lane: its anchor's neighbourhood, nothing bounded
    lower, upper = sweep.lower[lane_group], sweep.upper[lane_group]
    good = x_start.copy()
    prev_eps = None
    out = {"x": [], "group": [], "bounds": [], "solved": []}
    for i in range(int(lengths.max(initial=0))):
        live = i < lengths
        eps = np.zeros((L, K))
        nxt = np.zeros((L, K))
        for lane, w in enumerate(lane_walks):
            if len(w):
                eps[lane, 1:] = w[min(i, len(w) - 1)]
                nxt[lane, 1:] = w[min(i + 1, len(w) - 1)]
        x0 = np.where(live[:, None], x_start, good)
        solved, x_hat = sweep.run(lane_group, x0, weights, eps, bounded, nxt)
        ok = solved.feasible & live
        if not sweep.tangent and K == 2 and prev_eps is not None:
            x_hat = _secant(solved.x, good, eps[:, 1], prev_eps, nxt[:, 1], lower, upper)
        prev_eps = eps[:, 1] if prev_eps is None else np.where(ok, eps[:, 1], prev_eps)
        good = np.where(ok[:, None], solved.x, good)
        x_start = np.where(ok[:, None], x_hat, good)
        out["solved"].append(take(solved, live))
        out["x"].append(solved.x[live])
        out["group"].append(lane_group[live])
        out["bounds"].append(np.where(bounded > 0.5, eps, np.nan)[live])
    return out


def _repair(sweep: _Sweep, front: Front, values, scales) -> Front:
    """Grid points the walk left unconverged or infeasible re-solved once, each from the
    converged point of its group nearest to it in the scaled bounded objectives (a start on
    the front next to it); an answer that converges and is feasible replaces the point."""
    ok = front.converged & front.feasible
    bad = np.flatnonzero((front.anchor < 0) & ~ok)
    if bad.size == 0 or not ok.any():
        return front
    s = np.asarray(scales, float)[1:]
    starts, keep = [], []
    for i in bad:
        mates = np.flatnonzero(ok & (front.group == front.group[i]))
        if mates.size:
            dist = np.linalg.norm((front.objectives[mates, 1:] - front.bounds[i, 1:]) / s, axis=1)
            starts.append(front.x[mates[int(np.argmin(dist))]])
            keep.append(i)
    if not keep:
        return front
    keep = np.array(keep)
    K = front.objectives.shape[1]
    weights = np.tile(np.r_[1.0, np.full(K - 1, AUGMENTATION)], (keep.size, 1))
    bounded = np.isfinite(front.bounds[keep]).astype(float)
    solved, _ = sweep.run(front.group[keep], np.array(starts), weights, np.nan_to_num(front.bounds[keep]), bounded)
    better = solved.converged & solved.feasible
    out = Front(**{k: (np.array(v, copy=True) if isinstance(v, np.ndarray) else v) for k, v in vars(front).items()})
    rows = keep[better]
    out.x[rows], out.converged[rows], out.feasible[rows] = solved.x[better], True, True
    out.kkt_residual[rows], out.lam[rows] = solved.kkt[better], solved.lam[better]
    if rows.size:
        out.objectives[rows] = values(out.x[rows], out.group[rows])
    out.calls, out.trips = sweep.calls, sweep.trips
    return out


def _secant(x, x_prev, eps, eps_prev, eps_next, lower, upper):
    """Secant predictor x + (x − x_prev)·(ε_next − ε)/(ε − ε_prev), clipped to the box (Allgower
    & Georg 1990, §2.2); x where the last step did not move ε."""
    step = eps - eps_prev
    ratio = np.where(np.abs(step) > 0, (eps_next - eps) / np.where(step != 0, step, 1.0), 0.0)
    return np.clip(x + (x - x_prev) * ratio[:, None], lower, upper)


def _assemble(anchors: _Solved, FA, grid: Optional[_Solved], out, values, K: int, sweep: _Sweep) -> Front:
    G = FA.shape[0]
    a_group = np.repeat(np.arange(G), K)
    parts = [anchors]
    groups = [a_group]
    kind = [np.tile(np.arange(K), G)]
    bounds = [np.full((G * K, K), np.nan)]
    if grid is not None:
        parts.append(grid)
        groups.append(np.concatenate(out["group"]))
        kind.append(np.full(groups[-1].shape, -1))
        bounds.append(np.concatenate(out["bounds"]))
    s = _Solved(*[np.concatenate(a) for a in zip(*parts)])
    group = np.concatenate(groups)
    return Front(x=s.x, objectives=values(s.x, group), group=group, anchor=np.concatenate(kind),
                 bounds=np.concatenate(bounds), converged=s.converged, feasible=s.feasible, kkt_residual=s.kkt,
                 lam=s.lam, calls=sweep.calls, trips=sweep.trips)


def _round_integers(sweep: _Sweep, problem: Problem, front: Front, values, scales) -> Front:
    """Integers as in :mod:`diffsense.optimize.integer`: every point re-solved at the integer
    neighbours of its relaxed answer (the rest continuous, its own scalarisation: an anchor its
    objective alone, a grid point objective 0 under its ε bounds); the feasible, converged
    neighbour of lowest scalarised value replaces it (the rounded relaxed answer, flagged
    unconverged, when there is none)."""
    K = front.objectives.shape[1]
    N = front.x.shape[0]
    grid_weights = np.r_[1.0, np.full(K - 1, AUGMENTATION)]
    weights = np.where(front.anchor[:, None] >= 0, np.eye(K)[np.maximum(front.anchor, 0)], grid_weights)
    bounded = np.isfinite(front.bounds).astype(float)
    bounds = np.where(bounded > 0, front.bounds, 0.0)
    cand = integer_neighbours(problem, front.x)
    c = cand.group
    solved, _ = sweep.run(front.group[c], cand.x0, weights[c], bounds[c], bounded[c], lower=cand.lower,
                          upper=cand.upper)
    F = values(solved.x, front.group[c])
    score = np.where(solved.feasible & solved.converged, np.sum(weights[c] * F / np.asarray(scales), axis=1), np.inf)
    out = Front(**{k: (np.array(v, copy=True) if isinstance(v, np.ndarray) else v) for k, v in vars(front).items()})
    idx = np.asarray(problem.integer_indices, dtype=int)
    for i in range(N):
        mine = np.flatnonzero(c == i)
        j = mine[int(np.argmin(score[mine]))]
        if np.isfinite(score[j]):
            out.x[i], out.objectives[i] = solved.x[j], F[j]
            out.converged[i], out.feasible[i] = solved.converged[j], solved.feasible[j]
            out.kkt_residual[i], out.lam[i] = solved.kkt[j], solved.lam[j]
        else:
            out.x[i, idx] = np.round(out.x[i, idx])
            out.objectives[i] = values(out.x[i:i + 1], front.group[i:i + 1])[0]
            out.converged[i] = False
    out.calls, out.trips = sweep.calls, sweep.trips
    return out


def pareto_mask(F, rtol: float = 1e-9) -> np.ndarray:
    """Mask of the non-dominated rows of ``F`` (N, K), all minimised: a row is dominated when
    another is no worse in every objective and better by more than ``rtol``·(1 + |F|) in one;
    of rows equal within that tolerance the first is kept.

    >>> pareto_mask(np.array([[1.0, 3.0], [2.0, 2.0], [2.0, 3.0], [3.0, 1.0], [1.0, 3.0]])).tolist()
    [True, True, False, True, False]
    """
    F = np.asarray(F, dtype=float)
    tol = rtol * (1.0 + np.abs(F))
    keep = np.ones(F.shape[0], dtype=bool)
    for i in range(F.shape[0]):
        no_worse = np.all(F <= F[i] + tol[i], axis=1)
        better = np.any(F < F[i] - tol[i], axis=1)
        equal = ~better & np.all(np.abs(F - F[i]) <= tol[i], axis=1)
        if np.any(no_worse & better) or np.any(equal[:i] & keep[:i]):
            keep[i] = False
    return keep


def normalized(F, ideal=None, nadir=None) -> np.ndarray:
    """``F`` mapped to the ideal–nadir box: (F − ideal)/(nadir − ideal), columns of zero span left 0."""
    F = np.asarray(F, dtype=float)
    ideal = F.min(axis=0) if ideal is None else np.asarray(ideal, float)
    nadir = F.max(axis=0) if nadir is None else np.asarray(nadir, float)
    span = np.where(nadir > ideal, nadir - ideal, 1.0)
    return (F - ideal) / span


def knee_index(F) -> int:
    """Row of the knee of a front ``F`` (N, K): in the ideal–nadir box, the point farthest
    below the hyperplane Σ fₖ = 1 through the normalised anchors (Das 1999, module docstring).

    >>> knee_index(np.array([[0.0, 1.0], [0.1, 0.1], [0.5, 0.02], [1.0, 0.0]]))
    1
    """
    f = normalized(F)
    return int(np.argmax(1.0 - f.sum(axis=1)))


def hypervolume_2d(F, reference) -> float:
    """Area dominated by the 2-objective points ``F`` (minimised) and bounded by ``reference``.

    >>> hypervolume_2d(np.array([[1.0, 2.0], [2.0, 1.0]]), [3.0, 3.0])
    3.0
    """
    F = np.asarray(F, dtype=float)
    F = F[np.all(F < np.asarray(reference), axis=1)]
    F = F[np.argsort(F[:, 0])]
    area, y = 0.0, float(reference[1])
    for f0, f1 in F:
        if f1 < y:
            area += (reference[0] - f0) * (y - f1)
            y = f1
    return float(area)


__all__ = ["Scalarization", "scalarized_problem", "step_program", "Front", "trace_front", "grid_axes", "snake",
           "pareto_mask", "normalized", "knee_index", "hypervolume_2d", "walks", "ANCHOR_SLACK",
           "AUGMENTATION", "PROGRAM_CACHE_SIZE", "LOG_GRID_MAX_RATIO"]
