"""ITU-R P.676-12 Annex 1 gaseous attenuation.

Reference numbers: ITU-R Study Group 3 validation examples (CG-3M3J-13-ValEx-Rev5,
sheet "P676-12 SpAtt"; rows as extracted in the public ITU-Rpy test data
test_data/676/ITURP676-12_gamma.csv). Those examples give the *dry-air* pressure
P = 1013.25 hPa, T = 288.15 K, rho = 7.5 g/m^3; our API takes total pressure, so the tests pass
P + e with e = rho T / 216.7.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.physics.propagation import (
    gas_attenuation_db_per_km,
    oxygen_attenuation_db_per_km,
    water_vapour_attenuation_db_per_km,
)

from helpers.function_checks import grad_and_central_difference, with_arg

E_HPA = 7.5 * 288.15 / 216.7
P_TOTAL = 1013.25 + E_HPA

# f (GHz), gamma_o, gamma_w (dB/km) — ITU-R SG3 validation examples for P.676-12
VALEX = [
    (1, 0.005388658, 5.09e-05),
    (3, 0.00707596, 0.000462793),
    (10, 0.008224417, 0.005974125),
    (12, 0.008698264, 0.009535388),
    (20, 0.01188355, 0.097047305),
    (22, 0.013130223, 0.174207033),
    (23, 0.013847278, 0.180441698),
    (50, 0.277268639, 0.111158547),
    (55, 4.193281608, 0.131674477),
    (60, 14.6234748, 0.154841841),
    (61, 15.00715909, 0.159826896),
    (65, 3.808803518, 0.181534841),
    (90, 0.038869711, 0.341973394),
    (118, 1.134866202, 0.605921953),
    (119, 1.306379041, 0.61799348),
    (130, 0.041509084, 0.751844704),
    (183, 0.012733909, 27.66500831),
    (184, 0.012775319, 27.02483793),
    (250, 0.018753887, 3.077989748),
]


@pytest.mark.parametrize("f_ghz, g_o, g_w", VALEX)
def test_p676_12_itu_validation_examples(f_ghz, g_o, g_w):
    o = float(oxygen_attenuation_db_per_km(f_ghz * 1e9, P_TOTAL, 288.15, 7.5))
    w = float(water_vapour_attenuation_db_per_km(f_ghz * 1e9, P_TOTAL, 288.15, 7.5))
    t = float(gas_attenuation_db_per_km(f_ghz * 1e9, P_TOTAL, 288.15, 7.5))
    # the spreadsheet values carry 7-10 significant digits (5.09e-05: 3 digits)
    rtol_w = 2e-4 if f_ghz == 1 else 1e-6
    assert o == pytest.approx(g_o, rel=1e-6)
    assert w == pytest.approx(g_w, rel=rtol_w)
    assert t == pytest.approx(g_o + g_w, rel=1e-6)


def test_standard_atmosphere_60ghz_oxygen_about_15_db_per_km():
    # P.676-12 Fig. 1/2: the sea-level 60 GHz oxygen complex peaks near 15 dB/km
    # (ValEx: 14.62 dB/km at 60 GHz, 15.01 at 61 GHz).
    g = np.asarray(oxygen_attenuation_db_per_km(jnp.linspace(58e9, 62e9, 81)))
    assert 14.5 < g.max() < 15.6


def test_22ghz_water_line_peak_location():
    # Water-vapour line at 22.235080 GHz (Table 2): the pressure-broadened peak of gamma_w at
    # sea level lies within the line width (~3 GHz) of the line centre.
    f = jnp.linspace(18e9, 27e9, 901)
    w = np.asarray(water_vapour_attenuation_db_per_km(f))
    f_peak = float(f[int(np.argmax(w))]) / 1e9
    assert abs(f_peak - 22.235) < 0.5


def test_dry_air_has_no_water_vapour_attenuation():
    assert float(water_vapour_attenuation_db_per_km(22e9, 1013.25, 288.15, 0.0)) == 0.0


def test_jit_matches_eager():
    f = jax.jit(gas_attenuation_db_per_km)
    assert float(f(35e9, 1000.0, 280.0, 5.0)) == pytest.approx(
        float(gas_attenuation_db_per_km(35e9, 1000.0, 280.0, 5.0)), rel=1e-12)


def test_vmap_and_broadcast():
    fs = jnp.array([10e9, 60e9, 183e9])
    v = jax.vmap(lambda f: gas_attenuation_db_per_km(f))(fs)
    b = gas_attenuation_db_per_km(fs)
    assert v.shape == (3,) and np.allclose(v, b, rtol=1e-12)
    grid = gas_attenuation_db_per_km(fs[:, None], 1013.25, jnp.array([270.0, 300.0])[None, :])
    assert grid.shape == (3, 2)


@pytest.mark.parametrize("argnum, x0, h", [(0, 35e9, 1e3), (1, 900.0, 1e-3), (2, 290.0, 1e-4), (3, 10.0, 1e-5)])
def test_gradient_matches_central_difference(argnum, x0, h):
    args = (35e9, 900.0, 290.0, 10.0)
    g, fd = grad_and_central_difference(lambda x: gas_attenuation_db_per_km(*with_arg(args, argnum, x)), x0, h)
    assert g == pytest.approx(fd, rel=1e-6, abs=1e-14)


@settings(max_examples=30, deadline=None)
@given(f=st.floats(1e9, 1e12), p=st.floats(100.0, 1100.0), t=st.floats(200.0, 330.0), rho=st.floats(0.0, 20.0))
def test_gradient_finite_over_domain(f, p, t, rho):
    g = jax.grad(gas_attenuation_db_per_km, argnums=(0, 1, 2, 3))(f, p, t, rho)
    assert all(np.isfinite(float(x)) for x in g)


@pytest.mark.parametrize("kwargs", [
    dict(freq_hz=0.5e9), dict(freq_hz=1.1e12), dict(freq_hz=10e9, pressure_hpa=0.0),
    dict(freq_hz=10e9, temperature_k=100.0), dict(freq_hz=10e9, water_vapour_g_m3=-1.0),
    dict(freq_hz=10e9, pressure_hpa=5.0, water_vapour_g_m3=20.0),
])
def test_out_of_domain_raises(kwargs):
    with pytest.raises(DomainError):
        gas_attenuation_db_per_km(**kwargs)
