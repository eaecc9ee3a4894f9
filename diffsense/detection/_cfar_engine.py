"""Exact single-pulse CFAR detection for a noise estimate of known law (engine of OS, GO, SO;
its Swerling 0 rule also serves the single-pulse CA-CFAR, :func:`steady_target_pd`).

Model. One square-law sample per cell, noise of unit mean, so that under noise alone every cell
is exponential with mean 1. The cell under test ``Y`` is compared with ``T X``: ``X`` is the
noise estimate formed from the reference cells, ``T`` the threshold multiplier, ``S`` the mean
SNR of the cell under test (linear). Everything follows from three exact functions of the law
of ``X``, which the detector modules supply (the "law": :mod:`diffsense.detection.cfar_ordered`
for the order statistic, :mod:`diffsense.detection.cfar_greatest_smallest` for the greatest
and smallest of two half-window sums):

* the Laplace transform ``L(c) = E[exp(-c X)]`` (``law.log_laplace(log c)``);
* the tilted mean ``mu(c) = E[X exp(-c X)] / L(c)`` (``law.tilted_mean(log c)``);
* the distribution function ``F(x) = P(X <= x)`` (``law.log_cdf(log x)``), with ``F(x) ~ x^p``
  at 0 and the elasticity ``x F'(x)/F(x) <= p`` everywhere (``law.cdf_power = p``);

and a bracket of ``log T`` for a given Pfa (``law.log_multiplier_bracket(log Pfa)``).

False alarms: ``Pfa = P(Y > T X) = E[exp(-T X)] = L(T)``. The multiplier solves
``log L(T) = log Pfa``: safeguarded Newton iteration in ``log T`` inside the law's bracket
(:mod:`diffsense.numerics.bracketed_newton`), converged to round-off, differentiated implicitly.

Detection (single pulse, so Swerling 1 = 2 and Swerling 3 = 4):

* Swerling 1/2: ``Y`` is exponential with mean ``1 + S``: ``Pd = L(T/(1 + S))``.
* Swerling 3/4: ``Y`` is chi-square with 4 degrees of freedom, ``P(Y > t) = (1 + b0 t)
  exp(-t/(1 + S/2))`` with ``b0 = (S/2)/(1 + S/2)^2``, hence ``Pd = E[(1 + b0 T X)
  exp(-c X)] = L(c) (1 + b0 T mu(c))`` with ``c = T/(1 + S/2)``.
* Swerling 0 (steady target): ``Pd = E_X[Pd_fixed(T X)]`` with ``Pd_fixed`` the Marcum Q
  function; by Fubini the same number is ``E_Y[F(Y/T)]`` over the noncentral chi-square law of
  the cell under test, ``f_Y(y) = exp(-(y + S)) I0(2 sqrt(S y))``. This form is integrated: its
  factors are closed forms and the integrand ``y f_Y(y) F(y/T)`` is log-concave in ``y`` (the
  density, and the distribution function of a log-concave law, are), hence a unimodal bell in
  ``w = log y``, decaying like ``y^(p+1)`` to the left and ``exp(-y)`` to the right. The rule:
  the mode by bisection on the sign of the log-derivative (it lies in ``1 <= y <= 4(1 + p +
  S)``: the log-derivative in ``w`` is at least ``1 - y`` and at most ``1 + p - y + sqrt(S
  y)``), the two points where the integrand has fallen by ``e^-45`` (bisection, brackets from
  the same bounds), then the trapezoidal rule with 64 equally spaced nodes in ``tau`` with
  ``w = w_mode + beta sinh(tau)``, ``beta`` twice the curvature width of the peak (the map
  clusters nodes in the peak, which narrows like ``1/sqrt(S)`` at high SNR, and spreads them in
  the slowly decaying left tail). ``sqrt(y) - sqrt(S)`` is evaluated as ``sqrt(S) expm1((log y
  - log S)/2)`` so that the peak is free of cancellation, and ``log(exp(-z) I0(z))`` above z =
  1e3 from its asymptotic series (the derivative of ``log i0e`` cancels log10 z digits, which at
  120 dB cost the required SNR's derivative 2e-4 relative, 20 % at 128 dB). Measured against the
  closed form of k = 1 (``1 - exp(-S c/(1 + c))/(1 + c)``, c = n/T): value within 4e-15
  relative and ``d log(-log Pd)/d SNR`` within 1.3e-10 relative from -5 to 120 dB, 2e-8 at
  128 dB. The trapezoidal rule converges
  geometrically for such analytic, quickly decaying integrands (Trefethen & Weideman 2014).
  Above 200 dB (reached only by required-SNR roots for tiny Pfa with few cells) the peak is
  narrower than the resolution of ``w``; there ``Y`` is concentrated at its mean ``1 + S``
  (relative variance ``(1 + 2S)/(1 + S)^2 < 2e-20``), the first-order term of ``E[F(Y/T)] -
  F(E[Y]/T)`` vanishes and the second is below ``p^2 (1 + 2S)/(1 + S)^2`` relative, so ``Pd =
  F((1 + S)/T)``.

Required SNR. Swerling 1/2 in closed form: ``L(T(Pfa)/(1 + S)) = Pd`` means ``T(Pfa)/(1 + S)
= T(Pd)`` (the multiplier for a false-alarm probability Pd), so ``S = T(Pfa)/T(Pd) - 1``.
Otherwise safeguarded Newton iteration on ``log(-log Pd)`` versus SNR in dB, started at the
Swerling 1 value ``x1`` inside the bracket ``[x1 - 60, x1 + 30]`` dB (converged to 1e-12 dB;
NaN if the root were not inside: the fluctuation changes the requirement by far less, and the
domain-corner tests find every root inside) and differentiated implicitly. Pd is capped at
``1 - 1e-12`` in ``log(-log Pd)``: nearer to 1 its miss probability is rounding noise, whose
slope would stop the iteration; the flat cap sends it to bisection. The CFAR loss
subtracts the known-noise single-pulse requirement :func:`diffsense.detection.required_snr_db`
``(pd, pfa, 1, swerling)``.

Derivatives. The multiplier and the required SNR are implicit functions (``jax.custom_jvp``), in
the probabilities and in the law's arrays (whose tangents are those of a law built from traced
cell counts, :func:`law_loss_db`);
Pd is differentiated through its closed forms and, for Swerling 0, through the quadrature sum
at fixed nodes (the placement of the nodes carries no derivative: the rule integrates the
derivative of the integrand as accurately as the integrand).

Compiled programs. A law carries its tables (ranks, binomial coefficients, factorials) as
arrays padded to a power-of-two length of at least 64 (padding terms have weight 0 or a
logarithm of -inf), not as constants: one compiled program serves every number of cells of the
same padded length (n <= 64 for OS-CFAR, n <= 128 for GO/SO-CFAR) and both the GO and SO laws,
per function, Swerling class (0, 1-2, 3-4) and argument shape.

Accuracy is measured in tests/detection/test_cfar_ordered.py and
test_cfar_greatest_smallest.py and stated in the public functions' docstrings.

Sources: see the detector modules; L. N. Trefethen and J. A. C. Weideman, "The exponentially
convergent trapezoidal rule", SIAM Review 56(3), 385-458 (2014); M. Bagnoli and T. Bergstrom,
"Log-concave probability and its applications", Economic Theory 26, 445-469 (2005).
"""

from __future__ import annotations

import math
import operator
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.special import gammaln, i0e

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_choice, is_concrete
from diffsense.numerics.bracketed_newton import forward_slope, newton_decreasing
from diffsense.numerics.db import DB_PER_NEPER
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import as_float
from diffsense.detection.required_snr import required_snr_db  # the known-noise requirement

#: Admitted false-alarm probabilities, ``lo <= pfa < hi``; the loss functions need the
#: known-noise requirement, which takes pfa <= 0.5.
PFA_RANGE = (1e-100, 1.0, False, True)
PFA_LOSS_RANGE = (1e-100, 0.5)
#: Largest admitted detection probability of the required-SNR and loss functions.
PD_MAX = 0.9999
#: SNR domain of the Pd functions (dB).
SNR_RANGE_DB = (-100.0, 100.0)

_NEPER_PER_DB = 1.0 / DB_PER_NEPER
_SWERLING = (0, 1, 2, 3, 4)
_MIN_TABLE = 64  # shortest padded table
_NODES = 64  # trapezoidal nodes of the Swerling 0 quadrature
_DROP = 45.0  # the integrand is cut where it has fallen by exp(-_DROP) below its peak
_WIDTH_FACTOR = 2.0  # beta of the sinh map, in units of the peak's curvature width
_BISECTIONS = 60
#: log S above which the Swerling 0 law of the cell under test counts as concentrated (200 dB)
_LOG_SNR_CONCENTRATED = math.log(1e20)
_MAX_NEWTON = 100
_PD_CAP = 1.0 - 1e-12
#: bracket of the Swerling 0/3 required SNR: this far below and above the Swerling 1 value (dB)
_BRACKET_DB = (60.0, 30.0)


# --------------------------------------------------------------------------------------
# Padded tables and finite sums in the log domain
# --------------------------------------------------------------------------------------


def table_length(terms: int) -> int:
    """Padded length of a table of ``terms`` entries: a power of two, at least 64."""
    return max(_MIN_TABLE, 1 << max(terms - 1, 0).bit_length())


def padded(values, length: int, fill: float):
    """``values`` (1-D) followed by ``fill`` up to ``length`` entries (float64 numpy)."""
    out = np.full(length, fill, dtype=float)
    out[: len(values)] = values
    return out


def binomial_tail_table(n_trials: int, j_min: int, length: int | None = None):
    """Rows ``j``, ``n_trials - j``, ``log C(n_trials, j)`` for ``j = j_min .. n_trials``, padded.

    The binomial coefficients are exact integers logged once (correctly rounded): log-gamma
    differences would lose up to eps * lgamma(n + 1) absolutely. Padding: ``j = 0``, ``n - j =
    0``, log coefficient ``-inf`` (a term of probability 0 and derivative 0).
    """
    j = np.arange(j_min, n_trials + 1, dtype=float)
    log_c = [math.log(math.comb(n_trials, i)) for i in range(j_min, n_trials + 1)]
    length = table_length(len(j)) if length is None else length
    return np.stack([padded(j, length, 0.0), padded(n_trials - j, length, 0.0), padded(log_c, length, -np.inf)])


def binomial_tail_table_traced(n_trials, j_min, length: int):
    """:func:`binomial_tail_table` from numbers that may be traced, ``length`` rows: ``log C``
    from ``gammaln`` (relative error of a coefficient ~eps·log C(64, 32) = 1e-14 against the
    correctly rounded table); rows past ``n_trials`` padded as there."""
    j = j_min + jnp.arange(float(length))
    inside = j <= n_trials
    j_in = jnp.where(inside, j, 0.0)
    rest = jnp.where(inside, n_trials - j, 0.0)
    log_c = gammaln(n_trials + 1.0) - gammaln(j_in + 1.0) - gammaln(rest + 1.0)
    return jnp.stack([j_in, rest, jnp.where(inside, log_c, -jnp.inf)])


def logsumexp(terms):
    """log sum exp over the last axis (at least one term finite).

    The shift carries no derivative: the JVP of ``max`` divides by the number of elements equal
    to the maximum, which XLA's CPU fusion emitters (contracting to FMA differently in the
    recomputed operand) can make zero, giving NaN tangents.
    """
    top = jax.lax.stop_gradient(jnp.max(terms, axis=-1))
    return top + jnp.log(jnp.sum(jnp.exp(terms - top[..., None]), axis=-1))


def log_binomial_tail(table, log_p, log_q):
    """log P(Binomial(n, p) >= j_min) from ``log p``, ``log q = log(1 - p)`` (positive terms)."""
    j, n_minus_j, log_c = table[0], table[1], table[2]
    return logsumexp(log_c + j * log_p[..., None] + n_minus_j * log_q[..., None])


def log_one_minus_exp_neg(log_x):
    """log(1 - exp(-x)) from log x, for any finite log x (no underflow of x)."""
    x = jnp.exp(log_x)
    small = log_x < -20.0
    x_big = jnp.where(small, 1.0, x)
    return jnp.where(small, log_x - 0.5 * x, jnp.log(-jnp.expm1(-x_big)))


def log_expm1(z):
    """log(exp(z) - 1) for z > 0 without overflow."""
    return z + jnp.log(-jnp.expm1(-z))


# --------------------------------------------------------------------------------------
# Multiplier
# --------------------------------------------------------------------------------------


@jax.custom_jvp
def _log_multiplier(law, log_pfa):
    """log T(Pfa), the root of log L(T) = log Pfa (implicit derivative; the law is constant)."""
    lo, hi = law.log_multiplier_bracket(log_pfa)
    lo = lo - 1e-12 * (1.0 + jnp.abs(lo))
    hi = hi + 1e-12 * (1.0 + jnp.abs(hi))
    tolerance = lambda s: 1e-15 * jnp.maximum(1.0, jnp.abs(s))
    residual = forward_slope(lambda s: law.log_laplace(s) - log_pfa)
    s, _, _ = newton_decreasing(residual, 0.5 * (lo + hi), lo, hi, tolerance, _MAX_NEWTON)
    return s


@_log_multiplier.defjvp
def _log_multiplier_jvp(primals, tangents):
    # implicit: log L(law, s) = log Pfa  =>  ds = (dlog Pfa - d_law log L) / (d log L / ds)
    law, log_pfa = primals
    dlaw, dlog_pfa = tangents
    s = _log_multiplier(law, log_pfa)
    _, slope = jax.jvp(law.log_laplace, (s,), (jnp.ones_like(s),))
    _, d_law = jax.jvp(lambda law_: law_.log_laplace(s), (law,), (dlaw,))
    return s, (dlog_pfa - d_law) / slope


# --------------------------------------------------------------------------------------
# Detection probability
# --------------------------------------------------------------------------------------


#: coefficients ((2k-1)!!)^2 / (k! 8^k) of the large-argument series of exp(-z) I0(z)
_I0E_SERIES = tuple(math.prod(range(1, 2 * k, 2)) ** 2 / (math.factorial(k) * 8.0**k) for k in range(1, 7))
_I0E_SERIES_FROM = 1e3


def _log_i0e(z):
    """log(exp(-z) I0(z)), z >= 0. Above z = 1e3 from the asymptotic series (Abramowitz & Stegun
    9.7.1) ``-log(2 pi z)/2 + log(1 + sum_k a_k / z^k)`` (six terms, the next below 4e-19 there):
    there ``i0e``'s derivative ``i1e - i0e`` cancels ~log10(z) digits, which the quadrature's
    derivative at high SNR would inherit."""
    big = z > _I0E_SERIES_FROM
    zb = jnp.where(big, z, _I0E_SERIES_FROM)
    inv = 1.0 / zb
    series = sum(a * inv ** (k + 1) for k, a in enumerate(_I0E_SERIES))
    asymptotic = -0.5 * jnp.log(2.0 * math.pi * zb) + jnp.log1p(series)
    return jnp.where(big, asymptotic, jnp.log(i0e(jnp.where(big, 1.0, z))))


def _log_density_part(v, c0, log_snr):
    """log[y f_Y(y)] - c0 at log y = c0 + v: the Rician law of the cell under test."""
    snr = jnp.exp(log_snr)
    gap = jnp.expm1(0.5 * (c0 - log_snr + v))  # (sqrt(y) - sqrt(S)) / sqrt(S)
    z = 2.0 * jnp.exp(0.5 * (log_snr + c0 + v))  # 2 sqrt(S y)
    return v - snr * gap * gap + _log_i0e(z)


def _log_integrand(law, v, c0, log_snr, log_t):
    """log[y f_Y(y) F(y/T)] - c0 at log y = c0 + v (Swerling 0; see the module docstring)."""
    return _log_density_part(v, c0, log_snr) + law.log_cdf(c0 + v - log_t)


def _bisect(pred, lo, hi):
    """Bisection keeping pred(lo) True and pred(hi) False."""

    def body(_, state):
        lo, hi = state
        mid = 0.5 * (lo + hi)
        go_right = pred(mid)
        return jnp.where(go_right, mid, lo), jnp.where(go_right, hi, mid)

    return jax.lax.fori_loop(0, _BISECTIONS, body, (lo, hi))


def _quadrature_grid(law, log_snr, log_t):
    """Mode c0 (log y), offsets of the two cut points and beta of the Swerling 0 rule.

    Computed without derivatives (the rule integrates the derivative of the integrand as well
    as the integrand).
    """
    law = jax.lax.stop_gradient(law)
    log_snr = jax.lax.stop_gradient(log_snr)
    log_t = jax.lax.stop_gradient(log_t)
    zero = jnp.zeros_like(log_snr)
    y_c = 4.0 * (1.0 + law.cdf_power + jnp.exp(log_snr))

    def slope_positive(w):
        f = lambda w_: _log_integrand(law, w_, zero, log_snr, log_t)
        return jax.jvp(f, (w,), (jnp.ones_like(w),))[1] > 0.0

    lo, hi = _bisect(slope_positive, zero, jnp.log(y_c))
    c0 = 0.5 * (lo + hi)
    level = _log_integrand(law, zero, c0, log_snr, log_t) - _DROP
    # both cut points in one search (last axis: left, right), each between the mode (offset 0,
    # above the level) and a far end below it (the bounds of the module docstring)
    far = jnp.stack([math.log(0.5) - 2.0 * _DROP - 1.0 - c0, jnp.log(y_c + 4.0 * _DROP) - c0], axis=-1)

    def above(v):
        return _log_integrand(law, v, c0[..., None], log_snr[..., None], log_t[..., None]) >= level[..., None]

    _, ends = _bisect(above, jnp.zeros_like(far), far)
    # width of the peak from the curvature of the log-integrand at the mode
    ones = jnp.ones_like(c0)
    slope = lambda v: jax.jvp(lambda v_: _log_integrand(law, v_, c0, log_snr, log_t), (v,), (ones,))[1]
    curvature = -jax.jvp(slope, (zero,), (ones,))[1]
    width = _WIDTH_FACTOR / jnp.sqrt(jnp.clip(curvature, 1e-12, 1e12))
    return c0, ends[..., 0], ends[..., 1], width


def _pd_steady(law, log_snr, log_t):
    """Swerling 0: E_Y[F(Y/T)] by the trapezoidal rule; above 200 dB, F((1 + S)/T)."""
    big = log_snr > _LOG_SNR_CONCENTRATED
    quadrature = _pd_trapezoid(law, jnp.where(big, _LOG_SNR_CONCENTRATED, log_snr), log_t)
    concentrated = jnp.exp(law.log_cdf(jax.nn.softplus(log_snr) - log_t))
    return jnp.where(big, concentrated, quadrature)


def steady_target_pd(law, log_snr, log_t):
    """Swerling 0, one pulse: ``Pd = E_Y[F(Y/T)]`` for a noise estimate ``X`` of law ``law``
    (needs only ``law.log_cdf`` and ``law.cdf_power``), SNR ``S = exp(log_snr)`` and multiplier
    ``T = exp(log_t)``, by the rule of the module docstring; at most 1. Shared with the
    cell-averaging CFAR of :mod:`diffsense.detection.cfar`, whose estimate is Gamma(M, 1)."""
    return jnp.minimum(_pd_steady(law, log_snr, log_t), 1.0)


def _pd_trapezoid(law, log_snr, log_t):
    """E_Y[F(Y/T)], trapezoidal rule in tau with log y = c0 + beta sinh(tau)."""
    c0, v_lo, v_hi, beta = _quadrature_grid(law, log_snr, log_t)
    tau_lo, tau_hi = jnp.arcsinh(v_lo / beta), jnp.arcsinh(v_hi / beta)
    frac = np.linspace(0.0, 1.0, _NODES)
    h = (tau_hi - tau_lo) / (_NODES - 1)
    tau = tau_lo[..., None] + (tau_hi - tau_lo)[..., None] * frac
    v = beta[..., None] * jnp.sinh(tau)
    log_vals = _log_integrand(law, v, c0[..., None], log_snr[..., None], log_t[..., None])
    vals = jnp.exp(log_vals) * jnp.cosh(tau)
    return jnp.exp(c0) * (h * beta) * jnp.sum(vals, axis=-1)


def _pd(law, swerling: int, log_snr, log_t):
    """Pd for multiplier T = exp(log_t) and SNR S = exp(log_snr) (single pulse), at most 1."""
    if swerling == 1:
        pd = jnp.exp(law.log_laplace(log_t - jax.nn.softplus(log_snr)))
    elif swerling == 3:
        log_half_gain = jax.nn.softplus(log_snr - math.log(2.0))  # log(1 + S/2)
        log_c = log_t - log_half_gain
        b0_t = jnp.exp(log_t + log_snr - math.log(2.0) - 2.0 * log_half_gain)  # T (S/2)/(1+S/2)^2
        pd = jnp.exp(law.log_laplace(log_c)) * (1.0 + b0_t * law.tilted_mean(log_c))
    else:
        pd = _pd_steady(law, log_snr, log_t)
    return jnp.where(pd < 1.0, pd, 1.0)  # sums and products may round a few ulp above 1


@partial(jax.jit, static_argnums=1)
def _pd_jit(law, swerling, snr_db, log_pfa):
    return _pd(law, swerling, snr_db * _NEPER_PER_DB, _log_multiplier(law, log_pfa))


# --------------------------------------------------------------------------------------
# Required SNR
# --------------------------------------------------------------------------------------


def _h(law, swerling, x_db, log_t):
    """log(-log Pd) at SNR x_db: decreasing in x_db, nearly linear once Pd is near 1.

    Pd is capped at 1 - 1e-12 (far above PD_MAX): nearer to 1 the computed miss probability is
    rounding noise, whose slope would stop the iteration; the flat cap sends it to bisection.
    """
    pd = _pd(law, swerling, x_db * _NEPER_PER_DB, log_t)
    return jnp.log(-jnp.log(jnp.where(pd < _PD_CAP, pd, _PD_CAP)))


def _closed_snr_db(law, log_pd, log_pfa):
    """Swerling 1/2: S = T(Pfa)/T(Pd) - 1 (in dB)."""
    gap = _log_multiplier(law, log_pfa) - _log_multiplier(law, log_pd)
    return DB_PER_NEPER * jnp.log(jnp.expm1(gap))


@partial(jax.custom_jvp, nondiff_argnums=(1,))
def _iterated_snr_db(law, swerling, log_pd, log_pfa):
    log_t = _log_multiplier(law, log_pfa)
    target = jnp.log(-log_pd)
    x0 = _closed_snr_db(law, log_pd, log_pfa)  # the Swerling 1 requirement: start and bracket
    lo, hi = x0 - _BRACKET_DB[0], x0 + _BRACKET_DB[1]
    residual = lambda x: _h(law, swerling, x, log_t) - target
    x, lo_end, hi_end = newton_decreasing(forward_slope(residual), x0, lo, hi, lambda x: 1e-12, _MAX_NEWTON)
    # a root at an end of the bracket is not a root: NaN, never a substituted number
    inside = (lo_end > lo) | (hi_end < hi)
    return jnp.where(inside, x, jnp.nan)


@_iterated_snr_db.defjvp
def _iterated_snr_db_jvp(swerling, primals, tangents):
    law, log_pd, log_pfa = primals
    x = _iterated_snr_db(law, swerling, log_pd, log_pfa)

    def resid(x_, law_, log_pd_, log_pfa_):
        return _h(law_, swerling, x_, _log_multiplier(law_, log_pfa_)) - jnp.log(-log_pd_)

    _, dr_dx = jax.jvp(lambda x_: resid(x_, law, log_pd, log_pfa), (x,), (jnp.ones_like(x),))
    _, dr_dtheta = jax.jvp(lambda *theta: resid(x, *theta), (law, log_pd, log_pfa), tangents)
    return x, -dr_dtheta / dr_dx


def _required_snr_db(law, swerling, log_pd, log_pfa):
    if swerling == 1:
        return _closed_snr_db(law, log_pd, log_pfa)
    return _iterated_snr_db(law, swerling, log_pd, log_pfa)


_required_snr_jit = jax.jit(_required_snr_db, static_argnums=1)


@partial(jax.jit, static_argnums=0)
def _known_noise_db(swerling, pd, pfa):
    """The known-noise single-pulse requirement, compiled once per Swerling class and shape."""
    return required_snr_db(pd, pfa, 1, swerling)


# --------------------------------------------------------------------------------------
# Public-API helpers (argument checks, domain, compiled entry points)
# --------------------------------------------------------------------------------------


def static_int(where, name, value, lo, hi=None):
    """A concrete integer argument in [lo, hi] (static structure), else DomainError."""
    if isinstance(value, jax.core.Tracer) or not is_concrete(value):
        raise DomainError(f"{where}: argument '{name}' must be a static Python int, not a traced value")
    try:
        as_int = operator.index(value)
    except TypeError:
        if isinstance(value, float) and value.is_integer():
            as_int = int(value)
        else:
            raise DomainError(f"{where}: argument '{name}' must be an integer; got {value!r}") from None
    if as_int < lo or (hi is not None and as_int > hi):
        upper = "" if hi is None else f" and <= {hi}"
        raise DomainError(f"{where}: argument '{name}' must be >= {lo}{upper}; got {as_int}")
    return as_int


def _admitted(where, constraints, fills, greater=()):
    ok, _ = admit(where, constraints, greater)
    return ok, [guard(c[1], ok, f) for c, f in zip(constraints, fills)]


def _swerling_class(where, swerling):
    """1 for Swerling 1/2, 3 for 3/4, 0 for 0 (one pulse: the pairs coincide)."""
    check_choice("swerling", swerling, _SWERLING, where=where)
    return {0: 0, 1: 1, 2: 1, 3: 3, 4: 3}[int(swerling)]


def multiplier_api(where, law, pfa):
    (pfa,) = as_float(pfa)
    ok, (pfa,) = _admitted(where, [("pfa", pfa, *PFA_RANGE)], (1e-6,))
    return guard(_multiplier_jit(law, jnp.log(pfa)), ok)


@jax.jit
def _multiplier_jit(law, log_pfa):
    return jnp.exp(_log_multiplier(law, log_pfa))


def pfa_api(where, law, multiplier):
    (t,) = as_float(multiplier)
    ok, (t,) = _admitted(where, [("multiplier", t, 0.0, None, True, False)], (1.0,))
    return guard(_pfa_jit(law, jnp.log(t)), ok)


@jax.jit
def _pfa_jit(law, log_t):
    return jnp.exp(law.log_laplace(log_t))


def pd_api(where, law, snr_db, pfa, swerling):
    sw = _swerling_class(where, swerling)
    snr_db, pfa = jnp.broadcast_arrays(*as_float(snr_db, pfa))
    ok, (snr_db, pfa) = _admitted(where, [("snr_db", snr_db, *SNR_RANGE_DB), ("pfa", pfa, *PFA_RANGE)],
                                  (0.0, 1e-6))
    return guard(_pd_jit(law, sw, snr_db, jnp.log(pfa)), ok)


def _admit_pd(where, pd, pfa, pfa_range=PFA_RANGE):
    pd, pfa = jnp.broadcast_arrays(*as_float(pd, pfa))
    return _admitted(where, [("pd", pd, 0.0, PD_MAX, True, False), ("pfa", pfa, *pfa_range)], (0.5, 1e-6),
                     greater=[("argument 'pd'", pd, "'pfa'", pfa)])


def required_snr_api(where, law, pd, pfa, swerling):
    sw = _swerling_class(where, swerling)
    ok, (pd, pfa) = _admit_pd(where, pd, pfa)
    return guard(_required_snr_jit(law, sw, jnp.log(pd), jnp.log(pfa)), ok)


def law_loss_db(law, swerling, pd, pfa, where="law_loss_db"):
    """CFAR loss (dB) of a law: the required SNR with the law's estimate minus the known-noise
    single-pulse requirement, without the public functions' domain checks (for a law built inside
    a traced program, a chain's budget, whose parameter bounds keep pd and pfa in the domain)."""
    sw = _swerling_class(where, swerling)
    pd, pfa = jnp.broadcast_arrays(*as_float(pd, pfa))
    # the known-noise requirement's own domain (pd <= 1 - 1e-12, pfa <= 0.5) contains this one
    return _required_snr_jit(law, sw, jnp.log(pd), jnp.log(pfa)) - _known_noise_db(sw, pd, pfa)


def loss_api(where, law, pd, pfa, swerling):
    ok, (pd, pfa) = _admit_pd(where, pd, pfa, PFA_LOSS_RANGE)
    return guard(law_loss_db(law, swerling, pd, pfa, where), ok)
