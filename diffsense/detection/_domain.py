"""The domain contract of the public detection functions: one predicate, two enforcements.

Every public function lists its domain as interval constraints on its arguments (and, where
needed, a strict inequality between two of them, e.g. ``pd > pfa``). :func:`admit` evaluates the
constraints on the arguments *after* their conversion to the working dtype, so that a float32
run judges the numbers it will compute with:

* concrete arguments (an eager call): an argument outside its interval raises
  :class:`~diffsense.errors.DomainError` (through :func:`diffsense.numerics.checks.check_range`);
* traced arguments (inside ``jit``/``vmap``/``grad``), which cannot raise: the same predicate is
  returned as a boolean mask, and :func:`guard` makes the result NaN, value and derivative,
  wherever it is False.

So an eager call raises exactly where the jitted call returns NaN, and both return the same
number everywhere else. Out-of-domain elements are replaced by an in-domain placeholder before
the computation (:func:`guard` with a fill value), so that no iteration sees an argument for which
it was not written (e.g. an infinite threshold), and NaN is put back at the end.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete

__all__ = ["admit", "guard", "within"]


def within(x, lo=None, hi=None, lo_open=False, hi_open=False):
    """Elementwise ``lo <= x <= hi`` (strict where ``*_open``); False for NaN; subnormal x is 0."""
    x = jnp.asarray(x)
    if jnp.issubdtype(x.dtype, jnp.floating):
        # subnormal numbers count as zero, explicitly: XLA flushes them in some fused kernels
        # and not in others, and the eager check (check_range) treats them as zero too
        x = jnp.where(jnp.abs(x) < jnp.finfo(x.dtype).tiny, jnp.zeros_like(x), x)
    ok = ~jnp.isnan(x)
    if lo is not None:
        ok = ok & ((x > lo) if lo_open else (x >= lo))
    if hi is not None:
        ok = ok & ((x < hi) if hi_open else (x <= hi))
    return ok


def admit(where, constraints, greater=()):
    """Check the domain; return the mask of admissible elements and one mask per constraint.

    Args:
        where: name of the public function (for the message).
        constraints: tuples ``(name, x, lo, hi)`` or ``(name, x, lo, hi, lo_open, hi_open)``;
            ``lo``/``hi`` may be None (unbounded). NaN is always outside.
        greater: tuples ``(name_a, a, name_b, b)`` requiring ``a > b`` elementwise.

    Returns:
        ``(ok, each)``: ``ok`` is True where every constraint holds (broadcast over the
        arguments); ``each[i]`` is the mask of constraint i alone (the shape of its argument), for
        replacing an inadmissible argument by a placeholder without broadcasting it.

    Raises:
        DomainError: for concrete (eager) arguments outside the domain.
    """
    ok = jnp.asarray(True)
    each = []
    for c in constraints:
        name, x, lo, hi = c[:4]
        lo_open, hi_open = (c[4], c[5]) if len(c) > 4 else (False, False)
        check_range(name, x, lo, hi, lo_open=lo_open, hi_open=hi_open, where=where)
        each.append(within(x, lo, hi, lo_open, hi_open))
        ok = ok & each[-1]
    for name_a, a, name_b, b in greater:
        if is_concrete(a) and is_concrete(b):
            # numpy comparison: inside a trace even operations on concrete arrays are staged
            bad = ~(np.asarray(a, dtype=float) > np.asarray(b, dtype=float))
            if np.any(bad):
                raise DomainError(f"{where}: {name_a} must exceed {name_b}")
        ok = ok & (jnp.asarray(a) > jnp.asarray(b))
    return ok, each


@jax.custom_jvp
def _guard(x, ok, fill):
    return jnp.where(ok > 0, x, fill)


@_guard.defjvp
def _guard_jvp(primals, tangents):
    x, ok, fill = primals
    dx = tangents[0]
    # linear in dx (so reverse mode transposes it): NaN derivative outside the domain
    scale = jnp.where(ok > 0, 1.0, jnp.nan).astype(jnp.result_type(dx))
    return _guard(x, ok, fill), dx * scale


def guard(x, ok, fill=jnp.nan):
    """``x`` where ``ok``, else ``fill``; the derivative is NaN where not ``ok``.

    With ``fill=nan`` it marks a result as undefined; with an in-domain ``fill`` it replaces an
    inadmissible argument by a placeholder (whose derivative is still NaN, so that gradients
    with respect to an inadmissible argument are NaN rather than zero).
    """
    x = jnp.asarray(x)
    ok = jnp.broadcast_to(jnp.asarray(ok, dtype=bool), jnp.broadcast_shapes(jnp.shape(x), jnp.shape(ok)))
    x = jnp.broadcast_to(x, ok.shape)
    return _guard(x, ok.astype(x.dtype), jnp.asarray(fill, dtype=x.dtype))
