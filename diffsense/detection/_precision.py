"""Which floating-point precision a detection computation runs in (a static, trace-time choice).

Importing diffsense enables float64; with ``DIFFSENSE_X64=0`` JAX stays 32-bit and the
detection functions follow the dtype of their inputs. A few numerical choices differ for
float32 (truncation exponent, tighter start points, cancellation-free special functions, see
``_bounds`` and ``_logpmf``); this predicate selects them, so the float64 computation is the
same program as without them.
"""

from __future__ import annotations

import jax.numpy as jnp

__all__ = ["single_precision", "as_float"]


def single_precision(x) -> bool:
    """True when ``x`` (array, scalar or dtype) is a float of 32 bits or fewer."""
    return jnp.finfo(jnp.result_type(x)).bits <= 32


def as_float(*args):
    """The arguments as arrays of their common floating dtype (float64 unless all are float32)."""
    dtype = jnp.result_type(*args, float)
    return tuple(jnp.asarray(a, dtype=dtype) for a in args)
