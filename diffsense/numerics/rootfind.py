"""Differentiable root finding for monotone functions of a positive variable (detection range).

The detection range R solves SNR(R) − SNR_required = 0. With atmospheric attenuation the
equation is transcendental (book 9.9.1: 40 log10 R + 2αR = const), so it is solved numerically
inside JAX: a safeguarded Newton iteration in u = ln R, kept inside a shrinking bracket, and
differentiated implicitly with :func:`jax.lax.custom_root` (dR/dθ = −(∂f/∂θ)/(∂f/∂R)), never
through the iterations.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
from jax import lax


#: an iteration that moves ln x by less than this (relative to max(1, |ln x|)) everywhere ends
#: the solve: the Newton iteration has converged to round-off, or the bracket has shrunk to it
_SETTLED = 4.0 * float(jnp.finfo(jnp.float64).eps)


class RootResult(NamedTuple):
    """``root``: the solution (clipped to the bracket when there is none inside it);
    ``bracketed``: True where the residual changes sign inside the bracket, so ``root`` is a
    true root; ``residual``: f(root)."""

    root: jnp.ndarray
    bracketed: jnp.ndarray
    residual: jnp.ndarray


def decreasing_root_log(f: Callable, lo, hi, *, iterations: int = 100, differentiable: bool = True,
                        ends=None, with_residual: bool = True) -> RootResult:
    """Solve f(x) = 0 for x in [lo, hi] (x > 0) where f is decreasing in x, elementwise.

    ``f`` maps an array of x to an array of residuals of the same shape (elementwise), and may
    close over traced parameters; derivatives with respect to those flow through the implicit
    function theorem. Where f(lo) < 0 the root is below the bracket and ``lo`` is returned with
    ``bracketed`` False; where f(hi) > 0, ``hi`` likewise. Each iteration takes the Newton step in
    ln x when it stays inside the current bracket and the previous step at least halved the
    bracket, and bisects otherwise. The bracket in ln x therefore at least halves every second
    iteration: 100 iterations shrink a bracket up to ln(hi/lo) = 40 below 4e-14 even when no
    Newton step is accepted (Newton converges quadratically near a simple root, so usually a
    handful of iterations decide the answer).

    ``differentiable=False`` (for a caller that differentiates the root itself, or never) runs
    the same iteration without the implicit-derivative machinery, a smaller program, and stops
    early once a step moves ln x by less than 4 ε max(1, |ln x|) everywhere (later steps would
    not change the answer). In that mode ``ends`` may give ``(f(lo), f(hi))`` when the caller
    has them, and ``with_residual=False`` leaves ``residual`` None: each saves an evaluation of
    ``f`` in the program.
    """
    if ends is not None and differentiable:
        raise ValueError("decreasing_root_log: 'ends' is for differentiable=False")
    lo = jnp.asarray(lo, dtype=float)
    hi = jnp.asarray(hi, dtype=float)
    ulo0, uhi0 = jnp.broadcast_arrays(jnp.log(lo), jnp.log(hi))

    def g(u):
        return f(jnp.exp(u))

    def solve(g_, u0, ends=None):
        flo, fhi = (g_(ulo0), g_(uhi0)) if ends is None else ends

        def body(state):
            a, b, u, width_before, _, it = state
            val, slope = jax.jvp(g_, (u,), (jnp.ones_like(u),))
            # keep the bracket: g decreasing, so g(u) > 0 means the root lies above u
            a = jnp.where(val > 0, u, a)
            b = jnp.where(val > 0, b, u)
            width = b - a
            safe_slope = jnp.where(slope < 0, slope, -1.0)
            newton = u - val / safe_slope
            ok = (slope < 0) & (newton > a) & (newton < b) & jnp.isfinite(newton)
            ok = ok & (width <= 0.5 * width_before)
            u_next = jnp.where(ok, newton, 0.5 * (a + b))
            u_next = jnp.where(val == 0, u, u_next)
            settled = jnp.all(jnp.abs(u_next - u) <= _SETTLED * jnp.maximum(1.0, jnp.abs(u)))
            return a, b, u_next, width, settled, it + 1

        def cond(state):
            return (state[5] < iterations) & ~state[4]

        init = (ulo0, uhi0, u0, 4.0 * (uhi0 - ulo0), jnp.asarray(False), 0)
        if differentiable:
            # a fixed number of steps (a scan: its derivative passes through custom_root only)
            a, b, u, _, _, _ = lax.fori_loop(0, iterations, lambda _, st: body(st), init)
        else:
            a, b, u, _, _, _ = lax.while_loop(cond, body, init)
        u = jnp.where(flo <= 0, ulo0, jnp.where(fhi >= 0, uhi0, u))
        return u

    def tangent_solve(lin, y):
        # where f is flat at the returned point (only possible at a bracket end returned for
        # lack of a root, whose derivative is discarded below) divide by 1, not by 0: the
        # discarded branch must stay finite, since 0 x NaN is NaN in the chain rule
        d = lin(jnp.ones_like(y))
        flat = d == 0
        return jnp.where(flat, 0.0, y / jnp.where(flat, 1.0, d))

    u0 = 0.5 * (ulo0 + uhi0)
    if not differentiable:
        # both ends by one call of f (elementwise: a leading axis broadcasts), shared by the
        # iteration and the bracket test
        if ends is None:
            ends = g(jnp.stack([ulo0, uhi0]))
        f_lo, f_hi = (lax.stop_gradient(jnp.broadcast_to(e, ulo0.shape)) for e in ends)
        u = lax.stop_gradient(solve(g, u0, (f_lo, f_hi)))
        return RootResult(jnp.exp(u), (f_lo > 0) & (f_hi < 0), g(u) if with_residual else None)
    u = lax.custom_root(g, u0, solve, tangent_solve)
    bracketed = (g(ulo0) > 0) & (g(uhi0) < 0)
    # a bound returned for lack of a root does not move with the parameters
    u = jnp.where(bracketed, u, lax.stop_gradient(u))
    residual = g(u)
    return RootResult(jnp.exp(u), bracketed, residual)
