"""The radar sensor chain (kind ``"radar"``): pulsed monostatic radar link budget, detection,
clutter, jamming and detection range, built from a static :class:`~diffsense.scene.Scene`.

Budget (the book's link-budget table, Brooker §9.9.1 and §8.16.11), top to bottom, every term a
signed dB contribution; the total is the single-pulse SNR ``snr_db`` at ``range_m``::

    peak_power_dbw        10 log10 Pt
    transmit_loss_db      −L_tx
    two_way_gain_db       +2 G
    wavelength_db         10 log10(λ² / (4π)³)
    rcs_dbsm              10 log10 σ
    range_db              −40 log10 R
    scan_loss_db, matched_filter_loss_db, cfar_loss_db, misc_loss_db      −L each
    gas/rain/fog/dust_attenuation_db     −2 α_i R / 1000   (parts present only)
    multipath_db          +40 log10 |F|                     (part present only)
    boltzmann_db          −10 log10(k T0)      (dBW/Hz)
    bandwidth_db          −10 log10 β
    noise_figure_db       −NF
    receive_loss_db       −L_rx

The terms down to ``multipath_db`` sum to the received power Pr (dBW), the last four to minus the
noise power N = k T0 β F L_rx. A practical IF filter is charged with its mismatch loss relative to
the matched filter (detection.matched_filter_loss_db of β τ), as the book does; the option
``matched_filter="matched"`` drops the term (ideal matched filter, book §8.16.9.3).

Interference. Clutter parts give ``scr_db`` = 10 log10(σ F⁴ / Σ σ_clutter) (target and clutter
share range, gain, losses and attenuation; integration does not improve it, book §8.16.6);
a noise jammer adds J to N. Detection needs ``S/(N + J) ≥ SNR_req`` and ``S/C ≥ SCR_req``; the
chain combines them into one smooth criterion, the detection margin

    m(R) = −10 log10( 10^((SNR_req − SJNR(R))/10) + 10^((SCR_req − SCR(R))/10) )   (dB),

i.e. S ≥ SNR_req (N + J) + SCR_req C, never optimistic and at most 3 dB pessimistic where both
limits coincide. ``detection_range_m`` solves m(R) = 0 (book §9.9.1.4: a nonlinear equation once
attenuation enters) with :func:`diffsense.numerics.rootfind.decreasing_root_log` in [1 m, 10,000 km]
(inside 0.99 × the radar horizon with multipath; above the antenna height with sea clutter),
differentiable implicitly; ``detection_range_found`` is 1 where a crossing exists. With multipath
the SNR oscillates with range and the solver returns one crossing inside the bracket, not
necessarily the farthest.

Tracking (part ``"tracking"``), evaluated at ``range_m`` with the single-pulse ``snr_db`` of the
budget (noise only: clutter and jamming are not in the tracking noise):
  * range: an α-β filter sampled at the PRF (T = 1/f_p) smooths a split-gate range tracker of
    gate c τ/2. Measurement noise σ_R = (c τ/2)/(2.5 √(2 SNR)), output noise σ_R √K_x with the
    variance reduction K_x = Σh² of the position transfer function, lag a T²(1 − α)/β behind a
    constant acceleration a, and the book's cost √(lag² + σ²) (book §13.4.1, §13.6 ``ablag.m``).
    β follows α by the Benedict–Bordner relation β = α²/(2 − α) (book eq 13.11) or, with the
    option ``tracking_gains="critically_damped"``, α = 2√β − β (book eq 13.12);
  * angle: a type-2 servo of noise bandwidth β_n with a monopulse error slope k_m: noise
    θ3dB² β_n/(2 k_m² f_p βτ SNR) with θ3dB the azimuth beamwidth and βτ = bandwidth_hz ×
    pulse_width_s, dynamic lag a/(R · 2.5 β_n²) and their sum σ_θ² (book eqs
    14.9-14.11); the bandwidth β_o that minimises σ_θ² (book eq 14.12); and β_n over the
    positioner's lowest resonance, which the book keeps below 10 % (§14.6).
  The same acceleration a drives the range and the angle lag (the book applies eq 14.10 to
  each axis with its own component; here one worst-case value).

Detectability (static option ``detectability``):
  * ``"exact"`` — :func:`diffsense.detection.required_snr_db` (exact Swerling 0-4, real N).
    Noncoherent: required per-pulse SNR for N pulses; coherent: single-pulse value − 10 log10 N.
    The ``"linear"`` detector is evaluated with the square-law statistics: the two differ by
    less than 0.2 dB for all N (Marcum 1960; Skolnik 3rd ed. §2.6); the exact linear-law
    statistics are not in :mod:`diffsense.detection`.
  * ``"book"`` — single-pulse exact value minus the book's postdetection integration gain
    8 log10 N (N^0.8 rule); the linear (SDLA) detector needs 7 more pulses for the same gain
    (8 log10 max(N − 7, 1)), book §8.16.13. Coherent integration: gain 10 log10 N.
    ``pd`` is then Pd(SNR + gain, Pfa, 1 pulse), consistent with the requirement.
  * ``"given"`` — the per-pulse requirement is the parameter ``detectability_db`` (read from the
    book's charts, e.g. 15.2 + 8 − 15 = 8.2 dB in §9.9.1.1); no Pd model, so ``pd`` and the
    integration outputs are not produced.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
from jax.scipy.special import logsumexp

from diffsense.physics import antennas as _ant
from diffsense import detection as _det
from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.physics.constants import BOLTZMANN_J_K, REFERENCE_TEMPERATURE_K, SPEED_OF_LIGHT_M_S
from diffsense.detection.matched_filter import FILTERS
from diffsense.physics.propagation.cloud import cloud_attenuation_db_per_km
from diffsense.physics.propagation.dust import dust_mass_loading_g_m3, dust_radar_attenuation_db_per_km
from diffsense.physics.propagation.gas import gas_attenuation_db_per_km
from diffsense.physics.propagation.rain import rain_attenuation_db_per_km
from diffsense.physics.propagation.refraction import radar_horizon_m
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics import clutter as _clutter
from diffsense.physics import tracking as _trk
from diffsense.sensors.radar import equation as eq

__all__ = ["RadarChain", "PARTS", "OPTIONS", "ATTENUATION_PARTS", "CLUTTER_PARTS"]

_DB = 10.0 / math.log(10.0)
_LN10_10 = math.log(10.0) / 10.0
_C = SPEED_OF_LIGHT_M_S
_PD_SNR_DB = (-50.0, 80.0)  # domain of diffsense.detection.pd; Pd is 0/1 to float64 outside
#: outputs that depend on the required per-pulse SNR (an exact detectability solve)
_USES_REQUIRED_SNR = ("required_snr_db", "snr_margin_db", "faded_snr_margin_db", "detection_margin_db",
                      "detection_range_m", "detection_range_found", "burn_through_range_m")

PARTS = {
    "gas": "atmospheric gases on the whole path (ITU-R P.676-12, or a given specific attenuation)",
    "rain": "rain on the whole path (ITU-R P.838-3, or a given specific attenuation)",
    "fog": "fog / cloud liquid water on the whole path (ITU-R P.840-7)",
    "dust": "dust on the whole path, Rayleigh absorption, mass loading from visibility (book 7.2.6, 8.14.2)",
    "rain_clutter": "rain volume backscatter in the resolution cell (book 8.14, 9.9.3)",
    "dust_clutter": "dust volume backscatter in the resolution cell (book eq 8.45)",
    "sea_clutter": "sea-surface clutter, Barton's constant gamma (book 8.12.4, 8.13)",
    "wall_clutter": "shaft-wall clutter of the ore pass in the range gate c tau/2 seen by the beam (book 8.16.6)",
    "multipath": "two-ray sea multipath on the target path, 40 log10|F| (Blake 1986)",
    "jammer": "noise jammer, self-screening or stand-off (book 9.10)",
    "tracking": "range (alpha-beta filter, split gate) and angle (type-2 servo, monopulse) tracking errors at range_m (book 13.4-13.6, 14.6-14.7)",
}
ATTENUATION_PARTS = ("gas", "rain", "fog", "dust")
CLUTTER_PARTS = ("rain_clutter", "dust_clutter", "sea_clutter", "wall_clutter")

OPTIONS = {
    "swerling": (0, (0, 1, 2, 3, 4)),
    "detector": ("square_law", ("square_law", "linear")),
    "integration": ("noncoherent", ("noncoherent", "coherent")),
    "detectability": ("exact", ("exact", "book", "given")),
    "matched_filter": ("two_tuned", ("matched",) + tuple(FILTERS)),
    "antenna": ("circular_aperture", ("circular_aperture", "specified")),
    "gas_model": ("itu_p676", ("itu_p676", "specified")),
    "rain_model": ("itu_p838", ("itu_p838", "specified")),
    "rain_clutter_model": ("marshall_palmer", ("marshall_palmer", "specified")),
    "polarization": ("horizontal", ("horizontal", "vertical")),
    "jammer_type": ("self_screening", ("self_screening", "stand_off")),
    "wall_illumination": ("gaussian_beam", ("gaussian_beam", "filled")),
    "tracking_gains": ("benedict_bordner", ("benedict_bordner", "critically_damped")),
}

#: The book's circular-aperture beamwidth rule θ = 70 λ/d degrees, as a factor on λ/d (rad).
BOOK_BEAMWIDTH_FACTOR = _ant.BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR * math.pi / 180.0


def _db10(x):
    return _DB * jnp.log(x)


# --- scene parts (each a named sub-program of the traced evaluation) -------------------------


@scene_part("gas")
def gas_itu_attenuation_db_km(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    """One-way specific attenuation of gases (dB/km), ITU-R P.676-12."""
    return gas_attenuation_db_per_km(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)


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
    eta = _clutter.dust_volume_reflectivity_m2_m3(wavelength_m, visibility_m, eq.ROCK_DUST_K_SQUARED)
    return _clutter.volume_clutter_rcs_m2(eta, range_m, bw_az, bw_el, pulse_width_s, beam_shape_factor=beam_shape)


@scene_part("sea_clutter")
def sea_clutter_rcs_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state):
    """Sea clutter σ = γ sin ψ · A (m²), see :func:`diffsense.sensors.radar.equation.sea_clutter_rcs_m2`."""
    return eq.sea_clutter_rcs_m2(range_m, antenna_height_m, bw_az, bw_el, pulse_width_s, wavelength_m, sea_state)


@scene_part("wall_clutter")
def wall_clutter_rcs_gaussian_beam_m2(range_m, pass_diameter_m, range_gate_m, wall_reflectivity_db, beamwidth_rad):
    """Ore-pass wall clutter weighted by the two-way Gaussian beam at the wall angle (m²)."""
    w = eq.wall_illumination_factor(range_m, pass_diameter_m, beamwidth_rad)
    return eq.wall_clutter_rcs_m2(pass_diameter_m, range_gate_m, wall_reflectivity_db, w)


@scene_part("wall_clutter")
def wall_clutter_rcs_filled_m2(range_m, pass_diameter_m, range_gate_m, wall_reflectivity_db):
    """Ore-pass wall clutter when the beam fills the pass (book 8.16.6 worst case) (m²)."""
    return eq.wall_clutter_rcs_m2(pass_diameter_m, range_gate_m, wall_reflectivity_db) * jnp.ones_like(range_m)


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
    return _db10(j) - one_way_attenuation_db


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
    """Split-gate noise σ_R (m), variance reduction K_x and acceleration lag (m) of the α-β
    range tracker sampled at the PRF (book §13.6 ``ablag.m``)."""
    sigma = _trk.split_gate_range_noise_m(gate_m, snr_db)
    vrr = _trk.alpha_beta_position_variance_ratio(alpha, beta)
    lag = _trk.alpha_beta_acceleration_lag_m(acceleration_m_s2, 1.0 / prf_hz, alpha, beta)
    return sigma, vrr, lag


@scene_part("tracking")
def angle_tracking_errors(bandwidth_hz, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2,
                          range_m, monopulse_slope):
    """Servo angle tracking (book eqs 14.9-14.12): thermal-noise variance (rad²), dynamic lag
    (rad) and the optimum noise bandwidth β_o (Hz)."""
    noise = _trk.servo_angle_error_variance_rad2(bandwidth_hz, beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db,
                                                 jnp.zeros_like(acceleration_m_s2), range_m, monopulse_slope)
    lag = _trk.servo_dynamic_lag_rad(acceleration_m_s2 / range_m, bandwidth_hz)
    beta_o = _trk.servo_optimal_bandwidth_hz(beamwidth_rad, prf_hz, bandwidth_pulse_product, snr_db, acceleration_m_s2,
                                             range_m, monopulse_slope)
    return noise, lag, beta_o


# --- the chain --------------------------------------------------------------------------------


def _p(name, unit, doc, default=None, lo=None, hi=None, lo_open=False, hi_open=False, part=None, integer=False):
    return Param(name, unit, doc, default, lo, hi, lo_open, hi_open, part, integer)


class RadarChain(Chain):
    """Pulsed monostatic radar: link budget, detection, clutter, jamming, detection range."""

    kind = "radar"
    description = "pulsed monostatic radar (Brooker ch. 8-9): SNR budget, Pd, clutter, jamming, detection range"
    parts = PARTS
    options = OPTIONS

    # ----- structure -----
    def validate_scene(self, scene):
        super().validate_scene(scene)
        if self.option(scene, "integration") == "coherent" and self.option(scene, "swerling") in (2, 4):
            raise DomainError(
                "radar scene: coherent integration needs echoes that keep their phase over the pulses; "
                "Swerling 2 and 4 decorrelate from pulse to pulse (use integration='noncoherent')"
            )

    def parameters(self, scene):
        o = lambda name: self.option(scene, name)
        ps = [
            _p("range_m", "m", "target range R at which SNR, Pd and margins are evaluated", None, 1.0, 1e7),
            _p("peak_power_w", "W", "transmitter peak power Pt (before the transmit loss)", None, 0.0, 1e10, lo_open=True),
            _p("pulse_width_s", "s", "pulse length τ (uncompressed); range resolution c τ / 2", None, 1e-10, 1.0),
            _p("freq_hz", "Hz", "carrier frequency f; λ = c / f (1-300 GHz: the ITU-R models start at 1 GHz)", None, 1e9, 3e11),
            _p("bandwidth_hz", "Hz", "receiver (IF / matched-filter) noise bandwidth β", None, 1e2, 1e11),
            _p("rcs_m2", "m**2", "mean target radar cross-section σ (book 9.9.1: 1 m²)", 1.0, 0.0, 1e9, lo_open=True),
            _p("noise_figure_db", "dB", "receiver noise figure NF referred to the receiver input", None, 0.0, 60.0),
            _p("transmit_loss_db", "dB", "transmit line / duplexer loss L_tx (book 9.9.1: 2 dB)", 0.0, 0.0, 60.0),
            _p("receive_loss_db", "dB", "receive line loss L_rx, added to the noise (book 9.9.1.3: 2 dB)", 0.0, 0.0, 60.0),
            _p("scan_loss_db", "dB", "beam-shape / scanning loss (book 9.9.1: 1.6 dB for 1-D scan)", 0.0, 0.0, 60.0),
            _p("cfar_loss_db", "dB", "CFAR loss (book 9.9.1: 0.7 dB)", 0.0, 0.0, 60.0),
            _p("misc_loss_db", "dB", "miscellaneous losses (book 9.9.1: 1.3 dB)", 0.0, 0.0, 60.0),
            _p("prf_hz", "Hz", "pulse repetition frequency f_p", None, 0.0, 1e8, lo_open=True),
            _p("n_pulses", "1", "pulses integrated per detection N (real-valued relaxation)", 1.0, 1.0, 1e4, integer=True),
            _p("tangential_sensitivity_dbm", "dBm", "detector tangential sensitivity TSS (book 8.16.12: -75 dBm)", -75.0, -200.0, 50.0),
            _p("tss_margin_db", "dB", "working level above TSS for the weakest echo (book 8.16.12: 13 dB)", 13.0, 0.0, 60.0),
            _p("mixer_loss_db", "dB", "mixer conversion loss ahead of the IF amplifier (book 8.16.9.3: 8 dB)", 0.0, 0.0, 60.0),
            _p("rcs_fade_db", "dB", "depth of the RCS fades designed for (book 8.16.11: 15 dB)", 0.0, 0.0, 60.0),
        ]
        if o("antenna") == "circular_aperture":
            ps += [
                _p("antenna_diameter_m", "m", "circular antenna diameter d", None, 1e-3, 100.0),
                _p("aperture_efficiency", "1", "aperture efficiency ρ in G = 4πρA/λ² (book 8.16.9.1: 0.7 Cassegrain)", 0.7, 0.0, 1.0, lo_open=True),
                _p("beamwidth_factor", "1", "k in θ3dB = k λ / d rad (default the book's 70λ/d deg, 1.2217)", BOOK_BEAMWIDTH_FACTOR, 0.5, 3.0),
            ]
        else:
            ps += [
                _p("gain_db", "dB", "antenna gain G (book 9.9.1: 36 dB)", None, -10.0, 80.0),
                _p("beamwidth_az_deg", "deg", "azimuth 3 dB beamwidth (book 9.9.1: 1.25 deg)", None, 0.0, 90.0, lo_open=True),
                _p("beamwidth_el_deg", "deg", "elevation 3 dB beamwidth (book 9.9.3: 4 deg)", None, 0.0, 90.0, lo_open=True),
            ]
        if o("detectability") == "given":
            ps.append(_p("detectability_db", "dB", "required per-pulse SNR after integration (book 9.9.1.1: 8.2 dB)", None, -40.0, 60.0))
        else:
            ps += [
                _p("pd", "1", "required probability of detection", 0.9, 0.05, 0.999999),
                _p("pfa", "1", "probability of false alarm per decision", 1e-6, 1e-15, 1e-2),
            ]
        if scene.has("gas"):
            if o("gas_model") == "itu_p676":
                ps += [
                    _p("pressure_hpa", "hPa", "total air pressure (ITU-R P.676 standard 1013.25)", 1013.25, 100.0, 1200.0, part="gas"),
                    _p("water_vapour_g_m3", "g/m**3", "water-vapour density (ITU-R P.676 standard 7.5)", 7.5, 0.0, 50.0, part="gas"),
                ]
            else:
                ps.append(_p("gas_attenuation_db_km", "dB/km", "one-way gas attenuation (book 9.9.1.4: 0.003 at L band)", None, 0.0, 100.0, part="gas"))
        if (scene.has("gas") and o("gas_model") == "itu_p676") or scene.has("fog"):
            part = "gas" if scene.has("gas") and o("gas_model") == "itu_p676" else "fog"
            ps.append(_p("air_temperature_k", "K", "air (and fog water) temperature (ITU-R standard 288.15)", 288.15, 233.15, 323.15, part=part))
        rain_rate_needed = (scene.has("rain") and o("rain_model") == "itu_p838") or (
            scene.has("rain_clutter") and o("rain_clutter_model") == "marshall_palmer")
        if rain_rate_needed:
            part = "rain" if scene.has("rain") and o("rain_model") == "itu_p838" else "rain_clutter"
            ps.append(_p("rain_rate_mm_h", "mm/h", "rain rate (book 14.9 design value 25 mm/h)", 25.0, 0.0, 500.0, lo_open=True, part=part))
        if scene.has("rain") and o("rain_model") == "specified":
            ps.append(_p("rain_attenuation_db_km", "dB/km", "one-way rain attenuation (book 9.9.3: 0.02 in heavy rain)", None, 0.0, 100.0, part="rain"))
        if scene.has("fog"):
            ps.append(_p("liquid_water_g_m3", "g/m**3", "fog liquid water content (0.05 medium, 0.5 thick fog)", 0.05, 0.0, 10.0, part="fog"))
        if scene.has("dust") or scene.has("dust_clutter"):
            part = "dust" if scene.has("dust") else "dust_clutter"
            ps.append(_p("visibility_m", "m", "optical visibility in the dust (book 8.16.2: 20 m)", 20.0, 1.0, 1e5, part=part))
        if scene.has("rain_clutter") and o("rain_clutter_model") == "specified":
            ps.append(_p("rain_reflectivity_m2_m3", "m**2/m**3", "rain volume reflectivity η (book 9.9.3: 1e-7)", None, 0.0, 1e-2, lo_open=True, part="rain_clutter"))
        if scene.has("rain_clutter") or scene.has("dust_clutter"):
            part = "rain_clutter" if scene.has("rain_clutter") else "dust_clutter"
            ps.append(_p("beam_shape_factor", "1", "beam-shape factor α of the resolution volume (book 9.9.3: 1.33)", 1.33, 1.0, 2.0, part=part))
        if scene.has("sea_clutter") or scene.has("multipath"):
            part = "sea_clutter" if scene.has("sea_clutter") else "multipath"
            ps += [
                _p("sea_state", "1", "sea state (continuous; book Table 12.2 wind, WMO wave heights)", 3.0, 0.0, 6.0, lo_open=True, part=part),
                _p("antenna_height_m", "m", "antenna height above the sea (book 14.9: 8 m)", 8.0, 0.0, 1e4, lo_open=True, part=part),
            ]
        if scene.has("multipath"):
            ps.append(_p("target_height_m", "m", "target height above the sea (book 14.9 sea skimmer: 3 m)", 3.0, 0.0, 1e4, lo_open=True, part="multipath"))
        if scene.has("wall_clutter"):
            ps += [
                _p("pass_diameter_m", "m", "ore-pass (shaft) diameter (book 8.16.1: 6 m)", 6.0, 0.0, 100.0, lo_open=True, part="wall_clutter"),
                _p("wall_reflectivity_db", "dB", "mean wall reflectivity σ° (book 8.16.5: -10 dB)", -10.0, -60.0, 20.0, part="wall_clutter"),
            ]
        present_clutter = [c for c in CLUTTER_PARTS if scene.has(c)]
        if present_clutter:
            ps.append(_p("required_scr_db", "dB", "signal-to-clutter ratio needed for detection (book 8.16.6: 13 dB)", 13.0, -20.0, 60.0, part=present_clutter[0]))
        if scene.has("jammer"):
            ps += [
                _p("jammer_power_w", "W", "jammer power P_j", None, 0.0, 1e7, lo_open=True, part="jammer"),
                _p("jammer_gain_db", "dB", "jammer antenna gain toward the radar G_j", None, -50.0, 80.0, part="jammer"),
                _p("jammer_bandwidth_hz", "Hz", "jammer noise bandwidth β_j", None, 1e2, 1e11, part="jammer"),
            ]
            if o("jammer_type") == "stand_off":
                ps += [
                    _p("jammer_range_m", "m", "stand-off jammer range", None, 1.0, 1e7, part="jammer"),
                    _p("jammer_sidelobe_gain_db", "dB", "radar antenna gain toward the stand-off jammer (sidelobe)", None, -50.0, 80.0, part="jammer"),
                ]
        if scene.has("tracking"):
            critical = o("tracking_gains") == "critically_damped"
            ps += [
                _p("track_alpha", "1", "position gain α of the α-β range tracker (β from α by the option "
                   "tracking_gains; critically damped needs α < 1)", None, 0.0, 1.0, lo_open=True, hi_open=critical,
                   part="tracking"),
                _p("target_acceleration_m_s2", "m/s**2", "target acceleration a driving the range and angle lags "
                   "(book 13.6 ablag.m: 10 m/s²)", 10.0, 0.0, 1e4, lo_open=True, part="tracking"),
                _p("servo_bandwidth_hz", "Hz", "equivalent noise bandwidth β_n of the type-2 angle servo (book 14.7)",
                   None, 0.0, 1e3, lo_open=True, part="tracking"),
                _p("monopulse_slope", "1", "monopulse gain constant k_m (book 14.7: typically 1.6)",
                   _trk.MONOPULSE_SLOPE_TYPICAL, 0.0, 10.0, lo_open=True, part="tracking"),
                _p("positioner_resonance_hz", "Hz", "lowest natural resonance of the antenna positioner (book "
                   "14.6, Fig. 14.19: 10-30 Hz for a 1.5 m antenna)", None, 0.0, 1e4, lo_open=True, part="tracking"),
            ]
        return collect(ps)

    def outputs(self, scene):
        o = lambda name: self.option(scene, name)
        outs = [
            Output("snr_db", "dB", "single-pulse SNR at range_m (budget total)"),
            Output("received_power_dbm", "dBm", "peak echo power at the antenna port, after processing losses and propagation"),
            Output("noise_power_dbm", "dBm", "receiver noise k T0 β F L_rx"),
            Output("required_snr_db", "dB", "per-pulse SNR required for pd, pfa with n_pulses (detectability)"),
            Output("snr_margin_db", "dB", "snr_db - required_snr_db (noise only)"),
            Output("faded_snr_margin_db", "dB", "snr_db - rcs_fade_db - required_snr_db: the margin in the deepest RCS fade designed for (book 8.16.11)"),
            Output("detection_margin_db", "dB", "combined criterion m(range_m) including jamming and clutter"),
            Output("detection_range_m", "m", "range where the detection margin reaches 0"),
            Output("detection_range_found", "1", "1 where the detection range lies inside the search bracket, else 0"),
            Output("wavelength_m", "m", "λ = c / f"),
            Output("gain_db", "dB", "antenna gain"),
            Output("beamwidth_deg", "deg", "azimuth 3 dB beamwidth"),
            Output("beamwidth_el_deg", "deg", "elevation 3 dB beamwidth"),
            Output("range_resolution_m", "m", "c τ / 2"),
            Output("unambiguous_range_m", "m", "c / (2 f_p)"),
            Output("update_rate_hz", "Hz", "f_p / N"),
            Output("duty_cycle", "1", "τ f_p"),
            Output("average_power_w", "W", "Pt τ f_p"),
            Output("if_gain_db", "dB", "IF gain needed for the weakest echo to reach TSS + margin (book 8.16.12)"),
        ]
        if o("detectability") != "given":
            outs += [
                Output("pd", "1", "probability of detection at range_m against noise and jamming (SNR clipped to "
                       "[-50, 80] dB, where Pd is 0 or 1 to float64)"),
                Output("integration_gain_db", "dB", "reduction of the required per-pulse SNR from 1 to N pulses"),
                Output("integrated_snr_db", "dB", "snr_db + integration_gain_db"),
            ]
        if o("detectability") == "book" and o("integration") == "noncoherent":
            outs.append(Output("pulses_needed", "1", "pulses for the faded SNR by the book's N^0.8 rule (+7 for the linear detector), unrounded"))
        if any(scene.has(p) for p in ATTENUATION_PARTS):
            outs.append(Output("two_way_attenuation_db", "dB", "total two-way path attenuation at range_m"))
        if any(scene.has(c) for c in CLUTTER_PARTS):
            outs += [
                Output("scr_db", "dB", "signal-to-clutter ratio at range_m"),
                Output("scr_margin_db", "dB", "scr_db - required_scr_db"),
            ]
        if scene.has("jammer"):
            outs += [
                Output("sjr_db", "dB", "signal-to-jamming ratio at range_m"),
                Output("sjnr_db", "dB", "signal to jamming-plus-noise ratio at range_m"),
            ]
            if o("jammer_type") == "self_screening":
                outs.append(Output("burn_through_range_m", "m", "range where sjr_db equals required_snr_db"))
        if scene.has("jammer") or any(scene.has(c) for c in CLUTTER_PARTS):
            outs.append(Output("sinr_db", "dB", "signal to noise-plus-jamming-plus-clutter ratio at range_m"))
        if scene.has("tracking"):
            outs += [
                Output("track_beta", "1", "velocity gain β of the α-β range tracker"),
                Output("range_noise_m", "m", "split-gate measurement noise σ_R = (c τ/2)/(2.5 √(2 SNR)) at range_m"),
                Output("range_variance_reduction", "1", "K_x = Σh², output over input noise variance of the α-β filter"),
                Output("range_track_noise_m", "m", "range noise after the α-β filter σ_R √K_x"),
                Output("range_lag_m", "m", "steady lag of the smoothed range behind the acceleration, a T²(1 − α)/β"),
                Output("range_track_error_m", "m", "√(lag² + (σ_R √K_x)²), the book's range tracking cost"),
                Output("angle_noise_rad", "rad", "rms thermal-noise angle error of the servo (book eq 14.11, first term)"),
                Output("angle_lag_rad", "rad", "servo dynamic lag a/(R 2.5 β_n²) (book eq 14.10)"),
                Output("angle_error_rad", "rad", "rms angle tracking error √σ_θ² (book eq 14.11)"),
                Output("cross_range_error_m", "m", "range_m × angle_error_rad"),
                Output("servo_optimal_bandwidth_hz", "Hz", "servo noise bandwidth minimising σ_θ² (book eq 14.12)"),
                Output("servo_resonance_ratio", "1", "β_n over the positioner resonance (book 14.6: below 0.1)"),
            ]
        return {out.name: out for out in outs}

    # ----- evaluation -----
    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the exact detectability solves, Pd series and range root finds that no wanted output
        needs are not traced (see :class:`diffsense.sensors.chain.Chain`)."""
        o = lambda name: self.option(scene, name)
        swerling = o("swerling")
        lam = _C / p["freq_hz"]
        tau = p["pulse_width_s"]
        beta = p["bandwidth_hz"]
        r0 = p["range_m"]
        if scene.has("multipath") and all(is_concrete(x) for x in (r0, p["antenna_height_m"], p["target_height_m"])):
            with jax.ensure_compile_time_eval():  # concrete inputs: evaluate eagerly even under a trace
                horizon = radar_horizon_m(p["antenna_height_m"], p["target_height_m"])
                outside = bool(jnp.any(r0 >= horizon))
            if outside:
                raise DomainError("radar chain, multipath: 'range_m' must lie inside the radar horizon "
                                  f"d(h_antenna) + d(h_target) = {float(jnp.min(horizon)):.1f} m")

        # antenna
        if o("antenna") == "circular_aperture":
            d = p["antenna_diameter_m"]
            gain_db = _db10(_ant.gain_from_aperture(_ant.circular_aperture_area_m2(d), lam, p["aperture_efficiency"]))
            bw_az = _ant.beamwidth_rad(lam, d, p["beamwidth_factor"])
            bw_el = bw_az
        else:
            gain_db = p["gain_db"]
            bw_az = jnp.deg2rad(p["beamwidth_az_deg"])
            bw_el = jnp.deg2rad(p["beamwidth_el_deg"])

        # matched-filter mismatch
        mf = o("matched_filter")
        if mf == "matched":
            mf_loss = None
        else:
            bt = beta * tau
            if is_concrete(bt):
                lo, hi = (0.01, 2.86) if mf == "rectangular" else (0.01, 50.0)
                check_range("bandwidth_hz * pulse_width_s", bt, lo, hi, where=f"radar chain, matched_filter={mf!r}")
            mf_loss = _det.matched_filter_loss_db(bt, mf)

        # specific attenuations (dB/km one way), independent of range
        alphas = {}
        if scene.has("gas"):
            if o("gas_model") == "itu_p676":
                alphas["gas"] = gas_itu_attenuation_db_km(p["freq_hz"], p["pressure_hpa"], p["air_temperature_k"], p["water_vapour_g_m3"])
            else:
                alphas["gas"] = gas_given_attenuation_db_km(p["gas_attenuation_db_km"])
        if scene.has("rain"):
            if o("rain_model") == "itu_p838":
                tilt = 0.0 if o("polarization") == "horizontal" else 90.0
                alphas["rain"] = rain_itu_attenuation_db_km(p["freq_hz"], p["rain_rate_mm_h"], jnp.asarray(tilt))
            else:
                alphas["rain"] = rain_given_attenuation_db_km(p["rain_attenuation_db_km"])
        if scene.has("fog"):
            alphas["fog"] = fog_attenuation_db_km(p["freq_hz"], p["liquid_water_g_m3"], p["air_temperature_k"])
        if scene.has("dust"):
            alphas["dust"] = dust_attenuation_db_km(p["freq_hz"], p["visibility_m"])
        alpha_total = sum(alphas.values()) if alphas else None

        multipath_fn = None
        if scene.has("multipath"):
            fn = multipath_horizontal_db if o("polarization") == "horizontal" else multipath_vertical_db
            multipath_fn = lambda r: fn(r, p["antenna_height_m"], p["target_height_m"], p["freq_hz"], p["sea_state"])

        # range-independent signal terms and the noise
        const_terms = [
            ("peak_power_dbw", _db10(p["peak_power_w"])),
            ("transmit_loss_db", -p["transmit_loss_db"]),
            ("two_way_gain_db", 2.0 * gain_db),
            ("wavelength_db", 2.0 * _db10(lam) - eq.FOUR_PI_CUBED_DB),
            ("rcs_dbsm", _db10(p["rcs_m2"])),
        ]
        loss_terms = [("scan_loss_db", -p["scan_loss_db"])]
        if mf_loss is not None:
            loss_terms.append(("matched_filter_loss_db", -mf_loss))
        loss_terms += [("cfar_loss_db", -p["cfar_loss_db"]), ("misc_loss_db", -p["misc_loss_db"])]
        noise_terms = [
            ("boltzmann_db", -_DB * math.log(BOLTZMANN_J_K * REFERENCE_TEMPERATURE_K) * jnp.ones_like(beta)),
            ("bandwidth_db", -_db10(beta)),
            ("noise_figure_db", -p["noise_figure_db"]),
            ("receive_loss_db", -p["receive_loss_db"]),
        ]
        signal_const = sum(v for _, v in const_terms + loss_terms)
        noise_dbw = -sum(v for _, v in noise_terms)

        def range_terms(r):
            terms = [("range_db", -4.0 * _db10(r))]
            for name, a in alphas.items():
                terms.append((f"{name}_attenuation_db", -2.0 * a * r / 1e3))
            if multipath_fn is not None:
                terms.append(("multipath_db", multipath_fn(r)))
            return terms

        def signal_dbw(r):
            """Received echo power (dBW) and the multipath term (or None) at range r."""
            terms = range_terms(r)
            mp = dict(terms).get("multipath_db")
            return signal_const + sum(v for _, v in terms), mp

        def jamming_dbw(r):
            if o("jammer_type") == "self_screening":
                rj, gr = r, gain_db
            else:
                rj, gr = p["jammer_range_m"], p["jammer_sidelobe_gain_db"]
            att = alpha_total * rj / 1e3 if alpha_total is not None else jnp.zeros_like(rj)
            return jamming_power_dbw(p["jammer_power_w"], p["jammer_gain_db"], gr, lam, rj, p["jammer_bandwidth_hz"], beta, att)

        clutter_present = [c for c in CLUTTER_PARTS if scene.has(c)]

        def clutter_rcs_m2(r):
            total = 0.0
            if scene.has("rain_clutter"):
                if o("rain_clutter_model") == "marshall_palmer":
                    total = total + rain_clutter_rcs_marshall_palmer_m2(r, p["rain_rate_mm_h"], lam, bw_az, bw_el, tau, p["beam_shape_factor"])
                else:
                    total = total + rain_clutter_rcs_given_m2(r, p["rain_reflectivity_m2_m3"], bw_az, bw_el, tau, p["beam_shape_factor"])
            if scene.has("dust_clutter"):
                total = total + dust_clutter_rcs_m2(r, p["visibility_m"], lam, bw_az, bw_el, tau, p["beam_shape_factor"])
            if scene.has("sea_clutter"):
                total = total + sea_clutter_rcs_m2(r, p["antenna_height_m"], bw_az, bw_el, tau, lam, p["sea_state"])
            if scene.has("wall_clutter"):
                gate = eq.range_resolution_m(tau)
                if o("wall_illumination") == "gaussian_beam":
                    total = total + wall_clutter_rcs_gaussian_beam_m2(r, p["pass_diameter_m"], gate, p["wall_reflectivity_db"], bw_az)
                else:
                    total = total + wall_clutter_rcs_filled_m2(r, p["pass_diameter_m"], gate, p["wall_reflectivity_db"])
            return total

        def scr_db(r, mp):
            target = _db10(p["rcs_m2"])
            if mp is not None:
                target = target + mp
            return target - _db10(clutter_rcs_m2(r))

        def sjnr_db(r, s):
            if not scene.has("jammer"):
                return s - noise_dbw
            j = jamming_dbw(r)
            return s - _DB * jnp.logaddexp(noise_dbw / _DB, j / _DB)

        # detectability
        req, gain, req1 = self._required_snr(scene, p, wanted)
        req_scr = p["required_scr_db"] if clutter_present else None

        def margin_db(r):
            s, mp = signal_dbw(r)
            a = (req - sjnr_db(r, s)) * _LN10_10
            if not clutter_present:
                return -a / _LN10_10
            b = (req_scr - scr_db(r, mp)) * _LN10_10
            return -logsumexp(jnp.stack(jnp.broadcast_arrays(a, b)), axis=0) / _LN10_10

        # budget at range_m
        bb = BudgetBuilder()
        for name, v in const_terms:
            bb.add(name, v)
        rterms = dict(range_terms(r0))
        bb.add("range_db", rterms.pop("range_db"))
        for name, v in loss_terms:
            bb.add(name, v)
        for name, v in rterms.items():
            bb.add(name, v)
        for name, v in noise_terms:
            bb.add(name, v)
        budget = bb.build()
        snr = budget.total
        s0, mp0 = signal_dbw(r0)

        # search bracket
        lo = jnp.asarray(eq.RANGE_SEARCH_M[0])
        hi = jnp.asarray(eq.RANGE_SEARCH_M[1])
        if scene.has("sea_clutter"):
            lo = jnp.maximum(lo, 1.0 + p["antenna_height_m"])
        if scene.has("multipath"):
            lo = jnp.maximum(lo, 1.0 + jnp.abs(p["antenna_height_m"] - p["target_height_m"]))
            hi = jnp.minimum(hi, 0.99 * radar_horizon_m(p["antenna_height_m"], p["target_height_m"]))

        v = {"snr_db": snr, "received_power_dbm": s0 + 30.0, "noise_power_dbm": noise_dbw + 30.0}
        if req is not None:
            v.update({
                "required_snr_db": req,
                "snr_margin_db": snr - req,
                "faded_snr_margin_db": snr - p["rcs_fade_db"] - req,
                "detection_margin_db": margin_db(r0),
            })
        if needs(wanted, "detection_range_m", "detection_range_found"):
            root = decreasing_root_log(margin_db, lo, hi)
            v["detection_range_m"] = root.root
            v["detection_range_found"] = jnp.where(root.bracketed, 1.0, 0.0)
        v.update({
            "wavelength_m": lam,
            "gain_db": gain_db,
            "beamwidth_deg": jnp.rad2deg(bw_az),
            "beamwidth_el_deg": jnp.rad2deg(bw_el),
            "range_resolution_m": eq.range_resolution_m(tau),
            "unambiguous_range_m": eq.unambiguous_range_m(p["prf_hz"]),
            "update_rate_hz": eq.update_rate_hz(p["prf_hz"], p["n_pulses"]),
            "duty_cycle": tau * p["prf_hz"],
            "average_power_w": p["peak_power_w"] * tau * p["prf_hz"],
            "if_gain_db": eq.if_gain_required_db(s0 + 30.0, p["receive_loss_db"], p["mixer_loss_db"], p["rcs_fade_db"],
                                                 p["tangential_sensitivity_dbm"], p["tss_margin_db"]),
        })
        if o("detectability") != "given":
            if needs(wanted, "pd"):
                s_for_pd = sjnr_db(r0, s0)
                n = p["n_pulses"]
                if o("detectability") == "exact" and o("integration") == "noncoherent":
                    v["pd"] = _det.pd(jnp.clip(s_for_pd, *_PD_SNR_DB), p["pfa"], n, swerling)
                else:
                    v["pd"] = _det.pd(jnp.clip(s_for_pd + gain, *_PD_SNR_DB), p["pfa"], jnp.ones_like(n), swerling)
            if gain is not None:
                v["integration_gain_db"] = gain
                v["integrated_snr_db"] = snr + gain
            if o("detectability") == "book" and o("integration") == "noncoherent" and req1 is not None:
                needed = jnp.maximum(req1 - (snr - p["rcs_fade_db"]), 0.0)
                extra = _det.BOOK_SDLA_EXTRA_PULSES if o("detector") == "linear" else 0.0
                v["pulses_needed"] = 10.0 ** (needed / 8.0) + extra
        if alphas:
            v["two_way_attenuation_db"] = 2.0 * alpha_total * r0 / 1e3
        if clutter_present:
            scr0 = scr_db(r0, mp0)
            v["scr_db"] = scr0
            v["scr_margin_db"] = scr0 - req_scr
        if scene.has("jammer"):
            v["sjr_db"] = s0 - jamming_dbw(r0)
            v["sjnr_db"] = sjnr_db(r0, s0)
            if o("jammer_type") == "self_screening" and needs(wanted, "burn_through_range_m"):
                bt_root = decreasing_root_log(lambda r: signal_dbw(r)[0] - jamming_dbw(r) - req, lo, hi)
                v["burn_through_range_m"] = bt_root.root
        if scene.has("jammer") or clutter_present:
            parts_db = [noise_dbw / _DB]
            if scene.has("jammer"):
                parts_db.append(jamming_dbw(r0) / _DB)
            if clutter_present:
                parts_db.append((s0 - v["scr_db"]) / _DB)
            interference = _DB * logsumexp(jnp.stack(jnp.broadcast_arrays(*parts_db)), axis=0)
            v["sinr_db"] = s0 - interference
        if scene.has("tracking"):
            v.update(self._tracking(scene, p, snr, bw_az))
        return Evaluation(budget, v)

    def _tracking(self, scene, p, snr_db, beamwidth_rad):
        """Range and angle tracking outputs at range_m (part "tracking")."""
        alpha = p["track_alpha"]
        if self.option(scene, "tracking_gains") == "critically_damped":
            beta = tracking_beta_critically_damped(alpha)
        else:
            beta = tracking_beta_benedict_bordner(alpha)
        accel = p["target_acceleration_m_s2"]
        sigma, vrr, lag = range_tracking_errors(alpha, beta, eq.range_resolution_m(p["pulse_width_s"]), snr_db,
                                                p["prf_hz"], accel)
        track_noise = sigma * jnp.sqrt(vrr)
        bn = p["servo_bandwidth_hz"]
        noise_var, angle_lag, beta_o = angle_tracking_errors(bn, beamwidth_rad, p["prf_hz"],
                                                             p["bandwidth_hz"] * p["pulse_width_s"], snr_db, accel,
                                                             p["range_m"], p["monopulse_slope"])
        angle_error = jnp.sqrt(noise_var + angle_lag * angle_lag)
        return {
            "track_beta": beta,
            "range_noise_m": sigma,
            "range_variance_reduction": vrr,
            "range_track_noise_m": track_noise,
            "range_lag_m": lag,
            "range_track_error_m": jnp.sqrt(lag * lag + track_noise * track_noise),
            "angle_noise_rad": jnp.sqrt(noise_var),
            "angle_lag_rad": angle_lag,
            "angle_error_rad": angle_error,
            "cross_range_error_m": p["range_m"] * angle_error,
            "servo_optimal_bandwidth_hz": beta_o,
            "servo_resonance_ratio": bn / p["positioner_resonance_hz"],
        }

    def _required_snr(self, scene, p, wanted=None):
        """(required per-pulse SNR, integration gain, single-pulse requirement) in dB.

        Each entry is None when no output in ``wanted`` needs it (``wanted`` None: every output).
        The required SNR serves :data:`_USES_REQUIRED_SNR`; the gain ``integration_gain_db``,
        ``integrated_snr_db`` and, outside exact noncoherent detectability, ``pd``; the
        single-pulse requirement ``pulses_needed``, and it enters the required SNR (book and
        coherent: req1 − gain) or the gain (exact noncoherent: req1 − req_N).
        """
        o = lambda name: self.option(scene, name)
        if o("detectability") == "given":
            return p["detectability_db"], None, None
        swerling = o("swerling")
        n = p["n_pulses"]
        need_req = needs(wanted, *_USES_REQUIRED_SNR)
        need_gain = needs(wanted, "integration_gain_db", "integrated_snr_db")
        single = lambda: _det.required_snr_db(p["pd"], p["pfa"], jnp.ones_like(n), swerling)
        if o("integration") == "coherent" or o("detectability") == "book":
            if o("integration") == "coherent":
                gain = _DB * jnp.log(n)
            else:
                n_eff = n - _det.BOOK_SDLA_EXTRA_PULSES if o("detector") == "linear" else n
                gain = _det.book_integration_gain_db(jnp.maximum(n_eff, 1.0))
            req1 = single() if need_req or needs(wanted, "pulses_needed") else None
            return (req1 - gain if need_req else None), gain, req1
        # exact, noncoherent: the requirement for N pulses is solved directly
        reqn = _det.required_snr_db(p["pd"], p["pfa"], n, swerling) if need_req or need_gain else None
        req1 = single() if need_gain else None
        return reqn, (req1 - reqn if need_gain else None), req1
