"""Post-optimal sensitivity: derivatives of the optimum with respect to the parameters θ.

At a KKT point (x*, λ*, ν*) with active inequality set A and variables B held at a bound,
the solution satisfies the square system

    R(s, θ) = [ ∇ₓL(x, λ, ν, θ) on free variables;  x_B − bound_B;
                g_A(x, θ);  λ_inactive;  h(x, θ) ] = 0,        s = (x, λ, ν),

with L = f + λᵀg + νᵀh. Under the standard regularity assumptions — linear independence of
the active constraint gradients, strict complementarity (active multipliers > 0, so the
active set does not change under a small perturbation) and second-order sufficiency — the
Jacobian ∂R/∂s is nonsingular and the implicit function theorem gives

    ds*/dθ = −(∂R/∂s)⁻¹ ∂R/∂θ

(the basic sensitivity theorem: A. V. Fiacco, *Introduction to Sensitivity and Stability
Analysis in Nonlinear Programming*, Academic Press 1983, §3.2; Nocedal & Wright,
*Numerical Optimization*, 2nd ed., §12.8 for the multipliers as sensitivities)

and the envelope theorem gives the derivative of the optimal value without dx*/dθ:

    df*/dθ = ∂L/∂θ (x*, λ*, ν*, θ).

So multipliers are shadow prices: for a requirement written g(x, θ) = b(θ) − c(x) ≤ 0,
df*/dθ = λ·db/dθ — e.g. with θ the required SNR in dB, df*/dθ is what one more dB of
required SNR costs in units of f. Bound multipliers do not enter because the bounds do not
depend on θ (put θ-dependent limits into g).

The system is solved in the solver's scaled coordinates (the scales are held constant), and
the results are mapped back to physical units. A derivative across a change of active set
does not exist; where a constraint is weakly active (g = 0, λ = 0) the value returned is the
one-sided derivative with that constraint kept active.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
from jax.flatten_util import ravel_pytree

from diffsense.errors import DomainError
from diffsense.optimize.constrained import Result, SolverOptions, kkt_equations, make_model, solve
from diffsense.optimize.problem import Problem


class Sensitivity(NamedTuple):
    """Derivatives of the optimum with respect to θ.

    ``dx``: pytree shaped like θ whose leaves have shape (n, *leaf.shape): ∂x*ᵢ/∂θ.
    ``dlam``: (m, *leaf.shape) per leaf: ∂λ*/∂θ.  ``dnu``: (p, *leaf.shape): ∂ν*/∂θ.
    ``df``: pytree like θ: df*/dθ by the envelope theorem (∂L/∂θ at the optimum)."""

    dx: object
    dlam: object
    dnu: object
    df: object


class Solution(NamedTuple):
    """Differentiable part of a solve: x*, f*, λ*, ν* (physical units, see ``Result``)."""

    x: jax.Array
    f: jax.Array
    lam: jax.Array
    nu: jax.Array


def _scaled_point(problem: Problem, result: Result):
    sc = result.scales
    z = problem.to_scaled(result.x)
    lam = result.lam * sc.f / jnp.where(sc.g != 0, sc.g, 1.0)
    nu = result.nu * sc.f / jnp.where(sc.h != 0, sc.h, 1.0)
    return z, lam, nu


def _active_masks(problem: Problem, result: Result, options: SolverOptions):
    G = result.scales.g * result.g
    active = (G > -options.active_tol) | (result.lam > 0.0)
    at_lo = result.x <= problem.lower
    at_hi = (result.x >= problem.upper) & ~at_lo
    return active, at_lo, at_hi


def _lagrangian_phys(problem: Problem, x, lam, nu, theta):
    return problem.f(x, theta) + jnp.dot(lam, problem.g(x, theta)) + jnp.dot(nu, problem.h(x, theta))


def _tangent_map(problem: Problem, result: Result, theta, options: SolverOptions):
    """Returns (residual-of-θ function, J_s, unpack) for the active-set KKT system."""
    active, at_lo, at_hi = _active_masks(problem, result, options)
    z, lam, nu = _scaled_point(problem, result)
    n, m = z.shape[0], lam.shape[0]
    s0 = jnp.concatenate([z, lam, nu])
    scales = jax.tree_util.tree_map(jax.lax.stop_gradient, result.scales)

    def residual(s, th):
        model = make_model(problem, th, scales)
        return kkt_equations(model, active, at_lo, at_hi, s[:n], s[n:n + m], s[n + m:])

    J = jax.jacfwd(residual, argnums=0)(s0, theta)
    dxdz = jnp.where(problem.log_scale, result.x, problem.scale)
    fixed = at_lo | at_hi

    def unpack(ds):
        dz = jnp.where(fixed, 0.0, ds[:n])
        dx = dxdz * dz
        dlam = ds[n:n + m] * scales.g / scales.f
        dnu = ds[n + m:] * scales.h / scales.f
        return dx, dlam, dnu

    return residual, s0, J, unpack


def shadow_prices(problem: Problem, result: Result, theta):
    """df*/dθ by the envelope theorem: ∂/∂θ [f + λᵀg + νᵀh] at the optimum (pytree like θ).

    Units: units of f per unit of each θ leaf. Valid at a KKT point (``result.converged``)."""
    if theta is None:
        raise DomainError("shadow_prices: the problem has no parameters (theta is None)")
    return jax.grad(lambda th: _lagrangian_phys(problem, result.x, result.lam, result.nu, th))(theta)


def kkt_sensitivity(problem: Problem, result: Result, theta,
                    options: SolverOptions = SolverOptions()) -> Sensitivity:
    """dx*/dθ, dλ*/dθ, dν*/dθ by implicit differentiation of the active-set KKT system, and
    df*/dθ by the envelope theorem (module docstring). ``result`` must come from
    ``solve(problem, ..., theta, options)`` (same θ); jit/vmap-able. Where the KKT matrix is
    singular (degenerate active set) the entries are not finite."""
    if theta is None:
        raise DomainError("kkt_sensitivity: the problem has no parameters (theta is None)")
    residual, s0, J, unpack = _tangent_map(problem, result, theta, options)
    flat_theta, unravel = ravel_pytree(theta)
    R_theta = jax.jacfwd(lambda ft: residual(s0, unravel(ft)))(flat_theta)  # (N, q)
    ds = -jnp.linalg.solve(J, R_theta)  # (N, q)
    dx, dlam, dnu = jax.vmap(unpack, in_axes=1, out_axes=1)(ds)

    def to_tree(mat):
        # mat: (k, q) -> pytree like θ with leaves (k, *leaf.shape)
        cols = jax.vmap(unravel)(mat)  # row i -> pytree; stacked leaves (k, *leaf.shape)
        return cols

    return Sensitivity(dx=to_tree(dx), dlam=to_tree(dlam), dnu=to_tree(dnu),
                       df=shadow_prices(problem, result, theta))


def differentiable_solver(problem: Problem, options: SolverOptions = SolverOptions()):
    """``fn(x0, theta) -> Solution`` whose derivatives with respect to θ (forward or reverse
    mode, any order-1 transformation: jvp, grad, jacfwd, jacrev, under jit/vmap) are the
    implicit KKT derivatives above; x0 carries no derivative. f*'s derivative uses the
    envelope theorem. The solve is never differentiated through its iterations."""

    @jax.custom_jvp
    def solution(x0, theta):
        r = solve(problem, x0, theta, options)
        return Solution(r.x, r.f, r.lam, r.nu)

    @solution.defjvp
    def solution_jvp(primals, tangents):
        x0, theta = primals
        _, dtheta = tangents
        r = solve(problem, x0, theta, options)
        residual, s0, J, unpack = _tangent_map(problem, r, theta, options)
        _, r_dot = jax.jvp(lambda th: residual(s0, th), (theta,), (dtheta,))
        ds = -jnp.linalg.solve(J, r_dot)
        dx, dlam, dnu = unpack(ds)
        _, df = jax.jvp(lambda th: _lagrangian_phys(problem, r.x, r.lam, r.nu, th), (theta,), (dtheta,))
        return Solution(r.x, r.f, r.lam, r.nu), Solution(dx, df, dlam, dnu)

    return solution


__all__ = ["Sensitivity", "Solution", "kkt_sensitivity", "shadow_prices", "differentiable_solver"]
