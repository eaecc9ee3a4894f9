"""Tests of the registered radar chain (kind "radar") through the public chain API.

References: 40-digit mpmath evaluations of the link budget, closed-form derivatives, scipy's
noncentral chi-square law for the steady-target detection probability (independent of
diffsense.detection), and Skolnik's Table 5.1 (Brooker Table 9.1) for the mismatch loss.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize, stats

import diffsense  # noqa: F401
import diffsense.sensors.radar
from diffsense.errors import DomainError
from diffsense.scene import complete_parameters, evaluate, evaluator, output_table, parameter_table
from diffsense.sensors.parts import traced_parts
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.scene import Scene

MPMATH_DPS = 40  # working precision of this module's tests (set per test by tests/conftest.py)

# --- scene A: antenna given, per-pulse requirement given, ideal matched filter ---------------
SCENE_A = Scene("radar", [], {"antenna": "specified", "detectability": "given", "matched_filter": "matched"})
PARAMS_A = dict(
    range_m=40e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1.2e6, rcs_m2=2.0,
    noise_figure_db=3.0, transmit_loss_db=1.5, receive_loss_db=1.0, scan_loss_db=1.6, cfar_loss_db=0.7,
    misc_loss_db=1.3, prf_hz=1e3, n_pulses=12.0, gain_db=33.0, beamwidth_az_deg=1.5, beamwidth_el_deg=3.0,
    detectability_db=10.0,
)
EVAL_A = evaluator(SCENE_A)


def mp_budget_snr_db(p):
    """10 log10(Pt G² λ² σ / ((4π)³ R⁴ L_tx L_scan L_cfar L_misc k T0 β F L_rx)), 40 digits."""
    f = {k: mp.mpf(str(v)) for k, v in p.items()}
    db = lambda x: mp.mpf(10) ** (x / 10)
    lam = mp.mpf(SPEED_OF_LIGHT_M_S) / f["freq_hz"]
    pr = f["peak_power_w"] * db(2 * f["gain_db"]) * lam**2 * f["rcs_m2"] / ((4 * mp.pi) ** 3 * f["range_m"] ** 4)
    pr /= db(f["transmit_loss_db"] + f["scan_loss_db"] + f["cfar_loss_db"] + f["misc_loss_db"])
    n = mp.mpf("1.380649e-23") * 290 * f["bandwidth_hz"] * db(f["noise_figure_db"] + f["receive_loss_db"])
    return 10 * mp.log10(pr / n), 10 * mp.log10(pr) + 30, 10 * mp.log10(n) + 30


def test_chain_snr_equals_mpmath_link_budget():
    ev = EVAL_A(complete_parameters(SCENE_A, PARAMS_A))
    snr, pr_dbm, n_dbm = mp_budget_snr_db(PARAMS_A)
    assert abs(float(ev["snr_db"]) - float(snr)) < 1e-10
    assert abs(float(ev["received_power_dbm"]) - float(pr_dbm)) < 1e-10
    assert abs(float(ev["noise_power_dbm"]) - float(n_dbm)) < 1e-10


def test_budget_total_is_snr_and_reads_like_the_book_table():
    ev = EVAL_A(complete_parameters(SCENE_A, PARAMS_A))
    b = ev.budget
    assert abs(float(b.total) - float(ev["snr_db"])) < 1e-12
    assert b.names[:6] == ("peak_power_dbw", "transmit_loss_db", "two_way_gain_db", "wavelength_db", "rcs_dbsm", "range_db")
    assert b.names[-4:] == ("boltzmann_db", "bandwidth_db", "noise_figure_db", "receive_loss_db")
    # individual book-table lines: 2 x G, λ²/(4π)³, -kT0 = +203.98 dB
    lam = SPEED_OF_LIGHT_M_S / PARAMS_A["freq_hz"]
    assert abs(float(b["two_way_gain_db"]) - 66.0) < 1e-12
    assert abs(float(b["wavelength_db"]) - 10 * math.log10(lam**2 / (4 * math.pi) ** 3)) < 1e-12
    assert abs(float(b["boltzmann_db"]) + 10 * math.log10(1.380649e-23 * 290)) < 1e-12
    # the signal lines sum to Pr, the last four to -N
    sig = sum(float(v) for k, v in b.as_dict().items() if k not in ("boltzmann_db", "bandwidth_db", "noise_figure_db", "receive_loss_db"))
    assert abs(sig + 30 - float(ev["received_power_dbm"])) < 1e-10


def test_chain_timing_outputs_closed_forms():
    ev = EVAL_A(complete_parameters(SCENE_A, PARAMS_A))
    c = SPEED_OF_LIGHT_M_S
    assert abs(float(ev["range_resolution_m"]) - c * 1e-6 / 2) < 1e-9
    assert abs(float(ev["unambiguous_range_m"]) - c / 2e3) < 1e-6
    assert abs(float(ev["update_rate_hz"]) - 1e3 / 12) < 1e-10
    assert abs(float(ev["duty_cycle"]) - 1e-3) < 1e-15
    assert abs(float(ev["average_power_w"]) - 200.0) < 1e-10
    assert abs(float(ev["snr_margin_db"]) - (float(ev["snr_db"]) - 10.0)) < 1e-12


def test_chain_radar_designer_metrics_closed_forms():
    # EIRP, power-aperture product, minimum range and first blind speed from their definitions
    # (IEEE Std 686; Barton 2013 §1.4; Skolnik 2008 §1.2, §3.2), in mpmath
    ev = EVAL_A(complete_parameters(SCENE_A, PARAMS_A))
    f = {k: mp.mpf(str(v)) for k, v in PARAMS_A.items()}
    lam = mp.mpf(SPEED_OF_LIGHT_M_S) / f["freq_hz"]
    g = mp.mpf(10) ** (f["gain_db"] / 10)
    assert abs(float(ev["eirp_dbw"]) - float(10 * mp.log10(f["peak_power_w"]) - f["transmit_loss_db"] + f["gain_db"])) < 1e-12
    pa = f["peak_power_w"] * f["pulse_width_s"] * f["prf_hz"] * g * lam**2 / (4 * mp.pi)
    assert float(ev["power_aperture_w_m2"]) == pytest.approx(float(pa), rel=1e-13)
    assert float(ev["minimum_range_m"]) == pytest.approx(float(mp.mpf(SPEED_OF_LIGHT_M_S) * f["pulse_width_s"] / 2), rel=1e-15)
    assert float(ev["first_blind_speed_mps"]) == pytest.approx(float(lam * f["prf_hz"] / 2), rel=1e-14)
    # range-rate accuracy: the Cramér–Rao bound of the N-pulse dwell at the budget's single-pulse SNR
    # (checked against a Monte Carlo of the ML estimator in tests/physics/test_measurement_accuracy.py)
    t_rms = mp.sqrt(((f["n_pulses"] ** 2 - 1) / f["prf_hz"] ** 2 + f["pulse_width_s"] ** 2) / 12)
    snr_n = f["n_pulses"] * mp.mpf(10) ** (mp.mpf(float(ev["snr_db"])) / 10)
    sigma_v = lam / (4 * mp.pi * t_rms * mp.sqrt(2 * snr_n))
    sigma_prior = lam * f["prf_hz"] / (2 * mp.sqrt(12))  # folded into one blind-speed interval
    folded = 1 / mp.sqrt(1 / sigma_v**2 + 1 / sigma_prior**2)
    assert float(ev["range_rate_accuracy_mps"]) == pytest.approx(float(folded), rel=1e-13)


def test_chain_free_space_detection_range_closed_form():
    ev = EVAL_A(complete_parameters(SCENE_A, PARAMS_A))
    snr_1m = float(ev["snr_db"]) + 40 * math.log10(PARAMS_A["range_m"])
    want = 10 ** ((snr_1m - PARAMS_A["detectability_db"]) / 40)
    assert float(ev["detection_range_found"]) == 1.0
    assert abs(float(ev["detection_range_m"]) / want - 1) < 1e-10


def test_chain_jit_vmap_over_range_batch():
    ranges = jnp.array([1e3, 1e4, 1e5, 1e6])
    p = complete_parameters(SCENE_A, PARAMS_A)
    batched = jax.vmap(lambda r: EVAL_A(dict(p, range_m=r)).values["snr_db"])(ranges)
    for r, s in zip(ranges, batched):
        want = float(mp_budget_snr_db(dict(PARAMS_A, range_m=float(r)))[0])
        assert abs(float(s) - want) < 1e-10
    budgets = jax.vmap(lambda r: EVAL_A(dict(p, range_m=r)).budget)(ranges)
    assert budgets["range_db"].shape == (4,)


_GRAD_A = jax.jit(jax.grad(lambda q, out: EVAL_A(q).values[out], argnums=0), static_argnums=1)


def test_chain_gradients_closed_forms():
    p = complete_parameters(SCENE_A, PARAMS_A)
    g = _GRAD_A(p, "snr_db")
    ln10 = math.log(10)
    assert abs(float(g["range_m"]) - (-40 / (PARAMS_A["range_m"] * ln10))) < 1e-14
    assert abs(float(g["gain_db"]) - 2.0) < 1e-12
    assert abs(float(g["bandwidth_hz"]) - (-10 / (PARAMS_A["bandwidth_hz"] * ln10))) < 1e-16
    assert abs(float(g["freq_hz"]) - (-20 / (PARAMS_A["freq_hz"] * ln10))) < 1e-20
    # free space: R_det ∝ Pt^(1/4), so dR/dPt = R/(4 Pt) (implicit derivative through the root)
    gr = _GRAD_A(p, "detection_range_m")
    r = float(EVAL_A(p)["detection_range_m"])
    assert abs(float(gr["peak_power_w"]) / (r / (4 * PARAMS_A["peak_power_w"])) - 1) < 1e-8
    assert abs(float(gr["range_m"])) == 0.0


def test_chain_gradient_equals_central_difference_in_noise_figure():
    p = complete_parameters(SCENE_A, PARAMS_A)
    g = float(_GRAD_A(p, "detection_range_m")["noise_figure_db"])
    h = 1e-4
    rp = float(EVAL_A(dict(p, noise_figure_db=p["noise_figure_db"] + h))["detection_range_m"])
    rm = float(EVAL_A(dict(p, noise_figure_db=p["noise_figure_db"] - h))["detection_range_m"])
    fd = (rp - rm) / (2 * h)
    assert abs(g / fd - 1) < 1e-7  # float64 central difference: O(h²) + round-off ~1e-9


# --- scene B: circular antenna, mismatch filter, many parts -----------------------------------
SCENE_B = Scene(
    "radar",
    ["gas", "rain", "fog", "dust", "rain_clutter", "dust_clutter", "wall_clutter", "jammer"],
    {"detectability": "given", "matched_filter": "two_tuned"},
)
PARAMS_B = dict(
    range_m=5e3, peak_power_w=1e4, pulse_width_s=1e-6, freq_hz=10e9, bandwidth_hz=0.613e6, noise_figure_db=4.0,
    prf_hz=2e3, n_pulses=10.0, antenna_diameter_m=1.2, detectability_db=12.0, jammer_power_w=1.0,
    jammer_gain_db=0.0, jammer_bandwidth_hz=20e6, rain_rate_mm_h=10.0, visibility_m=200.0,
)
EVAL_B = evaluator(SCENE_B)


def test_chain_circular_antenna_gain_and_book_beamwidth():
    ev = EVAL_B(complete_parameters(SCENE_B, PARAMS_B))
    lam = SPEED_OF_LIGHT_M_S / 10e9
    d = 1.2
    g = 4 * math.pi * 0.7 * (math.pi * d * d / 4) / lam**2
    assert abs(float(ev["gain_db"]) - 10 * math.log10(g)) < 1e-12
    assert abs(float(ev["beamwidth_deg"]) - 70 * lam / d) < 1e-12  # book 8.16.7: θ = 70 λ/d deg


def test_chain_mismatch_loss_two_tuned_book_table_9_1():
    # two cascaded tuned circuits, βτ = 0.613: 0.56 dB (Skolnik Table 5.1 = Brooker Table 9.1, 2 digits)
    ev = EVAL_B(complete_parameters(SCENE_B, PARAMS_B))
    assert abs(float(ev.budget["matched_filter_loss_db"]) + 0.56) < 0.005


def test_chain_interference_outputs_are_consistent():
    ev = EVAL_B(complete_parameters(SCENE_B, PARAMS_B))
    v = {k: float(x) for k, x in ev.values.items()}
    lin = lambda x: 10 ** (x / 10)
    # S/(N+J) from S/N and S/J; S/(N+J+C) adds S/C
    assert abs(v["sjnr_db"] + 10 * math.log10(1 / lin(v["snr_db"]) + 1 / lin(v["sjr_db"]))) < 1e-9
    inv = 1 / lin(v["snr_db"]) + 1 / lin(v["sjr_db"]) + 1 / lin(v["scr_db"])
    assert abs(v["sinr_db"] + 10 * math.log10(inv)) < 1e-9
    # detection margin: S >= SNR_req (N + J) + SCR_req C
    m = -10 * math.log10(lin(12.0 - v["sjnr_db"]) + lin(13.0 - v["scr_db"]))
    assert abs(v["detection_margin_db"] - m) < 1e-9
    # the attenuation parts add up
    parts = sum(float(ev.budget[f"{k}_attenuation_db"]) for k in ("gas", "rain", "fog", "dust"))
    assert abs(v["two_way_attenuation_db"] + parts) < 1e-12


def test_chain_detection_range_has_zero_margin_and_burn_through_has_required_sjr():
    p = complete_parameters(SCENE_B, PARAMS_B)
    ev = EVAL_B(p)
    assert float(ev["detection_range_found"]) == 1.0
    at = EVAL_B(dict(p, range_m=ev["detection_range_m"]))
    assert abs(float(at["detection_margin_db"])) < 1e-8
    at_bt = EVAL_B(dict(p, range_m=ev["burn_through_range_m"]))
    assert abs(float(at_bt["sjr_db"]) - 12.0) < 1e-8


_SUM_B = jax.jit(jax.value_and_grad(lambda q: sum(jnp.sum(v) for v in EVAL_B(q).values.values())))

_LOG_DOMAIN = {  # log10 ranges drawn for the finiteness test (inside the documented domains)
    "range_m": (1.0, 6.0), "peak_power_w": (-2.0, 8.0), "pulse_width_s": (-8.0, -4.0), "freq_hz": (9.0, 11.4),
    "antenna_diameter_m": (-1.0, 1.0), "rain_rate_mm_h": (-1.0, 2.3), "visibility_m": (0.5, 4.0),
    "jammer_power_w": (-3.0, 4.0), "rcs_m2": (-3.0, 3.0),
}


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=len(_LOG_DOMAIN) + 1, max_size=len(_LOG_DOMAIN) + 1))
def test_chain_outputs_and_gradients_finite_over_domain(u):
    p = complete_parameters(SCENE_B, PARAMS_B)
    for (name, (lo, hi)), x in zip(_LOG_DOMAIN.items(), u):
        p[name] = jnp.asarray(10 ** (lo + (hi - lo) * x), dtype=float)
    p["bandwidth_hz"] = 0.613 / p["pulse_width_s"] * (0.5 + u[-1])  # βτ in the filter's domain
    value, grads = _SUM_B(p)
    assert np.isfinite(float(value))
    assert all(np.isfinite(float(g)) for g in grads.values())


# --- scene C: exact detection, steady target, one pulse ---------------------------------------
SCENE_C = Scene("radar", [], {"antenna": "specified", "detectability": "exact", "matched_filter": "matched", "swerling": 0})
PARAMS_C = dict(PARAMS_A, n_pulses=1.0, pd=0.9, pfa=1e-6)
del PARAMS_C["detectability_db"]
EVAL_C = evaluator(SCENE_C)


def scipy_pd_steady(snr_db, pfa):
    """Single-pulse steady target, square law: Pd = P(noncentral χ²₂(2S) > 2T), T = -ln Pfa."""
    return stats.ncx2.sf(-2 * math.log(pfa), 2, 2 * 10 ** (snr_db / 10))


def test_chain_exact_pd_and_required_snr_match_scipy_noncentral_chi_square():
    p = complete_parameters(SCENE_C, PARAMS_C)
    for r in (60e3, 90e3, 120e3):
        ev = EVAL_C(dict(p, range_m=jnp.asarray(r, dtype=float)))
        assert abs(float(ev["pd"]) - scipy_pd_steady(float(ev["snr_db"]), 1e-6)) < 1e-9
    req = optimize.brentq(lambda x: scipy_pd_steady(x, 1e-6) - 0.9, 0.0, 30.0, xtol=1e-12)
    ev = EVAL_C(p)
    assert abs(float(ev["required_snr_db"]) - req) < 1e-8  # DiFranco & Rubin: 13.18 dB
    assert abs(float(ev["integration_gain_db"])) < 1e-9
    # at the detection range the SNR equals the requirement, so Pd equals the target
    at = EVAL_C(dict(p, range_m=ev["detection_range_m"]))
    assert abs(float(at["pd"]) - 0.9) < 1e-8


_GRAD_C = jax.jit(jax.grad(lambda q: EVAL_C(q).values["pd"] + EVAL_C(q).values["snr_margin_db"] + EVAL_C(q).values["detection_range_m"] * 1e-5))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 7.0), st.floats(0.05, 0.999999), st.floats(-15.0, -2.0), st.floats(1.0, 1e4))
def test_chain_exact_detection_gradients_finite(log_r, pd, log_pfa, n):
    p = complete_parameters(SCENE_C, PARAMS_C)
    p.update(range_m=jnp.asarray(10**log_r, dtype=float), pd=jnp.asarray(pd, dtype=float), pfa=jnp.asarray(10**log_pfa, dtype=float), n_pulses=jnp.asarray(n, dtype=float))
    g = _GRAD_C(p)
    assert all(np.isfinite(float(x)) for x in g.values())


# --- structure and domain ---------------------------------------------------------------------


def test_absent_parts_are_not_traced():
    for scene, params, want in ((SCENE_A, PARAMS_A, set()), (SCENE_B, PARAMS_B, set(SCENE_B.parts))):
        jx = jax.make_jaxpr(lambda q: evaluate(scene, q).values)(complete_parameters(scene, params))
        assert traced_parts(jx) == want


def test_part_parameters_listed_only_when_the_part_exists():
    plain = parameter_table(Scene("radar", [], {"detectability": "given"}))
    for name in ("rain_rate_mm_h", "jammer_power_w", "sea_state", "pass_diameter_m", "required_scr_db", "visibility_m"):
        assert name not in plain
    rain = parameter_table(Scene("radar", ["rain"]))
    assert rain["rain_rate_mm_h"].part == "rain"
    assert parameter_table(Scene("radar", ["wall_clutter"]))["required_scr_db"].part == "wall_clutter"
    outs = output_table(Scene("radar", ["jammer"]))
    assert "burn_through_range_m" in outs and "scr_db" not in outs


def test_parameter_units_parse_and_domains_are_set():
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    full = Scene("radar", list(diffsense.sensors.radar.PARTS), {"jammer_type": "stand_off"})
    for prm in parameter_table(full).values():
        ureg.Unit(prm.unit)
        assert prm.lo is not None and prm.hi is not None and prm.lo < prm.hi, prm.name
        assert prm.doc
        if prm.default is not None:
            assert prm.lo <= prm.default <= prm.hi, prm.name
    assert parameter_table(full)["n_pulses"].integer


@pytest.mark.parametrize(
    "scene, params",
    [
        (Scene("radar", ["snow"]), {}),
        (Scene("radar", [], {"swerling": 5}), {}),
        (Scene("radar", [], {"window": "hann"}), {}),
        (Scene("radar", [], {"integration": "coherent", "swerling": 2}), {}),
        (SCENE_A, dict(PARAMS_A, range_m=0.5)),
        (SCENE_A, dict(PARAMS_A, pd=0.9)),
        (SCENE_A, {k: v for k, v in PARAMS_A.items() if k != "peak_power_w"}),
        (SCENE_A, dict(PARAMS_A, freq_hz=5e8)),
        (Scene("radar", [], {"antenna": "specified", "detectability": "given"}), dict(PARAMS_A, bandwidth_hz=1e9)),
    ],
)
def test_chain_rejects_bad_scenes_and_parameters(scene, params):
    with pytest.raises(DomainError):
        evaluate(scene, params)


def test_stand_off_jammer_sjr_equals_mpmath_closed_form():
    # S/J = Pt G² σ R_j² β_j / (4π R⁴ P_j G_j G_sl min(β_r, β_j) L): λ cancels (book 9.10, eq 9.31)
    scene = Scene("radar", ["jammer"], {"antenna": "specified", "detectability": "given", "matched_filter": "matched",
                                         "jammer_type": "stand_off"})
    extra = dict(jammer_power_w=200.0, jammer_gain_db=10.0, jammer_bandwidth_hz=30e6, jammer_range_m=80e3, jammer_sidelobe_gain_db=-5.0)
    ev = evaluator(scene)(complete_parameters(scene, dict(PARAMS_A, **extra)))
    f = {k: mp.mpf(str(v)) for k, v in dict(PARAMS_A, **extra).items()}
    db = lambda x: mp.mpf(10) ** (x / 10)
    loss = db(f["transmit_loss_db"] + f["scan_loss_db"] + f["cfar_loss_db"] + f["misc_loss_db"])
    sj = (f["peak_power_w"] * db(2 * f["gain_db"]) * f["rcs_m2"] * f["jammer_range_m"] ** 2 * f["jammer_bandwidth_hz"]
          / (4 * mp.pi * f["range_m"] ** 4 * f["jammer_power_w"] * db(f["jammer_gain_db"] + f["jammer_sidelobe_gain_db"])
             * f["bandwidth_hz"] * loss))
    assert abs(float(ev["sjr_db"]) - float(10 * mp.log10(sj))) < 1e-9
    assert "burn_through_range_m" not in ev.values
    # stand-off jamming does not change with target range: the detection range solves S = req (N + J)
    lin = lambda x: 10 ** (x / 10)
    at = evaluator(scene)(complete_parameters(scene, dict(PARAMS_A, **extra, range_m=float(ev["detection_range_m"]))))
    assert abs(float(at["sjnr_db"]) - PARAMS_A["detectability_db"]) < 1e-8
