"""Waveform relations against the book's numbers, exact physics and numerical experiments.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging* ("book"): §8.16.14 (ore-pass PRF
  500 kHz and update rate 31.25 kHz), §9.9.1.1 eq (9.26) (hits per scan 12.5), §12.7 eqs
  (12.37)–(12.41) (side-scan sonar: 0.05 m chirp resolution, 13.1 m cross-range, PRF 1.52 Hz,
  duty cycle 0.05 %, 32.9 ms pulse), §12.9 (Doppler beam sharpening: 83 Hz, 12 ms, 3 m at
  10 GHz; ≈800 Hz, 1.2 ms, 0.3 m at 94 GHz), §12.11 eqs (12.69)–(12.85) (SAR), §14.2.3.1 eqs
  (14.2)–(14.3) (blind speeds), eq (10.7) (Doppler).
- Exact relations evaluated independently: the two-way Doppler ratio (c + v)/(c − v) from
  eq (10.7) applied twice; the zeros of a single-delay-line MTI canceller |1 − e^{−j2πf_d/f_p}|;
  the half-power point of the SAR pattern sinc² (12.69) solved with mpmath; the exact geometric
  range curvature √(R² + (L/2)²) − R; a numerically dechirped triangular FMCW signal; the
  autocorrelation of a sampled linear-FM pulse.
"""

import math

import mpmath as mp
import numpy as np
import pytest

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import waveforms as wf
from diffsense.errors import DomainError
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S

from helpers.function_suite import function_suite

BOOK_C = 3e8  # the book rounds c to 3e8 m/s
SEA_C = 1522.0  # the book's sound speed for the side-scan sonar (§12.7)


def _tri_sum(r, v, df, t, lam):
    up, down = wf.fmcw_triangular_beat_frequencies_hz(r, v, df, t, lam)
    return up + 2.0 * down


def _inv_sum(up, down, df, t, lam):
    r, v = wf.fmcw_range_velocity_from_beats(up, down, df, t, lam)
    return r + 3.0 * v


# (name, fn, [(lo, hi, log)], [(arg index, bad value)])
SPECS = [
    ("res_bw", wf.range_resolution_bandwidth_m, [(1e3, 1e10, 1), (1e2, 1e9, 1)], [(0, 0.0), (1, -1.0)]),
    ("res_pulse", wf.range_resolution_pulse_m, [(1e-9, 1e-2, 1), (1e2, 1e9, 1)], [(0, 0.0)]),
    ("unamb_range", wf.unambiguous_range_m, [(1.0, 1e6, 1), (1e2, 1e9, 1)], [(0, -1.0)]),
    ("max_prf", wf.max_prf_hz, [(1.0, 1e6, 1), (1e2, 1e9, 1)], [(0, 0.0)]),
    ("duty", wf.duty_cycle, [(1.0, 1e4, 1), (1e-9, 1e-5, 1)], [(0, 0.0), (1, 2.0)]),
    ("update_rate", wf.update_rate_hz, [(1.0, 1e6, 1), (1.0, 1e3, 1)], [(1, 0.5)]),
    ("pc_gain_db", wf.pulse_compression_gain_db, [(1e3, 1e9, 1), (1e-7, 1e-2, 1)], [(0, 0.0)]),
    ("pc_gain", wf.pulse_compression_gain, [(1e3, 1e9, 1), (1e-7, 1e-2, 1)], [(1, -1e-6)]),
    ("doppler", wf.doppler_shift_hz, [(-1e3, 1e3, 0), (1e-3, 10.0, 1)], [(1, 0.0), (0, float("nan"))]),
    ("vel_from_doppler", wf.radial_velocity_from_doppler_m_s, [(-1e5, 1e5, 0), (1e-3, 10.0, 1)], [(1, -1.0)]),
    ("doppler_res", wf.doppler_resolution_hz, [(1e-4, 10.0, 1)], [(0, 0.0)]),
    ("unamb_vel", wf.unambiguous_velocity_m_s, [(1.0, 1e5, 1), (1e-3, 10.0, 1)], [(0, 0.0)]),
    ("blind_speed", wf.blind_speed_m_s, [(1e-6, 10.0, 0), (1e-3, 10.0, 1), (1.0, 1e5, 1)], [(0, -1.0), (2, 0.0)]),
    ("fmcw_beat", wf.fmcw_beat_frequency_hz, [(1e-6, 1e5, 0), (1e6, 1e10, 1), (1e-6, 1e-1, 1), (1e2, 1e9, 1)], [(0, -1.0), (2, 0.0)]),
    ("fmcw_tri", _tri_sum, [(1e-6, 1e4, 0), (-300.0, 300.0, 0), (1e6, 1e9, 1), (1e-5, 1e-2, 1), (1e-3, 1.0, 1)], [(0, -1.0), (4, 0.0)]),
    ("fmcw_range", wf.fmcw_range_from_beat_m, [(1e-6, 1e8, 0), (1e6, 1e10, 1), (1e-6, 1e-1, 1), (1e2, 1e9, 1)], [(0, -1.0)]),
    ("fmcw_inverse", _inv_sum, [(1e-6, 1e6, 0), (1e-6, 1e6, 0), (1e6, 1e9, 1), (1e-5, 1e-2, 1), (1e-3, 1.0, 1)], [(0, -3e6), (3, 0.0)]),
    ("fmcw_res", wf.fmcw_range_resolution_m, [(1e3, 1e10, 1)], [(0, 0.0)]),
    ("fft_bin", wf.fft_bin_width_hz, [(1e3, 1e9, 1), (16.0, 65536.0, 1), (1.0, 2.0, 0)], [(2, 0.9), (1, 0.5)]),
    ("fmcw_fs", wf.fmcw_sample_rate_hz, [(1e3, 1e9, 1), (2.0, 5.0, 0)], [(1, 1.5), (0, 0.0)]),
    ("real_xr", wf.real_aperture_cross_range_m, [(1.0, 1e6, 1), (1e-4, 1.0, 1)], [(1, 4.0), (0, 0.0)]),
    ("usar_L", wf.unfocused_sar_max_aperture_m, [(1.0, 1e6, 1), (1e-3, 1.0, 1)], [(0, 0.0)]),
    ("usar_xr", wf.unfocused_sar_cross_range_m, [(1.0, 1e6, 1), (1e-3, 1.0, 1)], [(1, 0.0)]),
    ("fsar_xr", wf.focused_sar_cross_range_m, [(0.01, 20.0, 1)], [(0, 0.0)]),
    ("isovel", wf.dbs_isovel_angle_rad, [(0.1, 10.0, 0), (0.1, 1.0, 1), (100.0, 300.0, 0)], [(0, -1.0), (1, 100.0)]),
    ("dbs_xr", wf.dbs_cross_range_m, [(1e2, 1e5, 1), (1e-3, 0.1, 1), (10.0, 300.0, 1), (1e-3, 1.0, 1), (0.05, 3.09, 0)], [(4, 0.0), (4, 3.2)]),
    ("hits", wf.hits_per_scan, [(0.1, 10.0, 1), (10.0, 1e4, 1), (1.0, 60.0, 1)], [(0, 0.0), (0, 400.0)]),
]
globals().update(function_suite(SPECS, jit_rel=1e-13, jit_atol=1e-300, vmap_rtol=1e-13, broadcast=True,
                                value_floor=1e-300))


# --------------------------------------------------------------------------------------------
# Book numbers
# --------------------------------------------------------------------------------------------


def test_ore_pass_prf_and_update_rate_book_8_16_14():
    # "For a maximum unambiguous range of 300 m ... maximum PRF of c/2Rmax = 500 kHz. With 16
    # pulses integrated, the update rate ... is reduced to 31.25 kHz." (c = 3e8: exact)
    prf = float(wf.max_prf_hz(300.0, BOOK_C))
    assert prf == pytest.approx(500e3, rel=1e-15)
    assert float(wf.update_rate_hz(prf, 16.0)) == pytest.approx(31.25e3, rel=1e-15)
    assert float(wf.unambiguous_range_m(prf, BOOK_C)) == pytest.approx(300.0, rel=1e-15)


def test_hits_per_scan_book_9_9_1_1():
    # n_b = 1.25 x 360 / (6 x 6) = 12.5 (the book then uses 10)
    assert float(wf.hits_per_scan(1.25, 360.0, 6.0)) == pytest.approx(12.5, rel=1e-15)


def test_side_scan_sonar_waveform_book_12_37_to_12_41():
    # chirp 111-126 kHz: dR = 1522 / (2 x 15e3) = 0.05 m (book prints 2 decimals; exact 0.0507)
    assert float(wf.range_resolution_bandwidth_m(15e3, SEA_C)) == pytest.approx(0.05, abs=0.001)
    # cross-range at 500 m for 1.5 deg: 500 x 1.5/57.3 = 13.1 m (exact radians 13.09)
    assert float(wf.real_aperture_cross_range_m(500.0, math.radians(1.5))) == pytest.approx(13.1, abs=0.015)
    # PRF for 500 m: 1522 / 1000 = 1.52 Hz (book rounds 1.522)
    prf = float(wf.max_prf_hz(500.0, SEA_C))
    assert prf == pytest.approx(1.52, abs=0.0025)
    # duty cycle 100 x 1.52 x 333e-6 = 0.05 % (book, 1 significant figure; exact 0.0506 %)
    assert 100.0 * float(wf.duty_cycle(1.52, 333e-6)) == pytest.approx(0.05, abs=0.001)
    # 5 % duty at 1.52 Hz allows tau = 5 / (100 x 1.52) = 32.9 ms: duty(1.52, 32.9 ms) = 5 %
    assert 100.0 * float(wf.duty_cycle(1.52, 32.9e-3)) == pytest.approx(5.0, abs=0.01)
    # "about 100 times longer than the 333 us" uncompressed pulse: resolutions c tau/2 compare so
    ratio = float(wf.range_resolution_pulse_m(32.9e-3, SEA_C) / wf.range_resolution_pulse_m(333e-6, SEA_C))
    assert ratio == pytest.approx(100.0, rel=0.02)


def test_doppler_beam_sharpening_numbers_book_12_9():
    # 83 Hz isodop spacing at 10 GHz needs t = 1/83 = 12 ms; at 250 m/s the radar moves 3 m.
    # At 94 GHz the spacing scales by 94/10 (book "800 Hz", exact 83 x 9.4 = 780 Hz), the time
    # to 1.2 ms (exact 1.28 ms) and the motion to 0.3 m (exact 0.32 m) — the book rounds.
    t10 = 1.0 / 83.0
    assert float(wf.doppler_resolution_hz(t10)) == pytest.approx(83.0, rel=1e-15)
    assert t10 == pytest.approx(12e-3, abs=0.5e-3)
    assert 250.0 * t10 == pytest.approx(3.0, abs=0.05)
    lam10 = BOOK_C / 10e9
    lam94 = BOOK_C / 94e9
    dv = 83.0 * lam10 / 2.0  # the isovel step behind the 83 Hz (inverse of eq 10.7)
    assert float(wf.radial_velocity_from_doppler_m_s(83.0, lam10)) == pytest.approx(dv, rel=1e-15)
    f94 = float(wf.doppler_shift_hz(dv, lam94))
    assert f94 == pytest.approx(800.0, rel=0.03)
    assert 1.0 / f94 == pytest.approx(1.2e-3, rel=0.07)
    assert 250.0 / f94 == pytest.approx(0.3, rel=0.07)


# --------------------------------------------------------------------------------------------
# Exact relations and numerical experiments
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("v", [-340.0, -30.0, 25.0, 300.0, 3000.0])
def test_doppler_matches_exact_two_way_shift_eq_10_7(v):
    # Eq (10.7) twice (target receives, then re-radiates): f2 = f (c + v)/(c - v); the first-order
    # shift 2v/lambda differs by the factor c/(c - v): relative error v/c.
    mp.mp.dps = 40
    f = mp.mpf(10e9)
    c = mp.mpf(SPEED_OF_LIGHT_M_S)
    exact = f * ((c + v) / (c - v) - 1)
    approx = float(wf.doppler_shift_hz(v, float(c / f)))
    assert approx == pytest.approx(float(exact), rel=1.01 * abs(v) / float(c))
    assert approx == pytest.approx(float(exact * (c - v) / c), rel=1e-14)


@pytest.mark.parametrize("n", [1, 2, 3, 7])
def test_blind_speeds_are_nulls_of_the_mti_canceller_eq_14_3(n):
    # A single delay-line canceller has |H(f_d)| = |1 - exp(-j 2 pi f_d / f_p)| (book §14.2.3):
    # zero at the blind speeds, maximum 2 halfway between them.
    lam, prf = 0.23, 360.0
    v = float(wf.blind_speed_m_s(n, lam, prf))
    fd = 2.0 * v / lam
    assert abs(1.0 - np.exp(-2j * np.pi * fd / prf)) < 1e-12
    fd_mid = 2.0 * (v - 0.5 * float(wf.blind_speed_m_s(1, lam, prf))) / lam
    assert abs(1.0 - np.exp(-2j * np.pi * fd_mid / prf)) == pytest.approx(2.0, abs=1e-12)


def test_unambiguous_velocity_is_half_a_turn_per_pulse():
    # Pulse-to-pulse Doppler phase 2 pi f_d / f_p reaches pi at v_u: a slightly faster target
    # aliases to a negative velocity; the unambiguous span equals the first blind speed.
    lam, prf = 0.03, 2000.0
    vu = float(wf.unambiguous_velocity_m_s(prf, lam))
    for eps, sign in ((-1e-6, 1.0), (1e-6, -1.0)):
        phase = np.angle(np.exp(1j * 2 * np.pi * (2 * vu * (1 + eps) / lam) / prf))
        assert np.sign(phase) == sign and abs(abs(phase) - np.pi) < 1e-4
    assert 2 * vu == pytest.approx(float(wf.blind_speed_m_s(1.0, lam, prf)), rel=1e-15)


def test_triangular_fmcw_matches_dechirped_signal():
    # Dechirp numerically: transmit phase phi(t) = 2 pi (f0 t +- k t^2 / 2); the echo from a target
    # closing at v from R0 is delayed by tau(t) = 2 (R0 - v t)/c; the beat frequency is the time
    # derivative of phi(t) - phi(t - tau(t)), taken here by a central difference mid-sweep.
    c = BOOK_C
    f0, df, tb, r0, v = 24e9, 150e6, 1e-3, 120.0, 25.0
    k = df / tb

    def phase(t, sign):
        return 2 * np.pi * (f0 * t + sign * 0.5 * k * t * t)

    def beat(sign, t, h=1e-7):
        def diff(tt):
            tau = 2 * (r0 - v * tt) / c
            return phase(tt, sign) - phase(tt - tau, sign)

        return (diff(t + h) - diff(t - h)) / (2 * h) / (2 * np.pi)

    # evaluate at t ~ 0 so the range has not changed: R(t) = r0
    up, down = wf.fmcw_triangular_beat_frequencies_hz(r0, v, df, tb, c / f0, c)
    assert float(up) == pytest.approx(beat(+1.0, 0.0), rel=2e-4)
    assert float(down) == pytest.approx(-beat(-1.0, 0.0), rel=2e-4)
    r_back, v_back = wf.fmcw_range_velocity_from_beats(beat(+1.0, 0.0), -beat(-1.0, 0.0), df, tb, c / f0, c)
    assert float(r_back) == pytest.approx(r0, rel=1e-4)
    assert float(v_back) == pytest.approx(v, rel=1e-4)


def test_pulse_compression_ratio_from_lfm_autocorrelation():
    # The compressed linear-FM pulse has its first null near 1/B (exactly where
    # B t (1 - t/tau) = 1), so tau / t_null -> B tau. Sonar chirp of the book: 15 kHz x 32.9 ms.
    b, tau = 15e3, 32.9e-3
    fs = 16 * b
    t = np.arange(int(round(tau * fs))) / fs
    s = np.exp(1j * np.pi * (b / tau) * (t - tau / 2) ** 2)
    n = len(s)
    spec = np.fft.fft(s, 2 * n)
    acf = np.abs(np.fft.ifft(spec * np.conj(spec)))[: n] ** 2  # power: quadratic at a null
    first_null = np.argmax(np.diff(acf) > 0)  # first local minimum after the peak
    # refine by parabola through the three samples around the minimum
    y0, y1, y2 = acf[first_null - 1 : first_null + 2]
    t_null = (first_null + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)) / fs
    gain = float(wf.pulse_compression_gain(b, tau))
    assert gain == pytest.approx(tau / t_null, rel=0.01)
    t_exact = (tau - math.sqrt(tau * tau - 4 * tau / b)) / 2
    assert t_null == pytest.approx(t_exact, rel=0.01)
    assert float(wf.pulse_compression_gain_db(b, tau)) == pytest.approx(10 * math.log10(b * tau), abs=1e-12)


def test_range_resolution_pulse_equals_bandwidth_form_for_matched_pulse():
    # book §11.7.2: c/(2 delta f) is the compressed equivalent of c tau / 2 with tau = 1/delta f
    for bw in (1e3, 3e8, 1e9):
        assert float(wf.range_resolution_pulse_m(1.0 / bw)) == pytest.approx(float(wf.range_resolution_bandwidth_m(bw)), rel=1e-15)


def test_unfocused_sar_coefficient_from_sinc_half_power_eq_12_76():
    # G_SAR = sinc^2(x), x = 2 pi L sin(theta)/lambda (12.69); half power at x_h. With
    # L = sqrt(R lambda / 2) (12.72) the resolution R sin(theta) = x_h sqrt(2)/(2 pi) sqrt(R lambda).
    mp.mp.dps = 30
    xh = mp.findroot(lambda x: (mp.sin(x) / x) ** 2 - mp.mpf(1) / 2, 1.39)
    coef = float(xh * mp.sqrt(2) / (2 * mp.pi))
    assert coef == pytest.approx(0.31321, abs=1e-5)
    r, lam = 5e3, 0.03
    got = float(wf.unfocused_sar_cross_range_m(r, lam))
    assert got / math.sqrt(r * lam) == pytest.approx(coef, rel=1e-3)  # the book's 0.313 rounds
    assert wf.UNFOCUSED_SAR_COEFFICIENT == pytest.approx(coef, abs=5e-4)


@pytest.mark.parametrize("r, lam", [(1e3, 0.03), (2e4, 0.0032), (5e5, 0.24)])
def test_unfocused_sar_aperture_limits_two_way_curvature_to_lambda_over_8_eq_12_71(r, lam):
    # exact geometry: the two-way path difference between the aperture centre and its end
    # 2 (sqrt(R^2 + (L/2)^2) - R) equals lambda/8 to relative order (L/R)^2
    lmax = float(wf.unfocused_sar_max_aperture_m(r, lam))
    excess = 2 * (math.hypot(r, lmax / 2) - r)
    assert excess == pytest.approx(lam / 8, rel=(lmax / r) ** 2)


@pytest.mark.parametrize("d, r, lam, v", [(1.0, 1e4, 0.03, 100.0), (10.0, 8e5, 0.056, 7500.0), (0.3, 2e3, 0.0032, 30.0)])
def test_focused_sar_resolution_from_doppler_history_eqs_12_80_to_12_85(d, r, lam, v):
    # Chain of the book's steps: footprint L_e = R lambda / D, dwell T_d = L_e / v, Doppler
    # bandwidth 2 v^2 T_d/(R lambda) (12.81), resolution 1/T_d (12.82), dxr = L_e df/Df (12.84).
    le = r * lam / d
    td = le / v
    dfd = 2 * v * v * td / (r * lam)
    assert float(wf.focused_sar_cross_range_m(d)) == pytest.approx(le * (1 / td) / dfd, rel=1e-13)


@pytest.mark.parametrize("theta_deg", [20.0, 45.0, 90.0, 135.0])
def test_dbs_resolution_matches_isovel_spacing_eq_12_67(theta_deg):
    # Isovel lines theta_N = arccos(1 - N dV / V) (12.67) with dV = lambda/(2T) (a 1/T Doppler
    # cell): R times the local line spacing equals lambda R/(2 V T sin theta).
    lam, v, t, r = 0.0032, 250.0, 0.05, 2e3
    dv = lam / (2 * t)
    theta = math.radians(theta_deg)
    n = (1 - math.cos(theta)) * v / dv
    spacing = 0.5 * (math.acos(1 - (n + 1) * dv / v) - math.acos(1 - (n - 1) * dv / v))
    assert float(wf.dbs_cross_range_m(r, lam, v, t, theta)) == pytest.approx(r * spacing, rel=1e-6)
    assert float(wf.dbs_isovel_angle_rad(n, dv, v)) == pytest.approx(theta, rel=1e-12)


def test_duty_cycle_above_one_rejected():
    with pytest.raises(DomainError):
        wf.duty_cycle(1e4, 2e-4)


def test_isovel_beyond_backward_direction_rejected():
    with pytest.raises(DomainError):
        wf.dbs_isovel_angle_rad(10.0, 50.0, 200.0)  # N dV / V = 2.5 > 2


def test_fmcw_inverse_rejects_negative_range():
    with pytest.raises(DomainError):
        wf.fmcw_range_velocity_from_beats(-2e6, 1e6, 1e8, 1e-3, 0.01)
