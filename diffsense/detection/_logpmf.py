"""Accurate logarithms of Poisson and binomial-type probabilities for real arguments.

The direct form ``k*log(mu) - mu - lgamma(k+1)`` cancels catastrophically when ``k`` and
``mu`` are large (absolute error ~ eps*mu in the exponent, i.e. ~1e-12 relative error of the
probability at mu ~ 1e4). The saddle-point form of Loader (2000), "Fast and accurate
computation of binomial probabilities",

    log p(k; mu) = -stirlerr(k) - bd0(k, mu) - 0.5*log(2*pi*k),

with ``stirlerr(x) = lgamma(x+1) - (x+1/2) log x + x - log(2 pi)/2`` (Stirling's remainder) and
``bd0(x, m) = x log(x/m) + m - x`` (a deviance, evaluated by a series when x is near m), keeps
full relative accuracy. All functions accept real (non-integer) ``k`` and are written with the
double-``where`` pattern so values and derivatives stay finite.
"""

from __future__ import annotations

import jax.numpy as jnp
from jax.scipy.special import gammaln

_HALF_LOG_2PI = 0.9189385332046727417803297364056176


def stirlerr(x):
    """Stirling remainder ``lgamma(x+1) - (x+1/2)log x + x - log(2 pi)/2`` for x > 0.

    For x >= 15 the asymptotic series 1/(12x) - 1/(360x^3) + 1/(1260x^5) - 1/(1680x^7)
    + 1/(1188x^9) is used (truncation < 2.3e-16 absolute at x = 15, the first omitted term
    being 691/(360360 x^11)); below 15 the defining expression is evaluated directly
    (absolute error <= ~5e-15).
    """
    x = jnp.asarray(x)
    big = x >= 15.0
    xb = jnp.where(big, x, 15.0)
    xs = jnp.where(big, 1.0, x)
    r = 1.0 / (xb * xb)
    series = (1.0 / 12.0 - r * (1.0 / 360.0 - r * (1.0 / 1260.0 - r * (1.0 / 1680.0 - r / 1188.0)))) / xb
    direct = gammaln(xs + 1.0) - (xs + 0.5) * jnp.log(xs) + xs - _HALF_LOG_2PI
    return jnp.where(big, series, direct)


def bd0(x, m):
    """Deviance term ``x*log(x/m) + m - x`` (>= 0) for x >= 0, m > 0.

    When |x - m| < 0.1 (x + m) it is summed as ``(x-m) v + 2x sum_{i>=1} v^(2i+1)/(2i+1)`` with
    ``v = (x-m)/(x+m)``; |v| < 0.1 makes 9 terms exact to < 1e-19 relative.
    """
    x = jnp.asarray(x)
    m = jnp.asarray(m)
    d = x - m
    s = x + m
    near = jnp.abs(d) < 0.1 * s
    v = jnp.where(near, d / jnp.where(near, s, 1.0), 0.0)
    v2 = v * v
    term = v * v2
    acc = jnp.zeros_like(v)
    for i in range(1, 10):
        acc = acc + term / (2 * i + 1)
        term = term * v2
    series = d * v + 2.0 * x * acc
    xpos = x > 0
    xf = jnp.where(far_ok := (~near) & xpos, x, 1.0)
    mf = jnp.where(far_ok, m, 1.0)
    far = jnp.where(xpos, xf * jnp.log(xf / mf) + mf - xf, m)
    return jnp.where(near, series, far)


def log_poisson_pmf(k, mu):
    """log(exp(-mu) mu^k / Gamma(k+1)) for real k >= 0, mu > 0, to full relative accuracy."""
    k = jnp.asarray(k)
    mu = jnp.asarray(mu)
    pos = k > 0
    kp = jnp.where(pos, k, 1.0)
    val = -stirlerr(kp) - bd0(kp, mu) - 0.5 * jnp.log(2.0 * jnp.pi * kp)
    return jnp.where(pos, val, -mu)


def log_binomial_pmf(k, size, p):
    """log of C(size, k) p^k (1-p)^(size-k) for real 0 <= k <= size, 0 < p < 1 (Loader 2000)."""
    k = jnp.asarray(k)
    size = jnp.asarray(size)
    p = jnp.asarray(p)
    q = 1.0 - p
    interior = (k > 0) & (k < size)
    ki = jnp.where(interior, k, 0.5 * size)
    ni = size
    val = (
        stirlerr(ni)
        - stirlerr(ki)
        - stirlerr(ni - ki)
        - bd0(ki, ni * p)
        - bd0(ni - ki, ni * q)
        + 0.5 * jnp.log(ni / (2.0 * jnp.pi * ki * (ni - ki)))
    )
    at0 = size * jnp.log1p(-p)
    atn = size * jnp.log(p)
    return jnp.where(interior, val, jnp.where(k <= 0, at0, atn))


def log_negbin_pmf(k, r, q):
    """log P(K = k) for K ~ NegBin(r, q): Gamma(k+r)/(Gamma(r) k!) q^k (1-q)^r.

    Uses NB(k; r, q) = r/(k+r) * Binomial(k; k+r, q) so the binomial saddle-point form applies.
    """
    k = jnp.asarray(k)
    r = jnp.asarray(r)
    return jnp.log(r / (k + r)) + log_binomial_pmf(k, k + r, q)
