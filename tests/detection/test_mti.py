"""MTI canceller: blind speeds, velocity response and losses (diffsense.detection.mti).

Independent references:
- Blind speeds v_k = k lambda PRF / 2 (Brooker eq. 14.3) in exact arithmetic.
- The canceller's weights by repeated convolution of [1, -1] (numpy); its response as the direct
  filter sum |sum_i w_i exp(-j 2 pi f_d i / PRF)|^2 (numpy complex), the noise gain as sum w_i^2,
  and the speed average of the normalised response by mpmath quadrature of the filter sum.
- The output noise correlation matrix built from the weights (numpy), giving n_e = M^2 / sum R^2.
- Swerling 2 detectability factor in closed form D(k) = T(Pfa, k) / T(Pd, k) - 1, with T the
  inverse regularized incomplete gamma function solved in mpmath (30 digits).
- The single-channel detector from its definition: M real samples, noncentral chi-square with M
  degrees of freedom and noncentrality S M (steady target, phase rotating over the dwell), against
  the I/Q detector (2M degrees of freedom, noncentrality 2 S M), both summed as Poisson mixtures
  of gamma laws in mpmath; Swerling 1 with two real samples against the closed forms
  Pd = Pfa^(1/(1+S)) (one I/Q pulse) and the Swerling 1 N = 2 formula of DiFranco & Rubin.
- The exact Swerling 2 law of the correlated canceller output (weighted sum of exponentials with
  the eigenvalues of the correlation matrix, mpmath), which measures the moment-matching model's
  error stated in the module docstring.
"""

import math
from fractions import Fraction

import jax
import jax.numpy as jnp
import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import gammainccinv

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.detection import mti
from helpers.function_suite import function_suite

MPMATH_DPS = 30


def _weights(order):
    w = np.array([1.0])
    for _ in range(order):
        w = np.convolve(w, [1.0, -1.0])
    return w


# --------------------------------------------------------------------------------------
# Blind speeds, weights, velocity response
# --------------------------------------------------------------------------------------


def test_blind_speeds_exact():
    lam, prf = 0.0299792458, 1250.0
    got = np.asarray(mti.blind_speeds_mps(lam, prf, 5))
    ref = [float(Fraction(k) * Fraction(lam) * Fraction(prf) / 2) for k in range(1, 6)]
    np.testing.assert_allclose(got, ref, rtol=2e-16)
    assert float(mti.first_blind_speed_mps(lam, prf)) == ref[0]
    assert mti.blind_speeds_mps(np.array([0.03, 0.1]), 1e3, 3).shape == (2, 3)
    g = jax.grad(lambda p: mti.blind_speeds_mps(0.03, p, 4)[3])(1e3)
    assert float(g) == pytest.approx(4 * 0.03 / 2, rel=1e-15)


def test_weights_and_noise_gain():
    for order in range(1, 9):
        w = _weights(order)
        np.testing.assert_array_equal(mti.mti_canceller_weights(order), w)
        assert mti.mti_noise_gain(order) == float(np.sum(w**2))


def _direct_response(v, lam, prf, order):
    w = _weights(order)
    fd = 2 * v / lam
    h = np.sum(w * np.exp(-2j * np.pi * fd * np.arange(order + 1) / prf))
    return abs(h) ** 2 / np.sum(w**2)


@pytest.mark.parametrize("order", [1, 2, 3, 5])
def test_velocity_response_matches_direct_filter_sum(order):
    lam, prf = 0.057, 880.0
    speeds = np.concatenate([np.linspace(-80, 80, 41), [0.0, 1e-3, 313.7, -4567.89]])
    got = np.asarray(mti.mti_velocity_response(speeds, lam, prf, order))
    ref = np.array([_direct_response(v, lam, prf, order) for v in speeds])
    peak = 4.0**order / math.comb(2 * order, order)
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-14 * peak)


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_velocity_response_average_is_one(order):
    # mpmath quadrature of the filter sum over one Doppler period: the noise gain sum w^2
    w = [mpmath.mpf(x) for x in _weights(order)]
    power = lambda th: abs(sum(wi * mpmath.expj(-th * i) for i, wi in enumerate(w))) ** 2
    avg = mpmath.quad(power, [0, mpmath.pi, 2 * mpmath.pi]) / (2 * mpmath.pi) / sum(x**2 for x in w)
    assert abs(avg - 1) < 1e-25
    # the implementation averaged over a uniform grid of one blind-speed interval (exact for a
    # trigonometric polynomial of degree 2n < number of points)
    v1 = float(mti.first_blind_speed_mps(0.1, 500.0))
    grid = v1 * np.arange(64) / 64
    assert float(jnp.mean(mti.mti_velocity_response(grid, 0.1, 500.0, order))) == pytest.approx(1.0, abs=1e-14)


def test_velocity_response_peak_zeros_and_edges():
    lam, prf = 0.03, 1000.0
    v1 = float(mti.first_blind_speed_mps(lam, prf))
    for order in (1, 2, 3):
        peak = 4.0**order / math.comb(2 * order, order)
        for k in (0.5, 1.5, -2.5):
            assert float(mti.mti_velocity_response(k * v1, lam, prf, order)) == pytest.approx(peak, rel=1e-14)
        for k in (0, 1, 7, -3):
            assert float(mti.mti_velocity_response(k * v1, lam, prf, order)) < 1e-25
    # single canceller 3.01 dB, double 4.26 dB at the peak (Skolnik ch. 3 / Richards ch. 5)
    assert 10 * math.log10(float(mti.mti_velocity_response(0.5 * v1, lam, prf, 1))) == pytest.approx(3.0103, abs=1e-4)
    assert 10 * math.log10(float(mti.mti_velocity_response(0.5 * v1, lam, prf, 2))) == pytest.approx(4.2597, abs=1e-4)
    g = jax.grad(lambda v: mti.mti_velocity_response(v, lam, prf, 2))
    for v in (0.0, v1, 1e6, -1e6):
        assert math.isfinite(float(g(v)))
    assert float(g(0.0)) == 0.0


# --------------------------------------------------------------------------------------
# Equivalent independent samples
# --------------------------------------------------------------------------------------


def _ne_from_matrix(n_pulses, order):
    w = _weights(order)
    m = n_pulses - order
    mat = np.zeros((m, n_pulses))
    for j in range(m):
        mat[j, j:j + order + 1] = w
    cov = mat @ mat.T
    corr = cov / cov[0, 0]
    return m * m / np.sum(corr**2)


def test_independent_samples_match_correlation_matrix():
    for order in (1, 2, 3, 4):
        ns = np.arange(order + 1, order + 40, dtype=float)
        got = np.asarray(mti.mti_independent_samples(ns, order))
        ref = [_ne_from_matrix(int(n), order) for n in ns]
        np.testing.assert_allclose(got, ref, rtol=1e-14)
    # rho_1 = -1/2 for the single canceller: n_e = M^2 / (M + (M - 1)/2)
    assert float(mti.mti_independent_samples(31.0, 1)) == pytest.approx(900 / (30 + 29 / 2), rel=1e-15)


@settings(max_examples=40, deadline=None)
@given(n=st.floats(1.0, 500.0), order=st.integers(1, 4))
def test_independent_samples_bounds(n, order):
    big_n = n + order
    ne = float(mti.mti_independent_samples(big_n, order))
    assert 1.0 - 1e-12 <= ne <= big_n - order + 1e-12


# --------------------------------------------------------------------------------------
# Losses: references
# --------------------------------------------------------------------------------------


def _mp_threshold(p, k):
    """T with Q(k, T) = p (regularized upper incomplete gamma), by mpmath root finding from
    scipy's estimate (on the logarithm of the smaller tail)."""
    k, p = mpmath.mpf(k), mpmath.mpf(p)
    if p < 0.5:
        f = lambda t: mpmath.log(mpmath.gammainc(k, t, mpmath.inf, regularized=True)) - mpmath.log(p)
    else:
        f = lambda t: mpmath.log(mpmath.gammainc(k, 0, t, regularized=True)) - mpmath.log(1 - p)
    return mpmath.findroot(f, mpmath.mpf(gammainccinv(float(k), float(p))))


def _mp_sw2_snr_db(pd, pfa, k):
    return 10 * mpmath.log10(_mp_threshold(pfa, k) / _mp_threshold(pd, k) - 1)


def _mp_ne(n_pulses, order):
    m = Fraction(n_pulses - order)
    den = m
    c0 = math.comb(2 * order, order)
    for k in range(1, order + 1):
        den += 2 * Fraction(math.comb(2 * order, order + k), c0) ** 2 * max(m - k, 0)
    ne = m * m / den
    return mpmath.mpf(ne.numerator) / ne.denominator


def test_integration_loss_swerling2_matches_mpmath():
    cases = [(order, n_pulses, pd, pfa) for order in (1, 2, 3) for n_pulses in sorted({order + 1, 5, 10, 100})
             for pd, pfa in ((0.5, 1e-4), (0.9, 1e-6), (0.99, 1e-8))]
    order_of = np.array([c[0] for c in cases])
    got = np.empty(len(cases))
    for order in (1, 2, 3):  # one vectorised call per (static) order
        sel = order_of == order
        n, pd, pfa = (np.array([c[k] for c in cases if c[0] == order], dtype=float) for k in (1, 2, 3))
        got[sel] = np.asarray(mti.mti_integration_loss_db(n, order, pd, pfa, swerling=2))
    for (order, n_pulses, pd, pfa), g in zip(cases, got):
        ref = _mp_sw2_snr_db(pd, pfa, _mp_ne(n_pulses, order)) - _mp_sw2_snr_db(pd, pfa, n_pulses)
        assert abs(g - float(ref)) < 1e-9, (order, n_pulses, pd, pfa, g, ref)


def test_blind_phase_loss_swerling2_matches_mpmath():
    cases = [(m, pd, pfa) for m in (2.0, 3.0, 10.0, 25.5, 200.0) for pd, pfa in ((0.5, 1e-4), (0.9, 1e-6), (0.99, 1e-10))]
    m, pd, pfa = (np.array([c[k] for c in cases]) for k in (0, 1, 2))
    got = np.asarray(mti.mti_blind_phase_loss_db(pd, pfa, m, swerling=2))
    for (mi, pdi, pfai), g in zip(cases, got):
        ref = _mp_sw2_snr_db(pdi, pfai, mpmath.mpf(mi) / 2) - _mp_sw2_snr_db(pdi, pfai, mi)
        assert abs(g - float(ref)) < 1e-9


def _mp_noncentral_gamma_sf(shape, mean_k, x):
    """P(Gamma(shape + K, 1) > x), K ~ Poisson(mean_k): the noncentral chi-square sf of 2x with
    2 shape degrees of freedom and noncentrality 2 mean_k."""
    total, k, weight_left = mpmath.mpf(0), 0, mpmath.mpf(1)
    while weight_left > mpmath.mpf(10) ** -25:
        pk = mpmath.exp(-mean_k) * mean_k**k / mpmath.factorial(k)
        total += pk * mpmath.gammainc(shape + k, x, mpmath.inf, regularized=True)
        weight_left -= pk
        k += 1
    return total


def _mp_required_snr_db(pd, pfa, dof, noncentrality_per_snr, start_db):
    """S (dB) at which P(chi^2_dof(S * c) > t) = pd, t from P(chi^2_dof > t) = pfa (in gamma units)."""
    x = _mp_threshold(pfa, mpmath.mpf(dof) / 2)
    f = lambda s_db: _mp_noncentral_gamma_sf(mpmath.mpf(dof) / 2, 10 ** (s_db / 10) * noncentrality_per_snr / 2, x) - pd
    return mpmath.findroot(f, start_db, tol=1e-25)


def test_blind_phase_loss_steady_target_from_the_single_channel_definition():
    # M real samples: chi^2_M with noncentrality S M; I/Q: chi^2_2M with noncentrality 2 S M
    pd, pfa, m = mpmath.mpf("0.9"), mpmath.mpf("1e-6"), 10
    got = float(mti.mti_blind_phase_loss_db(0.9, 1e-6, float(m), swerling=0))
    s_iq = _mp_required_snr_db(pd, pfa, 2 * m, 2 * m, 5.0)
    s_single = _mp_required_snr_db(pd, pfa, m, m, float(s_iq) + got)
    assert abs(got - float(s_single - s_iq)) < 1e-9


def test_blind_phase_loss_swerling1_two_samples_closed_forms():
    # two real samples of a Swerling 1 target = one I/Q pulse: Pd = Pfa^(1/(1+S));
    # the I/Q reference with two pulses: Pd = 1 - P(1, T) + (1 + 1/(2S)) P(1, T/(1 + 1/(2S))) e^(-T/(1+2S))
    # (DiFranco & Rubin; Mahafza), with Q(2, T) = (1 + T) e^-T = Pfa.
    pd, pfa = mpmath.mpf("0.9"), mpmath.mpf("1e-6")
    s_single = mpmath.log(pfa) / mpmath.log(pd) - 1
    t = mpmath.findroot(lambda t: (1 + t) * mpmath.exp(-t) - pfa, 16)

    def pd2(s):
        a = 1 + 1 / (2 * s)
        low = lambda x: mpmath.gammainc(1, 0, x, regularized=True)
        return 1 - low(t) + a * low(t / a) * mpmath.exp(-t / (1 + 2 * s))

    s_iq = mpmath.findroot(lambda s: pd2(s) - pd, 60)
    ref = 10 * mpmath.log10(s_single / s_iq)
    assert abs(float(mti.mti_blind_phase_loss_db(0.9, 1e-6, 2.0, swerling=1)) - float(ref)) < 1e-9


def test_integration_loss_steady_target_matches_mpmath_series():
    pd, pfa, n_pulses, order = mpmath.mpf("0.9"), mpmath.mpf("1e-6"), 10, 1
    got = float(mti.mti_integration_loss_db(float(n_pulses), order, 0.9, 1e-6, swerling=0))
    ne = _mp_ne(n_pulses, order)
    s_n = _mp_required_snr_db(pd, pfa, 2 * n_pulses, 2 * n_pulses, 5.0)
    s_ne = _mp_required_snr_db(pd, pfa, 2 * ne, 2 * ne, float(s_n) + got)
    assert abs(got - float(s_ne - s_n)) < 1e-9


# --------------------------------------------------------------------------------------
# The moment-matching model against the exact Swerling 2 law (module docstring)
# --------------------------------------------------------------------------------------


def _exact_sw2_mti_snr(n_pulses, order, pd, pfa):
    """Exact Swerling 2 requirement with the correlated outputs: sf(t) = sum_i c_i exp(-t/l_i)."""
    with mpmath.workdps(60):
        m = n_pulses - order
        c0 = math.comb(2 * order, order)
        corr = mpmath.matrix(m, m)
        for j in range(m):
            for k in range(m):
                lag = abs(j - k)
                if lag <= order:
                    corr[j, k] = mpmath.mpf((-1) ** lag * math.comb(2 * order, order + lag)) / c0
        lam = list(mpmath.eigsy(corr)[0])
        coef = [mpmath.fprod(li / (li - lj) for j, lj in enumerate(lam) if j != i) for i, li in enumerate(lam)]
        sf = lambda t: mpmath.fsum(c * mpmath.exp(-t / li) for c, li in zip(coef, lam))
        quantile = lambda p: mpmath.findroot(lambda t: mpmath.log(sf(t)) - mpmath.log(p), 3 * m + 20 if p < 0.5 else m / 2)
        return quantile(mpmath.mpf(pfa)) / quantile(mpmath.mpf(pd)) - 1


@pytest.mark.parametrize("order,n_pulses,model_minus_exact_db", [
    (1, 4, -0.111), (1, 10, -0.211), (2, 4, 0.464), (2, 10, -0.256), (3, 6, 0.196), (3, 10, -0.249),
    pytest.param(1, 30, -0.136, marks=pytest.mark.slow), pytest.param(2, 30, -0.181, marks=pytest.mark.slow),
    pytest.param(3, 20, -0.246, marks=pytest.mark.slow)])
def test_model_error_against_exact_swerling2_law(order, n_pulses, model_minus_exact_db):
    exact = _exact_sw2_mti_snr(n_pulses, order, "0.9", "1e-6")
    exact_loss = 10 * mpmath.log10(exact) - _mp_sw2_snr_db(mpmath.mpf("0.9"), mpmath.mpf("1e-6"), n_pulses)
    model = float(mti.mti_integration_loss_db(float(n_pulses), order, 0.9, 1e-6, swerling=2))
    assert model - float(exact_loss) == pytest.approx(model_minus_exact_db, abs=1e-3)
    assert abs(model - float(exact_loss)) <= (0.47 if n_pulses - order == 2 else 0.26)


# --------------------------------------------------------------------------------------
# Derivatives, properties, domain
# --------------------------------------------------------------------------------------


def test_loss_gradients_match_central_differences():
    f = jax.jit(lambda n, pd: mti.mti_integration_loss_db(n, 2, pd, 1e-6, swerling=2))
    g = jax.jit(jax.grad(lambda n, pd: mti.mti_integration_loss_db(n, 2, pd, 1e-6, swerling=2), argnums=(0, 1)))
    for n0, pd0 in ((7.0, 0.9), (23.4, 0.6)):
        gn, gp = (float(x) for x in g(n0, pd0))
        fd_n = (float(f(n0 + 1e-4, pd0)) - float(f(n0 - 1e-4, pd0))) / 2e-4
        fd_p = (float(f(n0, pd0 + 1e-6)) - float(f(n0, pd0 - 1e-6))) / 2e-6
        assert gn == pytest.approx(fd_n, rel=1e-6, abs=1e-9)
        assert gp == pytest.approx(fd_p, rel=1e-6, abs=1e-9)
    h = jax.jit(lambda m: mti.mti_blind_phase_loss_db(0.9, 1e-6, m, swerling=2))
    gm = float(jax.jit(jax.grad(lambda m: mti.mti_blind_phase_loss_db(0.9, 1e-6, m, swerling=2)))(12.5))
    assert gm == pytest.approx((float(h(12.5 + 1e-4)) - float(h(12.5 - 1e-4))) / 2e-4, rel=1e-6)


_blind_phase_sw2 = jax.jit(lambda m: mti.mti_blind_phase_loss_db(0.9, 1e-6, m, swerling=2))
_mti_loss_sw2 = jax.jit(lambda n: mti.mti_integration_loss_db(n, 1, 0.9, 1e-6, swerling=2))


@settings(max_examples=20, deadline=None)
@given(m=st.floats(2.0, 1e4))
def test_blind_phase_loss_bounds(m):
    # at least the many-sample limit 10 log10 sqrt(2); Swerling 2 at most its two-sample value
    loss = float(_blind_phase_sw2(m))
    assert 5 * math.log10(2) - 1e-9 <= loss <= 6.32


@settings(max_examples=20, deadline=None)
@given(n=st.floats(2.0, 1e4))
def test_integration_loss_positive_and_decreasing(n):
    loss = float(_mti_loss_sw2(n))
    assert loss > 0.0
    assert float(_mti_loss_sw2(min(n * 1.5, 1e4))) <= loss + 1e-9


SPECS = [
    ("first_blind_speed", mti.first_blind_speed_mps, [(1e-3, 10.0, 1), (10.0, 1e5, 1)], [(0, 0.0), (1, -1.0)], True),
    ("velocity_response_1", lambda v, lam, prf: mti.mti_velocity_response(v, lam, prf, 1),
     [(-190.0, 200.0, 0), (0.013, 1.0, 1), (110.0, 1e4, 1)], [(1, 0.0), (2, -5.0), (0, float("nan"))], True),
    ("velocity_response_3", lambda v, lam, prf: mti.mti_velocity_response(v, lam, prf, 3),
     [(-190.0, 200.0, 0), (0.013, 1.0, 1), (110.0, 1e4, 1)], [(0, float("inf"))], True),
    # smooth for N > 2n (kinks at the integers N <= 2n)
    ("independent_samples_2", lambda n: mti.mti_independent_samples(n, 2), [(4.01, 1e3, 1)], [(0, 2.5)], True),
]

globals().update(function_suite(SPECS, jit_rel=1e-13, jit_atol=1e-14, vmap_rtol=1e-13, value_floor=1.0))


def test_domain():
    with pytest.raises(DomainError):
        mti.mti_noise_gain(0)
    with pytest.raises(DomainError):
        mti.mti_velocity_response(10.0, 0.03, 1e3, 1.5)
    with pytest.raises(DomainError):
        mti.mti_integration_loss_db(2.0, 2, 0.9, 1e-6)  # needs N >= order + 1
    with pytest.raises(DomainError):
        mti.mti_blind_phase_loss_db(0.9, 1e-6, 10.0, swerling=4)
    with pytest.raises(DomainError):
        mti.mti_blind_phase_loss_db(0.9, 1e-6, 1.5)
    with pytest.raises(DomainError):
        mti.blind_speeds_mps(0.03, 1e3, 0)
    assert math.isnan(float(_blind_phase_sw2(1.0)))
    assert math.isnan(float(_mti_loss_sw2(1.5)))
