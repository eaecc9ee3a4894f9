"""Multistart: start designs (Sobol, Latin hypercube), clustering and honest success rates.

References: scipy.stats.qmc.Sobol (unscrambled, Joe–Kuo direction numbers) as an independent
implementation of the same sequence; the (0, m, 2)-net property of Sobol's first two
coordinates (Niederreiter, *Random Number Generation and Quasi-Monte Carlo Methods*, SIAM
1992, ch. 4), kept by linear scrambling and digital shifts (Matoušek 1998); the six-hump
camel function's six local minima and global value f* = −1.0316284535 at (±0.0898, ∓0.7126)
(Dixon & Szegö, *Towards Global Optimisation 2*, North-Holland 1978); HS002's published
optimum (Hock & Schittkowski 1981).
"""

import numpy as np
import pytest
from scipy.stats import qmc

import jax.numpy as jnp

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.optimize import (
    Problem,
    SolverOptions,
    latin_hypercube,
    make_multistart,
    sobol_points,
    start_points,
)
from diffsense.optimize import reference_problems as rp


def test_unscrambled_sobol_equals_scipy_joe_kuo_sequence():
    ours = sobol_points(1024, 32, scramble=False)
    ref = qmc.Sobol(32, scramble=False).random(1024)
    np.testing.assert_array_equal(ours, ref)


@pytest.mark.parametrize("seed", [0, 7])
def test_scrambled_sobol_keeps_net_property(seed):
    m = 8
    s = sobol_points(2**m, 32, seed=seed)
    assert np.all((s >= 0) & (s < 1))
    for j in range(32):  # one point per interval of width 2^-m on every axis
        assert np.all(np.bincount((s[:, j] * 2**m).astype(int), minlength=2**m) == 1)
    for k1 in range(m + 1):  # (0, m, 2)-net: every 2^-k1 x 2^-(m-k1) box holds one point
        k2 = m - k1
        cells = (np.floor(s[:, 0] * 2**k1) * 2**k2 + np.floor(s[:, 1] * 2**k2)).astype(int)
        assert np.all(np.bincount(cells, minlength=2**m) == 1)
    np.testing.assert_array_equal(s, sobol_points(2**m, 32, seed=seed))  # reproducible
    assert not np.allclose(s, sobol_points(2**m, 32, seed=seed + 1))


def test_latin_hypercube_one_point_per_stratum():
    u = latin_hypercube(50, 6, seed=3)
    for j in range(6):
        assert np.all(np.bincount((u[:, j] * 50).astype(int), minlength=50) == 1)


def test_start_points_log_scaled_variables_are_log_uniform():
    prob = Problem(lambda x, _: jnp.sum(x), [1e-9, -2.0], [1e-3, 2.0], log_scale=[True, False])
    x = start_points(prob, 256, seed=1)
    assert np.all(x[:, 0] >= 1e-9) and np.all(x[:, 0] <= 1e-3)
    # log10 of the first coordinate is stratified over [-9, -3]: one point per 1/256 of the decades
    u = (np.log10(x[:, 0]) + 9.0) / 6.0
    assert np.all(np.bincount(np.clip((u * 256).astype(int), 0, 255), minlength=256) == 1)
    with pytest.raises(DomainError):
        start_points(Problem(lambda x, _: x[0], -np.inf, np.inf), 4)


def _camel(x, _):
    x1, x2 = x[0], x[1]
    return (4.0 - 2.1 * x1**2 + x1**4 / 3.0) * x1**2 + x1 * x2 + (-4.0 + 4.0 * x2**2) * x2**2


def test_six_hump_camel_clusters_and_success_rate():
    prob = Problem(_camel, [-3.0, -2.0], [3.0, 2.0])
    run = make_multistart(prob, SolverOptions(), compile="fast")
    starts = start_points(prob, 64, seed=0)
    ms = run(jnp.asarray(starts))
    np.testing.assert_allclose(float(ms.best.f), -1.0316284535, atol=1e-10)
    leaders = np.asarray(ms.clusters.is_leader)
    xs = np.asarray(ms.results.x)[leaders]
    fs = np.asarray(ms.results.f)[leaders]
    assert int(ms.clusters.count) == 6  # the six local minima
    # both global minima found, symmetric about the origin
    glob = xs[np.isclose(fs, -1.0316284535, atol=1e-9)]
    assert len(glob) == 2
    np.testing.assert_allclose(np.abs(glob), [[0.0898, 0.7126], [0.0898, 0.7126]], atol=1e-4)
    np.testing.assert_allclose(glob[0], -glob[1], atol=1e-9)
    assert np.all(np.sign(glob[:, 0]) == -np.sign(glob[:, 1]))
    # every leader is a strict local minimum: central-difference gradient ~ 0, Hessian positive definite
    h = 1e-5
    for x in xs:
        f0 = lambda v: float(_camel(jnp.asarray(v), None))  # noqa: E731
        grad = [(f0(x + h * e) - f0(x - h * e)) / (2 * h) for e in np.eye(2)]
        assert np.max(np.abs(grad)) < 1e-6
        H = np.array([[(f0(x + h * (a + b)) - f0(x + h * (a - b)) - f0(x - h * (a - b)) + f0(x - h * (a + b)))
                       / (4 * h * h) for b in np.eye(2)] for a in np.eye(2)])
        assert np.all(np.linalg.eigvalsh(0.5 * (H + H.T)) > 0)
    # success rate recounted independently from the per-start results (all starts in the denominator)
    ok = np.asarray(ms.results.converged) & np.asarray(ms.results.feasible)
    recount = np.mean(ok & (np.asarray(ms.results.f) <= -1.0316284535 + 1e-6))
    np.testing.assert_allclose(float(ms.success_rate), recount, rtol=0)
    assert 0.0 < float(ms.success_rate) < 1.0
    # cluster sizes add up to the converged starts
    assert int(np.sum(np.asarray(ms.clusters.size))) == int(ok.sum())


def test_hs002_multistart_finds_published_optimum():
    P = rp.hs002()
    run = make_multistart(P.problem, SolverOptions(), compile="fast")
    starts = start_points(P.problem, 16, seed=2, box=([-3.0, 1.5], [3.0, 4.0]))
    ms = run(jnp.asarray(starts))
    np.testing.assert_allclose(float(ms.best.f), P.f_star, rtol=1e-9)
    np.testing.assert_allclose(np.asarray(ms.best.x), P.x_star, atol=1e-9)
    assert int(ms.clusters.count) == 2  # the two roots of 400 x^3 - 598 x - 2 with x1^2 near 1.5
