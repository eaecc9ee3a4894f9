"""Underwater ambient noise and hydrophone voltages (diffsense.physics.sea_noise).

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging* ("book"): §12.8 eqs (12.61)–(12.66)
  and Table 12.2 (side-scan sonar noise, worked example 4).
- Mellen (1952) thermal noise −15 + 20 log10 f_kHz and its crossover with Knudsen's −17 dB/decade
  (closed form).
"""

import math

import pytest

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import noise as nz
from diffsense.physics import sea_noise as sn

from helpers.function_suite import function_suite

# Each spec: (name, fn of positional floats, [(lo, hi, log_scale)], [(arg index, bad value)],
#             smooth) — smooth=False for table interpolations (FD skipped at random points).
SPECS = [
    ("sea_noise_1khz", sn.sea_surface_noise_1khz_db, [(0.0, 6.0, 0)], [(0, 6.5)], False),
    ("sea_noise_spectrum", sn.sea_surface_noise_spectrum_level_db, [(0.0, 6.0, 0), (500.0, 2e5, 1)], [(1, 100.0), (0, -1.0)], False),
    ("thermal_sea_noise", sn.thermal_sea_noise_spectrum_level_db, [(1e3, 1e7, 1)], [(0, 10.0)], True),
    ("ambient_sea_noise", sn.ambient_sea_noise_spectrum_level_db, [(0.0, 6.0, 0), (1e3, 2e5, 1)], [(1, 5e5)], False),
    ("band_noise_level", sn.band_noise_level_db, [(-20.0, 120.0, 0), (1.0, 1e6, 1), (1.0, 1e4, 1)], [(2, 0.5), (1, 0.0)], True),
    ("hydrophone_voltage", sn.hydrophone_voltage_v, [(0.0, 250.0, 0), (-220.0, -150.0, 0)], [(1, 10.0)], True),
]
# u = 0.23, 0.61 (the central-difference points): away from the Table 12.2 knots
globals().update(function_suite(SPECS, jit_rel=1e-12, jit_atol=lambda eager: 1e-12 * (abs(eager) > 1e-6),
                                vmap_rtol=1e-12, value_floor=1e-300))


# --------------------------------------------------------------------------------------
# Book numbers
# --------------------------------------------------------------------------------------


def test_side_scan_sea_noise_book_12_8():
    # N_f = 65 − 17 log10 117 = 30 dB (29.84); L_N = 30 + 10 log10(3000) − 10 log10(458.4) = 38 dB
    nf = float(sn.sea_surface_noise_spectrum_level_db(3.0, 117e3))
    assert nf == pytest.approx(30.0, abs=0.2)
    ln = float(sn.band_noise_level_db(nf, 3e3, 458.4))
    assert ln == pytest.approx(38.0, abs=0.05)


def test_side_scan_op_amp_noise_book_12_8():
    # signal: 50 dB re 1 µPa with −180 dB re 1 V/µPa → 320 nV (exactly 316 nV; book rounds)
    sig = float(sn.hydrophone_voltage_v(50.0, -180.0))
    assert sig == pytest.approx(320e-9, rel=0.015)
    # noise floor 38 dB → 79 nV; op amp 1.2 nV/√Hz in 3 kHz → 66 nV; total 102 nV
    floor = float(sn.hydrophone_voltage_v(38.0, -180.0))
    assert floor == pytest.approx(79e-9, rel=0.01)
    amp = float(nz.voltage_noise_rms_v(1.2e-9, 3e3))
    assert amp == pytest.approx(66e-9, rel=0.01)
    total = float(nz.add_uncorrelated_rms(floor, amp))
    # sqrt(79² + 66²) = 102.9 nV, printed 102 nV: tolerance 1.5 %
    assert total == pytest.approx(102e-9, rel=0.015)
    # SNR with the op amp: 20 log10(320/102) = 9.9 dB (book's rounded voltages); with the
    # unrounded 316 nV and 103.1 nV it is 9.73 dB: tolerance 0.2 dB
    assert 20 * math.log10(sig / total) == pytest.approx(9.9, abs=0.2)


def test_sea_noise_table_12_2_levels():
    for ss, level in zip((0.0, 0.5, 1.0, 2.0, 3.0, 6.0), (45, 50, 55, 60, 65, 70)):
        assert float(sn.sea_surface_noise_1khz_db(ss)) == pytest.approx(level, abs=1e-12)
    # −17 dB per decade
    d = float(sn.sea_surface_noise_spectrum_level_db(2.0, 10e3) - sn.sea_surface_noise_spectrum_level_db(2.0, 100e3))
    assert d == pytest.approx(17.0, abs=1e-12)


def test_thermal_sea_noise_and_crossover_mellen():
    # N_therm = −15 + 20 log10 f_kHz: 25 dB at 100 kHz
    assert float(sn.thermal_sea_noise_spectrum_level_db(100e3)) == pytest.approx(25.0, abs=1e-12)
    # sea state 0 (45 dB at 1 kHz) meets thermal noise where 45 − 17 x = −15 + 20 x, x = 60/37;
    # there the power sum is 3.01 dB above either
    f = 1e3 * 10 ** (60 / 37)
    level = 45 - 17 * 60 / 37
    assert float(sn.ambient_sea_noise_spectrum_level_db(0.0, f)) == pytest.approx(level + 10 * math.log10(2), abs=1e-10)
