"""What a solve returns: :class:`Result` with its :class:`KKTResidual`, :class:`Conflict` and
:class:`Scales` (pytrees of arrays; batched along a leading axis under vmap). Every solver
method returns the same :class:`Result`."""

from __future__ import annotations

from typing import NamedTuple, Optional

import jax


class KKTResidual(NamedTuple):
    """Scaled first-order optimality measures at the returned point (all ≥ 0).

    ``stationarity``: ‖P_box(z − ∇_z L₀) − z‖∞, the projected gradient of the scaled Lagrangian;
    ``feasibility``: max(‖max(G, 0)‖∞, ‖H‖∞); ``complementarity``: ‖min(λ̃, −G)‖∞."""

    stationarity: jax.Array
    feasibility: jax.Array
    complementarity: jax.Array


class Conflict(NamedTuple):
    """Masks explaining an infeasible answer (all False when ``feasible``): inequality and
    equality constraints left violated at the least-infeasible point, and lower/upper bounds
    that block any further reduction of the violation."""

    inequality: jax.Array
    equality: jax.Array
    lower: jax.Array
    upper: jax.Array


class Scales(NamedTuple):
    """Function scales used internally: F = f·f_scale, G = g⊙g_scale, H = h⊙h_scale."""

    f: jax.Array
    g: jax.Array
    h: jax.Array


class Result(NamedTuple):
    """Outcome of :func:`diffsense.optimize.solve` (a pytree; batched along a leading axis under vmap).

    x: solution (units of the variables), always inside [lower, upper].
    f, g, h: objective, inequality (≤ 0 when feasible) and equality values at x.
    lam: inequality multipliers λ ≥ 0 (units of f per unit of g; ∂f*/∂b for g ≤ b is −λ).
    nu: equality multipliers ν (units of f per unit of h).
    mu_lower, mu_upper: bound multipliers ≥ 0 (units of f per unit of x).
    converged: KKT residuals within tolerance (stationarity/complementarity ≤ tol, violation
        ≤ feas_tol). feasible: the returned x satisfies all constraints within feas_tol.
    kkt: :class:`KKTResidual` (scaled). iterations: outer iterations (the restoration solve,
    if any, counts as one); inner_iterations: their total.
    penalty: final ρ. polished: the Newton refinement was accepted.
    conflict: :class:`Conflict` masks. scales: :class:`Scales` used.
    jacobian: the Jacobian of the stacked (f, g, h) with respect to x at x (rows f, g, h;
        unscaled), from the solve's own last linearisation (the augmented Lagrangian; None for
        the SQP). A lane whose box pins every variable at x0 returns the linearisation at x0.
    """

    x: jax.Array
    f: jax.Array
    g: jax.Array
    h: jax.Array
    lam: jax.Array
    nu: jax.Array
    mu_lower: jax.Array
    mu_upper: jax.Array
    converged: jax.Array
    feasible: jax.Array
    kkt: KKTResidual
    iterations: jax.Array
    inner_iterations: jax.Array
    penalty: jax.Array
    polished: jax.Array
    conflict: Conflict
    scales: Scales
    jacobian: Optional[jax.Array] = None


__all__ = ["Result", "KKTResidual", "Conflict", "Scales"]
