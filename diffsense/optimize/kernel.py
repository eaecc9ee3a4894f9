"""What every solver method shares: the scaled problem, its linearisation and function scales.

Scaling of the functions (``f_scale="auto"``): s_f = 1/clip(max(‖∇_z f(z₀)‖∞, 0.01|f(z₀)|), 1e-8,
1e8) (s_f = 1 when both vanish: a start at a stationary point of f with f = 0 tells nothing of
its scale), and per constraint s_gᵢ = 1/clip(max(‖∇_z gᵢ(z₀)‖∞, 0.01|gᵢ(z₀)|), 1e-8, 1e8)
(likewise h), so a scaled constraint value is roughly a distance in scaled variables. The
solvers' ``tol`` and ``feas_tol`` apply to these scaled quantities F = s_f f, G = s_g ⊙ g,
H = s_h ⊙ h; the physical g, h are returned as well. The scales are held constant (no
derivative flows through them).

Each place where a solver evaluates the problem functions is a copy of the model in the
compiled program (on design models each copy costs seconds of compilation), so the solvers
evaluate through one function, :func:`linearize_at`: values and the n-column Jacobian of the
stacked (f, g, h) by forward mode.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
from jax import lax

from diffsense.optimize.bounds import bound_activity, physical_point
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem, check_start
from diffsense.optimize.result import Conflict, Scales


class ScaledModel(NamedTuple):
    """Scaled objective/constraints of one problem instance (closures over θ and scales)."""

    problem: Problem
    theta: object
    scales: Scales
    zlo: jax.Array
    zhi: jax.Array

    def FGH(self, z):
        """(F, G, H) at z in one evaluation of the problem functions."""
        x = self.problem.from_scaled(z)
        f, g, h = self.problem.fgh(x, self.theta)
        return self.scales.f * f, self.scales.g * g, self.scales.h * h

    def lagrangian(self, z, lam, nu):
        F, G, H = self.FGH(z)
        return F + jnp.dot(lam, G) + jnp.dot(nu, H)

    def augmented(self, z, lam, nu, rho, weight_f=1.0):
        """PHR augmented Lagrangian; with weight_f = 0, λ = ν = 0, ρ = 1 it is φ(z)."""
        F, G, H = self.FGH(z)
        eq = jnp.sum(nu * H + 0.5 * rho * H**2)
        ineq = jnp.sum(jnp.maximum(0.0, lam + rho * G) ** 2 - lam**2) / (2.0 * rho)
        return weight_f * F + eq + ineq


def make_model(problem: Problem, theta, scales: Scales) -> ScaledModel:
    zlo, zhi = problem.scaled_bounds()
    return ScaledModel(problem, theta, scales, zlo, zhi)


def inf_norm(v):
    """‖v‖∞, 0 for an empty vector."""
    return jnp.max(jnp.abs(v), initial=0.0)


def projected_gradient_norm(z, grad, zlo, zhi):
    """‖clip(z − ∇, zlo, zhi) − z‖∞ — zero exactly at a box-constrained stationary point."""
    return inf_norm(jnp.clip(z - grad, zlo, zhi) - z)


def scaled_start(problem: Problem, x0, theta):
    """(dtype, zlo, zhi, z0, m, p): the checked start projected into the box, in scaled
    coordinates, with the scaled bounds and the numbers of inequalities and equalities."""
    check_start(problem, x0)
    dtype = jnp.result_type(float)
    x0 = problem.clip(jnp.asarray(x0, dtype=dtype))
    zlo, zhi = problem.scaled_bounds()
    z0 = jnp.clip(problem.to_scaled(x0), zlo, zhi)
    m, p = problem.constraint_sizes(theta)
    return dtype, zlo, zhi, z0, m, p


def unit_scales(m: int, p: int, dtype) -> Scales:
    """Scales of 1 (the placeholder before the first linearisation sets them)."""
    return Scales(jnp.ones((), dtype), jnp.ones((m,), dtype), jnp.ones((p,), dtype))


def scales_from(jac, val, m: int, options: SolverOptions) -> Scales:
    """Function scales (module docstring) from the unscaled Jacobian ``jac`` (rows f, g, h) of
    the stacked (f, g, h) with respect to z, and its values ``val``, at the start."""
    dtype = val.dtype
    if options.f_scale == "auto":
        den = jnp.maximum(inf_norm(jnp.where(jnp.isfinite(jac[0]), jac[0], 0.0)), 0.01 * jnp.abs(val[0]))
        den = jnp.where(jnp.isfinite(den), den, 0.0)
        # a start where f and its gradient vanish says nothing about f's scale: leave f unscaled
        sf = jnp.where(den > 0.0, 1.0 / jnp.clip(den, 1e-8, 1e8), 1.0)
    else:
        sf = jnp.asarray(options.f_scale, dtype)
    if options.constraint_scaling and val.shape[0] > 1:
        den = jnp.maximum(jnp.max(jnp.abs(jac[1:]), axis=1), 0.01 * jnp.abs(val[1:]))
        den = jnp.where(jnp.isfinite(den), den, 1.0)
        sc = 1.0 / jnp.clip(den, 1e-8, 1e8)
    else:
        sc = jnp.ones((val.shape[0] - 1,), dtype)
    return jax.tree_util.tree_map(lax.stop_gradient, Scales(sf, sc[:m], sc[m:]))


def stack_fgh(problem: Problem, theta, x):
    """The stacked vector (f, g, h) at x."""
    f, g, h = problem.fgh(x, theta)
    return jnp.concatenate([f[None], g, h])


def linearize_at(problem: Problem, theta, z, zlo, zhi):
    """(x, values, Jacobian) of the stacked (f, g, h) at x = x(z) inside [lower, upper], the
    Jacobian with respect to x by forward mode (n tangents: the cheap direction for design
    problems, a handful of variables and a long chain); columns times dx/dz give ∂/∂z."""
    x = physical_point(problem, z, zlo, zhi)

    def fgh(xx):
        v = stack_fgh(problem, theta, xx)
        return v, v

    jac, val = jax.jacfwd(fgh, has_aux=True)(x)
    return x, val, jac


def dx_dz(problem: Problem, x):
    """dx/dz of the scaling map at x: x for log-scaled variables, the scale otherwise."""
    return jnp.where(problem.log_scale, x, problem.scale)


def conflict_masks(feasible, G, H, z, zlo, zhi, grad_phi, options: SolverOptions) -> Conflict:
    """:class:`Conflict` of an answer: violated scaled constraints G, H and the bounds at which
    the infeasibility gradient ``grad_phi`` (any positive scaling of ∇_z φ) pushes out of the box."""
    blo, bhi = bound_activity(zlo, zhi, z, grad_phi)
    small = 1e-3 * options.feas_tol
    return Conflict(
        inequality=(~feasible) & (G > options.feas_tol),
        equality=(~feasible) & (jnp.abs(H) > options.feas_tol),
        lower=(~feasible) & blo & (grad_phi > small),
        upper=(~feasible) & bhi & (grad_phi < -small),
    )


def pick(c, a, b):
    """Pytree select: ``a`` where ``c`` else ``b`` leaf by leaf."""
    return jax.tree_util.tree_map(lambda u, v: jnp.where(c, u, v), a, b)


__all__ = ["ScaledModel", "make_model", "inf_norm", "projected_gradient_norm", "scaled_start", "unit_scales",
           "scales_from", "stack_fgh", "linearize_at", "dx_dz", "conflict_masks", "pick"]
