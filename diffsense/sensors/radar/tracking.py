"""The radar chain's tracking stage (part ``"tracking"``): range and angle tracking errors at
``range_m`` from the single-pulse SNR of the budget (noise only: clutter and jamming are not in
the tracking noise). Every relation is one of :mod:`diffsense.physics.tracking`.

* Range: an α-β filter sampled at the PRF (T = 1/f_p) smooths a split-gate range tracker of
  gate c W/2 (W the echo's width after the IF filter, τ for a matched filter). Measurement noise
  σ_R = (c W/2)/(2.5 √(2 SNR)), output noise σ_R √K_x with the
  variance reduction K_x = Σh² of the position transfer function, lag a T²(1 − α)/β behind a
  constant acceleration a, and the book's cost √(lag² + σ_R² K_x) (book §13.4.1, §13.6
  ``ablag.m``). β follows α by the Benedict–Bordner relation β = α²/(2 − α) (book eq 13.11)
  or, with the option ``tracking_gains="critically_damped"``, α = 2√β − β (book eq 13.12).
* Angle: a type-2 servo of noise bandwidth β_n with a monopulse error slope k_m: noise
  θ3dB² β_n/(2 k_m² f_p βτ SNR) with θ3dB the azimuth beamwidth and βτ = bandwidth_hz ×
  pulse_width_s, dynamic lag a/(R · 2.5 β_n²) and their sum σ_θ² (book eqs 14.9-14.11); the
  bandwidth β_o that minimises σ_θ² (book eq 14.12); and β_n over the positioner's lowest
  resonance, which the book keeps below 10 % (§14.6).

The angle servo also follows the platform's own angular acceleration Ω̇ that reaches it (a ship's
roll, pitch and yaw less what a stabilised mount removes): its lag is that of the angular
acceleration a/R + Ω̇ (the worst case, both in the same sense; book 14.9.1 lists the ship motion).
The same acceleration a drives the range and the angle lag (the book applies eq 14.10 to each
axis with its own component; here one worst-case value).
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.physics.waveforms import range_resolution_pulse_m
from diffsense.sensors.radar import parts
from diffsense.sensors.radar.structure import option

__all__ = ["tracking_outputs", "TRACKING_OUTPUTS"]


#: the outputs of :func:`tracking_outputs`
TRACKING_OUTPUTS = ("track_beta", "range_noise_m", "range_variance_reduction", "range_track_noise_m", "range_lag_m",
                    "range_track_error_m", "angle_noise_rad", "angle_lag_rad", "angle_error_rad",
                    "cross_range_error_m", "servo_optimal_bandwidth_hz", "servo_resonance_ratio")


def tracking_outputs(scene, p, snr_db, beamwidth_rad, received_width_s):
    """Range and angle tracking outputs at ``range_m`` for the single-pulse ``snr_db`` (dB), the
    azimuth beamwidth (rad) and the width of the echo after the IF filter (s), whose c W/2 is the
    split gate."""
    alpha = p["track_alpha"]
    if option(scene, "tracking_gains") == "critically_damped":
        beta = parts.tracking_beta_critically_damped(alpha)
    else:
        beta = parts.tracking_beta_benedict_bordner(alpha)
    accel = p["target_acceleration_m_s2"]
    gate = range_resolution_pulse_m(received_width_s)
    sigma, vrr, lag, cost = parts.range_tracking_errors(alpha, beta, gate, snr_db, p["prf_hz"], accel)
    bn = p["servo_bandwidth_hz"]
    noise_var, angle_lag, angle_var, beta_o = parts.angle_tracking_errors(
        bn, beamwidth_rad, p["prf_hz"], p["bandwidth_hz"] * p["pulse_width_s"], snr_db,
        accel + p["platform_angular_acceleration_rad_s2"] * p["range_m"], p["range_m"],
        p["monopulse_slope"])
    angle_error = jnp.sqrt(angle_var)
    return {
        "track_beta": beta,
        "range_noise_m": sigma,
        "range_variance_reduction": vrr,
        "range_track_noise_m": sigma * jnp.sqrt(vrr),
        "range_lag_m": lag,
        "range_track_error_m": jnp.sqrt(cost),
        "angle_noise_rad": jnp.sqrt(noise_var),
        "angle_lag_rad": angle_lag,
        "angle_error_rad": angle_error,
        "cross_range_error_m": p["range_m"] * angle_error,
        "servo_optimal_bandwidth_hz": beta_o,
        "servo_resonance_ratio": bn / p["positioner_resonance_hz"],
    }
