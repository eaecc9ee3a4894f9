"""Dense QP solvers — the dual active-set method (Goldfarb–Idnani) and, for the shared closed
form, the interior-point method — against closed forms and the KKT conditions.

For a strictly convex QP the KKT conditions (stationarity, primal feasibility, u ≥ 0 on the
inequalities, complementarity) are sufficient for the unique optimum, so checking them on the
returned (y, u) is an independent test of optimality; closed forms where they exist.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.optimize.active_set import solve_qp_active_set
from diffsense.optimize.qp import solve_qp

_solve = jax.jit(solve_qp_active_set, static_argnums=(4,))


def _random_problem(rng, n, r, n_eq):
    M = rng.normal(size=(n, n))
    Q = M @ M.T + 0.05 * np.eye(n)
    c = rng.normal(size=n)
    A = np.vstack([rng.normal(size=(r, n)), np.eye(n), -np.eye(n)])
    b = np.concatenate([rng.normal(size=r), 3.0 * np.ones(2 * n)])
    return Q, c, A, b


def _assert_kkt(Q, c, A, b, n_eq, y, u, tol=1e-9):
    scale = 1.0 + np.max(np.abs(c)) + np.max(np.abs(A.T) @ np.abs(u))
    assert np.max(np.abs(Q @ y + c + A.T @ u)) <= tol * scale
    if n_eq:
        assert np.max(np.abs(A[:n_eq] @ y - b[:n_eq])) <= tol * (1.0 + np.max(np.abs(b[:n_eq])))
    assert np.max(A[n_eq:] @ y - b[n_eq:]) <= tol * (1.0 + np.max(np.abs(b)))
    assert np.min(u[n_eq:]) >= 0.0
    assert np.max(np.abs(u[n_eq:] * (b[n_eq:] - A[n_eq:] @ y))) <= tol * scale


@pytest.mark.parametrize("method, atol_y, atol_u", [("active_set", 1e-14, 1e-13), ("interior_point", 1e-12, 1e-10)])
def test_box_constrained_diagonal_closed_form(method, atol_y, atol_u):
    # min ½ Σ qᵢyᵢ² + cᵢyᵢ on lo ≤ y ≤ hi: y = clip(−c/q, lo, hi); u = max(∓(q y + c), 0) on the bounds
    rng = np.random.default_rng(3)
    q = rng.uniform(0.1, 10.0, 6)
    c = rng.normal(0.0, 5.0, 6)
    lo, hi = -np.ones(6), np.ones(6)
    A = np.vstack([np.eye(6), -np.eye(6)])
    b = np.concatenate([hi, -lo])
    args = (jnp.diag(q), jnp.asarray(c), jnp.asarray(A), jnp.asarray(b))
    if method == "active_set":
        s = _solve(*args, 0)
        assert bool(s.ok)
    else:
        s = solve_qp(*args)
    y = np.clip(-c / q, lo, hi)
    np.testing.assert_allclose(np.asarray(s.y), y, atol=atol_y)
    grad = q * y + c
    np.testing.assert_allclose(np.asarray(s.u), np.concatenate([np.maximum(-grad, 0), np.maximum(grad, 0)]),
                               atol=atol_u)


def test_equality_constrained_closed_form():
    # min ½‖y‖² − 1ᵀy s.t. Σy = 1 (first row) and y₀ − y₁ = 0.5: the KKT system solved directly
    n = 4
    A = np.array([[1.0, 1.0, 1.0, 1.0], [1.0, -1.0, 0.0, 0.0]])
    b = np.array([1.0, 0.5])
    c = -np.ones(n)
    K = np.block([[np.eye(n), A.T], [A, np.zeros((2, 2))]])
    sol = np.linalg.solve(K, np.concatenate([-c, b]))
    s = _solve(jnp.eye(n), jnp.asarray(c), jnp.asarray(A), jnp.asarray(b), 2)
    assert bool(s.ok)
    np.testing.assert_allclose(np.asarray(s.y), sol[:n], atol=1e-14)
    np.testing.assert_allclose(np.asarray(s.u), sol[n:], atol=1e-14)


def test_random_problems_satisfy_kkt_conditions_and_match_interior_point():
    rng = np.random.default_rng(0)
    ipm = jax.jit(solve_qp, static_argnums=(4,))
    for trial in range(60):  # three shapes: three compilations
        n_eq = trial % 3
        Q, c, A, b = _random_problem(rng, 6, 8, n_eq)
        s = _solve(jnp.asarray(Q), jnp.asarray(c), jnp.asarray(A), jnp.asarray(b), n_eq)
        # the same problem for the interior-point solver: each equality as two inequalities
        A2 = np.vstack([A[:n_eq], -A[:n_eq], A[n_eq:]])
        b2 = np.concatenate([b[:n_eq], -b[:n_eq], b[n_eq:]])
        ref = ipm(jnp.asarray(Q), jnp.asarray(c), jnp.asarray(A2), jnp.asarray(b2), 60)
        consistent = float(ref.primal) <= 1e-9
        assert bool(s.ok) == consistent
        if consistent:
            y, u = np.asarray(s.y), np.asarray(s.u)
            _assert_kkt(Q, c, A, b, n_eq, y, u)
            np.testing.assert_allclose(y, np.asarray(ref.y), atol=1e-6)


def test_inconsistent_rows_and_dependent_equalities_are_reported_not_answered():
    Q, c = jnp.eye(2), jnp.zeros(2)
    # y₀ ≤ −1 and −y₀ ≤ −1 (y₀ ≥ 1): no point satisfies both
    A = jnp.array([[1.0, 0.0], [-1.0, 0.0]])
    b = jnp.array([-1.0, -1.0])
    assert not bool(_solve(Q, c, A, b, 0).ok)
    # parallel equality rows with different right-hand sides: y₀ + y₁ = 1 and = 1.5
    A = jnp.array([[1.0, 1.0], [2.0, 2.0], [1.0, 0.0]])
    assert not bool(_solve(Q, c, A, jnp.array([1.0, 3.0, 5.0]), 2).ok)
    # the same equality twice (consistent): solved, y = (½, ½)
    s = _solve(Q, c, A, jnp.array([1.0, 2.0, 5.0]), 2)
    assert bool(s.ok)
    np.testing.assert_allclose(np.asarray(s.y), [0.5, 0.5], atol=1e-12)


def test_vmap_over_linear_terms_matches_one_at_a_time():
    rng = np.random.default_rng(5)
    Q, _, A, b = _random_problem(rng, 5, 6, 0)
    cs = rng.normal(size=(7, 5))
    batched = jax.vmap(lambda c: solve_qp_active_set(jnp.asarray(Q), c, jnp.asarray(A), jnp.asarray(b)))(
        jnp.asarray(cs))
    for i, c in enumerate(cs):
        one = _solve(jnp.asarray(Q), jnp.asarray(c), jnp.asarray(A), jnp.asarray(b), 0)
        assert bool(batched.ok[i]) == bool(one.ok)
        np.testing.assert_allclose(np.asarray(batched.y[i]), np.asarray(one.y), atol=1e-13)
