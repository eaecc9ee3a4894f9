"""The radar chain's scene parts: each a named sub-program of the traced evaluation
(:func:`diffsense.sensors.parts.scene_part`), called only when the scene holds the part.

Every function here is a thin wrapper around the physics it names (propagation, clutter,
multipath, jamming, tracking), so that :func:`diffsense.sensors.parts.traced_parts` can tell
which parts an evaluation contains. Units are in the names; dB explicit.
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.db import db10
from diffsense.physics import clutter as _clutter
from diffsense.physics import tracking as _trk
from diffsense.physics.propagation.cloud import cloud_attenuation_db_per_km
from diffsense.physics.propagation.dust import (
    ROCK_DUST_K_SQUARED,
    dust_mass_loading_g_m3,
    dust_radar_attenuation_db_per_km,
)
from diffsense.physics.propagation.gas import gas_attenuation_approx_db_per_km, gas_attenuation_db_per_km
from diffsense.physics.propagation.rain import rain_attenuation_db_per_km
from diffsense.detection.cumulative import closing_looks
from diffsense.sensors.parts import scene_part
from diffsense.sensors.radar import equation as eq
from diffsense.sensors.radar.structure import MAX_LOOKS

__all__ = [
    "gas_itu_attenuation_db_km",
    "gas_given_attenuation_db_km",
    "rain_itu_attenuation_db_km",
    "rain_given_attenuation_db_km",
    "fog_attenuation_db_km",
    "dust_attenuation_db_km",
    "rain_clutter_rcs_marshall_palmer_m2",
    "rain_clutter_rcs_given_m2",
    "dust_clutter_rcs_m2",
    "sea_clutter_rcs_nrl_horizontal_m2",
    "sea_clutter_rcs_nrl_vertical_m2",
    "sea_clutter_rcs_constant_gamma_m2",
    "wall_clutter_rcs_gaussian_beam_m2",
    "wall_clutter_rcs_filled_m2",
    "multipath_horizontal_db",
    "multipath_vertical_db",
    "jamming_power_dbw",
    "tracking_beta_benedict_bordner",
    "tracking_beta_critically_damped",
    "range_tracking_errors",
    "angle_tracking_errors",
]


# --- path attenuation (one way, dB/km) -------------------------------------------------------


@scene_part("gas")
def gas_itu_attenuation_db_km(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    """One-way specific attenuation of gases (dB/km), ITU-R P.676-12."""
    return gas_attenuation_db_per_km(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)


@scene_part("gas")
def gas_itu_approx_attenuation_db_km(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    """One-way specific attenuation of gases (dB/km), the closed forms of ITU-R P.676-10 Annex 2
    (option ``gas_model="itu_p676_approx"``)."""
    return gas_attenuation_approx_db_per_km(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)


@scene_part("gas")
def gas_given_attenuation_db_km(alpha_db_km):
    """A given one-way specific attenuation of gases (dB/km), e.g. book 9.9.1.4: 0.003 dB/km."""
    return alpha_db_km * 1.0


@scene_part("rain")
def rain_itu_attenuation_db_km(freq_hz, rain_rate_mm_h, tilt_deg):
    """One-way rain specific attenuation (dB/km), ITU-R P.838-3 (tilt 0 = H, 90 = V)."""
    return rain_attenuation_db_per_km(freq_hz, rain_rate_mm_h, tilt_deg)


@scene_part("rain")
def rain_given_attenuation_db_km(alpha_db_km):
    """A given one-way rain specific attenuation (dB/km), e.g. book 9.9.3: 0.02 dB/km."""
    return alpha_db_km * 1.0


@scene_part("fog")
def fog_attenuation_db_km(freq_hz, liquid_water_g_m3, temperature_k):
    """One-way fog/cloud specific attenuation (dB/km), ITU-R P.840-7."""
    return cloud_attenuation_db_per_km(freq_hz, liquid_water_g_m3, temperature_k)


@scene_part("dust")
def dust_attenuation_db_km(freq_hz, visibility_m):
    """One-way dust specific attenuation (dB/km) at the mass loading M = 37.3 V^-1.07."""
    return dust_radar_attenuation_db_per_km(freq_hz, dust_mass_loading_g_m3(visibility_m))


# --- clutter cross-sections (m²) --------------------------------------------------------------


@scene_part("rain_clutter")
def rain_clutter_rcs_marshall_palmer_m2(range_m, rain_rate_mm_h, wavelength_m, bw_az, bw_el, pulse_width_s, beam_shape):
    """Rain clutter σ = η V, η from Z = 200 R^1.6 (m²)."""
    eta = _clutter.rain_volume_reflectivity_m2_m3(rain_rate_mm_h, wavelength_m)
    return _clutter.volume_clutter_rcs_m2(eta, range_m, bw_az, bw_el, pulse_width_s, beam_shape_factor=beam_shape)


@scene_part("rain_clutter")
def rain_clutter_rcs_given_m2(range_m, eta_m2_m3, bw_az, bw_el, pulse_width_s, beam_shape):
    """Rain clutter σ = η V for a given η (m²), e.g. book 9.9.3: η = 1e-7 m²/m³."""
    return _clutter.volume_clutter_rcs_m2(eta_m2_m3, range_m, bw_az, bw_el, pulse_width_s, beam_shape_factor=beam_shape)


@scene_part("dust_clutter")
def dust_clutter_rcs_m2(range_m, visibility_m, wavelength_m, bw_az, bw_el, pulse_width_s, beam_shape):
    """Dust clutter σ = η V, η of book eq (8.45) with rock-dust |K|² (m²)."""
    eta = _clutter.dust_volume_reflectivity_m2_m3(wavelength_m, visibility_m, ROCK_DUST_K_SQUARED)
    return _clutter.volume_clutter_rcs_m2(eta, range_m, bw_az, bw_el, pulse_width_s, beam_shape_factor=beam_shape)


@scene_part("sea_clutter")
def sea_clutter_rcs_nrl_horizontal_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state):
    """Sea clutter σ = σ° A (m²), NRL model, horizontal polarization (4/3-earth grazing angle)."""
    return eq.sea_clutter_rcs_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state,
                                 "nrl", "horizontal")


@scene_part("sea_clutter")
def sea_clutter_rcs_nrl_vertical_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state):
    """Sea clutter σ = σ° A (m²), NRL model, vertical polarization (4/3-earth grazing angle)."""
    return eq.sea_clutter_rcs_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state,
                                 "nrl", "vertical")


@scene_part("sea_clutter")
def sea_clutter_rcs_constant_gamma_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state):
    """Sea clutter σ = γ sin ψ · A (m²), Barton's γ (book 8.12.4; grazing 1-60 deg)."""
    return eq.sea_clutter_rcs_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state,
                                 "constant_gamma")


@scene_part("wall_clutter")
def wall_clutter_rcs_gaussian_beam_m2(range_m, pass_diameter_m, range_gate_m, wall_reflectivity_db, beamwidth_rad,
                                      sidelobe_level_db):
    """Ore-pass wall clutter weighted two-way by the Gaussian beam on its sidelobe floor at the wall
    angle (m²)."""
    w = eq.wall_illumination_factor(range_m, pass_diameter_m, beamwidth_rad, sidelobe_level_db)
    return eq.wall_clutter_rcs_m2(pass_diameter_m, range_gate_m, wall_reflectivity_db, w)


@scene_part("wall_clutter")
def wall_clutter_rcs_filled_m2(range_m, pass_diameter_m, range_gate_m, wall_reflectivity_db):
    """Ore-pass wall clutter when the beam fills the pass (book 8.16.6 worst case) (m²)."""
    return eq.wall_clutter_rcs_m2(pass_diameter_m, range_gate_m, wall_reflectivity_db) * jnp.ones_like(range_m)


# --- multipath and jamming ---------------------------------------------------------------------


@scene_part("multipath")
def multipath_horizontal_db(range_m, antenna_height_m, target_height_m, freq_hz, sea_state):
    """Two-way multipath factor 40 log10|F| (dB), horizontal polarization."""
    return eq.multipath_factor_db(range_m, antenna_height_m, target_height_m, freq_hz, sea_state, "horizontal")


@scene_part("multipath")
def multipath_vertical_db(range_m, antenna_height_m, target_height_m, freq_hz, sea_state):
    """Two-way multipath factor 40 log10|F| (dB), vertical polarization."""
    return eq.multipath_factor_db(range_m, antenna_height_m, target_height_m, freq_hz, sea_state, "vertical")


@scene_part("jammer")
def jamming_power_dbw(jammer_power_w, jammer_gain_db, radar_gain_db, wavelength_m, jammer_range_m, jammer_bandwidth_hz,
                      receiver_bandwidth_hz, one_way_attenuation_db):
    """Jamming power in the receiver band (dBW), less the one-way path attenuation."""
    j = eq.jamming_power_w(jammer_power_w, jammer_gain_db, radar_gain_db, wavelength_m, jammer_range_m,
                           jammer_bandwidth_hz, receiver_bandwidth_hz)
    return db10(j) - one_way_attenuation_db


# --- tracking ----------------------------------------------------------------------------------


@scene_part("tracking")
def tracking_beta_benedict_bordner(alpha):
    """Velocity gain β = α²/(2 − α) of the α-β range tracker (book eq 13.11)."""
    return _trk.benedict_bordner_beta(alpha)


@scene_part("tracking")
def tracking_beta_critically_damped(alpha):
    """Velocity gain β = (1 − √(1 − α))² of the critically damped α-β tracker (book eq 13.12)."""
    return _trk.critically_damped_beta(alpha)


@scene_part("tracking")
def range_tracking_errors(alpha, beta, gate_m, snr_db, prf_hz, acceleration_m_s2):
    """Split-gate noise σ_R (m), variance reduction K_x, acceleration lag (m) and the book's
    tracking cost lag² + σ_R² K_x (m²) of the α-β range tracker sampled at the PRF (book §13.6
    ``ablag.m``)."""
    sigma = _trk.split_gate_range_noise_m(gate_m, snr_db)
    vrr = _trk.alpha_beta_position_variance_ratio(alpha, beta)
    lag = _trk.alpha_beta_acceleration_lag_m(acceleration_m_s2, 1.0 / prf_hz, alpha, beta)
    cost = _trk.alpha_beta_tracking_cost_m2(alpha, beta, acceleration_m_s2, 1.0 / prf_hz, sigma)
    return sigma, vrr, lag, cost


@scene_part("tracking")
def angle_tracking_errors(bandwidth_hz, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2,
                          range_m, monopulse_slope):
    """Servo angle tracking (book eqs 14.9-14.12): thermal-noise variance (rad²), dynamic lag
    (rad), total mean-square error (rad²) and the optimum noise bandwidth β_o (Hz)."""
    noise = _trk.servo_angle_noise_variance_rad2(bandwidth_hz, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db,
                                                 monopulse_slope)
    lag = _trk.servo_dynamic_lag_rad(acceleration_m_s2 / range_m, bandwidth_hz)
    total = _trk.servo_angle_error_variance_rad2(bandwidth_hz, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db,
                                                 acceleration_m_s2, range_m, monopulse_slope)
    beta_o = _trk.servo_optimal_bandwidth_hz(beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2,
                                             range_m, monopulse_slope)
    return noise, lag, total, beta_o


@scene_part("closing_target")
def closing_target_looks(range_m, closing_speed_mps, scan_period_s, first_look_range_m):
    """The looks at a closing target, range_m + i v T up to first_look_range_m, as
    :data:`MAX_LOOKS` masked ranges (:func:`diffsense.detection.cumulative.closing_looks`)."""
    return closing_looks(range_m, closing_speed_mps, scan_period_s, first_look_range_m, MAX_LOOKS,
                         where="radar chain, closing_target")
