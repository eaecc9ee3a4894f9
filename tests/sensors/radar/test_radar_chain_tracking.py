"""The radar chain's "tracking" part (range α-β tracker and angle servo) through the public chain.

References used by the assertions:
- Book §13.6 ``ablag.m``: a = 10 m/s², f_s = 50 Hz, SNR 10 dB, gate 3 m; split-gate noise
  σ = gate/(2.5 √(2 SNR)), variance reduction as the sum of squares of the impulse response of
  H(z) = (α + (β − α) z⁻¹)/(1 + (α + β − 2) z⁻¹ + (1 − α) z⁻²) (book eq 13.10, computed here by
  scipy.signal.lfilter on a unit impulse, as the script does), lag a T²(1 − α)/β.
- A direct simulation of the α-β recursion (book eqs 13.2-13.5) on a constant-acceleration
  trajectory: its steady-state error is the lag.
- Book eqs (14.9)-(14.12) for the servo, evaluated in mpmath (40 digits), with the chain's own
  SNR and the book's beamwidth θ = 70 λ/d deg; β_o must be the stationary point of σ_θ.
- Book eqs (13.11), (13.12) for the gains.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.scene import complete_parameters, evaluate, evaluator, output_table, parameter_table
from diffsense.sensors.parts import traced_parts
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.scene import Scene

MPMATH_DPS = 40  # working precision of this module's tests (set per test by tests/conftest.py)

OPTS = {"antenna": "circular_aperture", "detectability": "given", "matched_filter": "matched"}
TRACK = Scene("radar", ["tracking"], OPTS)
TRACK_CD = Scene("radar", ["tracking"], dict(OPTS, tracking_gains="critically_damped"))
PLAIN = Scene("radar", [], OPTS)
PARAMS = dict(
    range_m=8e3, peak_power_w=5e3, pulse_width_s=0.2e-6, freq_hz=16e9, bandwidth_hz=5e6, noise_figure_db=5.0,
    prf_hz=5e3, antenna_diameter_m=1.2, detectability_db=15.0, track_alpha=0.05, servo_bandwidth_hz=2.0,
    positioner_resonance_hz=30.0, target_acceleration_m_s2=20.0, monopulse_slope=1.6,
)
EVAL = evaluator(TRACK)
EVAL_CD = evaluator(TRACK_CD)


def run(scene=TRACK, **extra):
    ev = (EVAL_CD if scene is TRACK_CD else EVAL)
    return ev(complete_parameters(scene, dict(PARAMS, **extra)))


def book_ablag_params():
    """Chain parameters of the book's ablag.m case: 3 m gate, 50 Hz, SNR exactly 10 dB."""
    gate_pulse = 2 * 3.0 / SPEED_OF_LIGHT_M_S
    p = dict(PARAMS, pulse_width_s=gate_pulse, bandwidth_hz=1 / gate_pulse, prf_hz=50.0, target_acceleration_m_s2=10.0)
    snr0 = float(EVAL(complete_parameters(TRACK, p))["snr_db"])
    p["peak_power_w"] = p["peak_power_w"] * 10 ** ((10.0 - snr0) / 10)  # SNR ∝ Pt
    return p


def impulse_vrr(alpha, beta, n=4000):
    """Σ h² of the α-β position transfer function (book eq 13.10) by filtering a unit impulse."""
    x = np.zeros(n)
    x[0] = 1.0
    h = signal.lfilter([alpha, beta - alpha], [1.0, beta + alpha - 2.0, 1.0 - alpha], x)
    return float(np.sum(h * h))


def test_book_ablag_split_gate_noise_variance_reduction_and_lag_13_6():
    p = book_ablag_params()
    sigma_book = 3.0 / (2.5 * math.sqrt(2 * 10.0))  # ablag.m: tau/(2.5 sqrt(2 snr)) = 0.2683 m
    for alpha in (0.1, 0.25, 0.5, 0.75, 1.0):  # the script sweeps 0.1:0.01:1
        ev = EVAL(complete_parameters(TRACK, dict(p, track_alpha=alpha)))
        assert abs(float(ev["snr_db"]) - 10.0) < 1e-12
        beta = alpha**2 / (2 - alpha)  # book eq 13.11
        assert float(ev["track_beta"]) == pytest.approx(beta, rel=1e-14)
        assert float(ev["range_noise_m"]) == pytest.approx(sigma_book, rel=1e-12)
        vrr = impulse_vrr(alpha, beta)
        assert float(ev["range_variance_reduction"]) == pytest.approx(vrr, rel=1e-10)
        lag = 10.0 * (1 / 50.0) ** 2 * (1 - alpha) / beta
        assert float(ev["range_lag_m"]) == pytest.approx(lag, rel=1e-12, abs=1e-15)
        assert float(ev["range_track_noise_m"]) == pytest.approx(sigma_book * math.sqrt(vrr), rel=1e-10)
        assert float(ev["range_track_error_m"]) == pytest.approx(math.sqrt(lag**2 + sigma_book**2 * vrr), rel=1e-10)


def test_range_lag_equals_simulated_steady_state_error_of_the_recursion():
    # α-β recursion (book eqs 13.2-13.5) on R(t) = a t²/2 sampled at the PRF, no noise
    alpha = 0.3
    ev = run(track_alpha=alpha, prf_hz=100.0, target_acceleration_m_s2=20.0)
    beta = float(ev["track_beta"])
    t = np.arange(3000) / 100.0
    meas = 0.5 * 20.0 * t**2
    xp, vp = 0.0, 0.0
    for z in meas:
        x = xp + alpha * (z - xp)
        v = vp + beta * 100.0 * (z - xp)
        xp, vp = x + v / 100.0, v
    assert meas[-1] - x == pytest.approx(float(ev["range_lag_m"]), rel=1e-9)


def test_critically_damped_gains_satisfy_book_eq_13_12():
    for alpha in (0.05, 0.4, 0.9):
        ev = run(TRACK_CD, track_alpha=alpha)
        beta = float(ev["track_beta"])
        assert alpha == pytest.approx(2 * math.sqrt(beta) - beta, rel=1e-13)
        assert float(ev["range_variance_reduction"]) == pytest.approx(impulse_vrr(alpha, beta), rel=1e-10)


def servo_mp(ev, p):
    """Book eqs (14.10)-(14.12) in mpmath with the chain's SNR and θ = 70 λ/d deg."""
    f = {k: mp.mpf(str(v)) for k, v in p.items()}
    snr = mp.mpf(10) ** (mp.mpf(float(ev["snr_db"])) / 10)
    lam = mp.mpf(SPEED_OF_LIGHT_M_S) / f["freq_hz"]
    theta = mp.radians(70 * lam / f["antenna_diameter_m"])
    bt = f["bandwidth_hz"] * f["pulse_width_s"]
    a, km, fr, r, bn = (f[k] for k in ("target_acceleration_m_s2", "monopulse_slope", "prf_hz", "range_m", "servo_bandwidth_hz"))
    noise = theta**2 * bn / (2 * km**2 * fr * bt * snr)
    lag = a / r / (mp.mpf("2.5") * bn**2)  # eq 14.10 with K_a = 2.5 β_n² (14.9)
    beta_o = (mp.mpf("1.28") * a**2 * km**2 * fr * bt * snr / (theta**2 * r**2)) ** (mp.mpf(1) / 5)
    return noise, lag, beta_o


def test_servo_angle_error_and_optimum_bandwidth_book_14_9_to_14_12():
    for extra in ({}, dict(range_m=2e3, servo_bandwidth_hz=7.0), dict(range_m=20e3, target_acceleration_m_s2=3.0)):
        p = dict(PARAMS, **extra)
        ev = EVAL(complete_parameters(TRACK, p))
        noise, lag, beta_o = servo_mp(ev, p)
        assert float(ev["angle_noise_rad"]) == pytest.approx(float(mp.sqrt(noise)), rel=1e-12)
        assert float(ev["angle_lag_rad"]) == pytest.approx(float(lag), rel=1e-12)
        # eq 14.11: σ² = noise + a²/(6.25 R² β_n⁴) = noise + lag²
        assert float(ev["angle_error_rad"]) == pytest.approx(float(mp.sqrt(noise + lag**2)), rel=1e-12)
        assert float(ev["cross_range_error_m"]) == pytest.approx(p["range_m"] * float(mp.sqrt(noise + lag**2)), rel=1e-12)
        assert float(ev["servo_optimal_bandwidth_hz"]) == pytest.approx(float(beta_o), rel=1e-12)
        assert float(ev["servo_resonance_ratio"]) == pytest.approx(p["servo_bandwidth_hz"] / 30.0, rel=1e-15)


def test_optimum_bandwidth_is_the_stationary_point_of_the_angle_error():
    # dσ_θ/dβ_n through the public chain vanishes at β_o and changes sign there
    p = complete_parameters(TRACK, PARAMS)
    beta_o = float(EVAL(p)["servo_optimal_bandwidth_hz"])
    dsig = jax.jit(jax.grad(lambda b: EVAL(dict(p, servo_bandwidth_hz=b))["angle_error_rad"]))
    sigma = float(EVAL(dict(p, servo_bandwidth_hz=jnp.asarray(beta_o)))["angle_error_rad"])
    assert abs(float(dsig(jnp.asarray(beta_o)))) * beta_o / sigma < 1e-10
    assert float(dsig(jnp.asarray(0.9 * beta_o))) < 0 < float(dsig(jnp.asarray(1.1 * beta_o)))


def test_tracking_outputs_jit_vmap_and_gradients_equal_central_differences():
    p = complete_parameters(TRACK, PARAMS)
    keys = ("range_track_error_m", "angle_error_rad", "servo_optimal_bandwidth_hz", "range_noise_m")
    ranges = jnp.array([2e3, 8e3, 20e3])
    alphas = jnp.array([0.01, 0.2, 1.0])
    batched = jax.jit(jax.vmap(lambda r, a: {k: EVAL(dict(p, range_m=r, track_alpha=a))[k] for k in keys}))(ranges, alphas)
    for i in range(3):
        one = EVAL(dict(p, range_m=ranges[i], track_alpha=alphas[i]))
        for k in keys:
            assert float(batched[k][i]) == pytest.approx(float(one[k]), rel=1e-13)

    def total(q):
        ev = EVAL(q)
        return ev["range_track_error_m"] + 1e3 * ev["angle_error_rad"]

    grads = jax.jit(jax.grad(total))(p)
    for name in ("track_alpha", "servo_bandwidth_hz", "peak_power_w", "range_m", "antenna_diameter_m",
                 "target_acceleration_m_s2", "monopulse_slope", "pulse_width_s"):
        h = 1e-6 * float(p[name])
        up = float(total(dict(p, **{name: p[name] + h})))
        dn = float(total(dict(p, **{name: p[name] - h})))
        fd = (up - dn) / (2 * h)
        # central difference in float64: truncation O(h²) and rounding ~1e-16/h relative
        assert float(grads[name]) == pytest.approx(fd, rel=1e-6, abs=1e-12), name


_GRAD = jax.jit(jax.grad(lambda q: sum(EVAL(q)[k] for k in (
    "range_track_error_m", "angle_error_rad", "servo_optimal_bandwidth_hz", "cross_range_error_m",
    "servo_resonance_ratio", "range_lag_m", "track_beta"))))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(-3.0, 3.0), st.floats(-3.0, 4.0), st.floats(0.0, 7.0), st.floats(0.0, 8.0),
       st.floats(1.0, 6.0))
def test_tracking_values_and_gradients_finite_over_the_domain(u_alpha, log_bn, log_a, log_r, log_p, log_prf):
    p = complete_parameters(TRACK, PARAMS)
    p.update(track_alpha=jnp.asarray(max(u_alpha, 1e-9)), servo_bandwidth_hz=jnp.asarray(10**log_bn),
             target_acceleration_m_s2=jnp.asarray(10**log_a), range_m=jnp.asarray(10**log_r),
             peak_power_w=jnp.asarray(10**log_p), prf_hz=jnp.asarray(10**log_prf))
    ev = EVAL(p)
    assert all(np.isfinite(float(ev[k])) for k in output_table(TRACK) if k in ev.values)
    assert all(np.isfinite(float(g)) for g in _GRAD(p).values())


def test_tracking_part_traced_only_when_present():
    jx = jax.make_jaxpr(lambda q: evaluate(TRACK, q).values)(complete_parameters(TRACK, PARAMS))
    assert traced_parts(jx) == {"tracking"}
    plain = {k: v for k, v in PARAMS.items() if k in parameter_table(PLAIN)}
    jx = jax.make_jaxpr(lambda q: evaluate(PLAIN, q).values)(complete_parameters(PLAIN, plain))
    assert traced_parts(jx) == set()
    assert "angle_error_rad" not in output_table(PLAIN)


def test_tracking_parameters_belong_to_the_part_with_units_and_domains():
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    with_part, without = parameter_table(TRACK), parameter_table(PLAIN)
    new = set(with_part) - set(without)
    assert new == {"track_alpha", "target_acceleration_m_s2", "servo_bandwidth_hz", "monopulse_slope",
                   "positioner_resonance_hz", "platform_angular_acceleration_rad_s2"}
    for name in new:
        prm = with_part[name]
        assert prm.part == "tracking" and prm.doc
        ureg.Unit(prm.unit)
        assert prm.lo is not None and prm.hi is not None and prm.lo < prm.hi
        if prm.default is not None:
            assert prm.lo <= prm.default <= prm.hi
    assert with_part["monopulse_slope"].default == 1.6  # book 14.7, below eq 14.12
    assert not with_part["track_alpha"].hi_open and parameter_table(TRACK_CD)["track_alpha"].hi_open


@pytest.mark.parametrize(
    "scene, extra",
    [
        (TRACK, dict(track_alpha=0.0)),
        (TRACK, dict(track_alpha=1.5)),
        (TRACK_CD, dict(track_alpha=1.0)),
        (TRACK, dict(servo_bandwidth_hz=0.0)),
        (TRACK, dict(positioner_resonance_hz=-1.0)),
        (TRACK, dict(target_acceleration_m_s2=0.0)),
        (TRACK, dict(servo_bandwidth_hz=None)),
    ],
)
def test_tracking_domain_errors(scene, extra):
    p = dict(PARAMS, **extra)
    p = {k: v for k, v in p.items() if v is not None}
    with pytest.raises(DomainError):
        evaluate(scene, p)
