"""False-alarm thresholds of the noncoherently integrated square-law detector.

Noise is normalised so that, under noise alone, the sum of N square-law samples is
``Y ~ Gamma(N, 1)``. The threshold ``T`` on ``Y`` solves

    Pfa = Q(N, T) = Gamma(N, T) / Gamma(N)          (regularized upper incomplete gamma),

which for one pulse is ``T = -ln Pfa``, i.e. the envelope threshold ``Vt = sqrt(-2 psi ln Pfa)``
of Brooker eq. (9.14). ``T`` is found by Newton's method on ``log Q`` (concave in T for N >= 1,
so the iteration converges monotonically after the first step) and is therefore correct for
Pfa down to 1e-300: the classic shortcut ``gammaincinv(N, 1 - Pfa)`` cannot represent
``1 - Pfa`` once Pfa < 1.1e-16. Derivatives are implicit:
``dT/dPfa = -1/f(T)``, ``dT/dN = (dQ/dN)/f(T)`` with ``f`` the Gamma(N, 1) density.

Accuracy: the relative error of T equals the relative error of ``jax.scipy.special.gammaincc``
divided by the logarithmic slope, measured < 3e-13 in Q for N <= 3000 and < 2e-11 at N = 1e4
against mpmath (tests/test_detection_threshold.py).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.special import gammaincc, ndtri

from diffsense.numerics.checks import check_range
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


def _initial_guess(log_pfa, n):
    """Start below or near the root: max of two lower-biased estimates.

    Wilson-Hilferty's cube-root normal quantile (accurate for large n, moderate Pfa) is damped by
    the factor 0.9 in its excess over n and is not used in the far tail (z > 3 sqrt(n)), where it
    overshoots into the region where Q underflows; the exponential-tail estimate -ln Pfa + (n-1) ln(-ln Pfa) - lgamma(n) lies below
    the root for n >= 1 because Q(n, T) exceeds the density at T there.
    """
    z = -ndtri(jnp.exp(log_pfa))
    c = 1.0 / (9.0 * n)
    wh = n * jnp.maximum(1.0 - c + z * jnp.sqrt(c), 0.05) ** 3
    wh = n + 0.9 * (wh - n)
    lp = -log_pfa
    tail = lp + (n - 1.0) * jnp.log(jnp.maximum(lp, 1.0)) - jax.scipy.special.gammaln(n)
    far_tail = z > 3.0 * jnp.sqrt(n)
    return jnp.maximum(jnp.where(far_tail, tail, jnp.maximum(wh, tail)), 1e-3)


def _solve_threshold(pfa, n):
    """Bracketed Newton iteration on g(T) = log Q(n, T) - log Pfa (g decreasing and concave)."""
    log_pfa = jnp.log(pfa)
    t0 = _initial_guess(log_pfa, n)

    def body(state):
        t, lo, hi, _, it = state
        logq = jnp.log(gammaincc(n, t))
        g = logq - log_pfa
        finite = jnp.isfinite(g)
        lo = jnp.where(finite & (g > 0), t, lo)
        hi = jnp.where(~finite | (g <= 0), t, hi)
        slope = -jnp.exp(_log_density(n, t) - logq)  # d log Q / dT
        t_newton = t - g / slope
        ok = finite & jnp.isfinite(t_newton) & (t_newton >= lo) & (t_newton <= hi)
        fallback = jnp.where(jnp.isfinite(hi), 0.5 * (lo + hi), 2.0 * t)
        t_new = jnp.where(ok, t_newton, fallback)
        return t_new, lo, hi, jnp.abs(t_new - t), it + 1

    tol = max(_STEP_TOL, _STEP_TOL_EPS * float(jnp.finfo(t0.dtype).eps))  # float64: 1e-12

    def cond(state):
        t, _, _, delta, it = state
        return (it < _MAX_NEWTON) & jnp.any(delta > tol * jnp.maximum(t, 1.0))

    init = (t0, jnp.zeros_like(t0), jnp.full_like(t0, jnp.inf), jnp.full_like(t0, jnp.inf), 0)
    t, _, _, _, it = jax.lax.while_loop(cond, body, init)
    return t


@jax.custom_jvp
def _threshold(pfa, n):
    return _solve_threshold(pfa, n)


@_threshold.defjvp
def _threshold_jvp(primals, tangents):
    pfa, n = primals
    dpfa, dn = tangents
    t = _threshold(pfa, n)
    inv_density = jnp.exp(-_log_density(n, t))  # 1 / f(T)
    _, dq_dn = jax.jvp(lambda a: gammaincc(a, t), (n,), (jnp.ones_like(n),))
    dt = (dq_dn * dn - dpfa) * inv_density
    return t, dt


def threshold(pfa, n=1):
    """Threshold ``T`` on the integrated statistic ``Y ~ Gamma(n, 1)`` for false-alarm probability ``pfa``.

    Args:
        pfa: false-alarm probability per detection decision, 1e-300 <= pfa < 1.
        n: number of pulses integrated noncoherently (real, >= 1; non-integer values give the
           continuous relaxation of the Gamma(n, 1) law).

    Returns:
        ``T`` with ``Q(n, T) = pfa`` (dimensionless, in units of the mean noise power of one pulse).

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
    check_range("pfa", pfa, 1e-300, 1.0, hi_open=True, where="threshold")
    check_range("n", n, 1.0, None, where="threshold")
    pfa, n = jnp.broadcast_arrays(*as_float(pfa, n))
    return _threshold(pfa, n)


def pfa_from_threshold(threshold_value, n=1):
    """False-alarm probability ``Q(n, T)`` for a threshold ``T`` on ``Y ~ Gamma(n, 1)``.

    For one pulse Q(1, T) = exp(-T) (exponential noise power):

    >>> import math
    >>> float(pfa_from_threshold(5.0)), math.exp(-5.0)
    (0.006737947, 0.006737947)
    """
    check_range("threshold_value", threshold_value, 0.0, None, where="pfa_from_threshold")
    check_range("n", n, 1.0, None, where="pfa_from_threshold")
    t, n = as_float(threshold_value, n)
    return gammaincc(n, t)


def voltage_threshold(pfa, noise_variance_v2=1.0):
    """Envelope-detector threshold ``Vt = sqrt(-2 psi ln Pfa)`` in volts (Brooker eq. 9.14).

    Args:
        pfa: single-sample false-alarm probability, 0 < pfa < 1.
        noise_variance_v2: noise voltage variance psi at the IF filter output (V^2).

    >>> float(voltage_threshold(1e-10, 1.0))   # Brooker 9.2.2: 6.79 V
    6.79
    """
    check_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True, where="voltage_threshold")
    check_range("noise_variance_v2", noise_variance_v2, 0.0, None, lo_open=True, where="voltage_threshold")
    pfa, psi = as_float(pfa, noise_variance_v2)
    return jnp.sqrt(-2.0 * psi * jnp.log(pfa))


def pfa_from_false_alarm_time(false_alarm_time_s, bandwidth_hz):
    """Pfa = 1 / (Tfa * beta): one independent noise sample per 1/beta seconds (Brooker eq. 9.15).

    Brooker 9.9.1: Tfa = 9 h with beta = 0.613 / 2 us gives the book's Pfa of 1e-10:

    >>> float(pfa_from_false_alarm_time(9 * 3600.0, 0.613 / 2e-6))
    1.0e-10
    """
    check_range("false_alarm_time_s", false_alarm_time_s, 0.0, None, lo_open=True, where="pfa_from_false_alarm_time")
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where="pfa_from_false_alarm_time")
    tfa, b = as_float(false_alarm_time_s, bandwidth_hz)
    return 1.0 / (tfa * b)


def false_alarm_time_s(pfa, bandwidth_hz):
    """Mean time between false alarms Tfa = 1 / (Pfa * beta) in seconds (Brooker eq. 9.15).

    Brooker 9.2.2: Pfa = 1e-10 with the matched bandwidth 1/(0.3 us) gives 3.0e3 s (50 min):

    >>> float(false_alarm_time_s(1e-10, 1.0 / 0.3e-6)) / 60.0
    50.0
    """
    check_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True, where="false_alarm_time_s")
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where="false_alarm_time_s")
    p, b = as_float(pfa, bandwidth_hz)
    return 1.0 / (p * b)
