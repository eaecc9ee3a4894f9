"""STC and quantisation losses (diffsense.detection.receiver_losses).

Independent references:
- mpmath at 30 digits of the closed forms: STC gain 10 n log10(R/R_ref) (Skolnik 2001; Barton
  2013 ch. 10), the soft minimum -n w ln(1 + exp(-x/w)), quantisation noise q^2/(12 sigma^2)
  with q = 2 V_fs / 2^b (Richards 2014 ch. 3).
- The textbook rule SQNR = 6.02 b + 1.76 dB of a full-scale sinusoid, i.e. 10 log10(1.5 * 4^b).
- mpmath quadrature, cell by cell, of the exact quantisation-error power of a Gaussian input
  (the mean of (x - q round(x/q))^2), which checks the stated validity of the q^2/12 model
  (Widrow & Kollar 2008).
"""

import math

import jax
import jax.numpy as jnp
import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.detection import receiver_losses as rl
from helpers.function_suite import function_suite

MPMATH_DPS = 30


def _mp_db10(x):
    return 10 * mpmath.log10(x)


# --------------------------------------------------------------------------------------
# STC
# --------------------------------------------------------------------------------------


def test_stc_gain_hard_law_matches_mpmath():
    r_ref = 12e3
    ranges = [1.0, 37.5, 500.0, 3e3, 11999.0, 12e3, 12001.0, 5e4, 1e9]
    for n in (0.0, 2.0, 3.0, 4.0, 4.5):
        got = np.asarray(rl.stc_gain_db(np.array(ranges), r_ref, n))
        ref = [float(n * _mp_db10(mpmath.mpf(r) / r_ref)) if r < r_ref else 0.0 for r in ranges]
        np.testing.assert_allclose(got, ref, rtol=1e-14, atol=1e-13)
        np.testing.assert_array_equal(np.asarray(rl.stc_loss_db(np.array(ranges), r_ref, n)), -got)


def test_stc_gain_smooth_knee_matches_mpmath_and_bound():
    r_ref = 10e3
    for w in (0.1, 1.0, 3.0):
        for r in (100.0, 5e3, 9.9e3, 10e3, 10.1e3, 2e4, 1e6):
            x = _mp_db10(mpmath.mpf(r) / r_ref)
            ref = -4 * w * mpmath.log(1 + mpmath.exp(-x / w))
            got = float(rl.stc_gain_db(r, r_ref, 4.0, w))
            assert abs(got - float(ref)) <= 1e-13 * max(1.0, abs(float(ref)))
    # the deviation from the hard law is at most n w ln 2, reached at the knee
    assert float(rl.stc_gain_db(r_ref, r_ref, 4.0, 2.0)) == pytest.approx(-8 * math.log(2), rel=1e-15)


@settings(max_examples=40, deadline=None)
@given(log_r=st.floats(-3.0, 3.0), n=st.floats(0.0, 6.0), w=st.floats(0.01, 5.0))
def test_stc_properties(log_r, n, w):
    r = 1e4 * 10.0**log_r
    hard = float(rl.stc_gain_db(r, 1e4, n))
    soft = float(rl.stc_gain_db(r, 1e4, n, w))
    assert hard <= 0.0 and soft <= 0.0
    assert -1e-12 <= hard - soft <= n * w * math.log(2) * (1 + 1e-12) + 1e-12
    # monotone non-decreasing in range (the attenuation lifts with range)
    assert float(rl.stc_gain_db(r * 1.01, 1e4, n, w)) >= soft - 1e-12
    assert float(rl.stc_gain_db(r * 1.01, 1e4, n)) >= hard - 1e-12


def test_stc_target_snr_constant_inside_reference_range_for_r4_law():
    ranges = np.array([100.0, 1e3, 5e3, 11999.0])
    np.testing.assert_allclose(np.asarray(rl.stc_target_snr_db(ranges, 12e3, 15.0)), 15.0, atol=1e-12)
    # R^3 law: the SNR still rises as 10 log10(R_ref / R) inside; R^-4 beyond
    for r in (100.0, 3e3, 2e4, 1e5):
        r_mp = mpmath.mpf(r)
        ref = 15 + (10 if r < 12e3 else 40) * mpmath.log10(12e3 / r_mp)
        assert float(rl.stc_target_snr_db(r, 12e3, 15.0, 3.0)) == pytest.approx(float(ref), abs=1e-12)


# --------------------------------------------------------------------------------------
# Quantisation
# --------------------------------------------------------------------------------------


def test_quantisation_noise_matches_mpmath():
    for b in (1.0, 4.0, 8.0, 12.0, 16.0, 10.5):
        for fs_db in (-10.0, 0.0, 20.0, 60.0, 95.3):
            v_over_sigma = mpmath.mpf(10) ** (mpmath.mpf(fs_db) / 20)
            q_over_sigma = 2 * v_over_sigma / mpmath.mpf(2) ** b
            ref = _mp_db10(q_over_sigma**2 / 12)
            assert float(rl.quantisation_noise_db(b, fs_db)) == pytest.approx(float(ref), abs=1e-13)
            assert float(rl.noise_rms_lsb(b, fs_db)) == pytest.approx(float(1 / q_over_sigma), rel=1e-14)


def test_sqnr_of_full_scale_sine_is_6_02_bits_plus_1_76():
    # full-scale sine power V_fs^2 / 2 against q^2/12: SQNR = 10 log10(1.5 * 4^b) whatever FS_dB
    for b in (8, 12, 14):
        for fs_db in (30.0, 70.0):
            sine_over_noise_db = fs_db - 10 * math.log10(2)
            sqnr = sine_over_noise_db - float(rl.quantisation_noise_db(b, fs_db))
            assert sqnr == pytest.approx(float(_mp_db10(mpmath.mpf("1.5") * 4**b)), abs=1e-12)
            assert sqnr == pytest.approx(6.02 * b + 1.76, abs=0.003 * b + 0.01)


def test_quantisation_loss_matches_mpmath_and_is_consistent():
    for s in (1e-3, 0.1, 0.5, 1.0, 2.0, 37.0, 1e4):
        ref = _mp_db10(1 + 1 / (12 * mpmath.mpf(s) ** 2))
        assert float(rl.quantisation_loss_db(s)) == pytest.approx(float(ref), rel=1e-14)
    b, fs = 12.0, 55.0
    noise_db = float(rl.quantisation_noise_db(b, fs))
    loss = float(rl.quantisation_loss_db(rl.noise_rms_lsb(b, fs)))
    assert loss == pytest.approx(float(_mp_db10(1 + mpmath.mpf(10) ** (mpmath.mpf(noise_db) / 10))), rel=1e-13)


def _mp_gaussian_quantisation_error_power(sigma_lsb):
    """E[(x - round(x))^2] for x ~ N(0, sigma^2), q = 1: quadrature over each quantisation cell."""
    s = mpmath.mpf(sigma_lsb)
    cells = int(14 * s) + 2
    total = mpmath.mpf(0)
    for k in range(-cells, cells + 1):
        total += mpmath.quad(lambda x: (x - k) ** 2 * mpmath.npdf(x, 0, s), [k - mpmath.mpf(1) / 2, k + mpmath.mpf(1) / 2])
    return total


@pytest.mark.parametrize("sigma_lsb,relative_error", [(0.5, -0.0087443), (0.75, -1.8314e-5), (1.0, -3.2528e-9)])
def test_uniform_model_validity_stated_in_docstring(sigma_lsb, relative_error):
    exact = _mp_gaussian_quantisation_error_power(sigma_lsb)
    measured = float(exact * 12 - 1)
    assert measured == pytest.approx(relative_error, rel=1e-4)
    if sigma_lsb == 0.5:  # the docstring's loss comparison at half a step: 1.2494 dB model, 1.2399 dB exact
        assert float(rl.quantisation_loss_db(0.5)) == pytest.approx(1.2494, abs=5e-5)
        assert float(_mp_db10(1 + exact / mpmath.mpf(sigma_lsb) ** 2)) == pytest.approx(1.2399, abs=5e-5)


def test_clipping_statement_in_docstring():
    # V_fs = 10^(15/20) sigma: the clipped part of the noise power, 2 E[(|x| - V)^2; |x| > V]
    v = mpmath.mpf(10) ** (mpmath.mpf(15) / 20)
    clipped = 2 * mpmath.quad(lambda x: (x - v) ** 2 * mpmath.npdf(x), [v, mpmath.inf])
    assert float(clipped) == pytest.approx(1.0e-9, rel=0.05)


# --------------------------------------------------------------------------------------
# Edges, transformations, gradients, domain
# --------------------------------------------------------------------------------------


def test_no_nan_or_inf_at_edges():
    vals_grads = [
        (lambda r: rl.stc_gain_db(r, 1e4, 4.0), [1e-300, 1e-3, 1e4, 1e300]),
        (lambda r: rl.stc_gain_db(r, 1e4, 4.0, 0.5), [1e-300, 1e-3, 1e4, 1e300]),
        (lambda s: rl.quantisation_loss_db(s), [1e-300, 1e-100, 1.0, 1e100, 1e300]),
        (lambda b: rl.quantisation_noise_db(b, 40.0), [1.0, 64.0]),
        (lambda b: rl.noise_rms_lsb(b, 40.0), [1.0, 64.0]),
    ]
    for fn, xs in vals_grads:
        for x in xs:
            assert math.isfinite(float(fn(x))), (fn, x)
            assert math.isfinite(float(jax.grad(fn)(x))), (fn, x)
    # the derivative of the hard STC law at the reference range is taken from above
    assert float(jax.grad(lambda r: rl.stc_gain_db(r, 1e4, 4.0))(1e4)) == 0.0


def test_jit_returns_nan_where_eager_raises():
    f = jax.jit(rl.stc_gain_db)
    assert math.isnan(float(f(-1.0, 1e4, 4.0, 0.0)))
    assert math.isnan(float(jax.jit(rl.quantisation_loss_db)(0.0)))
    g = jax.grad(lambda s: rl.quantisation_loss_db(s))
    assert math.isnan(float(jax.jit(g)(-1.0)))
    with pytest.raises(DomainError):
        rl.quantisation_loss_db(0.0)


SPECS = [
    ("stc_gain_hard", lambda r, rr, n: rl.stc_gain_db(r, rr, n), [(1.0, 1e6, 1), (1e2, 1e5, 1), (0.0, 6.0, 0)],
     [(0, 0.0), (1, -1.0), (2, -1.0)], False),
    ("stc_gain_smooth", rl.stc_gain_db, [(1.0, 1e6, 1), (1e2, 1e5, 1), (0.0, 6.0, 0), (0.05, 5.0, 1)],
     [(3, -0.5), (0, -1.0)], True),
    ("stc_loss_smooth", rl.stc_loss_db, [(1.0, 1e6, 1), (1e2, 1e5, 1), (0.0, 6.0, 0), (0.05, 5.0, 1)],
     [(1, 0.0)], True),
    ("stc_target_snr", rl.stc_target_snr_db, [(1.0, 1e6, 1), (1e2, 1e5, 1), (-20.0, 40.0, 0), (0.0, 6.0, 0),
                                              (0.05, 5.0, 1)], [(2, float("nan"))], True),
    ("quantisation_noise", rl.quantisation_noise_db, [(1.0, 24.0, 0), (-20.0, 120.0, 0)], [(0, 0.5)], True),
    ("noise_rms_lsb", rl.noise_rms_lsb, [(1.0, 24.0, 0), (-20.0, 120.0, 0)], [(0, 0.0), (1, float("inf"))], True),
    ("quantisation_loss", rl.quantisation_loss_db, [(1e-3, 1e3, 1)], [(0, 0.0), (0, -2.0)], True),
]

globals().update(function_suite(SPECS, jit_rel=1e-13, jit_atol=1e-13, vmap_rtol=1e-13, value_floor=1.0))


def test_broadcasting():
    out = rl.stc_gain_db(jnp.array([[1e3], [2e3]]), jnp.array([5e3, 1e4, 2e4]))
    assert out.shape == (2, 3)
    np.testing.assert_allclose(np.asarray(out)[1, 1], 40 * math.log10(0.2), rtol=1e-14)
