"""The augmented-Lagrangian method (``SolverOptions(method="al")``): its outer loop and state.

Method
------
Neither optimistix nor jaxopt solves general inequality constraints, and optimistix has no
bounded minimiser, so the constraint layer lives here. The solver is the
Powell–Hestenes–Rockafellar (PHR) augmented Lagrangian with bounds kept in the subproblem
(the ALGENCAN scheme: Andreani, Birgin, Martínez & Schuverdt, SIAM J. Optim. 18 (2007)
1286–1309; Birgin & Martínez, *Practical Augmented Lagrangian Methods for Constrained
Optimization*, SIAM 2014, Algorithm 4.1; Nocedal & Wright, *Numerical Optimization*, 2nd ed.,
§17.3–17.4). In scaled coordinates z (see :mod:`diffsense.optimize.problem`) with scaled
functions F = s_f f, G = s_g ⊙ g, H = s_h ⊙ h:

    L_ρ(z; λ, ν) = F(z) + Σ_j [ν_j H_j + ρ/2 H_j²] + 1/(2ρ) Σ_i [max(0, λ_i + ρ G_i)² − λ_i²]

Each outer iteration minimises L_ρ over the box zlo ≤ z ≤ zhi (warm started, inner tolerance
``inner_tol_init`` divided by 100 per iteration down to ``tol``), then updates
λ ← max(0, λ + ρG), ν ← ν + ρH (safeguarded to |·| ≤ ``multiplier_max``), and multiplies ρ by
``penalty_growth`` when the infeasibility–complementarity measure
V = max(‖max(G, −λ/ρ)‖∞, ‖H‖∞) fell by less than ``feasibility_reduction`` — but only after
a subproblem that was solved to its tolerance (an inner solve cut off by ``max_inner`` says
nothing about feasibility progress, and a larger ρ would only worsen the next subproblem).
The max(0, ·) form handles inequalities without slack variables; with the updated multipliers
∇_z L_ρ(z; λ_old, ν_old) = ∇_z L₀(z; λ_new, ν_new), so the inner stationarity is the outer
stationarity.

Why this design:
* PHR keeps ρ bounded on regular problems (unlike a pure penalty), so the subproblems stay
  well conditioned, and its multiplier estimates converge to the KKT multipliers.
* Inner solver: BFGS over a smooth surjective reparameterisation of the box,
  z = c + r sin y (two finite bounds), z = lo + y² or hi − y² (one), z = y (none). An active
  bound is reached at a finite y where dz/dy = 0; there the reparameterised objective has
  curvature r·|∂L/∂z| > 0 in y when the bound is strictly active, so BFGS still converges
  superlinearly, and z lands on the bound to rounding. The price: a variable that sits on a
  bound while the gradient points into the box is also at a stationary point in y, so each
  subproblem starts from z with such variables pulled off their bounds (by 1e-6 of the
  half-range, 1e-12 for a one-sided bound; the nested solvers pull every variable off, the
  fused one only those the subproblem's gradient does not hold on their bound), and a
  subproblem can need more iterations than an active-set method when the active bounds
  change (the map is :func:`diffsense.optimize.bounds.box_reparameterisation`). The
  default, ``inner="fused"`` (:mod:`.al_fused`), runs its own BFGS with a weak-Wolfe line
  search inside the outer loop, one evaluation of the problem per trip; ``inner="bfgs"``
  nests (:mod:`.al_nested`) optimistix's BFGS (its line search backtracks on Armijo's
  condition, and it stops on small changes of y and of L_ρ); ``inner="lbfgsb"`` nests
  jaxopt's L-BFGS-B (Byrd, Lu, Nocedal & Zhu, SIAM J. Sci. Comput. 16 (1995) 1190), which
  works on the box itself. All three reach the same KKT points
  on the reference problems and on 30 random log-scaled convex problems with 5–30 variables
  and 3–15 constraints (checked against SciPy's SLSQP during development: the fused solver
  converged on all 30, objectives within 2e-9 relative; one such problem is in the tests).
  The nested optimistix BFGS program is half the size of the L-BFGS-B one on
  HS071 (2.4k vs 5k StableHLO lines), compiles ~3x faster and runs ~10x faster per solve.
  All are fixed-shape ``lax.while_loop``s that jit and vmap.
* Polish: once an outer iterate has KKT residual ≤ ``polish_start``, Newton's method is
  applied to the KKT equations of its active set (:mod:`diffsense.optimize.kkt`). The
  Newton point is kept only when it is finite, inside the bounds, keeps the active
  multipliers ≥ 0, does not raise the violation and lowers the KKT residual; otherwise the
  augmented-Lagrangian iterations simply continue.
* Infeasibility: when the outer loop ends with violated constraints (ρ at its cap without
  progress for 3 iterations, or out of iterations), one restoration solve minimises
  φ(z) = ½‖max(0, G)‖² + ½‖H‖² over the box from the last iterate (the same inner solver,
  with the f weight set to 0). Its minimiser is the least-infeasible compromise in scaled
  units; ``feasible`` tells whether the returned x satisfies every constraint within
  ``feas_tol``, and ``conflict`` lists the constraints left violated and the bounds that
  block any further reduction of φ (∂φ/∂z pushes out of the box there): the set of
  requirements that cannot be met together. The multipliers of an infeasible answer are
  the last AL estimates, which grow with ρ on the conflicting constraints.

Function scales: :mod:`diffsense.optimize.kernel`.

Evaluation sites. Each place where the solver evaluates the problem functions is a copy of the
model in the compiled program, and on design models each copy costs seconds of compilation.
The nested inner solvers have two: the inner solver's value and gradient of L_ρ, and one
forward-mode linearisation (values and n-column Jacobian of (f, g, h)) per outer trip at the
inner solution. A setup trip before the first outer iteration linearises at z₀ and takes the
scales from it; every later trip's linearisation gives the multiplier update, the KKT test and
the restoration checks; the last accepted one gives the answer (with ``polish`` a polished
iterate is linearised once more at the end). The fused solver has one: the linearisation,
which also gives the inner gradient. On the design optimiser's first step for the ore-pass
design (80 lanes, ``polish=False``), going from two sites to one cut tracing and lowering from
2.6 s to 2.2 s, XLA compilation from 4.6 s to 2.7 s and the run from 0.65 s to 0.3 s
(earlier, going from four sites to two had cut compilation from 14.5 s to 5.9 s).

Outputs are physical: x is projected onto [lower, upper] (so it never violates a bound) and
f, g, h, the KKT residual and ``feasible`` are all evaluated at that projected point;
λ ≥ 0 (inequalities), ν (equalities), bound multipliers μ_lower, μ_upper ≥ 0 with the
convention ∇f + J_gᵀλ + J_hᵀν − μ_lower + μ_upper = 0. Everything is fixed-shape and
NaN-free, so the solve can be jitted and vmapped over x0 and θ.

This module holds what the two ways of running the loop share — the state, the update after
a subproblem (:func:`close_subproblem`), the answer (:func:`run_al`) — and each way is a
``loop(ctx, state) -> state``: :func:`diffsense.optimize.al_nested.nested_loop` and
:func:`diffsense.optimize.al_fused.fused_loop`.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
from jax import lax

from diffsense.optimize.bounds import bound_multipliers, physical_point, snap_to_bounds
from diffsense.optimize.kernel import (
    conflict_masks,
    dx_dz,
    inf_norm,
    linearize_at,
    make_model,
    pick,
    scaled_start,
    scales_from,
    unit_scales,
)
from diffsense.optimize.kkt import is_converged, kkt_max, kkt_measures, kkt_residual, polish_newton
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.result import KKTResidual, Result, Scales

# phases of the loop: a subproblem of the augmented Lagrangian, the restoration, the end, and
# the setup trip that linearises at the start
AL, RESTORE, DONE, SETUP = 0, 1, 2, 3


class ALState(NamedTuple):
    """The loop's carry: trips so far ``k``, the iterate z with its scaled multipliers λ̃, ν̃ and
    penalty ρ, the last infeasibility–complementarity measure V (``v_prev``), the inner
    tolerance, inner steps so far, trips stalled at the penalty cap, the phase, whether the
    restoration and the polish were kept, and the iterate's scales and linearisation."""

    k: jax.Array
    z: jax.Array
    lam: jax.Array
    nu: jax.Array
    rho: jax.Array
    v_prev: jax.Array
    eps: jax.Array
    inner_total: jax.Array
    stall: jax.Array
    phase: jax.Array
    restored: jax.Array
    polished: jax.Array
    viol: jax.Array  # scaled constraint violation at z (inf before the first iteration)
    scales: Scales  # function scales (set by the setup trip)
    val: jax.Array  # unscaled (f, g, h) at z
    jac: jax.Array  # their Jacobian with respect to x at x(z)


class ALContext(NamedTuple):
    """What every trip of the augmented-Lagrangian loop needs besides its state (static
    settings and closures; never traced)."""

    problem: Problem
    theta: object
    options: SolverOptions
    zlo: jax.Array
    zhi: jax.Array
    m: int
    dtype: object
    can_restore: bool


def still_running(ctx: ALContext, s: ALState):
    """The loop's condition: not done, and within its trip cap."""
    return (s.phase != DONE) & (s.k < ctx.options.max_outer + 1)


def subproblem_settings(ctx: ALContext, s: ALState):
    """(λ, ν, ρ, objective weight, tolerance) of the subproblem the state's phase solves: the
    augmented Lagrangian, or φ (λ = ν = 0, ρ = 1, no objective) when restoring."""
    restoring = s.phase == RESTORE
    lam_e = jnp.where(restoring, 0.0, s.lam)
    nu_e = jnp.where(restoring, 0.0, s.nu)
    rho_e = jnp.where(restoring, 1.0, s.rho)
    w_f = jnp.where(restoring, 0.0, 1.0)
    eps_e = jnp.where(restoring, ctx.options.tol * 1e-2, s.eps)
    return lam_e, nu_e, rho_e, w_f, eps_e


def _try_polish(ctx: ALContext, scales: Scales, near, z, lam, nu, grad, G, kkt: KKTResidual):
    """The Newton polish of (z, λ, ν) where ``near`` (:func:`diffsense.optimize.kkt.polish_newton`),
    kept when it lowers the KKT residual without raising the violation. Returns (z, λ, ν, kkt,
    polished)."""
    options = ctx.options
    pmodel = make_model(ctx.problem, ctx.theta, scales)

    def polish(args):
        z, lam, nu, grad, G = args
        z_p, lam_p, nu_p, ok = polish_newton(pmodel, z, lam, nu, grad, G, options)
        return z_p, lam_p, nu_p, ok, kkt_measures(pmodel, z_p, lam_p, nu_p)

    def no_polish(args):
        z, lam, nu, _, _ = args
        inf = jnp.asarray(jnp.inf, ctx.dtype)
        return z, lam, nu, jnp.asarray(False), KKTResidual(inf, inf, inf)

    z_p, lam_p, nu_p, ok, kkt_p = lax.cond(near, polish, no_polish, (z, lam, nu, grad, G))
    polished = (ok & near & (kkt_max(kkt_p) <= kkt_max(kkt))
                & (kkt_p.feasibility <= jnp.maximum(kkt.feasibility, options.feas_tol)))
    return (jnp.where(polished, z_p, z), jnp.where(polished, lam_p, lam), jnp.where(polished, nu_p, nu),
            pick(polished, kkt_p, kkt), polished)


def close_subproblem(ctx: ALContext, s: ALState, z_new, x_new, val, jac, its, finite_z, eps_e) -> ALState:
    """The state after a subproblem (or the setup trip) ended at ``z_new``, where the problem
    was linearised as (x_new, val, jac): scales on the setup trip; otherwise the multiplier and
    penalty updates, the KKT test, the polish and the phase change (module docstring).
    ``finite_z`` False means the subproblem gave no usable point: the solve ends at ``s.z``."""
    options, m = ctx.options, ctx.m
    setup = s.phase == SETUP
    restoring = s.phase == RESTORE
    dxdz = dx_dz(ctx.problem, x_new)
    scales = pick(setup, scales_from(jac * dxdz[None, :], val, m, options), s.scales)
    G, H = scales.g * val[1:1 + m], scales.h * val[1 + m:]
    finite = finite_z & jnp.all(jnp.isfinite(val))
    v = jnp.maximum(inf_norm(jnp.maximum(G, -s.lam / s.rho)), inf_norm(H))
    lam = jnp.clip(s.lam + s.rho * G, 0.0, options.multiplier_max)
    nu = jnp.clip(s.nu + s.rho * H, -options.multiplier_max, options.multiplier_max)
    grad = dxdz * (scales.f * jac[0] + jac[1:1 + m].T @ (scales.g * lam) + jac[1 + m:].T @ (scales.h * nu))
    kkt = kkt_residual(z_new, grad, G, H, lam, ctx.zlo, ctx.zhi)

    # raise ρ only after a subproblem that was actually solved (stationarity within 10x its
    # tolerance): slow feasibility progress of an inexact inner solve is no reason to worsen
    # the conditioning of the next one
    slow = (v > options.feasibility_reduction * s.v_prev) & (kkt.stationarity <= 10.0 * eps_e)
    rho = jnp.where(slow & (v > options.feas_tol),
                    jnp.minimum(s.rho * options.penalty_growth, options.penalty_max), s.rho)
    at_cap = s.rho >= options.penalty_max
    stall = jnp.where(at_cap & (v >= 0.99 * s.v_prev) & (v > options.feas_tol), s.stall + 1, 0)

    polished = jnp.asarray(False)
    if options.polish:
        near = (kkt_max(kkt) <= options.polish_start) & finite & ~restoring & ~setup
        z_new, lam, nu, kkt, polished = _try_polish(ctx, scales, near, z_new, lam, nu, grad, G, kkt)

    # non-finite values at the inner solution: end at the previous iterate and multipliers
    val_t, jac_t = val, jac
    z_new = jnp.where(finite, z_new, s.z)
    lam = jnp.where(finite, lam, s.lam)
    nu = jnp.where(finite, nu, s.nu)
    val = jnp.where(finite, val, s.val)
    jac = jnp.where(finite, jac, s.jac)

    conv = is_converged(kkt, options)
    out_of_iters = s.k + 1 >= options.max_outer
    ended = conv | (stall >= 3) | out_of_iters | ~finite
    infeasible_end = ended & ~conv & (kkt.feasibility > options.feas_tol) & finite
    # restore on evidence of infeasibility (ρ capped without progress, or a violation far
    # above tolerance), not when the iterations merely ran out just short of feas_tol
    evidence = (stall >= 3) | (kkt.feasibility > 1e3 * options.feas_tol)
    next_phase = jnp.where(ended, jnp.where(infeasible_end & evidence & ctx.can_restore, RESTORE, DONE), AL)
    eps = jnp.maximum(options.tol, s.eps * 0.01)
    al_state = ALState(s.k + 1, z_new, lam, nu, rho, v, eps, s.inner_total + its, stall, next_phase,
                       s.restored, polished, jnp.where(finite, kkt.feasibility, s.viol), scales, val, jac)

    # restoration step (φ minimisation): keep it only if it lowers the violation
    keep = kkt.feasibility <= s.viol
    res_state = ALState(s.k + 1, jnp.where(keep, z_new, s.z), s.lam, s.nu, s.rho, s.v_prev, s.eps,
                        s.inner_total + its, s.stall, jnp.asarray(DONE), keep, jnp.asarray(False),
                        jnp.where(keep, kkt.feasibility, s.viol), scales,
                        jnp.where(keep, val, s.val), jnp.where(keep, jac, s.jac))

    # setup trip: the start, its linearisation and the scales; a start where the problem
    # functions are not finite ends the solve there, answering with those values (so the
    # result is neither feasible nor converged)
    setup_state = s._replace(phase=jnp.where(finite, AL, DONE), z=z_new, scales=scales, val=val_t, jac=jac_t)
    return pick(setup, setup_state, pick(restoring, res_state, al_state))


class _Final(NamedTuple):
    z: jax.Array
    x: jax.Array
    f: jax.Array
    g: jax.Array
    h: jax.Array
    lam: jax.Array
    nu: jax.Array
    mu_lower: jax.Array
    mu_upper: jax.Array
    kkt: KKTResidual
    grad_phi: jax.Array
    G: jax.Array
    H: jax.Array
    jac: jax.Array


def _final_from(problem: Problem, scales: Scales, zlo, zhi, z, x, val, jac, lam, nu, m: int) -> _Final:
    """Physical outputs at z from the linearisation (x, val, jac) of
    :func:`diffsense.optimize.kernel.linearize_at`: f, g, h, physical multipliers, bound
    multipliers, the scaled KKT residual and ∇_z φ."""
    f, g, h = val[0], val[1:1 + m], val[1 + m:]
    dxdz = dx_dz(problem, x)
    lam_p = lam * scales.g / scales.f
    nu_p = nu * scales.h / scales.f
    G = scales.g * g
    H = scales.h * h
    jac = jnp.where(jnp.isfinite(jac), jac, 0.0)
    r_x = jac[0] + jac[1:1 + m].T @ lam_p + jac[1 + m:].T @ nu_p
    gphi_x = jac[1:1 + m].T @ (scales.g * jnp.maximum(G, 0.0)) + jac[1 + m:].T @ (scales.h * H)
    grad_z = scales.f * dxdz * r_x
    kkt = kkt_residual(z, grad_z, G, H, lam, zlo, zhi)
    mu_lo, mu_hi = bound_multipliers(problem, x, r_x)
    return _Final(z, x, f, g, h, lam_p, nu_p, mu_lo, mu_hi, kkt, dxdz * gphi_x, G, H, jac)


def _final_outputs(ctx: ALContext, state: ALState) -> _Final:
    """The answer's outputs at the last iterate. A polished iterate is not where its trip
    linearised, so with ``polish`` the problem is linearised once more, at the iterate put
    exactly on the bounds it is within rounding of (an active bound is met exactly and gets
    its multiplier)."""
    problem, zlo, zhi, m = ctx.problem, ctx.zlo, ctx.zhi, ctx.m
    z, lam, nu, scales = state.z, state.lam, state.nu, state.scales
    if ctx.options.polish:
        z = snap_to_bounds(z, zlo, zhi)
        x, val, jac = linearize_at(problem, ctx.theta, z, zlo, zhi)
        return _final_from(problem, scales, zlo, zhi, z, x, val, jac, lam, nu, m)
    x = physical_point(problem, z, zlo, zhi)
    return _final_from(problem, scales, zlo, zhi, z, x, state.val, state.jac, lam, nu, m)


def _initial_state(options: SolverOptions, z0, m: int, p: int, dtype, unconstrained: bool) -> ALState:
    nvar = z0.shape[0]
    eps0 = options.tol if unconstrained else max(options.tol, options.inner_tol_init)
    return ALState(
        k=jnp.asarray(0), z=z0, lam=jnp.zeros((m,), dtype), nu=jnp.zeros((p,), dtype),
        rho=jnp.asarray(options.penalty_init, dtype), v_prev=jnp.asarray(jnp.inf, dtype),
        eps=jnp.asarray(eps0, dtype), inner_total=jnp.asarray(0), stall=jnp.asarray(0),
        phase=jnp.asarray(SETUP), restored=jnp.asarray(False), polished=jnp.asarray(False),
        viol=jnp.asarray(jnp.inf, dtype), scales=unit_scales(m, p, dtype),
        val=jnp.zeros((1 + m + p,), dtype), jac=jnp.zeros((1 + m + p, nvar), dtype),
    )


def run_al(problem: Problem, x0, theta, options: SolverOptions,
           loop: Callable[[ALContext, ALState], ALState]) -> Result:
    """Minimise ``problem`` from ``x0`` at ``theta`` by the augmented Lagrangian, its trips run
    by ``loop`` from the setup state to the end (module docstring). Pure and fixed-shape."""
    dtype, zlo, zhi, z0, m, p = scaled_start(problem, x0, theta)
    unconstrained = (m + p) == 0
    ctx = ALContext(problem, theta, options, zlo, zhi, m, dtype, options.restore and not unconstrained)
    state = loop(ctx, _initial_state(options, z0, m, p, dtype, unconstrained))
    final = _final_outputs(ctx, state)

    # an answer whose values are not finite (a start outside the model's domain) is never
    # converged, and feasible only when its constraint values are finite and met
    finite_g = jnp.all(jnp.isfinite(final.g)) & jnp.all(jnp.isfinite(final.h))
    feasible = (final.kkt.feasibility <= options.feas_tol) & finite_g
    converged = is_converged(final.kkt, options) & finite_g & jnp.isfinite(final.f)
    conflict = conflict_masks(feasible, final.G, final.H, final.z, zlo, zhi, final.grad_phi, options)
    return Result(
        x=final.x, f=final.f, g=final.g, h=final.h, lam=final.lam, nu=final.nu,
        mu_lower=final.mu_lower, mu_upper=final.mu_upper, converged=converged, feasible=feasible,
        kkt=final.kkt, iterations=state.k, inner_iterations=state.inner_total, penalty=state.rho,
        polished=state.polished, conflict=conflict, scales=state.scales, jacobian=final.jac,
    )


__all__ = ["AL", "RESTORE", "DONE", "SETUP", "ALState", "ALContext", "still_running", "subproblem_settings",
           "close_subproblem", "run_al"]
