"""Dense strictly convex QPs by the dual active-set method of Goldfarb and Idnani (fixed shape).

    minimise ½ yᵀQy + cᵀy   subject to   A_E y = b_E  (the first ``n_eq`` rows),
                                           A_I y ≤ b_I  (the other rows),      Q positive definite

Method: Goldfarb & Idnani, "A numerically stable dual method for solving strictly convex
quadratic programs", Math. Program. 27 (1983) 1–33 (the method the ``quadprog`` package
implements). It starts from the minimiser on the equality rows alone, which is dual
feasible, and adds violated inequality rows one at a time. Adding row p with multiplier t
moves the iterate by −t z, z = H a_p (H the inverse Hessian restricted to the null space of
the active rows), and the active multipliers by −t r (r = N* a_p, their rate of change):

    t₁ = s_p / a_pᵀz     (full step: row p becomes active; s_p = a_pᵀy − b_p > 0)
    t₂ = min_{j active inequality, r_j > 0} u_j / r_j     (partial step: row j's multiplier
                                                           reaches 0 and row j is dropped)

and takes t = min(t₁, t₂); after a drop the same row p is pursued again. Each iterate is the
minimiser on its active set with multipliers ≥ 0, the objective rises monotonically, and
the method ends in finitely many steps at the optimum or with proof that the rows are
inconsistent (a_p dependent on the active rows, z = 0, and no r_j > 0: t = ∞).

Linear algebra (range-space form): Ĝ = A Q⁻¹ Aᵀ and Q⁻¹Aᵀ are formed once; each step solves
with the active block of Ĝ (identity on the inactive rows) by Cholesky, so r = Ĝ_WW⁻¹ Ĝ_Wp
and z = Q⁻¹a_p − Q⁻¹A_Wᵀ r. Goldfarb and Idnani update QR factors instead; for the 10–50 rows
of a design problem's SQP subproblem the refactorisation costs the same few microseconds
and keeps the state a fixed-shape mask. A row is added only when a_pᵀz exceeds 1e-11 of
a_pᵀQ⁻¹a_p (independent of the active rows in the Q⁻¹ metric), so the active block stays
positive definite. Violations count above 1e-12·(1 + |b_p| + |A_p||y|) (rounding of the
row's terms); the most violated row per Euclidean row norm is added first.

``ok`` is False — and the caller should use another method — when the inequality rows are
inconsistent with each other and the equalities; when the equality rows are linearly
dependent and inconsistent (the Cholesky factor is not finite, or the rows are left unmet by
more than 1e-9 of their terms' size; dependent but consistent equalities are solved, with one
of their many multiplier vectors); after ``max_iterations`` steps; or when the answer fails
the a-posteriori test ‖Qy + c + Aᵀu‖∞ ≤ 1e-9 (1 + ‖c‖∞ + ‖Qy‖∞ + ‖|A|ᵀ|u|‖∞): on
inconsistent rows rounding can let nearly dependent rows pass the independence test, after
which the multipliers grow without bound instead of the method stopping with t = ∞.
"""

from __future__ import annotations

from typing import NamedTuple, Optional

import jax
import jax.numpy as jnp
import jax.scipy.linalg
from jax import lax

_INDEPENDENT = 1e-11  # a_pᵀz / a_pᵀQ⁻¹a_p below this: a_p depends on the active rows
_VIOLATED = 1e-12  # relative rounding allowance of a row's value
_STATIONARY = 1e-9  # largest accepted ‖Qy + c + Aᵀu‖∞ relative to the size of its terms


class ActiveSetSolution(NamedTuple):
    """Solution ``y``, multipliers ``u`` of every row (≥ 0 on inequalities, 0 on inactive
    rows, free sign on equalities; Qy + c + Aᵀu = 0), the ``active`` row mask, ``ok`` (an
    optimum was reached) and the number of steps ``iterations``."""

    y: jax.Array
    u: jax.Array
    active: jax.Array
    ok: jax.Array
    iterations: jax.Array


def solve_qp_active_set(Q, c, A, b, n_eq: int = 0, max_iterations: Optional[int] = None) -> ActiveSetSolution:
    """Solve the QP above by the dual active-set method (module docstring).

    Args:
        Q: (n, n) symmetric positive definite. c: (n,).
        A: (r, n) rows, the first ``n_eq`` equalities and the rest inequalities A y ≤ b.
        b: (r,). n_eq: number of equality rows (static).
        max_iterations: step cap (static); default 3r + 10.
    """
    n, r = c.shape[0], b.shape[0]
    dtype = c.dtype
    cap = 3 * r + 10 if max_iterations is None else int(max_iterations)
    chol_q = jax.scipy.linalg.cho_factor(0.5 * (Q + Q.T), lower=True)
    qi_at = jax.scipy.linalg.cho_solve(chol_q, A.T)  # Q⁻¹Aᵀ, (n, r)
    gram = A @ qi_at
    gram = 0.5 * (gram + gram.T)
    eq = jnp.arange(r) < n_eq
    row_norm = jnp.sqrt(jnp.sum(A * A, axis=1)) + jnp.finfo(dtype).tiny

    def gram_solve(mask, rhs):
        both = mask[:, None] & mask[None, :]
        M = jnp.where(both, gram, 0.0) + jnp.diag(jnp.where(mask, 0.0, 1.0).astype(dtype))
        L = jnp.linalg.cholesky(M)
        x = jax.scipy.linalg.cho_solve((L, True), jnp.where(mask, rhs, 0.0))
        return jnp.where(mask, x, 0.0), jnp.all(jnp.isfinite(x))

    def most_violated(y, active):
        """(row to add next, whether any row is violated)."""
        allowance = _VIOLATED * (1.0 + jnp.abs(b) + jnp.abs(A) @ jnp.abs(y))
        slack = A @ y - b
        violated = ~active & ~eq & (slack > allowance)
        return jnp.argmax(jnp.where(violated, slack / row_norm, -jnp.inf)), jnp.any(violated)

    # start: the minimiser on the equality rows, y = −Q⁻¹(c + A_Eᵀν), A_E y = b_E
    y_free = -jax.scipy.linalg.cho_solve(chol_q, c)
    nu, ok_eq = gram_solve(eq, A @ y_free - b)
    y0 = y_free - qi_at @ nu
    p0, any0 = most_violated(y0, eq)
    # status: 0 running, 1 optimal, 2 failed
    status0 = jnp.where(ok_eq & jnp.all(jnp.isfinite(y0)), jnp.where(any0, 0, 1), 2)

    def cond(s):
        k, _, _, _, _, status = s
        return (status == 0) & (k < cap)

    def body(s):
        # one step towards making row p active (s_p > 0): a full step adds it, a partial step
        # drops the blocking row and keeps p
        k, y, u, active, p, _ = s
        g_p = gram[:, p]
        rate, ok_m = gram_solve(active, g_p)
        z = qi_at[:, p] - qi_at @ rate
        zn = gram[p, p] - jnp.dot(g_p, rate)
        # at most n independent rows: beyond that a_p depends on the active rows however its z rounds
        independent = (zn > _INDEPENDENT * gram[p, p]) & (jnp.sum(active) < n)
        slack_p = jnp.dot(A[p], y) - b[p]
        t1 = jnp.where(independent, slack_p / jnp.where(independent, zn, 1.0), jnp.inf)
        blocking = active & ~eq & (rate > 0.0)
        ratio = jnp.where(blocking, u / jnp.where(blocking, rate, 1.0), jnp.inf)
        j = jnp.argmin(ratio)
        t2 = ratio[j]
        t = jnp.minimum(t1, t2)
        failed = ~jnp.isfinite(t) | ~ok_m

        full = t1 <= t2
        y_new = y - jnp.where(independent, t, 0.0) * z
        u_new = jnp.where(active, u - t * rate, u).at[p].add(t)
        active_new = active.at[p].set(full)
        active_new = jnp.where(full, active_new, active_new.at[j].set(False))
        u_new = jnp.where(full, u_new, u_new.at[j].set(0.0))
        u_new = jnp.where(active_new | (jnp.arange(r) == p), u_new, 0.0)
        p_next, any_next = most_violated(y_new, active_new)
        p_next = jnp.where(full, p_next, p)
        status = jnp.where(failed, 2, jnp.where(full & ~any_next, 1, 0))
        keep = lambda new, old: jnp.where(failed, old, new)  # noqa: E731
        return k + 1, keep(y_new, y), keep(u_new, u), keep(active_new, active), p_next, status

    init = (jnp.asarray(0), y0, nu, eq, p0, status0)
    k, y, u, active, _, status = lax.while_loop(cond, body, init)
    # a posteriori check of stationarity: near-dependent rows on an inconsistent problem can
    # pass the independence test and drive the multipliers to ~1e14 where rounding takes over
    # (and of the equality rows, which a singular equality block can leave unmet)
    residual = jnp.max(jnp.abs(Q @ y + c + A.T @ u))
    size = 1.0 + jnp.max(jnp.abs(c)) + jnp.max(jnp.abs(Q @ y)) + jnp.max(jnp.abs(A.T) @ jnp.abs(u))
    eq_err = jnp.where(eq, jnp.abs(A @ y - b) - _STATIONARY * (1.0 + jnp.abs(b) + jnp.abs(A) @ jnp.abs(y)), 0.0)
    ok = ((status == 1) & (residual <= _STATIONARY * size) & (jnp.max(eq_err) <= 0.0)
          & jnp.all(jnp.isfinite(y)) & jnp.all(jnp.isfinite(u)))
    return ActiveSetSolution(y, u, active, ok, k)


__all__ = ["ActiveSetSolution", "solve_qp_active_set"]
