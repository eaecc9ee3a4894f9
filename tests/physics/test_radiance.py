"""Blackbody radiation (diffsense.physics.radiance): Planck's law and its band integrals.

References used by the assertions: closed forms evaluated in mpmath — Stefan–Boltzmann law σT⁴
(CODATA σ), Wien's displacement constant b = 2.897771955e-3 m·K (CODATA 2018), Planck band
integrals by mpmath.quad. Photon-unit band integrals are checked in
tests/sensors/infrared/test_infrared.py, the brightness temperature in
tests/sensors/radiometer/test_radiometer.py.
"""

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import radiance as rd
from diffsense.errors import DomainError

from helpers.function_suite import function_suite
from diffsense.physics.constants import (
    BOLTZMANN_J_K,
    PLANCK_J_S,
    SPEED_OF_LIGHT_M_S,
    STEFAN_BOLTZMANN_W_M2_K4,
)

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)

# Each spec: (name, fn of positional floats, [(lo, hi, log_scale)], [(arg index, bad value)], smooth)
SPECS = [
    ("planck_radiance", rd.planck_spectral_radiance, [(1e-7, 1e-3, 1), (50.0, 6000.0, 1)], [(0, 0.0), (1, 0.0)], True),
    ("planck_exitance", rd.planck_spectral_exitance, [(1e-7, 1e-3, 1), (50.0, 6000.0, 1)], [(1, -5.0)], True),
    ("band_radiance", rd.band_radiance_w_m2_sr, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(2, 0.0), (1, 20.0)], True),
    ("band_exitance", rd.band_exitance_w_m2, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(0, 0.0)], True),
    ("band_fraction", rd.band_fraction, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(2, -1.0)], True),
    ("band_dL_dT", rd.band_radiance_temperature_derivative, [(2e-7, 4e-6, 1), (5e-6, 1e-3, 1), (200.0, 6000.0, 1)], [(2, 0.0)], True),
]
globals().update(function_suite(SPECS, jit_rel=1e-12, jit_atol=lambda eager: 1e-12 * (abs(eager) > 1e-6),
                                vmap_rtol=1e-12, value_floor=1e-300))


def test_band_integral_rejects_reversed_band():
    with pytest.raises(DomainError):
        rd.band_radiance_w_m2_sr(10e-6, 8e-6, 300.0)


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
    assert float(rd.planck_spectral_radiance(10e-6, 300.0)) == pytest.approx(float(ref), rel=1e-13)
    assert float(rd.planck_spectral_exitance(10e-6, 300.0)) == pytest.approx(float(mp.pi * ref), rel=1e-13)
    # Wien: dL_λ/dλ = 0 at λ = b/T, b = 2.897771955e-3 m K (CODATA 2018)
    for temp in (300.0, 1000.0, 5800.0):
        lam_max = 2.897771955e-3 / temp
        slope = float(jax.grad(rd.planck_spectral_radiance)(lam_max, temp))
        scale = float(rd.planck_spectral_radiance(lam_max, temp)) / lam_max
        assert abs(slope) < 1e-8 * scale


def test_total_exitance_stefan_boltzmann():
    # 10 nm – 1 m at 300 K holds all but ~1e-14 of σT⁴
    for t in (300.0,):
        m = float(rd.band_exitance_w_m2(1e-8, 1.0, t))
        assert m == pytest.approx(STEFAN_BOLTZMANN_W_M2_K4 * t**4, rel=1e-9)  # σ quoted to 10 digits
    # 10 nm – 10 m at 5800 K (ratio 1e9: 10 panels)
    m = float(rd.band_exitance_w_m2(1e-8, 10.0, 5800.0, n_panels=10))
    assert m == pytest.approx(STEFAN_BOLTZMANN_W_M2_K4 * 5800.0**4, rel=1e-9)


@pytest.mark.parametrize(
    "l1,l2,t",
    [(8e-6, 12e-6, 300.0), (3e-6, 5e-6, 300.0), (0.4e-6, 0.7e-6, 5800.0), (0.2e-6, 1e-3, 200.0), (1e-6, 2e-6, 6000.0), (0.3e-6, 1e-3, 1000.0)],
)
def test_band_radiance_and_derivative_vs_mpmath(l1, l2, t):
    ref = _mp_planck_band(l1, l2, t)
    assert float(rd.band_radiance_w_m2_sr(l1, l2, t)) == pytest.approx(float(ref), rel=1e-12)
    frac = ref * mp.pi / (mp.mpf(STEFAN_BOLTZMANN_W_M2_K4) * mp.mpf(t) ** 4)
    assert float(rd.band_fraction(l1, l2, t)) == pytest.approx(float(frac), rel=1e-9)  # σ to 10 digits
    dref = _mp_planck_band(l1, l2, t, deriv=True)
    assert float(rd.band_radiance_temperature_derivative(l1, l2, t)) == pytest.approx(float(dref), rel=1e-12)
    # and the autodiff derivative of the band radiance agrees
    g = float(jax.grad(rd.band_radiance_w_m2_sr, argnums=2)(l1, l2, t))
    assert g == pytest.approx(float(dref), rel=1e-11)


def test_band_fraction_wien_quarter():
    # F(0 → λT = b) = 0.25005 (from 15/π⁴ ∫_{x_b}^∞ x³/(e^x − 1) dx, x_b = hc/(k b) = 4.965)
    xb = mp.mpf(PLANCK_J_S) * mp.mpf(SPEED_OF_LIGHT_M_S) / (mp.mpf(BOLTZMANN_J_K) * mp.mpf("2.897771955e-3"))
    ref = 15 / mp.pi**4 * mp.quad(lambda x: x**3 / mp.expm1(x), [xb, 20, 60, mp.inf])
    got = float(rd.band_fraction(1e-9, 2.897771955e-3 / 1000.0, 1000.0))
    assert got == pytest.approx(float(ref), rel=1e-12)
    assert got == pytest.approx(0.25005, abs=1e-5)
