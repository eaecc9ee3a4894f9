"""Fast evaluation of the steady-target (Swerling 0/5) detection probability for one threshold.

This is the value-only kernel used by :func:`diffsense.detection.core.pd_given_threshold` when
the threshold ``T`` and the pulse count ``N`` are single numbers shared by every element
(e.g. Pd over a grid of SNRs at a fixed Pfa). Derivatives come from the general kernel of
``core.py``; both evaluate the same series, so they agree to round-off.

**Series.** With ``K ~ Poisson(mu)``, ``mu = N S``, and ``w_j = pois(N + j; T)`` (equation (1)
of ``core.py``), and ``sum_{j>=0} w_j = 1 - Q(N, T)``,

    Pd = Pfa + sum_j w_j P(K > j)                         (DOWN form)
       = Pfa + sum_j w_j - sum_j w_j P(K <= j)            (UP form)

summed over the Chernoff window ``j_lo <= j <= j_hi`` of ``core.window_bounds`` (each omitted
tail of ``w`` below exp(-L), L = 40). The DOWN form accumulates ``P(K > j)`` downward from the
Poisson quantile bound ``k_hi`` of K (above which K has mass below exp(-L)); the UP form
accumulates ``P(K <= j)`` upward from the lower bound ``k_lo``. Both are sums of positive terms.
An element uses UP when ``mu >= T - N`` (K's mean at or above the window centre, so Pd is not
small and an absolute error of a few ulp is round-off) and DOWN otherwise (which keeps full
relative accuracy of ``Pd - Pfa`` when it is tiny). With this split ``k_hi <= j_hi`` for every
DOWN element and ``k_lo >= j_lo`` for every UP element, so no element walks above the window:
the number of steps is at most the window length (about ``2 sqrt(2 L T)``, 90 at N = 10 and
Pfa = 1e-6) whatever the SNR, where the general kernel walks from ``k_hi`` even when it lies
far above the window (up to 190 steps in the same case). DOWN walks continue below the window
bottom to j = 0 (as in ``core.py``): when K's mean is small the terms of ``Pd - Pfa`` lie at the
smallest j, below a window that starts above 0 when T - N > sqrt(2 L T) (Pfa < ~1e-35 at N = 1).

The window sum ``W = sum_j w_j`` is kept in the UP form (instead of writing it ``1 - Pfa``)
because the threshold solver returns a T with ``Q(N, T) = Pfa`` only to the accuracy of the
incomplete gamma function (relative 1e-12 ... 2e-11 at large N): summing ``W`` makes both forms
carry the same threshold error, so Pd is continuous where an element changes direction.

**Why it is fast.** (a) The loop index ``j`` is one number shared by all elements of a chunk,
so the weight ``w_j`` is a scalar recursion (``w_{j-1} = w_j (N + j) / T``) computed once per
step instead of once per element, and the loop condition is a scalar comparison, not a
reduction over the chunk. (b) Each element does a few multiply/adds and one select per step,
and four steps are unrolled per loop iteration so XLA fuses them into fewer passes over the
chunk. (c) The only per-element transcendental work is the start value ``P(K = k_start)`` at an
integer ``k_start``: Stirling's remainder comes from a table (``k < 15``) or its asymptotic
series, so no log-gamma is evaluated. Elements of a chunk that need the other direction are
handled by a second loop over the same chunk in which they carry zero mass (chunks of SNRs in
random order therefore pay for both loops: about 2.5 times the time of sorted SNRs).

**Accuracy.** Start values use Loader's saddle-point form with a deviance series valid to
|v| = 0.35 (see ``_logpmf.bd0_wide``), so they are accurate to a few ulp of ``|log P|`` even at
the tail points where the recursions start; the recursions use correctly rounded quotients or a
double-double reciprocal, so their roundings do not accumulate a bias. Measured against the
40-digit mpmath reference at a fixed float threshold (N = 1 ... 1e4, Pfa = 0.5 ... 1e-300,
SNR from 30 dB below to 10 dB above the Pd = 0.5 point): |error| <= 1.5e-14.

**float32.** Same program with precision-dependent choices made at trace time: the truncation
exponent L = 20 and the exact Chernoff bound for ``k_hi`` (``_bounds``: the float64 bound puts
P(K = k_hi) below float32's range when N S < 1 and the sum is lost), the float32 splitting
constant of the double-float reciprocal, and the float32 Stirling remainder of ``_logpmf`` in
the start weights. Measured against mpmath (N = 1-100, Pfa 1e-3-1e-10, SNR -5...25 dB,
``benchmarks/float32_accuracy.py``): |error| <= 1.4e-6.
"""

from __future__ import annotations

import decimal
import math

import jax
import jax.numpy as jnp

from diffsense.detection._bounds import tail_exponent, tight_upper_bound, window_bounds
from diffsense.detection._logpmf import _HALF_LOG_2PI, bd0_wide, stirlerr
from diffsense.detection._precision import single_precision

__all__ = ["steady_pd", "log_poisson_pmf_at_integer"]

_PI_50 = "3.14159265358979323846264338327950288419716939937510"


def _stirlerr_table(k_max: int) -> tuple[float, ...]:
    """Stirling's remainder ``log k! - (k + 1/2) log k + k - log(2 pi)/2`` for k = 1..k_max-1.

    Evaluated once at import in 50-digit decimal arithmetic (``Decimal.ln`` is correctly
    rounded), so the float64 entries are correctly rounded; entry 0 is unused (set to 0).
    """
    ctx = decimal.Context(prec=50)
    half_log_2pi = ctx.multiply(decimal.Decimal("0.5"), ctx.ln(ctx.multiply(2, decimal.Decimal(_PI_50))))
    vals = [0.0]
    for k in range(1, k_max):
        dk = decimal.Decimal(k)
        v = ctx.ln(decimal.Decimal(math.factorial(k))) - ctx.multiply(dk + decimal.Decimal("0.5"), ctx.ln(dk))
        vals.append(float(v + dk - half_log_2pi))
    return tuple(vals)


_SERIES_FROM = 15
_STIRLERR_SMALL = _stirlerr_table(_SERIES_FROM)


def _stirlerr_at_integer(k):
    """Stirling's remainder at integer-valued k >= 1: table below 15, asymptotic series above.

    The series 1/(12k) - 1/(360k^3) + 1/(1260k^5) - 1/(1680k^7) + 1/(1188k^9) is the one of
    ``_logpmf.stirlerr`` (truncation < 2.3e-16 absolute at k = 15).
    """
    big = k >= _SERIES_FROM
    kb = jnp.where(big, k, float(_SERIES_FROM))
    r = 1.0 / (kb * kb)
    series = (1.0 / 12.0 - r * (1.0 / 360.0 - r * (1.0 / 1260.0 - r * (1.0 / 1680.0 - r / 1188.0)))) / kb
    idx = jnp.clip(k, 0.0, _SERIES_FROM - 1.0).astype(jnp.int32)
    table = jnp.asarray(_STIRLERR_SMALL, dtype=jnp.result_type(k))
    return jnp.where(big, series, table[idx])


def log_poisson_pmf_at_integer(k, mu):
    """log P(K = k), K ~ Poisson(mu), for integer-valued k >= 0 (float array) and mu > 0.

    Loader's saddle-point form ``-stirlerr(k) - bd0(k, mu) - log(2 pi k)/2`` (see ``_logpmf``)
    with Stirling's remainder from a table and the wide-range deviance series ``bd0_wide``:
    absolute error of a few ulp of |log P|, i.e. relative error of P ~1e-14 even at tail points.
    """
    pos = k > 0
    kp = jnp.where(pos, k, 1.0)
    val = -_stirlerr_at_integer(kp) - bd0_wide(kp, mu) - 0.5 * jnp.log(kp) - _HALF_LOG_2PI
    return jnp.where(pos, val, -mu)


def _log_poisson_weight(x, t):
    """log pois(x; t) for real x >= 0 (the weights w_j at x = n + j), with the wide deviance."""
    pos = x > 0
    xp = jnp.where(pos, x, 1.0)
    val = -stirlerr(xp) - bd0_wide(xp, t) - 0.5 * jnp.log(xp) - _HALF_LOG_2PI
    return jnp.where(pos, val, -t)


# Chunk length and unrolling, chosen by measurement (2-core CPU, N = 10, 1e6 SNRs): the
# per-step work per element is a few multiply-adds, so the fixed cost of a while-loop step is
# amortised over more elements than in the general kernel of core.py, while the loop state
# (five arrays of this length) stays in L2; unrolling four steps per iteration lets XLA fuse
# them. Measured CPU time (best of 9): 4096 x 4: 106 ms, 2048 x 4: 110 ms, 8192 x 4: 123 ms,
# 4096 x 2: 121 ms, 4096 x 8: 123 ms, 8192 x 1: 176 ms.
_CHUNK = 4096
_UNROLL = 4


def steady_pd(snr, t, n, pfa):
    """Swerling 0/5 Pd for SNRs ``snr`` (array) at one threshold ``t`` with ``n`` pulses.

    Args:
        snr: mean single-pulse SNR S (linear, > 0), any shape.
        t: threshold T on the integrated statistic (scalar, > 0).
        n: number of pulses (scalar, real >= 1).
        pfa: ``Q(n, t)`` (scalar).

    Returns Pd with the shape of ``snr``; error as the general kernel (round-off plus the
    truncation ``2 exp(-40)``). ``t``, ``n`` and ``pfa`` must be scalars: the weight recursion
    is shared by all elements. Evaluated chunk by chunk (``lax.map``), so the loop state of a
    chunk stays in the CPU cache and each chunk loops only over the steps its own SNRs need.
    """
    if any(jnp.ndim(a) for a in (t, n, pfa)):
        raise ValueError("steady_pd: t, n and pfa must be scalars")
    j_lo, j_hi = window_bounds(t, n)
    # UP form with the threshold's own rounding: the UP sum yields 1 - Pd(T) with the exact
    # identity Q(n, T) = 1 - sum_{j>=0} w_j, whereas the DOWN form adds the given Pfa. The
    # solver's T satisfies Q(n, T) = Pfa only to the accuracy of the incomplete gamma function
    # (relative 1e-12 ... 2e-11), so the UP form is written pfa + W - miss with W the window
    # sum of w_j (an exact 1 - Q(n, T) up to the truncation): both forms then carry the same
    # threshold error and Pd stays continuous where an element switches direction.
    w_sum = _window_sum(t, n, j_lo, j_hi)
    kernel = lambda x: _steady_kernel(x, t, n, pfa, j_lo, j_hi, w_sum, tail_exponent(t))
    shape, size = snr.shape, snr.size
    if size == 0:
        return jnp.zeros(shape, dtype=jnp.result_type(snr, t))
    if size <= _CHUNK:
        return kernel(snr)
    pad = (-size) % _CHUNK
    flat = jnp.concatenate([snr.reshape(-1), jnp.broadcast_to(snr.reshape(-1)[:1], (pad,))])
    out = jax.lax.map(kernel, flat.reshape(-1, _CHUNK))
    return out.reshape(-1)[:size].reshape(shape)


def _window_sum(t, n, j_lo, j_hi):
    """sum_{j_lo <= j <= j_hi} pois(n + j; t) (scalar recursion from the window bottom)."""

    def body(s):
        j, w, acc = s
        return j + 1.0, w * (t / (n + j + 1.0)), acc + w

    w0 = jnp.exp(_log_poisson_weight(n + j_lo, t))
    return jax.lax.while_loop(lambda s: s[0] <= j_hi, body, (j_lo, w0, jnp.zeros_like(w0)))[2]


# Veltkamp's splitting constants 2^27 + 1 (float64: two 26-bit halves) and 2^12 + 1 (float32:
# two 12-bit halves); the pairwise products of the halves are exact.
_SPLITTER = 134217729.0
_SPLITTER_SINGLE = 4097.0


def _split(a):
    c = (_SPLITTER_SINGLE if single_precision(a) else _SPLITTER) * a
    hi = c - (c - a)
    return hi, a - hi


def _reciprocal_double_double(x):
    """1/x as an unevaluated sum hi + lo with relative error ~eps^2 (Dekker's exact product).

    The DOWN recursion multiplies by (j + 1)/x at every step. With a rounded 1/x its relative
    error (up to 1.1e-16) would repeat at every step and bias the probabilities by up to
    (steps) x 1.1e-16; with hi + lo only the per-step roundings remain, which do not share a
    sign. A division per element and step would do the same at about 20 % more run time.
    """
    hi = 1.0 / x
    x_hi, x_lo = _split(x)
    h_hi, h_lo = _split(hi)
    p = x * hi
    err = ((x_hi * h_hi - p) + x_hi * h_lo + x_lo * h_hi) + x_lo * h_lo  # x * hi = p + err exactly
    return hi, ((1.0 - p) - err) * hi


def _unrolled(step):
    """``_UNROLL`` steps per loop iteration (steps past the window end are masked by the step)."""

    def body(s):
        for _ in range(_UNROLL):
            s = step(s)
        return s

    return body


def _steady_kernel(snr, t, n, pfa, j_lo, j_hi, w_sum, tail_l):
    """Both directional sums over one chunk of SNRs (see the module docstring)."""
    mu = n * snr
    # Poisson quantile bounds of K, each tail below exp(-tail_l) (as _bounds.poisson_quantile_bounds)
    k_lo = jnp.maximum(jnp.floor(mu - jnp.sqrt(2.0 * tail_l * mu)), 0.0)
    k_hi = jnp.ceil(mu + tail_l / 3.0 + jnp.sqrt(tail_l**2 / 9.0 + 2.0 * tail_l * mu))
    if single_precision(mu):
        k_hi = tight_upper_bound(mu, None, k_hi, tail_l)  # keeps P(K = k_hi) above float32's range
    up = mu >= t - n
    pmf_start = jnp.exp(log_poisson_pmf_at_integer(jnp.where(up, k_lo, k_hi), mu))
    zeros = jnp.zeros_like(mu)

    # DOWN: j runs from the highest k_hi of the DOWN elements (<= j_hi) down to 0, below the
    # window bottom: when K's mean is small the terms of Pd - Pfa lie at the smallest j, and
    # stopping at j_lo lost Pd - Pfa once it fell below exp(-L) absolutely (core.py). Steps
    # past 0 (unrolling) are masked.
    # Entering step j, `pmf` holds P(K = j + 1) and `surv` P(K > j + 1); an element's pmf is 0
    # until j reaches its own k_hi (UP elements never start: their start mass is 0 here).
    pmf_down = jnp.where(up, 0.0, pmf_start)
    inv_mu_hi, inv_mu_lo = _reciprocal_double_double(mu)
    j_top = jnp.max(jnp.where(up, -1.0, k_hi))

    def down_step(s):
        j, w, pmf, surv, acc = s
        surv = surv + pmf  # P(K > j)
        acc = acc + jnp.where((j >= 0.0) & (j <= j_hi), w, 0.0) * surv
        ratio = (j + 1.0) * inv_mu_hi + (j + 1.0) * inv_mu_lo  # (j + 1) / mu
        pmf = jnp.where(j == k_hi, pmf_down, pmf * ratio)  # P(K = j)
        return j - 1.0, w * ((n + j) / t), pmf, surv, acc

    w_top = jnp.exp(_log_poisson_weight(n + jnp.maximum(j_top, 0.0), t))
    _, _, _, _, acc = jax.lax.while_loop(
        lambda s: s[0] >= 0.0, _unrolled(down_step), (j_top, w_top, zeros, zeros, zeros)
    )

    # UP: j runs from the lowest k_lo of the UP elements (>= j_lo) to the window top. Entering
    # step j, `pmf` holds P(K = j - 1) and `cdf` P(K <= j - 1). (Were j below the window, the
    # weight would be held at w(j_lo) and masked out.)
    pmf_up = jnp.where(up, pmf_start, 0.0)
    j_bot = jnp.min(jnp.where(up, k_lo, j_hi + 1.0))

    def up_step(s):
        j, w, pmf, cdf, miss = s
        pmf = jnp.where(j == k_lo, pmf_up, pmf * (mu * (1.0 / jnp.maximum(j, 1.0))))  # P(K = j)
        cdf = cdf + pmf  # P(K <= j)
        miss = miss + jnp.where((j >= j_lo) & (j <= j_hi), w, 0.0) * cdf
        w_next = jnp.where(j >= j_lo, w * (t / (n + j + 1.0)), w)
        return j + 1.0, w_next, pmf, cdf, miss

    w_bot = jnp.exp(_log_poisson_weight(n + jnp.maximum(j_bot, j_lo), t))
    _, _, _, _, miss = jax.lax.while_loop(
        lambda s: s[0] <= j_hi, _unrolled(up_step), (j_bot, w_bot, zeros, zeros, zeros)
    )
    return jnp.clip(jnp.where(up, pfa + (w_sum - miss), pfa + acc), 0.0, 1.0)
