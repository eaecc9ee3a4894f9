"""Logarithms that keep full relative accuracy where XLA's own lose it.

``jnp.log1p(x)`` as XLA compiles it for the CPU carries up to 2.7e-14 relative error for x in
[-0.5, -0.3] (measured against numpy's ``log1p`` on 200 001 points: ≤ 2.2e-16 below |x| = 0.3,
1.1e-14 on [-0.4, -0.3], 2.7e-14 on [-0.5, -0.4]). For x <= -0.25, ``1 + x`` is exact or within
half an ulp of 1 + x relative to a number ≥ 0.5 (Sterbenz's lemma for x <= -0.5; one rounding
otherwise), so ``log(1 + x)`` is accurate to ~2 ulp there.
"""

from __future__ import annotations

import jax.numpy as jnp

__all__ = ["log_one_minus"]


def log_one_minus(p):
    """``log(1 - p)`` for p <= 1 to ~2 ulp relative (measured ≤ 4.4e-16 on p in [1e-300, 0.9999]):
    ``log1p(-p)`` for p <= 0.25, ``log(1 - p)`` above (module docstring); ``-inf`` at p = 1.

    >>> float(-jnp.expm1(log_one_minus(0.40625)))  # XLA's log1p alone gives 0.406249999999995
    0.40625
    """
    p = jnp.asarray(p)
    return jnp.where(p > 0.25, jnp.log(1.0 - p), jnp.log1p(-p))
