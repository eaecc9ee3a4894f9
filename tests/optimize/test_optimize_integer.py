"""Integer rounding with neighbour verification and catalog choice, against closed forms and
exhaustive enumeration (each enumeration below is independent of the solver: the
continuous part of every integer assignment is solved by hand)."""

import itertools
import math

import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.optimize import Problem, SolverOptions, solve_catalog, solve_mixed_integer
from diffsense.optimize.integer import rounding_candidates

OPTS = SolverOptions()


def test_pulses_and_power_integer_answer_closed_form():
    # minimise P + c n  s.t.  n P >= K  (n pulses integrated, P power; K = 10, c = 1).
    # Relaxation: n = P = sqrt(10), f = 2 sqrt(10). For integer n the best P is K/n, cost K/n + n:
    # n = 3 -> 19/3, n = 4 -> 6.5, so n* = 3, P* = 10/3. Rounding n with P kept at sqrt(10)
    # would violate n P >= 10 (3 sqrt(10) = 9.49): the continuous re-solve is needed.
    prob = Problem(lambda x, _: x[0] + x[1], [0.01, 1.0], [100.0, 20.0],
                   inequality=lambda x, _: jnp.array([10.0 - x[0] * x[1]]), integer=[False, True],
                   log_scale=[True, False])
    r = solve_mixed_integer(prob, jnp.array([1.0, 1.0]), None, OPTS, compile="fast")
    np.testing.assert_allclose(np.asarray(r.relaxed.x), [math.sqrt(10), math.sqrt(10)], rtol=1e-9)
    assert bool(r.found)
    np.testing.assert_allclose(np.asarray(r.best.x), [10.0 / 3.0, 3.0], rtol=1e-10)
    np.testing.assert_allclose(float(r.best.f), 19.0 / 3.0, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(r.candidate_f), [19.0 / 3.0, 6.5], rtol=1e-10)
    np.testing.assert_allclose(float(r.gap), 19.0 / 3.0 - 2 * math.sqrt(10), rtol=1e-8)


def _two_integer_problem():
    # minimise (x1-1.7)^2 + (x2-1.6)^2 + (y-x1)^2, x1, x2 integer in [0, 5], y in [-5, 5],
    # s.t. x1 + x2 <= 3.2. For fixed integers the continuous optimum is y = x1.
    return Problem(lambda x, _: (x[0] - 1.7) ** 2 + (x[1] - 1.6) ** 2 + (x[2] - x[0]) ** 2,
                   [0.0, 0.0, -5.0], [5.0, 5.0, 5.0], inequality=lambda x, _: jnp.array([x[0] + x[1] - 3.2]),
                   integer=[True, True, False])


def test_two_integers_nearest_rounding_infeasible_enumeration():
    prob = _two_integer_problem()
    # exhaustive enumeration over the integer grid with y = x1 (independent of the solver)
    best = min(((a - 1.7) ** 2 + (b - 1.6) ** 2, a, b) for a, b in itertools.product(range(6), repeat=2)
               if a + b <= 3.2)
    r = solve_mixed_integer(prob, jnp.zeros(3), None, OPTS, compile="fast")
    # the relaxation is the projection of (1.7, 1.6) on x1 + x2 = 3.2: (1.65, 1.55), y = 1.65
    np.testing.assert_allclose(np.asarray(r.relaxed.x), [1.65, 1.55, 1.65], atol=1e-9)
    # nearest rounding (2, 2) is infeasible; the neighbour check finds the enumerated optimum
    cands = [tuple(c) for c in np.asarray(r.candidates).astype(int)]
    assert not bool(r.candidate_feasible[cands.index((2, 2))])
    np.testing.assert_allclose(np.asarray(r.best.x), [best[1], best[2], best[1]], atol=1e-9)
    np.testing.assert_allclose(float(r.best.f), best[0], rtol=1e-10)


def test_neighbour_mode_for_many_integers_separable_closed_form():
    # k = 3 integers with max_enumerated = 2 -> nearest rounding and its 6 unit neighbours.
    # Separable convex objective sum (x_i - c_i)^2: the integer optimum is round(c).
    c = np.array([0.3, 2.7, -1.4])
    prob = Problem(lambda x, _: jnp.sum((x - jnp.asarray(c)) ** 2), -4.0 * np.ones(3), 4.0 * np.ones(3),
                   integer=True)
    r = solve_mixed_integer(prob, jnp.zeros(3), None, OPTS, max_enumerated=2, compile="fast")
    assert r.candidates.shape == (7, 3)
    np.testing.assert_allclose(np.asarray(r.best.x), np.round(c), atol=1e-12)
    np.testing.assert_allclose(float(r.best.f), np.sum((np.round(c) - c) ** 2), rtol=1e-12)


def test_rounding_candidates_respect_integer_bounds():
    cand = rounding_candidates(jnp.array([0.5, 4.9]), jnp.array([0.0, 0.0]), jnp.array([3.0, 4.0]))
    # 2^2 floor/ceil combinations, the second variable clipped to its integer upper bound 4
    np.testing.assert_array_equal(np.asarray(cand), [[0, 4], [0, 4], [1, 4], [1, 4]])


def test_catalog_picks_best_feasible_option_closed_form():
    # option k: cost c_k + (x - a_k)^2 with requirement x >= r_k, x in [-10, 10].
    # Closed form: x_k = max(a_k, r_k), f_k = c_k + (x_k - a_k)^2; option 3 needs x >= 20: infeasible.
    prob = Problem(lambda x, th: th[0] + (x[0] - th[1]) ** 2, -10.0, 10.0,
                   inequality=lambda x, th: jnp.array([th[2] - x[0]]))
    options = np.array([[1.0, 0.0, 1.0], [0.5, 0.0, 1.5], [0.0, 0.0, 20.0], [1.2, 3.0, -1.0]])
    r = solve_catalog(prob, jnp.array([0.0]), jnp.asarray(options), OPTS, compile="fast")
    xk = np.maximum(options[:, 1], options[:, 2])
    fk = options[:, 0] + (xk - options[:, 1]) ** 2
    feas = options[:, 2] <= 10.0
    np.testing.assert_array_equal(np.asarray(r.feasible), feas)
    assert np.all(np.asarray(r.results.converged)[feas])
    np.testing.assert_allclose(np.asarray(r.results.f)[feas], fk[feas], rtol=1e-10)
    expected = int(np.argmin(np.where(feas, fk, np.inf)))
    assert int(r.index) == expected
    np.testing.assert_allclose(float(r.best.x[0]), xk[expected], rtol=1e-10)


def test_catalog_items_fixing_variables_through_bounds():
    # a transmitter catalog fixes power P (W); choose the pulse width tau >= E/P freely with
    # cost price_k + b tau; closed form tau_k = E/P_k, f_k = price_k + b E / P_k.
    E, b = 1e-3, 1e6
    prob = Problem(lambda x, price: price + b * x[1], [1.0, 1e-9], [1e6, 1e-3],
                   inequality=lambda x, price: jnp.array([E - x[0] * x[1]]), log_scale=True)
    power = np.array([100.0, 1000.0, 5000.0])
    price = np.array([0.5, 2.0, 8.0])
    lo = np.stack([power, np.full(3, 1e-9)], axis=1)
    hi = np.stack([power, np.full(3, 1e-3)], axis=1)
    r = solve_catalog(prob, jnp.array([10.0, 1e-6]), jnp.asarray(price), OPTS, option_lower=lo, option_upper=hi,
                      compile="fast")
    fk = price + b * E / power
    np.testing.assert_allclose(np.asarray(r.results.f), fk, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(r.results.x[:, 0]), power, rtol=0)
    assert int(r.index) == int(np.argmin(fk))
    # the fixed power's bound multiplier is the value of more power: -df/dP = bE/P^2 (upper side)
    np.testing.assert_allclose(np.asarray(r.results.mu_upper[:, 0]), b * E / power**2, rtol=1e-8)
    np.testing.assert_allclose(np.asarray(r.results.mu_lower[:, 0]), 0.0, atol=0)


def test_mixed_integer_needs_integer_variables():
    prob = Problem(lambda x, _: jnp.sum(x**2), -np.ones(2), np.ones(2))
    with pytest.raises(DomainError):
        solve_mixed_integer(prob, jnp.zeros(2))
