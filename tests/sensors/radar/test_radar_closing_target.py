"""Radar part ``closing_target``: cumulative detection probability of a target closing at a
constant speed, one look per scan (Mallett & Brennan 1963; Skolnik 2001 ch. 2).

Independent reference: for a Swerling 1 target with one pulse, the single-look Pd is the closed
form Pd = Pfa^(1/(1+S)) (Swerling 1957); the free-space SNR falls as R^-4 from the chain's own
SNR at range_m (an mpmath budget of the same inputs, see test_radar_chain.py), and the looks
are at R + i v T up to the first-look range. Pc = 1 - prod(1 - Pd_i), all in mpmath.
"""

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.scene import Scene, complete_parameters, evaluate, evaluator, output_table

MPMATH_DPS = 30
SCENE = Scene("radar", ["closing_target"], {"antenna": "specified", "detectability": "exact", "matched_filter": "matched",
                                            "swerling": 1})
P = dict(range_m=60e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1e6, noise_figure_db=3.0,
         prf_hz=1e3, n_pulses=1.0, gain_db=33.0, beamwidth_az_deg=1.5, beamwidth_el_deg=3.0, pd=0.9, pfa=1e-6,
         closing_speed_mps=300.0, scan_period_s=10.0, first_look_range_m=100e3)
EVAL = evaluator(SCENE)


def _mp_cumulative(snr0_db, p):
    r0, step, first = mp.mpf(p["range_m"]), mp.mpf(p["closing_speed_mps"]) * p["scan_period_s"], mp.mpf(p["first_look_range_m"])
    s0 = mp.mpf(10) ** (mp.mpf(snr0_db) / 10)
    miss, i = mp.mpf(1), 0
    while r0 + i * step <= first:
        s = s0 * (r0 / (r0 + i * step)) ** 4
        miss *= 1 - mp.mpf(p["pfa"]) ** (1 / (1 + s))
        i += 1
    return 1 - miss, i


def test_cumulative_pd_equals_the_product_of_swerling_1_looks():
    ev = EVAL(complete_parameters(SCENE, P))
    ref, looks = _mp_cumulative(float(ev["snr_db"]), P)
    assert looks == 14  # 60, 63, ..., 99 km
    assert abs(float(ev["cumulative_pd"]) - float(ref)) < 1e-12
    # one look: the single-look Pd at range_m
    one = EVAL(complete_parameters(SCENE, dict(P, first_look_range_m=P["range_m"])))
    assert abs(float(one["cumulative_pd"]) - float(one["pd"])) < 1e-14
    assert float(ev["cumulative_pd"]) > float(one["pd"])


def test_gradient_in_power_matches_central_differences():
    def pc(power):
        return EVAL(complete_parameters(SCENE, dict(P, peak_power_w=power)))["cumulative_pd"]

    g = float(jax.grad(pc)(2e5))
    h = 1.0
    assert g == pytest.approx((float(pc(2e5 + h)) - float(pc(2e5 - h))) / (2 * h), rel=1e-6)
    assert g > 0


def test_too_many_looks_and_a_first_look_inside_range_are_refused():
    # the checked (eager) evaluation refuses; a traced one gives NaN, never a truncated product
    with pytest.raises(DomainError, match="at most 64"):
        evaluate(SCENE, dict(P, first_look_range_m=1e6))
    with pytest.raises(DomainError, match="first_look_range_m"):
        evaluate(SCENE, dict(P, first_look_range_m=50e3))
    assert mp.isnan(float(EVAL(complete_parameters(SCENE, dict(P, first_look_range_m=1e6)))["cumulative_pd"]))


def test_needs_a_detection_model():
    with pytest.raises(DomainError, match="closing_target"):
        output_table(Scene("radar", ["closing_target"], {"detectability": "given"}))
