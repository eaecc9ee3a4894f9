"""Cell-averaging CFAR (diffsense.detection.cfar).

Independent references:
- mpmath regularized incomplete beta for Pfa = I_{1/(1+alpha)}(MN, N).
- Closed forms: N = 1 multiplier alpha = Pfa^(-1/M) - 1; Swerling 1, N = 1:
  Pd = (1 + alpha/(1+S))^(-M), required SNR S = alpha/(Pd^(-1/M) - 1) - 1, fixed-threshold
  S = ln Pfa / ln Pd - 1 (Gandhi & Kassam 1988; Richards, Fundamentals of Radar Signal
  Processing, sec. 7.4).
- mpmath mixture series for the other Swerling cases: with the target energy expressed as a
  count K (Poisson(NS) for Swerling 0, negative binomial with shape r = 1, N, 2, 2N and mean NS
  for Swerling 1-4), Y | K ~ Gamma(N + K, 1) and therefore
  Pd = sum_k P(K = k) I_{1/(1+alpha)}(MN, N + k), evaluated term by term in mpmath.
"""

import math

import jax
import jax.numpy as jnp
import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from jax.scipy.special import gammaincc

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.detection import cfar
from diffsense.detection.cfar import cfar_loss_db, cfar_multiplier, cfar_pd, cfar_pfa, cfar_required_snr_db

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)


def _mp_pfa(alpha, m, n):
    return mpmath.betainc(m * n, n, 0, 1 / (1 + mpmath.mpf(alpha)), regularized=True)


def _mp_cfar_pd_mixture(snr_db, pfa, m, n, swerling, alpha):
    """Pd = sum_k P(K=k) I_{1/(1+alpha)}(MN, N+k) (alpha from mpmath root of the Pfa equation)."""
    s = mpmath.mpf(10) ** (mpmath.mpf(snr_db) / 10)
    mu = n * s
    x = 1 / (1 + mpmath.mpf(alpha))
    r = {1: 1, 2: n, 3: 2, 4: 2 * n}.get(swerling)
    total, k, tail = mpmath.mpf(0), 0, mpmath.mpf(1)
    while tail > mpmath.mpf(10) ** -15:
        if swerling == 0:
            pk = mpmath.exp(-mu) * mu**k / mpmath.factorial(k)
        else:
            pk = mpmath.binomial(k + r - 1, k) * (r / (r + mu)) ** r * (mu / (r + mu)) ** k
        total += pk * mpmath.betainc(m * n, n + k, 0, x, regularized=True)
        tail -= pk
        k += 1
    return total


def _mp_alpha(pfa, m, n):
    """Root of log I_{1/(1+alpha)}(MN, N) = log pfa in log(alpha), started from the code's value."""
    start = mpmath.log(float(cfar_multiplier(float(pfa), float(m), float(n))))
    target = mpmath.log(mpmath.mpf(pfa))
    s = mpmath.findroot(lambda s: mpmath.log(_mp_pfa(mpmath.exp(s), m, n)) - target, start, tol=1e-40)
    return mpmath.exp(s)


# --------------------------------------------------------------------------------------
# Multiplier
# --------------------------------------------------------------------------------------


def test_multiplier_single_pulse_closed_form():
    m = np.array([1.0, 4.0, 16.0, 64.0])
    pfa = np.array([1e-2, 1e-6, 1e-8, 1e-12])
    got = np.asarray(cfar_multiplier(pfa, m, 1))
    ref = np.array([float(mpmath.mpf(p) ** (-1 / mpmath.mpf(mm)) - 1) for p, mm in zip(pfa, m)])
    np.testing.assert_allclose(got, ref, rtol=1e-14)


def test_multiplier_integrated_matches_mpmath_incomplete_beta():
    mm, nn, pp = np.meshgrid([1.0, 2.0, 8.0, 32.0], [2.0, 5.0, 30.0, 100.0], [1e-3, 1e-8, 1e-14], indexing="ij")
    alpha = np.asarray(jax.jit(cfar_multiplier)(pp.ravel(), mm.ravel(), nn.ravel()))
    worst = max(
        abs(float(_mp_pfa(a, int(m), int(n)) / p - 1)) for a, m, n, p in zip(alpha, mm.ravel(), nn.ravel(), pp.ravel())
    )
    assert worst < 2e-11  # betainc accuracy (measured 3e-12)


def test_multiplier_richards_example_value():
    # Richards (2014) sec. 7.4 form for the summed estimate: alpha = Pfa^(-1/M) - 1.
    # M = 16, Pfa = 1e-6: alpha = 10^(6/16) - 1 = 1.37137...
    assert abs(float(cfar_multiplier(1e-6, 16)) - (10 ** (6 / 16) - 1)) < 1e-14


def test_pfa_round_trip():
    alpha = cfar_multiplier(1e-7, 24.0, 10.0)
    assert abs(float(cfar_pfa(alpha, 24.0, 10.0)) / 1e-7 - 1) < 1e-11


def test_multiplier_gradient_matches_closed_form_and_fd():
    # d alpha / d pfa for N = 1: -(1/M) pfa^(-1/M - 1)
    g = float(jax.grad(lambda p: cfar_multiplier(p, 16.0, 1.0))(1e-6))
    assert abs(g / (-(1 / 16) * 1e-6 ** (-1 / 16 - 1)) - 1) < 1e-10
    # N = 10: implicit derivative versus central differences of mpmath roots
    f = lambda p: _mp_alpha(p, 16, 10)
    p0, h = mpmath.mpf("1e-6"), mpmath.mpf("1e-12")
    fd = float((f(p0 + h) - f(p0 - h)) / (2 * h))
    g10 = float(jax.grad(lambda p: cfar_multiplier(p, 16.0, 10.0))(1e-6))
    assert abs(g10 / fd - 1) < 1e-8
    # d alpha / d M (continuous relaxation), N = 1 closed form: alpha = exp(-ln pfa / M) - 1
    gm = float(jax.grad(lambda m: cfar_multiplier(1e-6, m, 1.0))(16.0))
    assert abs(gm / (math.log(1e-6) / 16**2 * 10 ** (6 / 16)) - 1) < 1e-9  # relative ~3e-11 measured
    gm10 = float(jax.grad(lambda m: cfar_multiplier(1e-6, m, 10.0))(16.0))
    fdm = float((_mp_alpha(1e-6, mpmath.mpf(16) + mpmath.mpf("1e-6"), 10) - _mp_alpha(1e-6, mpmath.mpf(16) - mpmath.mpf("1e-6"), 10)) / mpmath.mpf("2e-6"))
    assert abs(gm10 / fdm - 1) < 1e-6  # d/da of betainc by central differences (~1e-7)


# --------------------------------------------------------------------------------------
# Detection probability
# --------------------------------------------------------------------------------------


def test_pd_swerling1_single_pulse_closed_form():
    snr_db = np.array([0.0, 10.0, 13.0, 20.0, 30.0])
    for m in (4, 16, 64):
        alpha = 1e-6 ** (-1 / m) - 1
        ref = (1 + alpha / (1 + 10 ** (snr_db / 10))) ** (-m)
        got = np.asarray(cfar_pd(snr_db, 1e-6, m, 1, swerling=1))
        np.testing.assert_allclose(got, ref, rtol=1e-13)


def test_pd_swerling2_matches_mpmath_incomplete_beta():
    for m, n, sdb in [(8, 5, 3.0), (16, 10, 0.0), (32, 30, -3.0)]:
        alpha = _mp_alpha(1e-8, m, n)
        s = mpmath.mpf(10) ** (mpmath.mpf(sdb) / 10)
        ref = mpmath.betainc(m * n, n, 0, 1 / (1 + alpha / (1 + s)), regularized=True)
        assert abs(float(cfar_pd(sdb, 1e-8, m, n, swerling=2)) - float(ref)) < 1e-11


@pytest.mark.parametrize("m", [1, 2, 4, 16, 64])
@pytest.mark.parametrize("n", [1, 2, 5, 10, 30])
def test_quadrature_reproduces_swerling2_closed_form(m, n):
    # The tilted Gauss-Laguerre rule applied to the Swerling 2 fixed-threshold law
    # Q(N, T/(1+S)) must give the exact I_{1/(1+alpha/(1+S))}(MN, N); N = 1 is Swerling 1.
    snr = 10 ** (np.array([-5.0, 0.0, 5.0, 10.0, 15.0, 20.0, 30.0]) / 10)
    pfa = 1e-8
    mm, nn = jnp.full(snr.shape, float(m)), jnp.full(snr.shape, float(n))
    alpha = cfar_multiplier(jnp.full(snr.shape, pfa), mm, nn)
    sw2 = lambda s, t, k: gammaincc(k, t / (1 + s))
    quad = cfar._pd_quadrature(jnp.asarray(snr), alpha, mm, nn, sw2, 1 / (1 + jnp.asarray(snr)))
    exact = cfar._pd_swerling2(jnp.asarray(snr), alpha, mm, nn)
    assert float(jnp.max(jnp.abs(quad - exact))) < 1e-11


@pytest.mark.slow
@pytest.mark.parametrize("swerling,m,n,snr_db", [(0, 16, 1, 13.0), (0, 8, 10, 5.0), (1, 16, 4, 3.0), (3, 16, 4, 8.0), (4, 24, 4, 6.0)])
def test_pd_quadrature_matches_mpmath_mixture_series(swerling, m, n, snr_db):
    pytest.importorskip("diffsense.detection.core")
    pfa = 1e-6
    alpha = _mp_alpha(pfa, m, n)
    ref = _mp_cfar_pd_mixture(snr_db, pfa, m, n, swerling, alpha)
    got = float(cfar_pd(snr_db, pfa, m, n, swerling=swerling))
    assert abs(got - float(ref)) < 1e-9


def test_pd_jit_vmap_broadcast():
    f = jax.jit(lambda s: cfar_pd(s, 1e-6, 16.0, 1.0, swerling=1))
    s = jnp.array([[5.0, 10.0], [15.0, 20.0]])
    got = f(s)
    alpha = 10 ** (6 / 16) - 1
    np.testing.assert_allclose(np.asarray(got), (1 + alpha / (1 + 10 ** (np.asarray(s) / 10))) ** (-16), rtol=1e-13)
    v = jax.vmap(lambda m: cfar_pd(10.0, 1e-6, m, 3.0, swerling=2))(jnp.array([8.0, 16.0]))
    assert v.shape == (2,) and float(v[0]) < float(v[1])


@settings(max_examples=10, deadline=None)
@given(snr_db=st.floats(-10.0, 30.0), m=st.integers(2, 64), n=st.integers(1, 20))
def test_pd_gradient_finite_and_matches_central_difference(snr_db, m, n):
    f = lambda s: cfar_pd(s, 1e-6, float(m), float(n), swerling=2)
    g = float(jax.grad(f)(snr_db))
    h = 1e-4
    fd = (float(f(snr_db + h)) - float(f(snr_db - h))) / (2 * h)
    assert math.isfinite(g)
    assert abs(g - fd) <= 1e-6 * max(abs(fd), 1e-8) + 1e-12


# --------------------------------------------------------------------------------------
# Required SNR and CFAR loss
# --------------------------------------------------------------------------------------


def _sw1_required_db(pd, pfa, m):
    alpha = pfa ** (-1.0 / m) - 1
    return 10 * math.log10(alpha / (pd ** (-1.0 / m) - 1) - 1)


def test_required_snr_swerling1_single_pulse_closed_form():
    pd = np.array([0.5, 0.9, 0.99, 0.5, 0.9, 0.99])
    pfa = np.array([1e-4, 1e-4, 1e-4, 1e-8, 1e-8, 1e-8])
    for m in (4.0, 16.0, 64.0):
        got = np.asarray(cfar_required_snr_db(pd, pfa, m, 1, swerling=1))
        ref = [_sw1_required_db(a, b, m) for a, b in zip(pd, pfa)]
        np.testing.assert_allclose(got, ref, atol=1e-8)


def _sw1_required_mp_db(pd, pfa, m):
    """The Swerling 1, one-pulse closed form at 30 digits (``pd^(-1/M) - 1`` cancels in float64)."""
    with mpmath.workdps(30):
        pd, pfa = mpmath.mpf(pd), mpmath.mpf(pfa)
        alpha = pfa ** (-1 / mpmath.mpf(m)) - 1
        return float(10 * mpmath.log10(alpha / mpmath.expm1(-mpmath.log(pd) / m) - 1))


def test_required_snr_settles_on_its_root_to_1e_10_db():
    """Once the Newton residual is exactly zero the iterate stays (a bisection step from there used
    to wander off: 3.9e-9 dB at Pd 0.99, Pfa 1e-12, M 8); over Pd 0.5-0.999, Pfa 1e-3-1e-12, M 8-64."""
    pds = [0.5, 0.9, 0.99, 0.999]
    pfas = [1e-3, 1e-6, 1e-9, 1e-12]
    pd = np.repeat(pds, len(pfas))
    pfa = np.tile(pfas, len(pds))
    for m in (8, 16, 32, 64):
        got = np.asarray(cfar_required_snr_db(pd, pfa, float(m), 1, swerling=1))
        ref = [_sw1_required_mp_db(a, b, m) for a, b in zip(pd, pfa)]
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-10)


def test_required_snr_gradient_matches_closed_form_derivative():
    g = jax.grad(lambda pd, pfa, m: cfar_required_snr_db(pd, pfa, m, 1.0, swerling=1), argnums=(0, 1, 2))(0.9, 1e-6, 16.0)
    eps = 1e-7
    fd_pd = (_sw1_required_db(0.9 + eps, 1e-6, 16) - _sw1_required_db(0.9 - eps, 1e-6, 16)) / (2 * eps)
    fd_pfa = (_sw1_required_db(0.9, 1e-6 * (1 + eps), 16) - _sw1_required_db(0.9, 1e-6 * (1 - eps), 16)) / (2e-6 * eps)
    fd_m = (_sw1_required_db(0.9, 1e-6, 16 + 1e-5) - _sw1_required_db(0.9, 1e-6, 16 - 1e-5)) / 2e-5
    np.testing.assert_allclose([float(x) for x in g], [fd_pd, fd_pfa, fd_m], rtol=1e-6)


def test_cfar_loss_swerling1_single_pulse_closed_form_and_large_m_limit():
    import diffsense.detection as det

    if not hasattr(det, "required_snr_db"):
        pytest.skip("diffsense.detection.required_snr_db (fixed-threshold requirement) not available")

    for pd, pfa, m in [(0.9, 1e-6, 16), (0.5, 1e-8, 32), (0.99, 1e-4, 8)]:
        fixed = 10 * math.log10(math.log(pfa) / math.log(pd) - 1)
        ref = _sw1_required_db(pd, pfa, m) - fixed
        assert abs(float(cfar_loss_db(pd, pfa, m, 1, swerling=1)) - ref) < 1e-7
    # M -> infinity: the loss vanishes like 1/M
    big = float(cfar_loss_db(0.9, 1e-6, 1e5, 1, swerling=1))
    assert 0.0 < big < 1e-3


@settings(max_examples=5, deadline=None)
@given(m=st.integers(4, 64), pd=st.floats(0.3, 0.99))
def test_required_snr_gradient_finite(m, pd):
    g = jax.grad(lambda p: cfar_required_snr_db(p, 1e-6, float(m), 1.0, swerling=1))(pd)
    eps = 1e-6
    fd = (_sw1_required_db(pd + eps, 1e-6, m) - _sw1_required_db(pd - eps, 1e-6, m)) / (2 * eps)
    assert math.isfinite(float(g)) and abs(float(g) / fd - 1) < 1e-5


# --------------------------------------------------------------------------------------
# Domain
# --------------------------------------------------------------------------------------


def test_out_of_domain_raises():
    with pytest.raises(DomainError):
        cfar_multiplier(0.0, 16)
    with pytest.raises(DomainError):
        cfar_multiplier(1e-6, 0.5)
    with pytest.raises(DomainError):
        cfar_multiplier(1e-6, 16, 0.0)
    with pytest.raises(DomainError):
        cfar_pd(10.0, 1e-6, 16, 1, swerling=5)
    with pytest.raises(DomainError):
        cfar_pd(200.0, 1e-6, 16, 1)
    with pytest.raises(DomainError):
        cfar_required_snr_db(1e-7, 1e-6, 16, 1, swerling=1)  # pd must exceed pfa
    with pytest.raises(DomainError):
        cfar_loss_db(1.0, 1e-6, 16)
    with pytest.raises(DomainError):
        cfar_pfa(-1.0, 16)


# --------------------------------------------------------------------------------------
# One pulse, steady (Swerling 0) and chi-square-4 (Swerling 3/4) targets against mpmath
# --------------------------------------------------------------------------------------


def _mp_steady_single_miss(s, alpha, m):
    """1 - Pd of a steady target, one pulse: with K ~ Poisson(S) the echo is Gamma(1 + K, 1), so
    1 - Pd = sum_k P(K = k) I_x(1 + k, M), x = alpha/(1 + alpha) (the module docstring's mixture
    series); summed over K's mean +- 12 standard deviations, I_x stepped in its first argument by
    I_x(a + 1, b) = I_x(a, b) - x^a (1 - x)^b Gamma(a + b)/(Gamma(a + 1) Gamma(b))."""
    s, alpha, m = mpmath.mpf(s), mpmath.mpf(alpha), mpmath.mpf(m)
    x = alpha / (1 + alpha)
    lx, l1x = mpmath.log(x), -mpmath.log1p(alpha)
    w = 12 * mpmath.sqrt(s) + 20
    k0, k1 = max(0, int(mpmath.floor(s - w))), int(mpmath.ceil(s + w))
    ibeta = mpmath.betainc(1 + k0, m, 0, x, regularized=True)
    total = mpmath.mpf(0)
    for k in range(k0, k1 + 1):
        total += mpmath.exp(-s + k * mpmath.log(s) - mpmath.loggamma(k + 1)) * ibeta
        a = 1 + k
        ibeta -= mpmath.exp(a * lx + m * l1x + mpmath.loggamma(a + m) - mpmath.loggamma(a + 1) - mpmath.loggamma(m))
    return total


def _mp_chi4_single_pd(s, alpha, m):
    """Swerling 3/4, one pulse: (1 + c)^-M (1 + b0 alpha M/(1 + c)), c = alpha/(1 + S/2),
    b0 = (S/2)/(1 + S/2)^2 (moments of the Gamma(M, 1) reference sum)."""
    s, alpha, m = mpmath.mpf(s), mpmath.mpf(alpha), mpmath.mpf(m)
    half = 1 + s / 2
    c = alpha / half
    return (1 + c) ** (-m) * (1 + (s / 2) / half**2 * alpha * m / (1 + c))


def _single_pulse_errors_db(swerling, cells, pfas, pds):
    """(error (dB) of the required SNR by the root's residual in the mpmath Pd over its slope,
    points whose requirement is NaN) on the grid."""
    errors, nan = [], []
    for m in cells:
        for pfa in pfas:
            alpha = mpmath.mpf(pfa) ** (-1 / mpmath.mpf(m)) - 1
            for pd in pds:
                x = float(cfar_required_snr_db(pd, pfa, float(m), 1, swerling=swerling))
                if not math.isfinite(x):
                    nan.append((m, pfa, pd, alpha))
                    continue
                s = mpmath.mpf(10) ** (mpmath.mpf(x) / 10)
                ref_pd = (1 - _mp_steady_single_miss(s, alpha, m)) if swerling == 0 else _mp_chi4_single_pd(s, alpha, m)
                slope = float(jax.grad(lambda v: cfar_pd(v, pfa, float(m), 1.0, swerling=swerling))(x))
                errors.append(abs(float(ref_pd - pd) / slope))
    return np.array(errors), nan


@pytest.mark.parametrize("swerling", [0, 3])
def test_single_pulse_required_snr_matches_mpmath(swerling):
    """Swerling 0 (the Fubini rule up to 64 cells, Gauss-Laguerre above) and Swerling 3/4 (closed
    form) on M 8-1000, Pfa 1e-2-1e-12, Pd 0.1-0.999 (the first version missed by 2.6e-5 dB at
    M 8, Pfa 1e-12, and returned the bracket's middle, 55 dB, where the quadrature's Pd rounded
    above 1)."""
    errors, nan = _single_pulse_errors_db(swerling, (8, 64, 1000), (1e-2, 1e-6, 1e-12), (0.1, 0.5, 0.99, 0.999))
    assert not nan
    assert errors.max() < 1e-10


@pytest.mark.slow
@pytest.mark.parametrize("swerling", [0, 3])
def test_single_pulse_required_snr_matches_mpmath_on_the_whole_grid(swerling):
    """As above on M 3-1e4 (one and two cells at Pfa 1e-2: smaller Pfa puts their requirement
    above 60 dB, where the series has millions of terms) and Pd 0.1-0.999."""
    errors, nan = _single_pulse_errors_db(swerling, (3, 4, 16, 32, 100, 10000), (1e-3, 1e-9, 1e-12),
                                          (0.1, 0.9, 0.999))
    few, nan_few = _single_pulse_errors_db(swerling, (1, 2), (1e-2,), (0.1, 0.5, 0.9, 0.999))
    # measured: 1.04e-8 dB at M 4, Pfa 1e-12, Pd 0.1 (Fubini rule), 3.1e-10 dB at M 1e4, Pd 0.999
    # (Gauss-Laguerre); below 1e-10 dB elsewhere (the module docstring states these)
    assert errors.max() < 1.1e-8 and few.max() < 1e-10
    assert not nan and not nan_few


def test_cfar_pd_never_exceeds_one_and_loss_gradients_match_central_differences():
    """Pd at high SNR stays at most 1 (the quadrature's sum rounded a few ulp above it), and the
    Swerling 0 one-pulse loss (Fubini rule) has the derivatives of its central differences in
    pd, pfa and the (relaxed) cell count."""
    snr = jnp.linspace(20.0, 100.0, 33)
    for sw in (0, 3, 4):
        assert float(jnp.max(cfar_pd(snr, 1e-6, 64.0, 1.0, swerling=sw))) <= 1.0
    f = lambda pd, pfa, m: cfar_loss_db(pd, pfa, m, 1, swerling=0)  # noqa: E731
    for pd, pfa, m in [(0.9, 1e-6, 16.0), (0.99, 1e-12, 8.0), (0.5, 1e-3, 3.0)]:
        g = jax.grad(f, argnums=(0, 1, 2))(pd, pfa, m)
        e = 1e-6
        fd = [(f(pd + e * (1 - pd), pfa, m) - f(pd - e * (1 - pd), pfa, m)) / (2 * e * (1 - pd)),
              (f(pd, pfa * (1 + e), m) - f(pd, pfa * (1 - e), m)) / (2 * e * pfa),
              (f(pd, pfa, m + 1e-4) - f(pd, pfa, m - 1e-4)) / 2e-4]
        np.testing.assert_allclose([float(v) for v in g], [float(v) for v in fd], rtol=1e-6)


def test_requirement_beyond_the_bracket_is_nan_not_a_bracket_end():
    """One reference cell at Pfa 1e-12 and Pd 0.999 needs about 150 dB (Swerling 1 closed form
    S = alpha/(pd^-1 - 1) - 1 with alpha = 1e12 - 1): the bracket ends at 100 dB, so no root."""
    closed = 10 * math.log10((1e12 - 1) / (1 / 0.999 - 1) - 1)
    assert closed > 140.0
    for sw in (0, 1, 3):
        assert math.isnan(float(cfar_required_snr_db(0.999, 1e-12, 1.0, 1, swerling=sw)))


@pytest.mark.slow
@pytest.mark.parametrize("m,n,pfa,pd", [(8, 2, 1e-12, 0.99), (4, 4, 1e-6, 0.5), (16, 4, 1e-9, 0.9)])
def test_steady_target_several_pulses_required_snr_matches_mpmath(m, n, pfa, pd):
    """Swerling 0 with N > 1 pulses and M N >= 16 (the Gauss-Laguerre rule): within 1e-10 dB of
    the mixture series, by the root's residual over its slope."""
    x = float(cfar_required_snr_db(pd, pfa, float(m), float(n), swerling=0))
    ref = _mp_cfar_pd_mixture(x, pfa, m, n, 0, _mp_alpha(pfa, m, n))
    slope = float(jax.grad(lambda v: cfar_pd(v, pfa, float(m), float(n), swerling=0))(x))
    assert abs(float(ref - pd) / slope) < 1e-10
