"""Post-optimal sensitivities against closed forms, published multipliers and re-solves.

Closed forms: Brooker eq. 14.12 (servo bandwidth) differentiated by hand; the energy-constrained
power/pulse-width problem and the simplex projection derived in each test. Published: the
HS071 multipliers of the Ipopt HS071 example (Hock & Schittkowski problem 71), which by the
envelope theorem are d f*/d(constraint constants). Finite differences: central differences
of full re-solves (float64; step and tolerance stated per test).
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.optimize import (
    Problem,
    SolverOptions,
    differentiable_solver,
    kkt_sensitivity,
    make_solver,
    solve,
)
from diffsense.optimize import reference_problems as rp
from diffsense.optimize.compile import jit_with_options

OPTS = SolverOptions()
SERVO = rp.servo_bandwidth()
SERVO_SOL = differentiable_solver(SERVO.problem, OPTS)
ONE = jnp.array([1.0])

# d ln(beta_o) / d ln(theta) and d ln(f*) / d ln(theta) from eq. 14.12 and f* = (5/4) A beta_o,
# A = theta3dB^2 / (2 km^2 fr btau SNR): beta_o ∝ (at^2 km^2 fr btau SNR / (theta^2 R^2))^(1/5)
BETA_EXP = {"snr": 0.2, "range_m": -0.4, "accel_m_s2": 0.4, "theta3db_rad": -0.4, "prf_hz": 0.2, "km": 0.4}
F_EXP = {"snr": -0.8, "range_m": -0.4, "accel_m_s2": 0.4, "theta3db_rad": 1.6, "prf_hz": -0.8, "km": -1.6}

_servo_jac_x = jit_with_options(jax.jacfwd(lambda th: SERVO_SOL(ONE, th).x[0]), "fast")
_servo_grad_f = jit_with_options(jax.grad(lambda th: SERVO_SOL(ONE, th).f), "fast")


def test_servo_bandwidth_derivatives_book_14_12_forward_and_reverse():
    th = SERVO.theta
    bo = float(rp.servo_optimum_hz(th))
    fo = float(rp.servo_error_variance(bo, th))
    dx = _servo_jac_x(th)  # forward mode
    df = _servo_grad_f(th)  # reverse mode through the custom JVP
    for k, e in BETA_EXP.items():
        np.testing.assert_allclose(float(dx[k]), e * bo / float(th[k]), rtol=1e-9, err_msg=k)
    for k, e in F_EXP.items():
        np.testing.assert_allclose(float(df[k]), e * fo / float(th[k]), rtol=1e-9, err_msg=k)


def test_servo_sensitivity_vmapped_over_snr():
    snr = jnp.array([1.0, 10.0, 100.0, 1000.0])
    ths = {k: jnp.broadcast_to(v, (4,)) for k, v in SERVO.theta.items()}
    ths["snr"] = snr
    d = jit_with_options(jax.vmap(jax.grad(lambda th: SERVO_SOL(ONE, th).x[0])), "fast")(ths)
    bo = rp.servo_optimum_hz(ths)
    np.testing.assert_allclose(np.asarray(d["snr"]), np.asarray(0.2 * bo / snr), rtol=1e-9)


# "what does one more dB of required SNR cost?" -- the SNR given in dB
_SNR_DB_PROBLEM = Problem(
    lambda x, snr_db: rp.servo_error_variance(x[0], {**SERVO.theta, "snr": 10.0 ** (snr_db / 10.0)}),
    0.01, 1000.0, log_scale=True)
_SNR_DB_SOL = differentiable_solver(_SNR_DB_PROBLEM, OPTS)
_snr_db_value_and_grad = jit_with_options(jax.value_and_grad(lambda s: _SNR_DB_SOL(ONE, s).f), "fast")


@settings(max_examples=10, deadline=None)
@given(st.floats(min_value=-5.0, max_value=40.0))
def test_cost_of_one_more_db_of_snr_closed_form(snr_db):
    # f* ∝ SNR^(-4/5)  ->  d f*/d SNR_dB = -(4/5) f* ln(10)/10   (rad^2 per dB)
    f, g = _snr_db_value_and_grad(jnp.asarray(snr_db))
    assert np.isfinite(float(g))
    th = {**SERVO.theta, "snr": 10.0 ** (snr_db / 10.0)}
    fo = float(rp.servo_error_variance(rp.servo_optimum_hz(th), th))
    np.testing.assert_allclose(float(f), fo, rtol=1e-12)
    np.testing.assert_allclose(float(g), -0.8 * fo * math.log(10.0) / 10.0, rtol=1e-9)


def test_energy_requirement_shadow_price_and_design_sensitivity():
    # minimise a P + b tau s.t. P tau >= E: P* = sqrt(bE/a), tau* = sqrt(aE/b), f* = 2 sqrt(abE)
    # -> d f*/dE = sqrt(ab/E) = lambda, dP*/dE = P*/(2E), dtau*/dE = tau*/(2E)
    a, b, E = 1e-3, 1e6, 1e-3
    prob = Problem(lambda x, e: a * x[0] + b * x[1], [1.0, 1e-9], [1e6, 1e-3],
                   inequality=lambda x, e: jnp.array([e - x[0] * x[1]]), log_scale=True)
    r = jit_with_options(lambda e: solve(prob, jnp.array([1e5, 1e-8]), e, OPTS), "fast")(jnp.asarray(E))
    S = jit_with_options(lambda r, e: kkt_sensitivity(prob, r, e, OPTS), "fast")(r, jnp.asarray(E))
    P, tau = math.sqrt(b * E / a), math.sqrt(a * E / b)
    np.testing.assert_allclose(float(S.df), math.sqrt(a * b / E), rtol=1e-9)
    np.testing.assert_allclose(float(r.lam[0]), math.sqrt(a * b / E), rtol=1e-9)
    np.testing.assert_allclose(np.asarray(S.dx), [P / (2 * E), tau / (2 * E)], rtol=1e-8)
    # dlambda/dE = d sqrt(ab/E)/dE = -lambda/(2E)
    np.testing.assert_allclose(float(S.dlam[0]), -math.sqrt(a * b / E) / (2 * E), rtol=1e-8)


def _hs071_parametric():
    def f(x, t):
        return x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2]
    return Problem(f, 1.0, 5.0 * np.ones(4), inequality=lambda x, t: jnp.array([t[0] - jnp.prod(x)]),
                   equality=lambda x, t: jnp.array([jnp.sum(x**2) - t[1]]))


def test_hs071_sensitivity_matches_published_multipliers_and_resolves():
    prob = _hs071_parametric()
    x0 = jnp.array([1.0, 5.0, 5.0, 1.0])
    run = jit_with_options(lambda t: solve(prob, x0, t, OPTS), "fast")
    t = jnp.array([25.0, 40.0])
    r = run(t)
    S = jit_with_options(lambda r, t: kkt_sensitivity(prob, r, t, OPTS), "fast")(r, t)
    # envelope theorem: d f*/d(25) = lambda, d f*/d(40) = -nu (Ipopt HS071 example multipliers)
    np.testing.assert_allclose(np.asarray(S.df), [0.5522937, -0.1614686], rtol=2e-6)
    # central differences of re-solves, h = 1e-4; truncation O(h^2) ~ 1e-8, solve accuracy ~1e-13
    h = 1e-4
    for i in range(2):
        e = jnp.zeros(2).at[i].set(h)
        rp_, rm_ = run(t + e), run(t - e)
        np.testing.assert_allclose(np.asarray(S.dx[:, i]), np.asarray((rp_.x - rm_.x) / (2 * h)), atol=1e-7)
        np.testing.assert_allclose(float(S.df[i]), float((rp_.f - rm_.f) / (2 * h)), rtol=1e-7)
        np.testing.assert_allclose(np.asarray(S.dlam[:, i]), np.asarray((rp_.lam - rm_.lam) / (2 * h)), atol=1e-7)
        np.testing.assert_allclose(np.asarray(S.dnu[:, i]), np.asarray((rp_.nu - rm_.nu) / (2 * h)), atol=1e-7)
    # the envelope value equals the chain rule grad f . dx/dtheta (f has no explicit theta)
    gf = jax.grad(lambda x: prob.f(x, t))(r.x)
    np.testing.assert_allclose(np.asarray(gf @ S.dx), np.asarray(S.df), rtol=1e-8)


def test_simplex_projection_jacobian_closed_form():
    # x*(a) = max(a - tau, 0): on the support S, dx_S/da_S = I - 11^T/|S|, zero elsewhere;
    # nu = tau = (sum_S a - 1)/|S| -> dnu/da_S = 1/|S|
    P = rp.simplex_projection()
    sol = differentiable_solver(P.problem, OPTS)
    a = jnp.array([0.9, 0.6, -0.2, 0.1])
    jac = jit_with_options(jax.jacrev(lambda a: sol(jnp.full(4, 0.25), a)), "fast")(a)
    xs = rp.simplex_projection_solution(np.asarray(a))
    S = xs > 0
    k = S.sum()
    expected = np.zeros((4, 4))
    expected[np.ix_(S, S)] = np.eye(k) - 1.0 / k
    np.testing.assert_allclose(np.asarray(jac.x), expected, atol=1e-10)
    np.testing.assert_allclose(np.asarray(jac.nu[0]), np.where(S, 1.0 / k, 0.0), atol=1e-10)
    # f* = 0.5 |x* - a|^2 -> envelope d f*/da = a - x* - 0 (the constraint does not involve a)
    np.testing.assert_allclose(np.asarray(jac.f), np.asarray(a) - xs, atol=1e-10)


def test_sensitivity_needs_parameters():
    prob = Problem(lambda x, _: jnp.sum(x**2), -np.ones(2), np.ones(2))
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([0.5, 0.5]))
    with pytest.raises(DomainError):
        kkt_sensitivity(prob, r, None)
