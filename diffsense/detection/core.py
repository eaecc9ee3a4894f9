"""Exact detection probability of the noncoherently integrated square-law detector.

Model (Brooker ch. 9; DiFranco & Rubin, *Radar Detection*, 1968; Shnidman, IEEE T-AES 1998):
N pulses of a square-law detector are summed; noise is normalised so that under noise alone
the sum is ``Y ~ Gamma(N, 1)``, and the threshold ``T`` gives ``Pfa = Q(N, T)``. ``S`` is the
mean signal-to-noise ratio of one pulse and ``mu = N S`` the mean total SNR.

**One representation for every Swerling case.** Conditioned on the target's fluctuation the
integrated statistic is a Poisson mixture of gamma laws, so in all cases

    Y ~ Gamma(N + K, 1),   Pd = sum_k P(K = k) Q(N + k, T),

where ``K`` is Poisson(mu) for a steady target (Swerling 0/5) and negative binomial with shape
``r`` and mean ``mu`` for a chi-square target with 2r degrees of freedom: r = 1 (Swerling 1),
r = N (Swerling 2), r = 2 (Swerling 3), r = 2N (Swerling 4). (The negative binomial is the
Poisson mixture over a gamma-distributed total signal energy.) Writing
``Q(N+k, T) = Q(N, T) + sum_{j<k} pois(N + j; T)`` with ``pois(m; T) = T^m e^-T / Gamma(m+1)``
and exchanging the sums gives

    Pd = Pfa + sum_{j >= 0} pois(N + j; T) * P(K > j).                                    (1)

The weights ``pois(N+j; T)`` are concentrated within a few sqrt(T) of ``j = T - N`` whatever
the SNR, so (1) is summed over the window ``T - N - sqrt(2 L T) <= j <= T - N + L/3 +
sqrt(L^2/9 + 2 L T)`` (Chernoff/Bernstein bounds of the Poisson tails, :mod:`._bounds`), which
bounds the truncation error by ``2 exp(-L)`` with L = 40 in float64, i.e. 8.5e-18 absolute
(L = 20 in float32: 4.1e-9). The number of terms grows like sqrt(T), not with the SNR. DOWN
walks (below) go on under the window to j = 0, because an absolute bound is not enough for
them: when K's mean is small the terms ``pois(N+j; T) P(K > j)`` peak at the smallest j, and
Pd - Pfa (down to 1e-300) must keep its relative accuracy. This costs steps only where the
window starts above 0, i.e. for T - N > sqrt(2 L T) (Pfa below ~1e-35 at N = 1, ~4e-18 at
N = 1e4).

**Two directions, two small quantities.** When K's mean lies below the window centre T - N
plus one standard deviation sqrt(T) of the weights (Pd <~ 0.8), the survival ``P(K > j)`` is accumulated downward from the top of K's range
(``P(K > j-1) = P(K > j) + P(K = j)``), a sum of positive terms, so ``Pd - Pfa`` keeps full
relative accuracy even when it is tiny (low SNR and Pfa down to 1e-300). The start value is
the probability at an upper quantile bound of K (Swerling 1/3: the closed-form survival).
Otherwise (Pd >~ 0.8) the CDF ``P(K <= j)`` is accumulated upward from a lower
quantile bound of K, and the same series gives the miss probability directly,

    1 - Pd = P(Y <= T) = sum_{j >= 0} pois(N + j; T) P(K <= j),                           (2)

with full relative accuracy however close Pd is to 1 (within 1e-12 and beyond), and without
the term Q(N, T): neither the threshold's rounding nor the cancellation of ``dQ/dN`` against
the series enters it. ``required_snr`` solves on the logarithm of the small one of the two.

``N`` may be real: (1) is the noncentral gamma law with real shape, equal to the exact result
at integers and smooth in between.

**Derivatives** are analytic (a ``jax.custom_jvp``), accumulated in the same loop:

* ``dPd/dmu = sum_j pois(N+j; T) P(K = j) (j + r)/(r + mu)`` (Poisson: factor 1),
* ``dPd/dT = -sum_j pois(N+j-1; T) P(K = j)`` (minus the density of Y at T),
* ``dPd/dN`` from the explicit N in ``pois`` (digamma), from ``mu = N S``, from
  ``dQ(N,T)/dN`` (DOWN; UP differentiates (2) instead, which has no Q term, so that the
  derivative does not arise as the difference of two O(1) numbers when Pd is near 1) and, for
  Swerling 4, from the shape r = 2N (through the digamma-weighted negative-binomial CDF).

Swerling 2 has the closed form ``Pd = Q(N, T/(1+S))`` because every pulse is an exponential
with mean 1+S; it is used directly (``_gamma.gamma_q``, accurate to ~1e-15 relative at N = 1e4).

**Domain.** ``pd_given_threshold`` accepts S >= 0 (clipped to [1e-30, 1e30], beyond which Pd is
Pfa or 1 to float64 precision; float32: [1e-15, 1e15]), 0 < T < inf and 1 <= N < inf: an
eager call outside raises DomainError, a traced call returns NaN (``_domain``).

**float32** (``DIFFSENSE_X64=0``, inputs float32). The float64 program is unchanged (the
choices below are made at trace time from the dtype); in float32 the loop differs in four ways,
each removing an error that float64 hides:

* truncation at L = 20 and the exact Chernoff upper bound of K (:mod:`._bounds`): with the
  float64 bounds the start value P(K = k_hi) fell below float32's smallest normal number
  (1.2e-38) whenever the mean of K was below about 1, and the whole sum was lost (Pd = Pfa:
  errors of 3e-3 to 2.4e-2 at N = 1-10 and low SNR);
* start values from cancellation-free special functions (``_logpmf``; the negative-binomial
  probability from its mean, ``log_negbin_pmf_mean``);
* negative-binomial ratios without the rounded constants 1/q and q, whose rounding repeats at
  every step;
* the weights rescaled at their mode. They all derive by recursion from the start weight
  ``exp(log pois)`` at a window edge (log about -25, rounded to a few 1e-6 relative); at the mode
  the logarithm is only ``-log(2 pi T)/2`` and accurate to a few 1e-7. So that every walk passes
  the mode, DOWN walks begin at the window top.

Measured against mpmath (``benchmarks/float32_accuracy.py``, tests/test_detection_float32.py):
|error| <= 4e-6 for Swerling 0, 1, 3, 4 at N = 1-100, Pfa 1e-3-1e-10, SNR -5...25 dB; Swerling 2
and the threshold are limited by the float32 accuracy of ``jax.scipy.special.gammaincc``
(7e-6 at N = 100; its relative error grows to 5e-4 at N = 1000).

**Fast path.** For Swerling 0/5 with one threshold and pulse count for all elements (scalar
``T`` and ``N``, e.g. Pd over an SNR grid at fixed Pfa), the value comes from
:mod:`diffsense.detection.steady`, which sums the same series (1) with a loop index shared by
the elements of a chunk, a scalar weight recursion and a choice of direction that keeps every
element inside the window (about 5 times faster than this module's loop at N = 10). Its
derivatives are the analytic partials of this module. Array thresholds, the other Swerling
cases, derivatives and the root finder of ``required_snr`` use the loop below.
"""

from __future__ import annotations

from functools import partial

import jax
from jax.custom_derivatives import SymbolicZero
import jax.numpy as jnp
from jax.scipy.special import digamma, gammaincc

import numpy as np

from diffsense.detection._bounds import mixing_bounds, tail_exponent, window_bounds
from diffsense.detection._domain import admit, guard
from diffsense.detection._gamma import gamma_q
from diffsense.detection._logpmf import log_negbin_pmf, log_negbin_pmf_mean, log_poisson_pmf
from diffsense.detection._precision import single_precision
from diffsense.detection.steady import steady_pd

__all__ = ["pd_given_threshold", "SWERLING_CASES", "window_bounds"]

SWERLING_CASES = (0, 1, 2, 3, 4, 5)


def _shape(swerling, n):
    """Negative-binomial shape r for the chi-square cases (None: Poisson)."""
    if swerling in (0, 5):
        return None
    if swerling == 1:
        return jnp.ones_like(n)
    if swerling == 3:
        return 2.0 * jnp.ones_like(n)
    if swerling == 4:
        return 2.0 * n
    raise ValueError(f"no mixture shape for swerling={swerling}")


def _log_pmf(swerling, k, mu, r, log_q, log_1mq):
    if r is None:
        return log_poisson_pmf(k, mu)
    if swerling == 1:
        return log_1mq + k * log_q
    if swerling == 3:
        return jnp.log1p(k) + 2.0 * log_1mq + k * log_q
    if single_precision(mu):
        return log_negbin_pmf_mean(k, r, mu)
    return log_negbin_pmf(k, r, jnp.exp(log_q))


def _closed_survival(swerling, m, log_q, log_1mq):
    """P(K >= m) in closed form for Swerling 1 (geometric) and 3 (negative binomial, r = 2)."""
    if swerling == 1:
        return jnp.exp(m * log_q)
    return jnp.exp(m * log_q) * (1.0 + m * jnp.exp(log_1mq))


def _walk_start(swerling, mu, r, t, n, tail_l, log_q, log_1mq):
    """Window, direction and start point of the recursion (see ``_mixture_sum``)."""
    j_lo, j_hi = window_bounds(t, n, tail_l)
    k_lo, k_hi = mixing_bounds(mu, r, tail_l)
    # Direction. UP when K's mean lies a standard deviation sqrt(T) of the weights above the
    # centre T - N of the window (Pd >~ 0.8, Pd - Pfa not small): the CDF F(j) = P(K < j) is
    # summed upward from k_lo, where it is below exp(-L), so that the miss probability
    # 1 - Pd = sum_j pois(N + j; T) P(K <= j) is a sum of positive terms with full relative
    # accuracy, however close Pd is to 1. DOWN otherwise: P(K > j) is summed downward from k_hi,
    # where it is below exp(-L) (Swerling 1/3: exact closed form at the start), so that Pd - Pfa
    # keeps full relative accuracy when it is tiny (UP would form it as 1 - P(K <= j), which
    # cancels when K's mean is tiny, e.g. at Pfa = 0.5 where T - N < 0). Both walk only from a
    # quantile bound of K to the window. When all of K's mass lies above the window
    # (k_lo > j_hi), P(K > j) = 1 on it, (1) sums to 1 - Pfa and no step is taken.
    above = k_lo > j_hi
    up = (mu > t - n + jnp.sqrt(t)) & ~above
    if swerling in (1, 3):
        j_down = jnp.minimum(k_hi, j_hi)
        surv0 = jnp.where(up, 0.0, _closed_survival(swerling, j_down + 1.0, log_q, log_1mq))
    else:
        j_down = k_hi
        surv0 = jnp.zeros_like(mu)  # DOWN: P(K > k_hi) ~ 0; UP: F(k_lo) ~ 0
    # K's recursion starts at j_start (P(K = j) is taken as 0 on the loop's way to it). UP loops
    # begin at the lower of k_lo and the window bottom, so that every window term is visited
    # (P(K > j) = 1 below k_lo); starting K's recursion at the window bottom instead would start
    # it from a probability that may underflow (P(K = 0) = e^-mu).
    j_start = jnp.where(up, k_lo, j_down)
    j_loop = jnp.where(up, jnp.minimum(k_lo, j_lo), j_down)
    j_start = jnp.where(above, j_lo - 1.0, j_start)
    j_loop = jnp.where(above, j_lo - 1.0, j_loop)
    return j_lo, j_hi, above, up, j_start, j_loop, surv0


def _ratios(j, mu, r, q_, inv_q, single):
    """P(K = j-1)/P(K = j) (DOWN) and P(K = j+1)/P(K = j) (UP)."""
    if r is None:
        return j / mu, mu / (j + 1.0)  # quotients, for the reason given at pois_next
    if single:
        # float32: no rounded constant (1/q, q) in the ratio, whose rounding (up to 6e-8)
        # would repeat at every step: 250 steps at N = 1 drift P(K = j) by 1.5e-5.
        return (j * mu + j * r) / ((j - 1.0 + r) * mu), ((j + r) * mu) / ((j + 1.0) * mu + (j + 1.0) * r)
    return j / (j - 1.0 + r) * inv_q, (j + r) / (j + 1.0) * q_


def _mixture_sum(snr, t, n, q0, swerling, with_partials, tail_l=None):
    """Evaluate (1), the miss probability 1 - Pd and, optionally, partial derivatives of Pd.

    ``with_partials``: False, True (w.r.t. snr, t, n), "snr_t" (w.r.t. snr and t: where n is
    not differentiated; dPd/dn needs the order derivative of Q(n, T), which JAX cannot
    differentiate again) or "snr" (only dPd/dsnr, for root finding). ``tail_l``: truncation exponent L (default :func:`tail_exponent`); the root finder
    of ``required_snr`` raises it so that the truncation stays below its target's accuracy.
    Returns ``(pd, excess, miss, partials)``: ``excess = Pd - Pfa`` as summed (full relative
    accuracy on DOWN walks), ``miss = 1 - Pd`` summed directly on UP walks (1 - pd on DOWN
    walks, where Pd <~ 1/2).
    """
    want_snr = bool(with_partials)
    want_t = with_partials is True or with_partials == "snr_t"
    want_n = with_partials is True
    mu = n * snr
    r = _shape(swerling, n)
    if tail_l is None:
        tail_l = tail_exponent(mu)
    if r is None:
        log_q = jnp.zeros_like(mu)
        log_1mq = jnp.zeros_like(mu)
    else:
        log_q = -jnp.log1p(r / mu)
        log_1mq = -jnp.log1p(mu / r)
    j_lo, j_hi, above, up, j_start, j_loop, surv0 = _walk_start(swerling, mu, r, t, n, tail_l, log_q, log_1mq)
    down = ~up
    pmf0 = jnp.exp(_log_pmf(swerling, j_start, mu, r, log_q, log_1mq))
    single = single_precision(mu)
    if single:
        # float32: DOWN walks start at the window top even when K's recursion starts lower (its
        # P(K = j) is 0 until j reaches j_start), so that every walk passes the anchor j_mode
        # of the weights (see the end of this function).
        j_loop = jnp.where(down & ~above, jnp.maximum(j_start, j_hi), j_loop)
        j_mode = jnp.clip(jnp.floor(t - n), j_lo, j_hi)
    # DOWN walks continue below the window to j = 0: the window holds the weights' mass to
    # exp(-L) absolutely, but when K's mean is small the terms of Pd - Pfa lie at the smallest j
    # (w_j P(K > j) peaks at j = 0 when N S T < 2N), so that stopping at the window bottom lost
    # all of Pd - Pfa once it fell below exp(-L) (Pfa < ~1e-35 at N = 1).
    j_floor = jnp.where(down & ~above, 0.0, j_lo)
    pmf_init = jnp.where(j_loop == j_start, pmf0, 0.0)
    j_first = jnp.clip(j_loop, j_floor, j_hi)
    pois0 = jnp.exp(log_poisson_pmf(n + j_first, t))
    inv_q = jnp.exp(-log_q)
    q_ = jnp.exp(log_q)
    inv_t = 1.0 / t
    zeros = jnp.zeros_like(t)

    state = dict(j=j_loop, pois=pois0, pmf=pmf_init, surv=surv0, acc=jnp.where(above, 1.0 - q0, 0.0), miss=zeros)
    if single:
        state["pois_mode"] = zeros
    if want_snr:
        state["d_mu"] = zeros
    if want_t:
        state["d_t"] = zeros
    if want_n:
        state.update(d_n=zeros, psi=digamma(n + j_first + 1.0))
    log_t = jnp.log(t)

    def cond(s):
        j = s["j"]
        return jnp.any(jnp.where(down, j >= j_floor, j <= j_hi))

    def body(s):
        j = s["j"]
        live = jnp.where(down, j >= j_floor, j <= j_hi)
        inside = live & (j >= j_floor) & (j <= j_hi)
        pois_j = s["pois"]
        pmf_j = s["pmf"]
        # DOWN keeps P(K > j) in "surv"; UP keeps F(j) = P(K < j) there.
        cdf = s["surv"] + pmf_j  # UP: P(K <= j)
        tail = jnp.where(down, s["surv"], 1.0 - cdf)
        counted = inside
        if single:
            # Above K's start point (float32 DOWN walks begin at the window top) P(K > j) is
            # below exp(-L) and not summed, as in float64, whose walk begins at that point.
            counted = inside & (up | (j <= j_start))
        out = {"acc": s["acc"] + jnp.where(counted, pois_j * tail, 0.0)}
        out["miss"] = s["miss"] + jnp.where(inside & up, pois_j * cdf, 0.0)
        if want_snr:
            weight = 1.0 if r is None else (j + r) / (r + mu)
            out["d_mu"] = s["d_mu"] + jnp.where(inside, pois_j * pmf_j * weight, 0.0)
        if want_t:
            out["d_t"] = s["d_t"] + jnp.where(inside, pois_j * ((n + j) * inv_t) * pmf_j, 0.0)
        if want_n:
            # dPd/dN at fixed T and mu: DOWN sum_j w'_j P(K > j) + dQ(N, T)/dN (added at the
            # end); UP -sum_j w'_j P(K <= j), the derivative of minus the miss probability,
            # which needs no dQ/dN and so does not cancel when Pd is near 1.
            factor = jnp.where(down, tail, -cdf)
            out["d_n"] = s["d_n"] + jnp.where(counted, pois_j * (log_t - s["psi"]) * factor, 0.0)
            psi_next = jnp.where(down, s["psi"] - 1.0 / (n + j), s["psi"] + 1.0 / (n + j + 1.0))
            out["psi"] = jnp.where(inside, psi_next, s["psi"])
        ratio_down, ratio_up = _ratios(j, mu, r, q_, inv_q, single)
        # Quotients, not products with a precomputed 1/t: the rounding error of 1/t would repeat
        # at every step and drift the weights by up to (steps) x 1.1e-16 (2e-13 over the
        # ~2000-term windows at N ~ 1e4); correctly rounded quotients do not accumulate a bias.
        pois_next = jnp.where(down, pois_j * ((n + j) / t), pois_j * (t / (n + j + 1.0)))
        out["surv"] = jnp.where(live, s["surv"] + pmf_j, s["surv"])
        pmf_next = pmf_j * jnp.where(down, ratio_down, ratio_up)
        pmf_next = jnp.where(jnp.where(down, j - 1.0, j + 1.0) == j_start, pmf0, pmf_next)
        if single:
            out["pois_mode"] = jnp.where(j == j_mode, pois_j, s["pois_mode"])
        out["pmf"] = jnp.where(live, pmf_next, pmf_j)
        out["pois"] = jnp.where(inside, pois_next, pois_j)
        out["j"] = jnp.where(down, j - 1.0, j + 1.0)
        return out

    s = jax.lax.while_loop(cond, body, state)
    if single:
        s = _rescale_at_mode(s, log_poisson_pmf(n + j_mode, t), above)
    pd = jnp.clip(q0 + s["acc"], 0.0, 1.0)
    miss = jnp.where(up, s["miss"], jnp.where(above, 0.0, 1.0 - pd))
    excess = s["acc"]
    if not want_snr:
        return pd, excess, miss, None
    d_snr = n * s["d_mu"]
    if not want_t:
        return pd, excess, miss, (d_snr, None, None)
    d_t = -s["d_t"]
    if not want_n:
        return pd, excess, miss, (d_snr, d_t, None)
    _, dq_dn = jax.jvp(lambda a: gammaincc(a, t), (n,), (jnp.ones_like(n),))
    # UP and above the window the Q(n, T) term is not part of the derivative (see body); above,
    # Pd = 1 - O(e^-L) whatever n.
    d_n = s["d_n"] + jnp.where(above | up, 0.0, dq_dn) + snr * s["d_mu"]
    if swerling == 4:
        d_n = d_n + 2.0 * _negbin_shape_partial(t, n, mu, r, log_q, j_hi, down & ~above, j_start)
    return pd, excess, miss, (d_snr, d_t, d_n)


def _rescale_at_mode(s, log_pois_mode, above):
    """float32: rescale the sums by the exact weight at the mode over the recursion's value there.

    The weights pois(N + j; T) all derive from the start weight at a window edge, the
    exponential of a log-probability of about -25 whose rounding (a few ulp of 25, i.e. a few
    1e-6) scales every term. At the mode of the weights (j = T - N) the log-probability is only
    -log(2 pi T)/2, so its exponential is accurate to a few 1e-7: rescaling by the ratio of that
    value to the recursion's value there removes the common factor.
    """
    ok = ~above & (s["pois_mode"] > 0.0)
    scale = jnp.where(ok, jnp.exp(log_pois_mode) / jnp.where(ok, s["pois_mode"], 1.0), 1.0)
    return {k: (v * scale if k in ("acc", "miss", "d_mu", "d_t", "d_n") else v) for k, v in s.items()}


def _negbin_shape_partial(t, n, mu, r, log_q, j_hi, from_top, k_top):
    """d Pd / d r at fixed mean mu for the negative-binomial mixture (Swerling 4).

    With D(m) = sum_{k<m} P(K=k) w(k), w(k) = d log P(K=k)/dr = psi(k+r) - psi(r) + log(1-q),
    the derivative of the survival at fixed q is dP(K>=m)/dr = -D(m); at fixed mu, q moves too:
    dP(K>=m)/dr|_mu = -D(m) - P(K=m-1)(m-1+r) q / r, and d Pd/dr = sum_j pois(N+j; T) of that
    at m = j + 1.

    Since sum_k P(K=k) w(k) = d/dr 1 = 0, D(m) is also -sum_{k>=m} P(K=k) w(k). Which sum is
    accurate depends on where K's mass lies: summed from k = 0 (``from_top`` False: UP walks,
    where Pd is near 1 and D(m) below K's mass is the small quantity), or from ``k_top`` downward
    with D(k_top + 1) = 0 (``from_top`` True: DOWN walks, where K's mass is at small k and the
    sum from 0 forms the tiny D(m) of large m as a difference of O(mu) terms: an absolute error
    of ~1e-19 that swamped dPd/dN when Pd - Pfa is below ~1e-17). The window walk goes on below
    the window to j = 0, as in ``_mixture_sum``.
    """
    q = jnp.exp(log_q)
    log_1mq = -jnp.log1p(mu / r)
    psi_r = digamma(r)

    def up_cond(s):
        return jnp.any((s["k"] <= j_hi) & ~from_top)

    def up_body(s):
        k = s["k"]
        active = (k <= j_hi) & ~from_top
        pmf = jnp.exp(s["log_pmf"])
        w = s["psi"] - psi_r + log_1mq
        return dict(
            k=k + 1.0,
            big_d=s["big_d"] + jnp.where(active, pmf * w, 0.0),
            log_pmf=jnp.where(active, s["log_pmf"] + jnp.log(k + r) - jnp.log(k + 1.0) + log_q, s["log_pmf"]),
            psi=jnp.where(active, s["psi"] + 1.0 / (k + r), s["psi"]),
        )

    zeros = jnp.zeros_like(t)
    up = jax.lax.while_loop(
        up_cond, up_body, dict(k=zeros, big_d=zeros, log_pmf=r * log_1mq, psi=psi_r)
    )
    # from the bottom: up["big_d"] = D(j_hi + 1); from the top: D(k_top + 1) = 0
    j_top = jnp.where(from_top, jnp.maximum(k_top, j_hi), j_hi)

    def down_cond(s):
        return jnp.any(s["j"] >= 0.0)

    def down_body(s):
        j = s["j"]
        active = j >= 0.0
        counted = active & (j <= j_hi)
        pmf_j = jnp.exp(s["log_pmf"])
        dsurv = -s["big_d"] - pmf_j * (j + r) * q / r  # d P(K >= j+1) / dr at fixed mu
        psi_jr = s["psi"] - 1.0 / (j + r)  # psi(j + r)
        w_j = psi_jr - psi_r + log_1mq
        jm = jnp.maximum(j, 1.0)
        return dict(
            j=j - 1.0,
            acc=s["acc"] + jnp.where(counted, s["pois"] * dsurv, 0.0),
            big_d=jnp.where(active, s["big_d"] - pmf_j * w_j, s["big_d"]),
            psi=jnp.where(active, psi_jr, s["psi"]),
            log_pmf=jnp.where(active, s["log_pmf"] + jnp.log(jm) - jnp.log(jm - 1.0 + r) - log_q, s["log_pmf"]),
            pois=jnp.where(counted, s["pois"] * ((n + j) / t), s["pois"]),
        )

    start = dict(
        j=j_top,
        acc=zeros,
        big_d=jnp.where(from_top, 0.0, up["big_d"]),
        psi=jnp.where(from_top, digamma(j_top + 1.0 + r), up["psi"]),
        log_pmf=log_negbin_pmf(j_top, r, q),
        pois=jnp.exp(log_poisson_pmf(n + jnp.minimum(j_top, j_hi), t)),
    )
    down = jax.lax.while_loop(down_cond, down_body, start)
    return down["acc"]


# Elements per chunk: the recursion state of a chunk (a few arrays of this length) stays in
# the CPU cache, and each chunk iterates only as long as its own widest window needs.
_CHUNK = 2048


def _chunked(fn, *arrays):
    """Apply an elementwise array function chunk by chunk (``lax.map``) over broadcast inputs."""
    shape = arrays[0].shape
    size = arrays[0].size
    if size <= _CHUNK:
        return fn(*arrays)
    pad = (-size) % _CHUNK
    flat = [jnp.concatenate([a.reshape(-1), jnp.broadcast_to(a.reshape(-1)[:1], (pad,))]) for a in arrays]
    rows = [f.reshape(-1, _CHUNK) for f in flat]
    out = jax.lax.map(lambda xs: fn(*xs), tuple(rows))
    return jax.tree_util.tree_map(lambda o: o.reshape(-1)[:size].reshape(shape), out)


@partial(jax.custom_jvp, nondiff_argnums=(4,))
def _pd_mixture(snr, t, n, q0, swerling):
    return _chunked(lambda *a: _mixture_sum(*a, swerling, with_partials=False)[0], snr, t, n, q0)


def _tangent(partials, dots):
    """Σ partial · tangent over the tangents that are not symbolic zeros."""
    total = None
    for p, d in zip(partials, dots):
        if p is None or isinstance(d, SymbolicZero):
            continue
        total = p * d if total is None else total + p * d
    return total


def _partials_mode(d_n_dot) -> object:
    """The partials a JVP needs: all, or without dPd/dn where n is not differentiated."""
    return "snr_t" if isinstance(d_n_dot, SymbolicZero) else True


def _pd_mixture_jvp(swerling, primals, tangents):
    snr, t, n, q0 = primals
    d_snr_dot, d_t_dot, d_n_dot, _ = tangents  # q0 is Q(n, t): its tangent follows from t, n
    mode = _partials_mode(d_n_dot)
    pd, _, _, partials = _chunked(lambda *a: _mixture_sum(*a, swerling, with_partials=mode), snr, t, n, q0)
    tangent = _tangent(partials, (d_snr_dot, d_t_dot, d_n_dot))
    return pd, jnp.zeros_like(pd) if tangent is None else tangent


_pd_mixture.defjvp(_pd_mixture_jvp, symbolic_zeros=True)


@jax.custom_jvp
def _pd_steady(snr, t, n, q0):
    """Swerling 0 Pd for scalar (t, n, q0): value from the fast kernel ``steady.steady_pd``."""
    return steady_pd(snr, t, n, q0)


def _pd_steady_jvp(primals, tangents):
    # Derivatives (and the value returned with them) come from the general kernel, whose
    # analytic partials are accumulated in the same loop.
    snr, t, n, q0 = primals
    d_snr_dot, d_t_dot, d_n_dot, _ = tangents
    t_b, n_b, q0_b = (jnp.broadcast_to(a, snr.shape) for a in (t, n, q0))
    mode = _partials_mode(d_n_dot)
    pd, _, _, partials = _chunked(lambda *a: _mixture_sum(*a, 0, with_partials=mode), snr, t_b, n_b, q0_b)
    tangent = _tangent(partials, (d_snr_dot, d_t_dot, d_n_dot))
    return pd, jnp.zeros_like(pd) if tangent is None else tangent


_pd_steady.defjvp(_pd_steady_jvp, symbolic_zeros=True)


def pd_given_threshold(snr_linear, threshold, n, swerling=0, *, pfa=None):
    """Detection probability for a threshold on the integrated statistic.

    Args:
        snr_linear: mean single-pulse SNR S (linear power ratio, >= 0; S = 0 gives Pfa and
            S = inf gives 1, the limits, which hold to float64 precision beyond 1e-30 and
            1e30, where S is clipped).
        threshold: threshold T on Y (units of the mean noise power of one pulse, 0 < T < inf).
        n: pulses integrated noncoherently (real, 1 <= n < inf).
        swerling: 0 (=5), 1, 2, 3 or 4 (static).
        pfa: optional ``Q(n, T)`` when already known (saves one incomplete-gamma evaluation
            and keeps the false-alarm probability bit-exact); its derivative is taken from T
            and n.

    Returns:
        Pd, exact to float64 round-off (see module docstring for the method). Outside the
        domain an eager call raises DomainError and a traced call returns NaN.

    One pulse: a Swerling 1 echo power is exponential with mean 1 + S, so Pd = exp(-T/(1+S)):

    >>> import math
    >>> float(pd_given_threshold(10.0, 13.8, 1, swerling=1)), math.exp(-13.8 / 11.0)
    (0.285205, 0.285205)
    """
    if swerling not in SWERLING_CASES:
        raise ValueError(f"swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    dtype = jnp.result_type(snr_linear, threshold, n, float)
    snr, t, n = (jnp.asarray(a, dtype=dtype) for a in (snr_linear, threshold, n))
    ok, each = admit("pd_given_threshold", [
        ("snr_linear", snr, 0.0, None),
        ("threshold", t, 0.0, np.inf, True, True),
        ("n", n, 1.0, np.inf, False, True),
    ])
    snr, t, n = (guard(a, m, 1.0) for a, m in zip((snr, t, n), each))
    lim = 1e15 if single_precision(snr) else 1e30  # +-150 / +-300 dB (probability.saturation_db)
    snr = jnp.clip(snr, 1.0 / lim, lim)
    return guard(_pd_given_threshold(snr, t, n, swerling, pfa), ok)


def _pd_given_threshold(snr, t, n, swerling, pfa):
    """:func:`pd_given_threshold` for admitted arrays of one dtype (no checks)."""
    dtype = snr.dtype
    if swerling in (0, 5) and t.size == 1 and n.size == 1 and (pfa is None or jnp.size(pfa) == 1):
        # One threshold for all elements (e.g. an SNR grid at fixed Pfa and N): fast kernel.
        shape = jnp.broadcast_shapes(snr.shape, t.shape, n.shape, jnp.shape(pfa) if pfa is not None else ())
        t0, n0 = t.reshape(()), n.reshape(())
        if pfa is None:
            q0 = gamma_q(n0, t0)
        else:
            q0 = jax.lax.stop_gradient(jnp.asarray(pfa, dtype=dtype).reshape(()))
        return _pd_steady(jnp.broadcast_to(snr, shape), t0, n0, q0)
    snr, t, n = jnp.broadcast_arrays(snr, t, n)
    if swerling == 2:
        return gamma_q(n, t / (1.0 + snr))
    if pfa is None:
        q0 = gamma_q(n, t)
    else:
        q0 = jnp.broadcast_to(jnp.asarray(pfa, dtype=dtype), t.shape)
        q0 = jax.lax.stop_gradient(q0)
    return _pd_mixture(snr, t, n, q0, swerling)
