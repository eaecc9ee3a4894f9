"""Waveform relations: resolution, ambiguity, Doppler, FMCW, SAR/DBS cross-range, scan timing.

Pure ``jnp`` formulas of broadcastable arrays; jit/vmap/grad-able. SI units; every argument
carries its unit in its name. The propagation speed defaults to the exact speed of light; pass
``propagation_speed_m_s`` for sound (the book uses c = 3e8 m/s for radar and 1522 m/s in sea
water for its side-scan sonar). Radial velocity is positive for a closing (approaching) target,
which gives a positive Doppler shift.

Sources (book = Brooker, *Introduction to Sensors for Ranging and Imaging*): range resolution
eqs (11.4), (11.25), (12.37); maximum PRF §8.16.14 and eq (12.39); duty cycle eq (12.40);
update rate §8.16.14 and §14.4 (f_p/N_p, range-gated pulsed Doppler tracking); FMCW eqs (11.20)–(11.25)
and the seeker example §11.12.4; hits per scan eq (9.26) and §9.9.1.1; blind speeds eqs
(14.2)–(14.3); Doppler shift eq (10.7); Doppler beam sharpening eq (12.67); unfocused SAR eqs
(12.71)–(12.76); focused SAR eqs (12.80)–(12.85); real-aperture cross-range eq (12.38).
The scan loss of a phased array is the cos θ factor of ``diffsense.physics.antennas.phased_array_gain``.

This module is the one home of these relations: the sensor chains (radar, lidar, sonar) call
them with their own propagation speed instead of keeping copies.
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import db10
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.physics.received_pulse import received_pulse_width_s

__all__ = [
    "range_resolution_bandwidth_m",
    "range_resolution_pulse_m",
    "range_resolution_received_m",
    "unambiguous_range_m",
    "max_prf_hz",
    "duty_cycle",
    "update_rate_hz",
    "pulse_compression_gain",
    "pulse_compression_gain_db",
    "doppler_shift_hz",
    "radial_velocity_from_doppler_m_s",
    "doppler_resolution_hz",
    "unambiguous_velocity_m_s",
    "blind_speed_m_s",
    "fmcw_beat_frequency_hz",
    "fmcw_triangular_beat_frequencies_hz",
    "fmcw_range_from_beat_m",
    "fmcw_range_velocity_from_beats",
    "fmcw_range_resolution_m",
    "fft_bin_width_hz",
    "fmcw_sample_rate_hz",
    "real_aperture_cross_range_m",
    "unfocused_sar_max_aperture_m",
    "unfocused_sar_cross_range_m",
    "UNFOCUSED_SAR_COEFFICIENT",
    "focused_sar_cross_range_m",
    "dbs_cross_range_m",
    "dbs_isovel_angle_rad",
    "hits_per_scan",
]

_C = SPEED_OF_LIGHT_M_S
_POS = dict(lo=0.0, hi=None, lo_open=True)

#: The book's unfocused-SAR coefficient, eq (12.76): x_h √2/(2π) = 0.31321 with x_h = 1.39156 the
#: half-power point of the SAR pattern sinc² (12.69) and the maximum unfocused aperture L = √(Rλ/2) (12.72).
UNFOCUSED_SAR_COEFFICIENT = 0.313


def _pos(name, x, where):
    check_range(name, x, 0.0, None, lo_open=True, where=where)


# ---------------------------------------------------------------------------------------------
# Range resolution, ambiguity, timing
# ---------------------------------------------------------------------------------------------


def range_resolution_bandwidth_m(bandwidth_hz, propagation_speed_m_s=_C):
    """Range resolution of a waveform of bandwidth B: ``δR = c / (2B)`` (m).

    Holds for a compressed pulse (chirp or code) and for FMCW with swept bandwidth Δf.

    Args:
        bandwidth_hz: signal (swept) bandwidth B (Hz), in (0, ∞).
        propagation_speed_m_s: wave speed c (m/s), in (0, ∞); default exact c.

    Source: book eqs (11.4), (11.25); side-scan sonar chirp 15 kHz → 0.05 m, eq (12.37);
    FMCW seeker 300 MHz → 0.5 m, §11.12.4.2 (with the book's c = 3e8 m/s):

    >>> float(range_resolution_bandwidth_m(300e6, 3e8))
    0.5
    >>> float(range_resolution_bandwidth_m(15e3, 1522.0))
    0.05
    """
    w = "range_resolution_bandwidth_m"
    _pos("bandwidth_hz", bandwidth_hz, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    return propagation_speed_m_s / (2.0 * jnp.asarray(bandwidth_hz))


def range_resolution_pulse_m(pulse_width_s, propagation_speed_m_s=_C):
    """Range resolution of an uncompressed rectangular pulse: ``δR = c τ / 2`` (m).

    Args:
        pulse_width_s: pulse width τ (s), in (0, ∞).
        propagation_speed_m_s: wave speed c (m/s), in (0, ∞).

    Source: book §11.7.2 below eq (11.25): c/(2Δf) is the pulse-compression/FMCW equivalent of
    the classical pulsed resolution cτ/2 with τ = 1/Δf (eq (11.4), not in the excerpt used here).
    Book §8.16.3: a 2 m range gate needs a 13.3 ns pulse (c = 3e8 m/s):

    >>> float(range_resolution_pulse_m(13.3e-9, 3e8))
    2.0
    """
    w = "range_resolution_pulse_m"
    _pos("pulse_width_s", pulse_width_s, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    return 0.5 * propagation_speed_m_s * jnp.asarray(pulse_width_s)


def range_resolution_received_m(pulse_width_s, bandwidth_hz, receiver_filter="matched", propagation_speed_m_s=_C):
    """Range resolution of a rectangular pulse as the receiver passes it: ``δR = c W / 2`` (m).

    W is the half-amplitude width of the echo after the IF filter
    (:func:`diffsense.physics.received_pulse.received_pulse_width_s`): τ for the ideal matched
    filter, so that δR = c τ / 2 (:func:`range_resolution_pulse_m`); a filter narrower than the
    pulse (β τ ≪ 1) smears the echo over about its own impulse response and δR ≈ c · 0.5/β (two
    tuned circuits). The same length is the range gate, the clutter-cell length and the split
    gate of a range tracker.

    Args:
        pulse_width_s: transmitted pulse length τ (s), in (0, ∞).
        bandwidth_hz: IF 3 dB bandwidth β (Hz), in (0, ∞); β τ in the filter's domain.
        receiver_filter: ``"matched"`` or a filter of
            :data:`diffsense.physics.received_pulse.RECEIVER_FILTERS` (static).
        propagation_speed_m_s: wave speed c (m/s), in (0, ∞).

    Source: book eq (11.4) and §8.16.3 (c τ / 2 for the matched pulse); the filtered pulse
    shapes of Skolnik (2001) §5.2 (see :mod:`diffsense.physics.received_pulse`).

    One tuned circuit, W = τ + ln(1 + exp(−π β τ))/(π β), with β τ = 0.5 (c = 3e8 m/s):

    >>> import math
    >>> w = 1e-6 + math.log(1 + math.exp(-math.pi * 0.5)) / (math.pi * 0.5e6)
    >>> float(range_resolution_received_m(1e-6, 0.5e6, "single_tuned", 3e8)), 1.5e8 * w
    (168.035, 168.035)
    """
    _pos("propagation_speed_m_s", propagation_speed_m_s, "range_resolution_received_m")
    return range_resolution_pulse_m(received_pulse_width_s(pulse_width_s, bandwidth_hz, receiver_filter),
                                    propagation_speed_m_s)


def unambiguous_range_m(prf_hz, propagation_speed_m_s=_C):
    """Maximum unambiguous range of a pulse train: ``R_u = c / (2 f_p)`` (m).

    Args:
        prf_hz: pulse repetition frequency f_p (Hz), in (0, ∞).
        propagation_speed_m_s: wave speed c (m/s), in (0, ∞).

    Source: book §8.16.14 and eq (12.39) (inverse form f_p = c / 2R_max); the ore-pass radar's
    500 kHz PRF is unambiguous to 300 m (c = 3e8 m/s):

    >>> float(unambiguous_range_m(500e3, 3e8))
    300.0
    """
    w = "unambiguous_range_m"
    _pos("prf_hz", prf_hz, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    return propagation_speed_m_s / (2.0 * jnp.asarray(prf_hz))


def max_prf_hz(max_range_m, propagation_speed_m_s=_C):
    """Highest PRF with no range ambiguity out to R_max: ``f_p = c / (2 R_max)`` (Hz).

    Args:
        max_range_m: maximum unambiguous range R_max (m), in (0, ∞).
        propagation_speed_m_s: wave speed c (m/s), in (0, ∞).

    Source: book §8.16.14 (300 m → 500 kHz), eq (12.39) (sonar, 500 m at 1522 m/s → 1.52 Hz):

    >>> float(max_prf_hz(300.0, 3e8))
    500000.0
    >>> float(max_prf_hz(500.0, 1522.0))
    1.52
    """
    w = "max_prf_hz"
    _pos("max_range_m", max_range_m, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    return propagation_speed_m_s / (2.0 * jnp.asarray(max_range_m))


def duty_cycle(prf_hz, pulse_width_s):
    """Transmitter duty cycle ``χ = f_p τ`` (fraction, not percent).

    Args:
        prf_hz: pulse repetition frequency f_p (Hz), in (0, ∞).
        pulse_width_s: pulse width τ (s), in (0, ∞); the product must not exceed 1.

    Source: book eq (12.40) (the book prints 100 f_p τ in percent: 1.52 Hz × 333 µs = 0.05 %):

    >>> float(duty_cycle(1.52, 333e-6))
    0.0005
    """
    w = "duty_cycle"
    _pos("prf_hz", prf_hz, w)
    _pos("pulse_width_s", pulse_width_s, w)
    d = jnp.asarray(prf_hz) * jnp.asarray(pulse_width_s)
    if is_concrete(prf_hz) and is_concrete(pulse_width_s):
        check_range("prf_hz * pulse_width_s", d, None, 1.0, where=w)
    return d


def update_rate_hz(prf_hz, pulses_per_update):
    """Measurement update rate when N pulses are integrated per output: ``f_u = f_p / N`` (Hz).

    Args:
        prf_hz: pulse repetition frequency f_p (Hz), in (0, ∞).
        pulses_per_update: pulses integrated (or FFT length) N per measurement, in [1, ∞);
            real values allowed (smooth relaxation of the count).

    Source: book §8.16.14 (500 kHz / 16 = 31.25 kHz) and §14.4 (range tracking loop updated at
    f_p/N_p when an N_p-point FFT extracts Doppler):

    >>> float(update_rate_hz(500e3, 16))
    31250.0
    """
    w = "update_rate_hz"
    _pos("prf_hz", prf_hz, w)
    check_range("pulses_per_update", pulses_per_update, 1.0, None, where=w)
    return jnp.asarray(prf_hz) / jnp.asarray(pulses_per_update)


def pulse_compression_gain(bandwidth_hz, pulse_width_s):
    """Pulse-compression (time–bandwidth) gain ``G_pc = B τ`` (ratio).

    The matched-filter output SNR gain of a coded/chirped pulse over an uncompressed pulse of
    the same peak power and resolution; equal to the compression ratio τ/τ_c with τ_c = 1/B.

    Args:
        bandwidth_hz: chirp/code bandwidth B (Hz), in (0, ∞).
        pulse_width_s: transmitted pulse width τ (s), in (0, ∞).

    Source: book §11.3–11.4 (compression ratio Bτ; sonar §12.7: 32.9 ms × 15 kHz, printed 493):

    >>> float(pulse_compression_gain(15e3, 32.9e-3))
    493.5
    """
    w = "pulse_compression_gain"
    _pos("bandwidth_hz", bandwidth_hz, w)
    _pos("pulse_width_s", pulse_width_s, w)
    return jnp.asarray(bandwidth_hz) * jnp.asarray(pulse_width_s)


def pulse_compression_gain_db(bandwidth_hz, pulse_width_s):
    """``10 log10(B τ)`` (dB); see :func:`pulse_compression_gain`.

    A 10 µs pulse swept over 100 MHz compresses by 1000, i.e. 30 dB:

    >>> float(pulse_compression_gain_db(100e6, 10e-6))
    30.0
    """
    return db10(pulse_compression_gain(bandwidth_hz, pulse_width_s))


# ---------------------------------------------------------------------------------------------
# Doppler
# ---------------------------------------------------------------------------------------------


def doppler_shift_hz(radial_velocity_m_s, wavelength_m):
    """Two-way (monostatic) Doppler shift ``f_d = 2 v_r / λ`` (Hz), positive for closing targets.

    First-order form of the exact two-way shift ``f (c + v)/(c − v) − f`` obtained by applying
    eq (10.7) twice; relative error v/c (1e-6 at 300 m/s for EM; 0.2 at 150 m/s in water —
    use with |v| ≪ c).

    Args:
        radial_velocity_m_s: radial velocity v_r (m/s), any real value (negative = opening).
        wavelength_m: transmitted wavelength λ (m), in (0, ∞).

    Source: book §10.1–10.2, eq (10.7); §12.9 (isodop spacing 83 Hz at 10 GHz).
    """
    w = "doppler_shift_hz"
    check_range("radial_velocity_m_s", radial_velocity_m_s, where=w)
    _pos("wavelength_m", wavelength_m, w)
    return 2.0 * jnp.asarray(radial_velocity_m_s) / jnp.asarray(wavelength_m)


def radial_velocity_from_doppler_m_s(doppler_hz, wavelength_m):
    """Radial velocity from a two-way Doppler shift ``v_r = f_d λ / 2`` (m/s).

    Args:
        doppler_hz: Doppler shift f_d (Hz), any real value.
        wavelength_m: wavelength λ (m), in (0, ∞).

    Source: inverse of book eq (10.7) to first order (see :func:`doppler_shift_hz`).
    """
    w = "radial_velocity_from_doppler_m_s"
    check_range("doppler_hz", doppler_hz, where=w)
    _pos("wavelength_m", wavelength_m, w)
    return 0.5 * jnp.asarray(doppler_hz) * jnp.asarray(wavelength_m)


def doppler_resolution_hz(observation_time_s):
    """Doppler (spectral) resolution of a coherent observation of length T: ``δf = 1 / T`` (Hz).

    Args:
        observation_time_s: coherent observation (dwell) time T (s), in (0, ∞).

    Source: book §12.9 ("a resolution of 83 Hz requires t = 1/β = 12 ms") and eq (12.82).
    """
    _pos("observation_time_s", observation_time_s, "doppler_resolution_hz")
    return 1.0 / jnp.asarray(observation_time_s)


def unambiguous_velocity_m_s(prf_hz, wavelength_m):
    """Largest |radial velocity| measured without Doppler ambiguity: ``v_u = λ f_p / 4`` (m/s).

    A coherent (I/Q) pulse train samples the Doppler at f_p, so |f_d| < f_p/2 is unambiguous:
    ``|v| < λ f_p / 4``. The full unambiguous span (−v_u, v_u) equals the first blind speed
    λ f_p / 2 (:func:`blind_speed_m_s` with n = 1).

    Args:
        prf_hz: pulse repetition frequency f_p (Hz), in (0, ∞).
        wavelength_m: wavelength λ (m), in (0, ∞).

    Source: Nyquist sampling of the Doppler at the PRF with book eqs (14.2)–(14.3); Skolnik,
    *Introduction to Radar Systems*, 3rd ed. (2001), ch. 3 (pulse-Doppler ambiguities).
    """
    w = "unambiguous_velocity_m_s"
    _pos("prf_hz", prf_hz, w)
    _pos("wavelength_m", wavelength_m, w)
    return 0.25 * jnp.asarray(wavelength_m) * jnp.asarray(prf_hz)


def blind_speed_m_s(n, wavelength_m, prf_hz):
    """MTI blind speeds ``v_n = n λ f_p / 2`` (m/s): Doppler at a multiple of the PRF.

    Args:
        n: blind-speed index n, in [0, ∞) (integers physically; reals accepted).
        wavelength_m: wavelength λ (m), in (0, ∞).
        prf_hz: pulse repetition frequency f_p (Hz), in (0, ∞).

    Source: book §14.2.3.1, eqs (14.2)–(14.3).
    """
    w = "blind_speed_m_s"
    check_range("n", n, 0.0, None, where=w)
    _pos("wavelength_m", wavelength_m, w)
    _pos("prf_hz", prf_hz, w)
    return 0.5 * jnp.asarray(n) * jnp.asarray(wavelength_m) * jnp.asarray(prf_hz)


# ---------------------------------------------------------------------------------------------
# FMCW
# ---------------------------------------------------------------------------------------------


def fmcw_beat_frequency_hz(range_m, sweep_bandwidth_hz, sweep_time_s, propagation_speed_m_s=_C):
    """Range beat frequency of a linear FMCW sweep ``f_b = (Δf / T_b)(2R / c)`` (Hz).

    Valid while the round-trip time 2R/c is much shorter than the sweep T_b (book's T_b ≫ T_p).
    For a moving target add the Doppler term (:func:`fmcw_triangular_beat_frequencies_hz`).

    Args:
        range_m: target range R (m), in [0, ∞).
        sweep_bandwidth_hz: swept bandwidth Δf (Hz), in (0, ∞).
        sweep_time_s: sweep (chirp) duration T_b (s), in (0, ∞).
        propagation_speed_m_s: wave speed c (m/s), in (0, ∞).

    Source: book eqs (11.20)–(11.22); seeker §11.12.4: 300 MHz, 500 µs, 1 km → 4 MHz:

    >>> float(fmcw_beat_frequency_hz(1e3, 300e6, 500e-6, 3e8))
    4000000.0
    """
    w = "fmcw_beat_frequency_hz"
    check_range("range_m", range_m, 0.0, None, where=w)
    _pos("sweep_bandwidth_hz", sweep_bandwidth_hz, w)
    _pos("sweep_time_s", sweep_time_s, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    return (jnp.asarray(sweep_bandwidth_hz) / jnp.asarray(sweep_time_s)) * (
        2.0 * jnp.asarray(range_m) / propagation_speed_m_s
    )


def fmcw_triangular_beat_frequencies_hz(
    range_m, radial_velocity_m_s, sweep_bandwidth_hz, sweep_time_s, wavelength_m, propagation_speed_m_s=_C
):
    """Up- and down-sweep beat frequencies of a triangular FMCW waveform (Hz).

    ``f_up = f_r − f_d``, ``f_down = f_r + f_d`` with the range beat ``f_r = 2RΔf/(c T_b)``
    (:func:`fmcw_beat_frequency_hz`) and the Doppler shift ``f_d = 2 v_r/λ``
    (:func:`doppler_shift_hz`, closing v_r > 0). Signed frequencies; a real (non-I/Q) receiver
    measures their magnitudes. Returns ``(f_up, f_down)``.

    Args:
        range_m: range R (m), in [0, ∞).
        radial_velocity_m_s: closing radial velocity v_r (m/s), any real value.
        sweep_bandwidth_hz: Δf (Hz), in (0, ∞).
        sweep_time_s: duration of each (up or down) sweep T_b (s), in (0, ∞).
        wavelength_m: carrier wavelength λ (m), in (0, ∞).
        propagation_speed_m_s: c (m/s), in (0, ∞).

    Source: book §11.7.3 eq (11.26) (Doppler–range coupling of the chirp) and §11.12.4.2
    (triangular sweep so that up/down differences separate Doppler from range); Stove, A. G.
    (1992), "Linear FMCW radar techniques", IEE Proc. F 139(5), 343–350.
    """
    f_r = fmcw_beat_frequency_hz(range_m, sweep_bandwidth_hz, sweep_time_s, propagation_speed_m_s)
    f_d = doppler_shift_hz(radial_velocity_m_s, wavelength_m)
    return f_r - f_d, f_r + f_d


def fmcw_range_from_beat_m(beat_frequency_hz, sweep_bandwidth_hz, sweep_time_s, propagation_speed_m_s=_C):
    """Range from an FMCW beat frequency ``R = T_b c f_b / (2 Δf)`` (m).

    With f_b replaced by the frequency resolution δf_b (e.g. :func:`fft_bin_width_hz`) this is
    the range-bin size δR = T_b c δf_b / (2Δf) of eq (11.24).

    Args:
        beat_frequency_hz: beat frequency f_b (Hz), in [0, ∞).
        sweep_bandwidth_hz: Δf (Hz), in (0, ∞).
        sweep_time_s: T_b (s), in (0, ∞).
        propagation_speed_m_s: c (m/s), in (0, ∞).

    Source: book eqs (11.23)–(11.24).
    """
    w = "fmcw_range_from_beat_m"
    check_range("beat_frequency_hz", beat_frequency_hz, 0.0, None, where=w)
    _pos("sweep_bandwidth_hz", sweep_bandwidth_hz, w)
    _pos("sweep_time_s", sweep_time_s, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    return jnp.asarray(sweep_time_s) * propagation_speed_m_s * jnp.asarray(beat_frequency_hz) / (
        2.0 * jnp.asarray(sweep_bandwidth_hz)
    )


def fmcw_range_velocity_from_beats(
    up_beat_hz, down_beat_hz, sweep_bandwidth_hz, sweep_time_s, wavelength_m, propagation_speed_m_s=_C
):
    """Range and closing velocity from triangular-FMCW up/down beats; inverse of
    :func:`fmcw_triangular_beat_frequencies_hz`.

    ``R = c T_b (f_up + f_down) / (4 Δf)``, ``v_r = λ (f_down − f_up) / 4``. Returns ``(R, v_r)``.

    Args:
        up_beat_hz, down_beat_hz: signed beat frequencies (Hz), any real values with
            f_up + f_down ≥ 0.
        sweep_bandwidth_hz: Δf (Hz), in (0, ∞).
        sweep_time_s: T_b (s), in (0, ∞).
        wavelength_m: λ (m), in (0, ∞).
        propagation_speed_m_s: c (m/s), in (0, ∞).

    Source: as :func:`fmcw_triangular_beat_frequencies_hz`.
    """
    w = "fmcw_range_velocity_from_beats"
    check_range("up_beat_hz", up_beat_hz, where=w)
    check_range("down_beat_hz", down_beat_hz, where=w)
    _pos("sweep_bandwidth_hz", sweep_bandwidth_hz, w)
    _pos("sweep_time_s", sweep_time_s, w)
    _pos("wavelength_m", wavelength_m, w)
    _pos("propagation_speed_m_s", propagation_speed_m_s, w)
    up = jnp.asarray(up_beat_hz)
    down = jnp.asarray(down_beat_hz)
    if is_concrete(up_beat_hz) and is_concrete(down_beat_hz):
        check_range("up_beat_hz + down_beat_hz", up + down, 0.0, None, where=w)
    rng = propagation_speed_m_s * jnp.asarray(sweep_time_s) * (up + down) / (4.0 * jnp.asarray(sweep_bandwidth_hz))
    vel = 0.25 * jnp.asarray(wavelength_m) * (down - up)
    return rng, vel


def fmcw_range_resolution_m(sweep_bandwidth_hz, propagation_speed_m_s=_C):
    """FMCW range resolution ``δR = c / (2 Δf)`` (m); same relation as
    :func:`range_resolution_bandwidth_m`. Source: book eq (11.25), §11.12.4.2 (300 MHz → 0.5 m)."""
    return range_resolution_bandwidth_m(sweep_bandwidth_hz, propagation_speed_m_s)


def fft_bin_width_hz(sample_rate_hz, n_fft, window_factor=1.0):
    """Noise bandwidth of one FFT bin widened by the window: ``β = k_w f_s / N`` (Hz).

    Args:
        sample_rate_hz: sample rate f_s (Hz), in (0, ∞).
        n_fft: FFT length N (real values accepted), in [1, ∞).
        window_factor: window noise-bandwidth factor k_w ≥ 1 (1 rectangular; the book uses 1.3
            for its window, Table 11.4 lists the factors), in [1, 3].

    Source: book §11.12.4.8: 1.3 × 5 MHz / 2048 ≈ 3 kHz (10 MHz sampling, 4096-point FFT:
    f_s/N = (f_s/2)/(N/2)):

    >>> float(fft_bin_width_hz(10e6, 4096, 1.3)), 1.3 * 5e6 / 2048
    (3173.83, 3173.83)
    """
    w = "fft_bin_width_hz"
    _pos("sample_rate_hz", sample_rate_hz, w)
    check_range("n_fft", n_fft, 1.0, None, where=w)
    check_range("window_factor", window_factor, 1.0, 3.0, where=w)
    return jnp.asarray(window_factor) * jnp.asarray(sample_rate_hz) / jnp.asarray(n_fft)


def fmcw_sample_rate_hz(max_beat_frequency_hz, oversampling=2.5):
    """ADC sample rate for FMCW beat signals ``f_s = k f_b,max`` (Hz).

    Nyquist needs k = 2; the book takes k = 2.5 to allow for a real anti-aliasing filter.

    Args:
        max_beat_frequency_hz: highest beat frequency f_b,max (Hz), in (0, ∞).
        oversampling: k, in [2, 10].

    Source: book §11.12.4 (4 MHz beat → 8 MHz Nyquist, 10 MHz with k = 2.5):

    >>> float(fmcw_sample_rate_hz(4e6))
    10000000.0
    """
    w = "fmcw_sample_rate_hz"
    _pos("max_beat_frequency_hz", max_beat_frequency_hz, w)
    check_range("oversampling", oversampling, 2.0, 10.0, where=w)
    return jnp.asarray(oversampling) * jnp.asarray(max_beat_frequency_hz)


# ---------------------------------------------------------------------------------------------
# Cross-range resolution: real beam, Doppler beam sharpening, SAR
# ---------------------------------------------------------------------------------------------


def real_aperture_cross_range_m(range_m, beamwidth_rad):
    """Cross-range resolution of a real (unfocused) beam ``δ_xr = R θ`` (m).

    Args:
        range_m: range R (m), in (0, ∞).
        beamwidth_rad: azimuth 3 dB beamwidth θ (rad), in (0, π].

    Source: book eq (12.38) (500 m × 1.5° = 13.1 m):

    >>> import math
    >>> float(real_aperture_cross_range_m(500.0, math.radians(1.5)))
    13.1
    """
    w = "real_aperture_cross_range_m"
    _pos("range_m", range_m, w)
    check_range("beamwidth_rad", beamwidth_rad, 0.0, math.pi, lo_open=True, where=w)
    return jnp.asarray(range_m) * jnp.asarray(beamwidth_rad)


def unfocused_sar_max_aperture_m(range_m, wavelength_m):
    """Longest unfocused synthetic aperture ``L_max = √(R λ / 2)`` (m): range curvature across
    the aperture reaches λ/8 (one-way), eqs (12.71)–(12.72).

    Args:
        range_m: range R (m), in (0, ∞).
        wavelength_m: wavelength λ (m), in (0, ∞).

    Source: book §12.11.1, eqs (12.71)–(12.72).
    """
    w = "unfocused_sar_max_aperture_m"
    _pos("range_m", range_m, w)
    _pos("wavelength_m", wavelength_m, w)
    return jnp.sqrt(0.5 * jnp.asarray(range_m) * jnp.asarray(wavelength_m))


def unfocused_sar_cross_range_m(range_m, wavelength_m):
    """Unfocused SAR cross-range resolution ``δ_xr = 0.313 √(R λ)`` (m).

    From the half-power width of the two-way synthetic-array pattern (12.69),
    sin θ = 0.886 λ / (4 L) (12.74), with L = L_max = √(Rλ/2) (12.72). The book's 0.313
    rounds x_h √2/(2π) = 0.31321 (x_h = 1.39156, sinc²(x_h) = 1/2): 0.07 % lower.

    Args:
        range_m: range R (m), in (0, ∞).
        wavelength_m: wavelength λ (m), in (0, ∞).

    Source: book §12.11.1, eq (12.76).
    """
    w = "unfocused_sar_cross_range_m"
    _pos("range_m", range_m, w)
    _pos("wavelength_m", wavelength_m, w)
    return UNFOCUSED_SAR_COEFFICIENT * jnp.sqrt(jnp.asarray(range_m) * jnp.asarray(wavelength_m))


def focused_sar_cross_range_m(antenna_length_m):
    """Focused strip-map SAR cross-range resolution ``δ_xr = D / 2`` (m), independent of range
    and wavelength.

    Doppler slope 2v²/(Rλ) (12.80) over the dwell T_d gives a Doppler bandwidth 2v²T_d/(Rλ)
    (12.81); the matched filter resolves 1/T_d (12.82); scaling the real-beam footprint
    L_e = v T_d = Rλ/D by their ratio (12.84) gives Rλ/(2 v T_d) = D/2 (12.85).

    Args:
        antenna_length_m: real antenna length D along track (m), in (0, ∞).

    Source: book §12.11.2, eqs (12.77)–(12.85) (the final line of (12.85) is lost in the text
    used here; D/2 follows from the preceding equations); Curlander & McDonough, *Synthetic
    Aperture Radar* (1991), ch. 1 (strip-map azimuth resolution D/2).
    """
    _pos("antenna_length_m", antenna_length_m, "focused_sar_cross_range_m")
    return 0.5 * jnp.asarray(antenna_length_m)


def dbs_isovel_angle_rad(n, velocity_step_m_s, platform_velocity_m_s):
    """Angle of the N-th isovel (isodop) line from the velocity vector
    ``θ_N = arccos(1 − N ΔV / V)`` (rad), book eq (12.67).

    Args:
        n: line index N, in [0, ∞) with N ΔV ≤ 2V.
        velocity_step_m_s: radial-velocity step between lines ΔV (m/s), in (0, ∞).
        platform_velocity_m_s: platform speed V (m/s), in (0, ∞).

    The derivative is infinite at θ = 0 and π (N = 0 and NΔV = 2V); the gradient is finite
    strictly inside.
    """
    w = "dbs_isovel_angle_rad"
    check_range("n", n, 0.0, None, where=w)
    _pos("velocity_step_m_s", velocity_step_m_s, w)
    _pos("platform_velocity_m_s", platform_velocity_m_s, w)
    x = jnp.asarray(n) * jnp.asarray(velocity_step_m_s) / jnp.asarray(platform_velocity_m_s)
    if is_concrete(x):
        check_range("n * velocity_step_m_s / platform_velocity_m_s", x, 0.0, 2.0, where=w)
    return jnp.arccos(1.0 - x)


def dbs_cross_range_m(range_m, wavelength_m, platform_velocity_m_s, observation_time_s, squint_angle_rad):
    """Doppler-beam-sharpened cross-range resolution ``δ_xr = λ R / (2 V T sin θ)`` (m).

    The Doppler 2V cos θ/λ of a ground point at angle θ from the velocity vector changes by
    2V sin θ δθ/λ; resolving δf = 1/T (12.82) gives δθ = λ/(2 V T sin θ) — the spacing of the
    isodop lines of eq (12.67) with ΔV = λ/(2T). Range walk (V T ≲ range bin) limits T (§12.9).

    Args:
        range_m: range R (m), in (0, ∞).
        wavelength_m: wavelength λ (m), in (0, ∞).
        platform_velocity_m_s: platform speed V (m/s), in (0, ∞).
        observation_time_s: coherent observation time T (s), in (0, ∞).
        squint_angle_rad: angle θ between beam and velocity vector (rad), in (0, π); resolution
            is lost (→ ∞) along track (θ → 0, π).

    Source: book §12.9, eq (12.67) and the 10/94 GHz example (83 Hz ↔ 12 ms ↔ 3 m at 250 m/s).
    """
    w = "dbs_cross_range_m"
    _pos("range_m", range_m, w)
    _pos("wavelength_m", wavelength_m, w)
    _pos("platform_velocity_m_s", platform_velocity_m_s, w)
    _pos("observation_time_s", observation_time_s, w)
    check_range("squint_angle_rad", squint_angle_rad, 0.0, math.pi, lo_open=True, hi_open=True, where=w)
    return (jnp.asarray(wavelength_m) * jnp.asarray(range_m)) / (
        2.0 * jnp.asarray(platform_velocity_m_s) * jnp.asarray(observation_time_s) * jnp.sin(jnp.asarray(squint_angle_rad))
    )


# ---------------------------------------------------------------------------------------------
# Scanning
# ---------------------------------------------------------------------------------------------


def hits_per_scan(beamwidth_deg, prf_hz, scan_rate_rpm):
    """Pulses hitting a point target as a fan beam scans past: ``n_b = θ_b f_p / (6 ω_m)``.

    θ_b in degrees, ω_m in rpm (6 ω_m = scan rate in deg/s). A real number (no rounding).

    Args:
        beamwidth_deg: azimuth 3 dB beamwidth θ_b (deg), in (0, 360].
        prf_hz: pulse repetition frequency f_p (Hz), in (0, ∞).
        scan_rate_rpm: antenna rotation rate ω_m (rpm), in (0, ∞).

    Source: book eq (9.26) (Skolnik 1980); §9.9.1.1: 1.25° × 360 Hz / (6 × 6 rpm) = 12.5:

    >>> float(hits_per_scan(1.25, 360.0, 6.0))
    12.5
    """
    w = "hits_per_scan"
    check_range("beamwidth_deg", beamwidth_deg, 0.0, 360.0, lo_open=True, where=w)
    _pos("prf_hz", prf_hz, w)
    _pos("scan_rate_rpm", scan_rate_rpm, w)
    return jnp.asarray(beamwidth_deg) * jnp.asarray(prf_hz) / (6.0 * jnp.asarray(scan_rate_rpm))
