"""Shared checks for tables of scalar model functions (used by the physics-model test files).

Two table shapes are served:

* ``spec = (name, fn, domain, bad, ...)`` — ``domain`` lists one ``(lo, hi, log)`` interval per
  argument, ``bad`` lists ``(argument index, out-of-domain value)`` pairs;
* one-argument cases ``(fn, args, i)`` — ``fn(*args)`` varied in its argument ``i`` only.
"""

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from diffsense._checks import DomainError

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
    """Assert every partial derivative is finite and equals a float64 finite difference.

    The first step is relative (1e-6·|x|, at least 1e-9 of the domain width on linear axes) and
    the difference central; where a step would leave the domain the second-order one-sided
    difference pointing inward is used. Both are O(h²), but near a domain edge a function such
    as sqrt(c + a·x) bends on a scale much shorter than any fixed step, so the step is shortened
    tenfold up to three times until the difference agrees. A wrong derivative disagrees at every
    step. The tolerance adds the difference's rounding error ~1e-16·|f|/h and a floor scaled by
    ``|f| + value_floor``.
    """
    grads = grad_j(*args)
    f0 = float(fn_j(*args))
    for i, (x, g, (lo_d, hi_d, log)) in enumerate(zip(args, grads, domain)):
        g = float(g)
        assert math.isfinite(g), f"gradient w.r.t. argument {i} is not finite at {args}"
        h0 = 1e-6 * abs(x) if log else 1e-6 * max(abs(x), 1e-3 * (hi_d - lo_d))

        def at(step):
            a = list(args)
            a[i] = x + step
            return float(fn_j(*a))

        tried = []
        for h in (h0, h0 * 1e-1, h0 * 1e-2, h0 * 1e-3):
            if lo_d <= x - h and x + h <= hi_d:
                fd = (at(h) - at(-h)) / (2 * h)
            else:
                inward = 1.0 if x - h < lo_d else -1.0
                fd = inward * (-3.0 * f0 + 4.0 * at(inward * h) - at(2 * inward * h)) / (2 * h)
            atol = 1e-9 * abs(f0) / h + 1e-10 * (abs(f0) + value_floor) / max(abs(x), 1.0)
            tried.append((h, fd))
            if abs(g - fd) <= rtol * max(abs(g), abs(fd)) + atol:
                break
        else:
            raise AssertionError(f"argument {i} at {args}: gradient {g} but differences {tried}")


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


def assert_gradient_finite(spec, u, value_floor, smooth=True):
    """At the point ``u`` of the domain the gradient is finite, and equals finite differences
    (rtol 1e-5) where the function is ``smooth``."""
    name, fn, domain = spec[:3]
    fn_j, grad_j = jitted(name, fn, len(domain))
    args = point(domain, u)
    if smooth:
        check_grad_vs_fd(fn_j, grad_j, args, domain, rtol=1e-5, value_floor=value_floor)
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
