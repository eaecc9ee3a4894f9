"""The radar chain's received-pulse width, sea-clutter models, sidelobe floor, noise-temperature
input and surface geometry, through the public chain.

References: the two-tuned-circuit envelope P(2, u) − P(2, u − w) and its half-amplitude
crossings by mpmath (tests/physics/test_received_pulse.py); the noise power k T0 β F L_rx against
k Ts β L_rx with Ts = Ta + T0 (F − 1), Ta = T0 (IEEE Std 145); the NRL formula and the 4/3-earth
grazing angle written out in closed form.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.report.sweeps import coverage_applies
from diffsense.scene import Scene, complete_parameters, evaluate, evaluator, parameter_table

import mpmath as mp

BASE = dict(range_m=5e3, peak_power_w=1e4, pulse_width_s=0.2e-6, freq_hz=9.5e9, bandwidth_hz=3.065e6, noise_figure_db=5.0,
            prf_hz=5e3, n_pulses=16.0, antenna_diameter_m=1.0, detectability_db=15.26)


def two_tuned_echo_width_over_tau(bt):
    """Half-amplitude width / τ after two tuned circuits of band β (βτ = bt): envelope
    P(2, u) − P(2, u − w), u = ω0 t, ω0 = π β / sqrt(√2 − 1), w = ω0 τ; crossings by mpmath."""
    w = mp.pi * mp.mpf(bt) / mp.sqrt(mp.sqrt(2) - 1)
    p2 = lambda u: mp.gammainc(2, 0, u, regularized=True) if u > 0 else mp.mpf(0)
    y = lambda u: p2(u) - p2(u - w)
    u_peak = w / (1 - mp.exp(-w))
    half = y(u_peak) / 2
    rise = mp.findroot(lambda u: y(u) - half, (mp.mpf("1e-12"), u_peak), solver="anderson")
    fall = mp.findroot(lambda u: y(u) - half, (u_peak, u_peak + w + 60), solver="anderson")
    return float((fall - rise) / w)


def run(scene, **extra):
    table = parameter_table(scene)
    return evaluator(scene)(complete_parameters(scene, {k: v for k, v in dict(BASE, **extra).items() if k in table}))


def test_range_resolution_and_tracking_gate_follow_the_two_tuned_echo():
    tuned = Scene("radar", ["tracking"], {"detectability": "given", "matched_filter": "two_tuned"})
    matched = Scene("radar", ["tracking"], {"detectability": "given", "matched_filter": "matched"})
    extra = dict(track_alpha=0.3, servo_bandwidth_hz=2.0, positioner_resonance_hz=30.0)
    ev_t, ev_m = run(tuned, **extra), run(matched, **extra)
    ratio = two_tuned_echo_width_over_tau(0.613)
    assert float(ev_m["range_resolution_m"]) == pytest.approx(SPEED_OF_LIGHT_M_S * 0.2e-6 / 2, rel=1e-15)
    assert float(ev_t["range_resolution_m"]) == pytest.approx(SPEED_OF_LIGHT_M_S * 0.2e-6 / 2 * ratio, rel=1e-9)
    # split-gate noise σ_R ∝ gate / sqrt(SNR); the SNRs differ by the mismatch loss
    snr = lambda ev: 10 ** (float(ev["snr_db"]) / 10)
    got = float(ev_t["range_noise_m"]) / float(ev_m["range_noise_m"])
    assert got == pytest.approx(ratio * math.sqrt(snr(ev_m) / snr(ev_t)), rel=1e-9)


def test_ore_pass_like_narrow_filter_reports_the_smeared_resolution():
    # τ = 10.9 ns with β = 5.96 MHz through two tuned circuits: the echo is ≈ 0.5/β long
    scene = Scene("radar", [], {"detectability": "given", "matched_filter": "two_tuned"})
    ev = run(scene, pulse_width_s=10.9e-9, bandwidth_hz=5.96e6, freq_hz=94e9, antenna_diameter_m=0.25, range_m=300.0)
    want = SPEED_OF_LIGHT_M_S / 2 * 10.9e-9 * two_tuned_echo_width_over_tau(5.96e6 * 10.9e-9)
    assert float(ev["range_resolution_m"]) == pytest.approx(want, rel=1e-9)
    assert float(ev["range_resolution_m"]) > 12.0


def test_noise_temperature_input_is_equivalent_to_the_noise_figure():
    fig = Scene("radar", [], {"detectability": "given"})
    temp = Scene("radar", [], {"detectability": "given", "noise_input": "temperature"})
    assert "noise_figure_db" not in parameter_table(temp) and "system_noise_temperature_k" in parameter_table(temp)
    for nf in (0.5, 5.0, 12.5):
        ts = 290.0 + 290.0 * (10 ** (nf / 10) - 1)  # Ts = Ta + T0 (F − 1), Ta = T0
        a = run(fig, noise_figure_db=nf, receive_loss_db=1.2)
        b = run(temp, system_noise_temperature_k=ts, receive_loss_db=1.2)
        for out in ("snr_db", "noise_power_dbm", "detection_range_m"):
            assert float(b[out]) == pytest.approx(float(a[out]), rel=1e-12, abs=1e-12)
        assert float(b.budget["system_temperature_db"]) == pytest.approx(-nf, abs=1e-12)
    # a cold antenna (Ta = 50 K) lowers the noise by 10 log10(T0 F / (Ta + T0 (F − 1)))
    f = 10 ** 0.5
    cold = run(temp, system_noise_temperature_k=50.0 + 290.0 * (f - 1))
    warm = run(fig, noise_figure_db=5.0)
    assert float(warm["noise_power_dbm"] - cold["noise_power_dbm"]) == pytest.approx(
        10 * math.log10(290 * f / (50 + 290 * (f - 1))), abs=1e-12)


SEA = dict(range_m=1.5e3, antenna_height_m=40.0, target_height_m=10.0, sea_state=4.0, required_scr_db=-12.0)


def test_sea_clutter_models_in_the_chain():
    nrl = Scene("radar", ["sea_clutter"], {"detectability": "given", "matched_filter": "matched"})
    gamma = Scene("radar", ["sea_clutter"], {"detectability": "given", "matched_filter": "matched",
                                             "sea_clutter_model": "constant_gamma"})
    ev_n, ev_g = run(nrl, **SEA), run(gamma, **SEA)
    # ψ over the 4/3 earth (1.52° here); pulse-limited cell R θ (c τ / 2) / cos ψ; same area in both
    ka = 4 / 3 * 6371e3
    r, h = SEA["range_m"], SEA["antenna_height_m"]
    psi = math.asin((2 * ka * h + h * h - r * r) / (2 * ka * r))
    d = math.degrees(psi)
    nrl_db = (-73.0 + 20.781 * math.log10(math.sin(psi)) + (27.5 + 7.351 * d) * math.log10(9.5) / (1 + 0.95 * d)
              + 25.65 * 5.0 ** (1 / (2 + 0.085 * d + 0.033 * 4.0)) + 0.0054 * d * d)
    from diffsense.physics.clutter import sea_clutter_gamma_db
    from diffsense.physics.sea_state import beaufort_from_sea_state
    g_db = float(sea_clutter_gamma_db(beaufort_from_sea_state(4.0), SPEED_OF_LIGHT_M_S / 9.5e9)) + 10 * math.log10(math.sin(psi))
    assert float(ev_g["scr_db"]) - float(ev_n["scr_db"]) == pytest.approx(nrl_db - g_db, abs=1e-9)


def test_sea_clutter_domains_in_the_chain():
    gamma = Scene("radar", ["sea_clutter"], {"detectability": "given", "sea_clutter_model": "constant_gamma"})
    with pytest.raises(DomainError, match="constant-gamma"):
        evaluate(gamma, dict(BASE, range_m=5e3, antenna_height_m=8.0))  # 0.075° grazing
    nrl = Scene("radar", ["sea_clutter", "multipath"], {"detectability": "given"})
    ev = evaluate(nrl, dict(BASE, range_m=5e3, antenna_height_m=8.0, target_height_m=3.0, sea_state=5.0))
    assert np.isfinite(float(ev["scr_db"]))
    with pytest.raises(DomainError, match="NRL"):
        evaluate(nrl, dict(BASE, range_m=5e3, antenna_height_m=8.0, target_height_m=3.0, freq_hz=94e9))


def test_sea_scene_gradients_finite_down_to_the_horizon():
    scene = Scene("radar", ["sea_clutter"], {"detectability": "given"})
    p = complete_parameters(scene, dict(BASE, antenna_height_m=8.0, sea_state=5.0))
    g = jax.jit(jax.grad(lambda q: sum(jnp.sum(v) for v in evaluator(scene)(q).values.values())))
    for r in (100.0, 2e3, 5e3, 11.6e3, 20e3):  # the 8 m antenna's horizon is at 11.66 km
        grads = g(dict(p, range_m=jnp.asarray(r)))
        assert all(np.isfinite(float(x)) for x in grads.values()), r


def test_coverage_chart_only_for_a_radar_looking_along_the_surface():
    assert coverage_applies(Scene("radar", ["gas"]))
    assert coverage_applies(Scene("radar", ["multipath", "sea_clutter"]))
    assert not coverage_applies(Scene("radar", ["dust", "wall_clutter"]))  # the ore pass
    assert not coverage_applies(Scene("radar", ["dust"], {"geometry": "shaft"}))
    assert coverage_applies(Scene("radar", ["wall_clutter"], {"geometry": "earth_surface"}))
    assert not coverage_applies(Scene("sonar", ["sea_noise"]))
    with pytest.raises(DomainError):
        evaluate(Scene("radar", ["sea_clutter"], {"geometry": "shaft"}), BASE)
