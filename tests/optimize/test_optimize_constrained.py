"""Augmented-Lagrangian solver against problems with published or closed-form optima.

Sources: Hock & Schittkowski, *Test Examples for Nonlinear Programming Codes* (LNEMS 187,
1981) for the HS problems (optimal values and points as published, so tolerances follow the
published digits); the Ipopt documentation's HS071 example output for HS071's multipliers;
Brooker eqs. 14.11–14.12 for the servo bandwidth; closed forms derived in each test.
"""

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.optimize import Problem, SolverOptions, make_solver, solve
from diffsense.optimize import reference_problems as rp

from helpers.reference_checks import (
    HS_WITH_PUBLISHED_OPTIMUM,
    assert_hs071_ipopt_multipliers,
    assert_published_optimum,
)

OPTS = SolverOptions()


@functools.lru_cache(maxsize=None)
def _ref(name):
    return getattr(rp, name)()


@functools.lru_cache(maxsize=None)
def _solver(name, inner="fused"):
    return make_solver(_ref(name).problem, SolverOptions(inner=inner), compile="fast")


def _run(name, inner="fused", x0=None):
    P = _ref(name)
    return _solver(name, inner)(jnp.asarray(P.x0 if x0 is None else x0), P.theta)


# published digits: f* to 1e-7 relative (HS quotes 7-10 significant digits), x* to 1e-6
@pytest.mark.parametrize("inner", ["fused", "bfgs"])
@pytest.mark.parametrize("name", HS_WITH_PUBLISHED_OPTIMUM)
def test_hock_schittkowski_published_optimum(name, inner):
    assert_published_optimum(_ref(name), _run(name, inner), x_atol=1e-6)


def test_fused_loop_evaluates_the_problem_at_one_site():
    # the fused loop traces the objective once (its one linearisation per trip); the nested
    # inner solver adds its own evaluation of the augmented Lagrangian
    traced = []

    def f(x, _):
        traced.append(1)
        return (x[0] - 1.0) ** 2 + x[1] ** 2

    prob = Problem(f, -5.0 * np.ones(2), 5.0 * np.ones(2), inequality=lambda x, _: jnp.array([1.0 - x[0] - x[1]]))
    counts = {}
    for inner in ("fused", "bfgs"):
        traced.clear()
        jax.jit(lambda x0: solve(prob, x0, None, SolverOptions(inner=inner, polish=False))).lower(jnp.zeros(2))
        counts[inner] = len(traced)
    assert counts == {"fused": 1, "bfgs": 2}
    # and it solves the problem: min (x1-1)^2 + x2^2 s.t. x1 + x2 >= 1 is at (1, 0), unconstrained
    r = make_solver(prob, SolverOptions(polish=False), compile="fast")(jnp.zeros(2))
    assert bool(r.converged)
    np.testing.assert_allclose(np.asarray(r.x), [1.0, 0.0], atol=1e-7)


def test_start_at_the_objectives_stationary_point_converges():
    # min x^2 + 1 s.t. x >= 1 from x0 = 0, where grad f = 0: the objective's scale comes from
    # |f(x0)| (a gradient-only rule scaled f by 1e8 and the solve stalled). Closed form: x* = 1,
    # f* = 2, lambda = f'(1) = 2.
    prob = Problem(lambda x, _: x[0] ** 2 + 1.0, -10.0, 10.0, inequality=lambda x, _: jnp.array([1.0 - x[0]]))
    r = make_solver(prob, OPTS, compile="fast")(jnp.zeros(1))
    assert bool(r.converged) and bool(r.feasible)
    np.testing.assert_allclose(float(r.x[0]), 1.0, rtol=1e-12)
    np.testing.assert_allclose(float(r.f), 2.0, rtol=1e-12)
    np.testing.assert_allclose(float(r.lam[0]), 2.0, rtol=1e-8)


def test_hs071_multipliers_match_ipopt_example():
    r = _run("hs071")
    assert_hs071_ipopt_multipliers(r, mu_atol=1e-6)
    np.testing.assert_allclose(np.asarray(r.mu_upper), 0.0, atol=1e-12)
    assert float(r.kkt.stationarity) <= 1e-10 and float(r.kkt.complementarity) <= 1e-10


def test_hs035_qp_multiplier_closed_form():
    # at x* = (4/3, 7/9, 4/9): grad f = -(2/9)(1, 1, 2) = -lambda * grad g  ->  lambda = 2/9
    r = _run("hs035")
    np.testing.assert_allclose(np.asarray(r.x), [4 / 3, 7 / 9, 4 / 9], atol=1e-12)
    np.testing.assert_allclose(float(r.lam[0]), 2.0 / 9.0, rtol=1e-10)
    np.testing.assert_allclose(float(r.f), 1.0 / 9.0, rtol=1e-12)


def test_hs076_multipliers_and_active_bound_closed_form():
    # KKT at the published x* = (3/11, 23/11, 0, 6/11): lambda_1 = 5/11, mu_lower_3 = 19/11
    r = _run("hs076")
    np.testing.assert_allclose(np.asarray(r.x), [3 / 11, 23 / 11, 0, 6 / 11], atol=1e-12)
    np.testing.assert_allclose(np.asarray(r.lam), [5 / 11, 0, 0], atol=1e-10)
    np.testing.assert_allclose(np.asarray(r.mu_lower), [0, 0, 19 / 11, 0], atol=1e-10)
    np.testing.assert_allclose(float(r.f), -103.0 / 22.0, rtol=1e-12)


def test_hs021_active_bound_multiplier():
    # x* = (2, 0): lower bound of x1 active with mu = d f/d x1 = 0.02 * 2; constraint inactive
    r = _run("hs021")
    assert float(r.x[0]) == 2.0
    np.testing.assert_allclose(np.asarray(r.mu_lower), [0.04, 0.0], atol=1e-12)
    assert float(r.lam[0]) == 0.0 and float(r.g[0]) < -1.0
    np.testing.assert_allclose(float(r.f), -99.96, rtol=1e-12)


@pytest.mark.parametrize("name,nu", [("hs007", [1 / (2 * math.sqrt(3))]), ("hs039", [-1.0, -1.0])])
def test_equality_multipliers_closed_form(name, nu):
    r = _run(name)
    np.testing.assert_allclose(np.asarray(r.nu), nu, rtol=1e-9)
    assert float(jnp.max(jnp.abs(r.h))) <= 1e-10


def test_hs002_bounded_rosenbrock_reaches_kkt_point_of_the_cubic():
    # HS002 (x2 >= 1.5) has two local minima on the bound: 400 x1^3 - 598 x1 - 2 = 0.
    # From the published start (-2, 1) a descent method reaches the negative root (as scipy's
    # SLSQP and L-BFGS-B do); the published optimum 0.0504261879 is the positive root
    # (found by multistart in test_optimize_multistart.py).
    roots = np.roots([400.0, 0.0, -598.0, -2.0]).real
    x1 = roots.min()
    f_local = 100 * (1.5 - x1**2) ** 2 + (1 - x1) ** 2
    r = _run("hs002")
    assert bool(r.converged)
    assert float(r.x[1]) == 1.5
    np.testing.assert_allclose(float(r.x[0]), x1, rtol=1e-10)
    np.testing.assert_allclose(float(r.f), f_local, rtol=1e-12)
    np.testing.assert_allclose(float(r.mu_lower[1]), 200 * (1.5 - x1**2), rtol=1e-8)
    # and the positive root is the published optimum
    x1p = roots.max()
    np.testing.assert_allclose(100 * (1.5 - x1p**2) ** 2 + (1 - x1p) ** 2, _ref("hs002").f_star, rtol=1e-9)


@pytest.mark.parametrize("name", ["hs071"])
def test_lbfgsb_inner_solver_reaches_published_optimum(name):
    P = _ref(name)
    r = _run(name, inner="lbfgsb")
    assert bool(r.converged)
    assert abs(float(r.f) - P.f_star) <= 1e-7 * max(1.0, abs(P.f_star))
    np.testing.assert_allclose(np.asarray(r.mu_lower), P.mu_lower_star, atol=1e-6)


def test_servo_bandwidth_book_14_12_vmapped_sweep():
    # Brooker eq. 14.12 closed form, to 1e-6 relative as the book's formula is exact for eq. 14.11;
    # a vmapped sweep over SNR, crossing range and target acceleration.
    P = _ref("servo_bandwidth")
    snr = jnp.array([2.0, 20.0, 200.0, 2000.0])
    rng = jnp.array([200.0, 1000.0, 5000.0, 20000.0])
    acc = jnp.array([5.0, 50.0, 100.0, 300.0])
    th = {k: jnp.broadcast_to(v, (4,)) for k, v in P.theta.items()}
    th.update(snr=snr, range_m=rng, accel_m_s2=acc)
    solver = make_solver(P.problem, OPTS, batched=True, compile="fast")
    r = solver(jnp.ones((4, 1)), th)
    bo = rp.servo_optimum_hz(th)
    assert np.all(np.asarray(r.converged))
    np.testing.assert_allclose(np.asarray(r.x[:, 0]), np.asarray(bo), rtol=1e-6)
    np.testing.assert_allclose(np.asarray(r.f), np.asarray(rp.servo_error_variance(bo, th)), rtol=1e-12)


def test_simplex_projection_qp_closed_form():
    # minimise 0.5|x - a|^2 on the simplex: x = max(a - tau, 0); nu = tau; mu_i = tau - a_i off support
    P = _ref("simplex_projection")
    solver = make_solver(P.problem, OPTS, batched=True, compile="fast")
    a = np.array([[0.9, 0.6, -0.2, 0.1], [0.3, 0.2, 0.25, 0.1], [2.0, -1.0, 0.5, 0.4], [0.0, 0.0, 0.0, 0.0]])
    r = solver(jnp.full((4, 4), 0.25), jnp.asarray(a))
    for i in range(4):
        xs = rp.simplex_projection_solution(a[i])
        free = xs > 0
        tau = np.mean((a[i] - xs)[free])
        np.testing.assert_allclose(np.asarray(r.x[i]), xs, atol=1e-10)
        np.testing.assert_allclose(float(r.nu[i, 0]), tau, atol=1e-9)
        np.testing.assert_allclose(np.asarray(r.mu_lower[i]), np.where(free, 0.0, tau - a[i]), atol=1e-9)


# ----------------------------------------------------------------- scaling: 1e-9 s next to 1e6 W
def _energy_problem(log_scale, p_max=1e6):
    # minimise a P + b tau  s.t.  P tau >= E.  Closed form on the constraint: P* = sqrt(bE/a),
    # tau* = sqrt(aE/b), f* = 2 sqrt(abE), lambda = a / tau* = sqrt(ab/E) (= d f*/dE).
    a, b = 1e-3, 1e6  # cost per watt, cost per second
    theta = jnp.asarray(1e-3)  # required pulse energy, J

    def f(x, E):
        return a * x[0] + b * x[1]

    def g(x, E):
        return jnp.array([E - x[0] * x[1]])
    kw = dict(log_scale=True) if log_scale else dict(scale=[1e3, 1e-6])
    prob = Problem(f, [1.0, 1e-9], [p_max, 1e-3], inequality=g, **kw)
    return prob, theta, a, b


@pytest.mark.parametrize("log_scale", [True, False])
def test_variables_spanning_nanoseconds_and_megawatts(log_scale):
    prob, E, a, b = _energy_problem(log_scale)
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([1e5, 1e-8]), E)
    E = float(E)
    assert bool(r.converged)
    np.testing.assert_allclose(np.asarray(r.x), [math.sqrt(b * E / a), math.sqrt(a * E / b)], rtol=1e-9)
    np.testing.assert_allclose(float(r.f), 2 * math.sqrt(a * b * E), rtol=1e-12)
    np.testing.assert_allclose(float(r.lam[0]), math.sqrt(a * b / E), rtol=1e-8)


def test_active_upper_bound_multiplier_closed_form():
    # P <= 500 W binds: tau = E/500, lambda = b/P, mu_upper(P) = lambda tau - a = 3e-3
    prob, E, a, b = _energy_problem(True, p_max=500.0)
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([10.0, 1e-4]), E)
    assert bool(r.converged)
    assert float(r.x[0]) == 500.0
    np.testing.assert_allclose(float(r.x[1]), 1e-3 / 500.0, rtol=1e-10)
    np.testing.assert_allclose(float(r.lam[0]), b / 500.0, rtol=1e-8)
    np.testing.assert_allclose(np.asarray(r.mu_upper), [b / 500.0 * 2e-6 - a, 0.0], rtol=1e-7, atol=1e-15)


def test_bounds_never_violated_from_outside_start():
    # unconstrained minimum (3, -2) lies outside the box [0, 1] x [0, 1]: answer is the corner (1, 0)
    prob = Problem(lambda x, _: (x[0] - 3.0) ** 2 + (x[1] + 2.0) ** 2, 0.0, np.ones(2))
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([7.0, -9.0]))
    np.testing.assert_array_equal(np.asarray(r.x), [1.0, 0.0])
    np.testing.assert_allclose(np.asarray(r.mu_upper), [4.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(np.asarray(r.mu_lower), [0.0, 4.0], atol=1e-12)


def test_twenty_log_scaled_variables_match_slsqp_reference():
    # minimise sum c_i x_i with c spanning 1e-3..1e3, x_i in [1e-3, 1e3] (log-scaled), subject to
    # ten dB-like requirements A log10(x) >= b. Convex in u = log10 x, so the optimum is unique;
    # reference: scipy SLSQP in u with analytic gradients and ftol 1e-15 (independent solver).
    from scipy.optimize import minimize

    rng = np.random.default_rng(1)
    n, m = 20, 10
    c = rng.uniform(0.5, 2, n) * 10.0 ** rng.uniform(-3, 3, n)
    A = rng.uniform(0, 10, (m, n))
    b = rng.uniform(5, 30, m)
    prob = Problem(lambda x, _: jnp.sum(jnp.asarray(c) * x), 1e-3 * np.ones(n), 1e3 * np.ones(n),
                   inequality=lambda x, _: jnp.asarray(b) - jnp.asarray(A) @ jnp.log10(x), log_scale=True)
    r = make_solver(prob, OPTS, compile="fast")(jnp.ones(n))
    ref = minimize(lambda u: float(np.sum(c * 10**u)), np.zeros(n), jac=lambda u: c * 10**u * np.log(10),
                   method="SLSQP", bounds=[(-3, 3)] * n,
                   constraints=[{"type": "ineq", "fun": lambda u: A @ u - b, "jac": lambda u: A}],
                   options={"ftol": 1e-15, "maxiter": 2000})
    assert np.all(A @ ref.x - b >= -1e-9)
    assert bool(r.converged) and bool(r.feasible)
    np.testing.assert_allclose(float(r.f), ref.fun, rtol=1e-9)
    np.testing.assert_allclose(np.log10(np.asarray(r.x)), ref.x, atol=1e-6)


# ----------------------------------------------------------------- infeasibility
def test_infeasible_conflicting_constraints_least_squares_compromise():
    # x1 + x2 >= 3 and x1 + x2 <= 1 cannot both hold; the least-infeasible point (min of the
    # summed squared violations) has x1 + x2 = 2, both violated by 1; the third constraint is slack.
    prob = Problem(lambda x, _: (x[0] - 1) ** 2 + (x[1] - 2) ** 2, 0.0, 5.0 * np.ones(2),
                   inequality=lambda x, _: jnp.array([3.0 - x[0] - x[1], x[0] + x[1] - 1.0, x[0] - x[1] - 10.0]))
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([0.5, 0.5]))
    assert not bool(r.feasible) and not bool(r.converged)
    np.testing.assert_allclose(float(r.x[0] + r.x[1]), 2.0, atol=1e-6)
    np.testing.assert_allclose(np.asarray(r.g[:2]), [1.0, 1.0], atol=1e-6)
    np.testing.assert_array_equal(np.asarray(r.conflict.inequality), [True, True, False])
    assert not np.any(np.asarray(r.conflict.lower)) and not np.any(np.asarray(r.conflict.upper))
    for leaf in jax.tree_util.tree_leaves(r):
        assert np.all(np.isfinite(np.asarray(leaf, dtype=float)))


def test_infeasible_against_bounds_names_blocking_bounds():
    # x in [0, 1]^2 with x1 + x2 >= 3 and x1 <= 0.9: the violation 0.5(3-x1-x2)^2 + 0.5(x1-0.9)^2
    # has d/dx1 = -(3 - x1 - x2) + (x1 - 0.9) = -0.9 < 0 at (1, 1): both upper bounds block.
    prob = Problem(lambda x, _: x[0] ** 2 + x[1] ** 2, 0.0, np.ones(2),
                   inequality=lambda x, _: jnp.array([3.0 - x[0] - x[1], x[0] - 0.9]))
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([0.5, 0.5]))
    assert not bool(r.feasible)
    np.testing.assert_array_equal(np.asarray(r.x), [1.0, 1.0])
    np.testing.assert_array_equal(np.asarray(r.conflict.inequality), [True, True])
    np.testing.assert_array_equal(np.asarray(r.conflict.upper), [True, True])


# ----------------------------------------------------------------- API edge
def test_domain_errors_at_the_api_edge():
    f = lambda x, _: jnp.sum(x**2)  # noqa: E731
    with pytest.raises(DomainError):
        Problem(f, [0.0, 2.0], [1.0, 1.0])
    with pytest.raises(DomainError):
        Problem(f, [0.0, 1.0], [1.0, 2.0], log_scale=True)
    with pytest.raises(DomainError):
        Problem(f, 0.0, 1.0, scale=-1.0)
    with pytest.raises(DomainError):
        SolverOptions(inner="newton")
    with pytest.raises(DomainError):
        SolverOptions(tol=0.0)
    prob = Problem(f, -np.ones(2), np.ones(2))
    from diffsense.optimize import solve
    with pytest.raises(DomainError):
        solve(prob, np.zeros(3))
    with pytest.raises(DomainError):
        solve(prob, np.array([np.nan, 0.0]))


def test_start_where_the_objective_is_not_finite_is_not_converged():
    # f = sqrt(x - 1) is NaN for x < 1: from x0 = 0.5 the solve ends at the start with the
    # values it found there (f NaN; g = x - 3 = -2.5, met), and never reports convergence
    prob = Problem(lambda x, _: jnp.sqrt(x[0] - 1.0), 0.0, 4.0 * np.ones(1),
                   inequality=lambda x, _: jnp.array([x[0] - 3.0]))
    r = make_solver(prob, OPTS, compile="fast")(jnp.array([0.5]))
    assert not bool(r.converged)
    assert float(r.x[0]) == 0.5 and np.isnan(float(r.f))
    assert float(r.g[0]) == -2.5 and bool(r.feasible)
