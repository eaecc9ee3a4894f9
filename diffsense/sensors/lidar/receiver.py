"""Optical receivers: direct detection with PIN and avalanche photodiodes, heterodyne
(coherent) detection, noise-equivalent power, optimum APD gain, pulse response of the
receiver filter.

Direct detection (PIN: M = 1, F = 1; APD: gain M, McIntyre excess noise F(M))::

    i_s = ℜ M P_s,    ℜ = η q λ / (h c)
    i_n² = 2 q (ℜ (P_s + P_b) + I_d) M² F(M) B + 4 k T B / R_L + i_a² B
    SNR  = i_s² / i_n²                         (electrical power ratio, "(i_s/i_n)²")

with P_b the background power, I_d the primary (multiplied) dark current, R_L the load (or
TIA feedback) resistance at temperature T and i_a the amplifier's input noise current density.
Brooker §9.1.3 eqs (9.6)–(9.7) and §9.1.3.5 (the SNR is the square of the ratio of the
photocurrent to the total noise current); McIntyre (1966) for F(M); the shot and Johnson terms
come from :mod:`diffsense.physics.noise`.

Heterodyne detection with a local oscillator of power P_LO and mixing (heterodyne)
efficiency η_m: the IF current has the mean-square value 2 η_m ℜ² P_s P_LO, and the noise is
the shot noise of all the DC photocurrent plus the thermal noise::

    SNR = 2 η_m ℜ² P_s P_LO / i_n²,   i_n² = 2 q (ℜ (P_LO + P_s + P_b) + I_d) B + 4 k T B / R_L + i_a² B
        → η η_m P_s / (h ν B)   when the LO shot noise dominates (quantum limit)

Kingston, R. H., *Detection of Optical and Infrared Radiation* (Springer, 1978), ch. 3;
Jelalian (1992) ch. 2 (heterodyne SNR, mixing efficiency).

B is the noise-equivalent bandwidth. :func:`single_pole_pulse_response` gives the peak
signal-power factor of a rectangular pulse through the single-pole (RC/TIA) filter of that
noise bandwidth, which completes the SNR of a pulse: SNR_peak = SNR(B) × response(B τ).
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.checks import check_choice, check_range
from diffsense.physics.constants import BOLTZMANN_J_K, ELEMENTARY_CHARGE_C, PLANCK_J_S, SPEED_OF_LIGHT_M_S
from diffsense.physics.noise import nep_from_noise_current_w, photodetector_noise_current_a

__all__ = [
    "responsivity_a_w",
    "direct_detection_noise_current_a",
    "direct_detection_snr",
    "direct_detection_nep_w",
    "heterodyne_snr",
    "heterodyne_nep_w",
    "heterodyne_noise_psd_a2_hz",
    "quantum_limited_heterodyne_snr",
    "single_pole_pulse_response",
    "optimum_apd_gain",
]

_Q = ELEMENTARY_CHARGE_C
_K = BOLTZMANN_J_K
_HC = PLANCK_J_S * SPEED_OF_LIGHT_M_S


#: below this log x² the cubic's root is taken from its series (x < 1e-4)
_LOG_SERIES_X2 = math.log(1e-8)

def _f(x):
    return jnp.asarray(x, dtype=jnp.result_type(float, x))


def _pos(name, x, where, hi=None):
    check_range(name, x, 0.0, hi, lo_open=True, where=where)


def responsivity_a_w(quantum_efficiency, wavelength_m):
    """Photodiode responsivity ``ℜ = η q λ / (h c)`` (A/W).

    Args:
        quantum_efficiency: quantum efficiency η, in (0, 1].
        wavelength_m: wavelength λ (m), in [1e-9, 1e-2].

    Exact. Example: η = 1 at 1.55 µm -> 1.2501 A/W, i.e. q λ/(h c) with the SI defining values:

    >>> float(responsivity_a_w(1.0, 1.55e-6)), 1.602176634e-19 * 1.55e-6 / (6.62607015e-34 * 299792458)
    (1.25016, 1.25016)
    """
    w = "responsivity_a_w"
    check_range("quantum_efficiency", quantum_efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("wavelength_m", wavelength_m, 1e-9, 1e-2, where=w)
    return _f(quantum_efficiency) * _Q * _f(wavelength_m) / _HC


def direct_detection_noise_current_a(signal_power_w, background_power_w, responsivity, dark_current_a, bandwidth_hz,
                                     temperature_k, load_resistance_ohm, amplifier_noise_a_rthz=0.0, gain=1.0,
                                     ionization_ratio=0.0):
    """RMS noise current of a direct-detection receiver (A).

    ``i_n = sqrt(2 q (ℜ(P_s + P_b) + I_d) M² F(M) B + 4 k T B / R_L + i_a² B)``.

    Args:
        signal_power_w: optical signal power P_s on the detector (W), in [0, ∞).
        background_power_w: background optical power P_b (W), in [0, ∞).
        responsivity: unity-gain responsivity ℜ (A/W), in (0, ∞).
        dark_current_a: primary dark current I_d (A), in [0, ∞) (multiplied by M in an APD).
        bandwidth_hz: noise-equivalent bandwidth B (Hz), in (0, ∞).
        temperature_k: load-resistor temperature T (K), in (0, 1e4].
        load_resistance_ohm: load or TIA feedback resistance R_L (Ω), in (0, ∞).
        amplifier_noise_a_rthz: amplifier input noise current density i_a (A/√Hz), [0, ∞).
        gain: APD gain M, in [1, 1e4] (1 for a PIN diode).
        ionization_ratio: McIntyre k, in [0, 1].

    Source: Brooker §9.1.3 via :func:`diffsense.physics.noise.photodetector_noise_current_a`
    (shot + Johnson), plus the amplifier term added in quadrature.
    """
    w = "direct_detection_noise_current_a"
    check_range("signal_power_w", signal_power_w, 0.0, None, where=w)
    check_range("background_power_w", background_power_w, 0.0, None, where=w)
    _pos("responsivity", responsivity, w)
    check_range("amplifier_noise_a_rthz", amplifier_noise_a_rthz, 0.0, None, where=w)
    photo = _f(responsivity) * (_f(signal_power_w) + _f(background_power_w))
    i_det = photodetector_noise_current_a(photo, dark_current_a, bandwidth_hz, temperature_k, load_resistance_ohm,
                                          gain=gain, ionization_ratio=ionization_ratio)
    i_a = _f(amplifier_noise_a_rthz)
    return jnp.sqrt(i_det * i_det + i_a * i_a * _f(bandwidth_hz))


def direct_detection_snr(signal_power_w, background_power_w, responsivity, dark_current_a, bandwidth_hz,
                         temperature_k, load_resistance_ohm, amplifier_noise_a_rthz=0.0, gain=1.0,
                         ionization_ratio=0.0):
    """Direct-detection SNR ``(ℜ M P_s)² / i_n²`` (linear electrical power ratio).

    Arguments as :func:`direct_detection_noise_current_a`. The SNR of a steady signal in the
    noise bandwidth B; for a pulse multiply by :func:`single_pole_pulse_response`.
    Source: Brooker §9.1.3.5 (SNR = (i_photo / i_noise)²); McIntyre (1966).
    """
    i_n = direct_detection_noise_current_a(signal_power_w, background_power_w, responsivity, dark_current_a,
                                           bandwidth_hz, temperature_k, load_resistance_ohm, amplifier_noise_a_rthz,
                                           gain, ionization_ratio)
    i_s = _f(responsivity) * _f(gain) * _f(signal_power_w)
    return (i_s / i_n) ** 2


def direct_detection_nep_w(signal_power_w, background_power_w, responsivity, dark_current_a, bandwidth_hz,
                           temperature_k, load_resistance_ohm, amplifier_noise_a_rthz=0.0, gain=1.0,
                           ionization_ratio=0.0):
    """Noise-equivalent power in the bandwidth B: ``NEP = i_n / (ℜ M)`` (W).

    The optical power whose signal current equals the RMS noise current at the operating
    point (the noise includes the shot noise of ``signal_power_w``; pass 0 for the
    signal-free NEP). SNR = (P_s / NEP)². Arguments as
    :func:`direct_detection_noise_current_a`; uses :func:`diffsense.physics.noise.nep_from_noise_current_w`.
    """
    i_n = direct_detection_noise_current_a(signal_power_w, background_power_w, responsivity, dark_current_a,
                                           bandwidth_hz, temperature_k, load_resistance_ohm, amplifier_noise_a_rthz,
                                           gain, ionization_ratio)
    return nep_from_noise_current_w(i_n, _f(responsivity) * _f(gain))


def heterodyne_noise_psd_a2_hz(signal_power_w, lo_power_w, background_power_w, responsivity, dark_current_a,
                               temperature_k, load_resistance_ohm, amplifier_noise_a_rthz):
    """One-sided noise current density of a heterodyne receiver (PIN, M = 1), i_n²/B (A²/Hz).

    ``2 q (ℜ (P_LO + P_s + P_b) + I_d) + 4 k T / R_L + i_a²``: shot noise of all the DC
    photocurrent and dark current, Johnson noise of the load, amplifier noise. Arguments (SI,
    all ≥ 0, R_L > 0) as :func:`heterodyne_snr`, with ``responsivity`` ℜ in A/W. Unchecked
    helper (no domain checks; callers check).
    """
    dc = _f(responsivity) * (_f(lo_power_w) + _f(signal_power_w) + _f(background_power_w)) + _f(dark_current_a)
    return 2.0 * _Q * dc + 4.0 * _K * _f(temperature_k) / _f(load_resistance_ohm) + _f(amplifier_noise_a_rthz) ** 2


def _check_heterodyne(w, signal_power_w, lo_power_w, bandwidth_hz, mixing_efficiency, background_power_w,
                      dark_current_a, temperature_k, load_resistance_ohm, amplifier_noise_a_rthz):
    check_range("signal_power_w", signal_power_w, 0.0, None, where=w)
    _pos("lo_power_w", lo_power_w, w)
    _pos("bandwidth_hz", bandwidth_hz, w)
    check_range("mixing_efficiency", mixing_efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("background_power_w", background_power_w, 0.0, None, where=w)
    check_range("dark_current_a", dark_current_a, 0.0, None, where=w)
    check_range("temperature_k", temperature_k, 0.0, 1e4, lo_open=True, where=w)
    _pos("load_resistance_ohm", load_resistance_ohm, w)
    check_range("amplifier_noise_a_rthz", amplifier_noise_a_rthz, 0.0, None, where=w)


def heterodyne_snr(signal_power_w, lo_power_w, quantum_efficiency, wavelength_m, bandwidth_hz, mixing_efficiency=1.0,
                   background_power_w=0.0, dark_current_a=0.0, temperature_k=290.0, load_resistance_ohm=1e4,
                   amplifier_noise_a_rthz=0.0):
    """Heterodyne (coherent) detection SNR, mean IF signal power over noise power (linear).

    ``SNR = 2 η_m ℜ² P_s P_LO / [(2 q (ℜ(P_LO + P_s + P_b) + I_d) + 4 k T / R_L + i_a²) B]``.

    Args:
        signal_power_w: received signal power P_s (W), in [0, ∞).
        lo_power_w: local-oscillator power P_LO (W), in (0, ∞).
        quantum_efficiency: η, in (0, 1].
        wavelength_m: λ (m), in [1e-9, 1e-2].
        bandwidth_hz: IF noise-equivalent bandwidth B (Hz), in (0, ∞).
        mixing_efficiency: heterodyne (mixing) efficiency η_m, in (0, 1]: spatial and
            polarization overlap of signal and LO fields.
        background_power_w: background power P_b on the detector (W), in [0, ∞).
        dark_current_a: dark current I_d (A), in [0, ∞).
        temperature_k: load temperature T (K), in (0, 1e4].
        load_resistance_ohm: load resistance R_L (Ω), in (0, ∞).
        amplifier_noise_a_rthz: amplifier noise current density i_a (A/√Hz), in [0, ∞).

    With P_LO → ∞ the SNR tends to :func:`quantum_limited_heterodyne_snr` η η_m P_s/(h ν B).
    Source: Kingston (1978) ch. 3; Jelalian (1992) ch. 2.
    """
    _check_heterodyne("heterodyne_snr", signal_power_w, lo_power_w, bandwidth_hz, mixing_efficiency,
                      background_power_w, dark_current_a, temperature_k, load_resistance_ohm, amplifier_noise_a_rthz)
    resp = responsivity_a_w(quantum_efficiency, wavelength_m)
    psd = heterodyne_noise_psd_a2_hz(signal_power_w, lo_power_w, background_power_w, resp, dark_current_a,
                                     temperature_k, load_resistance_ohm, amplifier_noise_a_rthz)
    signal = 2.0 * _f(mixing_efficiency) * resp * resp * _f(signal_power_w) * _f(lo_power_w)
    return signal / (psd * _f(bandwidth_hz))


def heterodyne_nep_w(lo_power_w, quantum_efficiency, wavelength_m, bandwidth_hz, mixing_efficiency=1.0,
                     background_power_w=0.0, dark_current_a=0.0, temperature_k=290.0, load_resistance_ohm=1e4,
                     amplifier_noise_a_rthz=0.0, signal_power_w=0.0):
    """Noise-equivalent power of a heterodyne receiver: the P_s giving SNR = 1 (W).

    ``NEP = i_n² / (2 η_m ℜ² P_LO)`` with the noise at the operating point (signal shot noise
    included through ``signal_power_w``); → h ν B / (η η_m) in the quantum limit.
    Arguments as :func:`heterodyne_snr`.
    """
    _check_heterodyne("heterodyne_nep_w", signal_power_w, lo_power_w, bandwidth_hz, mixing_efficiency,
                      background_power_w, dark_current_a, temperature_k, load_resistance_ohm, amplifier_noise_a_rthz)
    resp = responsivity_a_w(quantum_efficiency, wavelength_m)
    psd = heterodyne_noise_psd_a2_hz(signal_power_w, lo_power_w, background_power_w, resp, dark_current_a,
                                     temperature_k, load_resistance_ohm, amplifier_noise_a_rthz)
    return psd * _f(bandwidth_hz) / (2.0 * _f(mixing_efficiency) * resp * resp * _f(lo_power_w))


def quantum_limited_heterodyne_snr(signal_power_w, quantum_efficiency, wavelength_m, bandwidth_hz,
                                   mixing_efficiency=1.0):
    """Shot-noise (quantum) limited heterodyne SNR ``η η_m P_s / (h ν B)`` (linear).

    Args:
        signal_power_w: signal power P_s (W), in [0, ∞).
        quantum_efficiency: η, in (0, 1].
        wavelength_m: λ (m), in [1e-9, 1e-2] (h ν = h c / λ).
        bandwidth_hz: IF noise bandwidth B (Hz), in (0, ∞).
        mixing_efficiency: η_m, in (0, 1].

    Source: Kingston (1978) ch. 3 (the heterodyne receiver reaches one photoelectron per
    1/B seconds at SNR = 1); Jelalian (1992) ch. 2. One photon per 1/B seconds (P_s = h ν B)
    detected with η = 1 gives SNR 1:

    >>> h_nu = 6.62607015e-34 * 299792458 / 1.55e-6
    >>> float(quantum_limited_heterodyne_snr(h_nu * 1e6, 1.0, 1.55e-6, 1e6))
    1.0
    """
    w = "quantum_limited_heterodyne_snr"
    check_range("signal_power_w", signal_power_w, 0.0, None, where=w)
    check_range("quantum_efficiency", quantum_efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("wavelength_m", wavelength_m, 1e-9, 1e-2, where=w)
    _pos("bandwidth_hz", bandwidth_hz, w)
    check_range("mixing_efficiency", mixing_efficiency, 0.0, 1.0, lo_open=True, where=w)
    return (_f(quantum_efficiency) * _f(mixing_efficiency) * _f(signal_power_w) * _f(wavelength_m)
            / (_HC * _f(bandwidth_hz)))


def single_pole_pulse_response(bandwidth_hz, pulse_width_s, receiver="baseband"):
    """Peak signal-power factor of a rectangular pulse through a single-pole filter.

    A rectangular pulse of length τ through a one-pole low-pass filter of 3 dB bandwidth f_c
    peaks at 1 − exp(−2π f_c τ) of its input amplitude. With the noise-equivalent bandwidth
    B = (π/2) f_c of that filter the peak power factor is

    * ``"baseband"`` (direct detection, low-pass filter of noise bandwidth B):
      ``(1 − exp(−4 B τ))²``;
    * ``"if"`` (heterodyne, band-pass single-tuned filter of noise bandwidth B, whose
      envelope is the low-pass response with f_c = B/π): ``(1 − exp(−2 B τ))²``.

    The pulse SNR is SNR(B) times this factor; it equals the matched-filter efficiency
    ρ(β τ) of the single-tuned filter (Skolnik Table 5.1;
    :func:`diffsense.detection.matched_filter_efficiency`) times 2E/N0, with β τ = 4Bτ/π
    (baseband) or 2Bτ/π (IF). Exact for the single-pole response.

    Args:
        bandwidth_hz: noise-equivalent bandwidth B (Hz), in (0, ∞).
        pulse_width_s: rectangular pulse length τ (s), in (0, ∞).
        receiver: ``"baseband"`` or ``"if"`` (static).

    With 4 B τ = 1 (25 MHz, 10 ns) the baseband pulse peaks at 1 − 1/e of its amplitude:

    >>> import math
    >>> float(single_pole_pulse_response(25e6, 10e-9)), (1 - math.exp(-1)) ** 2
    (0.399576, 0.399576)
    """
    w = "single_pole_pulse_response"
    check_choice("receiver", receiver, ("baseband", "if"), where=w)
    _pos("bandwidth_hz", bandwidth_hz, w)
    _pos("pulse_width_s", pulse_width_s, w)
    scale = 4.0 if receiver == "baseband" else 2.0
    amp = -jnp.expm1(-scale * _f(bandwidth_hz) * _f(pulse_width_s))
    return amp * amp


def optimum_apd_gain(primary_current_a, ionization_ratio, temperature_k, load_resistance_ohm,
                     amplifier_noise_a_rthz=0.0):
    """APD gain that maximises the direct-detection SNR (McIntyre excess noise).

    With i_n² = 2 q I_p M² F(M) B + N_th B (N_th = 4kT/R_L + i_a²) and
    F = k M + (1 − k)(2 − 1/M), d SNR/dM = 0 gives the cubic

        ``k M³ + (1 − k) M = N_th / (q I_p)``

    whose single positive root is returned in closed form (hyperbolic solution of the
    depressed cubic M³ + p M − Q = 0, p = (1 − k)/k, Q = C/k, or Cardano's formula where the
    cubic term dominates; M = C at k = 0 and C^(1/3) at k = 1). The bandwidth cancels.

    Args:
        primary_current_a: primary (unmultiplied) DC current I_p = ℜ (P_s + P_b) + I_d (A),
            in (0, ∞).
        ionization_ratio: McIntyre k, in [0, 1].
        temperature_k: load temperature T (K), in (0, 1e4].
        load_resistance_ohm: R_L (Ω), in (0, ∞).
        amplifier_noise_a_rthz: i_a (A/√Hz), in [0, ∞).

    A root below 1 means unity gain is best (the SNR falls for every M > 1). The closed form
    is exact to float64 round-off. Source: derivation from Brooker §9.1.3 and McIntyre
    (1966); the same optimum condition for F = M^x is Personick's classic result
    M_opt^(2+x) = N_th/(x q I_p) (e.g. Senior, *Optical Fiber Communications*, ch. 9).
    """
    w = "optimum_apd_gain"
    _pos("primary_current_a", primary_current_a, w)
    check_range("ionization_ratio", ionization_ratio, 0.0, 1.0, where=w)
    check_range("temperature_k", temperature_k, 0.0, 1e4, lo_open=True, where=w)
    _pos("load_resistance_ohm", load_resistance_ohm, w)
    check_range("amplifier_noise_a_rthz", amplifier_noise_a_rthz, 0.0, None, where=w)
    n_th = 4.0 * _K * _f(temperature_k) / _f(load_resistance_ohm) + _f(amplifier_noise_a_rthz) ** 2
    # (N_th/q)/I_p, not N_th/(q I_p): the quotient rule's (q I_p)² ~ 1e-56 A² underflows float32
    c = (n_th / _Q) / _f(primary_current_a)
    k = _f(ionization_ratio)
    return _cubic_root(c, k)


def _cubic_root(c, k):
    """Positive root of k M³ + (1 − k) M = c for c > 0, 0 ≤ k ≤ 1, with finite derivatives.

    With p = (1 − k)/k, Q = c/k the cubic is M³ + p M − Q = 0; x = Q / (2 (p/3)^(3/2)) measures
    how cubic it is (x² = 27 c² k / (4 (1 − k)³)). Three exact forms avoid cancellation and
    overflow: x < 1e-4: M = c/(1−k) (1 − 4x²/27) (series of the next form; error O(x⁴));
    x < 1: M = c/(1−k) · 3 sinh(asinh(x)/3)/x (trigonometric-hyperbolic solution);
    x ≥ 1 or k = 1: Cardano, M = u − p/(3u), u³ = (Q/2)(1 + sqrt(1 + 1/x²)).
    The branch is chosen by log x² (x² itself overflows float32 for c ≳ 1e19), and x and 1/x²
    are formed from it only where their branch is taken (double ``where``), so values and
    derivatives stay finite in float32 and at k = 0.
    """
    below_one = k < 1.0
    inner = below_one & (k > 0.0)
    k_c = jnp.where(inner, k, 0.5)
    log_x2 = math.log(6.75) + 2.0 * jnp.log(jnp.where(c > 0.0, c, 1.0)) + jnp.log(k_c) - 3.0 * jnp.log1p(-k_c)
    cardano = (~below_one) | (inner & (log_x2 >= 0.0))
    series = below_one & ((~inner) | (log_x2 < _LOG_SERIES_X2))
    hyper = ~(cardano | series)
    # the series from x² itself (below 1e-8 there): its k-derivative stays exact at k = 0
    k_s = jnp.where(series, k, 0.0)
    c_s = jnp.where(series, c, 0.0)
    x2 = 6.75 * c_s * c_s * k_s / (1.0 - k_s) ** 3
    linear = c / (1.0 - jnp.where(below_one, k, 0.5))
    m_series = linear * (1.0 - (4.0 / 27.0) * x2)
    x_h = jnp.exp(0.5 * jnp.where(hyper, log_x2, math.log(0.25)))
    m_hyper = linear * 3.0 * jnp.sinh(jnp.arcsinh(x_h) / 3.0) / x_h
    k_k = jnp.where(cardano, k, 1.0)
    p = (1.0 - k_k) / k_k
    q = c / k_k
    inv_x2 = jnp.where(cardano & inner, jnp.exp(-jnp.where(cardano & inner, log_x2, 0.0)), 0.0)
    u = jnp.cbrt(0.5 * q * (1.0 + jnp.sqrt(1.0 + inv_x2)))
    m_cardano = u - p / (3.0 * u)
    return jnp.where(cardano, m_cardano, jnp.where(series, m_series, m_hyper))
