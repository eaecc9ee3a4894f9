"""Order-statistic CFAR (diffsense.detection.cfar_ordered), single pulse.

Independent references, in mpmath at 30 digits (shared parts in tests/helpers/cfar_references.py):
- Rohling's (1983) product ``Pfa = prod_{i<k} (n-i)/(n-i+T)``; the multiplier as its mpmath root.
- Swerling 1/2: the product at ``T/(1+S)``. Swerling 3/4: ``E[(1 + b0 T X) exp(-c X)] = L(c) -
  b0 T L'(c)``, ``L`` the product and ``L'`` its mpmath derivative (mp.diff).
- The definition ``Pd = E[Pd_fixed(T X_(k))]``: mpmath.quad of the order-statistic density
  ``k C(n,k) (1-e^-x)^(k-1) e^(-(n-k+1)x)`` (David & Nagaraja, Order Statistics, sec. 2.1) times
  the single-pulse fixed-threshold Pd (Swerling 0: the Marcum Q function as a Poisson mixture).
  It checks the closed-form references above and the Swerling 0 series below.
- Swerling 0, an exact discrete series, a different route: with ``J | X ~ Poisson(T X)`` and
  ``K ~ Poisson(S)``, ``Pd = P(J <= K) = sum_j P(J=j) P(K>=j)``; by Renyi's representation J is a
  sum of k independent geometric counts with success probabilities ``(n-i)/(n-i+T)``, so its law
  is their convolution.
- Richards, Fundamentals of Radar Signal Processing, sec. 6.5.6 / Fig. 6.29: N = 20, k = 15,
  multiplier 6.857 for Pfa = 1e-3.
- Required SNRs: Swerling 1/2 closed form ``S = T(Pfa)/T(Pd) - 1`` from the mpmath multipliers;
  otherwise one Newton step of the mpmath reference from the computed root. Known-noise
  requirements for the loss: mpmath roots of the single-pulse formulas.
- Cross-module: k = 1 (the minimum of n unit exponentials is exponential with mean 1/n) makes
  OS-CFAR CA-CFAR with one cell (diffsense.detection.cfar, its own quadrature); k = n the maximum.

Programs are compiled per function, Swerling class and argument shape, not per (n, k): the tests
keep to a few shapes (SNR grids of 5, Pd grids of 4, multiplier grids of 4, scalars for
gradients).
"""

import functools
import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffsense.detection.cfar import cfar_loss_db, cfar_pd
from diffsense.detection.cfar_ordered import (
    os_cfar_loss_db,
    os_cfar_multiplier,
    os_cfar_pd,
    os_cfar_pfa,
    os_cfar_required_snr_db,
)
from diffsense.detection.core import pd_given_threshold
from diffsense.errors import DomainError
from helpers import cfar_references as ref
from helpers.function_checks import check_grad_vs_fd

MPMATH_DPS = 30

SNR_DB = np.array([-5.0, 5.0, 13.0, 20.0, 35.0])
PD = np.array([0.1, 0.5, 0.9, 0.999])
PFA = (1e-2, 1e-6, 1e-12)
#: (n, k) pairs spanning n = 8 ... 64 and k = 1 ... n
CELLS = [(8, 1), (8, 6), (16, 4), (24, 18), (32, 32), (64, 16), (64, 48), (64, 64)]

# --------------------------------------------------------------------------------------
# mpmath references for the order statistic
# --------------------------------------------------------------------------------------


def _mp_log_laplace(t, n, k):
    return -mp.fsum(mp.log1p(t / (n - i)) for i in range(k))


@functools.lru_cache(maxsize=None)
def _mp_multiplier(pfa, n, k):
    log_a = mp.log(mp.expm1(-mp.log(mp.mpf(pfa)) / k))
    lo, hi = mp.log(n - k + 1) + log_a - 0.01, mp.log(n) + log_a + 0.01
    return ref.multiplier(lambda t: _mp_log_laplace(t, n, k), pfa, lo, hi)


def _mp_density(x, n, k):
    return k * mp.binomial(n, k) * (-mp.expm1(-x)) ** (k - 1) * mp.exp(-(n - k + 1) * x)


def _mp_closed_pd(snr_db, t, n, k, swerling):
    """Swerling 1: L(T/(1+S)); Swerling 3: L(c) - b0 T L'(c), L' by mpmath differentiation."""
    snr = ref.snr_linear(snr_db)
    laplace = lambda c: mp.exp(_mp_log_laplace(c, n, k))
    if swerling in (1, 2):
        return laplace(t / (1 + snr))
    c = t / (1 + snr / 2)
    b0 = (snr / 2) / (1 + snr / 2) ** 2
    return laplace(c) - b0 * t * mp.diff(laplace, c)


def _mp_pd_quad(snr_db, t, n, k, swerling):
    return ref.pd_quad(lambda x: _mp_density(x, n, k), snr_db, t, swerling, [0, 0.25, 0.5, 1, 2, 4, 8, 16, mp.inf])


@functools.lru_cache(maxsize=None)
def _mp_j_pmf(pfa, n, k, snr_db_max):
    """Law of J = sum of k geometric counts (failures before success, success (n-i)/(n-i+T))."""
    t = _mp_multiplier(pfa, n, k)
    j_max = ref.count_terms(ref.snr_linear(snr_db_max))
    pmf = [mp.mpf(1)] + [mp.mpf(0)] * j_max
    for i in range(k):
        p, q = (n - i) / (n - i + t), t / (n - i + t)
        acc, out = mp.mpf(0), []
        for j in range(j_max + 1):
            acc = q * acc + p * pmf[j]
            out.append(acc)
        pmf = out
    return pmf


def _mp_series_pd(snr_db, pfa, n, k, snr_db_max=35.0):
    """Swerling 0 exact series; the law of J is computed once per (pfa, n, k) up to snr_db_max."""
    pmf = _mp_j_pmf(pfa, n, k, snr_db_max)
    return ref.pd_steady_series(pmf[: ref.count_terms(ref.snr_linear(snr_db)) + 1], snr_db)


def _mp_required_snr_swerling1(pd, pfa, n, k):
    return float(10 * mp.log10(_mp_multiplier(pfa, n, k) / _mp_multiplier(pd, n, k) - 1))


def _distance_db(x_db, pd, pfa, n, k, swerling):
    """Distance of a computed required SNR from the root of the mpmath reference Pd."""
    if swerling in (3, 4):
        pd_ref = lambda x: _mp_closed_pd(x, _mp_multiplier(pfa, n, k), n, k, 3)
    else:
        pd_ref = lambda x: _mp_series_pd(x, pfa, n, k)
    return ref.newton_distance_db(pd_ref, x_db, pd)


def _prob_error(got, want):
    """Absolute error, and relative error where the value is below 1e-3 (small Pd near Pfa)."""
    return abs(got - want) / (want if want < 1e-3 else 1.0)


# --------------------------------------------------------------------------------------
# Multiplier and false alarms
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("n", [8, 16, 24, 32, 64])
def test_multiplier_matches_mpmath_root(n):
    pfa = np.array([1e-2, 1e-6, 1e-12, 1e-100])
    for k in sorted({1, max(n // 4, 1), 3 * n // 4, n}):
        got = np.asarray(os_cfar_multiplier(pfa, n, k))
        want = np.array([float(_mp_multiplier(p, n, k)) for p in pfa])
        # the rounding of log(pfa) alone moves log T by eps |ln pfa| / k (5e-14/k at 1e-100);
        # measured: within 1.3 of this bound
        rel = np.abs(got / want - 1)
        assert np.all(rel <= 2.2e-16 * (2.0 + 2.0 * np.abs(np.log(pfa)) / k)), (k, rel)


def test_multiplier_and_pfa_reproduce_richards_example():
    # Richards, Fundamentals of Radar Signal Processing, sec. 6.5.6 / Fig. 6.29: N = 20, k = 15,
    # "a multiplier of alpha_OS = 6.857 gives Pfa = 1e-3" (a value read off his Fig. 6.29). The
    # exact root is 6.85539 (2.3e-4 relative below the book's value) and Pfa(6.857) = 0.998724e-3
    # (1.3e-3 relative): the book's 4 digits.
    assert abs(float(os_cfar_multiplier(1e-3, 20, 15)) / 6.857 - 1) < 3e-4
    assert abs(float(os_cfar_pfa(6.857, 20, 15)) / 1e-3 - 1) < 1.5e-3
    assert abs(float(os_cfar_multiplier(1e-3, 20, 15)) - float(_mp_multiplier(1e-3, 20, 15))) < 1e-13


def test_pfa_closed_forms_and_round_trip():
    t = np.array([0.5, 3.0, 40.0, 1e4])
    # k = 1: minimum of n unit exponentials ~ Exp(rate n): Pfa = n/(n + T)
    np.testing.assert_allclose(np.asarray(os_cfar_pfa(t, 10, 1)), 10 / (10 + t), rtol=1e-15)
    # k = n = 2: maximum of two, CDF (1 - e^-x)^2: E[exp(-T max)] = 2/((1+T)(2+T))
    # (log-domain products: relative rounding ~ eps |ln Pfa|)
    np.testing.assert_allclose(np.asarray(os_cfar_pfa(t, 2, 2)), 2 / ((1 + t) * (2 + t)), rtol=1e-14)
    for n, k in CELLS:
        pfa = np.array([1e-2, 1e-5, 1e-9, 1e-12])
        back = np.asarray(os_cfar_pfa(os_cfar_multiplier(pfa, n, k), n, k))
        np.testing.assert_allclose(back, pfa, rtol=5e-14)


# --------------------------------------------------------------------------------------
# Detection probability
# --------------------------------------------------------------------------------------


def test_references_agree_with_the_definition():
    # the fixed-threshold laws used in the references, against the exact core
    for sw in (0, 1, 3):
        for snr, t in [(0.5, 3.0), (10.0, 13.8), (80.0, 40.0)]:
            want = float(ref.pd_fixed(mp.mpf(snr), mp.mpf(t), sw))
            assert abs(float(pd_given_threshold(snr, t, 1, sw)) - want) < 1e-14
    # the closed-form and series references, against mpmath.quad of E[Pd_fixed(T X_(k))]
    for n, k, pfa, snr_db, sw in [(8, 6, 1e-12, 20.0, 1), (64, 48, 1e-2, -5.0, 3), (24, 18, 1e-6, 13.0, 3),
                                  (24, 18, 1e-6, 13.0, 0)]:
        t = _mp_multiplier(pfa, n, k)
        quad = _mp_pd_quad(snr_db, t, n, k, sw)
        other = _mp_series_pd(snr_db, pfa, n, k) if sw == 0 else _mp_closed_pd(snr_db, t, n, k, sw)
        assert abs(quad / other - 1) < 1e-25


def test_pd_swerling_1_to_4_match_closed_forms():
    # measured: absolute error <= 2.5e-15, relative error of small Pd <= 2.1e-14 (n = 8-64,
    # k = 1-n, Pfa 1e-2-1e-12, SNR -5-35 dB)
    worst = 0.0
    for n, k in CELLS:
        for pfa in PFA:
            t = _mp_multiplier(pfa, n, k)
            for sw in (1, 3):
                got = np.asarray(os_cfar_pd(SNR_DB, pfa, n, k, sw))
                np.testing.assert_array_equal(np.asarray(os_cfar_pd(SNR_DB, pfa, n, k, sw + 1)), got)
                for s, g in zip(SNR_DB, got):
                    worst = max(worst, _prob_error(g, float(_mp_closed_pd(s, t, n, k, sw))))
    assert worst < 1e-13, worst


@pytest.mark.parametrize("n,k", [(8, 6), (24, 18), (64, 48)])
def test_pd_swerling0_matches_exact_series(n, k):
    # measured over this grid and the slow one: absolute <= 3e-15, relative (small Pd) <= 7e-15
    snr_db = np.array([-5.0, 5.0, 13.0, 20.0, 25.0])
    for pfa in (1e-2, 1e-12):
        got = np.asarray(os_cfar_pd(snr_db, pfa, n, k, 0))
        for s, g in zip(snr_db, got):
            want = float(_mp_series_pd(s, pfa, n, k, 25.0))
            assert _prob_error(g, want) < 2e-14, (pfa, s, g, want)


@pytest.mark.slow
@pytest.mark.parametrize("n,k,pfa", [(8, 1, 1e-6), (16, 4, 1e-8), (32, 32, 1e-4), (64, 16, 1e-10), (64, 64, 1e-3)])
def test_pd_swerling0_matches_exact_series_slow(n, k, pfa):
    got = np.asarray(os_cfar_pd(SNR_DB, pfa, n, k, 0))
    for s, g in zip(SNR_DB, got):
        want = float(_mp_series_pd(s, pfa, n, k))
        assert _prob_error(g, want) < 2e-14, (s, g, want)


@pytest.mark.slow
@pytest.mark.parametrize("n,k,pfa,snr_db", [(8, 6, 1e-12, 22.0), (64, 48, 1e-2, -5.0), (16, 4, 1e-8, 13.0)])
def test_pd_swerling0_matches_quadrature_of_definition(n, k, pfa, snr_db):
    want = float(_mp_pd_quad(snr_db, _mp_multiplier(pfa, n, k), n, k, 0))
    assert _prob_error(float(os_cfar_pd(snr_db, pfa, n, k, 0)), want) < 2e-14


def test_pd_extreme_pfa_and_vanishing_snr():
    # Pfa = 1e-100 (spot check of the admitted domain) against the exact series and product
    n, k = 24, 18
    got0 = np.asarray(os_cfar_pd(SNR_DB, 1e-100, n, k, 0))
    got1 = np.asarray(os_cfar_pd(SNR_DB, 1e-100, n, k, 1))
    t = _mp_multiplier(1e-100, n, k)
    for s, g0, g1 in zip(SNR_DB, got0, got1):
        assert _prob_error(g0, float(_mp_series_pd(s, 1e-100, n, k))) < 1e-13
        assert _prob_error(g1, float(_mp_closed_pd(s, t, n, k, 1))) < 1e-13
    # S -> 0: Pd -> Pfa with full relative accuracy (S = 1e-10)
    for sw in (0, 1, 3):
        got = np.asarray(os_cfar_pd(np.full(5, -100.0), 1e-8, n, k, sw))
        assert np.all(np.abs(got / 1e-8 - 1) < 1e-7) and np.all(got > 1e-8)


def test_pd_jit_vmap_broadcast():
    f = jax.jit(lambda s: os_cfar_pd(s, 1e-6, 24, 18, 1))
    s = jnp.array([[5.0, 10.0], [15.0, 20.0]])
    t = _mp_multiplier(1e-6, 24, 18)
    want = np.array([[float(_mp_closed_pd(x, t, 24, 18, 1)) for x in row] for row in np.asarray(s)])
    np.testing.assert_allclose(np.asarray(f(s)), want, rtol=1e-14)
    v = jax.vmap(lambda p: os_cfar_pd(13.0, p, 24, 18, 1))(jnp.array([1e-4, 1e-8]))
    assert v.shape == (2,) and float(v[0]) > float(v[1])


@pytest.mark.slow
def test_k_equals_one_is_ca_cfar_with_one_cell():
    # X_(1) ~ Exp(rate n): Y > T X_(1) is CA-CFAR with one cell and multiplier T / n. (At 20 dB
    # and above, Swerling 0, diffsense.detection.cfar's quadrature departs from the exact series
    # by up to 6e-5 for one cell at Pfa = 1e-4, so the comparison stops at 10 dB.)
    snr_db = np.array([0.0, 5.0, 10.0, 10.0, 10.0])
    for sw in (0, 1, 3):
        got = np.asarray(os_cfar_pd(snr_db, 1e-4, 5, 1, sw))
        want = np.asarray(cfar_pd(snr_db, 1e-4, 1, 1, swerling=sw))
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


# --------------------------------------------------------------------------------------
# Required SNR and loss
# --------------------------------------------------------------------------------------


def test_required_snr_swerling1_closed_form():
    # measured: <= 3e-13 dB from the mpmath closed form (n = 8-64, k = 1-n, Pfa 1e-2-1e-12)
    for n, k in CELLS:
        for pfa in PFA:
            got = np.asarray(os_cfar_required_snr_db(PD, pfa, n, k, 1))
            want = [_mp_required_snr_swerling1(p, pfa, n, k) for p in PD]
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-11)
            np.testing.assert_array_equal(np.asarray(os_cfar_required_snr_db(PD, pfa, n, k, 2)), got)


@pytest.mark.parametrize("sw", [0, 3])
def test_required_snr_matches_mpmath_roots(sw):
    # measured: <= 2e-12 dB (Swerling 0), <= 1e-13 dB (Swerling 3) from the reference roots
    n, k = 24, 18
    for pfa in (1e-2, 1e-12):
        got = np.asarray(os_cfar_required_snr_db(PD, pfa, n, k, sw))
        if sw == 3:
            np.testing.assert_array_equal(np.asarray(os_cfar_required_snr_db(PD, pfa, n, k, 4)), got)
        for p, x in zip(PD, got):
            assert abs(_distance_db(x, p, pfa, n, k, sw)) < 1e-10, (pfa, p, x)


@pytest.mark.slow
@pytest.mark.parametrize("n,k,pfa,sw", [(8, 6, 1e-6, 0), (64, 48, 1e-6, 0), (16, 4, 1e-9, 0), (32, 32, 1e-3, 0),
                                        (8, 1, 1e-12, 3), (64, 64, 1e-2, 3)])
def test_required_snr_matches_mpmath_roots_slow(n, k, pfa, sw):
    got = np.asarray(os_cfar_required_snr_db(PD, pfa, n, k, sw))
    for p, x in zip(PD, got):
        assert abs(_distance_db(x, p, pfa, n, k, sw)) < 1e-10, (p, x)


def _loss_reference(pd, pfa, n, k, sw, required):
    """The reference requirement (computed root corrected by one mpmath Newton step, or the
    Swerling 1 closed form) minus the mpmath known-noise requirement."""
    if sw in (1, 2):
        cfar = _mp_required_snr_swerling1(pd, pfa, n, k)
    else:
        cfar = required - _distance_db(required, pd, pfa, n, k, sw)
    return cfar - ref.known_noise_db(pd, pfa, sw)


_SLOW = pytest.mark.slow


@pytest.mark.parametrize("sw,n,k,pfa", [
    (1, 8, 6, 1e-12), (1, 64, 48, 1e-2), (0, 24, 18, 1e-6),
    pytest.param(3, 16, 12, 1e-9, marks=_SLOW), pytest.param(3, 64, 16, 1e-4, marks=_SLOW),
    pytest.param(0, 8, 2, 1e-3, marks=_SLOW), pytest.param(0, 32, 24, 1e-12, marks=_SLOW),
])
def test_loss_matches_references(sw, n, k, pfa):
    # measured: <= 1.1e-12 dB (Swerling 1), <= 2e-12 dB (Swerling 0)
    got = np.asarray(os_cfar_loss_db(PD, pfa, n, k, sw))
    required = np.asarray(os_cfar_required_snr_db(PD, pfa, n, k, sw))
    for p, g, r in zip(PD, got, required):
        assert abs(g - _loss_reference(p, pfa, n, k, sw, r)) < 1e-9


@pytest.mark.slow
def test_loss_exceeds_ca_cfar_loss():
    # In homogeneous exponential noise cell averaging is the best of these estimators (the
    # sum of the cells is sufficient for the exponential scale), so OS-CFAR loses more than
    # CA-CFAR (diffsense.detection.cfar) with the same cells; for k = 3n/4 the excess is a
    # fraction of a dB at n = 24 and Pfa = 1e-6 (Rohling 1983), growing as Pfa falls. Measured:
    # 0.38-0.50 dB (Swerling 0, 1e-4), 0.59-0.63 (Swerling 1, 1e-6), 0.99-1.05 (Swerling 1,
    # 1e-10), 0.78-0.86 dB (Swerling 3, 1e-8).
    for sw, pfa in [(0, 1e-4), (1, 1e-6), (1, 1e-10), (3, 1e-8)]:
        excess = np.asarray(os_cfar_loss_db(PD, pfa, 24, 18, sw)) - np.asarray(cfar_loss_db(PD, pfa, 24, 1, sw))
        assert np.all(excess > 0.3) and np.all(excess < 1.1), excess


# --------------------------------------------------------------------------------------
# Derivatives
# --------------------------------------------------------------------------------------


def test_multiplier_gradient_matches_implicit_closed_form():
    # dT/dPfa = 1 / (dPfa/dT), dPfa/dT = -Pfa sum_{i<k} 1/(n-i+T)
    grad = jax.grad(lambda p, n, k: os_cfar_multiplier(p, n, k))
    for n, k in [(24, 18), (8, 1), (64, 64)]:
        for pfa in (1e-2, 1e-10):
            t = _mp_multiplier(pfa, n, k)
            want = float(-1 / (pfa * mp.fsum(1 / (n - i + t) for i in range(k))))
            assert abs(float(grad(pfa, n, k)) / want - 1) < 1e-13


def test_required_snr_gradient_swerling1_matches_mpmath_differences():
    def want_req(pd, pfa):
        return 10 * mp.log10(_mp_multiplier(pfa, 24, 18) / _mp_multiplier(pd, 24, 18) - 1)

    pd0, pfa0, h = mp.mpf("0.9"), mp.mpf("1e-6"), mp.mpf("1e-12")
    d_pd = float((want_req(pd0 + h, pfa0) - want_req(pd0 - h, pfa0)) / (2 * h))
    d_pfa = float((want_req(pd0, pfa0 * (1 + h)) - want_req(pd0, pfa0 * (1 - h))) / (2 * h * pfa0))
    g = jax.grad(lambda a, b: os_cfar_required_snr_db(a, b, 24, 18, 1), argnums=(0, 1))(0.9, 1e-6)
    np.testing.assert_allclose([float(x) for x in g], [d_pd, d_pfa], rtol=1e-11)


def _check_gradients(fn, points, domain):
    grad = jax.grad(fn, argnums=(0, 1))
    for args in points:
        check_grad_vs_fd(fn, grad, args, domain, rtol=1e-6)


_PD_POINTS = [(-5.0, 1e-2), (13.0, 1e-6), (25.0, 1e-12)]
_REQ_POINTS = [(0.1, 1e-2), (0.5, 1e-6), (0.999, 1e-12)]
_GRADIENT_CASES = [("pd", 0), ("required", 3), ("loss", 1)]
_SLOW_GRADIENT_CASES = [("pd", 1), ("pd", 3), ("required", 0), ("loss", 0), ("loss", 3)]


def _gradient_case(kind, sw):
    # (8, 2), not (8, 1): with the minimum of 8 cells, Pd = 0.999 at Pfa = 1e-12 needs 128 dB
    # (Swerling 0), outside the Pd functions' domain, where the required SNR is NaN
    for n, k in [(24, 18), (8, 2), (64, 64)]:
        if kind == "pd":
            _check_gradients(lambda s, p: os_cfar_pd(s, p, n, k, sw), _PD_POINTS, [(-100, 100, False), (1e-100, 1, True)])
        elif kind == "required":
            f = lambda a, p: os_cfar_required_snr_db(a, p, n, k, sw)
            _check_gradients(f, _REQ_POINTS, [(1e-12, 0.9999, False), (1e-100, 1, True)])
        else:
            f = lambda a, p: os_cfar_loss_db(a, p, n, k, sw)
            _check_gradients(f, _REQ_POINTS, [(1e-12, 0.9999, False), (1e-100, 0.5, True)])


@pytest.mark.parametrize("kind,sw", _GRADIENT_CASES)
def test_gradients_match_finite_differences(kind, sw):
    _gradient_case(kind, sw)


@pytest.mark.slow
@pytest.mark.parametrize("kind,sw", _SLOW_GRADIENT_CASES)
def test_gradients_match_finite_differences_slow(kind, sw):
    _gradient_case(kind, sw)


# --------------------------------------------------------------------------------------
# Properties
# --------------------------------------------------------------------------------------

SETTINGS = settings(max_examples=15, deadline=None)


@SETTINGS
@given(s1=st.floats(-10.0, 30.0), ds=st.floats(0.05, 2.0), lp=st.floats(-12.0, -2.0), sw=st.sampled_from([0, 1, 3]),
       cells=st.sampled_from(CELLS))
def test_pd_increases_with_snr_and_lies_between_pfa_and_one(s1, ds, lp, sw, cells):
    pfa = 10.0**lp
    pd = np.asarray(os_cfar_pd(s1 + ds * np.arange(5.0), pfa, *cells, sw))
    assert pd[0] >= pfa and pd[-1] <= 1.0
    step = np.diff(pd)
    # strictly increasing while the miss probability is resolved; within rounding near 1
    assert np.all(step[pd[:-1] < 1.0 - 1e-10] > 0.0) and np.all(step > -4e-15)


@SETTINGS
@given(lp=st.floats(-12.0, -2.0), sw=st.sampled_from([0, 1, 3]))
def test_loss_decreases_with_more_cells(lp, sw):
    pfa = 10.0**lp
    # k = 3n/4; the known-noise part of the loss is the same for every n, so the required SNRs
    # order the losses
    req = np.array([np.asarray(os_cfar_required_snr_db(PD, pfa, n, 3 * n // 4, sw)) for n in (16, 32, 64)])
    assert np.all(req[0] > req[1]) and np.all(req[1] > req[2])


@pytest.mark.slow
def test_loss_decreases_with_cells_sweep():
    losses = np.array([np.asarray(os_cfar_loss_db(PD, 1e-6, n, 3 * n // 4, 1)) for n in range(8, 68, 4)])
    assert np.all(losses[:-1] > losses[1:]) and np.all(losses > 0)


# --------------------------------------------------------------------------------------
# Domain
# --------------------------------------------------------------------------------------


def test_out_of_domain_raises():
    for bad in [lambda: os_cfar_multiplier(1e-6, 24, 25),  # k > n
                lambda: os_cfar_multiplier(1e-6, 24, 0),
                lambda: os_cfar_multiplier(1e-6, 24.5, 18),
                lambda: os_cfar_multiplier(1e-101, 24, 18),
                lambda: os_cfar_pd(10.0, 1e-6, 24, 18, swerling=5),
                lambda: os_cfar_pd(101.0, 1e-6, 24, 18),
                lambda: os_cfar_required_snr_db(1e-7, 1e-6, 24, 18),  # pd must exceed pfa
                lambda: os_cfar_required_snr_db(0.99999, 1e-6, 24, 18),
                lambda: os_cfar_loss_db(0.9, 0.6, 24, 18),
                lambda: os_cfar_pfa(-1.0, 24, 18),
                lambda: jax.jit(lambda n: os_cfar_multiplier(1e-6, n, 2))(24)]:
        with pytest.raises(DomainError):
            bad()


def test_traced_out_of_domain_is_nan():
    f = jax.jit(lambda p: os_cfar_required_snr_db(p, 1e-6, 24, 18, 1))
    assert math.isnan(float(f(1e-7)))
    assert math.isnan(float(jax.grad(lambda p: f(p))(1e-7)))


#: corners of the documented domain: cells (n, k), SNR -100/100 dB, Pfa 1e-100 ... < 1 (loss:
#: 0.5), Pd just above Pfa ... PD_MAX
_CORNER_CELLS = [(1, 1), (2, 2), (8, 6), (64, 1), (64, 64)]


def _corner_values(sw):
    out = []
    for n, k in _CORNER_CELLS:
        out.append(os_cfar_multiplier(np.array([1e-100, 1e-12, 0.5, 0.999999]), n, k))
        out.append(os_cfar_pfa(np.array([1e-300, 1e-3, 1e3, 1e300]), n, k))
        out.append(os_cfar_pd(np.array([-100.0, 100.0, -100.0, 100.0, 0.0]), np.array([1e-100, 1e-100, 0.999999, 0.999999, 0.5]),
                              n, k, sw))
        for pfa in (1e-100, 0.5):
            pd = np.array([pfa * (1 + 1e-6), 0.6 if pfa == 0.5 else 1e-50, 0.9, 0.9999])
            out.append(os_cfar_required_snr_db(pd, pfa, n, k, sw))
            out.append(os_cfar_loss_db(pd, pfa, n, k, sw))
    return out


@pytest.mark.parametrize("sw", [0, 1, 3])
def test_values_finite_at_domain_corners(sw):
    for value in _corner_values(sw):
        assert np.all(np.isfinite(np.asarray(value)))


@pytest.mark.slow
@pytest.mark.parametrize("sw", [0, 1, 3])
def test_gradients_finite_at_domain_corners(sw):
    for n, k in _CORNER_CELLS:
        pd_grad = jax.grad(lambda s, p: os_cfar_pd(s, p, n, k, sw), argnums=(0, 1))
        for s, p in [(-100.0, 1e-100), (100.0, 1e-100), (-100.0, 0.999999), (100.0, 0.999999)]:
            assert np.all(np.isfinite([float(g) for g in pd_grad(s, p)])), (n, k, s, p)
        for fn, pfas in [(os_cfar_required_snr_db, (1e-100, 0.5, 0.99)), (os_cfar_loss_db, (1e-100, 0.5))]:
            grad = jax.grad(lambda a, p: fn(a, p, n, k, sw), argnums=(0, 1))
            for pfa in pfas:
                for pd in (pfa * (1 + 1e-6), 0.9999):
                    assert np.all(np.isfinite([float(g) for g in grad(pd, pfa)])), (fn, n, k, pd, pfa)


def test_minimum_of_the_cells_swerling0_closed_form_up_to_130_db():
    # k = 1: X_(1) ~ Exp(rate n), so Pd = E_Y[1 - exp(-n Y/T)] = 1 - exp(-S c/(1 + c))/(1 + c) with
    # c = n/T = Pfa/(1 - Pfa) (the moment generating function of the Rician power Y), and the
    # required SNR S = -ln((1 - Pd)(1 + c)) (1 + c)/c in closed form with its derivative
    # dS/dPd = (1 + c)/(c (1 - Pd)). Checks the quadrature's value and, where Pd is near 1 and
    # the SNR high, its derivative (measured: <= 1.3e-10 relative to 120 dB, 2e-8 at 128 dB).
    for n, pfa, pd in [(8, 1e-12, 0.999), (8, 1e-12, 0.9), (16, 1e-6, 0.5), (4, 1e-3, 0.99)]:
        c = pfa / (1 - pfa)
        snr = -math.log((1 - pd) * (1 + c)) * (1 + c) / c
        want = 10 * math.log10(snr)
        want_slope = 10 / math.log(10) * (1 + c) / (c * (1 - pd)) / snr
        f = lambda a: os_cfar_required_snr_db(a, pfa, n, 1, 0)
        assert abs(float(f(pd)) - want) < 1e-9, (n, pfa, pd)
        assert float(jax.grad(f)(pd)) == pytest.approx(want_slope, rel=1e-6)
