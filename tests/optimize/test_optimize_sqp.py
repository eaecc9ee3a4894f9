"""SQP solver and its interior-point QP (elastic subproblems) against published and closed-form optima.

Sources as in test_optimize_constrained.py: Hock & Schittkowski (LNEMS 187, 1981) optima; the
Ipopt documentation's HS071 multipliers; Brooker eqs. 14.11–14.12; closed forms per test.
"""

import functools
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.optimize import Problem, SolverOptions, make_solver
from diffsense.optimize import reference_problems as rp

from helpers.reference_checks import (
    HS_WITH_PUBLISHED_OPTIMUM,
    assert_hs071_ipopt_multipliers,
    assert_published_optimum,
)
from diffsense.optimize.qp import solve_qp
from diffsense.optimize import solve
from helpers.paths import DESIGNS


SQP = SolverOptions(method="sqp")


@functools.lru_cache(maxsize=None)
def _ref(name):
    return getattr(rp, name)()


@functools.lru_cache(maxsize=None)
def _solver(name):
    return make_solver(_ref(name).problem, SQP, compile="fast")


def _run(name):
    P = _ref(name)
    return _solver(name)(jnp.asarray(P.x0), P.theta)


# ----------------------------------------------------------------- QP subproblem solver
def test_qp_random_problems_satisfy_kkt_conditions():
    rng = np.random.default_rng(0)
    fn = jax.jit(solve_qp)
    for _ in range(40):  # one shape: one compilation
        n, r = 6, 8
        M = rng.normal(size=(n, n))
        Q = M @ M.T + 0.01 * np.eye(n)
        c = rng.normal(size=n)
        A = np.vstack([rng.normal(size=(r, n)), np.eye(n), -np.eye(n)])
        b = np.concatenate([np.abs(rng.normal(size=r)), 3.0 * np.ones(2 * n)])  # y = 0 is feasible
        s = fn(jnp.asarray(Q), jnp.asarray(c), jnp.asarray(A), jnp.asarray(b))
        y, u = np.asarray(s.y), np.asarray(s.u)
        assert np.max(A @ y - b) <= 1e-12
        assert np.min(u) >= 0.0
        assert np.max(np.abs(Q @ y + c + A.T @ u)) <= 1e-9 * (1 + np.max(np.abs(c)))
        assert np.max(np.abs(u * (b - A @ y))) <= 1e-10


# ----------------------------------------------------------------- SQP on reference problems
@pytest.mark.parametrize("name", HS_WITH_PUBLISHED_OPTIMUM)
def test_hock_schittkowski_published_optimum(name):
    assert_published_optimum(_ref(name), _run(name), x_atol=1e-5)


def test_hs071_multipliers_match_ipopt_example():
    assert_hs071_ipopt_multipliers(_run("hs071"), mu_atol=1e-5)


def test_hs035_qp_multiplier_closed_form():
    r = _run("hs035")
    np.testing.assert_allclose(np.asarray(r.x), [4 / 3, 7 / 9, 4 / 9], atol=1e-8)
    np.testing.assert_allclose(float(r.lam[0]), 2.0 / 9.0, rtol=1e-7)


def test_servo_bandwidth_book_14_12_vmapped_sweep():
    P = rp.servo_bandwidth()
    solver = make_solver(P.problem, SQP, batched=True, compile="fast")
    snr = jnp.asarray([5.0, 20.0, 100.0, 1000.0])
    theta = jax.vmap(lambda s: rp.servo_theta(snr=s))(snr)
    r = solver(jnp.ones((4, 1)), theta)
    expected = np.asarray(jax.vmap(rp.servo_optimum_hz)(theta))
    assert np.all(np.asarray(r.converged))
    # f is scaled by its gradient at the start (1 Hz), ~1e5 times its curvature at βo: the scaled
    # stationarity tolerance 1e-8 then holds within ~1e-5 of βo (the AL solver's tighter inner
    # solves land within 1e-6; see test_optimize_constrained.py)
    np.testing.assert_allclose(np.asarray(r.x[:, 0]), expected, rtol=1e-5)


def test_simplex_projection_closed_form_with_equality_multiplier():
    P = _ref("simplex_projection")
    r = _run("simplex_projection")
    assert bool(r.converged)
    np.testing.assert_allclose(np.asarray(r.x), P.x_star, atol=1e-8)
    np.testing.assert_allclose(np.asarray(r.nu), P.nu_star, atol=1e-7)


def test_infeasible_problem_is_reported_with_its_conflicting_constraints():
    # x1 + x2 >= 3 and x1 + x2 <= 1 cannot both hold; x1 - x2 <= 10 is slack throughout
    prob = Problem(lambda x, _: (x[0] - 1) ** 2 + (x[1] - 2) ** 2, 0.0, 5.0 * np.ones(2),
                   inequality=lambda x, _: jnp.array([3.0 - x[0] - x[1], x[0] + x[1] - 1.0, x[0] - x[1] - 10.0]))
    r = make_solver(prob, SolverOptions(method="sqp", max_sqp=30), compile="fast")(jnp.array([0.5, 0.5]))
    assert not bool(r.feasible) and not bool(r.converged)
    np.testing.assert_array_equal(np.asarray(r.conflict.inequality)[2], False)
    assert np.any(np.asarray(r.conflict.inequality)[:2])
    x = np.asarray(r.x)
    assert np.all(x >= 0.0) and np.all(x <= 5.0)
    for leaf in jax.tree_util.tree_leaves(r):
        assert np.all(np.isfinite(np.asarray(leaf, dtype=float)))


@functools.lru_cache(maxsize=None)
def _ore_pass_94ghz_gunn():
    """The shipped ore-pass model at 94 GHz with the Gunn transmitter: (model, index of that
    catalog combination, problem, jitted SQP solve of (x0, θ)), built once per test process."""
    from diffsense.design.model import DesignModel
    from diffsense.design.problem import requirement_problem
    from diffsense.design.spec import load_spec

    model = DesignModel(load_spec(DESIGNS / "ore_pass.toml"))
    combo = [c.index for c in model.combinations
             if c.values.get("freq_hz") == 94e9 and "Gunn" in " ".join(c.options.values())][0]
    problem = requirement_problem(model)
    solver = jax.jit(lambda x0, th: solve(problem, x0, th, SQP))
    return model, combo, problem, solver


def _ore_pass_solve(x0):
    # θ of the design problem; the interval requirements' slots at the far end of the shaft,
    # their worst point (the margins fall monotonically down a vertical shaft)
    model, combo, _, solver = _ore_pass_94ghz_gunn()
    # the optimiser's normalisation: the objective at the initial design, first catalog option
    # (this objective reads no chain output, so it is evaluated without one)
    first = model.inputs(0)
    scale = abs(float(jax.jit(model.objective_value)(model.design_values(model.initial, 0), first)))
    theta = model.solve_inputs(model.inputs(combo), combo, model.limits, scale)
    return solver(jnp.asarray(x0), jax.tree_util.tree_map(jnp.asarray, theta))


def _assert_book_beam_limited_optimum(r):
    # Brooker 8.16 at 94 GHz with the Gunn transmitter: of the requirements only the beam (≤ 1.1°)
    # binds at the optimum, so the antenna is the book's rule d = 70 λ/θ (8.16.7); the objective is
    # 10 per metre of antenna + 0.6 (94 GHz band) + 1 (Gunn)
    model, combo, _, _ = _ore_pass_94ghz_gunn()
    assert bool(r.converged) and bool(r.feasible)
    d_star = 70.0 * (299_792_458.0 / 94e9) / 1.1
    np.testing.assert_allclose(float(r.x[0]), d_star, rtol=1e-8)
    objective = float(model.evaluate_all(np.asarray(r.x), model.combo_table[combo])[2])
    np.testing.assert_allclose(objective, 10.0 * d_star + 1.6, rtol=1e-9)


def test_ore_pass_flat_optimum_lands_on_the_book_beamwidth_rule_in_few_iterations():
    # every pulse width, bandwidth, pulse count and PRF that meets the other requirements is optimal
    # too: a 4-dimensional set of optima. With an interior-point QP the SQP wandered along it for
    # 33 iterations.
    model = _ore_pass_94ghz_gunn()[0]
    r = _ore_pass_solve(model.initial)
    _assert_book_beam_limited_optimum(r)
    # 7 iterations since the range resolution follows the filtered echo (it couples bandwidth and
    # pulse width) and the requirements hold over the 10-300 m interval
    assert int(r.iterations) <= 8


def test_ore_pass_from_a_far_start_whose_first_step_is_elastic():
    # a Latin-hypercube start of the design optimiser (seed 0, 4th point) from which the first
    # linearisation is inconsistent: the elastic step's multipliers (~1e3) set a merit penalty of
    # 1500; held there, every later full step failed the merit test and the solve crept along at
    # step lengths of 2⁻⁹ to the iteration cap. With Powell's penalty rule it converges.
    from diffsense.optimize.multistart import start_points

    problem = _ore_pass_94ghz_gunn()[2]
    x0 = start_points(problem, 7, seed=0, method="lhs")[3]
    _assert_book_beam_limited_optimum(_ore_pass_solve(x0))
