"""Measurement accuracy of a coherent pulse train: the Cramér–Rao bound on its Doppler frequency
and range rate.

The echo of a dwell of N pulses, each τ long, one every T_r = 1/f_p, is a known waveform of
unknown amplitude, phase and Doppler frequency f in complex white noise. The Cramér–Rao bound on
an unbiased estimate of f is (Rife & Boorstyn 1974 for a sampled sinusoid; Van Trees 1968 §6.2 in
continuous time)

    σ_f = 1 / (2π t_rms sqrt(2 SNR_N)),      SNR_N = N · SNR_1,

where SNR_1 is the single-pulse signal-to-noise ratio after the matched filter (|s|² summed over
the pulse over the complex noise power per sample, the radar budget's ``snr_db``) and t_rms the
rms duration of the echo's energy about its centre. For N equal rectangular pulses

    t_rms² = ((N² − 1) T_r² + τ²) / 12

(the spread of the pulse centres, a discrete uniform law, plus the spread inside one pulse), so a
single pulse gives the classic σ_f ∝ 1/τ and a long train σ_f ∝ 1/(N T_r) (Skolnik, *Introduction
to Radar Systems* 3rd ed. §6.3; Barton & Leonov, *Radar Technology Encyclopedia*, "Doppler
accuracy"). The range rate follows from f = 2 v / λ: σ_v = λ σ_f / 2.

The bound is met by the maximum-likelihood estimator (the peak of the dwell's Doppler spectrum,
interpolated) once SNR_N is above the estimator's threshold, about 15 dB; below it the error is
larger (outliers). tests/physics/test_measurement_accuracy.py checks the bound by Monte Carlo of
that estimator.

A pulse train samples the Doppler phase once per pulse, so the range rate it measures is folded
into one blind-speed interval of width λ f_p / 2; not knowing it at all within that interval is an
rms error of λ f_p / (2 sqrt(12)). The radar's reported accuracy joins the two ends as the
Bayesian (Van Trees) bound with a prior of that variance (Van Trees 1968, *Detection, Estimation,
and Modulation Theory* I, §2.4.3):

    σ_v = (σ_CRB⁻² + σ_prior⁻²)^(−1/2),      σ_prior = λ f_p / (2 sqrt(12)),

which equals the Cramér–Rao bound to relative error σ_CRB²/(2 σ_prior²) where the estimate is
good, and the a-priori spread (not infinity) where the echo is lost in noise. The information form
keeps value and gradient finite at any SNR: 10^(SNR/10) underflows to zero, never overflows.
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.db import from_db10

__all__ = ["echo_rms_duration_s", "doppler_accuracy_hz", "range_rate_accuracy_mps", "folded_range_rate_accuracy_mps"]


def echo_rms_duration_s(n_pulses, prf_hz, pulse_width_s):
    """rms duration t_rms (s) of N rectangular pulses of width τ at PRF f_p:
    ``sqrt(((N² − 1)/f_p² + τ²)/12)`` (N real ≥ 1).

    >>> round(float(echo_rms_duration_s(1.0, 1e3, 1e-6) * 1e9), 3)  # one pulse: τ/sqrt(12)
    288.675
    """
    n = jnp.asarray(n_pulses, dtype=float)
    spread = (n * n - 1.0) / jnp.asarray(prf_hz) ** 2
    return jnp.sqrt((spread + jnp.asarray(pulse_width_s) ** 2) / 12.0)


def doppler_accuracy_hz(snr_db, n_pulses, prf_hz, pulse_width_s):
    """Cramér–Rao bound σ_f (Hz) on the Doppler frequency of a coherent dwell (module docstring):
    ``1 / (2π t_rms sqrt(2 N SNR_1))``, SNR_1 = 10^(snr_db/10) per pulse.

    16 pulses at 1 kHz, 10 dB each: t_rms = sqrt(255/12) ms, SNR_N = 160:

    >>> round(float(doppler_accuracy_hz(10.0, 16.0, 1e3, 1e-6)), 4)
    1.93
    """
    t_rms = echo_rms_duration_s(n_pulses, prf_hz, pulse_width_s)
    snr_n = jnp.asarray(n_pulses, dtype=float) * from_db10(snr_db)
    return 1.0 / (2.0 * math.pi * t_rms * jnp.sqrt(2.0 * snr_n))


def range_rate_accuracy_mps(snr_db, n_pulses, prf_hz, pulse_width_s, wavelength_m):
    """Cramér–Rao bound σ_v = λ σ_f / 2 (m/s) on the range rate measured over a coherent dwell of
    ``n_pulses`` pulses (module docstring)."""
    return 0.5 * jnp.asarray(wavelength_m) * doppler_accuracy_hz(snr_db, n_pulses, prf_hz, pulse_width_s)


def folded_range_rate_accuracy_mps(snr_db, n_pulses, prf_hz, pulse_width_s, wavelength_m):
    """Range-rate accuracy (m/s) of a coherent dwell, its Cramér–Rao bound limited by the a-priori
    spread of a range rate folded into one blind-speed interval (module docstring):
    ``(σ_CRB⁻² + σ_prior⁻²)^(−1/2)``, σ_prior = λ f_p / (2 sqrt(12)).

    Far above threshold it is the Cramér–Rao bound; with no echo, the prior spread:

    >>> crb = float(range_rate_accuracy_mps(30.0, 16.0, 1e3, 1e-6, 0.03))
    >>> round(float(folded_range_rate_accuracy_mps(30.0, 16.0, 1e3, 1e-6, 0.03)) / crb, 6)
    1.0
    >>> round(float(folded_range_rate_accuracy_mps(-1e4, 16.0, 1e3, 1e-6, 0.03)) * 2 * math.sqrt(12) / 30.0, 12)
    1.0
    """
    lam = jnp.asarray(wavelength_m, dtype=float)
    t_rms = echo_rms_duration_s(n_pulses, prf_hz, pulse_width_s)
    # Fisher information on v: (4π t_rms / λ)² · 2 N SNR_1, finite for every snr_db
    information = (4.0 * math.pi * t_rms / lam) ** 2 * 2.0 * jnp.asarray(n_pulses, dtype=float) * from_db10(snr_db)
    prior_information = 48.0 / (lam * jnp.asarray(prf_hz)) ** 2  # 1/σ_prior², σ_prior = λ f_p/(2√12)
    return 1.0 / jnp.sqrt(information + prior_information)
