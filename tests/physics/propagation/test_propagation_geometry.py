"""Refraction (radar horizon), free-space spreading and two-ray sea multipath.

Sources: closed forms of the effective-earth geometry (Skolnik 2001 §8.2) evaluated with
mpmath; ITU-R P.525-4 eq. (9) free-space loss 32.45 + 20 log f(MHz) + 20 log d(km); Brooker
§9.9.1 (worked_examples.md §2: 0.003 dB/km -> ~316 km, 0.02 dB/km -> ~216 km); Fermat's
principle solved numerically (scipy) for the specular point; Fresnel normal-incidence and
Brewster-angle closed forms; PSS-78 standard sea water conductivity 4.2914 S/m (S = 35,
15 °C; UNESCO 1981) for the Klein & Swift model.
"""

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.optimize import brentq, minimize_scalar

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation import (
    atmospheric_two_way_loss_db,
    fresnel_reflection_coefficient,
    free_space_path_loss_db,
    isotropic_spreading_loss_db,
    minimum_visible_target_height_m,
    propagation_factor_db,
    radar_horizon_m,
    roughness_factor,
    sea_water_permittivity,
    two_ray_geometry,
    two_ray_propagation_factor,
    two_way_spreading_loss_db,
)

from helpers.function_checks import grad_and_central_difference

AE = 4.0 / 3.0 * 6_371_000.0


# ---------------------------------------------------------------- refraction
def test_radar_horizon_closed_form_sea_skimmer():
    ref = mp.sqrt(2 * mp.mpf(AE) * 8 + 64) + mp.sqrt(2 * mp.mpf(AE) * 3 + 9)
    assert float(radar_horizon_m(8.0, 3.0)) == pytest.approx(float(ref), rel=1e-13)
    # classic rule d[km] = 4.12 (sqrt(h1) + sqrt(h2)) for k = 4/3 (Skolnik): within 0.1 %
    assert float(radar_horizon_m(8.0, 3.0)) / 1e3 == pytest.approx(4.12 * (8**0.5 + 3**0.5), rel=1e-3)


def test_minimum_visible_height_inverts_radar_horizon():
    d = radar_horizon_m(8.0, 3.0)
    assert float(minimum_visible_target_height_m(d, 8.0)) == pytest.approx(3.0, rel=1e-10)
    assert float(minimum_visible_target_height_m(5000.0, 8.0)) == 0.0


def test_refraction_jit_vmap_grad():
    f = jax.jit(radar_horizon_m)
    assert float(f(8.0, 3.0)) == pytest.approx(float(radar_horizon_m(8.0, 3.0)), rel=1e-14)
    hs = jnp.array([1.0, 10.0, 100.0])
    assert np.allclose(jax.vmap(lambda h: radar_horizon_m(h, 3.0))(hs), radar_horizon_m(hs, 3.0))
    for fun, x0, h in [(lambda h1: radar_horizon_m(h1, 3.0), 8.0, 1e-6),
                       (lambda k: radar_horizon_m(8.0, 3.0, k), 4 / 3, 1e-7),
                       (lambda r: minimum_visible_target_height_m(r, 8.0), 20e3, 1e-3)]:
        g, fd = grad_and_central_difference(fun, x0, h)
        assert g == pytest.approx(fd, rel=1e-6)
    assert np.isfinite(float(jax.grad(radar_horizon_m)(0.0, 3.0)))
    with pytest.raises(DomainError):
        radar_horizon_m(-1.0, 3.0)
    with pytest.raises(DomainError):
        radar_horizon_m(8.0, 3.0, 0.1)


# ---------------------------------------------------------------- free space
def test_free_space_loss_itu_r_p525():
    # P.525-4 eq. (9): L = 32.45 + 20 log f(MHz) + 20 log d(km) (constant rounded to 0.01 dB)
    assert float(free_space_path_loss_db(1e3, 1e9)) == pytest.approx(32.45 + 60.0, abs=0.01)
    ref = 20 * mp.log10(4 * mp.pi * 25e3 * 94e9 / mp.mpf(SPEED_OF_LIGHT_M_S))
    assert float(free_space_path_loss_db(25e3, 94e9)) == pytest.approx(float(ref), rel=1e-14)


def test_two_way_spreading_is_40logR_plus_constant():
    # one way 10 log10(4 pi R^2); radar: twice that = 40 log10 R + 20 log10(4 pi)
    assert float(isotropic_spreading_loss_db(1e4)) == pytest.approx(float(10 * mp.log10(4 * mp.pi * mp.mpf(1e8))), rel=1e-14)
    assert float(two_way_spreading_loss_db(1e4)) == pytest.approx(2 * float(isotropic_spreading_loss_db(1e4)), rel=1e-14)
    assert float(two_way_spreading_loss_db(1e4) - 40.0 * 4) == pytest.approx(float(20 * mp.log10(4 * mp.pi)), rel=1e-13)


@pytest.mark.parametrize("alpha, expected_km, tol", [(0.003, 316.0, 0.01), (0.02, 216.0, 0.01)])
def test_surveillance_radar_range_with_atmospheric_loss_book_9_9_1(alpha, expected_km, tol):
    # SNR = 230.1 - 40 log10 R - 2 alpha R = 8.2 dB (book: exact ~316 km; heavy rain ~216 km,
    # graphical, hence 1 % tolerance)
    g = lambda r_km: 230.1 - 40 * np.log10(r_km * 1e3) - float(atmospheric_two_way_loss_db(r_km * 1e3, alpha)) - 8.2  # noqa: E731
    assert brentq(g, 50.0, 400.0) == pytest.approx(expected_km, rel=tol)


def test_free_space_jit_vmap_grad_domain():
    assert float(jax.jit(free_space_path_loss_db)(1e3, 1e9)) == pytest.approx(float(free_space_path_loss_db(1e3, 1e9)))
    rs = jnp.array([1e2, 1e3, 1e4])
    assert np.allclose(jax.vmap(lambda r: two_way_spreading_loss_db(r))(rs), two_way_spreading_loss_db(rs))
    assert float(jax.grad(free_space_path_loss_db)(1e3, 1e9)) == pytest.approx(20 / (np.log(10) * 1e3), rel=1e-12)
    assert float(jax.grad(atmospheric_two_way_loss_db)(1e3, 0.1)) == pytest.approx(2e-4, rel=1e-12)
    for call in (lambda: free_space_path_loss_db(0.0, 1e9), lambda: atmospheric_two_way_loss_db(1e3, -0.1)):
        with pytest.raises(DomainError):
            call()


# ---------------------------------------------------------------- multipath
def test_flat_earth_perfect_reflector_closed_form():
    h1, h2, f = 8.0, 3.0, 10e9
    lam = SPEED_OF_LIGHT_M_S / f
    for r in [500.0, 2000.0, 10000.0]:
        g = mp.sqrt(mp.mpf(r) ** 2 - (h1 - h2) ** 2)
        delta = mp.sqrt(g**2 + (h1 + h2) ** 2) - r
        exact = 2 * abs(mp.sin(mp.pi * delta / lam))
        got = float(two_ray_propagation_factor(r, h1, h2, f, -1.0, earth_model="flat"))
        assert got == pytest.approx(float(exact), rel=1e-9)
        # textbook approximation F = 2 |sin(2 pi h1 h2 / (lambda R))|: relative error in delta
        # O(((h1 + h2)/R)^2) = 5e-4 at 500 m, amplified by x cot(x) in F -> 5e-3 tolerance
        assert got == pytest.approx(2 * abs(np.sin(2 * np.pi * h1 * h2 / (lam * r))), rel=5e-3)


def test_curved_earth_specular_point_satisfies_fermat_principle():
    h1, h2, r = 8.0, 3.0, 12000.0
    geo = two_ray_geometry(r, h1, h2)
    g = float(geo["ground_range"])
    phi = g / AE
    a = np.array([0.0, AE + h1])
    t = (AE + h2) * np.array([np.sin(phi), np.cos(phi)])

    def path(phi1):
        p = AE * np.array([np.sin(phi1), np.cos(phi1)])
        return np.linalg.norm(a - p) + np.linalg.norm(t - p)

    res = minimize_scalar(path, bounds=(0.0, phi), method="bounded", options={"xatol": 1e-14})
    assert float(geo["g1"]) == pytest.approx(res.x * AE, rel=1e-5)
    assert float(geo["path_difference"]) == pytest.approx(path(res.x) - r, rel=1e-6)
    assert np.linalg.norm(a - t) == pytest.approx(r, rel=1e-12)


def test_fresnel_normal_incidence_and_brewster_angle():
    eps = 70.0 - 40.0j
    n = np.sqrt(eps)
    assert complex(fresnel_reflection_coefficient(np.pi / 2, eps, "horizontal")) == pytest.approx((1 - n) / (1 + n), rel=1e-12)
    assert complex(fresnel_reflection_coefficient(np.pi / 2, eps, "vertical")) == pytest.approx((n - 1) / (n + 1), rel=1e-12)
    eps_r = 4.0  # lossless: Gamma_V = 0 at the Brewster grazing angle, sin psi_B = 1/sqrt(eps + 1)
    psi_b = np.arcsin(1 / np.sqrt(eps_r + 1))
    assert abs(complex(fresnel_reflection_coefficient(psi_b, eps_r, "vertical"))) < 1e-12
    assert complex(fresnel_reflection_coefficient(0.0, eps, "vertical")) == pytest.approx(-1.0, abs=1e-12)


def test_sea_water_conductivity_matches_pss78_standard():
    # low-frequency loss: sigma ~= -Im(eps) 2 pi f eps0; PSS-78: C(35, 15 C) = 4.2914 S/m
    f = 1e8
    eps = complex(sea_water_permittivity(f, 288.15, 35.0))
    sigma = -eps.imag * 2 * np.pi * f * 8.8541878128e-12
    assert sigma == pytest.approx(4.2914, rel=0.02)


def test_roughness_factors_closed_forms():
    lam, sigma_h, psi = 0.03, 0.2, 0.01
    g = 2 * mp.pi * sigma_h * mp.sin(psi) / lam
    x = 2 * g**2
    assert float(roughness_factor(sigma_h, psi, lam, "ament")) == pytest.approx(float(mp.exp(-x)), rel=1e-13)
    assert float(roughness_factor(sigma_h, psi, lam)) == pytest.approx(float(mp.exp(-x) * mp.besseli(0, x)), rel=1e-12)


def test_smooth_sea_flat_earth_approaches_perfect_reflector_at_low_grazing():
    # |Gamma_H| -> 1 as psi -> 0; at psi ~ 1e-3 rad, |Gamma_H| > 0.997 -> within 0.1 dB of 2 sin(.)
    h1, h2, f, r = 8.0, 3.0, 10e9, 10000.0
    got = float(propagation_factor_db(r, h1, h2, f, rms_wave_height_m=0.0, earth_model="flat"))
    ref = 40 * np.log10(float(two_ray_propagation_factor(r, h1, h2, f, -1.0, earth_model="flat")))
    assert got == pytest.approx(ref, abs=0.1)


def test_propagation_factor_lobe_bounds():
    # 0 <= |F| <= 2 -> 40 log10 |F| <= 12.04 dB everywhere
    r = jnp.linspace(100.0, 18000.0, 2000)
    v = np.asarray(propagation_factor_db(r, 8.0, 3.0, 10e9, sea_state=5))
    assert np.all(np.isfinite(v)) and v.max() <= 40 * np.log10(2) + 1e-9


def test_multipath_jit_vmap():
    f = jax.jit(propagation_factor_db, static_argnames=("sea_state", "polarization"))
    a = float(f(10e3, 8.0, 3.0, 9.4e9, sea_state=5, polarization="vertical"))
    assert a == pytest.approx(float(propagation_factor_db(10e3, 8.0, 3.0, 9.4e9, sea_state=5, polarization="vertical")), rel=1e-12)
    rs = jnp.array([2e3, 5e3, 1e4])
    v = jax.vmap(lambda r: propagation_factor_db(r, 8.0, 3.0, 9.4e9))(rs)
    assert np.allclose(v, propagation_factor_db(rs, 8.0, 3.0, 9.4e9), rtol=1e-12)


@pytest.mark.parametrize("which, x0, h", [("range", 7000.0, 1e-3), ("h1", 8.0, 1e-6), ("h2", 3.0, 1e-6),
                                         ("freq", 9.4e9, 10.0), ("sigma", 0.3, 1e-7)])
@pytest.mark.parametrize("polarization", ["horizontal", "vertical"])
def test_propagation_factor_gradient_matches_central_difference(which, x0, h, polarization):
    base = dict(range=7000.0, h1=8.0, h2=3.0, freq=9.4e9, sigma=0.3)

    def fun(x):
        a = dict(base)
        a[which] = x
        return propagation_factor_db(a["range"], a["h1"], a["h2"], a["freq"], polarization=polarization,
                                     rms_wave_height_m=a["sigma"])

    g, fd = grad_and_central_difference(fun, x0, h)
    assert g == pytest.approx(fd, rel=1e-5, abs=1e-9)


@settings(max_examples=30, deadline=None)
@given(frac=st.floats(0.001, 0.999), h1=st.floats(1.0, 50.0), h2=st.floats(1.0, 50.0), f=st.floats(1e9, 1e11),
       sigma=st.floats(0.0, 2.0))
def test_propagation_factor_gradient_finite_up_to_horizon(frac, h1, h2, f, sigma):
    r = max(frac * float(radar_horizon_m(h1, h2)), abs(h1 - h2) + 1.0)
    g = jax.grad(lambda *a: propagation_factor_db(*a[:4], rms_wave_height_m=a[4]), argnums=(0, 1, 2, 3, 4))(r, h1, h2, f, sigma)
    assert all(np.isfinite(float(x)) for x in g)


def test_multipath_out_of_domain_raises():
    for call in (lambda: propagation_factor_db(20e3, 8.0, 3.0, 10e9),  # beyond the radar horizon
                 lambda: propagation_factor_db(1e3, 8.0, 3.0, 10e9, sea_state=12),
                 lambda: propagation_factor_db(1e3, 8.0, 3.0, 10e9, polarization="circular"),
                 lambda: propagation_factor_db(1e3, -8.0, 3.0, 10e9),
                 lambda: propagation_factor_db(3.0, 8.0, 3.0, 10e9),
                 lambda: sea_water_permittivity(10e9, 350.0)):
        with pytest.raises(DomainError):
            call()
