"""Tracking loops: the α-β filter, split-gate range noise, the book's lag–noise trade, servo
angle-tracking bandwidth, and the Kalata tracking index.

Pure ``jnp`` functions, jit/vmap/grad-able. SI units; SNRs are passed in dB (``snr_db``) and
converted to power ratios inside. Gains α, β are dimensionless (β multiplies the innovation
divided by the sample time T).

Sources (book = Brooker, *Introduction to Sensors for Ranging and Imaging*):
- α-β filter: §13.4.1, eqs (13.2)–(13.5) (recursion), (13.10) (position transfer function),
  (13.11) (Benedict–Bordner gains), (13.12) (critically damped gains); §13.6 script ``ablag.m``
  (split-gate noise, variance reduction Σh², lag a T²(1 − α)/β, cost lag² + σ²).
- Variance reduction closed forms: Benedict, T. R. & Bordner, G. W. (1962), "Synthesis of an
  optimal set of radar track-while-scan smoothing equations", IRE Trans. Automatic Control
  AC-7(4), 27–32; Kalata, P. R. (1984), "The tracking index: a generalized parameter for α-β and
  α-β-γ target trackers", IEEE Trans. Aerospace and Electronic Systems AES-20(2), 174–182.
- Steady-state Kalman gains from the tracking index: Kalata (1984); Bar-Shalom, Li &
  Kirubarajan, *Estimation with Applications to Tracking and Navigation* (2001), §6.5
  (α-β filter for the discrete white-noise-acceleration model).
- Servo angle tracking: book §14.7, eqs (14.9)–(14.12) (after Barton 1976).
"""

from __future__ import annotations

import math
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
from jax import lax

from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import from_db10
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "benedict_bordner_beta",
    "critically_damped_alpha",
    "critically_damped_beta",
    "alpha_beta_filter",
    "alpha_beta_position_transfer",
    "alpha_beta_position_variance_ratio",
    "alpha_beta_velocity_variance_ratio_s2",
    "alpha_beta_acceleration_lag_m",
    "alpha_beta_tracking_cost_m2",
    "split_gate_range_noise_m",
    "benedict_bordner_tracking_cost_m2",
    "benedict_bordner_optimal_alpha",
    "servo_acceleration_error_constant_s2",
    "servo_dynamic_lag_rad",
    "servo_angle_noise_variance_rad2",
    "servo_angle_error_variance_rad2",
    "servo_optimal_bandwidth_hz",
    "MONOPULSE_SLOPE_TYPICAL",
    "kalata_tracking_index",
    "kalman_steady_state_alpha_beta",
]

#: Typical monopulse gain (error-slope) constant k_m, book §14.7 (below eq (14.12)).
MONOPULSE_SLOPE_TYPICAL = 1.6

def _check_stable(alpha, beta, where):
    """α in (0, 2), β in (0, 4 − 2α): the stability triangle of the α-β filter (Jury test on
    z² + (α + β − 2) z + (1 − α))."""
    check_range("alpha", alpha, 0.0, 2.0, lo_open=True, hi_open=True, where=where)
    check_range("beta", beta, 0.0, None, lo_open=True, where=where)
    if is_concrete(alpha) and is_concrete(beta):
        margin = 4.0 - 2.0 * np.asarray(alpha, dtype=float) - np.asarray(beta, dtype=float)
        check_range("4 - 2*alpha - beta", margin, 0.0, None, lo_open=True, where=where)


# ---------------------------------------------------------------------------------------------
# Gain relations
# ---------------------------------------------------------------------------------------------


def benedict_bordner_beta(alpha):
    """Benedict–Bordner velocity gain ``β = α² / (2 − α)``.

    Minimises the steady-state noise variance plus the transient to a ramp (Benedict & Bordner
    1962).

    Args:
        alpha: position gain α, in (0, 1].

    >>> float(benedict_bordner_beta(0.5)), 0.5**2 / (2 - 0.5)
    (0.166667, 0.166667)

    Source: book eq (13.11).
    """
    check_range("alpha", alpha, 0.0, 1.0, lo_open=True, where="benedict_bordner_beta")
    a = jnp.asarray(alpha)
    return a * a / (2.0 - a)


def critically_damped_alpha(beta):
    """Position gain of the critically damped α-β filter ``α = 2√β − β``.

    Both closed-loop poles coincide at z = 1 − √β (fastest non-oscillating step response).

    Args:
        beta: velocity gain β, in (0, 1]. The derivative is infinite at β = 0.

    Both poles at z = 1 − √β: the characteristic polynomial z² + (α + β − 2) z + (1 − α) is
    then (z − (1 − √β))², so with β = 0.25 its coefficients are those of (z − 0.5)²:

    >>> a = float(critically_damped_alpha(0.25))
    >>> a, a + 0.25 - 2.0, 1.0 - a
    (0.75, -1.0, 0.25)

    Source: book eq (13.12).
    """
    check_range("beta", beta, 0.0, 1.0, lo_open=True, where="critically_damped_alpha")
    b = jnp.asarray(beta)
    return 2.0 * jnp.sqrt(b) - b


def critically_damped_beta(alpha):
    """Inverse of :func:`critically_damped_alpha`: ``β = (1 − √(1 − α))²``.

    Args:
        alpha: position gain α, in (0, 1). The derivative is infinite at α = 1.

    Source: book eq (13.12) solved for β.
    """
    check_range("alpha", alpha, 0.0, 1.0, lo_open=True, hi_open=True, where="critically_damped_beta")
    a = jnp.asarray(alpha)
    # 1 - sqrt(1 - a) = a / (1 + sqrt(1 - a)) avoids cancellation for small alpha
    t = a / (1.0 + jnp.sqrt(1.0 - a))
    return t * t


# ---------------------------------------------------------------------------------------------
# The α-β filter itself and its transfer function
# ---------------------------------------------------------------------------------------------


def alpha_beta_filter(measurements_m, alpha, beta, sample_time_s, initial_position_m=0.0, initial_velocity_m_s=0.0):
    """Run the α-β tracker over a measurement sequence (last axis = time).

    Smoothing ``R̂_n = R̂_pn + α (R_n − R̂_pn)``, ``V̂_n = V̂_pn + (β/T)(R_n − R̂_pn)``;
    prediction ``R̂_p(n+1) = R̂_n + T V̂_n``, ``V̂_p(n+1) = V̂_n``. The first prediction is
    (``initial_position_m``, ``initial_velocity_m_s``).

    Args:
        measurements_m: measured positions R_n (m), shape (..., n).
        alpha: position gain α, in (0, 2); beta: velocity gain β, in (0, 4 − 2α) (stable).
        sample_time_s: sample interval T (s), in (0, ∞).
        initial_position_m, initial_velocity_m_s: initial prediction.

    Returns:
        ``(smoothed_position_m, smoothed_velocity_m_s)``, each shaped like ``measurements_m``.

    Source: book §13.4.1, eqs (13.2)–(13.5).
    """
    w = "alpha_beta_filter"
    _check_stable(alpha, beta, w)
    check_range("sample_time_s", sample_time_s, 0.0, None, lo_open=True, where=w)
    m = jnp.moveaxis(jnp.asarray(measurements_m, dtype=float), -1, 0)
    alpha = jnp.asarray(alpha, dtype=float)
    beta = jnp.asarray(beta, dtype=float)
    t = jnp.asarray(sample_time_s, dtype=float)
    xp0 = jnp.broadcast_to(jnp.asarray(initial_position_m, dtype=float), m.shape[1:])
    vp0 = jnp.broadcast_to(jnp.asarray(initial_velocity_m_s, dtype=float), m.shape[1:])

    def step(carry, z):
        xp, vp = carry
        r = z - xp
        x = xp + alpha * r
        v = vp + beta / t * r
        return (x + t * v, v), (x, v)

    _, (xs, vs) = lax.scan(step, (xp0, vp0), m)
    return jnp.moveaxis(xs, 0, -1), jnp.moveaxis(vs, 0, -1)


def alpha_beta_position_transfer(alpha, beta, freq_hz, sample_rate_hz):
    """Position transfer function of the α-β filter on the unit circle (complex).

    ``H(z) = (α + (β − α) z⁻¹) / (1 + (α + β − 2) z⁻¹ + (1 − α) z⁻²)`` at z = exp(j 2π f / f_s):
    smoothed position over measured position. |H| → 1 at f = 0 (no lag for constant velocity).

    Args:
        alpha: α in (0, 2); beta: β in (0, 4 − 2α).
        freq_hz: frequency f (Hz), in [0, f_s/2].
        sample_rate_hz: f_s = 1/T (Hz), in (0, ∞).

    Source: book eq (13.10) and the script ``ab_trans.m`` (§13.6, Figure 13.9).
    """
    w = "alpha_beta_position_transfer"
    _check_stable(alpha, beta, w)
    check_range("sample_rate_hz", sample_rate_hz, 0.0, None, lo_open=True, where=w)
    check_range("freq_hz", freq_hz, 0.0, None, where=w)
    if is_concrete(freq_hz) and is_concrete(sample_rate_hz):
        check_range("freq_hz - sample_rate_hz/2", np.asarray(freq_hz, float) - 0.5 * np.asarray(sample_rate_hz, float), None, 0.0, where=w)
    alpha = jnp.asarray(alpha)
    beta = jnp.asarray(beta)
    zi = jnp.exp(-2j * jnp.pi * jnp.asarray(freq_hz) / jnp.asarray(sample_rate_hz))  # z^-1
    return (alpha + (beta - alpha) * zi) / (1.0 + (alpha + beta - 2.0) * zi + (1.0 - alpha) * zi * zi)


def alpha_beta_position_variance_ratio(alpha, beta):
    """Steady-state noise variance reduction of the smoothed position ``σ²_x / σ²_n = Σ h²``.

    Closed form of the sum of squares of the impulse response of (13.10):

        ``K_x = (2α² + 2β − 3αβ) / (α (4 − 2α − β))``.

    Exact for white measurement noise (no approximation).

    Args:
        alpha: α in (0, 2); beta: β in (0, 4 − 2α) (stability triangle).

    The sum of squares of the impulse response of the filter itself, run over 400 samples:

    >>> import jax.numpy as jnp
    >>> h, _ = alpha_beta_filter(jnp.zeros(400).at[0].set(1.0), 0.5, 0.2, 1.0)
    >>> float(alpha_beta_position_variance_ratio(0.5, 0.2)), float(jnp.sum(h * h))
    (0.428571, 0.428571)

    Source: Benedict & Bordner (1962); Kalata (1984); the book computes Σh² numerically
    (§13.6, ``ablag.m``).
    """
    _check_stable(alpha, beta, "alpha_beta_position_variance_ratio")
    a = jnp.asarray(alpha)
    b = jnp.asarray(beta)
    return (2.0 * a * a + 2.0 * b - 3.0 * a * b) / (a * (4.0 - 2.0 * a - b))


def alpha_beta_velocity_variance_ratio_s2(alpha, beta, sample_time_s):
    """Steady-state variance of the smoothed velocity over the measurement variance (s⁻²).

    ``σ²_v / σ²_n = 2 β² / (T² α (4 − 2α − β))``; exact for white measurement noise.

    Args:
        alpha: α in (0, 2); beta: β in (0, 4 − 2α).
        sample_time_s: T (s), in (0, ∞).

    Source: Benedict & Bordner (1962); Kalata (1984).
    """
    w = "alpha_beta_velocity_variance_ratio_s2"
    _check_stable(alpha, beta, w)
    check_range("sample_time_s", sample_time_s, 0.0, None, lo_open=True, where=w)
    a = jnp.asarray(alpha)
    b = jnp.asarray(beta)
    t = jnp.asarray(sample_time_s)
    return 2.0 * b * b / (t * t * a * (4.0 - 2.0 * a - b))


def alpha_beta_acceleration_lag_m(acceleration_m_s2, sample_time_s, alpha, beta, *, predicted=False):
    """Steady-state lag of the α-β filter behind a constant acceleration a (m).

    Smoothed position: ``a T² (1 − α) / β`` (the book's form); one-step prediction:
    ``a T² / β`` (``predicted=True``). Exact in steady state.

    Args:
        acceleration_m_s2: target acceleration a (m/s²), any real value (sign carries through).
        sample_time_s: T (s), in (0, ∞).
        alpha: α in (0, 2); beta: β in (0, 4 − 2α).
        predicted: static flag, lag of the one-sample-ahead prediction instead.

    Source: book §13.6 script ``ablag.m`` (``lag = acc*ts^2*(1-alpha)/beta``); §13.4.1.
    """
    w = "alpha_beta_acceleration_lag_m"
    check_range("acceleration_m_s2", acceleration_m_s2, where=w)
    check_range("sample_time_s", sample_time_s, 0.0, None, lo_open=True, where=w)
    _check_stable(alpha, beta, w)
    t = jnp.asarray(sample_time_s)
    base = jnp.asarray(acceleration_m_s2) * t * t / jnp.asarray(beta)
    return base if predicted else base * (1.0 - jnp.asarray(alpha))


def split_gate_range_noise_m(gate_width_m, snr_db):
    """RMS range noise of a split-gate (early/late) tracker ``σ_R = ΔR / (2.5 √(2 SNR))`` (m).

    Args:
        gate_width_m: range gate size ΔR (m) (≈ cτ/2 of the pulse), in (0, ∞).
        snr_db: single-measurement SNR (dB), in [-20, 100].

    The book's ``ablag.m`` case, a 3 m gate at SNR 10 dB (a ratio of 10):

    >>> import math
    >>> float(split_gate_range_noise_m(3.0, 10.0)), 3.0 / (2.5 * math.sqrt(2 * 10))
    (0.268328, 0.268328)

    Source: book §13.6 script ``ablag.m`` (``sigma = tau/(2.5*sqrt(2*snr))``, tau the gate in m).
    """
    w = "split_gate_range_noise_m"
    check_range("gate_width_m", gate_width_m, 0.0, None, lo_open=True, where=w)
    check_range("snr_db", snr_db, -20.0, 100.0, where=w)
    return jnp.asarray(gate_width_m) / (2.5 * jnp.sqrt(2.0 * from_db10(snr_db)))


def benedict_bordner_tracking_cost_m2(alpha, acceleration_m_s2, sample_rate_hz, range_noise_m):
    """The book's tracking cost ``J(α) = lag² + σ_out²`` with Benedict–Bordner β (m²).

    ``lag = a T² (1 − α)/β``, ``σ_out² = σ_R² K_x(α, β)``, ``β = α²/(2 − α)``, T = 1/f_s.

    Args:
        alpha: α in (0, 1].
        acceleration_m_s2: target acceleration a (m/s²), in [0, ∞).
        sample_rate_hz: f_s (Hz), in (0, ∞).
        range_noise_m: measurement noise σ_R (m) (e.g. :func:`split_gate_range_noise_m`), in [0, ∞).

    Source: book §13.4.1 ("the cost function that is minimized in this case is [lag² + σ_r²]")
    and §13.6 ``ablag.m``.
    """
    w = "benedict_bordner_tracking_cost_m2"
    check_range("alpha", alpha, 0.0, 1.0, lo_open=True, where=w)
    check_range("acceleration_m_s2", acceleration_m_s2, 0.0, None, where=w)
    check_range("sample_rate_hz", sample_rate_hz, 0.0, None, lo_open=True, where=w)
    check_range("range_noise_m", range_noise_m, 0.0, None, where=w)
    return _bb_cost(jnp.asarray(alpha), acceleration_m_s2, 1.0 / jnp.asarray(sample_rate_hz), range_noise_m)


def _bb_cost(alpha, accel, ts, sigma):
    return _ab_cost(alpha, benedict_bordner_beta(alpha), accel, ts, sigma)


def _ab_cost(alpha, beta, accel, ts, sigma):
    lag = alpha_beta_acceleration_lag_m(accel, ts, alpha, beta)
    vrr = alpha_beta_position_variance_ratio(alpha, beta)
    return lag * lag + sigma * sigma * vrr


def alpha_beta_tracking_cost_m2(alpha, beta, acceleration_m_s2, sample_time_s, range_noise_m):
    """The book's tracking cost for any gains ``J = lag² + σ_R² K_x`` (m²).

    ``lag = a T² (1 − α)/β`` (:func:`alpha_beta_acceleration_lag_m`) and
    ``K_x`` (:func:`alpha_beta_position_variance_ratio`): the mean-square error of the smoothed
    position behind a constant acceleration a with white measurement noise σ_R. Its square root
    is the rms range tracking error.

    Args:
        alpha: α in (0, 2); beta: β in (0, 4 − 2α).
        acceleration_m_s2: a (m/s²), any real value.
        sample_time_s: T (s), in (0, ∞).
        range_noise_m: σ_R (m), in [0, ∞).

    With α = 1 the filter passes the measurement (K_x = 1, no lag), so J = σ_R²:

    >>> float(alpha_beta_tracking_cost_m2(1.0, 0.5, 10.0, 0.02, 0.3)), 0.3**2
    (0.09, 0.09)

    Source: book §13.4.1 (cost lag² + σ²) and §13.6 ``ablag.m``.
    """
    w = "alpha_beta_tracking_cost_m2"
    check_range("range_noise_m", range_noise_m, 0.0, None, where=w)
    return _ab_cost(jnp.asarray(alpha), jnp.asarray(beta), acceleration_m_s2, sample_time_s, jnp.asarray(range_noise_m))


def benedict_bordner_optimal_alpha(acceleration_m_s2, sample_rate_hz, range_noise_m, *, alpha_min=1e-6):
    """α minimising the book's cost lag² + σ² Σh² (Benedict–Bordner β), differentiably.

    Solves ``∂J/∂α = 0`` (:func:`benedict_bordner_tracking_cost_m2`) on [alpha_min, 1] with
    :func:`diffsense.numerics.rootfind.decreasing_root_log` applied to −∂J/∂α; derivatives of the
    optimum with respect to the arguments come from the implicit function theorem. J/σ_R²
    depends on α and q = a T²/σ_R only, and J is convex in α on (0, 1] (tested on a grid of q
    from 1e-8 to 1e4), so the stationary point is the minimum. The root is always inside
    (alpha_min, 1): at α = 1 the lag term is flat and the noise term rises, and at alpha_min the
    lag term ~ 16 q² σ_R² / α⁵ dominates for q > 1e-15. α* rises from 0.11 (q = 1e-3) through
    0.84 (q = 1) towards 1.

    Args:
        acceleration_m_s2: a (m/s²), in (0, ∞).
        sample_rate_hz: f_s (Hz), in (0, ∞).
        range_noise_m: σ_R (m), in (0, ∞).
        alpha_min: static lower end of the search bracket, in (0, 1).

    Source: book §13.4.1 and §13.6 (``ablag.m``: a = 10 m/s², f_s = 50 Hz, SNR 10 dB, 3 m gate;
    the book scans α = 0.1:0.01:1 and reads the minimum off a plot).
    """
    w = "benedict_bordner_optimal_alpha"
    check_range("acceleration_m_s2", acceleration_m_s2, 0.0, None, lo_open=True, where=w)
    check_range("sample_rate_hz", sample_rate_hz, 0.0, None, lo_open=True, where=w)
    check_range("range_noise_m", range_noise_m, 0.0, None, lo_open=True, where=w)
    return _bb_optimal_alpha(
        jnp.asarray(acceleration_m_s2, dtype=float),
        1.0 / jnp.asarray(sample_rate_hz, dtype=float),
        jnp.asarray(range_noise_m, dtype=float),
        alpha_min,
    )


@partial(jax.jit, static_argnums=3)
def _bb_optimal_alpha(accel, ts, sigma, alpha_min):
    accel, ts, sigma = jnp.broadcast_arrays(accel, ts, sigma)
    dcost = jax.grad(_bb_cost, argnums=0)

    def neg_slope(alpha):
        # elementwise -dJ/dalpha; vmap over the flattened arrays keeps it elementwise
        flat = jax.vmap(dcost)(alpha.ravel(), accel.ravel(), ts.ravel(), sigma.ravel())
        return -flat.reshape(alpha.shape)

    lo = jnp.full(accel.shape, alpha_min)
    hi = jnp.ones(accel.shape)
    # 120 iterations: the residual is steep (lag term ~ α⁻⁴) and Newton steps accepted inside the
    # bracket can shrink it slowly; 60 left errors up to 5e-6 (relative) on a Λ sweep, 100 none.
    return decreasing_root_log(neg_slope, lo, hi, iterations=120).root


# ---------------------------------------------------------------------------------------------
# Servo angle tracking (book 14.7)
# ---------------------------------------------------------------------------------------------


def servo_acceleration_error_constant_s2(noise_bandwidth_hz):
    """Acceleration error constant of a type-2 servo ``K_a = 2.5 β_n²`` (s⁻²).

    Args:
        noise_bandwidth_hz: loop equivalent noise bandwidth β_n (Hz), in (0, ∞).

    Source: book eq (14.9) (K_a = 0.63/t_o², t_o the equivalent averaging time).
    """
    check_range("noise_bandwidth_hz", noise_bandwidth_hz, 0.0, None, lo_open=True, where="servo_acceleration_error_constant_s2")
    bn = jnp.asarray(noise_bandwidth_hz)
    return 2.5 * bn * bn


def servo_dynamic_lag_rad(angular_acceleration_rad_s2, noise_bandwidth_hz):
    """Dynamic lag of a type-2 tracking loop ``ε_t = ω̇_t / K_a = ω̇_t / (2.5 β_n²)`` (rad).

    Args:
        angular_acceleration_rad_s2: target angular acceleration ω̇_t (rad/s²), any real value
            (a_t/R for a real acceleration a_t at range R).
        noise_bandwidth_hz: β_n (Hz), in (0, ∞).

    Source: book eq (14.10).
    """
    w = "servo_dynamic_lag_rad"
    check_range("angular_acceleration_rad_s2", angular_acceleration_rad_s2, where=w)
    return jnp.asarray(angular_acceleration_rad_s2) / servo_acceleration_error_constant_s2(noise_bandwidth_hz)


def _servo_noise_per_hz(beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, monopulse_slope):
    """Thermal-noise angle variance per hertz of servo bandwidth, θ² / (2 k_m² f_r βτ SNR) (rad²/Hz)."""
    return beamwidth_rad**2 / (2.0 * monopulse_slope**2 * prf_hz * bandwidth_pulse_product * from_db10(snr_db))


def _servo_terms(beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2, range_m, monopulse_slope):
    noise = _servo_noise_per_hz(beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, monopulse_slope)
    lag = acceleration_m_s2**2 / (6.25 * range_m**2)
    return noise, lag


def _check_servo_noise(w, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, monopulse_slope):
    check_range("beamwidth_rad", beamwidth_rad, 0.0, math.pi, lo_open=True, where=w)
    check_range("prf_hz", prf_hz, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_pulse_product", bandwidth_pulse_product, 0.0, None, lo_open=True, where=w)
    check_range("snr_db", snr_db, -20.0, 100.0, where=w)
    check_range("monopulse_slope", monopulse_slope, 0.0, None, lo_open=True, where=w)


def _check_servo(w, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2, range_m, monopulse_slope):
    _check_servo_noise(w, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, monopulse_slope)
    check_range("acceleration_m_s2", acceleration_m_s2, 0.0, None, lo_open=True, where=w)
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)


def servo_angle_noise_variance_rad2(
    noise_bandwidth_hz,
    beamwidth_rad,
    prf_hz,
    bandwidth_pulse_product,
    snr_db,
    monopulse_slope=MONOPULSE_SLOPE_TYPICAL,
):
    """Thermal-noise part of the mean-square angle tracking error (rad²):

        ``σ_n² = θ_3dB² β_n / (2 k_m² f_r βτ SNR)``

    Args: as :func:`servo_angle_error_variance_rad2` without the target's acceleration and range.

    A 1° beam, β_n = 2 Hz, k_m = 1.6, f_r = 1 kHz, βτ = 1 and SNR 20 dB, computed from the
    formula:

    >>> import math
    >>> theta = math.radians(1.0)
    >>> float(servo_angle_noise_variance_rad2(2.0, theta, 1e3, 1.0, 20.0, 1.6))
    1.19e-09
    >>> theta**2 * 2.0 / (2 * 1.6**2 * 1e3 * 1.0 * 100.0)
    1.19e-09

    Source: book eq (14.11), first term.
    """
    w = "servo_angle_noise_variance_rad2"
    check_range("noise_bandwidth_hz", noise_bandwidth_hz, 0.0, None, lo_open=True, where=w)
    _check_servo_noise(w, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, monopulse_slope)
    noise = _servo_noise_per_hz(jnp.asarray(beamwidth_rad), jnp.asarray(prf_hz), jnp.asarray(bandwidth_pulse_product),
                                jnp.asarray(snr_db), jnp.asarray(monopulse_slope))
    return noise * jnp.asarray(noise_bandwidth_hz)


def servo_angle_error_variance_rad2(
    noise_bandwidth_hz,
    beamwidth_rad,
    prf_hz,
    bandwidth_pulse_product,
    snr_db,
    acceleration_m_s2,
    range_m,
    monopulse_slope=MONOPULSE_SLOPE_TYPICAL,
):
    """Mean-square angle tracking error, thermal noise plus dynamic lag (rad²).

        ``σ_θ² = θ_3dB² β_n / (2 k_m² f_r βτ SNR) + a_t² / (6.25 R² β_n⁴)``

    the noise of :func:`servo_angle_noise_variance_rad2` plus the square of the lag of
    :func:`servo_dynamic_lag_rad` at the angular acceleration a_t / R.

    Args:
        noise_bandwidth_hz: servo noise bandwidth β_n (Hz), in (0, ∞).
        beamwidth_rad: antenna 3 dB beamwidth θ_3dB (rad), in (0, π].
        prf_hz: pulse repetition frequency f_r (Hz), in (0, ∞).
        bandwidth_pulse_product: IF bandwidth × pulse width βτ, in (0, ∞).
        snr_db: single-pulse SNR (dB), in [-20, 100].
        acceleration_m_s2: real or geometric target acceleration a_t (m/s²), in (0, ∞).
        range_m: (crossing) range R (m), in (0, ∞).
        monopulse_slope: monopulse gain constant k_m, in (0, ∞); typically 1.6.

    The two terms computed separately add up to it:

    >>> import math
    >>> theta = math.radians(1.0)
    >>> noise = servo_angle_noise_variance_rad2(2.0, theta, 1e3, 1.0, 20.0)
    >>> lag = servo_dynamic_lag_rad(50.0 / 5e3, 2.0)
    >>> float(servo_angle_error_variance_rad2(2.0, theta, 1e3, 1.0, 20.0, 50.0, 5e3)), float(noise + lag**2)
    (1.00119e-06, 1.00119e-06)

    Source: book eq (14.11).
    """
    w = "servo_angle_error_variance_rad2"
    check_range("noise_bandwidth_hz", noise_bandwidth_hz, 0.0, None, lo_open=True, where=w)
    _check_servo(w, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2, range_m, monopulse_slope)
    noise, lag = _servo_terms(
        jnp.asarray(beamwidth_rad), jnp.asarray(prf_hz), jnp.asarray(bandwidth_pulse_product),
        jnp.asarray(snr_db), jnp.asarray(acceleration_m_s2), jnp.asarray(range_m), jnp.asarray(monopulse_slope),
    )
    bn = jnp.asarray(noise_bandwidth_hz)
    return noise * bn + lag / bn**4


def servo_optimal_bandwidth_hz(
    beamwidth_rad,
    prf_hz,
    bandwidth_pulse_product,
    snr_db,
    acceleration_m_s2,
    range_m,
    monopulse_slope=MONOPULSE_SLOPE_TYPICAL,
):
    """Servo noise bandwidth minimising :func:`servo_angle_error_variance_rad2` (Hz).

        ``β_o = (1.28 a_t² k_m² f_r βτ SNR / (θ_3dB² R²))^(1/5)``

    Exact stationary point of (14.11): with σ² = A β + B β⁻⁴, dσ²/dβ = 0 gives β⁵ = 4B/A and
    4 · 2 / 6.25 = 1.28.

    Args: as :func:`servo_angle_error_variance_rad2` without ``noise_bandwidth_hz``.

    The variance is larger 1 % either side of β_o:

    >>> import math
    >>> args = (math.radians(1.0), 1e3, 1.0, 20.0, 50.0, 5e3)
    >>> b_o = float(servo_optimal_bandwidth_hz(*args))
    >>> var = lambda b: float(servo_angle_error_variance_rad2(b, *args))
    >>> var(0.99 * b_o) > var(b_o) < var(1.01 * b_o)
    True

    Source: book eq (14.12).
    """
    w = "servo_optimal_bandwidth_hz"
    _check_servo(w, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2, range_m, monopulse_slope)
    a = jnp.asarray(acceleration_m_s2)
    km = jnp.asarray(monopulse_slope)
    r = jnp.asarray(range_m)
    th = jnp.asarray(beamwidth_rad)
    arg = 1.28 * a * a * km * km * jnp.asarray(prf_hz) * jnp.asarray(bandwidth_pulse_product) * from_db10(snr_db) / (th * th * r * r)
    return arg**0.2


# ---------------------------------------------------------------------------------------------
# Kalata tracking index and steady-state Kalman gains
# ---------------------------------------------------------------------------------------------


def kalata_tracking_index(acceleration_std_m_s2, sample_time_s, measurement_std_m):
    """Kalata's tracking (maneuvering) index ``Λ = σ_a T² / σ_n`` (dimensionless).

    Args:
        acceleration_std_m_s2: process-noise acceleration standard deviation σ_a (m/s²), in (0, ∞)
            (piecewise-constant white acceleration over each sample interval).
        sample_time_s: T (s), in (0, ∞).
        measurement_std_m: measurement noise standard deviation σ_n (m), in (0, ∞).

    Source: Kalata (1984); Bar-Shalom, Li & Kirubarajan (2001) §6.5 (maneuvering index λ).
    """
    w = "kalata_tracking_index"
    check_range("acceleration_std_m_s2", acceleration_std_m_s2, 0.0, None, lo_open=True, where=w)
    check_range("sample_time_s", sample_time_s, 0.0, None, lo_open=True, where=w)
    check_range("measurement_std_m", measurement_std_m, 0.0, None, lo_open=True, where=w)
    t = jnp.asarray(sample_time_s)
    return jnp.asarray(acceleration_std_m_s2) * t * t / jnp.asarray(measurement_std_m)


def kalman_steady_state_alpha_beta(tracking_index):
    """Steady-state Kalman gains (α, β) of the constant-velocity filter from Λ.

    Published closed forms (Kalata 1984; Bar-Shalom et al. 2001 §6.5)::

        α = −(Λ² + 8Λ − (Λ + 4)√(Λ² + 8Λ)) / 8,   β = (Λ² + 4Λ − Λ√(Λ² + 8Λ)) / 4,

    equivalently ``r = (4 + Λ − √(Λ² + 8Λ))/4``, ``α = 1 − r²``, ``β = 2(1 − r)²`` (so
    ``β = 2(2 − α) − 4√(1 − α)`` and ``β²/(1 − α) = Λ²``). Evaluated here as
    ``r = 4 / (4 + Λ + √(Λ² + 8Λ))``, free of cancellation for all Λ. The model is the discrete
    white-noise-acceleration one (Q = σ_a² Γ Γᵀ, Γ = [T²/2, T]ᵀ); the gain on the velocity is β/T.

    Args:
        tracking_index: Λ, in (0, 1e8]. The derivative is infinite at Λ = 0.

    Returns:
        ``(alpha, beta)``.

    With Λ = 1 the published closed forms give α = −(1 + 8 − 5·3)/8 and β = (1 + 4 − 3)/4:

    >>> a, b = kalman_steady_state_alpha_beta(1.0)
    >>> float(a), float(b), -(1 + 8 - 5 * 3) / 8, (1 + 4 - 3) / 4
    (0.75, 0.5, 0.75, 0.5)
    """
    check_range("tracking_index", tracking_index, 0.0, 1e8, lo_open=True, where="kalman_steady_state_alpha_beta")
    lam = jnp.asarray(tracking_index)
    s = jnp.sqrt(lam) * jnp.sqrt(lam + 8.0)  # sqrt(lam^2 + 8 lam) without overflow
    d = 4.0 + lam + s
    r = 4.0 / d
    one_minus_r = (lam + s) / d
    return (1.0 - r) * (1.0 + r), 2.0 * one_minus_r * one_minus_r
