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

Linearising R at the solution for a perturbation with ∂(∇ₓL)/∂θ = r and ∂c_A/∂θ = c (c the
active constraints g_A and h) gives the linear algebra every KKT sensitivity needs,
:func:`active_set_derivative`:

    [ W_FF   A_AFᵀ ] [ dy_F ]      [ r_F ]
    [ A_AF   0     ] [ dμ_A ]  = − [ c_A ],      W = ∇²L,  A = ∂c/∂x,

F the free variables and A the active constraints (dy = 0 off F, dμ = 0 off A). When as many
constraints are active as variables are free and A_AF is nonsingular (a vertex), dy_F =
−A_AF⁻¹ c_A needs no W. The design report (:mod:`diffsense.report.postoptimal`) calls the same
function with its own W and A, and :func:`stationarity_multipliers` for multipliers
recomputed from ∇F + Aᵀμ = 0.

:func:`kkt_sensitivity` solves the system in the solver's scaled coordinates (the scales are
held constant), and maps the results back to physical units. A derivative across a change of active set
does not exist; where a constraint is weakly active (g = 0, λ = 0) the value returned is the
one-sided derivative with that constraint kept active.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
from jax.flatten_util import ravel_pytree

from diffsense.errors import DomainError
from diffsense.optimize.entry import solve
from diffsense.optimize.kernel import make_model
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.problem import Problem
from diffsense.optimize.result import Result


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


def _xp(*arrays):
    """NumPy when every array given is a host array (a report's linear algebra: no eager JAX
    dispatch, which would compile a small program per operation), else jax.numpy (traced)."""
    return np if all(a is None or isinstance(a, (np.ndarray, np.generic, float, int)) for a in arrays) else jnp


def _masks(n: int, k: int, free, active, xp=jnp):
    free = xp.ones((n,), bool) if free is None else xp.asarray(free, bool)
    active = xp.ones((k,), bool) if active is None else xp.asarray(active, bool)
    return free, active


def kkt_matrix(hessian, jacobian, free=None, active=None):
    """The matrix of :func:`active_set_derivative`'s system, (n + k) × (n + k): W (n × n) on the
    free variables and the constraint Jacobian A (k × n) on the active rows and free columns,
    identity rows and columns for the other variables and constraints (``free``, ``active``:
    boolean masks, default all). Nonsingular exactly when the reduced system is."""
    xp = _xp(hessian, jacobian, free, active)
    W, A = xp.asarray(hessian), xp.asarray(jacobian)
    n, k = W.shape[0], A.shape[0]
    free, active = _masks(n, k, free, active, xp)
    W_m = xp.where(free[:, None] & free[None, :], W, 0.0) + xp.diag(xp.where(free, 0.0, 1.0))
    A_m = xp.where(active[:, None] & free[None, :], A, 0.0)
    top = xp.concatenate([W_m, A_m.T], axis=1)
    bottom = xp.concatenate([A_m, xp.diag(xp.where(active, 0.0, 1.0))], axis=1)
    return xp.concatenate([top, bottom], axis=0)


def active_set_derivative(hessian, jacobian, d_stationarity, d_constraints, *, free=None, active=None):
    """(dy, dμ): derivative of a KKT point and its multipliers along a perturbation (module
    docstring), by the linearised active-set KKT system.

    ``hessian``: W = ∇²L (n, n), or None at a vertex (as many active constraints as free
    variables, no masks: dy = −A⁻¹ c, and dμ is None). ``jacobian``: A = ∂c/∂y of every
    constraint (k, n). ``d_stationarity``: r = ∂(∇L)/∂θ, shape (n, ...); ``d_constraints``:
    c = ∂c/∂θ, shape (k, ...) (trailing axes: the perturbation directions). ``free``,
    ``active``: masks of the free variables and active constraints (default all); dy is 0 off
    the free variables and dμ 0 off the active constraints. Fixed shape: jit/vmap-able. A
    singular system gives non-finite entries.

    Example, min ½(y₀² + y₁²) s.t. y₀ + y₁ − b = 0, whose solution is y = (b/2, b/2) with
    μ = −b/2 (stationarity y + μ(1, 1) = 0), so dy/db = (½, ½) and dμ/db = −½:

    >>> dy, dmu = active_set_derivative(jnp.eye(2), jnp.array([[1.0, 1.0]]), jnp.zeros(2), jnp.array([-1.0]))
    >>> [float(v) for v in dy], [float(v) for v in dmu]
    ([0.5, 0.5], [-0.5])
    """
    xp = _xp(hessian, jacobian, d_stationarity, d_constraints, free, active)
    A = xp.asarray(jacobian)
    r, c = xp.asarray(d_stationarity), xp.asarray(d_constraints)
    k, n = A.shape
    trailing = r.shape[1:]
    q = math.prod(trailing)
    r2, c2 = r.reshape((n, q)), c.reshape((k, q))
    if hessian is None:
        if free is not None or active is not None or n != k:
            raise DomainError("active_set_derivative: without a Hessian the active constraints must be as many as "
                              f"the variables (a vertex), unmasked; got {k} constraints, {n} variables")
        return -xp.linalg.solve(A, c2).reshape((n,) + trailing), None
    free, active = _masks(n, k, free, active, xp)
    rhs = xp.concatenate([xp.where(free[:, None], r2, 0.0), xp.where(active[:, None], c2, 0.0)], axis=0)
    sol = -xp.linalg.solve(kkt_matrix(hessian, A, free, active), rhs)
    return sol[:n].reshape((n,) + trailing), sol[n:].reshape((k,) + trailing)


def stationarity_multipliers(gradient, jacobian):
    """(μ, relative residual): the least-squares multipliers of ∇F + Aᵀμ = 0 for the objective
    gradient ``gradient`` (n,) and the active constraints' Jacobian ``jacobian`` (k, n), and
    max|∇F + Aᵀμ| / max|∇F| (0 at a KKT point).

    Example, ∇F = (1, 1) against the constraint gradient (−1, −1): μ = 1 exactly.

    >>> mu, res = stationarity_multipliers(jnp.array([1.0, 1.0]), jnp.array([[-1.0, -1.0]]))
    >>> float(mu[0]), float(res)
    (1.0, 0.0)
    """
    xp = _xp(gradient, jacobian)
    g, A = xp.asarray(gradient), xp.asarray(jacobian)
    mu = xp.linalg.lstsq(A.T, -g, rcond=None)[0] if xp is np else xp.linalg.lstsq(A.T, -g)[0]
    residual = xp.max(xp.abs(g + A.T @ mu), initial=0.0) / xp.maximum(xp.max(xp.abs(g), initial=0.0), 1e-300)
    return mu, residual


def linearised_kkt(problem: Problem, result: Result, theta, options: SolverOptions):
    """The solver's scaled KKT system at ``result``, linearised for implicit differentiation:
    returns ``(parts, z, derivative, unpack)`` with ``parts(z, θ) -> (∇_z L₀, (G, H))`` the
    Lagrangian gradient and constraints in the solver's scaled variables z (multipliers held),
    ``z`` the scaled solution, ``derivative(r, c)`` solving :func:`active_set_derivative` with
    its W and A at z and the result's active set for right-hand sides r = ∂(∇_z L₀)·dθ,
    c = ∂(G, H)·dθ, and ``unpack(dz, dμ̃)`` mapping a scaled step to physical (dx, dλ, dν).
    A directional derivative dx*/dθ·δ is ``unpack(*derivative(*jvp(parts(z, ·), θ, δ)))[0]``.
    ``result`` must come from ``solve(problem, ..., theta, options)``; jit/vmap-able."""
    active, at_lo, at_hi = _active_masks(problem, result, options)
    z, lam, nu = _scaled_point(problem, result)
    m = lam.shape[0]
    scales = jax.tree_util.tree_map(jax.lax.stop_gradient, result.scales)

    def parts(zz, th):
        model = make_model(problem, th, scales)

        def lag(y):
            F, G, H = model.FGH(y)
            return F + jnp.dot(lam, G) + jnp.dot(nu, H), jnp.concatenate([G, H])

        return jax.grad(lag, has_aux=True)(zz)

    W, A = jax.jacfwd(parts)(z, theta)
    fixed = at_lo | at_hi
    rows = jnp.concatenate([active, jnp.ones((A.shape[0] - m,), bool)])
    dxdz = jnp.where(problem.log_scale, result.x, problem.scale)

    def derivative(r, c):
        return active_set_derivative(W, A, r, c, free=~fixed, active=rows)

    def unpack(dz, dmu):
        dx = dxdz * jnp.where(fixed, 0.0, dz)
        return dx, dmu[:m] * scales.g / scales.f, dmu[m:] * scales.h / scales.f

    return parts, z, derivative, unpack


_linearised_kkt = linearised_kkt  # former private name


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
    parts, z, derivative, unpack = linearised_kkt(problem, result, theta, options)
    flat_theta, unravel = ravel_pytree(theta)
    r, c = jax.jacfwd(lambda ft: parts(z, unravel(ft)))(flat_theta)  # (n, q), (m + p, q)
    dz, dmu = derivative(r, c)
    dx, dlam, dnu = jax.vmap(unpack, in_axes=1, out_axes=1)(dz, dmu)

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
        parts, z, derivative, unpack = linearised_kkt(problem, r, theta, options)
        _, (r_dot, c_dot) = jax.jvp(lambda th: parts(z, th), (theta,), (dtheta,))
        dx, dlam, dnu = unpack(*derivative(r_dot, c_dot))
        _, df = jax.jvp(lambda th: _lagrangian_phys(problem, r.x, r.lam, r.nu, th), (theta,), (dtheta,))
        return Solution(r.x, r.f, r.lam, r.nu), Solution(dx, df, dlam, dnu)

    return solution


__all__ = ["Sensitivity", "Solution", "kkt_sensitivity", "shadow_prices", "differentiable_solver", "kkt_matrix",
           "active_set_derivative", "stationarity_multipliers", "linearised_kkt"]
