"""Dense convex quadratic programs by a primal–dual interior-point method (fixed shape, jit/vmap).

    minimise ½ yᵀQy + cᵀy   subject to   A y ≤ b          (Q symmetric positive semidefinite)

Mehrotra's predictor–corrector method (Mehrotra, SIAM J. Optim. 2 (1992) 575–601; Nocedal &
Wright, *Numerical Optimization*, 2nd ed., Algorithm 16.4 for quadratic programs; Wright,
*Primal-Dual Interior-Point Methods*, SIAM 1997, ch. 10). With slacks w = b − Ay ≥ 0 and
multipliers u ≥ 0 the optimality conditions are

    Qy + c + Aᵀu = 0,    Ay + w − b = 0,    wᵢuᵢ = 0.

Each iteration solves the Newton system reduced to (Q + Aᵀ diag(u/w) A) Δy = r, once for the
affine (predictor) direction and once for the centred corrector with σ = (μ_aff/μ)³, and steps a
common length α ≤ 1 that keeps w, u at least 0.5 % inside the positive orthant (one length for
primal and dual, as Q couples them). The method starts infeasible (y = 0, w = max(b, ζ), u = ζ),
needs no feasible point, and runs at most a fixed number of iterations (fewer once converged;
under vmap until every lane has). The iterate returned is the one with the least merit, the
largest of the relative residuals ‖r_d‖/(1 + ‖c‖), ‖r_p‖/(1 + ‖b‖) and μ/(1 + ‖c‖): once μ is
far below the residuals the reduced system is so ill-conditioned (u/w spans ~1e30) that further
steps only add rounding error. The iterations stop once the merit is below 1e-13; an update
that is not finite is not taken.

Used by :mod:`diffsense.optimize.sqp` for its subproblems, which have 10–100 rows: dense linear
algebra is the right tool at that size and compiles to a few hundred operations.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import jax.scipy.linalg
from jax import lax


class QPSolution(NamedTuple):
    """Primal solution ``y``, multipliers ``u`` ≥ 0 of the rows of A y ≤ b, slacks ``w`` = b − Ay
    as carried by the method (uᵢwᵢ ≈ μ: a row with uᵢ > wᵢ is active), and the residual
    measures at the end: ``dual`` = ‖Qy + c + Aᵀu‖∞, ``primal`` = ‖max(Ay − b, 0)‖∞ and the
    complementarity gap ``gap`` = wᵀu / rows."""

    y: jax.Array
    u: jax.Array
    w: jax.Array
    dual: jax.Array
    primal: jax.Array
    gap: jax.Array


def _max_step(v, dv):
    """Largest α ∈ (0, 1] with v + α dv ≥ 0 (v > 0)."""
    ratio = jnp.where(dv < 0.0, -v / jnp.where(dv < 0.0, dv, -1.0), jnp.inf)
    return jnp.minimum(1.0, jnp.min(ratio, initial=jnp.inf))


def solve_qp(Q, c, A, b, iterations: int = 30) -> QPSolution:
    """Solve the QP above with at most ``iterations`` Mehrotra predictor–corrector steps (module
    docstring).

    Args:
        Q: (n, n) symmetric positive semidefinite; with A it must make the problem bounded
            (Q + AᵀDA positive definite for positive diagonal D, e.g. every variable bounded).
        c: (n,) linear term. A: (r, n) and b: (r,): the inequality rows.
        iterations: largest number of interior-point iterations (static).
    """
    n, r = c.shape[0], b.shape[0]
    dtype = c.dtype

    def factor(w, u):
        D = u / w
        K = Q + (A.T * D) @ A
        return D, jax.scipy.linalg.cho_factor(0.5 * (K + K.T))

    def newton(fac, w, u, r_d, r_p, r_c):
        D, chol = fac
        dy = jax.scipy.linalg.cho_solve(chol, -r_d - A.T @ (D * r_p - r_c / w))
        du = D * (A @ dy + r_p) - r_c / w
        dw = -(r_c + w * du) / u
        return dy, dw, du

    def residuals(y, w, u):
        r_d = Q @ y + c + A.T @ u
        r_p = A @ y + w - b
        merit = jnp.maximum(jnp.maximum(jnp.max(jnp.abs(r_d), initial=0.0) / scale_d,
                                        jnp.max(jnp.abs(r_p), initial=0.0) / scale_p),
                            jnp.dot(w, u) / r / scale_d)
        return r_d, r_p, merit

    def step(carry):
        k, state, res, best, best_merit = carry
        y, w, u = state
        r_d, r_p, _ = res
        mu = jnp.dot(w, u) / r
        fac = factor(w, u)  # one factorisation serves predictor and corrector
        dy, dw, du = newton(fac, w, u, r_d, r_p, w * u)
        a_aff = jnp.minimum(_max_step(w, dw), _max_step(u, du))
        mu_aff = jnp.dot(w + a_aff * dw, u + a_aff * du) / r
        sigma = (mu_aff / mu) ** 3
        dy, dw, du = newton(fac, w, u, r_d, r_p, w * u + dw * du - sigma * mu)
        alpha = jnp.minimum(1.0, 0.995 * jnp.minimum(_max_step(w, dw), _max_step(u, du)))
        new = (y + alpha * dy, w + alpha * dw, u + alpha * du)
        ok = jnp.all(jnp.isfinite(new[0])) & jnp.all(new[1] > 0.0) & jnp.all(new[2] > 0.0)
        state = jax.tree_util.tree_map(lambda a, b_: jnp.where(ok, a, b_), new, state)
        res = residuals(*state)
        better = res[2] < best_merit
        best = jax.tree_util.tree_map(lambda a, b_: jnp.where(better, a, b_), state, best)
        return k + 1, state, res, best, jnp.where(better, res[2], best_merit)

    scale_d = 1.0 + jnp.max(jnp.abs(c), initial=0.0)
    scale_p = 1.0 + jnp.max(jnp.abs(b), initial=0.0)
    tol = 1e-13
    # start: w = u = ζ·1 with ζ the square root of the data's size (OOQP's default start, Gertz &
    # Wright, ACM TOMS 29 (2003) 58–81), w at least b so that y = 0 satisfies A y + w = b where b > ζ
    zeta = jnp.sqrt(jnp.maximum(jnp.maximum(scale_d, scale_p), 1.0 + jnp.max(jnp.abs(Q), initial=0.0)))
    start = (jnp.zeros((n,), dtype), jnp.maximum(b, zeta), jnp.full((r,), zeta, dtype))
    res0 = residuals(*start)
    _, _, _, (y, w, u), _ = lax.while_loop(lambda c: (c[0] < iterations) & (c[4] > tol), step,
                                           (0, start, res0, start, res0[2]))
    dual = jnp.max(jnp.abs(Q @ y + c + A.T @ u), initial=0.0)
    primal = jnp.max(jnp.maximum(A @ y - b, 0.0), initial=0.0)
    return QPSolution(y, u, w, dual, primal, jnp.dot(w, u) / r)


__all__ = ["QPSolution", "solve_qp"]
