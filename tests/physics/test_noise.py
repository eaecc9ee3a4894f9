"""Noise models: receiver noise, photodetectors, sea noise, blackbody, radiometers, jamming.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging* ("book"): §9.9.1.3 and §9.9.2
  (air-surveillance radar noise, worked example 2), §8.16.11 (ore-pass radar noise, worked
  example 3), §12.8 eqs (12.61)–(12.66) and Table 12.2 (side-scan sonar noise, worked example
  4), §11.12.4.8 (FMCW seeker noise, worked example 6).
- Closed forms evaluated in mpmath: Stefan–Boltzmann law σT⁴ (CODATA σ), Wien's displacement
  constant b = 2.897771955e-3 m·K (CODATA 2018), Friis transmission formula, McIntyre's
  equivalent form F = M[1 − (1 − k)(M − 1)²/M²], Planck band integrals by mpmath.quad.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import noise as nz
from diffsense.errors import DomainError

from helpers.function_checks import (
    assert_gradient_finite,
    assert_gradient_matches_fd,
    assert_jit_matches_eager,
    assert_out_of_domain_raises,
    assert_vmap_matches_loop,
)
from diffsense.physics.constants import (
    BOLTZMANN_J_K,
    PLANCK_J_S,
    SPEED_OF_LIGHT_M_S,
    STEFAN_BOLTZMANN_W_M2_K4,
)

mp.mp.dps = 30
BOOK_K = 1.38e-23  # the book's rounded Boltzmann constant


def _cascade2(g1, nf1, g2, nf2):
    return nz.cascade_noise_figure_db(jnp.stack([g1, g2]), jnp.stack([nf1, nf2]))


def _cascade2_domain_probe(g1, nf1, g2, nf2):
    return nz.cascade_noise_figure_db(np.array([g1, g2]), np.array([nf1, nf2]))


# Each spec: (name, fn of positional floats, [(lo, hi, log_scale)], [(arg index, bad value)],
#             smooth) — smooth=False for table interpolations (FD skipped at random points).
SPECS = [
    ("thermal_noise_w", nz.thermal_noise_power_w, [(1.0, 1e10, 1), (1.0, 1e4, 1)], [(0, 0.0), (1, -1.0)], True),
    ("thermal_noise_dbw", nz.thermal_noise_power_dbw, [(1.0, 1e10, 1), (1.0, 1e4, 1)], [(0, -5.0)], True),
    ("noise_temperature", nz.noise_temperature_k, [(0.0, 30.0, 0), (50.0, 400.0, 0)], [(0, -1.0), (1, 0.0)], True),
    ("noise_figure", nz.noise_figure_db, [(0.0, 1e5, 0), (50.0, 400.0, 0)], [(0, -1.0)], True),
    ("lossy_line", nz.lossy_line_noise_figure_db, [(0.0, 20.0, 0), (4.0, 400.0, 1)], [(0, -0.5), (1, -1.0)], True),
    ("cascade", _cascade2, [(-10.0, 40.0, 0), (0.0, 15.0, 0), (-10.0, 40.0, 0), (0.0, 15.0, 0)], [], True),
    ("system_temperature", nz.system_noise_temperature_k, [(0.0, 3000.0, 0), (0.0, 10.0, 0), (0.0, 3000.0, 0), (4.0, 400.0, 1)], [(1, -1.0), (0, -3.0)], True),
    ("receiver_noise_dbw", nz.receiver_noise_power_dbw, [(1.0, 1e10, 1), (0.0, 20.0, 0)], [(1, -1.0), (0, 0.0)], True),
    ("shot_variance", nz.shot_noise_variance_a2, [(0.0, 1e-2, 0), (1.0, 1e10, 1)], [(0, -1e-9), (1, 0.0)], True),
    ("johnson_variance", nz.johnson_noise_variance_a2, [(0.0, 1000.0, 0), (1.0, 1e10, 1), (1.0, 1e9, 1)], [(2, 0.0)], True),
    ("johnson_voltage", nz.johnson_noise_voltage_v, [(1.0, 1000.0, 1), (1.0, 1e10, 1), (1.0, 1e9, 1)], [(0, 0.0)], True),
    ("apd_excess", nz.apd_excess_noise_factor, [(1.0, 1e3, 1), (0.0, 1.0, 0)], [(0, 0.5), (1, 1.5)], True),
    ("photodetector_noise", nz.photodetector_noise_current_a, [(0.0, 1e-3, 0), (0.0, 1e-6, 0), (1.0, 1e9, 1), (1.0, 400.0, 1), (1.0, 1e9, 1)], [(4, 0.0), (3, 0.0)], True),
    ("apd_noise", lambda i, idk, b, m, k: nz.photodetector_noise_current_a(i, idk, b, 300.0, 1e4, gain=m, ionization_ratio=k), [(1e-9, 1e-3, 1), (0.0, 1e-6, 0), (1.0, 1e9, 1), (1.0, 300.0, 1), (0.0, 1.0, 0)], [(3, 0.9), (4, -0.1)], True),
    ("nep_from_dstar", nz.nep_from_detectivity_w, [(1e-10, 1e-2, 1), (1.0, 1e9, 1), (1e7, 1e13, 1)], [(2, 0.0)], True),
    ("dstar_from_nep", nz.detectivity_from_nep_jones, [(1e-10, 1e-2, 1), (1.0, 1e9, 1), (1e-15, 1e-6, 1)], [(0, 0.0)], True),
    ("nep_from_current", nz.nep_from_noise_current_w, [(1e-15, 1e-6, 1), (0.01, 100.0, 1)], [(1, 0.0)], True),
    ("sea_noise_1khz", nz.sea_surface_noise_1khz_db, [(0.0, 6.0, 0)], [(0, 6.5)], False),
    ("sea_noise_spectrum", nz.sea_surface_noise_spectrum_level_db, [(0.0, 6.0, 0), (500.0, 2e5, 1)], [(1, 100.0), (0, -1.0)], False),
    ("thermal_sea_noise", nz.thermal_sea_noise_spectrum_level_db, [(1e3, 1e7, 1)], [(0, 10.0)], True),
    ("ambient_sea_noise", nz.ambient_sea_noise_spectrum_level_db, [(0.0, 6.0, 0), (1e3, 2e5, 1)], [(1, 5e5)], False),
    ("band_noise_level", nz.band_noise_level_db, [(-20.0, 120.0, 0), (1.0, 1e6, 1), (1.0, 1e4, 1)], [(2, 0.5), (1, 0.0)], True),
    ("hydrophone_voltage", nz.hydrophone_voltage_v, [(0.0, 250.0, 0), (-220.0, -150.0, 0)], [(1, 10.0)], True),
    ("voltage_noise_rms", nz.voltage_noise_rms_v, [(1e-10, 1e-6, 1), (1.0, 1e8, 1)], [(0, -1e-9)], True),
    ("add_rms", nz.add_uncorrelated_rms, [(1e-9, 1.0, 1), (1e-9, 1.0, 1)], [(0, 0.0)], True),
    ("planck_radiance", nz.planck_spectral_radiance, [(1e-7, 1e-3, 1), (50.0, 6000.0, 1)], [(0, 0.0), (1, 0.0)], True),
    ("planck_exitance", nz.planck_spectral_exitance, [(1e-7, 1e-3, 1), (50.0, 6000.0, 1)], [(1, -5.0)], True),
    ("band_radiance", nz.band_radiance_w_m2_sr, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(2, 0.0), (1, 20.0)], True),
    ("band_exitance", nz.band_exitance_w_m2, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(0, 0.0)], True),
    ("band_fraction", nz.band_fraction, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(2, -1.0)], True),
    ("band_dL_dT", nz.band_radiance_temperature_derivative, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(2, 0.0)], True),
    ("total_power_dT", nz.total_power_radiometer_delta_t_k, [(10.0, 3000.0, 1), (1e6, 1e10, 1), (1e-3, 10.0, 1), (0.0, 1e-2, 0)], [(3, 2.0), (2, 0.0)], True),
    ("dicke_dT", nz.dicke_radiometer_delta_t_k, [(10.0, 3000.0, 1), (1e6, 1e10, 1), (1e-3, 10.0, 1)], [(1, 0.0)], True),
    ("antenna_temperature", lambda a, b, e, l: nz.antenna_temperature_k(a, b, e, radiation_efficiency=l), [(0.0, 400.0, 0), (0.0, 400.0, 0), (0.0, 1.0, 0), (0.5, 1.0, 0)], [(2, 1.1), (3, 0.0)], True),
    ("jammer_density", nz.jammer_noise_density_w_hz, [(1.0, 1e4, 1), (0.0, 20.0, 0), (0.0, 40.0, 0), (1e-3, 1.0, 1), (1e3, 1e6, 1), (1e5, 1e9, 1)], [(4, 0.0), (2, 90.0)], True),
    ("burn_through", lambda pt, g, s, pj, gj, bj, br, sjr: nz.self_screening_burn_through_range_m(pt, g, s, pj, gj, bj, br, sjr), [(1e3, 1e7, 1), (20.0, 45.0, 0), (0.1, 100.0, 1), (1.0, 1e3, 1), (0.0, 20.0, 0), (1e8, 1e9, 1), (1e5, 1e7, 1), (0.0, 20.0, 0)], [(0, 0.0), (6, 2e9)], True),
]
SPEC_IDS = [s[0] for s in SPECS]


@pytest.mark.parametrize("spec", SPECS, ids=SPEC_IDS)
def test_jit_matches_eager(spec):
    assert_jit_matches_eager(spec, rel=1e-12, atol=lambda eager: 1e-12 * (abs(eager) > 1e-6))


@pytest.mark.parametrize("spec", SPECS, ids=SPEC_IDS)
def test_vmap_matches_loop(spec):
    assert_vmap_matches_loop(spec, rtol=1e-12)


@pytest.mark.parametrize("spec", SPECS, ids=SPEC_IDS)
def test_gradient_matches_central_difference(spec):
    assert_gradient_matches_fd(spec, value_floor=1e-300)  # u = 0.23, 0.61: away from the Table 12.2 knots


@pytest.mark.parametrize("spec", SPECS, ids=SPEC_IDS)
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_gradient_finite_over_domain(spec, data):
    assert_gradient_finite(spec, [data.draw(st.floats(0.0, 1.0)) for _ in spec[2]], value_floor=1e-300, smooth=spec[4])


@pytest.mark.parametrize("spec", [s for s in SPECS if s[3]], ids=[s[0] for s in SPECS if s[3]])
def test_out_of_domain_raises(spec):
    assert_out_of_domain_raises(spec)


def test_cascade_out_of_domain_raises():
    with pytest.raises(DomainError):
        _cascade2_domain_probe(20.0, -1.0, 10.0, 3.0)
    with pytest.raises(DomainError):
        _cascade2_domain_probe(200.0, 1.0, 10.0, 3.0)


def test_band_integral_rejects_reversed_band():
    with pytest.raises(DomainError):
        nz.band_radiance_w_m2_sr(10e-6, 8e-6, 300.0)


def test_burn_through_rejects_receiver_wider_than_jammer():
    with pytest.raises(DomainError):
        nz.self_screening_burn_through_range_m(1e6, 30.0, 1.0, 100.0, 10.0, 1e6, 2e6, 10.0)


# --------------------------------------------------------------------------------------
# Book numbers
# --------------------------------------------------------------------------------------


def test_air_surveillance_noise_book_9_9_1_3():
    # N = 10 log10(k T0 β) + NF + L_rec = −149 + 4 + 2 = −143 dBW, β = 306 kHz. The book
    # rounds 10 log10(kTβ) = −149.12 dB to −149 (k = 1.38e-23 or exact: −149.118 either way).
    n = float(nz.receiver_noise_power_dbw(306e3, 4.0, loss_db=2.0))
    assert n == pytest.approx(-143.0, abs=0.15)
    assert float(nz.thermal_noise_power_dbw(306e3)) == pytest.approx(-149.0, abs=0.15)
    # the exact and the book's k differ by 0.002 dB
    book = 10 * math.log10(BOOK_K * 290 * 306e3)
    assert float(nz.thermal_noise_power_dbw(306e3)) - book == pytest.approx(10 * math.log10(BOLTZMANN_J_K / BOOK_K), abs=1e-12)
    assert abs(10 * math.log10(BOLTZMANN_J_K / BOOK_K)) < 0.0021


def test_rgcalc_bandwidth_penalty_book_9_9_2():
    # βτ = 1 instead of 0.613 (τ = 2 µs) "adds 2.1 dB to the noise floor"; 0.613/2 µs = 306 kHz
    d = float(nz.thermal_noise_power_dbw(1 / 2e-6) - nz.thermal_noise_power_dbw(0.613 / 2e-6))
    assert d == pytest.approx(2.1, abs=0.03)


def test_ore_pass_noise_book_8_16_11():
    # 10 log10(kTβ) = −127 dBW at 50 MHz; Pn = −127 + 13.7 + 30 = −83.2 dBm (printed; the sum
    # of its rounded terms is −83.3, the unrounded value −83.29): tolerance 0.1 dB.
    assert float(nz.thermal_noise_power_dbw(50e6)) == pytest.approx(-127.0, abs=0.02)
    pn_dbm = float(nz.receiver_noise_power_dbw(50e6, 13.7)) + 30.0
    assert pn_dbm == pytest.approx(-83.2, abs=0.1)
    # SNR at 300 m: −59.6 − Pn = 23.6 dB (book), same tolerance
    assert -59.6 - pn_dbm == pytest.approx(23.6, abs=0.1)


def test_fmcw_seeker_noise_book_11_12_4_8():
    # bin 1.3 × 5 MHz / 2048 ≈ 3 kHz, NF 15 dB → −154 dBW (unrounded −153.96)
    n = float(nz.receiver_noise_power_dbw(1.3 * 5e6 / 2048, 15.0))
    assert n == pytest.approx(-154.0, abs=0.05)


def test_side_scan_sea_noise_book_12_8():
    # N_f = 65 − 17 log10 117 = 30 dB (29.84); L_N = 30 + 10 log10(3000) − 10 log10(458.4) = 38 dB
    nf = float(nz.sea_surface_noise_spectrum_level_db(3.0, 117e3))
    assert nf == pytest.approx(30.0, abs=0.2)
    ln = float(nz.band_noise_level_db(nf, 3e3, 458.4))
    assert ln == pytest.approx(38.0, abs=0.05)


def test_side_scan_op_amp_noise_book_12_8():
    # signal: 50 dB re 1 µPa with −180 dB re 1 V/µPa → 320 nV (exactly 316 nV; book rounds)
    sig = float(nz.hydrophone_voltage_v(50.0, -180.0))
    assert sig == pytest.approx(320e-9, rel=0.015)
    # noise floor 38 dB → 79 nV; op amp 1.2 nV/√Hz in 3 kHz → 66 nV; total 102 nV
    floor = float(nz.hydrophone_voltage_v(38.0, -180.0))
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
        assert float(nz.sea_surface_noise_1khz_db(ss)) == pytest.approx(level, abs=1e-12)
    # −17 dB per decade
    d = float(nz.sea_surface_noise_spectrum_level_db(2.0, 10e3) - nz.sea_surface_noise_spectrum_level_db(2.0, 100e3))
    assert d == pytest.approx(17.0, abs=1e-12)


def test_thermal_sea_noise_and_crossover_mellen():
    # N_therm = −15 + 20 log10 f_kHz: 25 dB at 100 kHz
    assert float(nz.thermal_sea_noise_spectrum_level_db(100e3)) == pytest.approx(25.0, abs=1e-12)
    # sea state 0 (45 dB at 1 kHz) meets thermal noise where 45 − 17 x = −15 + 20 x, x = 60/37;
    # there the power sum is 3.01 dB above either
    f = 1e3 * 10 ** (60 / 37)
    level = 45 - 17 * 60 / 37
    assert float(nz.ambient_sea_noise_spectrum_level_db(0.0, f)) == pytest.approx(level + 10 * math.log10(2), abs=1e-10)


# --------------------------------------------------------------------------------------
# Receiver noise closed forms
# --------------------------------------------------------------------------------------


def test_noise_figure_temperature_round_trip():
    # 3 dB ↔ 290 (10^0.3 − 1) = 288.6 K
    t = float(nz.noise_temperature_k(3.0))
    assert t == pytest.approx(float(290 * (mp.power(10, mp.mpf("0.3")) - 1)), rel=1e-13)
    assert float(nz.noise_figure_db(t)) == pytest.approx(3.0, abs=1e-13)


def test_friis_cascade_closed_form():
    # LNA (G 20 dB, NF 1 dB) then mixer (NF 10 dB): F = 10^0.1 + (10 − 1)/100
    f = mp.power(10, mp.mpf("0.1")) + (10 - 1) / mp.mpf(100)
    assert float(nz.cascade_noise_figure_db([20.0, -6.0], [1.0, 10.0])) == pytest.approx(float(10 * mp.log10(f)), abs=1e-12)
    # a matched loss L at T0 ahead of a receiver adds L dB: 2 dB line + 4 dB receiver = 6 dB
    # (how the book folds the receive line into the noise figure, §9.9.1.3)
    assert float(nz.cascade_noise_figure_db([-2.0, 30.0], [2.0, 4.0])) == pytest.approx(6.0, abs=1e-12)
    assert float(nz.lossy_line_noise_figure_db(2.0)) == pytest.approx(2.0, abs=1e-12)


def test_system_temperature_matches_cascade():
    # T_sys − T_a = T0 (F_cascade − 1) for a line at T0 followed by the receiver
    t_rx = float(nz.noise_temperature_k(4.0))
    t_sys = float(nz.system_noise_temperature_k(0.0, 2.0, t_rx))
    f_db = float(nz.cascade_noise_figure_db([-2.0, 30.0], [2.0, 4.0]))
    assert t_sys == pytest.approx(290 * (10 ** (f_db / 10) - 1), rel=1e-12)
    # cold line: T_p(L − 1) with T_p = 20 K
    assert float(nz.system_noise_temperature_k(50.0, 3.0, 100.0, 20.0)) == pytest.approx(
        float(50 + 20 * (mp.power(10, mp.mpf("0.3")) - 1) + mp.power(10, mp.mpf("0.3")) * 100), rel=1e-13
    )


# --------------------------------------------------------------------------------------
# Photodetector noise
# --------------------------------------------------------------------------------------


def test_shot_and_johnson_noise_textbook_values():
    # 1 mA of shot noise: sqrt(2 q I) = 17.9 pA/√Hz; 1 kΩ at 300 K: 4.07 nV/√Hz
    assert math.sqrt(float(nz.shot_noise_variance_a2(1e-3, 1.0))) == pytest.approx(17.9e-12, rel=2e-3)
    assert float(nz.johnson_noise_voltage_v(300.0, 1.0, 1e3)) == pytest.approx(4.07e-9, rel=2e-3)
    # current and voltage forms agree: ⟨i²⟩ R² = ⟨v²⟩
    v2 = float(nz.johnson_noise_voltage_v(290.0, 1e6, 50.0)) ** 2
    assert float(nz.johnson_noise_variance_a2(290.0, 1e6, 50.0)) * 50.0**2 == pytest.approx(v2, rel=1e-13)


def test_apd_excess_noise_mcintyre_equivalent_form():
    for m, k in ((1.0, 0.3), (10.0, 0.02), (100.0, 0.5), (50.0, 1.0), (30.0, 0.0)):
        alt = mp.mpf(m) * (1 - (1 - mp.mpf(k)) * ((m - 1) / mp.mpf(m)) ** 2)
        assert float(nz.apd_excess_noise_factor(m, k)) == pytest.approx(float(alt), rel=1e-13)
    assert float(nz.apd_excess_noise_factor(40.0, 1.0)) == pytest.approx(40.0, rel=1e-14)  # F = M
    assert float(nz.apd_excess_noise_factor(40.0, 0.0)) == pytest.approx(2 - 1 / 40, rel=1e-14)


def test_photodetector_total_noise_closed_form():
    q, k = mp.mpf("1.602176634e-19"), mp.mpf("1.380649e-23")
    i_s, i_d, b, t, r, m, kk = 1e-7, 1e-9, 1e6, 300.0, 1e4, 50.0, 0.02
    f = kk * m + (1 - kk) * (2 - 1 / mp.mpf(m))
    var = 2 * q * (mp.mpf(i_s) + mp.mpf(i_d)) * m**2 * f * b + 4 * k * t * b / r
    got = float(nz.photodetector_noise_current_a(i_s, i_d, b, t, r, gain=m, ionization_ratio=kk))
    assert got == pytest.approx(float(mp.sqrt(var)), rel=1e-13)
    # PIN (M = 1): shot plus Johnson only
    pin = float(nz.photodetector_noise_current_a(i_s, i_d, b, t, r))
    assert pin**2 == pytest.approx(float(2 * q * (i_s + i_d) * b + 4 * k * t * b / r), rel=1e-13)


def test_nep_detectivity_conversions_book_eq_9_8():
    # NEP = sqrt(A_d Δf)/D*, A_d in cm²: 1 mm² (0.01 cm²), 10 kHz, D* = 1e10 Jones → 1e-9 W
    assert float(nz.nep_from_detectivity_w(1e-6, 1e4, 1e10)) == pytest.approx(1e-9, rel=1e-14)
    assert float(nz.detectivity_from_nep_jones(1e-6, 1e4, 1e-9)) == pytest.approx(1e10, rel=1e-14)
    assert float(nz.nep_from_noise_current_w(1e-9, 0.5)) == pytest.approx(2e-9, rel=1e-14)


# --------------------------------------------------------------------------------------
# Blackbody
# --------------------------------------------------------------------------------------


def _mp_planck_band(l1, l2, t, deriv=False):
    h, c, k = mp.mpf(PLANCK_J_S), mp.mpf(SPEED_OF_LIGHT_M_S), mp.mpf(BOLTZMANN_J_K)

    def f(lam):
        x = h * c / (lam * k * t)
        rad = 2 * h * c**2 / lam**5 / mp.expm1(x)
        return rad * x * mp.exp(x) / (mp.expm1(x) * t) if deriv else rad

    # split at the radiance peak region for mpmath's tanh-sinh
    pts = sorted({mp.mpf(l1), mp.mpf(l2)} | {p for p in (mp.mpf("2.9e-3") / t * s for s in (0.5, 1, 2, 5)) if l1 < p < l2})
    return mp.quad(f, pts)


def test_planck_spectral_radiance_closed_form_and_wien_peak():
    h, c, k = mp.mpf(PLANCK_J_S), mp.mpf(SPEED_OF_LIGHT_M_S), mp.mpf(BOLTZMANN_J_K)
    lam, t = mp.mpf("10e-6"), mp.mpf(300)
    ref = 2 * h * c**2 / lam**5 / mp.expm1(h * c / (lam * k * t))
    assert float(nz.planck_spectral_radiance(10e-6, 300.0)) == pytest.approx(float(ref), rel=1e-13)
    assert float(nz.planck_spectral_exitance(10e-6, 300.0)) == pytest.approx(float(mp.pi * ref), rel=1e-13)
    # Wien: dL_λ/dλ = 0 at λ = b/T, b = 2.897771955e-3 m K (CODATA 2018)
    for temp in (300.0, 1000.0, 5800.0):
        lam_max = 2.897771955e-3 / temp
        slope = float(jax.grad(nz.planck_spectral_radiance)(lam_max, temp))
        scale = float(nz.planck_spectral_radiance(lam_max, temp)) / lam_max
        assert abs(slope) < 1e-8 * scale


def test_total_exitance_stefan_boltzmann():
    # 10 nm – 1 m at 300 K holds all but ~1e-14 of σT⁴
    for t in (300.0,):
        m = float(nz.band_exitance_w_m2(1e-8, 1.0, t))
        assert m == pytest.approx(STEFAN_BOLTZMANN_W_M2_K4 * t**4, rel=1e-9)  # σ quoted to 10 digits
    # 10 nm – 10 m at 5800 K (ratio 1e9: 10 panels)
    m = float(nz.band_exitance_w_m2(1e-8, 10.0, 5800.0, n_panels=10))
    assert m == pytest.approx(STEFAN_BOLTZMANN_W_M2_K4 * 5800.0**4, rel=1e-9)


@pytest.mark.parametrize(
    "l1,l2,t",
    [(8e-6, 12e-6, 300.0), (3e-6, 5e-6, 300.0), (0.4e-6, 0.7e-6, 5800.0), (0.2e-6, 1e-3, 200.0), (1e-6, 2e-6, 6000.0), (0.3e-6, 1e-3, 1000.0)],
)
def test_band_radiance_and_derivative_vs_mpmath(l1, l2, t):
    ref = _mp_planck_band(l1, l2, t)
    assert float(nz.band_radiance_w_m2_sr(l1, l2, t)) == pytest.approx(float(ref), rel=1e-12)
    frac = ref * mp.pi / (mp.mpf(STEFAN_BOLTZMANN_W_M2_K4) * mp.mpf(t) ** 4)
    assert float(nz.band_fraction(l1, l2, t)) == pytest.approx(float(frac), rel=1e-9)  # σ to 10 digits
    dref = _mp_planck_band(l1, l2, t, deriv=True)
    assert float(nz.band_radiance_temperature_derivative(l1, l2, t)) == pytest.approx(float(dref), rel=1e-12)
    # and the autodiff derivative of the band radiance agrees
    g = float(jax.grad(nz.band_radiance_w_m2_sr, argnums=2)(l1, l2, t))
    assert g == pytest.approx(float(dref), rel=1e-11)


def test_band_fraction_wien_quarter():
    # F(0 → λT = b) = 0.25005 (from 15/π⁴ ∫_{x_b}^∞ x³/(e^x − 1) dx, x_b = hc/(k b) = 4.965)
    xb = mp.mpf(PLANCK_J_S) * mp.mpf(SPEED_OF_LIGHT_M_S) / (mp.mpf(BOLTZMANN_J_K) * mp.mpf("2.897771955e-3"))
    ref = 15 / mp.pi**4 * mp.quad(lambda x: x**3 / mp.expm1(x), [xb, 20, 60, mp.inf])
    got = float(nz.band_fraction(1e-9, 2.897771955e-3 / 1000.0, 1000.0))
    assert got == pytest.approx(float(ref), rel=1e-12)
    assert got == pytest.approx(0.25005, abs=1e-5)


# --------------------------------------------------------------------------------------
# Radiometers, jamming
# --------------------------------------------------------------------------------------


def test_radiometer_sensitivity_closed_forms():
    # T_sys 500 K, β 100 MHz, τ 1 s: total power 0.05 K; Dicke 0.1 K; with ΔG/G = 1e-4:
    # 500 sqrt(1e-8 + 1e-8) = 0.0707 K
    assert float(nz.total_power_radiometer_delta_t_k(500.0, 1e8, 1.0)) == pytest.approx(0.05, rel=1e-13)
    assert float(nz.dicke_radiometer_delta_t_k(500.0, 1e8, 1.0)) == pytest.approx(0.1, rel=1e-13)
    assert float(nz.total_power_radiometer_delta_t_k(500.0, 1e8, 1.0, 1e-4)) == pytest.approx(500 * math.sqrt(2e-8), rel=1e-13)


def test_antenna_temperature_closed_form():
    # η_M 0.9, T_ML 250 K, T_SL 100 K, η_l 0.95 at 290 K: 0.95 (225 + 10) + 0.05·290
    got = float(nz.antenna_temperature_k(250.0, 100.0, 0.9, radiation_efficiency=0.95, physical_temperature_k=290.0))
    assert got == pytest.approx(0.95 * 235.0 + 0.05 * 290.0, rel=1e-14)


def test_jammer_density_matches_friis_transmission():
    # N_j β_j is the power received over a one-way link: P_j G_j G_r (λ/4πR)²
    pj, gj, gr, lam, r, bj = 100.0, 10.0, 30.0, 0.03, 50e3, 500e6
    friis = mp.mpf(pj) * mp.power(10, mp.mpf(gj + gr) / 10) * (mp.mpf(lam) / (4 * mp.pi * r)) ** 2
    nj = float(nz.jammer_noise_density_w_hz(pj, gj, gr, lam, r, bj))
    assert nj * bj == pytest.approx(float(friis), rel=1e-13)


def test_burn_through_range_balances_echo_and_jamming():
    pt, g_db, sigma, pj, gj_db, bj, br, sjr_db, lam = 1e6, 35.0, 5.0, 100.0, 10.0, 500e6, 1e6, 13.0, 0.03
    r = float(nz.self_screening_burn_through_range_m(pt, g_db, sigma, pj, gj_db, bj, br, sjr_db))
    g = 10 ** (g_db / 10)
    echo = pt * g * g * lam**2 * sigma / ((4 * math.pi) ** 3 * r**4)
    jam = float(nz.jammer_noise_density_w_hz(pj, gj_db, g_db, lam, r, bj)) * br
    assert 10 * math.log10(echo / jam) == pytest.approx(sjr_db, abs=1e-10)
