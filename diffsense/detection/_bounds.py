"""Truncation bounds of the detection series: the Poisson-weight window and the range of K.

The series ``Pd = Pfa + sum_j pois(N + j; T) P(K > j)`` (``core.py``) is summed over a window
of j outside which the weights have mass below exp(-L), and the recursions for the law of
the mixing variable K start at quantile bounds of K outside which its mass is below exp(-L).

**Truncation exponent per precision.** float64 uses L = 40 (each omitted tail below 4.2e-18,
under its round-off). float32 uses L = 20 (each omitted tail below 2.1e-9, under its
resolution of 6e-8). The smaller L matters beyond speed: the recursions start at the bounds,
where the probabilities are about exp(-L) or smaller, and float32 flushes numbers below 1.2e-38
(exp(-87.3)) to zero, after which a multiplicative recursion stays at zero.

**Tight upper bound of K in float32.** The upper bounds below come from Bernstein's inequality
(Poisson) or from a gamma Chernoff bound composed with the Poisson one (negative binomial).
Both are loose when the mean ``mu`` of K is small: for ``mu = 0.01`` the bound is k = 14, where
P(K = k) = 1e-39 (Poisson, L = 20), and for ``mu = 1e-5`` P(K = 14) = 1e-81. In float32 the start
value then underflows and the whole sum (value and derivative) is lost. The float32 path
therefore also solves the exact Chernoff bound ``D(k) = L``, with the rate function

    Poisson:           D(k) = k log(k/mu) - k + mu,
    negative binomial: D(k) = k log1p(r d / (mu (k + r))) - r log1p(d / (mu + r)),  d = k - mu

(``P(K >= k) <= exp(-D(k))`` for ``k > mu``; the negative-binomial form is the Legendre
transform of its log moment generating function, written so that no large terms cancel). D is
convex and increasing for k > mu, so every Newton iterate after the first lies at or above the
root and is itself a valid bound; the smaller of it and the composite bound is used. Measured
in float32 against scipy over mu = 1e-5 ... 1e12 (Poisson and r = 1, 2, 20, 200, 2e4):
P(K > k_hi) <= exp(-22.8) and P(K = k_hi) >= exp(-52) = 2.6e-23. The float64 path keeps the
composite bounds for mu >= 1, whose start values stay above 9e-164 for mu >= 1e-5, and uses the
exact Chernoff bound below mu = 1, so that P(K = k_hi) stays representable at any SNR (the
required-SNR root finder resolves Pd - Pfa down to SNRs of -200 dB and below).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from diffsense.detection._logpmf import bd0
from diffsense.detection._precision import single_precision

__all__ = [
    "tail_exponent",
    "window_bounds",
    "poisson_quantile_bounds",
    "mixing_bounds",
    "tight_upper_bound",
]

# Truncation exponent: each omitted tail is below exp(-L).
_TAIL_L = 40.0
_TAIL_L_SINGLE = 20.0

# Newton steps of the tight float32 upper bound, from the composite bound (every iterate is a
# valid bound; see the module docstring for the measured result).
_TIGHT_STEPS = 6
# float64 uses the tight bound only below this mean of K (where the composite bound's start
# value would approach float64's range).
_TIGHT_MU_64 = 1.0


def tail_exponent(x) -> float:
    """Truncation exponent L for the precision of ``x`` (array or dtype): 40 (float64), 20 (float32)."""
    return _TAIL_L_SINGLE if single_precision(x) else _TAIL_L


def window_bounds(threshold, n, tail_l=None):
    """Integer window [j_lo, j_hi] of terms kept in the series (as floats).

    ``T - N - sqrt(2 L T) <= j <= T - N + L/3 + sqrt(L^2/9 + 2 L T)`` (Chernoff/Bernstein bounds
    of the Poisson(T) tails), L from :func:`tail_exponent` unless given (may be an array).
    """
    t = threshold
    if tail_l is None:
        tail_l = tail_exponent(t)
    right = tail_l / 3.0 + jnp.sqrt(tail_l**2 / 9.0 + 2.0 * tail_l * t)
    left = jnp.sqrt(2.0 * tail_l * t)
    j_hi = jnp.maximum(jnp.ceil(t - n + right), 0.0)
    j_lo = jnp.clip(jnp.floor(t - n - left), 0.0, j_hi)
    return j_lo, j_hi


def gamma_chernoff_factors(shape, tail_l):
    """Factors (u_lo, u_hi) with P(G < u_lo E[G]) and P(G > u_hi E[G]) each <= exp(-L) for G ~ Gamma(shape).

    The Chernoff bound of the gamma law is exp(-shape (u - 1 - log u)); both roots of
    u - log u = 1 + L/shape are found by Newton's method (convex, monotone from the start points).
    """
    a = tail_l / shape
    u = 1.0 + 2.0 * a + 2.0 * jnp.sqrt(a)
    v = jnp.maximum(-(1.0 + a), jnp.log(jnp.maximum(1.0 - jnp.sqrt(2.0 * a), 1e-300)))

    def step(_, uv):
        u, v = uv
        ev = jnp.exp(v)
        return u - (u - jnp.log(u) - 1.0 - a) / (1.0 - 1.0 / u), v - (ev - v - 1.0 - a) / (ev - 1.0)

    u, v = jax.lax.fori_loop(0, 8, step, (u, v))
    return jnp.exp(v), u


def poisson_quantile_bounds(lam, tail_l):
    """Integers (k_lo, k_hi) with P(Pois(lam) < k_lo), P(Pois(lam) > k_hi) <= exp(-L) (Chernoff/Bernstein)."""
    k_hi = jnp.ceil(lam + tail_l / 3.0 + jnp.sqrt(tail_l**2 / 9.0 + 2.0 * tail_l * lam))
    k_lo = jnp.maximum(jnp.floor(lam - jnp.sqrt(2.0 * tail_l * lam)), 0.0)
    return k_lo, k_hi


def tight_upper_bound(mu, r, k_start, tail_l):
    """Integer k >= mu with P(K > k) <= exp(-L) from the exact Chernoff bound, capped at ``k_start``.

    ``r`` is the negative-binomial shape, or None for a Poisson K; ``k_start`` (> mu) is a valid
    bound to start Newton's method from (see the module docstring).
    """
    def step(_, k):
        if r is None:
            rate = bd0(k, mu)
            slope = jnp.log(k / mu)
        else:
            d = k - mu
            slope = jnp.log1p(r * d / (mu * (k + r)))
            rate = k * slope - r * jnp.log1p(d / (mu + r))
        return k - (rate - tail_l) / slope

    # a loop, not unrolled steps: one copy of the rate in a compiled program
    k = jax.lax.fori_loop(0, _TIGHT_STEPS, step, jnp.asarray(k_start, dtype=jnp.result_type(k_start, mu)))
    return jnp.minimum(k_start, jnp.ceil(k))


def mixing_bounds(mu, r, tail_l):
    """Bounds (k_lo, k_hi) outside which the mixing variable K has mass <= 2 exp(-L) per side.

    ``r`` is the negative-binomial shape (None: Poisson). In single precision the upper bound is
    tightened by :func:`tight_upper_bound`.
    """
    if r is None:
        k_lo, k_hi = poisson_quantile_bounds(mu, tail_l)
    else:
        u_lo, u_hi = gamma_chernoff_factors(r, tail_l)
        k_lo, _ = poisson_quantile_bounds(mu * u_lo, tail_l)
        _, k_hi = poisson_quantile_bounds(mu * u_hi, tail_l)
    if single_precision(mu):
        k_hi = tight_upper_bound(mu, r, k_hi, tail_l)
    else:
        # float64: the composite bound's start value P(K = k_hi) underflows once the mean of K
        # is below about 1e-5 (e.g. SNR < -50 dB at N = 1), and Pd - Pfa would be lost; there
        # the exact Chernoff bound is used (double where: it is evaluated at mu = 1 elsewhere).
        # So it is wherever L exceeds its default: the root finder of required_snr raises L up
        # to ~600, where the composite bound underflowed already at mu ~ 1 (e.g. k_hi = 171 at
        # mu = 1.02, L = 250: P(K = k_hi) ~ e^-710, and Pd - Pfa summed to 0).
        small = (mu < _TIGHT_MU_64) | (jnp.asarray(tail_l) > _TAIL_L)
        mu_s = jnp.where(small, mu, 1.0)
        k_tight = tight_upper_bound(mu_s, r, jnp.where(small, k_hi, 1e3), tail_l)
        k_hi = jnp.where(small, k_tight, k_hi)
    return k_lo, k_hi
