"""Radiometer physics (diffsense.sensors.radiometer): brightness temperatures, beam, sensitivity, detection.

References used by the assertions:
- Closed forms evaluated in mpmath (30 digits): Planck brightness (hf/k)/(e^{hf/kT} − 1) and
  its high-temperature series T − hf/2k + (hf/k)²/(12 T); radiative transfer through an
  isothermal layer; the Gaussian beam integral ∫ exp(−4 ln2 ψ²/θ²) 2πψ dψ (mpmath.quad);
  the unbalanced Dicke sensitivity (Ulaby, Moore & Fung 1981 Vol. I ch. 6); the normal
  distribution (mpmath.ncdf / erfinv) for the Gaussian-shift detector (Van Trees 1968 §2.2).
- Brooker §8.16.9 (worked example 3, ore-pass radar): 250 mm antenna, aperture efficiency 0.7,
  94 GHz (λ = 3.19 mm): G = 4πρA/λ² = 42,432 and θ3dB = 0.89° (70 λ/d rule).
- Radiometer equation examples, rfessentials.com "How does integration time improve the
  sensitivity of a radiometer?" (2026): total power, T_sys = 500 K, B = 100 MHz, τ = 1 s →
  0.05 K; T_sys = 300 K, B = 500 MHz, τ = 10 ms → 0.134 K; a Dicke radiometer has K = 2.
- Kraus, *Radio Astronomy* (1986): Gaussian beam solid angle 1.133 θ².
"""

import math

import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.physics import noise
from diffsense.physics.radiance import planck_brightness_temperature_k
from diffsense.sensors import radiometer as rm
from diffsense.errors import DomainError
from diffsense.physics.constants import BOLTZMANN_J_K, PLANCK_J_S

from helpers.function_suite import function_suite

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)
HF_K = mp.mpf(PLANCK_J_S) / mp.mpf(BOLTZMANN_J_K)


def mp_planck(t, f):
    x = HF_K * mp.mpf(f) / mp.mpf(t)
    return HF_K * mp.mpf(f) / mp.expm1(x)


# (name, fn, [(lo, hi, log)], [(arg index, bad value)])
SPECS = [
    ("opacity", rm.opacity_from_attenuation_db, [(0.0, 100.0, 0)], [(0, -1.0)]),
    ("planck_brightness", planck_brightness_temperature_k, [(1.0, 1000.0, 1), (1e9, 1e12, 1)], [(0, 0.0), (1, -1.0)]),
    ("slant_opacity", rm.slant_opacity_np, [(0.0, 5.0, 0), (5.0, 90.0, 0)], [(1, 2.0), (0, -0.1)]),
    ("through_layer", rm.brightness_through_layer_k, [(0.0, 300.0, 0), (0.0, 10.0, 0), (0.0, 300.0, 0)], [(1, -0.5), (0, -1.0)]),
    ("sky_brightness", rm.sky_brightness_temperature_k, [(0.0, 5.0, 0), (200.0, 300.0, 0), (1e9, 1e12, 1), (1.0, 5.0, 0)],
     [(1, 0.0), (3, 20.0)]),
    ("apparent", rm.apparent_temperature_k, [(0.0, 1.0, 0), (1.0, 400.0, 0), (1.0, 300.0, 0)], [(0, 1.5), (2, -3.0)]),
    ("contrast", rm.brightness_contrast_k, [(0.0, 1.0, 0), (1.0, 400.0, 0), (0.0, 1.0, 0), (1.0, 400.0, 0), (1.0, 300.0, 0)],
     [(2, -0.1)]),
    ("beam_solid_angle", rm.beam_solid_angle_sr, [(1e-4, 0.1, 1), (1e-4, 10.0, 1), (0.1, 1.0, 0)], [(2, 0.0), (0, 0.0)]),
    ("gaussian_beamwidth", rm.gaussian_beamwidth_rad, [(1e-8, 0.5, 1)], [(0, 0.0), (0, 2.0)]),
    ("fill_fraction", rm.gaussian_beam_fill_fraction, [(0.0, 0.1, 0), (1e-6, 0.1, 1)], [(0, -1.0), (1, 0.0)]),
    ("unbalanced_dicke", rm.unbalanced_dicke_delta_t_k,
     [(0.0, 400.0, 0), (10.0, 3000.0, 1), (0.0, 400.0, 0), (1e6, 1e10, 1), (1e-4, 10.0, 1), (0.0, 1e-2, 0)],
     [(5, 2.0), (3, 0.0), (1, -1.0)]),
    ("gaussian_pd", rm.gaussian_detection_probability, [(0.0, 12.0, 0), (1e-12, 0.1, 1)], [(1, 0.9), (0, -1.0)]),
    ("gaussian_deflection", rm.gaussian_required_deflection, [(0.5, 0.999, 0), (1e-12, 0.1, 1)], [(0, 1.0), (1, 0.7)]),
]
# the contrast is a difference of apparent temperatures: its differences round at their size
globals().update(function_suite(SPECS, jit_rel=1e-13, jit_atol=1e-14, vmap_rtol=1e-13, value_floor=1.0,
                                term_scales={"contrast": lambda a: max(a[1], a[3], a[4])}))


def test_required_deflection_rejects_pd_below_pfa():
    with pytest.raises(DomainError):
        rm.gaussian_required_deflection(0.01, 0.05)


# --- reference values -------------------------------------------------------------------------


@pytest.mark.parametrize("t,f", [(290.0, 94e9), (2.72548, 94e9), (50.0, 35e9), (300.0, 1e12), (1.0, 1e9)])
def test_planck_brightness_vs_mpmath(t, f):
    got = float(planck_brightness_temperature_k(t, f))
    assert got == pytest.approx(float(mp_planck(t, f)), rel=1e-14)


def test_planck_brightness_high_temperature_series():
    # B = T − hf/2k + (hf/k)²/(12 T) − ... ; at 290 K, 94 GHz the next term is ~1e-6 K
    t, f = 290.0, 94e9
    t0 = float(HF_K) * f
    series = t - t0 / 2 + t0**2 / (12 * t)
    assert float(planck_brightness_temperature_k(t, f)) == pytest.approx(series, abs=1e-5)
    assert t0 == pytest.approx(4.5114, rel=1e-4)  # hf/k at 94 GHz


def test_layer_brightness_closed_form_and_limits():
    tb, tau, tm = 60.0, 0.37, 275.0
    ref = mp.mpf(tb) * mp.e ** (-tau) + mp.mpf(tm) * (1 - mp.e ** (-tau))
    assert float(rm.brightness_through_layer_k(tb, tau, tm)) == pytest.approx(float(ref), rel=1e-14)
    assert float(rm.brightness_through_layer_k(tb, 0.0, tm)) == tb
    assert float(rm.brightness_through_layer_k(tb, 60.0, tm)) == pytest.approx(tm, rel=1e-15)


def test_sky_brightness_secant_law_and_cosmic_floor():
    tau_z, tm, f = 0.2, 275.0, 94e9
    tau = float(rm.slant_opacity_np(tau_z, 30.0))
    assert tau == pytest.approx(0.4, rel=1e-14)  # sec(60° zenith angle) = 2
    got = float(rm.sky_brightness_temperature_k(tau, tm, f))
    ref = mp_planck(tm, f) * (1 - mp.e ** (-mp.mpf(tau))) + mp_planck(rm.COSMIC_BACKGROUND_TEMPERATURE_K, f) * mp.e ** (-mp.mpf(tau))
    assert got == pytest.approx(float(ref), rel=1e-14)
    # a transparent atmosphere shows the cosmic background (1.0766 K of RJ brightness at 94 GHz)
    assert float(rm.sky_brightness_temperature_k(0.0, tm, f)) == pytest.approx(
        float(mp_planck(2.72548, f)), rel=1e-14)


def test_metal_target_mirrors_the_sky_and_contrast_closed_form():
    t_sky, t_ground = 61.4, 287.7
    assert float(rm.apparent_temperature_k(0.0, 300.0, t_sky)) == t_sky
    assert float(rm.apparent_temperature_k(1.0, 300.0, t_sky)) == 300.0
    got = float(rm.brightness_contrast_k(0.0, 300.0, 0.9, t_ground, t_sky))
    assert got == pytest.approx(-0.9 * (t_ground - t_sky), rel=1e-14)


def test_beam_solid_angle_gives_book_ore_pass_gain_8_16_9():
    # Brooker 8.16.9: 250 mm Cassegrain, rho = 0.7, 94 GHz (lambda 3.19 mm): G = 42,432
    omega = float(rm.beam_solid_angle_sr(3.19e-3, math.pi * 0.25**2 / 4, 0.7))
    assert 4 * math.pi / omega == pytest.approx(42432.0, rel=1e-4)  # book prints 5 digits


def test_gaussian_beamwidth_solid_angle_1_133_and_book_beamwidth():
    theta = 0.02
    omega = 1.1330900354567985 * theta**2  # π/(4 ln 2), Kraus's 1.133 θ²
    assert float(rm.gaussian_beamwidth_rad(omega)) == pytest.approx(theta, rel=1e-15)
    # Book 8.16.7: 250 mm at 94 GHz, θ = 70 λ/d = 0.89°; the Gaussian beam with the solid angle
    # λ²/(0.7 A) is 0.93° — a 4 % wider beam because 70λ/d assumes a different taper than a
    # Gaussian of the same solid angle (tolerance 5 %)
    omega_a = float(rm.beam_solid_angle_sr(3.19e-3, math.pi * 0.25**2 / 4, 0.7))
    assert math.degrees(float(rm.gaussian_beamwidth_rad(omega_a))) == pytest.approx(0.89, rel=0.05)


@pytest.mark.parametrize("omega_t_over_m", [1e-3, 0.3, 1.0, 4.0])
def test_fill_fraction_equals_gaussian_beam_integral(omega_t_over_m):
    theta = mp.mpf("0.03")
    omega_m = mp.pi * theta**2 / (4 * mp.log(2))
    alpha = mp.sqrt(omega_t_over_m * omega_m / mp.pi)  # disc of solid angle π α²
    inside = mp.quad(lambda psi: mp.e ** (-4 * mp.log(2) * psi**2 / theta**2) * 2 * mp.pi * psi, [0, alpha])
    got = float(rm.gaussian_beam_fill_fraction(float(omega_t_over_m * omega_m), float(omega_m)))
    assert got == pytest.approx(float(inside / omega_m), rel=1e-13)


def test_small_target_antenna_contrast_is_kraus_point_source_limit():
    # η_M F ΔT → (Ω_t/Ω_A) ΔT for Ω_t ≪ Ω_M (Kraus: T_A = T_s Ω_s/Ω_A)
    omega_a, eta_m, omega_t = 2e-3, 0.85, 2e-8
    fill = float(rm.gaussian_beam_fill_fraction(omega_t, eta_m * omega_a))
    assert eta_m * fill == pytest.approx(omega_t / omega_a, rel=1e-5)


def test_radiometer_equation_published_examples():
    # rfessentials.com: total power 500 K, 100 MHz, 1 s -> 0.05 K; 300 K, 500 MHz, 10 ms -> 0.134 K;
    # Dicke K = 2 -> 0.268 K. The balanced unbalanced-Dicke formula must give the Dicke value.
    assert float(noise.total_power_radiometer_delta_t_k(500.0, 1e8, 1.0)) == pytest.approx(0.05, rel=1e-12)
    assert float(noise.total_power_radiometer_delta_t_k(300.0, 5e8, 0.01)) == pytest.approx(0.134, abs=5e-4)
    t_a, t_r = 100.0, 200.0  # T_sys = 300 K
    got = float(rm.unbalanced_dicke_delta_t_k(t_a, t_r, t_a, 5e8, 0.01, 1e-3))
    assert got == pytest.approx(2 * 0.13416407864998739, rel=1e-14)
    assert got == pytest.approx(float(noise.dicke_radiometer_delta_t_k(t_a + t_r, 5e8, 0.01)), rel=1e-14)


def test_unbalanced_dicke_closed_form_and_gain_limit():
    ta, tr, tref, b, tau, g = 150.0, 600.0, 290.0, 2e8, 0.05, 3e-3
    ref = mp.sqrt((2 * (mp.mpf(ta) + tr) ** 2 + 2 * (mp.mpf(tref) + tr) ** 2) / (mp.mpf(b) * tau) + (g * (ta - tref)) ** 2)
    assert float(rm.unbalanced_dicke_delta_t_k(ta, tr, tref, b, tau, g)) == pytest.approx(float(ref), rel=1e-14)
    # infinite integration: only the unbalanced gain term is left
    assert float(rm.unbalanced_dicke_delta_t_k(ta, tr, tref, b, 1e12, g)) == pytest.approx(g * (tref - ta), rel=1e-6)


def test_gaussian_detection_matches_normal_distribution():
    for d, pfa in [(6.0, 1e-6), (3.0, 1e-3), (0.0, 0.1), (10.0, 1e-20)]:
        z = -mp.sqrt(2) * mp.erfinv(1 - 2 * mp.mpf(pfa))  # Φ⁻¹(pfa)
        ref = mp.ncdf(d + z)
        assert float(rm.gaussian_detection_probability(d, pfa)) == pytest.approx(float(ref), rel=1e-12)
    # Pd 0.9 at Pfa 1e-6 needs d = 1.28155 + 4.75342 = 6.03497
    d = float(rm.gaussian_required_deflection(0.9, 1e-6))
    assert d == pytest.approx(float(mp.sqrt(2) * (mp.erfinv(0.8) + mp.erfinv(1 - 2e-6))), rel=1e-12)
    assert float(rm.gaussian_detection_probability(d, 1e-6)) == pytest.approx(0.9, rel=1e-13)
