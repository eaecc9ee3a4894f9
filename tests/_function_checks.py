"""Shared checks for tables of scalar model functions: domain sampling and gradient versus
central differences (used by the physics-model test files)."""

import math

import jax

_CACHE = {}


def point(domain, u):
    """Map each u in [0, 1] onto its (lo, hi, log) interval (log-uniform when ``log``)."""
    out = []
    for (lo, hi, log), ui in zip(domain, u):
        out.append(math.exp(math.log(lo) + ui * (math.log(hi) - math.log(lo))) if log else lo + ui * (hi - lo))
    return out


def jitted(name, fn, n):
    """``(jit(fn), jit(grad(fn)))`` over all ``n`` arguments, compiled once per ``name``."""
    key = (name, fn)
    if key not in _CACHE:
        _CACHE[key] = (jax.jit(fn), jax.jit(jax.grad(fn, argnums=tuple(range(n)))))
    return _CACHE[key]


def check_grad_vs_fd(fn_j, grad_j, args, domain, rtol=2e-6, value_floor=1.0):
    """Assert every partial derivative is finite and equals a float64 central difference.

    The step is relative (1e-6·|x|, at least 1e-9 of the domain width on linear axes); the
    tolerance adds the central difference's rounding error ~1e-16·|f|/h and a floor scaled by
    ``|f| + value_floor``.
    """
    grads = grad_j(*args)
    f0 = float(fn_j(*args))
    for i, (x, g, (lo_d, hi_d, log)) in enumerate(zip(args, grads, domain)):
        g = float(g)
        assert math.isfinite(g), f"gradient w.r.t. argument {i} is not finite at {args}"
        h = 1e-6 * abs(x) if log else 1e-6 * max(abs(x), 1e-3 * (hi_d - lo_d))
        hi = list(args)
        lo = list(args)
        hi[i] = x + h
        lo[i] = x - h
        fd = (float(fn_j(*hi)) - float(fn_j(*lo))) / (2 * h)
        atol = 1e-9 * abs(f0) / h + 1e-10 * (abs(f0) + value_floor) / max(abs(x), 1.0)
        assert abs(g - fd) <= rtol * max(abs(g), abs(fd)) + atol, (i, args, g, fd)
