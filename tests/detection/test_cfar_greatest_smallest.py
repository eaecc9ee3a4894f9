"""Greatest-of and smallest-of CFAR (diffsense.detection.cfar_greatest_smallest), single pulse.

Independent references, in mpmath at 30 digits (40 inside the GO differences; shared parts in
tests/helpers/cfar_references.py), for half windows of m = n/2 cells, T on the half-window sum:
- The false-alarm sums of Weiss (1982) and Gandhi & Kassam (1988):
  ``Pfa_SO(T) = 2 sum_{i<m} C(m-1+i, i) (2+T)^-(m+i)``, ``Pfa_GO(T) = 2 (1+T)^-m - Pfa_SO(T)``;
  the multipliers as their mpmath roots. These sums are themselves checked against mpmath.quad
  of ``E[exp(-T X)]`` over the densities ``2 f_m(x) P(m, x)`` (GO) and ``2 f_m(x) Q(m, x)``
  (SO) with mpmath's regularized incomplete gamma function.
- Swerling 1/2: the sums at ``T/(1+S)``. Swerling 3/4: ``L(c) - b0 T L'(c)`` with ``L'`` the
  mpmath derivative (mp.diff) of the sums.
- Swerling 0, an exact discrete series: ``Pd = P(J <= K) = sum_j P(J=j) P(K>=j)`` with
  ``J | X ~ Poisson(T X)``, ``K ~ Poisson(S)``; the law of J in closed form, Gamma integrals of
  the densities above: ``P_SO(J=j) = 2 sum_{l<m} T^j (m-1+j+l)! / (j! (m-1)! l! (2+T)^(m+j+l))``,
  ``P_GO(J=j) = 2 NB(j) - P_SO(J=j)`` with ``NB(j) = C(m-1+j, j) T^j (1+T)^-(m+j)``.
- The definition ``Pd = E_X[Pd_fixed(T X)]`` by mpmath.quad over the densities (Swerling 0:
  the Marcum Q function as a Poisson mixture), which checks the series.
- Richards, Fundamentals of Radar Signal Processing, sec. 6.5.5, after eq. 6.155: N = 20,
  alpha_GO = 7.24 on the half-window average (see the test).
- Cross-module: n = 2 (m = 1) has closed forms: GO is OS-CFAR with k = n = 2, and SO-CFAR with
  two cells is OS-CFAR with k = 1, the minimum (diffsense.detection.cfar_ordered).
- Required SNRs: Swerling 1/2 closed form ``S = T(Pfa)/T(Pd) - 1`` from the mpmath
  multipliers; otherwise one Newton step of the mpmath reference from the computed root. Loss:
  minus the mpmath known-noise requirement.

GO and SO share every compiled program (one law with a traced selector); the tests keep to a few
argument shapes (SNR grids of 5, Pd grids of 4, multiplier grids of 4, scalars for gradients).
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

from diffsense.detection.cfar import cfar_loss_db
from diffsense.detection.cfar_greatest_smallest import (
    go_cfar_loss_db,
    go_cfar_multiplier,
    go_cfar_pd,
    go_cfar_pfa,
    go_cfar_required_snr_db,
    so_cfar_loss_db,
    so_cfar_multiplier,
    so_cfar_pd,
    so_cfar_pfa,
    so_cfar_required_snr_db,
)
from diffsense.detection.cfar_ordered import os_cfar_pd, os_cfar_required_snr_db
from diffsense.errors import DomainError
from helpers import cfar_references as ref
from helpers.function_checks import check_grad_vs_fd

MPMATH_DPS = 30

SNR_DB = np.array([-5.0, 5.0, 13.0, 20.0, 35.0])
PD = np.array([0.1, 0.5, 0.9, 0.999])
PFA = (1e-2, 1e-6, 1e-12)
CELLS = (8, 16, 24, 32, 64)
#: the functions of each detector, by name
GO = dict(multiplier=go_cfar_multiplier, pfa=go_cfar_pfa, pd=go_cfar_pd, required=go_cfar_required_snr_db,
          loss=go_cfar_loss_db)
SO = dict(multiplier=so_cfar_multiplier, pfa=so_cfar_pfa, pd=so_cfar_pd, required=so_cfar_required_snr_db,
          loss=so_cfar_loss_db)
DETECTORS = {True: GO, False: SO}

# --------------------------------------------------------------------------------------
# mpmath references for the greatest / smallest of two half-window sums
# --------------------------------------------------------------------------------------


def _mp_laplace(c, n, greatest):
    """Weiss / Gandhi & Kassam: E[exp(-c X)] for X = max or min of two Gamma(n/2, 1) sums."""
    m = n // 2
    # GO as a difference cancels up to log10(2 (1+c)^-m / L_GO) <= 2m log10(2+c) digits: carry them
    extra = 10 + (int(mp.ceil(2 * m * mp.log10(2 + c))) if greatest else 0)
    with mp.workdps(mp.mp.dps + extra):
        so = 2 * mp.fsum(mp.binomial(m - 1 + i, i) * (2 + c) ** -(m + i) for i in range(m))
        out = 2 * (1 + c) ** -m - so if greatest else so
    return +out


@functools.lru_cache(maxsize=None)
def _mp_multiplier(pfa, n, greatest):
    m = n // 2
    a = mp.expm1(-mp.log(mp.mpf(pfa)) / n)
    lo, hi = (a, 2 * a) if greatest else (mp.expm1(-mp.log(mp.mpf(pfa)) / m), (2 / mp.mpf(pfa)) ** (mp.mpf(1) / m))
    return ref.multiplier(lambda t: mp.log(_mp_laplace(t, n, greatest)), pfa, mp.log(lo) - 0.01, mp.log(hi) + 0.01)


def _mp_density(x, n, greatest):
    m = n // 2
    f_m = x ** (m - 1) * mp.exp(-x) / mp.factorial(m - 1)
    p = mp.gammainc(m, 0, x, regularized=True)
    return 2 * f_m * (p if greatest else 1 - p)


def _mp_closed_pd(snr_db, t, n, greatest, swerling):
    snr = ref.snr_linear(snr_db)
    laplace = lambda c: _mp_laplace(c, n, greatest)
    if swerling in (1, 2):
        return laplace(t / (1 + snr))
    c = t / (1 + snr / 2)
    b0 = (snr / 2) / (1 + snr / 2) ** 2
    return laplace(c) - b0 * t * mp.diff(laplace, c)


def _mp_pd_quad(snr_db, t, n, greatest, swerling):
    return ref.pd_quad(lambda x: _mp_density(x, n, greatest), snr_db, t, swerling, [0, 1, 2, 4, 8, 16, 32, 64, mp.inf])


@functools.lru_cache(maxsize=None)
def _mp_j_pmf(pfa, n, greatest, snr_db_max):
    """Law of J | X ~ Poisson(T X) (module docstring), by recurrences in j."""
    m = n // 2
    t = _mp_multiplier(pfa, n, greatest)
    j_max = ref.count_terms(ref.snr_linear(snr_db_max))
    with mp.workdps(mp.mp.dps + 10):
        nb = (1 + t) ** -m
        terms = [2 * mp.binomial(m - 1 + l, l) * (2 + t) ** -(m + l) for l in range(m)]
        pmf = []
        for j in range(j_max + 1):
            so = mp.fsum(terms)
            pmf.append(+(2 * nb - so if greatest else so))
            nb *= t * (m + j) / ((j + 1) * (1 + t))
            terms = [x * t * (m + j + l) / ((j + 1) * (2 + t)) for l, x in enumerate(terms)]
    return pmf


def _mp_series_pd(snr_db, pfa, n, greatest, snr_db_max=35.0):
    pmf = _mp_j_pmf(pfa, n, greatest, snr_db_max)
    return ref.pd_steady_series(pmf[: ref.count_terms(ref.snr_linear(snr_db)) + 1], snr_db)


def _mp_required_snr_swerling1(pd, pfa, n, greatest):
    return float(10 * mp.log10(_mp_multiplier(pfa, n, greatest) / _mp_multiplier(pd, n, greatest) - 1))


def _distance_db(x_db, pd, pfa, n, greatest, swerling):
    if swerling in (3, 4):
        pd_ref = lambda x: _mp_closed_pd(x, _mp_multiplier(pfa, n, greatest), n, greatest, 3)
    else:
        pd_ref = lambda x: _mp_series_pd(x, pfa, n, greatest)
    return ref.newton_distance_db(pd_ref, x_db, pd)


def _prob_error(got, want):
    """Absolute error, and relative error where the value is below 1e-3 (small Pd near Pfa)."""
    return abs(got - want) / (want if want < 1e-3 else 1.0)


# --------------------------------------------------------------------------------------
# Multiplier and false alarms
# --------------------------------------------------------------------------------------


def test_reference_sums_match_quadrature_of_the_densities():
    for n, greatest, c in [(8, True, 3.0), (8, False, 40.0), (64, True, 0.3), (64, False, 2.0)]:
        with mp.workdps(50):  # at 30 digits mp.quad leaves 2e-20 relative on the smallest (1e-15) value
            quad = mp.quad(lambda x: _mp_density(x, n, greatest) * mp.exp(-c * x), [0, 1, 4, 16, 64, mp.inf])
        assert abs(quad / _mp_laplace(mp.mpf(c), n, greatest) - 1) < 1e-25


@pytest.mark.parametrize("greatest", [True, False])
def test_multiplier_matches_mpmath_root(greatest):
    f = DETECTORS[greatest]["multiplier"]
    pfa = np.array([1e-2, 1e-6, 1e-12, 1e-100])
    for n in CELLS:
        got = np.asarray(f(pfa, n))
        want = np.array([float(_mp_multiplier(p, n, greatest)) for p in pfa])
        # the rounding of log(pfa) alone moves log T by ~eps |ln pfa| / m; measured: within 1.1
        # of this bound
        rel = np.abs(got / want - 1)
        assert np.all(rel <= 2.2e-16 * (2.0 + 2.0 * np.abs(np.log(pfa)) / (n // 2))), (n, rel)


def test_go_multiplier_reproduces_richards_example():
    # Richards, Fundamentals of Radar Signal Processing (2nd ed.), sec. 6.5.5 after eq. 6.155:
    # "For N = 20 and [Pfa], alpha_GO = 7.24", alpha_GO multiplying the larger of the two
    # half-window averages (eq. 6.154), i.e. m T on our half-window sum. The Pfa is typeset as
    # an image in the stored copy we read; 1e-3, the Pfa of the section's other examples (the OS
    # example: N = 20, k = 15, 6.857), is the only decade that gives 7.24: 1e-2 and 1e-4 give 4.51
    # and 10.33. The exact multiplier is 7.23969, within the book's 3 digits (error 3.1e-4).
    alpha = 10 * np.asarray(go_cfar_multiplier(np.array([1e-2, 1e-3, 1e-4, 1e-6]), 20))
    assert abs(alpha[1] - 7.24) < 5e-4
    assert abs(alpha[0] - 7.24) > 2 and abs(alpha[2] - 7.24) > 2


def test_pfa_closed_forms_and_round_trip():
    t = np.array([0.5, 3.0, 40.0, 1e4])
    # two cells: the maximum of two unit exponentials has E[exp(-T max)] = 2/((1+T)(2+T)); the
    # minimum is exponential with mean 1/2: 2/(2+T)
    np.testing.assert_allclose(np.asarray(go_cfar_pfa(t, 2)), 2 / ((1 + t) * (2 + t)), rtol=1e-14)
    np.testing.assert_allclose(np.asarray(so_cfar_pfa(t, 2)), 2 / (2 + t), rtol=1e-15)
    pfa = np.array([1e-2, 1e-5, 1e-9, 1e-12])
    for n in CELLS:
        for det in (GO, SO):
            back = np.asarray(det["pfa"](det["multiplier"](pfa, n), n))
            np.testing.assert_allclose(back, pfa, rtol=5e-14)


# --------------------------------------------------------------------------------------
# Detection probability
# --------------------------------------------------------------------------------------


def test_references_agree_with_the_definition():
    # the closed-form and series references, against mpmath.quad of E[Pd_fixed(T X)]
    for n, greatest, pfa, snr_db, sw in [(8, True, 1e-12, 20.0, 1), (64, False, 1e-2, -5.0, 3),
                                         (16, True, 1e-6, 13.0, 3), (16, False, 1e-6, 13.0, 0)]:
        t = _mp_multiplier(pfa, n, greatest)
        quad = _mp_pd_quad(snr_db, t, n, greatest, sw)
        other = _mp_series_pd(snr_db, pfa, n, greatest, 13.0) if sw == 0 else _mp_closed_pd(snr_db, t, n, greatest, sw)
        assert abs(quad / other - 1) < 1e-25


@pytest.mark.parametrize("greatest", [True, False])
def test_pd_swerling_1_to_4_match_closed_forms(greatest):
    # measured: absolute error <= 3e-15, relative error of small Pd <= 3e-14 (n = 8-64,
    # Pfa 1e-2-1e-12, SNR -5-35 dB)
    f = DETECTORS[greatest]["pd"]
    worst = 0.0
    for n in CELLS:
        for pfa in PFA:
            t = _mp_multiplier(pfa, n, greatest)
            for sw in (1, 3):
                got = np.asarray(f(SNR_DB, pfa, n, sw))
                np.testing.assert_array_equal(np.asarray(f(SNR_DB, pfa, n, sw + 1)), got)
                for s, g in zip(SNR_DB, got):
                    worst = max(worst, _prob_error(g, float(_mp_closed_pd(s, t, n, greatest, sw))))
    assert worst < 1e-13, worst


@pytest.mark.parametrize("n,greatest", [(8, True), (64, True), (8, False), (64, False)])
def test_pd_swerling0_matches_exact_series(n, greatest):
    # measured over this grid and the slow one: absolute <= 4e-15, relative (small Pd) <= 1e-14
    snr_db = np.array([-5.0, 5.0, 13.0, 20.0, 25.0])
    for pfa in (1e-2, 1e-12):
        got = np.asarray(DETECTORS[greatest]["pd"](snr_db, pfa, n, 0))
        for s, g in zip(snr_db, got):
            want = float(_mp_series_pd(s, pfa, n, greatest, 25.0))
            assert _prob_error(g, want) < 2e-14, (pfa, s, g, want)


@pytest.mark.slow
@pytest.mark.parametrize("n,greatest,pfa", [(16, True, 1e-6), (24, False, 1e-9), (32, True, 1e-4), (32, False, 1e-3)])
def test_pd_swerling0_matches_exact_series_slow(n, greatest, pfa):
    got = np.asarray(DETECTORS[greatest]["pd"](SNR_DB, pfa, n, 0))
    for s, g in zip(SNR_DB, got):
        assert _prob_error(g, float(_mp_series_pd(s, pfa, n, greatest))) < 2e-14, s


@pytest.mark.slow
@pytest.mark.parametrize("n,greatest,pfa,snr_db", [(8, True, 1e-12, 22.0), (64, False, 1e-2, 13.0)])
def test_pd_swerling0_matches_quadrature_of_definition(n, greatest, pfa, snr_db):
    want = float(_mp_pd_quad(snr_db, _mp_multiplier(pfa, n, greatest), n, greatest, 0))
    assert _prob_error(float(DETECTORS[greatest]["pd"](snr_db, pfa, n, 0)), want) < 2e-14


def test_two_cells_are_order_statistics():
    # m = 1: max(Z1, Z2) and min(Z1, Z2) of two unit exponentials are the order statistics
    # k = 2 and k = 1 of n = 2 cells (diffsense.detection.cfar_ordered, its own law)
    for sw in (0, 1, 3):
        for pfa in (1e-3, 1e-9):
            np.testing.assert_allclose(np.asarray(go_cfar_pd(SNR_DB, pfa, 2, sw)),
                                       np.asarray(os_cfar_pd(SNR_DB, pfa, 2, 2, sw)), rtol=1e-13, atol=1e-15)
            np.testing.assert_allclose(np.asarray(so_cfar_pd(SNR_DB, pfa, 2, sw)),
                                       np.asarray(os_cfar_pd(SNR_DB, pfa, 2, 1, sw)), rtol=1e-13, atol=1e-15)


def test_pd_extreme_pfa_and_vanishing_snr():
    for greatest in (True, False):
        t = _mp_multiplier(1e-100, 24, greatest)
        got1 = np.asarray(DETECTORS[greatest]["pd"](SNR_DB, 1e-100, 24, 1))
        for s, g in zip(SNR_DB, got1):
            assert _prob_error(g, float(_mp_closed_pd(s, t, 24, greatest, 1))) < 1e-13
        # S -> 0: Pd -> Pfa with full relative accuracy (S = 1e-10)
        for sw in (0, 1, 3):
            got = np.asarray(DETECTORS[greatest]["pd"](np.full(5, -100.0), 1e-8, 24, sw))
            assert np.all(np.abs(got / 1e-8 - 1) < 1e-7) and np.all(got > 1e-8)


def test_pd_jit_vmap_broadcast():
    f = jax.jit(lambda s: so_cfar_pd(s, 1e-6, 16, 1))
    s = jnp.array([[5.0, 10.0], [15.0, 20.0]])
    t = _mp_multiplier(1e-6, 16, False)
    want = np.array([[float(_mp_closed_pd(x, t, 16, False, 1)) for x in row] for row in np.asarray(s)])
    np.testing.assert_allclose(np.asarray(f(s)), want, rtol=1e-14)
    v = jax.vmap(lambda p: go_cfar_pd(13.0, p, 16, 1))(jnp.array([1e-4, 1e-8]))
    assert v.shape == (2,) and float(v[0]) > float(v[1])


# --------------------------------------------------------------------------------------
# Required SNR and loss
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("greatest", [True, False])
def test_required_snr_swerling1_closed_form(greatest):
    # measured: <= 3e-13 dB from the mpmath closed form (n = 8-64, Pfa 1e-2-1e-12)
    f = DETECTORS[greatest]["required"]
    for n in CELLS:
        for pfa in PFA:
            got = np.asarray(f(PD, pfa, n, 1))
            want = [_mp_required_snr_swerling1(p, pfa, n, greatest) for p in PD]
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-11)
            np.testing.assert_array_equal(np.asarray(f(PD, pfa, n, 2)), got)


@pytest.mark.parametrize("sw,n,greatest,pfa", [(0, 16, True, 1e-2), (0, 24, False, 1e-12), (3, 8, False, 1e-6),
                                               (3, 64, True, 1e-12)])
def test_required_snr_matches_mpmath_roots(sw, n, greatest, pfa):
    # measured: <= 3e-12 dB (Swerling 0), <= 1e-13 dB (Swerling 3) from the reference roots
    got = np.asarray(DETECTORS[greatest]["required"](PD, pfa, n, sw))
    for p, x in zip(PD, got):
        assert abs(_distance_db(x, p, pfa, n, greatest, sw)) < 1e-10, (p, x)


@pytest.mark.slow
@pytest.mark.parametrize("sw,n,greatest,pfa", [(0, 8, True, 1e-6), (0, 64, False, 1e-6), (0, 32, True, 1e-12),
                                               (0, 8, False, 1e-3), (3, 16, True, 1e-2), (3, 32, False, 1e-9)])
def test_required_snr_matches_mpmath_roots_slow(sw, n, greatest, pfa):
    got = np.asarray(DETECTORS[greatest]["required"](PD, pfa, n, sw))
    for p, x in zip(PD, got):
        assert abs(_distance_db(x, p, pfa, n, greatest, sw)) < 1e-10, (p, x)


def _loss_reference(pd, pfa, n, greatest, sw, required):
    if sw in (1, 2):
        cfar = _mp_required_snr_swerling1(pd, pfa, n, greatest)
    else:
        cfar = required - _distance_db(required, pd, pfa, n, greatest, sw)
    return cfar - ref.known_noise_db(pd, pfa, sw)


_SLOW = pytest.mark.slow


@pytest.mark.parametrize("sw,n,greatest,pfa", [
    (1, 8, True, 1e-12), (1, 64, False, 1e-2), (0, 16, False, 1e-6), (0, 32, True, 1e-3),
    pytest.param(3, 8, True, 1e-9, marks=_SLOW), pytest.param(3, 64, False, 1e-4, marks=_SLOW),
    pytest.param(0, 64, True, 1e-12, marks=_SLOW), pytest.param(0, 8, False, 1e-2, marks=_SLOW),
])
def test_loss_matches_references(sw, n, greatest, pfa):
    # measured: <= 1e-12 dB (Swerling 1), <= 3e-12 dB (Swerling 0)
    det = DETECTORS[greatest]
    got = np.asarray(det["loss"](PD, pfa, n, sw))
    required = np.asarray(det["required"](PD, pfa, n, sw))
    for p, g, r in zip(PD, got, required):
        assert abs(g - _loss_reference(p, pfa, n, greatest, sw, r)) < 1e-9


@pytest.mark.slow
def test_loss_ordering_ca_go_so():
    # Homogeneous noise: CA-CFAR (the sum of all n cells, sufficient for the exponential scale)
    # loses least, GO-CFAR a little more (Hansen & Sawyers 1980: some tenths of a dB), SO-CFAR
    # the most (Weiss 1982), the more so the fewer the cells. Measured below: GO - CA
    # 0.05-0.55 dB, SO - GO 0.3-6 dB.
    for n, pfa, sw in [(8, 1e-6, 1), (16, 1e-4, 0), (32, 1e-8, 3), (64, 1e-6, 1)]:
        ca = np.asarray(cfar_loss_db(PD, pfa, n, 1, sw))
        go = np.asarray(go_cfar_loss_db(PD, pfa, n, sw))
        so = np.asarray(so_cfar_loss_db(PD, pfa, n, sw))
        assert np.all(ca < go) and np.all(go < so), (n, ca, go, so)
        assert np.all(go - ca < 0.6), (n, go - ca)


def test_loss_ordering_go_so():
    for n in CELLS:
        go = np.asarray(go_cfar_loss_db(PD, 1e-6, n, 1))
        so = np.asarray(so_cfar_loss_db(PD, 1e-6, n, 1))
        assert np.all(0 < go) and np.all(go < so)


# --------------------------------------------------------------------------------------
# Derivatives
# --------------------------------------------------------------------------------------


def test_multiplier_gradient_matches_implicit_derivative():
    # dT/dPfa = 1 / (dPfa/dT) with dPfa/dT the mpmath derivative of the closed-form sums
    for greatest in (True, False):
        grad = jax.grad(lambda p, n: DETECTORS[greatest]["multiplier"](p, n))
        for n in (8, 64):
            for pfa in (1e-2, 1e-10):
                t = _mp_multiplier(pfa, n, greatest)
                want = float(1 / mp.diff(lambda x: _mp_laplace(x, n, greatest), t))
                assert abs(float(grad(pfa, n)) / want - 1) < 1e-12


def test_required_snr_gradient_swerling1_matches_mpmath_differences():
    for greatest in (True, False):
        def want_req(pd, pfa):
            return 10 * mp.log10(_mp_multiplier(pfa, 16, greatest) / _mp_multiplier(pd, 16, greatest) - 1)

        pd0, pfa0, h = mp.mpf("0.9"), mp.mpf("1e-6"), mp.mpf("1e-12")
        d_pd = float((want_req(pd0 + h, pfa0) - want_req(pd0 - h, pfa0)) / (2 * h))
        d_pfa = float((want_req(pd0, pfa0 * (1 + h)) - want_req(pd0, pfa0 * (1 - h))) / (2 * h * pfa0))
        g = jax.grad(lambda a, b: DETECTORS[greatest]["required"](a, b, 16, 1), argnums=(0, 1))(0.9, 1e-6)
        np.testing.assert_allclose([float(x) for x in g], [d_pd, d_pfa], rtol=1e-11)


_PD_POINTS = [(-5.0, 1e-2), (13.0, 1e-6), (25.0, 1e-12)]
_REQ_POINTS = [(0.1, 1e-2), (0.5, 1e-6), (0.999, 1e-12)]


def _gradient_case(kind, sw):
    for greatest in (True, False):
        f = DETECTORS[greatest][kind]
        for n in (8, 64):
            if kind == "pd":
                fn, points, domain = (lambda a, p: f(a, p, n, sw)), _PD_POINTS, [(-100, 100, False), (1e-100, 1, True)]
            else:
                top = 0.5 if kind == "loss" else 1.0
                fn, points, domain = (lambda a, p: f(a, p, n, sw)), _REQ_POINTS, [(1e-12, 0.9999, False), (1e-100, top, True)]
            grad = jax.grad(fn, argnums=(0, 1))
            for args in points:
                check_grad_vs_fd(fn, grad, args, domain, rtol=1e-6)


@pytest.mark.parametrize("kind,sw", [("pd", 0), ("required", 3), ("loss", 1)])
def test_gradients_match_finite_differences(kind, sw):
    _gradient_case(kind, sw)


@pytest.mark.slow
@pytest.mark.parametrize("kind,sw", [("pd", 1), ("pd", 3), ("required", 0), ("loss", 0), ("loss", 3)])
def test_gradients_match_finite_differences_slow(kind, sw):
    _gradient_case(kind, sw)


# --------------------------------------------------------------------------------------
# Properties
# --------------------------------------------------------------------------------------

SETTINGS = settings(max_examples=15, deadline=None)


@SETTINGS
@given(s1=st.floats(-10.0, 30.0), ds=st.floats(0.05, 2.0), lp=st.floats(-12.0, -2.0), sw=st.sampled_from([0, 1, 3]),
       n=st.sampled_from(CELLS), greatest=st.booleans())
def test_pd_increases_with_snr_and_lies_between_pfa_and_one(s1, ds, lp, sw, n, greatest):
    pfa = 10.0**lp
    pd = np.asarray(DETECTORS[greatest]["pd"](s1 + ds * np.arange(5.0), pfa, n, sw))
    assert pd[0] >= pfa and pd[-1] <= 1.0
    step = np.diff(pd)
    # strictly increasing while the miss probability is resolved; within rounding near 1
    assert np.all(step[pd[:-1] < 1.0 - 1e-10] > 0.0) and np.all(step > -4e-15)


@SETTINGS
@given(lp=st.floats(-12.0, -2.0), sw=st.sampled_from([0, 1, 3]), greatest=st.booleans())
def test_required_snr_decreases_with_more_cells(lp, sw, greatest):
    pfa = 10.0**lp
    req = np.array([np.asarray(DETECTORS[greatest]["required"](PD, pfa, n, sw)) for n in (16, 32, 64)])
    assert np.all(req[0] > req[1]) and np.all(req[1] > req[2])


# --------------------------------------------------------------------------------------
# Domain
# --------------------------------------------------------------------------------------


def test_out_of_domain_raises():
    for det in (GO, SO):
        for bad in [lambda: det["multiplier"](1e-6, 23),  # odd
                    lambda: det["multiplier"](1e-6, 0),
                    lambda: det["multiplier"](1e-6, 24.5),
                    lambda: det["multiplier"](1e-101, 24),
                    lambda: det["pd"](10.0, 1e-6, 24, swerling=5),
                    lambda: det["pd"](101.0, 1e-6, 24),
                    lambda: det["required"](1e-7, 1e-6, 24),  # pd must exceed pfa
                    lambda: det["required"](0.99999, 1e-6, 24),
                    lambda: det["loss"](0.9, 0.6, 24),
                    lambda: det["pfa"](-1.0, 24),
                    lambda: jax.jit(lambda n: det["multiplier"](1e-6, n))(24)]:
            with pytest.raises(DomainError):
                bad()


def test_traced_out_of_domain_is_nan():
    f = jax.jit(lambda p: go_cfar_required_snr_db(p, 1e-6, 24, 1))
    assert math.isnan(float(f(1e-7)))
    assert math.isnan(float(jax.grad(lambda p: f(p))(1e-7)))


_CORNER_CELLS = (2, 8, 64)


def _corner_values(det, sw):
    out = []
    for n in _CORNER_CELLS:
        out.append(det["multiplier"](np.array([1e-100, 1e-12, 0.5, 0.999999]), n))
        out.append(det["pfa"](np.array([1e-300, 1e-3, 1e3, 1e300]), n))
        out.append(det["pd"](np.array([-100.0, 100.0, -100.0, 100.0, 0.0]), np.array([1e-100, 1e-100, 0.999999, 0.999999, 0.5]),
                             n, sw))
        for pfa in (1e-100, 0.5):
            pd = np.array([pfa * (1 + 1e-6), 0.6 if pfa == 0.5 else 1e-50, 0.9, 0.9999])
            out.append(det["required"](pd, pfa, n, sw))
            out.append(det["loss"](pd, pfa, n, sw))
    return out


@pytest.mark.parametrize("sw", [0, 1, 3])
def test_values_finite_at_domain_corners(sw):
    for det in (GO, SO):
        for value in _corner_values(det, sw):
            assert np.all(np.isfinite(np.asarray(value)))


@pytest.mark.slow
@pytest.mark.parametrize("sw", [0, 1, 3])
def test_gradients_finite_at_domain_corners(sw):
    for det in (GO, SO):
        for n in _CORNER_CELLS:
            pd_grad = jax.grad(lambda s, p: det["pd"](s, p, n, sw), argnums=(0, 1))
            for s, p in [(-100.0, 1e-100), (100.0, 1e-100), (-100.0, 0.999999), (100.0, 0.999999)]:
                assert np.all(np.isfinite([float(g) for g in pd_grad(s, p)])), (n, s, p)
            for kind, pfas in [("required", (1e-100, 0.5, 0.99)), ("loss", (1e-100, 0.5))]:
                grad = jax.grad(lambda a, p: det[kind](a, p, n, sw), argnums=(0, 1))
                for pfa in pfas:
                    for pd in (pfa * (1 + 1e-6), 0.9999):
                        assert np.all(np.isfinite([float(g) for g in grad(pd, pfa)])), (kind, n, pd, pfa)


def test_required_snr_two_cells_equals_order_statistic():
    # n = 2 through the required-SNR iteration as well (GO = OS k = 2, SO = OS k = 1)
    for sw in (0, 3):
        np.testing.assert_allclose(np.asarray(go_cfar_required_snr_db(PD, 1e-4, 2, sw)),
                                   np.asarray(os_cfar_required_snr_db(PD, 1e-4, 2, 2, sw)), atol=1e-10)
