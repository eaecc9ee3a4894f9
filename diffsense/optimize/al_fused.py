"""The augmented-Lagrangian loop with its BFGS subproblem solver fused in (``inner="fused"``).

:mod:`.al` describes the method: the PHR augmented Lagrangian L_ρ minimised over the box by
BFGS on the reparameterisation z = z(y) (:func:`.bounds.box_reparameterisation`), then the
multiplier, penalty and phase updates of :func:`.al.close_subproblem`. Nested
(:mod:`.al_nested`), that is two loops and two evaluation sites: the inner solver's value and
gradient of L_ρ, and the outer linearisation. Each site is a copy of the model in the
compiled program, and on design models each copy costs seconds of compilation.

Here both loops are one ``lax.while_loop`` whose every trip evaluates the problem once, by
one forward-mode linearisation (values and n-column Jacobian of (f, g, h)) at a trial point.
The Jacobian gives L_ρ's gradient for any multipliers without evaluating again,

    ∇_x L_ρ = w s_f ∇f + J_gᵀ (s_g ⊙ max(0, λ + ρ G)) + J_hᵀ (s_h ⊙ (ν + ρ H)),

so a subproblem that ends at an accepted point hands that point's linearisation straight to
the outer update. A trip is one of:

* the setup trip: the start z₀, whose linearisation gives the function scales;
* a subproblem's start y₀ = y⁻¹(z), accepted as is. Variables are pulled off their bounds
  (where dz/dy = 0 a gradient method could not move them off), except those that the new
  subproblem's gradient at z (from z's linearisation, already at hand) pushes out of the box:
  they stay exactly on their bound, a stationary point in y. Pulling those off too would
  leave each subproblem to bring them back, and would leave the projected gradient no smaller
  than the pull-off distance;
* a line-search trial y + α p along the BFGS direction p = −B⁻¹ ∇_y L_ρ. B⁻¹ starts as I
  and is updated by the BFGS formula after each accepted step (left alone when
  sᵀy ≤ 10⁻¹² ‖s‖‖y‖; Nocedal & Wright, *Numerical Optimization*, 2nd ed., eq. 6.17). It is
  carried from one subproblem to the next, which differ only in multipliers and penalty (on
  the shipped designs' first-step lanes this took 11–30 % fewer BFGS steps than starting
  each subproblem from I, with the same lanes converged), and reset to I for the
  restoration, which minimises another function, or when it stops giving a descent
  direction.

The step satisfies the weak Wolfe conditions, φ(α) ≤ φ(0) + 10⁻⁴ α φ'(0) and
φ'(α) ≥ 0.9 φ'(0) for φ(α) = L_ρ(y + αp) (N&W §3.1), found by the bracketing of Lewis and
Overton (Math. Program. 141 (2013) 135–163): a trial failing the decrease condition becomes
the upper end of the bracket, one meeting it but still descending steeply the lower end; the
next trial doubles α while there is no upper end and bisects the bracket otherwise. The
gradient at each trial comes with its linearisation, so the curvature test costs nothing,
and it keeps sᵀy > 0 for the BFGS update. Where L_ρ is flat to rounding the decrease test
compares rounding errors; there the approximate Wolfe condition of Hager and Zhang (SIAM J.
Optim. 16 (2005) 170–192) replaces it: φ(α) ≤ φ(0) + 100 ε (1 + |φ(0)|) and
φ'(α) ≤ −0.8 φ'(0). After ``max_line_search`` trials a trial meeting the decrease condition
is taken whatever its curvature.

A subproblem ends at an accepted point whose projected gradient ‖P(z − ∇_z L_ρ) − z‖∞ is
within its tolerance (the ALGENCAN test, and by the multiplier identity of
:mod:`.al` the outer stationarity), after ``max_inner`` accepted steps, when
``max_line_search`` trials find no decrease, or when a step, accepted or tried, is too short
to move y (α‖p‖∞ ≤ 50 ε (1 + ‖y‖∞)): the last accepted point stands. Non-finite trial values
fail the decrease test; a subproblem whose start is not finite ends the solve at the
previous iterate.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
from jax import lax

from diffsense.optimize.al import (
    RESTORE,
    SETUP,
    ALContext,
    ALState,
    close_subproblem,
    run_al,
    still_running,
    subproblem_settings,
)
from diffsense.optimize.bounds import box_reparameterisation, physical_point, snap_to_bounds
from diffsense.optimize.kernel import dx_dz, linearize_at, pick, projected_gradient_norm, scales_from
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.result import Result

_ARMIJO = 1e-4  # sufficient-decrease constant
_WOLFE = 0.9  # curvature constant
_HZ_DELTA = 0.1  # Hager-Zhang's δ of the approximate Wolfe condition
_ROUNDING = 100.0  # rounding level of L_ρ, in units of the machine epsilon (relative)
_NEGLIGIBLE = 50.0  # shortest step that moves y, in units of the machine epsilon (relative)
_CURVATURE = 1e-12  # least sᵀy / (‖s‖‖y‖) for a BFGS update


class _Fused(NamedTuple):
    al: ALState  # outer iterate (the subproblem's start), multipliers, penalty, phase
    start: jax.Array  # the next trip evaluates a subproblem's start point
    y: jax.Array  # accepted point of the subproblem (reparameterised)
    z: jax.Array
    val: jax.Array  # unscaled (f, g, h) there and their Jacobian with respect to x
    jac: jax.Array
    L: jax.Array  # subproblem value and gradients with respect to y and z there
    gy: jax.Array
    gz: jax.Array
    hinv: jax.Array  # BFGS inverse Hessian approximation (y)
    p: jax.Array  # search direction
    alpha: jax.Array  # step length of the next trial
    lo: jax.Array  # bracket of the weak-Wolfe step: lo satisfies the decrease condition,
    hi: jax.Array  # hi fails it (inf until a trial does)
    fails: jax.Array  # failed trials of the current line search
    steps: jax.Array  # accepted steps of the current subproblem


def augmented_from(val, jac, dxdz, scales, lam, nu, rho, w_f, m: int):
    """L_ρ and ∇_z L_ρ from the problem's linearisation (values, Jacobian with respect to x)."""
    G, H = scales.g * val[1:1 + m], scales.h * val[1 + m:]
    act = jnp.maximum(0.0, lam + rho * G)
    value = (w_f * scales.f * val[0] + jnp.sum(nu * H + 0.5 * rho * H**2)
             + jnp.sum(act**2 - lam**2) / (2.0 * rho))
    grad_x = w_f * scales.f * jac[0] + jac[1:1 + m].T @ (scales.g * act) + jac[1 + m:].T @ (scales.h * (nu + rho * H))
    return value, dxdz * grad_x


def _bfgs_update(hinv, s, y):
    """Inverse-Hessian BFGS update with step ``s`` and gradient change ``y``, skipped without
    positive curvature."""
    sy = jnp.dot(s, y)
    ok = (sy > _CURVATURE * jnp.sqrt(jnp.dot(s, s) * jnp.dot(y, y))) & jnp.isfinite(sy)
    r = 1.0 / jnp.where(ok, sy, 1.0)
    v = jnp.eye(s.shape[0], dtype=s.dtype) - r * jnp.outer(s, y)
    return jnp.where(ok, v @ hinv @ v.T + r * jnp.outer(s, s), hinv)


def fused_loop(ctx: ALContext, state: ALState) -> ALState:
    """Run the solve from the setup state to its end; returns the final outer state."""
    problem, theta, options = ctx.problem, ctx.theta, ctx.options
    zlo, zhi, m = ctx.zlo, ctx.zhi, ctx.m
    forward, inverse = box_reparameterisation(zlo, zhi)
    n = state.z.shape[0]
    dtype = state.z.dtype
    eye = jnp.eye(n, dtype=dtype)
    eps = float(jnp.finfo(dtype).eps)

    def dz_dy(y):
        return jax.jvp(forward, (y,), (jnp.ones_like(y),))[1]

    def cond(fs: _Fused):
        return still_running(ctx, fs.al)

    def body(fs: _Fused):
        s = fs.al
        setup = s.phase == SETUP
        lam_e, nu_e, rho_e, w_f, eps_e = subproblem_settings(ctx, s)
        # a subproblem starts at the outer iterate with the variables pulled off their bounds,
        # except those the new subproblem's gradient there (from the iterate's linearisation)
        # holds on a bound: they stay on it exactly
        x_s = physical_point(problem, s.z, zlo, zhi)
        _, gz_s = augmented_from(s.val, s.jac, dx_dz(problem, x_s), s.scales, lam_e, nu_e, rho_e, w_f, m)
        hold = ((s.z <= zlo) & (gz_s >= 0.0)) | ((s.z >= zhi) & (gz_s <= 0.0))
        y_t = jnp.where(fs.start, inverse(s.z, hold), fs.y + fs.alpha * fs.p)
        z_t = jnp.where(setup, s.z, snap_to_bounds(jnp.clip(forward(y_t), zlo, zhi), zlo, zhi))
        # the only evaluation of the problem functions in the loop
        x_t, val_t, jac_t = linearize_at(problem, theta, z_t, zlo, zhi)
        dxdz = dx_dz(problem, x_t)
        scales = pick(setup, scales_from(jac_t * dxdz[None, :], val_t, m, options), s.scales)
        L_t, gz_t = augmented_from(val_t, jac_t, dxdz, scales, lam_e, nu_e, rho_e, w_f, m)
        gy_t = gz_t * dz_dy(y_t)
        finite_t = jnp.isfinite(L_t) & jnp.all(jnp.isfinite(gy_t)) & jnp.all(jnp.isfinite(val_t))

        slope = jnp.dot(fs.gy, fs.p)
        slope_t = jnp.dot(gy_t, fs.p)
        armijo = L_t <= fs.L + _ARMIJO * fs.alpha * slope
        # flat to rounding: Hager and Zhang's approximate Wolfe decrease (module docstring)
        level = _ROUNDING * eps * (1.0 + jnp.abs(fs.L))
        approx = (L_t <= fs.L + level) & (slope_t <= (1.0 - 2.0 * _HZ_DELTA) * -slope)
        decrease = finite_t & (armijo | approx)
        curvature = slope_t >= _WOLFE * slope
        fails = jnp.where(fs.start, 0, fs.fails + 1)
        last_try = fails >= options.max_line_search
        accept = (fs.start & finite_t) | (~fs.start & decrease & (curvature | last_try))
        start_bad = fs.start & ~finite_t & ~setup
        # B⁻¹ carries over from one subproblem to the next (they differ in multipliers and
        # penalty only); the restoration minimises another function and starts from I
        h_start = jnp.where(s.phase == RESTORE, eye, fs.hinv)
        hinv = jnp.where(fs.start, h_start, jnp.where(accept, _bfgs_update(fs.hinv, y_t - fs.y, gy_t - fs.gy), fs.hinv))
        steps = jnp.where(fs.start, 0, fs.steps + accept.astype(fs.steps.dtype))
        y_a = jnp.where(accept, y_t, fs.y)
        z_a = jnp.where(accept, z_t, fs.z)
        val_a = jnp.where(accept, val_t, fs.val)
        jac_a = jnp.where(accept, jac_t, fs.jac)
        L_a = jnp.where(accept, L_t, fs.L)
        gy_a = jnp.where(accept, gy_t, fs.gy)
        gz_a = jnp.where(accept, gz_t, fs.gz)

        # weak-Wolfe bracketing (module docstring)
        fails = jnp.where(accept, 0, fails)
        hi = jnp.where(decrease, fs.hi, fs.alpha)
        lo = jnp.where(decrease, fs.alpha, fs.lo)
        alpha_next = jnp.where(jnp.isfinite(hi), 0.5 * (lo + hi), 2.0 * fs.alpha)
        y_size = 1.0 + jnp.max(jnp.abs(fs.y))
        negligible = fs.alpha * jnp.max(jnp.abs(fs.p)) <= _NEGLIGIBLE * eps * y_size
        search_failed = ~accept & ~fs.start & (last_try | negligible)
        stalled = accept & ~fs.start & negligible
        stationary = projected_gradient_norm(z_a, gz_a, zlo, zhi) <= eps_e
        done = setup | start_bad | search_failed | stalled | (accept & (stationary | (steps >= options.max_inner)))

        # the next direction from an accepted point (steepest descent if B⁻¹ lost descent)
        p_new = -hinv @ gy_a
        descent = jnp.dot(p_new, gy_a) < 0.0
        hinv = jnp.where(descent, hinv, eye)
        p_new = jnp.where(descent, p_new, -gy_a)

        # the setup trip hands over its own evaluation whatever its values (close_subproblem
        # ends the solve at a start where they are not finite)
        z_c, val_c, jac_c = (jnp.where(setup, z_t, z_a), jnp.where(setup, val_t, val_a),
                             jnp.where(setup, jac_t, jac_a))
        closed = close_subproblem(ctx, s, z_c, physical_point(problem, z_c, zlo, zhi), val_c, jac_c, steps,
                                  ~start_bad, eps_e)
        al = pick(done, closed, s)
        cont = _Fused(al, jnp.asarray(False), y_a, z_a, val_a, jac_a, L_a, gy_a, gz_a, hinv,
                      jnp.where(accept, p_new, fs.p), jnp.where(accept, jnp.ones_like(fs.alpha), alpha_next),
                      jnp.where(accept, jnp.zeros_like(lo), lo), jnp.where(accept, jnp.full_like(hi, jnp.inf), hi),
                      fails, steps)
        restart = cont._replace(start=jnp.asarray(True), fails=jnp.zeros_like(fails), steps=jnp.zeros_like(steps),
                                alpha=jnp.ones_like(fs.alpha), lo=jnp.zeros_like(lo), hi=jnp.full_like(hi, jnp.inf))
        return pick(done, restart, cont)

    fs0 = _Fused(
        al=state, start=jnp.asarray(True), y=jnp.zeros((n,), dtype), z=state.z, val=state.val, jac=state.jac,
        L=jnp.zeros((), dtype), gy=jnp.zeros((n,), dtype), gz=jnp.zeros((n,), dtype), hinv=eye, p=jnp.zeros((n,), dtype),
        alpha=jnp.ones((), dtype), lo=jnp.zeros((), dtype), hi=jnp.full((), jnp.inf, dtype), fails=jnp.asarray(0),
        steps=jnp.asarray(0))
    return lax.while_loop(cond, body, fs0).al


def solve_al_fused(problem: Problem, x0, theta, options: SolverOptions) -> Result:
    """The augmented-Lagrangian solve with the fused BFGS inner solver (module docstring)."""
    return run_al(problem, x0, theta, options, fused_loop)


__all__ = ["fused_loop", "solve_al_fused", "augmented_from"]
