"""The box lower ≤ x ≤ upper: when a variable is on a bound, and the maps that respect the box.

All solvers work in the scaled coordinates z of :mod:`diffsense.optimize.problem`, where the
box is zlo ≤ z ≤ zhi. A scaled coordinate within

    BOUND_RTOL · (1 + |bound|)        (BOUND_RTOL = 1e-9)

of a finite bound is *on* that bound: the solvers put it there exactly
(:func:`snap_to_bounds`), so an active bound is met exactly and gets a bound multiplier, and
the same test tells which variables a gradient holds on the box (:func:`bound_activity`) and,
after a solve, which variables of a physical answer sit on a bound
(:func:`variables_on_bounds`). Relative to 1 + |bound| so that it means ~1e-9 of a scaled
unit near the origin (linear variables of their typical magnitude, log variables within a
factor e of it) and ~1e-9 relative far from it.

The module also holds the smooth reparameterisation of the box that the augmented
Lagrangian's BFGS inner solvers minimise over (:func:`box_reparameterisation`).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.optimize.problem import Problem

BOUND_RTOL = 1e-9  # a scaled coordinate this close (relative to 1 + |bound|) to a bound is on it


def bound_tolerance(bound):
    """BOUND_RTOL · (1 + |bound|) for a scaled bound (an infinite bound counts as 0: it is never reached).

    >>> float(bound_tolerance(jnp.asarray(3.0)))
    4e-09
    """
    return BOUND_RTOL * (1.0 + jnp.abs(jnp.where(jnp.isfinite(bound), bound, 0.0)))


def near_bounds(z, zlo, zhi):
    """Masks (on the lower bound, on the upper bound) of scaled coordinates z (module docstring)."""
    return z - zlo <= bound_tolerance(zlo), zhi - z <= bound_tolerance(zhi)


def snap_to_bounds(z, zlo, zhi):
    """z with the coordinates that are on a bound (:func:`near_bounds`) put exactly on it."""
    on_lo, on_hi = near_bounds(z, zlo, zhi)
    return jnp.where(on_lo, zlo, jnp.where(on_hi, zhi, z))


def bound_activity(zlo, zhi, z, grad):
    """Masks of variables held at their lower/upper bound: on it, with the gradient ``grad``
    of the function being minimised pushing out of the box."""
    on_lo, on_hi = near_bounds(z, zlo, zhi)
    return on_lo & (grad >= 0.0), on_hi & (grad <= 0.0)


def physical_point(problem: Problem, z, zlo, zhi):
    """x(z) inside [lower, upper], exactly on a bound where z is on or beyond it."""
    x = problem.clip(problem.from_scaled(z))
    return jnp.where(z <= zlo, problem.lower, jnp.where(z >= zhi, problem.upper, x))


def bound_multipliers(problem: Problem, x, r_x):
    """(μ_lower, μ_upper) ≥ 0 from the physical Lagrangian gradient r_x at x (a fixed variable
    is on both bounds: the sign of r picks the multiplier)."""
    mu_lo = jnp.where(x <= problem.lower, jnp.maximum(r_x, 0.0), 0.0)
    mu_hi = jnp.where(x >= problem.upper, jnp.maximum(-r_x, 0.0), 0.0)
    return mu_lo, mu_hi


def variables_on_bounds(problem: Problem, x):
    """Masks (on the lower bound, on the upper bound) of a physical point x (units of the
    variables), by the solvers' own test in scaled coordinates (module docstring); a fixed
    variable (lower = upper) counts as on its lower bound only. NumPy arrays.

    >>> p = Problem(lambda x, _: x[0], [1.0, 0.0], [100.0, 2.0], log_scale=[True, False])
    >>> lo, hi = variables_on_bounds(p, [1.0, 2.0 - 1e-6])
    >>> lo.tolist(), hi.tolist()
    ([True, False], [False, False])
    """
    # in NumPy (the same formulas as the solvers' traced ones): no eager JAX dispatch
    x = np.asarray(x, dtype=float)
    log = np.asarray(problem.log_scale, bool)
    scaled = problem.to_scaled_host
    zlo, zhi = scaled(problem.lower), scaled(problem.upper)
    z = scaled(np.where(log, np.maximum(x, np.finfo(float).tiny), x))

    def tol(b):
        return BOUND_RTOL * (1.0 + np.abs(np.where(np.isfinite(b), b, 0.0)))

    on_lo = z - zlo <= tol(zlo)
    on_hi = zhi - z <= tol(zhi)
    return on_lo, on_hi & ~on_lo


def box_reparameterisation(zlo, zhi):
    """Smooth surjection y ↦ z onto the box and a right inverse.

    z = c + r sin y (two finite bounds, c the centre and r the half-width), z = lo + y² or
    hi − y² (one), z = y (none). An active bound is reached at a finite y where dz/dy = 0;
    there the reparameterised function has curvature r·|∂L/∂z| > 0 in y when the bound is
    strictly active. ``inverse(z, hold)`` starts slightly off the bounds (1e-6 of the
    half-range, 1e-12 for a one-sided bound), where dz/dy = 0 would stall a gradient method,
    except for the variables ``hold`` keeps exactly where they are.

    >>> forward, inverse = box_reparameterisation(jnp.array([-1.0, 0.0]), jnp.array([3.0, jnp.inf]))
    >>> [round(float(v), 12) for v in forward(inverse(jnp.array([2.0, 4.0])))]
    [2.0, 4.0]
    """
    flo = jnp.isfinite(zlo)
    fhi = jnp.isfinite(zhi)
    both = flo & fhi
    lo_s = jnp.where(flo, zlo, 0.0)
    hi_s = jnp.where(fhi, zhi, 0.0)
    c = 0.5 * (lo_s + hi_s)
    r = 0.5 * (hi_s - lo_s)
    r_safe = jnp.where(r > 0, r, 1.0)

    def forward(y):
        two = c + r * jnp.sin(y)
        low = lo_s + y**2
        high = hi_s - y**2
        return jnp.where(both, two, jnp.where(flo, low, jnp.where(fhi, high, y)))

    def inverse(z, hold=False):
        margin = jnp.where(hold, 0.0, 1e-6)
        u = jnp.clip((z - c) / r_safe, -1.0 + margin, 1.0 - margin)
        two = jnp.where(r > 0, jnp.arcsin(u), 0.0)
        floor = jnp.where(hold, 0.0, 1e-12)
        low = jnp.sqrt(jnp.maximum(z - lo_s, floor))
        high = jnp.sqrt(jnp.maximum(hi_s - z, floor))
        return jnp.where(both, two, jnp.where(flo, low, jnp.where(fhi, high, z)))

    return forward, inverse


__all__ = ["BOUND_RTOL", "bound_tolerance", "near_bounds", "snap_to_bounds", "bound_activity", "physical_point",
           "bound_multipliers", "variables_on_bounds", "box_reparameterisation"]
