"""The radiometer chain (Scene("radiometer", ...)) through the public evaluate().

References used by the assertions:
- An independent 30-digit mpmath evaluation of the documented model (Ulaby, Moore & Fung 1981
  Vol. I ch. 4–6): Planck brightness, sky brightness of an absorbing atmosphere with the secant
  law, apparent temperatures of a metal target and of ground reflecting the sky, path
  transmission and emission, Gaussian-beam fill, antenna temperature with main-beam efficiency,
  total-power and unbalanced-Dicke sensitivity, Gaussian-shift detection. Specific attenuations
  (ITU-R P.676-12, P.838-3, P.840-7) come from diffsense.physics.propagation, validated against the
  ITU-R data in their own test files.
- Brooker §8.16.9 (worked example 3): 250 mm antenna, aperture efficiency 0.7, 94 GHz:
  G = 42,432 (46.2 dB) and θ3dB = 0.89°.
- A balanced Dicke radiometer is twice as noisy as a total-power radiometer without gain
  fluctuations (K = 2; rfessentials.com radiometer-equation note; Ulaby et al. ch. 6).
"""

import math

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401
from helpers.chain_checks import WeightedOutputs
from diffsense.errors import DomainError
from diffsense.scene import complete_parameters, evaluate, output_table, parameter_table
from diffsense.sensors.parts import traced_parts
from diffsense.physics.constants import BOLTZMANN_J_K, PLANCK_J_S, SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation import (
    cloud_attenuation_db_per_km,
    gas_attenuation_db_per_km,
    oxygen_attenuation_db_per_km,
    rain_attenuation_db_per_km,
    water_vapour_attenuation_db_per_km,
)
from diffsense.scene import Scene

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)
HF_K = mp.mpf(PLANCK_J_S) / mp.mpf(BOLTZMANN_J_K)

PLAIN = Scene("radiometer")
WEATHER = Scene("radiometer", ["gas", "rain", "fog"])
DICKE = Scene("radiometer", ["gas", "rain", "fog"], {"receiver": "dicke"})


def B(t, f):
    return HF_K * f / mp.expm1(HF_K * f / mp.mpf(t))


def hand_model(scene, p):
    """The chain's documented equations, evaluated independently in mpmath."""
    p = {k: mp.mpf(float(v)) for k, v in p.items()}
    f = p["freq_hz"]
    args = (float(f), float(p["pressure_hpa"]), float(p["air_temperature_k"]), float(p["water_vapour_g_m3"]))
    zen_db = (mp.mpf(float(oxygen_attenuation_db_per_km(*args))) * p["oxygen_equivalent_height_m"]
              + mp.mpf(float(water_vapour_attenuation_db_per_km(*args))) * p["water_vapour_equivalent_height_m"]) / 1000
    path_db = mp.mpf(0)
    r = p["range_m"]
    if scene.has("gas"):
        path_db += mp.mpf(float(gas_attenuation_db_per_km(*args))) * r / 1000
    if scene.has("rain"):
        g = mp.mpf(float(rain_attenuation_db_per_km(float(f), float(p["rain_rate_mm_h"]), "circular")))
        zen_db += g * p["rain_height_m"] / 1000
        path_db += g * r / 1000
    if scene.has("fog"):
        g = mp.mpf(float(cloud_attenuation_db_per_km(float(f), float(p["fog_liquid_water_g_m3"]), float(p["air_temperature_k"]))))
        zen_db += g * p["fog_thickness_m"] / 1000
        path_db += g * r / 1000
    tau_sky = zen_db * mp.log(10) / 10 / mp.sin(mp.radians(p["depression_angle_deg"]))
    t_sky = B(p["sky_mean_radiating_temperature_k"], f) * (1 - mp.e**-tau_sky) + B(p["cosmic_temperature_k"], f) * mp.e**-tau_sky
    t_t = p["target_emissivity"] * B(p["target_temperature_k"], f) + (1 - p["target_emissivity"]) * t_sky
    t_g = p["ground_emissivity"] * B(p["ground_temperature_k"], f) + (1 - p["ground_emissivity"]) * t_sky
    tau = path_db * mp.log(10) / 10
    t_air = B(p["air_temperature_k"], f)
    t_t_s = t_t * mp.e**-tau + t_air * (1 - mp.e**-tau)
    t_g_s = t_g * mp.e**-tau + t_air * (1 - mp.e**-tau)
    lam = mp.mpf(SPEED_OF_LIGHT_M_S) / f
    omega_a = lam**2 / (p["aperture_efficiency"] * mp.pi * p["antenna_diameter_m"] ** 2 / 4)
    omega_m = p["main_beam_efficiency"] * omega_a
    fill = 1 - mp.e ** (-(p["target_area_m2"] / r**2) / omega_m)
    eta = p["main_beam_efficiency"]
    ta_g = t_g_s
    ta_t = eta * (fill * t_t_s + (1 - fill) * t_g_s) + (1 - eta) * t_g_s
    t_rec = 290 * (10 ** (p["noise_figure_db"] / 10) - 1)
    t_sys = ta_g + t_rec
    bt = p["bandwidth_hz"] * p["integration_time_s"]
    if scene.option("receiver", "total_power") == "dicke":
        t_ref = B(p["reference_temperature_k"], f)
        dt = mp.sqrt(2 * ((ta_g + t_rec) ** 2 + (t_ref + t_rec) ** 2) / bt + (p["gain_variation"] * (ta_g - t_ref)) ** 2)
    else:
        dt = t_sys * mp.sqrt(1 / bt + p["gain_variation"] ** 2)
    d = abs(ta_t - ta_g) / dt
    z_fa = mp.sqrt(2) * mp.erfinv(1 - 2 * p["pfa"])
    d_req = mp.sqrt(2) * mp.erfinv(2 * p["pd"] - 1) + z_fa
    theta = mp.sqrt(4 * mp.log(2) * omega_m / mp.pi)
    return {
        "sky_temperature_k": t_sky, "target_apparent_temperature_k": t_t, "ground_apparent_temperature_k": t_g,
        "contrast_k": t_t - t_g, "path_transmission": mp.e**-tau, "antenna_gain_db": 10 * mp.log10(4 * mp.pi / omega_a),
        "beamwidth_rad": theta, "footprint_diameter_m": r * theta, "beam_fill": fill, "antenna_temperature_k": ta_g,
        "antenna_temperature_target_k": ta_t, "antenna_contrast_k": ta_t - ta_g, "system_temperature_k": t_sys,
        "delta_t_k": dt, "snr_db": 10 * mp.log10(d), "required_snr_db": 10 * mp.log10(d_req),
        "snr_margin_db": 10 * mp.log10(d / d_req), "pd": mp.ncdf(d - z_fa),
    }


CASES = [
    (PLAIN, {}),
    (WEATHER, dict(range_m=400.0, depression_angle_deg=35.0, rain_rate_mm_h=2.5, fog_liquid_water_g_m3=0.3,
                   target_emissivity=0.05, target_area_m2=12.0, integration_time_s=4e-3, gain_variation=3e-4)),
    (DICKE, dict(freq_hz=35e9, antenna_diameter_m=0.3, bandwidth_hz=5e8, reference_temperature_k=310.0,
                 gain_variation=2e-3, water_vapour_g_m3=12.0, air_temperature_k=298.0, range_m=1200.0)),
]


@pytest.mark.parametrize("scene,params", CASES, ids=["plain", "gas_rain_fog", "dicke_gas_rain_fog"])
def test_chain_matches_independent_mpmath_model(scene, params):
    ev = evaluate(scene, params)
    ref = hand_model(scene, complete_parameters(scene, params))
    for name, value in ref.items():
        tol = 1e-12 if name.endswith("_db") else 1e-11
        assert float(ev[name]) == pytest.approx(float(value), rel=1e-11, abs=tol), name
    # the budget terms add up to the SNR
    assert float(sum(ev.budget.values)) == pytest.approx(float(ev["snr_db"]), abs=1e-12)
    assert set(ev.values) == set(output_table(scene))


def test_metal_target_mirrors_the_sky_and_rain_fills_the_contrast():
    dry = evaluate(PLAIN)
    assert float(dry["target_apparent_temperature_k"]) == float(dry["sky_temperature_k"])  # ε = 0
    assert float(dry["contrast_k"]) < -150.0  # a metal vehicle is ~200 K colder than ground at 94 GHz
    wet = evaluate(Scene("radiometer", ["rain"]), rain_rate_mm_h=25.0)
    assert float(wet["sky_temperature_k"]) > 250.0  # the rain column is nearly opaque
    assert abs(float(wet["contrast_k"])) < 0.2 * abs(float(dry["contrast_k"]))
    # opaque sky: contrast → ε_g (T_m − T_g) in Planck brightness
    opaque = evaluate(Scene("radiometer", ["rain"]), rain_rate_mm_h=200.0, rain_height_m=10000.0)
    f = 94e9
    limit = 0.9 * (B(275.0, f) - B(290.0, f))
    assert float(opaque["contrast_k"]) == pytest.approx(float(limit), abs=1e-6)


def test_book_ore_pass_antenna_through_chain_8_16_9():
    ev = evaluate(PLAIN, freq_hz=94e9, antenna_diameter_m=0.25, aperture_efficiency=0.7, main_beam_efficiency=1.0)
    # G = 42,432 with λ = 3.19 mm; the exact c moves λ by 0.02 % (0.002 dB)
    assert float(ev["antenna_gain_db"]) == pytest.approx(10 * math.log10(42432.0), abs=0.01)
    # Gaussian beam of the same solid angle vs the book's 70 λ/d = 0.89°: within 5 % (taper model)
    assert math.degrees(float(ev["beamwidth_rad"])) == pytest.approx(0.89, rel=0.05)


def test_balanced_dicke_is_twice_total_power():
    # choose the reference load whose Planck brightness equals the antenna temperature
    common = dict(gain_variation=0.0, range_m=300.0)
    tp = evaluate(Scene("radiometer", ["gas"]), common)
    ta = mp.mpf(float(tp["antenna_temperature_k"]))
    t_ref = HF_K * 94e9 / mp.log1p(HF_K * 94e9 / ta)  # inverse Planck brightness
    dk = evaluate(Scene("radiometer", ["gas"], {"receiver": "dicke"}), common, reference_temperature_k=float(t_ref))
    assert float(dk["delta_t_k"]) == pytest.approx(2 * float(tp["delta_t_k"]), rel=1e-12)
    assert float(dk["snr_db"]) == pytest.approx(float(tp["snr_db"]) - 10 * math.log10(2), abs=1e-11)


def test_detection_range_is_where_the_margin_vanishes():
    for scene, params in CASES:
        ev = evaluate(scene, params)
        r = float(ev["detection_range_m"])
        assert 1.0 < r < 1e5
        at_r = evaluate(scene, dict(params, range_m=r))
        assert float(at_r["snr_margin_db"]) == pytest.approx(0.0, abs=1e-9)
        assert float(at_r["pd"]) == pytest.approx(0.9, abs=1e-9)


CHECKS = WeightedOutputs(("snr_margin_db", "detection_range_m", "delta_t_k", "pd", "sky_temperature_k"),
                        [1.0, 1e-3, 10.0, 3.0, 0.01])  # generic weights: one gradient checks every output


def test_chain_jit_and_vmap():
    CHECKS.assert_jit_and_vmap(PLAIN, complete_parameters(PLAIN, {}), [50.0, 150.0, 600.0])


DOMAIN_SWEEP = {
    "freq_hz": (2e9, 3e11), "range_m": (1.0, 1e5), "depression_angle_deg": (5.0, 90.0), "target_area_m2": (0.0, 1e3),
    "target_emissivity": (0.0, 1.0), "ground_emissivity": (0.0, 1.0), "noise_figure_db": (0.0, 30.0),
    "antenna_diameter_m": (0.01, 10.0), "integration_time_s": (1e-6, 10.0), "water_vapour_g_m3": (0.0, 30.0),
    "rain_rate_mm_h": (0.1, 200.0), "fog_liquid_water_g_m3": (0.0, 5.0), "gain_variation": (0.0, 0.1),
}


# edge cases where the SNR does not vary with range (zero contrast; a target filling the beam on
# a clear path with the SNR below the requirement): the detection range and its gradient stay finite
EDGES = {PLAIN: [dict(target_emissivity=0.9, target_temperature_k=290.0),
                 dict(target_area_m2=1e4, integration_time_s=1e-9, pd=0.999999, pfa=1e-12)],
         DICKE: [dict(target_emissivity=0.9, target_temperature_k=290.0, rain_rate_mm_h=0.0)]}


@pytest.mark.parametrize("scene,params", [CASES[0], CASES[2]], ids=["plain", "dicke_gas_rain_fog"])
def test_chain_gradient_matches_central_difference_and_is_finite(scene, params):
    base = complete_parameters(scene, params)
    names = ["freq_hz", "range_m", "antenna_diameter_m", "aperture_efficiency", "main_beam_efficiency",
             "integration_time_s", "noise_figure_db", "gain_variation", "target_area_m2", "target_emissivity",
             "ground_temperature_k", "air_temperature_k", "water_vapour_g_m3", "depression_angle_deg",
             "sky_mean_radiating_temperature_k", "pd", "pfa", "fog_liquid_water_g_m3", "fog_thickness_m",
             "rain_rate_mm_h", "rain_height_m", "reference_temperature_k"]
    CHECKS.assert_gradient_matches_fd(scene, base, [n for n in names if n in base], rel_step=1e-6)
    CHECKS.assert_finite_over(scene, params, {k: v for k, v in DOMAIN_SWEEP.items() if k in base},
                              extra_points=EDGES[scene])


def test_absent_parts_are_not_traced():
    for scene, expected in ((PLAIN, set()), (Scene("radiometer", ["rain"]), {"rain"}), (WEATHER, {"gas", "rain", "fog"}),
                            (DICKE, {"gas", "rain", "fog"}), (Scene("radiometer", ["fog"], {"receiver": "dicke"}), {"fog"})):
        p = complete_parameters(scene, {})
        jx = jax.make_jaxpr(lambda q: evaluate(scene, q).values)(p)
        assert traced_parts(jx) == expected
    assert "rain_rate_mm_h" not in parameter_table(PLAIN)
    assert parameter_table(WEATHER)["rain_rate_mm_h"].part == "rain"
    assert "reference_temperature_k" in parameter_table(DICKE) and "reference_temperature_k" not in parameter_table(PLAIN)


def test_parameters_have_units_domains_and_docs():
    from diffsense.design.units import registry

    for name, prm in parameter_table(Scene("radiometer", ["gas", "rain", "fog"], {"receiver": "dicke"})).items():
        registry().Unit(prm.unit)
        assert prm.doc and prm.lo is not None and prm.hi is not None, name


def test_domain_errors():
    with pytest.raises(DomainError):
        evaluate(PLAIN, range_m=0.5)
    with pytest.raises(DomainError):
        evaluate(PLAIN, target_emissivity=1.2)
    with pytest.raises(DomainError):
        evaluate(PLAIN, freq_hz=5e12)
    with pytest.raises(DomainError):
        evaluate(PLAIN, pd=1e-7)  # below pfa
    with pytest.raises(DomainError):
        evaluate(PLAIN, rain_rate_mm_h=5.0)  # no rain in the scene
    with pytest.raises(DomainError):
        evaluate(Scene("radiometer", ["haze"]))
    with pytest.raises(DomainError):
        evaluate(Scene("radiometer", options={"receiver": "correlation"}))
