"""Receiver noise (diffsense.physics.noise): receiver noise, photodetectors, voltage noise,
radiometers, jamming.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging* ("book"): §9.9.1.3 and §9.9.2
  (air-surveillance radar noise, worked example 2), §8.16.11 (ore-pass radar noise, worked
  example 3), §11.12.4.8 (FMCW seeker noise, worked example 6). The side-scan sonar noise of
  §12.8 is in test_sea_noise.py, blackbody radiation in test_radiance.py.
- Closed forms evaluated in mpmath: Friis transmission formula, McIntyre's equivalent form
  F = M[1 − (1 − k)(M − 1)²/M²].
"""

import math

import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import noise as nz
from diffsense.errors import DomainError

from helpers.function_suite import function_suite
from diffsense.physics.constants import BOLTZMANN_J_K

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)
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
    ("voltage_noise_rms", nz.voltage_noise_rms_v, [(1e-10, 1e-6, 1), (1.0, 1e8, 1)], [(0, -1e-9)], True),
    ("add_rms", nz.add_uncorrelated_rms, [(1e-9, 1.0, 1), (1e-9, 1.0, 1)], [(0, 0.0)], True),
    ("total_power_dT", nz.total_power_radiometer_delta_t_k, [(10.0, 3000.0, 1), (1e6, 1e10, 1), (1e-3, 10.0, 1), (0.0, 1e-2, 0)], [(3, 2.0), (2, 0.0)], True),
    ("dicke_dT", nz.dicke_radiometer_delta_t_k, [(10.0, 3000.0, 1), (1e6, 1e10, 1), (1e-3, 10.0, 1)], [(1, 0.0)], True),
    ("antenna_temperature", lambda a, b, e, l: nz.antenna_temperature_k(a, b, e, radiation_efficiency=l), [(0.0, 400.0, 0), (0.0, 400.0, 0), (0.0, 1.0, 0), (0.5, 1.0, 0)], [(2, 1.1), (3, 0.0)], True),
    ("jammer_density", nz.jammer_noise_density_w_hz, [(1.0, 1e4, 1), (0.0, 20.0, 0), (0.0, 40.0, 0), (1e-3, 1.0, 1), (1e3, 1e6, 1), (1e5, 1e9, 1)], [(4, 0.0), (2, 90.0)], True),
    ("burn_through", lambda pt, g, s, pj, gj, bj, br, sjr: nz.self_screening_burn_through_range_m(pt, g, s, pj, gj, bj, br, sjr), [(1e3, 1e7, 1), (20.0, 45.0, 0), (0.1, 100.0, 1), (1.0, 1e3, 1), (0.0, 20.0, 0), (1e8, 1e9, 1), (1e5, 1e7, 1), (0.0, 20.0, 0)], [(0, 0.0), (6, 2e9)], True),
]
globals().update(function_suite(SPECS, jit_rel=1e-12, jit_atol=lambda eager: 1e-12 * (abs(eager) > 1e-6),
                                vmap_rtol=1e-12, value_floor=1e-300))


def test_cascade_out_of_domain_raises():
    with pytest.raises(DomainError):
        _cascade2_domain_probe(20.0, -1.0, 10.0, 3.0)
    with pytest.raises(DomainError):
        _cascade2_domain_probe(200.0, 1.0, 10.0, 3.0)


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
