"""Doppler and range-rate accuracy (diffsense.physics.measurement_accuracy) against a Monte Carlo
of the maximum-likelihood estimator.

Independent reference: complex baseband echoes of N rectangular pulses (M samples each, width τ,
one every T_r) with a known Doppler frequency, unknown phase, in complex white Gaussian noise; the
frequency is estimated by maximising the dwell's periodogram |Σ y_k exp(-j 2π f t_k)|² (a grid,
then Newton's method on its derivative). Far above the estimator's threshold its rms error
reaches the Cramér–Rao bound; with 20000 trials the rms error is known to 0.5 % (1/sqrt(2K)).
The single-pulse SNR is the matched filter's: M A² / σ² (A the sample amplitude, σ² the complex
noise power per sample). The discrete samples inside a pulse have an rms spread (1 - 1/M²)^(1/2)
times the continuous τ/sqrt(12); with M = 32 that is 0.05 %.
"""

import math

import jax
import numpy as np
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.physics.measurement_accuracy import (
    doppler_accuracy_hz, echo_rms_duration_s, folded_range_rate_accuracy_mps, range_rate_accuracy_mps,
)

TRIALS = 20000


def _ml_rms_error_hz(n, m, tau, t_r, snr1_db, f_true, seed):
    rng = np.random.default_rng(seed)
    t = (np.arange(n)[:, None] * t_r + (np.arange(m)[None, :] + 0.5) * tau / m).ravel()
    amp = math.sqrt(10 ** (snr1_db / 10) / m)  # M A^2 / sigma^2 = SNR_1 with sigma^2 = 1
    phase = rng.uniform(0, 2 * math.pi, (TRIALS, 1))
    noise = (rng.standard_normal((TRIALS, t.size)) + 1j * rng.standard_normal((TRIALS, t.size))) / math.sqrt(2)
    y = amp * np.exp(1j * (2 * math.pi * f_true * t + phase)) + noise
    bound = float(doppler_accuracy_hz(snr1_db, float(n), 1.0 / t_r, tau))
    grid = f_true + np.linspace(-12 * bound, 12 * bound, 481)
    spectrum = np.abs(y @ np.exp(-2j * math.pi * np.outer(t, grid))) ** 2
    f = grid[np.argmax(spectrum, axis=1)]
    w = 2 * math.pi * t
    for _ in range(6):  # Newton on dP/df, P = |Y|^2
        e = np.exp(-1j * np.outer(f, w))
        y0 = np.sum(y * e, axis=1)
        y1 = np.sum(y * e * (-1j * w), axis=1)
        y2 = np.sum(y * e * (-(w ** 2)), axis=1)
        d1 = 2 * np.real(np.conj(y0) * y1)
        d2 = 2 * np.real(np.abs(y1) ** 2 + np.conj(y0) * y2)
        f = f - d1 / d2
    return float(np.sqrt(np.mean((f - f_true) ** 2))), bound


@pytest.mark.parametrize("n,tau,t_r,snr1_db", [
    (1, 1e-3, 1e-3, 25.0),     # one pulse: sigma_f = sqrt(3) / (pi tau sqrt(2 SNR))
    (8, 1e-4, 5e-4, 21.0),     # a train: the pulse centres' spread dominates
])
def test_bound_equals_the_monte_carlo_rms_error_of_the_ml_estimator(n, tau, t_r, snr1_db):
    rms, bound = _ml_rms_error_hz(n, 32, tau, t_r, snr1_db, f_true=37.0, seed=n)
    assert rms == pytest.approx(bound, rel=0.03)


def test_closed_forms_and_range_rate():
    # one pulse: t_rms = tau / sqrt(12); N pulses, tau -> 0: t_rms = T_r sqrt((N^2 - 1) / 12)
    assert float(echo_rms_duration_s(1.0, 1e3, 2e-6)) == pytest.approx(2e-6 / math.sqrt(12), rel=1e-14)
    assert float(echo_rms_duration_s(10.0, 1e3, 0.0)) == pytest.approx(1e-3 * math.sqrt(99 / 12), rel=1e-14)
    sigma_f = float(doppler_accuracy_hz(13.0, 10.0, 1e3, 1e-6))
    assert float(range_rate_accuracy_mps(13.0, 10.0, 1e3, 1e-6, 0.03)) == pytest.approx(0.015 * sigma_f, rel=1e-14)
    # finite gradients over the pulses' real relaxation from N = 1
    g = jax.grad(lambda nn: doppler_accuracy_hz(10.0, nn, 1e3, 1e-6))(1.0)
    assert math.isfinite(float(g)) and float(g) < 0


def test_folded_accuracy_joins_the_bound_and_the_prior_spread_finitely():
    lam, prf = 0.03, 2e3
    prior = lam * prf / (2 * math.sqrt(12))  # rms of a rate uniform over one blind-speed interval
    for snr_db in (20.0, 0.0, -20.0):
        crb = float(range_rate_accuracy_mps(snr_db, 16.0, prf, 1e-6, lam))
        folded = float(folded_range_rate_accuracy_mps(snr_db, 16.0, prf, 1e-6, lam))
        assert folded == pytest.approx((crb**-2 + prior**-2) ** -0.5, rel=1e-13)
        assert folded < min(crb, prior)
    # the echo lost in noise (any SNR, down to where 10^(SNR/10) underflows): the prior spread
    for snr_db in (-400.0, -1e5, -1e300):
        value, grads = jax.value_and_grad(folded_range_rate_accuracy_mps, argnums=(0, 1, 2, 3, 4))(
            snr_db, 16.0, prf, 1e-6, lam)
        assert float(value) == pytest.approx(prior, rel=1e-13)
        assert all(math.isfinite(float(g)) for g in grads)
