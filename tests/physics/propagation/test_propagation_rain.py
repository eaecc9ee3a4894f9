"""ITU-R P.838-3 rain specific attenuation.

Reference numbers: ITU-R Study Group 3 validation examples (CG-3M3J-13-ValEx-Rev5.1, P.838-3
rows, as extracted in the public ITU-Rpy test data test_data/838/ITURP838-3_rain_specific_
attenuation.csv): elevation, f, R, tau -> k, alpha, gamma_R.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.physics.propagation import rain_attenuation_db_per_km, rain_coefficients

from helpers.function_checks import grad_and_central_difference, with_arg

VALEX = [  # el (deg), f (GHz), R (mm/h), tau (deg), k, alpha, gamma (dB/km)
    (31.07699124, 14.25, 26.48052, 0, 0.03975488, 1.12418043, 1.58130839),
    (40.232036, 14.25, 33.936232, 0, 0.04007624, 1.11804138, 2.06173213),
    (46.35969261, 14.25, 27.13586832, 0, 0.04030344, 1.11376017, 1.5920842),
    (31.07699124, 29, 26.48052, 0, 0.22106804, 0.95320005, 5.02180189),
    (52.67898486, 29, 78.2994993, 0, 0.21923716, 0.9464763, 13.59290086),
    (22.27833468, 14.25, 50.639304, 0, 0.03949319, 1.12925336, 3.32139638),
    (48.24117054, 14.25, 63.62668149, 90, 0.04226474, 1.07871664, 3.72901264),
    (85.80459566, 14.25, 99.13558978, 90, 0.04133039, 1.09499629, 6.34064598),
    (20.14335809, 14.25, 42.91007183, 90, 0.04319835, 1.0631531, 2.35032323),
    (48.24117054, 29, 63.62668149, 90, 0.21517927, 0.93116621, 10.28699163),
    (85.80459566, 29, 99.13558978, 90, 0.21737148, 0.93950825, 16.3183686),
    (20.14335809, 29, 42.91007183, 90, 0.21298877, 0.92265917, 6.83364556),
]


@pytest.mark.parametrize("el, f, r, tau, k, alpha, gamma", VALEX)
def test_p838_3_itu_validation_examples(el, f, r, tau, k, alpha, gamma):
    kk, aa = rain_coefficients(f * 1e9, float(tau), el)
    # the spreadsheet rounds k and alpha to 8 decimals: half a unit of the last digit
    assert float(kk) == pytest.approx(k, rel=1e-7, abs=5.01e-9)
    assert float(aa) == pytest.approx(alpha, rel=1e-7, abs=5.01e-9)
    assert float(rain_attenuation_db_per_km(f * 1e9, r, float(tau), el)) == pytest.approx(gamma, rel=1e-7)


def test_named_polarizations_equal_tilt_angles():
    for name, tau in [("horizontal", 0.0), ("vertical", 90.0), ("circular", 45.0)]:
        a = rain_attenuation_db_per_km(20e9, 25.0, name, 10.0)
        b = rain_attenuation_db_per_km(20e9, 25.0, tau, 10.0)
        assert float(a) == pytest.approx(float(b), rel=1e-14)


def test_circular_k_is_mean_of_h_and_v():
    # P.838-3 eq. (4) with tau = 45 deg: cos(2 tau) = 0 -> k = (kH + kV)/2 at any elevation
    kh, _ = rain_coefficients(35e9, "horizontal", 0.0)
    kv, _ = rain_coefficients(35e9, "vertical", 0.0)
    kc, _ = rain_coefficients(35e9, "circular", 30.0)
    assert float(kc) == pytest.approx(0.5 * float(kh + kv), rel=1e-14)


def test_zero_rain_zero_attenuation_and_finite_gradient():
    assert float(rain_attenuation_db_per_km(10e9, 0.0)) == 0.0
    assert np.isfinite(float(jax.grad(rain_attenuation_db_per_km, argnums=1)(10e9, 0.0)))


def test_jit_vmap_broadcast():
    f = jax.jit(rain_attenuation_db_per_km, static_argnums=2)
    assert float(f(29e9, 26.48052, "horizontal", 31.07699124)) == pytest.approx(5.02180189, rel=1e-7)
    rates = jnp.array([1.0, 10.0, 100.0])
    v = jax.vmap(lambda r: rain_attenuation_db_per_km(94e9, r))(rates)
    assert np.allclose(v, rain_attenuation_db_per_km(94e9, rates), rtol=1e-12)
    assert rain_attenuation_db_per_km(jnp.array([10e9, 35e9])[:, None], rates[None, :]).shape == (2, 3)


@pytest.mark.parametrize("argnum, x0, h", [(0, 35e9, 1e3), (1, 25.0, 1e-5), (3, 30.0, 1e-5)])
def test_gradient_matches_central_difference(argnum, x0, h):
    args = (35e9, 25.0, "vertical", 30.0)
    g, fd = grad_and_central_difference(lambda x: rain_attenuation_db_per_km(*with_arg(args, argnum, x)), x0, h)
    assert g == pytest.approx(fd, rel=1e-6)


def test_gradient_in_tilt_angle_matches_central_difference():
    g, fd = grad_and_central_difference(lambda tau: rain_attenuation_db_per_km(35e9, 25.0, tau, 10.0), 30.0, 1e-5)
    assert g == pytest.approx(fd, rel=1e-6)


@settings(max_examples=30, deadline=None)
@given(f=st.floats(1e9, 1e12), r=st.floats(0.01, 500.0), el=st.floats(0.0, 90.0), tau=st.floats(0.0, 90.0))
def test_gradient_finite_over_domain(f, r, el, tau):
    g = jax.grad(rain_attenuation_db_per_km, argnums=(0, 1, 2, 3))(f, r, tau, el)
    assert all(np.isfinite(float(x)) for x in g)


@pytest.mark.parametrize("args", [(0.5e9, 10.0), (2e12, 10.0), (10e9, -1.0), (10e9, 10.0, "diagonal"),
                                  (10e9, 10.0, "horizontal", 95.0)])
def test_out_of_domain_raises(args):
    with pytest.raises(DomainError):
        rain_attenuation_db_per_km(*args)
