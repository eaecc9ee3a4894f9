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

**float32.** A relative error of the log-probability becomes a relative error of the
probability multiplied by |log p| (about 20-45 at the start points of the detection
recursions), and the start value scales every term derived from it. Two float64 shortcuts lose
too much in float32: Stirling's remainder below 15 by its defining expression (cancellation of
terms up to 40 to a result below 0.08: 4.6e-6 absolute), and the deviance in closed form
already from |v| = 0.1 (3e-5 absolute at x/m = 1.85, m = 153). In float32 ``stirlerr`` uses the
asymptotic series from x = 3 with a cancellation-free upward recurrence below, and ``bd0`` the
wide-range series ``bd0_wide``. Measured against mpmath in float32: stirlerr <= 8.1e-9
absolute for x >= 1 (1.8e-7 for 0.1 <= x < 1), bd0 <= 6 ulp of its value (or 1.5e-7 absolute
where it is near 0) for deviances below 60. The float64 path is unchanged.
"""

from __future__ import annotations

import jax.numpy as jnp
from jax.scipy.special import gammaln

from diffsense.detection._precision import single_precision

_HALF_LOG_2PI = 0.9189385332046727417803297364056176


def stirlerr(x):
    """Stirling remainder ``lgamma(x+1) - (x+1/2)log x + x - log(2 pi)/2`` for x > 0.

    For x >= 15 the asymptotic series 1/(12x) - 1/(360x^3) + 1/(1260x^5) - 1/(1680x^7)
    + 1/(1188x^9) is used (truncation < 2.3e-16 absolute at x = 15, the first omitted term
    being 691/(360360 x^11)); below 15 the defining expression is evaluated directly
    (absolute error <= ~5e-15).
    """
    x = jnp.asarray(x)
    if single_precision(x):
        return _stirlerr_single(x)
    big = x >= 15.0
    xb = jnp.where(big, x, 15.0)
    xs = jnp.where(big, 1.0, x)
    r = 1.0 / (xb * xb)
    series = (1.0 / 12.0 - r * (1.0 / 360.0 - r * (1.0 / 1260.0 - r * (1.0 / 1680.0 - r / 1188.0)))) / xb
    direct = gammaln(xs + 1.0) - (xs + 0.5) * jnp.log(xs) + xs - _HALF_LOG_2PI
    return jnp.where(big, series, direct)


def _stirlerr_series(x):
    """Asymptotic series of Stirling's remainder to 1/(1188 x^9) (see ``stirlerr``)."""
    r = 1.0 / (x * x)
    return (1.0 / 12.0 - r * (1.0 / 360.0 - r * (1.0 / 1260.0 - r * (1.0 / 1680.0 - r / 1188.0)))) / x


# float32: the series errs by < 8.1e-9 from x = 3 (mpmath); below, three steps of the
# recurrence stirlerr(y) = stirlerr(y + 1) + (y + 1/2) log1p(1/y) - 1 reach it. For y >= 1 the
# step is summed as z^2/3 + z^4/5 + z^6/7 + ..., z = 1/(2y + 1) <= 1/3 (the expansion of
# (1/(2z)) log((1+z)/(1-z)) - 1), free of the cancellation of the closed form (which loses
# ~1e-7 absolute per step); for y < 1 the closed form does not cancel.
_SERIES_FROM_SINGLE = 3.0
_RECURRENCE_STEPS_SINGLE = 3
_STEP_SERIES_TERMS = 9  # z^18 / 21 < 1e-10


def _stirlerr_step_single(y):
    """(y + 1/2) log1p(1/y) - 1 for y > 0 (float32, see above)."""
    ge1 = y >= 1.0
    yb = jnp.where(ge1, y, 1.0)
    z2 = 1.0 / ((2.0 * yb + 1.0) ** 2)
    poly = jnp.full_like(z2, 1.0 / (2 * _STEP_SERIES_TERMS + 1))
    for i in range(_STEP_SERIES_TERMS - 1, 0, -1):
        poly = poly * z2 + 1.0 / (2 * i + 1)
    series = z2 * poly
    ys = jnp.where(ge1, 1.0, y)
    closed = (ys + 0.5) * jnp.log1p(1.0 / ys) - 1.0
    return jnp.where(ge1, series, closed)


def _stirlerr_single(x):
    """Stirling's remainder for x > 0 in float32 (see the module docstring)."""
    big = x >= _SERIES_FROM_SINGLE
    xs = jnp.where(big, 1.0, x)  # double where: the recurrence branch only sees x < 3
    shift = jnp.zeros_like(x)
    for i in range(_RECURRENCE_STEPS_SINGLE):
        shift = shift + _stirlerr_step_single(xs + float(i))
    small = _stirlerr_series(xs + float(_RECURRENCE_STEPS_SINGLE)) + shift
    return jnp.where(big, _stirlerr_series(jnp.where(big, x, _SERIES_FROM_SINGLE)), small)


def bd0(x, m):
    """Deviance term ``x*log(x/m) + m - x`` (>= 0) for x >= 0, m > 0.

    When |x - m| < 0.1 (x + m) it is summed as ``(x-m) v + 2x sum_{i>=1} v^(2i+1)/(2i+1)`` with
    ``v = (x-m)/(x+m)``; |v| < 0.1 makes 9 terms exact to < 1e-19 relative.
    """
    x = jnp.asarray(x)
    m = jnp.asarray(m)
    if single_precision(jnp.result_type(x, m)):
        return bd0_wide(x, m)
    d = x - m
    s = x + m
    near = jnp.abs(d) < 0.1 * s
    v = jnp.where(near, d / jnp.where(near, s, 1.0), 0.0)
    v2 = v * v
    # sum_{i=1..9} v^(2i+1)/(2i+1) = v^3 (1/3 + v^2 (1/5 + ...)) by Horner's rule
    poly = jnp.full_like(v2, 1.0 / 19.0)
    for i in range(8, 0, -1):
        poly = poly * v2 + 1.0 / (2 * i + 1)
    series = d * v + 2.0 * x * (v * v2) * poly
    xpos = x > 0
    xf = jnp.where(far_ok := (~near) & xpos, x, 1.0)
    mf = jnp.where(far_ok, m, 1.0)
    far = jnp.where(xpos, xf * jnp.log(xf / mf) + mf - xf, m)
    return jnp.where(near, series, far)


# Deviance series ``bd0(x, m) = (x - m) v + 2 x sum_{i>=1} v^(2i+1)/(2i+1)``, v = (x-m)/(x+m),
# used for |v| < _BD0_SERIES_V with _BD0_TERMS terms (truncation 0.35^40/41 < 1e-19 relative).
# ``bd0`` (float64) switches to ``x log(x/m) + m - x`` already at |v| = 0.1, where that form
# loses up to eps (x |log(x/m)| + |x - m|) to cancellation: 1.7e-13 absolute in log P(K = k)
# at the Chernoff bounds of K for mu ~ 1e3 (k/mu ~ 1.3). With the series up to |v| = 0.35 the
# closed form is used only where x and m are small (m < ~160 at the Chernoff bounds) and its
# cancellation error stays below ~1e-14.
_BD0_SERIES_V = 0.35
_BD0_TERMS = 20


def bd0_wide(x, m, d=None):
    """``x log(x/m) + m - x`` for x >= 0, m > 0, by the series for |v| < 0.35 (see above).

    ``d``: the difference ``x - m`` when the caller has it more accurately than by subtracting a
    rounded ``m`` (the series' error is then relative to the deviance itself).
    """
    d = x - m if d is None else d
    near = jnp.abs(d) < _BD0_SERIES_V * (x + m)
    v = jnp.where(near, d / (x + m), 0.0)
    v2 = v * v
    poly = jnp.full_like(v2, 1.0 / (2 * _BD0_TERMS + 1))
    for i in range(_BD0_TERMS - 1, 0, -1):
        poly = poly * v2 + 1.0 / (2 * i + 1)
    series = d * v + 2.0 * x * (v * v2) * poly
    pos = x > 0
    xf = jnp.where(~near & pos, x, 1.0)
    mf = jnp.where(~near & pos, m, 1.0)
    far = jnp.where(pos, xf * jnp.log(xf / mf) + mf - xf, m)
    return jnp.where(near, series, far)


def log_poisson_pmf(k, mu):
    """log(exp(-mu) mu^k / Gamma(k+1)) for real k >= 0, mu > 0, to full relative accuracy."""
    k = jnp.asarray(k)
    mu = jnp.asarray(mu)
    pos = k > 0
    kp = jnp.where(pos, k, 1.0)
    val = -stirlerr(kp) - bd0(kp, mu) - 0.5 * jnp.log(2.0 * jnp.pi * kp)
    return jnp.where(pos, val, -mu)


def log_binomial_pmf(k, size, p, q=None):
    """log of C(size, k) p^k (1-p)^(size-k) for real 0 <= k <= size, 0 < p < 1 (Loader 2000).

    ``q`` is ``1 - p`` when the caller has it to full relative accuracy (``1 - p`` rounded from
    p loses digits when p is near 1); by default it is computed as ``1 - p``.
    """
    k = jnp.asarray(k)
    size = jnp.asarray(size)
    p = jnp.asarray(p)
    q_given = q is not None
    q = jnp.asarray(q) if q_given else 1.0 - p
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
    at0 = size * (jnp.log(q) if q_given else jnp.log1p(-p))
    atn = size * jnp.log(p)
    return jnp.where(interior, val, jnp.where(k <= 0, at0, atn))


def log_negbin_pmf(k, r, q, q_complement=None):
    """log P(K = k) for K ~ NegBin(r, q): Gamma(k+r)/(Gamma(r) k!) q^k (1-q)^r.

    Uses NB(k; r, q) = r/(k+r) * Binomial(k; k+r, q) so the binomial saddle-point form applies.
    ``q_complement``: ``1 - q`` to full relative accuracy, if known (see ``log_binomial_pmf``).
    """
    k = jnp.asarray(k)
    r = jnp.asarray(r)
    return jnp.log(r / (k + r)) + log_binomial_pmf(k, k + r, q, q_complement)


def log_negbin_pmf_mean(k, r, mu):
    """log P(K = k) for K negative binomial with shape r and mean mu (float32 form).

    Same saddle-point form as ``log_negbin_pmf`` with ``q = mu/(mu + r)``, but the deviances
    ``bd0(k, (k + r) q)`` and ``bd0(r, (k + r)(1 - q))`` are evaluated from their exact
    differences ``+-r (k - mu)/(mu + r)``: with a rounded q their error is |k - mu| times the
    rounding of q (1e-5 in log P at k - mu = 90 in float32), with the exact difference a few
    ulp of the deviance.
    """
    k = jnp.asarray(k)
    r = jnp.asarray(r)
    mu = jnp.asarray(mu)
    pos = k > 0
    kp = jnp.where(pos, k, 1.0)
    size = kp + r
    d = r * (kp - mu) / (mu + r)
    m_k = size * (mu / (mu + r))
    m_r = size * (r / (mu + r))
    val = (
        stirlerr(size)
        - stirlerr(kp)
        - stirlerr(r)
        - bd0_wide(kp, m_k, d)
        - bd0_wide(r, m_r, -d)
        + 0.5 * jnp.log(size / (2.0 * jnp.pi * kp * r))
        + jnp.log(r / size)
    )
    return jnp.where(pos, val, -r * jnp.log1p(mu / r))
