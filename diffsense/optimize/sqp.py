"""Sequential quadratic programming (SQP) for small dense design problems.

    minimise f(x, θ)  s.t.  g(x, θ) ≤ 0,  h(x, θ) = 0,  lower ≤ x ≤ upper

The method of Wilson, Han and Powell with a damped BFGS Hessian and an ℓ1 merit line search
(Han, J. Optim. Theory Appl. 22 (1977) 297; Powell, *Numerical Analysis Dundee 1977*, LNM 630,
144–157; Nocedal & Wright, *Numerical Optimization*, 2nd ed., Algorithm 18.3 and §18.3), the
method of SciPy's SLSQP (Kraft, DFVLR-FB 88-28, 1988), with three choices of its own:

* **One evaluation per trip, and one evaluation site.** Every trip of the loop linearises the
  stacked vector (f, g, h) once, by forward-mode differentiation in the scaled variables z
  (``Problem.from_scaled``; n tangents for n variables, the cheap direction for design problems:
  a handful of variables, a chain of hundreds of operations), at the line search's trial point.
  An accepted trial is the next iterate with its linearisation already in hand, so a full step
  costs one linearisation, and the model appears once in the compiled program (each place that
  evaluates it is a copy, and a design model's copy costs seconds of compilation). On the
  ore-pass design this halves the work per iteration against a linearisation per iterate plus
  value-only trials: 5 linearisations for 4 iterations, 0.8 ms instead of 1.5 ms per solve
  (back-to-back calls, one run each). Function scales are taken from the first linearisation
  exactly as :func:`diffsense.optimize.solve` takes them (so tolerances mean the same in both
  solvers).
* **Subproblem by a dual active-set method, elastic when inconsistent.** The QP

      min_d ½ dᵀBd + ∇Fᵀd   s.t.  H + J_H d = 0,  G + J_G d ≤ 0,  zlo − z ≤ d ≤ zhi − z

  is solved by the Goldfarb–Idnani method (:mod:`diffsense.optimize.active_set`): exact to
  rounding, with multipliers exactly 0 on inactive rows, in a few steps (one per change of
  the active set). Its exactness matters where the optimum is not a point: on the ore-pass
  design the objective and the one active requirement depend on the antenna alone, so the
  optimum is a 4-dimensional set along which B has almost no curvature, and the ~1e-12
  residual of an interior-point solve, divided by that curvature, made the iterate wander
  along the set (33 iterations in all); the active-set QP ends the solve in 4. When the
  linearised constraints are inconsistent (far from the solution, or on an infeasible
  problem) the method says so, and the elastic QP

      min_d ½ dᵀBd + ∇Fᵀd + M (Σ sᵢ + Σ tⱼ)
      s.t.  G + J_G d ≤ s,  |H + J_H d| ≤ t,  s, t ≥ 0,  zlo − z ≤ d ≤ zhi − z

  (always feasible: the ℓ1 elastic mode of SNOPT, Gill, Murray & Saunders, SIAM Rev. 47
  (2005) 99–131; M = ``elastic_weight`` in scaled units) is solved instead by
  :func:`diffsense.optimize.qp.solve_qp` (Mehrotra predictor–corrector, at most
  ``qp_iterations`` steps). Variables without a finite bound get a step bound of ±10 scaled
  units.
* **Damped BFGS.** B starts as I, is rescaled by yᵀy/sᵀy before its first update (Shanno &
  Phua) and is updated with Powell's damping (yᵀs ≥ 0.2 sᵀBs), so it stays positive definite.

The ℓ1 merit φ = F + π(Σ max(Gᵢ, 0) + Σ |Hⱼ|), with π = max(π̂, (π_old + π̂)/2) and
π̂ = 1.5 max|multiplier| (Powell's rule, Numerical Analysis Dundee 1977, as in SLSQP: π can fall
back towards the multipliers after a large early estimate; a π held at its largest value —
1500 after an elastic first step on one ore-pass start, against multipliers below 1 later —
makes every full step that bends a nearly active constraint fail the merit test, and that
start then crept along at step lengths of 2⁻⁹ for 100 iterations), is decreased by an Armijo
search (sufficient decrease 1e-4·α·φ′, plus 1e-14·(1 + |φ|) of rounding):
the full step first; then, against the Maratos effect (a full step near the solution that the
merit rejects because the constraints curve), the full step plus the second-order correction
−J_Aᵀ(J_A J_Aᵀ)⁻¹ c_A(z + d) on the active constraints (Nocedal & Wright §18.3, eq. 18.51 with
the variables at bounds held); then the step halved per trial, ``max_line_search`` times at
most. A step that finds no decrease resets B to I. Convergence is the KKT test of
:func:`diffsense.optimize.solve` (projected-gradient stationarity and complementarity ≤ ``tol``,
violation ≤ ``feas_tol``, in scaled units) at the iterate with the multipliers of its own
subproblem, and a negligible next step: ‖d‖∞ ≤ tol·(1 + ‖z‖∞), or dᵀBd ≤ tol²·(1 + |F|)
(the predicted change of F below its rounding, which allows steps of any length along a set of
optima). The step test is there because f is scaled at the start, and where its curvature at
the optimum is much smaller than there, a small scaled gradient alone leaves the iterate
inaccurate (as on the servo-bandwidth test problem).
An iterate on a bound (:mod:`diffsense.optimize.bounds`: within 1e-9 of it, relative) is put on
it, so active bounds are met exactly.

Scope. Fast and compact on well-posed problems; it has no restoration phase: an infeasible
problem ends with ``converged`` False and ``conflict`` marking the constraints left violated and
the bounds that block progress (read from the ℓ1 infeasibility gradient), but the answer is the
last iterate, not a least-infeasible point. :func:`diffsense.optimize.solve` (``method="al"``)
is the robust method, and the one :func:`diffsense.design.optimizer.optimize_design` uses.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
from jax import lax

from diffsense.optimize.active_set import solve_qp_active_set
from diffsense.optimize.bounds import bound_multipliers, physical_point, snap_to_bounds
from diffsense.optimize.kernel import (
    conflict_masks,
    dx_dz,
    inf_norm,
    pick,
    scaled_start,
    scales_from,
    stack_fgh,
    unit_scales,
)
from diffsense.optimize.kkt import is_converged, kkt_residual
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.qp import solve_qp
from diffsense.optimize.result import KKTResidual, Result, Scales

_FREE_STEP = 10.0  # step bound (scaled units) of a variable without a finite bound


class _Lin(NamedTuple):
    """Scaled linearisation at z: values F, G, H and Jacobians."""

    F: jax.Array
    dF: jax.Array
    G: jax.Array
    JG: jax.Array
    H: jax.Array
    JH: jax.Array


class _State(NamedTuple):
    k: jax.Array  # subproblems solved (iterations)
    z: jax.Array  # the iterate
    lin: _Lin  # scaled linearisation at z
    raw: jax.Array  # unscaled (f, g, h) at z
    lam: jax.Array  # multipliers of the subproblem at z
    nu: jax.Array
    B: jax.Array
    pi: jax.Array
    scales: Scales
    kkt: KKTResidual  # at z with (lam, nu)
    d: jax.Array  # the subproblem's step from z
    phi0: jax.Array  # merit at z and its directional slope along d
    slope: jax.Array
    j: jax.Array  # trial of the line search along d (0: full step, 1: second-order correction, …)
    z_trial: jax.Array  # the point the next trip linearises
    raw_full: jax.Array  # (f, g, h) at the full step's trial (for the correction)
    J_act: jax.Array  # active rows of the constraint Jacobian, for the correction
    row_on: jax.Array
    done: jax.Array
    evaluations: jax.Array


def _scaled_lin(val, jac, s: Scales, m: int) -> _Lin:
    return _Lin(s.f * val[0], s.f * jac[0], s.g * val[1:1 + m], s.g[:, None] * jac[1:1 + m],
                s.h * val[1 + m:], s.h[:, None] * jac[1 + m:])


def _damped_bfgs(B, s, y, first):
    """Powell-damped BFGS update of B with step s and gradient change y."""
    Bs = B @ s
    sBs = jnp.dot(s, Bs)
    sy = jnp.dot(s, y)
    # Shanno–Phua initial scaling, before the first update
    scale = jnp.where(first & (sy > 0), jnp.dot(y, y) / jnp.where(sy > 0, sy, 1.0), 1.0)
    B = B * scale
    Bs, sBs = Bs * scale, sBs * scale
    theta = jnp.where(sy >= 0.2 * sBs, 1.0, 0.8 * sBs / jnp.where(sBs - sy != 0, sBs - sy, 1.0))
    r = theta * y + (1.0 - theta) * Bs
    sr = jnp.dot(s, r)
    ok = (sBs > 1e-300) & (sr > 1e-300) & jnp.all(jnp.isfinite(r))
    B_new = B - jnp.outer(Bs, Bs) / jnp.where(ok, sBs, 1.0) + jnp.outer(r, r) / jnp.where(ok, sr, 1.0)
    B_new = 0.5 * (B_new + B_new.T)
    return jnp.where(ok & jnp.all(jnp.isfinite(B_new)), B_new, B)


def _elastic_qp_step(lin: _Lin, B, dlo, dhi, weight, iterations):
    """Elastic QP by interior point (module docstring): step d, multipliers λ (inequalities)
    and ν (equalities), and the elastic slack total Σs + Σt."""
    n, m, p = lin.dF.shape[0], lin.G.shape[0], lin.H.shape[0]
    nv = n + m + p
    dtype = lin.dF.dtype
    Q = jnp.zeros((nv, nv), dtype).at[:n, :n].set(B)
    c = jnp.concatenate([lin.dF, jnp.full((m + p,), weight, dtype)])
    Im, Ip, In = jnp.eye(m, dtype=dtype), jnp.eye(p, dtype=dtype), jnp.eye(n, dtype=dtype)
    zmp = jnp.zeros((m, p), dtype)
    zpm = jnp.zeros((p, m), dtype)
    rows = [
        jnp.concatenate([lin.JG, -Im, zmp], axis=1),                             # G + J d ≤ s
        jnp.concatenate([lin.JH, zpm, -Ip], axis=1),                             # H + J d ≤ t
        jnp.concatenate([-lin.JH, zpm, -Ip], axis=1),                            # −H − J d ≤ t
        jnp.concatenate([jnp.zeros((m, n), dtype), -Im, zmp], axis=1),           # s ≥ 0
        jnp.concatenate([jnp.zeros((p, n), dtype), zpm, -Ip], axis=1),           # t ≥ 0
        jnp.concatenate([In, jnp.zeros((n, m + p), dtype)], axis=1),             # d ≤ dhi
        jnp.concatenate([-In, jnp.zeros((n, m + p), dtype)], axis=1),            # d ≥ dlo
    ]
    A = jnp.concatenate(rows, axis=0)
    b = jnp.concatenate([-lin.G, -lin.H, lin.H, jnp.zeros((m + p,), dtype), dhi, -dlo])
    sol = solve_qp(Q, c, A, b, iterations)
    d = sol.y[:n]
    # rows with uᵢ < wᵢ are inactive (uᵢwᵢ = μ → 0): their multiplier is μ-sized noise, set to 0
    u = jnp.where(sol.u >= sol.w, sol.u, 0.0)
    lam = u[:m]
    nu = u[m:m + p] - u[m + p:m + 2 * p]
    elastic = jnp.sum(jnp.maximum(sol.y[n:], 0.0))
    return d, lam, nu, elastic


def _qp_step(lin: _Lin, B, dlo, dhi, weight, iterations):
    """Subproblem (module docstring): the QP on the linearised constraints by the dual
    active-set method, or, when that reports the linearisation inconsistent (or fails), the
    elastic QP by interior point. Returns d, λ, ν and the elastic slack total."""
    n, m, p = lin.dF.shape[0], lin.G.shape[0], lin.H.shape[0]
    eye = jnp.eye(n, dtype=lin.dF.dtype)
    A = jnp.concatenate([lin.JH, lin.JG, eye, -eye], axis=0)
    b = jnp.concatenate([-lin.H, -lin.G, dhi, -dlo])
    sol = solve_qp_active_set(B, lin.dF, A, b, n_eq=p)

    def exact(_):
        return sol.y, sol.u[p:p + m], sol.u[:p], jnp.zeros((), lin.dF.dtype)

    def elastic(_):
        return _elastic_qp_step(lin, B, dlo, dhi, weight, iterations)

    return lax.cond(sol.ok, exact, elastic, None)


class _Context(NamedTuple):
    """Static settings and closures of one SQP solve (never traced)."""

    problem: Problem
    theta: object
    options: SolverOptions
    zlo: jax.Array
    zhi: jax.Array
    m: int
    p: int
    dtype: object


class _Step(NamedTuple):
    """A subproblem's answer at an iterate: the step and its multipliers, the KKT test there,
    the merit penalty, value and slope, and what the line search's correction needs."""

    d: jax.Array
    lam: jax.Array
    nu: jax.Array
    kkt: KKTResidual
    stop: jax.Array
    pi: jax.Array
    phi0: jax.Array
    slope: jax.Array
    z_full: jax.Array  # the full step's trial point
    J_act: jax.Array
    row_on: jax.Array


def _linearize(ctx: _Context, z):
    """(Jacobian with respect to z, values) of the stacked (f, g, h) at x = x(z), by forward mode."""
    def with_value(zz):
        v = stack_fgh(ctx.problem, ctx.theta, ctx.problem.from_scaled(zz))
        return v, v
    return jax.jacfwd(with_value, has_aux=True)(z)


def _merit(ctx: _Context, raw, scales: Scales, pi):
    """ℓ1 merit F + π (Σ max(G, 0) + Σ |H|) and its infeasibility term at values ``raw``."""
    m = ctx.m
    F = scales.f * raw[0]
    G = scales.g * raw[1:1 + m]
    H = scales.h * raw[1 + m:]
    infeas = jnp.sum(jnp.maximum(G, 0.0)) + jnp.sum(jnp.abs(H))
    return F + pi * infeas, infeas


def _grad_lag(lin: _Lin, lam, nu):
    return lin.dF + lin.JG.T @ lam + lin.JH.T @ nu


def _step_length(ctx: _Context, j):
    """α of line-search trial j: 1 for the full step (j = 0) and the corrected step (j = 1),
    then halved per trial."""
    return jnp.where(j <= 1, 1.0, 0.5 ** jnp.maximum(j - 1, 0).astype(ctx.dtype))


def _trial_point(ctx: _Context, s_z, d, j, raw_full, J_act, row_on, scales: Scales):
    """Trial j of the line search from s_z along d: the full step, then the full step with
    the second-order correction, then the step halved per trial."""
    m, p = ctx.m, ctx.p

    def correction():
        c_full = jnp.concatenate([scales.g * raw_full[1:1 + m], scales.h * raw_full[1 + m:]])
        c_full = jnp.where(row_on & jnp.isfinite(c_full), c_full, 0.0)
        gram = J_act @ J_act.T + jnp.diag(jnp.where(row_on, 0.0, 1.0))
        gram = gram + 1e-12 * (1.0 + jnp.max(jnp.abs(gram), initial=0.0)) * jnp.eye(m + p, dtype=ctx.dtype)
        corr = -J_act.T @ jnp.linalg.solve(gram, c_full)
        return d + jnp.where(jnp.all(jnp.isfinite(corr)), corr, 0.0)

    step = lax.cond(j == 1, correction, lambda: _step_length(ctx, j) * d)
    return snap_to_bounds(jnp.clip(s_z + step, ctx.zlo, ctx.zhi), ctx.zlo, ctx.zhi)


def _subproblem(ctx: _Context, z, lin: _Lin, raw, B, scales: Scales, pi_old, lam_old, nu_old, k) -> _Step:
    """QP at z: step, multipliers, KKT test, penalty, merit slope and the first trial."""
    options, zlo, zhi, p = ctx.options, ctx.zlo, ctx.zhi, ctx.p
    dlo = jnp.where(jnp.isfinite(zlo), zlo - z, -_FREE_STEP)
    dhi = jnp.where(jnp.isfinite(zhi), zhi - z, _FREE_STEP)
    d, lam_q, nu_q, elastic = _qp_step(lin, B, dlo, dhi, options.elastic_weight, options.qp_iterations)
    d = jnp.where(jnp.isfinite(d), d, 0.0)
    lam_q = jnp.where(jnp.isfinite(lam_q), lam_q, lam_old)
    nu_q = jnp.where(jnp.isfinite(nu_q), nu_q, nu_old)
    # KKT test at z with the subproblem's multipliers, and the step it asks for negligible:
    # the scaled gradient can be small long before the iterate is accurate when f's scale
    # was set far from the optimum
    kkt = kkt_residual(z, _grad_lag(lin, lam_q, nu_q), lin.G, lin.H, lam_q, zlo, zhi)
    settled = ((inf_norm(d) <= options.tol * (1.0 + inf_norm(z)))
               | (jnp.dot(d, B @ d) <= options.tol ** 2 * (1.0 + jnp.abs(lin.F))))
    stop = (is_converged(kkt, options) & settled) | (k >= options.max_sqp)
    need = 1.5 * jnp.maximum(inf_norm(lam_q), inf_norm(nu_q)) + 1e-8
    pi = jnp.maximum(need, 0.5 * (pi_old + need))
    phi0, infeas0 = _merit(ctx, raw, scales, pi)
    slope = jnp.dot(lin.dF, d) - pi * jnp.maximum(infeas0 - elastic, 0.0)
    slope = jnp.minimum(slope, -0.5 * jnp.dot(d, B @ d))
    active_g = (lam_q > 1e-10) | (lin.G + lin.JG @ d >= -1e-9)
    z_full = snap_to_bounds(jnp.clip(z + d, zlo, zhi), zlo, zhi)
    free = (z_full > zlo) & (z_full < zhi)  # variables the full step leaves off the bounds
    J_act = jnp.concatenate([lin.JG * active_g[:, None], lin.JH], axis=0) * free[None, :]
    row_on = jnp.concatenate([active_g, jnp.ones((p,), bool)])
    return _Step(d, lam_q, nu_q, kkt, stop, pi, phi0, slope, z_full, J_act, row_on)


def _initial_state(ctx: _Context, z0) -> _State:
    m, p, dtype = ctx.m, ctx.p, ctx.dtype
    n = z0.shape[0]
    empty = _Lin(jnp.zeros((), dtype), jnp.zeros((n,), dtype), jnp.zeros((m,), dtype), jnp.zeros((m, n), dtype),
                 jnp.zeros((p,), dtype), jnp.zeros((p, n), dtype))
    inf = jnp.asarray(jnp.inf, dtype)
    return _State(
        k=jnp.asarray(0), z=z0, lin=empty, raw=jnp.zeros((1 + m + p,), dtype),
        lam=jnp.zeros((m,), dtype), nu=jnp.zeros((p,), dtype), B=jnp.eye(n, dtype=dtype),
        pi=jnp.asarray(0.0, dtype), scales=unit_scales(m, p, dtype),
        kkt=KKTResidual(inf, inf, inf), d=jnp.zeros((n,), dtype), phi0=inf, slope=jnp.zeros((), dtype),
        j=jnp.asarray(0), z_trial=z0, raw_full=jnp.zeros((1 + m + p,), dtype),
        J_act=jnp.zeros((m + p, n), dtype), row_on=jnp.zeros((m + p,), bool),
        done=jnp.asarray(False), evaluations=jnp.asarray(0),
    )


def _trip(ctx: _Context, s: _State) -> _State:
    """One trip of the loop: linearise at the trial point, test it by the merit, then either
    solve the next subproblem from the accepted point or move to the next trial."""
    options, m, dtype = ctx.options, ctx.m, ctx.dtype
    n = s.z.shape[0]
    # the one evaluation of the trip: the linearisation at the trial point (z₀ on the first
    # trip); an accepted trial becomes the iterate with its linearisation already in hand
    jac, raw_t = _linearize(ctx, s.z_trial)
    finite_t = jnp.all(jnp.isfinite(jac)) & jnp.all(jnp.isfinite(raw_t))
    start = s.evaluations == 0
    scales = pick(start, scales_from(jac, raw_t, m, options), s.scales)
    lin_t = _scaled_lin(raw_t, jac, scales, m)

    # Armijo test of the ℓ1 merit (sufficient decrease 1e-4·α·φ′ plus rounding)
    phi_t, _ = _merit(ctx, raw_t, scales, s.pi)
    alpha = _step_length(ctx, s.j)
    noise = 1e-14 * (1.0 + jnp.abs(s.phi0))
    decrease = jnp.isfinite(phi_t) & (phi_t <= s.phi0 + 1e-4 * alpha * s.slope + noise)
    tiny = inf_norm(s.d) <= 1e-14 * (1.0 + inf_norm(s.z))
    accepted = start | (finite_t & (decrease | tiny))
    exhausted = ~accepted & (s.j >= options.max_line_search)
    raw_full = jnp.where(s.j == 0, raw_t, s.raw_full)

    # BFGS update with the multipliers of the last subproblem; no decrease found: B = I
    y = _grad_lag(lin_t, s.lam, s.nu) - _grad_lag(s.lin, s.lam, s.nu)
    B = jnp.where(accepted & ~start, _damped_bfgs(s.B, s.z_trial - s.z, y, s.k == 1), s.B)
    B = jnp.where(exhausted, jnp.eye(n, dtype=dtype), B)
    z = jnp.where(accepted, s.z_trial, s.z)
    lin = pick(accepted, lin_t, s.lin)
    raw = jnp.where(accepted, raw_t, s.raw)
    # a start where the model is not finite ends the solve there
    bad_start = start & ~finite_t

    def new_iteration(_):
        q = _subproblem(ctx, z, lin, raw, B, scales, s.pi, s.lam, s.nu, s.k)
        return (jnp.where(q.stop, s.k, s.k + 1), q.d, q.lam, q.nu, q.kkt, q.stop, q.pi, q.phi0, q.slope,
                jnp.asarray(0), q.z_full, q.J_act, q.row_on)

    def next_trial(_):
        z_next = _trial_point(ctx, s.z, s.d, s.j + 1, raw_full, s.J_act, s.row_on, scales)
        return (s.k, s.d, s.lam, s.nu, s.kkt, jnp.asarray(False), s.pi, s.phi0, s.slope, s.j + 1, z_next,
                s.J_act, s.row_on)

    (k, d, lam, nu, kkt, stop, pi, phi0, slope, j, z_trial, J_act, row_on) = lax.cond(
        (accepted | exhausted) & ~bad_start, new_iteration, next_trial, None)
    return _State(k=k, z=z, lin=lin, raw=raw, lam=lam, nu=nu, B=B, pi=pi, scales=scales, kkt=kkt, d=d,
                  phi0=phi0, slope=slope, j=j, z_trial=z_trial, raw_full=raw_full, J_act=J_act,
                  row_on=row_on, done=stop | bad_start, evaluations=s.evaluations + 1)


def _answer(ctx: _Context, state: _State) -> Result:
    """The :class:`Result` at the last iterate (physical values, multipliers and bound
    multipliers, the KKT test, and the conflict read from the ℓ1 infeasibility gradient)."""
    problem, options, m = ctx.problem, ctx.options, ctx.m
    z, lin, raw, scales = state.z, state.lin, state.raw, state.scales
    x = physical_point(problem, z, ctx.zlo, ctx.zhi)
    f, g, h = raw[0], raw[1:1 + m], raw[1 + m:]
    lam_p = state.lam * scales.g / scales.f
    nu_p = state.nu * scales.h / scales.f
    dxdz = dx_dz(problem, x)
    mu_lo, mu_hi = bound_multipliers(problem, x, _grad_lag(lin, state.lam, state.nu) / (scales.f * dxdz))
    kkt = state.kkt
    feasible = kkt.feasibility <= options.feas_tol
    converged = is_converged(kkt, options)
    grad_phi = lin.JG.T @ jnp.maximum(lin.G, 0.0) + lin.JH.T @ lin.H
    conflict = conflict_masks(feasible, lin.G, lin.H, z, ctx.zlo, ctx.zhi, grad_phi, options)
    return Result(
        x=x, f=f, g=g, h=h, lam=lam_p, nu=nu_p, mu_lower=mu_lo, mu_upper=mu_hi, converged=converged,
        feasible=feasible, kkt=kkt, iterations=state.k, inner_iterations=state.evaluations, penalty=state.pi,
        polished=jnp.asarray(False), conflict=conflict, scales=scales,
    )


def solve_sqp(problem: Problem, x0, theta=None, options: SolverOptions = SolverOptions()) -> Result:
    """Minimise ``problem`` from ``x0`` by SQP (module docstring); same :class:`Result` as
    :func:`diffsense.optimize.solve`. Pure and fixed-shape: jit it, vmap it over x0 and θ.
    ``options.max_sqp`` caps the iterations, ``qp_iterations`` and ``elastic_weight`` set the
    subproblem, ``max_line_search`` the backtracking trials; ``tol``, ``feas_tol``, ``f_scale``
    and ``constraint_scaling`` mean what they mean for the augmented Lagrangian."""
    dtype, zlo, zhi, z0, m, p = scaled_start(problem, x0, theta)
    ctx = _Context(problem, theta, options, zlo, zhi, m, p, dtype)
    state = lax.while_loop(lambda s: ~s.done, lambda s: _trip(ctx, s), _initial_state(ctx, z0))
    return _answer(ctx, state)


__all__ = ["solve_sqp"]
