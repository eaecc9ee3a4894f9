"""Worst case of a smooth function over a box (diffsense.optimize.semi_infinite): interior minima
between grid points found to machine precision, several equal minima returned separately,
derivatives by the envelope theorem, boxes of two dimensions, and the dense re-check."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.optimize.semi_infinite import box, dense_check, worst_points


def test_interior_minimum_between_grid_points_is_found_exactly():
    bx = box([0.0], [1.0], counts=17)
    vals, pts = worst_points(lambda th, p: (p[0] - th) ** 2 + 0.5, 0.3712345, bx, n_worst=1)
    assert pts[0, 0] == pytest.approx(0.3712345, abs=1e-12)
    assert vals[0] == pytest.approx(0.5, abs=1e-15)


def _nulls(theta, p):
    # multipath-like lobes in range: sharp nulls of depth -30 dB at R = 2000 / (n pi)
    return theta + 10.0 * jnp.log10(1e-3 + jnp.sin(2000.0 / p[0]) ** 2)


def test_equal_multipath_like_nulls_come_back_as_separate_constraints():
    bx = box([150.0], [12000.0])
    vals, pts = worst_points(_nulls, 5.0, bx, n_worst=3)
    expected = sorted(2000.0 / (n * math.pi) for n in (1, 2, 3, 4))
    got = sorted(float(p) for p in pts[:, 0])
    # three distinct nulls, each at its closed-form position and depth
    assert len({round(g, 3) for g in got}) == 3
    for g in got:
        assert min(abs(g - e) / e for e in expected) < 1e-9
    assert np.allclose(vals, 5.0 - 30.0, atol=1e-9)


def test_derivative_of_the_worst_value_is_the_envelope_derivative():
    bx = box([50.0], [12000.0])

    def v(theta, p):
        a, b = theta
        return a + b * jnp.log10(p[0]) + 10.0 * jnp.log10(1e-2 + jnp.sin(3000.0 / p[0]) ** 2)

    theta = jnp.array([2.0, -40.0])
    worst = lambda th: worst_points(v, th, bx, n_worst=1)[0][0]  # noqa: E731
    g = jax.grad(worst)(theta)
    _, pts = worst_points(v, theta, bx, n_worst=1)
    # envelope theorem: d min / d theta = dv/dtheta at the minimiser
    assert np.allclose(g, [1.0, math.log10(float(pts[0, 0]))], rtol=1e-12)
    # and it equals the finite difference of the true minimum value
    h = 1e-4
    fd = (worst(theta + jnp.array([0.0, h])) - worst(theta - jnp.array([0.0, h]))) / (2 * h)
    assert float(fd) == pytest.approx(float(g[1]), rel=1e-6)


def test_two_dimensional_box_interior_minimum():
    bx = box([0.0, 0.0], [1.0, 2.0])

    def v(theta, p):
        return (p[0] - 0.2345) ** 2 + 3.0 * (p[1] - theta) ** 2 + 0.05 * jnp.cos(9.0 * p[0]) - 1.0

    vals, pts = worst_points(v, 1.4321, bx, n_worst=2)
    # closed form of the x-minimiser: 2 (x - 0.2345) = 0.45 sin(9x)
    x = 0.2345
    for _ in range(50):
        f, df = 2 * (x - 0.2345) - 0.45 * math.sin(9 * x), 2 - 4.05 * math.cos(9 * x)
        x -= f / df
    assert pts[0, 1] == pytest.approx(1.4321, abs=1e-10)
    assert pts[0, 0] == pytest.approx(x, abs=1e-10)


def test_minimum_on_a_face_of_the_box():
    bx = box([1.0, 1.0], [2.0, 3.0], log=False)
    vals, pts = worst_points(lambda th, p: th * p[0] + (p[1] - 2.5) ** 2, 1.0, bx, n_worst=1)
    assert np.allclose(pts[0], [1.0, 2.5], atol=1e-12)
    assert vals[0] == pytest.approx(1.0, abs=1e-14)


def test_jit_and_vmap_over_the_design():
    bx = box([150.0], [12000.0])
    f = jax.jit(jax.vmap(lambda th: worst_points(_nulls, th, bx, n_worst=2)[0]))
    out = f(jnp.array([0.0, 1.0, 2.0]))
    assert np.allclose(out, np.array([[-30.0] * 2, [-29.0] * 2, [-28.0] * 2]), atol=1e-9)


def test_dense_check_uses_its_own_grid_and_finds_the_worst_point():
    bx = box([150.0], [12000.0])
    fn = jax.jit(jax.vmap(lambda p: _nulls(0.0, p)))
    check = dense_check(fn, bx, n_points=10_001,
                        refine=lambda p: tuple(np.asarray(a)[0] for a in worst_points(
                            _nulls, 0.0, bx, n_worst=1, extra=jnp.asarray(p)[None, :])[::-1]))
    assert check.n_points >= 10_001
    grid = bx.grid()[:, 0]
    assert not np.any(np.isin(check.curve_p[1:-1], grid))  # no point shared with the solver grid
    assert check.worst_value == pytest.approx(-30.0, abs=1e-9)


def test_bad_boxes_are_refused():
    with pytest.raises(ValueError):
        box([1.0], [1.0])
    with pytest.raises(ValueError):
        box([0.0], [10.0], log=True)


def test_a_null_far_narrower_than_the_grid_cell_is_found_to_machine_precision():
    # two-ray interference with reflection coefficient 0.999: 20 log10 |1 - rho e^{i phi}|, phi =
    # 2 pi 400 / p, has nulls at p = 400 / k of depth 20 log10(1 - rho) = -60 dB; about 10 m wide
    # at -20 dB near p = 100, against a grid cell of 47 m. Newton alone fails here (the function is
    # concave away from the null); the bracketed line search must land on the closed form.
    rho = 0.999

    def f(theta, p):
        phi = 2.0 * math.pi * 400.0 / p[0]
        return theta + 10.0 * jnp.log10(1.0 + rho**2 - 2.0 * rho * jnp.cos(phi))

    bx = box([90.0], [110.0], counts=3, log=False)  # the null at 100 lies between grid points only
    vals, pts = worst_points(f, 0.0, bx, n_worst=1)
    assert pts[0, 0] == pytest.approx(100.0, rel=1e-12)
    assert vals[0] == pytest.approx(20.0 * math.log10(1.0 - rho), abs=1e-9)


def test_shared_value_only_search_finds_each_functions_minima_and_envelope_derivative():
    from diffsense.optimize.semi_infinite import worst_points_shared

    # three functions of one point, evaluated together: an interior quadratic minimum between
    # grid points, multipath-like nulls (closed-form positions), and a minimum on the box face
    def fns(theta, p):
        return jnp.stack([(p[0] - theta) ** 2 + 0.5, _nulls(theta, jnp.asarray([p[0] * 1000.0])),
                          theta * p[0]])

    bx = box([0.15], [12.0])
    vals, pts = worst_points_shared(fns, 0.3712345, bx, 3, n_worst=2)
    # values alone place a smooth minimiser to ~sqrt(eps) (the values are flat at round-off there)
    assert pts[0, 0, 0] == pytest.approx(0.3712345, rel=1e-7) and vals[0, 0] == pytest.approx(0.5, abs=1e-14)
    nulls = [2000.0 / (n * math.pi) / 1000.0 for n in (1, 2, 3, 4)]
    for p in pts[1, :, 0]:
        assert min(abs(float(p) - e) / e for e in nulls) < 1e-7
    assert np.allclose(vals[1], 0.3712345 - 30.0, atol=1e-6)
    assert float(pts[2, 0, 0]) == 0.15 and float(vals[2, 0]) == pytest.approx(0.3712345 * 0.15, rel=1e-15)
    # the same values as the Newton polish, one function at a time
    newton = worst_points(lambda th, p: fns(th, p)[0], 0.3712345, bx, n_worst=1)[0][0]
    assert float(vals[0, 0]) == pytest.approx(float(newton), abs=1e-14)
    # envelope derivative: d/dtheta of min_p theta*p over [0.15, 12] is 0.15
    g = jax.grad(lambda th: worst_points_shared(fns, th, bx, 3, n_worst=1)[0][2, 0])(0.5)
    assert float(g) == pytest.approx(0.15, rel=1e-12)
