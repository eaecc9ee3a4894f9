"""Binomial law and one trial of M-of-N binary integration (the independent-trial part of
:mod:`diffsense.detection.binary`, whose docstring states the model, sources and accuracy).

``B(p) = P(Bin(N, p) >= M)`` summed term by term from Loader's saddle-point binomial probabilities,
its inverse (safeguarded Newton in log p, implicit derivative ``dp = d target / B'(p)``), the
per-trial probability of one pulse or CPI at a threshold, and ``Pd = B(p_d(S))`` for targets whose
trials are independent (Swerling 0, 2, 4).
"""

from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp
from jax.scipy.special import gammaln

from diffsense.detection._gamma import log_gamma_pq
from diffsense.detection._logpmf import log_binomial_pmf, log_poisson_pmf
from diffsense.detection.core import _chunked, _mixture_sum

#: largest number of trials N (the binomial sums have N_MAX + 1 terms)
N_MAX = 100
_TERMS = N_MAX + 1
_LEVEL_MAX_ITER = 100




def _binomial_pmf(k, size, p, q):
    """P(Bin(size, p) = k), 0 outside 0 <= k <= size (q = 1 - p, given for its accuracy)."""
    ok = (k >= 0) & (k <= size)
    kk = jnp.where(ok, k, 0.0)
    ss = jnp.where(ok, size, 0.0)
    tiny = jnp.finfo(jnp.result_type(p)).tiny
    val = log_binomial_pmf(kk, ss, jnp.clip(p, tiny, 1.0), jnp.clip(q, tiny, 1.0))
    return jnp.where(ok, jnp.exp(val), 0.0)


def _binomial_tails(p, q, n, m):
    """(P(Bin(n, p) >= m), P(Bin(n, p) < m)), each a sum of positive terms."""
    k = jnp.arange(_TERMS, dtype=jnp.result_type(p))
    pmf = _binomial_pmf(k, n[..., None], p[..., None], q[..., None])
    upper = jnp.sum(jnp.where(k >= m[..., None], pmf, 0.0), axis=-1)
    lower = jnp.sum(jnp.where(k < m[..., None], pmf, 0.0), axis=-1)
    return upper, lower


def _tail_slope(p, q, n, m):
    """d/dp P(Bin(n, p) >= m) = n P(Bin(n-1, p) = m-1) (the Beta(m, n-m+1) density)."""
    return n * _binomial_pmf(m - 1.0, n - 1.0, p, q)


def _solve_log_level(log_target, n, m):
    """u = log p with P(Bin(n, p) >= m) = exp(log_target) (elementwise; safeguarded Newton in u).

    Bracket: C(n, m) p^m >= P(Bin(n, p) >= m) >= p^n, so the root lies in
    [(log_target - log C(n, m)) / m, log_target / n]; Newton steps that leave the current bracket
    are replaced by bisection.
    """
    log_c = gammaln(n + 1.0) - gammaln(m + 1.0) - gammaln(n - m + 1.0)
    lo = (log_target - log_c) / m - 1e-12 * jnp.abs(log_target)
    hi = jnp.minimum(log_target / n, 0.0)

    def body(s):
        u, lo, hi, _, it = s
        p = jnp.exp(u)
        q = -jnp.expm1(u)
        up, _ = _binomial_tails(p, q, n, m)
        r = jnp.log(up) - log_target
        slope = m * _binomial_pmf(m, n, p, q) / up  # d log B / d u
        lo = jnp.where(r < 0, u, lo)
        hi = jnp.where(r < 0, hi, u)
        u_new = u - r / slope
        ok = jnp.isfinite(u_new) & (u_new >= lo) & (u_new <= hi)
        u_new = jnp.where(ok, u_new, 0.5 * (lo + hi))
        u_new = jnp.where(r == 0, u, u_new)
        return u_new, lo, hi, jnp.abs(u_new - u), it + 1

    def cond(s):
        tol = 4.0 * jnp.finfo(s[0].dtype).eps * jnp.maximum(jnp.abs(s[0]), 1.0)
        return (s[4] < _LEVEL_MAX_ITER) & jnp.any(s[3] > tol)

    init = (lo, lo, hi, jnp.full_like(lo, jnp.inf), 0)
    return jax.lax.while_loop(cond, body, init)[0]


@jax.custom_jvp
def _binomial_level(target, n, m):
    """(p, 1 - p) with P(Bin(n, p) >= m) = target, the smaller of the two to full relative accuracy.

    Targets above 1/2 are solved through the complement, P(Bin(n, 1 - p) >= n - m + 1) = 1 - target,
    so that 1 - p keeps its digits when p is near 1. Both problems go through one loop (stacked).
    """
    low = target <= 0.5
    log_t = jnp.stack([jnp.log(jnp.where(low, target, 0.25)), jnp.log1p(-jnp.where(low, 0.75, target))])
    u = _solve_log_level(log_t, jnp.stack([n, n]), jnp.stack([m, n - m + 1.0]))
    p = jnp.where(low, jnp.exp(u[0]), -jnp.expm1(u[1]))
    q = jnp.where(low, -jnp.expm1(u[0]), jnp.exp(u[1]))
    return p, q


@_binomial_level.defjvp
def _binomial_level_jvp(primals, tangents):
    target, n, m = primals
    p, q = _binomial_level(target, n, m)
    dp = tangents[0] / _tail_slope(p, q, n, m)  # implicit: dB/dp dp = d target
    return (p, q), (dp, -dp)


# --------------------------------------------------------------------------------------
# one trial
# --------------------------------------------------------------------------------------


def _trial(x, t, n_p, q0, swerling):
    """Per-trial (p, 1 - p, dp/dx, dp/dT) at per-pulse SNR x (linear) and threshold T."""
    x, t, n_p, q0 = jnp.broadcast_arrays(x, t, n_p, q0)
    x = jnp.clip(x, 1e-30, 1e30)
    if swerling == 2:
        # every pulse exponential with mean 1 + x: p = Q(n_p, T / (1 + x)) (closed form)
        y = t / (1.0 + x)
        log_miss, log_p = log_gamma_pq(n_p, y)
        density = jnp.exp(log_poisson_pmf(n_p - 1.0, y))  # Gamma(n_p, 1) density at y
        p, miss = jnp.exp(log_p), jnp.exp(log_miss)
        p_x, p_t = density * y / (1.0 + x), -density / (1.0 + x)
    else:
        p, _, miss, (p_x, p_t, _) = _chunked(
            lambda *a: _mixture_sum(*a, swerling, with_partials="snr_t"), x, t, n_p, q0)
    # one consistent pair: the smaller of p and 1 - p as computed (full relative accuracy), the
    # other as its complement (so that the binomial terms sum to 1)
    high = miss < 0.5
    return jnp.where(high, 1.0 - miss, p), jnp.where(high, miss, 1.0 - p), p_x, p_t


@partial(jax.custom_jvp, nondiff_argnums=(6,))
def _pd_independent(x, t, n_p, q0, n, m, swerling):
    p, q, _, _ = _trial(x, t, n_p, q0, swerling)
    return _tail_value(p, q, n, m)


def _tail_value(p, q, n, m):
    """P(Bin(n, p) >= m) from the smaller of its two tail sums (so never above 1)."""
    upper, lower = _binomial_tails(p, q, n, m)
    return jnp.where(lower < 0.5, 1.0 - lower, upper)


@_pd_independent.defjvp
def _pd_independent_jvp(swerling, primals, tangents):
    x, t, n_p, q0, n, m = primals
    dx, dt = tangents[:2]
    p, q, p_x, p_t = _trial(x, t, n_p, q0, swerling)
    slope = _tail_slope(p, q, n, m)
    return _tail_value(p, q, n, m), slope * (p_x * dx + p_t * dt)


# --------------------------------------------------------------------------------------
# shared RCS (Swerling 1, 3): quadrature over the log-SNR grid
