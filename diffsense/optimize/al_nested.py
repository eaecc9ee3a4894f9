"""The augmented-Lagrangian loop with a nested inner solver (``inner="bfgs"`` or ``"lbfgsb"``).

Each trip of the outer ``lax.while_loop`` runs a whole inner solve of the subproblem of
:mod:`diffsense.optimize.al` — optimistix's BFGS over the box reparameterisation
(:func:`diffsense.optimize.bounds.box_reparameterisation`), or jaxopt's L-BFGS-B on the box
itself (Byrd, Lu, Nocedal & Zhu, SIAM J. Sci. Comput. 16 (1995) 1190) — then linearises the
problem once at the inner solution for the outer update. Two evaluation sites (the inner
solver's value and gradient of L_ρ, and the linearisation): the default fused loop
(:mod:`diffsense.optimize.al_fused`) has one.
"""

from __future__ import annotations

import warnings

import jax.numpy as jnp
from jax import lax

from diffsense.optimize.al import (
    SETUP,
    ALContext,
    ALState,
    close_subproblem,
    run_al,
    still_running,
    subproblem_settings,
)
from diffsense.optimize.bounds import box_reparameterisation, snap_to_bounds
from diffsense.optimize.kernel import linearize_at, make_model
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.result import Result


def _inner_lbfgsb(fun, z, zlo, zhi, tol, options: SolverOptions):
    with warnings.catch_warnings():  # jaxopt announces on import that it is in maintenance mode
        warnings.simplefilter("ignore", DeprecationWarning)
        from jaxopt import LBFGSB

    solver = LBFGSB(
        fun=fun,
        tol=tol,
        maxiter=options.max_inner,
        history_size=options.history_size,
        implicit_diff=False,
        unroll=False,
        jit=True,
        stop_if_linesearch_fails=True,
    )
    out = solver.run(z, (zlo, zhi))
    return out.params, out.state.iter_num


def _inner_bfgs(fun, z, zlo, zhi, tol, options: SolverOptions):
    forward, inverse = box_reparameterisation(zlo, zhi)
    # optimistix stops on small steps and small f changes (Cauchy test), not on the gradient;
    # a 10x tighter test brings the projected gradient below ``tol`` on well-scaled problems
    import optimistix as optx  # the nested BFGS only (imported on use: it is not the default)

    solver = optx.BFGS(rtol=0.1 * tol, atol=0.1 * tol)
    sol = optx.minimise(lambda y, _: fun(forward(y)), solver, inverse(z), None,
                        max_steps=options.max_inner, throw=False)
    znew = jnp.clip(forward(sol.value), zlo, zhi)
    return znew, sol.stats["num_steps"]


_INNER = {"lbfgsb": _inner_lbfgsb, "bfgs": _inner_bfgs}


def nested_loop(ctx: ALContext, state: ALState) -> ALState:
    """Run the solve from the setup state to its end, one inner solve per trip."""
    problem, theta, zlo, zhi = ctx.problem, ctx.theta, ctx.zlo, ctx.zhi
    inner = _INNER[ctx.options.inner]

    def body(s: ALState):
        lam_e, nu_e, rho_e, w_f, eps_e = subproblem_settings(ctx, s)
        setup = s.phase == SETUP
        model = make_model(problem, theta, s.scales)
        fun = lambda z: model.augmented(z, lam_e, nu_e, rho_e, w_f)  # noqa: E731
        # the setup trip only linearises at the start (its scales are not known before); under
        # vmap the skipped inner solve still runs, with a tolerance that stops it after one step
        z_new, its = lax.cond(
            setup, lambda: (s.z, jnp.asarray(0)),
            lambda: inner(fun, s.z, zlo, zhi, jnp.where(setup, 1e30, eps_e), ctx.options))
        # the problem functions are evaluated once per trip, here (each evaluation site is a
        # copy of the model in the compiled program): value and Jacobian at the inner solution
        # (put exactly on the bounds it is within rounding of), or at the previous iterate when
        # the inner solution is not finite
        finite_z = jnp.all(jnp.isfinite(z_new))
        z_new = snap_to_bounds(jnp.where(finite_z, z_new, s.z), zlo, zhi)
        x_new, val, jac = linearize_at(problem, theta, z_new, zlo, zhi)
        return close_subproblem(ctx, s, z_new, x_new, val, jac, its, finite_z, eps_e)

    return lax.while_loop(lambda s: still_running(ctx, s), body, state)


def solve_al_nested(problem: Problem, x0, theta, options: SolverOptions) -> Result:
    """The augmented-Lagrangian solve with the nested inner solver ``options.inner``."""
    return run_al(problem, x0, theta, options, nested_loop)


__all__ = ["nested_loop", "solve_al_nested"]
