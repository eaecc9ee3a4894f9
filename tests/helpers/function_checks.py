"""Shared checks for tables of scalar model functions (used by the physics-model test files).

Two table shapes are served:

* ``spec = (name, fn, domain, bad, ...)`` — ``domain`` lists one ``(lo, hi, log)`` interval per
  argument, ``bad`` lists ``(argument index, out-of-domain value)`` pairs;
* one-argument cases ``(fn, args, i)`` — ``fn(*args)`` varied in its argument ``i`` only.
"""

import functools
import math
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from diffsense.errors import DomainError

_CACHE = {}

# Relative rounding error allowed in one evaluation of a model function: ~450 eps, room for
# special functions and series accurate to ~1e-13 rather than to the last bit.
ROUNDING = 1e-13


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


def check_grad_vs_fd(fn_j, grad_j, args, domain, rtol=2e-6, value_floor=1.0, term_scale=None):
    """Assert every partial derivative is finite and equals a float64 finite difference.

    Differences are taken at six steps h = h0·10^k, k = 2 … −3, with h0 = 1e-6·|x| (on linear
    axes at least 1e-9 of the domain width): central, or the second-order one-sided difference
    pointing inward where the step would leave the domain (steps that fit neither are skipped).
    Each difference's error is estimated as its distance to the next shorter step's difference
    (truncation, O(h²)) plus the rounding bound ROUNDING·(|f| + term_scale)/h, and the gradient is
    compared with the difference of least estimated error, within ``rtol`` plus twice that
    estimate. So a function that bends on a short scale near a domain edge (sqrt(c + a·x)) is
    judged at a short step, a function limited by rounding at a long one, and a gradient wrong by
    more than its differences' spread fails. ``term_scale(args)`` is the size of the terms that
    cancel in a function whose value is a difference of larger ones (a contrast T₁ − T₂), which
    sets its rounding. A floor 1e-10·(|f| + value_floor)/max(|x|, 1) is added.
    """
    grads = grad_j(*args)
    f0 = float(fn_j(*args))
    rounding = ROUNDING * (abs(f0) + (float(term_scale(args)) if term_scale else 0.0))
    for i, (x, g, (lo_d, hi_d, log)) in enumerate(zip(args, grads, domain)):
        g = float(g)
        assert math.isfinite(g), f"gradient w.r.t. argument {i} is not finite at {args}"
        h0 = 1e-6 * abs(x) if log else 1e-6 * max(abs(x), 1e-3 * (hi_d - lo_d))

        def at(step):
            a = list(args)
            a[i] = x + step
            return float(fn_j(*a))

        diffs = []
        for k in (2, 1, 0, -1, -2, -3):
            h = h0 * 10.0**k
            if lo_d <= x - h and x + h <= hi_d:
                diffs.append((h, (at(h) - at(-h)) / (2 * h)))
            elif lo_d <= x + 2 * h <= hi_d or lo_d <= x - 2 * h <= hi_d:
                inward = 1.0 if lo_d <= x + 2 * h <= hi_d else -1.0
                diffs.append((h, inward * (-3.0 * f0 + 4.0 * at(inward * h) - at(2 * inward * h)) / (2 * h)))
        errors = [abs(fd - diffs[j + 1][1]) + rounding / h for j, (h, fd) in enumerate(diffs[:-1])]
        best = min(range(len(errors)), key=errors.__getitem__)
        fd = diffs[best][1]
        floor = 1e-10 * (abs(f0) + value_floor) / max(abs(x), 1.0)
        floor += 16 * sys.float_info.min  # XLA:CPU flushes subnormal results (< 2.2e-308) to zero
        if not abs(g - fd) <= rtol * max(abs(g), abs(fd)) + 2 * errors[best] + floor:
            raise AssertionError(f"argument {i} at {args}: gradient {g} but differences {diffs} "
                                 f"(best h = {diffs[best][0]:.3g}, estimated error {errors[best]:.3g})")


# --- tables of (name, fn, domain, bad, ...) ------------------------------------------------------


def assert_jit_matches_eager(spec, rel, atol=0.0):
    """jit equals eager at an interior point; ``atol`` may be a function of the eager value."""
    name, fn, domain = spec[:3]
    args = point(domain, [0.37] * len(domain))
    eager = float(fn(*args))
    assert math.isfinite(eager)
    fn_j, _ = jitted(name, fn, len(domain))
    tol = atol(eager) if callable(atol) else atol
    assert float(fn_j(*args)) == pytest.approx(eager, rel=rel, abs=tol)


def assert_vmap_matches_loop(spec, rtol, broadcast=False):
    """vmap over three interior points equals a Python loop (and plain broadcasting)."""
    fn, domain = spec[1], spec[2]
    rows = [point(domain, [u] * len(domain)) for u in (0.1, 0.5, 0.9)]
    cols = [jnp.asarray([r[i] for r in rows]) for i in range(len(domain))]
    batched = jax.vmap(fn)(*cols)
    np.testing.assert_allclose(np.asarray(batched), [float(fn(*r)) for r in rows], rtol=rtol)
    if broadcast:
        np.testing.assert_allclose(np.asarray(fn(*cols)), np.asarray(batched), rtol=rtol)


def assert_gradient_matches_fd(spec, value_floor):
    """Gradient equals finite differences at two interior points (u = 0.23, 0.61)."""
    name, fn, domain = spec[:3]
    fn_j, grad_j = jitted(name, fn, len(domain))
    for u in (0.23, 0.61):
        check_grad_vs_fd(fn_j, grad_j, point(domain, [u] * len(domain)), domain, value_floor=value_floor)


def assert_gradient_finite(spec, u, value_floor, smooth=True, term_scale=None):
    """At the point ``u`` of the domain the gradient is finite, and equals finite differences
    (rtol 1e-5, rounding bound ``term_scale`` as in :func:`check_grad_vs_fd`) where the function
    is ``smooth``."""
    name, fn, domain = spec[:3]
    fn_j, grad_j = jitted(name, fn, len(domain))
    args = point(domain, u)
    if smooth:
        check_grad_vs_fd(fn_j, grad_j, args, domain, rtol=1e-5, value_floor=value_floor, term_scale=term_scale)
    else:
        assert all(math.isfinite(float(g)) for g in grad_j(*args))


def assert_out_of_domain_raises(spec):
    """Each listed out-of-domain argument value raises DomainError."""
    fn, domain, bad = spec[1], spec[2], spec[3]
    args = point(domain, [0.5] * len(domain))
    for i, value in bad:
        a = list(args)
        a[i] = value
        with pytest.raises(DomainError):
            fn(*a)


# --- one-argument cases (fn, args, i) ---------------------------------------------------------


def with_arg(args, i, x):
    """``args`` with argument ``i`` replaced by ``x``."""
    out = list(args)
    out[i] = x
    return tuple(out)


@functools.lru_cache(maxsize=None)
def compiled_in_argument(fn, args, i):
    """(jitted f(x), jitted df/dx, jitted vmapped f) of ``fn`` varied in argument ``i``."""

    def f(x):
        return fn(*with_arg(args, i, x))

    return jax.jit(f), jax.jit(jax.grad(f)), jax.jit(jax.vmap(f))


def assert_argument_case(fn, args, i):
    """jit and vmap equal eager (rel 1e-12); the derivative in argument ``i`` equals a central
    difference (rel 1e-6)."""
    f_jit, g_jit, f_vmap = compiled_in_argument(fn, args, i)
    eager = float(fn(*args))
    assert float(f_jit(jnp.float64(args[i]))) == pytest.approx(eager, rel=1e-12)
    xs = np.array([args[i] * 0.5, args[i], args[i] * 0.9])
    for x, b in zip(xs, np.asarray(f_vmap(jnp.asarray(xs)))):
        assert b == pytest.approx(float(fn(*with_arg(args, i, x))), rel=1e-12)
    h = 1e-6 * abs(args[i])
    fd = (float(fn(*with_arg(args, i, args[i] + h))) - float(fn(*with_arg(args, i, args[i] - h)))) / (2 * h)
    assert float(g_jit(jnp.float64(args[i]))) == pytest.approx(fd, rel=1e-6, abs=1e-9 * max(1.0, abs(eager)))


def assert_argument_gradient_finite(fn, args, i, lo, hi, u):
    """The derivative in argument ``i`` is finite at the point ``u`` of [lo, hi] (log-uniform
    when lo > 0)."""
    x = math.exp(math.log(lo) + u * (math.log(hi) - math.log(lo))) if lo > 0 else lo + u * (hi - lo)
    assert np.isfinite(float(compiled_in_argument(fn, args, i)[1](jnp.float64(x))))


def grad_and_central_difference(fun, x0, h):
    """``(fun′(x0), (fun(x0 + h) − fun(x0 − h))/(2h))`` as floats: a derivative by jax.grad and
    the central difference that checks it."""
    return float(jax.grad(fun)(x0)), float((fun(x0 + h) - fun(x0 - h)) / (2 * h))
