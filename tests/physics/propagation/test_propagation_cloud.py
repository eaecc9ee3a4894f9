"""ITU-R P.840-7 cloud/fog specific attenuation coefficient K_l.

Sources: (1) ITU-R SG3 validation examples for P.840-8 (CG-3M3J-13-ValEx-Rev5.1, as extracted
in ITU-Rpy test_data/840/ITURP840-8_cloud_attenuation.csv): A_c = L K_l(f, 273.15 K)/sin(el)
with the same L at a site and probability, so A_c(29 GHz)/A_c(14.25 GHz) = K_l(29)/K_l(14.25)
(P.840-8 evaluates K_l at 273.15 K with the same double-Debye equations as P.840-7).
(2) An independent 50-digit mpmath evaluation of P.840-7 eqs. (2)-(10).
"""

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.physics.propagation import cloud_attenuation_coefficient, cloud_attenuation_db_per_km

from helpers.function_checks import grad_and_central_difference, with_arg

# (A_c at 29 GHz, A_c at 14.25 GHz) at the same site and exceedance probability
VALEX_PAIRS = [(1.77246907, 0.45516982), (1.02564344, 0.2633851), (2.43180268, 0.62448661),
               (4.70577375, 1.20844208), (3.00280519, 0.77111998), (2.669786, 0.68560069)]


@pytest.mark.parametrize("a29, a14", VALEX_PAIRS)
def test_kl_frequency_ratio_matches_p840_validation_examples(a29, a14):
    r = cloud_attenuation_coefficient(29e9, 273.15) / cloud_attenuation_coefficient(14.25e9, 273.15)
    # spreadsheet values carry 8-9 significant digits
    assert float(r) == pytest.approx(a29 / a14, rel=1e-7)


def _kl_mpmath(f_ghz, t_k):
    mp.mp.dps = 50
    f, theta = mp.mpf(f_ghz), mp.mpf(300) / mp.mpf(t_k)
    e0 = mp.mpf("77.66") + mp.mpf("103.3") * (theta - 1)
    e1 = mp.mpf("0.0671") * e0
    e2 = mp.mpf("3.52")
    fp = mp.mpf("20.20") - 146 * (theta - 1) + 316 * (theta - 1) ** 2
    fs = mp.mpf("39.8") * fp
    epp = f * (e0 - e1) / (fp * (1 + (f / fp) ** 2)) + f * (e1 - e2) / (fs * (1 + (f / fs) ** 2))
    ep = (e0 - e1) / (1 + (f / fp) ** 2) + (e1 - e2) / (1 + (f / fs) ** 2) + e2
    eta = (2 + ep) / epp
    return mp.mpf("0.819") * f / (epp * (1 + eta**2))


@pytest.mark.parametrize("f_ghz, t_k", [(5, 273.15), (30, 273.15), (94, 283.15), (300, 293.15), (1000, 253.15)])
def test_kl_matches_mpmath_evaluation_of_p840_7(f_ghz, t_k):
    assert float(cloud_attenuation_coefficient(f_ghz * 1e9, t_k)) == pytest.approx(float(_kl_mpmath(f_ghz, t_k)), rel=1e-12)


def test_kl_rayleigh_low_frequency_scales_as_f_squared():
    # For f << f_p (~9 GHz at 0 C) K_l -> const * f^2 (Debye loss ~ f, K_l ~ f eps''/|eps+2|^2)
    r = cloud_attenuation_coefficient(0.2e9, 273.15) / cloud_attenuation_coefficient(0.1e9, 273.15)
    assert float(r) == pytest.approx(4.0, rel=2e-3)


def test_attenuation_is_kl_times_liquid_water():
    assert float(cloud_attenuation_db_per_km(35e9, 0.5, 280.0)) == pytest.approx(
        0.5 * float(cloud_attenuation_coefficient(35e9, 280.0)), rel=1e-14)


def test_jit_vmap_broadcast():
    f = jax.jit(cloud_attenuation_coefficient)
    assert float(f(30e9, 273.15)) == pytest.approx(float(_kl_mpmath(30, 273.15)), rel=1e-12)
    fs = jnp.array([10e9, 35e9, 94e9])
    v = jax.vmap(lambda x: cloud_attenuation_coefficient(x, 273.15))(fs)
    assert np.allclose(v, cloud_attenuation_coefficient(fs, 273.15), rtol=1e-13)
    assert cloud_attenuation_db_per_km(fs[:, None], jnp.array([0.1, 1.0]), 273.15).shape == (3, 2)


@pytest.mark.parametrize("argnum, x0, h", [(0, 35e9, 1e3), (1, 280.0, 1e-4)])
def test_gradient_matches_central_difference(argnum, x0, h):
    args = (35e9, 280.0)
    g, fd = grad_and_central_difference(lambda x: cloud_attenuation_coefficient(*with_arg(args, argnum, x)), x0, h)
    assert g == pytest.approx(fd, rel=1e-6)


@settings(max_examples=30, deadline=None)
@given(f=st.floats(1e8, 1e12), t=st.floats(233.15, 323.15), m=st.floats(0.0, 10.0))
def test_gradient_finite_over_domain(f, t, m):
    g = jax.grad(cloud_attenuation_db_per_km, argnums=(0, 1, 2))(f, m, t)
    assert all(np.isfinite(float(x)) for x in g)


@pytest.mark.parametrize("args", [(1e7, 273.15), (2e12, 273.15), (30e9, 200.0), (30e9, 400.0)])
def test_out_of_domain_raises(args):
    with pytest.raises(DomainError):
        cloud_attenuation_coefficient(*args)
    with pytest.raises(DomainError):
        cloud_attenuation_db_per_km(30e9, -0.1, 273.15)
