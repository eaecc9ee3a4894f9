"""Lanes: many solves of one problem through one compiled program, against closed forms.

Each expected value below is solved by hand: a separable quadratic's minimiser clipped to its
box, and the stationarity condition of a two-variable quadratic with one variable pinned."""

import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.optimize import Problem, SolverOptions
from diffsense.optimize.integer import integer_neighbours
from diffsense.optimize.lanes import (
    Lanes,
    best_per_group,
    lane_grid,
    make_lane_solver,
    pin_variables,
    solve_in_batches,
    solve_lanes,
)

OPTS = SolverOptions()


def _shifted_quadratic():
    # minimise (x - θ₀)² subject to x ≥ θ₁ on [-10, 10]: x* = max(θ₀, θ₁) while θ₁ ≤ 10
    return Problem(lambda x, th: (x[0] - th[0]) ** 2, -10.0, 10.0, inequality=lambda x, th: jnp.array([th[1] - x[0]]))


def test_batches_of_fixed_size_reuse_one_compiled_program():
    prob = _shifted_quadratic()
    thetas = np.stack([np.linspace(-3.0, 3.0, 7), np.zeros(7)], axis=1)
    lanes = lane_grid(np.zeros((1, 1)), thetas, lower=prob.lower, upper=prob.upper)
    solver = make_lane_solver(prob, OPTS, lockstep=1, compile="fast")
    res = solve_lanes(solver, lanes, batch=3)  # 3 + 3 + 1 lanes (the last call padded)
    assert res.x.shape == (7, 1)
    np.testing.assert_allclose(res.x[:, 0], np.maximum(thetas[:, 0], 0.0), atol=1e-9)
    assert solver._cache_size() == 1


def test_best_per_group_takes_the_lowest_feasible_then_the_least_infeasible():
    # groups: requirement x ≥ r with r = 0.5, 2 and 20 (beyond the box: infeasible); two starts each
    prob = _shifted_quadratic()
    req = np.array([0.5, 2.0, 20.0])
    lanes = lane_grid([[-5.0], [5.0]], np.stack([np.ones(3), req], axis=1), lower=prob.lower, upper=prob.upper)
    np.testing.assert_array_equal(lanes.group, [0, 1, 2, 0, 1, 2])
    res = solve_lanes(make_lane_solver(prob, OPTS, compile="fast"), lanes)
    rows, found = best_per_group(res, lanes.group, 3)
    np.testing.assert_array_equal(found, [True, True, False])
    np.testing.assert_allclose(res.f[rows[:2]], [0.0, 1.0], atol=1e-12)  # (max(1, r) − 1)²
    # the infeasible group answers its least-infeasible lane: x on its upper bound 10
    np.testing.assert_allclose(res.x[rows[2]], [10.0], rtol=0)
    with pytest.raises(DomainError):
        best_per_group(res, lanes.group, 4)


def test_pinned_variable_is_held_exactly_and_gets_its_bound_multiplier():
    # f = (x₀ − 1)² + (x₁ − 2)² + x₀x₁ with x₀ pinned at 3: ∂f/∂x₁ = 2(x₁ − 2) + 3 = 0 gives
    # x₁ = 0.5, f = 4 + 2.25 + 1.5 = 7.75, and the pin holds against ∂f/∂x₀ = 2(3 − 1) + 0.5 = 4.5
    prob = Problem(lambda x, _: (x[0] - 1.0) ** 2 + (x[1] - 2.0) ** 2 + x[0] * x[1], [-5.0, -5.0], [5.0, 5.0])
    x = np.array([[3.0, 0.0]])
    lower, upper = pin_variables(prob.lower, prob.upper, x, np.array([True, False]))
    np.testing.assert_array_equal(lower, [[3.0, -5.0]])
    np.testing.assert_array_equal(upper, [[3.0, 5.0]])
    lanes = Lanes(x, None, lower, upper, np.zeros(1, dtype=int))
    res = solve_lanes(make_lane_solver(prob, OPTS, compile="fast"), lanes)
    assert res.x[0, 0] == 3.0
    np.testing.assert_allclose(res.x[0, 1], 0.5, rtol=1e-12)
    np.testing.assert_allclose(res.f[0], 7.75, rtol=1e-12)
    np.testing.assert_allclose(res.mu_lower[0, 0] - res.mu_upper[0, 0], 4.5, rtol=1e-10)


def test_integer_neighbours_pin_each_candidate_in_the_box():
    prob = Problem(lambda x, _: jnp.sum(x**2), [0.0, -1.0, 0.0], [4.0, 1.0, 2.5], integer=[True, False, True])
    lanes = integer_neighbours(prob, [[1.4, 0.3, 2.2], [3.0, -0.5, 0.0]])
    assert lanes.x0.shape == (8, 3) and lanes.theta is None
    np.testing.assert_array_equal(lanes.group, [0, 0, 0, 0, 1, 1, 1, 1])
    # floor/ceil of (1.4, 2.2) inside the integers of the bounds (the second one's ceiling 3 > 2.5: clipped to 2)
    np.testing.assert_array_equal(lanes.x0[:4][:, [0, 2]], [[1, 2], [1, 2], [2, 2], [2, 2]])
    np.testing.assert_array_equal(lanes.x0[:, 1], [0.3] * 4 + [-0.5] * 4)  # continuous part kept
    np.testing.assert_array_equal(lanes.lower[:, [0, 2]], lanes.x0[:, [0, 2]])
    np.testing.assert_array_equal(lanes.upper[:, [0, 2]], lanes.x0[:, [0, 2]])
    np.testing.assert_array_equal(lanes.lower[:, 1], -1.0)
    np.testing.assert_array_equal(lanes.upper[:, 1], 1.0)


def test_solve_in_batches_needs_rows():
    with pytest.raises(DomainError):
        solve_in_batches(lambda x: x, 2, np.zeros((0, 1)))


def test_batches_run_on_threads_give_each_row_its_own_answer_in_order():
    # the closed form x* = max(θ₀, θ₁) per row: the batches after the first run on two threads,
    # and every row must come back at its own place, equal to the one-thread result
    prob = _shifted_quadratic()
    thetas = np.stack([np.linspace(-5.0, 5.0, 11), np.linspace(1.0, -1.0, 11)], axis=1)
    lanes = lane_grid(np.zeros((1, 1)), thetas, lower=prob.lower, upper=prob.upper)
    solver = make_lane_solver(prob, OPTS, lockstep=1, compile="fast")
    cols = (lanes.x0, lanes.theta, lanes.lower, lanes.upper)
    one = solve_in_batches(solver, 2, *cols, threads=1)
    two = solve_in_batches(solver, 2, *cols, threads=2)
    np.testing.assert_allclose(two.x[:, 0], np.maximum(thetas[:, 0], thetas[:, 1]), atol=1e-9)
    np.testing.assert_array_equal(two.x, one.x)
    np.testing.assert_array_equal(two.f, one.f)


def test_pinned_padding_pins_only_the_padding_rows_and_keeps_every_answer():
    # 11 lanes in calls of 4: the last call has one padding row; pinned, its box is its start,
    # and the real rows' answers equal those of the plain (repeated-row) padding
    prob = _shifted_quadratic()
    thetas = np.stack([np.linspace(-5.0, 5.0, 11), np.linspace(1.0, -1.0, 11)], axis=1)
    lanes = lane_grid(np.full((1, 1), 0.5), thetas, lower=prob.lower, upper=prob.upper)
    solver = make_lane_solver(prob, OPTS, lockstep=1, compile="fast")
    seen = []

    def spy(x0, theta, lower, upper):
        seen.append((np.array(x0), np.array(lower), np.array(upper)))
        return solver(x0, theta, lower, upper)

    cols = (lanes.x0, lanes.theta, lanes.lower, lanes.upper)
    pinned = solve_in_batches(spy, 4, *cols, threads=1, pin_padding=True)
    plain = solve_in_batches(solver, 4, *cols, threads=1)
    x0, lower, upper = seen[-1]
    np.testing.assert_array_equal(lower[3:], x0[3:])
    np.testing.assert_array_equal(upper[3:], x0[3:])
    np.testing.assert_array_equal(lower[:3], lanes.lower[8:])
    np.testing.assert_array_equal(upper[:3], lanes.upper[8:])
    np.testing.assert_array_equal(seen[0][1], lanes.lower[:4])  # full calls are not touched
    np.testing.assert_array_equal(pinned.x, plain.x)
    np.testing.assert_allclose(pinned.x[:, 0], np.maximum(thetas[:, 0], thetas[:, 1]), atol=1e-9)


def test_problem_is_an_immutable_pytree_of_its_bounds():
    import jax

    prob = Problem(lambda x, th: jnp.sum(x ** 2), [0.1, -1.0], [10.0, 1.0], log_scale=[True, False],
                   names=["a", "b"])
    leaves, tree = jax.tree_util.tree_flatten(prob)
    # the arrays are the leaves (lower, upper, scale, log flags); the functions are structure
    assert len(leaves) == 4
    np.testing.assert_array_equal(leaves[2], [1.0, 1.0])  # √(0.1·10) and max(|−1|, |1|)
    back = jax.tree_util.tree_unflatten(tree, leaves)
    assert back.names == ("a", "b") and back.objective is prob.objective
    moved = prob.with_bounds([1.0, -0.5], [2.0, 0.5])
    np.testing.assert_array_equal(moved.lower, [1.0, -0.5])
    np.testing.assert_array_equal(prob.lower, [0.1, -1.0])  # the original is unchanged
    with pytest.raises(AttributeError, match="immutable"):
        prob.lower = np.zeros(2)
    with pytest.raises(TypeError, match="no field"):
        prob.replace(bounds=None)
    # traced bounds: a jitted function of the bounds
    f = jax.jit(lambda lo: prob.with_bounds(lo, prob.upper).scaled_bounds()[0])
    np.testing.assert_allclose(f(np.array([1.0, 0.0])), [0.0, 0.0], atol=1e-15)
