"""Ultrasound in air (diffsense.sensors.ultrasonic): transducer SPL, receiver voltage, pulse-echo
bookkeeping and the "ultrasonic" chain.

Independent references used by the assertions:
- Brooker §13.20 (beacon: 126 dB, 102.4 dB, 18.6 mV) and §8.16.2 (λ = θ d/70 = 0.016 m, 21.6 kHz);
  the complete worked examples through the chain are in tests/test_book_ultrasonic_beacon.py.
- Closed forms: an infinite plane mirror at range R returns the field of an image source at 2R
  (so its target strength is 20 log10(R/2), Urick ch. 9), 20 log10(20 µPa / 1 µbar) = −73.98 dB,
  amplifier noise e_n √B, ISO 9613-1 absorption and sound speed from diffsense.physics.propagation.acoustic.
- Central finite differences of the chain (float64) for its gradients.
"""

import math

import jax
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401
from diffsense.sensors import ultrasonic as us
from diffsense.errors import DomainError
from diffsense.scene import CHAINS, complete_parameters, evaluate, output_table, parameter_table
from diffsense.sensors.parts import traced_parts
from diffsense.physics.propagation import acoustic
from diffsense.scene import Scene
from diffsense.design.units import check_unit

from helpers.chain_checks import BatchedJvp
from helpers.function_suite import argument_suite

# -------------------------------------------------------------------------------------------
# Functions
# -------------------------------------------------------------------------------------------


def test_spl_scales_with_drive_voltage_squared_book_13_20():
    assert float(us.spl_at_reference_db(120.0, 20.0, 10.0)) == pytest.approx(126.0, abs=0.05)
    assert float(us.spl_at_reference_db(120.0, 10.0, 10.0)) == pytest.approx(120.0, abs=1e-12)
    assert float(us.spl_at_reference_db(100.0, 1.0, 10.0)) == pytest.approx(80.0, abs=1e-12)


def test_receiver_output_voltage_book_13_20():
    # 20 log10 V = 102.4 − 63 + 20 log10(0.0002) → 18.6 mV (the book rounds −73.98 to −74).
    assert us.SPL_TO_MICROBAR_DB == pytest.approx(-73.98, abs=0.005)
    assert float(us.receiver_output_voltage_v(102.4, -63.0)) == pytest.approx(18.6e-3, abs=0.1e-3)
    # 94 dB SPL = 1 Pa = 10 µbar; at 0 dB re 1 V/µbar that is 10 V (1 Pa: 93.98 dB)
    assert float(us.receiver_output_voltage_v(20 * math.log10(1.0 / 20e-6), 0.0)) == pytest.approx(10.0, rel=1e-12)


def test_one_way_received_spl_book_13_31():
    assert float(us.one_way_received_spl_db(126.0, 3.0, 1.2, 0.3)) == pytest.approx(102.4, abs=1e-9)


@pytest.mark.parametrize("r,alpha,r0", [(3.0, 1.2, 0.3), (0.5, 0.0, 0.3), (20.0, 0.2, 1.0)])
def test_pulse_echo_from_plane_mirror_equals_image_source(r, alpha, r0):
    # A plane at R reflects like an image source at 2R: L0 − 20 log10(2R/R0) − 2αR, i.e. TS = 20 log10(R/2).
    got = float(us.pulse_echo_received_spl_db(120.0, r, alpha, 20 * math.log10(r / 2), r0))
    assert got == pytest.approx(120.0 - 20 * math.log10(2 * r / r0) - 2 * alpha * r, abs=1e-9)


def test_beamwidth_rule_wavelength_and_frequency_book_8_16_2():
    # λ = θ/70 × d = 1.1/70 = 0.0157 m, printed "0.016 m"; 340 m/s → 21.6 kHz.
    assert float(us.max_wavelength_for_beamwidth_book_m(1.0, 1.1)) == pytest.approx(0.016, abs=0.0005)
    assert float(us.min_frequency_for_beamwidth_book_hz(1.0, 1.1, 340.0)) == pytest.approx(21.6e3, abs=50.0)


_CASES = {
    "spl_at_reference_db": (us.spl_at_reference_db, (120.0, 20.0, 10.0), 1, (1e-3, 1e4)),
    "receiver_output_voltage_v": (us.receiver_output_voltage_v, (102.4, -63.0), 0, (-100.0, 200.0)),
    "receiver_output_level_dbv": (us.receiver_output_level_dbv, (102.4, -63.0), 1, (-200.0, 50.0)),
    "one_way_received_spl_db": (us.one_way_received_spl_db, (126.0, 3.0, 1.2, 0.3), 1, (1e-3, 1e4)),
    "pulse_echo_received_spl_db": (us.pulse_echo_received_spl_db, (126.0, 3.0, 1.2, -10.0, 0.3), 1, (1e-3, 1e4)),
    "max_wavelength_for_beamwidth_book_m": (us.max_wavelength_for_beamwidth_book_m, (1.0, 1.1), 1, (1e-3, 180.0)),
    "min_frequency_for_beamwidth_book_hz": (us.min_frequency_for_beamwidth_book_hz, (1.0, 1.1, 340.0), 0, (1e-3, 100.0)),
}


globals().update(argument_suite(_CASES))


@pytest.mark.parametrize(
    "call",
    [
        lambda: us.spl_at_reference_db(120.0, 0.0, 10.0),
        lambda: us.spl_at_reference_db(300.0, 1.0, 10.0),
        lambda: us.receiver_output_voltage_v(102.0, 80.0),
        lambda: us.receiver_output_level_dbv(float("nan"), -63.0),
        lambda: us.one_way_received_spl_db(126.0, -3.0, 1.2),
        lambda: us.one_way_received_spl_db(126.0, 3.0, -1.2),
        lambda: us.pulse_echo_received_spl_db(126.0, 3.0, 1.2, 100.0),
        lambda: us.max_wavelength_for_beamwidth_book_m(1.0, 200.0),
        lambda: us.min_frequency_for_beamwidth_book_hz(1.0, 1.1, 0.0),
    ],
)
def test_out_of_domain_raises(call):
    with pytest.raises(DomainError):
        call()


# -------------------------------------------------------------------------------------------
# The chain
# -------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "scene,params",
    [
        (Scene("ultrasonic", ["rain"]), {"range_m": 3.0}),
        (Scene("ultrasonic", [], {"mode": "both"}), {"range_m": 3.0}),
        (Scene("ultrasonic", [], {"target": "sphere"}), {"range_m": 3.0}),  # target needs pulse_echo
        (Scene("ultrasonic", []), {}),  # range_m missing
        (Scene("ultrasonic", []), {"range_m": 3.0, "relative_humidity_pct": 120.0}),
        (Scene("ultrasonic", []), {"range_m": 3.0, "temperature_k": 400.0}),
        (Scene("ultrasonic", [], {"absorption": "given"}), {"range_m": 3.0, "absorption_db_per_m": -1.0}),
        (Scene("ultrasonic", [], {"mode": "pulse_echo"}), {"range_m": 3.0}),  # target_strength_db missing
        (Scene("ultrasonic", []), {"range_m": 3.0, "pd": 0.9}),  # pd only with a noise part
    ],
)
def test_invalid_scene_or_parameter_raises(scene, params):
    with pytest.raises(DomainError):
        evaluate(scene, params)


def test_parameters_and_outputs_follow_the_parts():
    bare = parameter_table(Scene("ultrasonic", []))
    assert "amplifier_noise_density_v_rthz" not in bare and "pd" not in bare
    assert "snr_db" not in output_table(Scene("ultrasonic", []))
    full = Scene("ultrasonic", ["receiver_noise", "ambient_noise"], {"mode": "pulse_echo", "target": "sphere"})
    table = parameter_table(full)
    assert table["amplifier_noise_density_v_rthz"].part == "receiver_noise"
    assert table["ambient_noise_spectrum_level_db"].part == "ambient_noise"
    for prm in table.values():
        check_unit(prm.unit)
    for out in output_table(full).values():
        check_unit(out.unit)


def _parts_traced(scene, **params):
    p = complete_parameters(scene, params)
    return traced_parts(jax.make_jaxpr(lambda q: CHAINS["ultrasonic"].compute(scene, q).values["received_spl_db"])(p))


def test_absent_parts_are_not_traced():
    assert _parts_traced(Scene("ultrasonic", []), range_m=3.0) == set()
    assert _parts_traced(Scene("ultrasonic", ["ambient_noise"]), range_m=3.0,
                         ambient_noise_spectrum_level_db=0.0) == {"ambient_noise"}
    assert _parts_traced(Scene("ultrasonic", ["receiver_noise", "ambient_noise"]), range_m=3.0,
                         ambient_noise_spectrum_level_db=0.0) == {"receiver_noise", "ambient_noise"}


def test_chain_pulse_echo_closed_form_with_iso_absorption_and_noise():
    scene = Scene("ultrasonic", ["receiver_noise", "ambient_noise"], {"mode": "pulse_echo", "target": "sphere"})
    r, a, t, rh, f, b, en, amb = 2.5, 0.05, 288.15, 60.0, 50e3, 2e3, 5e-9, -10.0
    e = evaluate(scene, range_m=r, target_radius_m=a, temperature_k=t, relative_humidity_pct=rh, freq_hz=f,
                 bandwidth_hz=b, amplifier_noise_density_v_rthz=en, ambient_noise_spectrum_level_db=amb)
    alpha = float(acoustic.air_absorption_db_per_m(f, t, rh))
    c = float(acoustic.sound_speed_humid_air(t, rh))
    ts = 20 * math.log10(a / 2)
    spl = 120 + 20 * math.log10(2.0) - 20 * math.log10(r / 0.3) - alpha * r + ts - 20 * math.log10(r) - alpha * r
    assert float(e["received_spl_db"]) == pytest.approx(spl, abs=1e-9)
    v = 10 ** ((spl - 63 + 20 * math.log10(2e-4)) / 20)
    assert float(e["output_voltage_v"]) == pytest.approx(v, rel=1e-9)
    v_amb = 10 ** ((amb + 10 * math.log10(b) - 63 + 20 * math.log10(2e-4)) / 20)
    v_n = math.hypot(en * math.sqrt(b), v_amb)
    assert float(e["noise_voltage_v"]) == pytest.approx(v_n, rel=1e-9)
    assert float(e["snr_db"]) == pytest.approx(20 * math.log10(v / v_n), abs=1e-9)
    assert float(e.budget.total) == pytest.approx(float(e["snr_db"]), abs=1e-9)
    assert float(e["time_of_flight_s"]) == pytest.approx(2 * r / c, rel=1e-12)
    assert float(e["range_resolution_m"]) == pytest.approx(c * 1e-3 / 2, rel=1e-12)


SCENE = Scene("ultrasonic", ["receiver_noise", "ambient_noise"], {"mode": "pulse_echo", "target": "sphere"})
BASE = dict(range_m=9.6, freq_hz=40e3, drive_voltage_v=20.0, temperature_k=295.0, relative_humidity_pct=40.0,
            target_radius_m=0.1, bandwidth_hz=1e3, pd=0.9, amplifier_noise_density_v_rthz=10e-9,
            ambient_noise_spectrum_level_db=-20.0)
DIFF = tuple(BASE)
OUTS = ("snr_margin_db", "detection_range_m", "pd", "output_voltage_v", "time_of_flight_s")
K = len(DIFF)
JVP = BatchedJvp("ultrasonic", SCENE, OUTS, DIFF, zero_step=1e-6)


def test_chain_jit_vmap_grad_match_eager_and_central_differences():
    # derivatives equal central differences to abs 1e-9·max(1e-6, |value|): the outputs are volts
    # and seconds
    eager = JVP.assert_matches_eager_and_differences(BASE, value_atol=1e-15, derivative_floor=1e-6)
    assert 0.05 < float(eager["pd"]) < 0.99  # on the Pd slope, so its derivative is exercised


_DOMAIN = dict(range_m=(0.01, 1e4, True), freq_hz=(1e3, 1e6, True), drive_voltage_v=(1e-3, 1e4, True),
               temperature_k=(253.0, 323.0, False), relative_humidity_pct=(1.0, 100.0, False),
               target_radius_m=(1e-4, 100.0, True), bandwidth_hz=(1.0, 1e6, True), pd=(0.1, 0.999999, False),
               amplifier_noise_density_v_rthz=(1e-12, 1e-3, True), ambient_noise_spectrum_level_db=(-100.0, 150.0, False))


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=K, max_size=K))
def test_chain_values_and_gradients_finite_over_domain(us_):
    JVP.assert_finite_at(BASE, _DOMAIN, us_)
