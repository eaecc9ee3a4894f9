"""Antennas and apertures against the book's worked examples and closed forms.

Book: Brooker, *Introduction to Sensors for Ranging and Imaging* — 8.16.7/8.16.9 (ore-pass
antenna, worked example 3), 12.8 eq. 12.43 (side-scan sonar directivity, worked example 4),
12.5.1 eqs 12.29-12.32 (phased arrays, worked_examples section 8).
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401
from diffsense.physics import antennas as an
from diffsense.errors import DomainError

BOOK_C = 3e8  # the book rounds c to 3e8 m/s


def test_ore_pass_antenna_gain_book_8_16_9():
    # Worked example 3: 250 mm, rho = 0.7, 94 GHz -> G = 42,432 (46.2 dB) with c = 3e8.
    # The book's 42,432 follows from lambda rounded to 3.19 mm; with lambda = 3e8/94e9
    # exactly the gain is 42,393 (0.09 % lower). Both give 46.3 dB to 0.05 dB.
    area = an.circular_aperture_area_m2(0.25)
    g_rounded = float(an.gain_from_aperture(area, 3.19e-3, 0.7))
    assert g_rounded == pytest.approx(42432, abs=1.0)
    lam = float(an.wavelength_m(94e9, BOOK_C))
    g = float(an.gain_from_aperture(area, lam, 0.7))
    assert g == pytest.approx(42432, rel=1e-3)
    assert float(an.gain_db(g)) == pytest.approx(46.2, abs=0.1)


def test_ore_pass_beamwidth_book_8_16_8():
    # theta = 70 lambda / d = 0.89 deg for 250 mm at 94 GHz.
    lam = float(an.wavelength_m(94e9, BOOK_C))
    assert float(an.beamwidth_book_deg(lam, 0.25)) == pytest.approx(0.89, abs=0.005)


@pytest.mark.parametrize("freq_ghz, diameter_m", [(10.0, 2.1), (35.0, 0.6), (77.0, 0.27), (94.0, 0.22)])
def test_ore_pass_table_8_10_diameters(freq_ghz, diameter_m):
    # Table 8.10 lists d = 70 lambda / theta for a 1.0 deg beam (10 GHz: 0.03 m -> 2.1 m).
    lam = float(an.wavelength_m(freq_ghz * 1e9, BOOK_C))
    d = float(an.aperture_diameter_for_beamwidth_book_m(lam, 1.0))
    assert d == pytest.approx(diameter_m, abs=0.006)  # table prints 2 significant figures


def test_ore_pass_ultrasound_wavelength_book_8_16_2():
    # A 1 m transducer with a 1.1 deg beam needs lambda = theta d / 70 = 0.016 m.
    d = float(an.aperture_diameter_for_beamwidth_book_m(0.0157, 1.1))
    assert d == pytest.approx(1.0, rel=0.01)


def test_side_scan_sonar_directivity_book_12_43():
    # Worked example 4: G = 4 pi 57.3^2 / (1.5 x 60) = 458.4 (the book's 57.3 for 180/pi;
    # exact conversion 458.37).
    g = float(an.directivity_from_beamwidths_deg(1.5, 60.0))
    assert g == pytest.approx(458.4, abs=0.1)
    assert float(an.directivity_index_db(g)) == pytest.approx(26.6, abs=0.05)
    g_rad = float(an.directivity_from_beamwidths(math.radians(1.5), math.radians(60.0)))
    assert g_rad == pytest.approx(g, rel=1e-14)
    # on-axis intensity 47.7 W/m^2 x 458.4 = 21,864 W/m^2
    assert 1500 * 0.4 / (4 * math.pi) * g == pytest.approx(21864, rel=2e-3)


def test_gain_aperture_inverse_and_effective_aperture():
    lam = 0.03
    g = float(an.gain_from_aperture(2.0, lam, 0.6))
    assert float(an.aperture_area_from_gain_m2(g, lam, 0.6)) == pytest.approx(2.0, rel=1e-14)
    assert float(an.effective_aperture_m2(g, lam)) == pytest.approx(1.2, rel=1e-14)


def test_beamwidth_factors():
    assert float(an.beamwidth_rad(0.01, 1.0)) == pytest.approx(0.00886, rel=1e-12)
    assert float(an.beamwidth_rad(0.01, 1.0, an.UNIFORM_CIRCULAR_BEAMWIDTH_FACTOR)) == pytest.approx(0.0102, rel=1e-12)
    # The uniform line source's 0.886: |sinc|^2 = 1/2 at u = 1.3916 rad -> 2u/pi = 0.8859.
    from scipy.optimize import brentq

    u = brentq(lambda v: (math.sin(v) / v) ** 2 - 0.5, 1.0, 2.0)
    assert 2 * u / math.pi == pytest.approx(an.UNIFORM_RECTANGULAR_BEAMWIDTH_FACTOR, abs=5e-4)
    # The uniform circular aperture: (2 J1(v)/v)^2 = 1/2 at v = 1.6163 -> 2v/pi = 1.029.
    from scipy.special import j1

    v = brentq(lambda w: (2 * j1(w) / w) ** 2 - 0.5, 1.0, 2.5)
    assert 2 * v / math.pi == pytest.approx(an.UNIFORM_CIRCULAR_BEAMWIDTH_FACTOR, abs=0.01)


def test_phased_array_gain_and_beamwidth_book_12_30_12_31():
    lam = 0.03
    g0 = float(an.phased_array_gain(1.0, lam, 0.0))
    assert g0 == pytest.approx(4 * math.pi / lam**2, rel=1e-14)
    assert float(an.phased_array_gain(1.0, lam, math.radians(60.0))) == pytest.approx(0.5 * g0, rel=1e-12)
    bw0 = float(an.phased_array_beamwidth_rad(lam, 64, lam / 2, 0.0))
    assert bw0 == pytest.approx(0.886 * lam / (64 * lam / 2), rel=1e-14)
    assert float(an.phased_array_beamwidth_rad(lam, 64, lam / 2, math.radians(60.0))) == pytest.approx(2 * bw0, rel=1e-12)
    # cosine-on-pedestal taper with 2a1/a0 = 1 widens by 1.636 (eq. 12.32)
    assert float(an.phased_array_beamwidth_rad(lam, 64, lam / 2, 0.0, 0.999999)) == pytest.approx(1.636 * bw0, rel=1e-5)


def test_phased_array_beamwidth_matches_array_factor_numerically():
    # Half-power width of |sin(N psi/2)/(N sin(psi/2))|^2, psi = 2 pi d/lambda (sin th - sin th0).
    n, d_over_lam, th0 = 32, 0.5, math.radians(30.0)
    from scipy.optimize import brentq

    def af(th):
        psi = 2 * math.pi * d_over_lam * (math.sin(th) - math.sin(th0))
        if abs(psi) < 1e-12:
            return 1.0
        return (math.sin(n * psi / 2) / (n * math.sin(psi / 2))) ** 2

    hi = brentq(lambda t: af(t) - 0.5, th0, th0 + 0.2)
    lo = brentq(lambda t: af(t) - 0.5, th0 - 0.2, th0)
    approx = float(an.phased_array_beamwidth_rad(1.0, n, d_over_lam, th0))
    assert approx == pytest.approx(hi - lo, rel=0.01)


def test_grating_lobe_condition():
    lam = 0.03
    assert float(an.grating_lobe_free_spacing_m(lam, 0.0)) == pytest.approx(lam, rel=1e-15)
    assert float(an.grating_lobe_free_spacing_m(lam, math.pi / 2)) == pytest.approx(lam / 2, rel=1e-15)
    # d = lambda/2 is free at any scan (Brooker 12.4); margin >= 0 at 90 deg.
    assert float(an.grating_lobe_margin(lam / 2, lam, math.pi / 2)) == pytest.approx(0.0, abs=1e-15)
    # Check against the lobe position: sin(theta_g) = sin(theta0) - lambda/d must stay < -1.
    d, th0 = 0.6 * lam, math.radians(40.0)
    margin = float(an.grating_lobe_margin(d, lam, th0))
    lobe_in_space = math.sin(th0) - lam / d >= -1.0
    assert (margin > 0) == (not lobe_in_space)


def test_beam_fill_ratio():
    # 1 m^2 at 100 m with a 0.02 x 0.02 rad beam: footprint pi/4 x 4 m^2 = pi m^2.
    assert float(an.beam_fill_ratio(1.0, 100.0, 0.02, 0.02)) == pytest.approx(1 / math.pi, rel=1e-14)
    assert float(an.beam_fill_ratio(100.0, 100.0, 0.02, 0.02)) == 1.0


FUNCS = {
    "gain_area": (lambda x: an.gain_from_aperture(x, 0.0032, 0.7), 0.05),
    "gain_lambda": (lambda x: an.gain_from_aperture(0.05, x, 0.7), 0.0032),
    "gain_db": (an.gain_db, 42432.0),
    "area_from_gain": (lambda x: an.aperture_area_from_gain_m2(x, 0.0032, 0.7), 1e4),
    "eff_aperture": (lambda x: an.effective_aperture_m2(x, 0.0032), 1e4),
    "beamwidth": (lambda x: an.beamwidth_rad(0.0032, x), 0.25),
    "book_bw": (lambda x: an.beamwidth_book_deg(0.0032, x), 0.25),
    "book_d": (lambda x: an.aperture_diameter_for_beamwidth_book_m(0.0032, x), 1.1),
    "directivity": (lambda x: an.directivity_from_beamwidths(x, 0.03), 0.02),
    "directivity_deg": (lambda x: an.directivity_from_beamwidths_deg(x, 60.0), 1.5),
    "di": (an.directivity_index_db, 458.4),
    "pa_gain": (lambda x: an.phased_array_gain(1.0, 0.03, x), 0.5),
    "pa_bw": (lambda x: an.phased_array_beamwidth_rad(0.03, 64.0, 0.015, x), 0.5),
    "pa_bw_n": (lambda x: an.phased_array_beamwidth_rad(0.03, x, 0.015, 0.3), 64.0),
    "grating": (lambda x: an.grating_lobe_margin(0.015, 0.03, x), 0.7),
    "fill": (lambda x: an.beam_fill_ratio(x, 100.0, 0.02, 0.02), 1.0),
    "wavelength": (lambda x: an.wavelength_m(x), 94e9),
}


@pytest.mark.parametrize("name", sorted(FUNCS))
def test_jit_and_grad_match_fd(name):
    fn, x0 = FUNCS[name]
    assert float(jax.jit(fn)(x0)) == pytest.approx(float(fn(x0)), rel=1e-14)
    g = float(jax.grad(fn)(jnp.float64(x0)))
    h = 1e-6 * abs(x0)
    fd = (float(fn(x0 + h)) - float(fn(x0 - h))) / (2 * h)
    assert math.isfinite(g)
    assert g == pytest.approx(fd, rel=1e-6)


def test_vmap_broadcast():
    d = jnp.array([0.2, 0.25, 0.3])
    g = jax.jit(jax.vmap(lambda x: an.gain_from_aperture(an.circular_aperture_area_m2(x), 0.0032, 0.7)))(d)
    np.testing.assert_allclose(g, an.gain_from_aperture(an.circular_aperture_area_m2(d), 0.0032, 0.7), rtol=1e-14)
    th = jnp.linspace(-1.0, 1.0, 5)
    assert an.phased_array_gain(jnp.array([[1.0], [2.0]]), 0.03, th).shape == (2, 5)


_grad_pa = jax.jit(jax.grad(lambda lam, n, d, th: an.phased_array_beamwidth_rad(lam, n, d, th), argnums=(0, 1, 2, 3)))
_grad_gl = jax.jit(jax.grad(an.grating_lobe_margin, argnums=(0, 1, 2)))


@settings(max_examples=30, deadline=None)
@given(
    lam=st.floats(1e-4, 10.0),
    n=st.floats(2.0, 1e4),
    d=st.floats(1e-4, 10.0),
    th=st.floats(-1.4, 1.4),
)
def test_array_gradients_finite(lam, n, d, th):
    assert all(math.isfinite(float(x)) for x in _grad_pa(lam, n, d, th))
    assert all(math.isfinite(float(x)) for x in _grad_gl(d, lam, th))


@pytest.mark.parametrize(
    "call",
    [
        lambda: an.gain_from_aperture(0.0, 0.01),
        lambda: an.gain_from_aperture(1.0, 0.01, 1.2),
        lambda: an.gain_from_aperture(1.0, -0.01),
        lambda: an.wavelength_m(0.0),
        lambda: an.beamwidth_rad(0.01, 0.0),
        lambda: an.directivity_from_beamwidths_deg(0.0, 10.0),
        lambda: an.directivity_index_db(0.0),
        lambda: an.phased_array_gain(1.0, 0.03, 2.0),
        lambda: an.phased_array_beamwidth_rad(0.03, 1.0, 0.015, 0.0),
        lambda: an.phased_array_beamwidth_rad(0.03, 16.0, 0.015, 1.5),
        lambda: an.grating_lobe_margin(0.0, 0.03, 0.0),
        lambda: an.beam_fill_ratio(-1.0, 100.0, 0.02, 0.02),
        lambda: an.aperture_diameter_for_beamwidth_book_m(0.003, float("nan")),
    ],
)
def test_out_of_domain_raises(call):
    with pytest.raises(DomainError):
        call()
