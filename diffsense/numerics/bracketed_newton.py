"""Safeguarded Newton iteration for the root of a decreasing function inside a bracket.

Elementwise over arrays, inside ``jax.lax.while_loop``. Each step evaluates the residual ``g``
and its slope, shrinks the bracket to the side where the root lies (``g`` decreases, so
``g > 0`` puts the root above the iterate), and takes the Newton step when it is finite and
strictly inside the bracket, the bracket's midpoint otherwise (Press et al., *Numerical
Recipes* 3rd ed. §9.4, "rtsafe"). An element whose residual is exactly zero stays put. The loop
ends when every element's last step is at most ``tolerance(x)`` or after ``max_iter`` steps.

The iteration carries no derivative worth having: callers differentiate the root implicitly
(``jax.custom_jvp``), ``dx/dθ = -(∂g/∂θ)/(∂g/∂x)``.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

__all__ = ["newton_decreasing", "forward_slope"]


def forward_slope(residual):
    """``x -> (residual(x), d residual/dx)`` by one forward-mode JVP (``residual`` elementwise)."""
    return lambda x: jax.jvp(residual, (x,), (jnp.ones_like(x),))


def newton_decreasing(residual_and_slope, x0, lo, hi, tolerance, max_iter: int):
    """Root of a decreasing residual in ``[lo, hi]``, started at ``x0``.

    Args:
        residual_and_slope: ``x -> (g(x), g'(x))``, elementwise (may close over traced values);
            :func:`forward_slope` makes one from ``g``.
        x0, lo, hi: start and bracket (arrays of one shape; ``lo < x0 < hi`` is not required).
        tolerance: ``x ->`` the step size below which an element has settled.
        max_iter: largest number of steps (static).

    Returns:
        ``(x, lo, hi)``: the last iterate and the final bracket. A root outside the initial
        bracket leaves the iterate at the nearer end (the caller tests the bracket).

    >>> import math
    >>> x, _, _ = newton_decreasing(forward_slope(lambda x: 2.0 - x * x), jnp.asarray(1.0),
    ...                             jnp.asarray(0.0), jnp.asarray(2.0), lambda x: 1e-15, 50)
    >>> abs(float(x) - math.sqrt(2.0)) < 1e-15
    True
    """

    def body(state):
        x, lo, hi, _, it = state
        g, dg = residual_and_slope(x)
        lo = jnp.where(g > 0.0, x, lo)
        hi = jnp.where(g <= 0.0, x, hi)
        x_newton = x - g / dg
        ok = jnp.isfinite(x_newton) & (x_newton > lo) & (x_newton < hi)
        x_new = jnp.where(ok, x_newton, 0.5 * (lo + hi))
        x_new = jnp.where(g == 0.0, x, x_new)
        return x_new, lo, hi, jnp.abs(x_new - x), it + 1

    def cond(state):
        x, _, _, step, it = state
        return (it < max_iter) & jnp.any(step > tolerance(x))

    x, lo, hi, _, _ = jax.lax.while_loop(cond, body, (x0, lo, hi, jnp.full_like(x0, jnp.inf), 0))
    return x, lo, hi
