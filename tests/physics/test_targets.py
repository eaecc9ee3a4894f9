"""Target models against the book, closed forms, mpmath and scipy distributions.

Book: Brooker, *Introduction to Sensors for Ranging and Imaging* — 8.4 (plate eqs 8.10-8.11),
8.10 (laser cross section eqs 8.19-8.20), 8.11.4 (TS of a sphere eq. 8.24 and Table 8.6),
8.16.4-8.16.6 (ore pass: |K|^2, sigma0 = -3 dB, footprint; worked example 3), 12.8
(1 m sphere TS = -12 dB; worked example 4).
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

import diffsense  # noqa: F401
from diffsense.physics import targets as tg
from diffsense.errors import DomainError

# --------------------------------------------------------------------------------------
# Book numbers
# --------------------------------------------------------------------------------------


def test_sonar_sphere_target_strength_book_12_8():
    # Worked example 4: 1 m diameter sphere, TS = 10 log10(a^2/4) = -12 dB (book rounds -12.04).
    assert float(tg.target_strength_sphere_db(0.5)) == pytest.approx(-12.0, abs=0.05)
    assert float(tg.target_strength_sphere_db(0.5)) == pytest.approx(20 * math.log10(0.5 / 2), abs=1e-12)


def test_ore_pass_dielectric_ratio_book_8_16_4():
    # Worked example 3: rock 5.23 -> 0.34, water 8.45 -> 0.51, ratio 1.5 (1.8 dB).
    k_rock = float(tg.dielectric_factor_k2(5.23))
    k_water = float(tg.dielectric_factor_k2(8.45))
    assert k_rock == pytest.approx(0.34, abs=0.005)
    assert k_water == pytest.approx(0.51, abs=0.005)
    assert k_water / k_rock == pytest.approx(1.5, abs=0.05)
    # The book takes dB of the rounded 1.5 (1.76 dB); unrounded ratio 1.485 -> 1.72 dB.
    assert 10 * math.log10(k_water / k_rock) == pytest.approx(1.8, abs=0.1)


def test_ore_pass_rock_footprint_rcs_book_8_16_6():
    # sigma0 = 0.5 (-3 dB) over pi 6^2/4 = 28.3 m^2 (14.5 dBm^2) -> 11.5 dBm^2.
    area = math.pi * 6.0**2 / 4.0
    assert 10 * math.log10(area) == pytest.approx(14.5, abs=0.05)
    sigma = float(tg.extended_target_rcs_m2(0.5, area))
    assert 10 * math.log10(sigma) == pytest.approx(11.5, abs=0.05)
    # wall clutter: pi d dR = 37.7 m^2 at sigma0 = -10 dB -> 5.8 dBm^2; SCR 5.7 dB
    clutter = float(tg.extended_target_rcs_m2(0.1, math.pi * 6.0 * 2.0))
    assert 10 * math.log10(clutter) == pytest.approx(5.8, abs=0.05)
    assert 10 * math.log10(sigma / clutter) == pytest.approx(5.7, abs=0.05)


def test_lambertian_laser_cross_section_book_8_15_to_8_18():
    # sigma = rho G A with G = 4 pi / Omega = 4 for Omega = pi (book eqs 8.15-8.18); Lambert's
    # law and the projected area give cos^2 off the normal (cos^2(60 deg) = 1/4)
    assert float(tg.laser_cross_section_lambertian_m2(0.5, 2.0, 0.0)) == pytest.approx(4.0, rel=1e-15)
    assert float(tg.laser_cross_section_lambertian_m2(0.5, 2.0, math.pi / 3)) == pytest.approx(1.0, rel=1e-14)


def test_specular_laser_cross_section_is_plate_times_reflectivity_book_8_19():
    lam = 1.06e-6
    assert float(tg.laser_cross_section_specular_m2(0.8, 1e-4, lam)) == pytest.approx(
        0.8 * float(tg.rcs_plate_normal_m2(1e-4, lam)), rel=1e-14
    )


# --------------------------------------------------------------------------------------
# Table 8.6 target strengths are 10 log10(sigma / 4 pi) of the RCS formulas
# --------------------------------------------------------------------------------------


def test_table_8_6_consistent_with_cross_sections():
    lam = 0.0128  # 117 kHz in 1500 m/s water
    ts = tg.target_strength_from_cross_section_db
    assert float(tg.target_strength_sphere_db(2.0)) == pytest.approx(float(ts(tg.rcs_sphere_optical_m2(2.0))), abs=1e-12)
    assert float(tg.target_strength_plate_db(0.3, lam)) == pytest.approx(float(ts(tg.rcs_plate_normal_m2(0.3, lam))), abs=1e-12)
    assert float(tg.target_strength_rectangular_plate_db(0.5, 0.6, lam)) == pytest.approx(
        float(ts(tg.rcs_flat_plate_m2(0.6, 0.5, lam))), abs=1e-12
    )
    assert float(tg.target_strength_circular_plate_db(0.2, lam)) == pytest.approx(
        float(ts(tg.rcs_plate_normal_m2(math.pi * 0.04, lam))), abs=1e-12
    )
    assert float(tg.target_strength_cylinder_db(0.3, 2.0, lam)) == pytest.approx(
        float(ts(tg.rcs_cylinder_m2(0.3, 2.0, lam))), abs=1e-12
    )
    # convex surface with equal radii is the sphere
    assert float(tg.target_strength_convex_surface_db(1.5, 1.5)) == pytest.approx(
        float(tg.target_strength_sphere_db(1.5)), abs=1e-12
    )


def test_angle_correction_book_8_11_4_2():
    # TS(theta) - TS(0) = 10 log10[(sin x/x)^2] + 10 log10 cos^2 theta, x = (2 pi L/lambda) sin theta.
    lam, length, theta = 0.0128, 1.0, math.radians(0.3)
    x = 2 * math.pi * length / lam * math.sin(theta)
    expected = 10 * math.log10((math.sin(x) / x) ** 2) + 10 * math.log10(math.cos(theta) ** 2)
    got = float(tg.target_strength_cylinder_db(0.2, length, lam, theta) - tg.target_strength_cylinder_db(0.2, length, lam))
    assert got == pytest.approx(expected, abs=1e-10)
    got_plate = float(
        tg.target_strength_rectangular_plate_db(0.4, length, lam, theta) - tg.target_strength_rectangular_plate_db(0.4, length, lam)
    )
    assert got_plate == pytest.approx(expected, abs=1e-10)


# --------------------------------------------------------------------------------------
# RCS closed forms
# --------------------------------------------------------------------------------------


def test_flat_plate_pattern_eq_8_10():
    a, b, lam = 0.5, 0.3, 0.03
    s0 = 4 * math.pi * (a * b) ** 2 / lam**2
    assert float(tg.rcs_flat_plate_m2(a, b, lam)) == pytest.approx(s0, rel=1e-14)
    # first null at sin theta = lambda / (2a)
    th_null = math.asin(lam / (2 * a))
    assert float(tg.rcs_flat_plate_m2(a, b, lam, th_null)) == pytest.approx(0.0, abs=1e-20 * s0)
    # first sidelobe of sinc^2: -13.26 dB near x = 4.4934
    th_sl = math.asin(4.4934094579 * lam / (2 * math.pi * a))
    rel = float(tg.rcs_flat_plate_m2(a, b, lam, th_sl)) / (s0 * math.cos(th_sl) ** 2)
    assert 10 * math.log10(rel) == pytest.approx(-13.26, abs=0.01)


def test_corner_reflectors_and_cylinder_closed_forms():
    lam = 0.0032
    assert float(tg.rcs_trihedral_triangular_m2(0.1, lam)) == pytest.approx(4 * math.pi * 1e-4 / (3 * lam**2), rel=1e-14)
    # a square trihedral returns 9x the triangular one of the same edge
    assert float(tg.rcs_trihedral_square_m2(0.1, lam)) == pytest.approx(9 * float(tg.rcs_trihedral_triangular_m2(0.1, lam)), rel=1e-14)
    # dihedral: twice the single plate of the same area (8 pi vs 4 pi)
    assert float(tg.rcs_dihedral_m2(0.2, 0.1, lam)) == pytest.approx(2 * float(tg.rcs_plate_normal_m2(0.02, lam)), rel=1e-14)
    assert float(tg.rcs_cylinder_m2(0.05, 1.0, lam)) == pytest.approx(2 * math.pi * 0.05 / lam, rel=1e-14)
    th_null = math.asin(lam / (2 * 1.0))
    assert float(tg.rcs_cylinder_m2(0.05, 1.0, lam, th_null)) == pytest.approx(0.0, abs=1e-12)


def _mie_pec_mpmath(x):
    x = mp.mpf(x)
    n_max = int(math.ceil(float(x) + 4 * float(x) ** (1 / 3) + 8))
    total = mp.mpc(0)

    def jn(n):
        return mp.sqrt(mp.pi / (2 * x)) * mp.besselj(n + mp.mpf(1) / 2, x)

    def yn(n):
        return mp.sqrt(mp.pi / (2 * x)) * mp.bessely(n + mp.mpf(1) / 2, x)

    for n in range(1, n_max + 1):
        h, hp = jn(n) + 1j * yn(n), jn(n - 1) + 1j * yn(n - 1)
        a_n = jn(n) / h
        b_n = (x * jn(n - 1) - n * jn(n)) / (x * hp - n * h)
        total += (-1) ** n * (2 * n + 1) * (a_n - b_n)
    return float(abs(total) ** 2 / x**2)


@pytest.mark.parametrize("ka", [0.04, 0.3, 1.0, 2.5, 7.0, 20.0, 60.0])
def test_mie_series_matches_mpmath(ka):
    mp.mp.dps = 30
    a = ka / (2 * math.pi)
    got = float(tg.rcs_sphere_mie_m2(a, 1.0)) / (math.pi * a * a)
    assert got == pytest.approx(_mie_pec_mpmath(ka), rel=1e-8)


def test_mie_limits_and_first_peak():
    # Rayleigh: 9 pi a^2 (ka)^4 within 0.1 % at ka = 0.05; optical: pi a^2 within 0.01 % at ka = 200;
    # first resonance sigma/(pi a^2) = 3.64 near ka = 1 (the resonance peak of Knott et al. ch. 3).
    a = 0.05 / (2 * math.pi)
    assert float(tg.rcs_sphere_mie_m2(a, 1.0)) == pytest.approx(float(tg.rcs_sphere_rayleigh_m2(a, 1.0)), rel=1e-3)
    a = 200 / (2 * math.pi)
    assert float(tg.rcs_sphere_mie_m2(a, 1.0)) == pytest.approx(float(tg.rcs_sphere_optical_m2(a)), rel=1e-3)
    radii = np.linspace(0.8, 1.2, 81) / (2 * math.pi)
    peak = float(np.max(np.asarray(tg.rcs_sphere_mie_m2(radii, 1.0)) / (math.pi * radii**2)))
    assert peak == pytest.approx(3.65, abs=0.02)


def test_mie_gradient_matches_fd_and_jit():
    fn = jax.jit(lambda a: tg.rcs_sphere_mie_m2(a, 1.0, n_terms=20))
    a0 = 1.3
    g = float(jax.grad(fn)(a0))
    h = 1e-6
    fd = (float(fn(a0 + h)) - float(fn(a0 - h))) / (2 * h)
    assert g == pytest.approx(fd, rel=1e-6)
    assert float(fn(a0)) == pytest.approx(float(tg.rcs_sphere_mie_m2(a0, 1.0)), rel=1e-10)
    with pytest.raises(DomainError):
        jax.jit(lambda a: tg.rcs_sphere_mie_m2(a, 1.0))(a0)  # traced without n_terms


def test_dielectric_rayleigh_sphere_water_drop():
    # 1 mm drop at 10 GHz, |K|^2 = 0.93: pi^5 0.93 D^6 / lambda^4
    lam = 0.03
    expected = math.pi**5 * 0.93 * (2e-3) ** 6 / lam**4
    assert float(tg.rcs_dielectric_sphere_rayleigh_m2(1e-3, lam, 0.93)) == pytest.approx(expected, rel=1e-14)
    # complex permittivity (book 8.14: water 8.45 - j15.45 at 94 GHz) is accepted
    k2 = float(tg.dielectric_factor_k2(8.45 - 15.45j))
    eps = complex(8.45, -15.45)
    assert k2 == pytest.approx(abs((eps - 1) / (eps + 2)) ** 2, rel=1e-14)


# --------------------------------------------------------------------------------------
# Swerling models
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", [1, 2, 3, 4])
def test_swerling_cdf_and_pdf_match_scipy(case):
    mean = 2.5
    s = np.linspace(0.0, 12.0, 25)
    ref = stats.expon(scale=mean) if case in (1, 2) else stats.gamma(a=2, scale=mean / 2)
    np.testing.assert_allclose(tg.swerling_rcs_cdf(s, mean, case), ref.cdf(s), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(tg.swerling_rcs_pdf(s, mean, case), ref.pdf(s), rtol=1e-12, atol=1e-15)


def test_swerling_lower_tail_accuracy():
    # For case 3/4, F(s) ~ 2 (s/mean)^2 for small s (series of 1 - (1+u)e^-u = u^2/2 - u^3/3 ...).
    u = 2e-9
    got = float(tg.swerling_rcs_cdf(u / 2, 1.0, 3))
    assert got == pytest.approx(u**2 / 2 - u**3 / 3, rel=1e-9)


def test_swerling_case_zero():
    assert float(tg.swerling_rcs_cdf(0.99, 1.0, 0)) == 0.0
    assert float(tg.swerling_rcs_cdf(1.0, 1.0, 0)) == 1.0
    samples = tg.swerling_rcs_sample(jax.random.PRNGKey(0), 3.0, 0, n_scans=2, n_pulses=3)
    np.testing.assert_array_equal(samples, 3.0)


@pytest.mark.parametrize("case", [1, 2, 3, 4])
def test_swerling_samples_distribution_and_correlation(case):
    mean = 2.0
    samples = np.asarray(tg.swerling_rcs_sample(jax.random.PRNGKey(case), mean, case, n_scans=4000, n_pulses=5))
    assert samples.shape == (4000, 5)
    ref = stats.expon(scale=mean) if case in (1, 2) else stats.gamma(a=2, scale=mean / 2)
    first_pulse = samples[:, 0]
    assert stats.kstest(first_pulse, ref.cdf).pvalue > 1e-3
    # mean within 5 standard errors; variance mean^2 (chi2 2 dof) or mean^2/2 (4 dof)
    var = mean**2 if case in (1, 2) else mean**2 / 2
    assert first_pulse.mean() == pytest.approx(mean, abs=5 * math.sqrt(var / 4000))
    if case in (1, 3):
        # scan-to-scan: all pulses of a scan equal
        np.testing.assert_array_equal(samples, samples[:, :1] * np.ones((1, 5)))
    else:
        assert abs(np.corrcoef(samples[:, 0], samples[:, 1])[0, 1]) < 0.1


def test_swerling_samples_reparameterised_gradient():
    key = jax.random.PRNGKey(7)
    f = lambda m: jnp.mean(tg.swerling_rcs_sample(key, m, 2, n_scans=10, n_pulses=10))  # noqa: E731
    g = float(jax.grad(f)(3.0))
    assert g == pytest.approx(float(f(3.0)) / 3.0, rel=1e-12)  # samples are m * z


# --------------------------------------------------------------------------------------
# jit / vmap / grad / domain
# --------------------------------------------------------------------------------------

FUNCS = {
    "optical": (tg.rcs_sphere_optical_m2, 0.5),
    "rayleigh": (lambda x: tg.rcs_sphere_rayleigh_m2(x, 0.03), 0.001),
    "diel_rayleigh": (lambda x: tg.rcs_dielectric_sphere_rayleigh_m2(x, 0.03, 0.93), 0.001),
    "plate_angle": (lambda x: tg.rcs_flat_plate_m2(0.5, 0.3, 0.03, x), 0.02),
    "plate_angle_zero": (lambda x: tg.rcs_flat_plate_m2(0.5, 0.3, 0.03, x), 0.0),
    "plate_normal": (lambda x: tg.rcs_plate_normal_m2(x, 0.03), 0.15),
    "trihedral": (lambda x: tg.rcs_trihedral_triangular_m2(x, 0.0032), 0.1),
    "trihedral_sq": (lambda x: tg.rcs_trihedral_square_m2(x, 0.0032), 0.1),
    "dihedral": (lambda x: tg.rcs_dihedral_m2(x, 0.1, 0.0032), 0.2),
    "cylinder": (lambda x: tg.rcs_cylinder_m2(0.05, 1.0, 0.0032, x), 0.001),
    "lambert": (lambda x: tg.laser_cross_section_lambertian_m2(0.5, 2.0, x), 0.4),
    "specular": (lambda x: tg.laser_cross_section_specular_m2(x, 1e-4, 1e-6), 0.8),
    "ts_sigma": (tg.target_strength_from_cross_section_db, 3.0),
    "ts_sphere": (tg.target_strength_sphere_db, 0.5),
    "ts_convex": (lambda x: tg.target_strength_convex_surface_db(x, 2.0), 1.0),
    "ts_plate": (lambda x: tg.target_strength_plate_db(x, 0.0128), 0.3),
    "ts_rect": (lambda x: tg.target_strength_rectangular_plate_db(0.5, 1.0, 0.0128, x), 0.003),
    "ts_circ": (lambda x: tg.target_strength_circular_plate_db(x, 0.0128), 0.2),
    "ts_cyl": (lambda x: tg.target_strength_cylinder_db(0.3, 2.0, 0.0128, x), 0.001),
    "k2": (tg.dielectric_factor_k2, 5.23),
    "extended": (lambda x: tg.extended_target_rcs_m2(x, 28.27), 0.5),
    "pdf1": (lambda x: tg.swerling_rcs_pdf(x, 2.0, 1), 1.5),
    "pdf3_mean": (lambda x: tg.swerling_rcs_pdf(1.5, x, 3), 2.0),
    "cdf4": (lambda x: tg.swerling_rcs_cdf(x, 2.0, 4), 1.5),
}


@pytest.mark.parametrize("name", sorted(FUNCS))
def test_jit_and_grad_match_fd(name):
    fn, x0 = FUNCS[name]
    assert float(jax.jit(fn)(x0)) == pytest.approx(float(fn(x0)), rel=1e-13)
    g = float(jax.grad(fn)(jnp.float64(x0)))
    h = 1e-6 * max(abs(x0), 1e-3)
    fd = (float(fn(x0 + h)) - float(fn(x0 - h))) / (2 * h)
    assert math.isfinite(g)
    assert g == pytest.approx(fd, rel=1e-5, abs=1e-9 * max(1.0, abs(float(fn(x0)))))


def test_vmap_broadcast():
    th = jnp.linspace(-0.1, 0.1, 7)
    v = jax.jit(jax.vmap(lambda t: tg.rcs_flat_plate_m2(0.5, 0.3, 0.03, t)))(th)
    np.testing.assert_allclose(v, tg.rcs_flat_plate_m2(0.5, 0.3, 0.03, th), rtol=1e-14)
    ka = jnp.array([0.5, 1.0, 3.0])
    m = tg.rcs_sphere_mie_m2(ka / (2 * jnp.pi), 1.0)
    assert m.shape == (3,)
    assert tg.swerling_rcs_sample(jax.random.PRNGKey(0), jnp.array([1.0, 2.0]), 2, 3, 4).shape == (2, 3, 4)


_grad_ts_cyl = jax.jit(jax.grad(tg.target_strength_cylinder_db, argnums=(0, 1, 2, 3)))
_grad_plate = jax.jit(jax.grad(tg.rcs_flat_plate_m2, argnums=(0, 1, 2, 3)))
_grad_sinc = jax.jit(jax.grad(tg._sinc))
_grad_cdf3 = jax.jit(jax.grad(lambda s, m: tg.swerling_rcs_cdf(s, m, 3), argnums=(0, 1)))


@settings(max_examples=30, deadline=None)
@given(
    a=st.floats(0.01, 10.0),
    length=st.floats(0.01, 10.0),
    lam=st.floats(1e-3, 1.0),
    th=st.floats(-1.5, 1.5),
    s=st.floats(0.0, 100.0),
    x=st.floats(-1e-2, 1e-2),
)
def test_gradients_finite_over_domain(a, length, lam, th, s, x):
    assert all(math.isfinite(float(g)) for g in _grad_ts_cyl(a, length, lam, th))
    assert all(math.isfinite(float(g)) for g in _grad_plate(a, length, lam, th))
    assert all(math.isfinite(float(g)) for g in _grad_cdf3(s, a))
    # Taylor branch of sin(x)/x against the closed form derivative (cos x - sin x / x) / x
    d = float(_grad_sinc(x))
    mp.mp.dps = 40
    exact = float(mp.diff(lambda t: mp.sinc(t), mp.mpf(x))) if x != 0 else 0.0
    assert d == pytest.approx(exact, rel=1e-9, abs=1e-15)


@pytest.mark.parametrize(
    "call",
    [
        lambda: tg.rcs_sphere_optical_m2(0.0),
        lambda: tg.rcs_sphere_mie_m2(1e-4, 1.0),
        lambda: tg.rcs_sphere_mie_m2(100.0, 1.0),
        lambda: tg.rcs_flat_plate_m2(1.0, 1.0, 0.03, 2.0),
        lambda: tg.rcs_cylinder_m2(1.0, -1.0, 0.03),
        lambda: tg.laser_cross_section_lambertian_m2(1.5, 1.0),
        lambda: tg.dielectric_factor_k2(0.5),
        lambda: tg.rcs_dielectric_sphere_rayleigh_m2(1e-3, 0.03, 1.5),
        lambda: tg.target_strength_cylinder_db(0.3, 2.0, 0.01, math.pi / 2),
        lambda: tg.swerling_rcs_pdf(1.0, 1.0, 5),
        lambda: tg.swerling_rcs_pdf(1.0, 1.0, 0),
        lambda: tg.swerling_rcs_cdf(-1.0, 1.0, 1),
        lambda: tg.swerling_rcs_sample(jax.random.PRNGKey(0), 0.0, 1),
        lambda: tg.swerling_rcs_sample(jax.random.PRNGKey(0), 1.0, 1, n_pulses=0),
        lambda: tg.extended_target_rcs_m2(-0.1, 1.0),
    ],
)
def test_out_of_domain_raises(call):
    with pytest.raises(DomainError):
        call()
