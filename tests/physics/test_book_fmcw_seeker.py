"""Worked example 6: the book's FMCW seeker (Brimstone-like), §11.12.4.

Book (Brooker, *Introduction to Sensors for Ranging and Imaging*, §11.12.4.2–11.12.4.8):
- swept bandwidth 300 MHz → δR = c/(2Δf) = 0.5 m;
- 1 km operational range, 500 µs up-sweep → f_b = (Δf/T)(2R/c) = 4 MHz;
- sampling 2.5 × 4 MHz = 10 MHz (Nyquist 8 MHz);
- 4096-point FFT → 2048 range gates; 1 km at 0.5 m needs 2000 gates;
- FFT bin widened by the window: 1.3 × 5 MHz / 2048 ≈ 3 kHz;
- noise floor 10 log10(k T β) + NF with NF = 15 dB → −154 dBW.
The book uses c = 3e8 m/s and k = 1.38e-23 J/K; the code uses the exact k (0.002 dB apart).
"""

import math

import pytest

import diffsense  # noqa: F401
from diffsense.physics import noise as nz
from diffsense.physics import waveforms as wf
from diffsense.physics.constants import BOLTZMANN_J_K

BOOK_C = 3e8
BOOK_K = 1.38e-23
SWEEP_HZ = 300e6
SWEEP_S = 500e-6
RANGE_M = 1000.0


def test_seeker_range_resolution_300_mhz_is_half_metre():
    assert float(wf.fmcw_range_resolution_m(SWEEP_HZ, BOOK_C)) == pytest.approx(0.5, rel=1e-15)
    # 1 km at 0.5 m needs 2000 gates; 2048 gates from a 4096-point FFT cover it
    n_gates = RANGE_M / float(wf.fmcw_range_resolution_m(SWEEP_HZ, BOOK_C))
    assert n_gates == pytest.approx(2000.0, rel=1e-15)
    assert n_gates <= 4096 / 2


def test_seeker_beat_frequency_at_1_km_is_4_mhz():
    fb = float(wf.fmcw_beat_frequency_hz(RANGE_M, SWEEP_HZ, SWEEP_S, BOOK_C))
    assert fb == pytest.approx(4e6, rel=1e-15)
    # and back: 4 MHz -> 1 km
    assert float(wf.fmcw_range_from_beat_m(4e6, SWEEP_HZ, SWEEP_S, BOOK_C)) == pytest.approx(RANGE_M, rel=1e-15)


def test_seeker_sample_rate_10_mhz():
    fb = wf.fmcw_beat_frequency_hz(RANGE_M, SWEEP_HZ, SWEEP_S, BOOK_C)
    assert float(wf.fmcw_sample_rate_hz(fb, 2.0)) == pytest.approx(8e6, rel=1e-15)  # Nyquist
    assert float(wf.fmcw_sample_rate_hz(fb)) == pytest.approx(10e6, rel=1e-15)  # book's 2.5x


def test_seeker_fft_bin_about_3_khz_and_half_metre_bins():
    fs = float(wf.fmcw_sample_rate_hz(wf.fmcw_beat_frequency_hz(RANGE_M, SWEEP_HZ, SWEEP_S, BOOK_C)))
    # 1.3 x 5 MHz / 2048 = 1.3 x 10 MHz / 4096 = 3173.8 Hz, "≈ 3 kHz" in the book (1 figure)
    bin_hz = float(wf.fft_bin_width_hz(fs, 4096.0, 1.3))
    assert bin_hz == pytest.approx(1.3 * 5e6 / 2048, rel=1e-15)
    assert bin_hz == pytest.approx(3e3, rel=0.06)
    # eq (11.24) with the spectral resolution δf_b = 1/T_b gives eq (11.25): δR = c/(2Δf) = 0.5 m
    rng_bin = float(wf.fmcw_range_from_beat_m(1.0 / SWEEP_S, SWEEP_HZ, SWEEP_S, BOOK_C))
    assert rng_bin == pytest.approx(0.5, rel=1e-15)


def test_seeker_noise_floor_minus_154_dbw():
    fs = float(wf.fmcw_sample_rate_hz(wf.fmcw_beat_frequency_hz(RANGE_M, SWEEP_HZ, SWEEP_S, BOOK_C)))
    beta = float(wf.fft_bin_width_hz(fs, 4096.0, 1.3))
    n_dbw = float(nz.receiver_noise_power_dbw(beta, 15.0))
    # book: -154 dBW (rounded to 1 dB); exact k gives -153.96 dBW
    assert n_dbw == pytest.approx(-154.0, abs=0.5)
    book = 10 * math.log10(BOOK_K * 290.0 * beta) + 15.0
    assert n_dbw == pytest.approx(book, abs=0.0025)  # exact vs rounded Boltzmann constant
    assert n_dbw - book == pytest.approx(10 * math.log10(BOLTZMANN_J_K / BOOK_K), abs=1e-12)
