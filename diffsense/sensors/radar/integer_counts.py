"""Integer counts (reference cells, pulses, M of M-of-N) seen by an optimizer as relaxed reals."""

from __future__ import annotations

import jax
import jax.numpy as jnp

__all__ = ["between_integer_counts"]


def between_integer_counts(value_at, count):
    """``value_at(c)`` for an integer count c, linearly interpolated between the integers around a
    relaxed real ``count`` (an optimizer's integer variable): exact at integers, continuous, its
    derivative the difference of the two neighbours. The counts handed to ``value_at`` carry no
    derivative (their tangents are symbolic zeros)."""
    low = jax.lax.stop_gradient(jnp.floor(count))
    frac = count - low
    high = jnp.where(frac > 0.0, low + 1.0, low)  # no evaluation past an integer upper bound
    return (1.0 - frac) * value_at(low) + frac * value_at(high)
