"""First-order optimality (KKT) in scaled coordinates: residuals, the convergence test, the
active-set KKT equations and their Newton polish.

With the scaled Lagrangian L₀ = F + λ̃ᵀG + ν̃ᵀH on the box zlo ≤ z ≤ zhi, a KKT point has

* stationarity: projected gradient ‖P_box(z − ∇_z L₀) − z‖∞ = 0,
* feasibility: max(‖max(G, 0)‖∞, ‖H‖∞) = 0,
* complementarity: ‖min(λ̃, −G)‖∞ = 0 (λ̃ ≥ 0, and λ̃ᵢ = 0 wherever Gᵢ < 0).

A solve has converged when the first and last are ≤ ``tol`` and the feasibility is
≤ ``feas_tol`` (:func:`is_converged`); every solver method uses that test.

Polish (augmented Lagrangian): once an iterate has KKT residual ≤ ``polish_start``, the
active set is read off (G > −``active_tol`` or λ̃ > 0; variables held on a bound) and Newton's
method is applied to the KKT equations of that active set (∇L₀ = 0 on free variables,
G_A = 0, H = 0, λ̃_inactive = 0, :func:`kkt_equations`). Newton converges quadratically under
second-order sufficiency and linearly independent active gradients, so multipliers come out
to ~1e-12 instead of the ~tol of an augmented-Lagrangian estimate; the same KKT system is the
one :mod:`diffsense.optimize.sensitivity` differentiates (Nocedal & Wright, *Numerical
Optimization*, 2nd ed., §12.3 and §18.1).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax import lax

from diffsense.optimize.bounds import bound_activity
from diffsense.optimize.kernel import ScaledModel, inf_norm, projected_gradient_norm
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.result import KKTResidual


def kkt_residual(z, grad, G, H, lam, zlo, zhi) -> KKTResidual:
    """:class:`KKTResidual` at z from the scaled Lagrangian gradient ``grad`` and the scaled
    constraint values G, H with multipliers λ̃ (module docstring)."""
    stat = projected_gradient_norm(z, grad, zlo, zhi)
    feas = jnp.maximum(inf_norm(jnp.maximum(G, 0.0)), inf_norm(H))
    comp = inf_norm(jnp.minimum(lam, -G))
    return KKTResidual(stat, feas, comp)


def kkt_measures(model: ScaledModel, z, lam, nu) -> KKTResidual:
    """Scaled stationarity, feasibility and complementarity at (z, λ̃, ν̃)."""
    (_, (G, H)), grad = jax.value_and_grad(
        lambda zz: (lambda F, G, H: (F + jnp.dot(lam, G) + jnp.dot(nu, H), (G, H)))(*model.FGH(zz)),
        has_aux=True)(z)
    return kkt_residual(z, grad, G, H, lam, model.zlo, model.zhi)


def kkt_max(k: KKTResidual):
    """The largest of the three residuals."""
    return jnp.maximum(jnp.maximum(k.stationarity, k.feasibility), k.complementarity)


def is_converged(k: KKTResidual, options: SolverOptions):
    """The convergence test of every solver (module docstring)."""
    return (k.stationarity <= options.tol) & (k.feasibility <= options.feas_tol) & (k.complementarity <= options.tol)


def active_set(G, lam, options: SolverOptions):
    """Inequalities treated as active: scaled value above −active_tol or a positive multiplier
    (in the augmented Lagrangian λ > 0 exactly when G > −λ_prev/ρ, i.e. the constraint acted
    in the last subproblem)."""
    return (G > -options.active_tol) | (lam > 0.0)


def kkt_equations(model: ScaledModel, active, at_lo, at_hi, z, lam, nu):
    """Residual of the active-set KKT equations in scaled coordinates (fixed shape n + m + p).

    Rows: ∇_z L₀ for free variables (z − bound for variables fixed at a bound); G_i for active
    inequalities (λ̃_i for inactive ones, which pins them to 0); H."""

    def lag(zz):
        F, G, H = model.FGH(zz)
        return F + jnp.dot(lam, G) + jnp.dot(nu, H), (G, H)

    grad, (G, H) = jax.grad(lag, has_aux=True)(z)
    zb = jnp.where(at_lo, model.zlo, jnp.where(at_hi, model.zhi, z))
    zb = jnp.where(jnp.isfinite(zb), zb, 0.0)
    r_z = jnp.where(at_lo | at_hi, z - zb, grad)
    r_l = jnp.where(active, G, lam)
    return jnp.concatenate([r_z, r_l, H])


def polish_newton(model: ScaledModel, z, lam, nu, grad, G, options: SolverOptions):
    """``options.polish_steps`` Newton iterations on the active-set KKT equations from
    (z, λ̃, ν̃), the active set read off the Lagrangian gradient ``grad`` and G (module
    docstring). Returns the candidate (z, λ̃, ν̃) and whether it is usable: finite, inside the
    bounds (to 1e-12 relative) and with active multipliers ≥ −tol; otherwise the start."""
    n, m = z.shape[0], lam.shape[0]
    at_lo, at_hi = bound_activity(model.zlo, model.zhi, z, grad)
    active = active_set(G, lam, options)

    def eqs(s):
        r = kkt_equations(model, active, at_lo, at_hi, s[:n], s[n:n + m], s[n + m:])
        return r, r

    def step(_, s):
        J, r = jax.jacfwd(eqs, has_aux=True)(s)
        d = jnp.linalg.solve(J, -r)
        # a singular J (duplicated active constraints: interval slots at one point) has
        # consistent equations: their least-squares (minimum-norm) step
        d = jnp.where(jnp.all(jnp.isfinite(d)), d, jnp.linalg.lstsq(J, -r)[0])
        s_new = s + d
        return jnp.where(jnp.all(jnp.isfinite(s_new)), s_new, s)

    s0 = jnp.concatenate([z, lam, nu])
    s = lax.fori_loop(0, options.polish_steps, step, s0)
    z_p, lam_p, nu_p = s[:n], s[n:n + m], s[n + m:]
    slack_lo = 1e-12 * (1 + jnp.abs(jnp.where(jnp.isfinite(model.zlo), model.zlo, 0.0)))
    slack_hi = 1e-12 * (1 + jnp.abs(jnp.where(jnp.isfinite(model.zhi), model.zhi, 0.0)))
    ok = jnp.all(jnp.isfinite(s))
    ok &= jnp.all(z_p >= model.zlo - slack_lo) & jnp.all(z_p <= model.zhi + slack_hi)
    ok &= jnp.all(jnp.where(active, lam_p >= -options.tol, True))
    z_p = jnp.clip(z_p, model.zlo, model.zhi)
    lam_p = jnp.where(active, jnp.maximum(lam_p, 0.0), 0.0)
    return jnp.where(ok, z_p, z), jnp.where(ok, lam_p, lam), jnp.where(ok, nu_p, nu), ok


__all__ = ["kkt_residual", "kkt_measures", "kkt_max", "is_converged", "active_set", "kkt_equations",
           "polish_newton"]
