"""The radar chain's parameter and output tables: names, units (SI, dB explicit), meaning,
defaults (the book's worked examples where they exist) and domains, for the parts and options of
a scene."""

from __future__ import annotations

import math

from diffsense.physics import antennas as _ant
from diffsense.physics import tracking as _trk
from diffsense.sensors.chain import Output, Param, collect
from diffsense.sensors.radar.loss_models import loss_model_parameters
from diffsense.sensors.radar.structure import ATTENUATION_PARTS, CLUTTER_PARTS, MAX_LOOKS, clutter_parts_present, option

__all__ = ["BOOK_BEAMWIDTH_FACTOR", "MAX_LOOKS", "radar_parameters", "radar_outputs"]

#: The book's circular-aperture beamwidth rule θ = 70 λ/d degrees, as a factor on λ/d (rad).
BOOK_BEAMWIDTH_FACTOR = _ant.BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR * math.pi / 180.0


def _noise_parameter(scene):
    if option(scene, "noise_input") == "temperature":
        return Param("system_noise_temperature_k", "K", "system noise temperature Ts = Ta + T0 (F - 1) referred to the "
                     "receiver input (IEEE Std 145; Ts = T0 F = 290 F when Ta = T0); N = k Ts β L_rx", None, 1.0, 1e7)
    return Param("noise_figure_db", "dB", "receiver noise figure NF referred to the receiver input", None, 0.0, 60.0)


def _core_parameters(scene):
    return [
        Param("range_m", "m", "target range R at which SNR, Pd and margins are evaluated", None, 1.0, 1e7),
        Param("peak_power_w", "W", "transmitter peak power Pt (before the transmit loss)", None, 0.0, 1e10, lo_open=True),
        Param("pulse_width_s", "s", "pulse length τ (uncompressed); the echo leaves the IF filter W wide "
              "(τ for a matched filter) and the range resolution is c W / 2", None, 1e-10, 1.0),
        Param("freq_hz", "Hz", "carrier frequency f; λ = c / f (1-300 GHz: the ITU-R models start at 1 GHz)", None, 1e9, 3e11),
        Param("bandwidth_hz", "Hz", "receiver (IF / matched-filter) noise bandwidth β", None, 1e2, 1e11),
        Param("rcs_m2", "m**2", "mean target radar cross-section σ (book 9.9.1: 1 m²)", 1.0, 0.0, 1e9, lo_open=True),
        _noise_parameter(scene),
        Param("transmit_loss_db", "dB", "transmit line / duplexer loss L_tx (book 9.9.1: 2 dB)", 0.0, 0.0, 60.0),
        Param("receive_loss_db", "dB", "receive line loss L_rx, added to the noise (book 9.9.1.3: 2 dB)", 0.0, 0.0, 60.0),
        *loss_model_parameters(scene),
        Param("prf_hz", "Hz", "pulse repetition frequency f_p", None, 0.0, 1e8, lo_open=True),
        Param("n_pulses", "1", "pulses integrated per detection N (real-valued relaxation)", 1.0, 1.0, 1e4, integer=True),
        *_binary_parameters(scene),
        Param("tangential_sensitivity_dbm", "dBm", "detector tangential sensitivity TSS (book 8.16.12: -75 dBm)", -75.0, -200.0, 50.0),
        Param("tss_margin_db", "dB", "working level above TSS for the weakest echo (book 8.16.12: 13 dB)", 13.0, 0.0, 60.0),
        Param("mixer_loss_db", "dB", "mixer conversion loss ahead of the IF amplifier (book 8.16.9.3: 8 dB)", 0.0, 0.0, 60.0),
        Param("rcs_fade_db", "dB", "depth of the RCS fades designed for (book 8.16.11: 15 dB)", 0.0, 0.0, 60.0),
    ]


def _binary_parameters(scene):
    if option(scene, "integration") != "binary":
        return []
    return [Param("binary_m", "1", "M of M-of-N binary integration: a detection needs at least M of the n_pulses pulses "
                  "(N ≤ 100) over their own threshold, M ≤ N (Shnidman 1998: the best M is about 10^-0.02 N^0.8 for "
                  "Swerling 0, 1, 3)", None, 1.0, 100.0, integer=True)]


def _antenna_parameters(scene):
    if option(scene, "antenna") == "circular_aperture":
        return [
            Param("antenna_diameter_m", "m", "circular antenna diameter d", None, 1e-3, 100.0),
            Param("aperture_efficiency", "1", "aperture efficiency ρ in G = 4πρA/λ² (book 8.16.9.1: 0.7 Cassegrain)", 0.7, 0.0, 1.0, lo_open=True),
            Param("beamwidth_factor", "1", "k in θ3dB = k λ / d rad (default the book's 70λ/d deg, 1.2217)", BOOK_BEAMWIDTH_FACTOR, 0.5, 3.0),
        ]
    if option(scene, "antenna") == "rectangular_aperture":
        return [
            Param("aperture_width_m", "m", "horizontal dimension w of a rectangular aperture (sets the azimuth "
                  "beamwidth k λ / w)", None, 1e-3, 100.0),
            Param("aperture_height_m", "m", "vertical dimension h of a rectangular aperture (sets the elevation "
                  "beamwidth k λ / h); not the height above the sea (antenna_height_m)", None, 1e-3, 100.0),
            Param("aperture_efficiency", "1", "aperture efficiency ρ in G = 4πρ w h/λ²", 0.7, 0.0, 1.0, lo_open=True),
            Param("beamwidth_factor", "1", "k in θ3dB = k λ / (w or h) rad (default 0.886: uniform illumination, "
                  "the rectangular aperture of the book's chapter 12 synthetic-aperture listing, asin(0.887 λ/d))", _ant.UNIFORM_RECTANGULAR_BEAMWIDTH_FACTOR, 0.5, 3.0),
        ]
    return [
        Param("gain_db", "dB", "antenna gain G (book 9.9.1: 36 dB)", None, -10.0, 80.0),
        Param("beamwidth_az_deg", "deg", "azimuth 3 dB beamwidth (book 9.9.1: 1.25 deg)", None, 0.0, 90.0, lo_open=True),
        Param("beamwidth_el_deg", "deg", "elevation 3 dB beamwidth (book 9.9.3: 4 deg)", None, 0.0, 90.0, lo_open=True),
    ]


def _detectability_parameters(scene):
    if option(scene, "detectability") == "given":
        return [Param("detectability_db", "dB", "required per-pulse SNR after integration (book 9.9.1.1: 8.2 dB)", None, -40.0, 60.0)]
    return [
        Param("pd", "1", "required probability of detection", 0.9, 0.05, 0.999999),
        Param("pfa", "1", "probability of false alarm per decision", 1e-6, 1e-15, 1e-2),
    ]


def _path_parameters(scene):
    """Gas, rain, fog and dust on the path (and the inputs they share with clutter)."""
    ps = []
    itu_gas = scene.has("gas") and option(scene, "gas_model") in ("itu_p676", "itu_p676_approx")
    if itu_gas:
        ps += [
            Param("pressure_hpa", "hPa", "total air pressure (ITU-R P.676 standard 1013.25)", 1013.25, 100.0, 1200.0, part="gas"),
            Param("water_vapour_g_m3", "g/m**3", "water-vapour density (ITU-R P.676 standard 7.5)", 7.5, 0.0, 50.0, part="gas"),
        ]
    elif scene.has("gas"):
        ps.append(Param("gas_attenuation_db_km", "dB/km", "one-way gas attenuation (book 9.9.1.4: 0.003 at L band)", None, 0.0, 100.0, part="gas"))
    if itu_gas or scene.has("fog"):
        ps.append(Param("air_temperature_k", "K", "air (and fog water) temperature (ITU-R standard 288.15)", 288.15, 233.15, 323.15,
                        part="gas" if itu_gas else "fog"))
    itu_rain = scene.has("rain") and option(scene, "rain_model") == "itu_p838"
    if itu_rain or (scene.has("rain_clutter") and option(scene, "rain_clutter_model") == "marshall_palmer"):
        ps.append(Param("rain_rate_mm_h", "mm/h", "rain rate (book 14.9 design value 25 mm/h)", 25.0, 0.0, 500.0, lo_open=True,
                        part="rain" if itu_rain else "rain_clutter"))
    if scene.has("rain") and option(scene, "rain_model") == "specified":
        ps.append(Param("rain_attenuation_db_km", "dB/km", "one-way rain attenuation (book 9.9.3: 0.02 in heavy rain)", None, 0.0, 100.0, part="rain"))
    if scene.has("fog"):
        ps.append(Param("liquid_water_g_m3", "g/m**3", "fog liquid water content (0.05 medium, 0.5 thick fog)", 0.05, 0.0, 10.0, part="fog"))
    if scene.has("dust") or scene.has("dust_clutter"):
        ps.append(Param("visibility_m", "m", "optical visibility in the dust (book 8.16.2: 20 m)", 20.0, 1.0, 1e5,
                        part="dust" if scene.has("dust") else "dust_clutter"))
    return ps


def _clutter_parameters(scene):
    """Clutter, sea and multipath geometry, and the required SCR."""
    ps = []
    if scene.has("rain_clutter") and option(scene, "rain_clutter_model") == "specified":
        ps.append(Param("rain_reflectivity_m2_m3", "m**2/m**3", "rain volume reflectivity η (book 9.9.3: 1e-7)", None, 0.0, 1e-2, lo_open=True, part="rain_clutter"))
    if scene.has("rain_clutter") or scene.has("dust_clutter"):
        ps.append(Param("beam_shape_factor", "1", "beam-shape factor α of the resolution volume (book 9.9.3: 1.33)", 1.33, 1.0, 2.0,
                        part="rain_clutter" if scene.has("rain_clutter") else "dust_clutter"))
    if scene.has("sea_clutter") or scene.has("multipath"):
        part = "sea_clutter" if scene.has("sea_clutter") else "multipath"
        ps += [
            Param("sea_state", "1", "sea state (continuous; book Table 12.2 wind, WMO wave heights)", 3.0, 0.0, 6.0, lo_open=True, part=part),
            Param("antenna_height_m", "m", "antenna height above the sea (book 14.9: 8 m)", 8.0, 0.0, 1e4, lo_open=True, part=part),
        ]
    if scene.has("multipath"):
        ps.append(Param("target_height_m", "m", "target height above the sea (book 14.9 sea skimmer: 3 m)", 3.0, 0.0, 1e4, lo_open=True, part="multipath"))
    if scene.has("wall_clutter"):
        ps += [
            Param("pass_diameter_m", "m", "ore-pass (shaft) diameter (book 8.16.1: 6 m)", 6.0, 0.0, 100.0, lo_open=True, part="wall_clutter"),
            Param("wall_reflectivity_db", "dB", "mean wall reflectivity σ° (book 8.16.5: -10 dB)", -10.0, -60.0, 20.0, part="wall_clutter"),
        ]
        if option(scene, "wall_illumination") == "gaussian_beam":
            ps.append(Param("sidelobe_level_db", "dB", "one-way antenna sidelobe level relative to the main-beam peak, "
                            "the floor of the beam's weight on the wall (-25 dB: a tapered reflector; uniform circular "
                            "aperture -17.6 dB)", -25.0, -80.0, 0.0, part="wall_clutter"))
    present = clutter_parts_present(scene)
    if present:
        ps.append(Param("required_scr_db", "dB", "signal-to-clutter ratio needed for detection (book 8.16.6: 13 dB)", 13.0, -20.0, 60.0, part=present[0]))
    return ps


def _jammer_parameters(scene):
    if not scene.has("jammer"):
        return []
    ps = [
        Param("jammer_power_w", "W", "jammer power P_j", None, 0.0, 1e7, lo_open=True, part="jammer"),
        Param("jammer_gain_db", "dB", "jammer antenna gain toward the radar G_j", None, -50.0, 80.0, part="jammer"),
        Param("jammer_bandwidth_hz", "Hz", "jammer noise bandwidth β_j", None, 1e2, 1e11, part="jammer"),
    ]
    if option(scene, "jammer_type") == "stand_off":
        ps += [
            Param("jammer_range_m", "m", "stand-off jammer range", None, 1.0, 1e7, part="jammer"),
            Param("jammer_sidelobe_gain_db", "dB", "radar antenna gain toward the stand-off jammer (sidelobe)", None, -50.0, 80.0, part="jammer"),
        ]
    return ps


def _tracking_parameters(scene):
    if not scene.has("tracking"):
        return []
    critical = option(scene, "tracking_gains") == "critically_damped"
    return [
        Param("track_alpha", "1", "position gain α of the α-β range tracker (β from α by the option "
              "tracking_gains; critically damped needs α < 1)", None, 0.0, 1.0, lo_open=True, hi_open=critical,
              part="tracking"),
        Param("target_acceleration_m_s2", "m/s**2", "target acceleration a driving the range and angle lags "
              "(book 13.6 ablag.m: 10 m/s²)", 10.0, 0.0, 1e4, lo_open=True, part="tracking"),
        Param("platform_angular_acceleration_rad_s2", "rad/s**2", "angular acceleration of the platform that reaches "
              "the angle servo, added to a/R (ship motion less the mount's stabilisation; 0: a perfectly "
              "stabilised or fixed mount)", 0.0, 0.0, 100.0, part="tracking"),
        Param("servo_bandwidth_hz", "Hz", "equivalent noise bandwidth β_n of the type-2 angle servo (book 14.7)",
              None, 0.0, 1e3, lo_open=True, part="tracking"),
        Param("monopulse_slope", "1", "monopulse gain constant k_m (book 14.7: typically 1.6)",
              _trk.MONOPULSE_SLOPE_TYPICAL, 0.0, 10.0, lo_open=True, part="tracking"),
        Param("positioner_resonance_hz", "Hz", "lowest natural resonance of the antenna positioner (book "
              "14.6, Fig. 14.19: 10-30 Hz for a 1.5 m antenna)", None, 0.0, 1e4, lo_open=True, part="tracking"),
    ]


def _closing_target_parameters(scene):
    if not scene.has("closing_target"):
        return []
    return [
        Param("closing_speed_mps", "m/s", "closing (radial) speed of the target", None, 0.0, 1e4, lo_open=True,
              part="closing_target"),
        Param("scan_period_s", "s", "time between looks at the target (antenna scan period)", None, 0.0, 1e4,
              lo_open=True, part="closing_target"),
        Param("first_look_range_m", "m", "range of the target's first look (the horizon, or where it appears); "
              f"at most {MAX_LOOKS} looks from there to range_m", None, 1.0, 1e7, part="closing_target"),
    ]


def radar_parameters(scene):
    """``{name: Param}`` of a radar scene, in a fixed order: core, antenna, detectability, path,
    clutter, jammer, tracking."""
    return collect(_core_parameters(scene) + _antenna_parameters(scene) + _detectability_parameters(scene)
                   + _path_parameters(scene) + _clutter_parameters(scene) + _jammer_parameters(scene)
                   + _tracking_parameters(scene) + _closing_target_parameters(scene))


_CORE_OUTPUTS = (
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
    Output("range_resolution_m", "m", "c W / 2: W the half-amplitude width of the echo after the IF filter "
           "(W = τ for the matched filter)"),
    Output("unambiguous_range_m", "m", "c / (2 f_p)"),
    Output("update_rate_hz", "Hz", "f_p / N"),
    Output("duty_cycle", "1", "τ f_p"),
    Output("average_power_w", "W", "Pt τ f_p"),
    Output("eirp_dbw", "dBW", "effective isotropic radiated power 10 log10 Pt - L_tx + G (IEEE Std 686)"),
    Output("power_aperture_w_m2", "W m**2", "power-aperture product Pav A_e, A_e = G λ²/(4π) the effective aperture "
           "(the search radar equation's figure of merit, Barton 2013 §1.4)"),
    Output("minimum_range_m", "m", "c τ / 2: an echo from nearer returns while the pulse is still being transmitted "
           "(the receiver is blanked; Skolnik 2008 §1.2)"),
    Output("first_blind_speed_mps", "m/s", "λ f_p / 2: the radial speed whose Doppler shift equals the PRF, blind "
           "to pulse-to-pulse (MTI) cancellation (Skolnik 2008 §3.2)"),
    Output("range_rate_accuracy_mps", "m/s", "Cramér–Rao bound λ/(4π t_rms sqrt(2 N SNR)) on the range rate measured "
           "over a coherent dwell of the N pulses at range_m, t_rms² = ((N² - 1)/f_p² + τ²)/12, limited by the "
           "spread λ f_p/(2√12) of a rate folded into one blind-speed interval: (σ_CRB⁻² + σ_prior⁻²)^(-1/2) "
           "(diffsense.physics.measurement_accuracy)"),
    Output("if_gain_db", "dB", "IF gain needed for the weakest echo to reach TSS + margin (book 8.16.12)"),
)

_TRACKING_OUTPUTS = (
    Output("track_beta", "1", "velocity gain β of the α-β range tracker"),
    Output("range_noise_m", "m", "split-gate measurement noise σ_R = (c W/2)/(2.5 √(2 SNR)) at range_m (gate c W/2)"),
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
)


def _detection_outputs(scene):
    outs = []
    if option(scene, "detectability") != "given":
        outs += [
            Output("pd", "1", "probability of detection at range_m against noise and jamming (SNR clipped to "
                   "[-50, 80] dB, where Pd is 0 or 1 to float64)"),
            Output("integration_gain_db", "dB", "reduction of the required per-pulse SNR from 1 to N pulses"),
            Output("integrated_snr_db", "dB", "snr_db + integration_gain_db"),
        ]
    if option(scene, "detectability") == "book" and option(scene, "integration") == "noncoherent":
        outs.append(Output("pulses_needed", "1", "pulses for the faded SNR by the book's N^0.8 rule (+7 for the linear detector), unrounded"))
    return outs


def _interference_outputs(scene):
    outs = []
    if any(scene.has(p) for p in ATTENUATION_PARTS):
        outs.append(Output("two_way_attenuation_db", "dB", "total two-way path attenuation at range_m"))
    clutter = any(scene.has(c) for c in CLUTTER_PARTS)
    if clutter:
        outs += [
            Output("scr_db", "dB", "signal-to-clutter ratio at range_m"),
            Output("scr_margin_db", "dB", "scr_db - required_scr_db"),
        ]
    if scene.has("jammer"):
        outs += [
            Output("sjr_db", "dB", "signal-to-jamming ratio at range_m"),
            Output("sjnr_db", "dB", "signal to jamming-plus-noise ratio at range_m"),
        ]
        if option(scene, "jammer_type") == "self_screening":
            outs.append(Output("burn_through_range_m", "m", "range where sjr_db equals required_snr_db"))
    if scene.has("jammer") or clutter:
        outs.append(Output("sinr_db", "dB", "signal to noise-plus-jamming-plus-clutter ratio at range_m"))
    return outs


def radar_outputs(scene):
    """``{name: Output}`` of a radar scene."""
    outs = list(_CORE_OUTPUTS) + _detection_outputs(scene) + _interference_outputs(scene)
    if scene.has("closing_target") and option(scene, "detectability") != "given":
        outs.append(Output("cumulative_pd", "1", "probability that at least one look detects the closing target by "
                           "range_m, 1 - Π(1 - Pd(R_i)) over the looks R_i = range_m + i v T up to first_look_range_m "
                           "(Pd against noise and jamming at each)"))
    if scene.has("tracking"):
        outs += list(_TRACKING_OUTPUTS)
    return {out.name: out for out in outs}
