"""Clutter models: surface area, reflectivity, volume clutter, wall clutter, reverberation.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging* ("book"): §9.9.3 rain clutter of
  the air-surveillance radar (worked example 2), §8.16.4–8.16.6 ore-pass target and wall
  clutter (worked example 3), §12.7–12.8 side-scan bottom echo (worked example 4), §8.14.2
  dust backscatter (worked_examples §8), Table 12.2 (sea state ↔ wind), §14.9 (sea state 5
  wave height).
- WMO Beaufort table, wind speed bands at 10 m (m/s): 0.3–1.5, 1.6–3.3, 3.4–5.4, 5.5–7.9,
  8.0–10.7, 10.8–13.8, 13.9–17.1, 17.2–20.7, 20.8–24.4, 24.5–28.4, 28.5–32.6, ≥32.7.
- Closed forms evaluated independently with mpmath.
"""

import math

import jax
import mpmath as mp
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import clutter as cl
from diffsense.errors import DomainError

from helpers.function_suite import function_suite

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)

# --------------------------------------------------------------------------------------
# Transformation checks shared by every function: jit, vmap, gradient vs central
# differences, finite gradients over the documented domain, DomainError outside it.
# Each spec: (name, fn of positional floats, [(lo, hi, log_scale)], [(arg index, bad value)],
#             smooth) — smooth=False for piecewise-linear table interpolations (FD skipped at
#             random points, where a knot may lie inside the stencil).
# --------------------------------------------------------------------------------------

SPECS = [
    ("beam_limited_area", cl.beam_limited_area_m2, [(10, 1e5, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (0.01, 1.5, 0)], [(0, -1.0), (3, 0.0), (1, 4.0)], True),
    ("beam_limited_area_elliptical", lambda r, a, e, g: cl.beam_limited_area_m2(r, a, e, g, elliptical=True), [(10, 1e5, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (0.01, 1.5, 0)], [(3, 2.0)], True),
    ("pulse_limited_area", cl.pulse_limited_area_m2, [(10, 1e5, 1), (1e-3, 0.5, 1), (1e-8, 1e-4, 1), (0.0, 1.5, 0)], [(2, 0.0), (3, math.pi / 2)], True),
    ("surface_clutter_area", cl.surface_clutter_area_m2, [(10, 1e5, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (1e-8, 1e-4, 1), (0.01, 1.5, 0)], [(4, 0.0), (4, math.pi / 2), (3, -1e-6)], True),
    ("surface_clutter_rcs", cl.surface_clutter_rcs_m2, [(1e-4, 1.0, 1), (1.0, 1e6, 1)], [(0, -0.1)], True),
    ("constant_gamma_sigma0", cl.constant_gamma_sigma0, [(-40.0, 0.0, 0), (0.0, 1.57, 0)], [(0, 30.0), (1, 2.0)], True),
    ("sea_clutter_gamma", cl.sea_clutter_gamma_db, [(0.0, 12.0, 0), (1e-3, 1.0, 1)], [(0, 13.0), (1, 2.0)], True),
    ("sea_state_wind", cl.sea_state_wind_speed_knots, [(0.0, 6.0, 0)], [(0, 7.0), (0, -0.1)], False),
    ("beaufort_from_wind", cl.beaufort_from_wind_speed, [(0.1, 40.0, 1)], [(0, 0.0), (0, 41.0)], True),
    ("beaufort_from_sea_state", cl.beaufort_from_sea_state, [(0.05, 6.0, 0)], [(0, 0.0)], False),
    ("k_squared", cl.dielectric_factor_k_squared, [(1.0, 80.0, 1), (0.0, 40.0, 0)], [(0, 0.5), (1, -1.0)], True),
    ("rain_z", cl.rain_reflectivity_factor_mm6_m3, [(0.1, 200.0, 1), (100.0, 500.0, 0), (1.0, 2.0, 0)], [(0, 0.0), (2, -1.0)], True),
    ("volume_reflectivity", cl.volume_reflectivity_m2_m3, [(1.0, 1e6, 1), (3e-3, 1.0, 1), (0.1, 1.0, 0)], [(1, 1e-4), (2, 0.0)], True),
    ("rain_eta", cl.rain_volume_reflectivity_m2_m3, [(0.1, 200.0, 1), (3e-3, 1.0, 1)], [(0, -1.0)], True),
    ("dust_eta", cl.dust_volume_reflectivity_m2_m3, [(3e-3, 1.0, 1), (1.0, 1e4, 1), (0.1, 1.0, 0)], [(1, 0.0), (2, 1.5)], True),
    ("resolution_volume", cl.resolution_volume_m3, [(10, 1e5, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (1e-8, 1e-4, 1)], [(3, 0.0), (0, 0.0)], True),
    ("volume_clutter_rcs", cl.volume_clutter_rcs_m2, [(1e-10, 1e-5, 1), (10, 1e5, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (1e-8, 1e-4, 1)], [(0, -1e-7)], True),
    ("cylinder_wall_area", cl.cylinder_wall_area_m2, [(0.1, 100.0, 1), (0.01, 100.0, 1)], [(0, 0.0), (1, -2.0)], True),
    ("signal_to_clutter", cl.signal_to_clutter_db, [(1e-3, 1e3, 1), (1e-3, 1e3, 1)], [(1, 0.0)], True),
    ("clutter_limited_range", cl.volume_clutter_limited_range_m, [(1e-2, 1e2, 1), (0.0, 30.0, 0), (1e-10, 1e-5, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (1e-8, 1e-4, 1)], [(2, 0.0), (1, 200.0)], True),
    ("lambert", cl.lambert_scattering_strength_db, [(0.01, 1.57, 0), (-40.0, -10.0, 0)], [(0, 0.0), (1, 5.0)], True),
    ("chapman_harris", cl.chapman_harris_surface_scattering_strength_db, [(0.02, 1.04, 0), (1.0, 30.0, 0), (400.0, 6400.0, 1)], [(2, 10e3), (1, 0.0), (0, 1.2)], True),
    ("reverberation_area", cl.reverberation_area_m2, [(10, 1e4, 1), (1e-3, 0.5, 1), (1e-5, 0.1, 1)], [(2, 0.0)], True),
    ("reverberation_volume", cl.reverberation_volume_m3, [(10, 1e4, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (1e-5, 0.1, 1)], [(0, -5.0)], True),
    ("reverberation_level", cl.reverberation_level_db, [(150, 240, 0), (0, 120, 0), (-90, -10, 0), (1.0, 1e6, 1)], [(3, 0.0), (2, 10.0)], True),
    ("surface_reverberation_level", cl.surface_reverberation_level_db, [(150, 240, 0), (0, 120, 0), (-90, -10, 0), (10, 1e4, 1), (1e-3, 0.5, 1), (1e-5, 0.1, 1)], [(1, -1.0)], True),
    ("volume_reverberation_level", cl.volume_reverberation_level_db, [(150, 240, 0), (0, 120, 0), (-90, -10, 0), (10, 1e4, 1), (1e-3, 0.5, 1), (1e-3, 0.5, 1), (1e-5, 0.1, 1)], [(4, 0.0)], True),
    ("reflectivity_ts", cl.reflectivity_target_strength_db, [(-60.0, 10.0, 0), (1e-3, 1e4, 1)], [(1, 0.0), (0, 50.0)], True),
]
# u = 0.23, 0.61 (the central-difference points): away from the Table 12.2 knots
globals().update(function_suite(SPECS, jit_rel=1e-13, jit_atol=1e-12, vmap_rtol=1e-12, value_floor=1.0))


# --------------------------------------------------------------------------------------
# Worked example 2 (book §9.9.3): rain clutter of the L-band air-surveillance radar
# --------------------------------------------------------------------------------------


def test_rain_clutter_rcs_air_surveillance_book_9_9_3():
    # σ_clut = η π R² θaz θel cτ /(8·1.33²) = 1.86e-8 R²  (= −77.3 + 20 log10 R dBsm).
    # The book uses c = 3e8; with exact c the coefficient is 1.8635e-8 (0.07 % lower). The
    # book prints 3 significant figures: tolerance 0.3 %.
    for r in (1e3, 1e4, 1e5):
        sigma = float(cl.volume_clutter_rcs_m2(1e-7, r, 0.02, 0.07, 2e-6, beam_shape_factor=1.33))
        assert sigma / r**2 == pytest.approx(1.86e-8, rel=3e-3)
        assert 10 * math.log10(sigma) == pytest.approx(-77.3 + 20 * math.log10(r), abs=0.01)
    book_c = float(cl.volume_clutter_rcs_m2(1e-7, 1.0, 0.02, 0.07, 2e-6, speed_m_s=3e8))
    exact = mp.pi * 0.02 * 0.07 * 3e8 * 2e-6 / (8 * mp.mpf(1.33) ** 2) * mp.mpf("1e-7")
    assert book_c == pytest.approx(float(exact), rel=1e-14)


def test_rain_clutter_limited_range_book_9_9_3():
    # −77.3 + 20 log10 R = σ_tar − 15.2 with σ_tar = 0 dBsm → R = 1274 m. The book rounds the
    # clutter coefficient to −77.3 dB (exact −77.297 dB with c = 299 792 458 m/s, giving
    # 1273.0 m): tolerance 0.15 %.
    r = float(cl.volume_clutter_limited_range_m(1.0, 15.2, 1e-7, 0.02, 0.07, 2e-6))
    assert r == pytest.approx(1274.0, rel=1.5e-3)
    # at that range the signal-to-clutter ratio is exactly the requirement
    sigma_c = cl.volume_clutter_rcs_m2(1e-7, r, 0.02, 0.07, 2e-6)
    assert float(cl.signal_to_clutter_db(1.0, sigma_c)) == pytest.approx(15.2, abs=1e-12)


def test_rain_reflectivity_marshall_palmer_closed_form():
    # Z = 200 R^1.6; η = π⁵ 0.93 Z·1e-18 / λ⁴ (book eq 8.37), evaluated in mpmath.
    for rate, lam in ((1.0, 0.1), (25.0, 0.03), (50.0, 0.23)):
        z = mp.mpf(200) * mp.mpf(rate) ** mp.mpf("1.6")
        eta = mp.pi**5 * mp.mpf("0.93") * z * mp.mpf("1e-18") / mp.mpf(lam) ** 4
        assert float(cl.rain_reflectivity_factor_mm6_m3(rate)) == pytest.approx(float(z), rel=1e-13)
        assert float(cl.rain_volume_reflectivity_m2_m3(rate, lam)) == pytest.approx(float(eta), rel=1e-13)
    # 10 log10 Z = 23 dBZ at 1 mm/h (Marshall–Palmer)
    assert 10 * math.log10(float(cl.rain_reflectivity_factor_mm6_m3(1.0))) == pytest.approx(23.01, abs=0.01)


# --------------------------------------------------------------------------------------
# Worked example 3 (book §8.16): ore-pass wall clutter and target
# --------------------------------------------------------------------------------------


def test_ore_pass_wall_clutter_scr_book_8_16_6():
    area = float(cl.cylinder_wall_area_m2(6.0, 2.0))
    assert area == pytest.approx(37.7, abs=0.05)  # book: 37.7 m²
    assert 10 * math.log10(area) == pytest.approx(15.8, abs=0.05)  # 15.8 dBm²
    sigma_clut = float(cl.surface_clutter_rcs_m2(10 ** (-10 / 10), area))
    assert 10 * math.log10(sigma_clut) == pytest.approx(5.8, abs=0.05)  # 5.8 dBm²
    sigma_tar = float(cl.surface_clutter_rcs_m2(10 ** (-3 / 10), math.pi * 6.0**2 / 4))
    assert 10 * math.log10(sigma_tar) == pytest.approx(11.5, abs=0.05)  # 14.5 − 3 = 11.5 dBm²
    # book: SCR = 11.5 − 5.8 = 5.7 dB from rounded terms; unrounded 5.75 dB
    assert float(cl.signal_to_clutter_db(sigma_tar, sigma_clut)) == pytest.approx(5.7, abs=0.06)


def test_rock_and_water_dielectric_factor_book_8_16_4():
    # |(ε−1)/(ε+2)|²: rock 5.23 → 0.34, water 8.45 → 0.51; ratio 1.5 (1.8 dB).
    rock = float(cl.dielectric_factor_k_squared(5.23))
    water = float(cl.dielectric_factor_k_squared(8.45))
    assert rock == pytest.approx(0.34, abs=0.005)
    assert water == pytest.approx(0.51, abs=0.005)
    assert water / rock == pytest.approx(1.5, abs=0.02)
    # the book converts its rounded ratio 1.5 (1.76 dB); unrounded 0.508/0.342 is 1.72 dB
    assert 10 * math.log10(water / rock) == pytest.approx(1.8, abs=0.1)
    # complex permittivity: compare with mpmath
    eps = mp.mpc(8.45, -15.45)
    assert float(cl.dielectric_factor_k_squared(8.45, 15.45)) == pytest.approx(float(abs((eps - 1) / (eps + 2)) ** 2), rel=1e-13)


def test_dust_backscatter_constant_book_8_14_2():
    # eq (8.44): Z = 2.25e-9/V^1.07 · ΣP_iD_i⁶/ΣP_ir_i³ with ΣPr³ = 4e-14 m³, ΣPD⁶ = 2e-24 m⁶,
    # so η λ⁴ V^1.07 / (π⁵|K|²) must equal 2.25e-9 · 2e-24/4e-14 = 1.125e-19 (eq 8.45).
    lam, vis, k2 = 3e8 / 35e9, 20.0, 0.34
    eta = float(cl.dust_volume_reflectivity_m2_m3(lam, vis, k2))
    assert eta * lam**4 * vis**1.07 / (math.pi**5 * k2) == pytest.approx(2.25e-9 * 2e-24 / 4e-14, rel=1e-13)
    # and the same η from the general Rayleigh form with Z in mm⁶/m³
    z_mm6 = 1.125e-19 / vis**1.07 * 1e18
    assert float(cl.volume_reflectivity_m2_m3(z_mm6, lam, k2)) == pytest.approx(eta, rel=1e-13)


# --------------------------------------------------------------------------------------
# Surface clutter area and reflectivity models
# --------------------------------------------------------------------------------------


def test_beam_and_pulse_limited_areas_closed_form():
    r, az, el, tau, psi = mp.mpf(5000), mp.mpf("0.02"), mp.mpf("0.05"), mp.mpf("1e-6"), mp.mpf("0.1")
    beam = r * az * r * el / mp.sin(psi)
    pulse = r * az * (mp.mpf(299792458) * tau / 2) / mp.cos(psi)
    assert float(cl.beam_limited_area_m2(5000.0, 0.02, 0.05, 0.1)) == pytest.approx(float(beam), rel=1e-13)
    assert float(cl.beam_limited_area_m2(5000.0, 0.02, 0.05, 0.1, elliptical=True)) == pytest.approx(float(beam * mp.pi / 4), rel=1e-13)
    assert float(cl.pulse_limited_area_m2(5000.0, 0.02, 1e-6, 0.1)) == pytest.approx(float(pulse), rel=1e-13)


@settings(max_examples=30, deadline=None)
@given(
    r=st.floats(10.0, 1e5),
    psi=st.floats(0.001, 1.56),
    tau=st.floats(1e-9, 1e-4),
)
def test_smooth_minimum_area_bounds(r, psi, tau):
    # The smooth minimum never exceeds the exact minimum and is within a factor 2^(-1/p).
    exact = float(cl.surface_clutter_area_m2(r, 0.02, 0.05, tau, psi, sharpness=None))
    smooth = float(cl.surface_clutter_area_m2(r, 0.02, 0.05, tau, psi, sharpness=16.0))
    assert smooth <= exact * (1 + 1e-13)
    assert smooth >= exact * 2.0 ** (-1 / 16) * (1 - 1e-13)


def test_smooth_minimum_area_error_at_crossover():
    # Equal areas: R θel / sin ψ = cτ/2 / cos ψ → tan ψ = 2 R θel /(cτ); there A = min·2^(-1/p).
    r, el, tau = 2000.0, 0.05, 1e-6
    psi = math.atan(2 * r * el / (299792458.0 * tau))
    exact = float(cl.surface_clutter_area_m2(r, 0.02, el, tau, psi, sharpness=None))
    for p in (4.0, 16.0, 64.0):
        smooth = float(cl.surface_clutter_area_m2(r, 0.02, el, tau, psi, sharpness=p))
        assert 10 * math.log10(smooth / exact) == pytest.approx(-10 * math.log10(2) / p, abs=1e-9)


def test_surface_clutter_area_picks_limiting_case():
    # far from the crossover the cell is pulse-limited at low grazing, beam-limited near vertical
    low = float(cl.surface_clutter_area_m2(1e4, 0.02, 0.05, 1e-7, 0.01))
    assert low == pytest.approx(float(cl.pulse_limited_area_m2(1e4, 0.02, 1e-7, 0.01)), rel=1e-12)
    high = float(cl.surface_clutter_area_m2(100.0, 0.02, 0.01, 1e-5, 1.4))
    assert high == pytest.approx(float(cl.beam_limited_area_m2(100.0, 0.02, 0.01, 1.4)), rel=1e-12)


def test_constant_gamma_closed_form():
    # σ° = γ sin ψ: γ = −15 dB at 30° → 10^-1.5 · 0.5
    assert float(cl.constant_gamma_sigma0(-15.0, math.pi / 6)) == pytest.approx(10**-1.5 * 0.5, rel=1e-14)


def test_sea_clutter_gamma_barton_book_eq_8_29():
    # 10 log γ = 6 K_B − 10 log λ − 64: K_B = 4 at X band (λ = 0.03 m) → 24 + 15.229 − 64
    assert float(cl.sea_clutter_gamma_db(4.0, 0.03)) == pytest.approx(24 + 10 * math.log10(1 / 0.03) - 64, abs=1e-12)
    # each Beaufort step adds 6 dB; a tenfold wavelength removes 10 dB
    assert float(cl.sea_clutter_gamma_db(5.0, 0.03) - cl.sea_clutter_gamma_db(4.0, 0.03)) == pytest.approx(6.0, abs=1e-12)
    assert float(cl.sea_clutter_gamma_db(4.0, 0.3) - cl.sea_clutter_gamma_db(4.0, 0.03)) == pytest.approx(-10.0, abs=1e-12)


def test_beaufort_from_wind_speed_matches_wmo_bands():
    # WMO Beaufort table, wind speed at 10 m in m/s for forces 1..12. Every speed inside a
    # band must round to that force, both band edges included.
    bands_m_s = [(0.3, 1.5), (1.6, 3.3), (3.4, 5.4), (5.5, 7.9), (8.0, 10.7), (10.8, 13.8),
                 (13.9, 17.1), (17.2, 20.7), (20.8, 24.4), (24.5, 28.4), (28.5, 32.6), (32.7, 40.0)]
    for force, (lo, hi) in enumerate(bands_m_s, start=1):
        for v in (lo, 0.5 * (lo + hi), hi if force < 12 else lo):
            assert round(float(cl.beaufort_from_wind_speed(v))) == force, (force, v)


def test_sea_state_table_12_2_wind_speeds():
    for ss, kn in zip((0.5, 1, 2, 3, 6), (2, 5, 10, 15, 35)):
        assert float(cl.sea_state_wind_speed_knots(float(ss))) == pytest.approx(kn, abs=1e-12)
    # sea state 3: 15 kn = 7.72 m/s → Beaufort 4 (11–16 kn)
    assert round(float(cl.beaufort_from_sea_state(3.0))) == 4


def test_sea_state_5_wave_height_book_14_9():
    # book §14.9: sea state 5, "very rough, wave height 2.4 to 3.6 m"
    lo, hi = cl.sea_state_wave_height_range_m(5)
    assert lo == pytest.approx(2.4, abs=0.05)
    assert hi == pytest.approx(3.6, abs=0.07)
    with pytest.raises(DomainError):
        cl.sea_state_wave_height_range_m(9)


def test_smooth_area_sharpness_rejected_below_one():
    with pytest.raises(DomainError):
        cl.surface_clutter_area_m2(1e3, 0.02, 0.05, 1e-6, 0.1, sharpness=0.5)


# --------------------------------------------------------------------------------------
# Sonar backscatter and reverberation
# --------------------------------------------------------------------------------------


def test_side_scan_bottom_target_strength_book_12_60():
    # TS = 10 log10(δR R θaz / 4π) + S_b with S_b = −20 dB, δR = 0.25 m, θaz = 0.0262 rad
    # → 10 log10 R − 52.8 dB (book eq 12.60)
    for r in (10.0, 500.0):
        ts = float(cl.reflectivity_target_strength_db(-20.0, 0.25 * 0.0262 * r))
        assert ts - 10 * math.log10(r) == pytest.approx(-52.8, abs=0.05)
    # pulse compression to δR = 0.05 m lowers it by 10 log10(0.25/0.05) = 6.99 dB (book: 7)
    d = float(cl.reflectivity_target_strength_db(-20.0, 0.25 * 0.0262) - cl.reflectivity_target_strength_db(-20.0, 0.05 * 0.0262))
    assert d == pytest.approx(7.0, abs=0.02)


def test_lambert_mackenzie_closed_form():
    # μ = −27 dB (Mackenzie 1961): S = −27 at normal incidence, −27 + 20 log10(0.5) at 30°
    assert float(cl.lambert_scattering_strength_db(math.pi / 2)) == pytest.approx(-27.0, abs=1e-12)
    assert float(cl.lambert_scattering_strength_db(math.pi / 6)) == pytest.approx(-27.0 + 20 * math.log10(0.5), abs=1e-12)


def test_chapman_harris_closed_forms():
    # At θ = 30° the angular term vanishes: S = −42.4 log10 β + 2.6, β = 158 (v f^(1/3))^(-0.58)
    v, f = 15.0, 1000.0
    beta = mp.mpf(158) * (mp.mpf(v) * mp.mpf(f) ** (mp.mpf(1) / 3)) ** mp.mpf("-0.58")
    s30 = float(cl.chapman_harris_surface_scattering_strength_db(math.radians(30.0), v, f))
    assert s30 == pytest.approx(float(-42.4 * mp.log10(beta) + 2.6), abs=1e-10)
    # slope in log10 θ is 3.3 β: d S / d ln θ = 3.3 β / ln 10
    g = float(jax.grad(cl.chapman_harris_surface_scattering_strength_db)(math.radians(10.0), v, f))
    assert g * math.radians(10.0) == pytest.approx(float(3.3 * beta / mp.log(10)), rel=1e-10)
    # stronger wind → stronger scattering at low grazing
    s_calm = float(cl.chapman_harris_surface_scattering_strength_db(math.radians(10.0), 5.0, f))
    s_wind = float(cl.chapman_harris_surface_scattering_strength_db(math.radians(10.0), 25.0, f))
    assert s_wind > s_calm


def test_reverberation_levels_closed_form():
    # RL = SL − 2 TL + S + 10 log10 A, A = (cτ/2) R θ: SL 220, TL 60, S −30, R 1000 m,
    # τ 1 ms, θ 0.1 rad, c 1500 → A = 75 m²
    area = mp.mpf(1500) * mp.mpf("1e-3") / 2 * 1000 * mp.mpf("0.1")
    rl = 220 - 120 - 30 + 10 * mp.log10(area)
    assert float(cl.surface_reverberation_level_db(220.0, 60.0, -30.0, 1000.0, 0.1, 1e-3)) == pytest.approx(float(rl), abs=1e-11)
    # volume (book eq 8.48): V = (cτ/2) π R² θaz θel / 4
    vol = mp.mpf(1500) * mp.mpf("1e-3") / 2 * mp.pi * mp.mpf(1000) ** 2 * mp.mpf("0.1") * mp.mpf("0.2") / 4
    rlv = 220 - 120 - 80 + 10 * mp.log10(vol)
    assert float(cl.volume_reverberation_level_db(220.0, 60.0, -80.0, 1000.0, 0.1, 0.2, 1e-3)) == pytest.approx(float(rlv), abs=1e-11)
