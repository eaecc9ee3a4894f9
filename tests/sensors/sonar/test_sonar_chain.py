"""The "sonar" chain: scene structure, absent parts, jit/vmap/grad against central differences.

Numbers checked here come from closed forms: central finite differences of the chain itself
(float64, relative step 1e-6, agreement to 1e-5 relative), the budget identity (the terms sum to
``snr_db``), and the book's noise bookkeeping N_f + 10 log10 B − DI (eq (12.64)). The book's
worked example is in tests/test_book_sidescan_sonar.py.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.scene import CHAINS, complete_parameters, evaluate, output_table, parameter_table
from diffsense.sensors.parts import traced_parts
from diffsense.scene import Scene
from diffsense.design.units import check_unit

from helpers.chain_checks import BatchedJvp

ALL_ACTIVE_PARTS = ("sea_noise", "thermal_noise", "receiver_noise", "surface_reverberation",
                    "bottom_reverberation", "volume_reverberation")

# -------------------------------------------------------------------------------------------
# Scene structure and domains
# -------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "scene,params",
    [
        (Scene("sonar", ["fog"]), {"range_m": 100.0, "freq_hz": 1e4}),  # unknown part
        (Scene("sonar", ["sea_noise"], {"mode": "sideways"}), {"range_m": 100.0, "freq_hz": 1e4}),
        (Scene("sonar", ["sea_noise"], {"colour": 1}), {"range_m": 100.0, "freq_hz": 1e4}),
        (Scene("sonar", []), {"range_m": 100.0, "freq_hz": 1e4}),  # nothing limits the SNR
        (Scene("sonar", ["sea_noise", "volume_reverberation"], {"mode": "passive"}),
         {"range_m": 100.0, "freq_hz": 1e4, "source_level_db": 140.0}),
        (Scene("sonar", ["sea_noise"], {"mode": "passive", "waveform": "chirp"}),
         {"range_m": 100.0, "freq_hz": 1e4, "source_level_db": 140.0}),
        (Scene("sonar", ["sea_noise"]), {"freq_hz": 1e4}),  # range_m missing
        (Scene("sonar", ["sea_noise"]), {"range_m": 100.0, "freq_hz": 1e4, "rcs_m2": 1.0}),  # unknown name
        (Scene("sonar", ["sea_noise"]), {"range_m": 100.0, "freq_hz": 3e5}),  # above Knudsen's 200 kHz
        (Scene("sonar", ["thermal_noise"]), {"range_m": 0.5, "freq_hz": 1e4}),  # below 1 m
        (Scene("sonar", ["thermal_noise"]), {"range_m": 100.0, "freq_hz": 1e4, "efficiency": 1.2}),
        (Scene("sonar", ["thermal_noise"]), {"range_m": 100.0, "freq_hz": 1e4, "pd": 0.01}),
        (Scene("sonar", ["surface_reverberation"], {"surface_scattering": "chapman_harris"}),
         {"range_m": 100.0, "freq_hz": 1e4}),  # Chapman-Harris measured up to 6.4 kHz
        (Scene("sonar", ["sea_noise"], {"sound_speed": "mackenzie"}),
         {"range_m": 100.0, "freq_hz": 1e4, "salinity_ppt": 10.0}),  # Mackenzie needs 25-40 ppt
        (Scene("sonar", ["sea_noise"], {"sound_speed": "given"}),
         {"range_m": 100.0, "freq_hz": 1e4, "sound_speed_m_s": 340.0}),
    ],
)
def test_invalid_scene_or_parameter_raises(scene, params):
    with pytest.raises(DomainError):
        evaluate(scene, params)


def test_parameters_exist_only_with_their_part_and_units_parse():
    bare = parameter_table(Scene("sonar", ["thermal_noise"]))
    for name in ("sea_state", "amplifier_noise_density_v_rthz", "surface_scattering_strength_db",
                 "bottom_scattering_strength_db", "volume_scattering_strength_db"):
        assert name not in bare
    full = parameter_table(Scene("sonar", ALL_ACTIVE_PARTS))
    assert full["sea_state"].part == "sea_noise"
    assert full["amplifier_noise_density_v_rthz"].part == "receiver_noise"
    assert full["volume_scattering_strength_db"].part == "volume_reverberation"
    for scene in (Scene("sonar", ALL_ACTIVE_PARTS, {"waveform": "chirp", "source": "tvr", "target": "seafloor",
                                                    "sound_speed": "mackenzie", "spreading": "cylindrical",
                                                    "bottom_scattering": "lambert"}),
                  Scene("sonar", ["sea_noise"], {"mode": "passive", "absorption": "given"})):
        for prm in parameter_table(scene).values():
            check_unit(prm.unit)
            assert prm.doc
        for out in output_table(scene).values():
            check_unit(out.unit)
    assert "reverberation_level_db" in output_table(Scene("sonar", ["volume_reverberation"]))
    assert "reverberation_level_db" not in output_table(Scene("sonar", ["sea_noise"]))


def _parts_traced(scene, **params):
    p = complete_parameters(scene, params)
    jaxpr = jax.make_jaxpr(lambda q: CHAINS["sonar"].compute(scene, q).values["snr_margin_db"])(p)
    return traced_parts(jaxpr)


def test_absent_parts_are_not_traced():
    assert _parts_traced(Scene("sonar", ["sea_noise"]), range_m=300.0, freq_hz=1e5) == {"sea_noise"}
    assert _parts_traced(Scene("sonar", ["thermal_noise", "volume_reverberation"]), range_m=300.0,
                         freq_hz=1e5) == {"thermal_noise", "volume_reverberation"}
    full = Scene("sonar", ALL_ACTIVE_PARTS, {"surface_scattering": "chapman_harris", "bottom_scattering": "lambert"})
    assert _parts_traced(full, range_m=300.0, freq_hz=5e3) == set(ALL_ACTIVE_PARTS)
    passive = Scene("sonar", ["receiver_noise"], {"mode": "passive"})
    assert _parts_traced(passive, range_m=300.0, freq_hz=5e3, source_level_db=130.0) == {"receiver_noise"}


# -------------------------------------------------------------------------------------------
# jit + vmap + grad of the chain, against central differences
# -------------------------------------------------------------------------------------------

SCENE = Scene("sonar", ["sea_noise", "receiver_noise", "bottom_reverberation"], {"waveform": "chirp"})
BASE = dict(range_m=800.0, freq_hz=117e3, sea_state=2.5, pulse_width_s=5e-3, chirp_bandwidth_hz=15e3,
            temperature_c=10.0, target_radius_m=1.0, electrical_power_w=1500.0, beamwidth_az_deg=1.5,
            pd=0.9, bottom_scattering_strength_db=-20.0)
DIFF = ("range_m", "freq_hz", "sea_state", "pulse_width_s", "chirp_bandwidth_hz", "temperature_c",
        "target_radius_m", "electrical_power_w", "beamwidth_az_deg", "pd", "bottom_scattering_strength_db")
OUTS = ("snr_margin_db", "detection_range_m", "pd", "cross_range_resolution_m", "max_pulse_length_s")
K = len(DIFF)
JVP = BatchedJvp("sonar", SCENE, OUTS, DIFF)  # one compilation serves every test below


def test_chain_jit_vmap_grad_match_eager_and_central_differences():
    # jit + vmap equal eager (abs 1e-12), budget terms sum to snr_db, derivatives equal
    # central differences (abs 1e-9·max(1, |value|))
    eager = JVP.assert_matches_eager_and_differences(BASE, value_atol=1e-12, derivative_floor=1.0)
    assert float(eager["pd"]) == pytest.approx(0.5, abs=0.49)  # the base point is on the Pd slope


_DOMAIN = dict(range_m=(1.0, 1e6, True), freq_hz=(1e3, 2e5, True), sea_state=(0.0, 6.0, False),
               pulse_width_s=(1e-6, 10.0, True), chirp_bandwidth_hz=(1.0, 1e6, True),
               temperature_c=(-2.0, 30.0, False), target_radius_m=(1e-3, 1e3, True),
               electrical_power_w=(1e-3, 1e7, True), beamwidth_az_deg=(0.01, 180.0, True),
               pd=(0.1, 0.999999, False), bottom_scattering_strength_db=(-150.0, 0.0, False))


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=K, max_size=K))
def test_chain_values_and_gradients_finite_over_domain(us):
    values = JVP.assert_finite_at(BASE, _DOMAIN, us)
    assert np.all(np.abs(values[:, -1]) < 1e-8 * np.maximum(1.0, np.abs(values[:, 0])))


def test_passive_chain_gradient_matches_central_difference():
    scene = Scene("sonar", ["sea_noise", "thermal_noise"], {"mode": "passive", "absorption": "book"})
    base = dict(range_m=5e3, freq_hz=8e3, source_level_db=150.0, bandwidth_hz=50.0, integration_time_s=2.0,
                sea_state=1.5, pd=0.7, pfa=1e-4)

    def f(x):
        p = complete_parameters(scene, base)
        p = dict(p, range_m=x[0], bandwidth_hz=x[1], integration_time_s=x[2], pd=x[3])
        v = CHAINS["sonar"].compute(scene, p).values
        return jnp.stack([v["snr_margin_db"], v["detection_range_m"], v["pd"]])

    x0 = np.array([base["range_m"], base["bandwidth_hz"], base["integration_time_s"], base["pd"]])
    jac = np.asarray(jax.jit(jax.jacfwd(f))(jnp.asarray(x0)))
    f_jit = jax.jit(f)
    for i in range(4):
        h = 1e-6 * x0[i]
        e = np.zeros(4)
        e[i] = h
        fd = (np.asarray(f_jit(x0 + e)) - np.asarray(f_jit(x0 - e))) / (2 * h)
        np.testing.assert_allclose(jac[:, i], fd, rtol=1e-5, atol=1e-10)
