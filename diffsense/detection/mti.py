"""MTI (delay-line canceller) blind speeds, velocity response and detection losses.

Model. An MTI canceller of order ``n`` (an ``(n+1)``-pulse binomial canceller: ``n = 1`` the
two-pulse single canceller, ``n = 2`` the three-pulse double canceller) forms from the complex
(I/Q) returns ``x_k`` of successive pulses the output ``y_j = sum_i w_i x_{j+i}`` with the
binomial weights ``w_i = (-1)^i C(n, i)``, i = 0..n (the ``n``-fold cascade of ``1 - z^-1``).

Blind speeds. A target of radial speed ``v`` has the Doppler frequency ``f_d = 2 v / lambda``;
the canceller's zeros lie at ``f_d = k PRF``, i.e. at the blind speeds::

    v_k = k lambda PRF / 2,   k = 1, 2, ...                 (Brooker eq. 14.3)

Velocity response (power, normalised). ``|H(f_d)|^2 = |2 sin(pi f_d / PRF)|^(2n)``, whose
average over one Doppler period is the noise gain ``sum_i w_i^2 = C(2n, n)`` (Parseval; the
Vandermonde identity). :func:`mti_velocity_response` divides by it (noise-gain
normalisation): the result is the canceller's SNR gain for a target at that speed, its
average over a uniform distribution of speed is exactly 1 (0 dB), its maximum at
``f_d = PRF/2`` is ``4^n / C(2n, n)`` (3.01 dB single, 4.26 dB double canceller).

Integration loss (noise correlation and consumed pulses). Of ``N`` pulses the canceller
delivers ``M = N - n`` outputs (sliding window) whose noise is correlated, with the
correlation coefficient at lag ``k``::

    rho_k = sum_i w_i w_{i+k} / sum_i w_i^2 = (-1)^k C(2n, n+k) / C(2n, n)   (0 for k > n)

(``rho_1 = -1/2`` for the single canceller). The noncoherent sum of the ``M`` square-law
outputs under noise alone has mean ``M`` and variance ``sum_{j,l} rho_{|j-l|}^2`` (in units of
the output noise power); a sum of ``n_e`` independent samples with the same mean-to-spread
ratio has::

    n_e = M^2 / (M + 2 sum_{k=1}^{n} max(M - k, 0) rho_k^2)            (1 <= n_e <= M)

(:func:`mti_independent_samples`; moment matching, the usual "equivalent number of independent
samples"). With the noise-gain normalisation every output carries the input's per-pulse SNR
on average over speed, so the model replaces N independent pulses by ``n_e`` independent
samples of the same SNR, and the MTI integration loss is the difference of detectability
factors (:func:`diffsense.detection.required_snr_db`, continuous relaxation in N)::

    L_mti = D(Pd, Pfa, n_e) - D(Pd, Pfa, N)    (dB)
          = [D(M) - D(N)]  (pulses consumed)  +  [D(n_e) - D(M)]  (noise correlation).

The velocity-response loss (the extra SNR needed when Pd is averaged over target speeds
through the response) is a separate loss and is not computed here; the normalised response
above is its ingredient.

Model error: the gamma law with ``n_e`` samples matches the first two moments only. For
Swerling 2 (a pulse-to-pulse independent target is white like the noise, so the exact law is
the weighted sum of exponentials with the eigenvalues of the output correlation matrix) the
exact loss, computed in mpmath in tests/detection/test_mti.py at Pd = 0.9, Pfa = 1e-6, exceeds
the model by 0.11-0.21 dB for the single canceller (N = 4-30), 0.14-0.26 dB for the double
(N = 6-30) and 0.21-0.25 dB for the triple (N = 10-30); with only two or three outputs the
model is pessimistic instead (by 0.46 dB for the double canceller at N = 4, 0.20 dB for the
triple at N = 6). So the model is within 0.26 dB of the exact loss whenever the canceller
leaves M >= 3 outputs, 0.47 dB at M = 2 (exact at M = 1). The value of the model itself is
exact to the accuracy of ``required_snr_db`` (< 1e-9 dB).

Blind-phase loss. A single-channel (I only, no Q) canceller sees the real part ``A cos(theta
+ k phi)`` of the target's complex amplitude and real Gaussian noise of half the complex noise
power. Integrating ``M`` square-law samples gives, in units of the per-channel noise power,
a noncentral chi-square with ``M`` degrees of freedom and noncentrality ``2 S sum_k
cos^2(theta + k phi)``, with ``S`` the I/Q per-pulse SNR. Averaged over the dwell (the
target's Doppler phase ``phi`` rotating, ``sum_k cos^2 = M/2``: the target not near zero
Doppler nor a blind speed) this is ``chi^2_M(S M)``, which is exactly the law of an I/Q
detector integrating ``M/2`` samples of SNR ``S`` (``chi^2_{2K}(2 S K)``, K = M/2). Hence::

    L_bp = D(Pd, Pfa, M/2) - D(Pd, Pfa, M)    (dB)

exactly for Swerling 0, 1, 3 (the power is constant over the dwell, only the noncentrality
matters) and Swerling 2 (the I component of a complex Gaussian amplitude is real Gaussian, for
any phase history); Swerling 4 is not covered (its per-pulse amplitude is not complex
Gaussian, the equivalence fails). The loss tends to 10 log10 sqrt(2) = 1.51 dB for many samples
(noncoherent integration gain ~ sqrt(M)); at Pfa = 1e-6 it is 2.44-2.58 dB for M = 2 and
2.0-2.2 dB for M = 20 (Swerling 0, 1, 3, Pd = 0.5-0.99). Swerling 2 also loses half its
diversity: 6.3 dB at M = 2 and 2.56 dB at M = 20 (Pd = 0.9). A target whose phase stays
fixed over the dwell (zero Doppler relative to the dwell length) suffers the larger,
fluctuation-like loss of the noncentrality ``2 S M cos^2 theta`` averaged over ``theta``; that
case is not implemented here.

Derivatives. Blind speeds and the velocity response are closed forms (autodiff; the Doppler
phase is reduced to [-1/2, 1/2] cycle before the sine, which does not change the derivative).
The losses inherit the implicit derivatives of ``required_snr_db`` (in pd, pfa and the
continuous pulse count); ``n_e`` is piecewise rational in N with kinks at the integers
N <= 2n (where ``max(M - k, 0)`` switches; the derivative there is the one from below), smooth
for N > 2n. Between the integers the relaxation is floored at ``n_e = 1`` (for n >= 3 the
rational form dips below 1 between M = 1 and M = 2, to 0.9965 for n = 3 and 0.922 for n = 16).

Sources
-------
- G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009), sec. 14.2.3,
  eqs. (14.2)-(14.3) (blind speeds ``v_n = n lambda f_p / 2``) and Figure 14.12 (single and
  double canceller responses).
- M. I. Skolnik, *Introduction to Radar Systems*, 3rd ed. (McGraw-Hill, 2001), ch. 3 "MTI and
  Pulse Doppler Radar" (delay-line canceller response ``2 |sin(pi f_d T)|``, blind speeds,
  cascaded cancellers with binomial weights).
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed. (McGraw-Hill, 2014),
  ch. 5 "Doppler processing" (MTI cancellers, noise gain and its normalisation, blind speeds).
- D. K. Barton, *Radar Equations for Modern Radar* (Artech House, 2013), ch. 10 (loss factors):
  MTI losses split into noise-correlation (integration) loss, velocity-response loss and the
  blind-phase loss of single-channel MTI. Barton's own curves are not reproduced; the
  moment-matched ``n_e`` and the ``M/2`` equivalence above are this module's models.
- B. R. Mahafza, *Radar Systems Analysis and Design Using MATLAB*, 3rd ed. (CRC, 2013), MTI
  chapter (single and double delay-line cancellers, blind speeds).
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import as_float
from diffsense.detection.core import SWERLING_CASES
from diffsense.detection.probability import N_RANGE
from diffsense.detection.required_snr import required_snr_db

__all__ = [
    "blind_speeds_mps",
    "first_blind_speed_mps",
    "mti_canceller_weights",
    "mti_noise_gain",
    "mti_velocity_response",
    "mti_independent_samples",
    "mti_integration_loss_db",
    "mti_blind_phase_loss_db",
]

#: largest canceller order accepted (a 17-pulse canceller; C(32, 16) = 6.0e8 is exact in float64)
MAX_ORDER = 16
#: Swerling cases for which the blind-phase equivalence is exact (module docstring)
BLIND_PHASE_SWERLING = (0, 1, 2, 3, 5)


def _check_order(order, where):
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not 1 <= order <= MAX_ORDER:
        raise DomainError(f"{where}: argument 'order' must be an int in [1, {MAX_ORDER}] (static); got {order!r}")
    return int(order)


def _check_swerling(swerling, allowed, where):
    if swerling not in allowed:
        raise DomainError(f"{where}: argument 'swerling' must be one of {list(allowed)}; got {swerling!r}")


def first_blind_speed_mps(wavelength_m, prf_hz):
    """First blind speed ``v_1 = lambda PRF / 2`` (m/s) of an MTI canceller.

    Args:
        wavelength_m: carrier wavelength (m), > 0.
        prf_hz: pulse repetition frequency (Hz), > 0.

    Returns:
        The radial speed (m/s) whose Doppler shift ``2 v / lambda`` equals the PRF.

    Source: Brooker eq. (14.3); Skolnik (2001) ch. 3. Exact (one product).

    X band (10 GHz, lambda = c / f = 0.0299792458 m) at PRF = 1 kHz: 14.99 m/s.

    >>> float(first_blind_speed_mps(299792458.0 / 10e9, 1000.0))
    14.9896229
    """
    lam, prf = as_float(wavelength_m, prf_hz)
    ok, (c_lam, c_prf) = admit("first_blind_speed_mps", [("wavelength_m", lam, 0.0, None, True, False),
                                                         ("prf_hz", prf, 0.0, None, True, False)])
    return guard(0.5 * guard(lam, c_lam, 1.0) * guard(prf, c_prf, 1.0), ok)


def blind_speeds_mps(wavelength_m, prf_hz, count: int):
    """The first ``count`` blind speeds ``v_k = k lambda PRF / 2``, k = 1..count (m/s).

    Args:
        wavelength_m: wavelength (m), > 0.
        prf_hz: PRF (Hz), > 0.
        count: number of blind speeds (static int >= 1).

    Returns:
        Array of shape ``broadcast(wavelength_m, prf_hz).shape + (count,)``.

    Source: Brooker eqs. (14.2)-(14.3), ``f_d = n f_p``, ``v_n = n lambda f_p / 2``.

    L band (lambda = 0.23 m) at 300 Hz: multiples of 34.5 m/s.

    >>> [round(float(v), 6) for v in blind_speeds_mps(0.23, 300.0, 3)]
    [34.5, 69.0, 103.5]
    """
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise DomainError(f"blind_speeds_mps: argument 'count' must be an int >= 1 (static); got {count!r}")
    v1 = first_blind_speed_mps(wavelength_m, prf_hz)
    return v1[..., None] * jnp.arange(1, int(count) + 1, dtype=v1.dtype)


def mti_canceller_weights(order: int = 1):
    """Binomial weights ``w_i = (-1)^i C(n, i)``, i = 0..n, of the order-``n`` canceller.

    >>> mti_canceller_weights(2).tolist()
    [1.0, -2.0, 1.0]
    """
    n = _check_order(order, "mti_canceller_weights")
    return np.array([(-1) ** i * math.comb(n, i) for i in range(n + 1)], dtype=float)


def mti_noise_gain(order: int = 1):
    """Noise power gain ``sum_i w_i^2 = C(2n, n)`` of the order-``n`` binomial canceller.

    (Vandermonde: ``sum_i C(n, i)^2 = C(2n, n)``.) Single canceller 2, double 6, triple 20.

    >>> [mti_noise_gain(n) for n in (1, 2, 3)]
    [2.0, 6.0, 20.0]
    """
    n = _check_order(order, "mti_noise_gain")
    return float(math.comb(2 * n, n))


def mti_velocity_response(radial_speed_mps, wavelength_m, prf_hz, order: int = 1):
    """Power response of the order-``n`` binomial canceller, normalised to its noise gain.

    ``G(v) = |2 sin(pi f_d / PRF)|^(2n) / C(2n, n)``, ``f_d = 2 v / lambda``: the target's SNR
    gain through the canceller (output SNR / input SNR). Its average over one blind-speed
    interval is 1 (0 dB); zeros at the blind speeds; maximum ``4^n / C(2n, n)`` at odd multiples
    of half the first blind speed.

    Args:
        radial_speed_mps: radial speed (m/s), any finite real (sign irrelevant).
        wavelength_m: wavelength (m), > 0.
        prf_hz: PRF (Hz), > 0.
        order: canceller order n (static int 1..16; n = 1 is the two-pulse canceller).

    Returns:
        Linear power ratio in [0, 4^n / C(2n, n)]. Error: a few ulp relative to the phase
        ``2 v / (lambda PRF)``, whose own rounding (1.1e-16 of it) dominates far from v = 0.

    Source: Skolnik (2001) ch. 3 (``|H| = 2 |sin(pi f_d T)|``, cascaded cancellers); Richards
    (2014) ch. 5 (noise-gain normalisation); Brooker Figure 14.12.

    At half the first blind speed the single canceller gives 4/2 (3.01 dB), the double 16/6:

    >>> v = 0.5 * float(first_blind_speed_mps(0.03, 1000.0))
    >>> float(mti_velocity_response(v, 0.03, 1000.0, 1)), float(mti_velocity_response(v, 0.03, 1000.0, 2))
    (2.0, 2.66666667)
    """
    where = "mti_velocity_response"
    n = _check_order(order, where)
    v, lam, prf = jnp.broadcast_arrays(*as_float(radial_speed_mps, wavelength_m, prf_hz))
    ok, _ = admit(where, [("radial_speed_mps", v, -jnp.inf, jnp.inf, True, True),
                          ("wavelength_m", lam, 0.0, None, True, False), ("prf_hz", prf, 0.0, None, True, False)])
    v, lam, prf = guard(v, ok, 0.0), guard(lam, ok, 1.0), guard(prf, ok, 1.0)
    cycles = 2.0 * v / (lam * prf)  # Doppler phase per pulse, in cycles
    reduced = cycles - jnp.round(cycles)  # in [-1/2, 1/2]; d reduced / d cycles = 1
    s2 = jnp.sin(jnp.pi * reduced) ** 2
    return guard((4.0 * s2) ** n / math.comb(2 * n, n), ok)


def _rho_squared(n):
    """Squared noise correlation coefficients rho_k^2, k = 1..n, of the order-n canceller output."""
    c0 = math.comb(2 * n, n)
    return [(math.comb(2 * n, n + k) / c0) ** 2 for k in range(1, n + 1)]


def _independent_samples(n_pulses, n):
    m = n_pulses - n
    denominator = m
    for k, r2 in enumerate(_rho_squared(n), start=1):
        denominator = denominator + 2.0 * r2 * jnp.where(m > k, m - k, 0.0)
    # between M = 1 and 2 the rational relaxation dips below 1 for n >= 3 (rho_1^2 > 1/2); n_e = 1
    # there (exact at the integers, and the domain of the detectability factor)
    return jnp.maximum(m * m / denominator, 1.0)


def mti_independent_samples(n_pulses, order: int = 1):
    """Equivalent number ``n_e`` of independent noise samples after a sliding-window canceller.

    ``n_e = M^2 / (M + 2 sum_{k=1}^{n} max(M - k, 0) rho_k^2)``, ``M = N - n`` outputs,
    ``rho_k = (-1)^k C(2n, n+k) / C(2n, n)`` (module docstring: matches the mean and variance of
    the noncoherent sum of the correlated square-law outputs).

    Args:
        n_pulses: pulses N at the canceller input, real, ``N >= order + 1``
            (continuous relaxation between integers).
        order: canceller order n (static int 1..16).

    Returns:
        ``n_e`` with ``1 <= n_e <= M`` (exact rational arithmetic in float64, error ~1e-16
        relative).

    Source: moment matching (equivalent independent samples) applied to the canceller's output
    correlation; Barton (2013) ch. 10 (MTI noise-correlation loss); Richards (2014) ch. 5.

    Ten pulses through the single canceller: M = 9, rho_1 = -1/2, n_e = 81 / (9 + 16/4):

    >>> float(mti_independent_samples(10.0, 1)), 81 / 13
    (6.23076923, 6.23076923)
    """
    where = "mti_independent_samples"
    n = _check_order(order, where)
    (big_n,) = as_float(n_pulses)
    ok, _ = admit(where, [("n_pulses", big_n, n + 1.0, None)])
    return guard(_independent_samples(guard(big_n, ok, n + 1.0), n), ok)


def mti_integration_loss_db(n_pulses, order: int, pd, pfa, swerling: int = 0):
    """MTI integration loss (dB): pulses consumed by the canceller plus output noise correlation.

    ``L = D(pd, pfa, n_e) - D(pd, pfa, N)`` with ``n_e`` from :func:`mti_independent_samples`
    and ``D`` the exact detectability factor :func:`diffsense.detection.required_snr_db`
    (square-law detector, noncoherent integration, real pulse counts). Splits as
    ``[D(M) - D(N)] + [D(n_e) - D(M)]``: ``M = N - n`` outputs, then their correlation.

    Args:
        n_pulses: pulses N at the canceller input, real in [order + 1, 1e4].
        order: canceller order n (static int 1..16).
        pd: detection probability, pfa < pd <= 1 - 1e-12.
        pfa: false-alarm probability, 1e-300 ... 0.5.
        swerling: target model 0-4 (5 = 0), static.

    Returns:
        Loss in dB (>= 0). Accuracy of the model value: that of ``required_snr_db``
        (< 1e-9 dB). Model error (moment matching, module docstring): within 0.26 dB of the
        exact Swerling 2 law for M = N - n >= 3 outputs (mostly optimistic, by 0.11-0.26 dB),
        0.47 dB at M = 2.

    Source: Barton (2013) ch. 10 (MTI noise-correlation loss); model as stated in the module
    docstring.

    Swerling 2 has ``D = T(Pfa, k) / T(Pd, k) - 1`` with the inverse incomplete gamma
    function (scipy's, for real k): ten pulses, single canceller, n_e = 81/13:

    >>> import math
    >>> from scipy.special import gammainccinv
    >>> s = lambda k: gammainccinv(k, 1e-6) / gammainccinv(k, 0.9) - 1.0
    >>> float(mti_integration_loss_db(10.0, 1, 0.9, 1e-6, swerling=2)), 10 * math.log10(s(81 / 13) / s(10))
    (2.0238043, 2.0238043)
    """
    where = "mti_integration_loss_db"
    n = _check_order(order, where)
    _check_swerling(swerling, SWERLING_CASES, where)
    big_n, pd, pfa = jnp.broadcast_arrays(*as_float(n_pulses, pd, pfa))
    ok, _ = admit(where, [("n_pulses", big_n, n + 1.0, N_RANGE[1])])
    big_n = guard(big_n, ok, n + 1.0)
    n_e = _independent_samples(big_n, n)
    return guard(required_snr_db(pd, pfa, n_e, swerling) - required_snr_db(pd, pfa, big_n, swerling), ok)


def mti_blind_phase_loss_db(pd, pfa, n_samples, swerling: int = 0):
    """Blind-phase loss (dB) of a single-channel (I only) canceller, averaged over the dwell.

    ``L_bp = D(pd, pfa, M/2) - D(pd, pfa, M)``: ``M`` real square-law samples of a target whose
    Doppler phase rotates over the dwell detect exactly like ``M/2`` I/Q samples of the same
    per-pulse SNR (module docstring). Exact for Swerling 0, 1, 2, 3 under that assumption.

    Args:
        pd: detection probability, pfa < pd <= 1 - 1e-12.
        pfa: false-alarm probability, 1e-300 ... 0.5.
        n_samples: independent canceller output samples M integrated, real in [2, 1e4] (use
            :func:`mti_independent_samples` for a sliding-window canceller).
        swerling: 0, 1, 2, 3 (5 = 0), static; Swerling 4 is rejected (no exact equivalence).

    Returns:
        Loss in dB: 1.51 dB in the limit of many samples, 2.4-2.6 dB for two (Swerling 0, 1,
        3); Swerling 2 more at few samples (6.3 dB for two at Pd = 0.9). Accuracy that of ``required_snr_db`` (< 1e-9 dB).

    Source: Barton (2013) ch. 10 (blind-phase loss of single-channel MTI); the equivalence
    ``chi^2_M(S M) = chi^2_{2K}(2 S K)``, K = M/2, is derived in the module docstring.

    Swerling 2 in closed form (scipy's inverse incomplete gamma): 20 samples lose as much as
    halving the I/Q integration to 10:

    >>> import math
    >>> from scipy.special import gammainccinv
    >>> s = lambda k: gammainccinv(k, 1e-6) / gammainccinv(k, 0.9) - 1.0
    >>> float(mti_blind_phase_loss_db(0.9, 1e-6, 20.0, swerling=2)), 10 * math.log10(s(10) / s(20))
    (2.55999113, 2.55999113)
    """
    where = "mti_blind_phase_loss_db"
    _check_swerling(swerling, BLIND_PHASE_SWERLING, where)
    pd, pfa, m = jnp.broadcast_arrays(*as_float(pd, pfa, n_samples))
    ok, _ = admit(where, [("n_samples", m, 2.0, N_RANGE[1])])
    m = guard(m, ok, 2.0)
    return guard(required_snr_db(pd, pfa, 0.5 * m, swerling) - required_snr_db(pd, pfa, m, swerling), ok)
