"""Cell-averaging CFAR (CA-CFAR) after noncoherent integration of N square-law pulses.

Model. In every range cell the square-law detector output, summed over N pulses and
normalised to the mean noise power of one pulse, is ``Gamma(N, 1)`` under noise alone. The
noise level is estimated from M reference cells, ``Z = sum of the M cell statistics ~
Gamma(M N, 1)``, and the cell under test ``Y`` is declared a detection when ``Y > alpha Z``.
``S`` is the mean per-pulse signal-to-noise ratio (linear; ``snr_db = 10 log10 S``).

False alarms. ``Y/(Y+Z) ~ Beta(N, M N)``, hence::

    Pfa = P(Y > alpha Z) = I_{1/(1+alpha)}(M N, N)        (N = 1: Pfa = (1+alpha)^(-M))

with ``I_x(a, b)`` the regularized incomplete beta function. ``alpha`` does not depend on the
noise power: the false-alarm rate is constant.

Detection.
- Swerling 2 (independent exponential power from pulse to pulse), any N: ``Y = (1+S) Y0``
  with ``Y0 ~ Gamma(N, 1)``, so ``Pd = I_{1/(1+alpha/(1+S))}(M N, N)`` (exact).
- Swerling 1 with N = 1 coincides with Swerling 2: ``Pd = (1 + alpha/(1+S))^(-M)`` (exact).
- Swerling 3 and 4 with N = 1 (they coincide): the echo power is chi-square with 4 degrees of
  freedom, ``P(Y > t) = (1 + b0 t) exp(-t/(1+S/2))``, ``b0 = (S/2)/(1+S/2)^2``, and the
  moments of ``Z ~ Gamma(M, 1)`` give ``Pd = (1+c)^(-M) (1 + b0 alpha M/(1+c))``,
  ``c = alpha/(1+S/2)`` (exact).
- Otherwise (Swerling 0; Swerling 1, 3, 4 with N > 1)::

      Pd = E_Z[ Pd_fixed(T = alpha Z) ],  Z ~ Gamma(M N, 1),

  with ``Pd_fixed`` the known-noise detection probability for a threshold ``T`` on the
  integrated statistic (:func:`diffsense.detection.core.pd_given_threshold`). The expectation
  is evaluated by a 64-node generalized Gauss-Laguerre rule for ``Z ~ Gamma(M N, 1)`` (nodes
  and weights from the Golub-Welsch eigenproblem, so they follow traced ``M N``), exponentially
  tilted by the tail rate of ``Pd_fixed`` (see :func:`_pd_quadrature`) so that large
  multipliers (few reference cells) are handled. Applied to the Swerling 1/2 laws, whose
  expectations are known in closed form, the error measured in ``tests/test_cfar.py`` is below
  1e-12 absolute for M >= 3 (N = 1-100, Pfa 1e-4-1e-12, S = -5-40 dB) and for M = 1-2 with
  N <= 30; it reaches 4e-10 (M = 2) and 4e-5 (M = 1) at N = 100.

  A steady target (Swerling 0) is the hard case for this rule: ``Pd_fixed(alpha z)`` falls
  from 1 to 0 within ``~2 sqrt(N S)/alpha`` of its midpoint, a near step that the nodes of a
  Gamma law with a small shape ``M N`` do not resolve when the multiplier is large (few cells,
  small Pfa). With **one pulse and M <= 64** Pd is therefore computed in the Fubini form
  ``Pd = E_Y[P(M, Y/alpha)]`` over the Rician law of the cell under test, the bell-shaped,
  log-concave integrand of the OS/GO/SO engine's Swerling 0 rule
  (:func:`diffsense.detection._cfar_engine.steady_target_pd`, the noise estimate's
  distribution function ``P(M, x)`` the regularized lower incomplete gamma function); above
  64 cells the Gauss-Laguerre nodes resolve the step and that rule is kept (the Fubini rule's
  sharp factor ``P(M, .)`` loses it there: 7e-5 in Pd at M = 1e4). Measured against mpmath
  series in ``tests/detection/test_cfar.py``: the one-pulse required SNR within 1e-10 dB for
  M = 8-1000 (Pfa 1e-2-1e-12, Pd 0.1-0.999) and M = 1-2 at Pfa 1e-2; over M = 3-1e4 within
  1.1e-8 dB (the worst: M = 4, Pfa 1e-12, Pd 0.1; 3.1e-10 dB at M = 1e4, Pd 0.999); with N > 1 pulses and
  ``M N >= 16`` within 1e-10 dB (Pfa 1e-6-1e-12; these and the numbers below measured with
  the same series, some of them kept as slow tests), but with fewer cells and pulses the rule
  still misses the step: measured 1.6e-4 dB at M = 4, N = 2, 4e-4 dB at M = 2, N = 4 and
  0.24 dB at M = 2, N = 2 (Pfa 1e-12, Pd 0.99); 1e-10 dB at M = 3, N = 2, Pfa 1e-6.
  Swerling 1, 3, 4 with N > 1 (exponential tails, which the tilt absorbs): within 5e-9 dB
  at M = 2-8, N = 2-4, Pfa 1e-6-1e-12.

CFAR loss. ``L = S_cfar - S_fixed`` (dB): ``S_cfar`` solves ``cfar_pd(S) = Pd`` (safeguarded
Newton iteration on ``log(-log Pd)`` in dB, derivatives implicit), ``S_fixed`` is the
known-noise requirement :func:`diffsense.detection.required_snr_db`. Swerling 1, N = 1 closed
form: ``S_cfar = alpha / (Pd^(-1/M) - 1) - 1``, ``S_fixed = ln Pfa / ln Pd - 1``.

Derivatives. ``alpha`` and the required SNR are implicit functions (custom JVPs). The
incomplete beta function is differentiated exactly in ``x``; in the counts ``M`` and ``N``
(continuous relaxation: any real >= 1) by central differences of step ``1e-5 max(1, a)``,
relative error ~1e-7.

Sources
-------
- H. M. Finn and R. S. Johnson, "Adaptive detection mode with threshold control as a function
  of spatially sampled clutter-level estimates", RCA Review 29, 414-464 (1968).
- P. P. Gandhi and S. A. Kassam, "Analysis of CFAR processors in nonhomogeneous background",
  IEEE Trans. AES 24(4), 427-445 (1988) (Swerling 1 CA-CFAR: ``Pd = (1 + T/(1+S))^(-M)``
  with ``T`` the multiplier of the summed reference cells).
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed. (McGraw-Hill, 2014),
  sec. 7.4 (CA-CFAR multiplier ``alpha = Pfa^(-1/M) - 1`` for the summed estimate, CFAR loss).
- G. Brooker, *Introduction to Sensors for Ranging and Imaging*, sec. 9.8 (CFAR processors)
  and the worked example 9.9.1 (CFAR loss 0.7 dB).
- G. H. Golub and J. H. Welsch, "Calculation of Gauss quadrature rules", Math. Comp. 23,
  221-230 (1969).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.special import betainc, gammaln, ndtri

from diffsense.numerics.checks import check_choice, is_concrete
from diffsense.numerics.bracketed_newton import forward_slope, newton_decreasing
from diffsense.numerics.db import from_db10
from diffsense.detection import core  # the known-noise detector model
from diffsense.detection._cfar_engine import steady_target_pd  # Swerling 0, one pulse (Fubini form)
from diffsense.detection._gamma import log_gamma_pq
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import as_float
from diffsense.detection.required_snr import required_snr_db  # the known-noise requirement

__all__ = [
    "cfar_multiplier",
    "cfar_pfa",
    "cfar_pd",
    "cfar_required_snr_db",
    "cfar_loss_db",
]

_QUAD_NODES = 64
_FD_REL_STEP = 1e-5
_MAX_NEWTON = 100
_ROOT_ITERATIONS = 40
#: the Newton step (dB) below which the required SNR has settled (quadratic convergence: its error
#: is then far below 1e-11 dB)
_SNR_STEP_DB = 1e-11
_SNR_BRACKET_DB = (-40.0, 100.0)
#: reference cells up to which the one-pulse Swerling 0 Pd uses the Fubini form (module docstring)
_FUBINI_MAX_CELLS = 64.0
#: an iterate this near an end of the bracket (dB) is not a root
_BRACKET_END_DB = 1e-6
#: largest Pd the required-SNR iteration sees (:func:`_h`): nearer to 1 the quadrature's miss
#: probability 1 - Pd is rounding noise
_PD_CAP = 1.0 - 1e-12


# --------------------------------------------------------------------------------------
# log of the regularized incomplete beta function, differentiable in a, b and x
# --------------------------------------------------------------------------------------


@jax.custom_jvp
def _log_ibeta(a, b, x):
    """log I_x(a, b) (jax.scipy betainc, measured relative error < 4e-12 for a <= 3200)."""
    return jnp.log(betainc(a, b, x))


@_log_ibeta.defjvp
def _log_ibeta_jvp(primals, tangents):
    a, b, x = primals
    da, db, dx = tangents
    val = _log_ibeta(a, b, x)
    # d/dx I = x^(a-1) (1-x)^(b-1) / B(a, b)
    xs = jnp.clip(x, 1e-300, 1.0 - 1e-16)
    # (jax.scipy.special.betaln is only accurate to ~1e-7 here; use log-gamma values)
    log_beta = gammaln(a) + gammaln(b) - gammaln(a + b)
    log_dens = (a - 1.0) * jnp.log(xs) + (b - 1.0) * jnp.log1p(-xs) - log_beta
    d_dx = jnp.exp(log_dens - val)
    ha = _FD_REL_STEP * jnp.maximum(a, 1.0)
    hb = _FD_REL_STEP * jnp.maximum(b, 1.0)
    d_da = (_log_ibeta(a + ha, b, x) - _log_ibeta(a - ha, b, x)) / (2.0 * ha)
    d_db = (_log_ibeta(a, b + hb, x) - _log_ibeta(a, b - hb, x)) / (2.0 * hb)
    return val, d_dx * dx + d_da * da + d_db * db


def _log_pfa(alpha, m, n):
    """log Pfa = log I_{1/(1+alpha)}(M N, N)."""
    return _log_ibeta(m * n, n, 1.0 / (1.0 + alpha))


# --------------------------------------------------------------------------------------
# Multiplier
# --------------------------------------------------------------------------------------


def _paulson_log_alpha(log_pfa, m, n):
    """Initial guess: Paulson's cube-root normal approximation of the F(2N, 2MN) quantile.

    ``P(Y > alpha Z) = P(F > alpha M)`` with ``F = (Y/N)/(Z/(MN)) ~ F(2N, 2MN)``. Returns NaN
    where the approximation has no real solution (tiny Pfa with small M N).
    """
    z = -ndtri(jnp.exp(log_pfa))
    c1 = 2.0 / (9.0 * 2.0 * n)
    c2 = 2.0 / (9.0 * 2.0 * m * n)
    a, b = 1.0 - c2, 1.0 - c1
    q = a * a - z * z * c2
    disc = a * a * b * b - q * (b * b - z * z * c1)
    ok = (q > 0.0) & (disc >= 0.0)
    w = (a * b + jnp.sqrt(jnp.where(ok, disc, 1.0))) / jnp.where(ok, q, 1.0)
    return jnp.where(ok & (w > 0.0), 3.0 * jnp.log(jnp.where(w > 0.0, w, 1.0)) - jnp.log(m), jnp.nan)


def _solve_log_alpha(log_pfa, m, n):
    # Bracket in s = log(alpha): at s = -30 Pfa ~ 1 > pfa; at the single-pulse value
    # alpha_1 = Pfa^(-1/M) - 1 the N-pulse false-alarm probability is already <= pfa (the
    # ratio Y/Z concentrates as N grows). Safeguarded Newton on log Pfa(s) - log pfa, which is
    # concave and decreasing in s; bisection whenever the Newton step leaves the bracket or
    # Pfa underflows.
    hi = jnp.log(jnp.expm1(-log_pfa / m)) + 1e-12
    lo = jnp.full_like(hi, -30.0)
    s0 = _paulson_log_alpha(log_pfa, m, n)
    s0 = jnp.where(jnp.isfinite(s0) & (s0 > lo) & (s0 < hi), s0, hi - 1e-3)
    residual = lambda s_: _log_pfa(jnp.exp(s_), m, n) - log_pfa
    s, _, _ = newton_decreasing(forward_slope(residual), s0, lo, hi, lambda s_: 1e-14, _MAX_NEWTON)
    return s


@jax.custom_jvp
def _log_alpha(log_pfa, m, n):
    single = jnp.log(jnp.expm1(-log_pfa / m))
    multi = _solve_log_alpha(log_pfa, m, jnp.where(n == 1.0, 2.0, n))
    return jnp.where(n == 1.0, single, multi)


@_log_alpha.defjvp
def _log_alpha_jvp(primals, tangents):
    log_pfa, m, n = primals
    dlp, dm, dn = tangents
    s = _log_alpha(log_pfa, m, n)
    f = lambda s_, m_, n_: _log_pfa(jnp.exp(s_), m_, n_)
    _, dg_ds = jax.jvp(lambda s_: f(s_, m, n), (s,), (jnp.ones_like(s),))
    _, dg_dtheta = jax.jvp(lambda m_, n_: f(s, m_, n_), (m, n), (dm, dn))
    return s, (dlp - dg_dtheta) / dg_ds


def _common(pfa, m, n):
    """Domain constraints shared by the CA-CFAR functions (see ``_domain.admit``)."""
    return [("pfa", pfa, 1e-300, 1.0, False, True), ("m_cells", m, 1.0, None), ("n", n, 1.0, None)]


def _admitted(where, constraints, fills, greater=()):
    """Admission of the arguments: ``(ok, placeholders)`` (DomainError if eager, see ``_domain``)."""
    ok, _ = admit(where, constraints, greater)
    return ok, [guard(c[1], ok, f) for c, f in zip(constraints, fills)]


def cfar_multiplier(pfa, m_cells, n=1):
    """CA-CFAR threshold multiplier ``alpha`` on the sum ``Z`` of the reference cells.

    Solves ``Pfa = I_{1/(1+alpha)}(M N, N)`` (regularized incomplete beta); for ``N = 1`` the
    closed form ``alpha = Pfa^(-1/M) - 1``. For ``N > 1`` Newton's method on ``log Pfa`` as a
    function of ``log alpha`` (converged to 1e-15 relative; accuracy then set by ``betainc``,
    < 4e-12 relative in Pfa), implicitly differentiated.

    Args:
        pfa: false-alarm probability, 1e-300 <= pfa < 1.
        m_cells: number of reference cells M (real >= 1; derivatives are the continuous
            relaxation).
        n: number of pulses integrated noncoherently per cell (real >= 1).

    Returns:
        ``alpha`` (dimensionless): detection when ``Y > alpha Z`` with ``Y`` the cell under test
        and ``Z`` the sum of the M reference-cell statistics.

    Source: Finn & Johnson (1968); Richards, *Fundamentals of Radar Signal Processing*,
    2nd ed., sec. 7.4; Gandhi & Kassam (1988) eq. for the CA detector.

    One pulse, 16 reference cells, Pfa = 1e-6 (closed form); for N = 4 pulses the multiplier
    returns Pfa through scipy's independent incomplete beta function:

    >>> float(cfar_multiplier(1e-6, 16)), 1e-6 ** (-1 / 16) - 1
    (1.37137, 1.37137)
    >>> from scipy.special import betainc
    >>> a4 = float(cfar_multiplier(1e-6, 16, 4))
    >>> float(betainc(16 * 4, 4, 1 / (1 + a4)) / 1e-6)
    1.0000000
    """
    pfa, m, n = jnp.broadcast_arrays(*as_float(pfa, m_cells, n))
    ok, (pfa, m, n) = _admitted("cfar_multiplier", _common(pfa, m, n), (1e-6, 16.0, 1.0))
    return guard(_alpha_jit(pfa, m, n), ok)


@jax.jit
def _alpha_jit(pfa, m, n):
    return jnp.exp(_log_alpha(jnp.log(pfa), m, n))


def cfar_pfa(alpha, m_cells, n=1):
    """False-alarm probability ``I_{1/(1+alpha)}(M N, N)`` of CA-CFAR for a multiplier ``alpha``.

    Args:
        alpha: multiplier of the reference-cell sum (> 0).
        m_cells: number of reference cells M (real >= 1).
        n: pulses integrated per cell (real >= 1).

    >>> float(cfar_pfa(1.0, 10)), 2.0 ** -10    # one pulse: (1 + alpha)^(-M)
    (0.00097656, 0.00097656)
    """
    alpha, m, n = jnp.broadcast_arrays(*as_float(alpha, m_cells, n))
    ok, (alpha, m, n) = _admitted("cfar_pfa", [("alpha", alpha, 0.0, None, True, False), ("m_cells", m, 1.0, None),
                                               ("n", n, 1.0, None)], (1.0, 16.0, 1.0))
    return guard(jnp.exp(_log_pfa(alpha, m, n)), ok)


# --------------------------------------------------------------------------------------
# Detection probability
# --------------------------------------------------------------------------------------


def _gauss_laguerre(a, k: int = _QUAD_NODES):
    """Nodes and normalized weights for E[g(Z)], Z ~ Gamma(a, 1) (Golub-Welsch).

    Jacobi matrix of the generalized Laguerre polynomials L_j^(a-1): diagonal 2j + a
    (j = 0..k-1), off-diagonal sqrt(j (j + a - 1)) (j = 1..k-1). Weights = squared first eigenvector
    components (they sum to 1).
    """
    i = jnp.arange(k)
    row, col = i[:, None], i[None, :]
    mx = jnp.maximum(row, col).astype(a.dtype)
    adjacent = jnp.abs(row - col) == 1
    mx_safe = jnp.where(adjacent, mx, 1.0)
    aa = a[..., None, None]
    off = jnp.sqrt(mx_safe * (mx_safe + aa - 1.0))
    mat = jnp.where(row == col, 2.0 * mx + aa, jnp.where(adjacent, off, 0.0))
    nodes, vecs = jnp.linalg.eigh(mat)
    weights = vecs[..., 0, :] ** 2
    return nodes, weights


def _tail_rate(snr_linear, n, swerling: int):
    """Exponential decay rate ``kappa`` of Pd_fixed(T) in T (large-T tail), per Swerling case.

    Swerling 2: exp(-T/(1+S)); Swerling 4: exp(-T/(1+S/2)); Swerling 1: exp(-T/(1+N S));
    Swerling 3: exp(-T/(1+N S/2)); Swerling 0: exp(-T + 2 sqrt(N S T)), for which 1/(1+S)
    is used (slower than the true rate 1, so the tilted integrand still decays).
    """
    if swerling == 1:
        return 1.0 / (1.0 + n * snr_linear)
    if swerling == 3:
        return 1.0 / (1.0 + 0.5 * n * snr_linear)
    if swerling == 4:
        return 1.0 / (1.0 + 0.5 * snr_linear)
    return 1.0 / (1.0 + snr_linear)


def _pd_quadrature(snr_linear, alpha, m, n, pd_fixed, kappa):
    """E_Z[pd_fixed(snr, alpha Z, n)], Z ~ Gamma(M N, 1), by tilted generalized Gauss-Laguerre.

    With ``c = 1 + kappa alpha`` and ``u = c Z``::

        E = sum_k w_k pd_fixed(alpha u_k / c) exp(kappa alpha u_k / c - M N log c)

    where (u_k, w_k) is the Gauss rule for Gamma(M N, 1). The exponential tilt absorbs the
    decay ``exp(-kappa T)`` of Pd_fixed, so the remaining integrand is a polynomial of degree
    N - 1 for Swerling 2 (integer N) and a constant for Swerling 1 with N = 1 (the rule is then
    exact), and slowly varying otherwise, whatever the size of alpha.
    """
    a = m * n
    nodes, weights = _gauss_laguerre(a)
    c = 1.0 + kappa * alpha
    scale = (alpha / c)[..., None]
    log_tilt = (kappa * alpha / c)[..., None] * nodes - (a * jnp.log(c))[..., None]
    vals = pd_fixed(snr_linear[..., None], scale * nodes, n[..., None])
    return jnp.sum(weights * vals * jnp.exp(log_tilt), axis=-1)


def _pd_swerling2(snr_linear, alpha, m, n):
    return jnp.exp(_log_ibeta(m * n, n, 1.0 / (1.0 + alpha / (1.0 + snr_linear))))


def _core_pd_given_threshold(swerling: int):
    return lambda s, t, n: core.pd_given_threshold(s, t, n, swerling)


@jax.custom_jvp
def _log_gamma_p(a, log_x):
    """log P(a, x) at x = exp(log_x): the regularized lower incomplete gamma function, the
    distribution function of Gamma(a, 1) (:func:`diffsense.detection._gamma.log_gamma_pq`, full
    relative accuracy), differentiable in log x exactly and in a by central differences."""
    return log_gamma_pq(a, jnp.exp(log_x))[0]


@_log_gamma_p.defjvp
def _log_gamma_p_jvp(primals, tangents):
    a, log_x = primals
    da, dlx = tangents
    val = _log_gamma_p(a, log_x)
    # d log P / d log x = x f(x) / P with the Gamma(a, 1) density f
    d_lx = jnp.exp(a * log_x - jnp.exp(log_x) - gammaln(a) - val)
    h = _FD_REL_STEP * jnp.maximum(a, 1.0)
    d_a = (_log_gamma_p(a + h, log_x) - _log_gamma_p(a - h, log_x)) / (2.0 * h)
    return val, d_lx * dlx + d_a * da


@partial(jax.tree_util.register_dataclass, data_fields=["m"], meta_fields=[])
@dataclass(frozen=True)
class _CellSum:
    """Law of the one-pulse CA noise estimate, the sum of M unit-mean exponential cells:
    Gamma(M, 1), F(x) = P(M, x) ~ x^M / Gamma(M + 1) at 0 (what the Swerling 0 rule of
    :mod:`diffsense.detection._cfar_engine` needs)."""

    m: object

    @property
    def cdf_power(self):
        return self.m

    def log_cdf(self, log_x):
        """log P(M, x); ``log_x`` may carry trailing axes (the rule's nodes) beyond M's shape."""
        m = jnp.asarray(self.m)
        return _log_gamma_p(jnp.reshape(m, m.shape + (1,) * (jnp.ndim(log_x) - m.ndim)), log_x)


def _pd_steady_fubini(snr_linear, alpha, m):
    """Swerling 0, one pulse: Pd = E_Y[P(M, Y/alpha)] over the Rician cell under test (the
    Fubini form of E_Z[Pd_fixed(alpha Z)], module docstring; used for M <=
    :data:`_FUBINI_MAX_CELLS`)."""
    return steady_target_pd(_CellSum(m), jnp.log(snr_linear), jnp.log(alpha))


def _pd_chi4_single(snr_linear, alpha, m):
    """Swerling 3/4, one pulse (the two coincide): the echo power is chi-square with 4 degrees
    of freedom, P(Y > t) = (1 + b0 t) exp(-t/(1 + S/2)) with b0 = (S/2)/(1 + S/2)^2, so with
    E[exp(-c Z)] = (1 + c)^-M and E[Z exp(-c Z)] = M (1 + c)^(-M-1) for Z ~ Gamma(M, 1)::

        Pd = (1 + c)^-M (1 + b0 alpha M / (1 + c)),   c = alpha / (1 + S/2)."""
    half = 1.0 + 0.5 * snr_linear
    c = alpha / half
    b0 = 0.5 * snr_linear / (half * half)
    return jnp.exp(-m * jnp.log1p(c) + jnp.log1p(b0 * alpha * m / (1.0 + c)))


def _pd_from_alpha(snr_linear, alpha, m, n, model):
    """Pd by the exact form where one applies (module docstring: Swerling 2; one pulse of
    Swerling 1, 3, 4; one pulse of Swerling 0 with M <= :data:`_FUBINI_MAX_CELLS`), elsewhere by
    the Gauss-Laguerre rule."""
    swerling, single_pulse = model
    if swerling == 2 or (swerling == 1 and single_pulse):
        return _pd_swerling2(snr_linear, alpha, m, n)
    one = n == 1.0
    if swerling == 1:
        here, exact = one, _pd_swerling2(snr_linear, alpha, m, n)
    elif swerling == 0:
        here = one & (m <= _FUBINI_MAX_CELLS)
        exact = _pd_steady_fubini(snr_linear, alpha, jnp.where(here, m, 1.0))
    else:
        here, exact = one, _pd_chi4_single(snr_linear, alpha, m)
    if single_pulse and swerling != 0:
        return exact
    # double where: the rule sees benign arguments where the exact form is taken (at the large
    # multipliers of few cells it would walk millions of terms of core's series per node)
    alpha_q, m_q = jnp.where(here, 1.0, alpha), jnp.where(here, _FUBINI_MAX_CELLS, m)
    quad = _pd_quadrature(snr_linear, alpha_q, m_q, n, _core_pd_given_threshold(swerling),
                          _tail_rate(snr_linear, n, swerling))
    return jnp.where(here, exact, quad)


def cfar_pd(snr_db, pfa, m_cells, n=1, swerling=0):
    """Detection probability of CA-CFAR with M reference cells after N-pulse integration.

    ``Pd = P(Y > alpha Z)`` with ``alpha = cfar_multiplier(pfa, M, N)``:
    Swerling 2 (any N) and Swerling 1 (N = 1) exactly, ``Pd = I_{1/(1+alpha/(1+S))}(M N, N)``
    (``= (1 + alpha/(1+S))^(-M)`` for N = 1); Swerling 3/4 with N = 1 in closed form; Swerling 0
    with N = 1 and M <= 64 by the Fubini rule over the cell under test; other cases
    ``Pd = E_Z[Pd_fixed(alpha Z)]`` by 64-node tilted generalized Gauss-Laguerre quadrature over
    ``Z ~ Gamma(M N, 1)`` (errors as measured in the module docstring: a steady target with
    few cells and pulses, M N < 16, and small Pfa is the weak corner).

    Args:
        snr_db: mean per-pulse signal-to-noise ratio in dB (-100 to 100).
        pfa: false-alarm probability, 1e-300 <= pfa < 1.
        m_cells: number of reference cells M (real >= 1).
        n: pulses integrated noncoherently (real >= 1).
        swerling: target fluctuation model 0-4 (static int).

    Returns:
        Pd in [Pfa, 1].

    Source: Gandhi & Kassam (1988); Richards, *Fundamentals of Radar Signal Processing*,
    sec. 7.4; Brooker sec. 9.8.

    Swerling 1, one pulse: Pd = (1 + alpha/(1+S))^(-M) with alpha = Pfa^(-1/M) - 1
    (Gandhi & Kassam), evaluated in closed form:

    >>> alpha = 1e-6 ** (-1 / 16) - 1
    >>> float(cfar_pd(20.0, 1e-6, 16, 1, swerling=1)), (1 + alpha / (1 + 100.0)) ** -16
    (0.80591, 0.80591)
    """
    where = "cfar_pd"
    check_choice("swerling", swerling, (0, 1, 2, 3, 4), where=where)
    model = _model(swerling, n)
    snr_db, pfa, m, n = jnp.broadcast_arrays(*as_float(snr_db, pfa, m_cells, n))
    ok, (snr_db, pfa, m, n) = _admitted(where, [("snr_db", snr_db, -100.0, 100.0)] + _common(pfa, m, n),
                                        (0.0, 1e-6, 16.0, 1.0))
    return guard(_cfar_pd(snr_db, pfa, m, n, model), ok)


@partial(jax.jit, static_argnums=4)
def _cfar_pd(snr_db, pfa, m, n, model):
    alpha = jnp.exp(_log_alpha(jnp.log(pfa), m, n))
    snr = from_db10(snr_db)
    return jnp.minimum(_pd_from_alpha(snr, alpha, m, n, model), 1.0)  # the quadrature may round a few ulp above 1


# --------------------------------------------------------------------------------------
# Required SNR and CFAR loss
# --------------------------------------------------------------------------------------


def _model(swerling, n):
    """Static model key: (Swerling case, True when n is known to be 1 everywhere)."""
    single = bool(is_concrete(n) and np.all(np.asarray(n, dtype=float) == 1.0))
    return (int(swerling), single)


def _h(snr_db, log_alpha, m, n, model):
    """log(-log Pd): decreasing in snr_db, close to linear once Pd is near 1.

    Pd is capped at :data:`_PD_CAP`: the quadrature's sum rounds to 1 or a few ulp above it at
    high SNR, where log(-log Pd) would be NaN and the iteration would stall at the middle of its
    bracket (Swerling 0: 55 dB instead of 14.5 dB at Pd 0.99, Pfa 1e-6, M 64); the flat cap
    sends it to bisection instead."""
    pd = _pd_from_alpha(from_db10(snr_db), jnp.exp(log_alpha), m, n, model)
    return jnp.log(-jnp.log(jnp.minimum(pd, _PD_CAP)))


def _solve_snr_db(target, log_alpha, m, n, model):
    """The SNR (dB) with log(-log Pd) = ``target``: safeguarded Newton iteration
    (:func:`~diffsense.numerics.bracketed_newton.newton_decreasing`; an element whose residual
    is exactly zero stays there) until a step is at most 1e-11 dB."""
    lo = jnp.full_like(target, _SNR_BRACKET_DB[0])
    hi = jnp.full_like(target, _SNR_BRACKET_DB[1])
    x0 = jnp.full_like(target, 10.0)
    x, _, _ = newton_decreasing(forward_slope(lambda x_: _h(x_, log_alpha, m, n, model) - target), x0, lo, hi,
                                lambda x_: _SNR_STEP_DB, _ROOT_ITERATIONS)
    # an iterate left at an end of the bracket is not a root (the requirement lies outside it,
    # e.g. one reference cell at Pfa 1e-12 needs ~150 dB): NaN, never a substituted number
    inside = (x > lo + _BRACKET_END_DB) & (x < hi - _BRACKET_END_DB)
    return jnp.where(inside, x, jnp.nan)


@partial(jax.custom_jvp, nondiff_argnums=(4,))
def _required_snr_db(log_pd, log_pfa, m, n, model):
    log_alpha = _log_alpha(log_pfa, m, n)
    target = jnp.log(-log_pd)
    return _solve_snr_db(target, log_alpha, m, n, model)


@_required_snr_db.defjvp
def _required_snr_db_jvp(model, primals, tangents):
    log_pd, log_pfa, m, n = primals
    dlpd, dlpfa, dm, dn = tangents
    x = _required_snr_db(log_pd, log_pfa, m, n, model)

    def resid(x_, log_pd_, log_pfa_, m_, n_):
        return _h(x_, _log_alpha(log_pfa_, m_, n_), m_, n_, model) - jnp.log(-log_pd_)

    _, dr_dx = jax.jvp(lambda x_: resid(x_, log_pd, log_pfa, m, n), (x,), (jnp.ones_like(x),))
    _, dr_dtheta = jax.jvp(
        lambda a, b, c, d: resid(x, a, b, c, d), (log_pd, log_pfa, m, n), (dlpd, dlpfa, dm, dn)
    )
    return x, -dr_dtheta / dr_dx


_required_snr_db_jit = jax.jit(_required_snr_db, static_argnums=4)


def _admit_pd(where, pd, pfa, m, n):
    """Domain of the required-SNR functions: ``pfa < pd < 1`` and the common constraints."""
    constraints = [("pd", pd, 0.0, 1.0, True, True)] + _common(pfa, m, n)
    return _admitted(where, constraints, (0.5, 1e-6, 16.0, 1.0), greater=[("argument 'pd'", pd, "'pfa'", pfa)])


def cfar_required_snr_db(pd, pfa, m_cells, n=1, swerling=0):
    """Per-pulse SNR (dB) at which CA-CFAR reaches detection probability ``pd``.

    Root of ``cfar_pd(S) = pd``: safeguarded Newton iteration on ``log(-log Pd)`` versus
    ``S`` in dB inside the bracket [-40, 100] dB (until a step is at most 1e-11 dB, at most 40
    steps), implicitly differentiated. Swerling 1, N = 1 closed form
    ``S = alpha / (pd^(-1/M) - 1) - 1``.

    Args:
        pd: required detection probability, pfa < pd < 1.
        pfa: false-alarm probability, 1e-300 <= pfa < 1.
        m_cells: reference cells M (real >= 1).
        n: pulses integrated (real >= 1).
        swerling: 0-4 (static int).

    Returns:
        Per-pulse SNR in dB. Accuracy: that of :func:`cfar_pd` divided by its slope (module
        docstring). NaN where the requirement lies outside the bracket, above 100 dB (e.g. one
        reference cell at Pfa 1e-12 and Pd 0.999: about 150 dB), never a bracket end in its
        place; the domain is the set of arguments whose required SNR lies in -40 ... 100 dB.

    >>> import math
    >>> alpha = 1e-6 ** (-1 / 16) - 1     # Swerling 1, one pulse: closed form
    >>> closed = 10 * math.log10(alpha / (0.9 ** (-1 / 16) - 1) - 1)
    >>> float(cfar_required_snr_db(0.9, 1e-6, 16, 1, swerling=1)), closed
    (23.1507, 23.1507)
    """
    where = "cfar_required_snr_db"
    check_choice("swerling", swerling, (0, 1, 2, 3, 4), where=where)
    model = _model(swerling, n)
    pd, pfa, m, n = jnp.broadcast_arrays(*as_float(pd, pfa, m_cells, n))
    ok, (pd, pfa, m, n) = _admit_pd(where, pd, pfa, m, n)
    return guard(_required_snr_db_jit(jnp.log(pd), jnp.log(pfa), m, n, model), ok)


def cfar_loss_db(pd, pfa, m_cells, n=1, swerling=0):
    """CA-CFAR loss: extra per-pulse SNR (dB) needed relative to a known-noise threshold.

    ``L = cfar_required_snr_db(pd, pfa, M, N, swerling) - required_snr_db(pd, pfa, N, swerling)``
    with the fixed-threshold requirement from :func:`diffsense.detection.required_snr_db`.
    Swerling 1, N = 1 closed form::

        L = 10 log10[(alpha/(pd^(-1/M) - 1) - 1) / (ln Pfa / ln pd - 1)],  alpha = Pfa^(-1/M) - 1

    which tends to 0 dB as M -> infinity.

    Args:
        pd: detection probability, pfa < pd < 1.
        pfa: false-alarm probability, 1e-300 <= pfa < 1.
        m_cells: reference cells M (real >= 1).
        n: pulses integrated noncoherently (real >= 1).
        swerling: 0-4 (static int).

    Returns:
        CFAR loss in dB (> 0); NaN where :func:`cfar_required_snr_db` is (a requirement above
        100 dB).

    Source: Richards, *Fundamentals of Radar Signal Processing*, 2nd ed., sec. 7.4 (CFAR
    loss); Gandhi & Kassam (1988); Brooker 9.9.1 (0.7 dB budgeted).

    Swerling 1, one pulse, 16 reference cells, the closed form above:

    >>> import math
    >>> alpha = 1e-6 ** (-1 / 16) - 1
    >>> closed = 10 * math.log10((alpha / (0.9 ** (-1 / 16) - 1) - 1) / (math.log(1e-6) / math.log(0.9) - 1))
    >>> float(cfar_loss_db(0.9, 1e-6, 16, 1, swerling=1)), closed
    (2.0071, 2.0071)
    """
    where = "cfar_loss_db"
    check_choice("swerling", swerling, (0, 1, 2, 3, 4), where=where)
    model = _model(swerling, n)
    pd, pfa, m, n = jnp.broadcast_arrays(*as_float(pd, pfa, m_cells, n))
    ok, (pd, pfa, m, n) = _admit_pd(where, pd, pfa, m, n)
    s_cfar = _required_snr_db_jit(jnp.log(pd), jnp.log(pfa), m, n, model)
    # the known-noise requirement has its own (narrower) domain: pfa <= 0.5, n <= 1e4
    return guard(s_cfar - required_snr_db(pd, pfa, n, swerling), ok)
