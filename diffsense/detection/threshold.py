"""False-alarm thresholds of the noncoherently integrated square-law detector.

Noise is normalised so that, under noise alone, the sum of N square-law samples is
``Y ~ Gamma(N, 1)``. The threshold ``T`` on ``Y`` solves

    Pfa = Q(N, T) = Gamma(N, T) / Gamma(N)          (regularized upper incomplete gamma),

which for one pulse is ``T = -ln Pfa``, i.e. the envelope threshold ``Vt = sqrt(-2 psi ln Pfa)``
of Brooker eq. (9.14). ``T`` is found by Newton's method on ``log Q`` (concave in T for N >= 1,
so the iteration converges monotonically after the first step) and is therefore correct for
Pfa down to 1e-300: the classic shortcut ``gammaincinv(N, 1 - Pfa)`` cannot represent
``1 - Pfa`` once Pfa < 1.1e-16. For a target above 1/2 the equivalent ``log P(N, T) =
log(1 - Pfa)`` is solved instead, so that T stays accurate for targets within 1e-12 of 1.
Derivatives are implicit: ``dT/dPfa = -1/f(T)``, ``dT/dN = (dQ/dN)/f(T)`` with ``f`` the
Gamma(N, 1) density.

Accuracy: log P and log Q come from ``_gamma.log_gamma_pq``, whose prefactor has no
cancellation (``jax.scipy.special.gammaincc`` loses up to 2e-11 relative at N = 1e4 in its
prefactor, and a threshold solved against it was off by 2e-13 relative, enough to put
``required_snr_db(1 - 1e-12, 0.5, 1e4)`` 2 dB off). Measured against mpmath over N = 1 ... 1e4
and Pfa = 1e-300 ... 1 - 1e-12: relative error of T below 4e-15
(tests/detection/test_detection_domain_properties.py).
"""

from __future__ import annotations

import jax
from jax.custom_derivatives import SymbolicZero
import jax.numpy as jnp
from jax.scipy.special import gammaincc, gammaln, ndtri

from diffsense.detection._domain import admit, guard
from diffsense.detection._gamma import gamma_q, log_gamma_pq
from diffsense.detection._logpmf import log_poisson_pmf
from diffsense.detection._precision import as_float

__all__ = [
    "threshold",
    "pfa_from_threshold",
    "voltage_threshold",
    "pfa_from_false_alarm_time",
    "false_alarm_time_s",
]

_MAX_NEWTON = 40
# Largest pulse count of :func:`threshold` (the incomplete-gamma series and fraction need
# O(sqrt(n)) terms, within their term limit up to here).
_N_MAX = 1e6
# Newton stops once a step is below this relative size; gammaincc's own relative error
# (<= ~2e-11 at n = 1e4) sets the attainable accuracy, and the next quadratic step would be
# far below it. In float32 the floor is a few ulp (``_STEP_TOL_EPS`` x eps = 9.5e-7): a
# relative step of 1e-12 is below its resolution, and the iteration would always run to
# ``_MAX_NEWTON``.
_STEP_TOL = 1e-12
_STEP_TOL_EPS = 8.0


def _log_density(n, t):
    """log of the Gamma(n, 1) density at t: log pois(n-1; t)."""
    return log_poisson_pmf(n - 1.0, t)


def _initial_guess(log_q, log_p, n, lower):
    """Start near the root: Wilson-Hilferty's cube-root normal quantile and a tail estimate.

    Upper mode (solve Q = q): Wilson-Hilferty's quantile is damped by the factor 0.9 in its
    excess over n and is not used in the far tail (z > 3 sqrt(n)), where it overshoots into the
    region where Q underflows; the exponential-tail estimate -ln q + (n-1) ln(-ln q) - lgamma(n)
    lies below the root for n >= 1 because Q(n, T) exceeds the density at T there. Lower mode
    (solve P = p for small p): P(n, T) <= T^n / Gamma(n + 1), so ``(p Gamma(n+1))^(1/n)`` lies
    below the root; Wilson-Hilferty's quantile, damped by 1.1 in its (negative) excess over n,
    is used where it is larger (moderate p).
    """
    c = 1.0 / (9.0 * n)
    z = -ndtri(jnp.exp(log_q))
    wh_raw = n * jnp.maximum(1.0 - c + z * jnp.sqrt(c), 0.05) ** 3
    wh = n + 0.9 * (wh_raw - n)
    lq = -log_q
    tail = lq + (n - 1.0) * jnp.log(jnp.maximum(lq, 1.0)) - gammaln(n)
    far_tail = z > 3.0 * jnp.sqrt(n)
    upper = jnp.where(far_tail, tail, jnp.maximum(wh, tail))
    small = jnp.exp((log_p + gammaln(n + 1.0)) / n)
    start = jnp.where(lower, jnp.maximum(small, n + 1.1 * (wh_raw - n)), upper)
    return jnp.maximum(start, 1e-300)


def _solve_threshold(q, n):
    """Bracketed Newton iteration on g(T) = log F(n, T) - log F_target (F = Q or P, see below).

    For q <= 1/2 it solves ``log Q(n, T) = log q`` (g decreasing and concave); for q > 1/2 the
    equivalent ``log P(n, T) = log(1 - q)`` (increasing and concave; 1 - q is exact there), so
    that T keeps full accuracy when q is within 1e-12 of 1 (the Swerling 2 threshold ratio of
    ``required_snr`` solves Q(n, T) = Pd). Both logarithms come from ``_gamma.log_gamma_pq``.
    """
    lower = q > 0.5
    log_q = jnp.log(q)
    log_p = jnp.log1p(-q)
    log_target = jnp.where(lower, log_p, log_q)
    sign = jnp.where(lower, 1.0, -1.0)  # sign of dg/dT
    t0 = _initial_guess(log_q, log_p, n, lower)

    def body(state):
        t, lo, hi, _, it = state
        log_pp, log_qq = log_gamma_pq(n, t)
        log_f = jnp.where(lower, log_pp, log_qq)
        g = log_f - log_target
        finite = jnp.isfinite(g)
        below = finite & (sign * g < 0)  # root lies above t
        lo = jnp.where(below, t, lo)
        hi = jnp.where(~below, t, hi)
        slope = sign * jnp.exp(_log_density(n, t) - log_f)  # d log F / dT
        t_newton = t - g / slope
        ok = finite & jnp.isfinite(t_newton) & (t_newton >= lo) & (t_newton <= hi)
        fallback = jnp.where(jnp.isfinite(hi), 0.5 * (lo + hi), 2.0 * t)
        t_new = jnp.where(ok, t_newton, fallback)
        return t_new, lo, hi, jnp.abs(t_new - t), it + 1

    tol = max(_STEP_TOL, _STEP_TOL_EPS * float(jnp.finfo(t0.dtype).eps))  # float64: 1e-12

    def cond(state):
        t, _, _, delta, it = state
        return (it < _MAX_NEWTON) & jnp.any(delta > tol * t)

    init = (t0, jnp.zeros_like(t0), jnp.full_like(t0, jnp.inf), jnp.full_like(t0, jnp.inf), 0)
    t, _, _, _, it = jax.lax.while_loop(cond, body, init)
    return t


@jax.custom_jvp
def _threshold(pfa, n):
    return _solve_threshold(pfa, n)


def _threshold_tangents(t, n, dpfa, dn):
    """The tangents (dT from Pfa, dT from N) of T = :func:`_threshold` (Pfa, N) at its value
    ``t``, by the implicit function theorem on Q(N, T) = Pfa: dT = (∂Q/∂N dN − dPfa) / f(T),
    f the Gamma(N, 1) density; each None where its tangent is a symbolic zero."""
    inv_density = jnp.exp(-_log_density(n, t))  # 1 / f(T)
    from_pfa = None if isinstance(dpfa, SymbolicZero) else -dpfa * inv_density
    from_n = None
    if not isinstance(dn, SymbolicZero):
        # ∂Q/∂n (the order derivative of the incomplete gamma function, which JAX cannot
        # differentiate again): only where n is differentiated, so that second derivatives
        # in the other inputs exist
        _, dq_dn = jax.jvp(lambda a: gammaincc(a, t), (n,), (jnp.ones_like(n),))
        from_n = dq_dn * dn * inv_density
    return from_pfa, from_n


def _threshold_jvp(primals, tangents):
    pfa, n = primals
    t = _threshold(pfa, n)
    parts = [d for d in _threshold_tangents(t, n, *tangents) if d is not None]
    return t, sum(parts[1:], parts[0]) if parts else jnp.zeros_like(t)


_threshold.defjvp(_threshold_jvp, symbolic_zeros=True)


def threshold(pfa, n=1):
    """Threshold ``T`` on the integrated statistic ``Y ~ Gamma(n, 1)`` for false-alarm probability ``pfa``.

    Args:
        pfa: false-alarm probability per detection decision, 1e-300 <= pfa < 1.
        n: number of pulses integrated noncoherently (real, 1 ... 1e6; non-integer values give
           the continuous relaxation of the Gamma(n, 1) law).

    Returns:
        ``T`` with ``Q(n, T) = pfa`` (dimensionless, in units of the mean noise power of one pulse).
        Outside the domain an eager call raises DomainError and a traced call returns NaN.

    Examples: one pulse, Pfa = 1e-10 gives T = -ln Pfa = 23.03, so the envelope threshold for
    noise variance psi = 1 V^2 is sqrt(2 T) = 6.79 V (Brooker 9.2.2 prints both numbers). For
    N pulses the threshold returns Pfa through scipy's independent incomplete gamma function:

    >>> float(threshold(1e-10))
    23.03
    >>> float((2.0 * threshold(1e-10)) ** 0.5)
    6.79
    >>> from scipy.special import gammaincc
    >>> float(gammaincc(10.0, float(threshold(1e-6, 10))) / 1e-6)
    1.0000000
    """
    pfa, n = jnp.broadcast_arrays(*as_float(pfa, n))
    ok, _ = admit("threshold", [("pfa", pfa, 1e-300, 1.0, False, True), ("n", n, 1.0, _N_MAX)])
    pfa, n = guard(pfa, ok, 0.5), guard(n, ok, 1.0)
    return guard(_threshold(pfa, n), ok)


def pfa_from_threshold(threshold_value, n=1):
    """False-alarm probability ``Q(n, T)`` for a threshold ``T`` on ``Y ~ Gamma(n, 1)``.

    For one pulse Q(1, T) = exp(-T) (exponential noise power):

    >>> import math
    >>> float(pfa_from_threshold(5.0)), math.exp(-5.0)
    (0.006737947, 0.006737947)
    """
    t, n = as_float(threshold_value, n)
    ok, (ok_t, ok_n) = admit("pfa_from_threshold", [("threshold_value", t, 0.0, None), ("n", n, 1.0, None)])
    return guard(gamma_q(guard(n, ok_n, 1.0), guard(t, ok_t, 1.0)), ok)


def voltage_threshold(pfa, noise_variance_v2=1.0):
    """Envelope-detector threshold ``Vt = sqrt(-2 psi ln Pfa)`` in volts (Brooker eq. 9.14).

    Args:
        pfa: single-sample false-alarm probability, 0 < pfa < 1.
        noise_variance_v2: noise voltage variance psi at the IF filter output (V^2).

    >>> float(voltage_threshold(1e-10, 1.0))   # Brooker 9.2.2: 6.79 V
    6.79
    """
    pfa, psi = as_float(pfa, noise_variance_v2)
    ok, (ok_p, ok_v) = admit("voltage_threshold", [("pfa", pfa, 0.0, 1.0, True, True),
                                                  ("noise_variance_v2", psi, 0.0, None, True, False)])
    pfa, psi = guard(pfa, ok_p, 0.5), guard(psi, ok_v, 1.0)
    return guard(jnp.sqrt(-2.0 * psi * jnp.log(pfa)), ok)


def pfa_from_false_alarm_time(false_alarm_time_s, bandwidth_hz):
    """Pfa = 1 / (Tfa * beta): one independent noise sample per 1/beta seconds (Brooker eq. 9.15).

    Brooker 9.9.1: Tfa = 9 h with beta = 0.613 / 2 us gives the book's Pfa of 1e-10:

    >>> float(pfa_from_false_alarm_time(9 * 3600.0, 0.613 / 2e-6))
    1.0e-10
    """
    tfa, b = as_float(false_alarm_time_s, bandwidth_hz)
    ok, _ = admit("pfa_from_false_alarm_time", [("false_alarm_time_s", tfa, 0.0, None, True, False),
                                                ("bandwidth_hz", b, 0.0, None, True, False)])
    return guard(1.0 / (tfa * b), ok)


def false_alarm_time_s(pfa, bandwidth_hz):
    """Mean time between false alarms Tfa = 1 / (Pfa * beta) in seconds (Brooker eq. 9.15).

    Brooker 9.2.2: Pfa = 1e-10 with the matched bandwidth 1/(0.3 us) gives 3.0e3 s (50 min):

    >>> float(false_alarm_time_s(1e-10, 1.0 / 0.3e-6)) / 60.0
    50.0
    """
    p, b = as_float(pfa, bandwidth_hz)
    ok, _ = admit("false_alarm_time_s", [("pfa", p, 0.0, 1.0, True, True), ("bandwidth_hz", b, 0.0, None, True, False)])
    return guard(1.0 / (p * b), ok)
