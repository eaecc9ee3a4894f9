"""Property tests (hypothesis) over the documented domain: SNR -50...80 dB, Pfa 1e-300...0.5,
N 1...1e4, every Swerling case."""

import jax
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from diffsense import detection as det

SWERLING = st.sampled_from([0, 1, 2, 3, 4])
SNR_DB = st.floats(-50.0, 80.0)
LOG_PFA = st.floats(-300.0, np.log10(0.5))
N = st.floats(1.0, 1e4)
SETTINGS = settings(max_examples=25, deadline=None)

# one compiled program per Swerling case (static), reused by every hypothesis example: eager
# calls would compile the series and root-finding loops again for each example
_PD = {sw: jax.jit(lambda s, f, n, sw=sw: det.pd(s, f, n, sw)) for sw in range(5)}
_PD_GRAD = {sw: jax.jit(jax.grad(lambda s, f, n, sw=sw: det.pd(s, f, n, sw), argnums=(0, 1, 2))) for sw in range(5)}
_RSNR = {sw: jax.jit(lambda p, f, n, sw=sw: det.required_snr_db(p, f, n, sw)) for sw in range(5)}
_RSNR_GRAD = {sw: jax.jit(jax.grad(lambda p, f, n, sw=sw: det.required_snr_db(p, f, n, sw), argnums=(0, 1, 2)))
              for sw in range(5)}
_THRESHOLD = jax.jit(det.threshold)
_THRESHOLD_GRAD = jax.jit(jax.grad(det.threshold, argnums=(0, 1)))
_PFA_FROM_THRESHOLD = jax.jit(det.pfa_from_threshold)


@SETTINGS
@given(sw=SWERLING, snr=SNR_DB, lp=LOG_PFA, n=N)
def test_pd_is_a_probability_at_least_pfa_and_gradients_finite(sw, snr, lp, n):
    pfa = 10.0**lp
    p = float(_PD[sw](snr, pfa, n))
    assert 0.0 <= p <= 1.0
    assert p >= pfa * (1 - 1e-10)
    g = _PD_GRAD[sw](snr, pfa, n)
    assert all(np.isfinite(float(x)) for x in g)


@SETTINGS
@given(sw=SWERLING, snr=st.floats(-50.0, 79.0), lp=LOG_PFA, n=N, d=st.floats(0.01, 1.0))
def test_pd_monotone_in_snr_pfa_and_n(sw, snr, lp, n, d):
    pfa = 10.0**lp
    p = float(_PD[sw](snr, pfa, n))
    # Monotone up to the error of each evaluation, and the two compared may err in opposite
    # directions. One evaluation errs by (a) the round-off of the summed series, up to 3.9e-13
    # (measured worst |dPd| against mpmath over the reference grid), plus (b) the threshold's:
    # Pd = Pfa + (1 - Q(N, T)) - miss carries gammaincc's relative error in Q times Pfa, below
    # 3e-13 for N <= 3000 and 2e-11 up to N = 1e4 (measured against mpmath,
    # diffsense/detection/threshold.py). Near Pd = 1 with N = 4110, Pfa = 0.32 that is 1.8e-12.
    q_rel = 3e-13 if n + d <= 3000 else 2e-11
    tol = 2.0 * (3.9e-13 + q_rel * min(pfa * (1 + d), 0.5))
    assert float(_PD[sw](snr + d, pfa, n)) >= p - tol
    assert float(_PD[sw](snr, min(pfa * (1 + d), 0.5), n)) >= p - tol
    assert float(_PD[sw](snr, pfa, min(n + d, 1e4))) >= p - tol


@SETTINGS
@given(sw=SWERLING, pd_t=st.floats(0.05, 0.999), lp=st.floats(-15.0, -1.5), n=st.floats(1.0, 300.0))
def test_required_snr_round_trip(sw, pd_t, lp, n):
    pfa = 10.0**lp
    x = _RSNR[sw](pd_t, pfa, n)
    assert np.isfinite(float(x))
    assert float(_PD[sw](x, pfa, n)) == __import__("pytest").approx(pd_t, abs=1e-11)
    g = _RSNR_GRAD[sw](pd_t, pfa, n)
    assert all(np.isfinite(float(v)) for v in g)


@SETTINGS
@given(lp=st.floats(-300.0, np.log10(0.5)), n=N)
def test_threshold_round_trip_and_gradient_finite(lp, n):
    pfa = 10.0**lp
    t = _THRESHOLD(pfa, n)
    back = float(_PFA_FROM_THRESHOLD(t, n))
    assert back == __import__("pytest").approx(pfa, rel=5e-11)
    g = _THRESHOLD_GRAD(pfa, n)
    assert all(np.isfinite(float(v)) for v in g)


def test_out_of_domain_arguments_raise_clear_errors():
    import pytest

    from diffsense.errors import DomainError

    with pytest.raises(DomainError, match="pfa"):
        det.pd(10.0, 0.7, 1, 0)
    # every finite SNR is in the domain of pd (Pd -> Pfa, Pd -> 1); NaN and inf are not
    with pytest.raises(DomainError, match="snr_db"):
        det.pd(float("nan"), 1e-6, 1, 0)
    with pytest.raises(DomainError, match="snr_db"):
        det.pd(float("inf"), 1e-6, 1, 0)
    with pytest.raises(DomainError, match="'n'"):
        det.pd(10.0, 1e-6, 0.5, 0)
    with pytest.raises(ValueError, match="swerling"):
        det.pd(10.0, 1e-6, 1, 7)
    with pytest.raises(DomainError, match="pd must exceed pfa"):
        det.required_snr_db(0.1, 0.3, 1, 0)
    with pytest.raises(DomainError, match="pfa"):
        det.required_snr_db(0.9, 1e-12, 1, 0, method="albersheim")


def test_jit_and_vmap():
    f = jax.jit(det.pd, static_argnums=3)
    snr = np.linspace(0.0, 20.0, 7)
    a = np.asarray(f(snr, 1e-6, 10.0, 1))
    b = np.asarray(jax.vmap(lambda s: det.pd(s, 1e-6, 10.0, 1))(snr))
    c = np.array([float(det.pd(s, 1e-6, 10.0, 1)) for s in snr])
    # jit fuses differently from eager execution: agreement is at round-off level
    assert np.max(np.abs(a - c)) < 1e-13 and np.max(np.abs(b - c)) < 1e-13
