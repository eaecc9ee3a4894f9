"""Domain checks at the API edge.

A public function calls :func:`check_range` on each argument. When the argument is a concrete
value (Python number, NumPy or concrete JAX array) an out-of-domain value raises
:class:`DomainError` naming the argument, the allowed range and the offending value. Inside
``jit``/``vmap``/``grad`` the argument is a tracer and the check is skipped, so the traced
program carries no branching; callers that trace are expected to have validated their inputs
once, outside the transformation.
"""

from __future__ import annotations

import numpy as np
from jax import core as _core

from diffsense.errors import DomainError


def is_concrete(x) -> bool:
    """True when ``x`` holds concrete values (not a JAX tracer)."""
    if isinstance(x, _core.Tracer):
        return False
    return True


def check_range(name: str, x, lo=None, hi=None, *, lo_open=False, hi_open=False, where: str = ""):
    """Raise :class:`DomainError` if a concrete ``x`` has elements outside ``[lo, hi]``.

    ``lo_open``/``hi_open`` make the bound strict. NaN is always rejected. ``where`` names the
    function (or model) for the message.
    """
    if not is_concrete(x):
        return
    a = np.asarray(x)
    a = a.astype(a.dtype if np.issubdtype(a.dtype, np.floating) else float)
    # XLA treats subnormal inputs as zero (in comparisons and arithmetic, eager or jitted), so
    # the check judges the number the computation will see: eager and traced calls agree
    subnormal = (a != 0) & (np.abs(a) < np.finfo(a.dtype).tiny)
    a = np.where(subnormal, np.copysign(0.0, a), a)
    bad = np.isnan(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        bad |= (a >= hi) if hi_open else (a > hi)
    if np.any(bad):
        first = a[bad].flat[0]
        shown = np.asarray(x, dtype=float)[bad].flat[0]
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        lb = "(" if lo_open or lo is None else "["
        rb = ")" if hi_open or hi is None else "]"
        ctx = f"{where}: " if where else ""
        raise DomainError(
            f"{ctx}argument '{name}' must lie in {lb}{lo_s}, {hi_s}{rb}; got {float(shown)!r}"
            + (" (a subnormal number, which the computation treats as 0)" if first == 0 and shown != 0 else "")
            + (f" ({int(np.count_nonzero(bad))} of {a.size} elements out of range)" if a.size > 1 else "")
        )


def check_choice(name: str, value, choices, *, where: str = ""):
    """Raise :class:`DomainError` unless ``value`` is one of ``choices``."""
    if value not in choices:
        ctx = f"{where}: " if where else ""
        raise DomainError(f"{ctx}argument '{name}' must be one of {sorted(map(str, choices))}; got {value!r}")
