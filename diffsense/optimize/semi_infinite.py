"""Semi-infinite constraints: the worst case of a smooth function over a box, differentiably.

A requirement that must hold for *every* value of a parameter p in a box B (every range from
50 m to 12 km, every target height from 3 to 30 m) is the semi-infinite constraint

    min_{p ∈ B} v(θ, p) ≥ 0,

v the margin (dB or scaled units) at design θ. Its value is the smallest local minimum of v over
B, and by the envelope theorem (Danskin 1967; Still, *Lectures on semi-infinite programming*,
2018, §2) the derivative of a local minimum value v(θ, p*(θ)) with respect to θ is ∂v/∂θ at p*:
the minimiser's own motion does not contribute, because ∂v/∂p = 0 at an interior minimiser and p*
stays on the face it lies on at a boundary one. So the constraint is evaluated as
v(θ, stop_gradient(p*)) and its automatic derivative is the right one.

Finding p* reliably (:func:`worst_points`), in a fixed-shape, jit/vmap-able program:

1. v on a grid of the box (per dimension uniform, or uniform in log p for dimensions marked log —
   multipath lobes and the R⁻⁴ law are both natural in log range);
2. the grid's local minima (a point no higher than its axis neighbours; a box face counts as a
   side with no neighbour) rank first, the other points after them by value;
3. the ``n_worst`` best-ranked points are refined by exact line minimisation along each grid
   coordinate u (p or log p) in turn — one sweep for an interval, four for a box — each by
   Newton's method on the derivative ∂v/∂u_i = 0 safeguarded by bisection inside the bracket of
   the neighbouring grid points (a grid local minimum has ∂v/∂u_i < 0 at its left neighbour and
   > 0 at its right one). Newton alone is not enough: near a deep multipath null v behaves like
   log|u − u₀|, concave away from the null, where an unguarded Newton step goes the wrong way.
   A minimum between grid points is therefore found to machine precision when the grid resolves
   the basin it lies in — a grid coarser than
   the function's structure can miss a minimum, which is why designs are re-checked afterwards on
   a dense grid independent of this one (:func:`dense_check`) and missed points are handed back
   as extra candidates (``extra`` points enter step 2 as candidates).

Several near-equal minima (two multipath nulls of the same depth) come back as separate points,
so a caller can make each of them a constraint: the active set then holds both, as it must.
Duplicates (two starts converging to one minimum) are returned as they are: identical
constraints are harmless to the augmented Lagrangian.
"""

from __future__ import annotations

from typing import Callable, NamedTuple, Optional, Sequence

import jax
import jax.numpy as jnp
import numpy as np
from jax import lax

__all__ = ["Box", "box", "worst_points", "worst_points_shared", "worst_points_grouped", "worst_values", "dense_check",
           "DenseCheck", "grid_points", "dense_points", "default_counts", "dense_size", "dense_per_axis"]


class Box(NamedTuple):
    """A box of parameters with its search grid (static: numpy arrays, hashed by identity).

    ``lower``/``upper``: bounds (d,); ``log``: dimensions gridded in log p (d,) bool; ``counts``:
    grid points per dimension (tuple of d ints)."""

    lower: np.ndarray
    upper: np.ndarray
    log: np.ndarray
    counts: tuple

    @property
    def dim(self) -> int:
        return len(self.counts)

    def to_u(self, p):
        return jnp.where(self.log, jnp.log(jnp.where(self.log, p, 1.0)), p)

    def from_u(self, u):
        return jnp.where(self.log, jnp.exp(u), u)

    def u_bounds(self):
        lo = np.where(self.log, np.log(np.where(self.log, self.lower, 1.0)), self.lower)
        hi = np.where(self.log, np.log(np.where(self.log, self.upper, 1.0)), self.upper)
        return lo, hi

    def grid(self) -> np.ndarray:
        """The grid points (K, d) in p, C order over the dimensions."""
        lo, hi = self.u_bounds()
        axes = [np.linspace(lo[i], hi[i], self.counts[i]) for i in range(self.dim)]
        mesh = np.meshgrid(*axes, indexing="ij")
        u = np.stack([m.ravel() for m in mesh], axis=-1)
        return np.where(self.log, np.exp(np.where(self.log, u, 0.0)), u)

    def cell(self) -> np.ndarray:
        """Grid spacing in u per dimension (d,)."""
        lo, hi = self.u_bounds()
        return (hi - lo) / np.maximum(np.asarray(self.counts) - 1, 1)


def default_counts(d: int) -> tuple:
    """Grid points per dimension of a box of ``d`` dimensions when none are given: 129 for one,
    33 per dimension for two, 17 for three or more."""
    return (129,) if d == 1 else (33,) * d if d == 2 else (17,) * d


def dense_size(d: int, n_points: int) -> int:
    """Points of :func:`dense_points`' grid of a box of ``d`` dimensions asked ``n_points``:
    (⌈n^(1/d)⌉ + 1)^d."""
    return dense_per_axis(d, n_points) ** d


def dense_per_axis(d: int, n_points: int) -> int:
    """Points per dimension of :func:`dense_points`' grid: ⌈n^(1/d)⌉ + 1."""
    return int(np.ceil(n_points ** (1.0 / d))) + 1


def box(lower: Sequence[float], upper: Sequence[float], *, counts=None, log=None) -> Box:
    """A :class:`Box` with default grids: 129 points for one dimension, 33 per dimension for two,
    17 for three or more; log spacing where the lower bound is positive and the box spans a factor
    of ten or more (unless ``log`` says otherwise)."""
    lower = np.atleast_1d(np.asarray(lower, dtype=float))
    upper = np.atleast_1d(np.asarray(upper, dtype=float))
    if lower.shape != upper.shape or not np.all(lower < upper):
        raise ValueError(f"a box needs lower < upper in every dimension; got {lower} and {upper}")
    d = lower.size
    if counts is None:
        counts = default_counts(d)
    counts = tuple(int(c) for c in np.broadcast_to(np.asarray(counts), (d,)))
    if any(c < 3 for c in counts):
        raise ValueError("a box grid needs at least 3 points per dimension")
    if log is None:
        log = (lower > 0) & (upper >= 10.0 * lower)
    log = np.broadcast_to(np.asarray(log, dtype=bool), (d,)).copy()
    if np.any(log & (lower <= 0)):
        raise ValueError("log spacing needs a positive lower bound")
    return Box(lower, upper, log, counts)


def _local_minimum_mask(values, counts):
    """Grid points no higher than any of their axis neighbours (C-order grid of ``counts``)."""
    v = values.reshape(counts)
    mask = jnp.ones(v.shape, dtype=bool)
    for axis in range(v.ndim):
        ahead = jnp.concatenate([lax.slice_in_dim(v, 1, None, axis=axis),
                                 jnp.full_like(lax.slice_in_dim(v, 0, 1, axis=axis), jnp.inf)], axis=axis)
        behind = jnp.concatenate([jnp.full_like(lax.slice_in_dim(v, 0, 1, axis=axis), jnp.inf),
                                  lax.slice_in_dim(v, 0, -1, axis=axis)], axis=axis)
        mask &= (v <= ahead) & (v <= behind)
    return mask.ravel()


def _line_minimum(fn_u, u, i, a, b, iters: int):
    """Minimise ``fn_u`` along coordinate ``i`` of ``u`` inside [a, b] (scalars): Newton on the
    derivative safeguarded by bisection. With g = ∂f/∂u_i of opposite signs at the ends (g(a) < 0 <
    g(b)) the bracket holds a minimum and shrinks by at least half per step that is not a Newton
    step; otherwise the lower end is taken. The result is kept only if f does not increase."""
    e = jnp.zeros_like(u).at[i].set(1.0)

    def f_t(t):
        return fn_u(u + (t - u[i]) * e)

    def g_t(t):
        return jax.jvp(f_t, (t,), (jnp.ones_like(t),))[1]

    def gh_t(t):
        return jax.jvp(g_t, (t,), (jnp.ones_like(t),))

    ga, gb = g_t(a), g_t(b)
    bracketed = (ga < 0) & (gb > 0)

    def body(_, state):
        lo, hi, t = state
        g, h = gh_t(t)
        g = jnp.where(jnp.isfinite(g), g, 0.0)
        lo = jnp.where(g < 0, t, lo)
        hi = jnp.where(g > 0, t, hi)
        newton = t - g / jnp.where(h > 0, h, 1.0)
        ok = (h > 0) & (newton > lo) & (newton < hi)
        t = jnp.where(g == 0, t, jnp.where(ok, newton, 0.5 * (lo + hi)))
        return lo, hi, t

    t0 = jnp.clip(u[i], a, b)
    _, _, t = lax.fori_loop(0, iters, body, (a, b, t0))
    ends = jnp.where(f_t(a) <= f_t(b), a, b)
    t = jnp.where(bracketed, t, ends)
    cand = u.at[i].set(t)
    return jnp.where(fn_u(cand) <= fn_u(u), cand, u)


def _refine(fn_u, u0, lo, hi, cell, sweeps: int, iters: int = 40):
    """Polish a grid minimum: ``sweeps`` cycles of exact line minimisation along each coordinate
    (:func:`_line_minimum`) inside [u0 − cell, u0 + cell] ∩ [lo, hi] (for a grid local minimum
    this bracket holds the minimum of its basin along each axis)."""
    a = jnp.maximum(lo, u0 - cell)
    b = jnp.minimum(hi, u0 + cell)

    def sweep(_, u):
        for i in range(u0.size):
            u = _line_minimum(fn_u, u, i, a[i], b[i], iters)
        return u

    return lax.fori_loop(0, sweeps, sweep, u0)


#: points per coordinate and rounds of the value-only polish (:func:`_zoom`)
ZOOM_POINTS = 9
ZOOM_ROUNDS = 14


def _zoom(fn_u, u0, lo, hi, cell, sweeps: int, rounds: int = ZOOM_ROUNDS, points: int = ZOOM_POINTS):
    """Polish a grid minimum from values alone: along each coordinate in turn, ``points`` evenly
    spaced values on [u − h, u + h] ∩ [lo, hi] (h = one grid cell at first), move to the
    smallest, and shrink h by (points − 1)/2 — ``rounds`` times; ``sweeps`` cycles over the
    coordinates. Each round keeps the minimum of its basin inside the new bracket when the basin
    is resolved by the points (a unimodal function on the bracket), so the minimiser is located
    to cell · 4^−rounds (3.7e−9 of a cell with the defaults) — or to ~√ε relative at a smooth
    minimum, where the values differ only by round-off — and the minimum's value to round-off. It needs no derivatives of ``fn``, so its compiled program is a fraction of the
    Newton polish's (the live explorer uses it); where ``fn`` is not unimodal on a cell both
    polishes keep a local minimum, and the dense re-check settles the design."""
    offsets = jnp.linspace(-1.0, 1.0, points)
    shrink = (points - 1) / 2.0

    def line(u, i, h):
        ts = jnp.clip(u[i] + h * offsets, lo[i], hi[i])
        cands = jnp.tile(u, (points, 1)).at[:, i].set(ts)
        vals = jax.vmap(fn_u)(cands)
        vals = jnp.where(jnp.isfinite(vals), vals, jnp.inf)
        # the middle candidate is u itself (u lies in [lo, hi]), so the move never goes uphill
        return cands[jnp.argmin(vals)]

    return _zoom_rounds(line, u0, cell, u0.size, sweeps, rounds, shrink)


def _zoom_rounds(line, state, cell, dim: int, sweeps: int, rounds: int, shrink: float):
    """``sweeps`` × ``rounds`` × ``dim`` calls ``state = line(state, c, h)``, the half-width h
    one grid cell at first and divided by ``shrink`` each round."""
    def sweep(_, state):
        def round_(r, state):
            h = cell / shrink**r
            for c in range(dim):
                state = line(state, c, h[c])
            return state
        return lax.fori_loop(0, rounds, round_, state)

    return lax.fori_loop(0, sweeps, sweep, state)


def worst_points(fn: Callable, theta, bx: Box, n_worst: int = 3, *, extra=None, sweeps: Optional[int] = None,
                 polish: str = "newton"):
    """The ``n_worst`` lowest local minima of ``fn(theta, p)`` (p of shape (d,)) over the box ``bx``
    and where they lie: ``(values (n_worst,), points (n_worst, d))``, sorted by value (module
    docstring). ``theta`` is any pytree (the design); the search itself runs on
    ``stop_gradient(theta)``, so derivatives with respect to θ flow only through the final values
    ``fn(theta, p*)`` at the fixed points p* — the envelope theorem. ``extra``: candidate points
    (E, d) added to the grid's (e.g. points a dense check found). ``polish``: ``"newton"`` (exact
    line minimisation, :func:`_refine`) or ``"zoom"`` (values only, :func:`_zoom`: a much smaller
    program to compile, the minimiser to 4e−9 of a grid cell)."""
    theta_s = jax.tree_util.tree_map(lax.stop_gradient, theta)
    grid = jnp.asarray(bx.grid())
    cands = grid if extra is None else jnp.concatenate([grid, jnp.asarray(extra, dtype=grid.dtype)], axis=0)
    values = jax.vmap(lambda q: fn(theta_s, q))(cands)
    finite = jnp.isfinite(values)
    mask = _local_minimum_mask(values[: grid.shape[0]], bx.counts)
    if extra is not None:
        mask = jnp.concatenate([mask, jnp.ones((cands.shape[0] - grid.shape[0],), dtype=bool)])
    # rank: local minima first (by value), then every other point (by value); non-finite last
    span = jnp.max(jnp.where(finite, jnp.abs(values), 0.0)) + 1.0
    score = jnp.where(finite, values, 1e300) + jnp.where(mask, 0.0, 4.0 * span)
    _, idx = lax.top_k(-score, n_worst)
    lo, hi = (jnp.asarray(a) for a in bx.u_bounds())
    cell = jnp.asarray(bx.cell())

    def fn_u(u):
        return fn(theta_s, bx.from_u(u))

    n_sweeps = (1 if bx.dim == 1 else 4) if sweeps is None else sweeps
    if polish == "newton":
        start = lambda u0: _refine(fn_u, u0, lo, hi, cell, n_sweeps)
    elif polish == "zoom":
        start = lambda u0: _zoom(fn_u, u0, lo, hi, cell, n_sweeps)
    else:
        raise ValueError(f"polish must be 'newton' or 'zoom'; got {polish!r}")
    u_best = jax.vmap(start)(bx.to_u(cands[idx]))
    points = lax.stop_gradient(jnp.clip(bx.from_u(u_best), bx.lower, bx.upper))
    vals = jax.vmap(lambda q: fn(theta, q))(points)
    order = jnp.argsort(lax.stop_gradient(vals))
    return vals[order], points[order]


def worst_points_shared(fn_multi: Callable, theta, bx: Box, m: int, n_worst: int = 3, *,
                        differentiable: bool = True, sweeps: Optional[int] = None,
                        rounds: int = ZOOM_ROUNDS, points: int = ZOOM_POINTS):
    """:func:`worst_points` with the value-only polish for ``m`` functions over one box at once.

    ``fn_multi(theta, p)`` returns the m values (m,) at one point — e.g. several outputs of one
    sensor chain, computed together. Every evaluation (the grid; per round and coordinate, the
    ``points`` candidates of each function's ``n_worst`` starts) is one batched call of
    ``fn_multi``, so the compiled program holds two or three copies of it whatever m is, instead
    of three per function; each function ranks and moves on its own column. Returns ``(values
    (m, n_worst), points (m, n_worst, d))``, each function's sorted. With ``differentiable``
    False the values are the polish's own (no derivative with respect to ``theta``; one copy
    fewer); otherwise they are re-evaluated at the stopped points (the envelope theorem)."""
    theta_s = jax.tree_util.tree_map(lax.stop_gradient, theta)
    grid = jnp.asarray(bx.grid())
    values = jax.vmap(lambda q: fn_multi(theta_s, q))(grid)  # (K, m)
    lo, hi = (jnp.asarray(a) for a in bx.u_bounds())
    cell = jnp.asarray(bx.cell())
    starts, start_vals = [], []
    for i in range(m):
        v = values[:, i]
        finite = jnp.isfinite(v)
        mask = _local_minimum_mask(v, bx.counts)
        span = jnp.max(jnp.where(finite, jnp.abs(v), 0.0)) + 1.0
        score = jnp.where(finite, v, 1e300) + jnp.where(mask, 0.0, 4.0 * span)
        _, idx = lax.top_k(-score, n_worst)
        starts.append(bx.to_u(grid[idx]))
        start_vals.append(jnp.where(finite, v, jnp.inf)[idx])
    u0 = jnp.stack(starts)  # (m, n_worst, d)
    v0 = jnp.stack(start_vals)  # (m, n_worst)
    offsets = jnp.linspace(-1.0, 1.0, points)
    shrink = (points - 1) / 2.0
    own = jnp.arange(m)

    def line(state, c, h):
        u, _ = state
        ts = jnp.clip(u[..., c][..., None] + h * offsets, lo[c], hi[c])  # (m, n_worst, P)
        cands = jnp.broadcast_to(u[:, :, None, :], ts.shape + (u.shape[-1],)).at[..., c].set(ts)
        flat = cands.reshape(-1, u.shape[-1])
        vals = jax.vmap(lambda uu: fn_multi(theta_s, bx.from_u(uu)))(flat).reshape(ts.shape + (m,))
        vals = vals[own, :, :, own]  # each function's own column: (m, n_worst, P)
        vals = jnp.where(jnp.isfinite(vals), vals, jnp.inf)
        k = jnp.argmin(vals, axis=-1)  # the middle candidate is u itself: never uphill
        u_new = jnp.take_along_axis(cands, k[..., None, None], axis=2)[:, :, 0, :]
        return u_new, jnp.take_along_axis(vals, k[..., None], axis=2)[..., 0]

    n_sweeps = (1 if bx.dim == 1 else 4) if sweeps is None else sweeps
    u_best, v_best = _zoom_rounds(line, (u0, v0), cell, bx.dim, n_sweeps, rounds, shrink)
    pts = lax.stop_gradient(jnp.clip(bx.from_u(u_best), bx.lower, bx.upper))
    if differentiable:
        flat = jax.vmap(lambda q: fn_multi(theta, q))(pts.reshape(-1, bx.dim)).reshape(m, n_worst, m)
        v_best = flat[own, :, own]
    order = jnp.argsort(lax.stop_gradient(v_best), axis=-1)
    return jnp.take_along_axis(v_best, order, axis=-1), jnp.take_along_axis(pts, order[..., None], axis=1)


def worst_values(fn: Callable, theta, bx: Box, n_worst: int = 3, *, extra=None, sweeps: Optional[int] = None):
    """The values of :func:`worst_points` only."""
    return worst_points(fn, theta, bx, n_worst, extra=extra, sweeps=sweeps)[0]


class DenseCheck(NamedTuple):
    """Outcome of :func:`dense_check`: the smallest value found and where, the number of points
    evaluated, and the curve of values on a 1-D box (``None`` for more dimensions)."""

    worst_value: float
    worst_point: np.ndarray
    n_points: int
    curve_p: object
    curve_v: object


def dense_check(fn_batch: Callable, bx: Box, *, n_points: int = 10_001, refine: Callable = None) -> DenseCheck:
    """Re-check a design on a dense grid independent of the solver's: ``fn_batch(P)`` evaluates the
    margin at points P (n, d) (e.g. a compiled, vmapped evaluation); the grid has at least
    ``n_points`` points (per dimension ⌈n^(1/d)⌉ + 1, shifted by a third of a cell against the
    box's own grid so no point coincides with the solver's, ends included); optionally
    ``refine(p) -> (p*, v*)`` polishes the smallest point found. Returns a :class:`DenseCheck`."""
    d = bx.dim
    per = int(np.ceil(n_points ** (1.0 / d))) + 1
    lo, hi = bx.u_bounds()
    axes = []
    for i in range(d):
        base = np.linspace(lo[i], hi[i], per)
        shift = (hi[i] - lo[i]) / (per - 1) / 3.0
        inner = np.clip(base[1:-1] + shift, lo[i], hi[i])
        axes.append(np.concatenate([[lo[i]], inner, [hi[i]]]))
    mesh = np.meshgrid(*axes, indexing="ij")
    u = np.stack([m.ravel() for m in mesh], axis=-1)
    pts = np.where(bx.log, np.exp(np.where(bx.log, u, 0.0)), u)
    pts = np.clip(pts, bx.lower, bx.upper)
    vals = np.asarray(fn_batch(pts), dtype=float)
    bad = ~np.isfinite(vals)
    k = int(np.argmax(bad)) if bad.any() else int(np.argmin(vals))
    worst_p, worst_v = pts[k], float(vals[k])
    if refine is not None and not bad.any():
        p_r, v_r = refine(worst_p)
        if np.isfinite(v_r) and v_r < worst_v:
            worst_p, worst_v = np.asarray(p_r, dtype=float), float(v_r)
    curve = (pts[:, 0], vals) if d == 1 else (None, None)
    return DenseCheck(worst_v, worst_p, int(pts.shape[0]), curve[0], curve[1])


# --- boxes given as data (traced bounds, static grid sizes) ------------------------------------


def _u_bounds(lower, upper, log):
    """The box in u = p (linear) or ln p (log dimensions), traceable."""
    lo = jnp.where(log, jnp.log(jnp.where(log, lower, 1.0)), lower)
    hi = jnp.where(log, jnp.log(jnp.where(log, upper, 1.0)), upper)
    return lo, hi


def _from_u(u, log):
    return jnp.where(log, jnp.exp(jnp.where(log, u, 0.0)), u)


def grid_points(lower, upper, log, counts):
    """The search grid of a box given as data — bounds ``lower``/``upper`` (d,), ``log`` (d,) bool,
    possibly traced — with ``counts`` (static) points per dimension: (K, d) in p, C order, as
    :meth:`Box.grid`."""
    lo, hi = _u_bounds(lower, upper, log)
    axes = [lo[i] + (hi[i] - lo[i]) * jnp.linspace(0.0, 1.0, counts[i]) for i in range(len(counts))]
    mesh = jnp.meshgrid(*axes, indexing="ij")
    u = jnp.stack([m.ravel() for m in mesh], axis=-1)
    return jnp.clip(_from_u(u, log), lower, upper)


def dense_points(lower, upper, log, n_points: int):
    """The dense re-check grid of a box given as data (see :func:`dense_check`): per dimension
    ⌈n^(1/d)⌉ + 1 points, the inner ones shifted by a third of a cell against a uniform grid in u,
    ends included; (P, d) in p, C order. Traceable in the bounds."""
    d = int(np.shape(lower)[-1])
    per = dense_per_axis(d, n_points)
    lo, hi = _u_bounds(lower, upper, log)
    t = np.linspace(0.0, 1.0, per)
    t_inner = np.concatenate([[0.0], np.clip(t[1:-1] + 1.0 / (per - 1) / 3.0, 0.0, 1.0), [1.0]])
    axes = [lo[i] + (hi[i] - lo[i]) * jnp.asarray(t_inner) for i in range(d)]
    mesh = jnp.meshgrid(*axes, indexing="ij")
    u = jnp.stack([m.ravel() for m in mesh], axis=-1)
    return jnp.clip(_from_u(u, log), lower, upper)


def worst_points_grouped(fn_multi: Callable, theta, lower, upper, log, counts: tuple, n_worst: int = 3, *,
                         extra=None, differentiable: bool = False, sweeps: Optional[int] = None,
                         rounds: int = ZOOM_ROUNDS, points: int = ZOOM_POINTS):
    """The value-only search of :func:`worst_points_shared` for ``m`` functions, each over its own
    box given as data: ``lower``/``upper``/``log`` (m, d) (traceable), ``counts`` (d,) static grid
    points per dimension shared by the m boxes. ``fn_multi(theta, p)`` returns the m values (m,)
    at one point (each function reads its own column). ``extra``: candidate points (m, E, d)
    ranked with the grid's local minima (e.g. the worst points a previous search or a dense
    re-check found). Returns ``(values (m, n_worst), points (m, n_worst, d))``, each function's
    sorted; with ``differentiable`` the values are re-evaluated at the stopped points (derivatives
    by the envelope theorem), otherwise they are the polish's own (no derivative).

    Every evaluation — the grid, in chunks of one polish step's size, then each step of the
    polish (:func:`_zoom`'s rounds along each coordinate) — is one trip of a single loop, so a
    compiled program holds one copy of ``fn_multi``."""
    theta_s = jax.tree_util.tree_map(lax.stop_gradient, theta)
    lower, upper, log = (jnp.asarray(a) for a in (lower, upper, log))
    m, d = lower.shape
    grids = jax.vmap(lambda lo, hi, lg: grid_points(lo, hi, lg, counts))(lower, upper, log)  # (m, K, d)
    if extra is not None:
        grids = jnp.concatenate([grids, jnp.clip(jnp.asarray(extra, dtype=grids.dtype), lower[:, None, :],
                                                 upper[:, None, :])], axis=1)
    n_grid = int(np.prod(counts))
    n_cand = grids.shape[1]
    own = jnp.arange(m)
    u_lo, u_hi = _u_bounds(lower, upper, log)  # (m, d)
    cell = (u_hi - u_lo) / jnp.maximum(jnp.asarray(counts, dtype=u_lo.dtype) - 1.0, 1.0)
    grid_u = jnp.where(log[:, None, :], jnp.log(jnp.where(log[:, None, :], grids, 1.0)), grids)
    offsets = jnp.linspace(-1.0, 1.0, points)
    shrink = (points - 1) / 2.0
    n_sweeps = (1 if d == 1 else 4) if sweeps is None else sweeps

    # one evaluation size for every trip: a polish step's candidates (m, n_worst, points)
    size = m * n_worst * points
    flat = grids.reshape(-1, d)
    chunks = -(-flat.shape[0] // size)
    flat = jnp.concatenate([flat, jnp.broadcast_to(flat[-1:], (chunks * size - flat.shape[0], d))])
    steps = n_sweeps * rounds * d

    def starts_of(v, g_u):
        finite = jnp.isfinite(v)
        mask = _local_minimum_mask(v[:n_grid], counts)
        mask = jnp.concatenate([mask, jnp.ones((v.shape[0] - n_grid,), dtype=bool)])
        span = jnp.max(jnp.where(finite, jnp.abs(v), 0.0)) + 1.0
        score = jnp.where(finite, v, 1e300) + jnp.where(mask, 0.0, 4.0 * span)
        _, idx = lax.top_k(-score, n_worst)
        return g_u[idx], jnp.where(finite, v, jnp.inf)[idx]

    def candidates(u, k):
        # polish step k: round r along coordinate c (sweeps × rounds × coordinates, in that order)
        c = k % d
        h = jnp.take(cell, c, axis=1) / shrink ** ((k // d) % rounds)  # (m,)
        uc = jnp.take(u, c, axis=2)  # (m, n_worst)
        ts = jnp.clip(uc[..., None] + h[:, None, None] * offsets, jnp.take(u_lo, c, axis=1)[:, None, None],
                      jnp.take(u_hi, c, axis=1)[:, None, None])
        onehot = jnp.arange(d) == c
        return jnp.where(onehot, ts[..., None], u[:, :, None, :])  # (m, n_worst, points, d)

    def trip(s, state):
        grid_values, u, v = state
        k = jnp.maximum(s - chunks, 0)
        cands = candidates(u, k)
        polish_pts = _from_u(cands, log[:, None, None, :]).reshape(-1, d)
        grid_pts = lax.dynamic_slice_in_dim(flat, jnp.minimum(s, chunks - 1) * size, size)
        in_grid = s < chunks
        vals = jax.vmap(lambda q: fn_multi(theta_s, q))(jnp.where(in_grid, grid_pts, polish_pts))  # (size, m)
        grid_values = jnp.where(in_grid, lax.dynamic_update_slice_in_dim(
            grid_values, vals, jnp.minimum(s, chunks - 1) * size, axis=0), grid_values)

        def from_grid(_):
            own_values = grid_values[:m * n_cand].reshape(m, n_cand, m)[own, :, own]  # (m, K+E)
            return jax.vmap(starts_of)(own_values, grid_u)

        u, v = lax.cond(s == chunks - 1, from_grid, lambda _: (u, v), None)
        cand_vals = vals.reshape(m, n_worst, points, m)[own, :, :, own]  # each function's own column
        cand_vals = jnp.where(jnp.isfinite(cand_vals), cand_vals, jnp.inf)
        best = jnp.argmin(cand_vals, axis=-1)  # the middle candidate is u itself: never uphill
        u_new = jnp.take_along_axis(cands, best[..., None, None], axis=2)[:, :, 0, :]
        v_new = jnp.take_along_axis(cand_vals, best[..., None], axis=2)[..., 0]
        polish = s >= chunks
        return grid_values, jnp.where(polish, u_new, u), jnp.where(polish, v_new, v)

    init = (jnp.zeros((chunks * size, m), dtype=grids.dtype), jnp.zeros((m, n_worst, d), dtype=grids.dtype),
            jnp.zeros((m, n_worst), dtype=grids.dtype))
    _, u_best, v_best = lax.fori_loop(0, chunks + steps, trip, init)
    pts = lax.stop_gradient(jnp.clip(_from_u(u_best, log[:, None, :]), lower[:, None, :], upper[:, None, :]))
    if differentiable:
        v_best = jax.vmap(lambda q: fn_multi(theta, q))(pts.reshape(-1, d)).reshape(m, n_worst, m)[own, :, own]
    order = jnp.argsort(lax.stop_gradient(v_best), axis=-1)
    return jnp.take_along_axis(v_best, order, axis=-1), jnp.take_along_axis(pts, order[..., None], axis=1)
