"""Pareto fronts by epsilon-constraint continuation on problems whose fronts are known in
closed form: points lie on the front to solver tolerance, anchors are each objective's own
optimum, the grid covers the front, integers come out integer, and the front helpers
(non-domination, knee, hypervolume) agree with hand-worked cases."""

import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.optimize import Problem
from diffsense.optimize.continuation import (hypervolume_2d, knee_index, pareto_mask, scalarized_problem,
                                             trace_front, Scalarization)

K_PD4 = 2.0e4  # P d^4 = K: the power-aperture product of a search radar (arbitrary units)


def power_aperture_problem():
    # minimise (P, d) s.t. P d^4 >= K, 1e3 <= P <= 1e7, 1 <= d <= 10: the front is P d^4 = K
    # from d = (K/1e3)^(1/4) (P at its lower bound) to d = 1 (P = K)
    return Problem(lambda x, th: 0.0 * x[0], [1e3, 1.0], [1e7, 10.0],
                   inequality=lambda x, th: jnp.array([1.0 - x[0] * x[1] ** 4 / th]), log_scale=True)


@pytest.fixture(scope="module")
def power_aperture():
    return trace_front(power_aperture_problem(), lambda x, th: x, np.array([K_PD4]), np.array([[1e5, 3.0]]),
                       points=25)


def test_every_point_lies_on_the_exact_front(power_aperture):
    f = power_aperture
    assert f.converged.all() and f.feasible.all()
    assert np.max(np.abs(f.x[:, 0] * f.x[:, 1] ** 4 / K_PD4 - 1.0)) <= 1e-6
    assert np.max(f.kkt_residual) <= 1e-8


def test_anchors_are_each_objectives_own_optimum(power_aperture):
    f = power_aperture
    a0 = f.x[f.anchor == 0][0]
    a1 = f.x[f.anchor == 1][0]
    assert a0[0] == pytest.approx(1e3, rel=1e-9) and a0[1] == pytest.approx((K_PD4 / 1e3) ** 0.25, rel=1e-7)
    assert a1[1] == pytest.approx(1.0, rel=1e-8) and a1[0] == pytest.approx(K_PD4, rel=1e-7)


def test_points_are_evenly_spread_and_non_dominated(power_aperture):
    f = power_aperture
    assert f.x.shape[0] == 25
    d = np.sort(f.x[:, 1])
    assert np.allclose(np.diff(d), (d[-1] - d[0]) / 24, rtol=1e-6)
    assert pareto_mask(f.objectives).all()


def test_convex_front_of_two_distances():
    # F1 = |x|^2, F2 = |x - (2, 0)|^2 over a box: the Pareto set is the segment between the two
    # centres, where F2 = (2 - sqrt(F1))^2
    prob = Problem(lambda x, th: 0.0 * x[0], [-3.0, -3.0], [3.0, 3.0])
    front = trace_front(prob, lambda x, th: jnp.array([x @ x, (x - jnp.array([2.0, 0.0])) @ (x - jnp.array([2.0, 0.0]))]),
                        np.zeros((1, 1)), np.array([[0.5, 1.0]]), points=15)
    assert front.converged.all()
    F = front.objectives
    np.testing.assert_allclose(F[:, 1], (2.0 - np.sqrt(F[:, 0])) ** 2, atol=1e-7)
    np.testing.assert_allclose(front.x[:, 1], 0.0, atol=1e-6)


def test_three_objectives_stay_in_the_triangle_of_the_centres():
    # F_k = |x - a_k|^2: the Pareto set is the triangle spanned by the a_k
    a = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    prob = Problem(lambda x, th: 0.0 * x[0], [-3.0, -3.0], [3.0, 3.0])
    front = trace_front(prob, lambda x, th: jnp.sum((x[None, :] - jnp.asarray(a)) ** 2, axis=1), np.zeros((1, 1)),
                        np.array([[0.5, 0.5]]), points=16)
    ok = front.converged & front.feasible
    assert ok.sum() >= 8
    x = front.x[ok]
    assert np.all(x >= -1e-6) and np.all(x.sum(axis=1) <= 2.0 + 1e-6)
    distinct = np.unique(np.round(front.objectives[ok], 9), axis=0)
    assert pareto_mask(distinct, rtol=1e-5).sum() >= 6


def test_integer_variables_come_out_integer_and_feasible():
    # minimise (n, c) with n integer, n c >= 10: the front is c = 10 / n at n = 1 ... 10
    prob = Problem(lambda x, th: 0.0 * x[0], [1.0, 0.5], [10.0, 20.0], inequality=lambda x, th: jnp.array([1.0 - x[0] * x[1] / 10.0]),
                   integer=[True, False])
    front = trace_front(prob, lambda x, th: x, np.zeros((1, 1)), np.array([[3.0, 5.0]]), points=12)
    ok = front.converged & front.feasible
    kept = np.flatnonzero(ok)[pareto_mask(front.objectives[ok])]
    assert kept.size >= 5
    n, c = front.x[kept, 0], front.x[kept, 1]
    np.testing.assert_allclose(n, np.round(n), atol=0)
    np.testing.assert_allclose(c, 10.0 / n, rtol=1e-6)


def test_scalarized_problem_bounds_only_the_bounded_objectives():
    prob = Problem(lambda x, th: 0.0 * x[0], [0.0], [1.0], inequality=lambda x, th: x - 0.5)
    sp = scalarized_problem(prob, lambda x, th: jnp.array([x[0], 1.0 - x[0]]), [1.0, 2.0])
    th = (None, Scalarization(jnp.array([1.0, 0.0]), jnp.array([0.0, 0.2]), jnp.array([0.0, 1.0])))
    g = np.asarray(sp.g(jnp.array([0.3]), th))
    # problem's own g, then -1 (objective 0 unbounded), then (0.7 - 0.2)/2
    np.testing.assert_allclose(g, [-0.2, -1.0, 0.25])


def test_front_helpers_on_hand_worked_cases():
    F = np.array([[0.0, 1.0], [0.2, 0.2], [1.0, 0.0], [0.5, 0.5]])
    assert pareto_mask(F).tolist() == [True, True, True, False]
    assert knee_index(F[:3]) == 1
    # two unit squares' union below (2, 2): 2 x 1 + 1 x 1 - overlap 1 x 1 ... by hand 1.8x... = 3.24
    assert hypervolume_2d(np.array([[0.0, 1.0], [0.2, 0.2], [1.0, 0.0]]), [2.0, 2.0]) == pytest.approx(
        2.0 * 1.0 + 1.8 * 0.8 + 1.0 * 0.2)
