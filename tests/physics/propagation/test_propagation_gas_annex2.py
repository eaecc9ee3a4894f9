"""ITU-R P.676-10 Annex 2 approximate specific attenuation (1-350 GHz).

The Recommendation states that its closed forms agree with the line-by-line calculation within
about ±15 % on average away from the line centres (P.676-10 Annex 2 §1). Here they are held to
that against the P.676-12 line-by-line of :func:`gas_attenuation_db_per_km` (itself checked
against the ITU-R SG3 validation examples in test_propagation_gas.py), and to the measured
agreement their docstring states. The branch formulas are checked by hand at rp = rt = 1, where
every xi_i is 1, and through the Recommendation's near-continuity at its branch edges.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense import Scene, evaluate
from diffsense.errors import DomainError
from diffsense.physics.propagation import (
    gas_attenuation_approx_db_per_km,
    gas_attenuation_db_per_km,
    oxygen_attenuation_approx_db_per_km,
    water_vapour_attenuation_approx_db_per_km,
)

F_GHZ = np.arange(1.0, 350.0 + 1e-9, 0.25)


def _relative_difference(pressure_hpa=1013.25, temperature_k=288.15, rho=7.5):
    approx = np.asarray(gas_attenuation_approx_db_per_km(F_GHZ * 1e9, pressure_hpa, temperature_k, rho))
    exact = np.asarray(gas_attenuation_db_per_km(F_GHZ * 1e9, pressure_hpa, temperature_k, rho))
    return approx - exact, approx / exact - 1.0


def test_standard_atmosphere_within_the_recommendations_15_percent():
    diff, rel = _relative_difference()
    # the Recommendation: about ±15 % on average; against P.676-12 even the worst point is inside
    assert np.max(np.abs(rel)) <= 0.15
    # the figures the docstring states: worst 12.3 %, mean 8.8 %, 1.1 dB/km, 0.016 dB/km below 50 GHz
    assert np.max(np.abs(rel)) == pytest.approx(0.1231, abs=5e-4)
    assert np.mean(np.abs(rel)) == pytest.approx(0.088, abs=1e-3)
    assert np.max(np.abs(diff)) == pytest.approx(1.10, abs=0.01)
    assert np.max(np.abs(diff[F_GHZ <= 50.0])) <= 0.0165
    # "generally within 0.1 dB/km" holds away from the 60 GHz band and the 183/325 GHz lines
    away = (F_GHZ <= 50.0) | ((F_GHZ >= 70.0) & (F_GHZ <= 170.0))
    assert np.max(np.abs(diff[away])) <= 0.3


@pytest.mark.parametrize("pressure_hpa, temperature_k, rho", [
    (500.0, 253.15, 2.0), (800.0, 273.15, 7.5), (1013.25, 303.15, 20.0), (1013.25, 288.15, 0.0)])
def test_other_atmospheres_within_the_stated_mean_and_worst(pressure_hpa, temperature_k, rho):
    _, rel = _relative_difference(pressure_hpa, temperature_k, rho)
    assert np.mean(np.abs(rel)) <= 0.24
    assert np.max(np.abs(rel)) <= 0.35


def test_branches_by_hand_at_unit_pressure_and_temperature_ratios():
    # rp = 1013/1013 = 1 and rt = 288/(273 + 15) = 1: every phi(...) is its scale factor
    p, t = 1013.0, 288.15
    o = lambda f: float(oxygen_attenuation_approx_db_per_km(f * 1e9, p, t, 0.0))  # noqa: E731
    assert o(30.0) == pytest.approx((7.2 / (30**2 + 0.34) + 0.62 / (24**1.16 + 0.83)) * 30**2 * 1e-3, rel=1e-13)
    assert o(56.0) == pytest.approx(math.exp(math.log(2.192) / 24 * (-2) * (-4) - math.log(12.59) / 8 * 2 * (-4)
                                             + math.log(15.0) / 12 * 2 * (-2)), rel=1e-13)
    assert o(61.0) == pytest.approx(15.0 + (14.28 - 15.0) / 2, rel=1e-13)
    assert o(65.0) == pytest.approx(math.exp(math.log(14.28) / 8 * 1 * (-1) - math.log(6.819) / 4 * 3 * (-1)
                                             + math.log(1.908) / 8 * 3 * 1), rel=1e-13)
    assert o(94.0) == pytest.approx((3.02e-4 + 0.283 / ((94 - 118.75) ** 2 + 2.91)
                                     + 0.502 * (1 - 0.0163 * 28) / (28**1.4346 + 1.15)) * 94**2 * 1e-3, rel=1e-13)
    assert o(200.0) == pytest.approx((3.02e-4 / (1 + 1.9e-5 * 200**1.5) + 0.283 / ((200 - 118.75) ** 2 + 2.91))
                                     * 200**2 * 1e-3 - 0.00306, rel=1e-13)
    # water vapour at 22.235 GHz, rho = 7.5: eta1 = 0.955 + 0.045 = 1, eta2 = 0.735 + 0.0353 * 7.5
    f, e1, e2 = 22.235, 1.0, 0.735 + 0.0353 * 7.5
    g = lambda fi: 1 + ((f - fi) / (f + fi)) ** 2  # noqa: E731
    terms = (3.98 / 9.42 * g(22.0) + 11.96 / ((f - 183.31) ** 2 + 11.14) + 0.081 / ((f - 321.226) ** 2 + 6.29)
             + 3.66 / ((f - 325.153) ** 2 + 9.22) + 25.37 / (f - 380) ** 2 + 17.4 / (f - 448) ** 2
             + 844.6 / (f - 557) ** 2 * g(557.0) + 290 / (f - 752) ** 2 * g(752.0) + 8.3328e4 * e2 / (f - 1780) ** 2 * g(1780.0))
    w = float(water_vapour_attenuation_approx_db_per_km(f * 1e9, p, t, 7.5))
    assert w == pytest.approx(terms * e1 * f**2 * 7.5 * 1e-4, rel=1e-13)


@pytest.mark.parametrize("edge, jump", [(54.0, 0.004), (60.0, 1e-9), (62.0, 1e-9), (66.0, 0.003), (120.0, 0.007)])
def test_branch_edges_are_nearly_continuous(edge, jump):
    below = float(oxygen_attenuation_approx_db_per_km(edge * 1e9))
    above = float(oxygen_attenuation_approx_db_per_km(edge * 1e9 * (1 + 1e-12)))
    assert abs(above / below - 1.0) <= jump


def test_dry_air_has_no_water_vapour_term_and_total_is_the_sum():
    assert float(water_vapour_attenuation_approx_db_per_km(183.31e9, 1013.25, 288.15, 0.0)) == 0.0
    f = jnp.array([5e9, 57e9, 183e9])
    total = gas_attenuation_approx_db_per_km(f, 900.0, 280.0, 5.0)
    parts = oxygen_attenuation_approx_db_per_km(f, 900.0, 280.0, 5.0) + water_vapour_attenuation_approx_db_per_km(f, 900.0, 280.0, 5.0)
    np.testing.assert_allclose(total, parts, rtol=1e-15)


def test_jit_and_gradients_finite_across_every_branch():
    fn = lambda f, p, t, rho: gas_attenuation_approx_db_per_km(f, p, t, rho)  # noqa: E731
    f = jnp.array([1e9, 54e9, 55e9, 60e9, 61e9, 62e9, 66e9, 90e9, 120e9, 121e9, 350e9])
    np.testing.assert_allclose(jax.jit(fn)(f, 1013.25, 288.15, 7.5), fn(f, 1013.25, 288.15, 7.5), rtol=1e-14)
    for x in f:
        grads = jax.grad(fn, argnums=(0, 1, 2, 3))(x, 1013.25, 288.15, 7.5)
        assert all(np.isfinite(float(g)) for g in grads)
    # d gamma / d f against a central difference inside a branch (94 GHz)
    h = 1e3
    fd = (float(fn(94e9 + h, 1013.25, 288.15, 7.5)) - float(fn(94e9 - h, 1013.25, 288.15, 7.5))) / (2 * h)
    assert float(jax.grad(fn)(94e9, 1013.25, 288.15, 7.5)) == pytest.approx(fd, rel=1e-6)


def test_out_of_domain_raises():
    with pytest.raises(DomainError, match="freq_hz"):
        gas_attenuation_approx_db_per_km(351e9)
    with pytest.raises(DomainError, match="temperature_k"):
        gas_attenuation_approx_db_per_km(10e9, 1013.25, 100.0)
    # the same physical domain as the line-by-line model: e = rho T / 216.7 below the pressure
    # (here e = 50 · 300 / 216.7 = 69.2 hPa against 50 hPa)
    with pytest.raises(DomainError, match="Annex 2 .*partial pressure"):
        gas_attenuation_approx_db_per_km(10e9, 50.0, 300.0, 50.0)
    assert np.isfinite(float(gas_attenuation_approx_db_per_km(10e9, 80.0, 300.0, 50.0)))


def test_radar_option_itu_p676_approx_uses_the_closed_forms():
    params = dict(range_m=30e3, peak_power_w=5e6, gain_db=36, freq_hz=10e9, rcs_m2=1, pulse_width_s=2e-6,
                  bandwidth_hz=0.613 / 2e-6, noise_figure_db=4, prf_hz=360, n_pulses=10,
                  beamwidth_az_deg=1.25, beamwidth_el_deg=4, detectability_db=8.2)
    options = {"antenna": "specified", "detectability": "given"}
    loss = {}
    for model in ("itu_p676", "itu_p676_approx"):
        ev = evaluate(Scene("radar", ["gas"], dict(options, gas_model=model)), params, pressure_hpa=1000.0,
                      water_vapour_g_m3=10.0, air_temperature_k=290.0)
        loss[model] = float(ev.budget.as_dict()["gas_attenuation_db"])
    # two-way loss -2 gamma R over 30 km, gamma of each model at the same atmosphere
    for model, fn in (("itu_p676", gas_attenuation_db_per_km), ("itu_p676_approx", gas_attenuation_approx_db_per_km)):
        assert loss[model] == pytest.approx(-2 * 30 * float(fn(10e9, 1000.0, 290.0, 10.0)), rel=1e-12)
