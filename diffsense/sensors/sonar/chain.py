"""Sonar: source level, the sonar equations, detection threshold, side-scan geometry and the
``"sonar"`` sensor chain.

Physics reused from the rest of the package: absorption and spreading
(:mod:`diffsense.physics.propagation.acoustic`), sea noise and hydrophone voltages (:mod:`diffsense.physics.noise`),
reverberation and scattering strengths (:mod:`diffsense.physics.clutter`), target strengths
(:mod:`diffsense.physics.targets`), directivity (:mod:`diffsense.physics.antennas`) and the detection layer
(:mod:`diffsense.detection`).

Sources
-------
- G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009), ch. 12: side-scan
  sonar §12.7-12.8, eqs (12.37)-(12.66), Tables 12.1-12.2; reverberation §8.15, eqs (8.47)-(8.48).
- R. J. Urick, *Principles of Underwater Sound*, 3rd ed. (McGraw-Hill, 1983): the sonar equations
  (ch. 2), source level from acoustic power (ch. 4), detection threshold and the detection index
  of the receiver operating characteristic (ch. 12).
- W. W. Peterson, T. G. Birdsall and W. C. Fox, "The theory of signal detectability", Trans. IRE
  PGIT-4, 171-212 (1954): the Gaussian ROC, d = (Φ⁻¹(Pd) − Φ⁻¹(Pfa))².

Decibel conventions: levels are dB re 1 µPa (pressure) at 1 m for source levels; noise spectrum
levels are dB re 1 µPa²/Hz; target and scattering strengths dB re 1 m (1 m², 1 m³ per unit).
"""

from __future__ import annotations

from typing import Dict

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtr, ndtri

from diffsense.physics import antennas, clutter, noise, targets
from diffsense import detection
from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.detection.single_pulse import single_pulse_pd, single_pulse_required_snr_db
from diffsense.physics.propagation import acoustic
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "SOURCE_LEVEL_CONSTANT_DB",
    "acoustic_impedance_rayl",
    "isotropic_intensity_w_m2",
    "sound_pressure_level_db",
    "source_level_db",
    "source_level_from_acoustic_power_db",
    "drive_voltage_rms_v",
    "source_level_from_tvr_db",
    "equivalent_pressure_level_db",
    "echo_level_db",
    "active_signal_excess_noise_db",
    "active_signal_excess_reverberation_db",
    "passive_signal_excess_db",
    "detection_index",
    "pd_from_detection_index",
    "detection_threshold_known_signal_db",
    "detection_threshold_energy_db",
    "detection_threshold_db",
    "pulse_range_resolution_m",
    "chirp_range_resolution_m",
    "cross_range_resolution_m",
    "max_prf_hz",
    "duty_cycle",
    "max_pulse_length_s",
    "pulse_compression_gain_db",
    "SonarChain",
]

_LN10 = float(np.log(10.0))
_DEG = float(np.pi / 180.0)


def _db10(x):
    return (10.0 / _LN10) * jnp.log(x)


def _db20(x):
    return (20.0 / _LN10) * jnp.log(x)


def _power_sum_db(a_db, b_db):
    """10 log10(10^(a/10) + 10^(b/10)), stable for any magnitudes."""
    k = _LN10 / 10.0
    return jnp.logaddexp(a_db * k, b_db * k) / k


def _increment_db(x_db):
    """10 log10(1 + 10^(x/10)) (the rise of a level when a second one x dB above it is added)."""
    k = _LN10 / 10.0
    return jnp.logaddexp(0.0, x_db * k) / k


# ---------------------------------------------------------------------------------------------
# Source level
# ---------------------------------------------------------------------------------------------


def acoustic_impedance_rayl(density_kg_m3, sound_speed_m_s):
    """Characteristic acoustic impedance ``Z = ρ c`` (kg m⁻² s⁻¹, i.e. rayl).

    Book eq (12.45): 1026.4 × 1522 = 1.56e6 rayl for sea water; eq (13.28): 1.229 × 340 = 418
    rayl for air. Exact for a plane progressive wave.

    Args:
        density_kg_m3: density ρ (kg/m³), in (0, ∞).
        sound_speed_m_s: sound speed c (m/s), in (0, ∞).
    """
    w = "acoustic_impedance_rayl"
    check_range("density_kg_m3", density_kg_m3, 0.0, None, lo_open=True, where=w)
    check_range("sound_speed_m_s", sound_speed_m_s, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(density_kg_m3) * jnp.asarray(sound_speed_m_s)


def isotropic_intensity_w_m2(electrical_power_w, efficiency, range_m=1.0):
    """Intensity of an omnidirectional projector ``I = P η / (4π R²)`` (W/m²).

    Book eq (12.42): 1500 W × 0.4 / 4π = 47.7 W/m² at 1 m. Exact (far field, lossless medium).

    Args:
        electrical_power_w: electrical input power P (W), in (0, ∞).
        efficiency: electro-acoustic conversion efficiency η, in (0, 1].
        range_m: distance R (m), in (0, ∞); 1 m for a source level.
    """
    w = "isotropic_intensity_w_m2"
    check_range("electrical_power_w", electrical_power_w, 0.0, None, lo_open=True, where=w)
    check_range("efficiency", efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    r = jnp.asarray(range_m)
    return jnp.asarray(electrical_power_w) * jnp.asarray(efficiency) / (4.0 * np.pi * r * r)


def sound_pressure_level_db(intensity_w_m2, impedance_rayl, reference_pressure_pa=1e-6):
    """Sound pressure level of a plane wave ``L = 10 log10(I Z / p_ref²)`` (dB re p_ref).

    From p² = I Z (book eq (12.46), (13.27)). With p_ref = 1 µPa (water) this is the book's
    ``120 + 10 log10(I Z)`` (eq (12.48)); with p_ref = 20 µPa and Z = 418 rayl (air) it is
    ``10 log10 I + 120.2`` (eq (13.29), which the book rounds to +120). Exact.

    Args:
        intensity_w_m2: intensity I (W/m²), in (0, ∞).
        impedance_rayl: acoustic impedance Z (rayl), in (0, ∞).
        reference_pressure_pa: reference pressure (Pa), in (0, ∞); 1e-6 (water) or 2e-5 (air).
    """
    w = "sound_pressure_level_db"
    check_range("intensity_w_m2", intensity_w_m2, 0.0, None, lo_open=True, where=w)
    check_range("impedance_rayl", impedance_rayl, 0.0, None, lo_open=True, where=w)
    check_range("reference_pressure_pa", reference_pressure_pa, 0.0, None, lo_open=True, where=w)
    p_ref = jnp.asarray(reference_pressure_pa)
    return _db10(jnp.asarray(intensity_w_m2) * jnp.asarray(impedance_rayl) / (p_ref * p_ref))


def source_level_db(electrical_power_w, efficiency, directivity, impedance_rayl):
    """On-axis source level from electrical power ``SL = 120 + 10 log10(P η G Z / 4π)`` (dB re 1 µPa at 1 m).

    The book's intensity form (eqs (12.42)-(12.48)): on-axis intensity at 1 m is
    I = G P η / 4π and SL = 10 log10(I Z / (1 µPa)²). ITC-5202 example: 1500 W, η = 0.4,
    G = 458.4, Z = 1.56e6 → 225.3 dB. Exact given P, η, G and Z (far-field extrapolation to 1 m).

    Args:
        electrical_power_w: electrical drive power P (W), in (0, ∞).
        efficiency: electro-acoustic efficiency η, in (0, 1].
        directivity: transmit directivity G (linear), in [1, ∞).
        impedance_rayl: ρc of the water (rayl), in (0, ∞).
    """
    w = "source_level_db"
    check_range("directivity", directivity, 1.0, None, where=w)
    intensity = isotropic_intensity_w_m2(electrical_power_w, efficiency) * jnp.asarray(directivity)
    return sound_pressure_level_db(intensity, impedance_rayl, 1e-6)


SOURCE_LEVEL_CONSTANT_DB = 170.8
"""``10 log10(ρc × 1e12 / 4π)`` for ρc = 1.5e6 rayl (exactly 170.77 dB), rounded as usually quoted."""


def source_level_from_acoustic_power_db(acoustic_power_w, directivity_index_db):
    """Source level from radiated acoustic power ``SL = 170.8 + 10 log10 P_a + DI`` (dB re 1 µPa at 1 m).

    The constant is 10 log10(ρc · 10¹² / 4π) for standard sea water ρc = 1.5e6 rayl (170.77 dB,
    quoted as 170.8; Urick ch. 4). Older texts referred to 1 µbar at 1 yd quote 71.5 dB, the
    same relation: 170.77 − 100 + 20 log10(1/0.9144) = 71.55. Against :func:`source_level_db`
    it differs by 10 log10(1.5e6 / ρc) + 0.031 dB (−0.15 dB for the book's 1.56e6 rayl).

    Args:
        acoustic_power_w: radiated acoustic power P_a = η P (W), in (0, ∞).
        directivity_index_db: transmit directivity index DI (dB), in [0, 80].
    """
    w = "source_level_from_acoustic_power_db"
    check_range("acoustic_power_w", acoustic_power_w, 0.0, None, lo_open=True, where=w)
    check_range("directivity_index_db", directivity_index_db, 0.0, 80.0, where=w)
    return SOURCE_LEVEL_CONSTANT_DB + _db10(jnp.asarray(acoustic_power_w)) + jnp.asarray(directivity_index_db)


def drive_voltage_rms_v(electrical_power_w, conductance_s):
    """RMS drive voltage for a power into a transducer conductance ``V = sqrt(P / G)`` (V).

    Book eqs (12.49)-(12.50): 1500 W into 5.5 mS → 522 V rms. Exact for a resistive load G.

    Args:
        electrical_power_w: electrical power P (W), in (0, ∞).
        conductance_s: transducer input conductance G (S), in (0, ∞).
    """
    w = "drive_voltage_rms_v"
    check_range("electrical_power_w", electrical_power_w, 0.0, None, lo_open=True, where=w)
    check_range("conductance_s", conductance_s, 0.0, None, lo_open=True, where=w)
    return jnp.sqrt(jnp.asarray(electrical_power_w) / jnp.asarray(conductance_s))


def source_level_from_tvr_db(tvr_db, drive_voltage_rms_v_):
    """Source level from the transmitting voltage response ``SL = TVR + 20 log10 V`` (dB re 1 µPa at 1 m).

    Book eq (12.51): TVR 170 dB re 1 µPa/V at 1 m and 522 V rms → 224.3 dB. Exact by definition
    of the TVR (read off the maker's curve at the operating frequency).

    Args:
        tvr_db: TVR (dB re 1 µPa/V at 1 m), in [50, 300].
        drive_voltage_rms_v_: RMS drive voltage V (V), in (0, ∞).
    """
    w = "source_level_from_tvr_db"
    check_range("tvr_db", tvr_db, 50.0, 300.0, where=w)
    check_range("drive_voltage_rms_v", drive_voltage_rms_v_, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(tvr_db) + _db20(jnp.asarray(drive_voltage_rms_v_))


def equivalent_pressure_level_db(voltage_rms_v, receive_sensitivity_db):
    """Pressure level that would produce an RMS voltage ``L = 20 log10 V − M`` (dB re 1 µPa).

    Inverse of :func:`diffsense.physics.noise.hydrophone_voltage_v` (book eqs (12.65)-(12.66)); used to
    refer an amplifier's noise voltage to the water: 66 nV with M = −180 dB re 1 V/µPa → 36.4 dB.

    Args:
        voltage_rms_v: RMS voltage V (V), in (0, ∞).
        receive_sensitivity_db: open-circuit receive response M (dB re 1 V/µPa), in [-300, 0].
    """
    w = "equivalent_pressure_level_db"
    check_range("voltage_rms_v", voltage_rms_v, 0.0, None, lo_open=True, where=w)
    check_range("receive_sensitivity_db", receive_sensitivity_db, -300.0, 0.0, where=w)
    return _db20(jnp.asarray(voltage_rms_v)) - jnp.asarray(receive_sensitivity_db)


# ---------------------------------------------------------------------------------------------
# Sonar equations
# ---------------------------------------------------------------------------------------------


def echo_level_db(source_level_db_, transmission_loss_db, target_strength_db):
    """Echo level at the receiver ``EL = SL − 2 TL + TS`` (dB re 1 µPa), book eq (12.57).

    Args:
        source_level_db_: SL (dB re 1 µPa at 1 m), in [0, 300].
        transmission_loss_db: one-way TL (dB), in [-100, 1e5].
        target_strength_db: TS (dB re 1 m), in [-150, 100].
    """
    w = "echo_level_db"
    check_range("source_level_db", source_level_db_, 0.0, 300.0, where=w)
    check_range("transmission_loss_db", transmission_loss_db, -100.0, 1e5, where=w)
    check_range("target_strength_db", target_strength_db, -150.0, 100.0, where=w)
    return jnp.asarray(source_level_db_) - 2.0 * jnp.asarray(transmission_loss_db) + jnp.asarray(target_strength_db)


def active_signal_excess_noise_db(
    source_level_db_, transmission_loss_db, target_strength_db, noise_level_db, directivity_index_db, detection_threshold_db_
):
    """Noise-limited active sonar equation ``SE = SL − 2 TL + TS − (NL − DI) − DT`` (dB).

    NL is the isotropic noise level in the receiver band (dB re 1 µPa), DI the receive
    directivity index and DT the detection threshold in the same band (Urick ch. 2). SE ≥ 0 means
    detection at the (Pd, Pfa) that defines DT. Exact bookkeeping of the terms (all dB).

    Args: levels in dB (SL, NL re 1 µPa; TS re 1 m; TL, DI, DT in dB), any real values.
    """
    return (
        jnp.asarray(source_level_db_)
        - 2.0 * jnp.asarray(transmission_loss_db)
        + jnp.asarray(target_strength_db)
        - (jnp.asarray(noise_level_db) - jnp.asarray(directivity_index_db))
        - jnp.asarray(detection_threshold_db_)
    )


def active_signal_excess_reverberation_db(
    source_level_db_, transmission_loss_db, target_strength_db, reverberation_level_db, detection_threshold_db_
):
    """Reverberation-limited active sonar equation ``SE = SL − 2 TL + TS − RL − DT`` (dB).

    RL is the reverberation level at the receiver (dB re 1 µPa, see
    :func:`diffsense.physics.clutter.reverberation_level_db`); directivity enters RL through the
    reverberating area or volume, so no DI term appears (Urick ch. 2).

    Args: levels in dB, any real values.
    """
    return (
        jnp.asarray(source_level_db_)
        - 2.0 * jnp.asarray(transmission_loss_db)
        + jnp.asarray(target_strength_db)
        - jnp.asarray(reverberation_level_db)
        - jnp.asarray(detection_threshold_db_)
    )


def passive_signal_excess_db(source_level_db_, transmission_loss_db, noise_level_db, directivity_index_db, detection_threshold_db_):
    """Passive sonar equation ``SE = SL − TL − (NL − DI) − DT`` (dB).

    SL is the target's radiated level in the receiver band (dB re 1 µPa at 1 m), TL one way
    (Urick ch. 2).

    Args: levels in dB, any real values.
    """
    return (
        jnp.asarray(source_level_db_)
        - jnp.asarray(transmission_loss_db)
        - (jnp.asarray(noise_level_db) - jnp.asarray(directivity_index_db))
        - jnp.asarray(detection_threshold_db_)
    )


# ---------------------------------------------------------------------------------------------
# Detection threshold
# ---------------------------------------------------------------------------------------------


def _check_pd_pfa(where, pd, pfa):
    check_range("pd", pd, 0.0, 1.0, lo_open=True, hi_open=True, where=where)
    check_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True, where=where)
    if is_concrete(pd) and is_concrete(pfa):
        gap = np.asarray(pd, dtype=float) - np.asarray(pfa, dtype=float)
        check_range("pd - pfa", gap, 0.0, None, lo_open=True, where=where)


def detection_index(pd, pfa):
    """Detection index of the Gaussian ROC ``d = (Φ⁻¹(Pd) − Φ⁻¹(Pfa))²``.

    For a decision statistic that is Gaussian with equal variance σ² under noise and under
    signal plus noise, d = (ΔM)²/σ² and Pfa = Q(T), Pd = Q(T − √d) (Peterson, Birdsall & Fox
    1954; Urick ch. 12 plots these ROC curves). Pd 0.5, Pfa 1e-4 → d = 13.8. Exact for that
    model; for envelope-detected sinusoids use :func:`detection_threshold_db`.

    Args:
        pd: detection probability, in (0, 1), > pfa.
        pfa: false-alarm probability, in (0, 1).
    """
    _check_pd_pfa("detection_index", pd, pfa)
    root = ndtri(jnp.asarray(pd, dtype=float)) - ndtri(jnp.asarray(pfa, dtype=float))
    return root * root


def pd_from_detection_index(detection_index_, pfa):
    """Detection probability of the Gaussian ROC ``Pd = Φ(√d + Φ⁻¹(Pfa))``.

    Inverse of :func:`detection_index` in Pd. Exact for the equal-variance Gaussian model.

    Args:
        detection_index_: d, in [0, ∞) (the derivative in d is singular at d = 0).
        pfa: false-alarm probability, in (0, 1).
    """
    w = "pd_from_detection_index"
    check_range("detection_index", detection_index_, 0.0, None, where=w)
    check_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True, where=w)
    return ndtr(jnp.sqrt(jnp.asarray(detection_index_, dtype=float)) + ndtri(jnp.asarray(pfa, dtype=float)))


def detection_threshold_known_signal_db(detection_index_, duration_s):
    """Detection threshold for a signal known exactly (cross-correlator) ``DT = 10 log10(d / 2t)`` (dB).

    Referred to the noise in a 1 Hz band (signal power over noise spectral density N0). The
    correlator output has d = 2E/N0 with E = S t the signal energy, so S/N0 = d/(2t) (Urick
    ch. 12). Exact for white Gaussian noise.

    Args:
        detection_index_: d, in (0, ∞).
        duration_s: signal duration t (s), in (0, ∞).
    """
    w = "detection_threshold_known_signal_db"
    check_range("detection_index", detection_index_, 0.0, None, lo_open=True, where=w)
    check_range("duration_s", duration_s, 0.0, None, lo_open=True, where=w)
    return _db10(jnp.asarray(detection_index_) / (2.0 * jnp.asarray(duration_s)))


def detection_threshold_energy_db(detection_index_, bandwidth_hz, duration_s):
    """Detection threshold of an energy detector for a noise-like signal ``DT = 5 log10(d B / t)`` (dB).

    Referred to the noise in a 1 Hz band. With band-level SNR s = S/N and B t ≫ 1 the
    integrator output gives d = s² B t (Urick ch. 12), so S/N0 = B s = sqrt(d B / t). Subtract
    10 log10 B for the threshold in the band B: ``5 log10(d / (B t))``. Error: the Gaussian
    approximation of the chi-square statistic is optimistic for small B t. Against the exact
    chi-square detector (Gaussian signal in Gaussian noise, 2Bt degrees of freedom) at Pd 0.9,
    Pfa 1e-6 it is low by 3.5 dB at B t = 10, 1.1 dB at 100, 0.34 dB at 1e3 and 0.11 dB at 1e4
    (tests/test_sonar.py).

    Args:
        detection_index_: d, in (0, ∞).
        bandwidth_hz: receiver bandwidth B (Hz), in (0, ∞).
        duration_s: integration time t (s), in (0, ∞).
    """
    w = "detection_threshold_energy_db"
    check_range("detection_index", detection_index_, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("duration_s", duration_s, 0.0, None, lo_open=True, where=w)
    return 0.5 * _db10(jnp.asarray(detection_index_) * jnp.asarray(bandwidth_hz) / jnp.asarray(duration_s))


def detection_threshold_db(pd, pfa, swerling=0):
    """Detection threshold in the receiver band for an envelope-detected echo (dB).

    The book treats the sonar echo as a sinusoid in white noise and reads the required SNR off
    the radar Pd/Pfa curves (§12.8); this is :func:`diffsense.detection.required_snr_db` for one
    pulse (exact Marcum/Swerling, ≤ 1e-9 dB). Pd 0.9, Pfa 1e-6, steady echo → 13.2 dB.

    Args:
        pd: detection probability, in (pfa, 1 − 1e-12].
        pfa: false-alarm probability, in [1e-300, 0.5].
        swerling: echo fluctuation model 0-4 (static).
    """
    return detection.required_snr_db(pd, pfa, 1, swerling)


# ---------------------------------------------------------------------------------------------
# Side-scan geometry and timing
# ---------------------------------------------------------------------------------------------


def pulse_range_resolution_m(pulse_width_s, sound_speed_m_s=1500.0):
    """Range resolution of an uncompressed pulse ``δR = c τ / 2`` (m). 333 µs at 1522 m/s → 0.25 m.

    Args:
        pulse_width_s: τ (s), in (0, ∞).
        sound_speed_m_s: c (m/s), in (0, ∞).
    """
    w = "pulse_range_resolution_m"
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=w)
    check_range("sound_speed_m_s", sound_speed_m_s, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(sound_speed_m_s) * jnp.asarray(pulse_width_s) / 2.0


def chirp_range_resolution_m(chirp_bandwidth_hz, sound_speed_m_s=1500.0):
    """Range resolution after pulse compression ``δR = c / (2 Δf)`` (m), book eq (12.37): 15 kHz → 0.05 m.

    Args:
        chirp_bandwidth_hz: swept bandwidth Δf (Hz), in (0, ∞).
        sound_speed_m_s: c (m/s), in (0, ∞).
    """
    w = "chirp_range_resolution_m"
    check_range("chirp_bandwidth_hz", chirp_bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("sound_speed_m_s", sound_speed_m_s, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(sound_speed_m_s) / (2.0 * jnp.asarray(chirp_bandwidth_hz))


def cross_range_resolution_m(range_m, beamwidth_rad):
    """Unfocused cross-range resolution ``δx = R θ_az`` (m), book eq (12.38): 500 m, 1.5° → 13.1 m.

    Args:
        range_m: R (m), in (0, ∞).
        beamwidth_rad: azimuth beamwidth θ_az (rad), in (0, π].
    """
    w = "cross_range_resolution_m"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("beamwidth_rad", beamwidth_rad, 0.0, np.pi, lo_open=True, where=w)
    return jnp.asarray(range_m) * jnp.asarray(beamwidth_rad)


def max_prf_hz(max_range_m, sound_speed_m_s=1500.0):
    """Highest unambiguous pulse repetition frequency ``f_pr = c / (2 R_max)`` (Hz), book eq (12.39): 1.52 Hz.

    Args:
        max_range_m: R_max (m), in (0, ∞).
        sound_speed_m_s: c (m/s), in (0, ∞).
    """
    w = "max_prf_hz"
    check_range("max_range_m", max_range_m, 0.0, None, lo_open=True, where=w)
    check_range("sound_speed_m_s", sound_speed_m_s, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(sound_speed_m_s) / (2.0 * jnp.asarray(max_range_m))


def duty_cycle(prf_hz, pulse_width_s):
    """Transmit duty cycle ``χ = f_pr τ`` (fraction; the book quotes 100 χ %), eq (12.40): 0.05 %.

    Args:
        prf_hz: f_pr (Hz), in (0, ∞).
        pulse_width_s: τ (s), in (0, ∞).
    """
    w = "duty_cycle"
    check_range("prf_hz", prf_hz, 0.0, None, lo_open=True, where=w)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(prf_hz) * jnp.asarray(pulse_width_s)


def max_pulse_length_s(max_duty_cycle, prf_hz):
    """Longest pulse (chirp) allowed by a duty-cycle limit ``τ = χ / f_pr`` (s), eq (12.41): 5 % → 32.9 ms.

    Args:
        max_duty_cycle: χ (fraction), in (0, 1].
        prf_hz: f_pr (Hz), in (0, ∞).
    """
    w = "max_pulse_length_s"
    check_range("max_duty_cycle", max_duty_cycle, 0.0, 1.0, lo_open=True, where=w)
    check_range("prf_hz", prf_hz, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(max_duty_cycle) / jnp.asarray(prf_hz)


def pulse_compression_gain_db(bandwidth_hz, pulse_width_s):
    """SNR gain of a matched filter on a coded pulse ``10 log10(B τ)`` relative to noise in B (dB).

    The matched-filter output SNR is E/N0 = S τ / N0 = (S / N0 B) · B τ, so referred to the noise
    in the compressed bandwidth B the echo gains B τ (0 dB for a plain pulse with B = 1/τ).
    Exact for a matched filter in white noise (North 1943; Skolnik, *Introduction to Radar
    Systems*, ch. 10).

    Args:
        bandwidth_hz: B (Hz), in (0, ∞).
        pulse_width_s: τ (s), in (0, ∞).
    """
    w = "pulse_compression_gain_db"
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=w)
    return _db10(jnp.asarray(bandwidth_hz) * jnp.asarray(pulse_width_s))


# ---------------------------------------------------------------------------------------------
# Scene parts
# ---------------------------------------------------------------------------------------------


@scene_part("sea_noise")
def sea_noise_spectrum_level_db(sea_state, freq_hz):
    """Knudsen sea-surface noise spectrum level, dB re 1 µPa²/Hz (book eq (12.61), Table 12.2)."""
    return noise.sea_surface_noise_spectrum_level_db(sea_state, freq_hz)


@scene_part("thermal_noise")
def thermal_noise_spectrum_level_db(freq_hz):
    """Mellen's thermal noise of sea water, dB re 1 µPa²/Hz (book eq (9.10))."""
    return noise.thermal_sea_noise_spectrum_level_db(freq_hz)


@scene_part("receiver_noise")
def receiver_noise_level_db(noise_density_v_rthz, bandwidth_hz, receive_sensitivity_db):
    """Amplifier voltage noise in the band referred to the water, dB re 1 µPa (book §12.8)."""
    v = noise.voltage_noise_rms_v(noise_density_v_rthz, bandwidth_hz)
    return _db20(v) - receive_sensitivity_db


@scene_part("surface_reverberation")
def surface_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s, c):
    """Sea-surface reverberation level, A = (cτ/2) R θ_az (book eq (8.47)), dB re 1 µPa."""
    return clutter.surface_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s, speed_m_s=c)


@scene_part("surface_reverberation")
def surface_chapman_harris_strength_db(grazing_rad, wind_speed_knots, freq_hz):
    """Chapman-Harris sea-surface scattering strength, dB."""
    return clutter.chapman_harris_surface_scattering_strength_db(grazing_rad, wind_speed_knots, freq_hz)


@scene_part("bottom_reverberation")
def bottom_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s, c):
    """Sea-floor reverberation level, A = (cτ/2) R θ_az (book eq (8.47)), dB re 1 µPa."""
    return clutter.surface_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s, speed_m_s=c)


@scene_part("bottom_reverberation")
def bottom_lambert_strength_db(grazing_rad, mu_db):
    """Lambert's-law bottom scattering strength, dB."""
    return clutter.lambert_scattering_strength_db(grazing_rad, mu_db)


@scene_part("volume_reverberation")
def volume_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, el_rad, tau_s, c):
    """Volume reverberation level, V = (cτ/2) π R² θ_az θ_el / 4 (book eq (8.48)), dB re 1 µPa."""
    return clutter.volume_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, el_rad, tau_s, speed_m_s=c)


# ---------------------------------------------------------------------------------------------
# The chain
# ---------------------------------------------------------------------------------------------

_NOISE_PARTS = ("sea_noise", "thermal_noise", "receiver_noise")
_AMBIENT_PARTS = ("sea_noise", "thermal_noise")
_REVERB_PARTS = ("surface_reverberation", "bottom_reverberation", "volume_reverberation")
_ACTIVE_ONLY_OPTIONS = ("waveform", "source", "target", "swerling", "surface_scattering", "bottom_scattering")
_RANGE_BRACKET_M = (1.0, 1.0e6)


class SonarChain(Chain):
    """Active and passive sonar link budget (book ch. 12; Urick's sonar equations).

    Active (``mode="active"``)::

        SNR = SL − 2 TL + TS − 10 log10( (NL_amb − DI ⊕ NL_rx) / PG  ⊕  RL )      (⊕: power sum)

    with SL from electrical power, efficiency and directivity (book eqs (12.42)-(12.48)), from
    the TVR and drive voltage (eq (12.51)) or given; TL = 20 log10 R + α R (eq (12.53)) or
    spherical-then-cylindrical; TS of a sphere, given, or of the sea-floor patch (eq (12.59));
    ambient noise band level N_f + 10 log10 B − DI (eq (12.64)); the amplifier's noise referred
    to the water through the receive response (§12.8); reverberation levels from scattering
    strengths (eqs (8.47)-(8.48)); PG = 10 log10(B τ) the pulse-compression gain of a chirp
    (0 dB for a plain pulse, B = 1/τ). The detection threshold is the book's: the required
    single-pulse SNR of an envelope detector for (Pd, Pfa) and the Swerling option
    (:func:`detection_threshold_db`). ``signal_excess_db`` = SNR − DT.

    Passive (``mode="passive"``): SNR = SL − TL − (NL_amb − DI ⊕ NL_rx) in the band B, and the
    threshold of an energy detector integrating for t seconds, DT = 5 log10(d / (B t)) with the
    detection index d of (Pd, Pfa) (:func:`detection_threshold_energy_db`; Urick's large-Bt form,
    optimistic by 1.1 dB at B t = 100 and 0.34 dB at 1000); Pd from the Gaussian ROC.

    ``detection_range_m`` solves SNR(R) = DT in [1 m, 1000 km] (:func:`diffsense.numerics.rootfind.decreasing_root_log`);
    where SNR stays above (below) DT over the whole bracket it returns the bracket end with zero
    gradient. ``snr_margin_db`` at ``range_m`` is the smooth constraint to use instead.
    """

    kind = "sonar"
    description = "active/passive sonar: source level, transmission loss, target strength, sea noise, reverberation"
    parts = {
        "sea_noise": "wind/wave noise of the sea surface (Knudsen, sea state; book Table 12.2, eq (12.61))",
        "thermal_noise": "molecular thermal noise of the water (Mellen 1952, book eq (9.10))",
        "receiver_noise": "preamplifier voltage noise referred to the water through the receive response",
        "surface_reverberation": "sea-surface reverberation (constant strength or Chapman-Harris)",
        "bottom_reverberation": "sea-floor reverberation (constant strength or Lambert's law)",
        "volume_reverberation": "volume reverberation (scattering strength S_v)",
    }
    options = {
        "mode": ("active", ("active", "passive")),
        "waveform": ("pulse", ("pulse", "chirp")),
        "source": ("power", ("power", "tvr", "level")),
        "target": ("sphere", ("sphere", "given", "seafloor")),
        "swerling": (0, (0, 1, 2, 3, 4)),
        "absorption": ("francois_garrison", ("francois_garrison", "book", "given")),
        "sound_speed": ("given", ("given", "mackenzie")),
        "spreading": ("spherical", ("spherical", "cylindrical")),
        "surface_scattering": ("constant", ("constant", "chapman_harris")),
        "bottom_scattering": ("constant", ("constant", "lambert")),
    }

    # -- structure ------------------------------------------------------------------------

    def validate_scene(self, scene) -> None:
        super().validate_scene(scene)
        mode = self.option(scene, "mode")
        if mode == "passive":
            bad = sorted(p for p in scene.parts if p in _REVERB_PARTS)
            if bad:
                raise DomainError(f"sonar scene: reverberation part(s) {bad} need mode='active'")
            opts = sorted(k for k, _ in scene.options if k in _ACTIVE_ONLY_OPTIONS)
            if opts:
                raise DomainError(f"sonar scene: option(s) {opts} apply only to mode='active'")
            if not any(scene.has(p) for p in _NOISE_PARTS):
                raise DomainError(f"sonar scene (passive): needs at least one noise part of {list(_NOISE_PARTS)}")
        elif not any(scene.has(p) for p in _NOISE_PARTS + _REVERB_PARTS):
            raise DomainError(
                f"sonar scene: needs at least one noise or reverberation part of {list(_NOISE_PARTS + _REVERB_PARTS)}"
            )

    def _freq_domain(self, scene):
        lo, hi = 1.0e3, 1.0e6
        if scene.has("sea_noise"):
            hi = min(hi, 2.0e5)
        if scene.has("surface_reverberation") and self.option(scene, "surface_scattering") == "chapman_harris":
            hi = min(hi, 6400.0)
        return lo, hi

    def parameters(self, scene) -> Dict[str, Param]:
        self.validate_scene(scene)
        active = self.option(scene, "mode") == "active"
        f_lo, f_hi = self._freq_domain(scene)
        ps = [
            Param("range_m", "m", "range to the target R", lo=_RANGE_BRACKET_M[0], hi=_RANGE_BRACKET_M[1]),
            Param("freq_hz", "Hz", "acoustic (centre) frequency", lo=f_lo, hi=f_hi),
            Param("beamwidth_az_deg", "degree", "horizontal (azimuth) 3 dB beamwidth; ITC-5202 1.5° (book Table 12.1)",
                  default=1.5, lo=0.0, hi=180.0, lo_open=True),
            Param("beamwidth_el_deg", "degree", "vertical (elevation) 3 dB beamwidth; ITC-5202 60° (book Table 12.1)",
                  default=60.0, lo=0.0, hi=180.0, lo_open=True),
            Param("receive_sensitivity_db", "dB", "open-circuit receive response M, dB re 1 V/µPa; ITC-5202 −180 dB (book §12.8)",
                  default=-180.0, lo=-300.0, hi=0.0),
            Param("pd", "1", "required detection probability", default=0.9, lo=0.1, hi=0.999999),
            Param("pfa", "1", "false-alarm probability", default=1e-6, lo=1e-15, hi=0.05),
        ]
        mackenzie = self.option(scene, "sound_speed") == "mackenzie"
        absorption = self.option(scene, "absorption")
        if not mackenzie:
            ps.append(Param("sound_speed_m_s", "m/s", "speed of sound in the water; book §12.8: 1522 m/s",
                            default=1500.0, lo=1400.0, hi=1650.0))
        needs_water = mackenzie or absorption == "francois_garrison"
        if needs_water:
            ps.append(Param("temperature_c", "degC", "water temperature (°C)", default=5.0, lo=-2.0, hi=30.0))
            ps.append(Param("salinity_ppt", "1", "salinity, parts per thousand",
                            default=35.0, lo=25.0 if mackenzie else 0.0, hi=40.0, lo_open=not mackenzie))
            ps.append(Param("depth_m", "m", "depth of the sound path", default=0.0, lo=0.0,
                            hi=8000.0 if mackenzie else 10000.0))
        if absorption == "francois_garrison":
            ps.append(Param("ph", "1", "pH of the water (Francois-Garrison boric-acid term)", default=8.0, lo=6.0, hi=9.0))
        elif absorption == "given":
            ps.append(Param("absorption_db_per_m", "dB/m", "absorption coefficient α (one way)",
                            default=0.0329, lo=0.0, hi=10.0))
        if self.option(scene, "spreading") == "cylindrical":
            ps.append(Param("transition_range_m", "m", "spherical-to-cylindrical transition range (about the water depth)",
                            default=100.0, lo=1.0, hi=1.0e5))
        if active:
            ps += self._active_parameters(scene)
        else:
            ps += [
                Param("source_level_db", "dB", "target's radiated level in the receiver band, dB re 1 µPa at 1 m",
                      lo=0.0, hi=300.0),
                Param("bandwidth_hz", "Hz", "receiver bandwidth B", default=100.0, lo=0.0, lo_open=True, hi=1.0e6),
                Param("integration_time_s", "s", "energy-detector integration time t", default=1.0,
                      lo=0.0, lo_open=True, hi=1.0e5),
            ]
        if scene.has("sea_noise"):
            ps.append(Param("sea_state", "1", "sea state (book Table 12.2)", default=3.0, lo=0.0, hi=6.0, part="sea_noise"))
        if scene.has("receiver_noise"):
            ps.append(Param("amplifier_noise_density_v_rthz", "V/Hz**0.5",
                            "preamplifier input voltage-noise density; book §12.8: 1.2 nV/√Hz",
                            default=1.2e-9, lo=0.0, lo_open=True, hi=1e-3, part="receiver_noise"))
        return collect(ps)

    def _active_parameters(self, scene):
        ps = [Param("pulse_width_s", "s", "transmitted pulse (or chirp) length τ; book §12.8: 333 µs",
                    default=333e-6, lo=1e-6, hi=10.0),
              Param("max_duty_cycle", "1", "transmitter duty-cycle limit (book §12.8: 5 %)",
                    default=0.05, lo=0.0, lo_open=True, hi=1.0)]
        if self.option(scene, "waveform") == "chirp":
            ps.append(Param("chirp_bandwidth_hz", "Hz", "swept chirp bandwidth Δf; book §12.8: 15 kHz",
                            default=15e3, lo=1.0, hi=1e6))
        source = self.option(scene, "source")
        if source in ("power", "tvr"):
            ps.append(Param("electrical_power_w", "W", "electrical drive power; ITC-5202 1500 W (book Table 12.1)",
                            default=1500.0, lo=0.0, lo_open=True, hi=1e7))
        if source == "power":
            ps.append(Param("efficiency", "1", "electro-acoustic efficiency; ITC-5202 0.4 (book Table 12.1)",
                            default=0.4, lo=0.0, lo_open=True, hi=1.0))
            ps.append(Param("water_density_kg_m3", "kg/m**3", "water density ρ (book §12.8: 1026.4)",
                            default=1026.4, lo=990.0, hi=1050.0))
        elif source == "tvr":
            ps.append(Param("tvr_db", "dB", "transmitting voltage response, dB re 1 µPa/V at 1 m (book: 170 dB)",
                            default=170.0, lo=50.0, hi=300.0))
            ps.append(Param("conductance_s", "S", "transducer input conductance (book: 5.5 mS)",
                            default=5.5e-3, lo=0.0, lo_open=True, hi=100.0))
        else:
            ps.append(Param("source_level_db", "dB", "source level, dB re 1 µPa at 1 m", lo=0.0, hi=300.0))
        target = self.option(scene, "target")
        if target == "sphere":
            ps.append(Param("target_radius_m", "m", "radius of a large (ka ≫ 1) sphere; book §12.8: 0.5 m",
                            default=0.5, lo=0.0, lo_open=True, hi=1e3))
        elif target == "given":
            ps.append(Param("target_strength_db", "dB", "target strength TS, dB re 1 m", lo=-100.0, hi=60.0))
        else:
            ps.append(Param("seafloor_scattering_strength_db", "dB",
                            "bottom scattering strength S_b of the imaged sea floor (book §12.8: −20 dB, pebbles and rock)",
                            default=-20.0, lo=-100.0, hi=0.0))
        if scene.has("surface_reverberation"):
            if self.option(scene, "surface_scattering") == "constant":
                ps.append(Param("surface_scattering_strength_db", "dB",
                                "sea-surface scattering strength S_s (book Table 8.9: −45 to −58 dB at sea state 2)",
                                default=-50.0, lo=-150.0, hi=0.0, part="surface_reverberation"))
            else:
                ps.append(Param("wind_speed_knots", "knot", "wind speed for Chapman-Harris", default=10.0,
                                lo=0.0, lo_open=True, hi=30.0, part="surface_reverberation"))
                ps.append(Param("surface_grazing_angle_deg", "degree", "grazing angle at the sea surface",
                                default=10.0, lo=0.0, lo_open=True, hi=60.0, part="surface_reverberation"))
        if scene.has("bottom_reverberation"):
            if self.option(scene, "bottom_scattering") == "constant":
                ps.append(Param("bottom_scattering_strength_db", "dB",
                                "sea-floor scattering strength S_b (book Table 8.9: −24 to −32 dB pebbles and rock)",
                                default=-28.0, lo=-150.0, hi=0.0, part="bottom_reverberation"))
            else:
                ps.append(Param("lambert_mu_db", "dB", "Lambert parameter 10 log10 μ (Mackenzie 1961: −27 dB)",
                                default=-27.0, lo=-60.0, hi=0.0, part="bottom_reverberation"))
                ps.append(Param("bottom_grazing_angle_deg", "degree", "grazing angle at the sea floor",
                                default=10.0, lo=0.0, lo_open=True, hi=90.0, part="bottom_reverberation"))
        if scene.has("volume_reverberation"):
            ps.append(Param("volume_scattering_strength_db", "dB", "volume scattering strength S_v (book §8.15.2: ≈ −80 dB)",
                            default=-80.0, lo=-150.0, hi=0.0, part="volume_reverberation"))
        return ps

    def outputs(self, scene) -> Dict[str, Output]:
        self.validate_scene(scene)
        active = self.option(scene, "mode") == "active"
        has_noise = any(scene.has(p) for p in _NOISE_PARTS)
        outs = [
            Output("source_level_db", "dB", "source level, dB re 1 µPa at 1 m" + ("" if active else " (target, in band)")),
            Output("directivity_index_db", "dB", "directivity index DI = 10 log10(4π/(θ_az θ_el))"),
            Output("sound_speed_m_s", "m/s", "speed of sound used"),
            Output("wavelength_m", "m", "acoustic wavelength c/f"),
            Output("absorption_db_per_m", "dB/m", "absorption coefficient α"),
            Output("transmission_loss_db", "dB", "one-way transmission loss TL at range_m"),
            Output("snr_db", "dB", "signal to noise (plus reverberation) ratio at range_m after matched filtering"),
            Output("required_snr_db", "dB", "detection threshold DT for (pd, pfa) in the receiver band"),
            Output("signal_excess_db", "dB", "signal excess SE = SNR − DT at range_m"),
            Output("snr_margin_db", "dB", "same as signal_excess_db (constraint form)"),
            Output("pd", "1", "detection probability at range_m for pfa"),
            Output("detection_range_m", "m", "range where SNR = DT (bracket [1 m, 1000 km])"),
            Output("bandwidth_hz", "Hz", "receiver (noise) bandwidth"),
            Output("signal_voltage_v", "V", "RMS open-circuit voltage of the echo (signal) at the transducer"),
        ]
        if has_noise:
            outs += [
                Output("noise_level_db", "dB", "noise in the band referred to the water on axis: NL_amb − DI ⊕ NL_rx, dB re 1 µPa"),
                Output("noise_voltage_v", "V", "RMS noise voltage at the transducer output (incl. amplifier noise)"),
            ]
        if any(scene.has(p) for p in _AMBIENT_PARTS):
            outs.append(Output("noise_spectrum_level_db", "dB", "ambient noise spectrum level, dB re 1 µPa²/Hz"))
        if active:
            outs += [
                Output("target_strength_db", "dB", "target strength TS at range_m"),
                Output("echo_level_db", "dB", "echo level EL = SL − 2TL + TS, dB re 1 µPa"),
                Output("processing_gain_db", "dB", "pulse-compression gain 10 log10(B τ)"),
                Output("range_resolution_m", "m", "range resolution c/(2B): cτ/2 (pulse) or c/(2Δf) (chirp)"),
                Output("cross_range_resolution_m", "m", "cross-range resolution R θ_az at range_m"),
                Output("prf_hz", "Hz", "highest unambiguous PRF c/(2 range_m)"),
                Output("duty_cycle", "1", "duty cycle at that PRF (fraction)"),
                Output("max_pulse_length_s", "s", "longest pulse the duty-cycle limit allows at that PRF"),
            ]
            if any(scene.has(p) for p in _REVERB_PARTS):
                outs.append(Output("reverberation_level_db", "dB", "total reverberation level, dB re 1 µPa"))
        else:
            outs.append(Output("detection_index", "1", "detection index d of (pd, pfa), Gaussian ROC"))
        return {o.name: o for o in outs}

    # -- evaluation -----------------------------------------------------------------------

    def _environment(self, scene, p):
        env = {}
        freq = p["freq_hz"]
        if self.option(scene, "sound_speed") == "mackenzie":
            c = acoustic.sound_speed_seawater(p["temperature_c"], p["salinity_ppt"], p["depth_m"])
        else:
            c = p["sound_speed_m_s"]
        absorption = self.option(scene, "absorption")
        if absorption == "francois_garrison":
            alpha = acoustic.seawater_absorption_db_per_km(
                freq, p["temperature_c"], p["salinity_ppt"], p["depth_m"], p["ph"]) / 1000.0
        elif absorption == "book":
            alpha = acoustic.seawater_absorption_simple_db_per_m(freq)
        else:
            alpha = p["absorption_db_per_m"]
        gain = antennas.directivity_from_beamwidths_deg(p["beamwidth_az_deg"], p["beamwidth_el_deg"])
        env.update(c=c, alpha=alpha, gain=gain, di=antennas.directivity_index_db(gain),
                   az_rad=p["beamwidth_az_deg"] * _DEG, el_rad=p["beamwidth_el_deg"] * _DEG)
        active = self.option(scene, "mode") == "active"
        if active:
            tau = p["pulse_width_s"]
            if self.option(scene, "waveform") == "chirp":
                bandwidth = p["chirp_bandwidth_hz"]
                env["pg"] = pulse_compression_gain_db(bandwidth, tau)
            else:
                bandwidth = 1.0 / tau
                env["pg"] = jnp.zeros_like(tau)
            env["tau"] = tau
            source = self.option(scene, "source")
            if source == "power":
                z = acoustic_impedance_rayl(p["water_density_kg_m3"], c)
                env["sl"] = source_level_db(p["electrical_power_w"], p["efficiency"], gain, z)
            elif source == "tvr":
                env["sl"] = source_level_from_tvr_db(p["tvr_db"], drive_voltage_rms_v(p["electrical_power_w"], p["conductance_s"]))
            else:
                env["sl"] = p["source_level_db"]
        else:
            bandwidth = p["bandwidth_hz"]
            env["sl"] = p["source_level_db"]
        env["bandwidth"] = bandwidth
        # noise
        ambient = None
        if scene.has("sea_noise"):
            ambient = sea_noise_spectrum_level_db(p["sea_state"], freq)
        if scene.has("thermal_noise"):
            th = thermal_noise_spectrum_level_db(freq)
            ambient = th if ambient is None else _power_sum_db(ambient, th)
        env["ambient_spectrum"] = ambient
        if ambient is not None:
            env["ambient_band"] = noise.band_noise_level_db(ambient, bandwidth, gain)
        env["receiver"] = (
            receiver_noise_level_db(p["amplifier_noise_density_v_rthz"], bandwidth, p["receive_sensitivity_db"])
            if scene.has("receiver_noise") else None
        )
        return env

    def _transmission_loss(self, scene, p, env, r):
        spreading = self.option(scene, "spreading")
        kw = {"transition_range_m": p["transition_range_m"]} if spreading == "cylindrical" else {}
        tl = acoustic.transmission_loss_db(r, env["alpha"], spreading, 1.0, **kw)
        absorption = env["alpha"] * r
        return tl, tl - absorption, absorption

    def _target_strength(self, scene, p, env, r):
        target = self.option(scene, "target")
        if target == "sphere":
            return targets.target_strength_sphere_db(p["target_radius_m"])
        if target == "given":
            return p["target_strength_db"]
        # sea-floor patch δR × R θ_az (book eq (12.59))
        area = env["c"] / (2.0 * env["bandwidth"]) * r * env["az_rad"]
        return clutter.reflectivity_target_strength_db(p["seafloor_scattering_strength_db"], area)

    def _reverberation(self, scene, p, env, r, tl):
        levels = []
        tau_eff = 1.0 / env["bandwidth"]  # compressed cell length c/(2B)
        sl, c = env["sl"], env["c"]
        if scene.has("surface_reverberation"):
            if self.option(scene, "surface_scattering") == "constant":
                s = p["surface_scattering_strength_db"]
            else:
                s = surface_chapman_harris_strength_db(p["surface_grazing_angle_deg"] * _DEG, p["wind_speed_knots"], p["freq_hz"])
            levels.append(surface_reverberation_level_db(sl, tl, s, r, env["az_rad"], tau_eff, c))
        if scene.has("bottom_reverberation"):
            if self.option(scene, "bottom_scattering") == "constant":
                s = p["bottom_scattering_strength_db"]
            else:
                s = bottom_lambert_strength_db(p["bottom_grazing_angle_deg"] * _DEG, p["lambert_mu_db"])
            levels.append(bottom_reverberation_level_db(sl, tl, s, r, env["az_rad"], tau_eff, c))
        if scene.has("volume_reverberation"):
            levels.append(volume_reverberation_level_db(sl, tl, p["volume_scattering_strength_db"], r,
                                                        env["az_rad"], env["el_rad"], tau_eff, c))
        if not levels:
            return None
        total = levels[0]
        for lv in levels[1:]:
            total = _power_sum_db(total, lv)
        return total

    def _link(self, scene, p, env, r):
        """Budget at range ``r`` and the intermediate levels."""
        active = self.option(scene, "mode") == "active"
        b = BudgetBuilder()
        tl, spreading, absorption = self._transmission_loss(scene, p, env, r)
        extra = {"tl": tl}
        b.add("source_level", env["sl"])
        if active:
            b.add("two_way_spreading", -2.0 * spreading)
            b.add("two_way_absorption", -2.0 * absorption)
            ts = self._target_strength(scene, p, env, r)
            b.add("target_strength", ts)
            extra["ts"] = ts
            extra["signal"] = env["sl"] - 2.0 * tl + ts
        else:
            b.add("spreading", -spreading)
            b.add("absorption", -absorption)
            extra["signal"] = env["sl"] - tl
        # noise, referred to the water on axis, in the band (before compression)
        ambient, receiver = env.get("ambient_band"), env["receiver"]
        noise_db = None
        if ambient is not None:
            b.add("noise_spectrum_level", -env["ambient_spectrum"])
            b.add("noise_bandwidth", -_db10(env["bandwidth"]))
            b.add("receive_directivity_index", env["di"])
            noise_db = ambient
            if receiver is not None:
                b.add("receiver_noise", -_increment_db(receiver - ambient))
                noise_db = _power_sum_db(ambient, receiver)
        elif receiver is not None:
            b.add("receiver_noise_level", -receiver)
            noise_db = receiver
        extra["noise"] = noise_db
        reverb = self._reverberation(scene, p, env, r, tl) if active else None
        extra["reverb"] = reverb
        if noise_db is not None:
            if active and self.option(scene, "waveform") == "chirp":
                b.add("processing_gain", env["pg"])
            if reverb is not None:
                b.add("reverberation", -_increment_db(reverb + env["pg"] - noise_db))
        else:
            b.add("reverberation_level", -reverb)
        return b.build(), extra

    def compute(self, scene, p, wanted=None) -> Evaluation:
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the active detection threshold solve, the Pd series and the range root find are traced
        only when a wanted output needs them (see :class:`diffsense.sensors.chain.Chain`)."""
        active = self.option(scene, "mode") == "active"
        env = self._environment(scene, p)
        budget, extra = self._link(scene, p, env, p["range_m"])
        snr = budget.total
        if active:
            # pd and pfa were checked against their domains (pd >= 0.1 > 0.05 >= pfa) by complete_parameters
            swerling = self.option(scene, "swerling")
            need_required = needs(wanted, "required_snr_db", "signal_excess_db", "snr_margin_db", "detection_range_m")
            required = single_pulse_required_snr_db(p["pd"], p["pfa"], swerling) if need_required else None
            pd_at = single_pulse_pd(snr, p["pfa"], swerling) if needs(wanted, "pd") else None
        else:
            d_req = detection_index(p["pd"], p["pfa"])
            bt = p["bandwidth_hz"] * p["integration_time_s"]
            required = detection_threshold_energy_db(d_req, p["bandwidth_hz"], p["integration_time_s"]) - _db10(p["bandwidth_hz"])
            # achieved index d = (S/N)^2 B t ; sqrt(d) = (S/N) sqrt(Bt)
            root_d = jnp.exp(jnp.clip(snr, -300.0, 300.0) * (_LN10 / 10.0)) * jnp.sqrt(bt)
            pd_at = ndtr(root_d + ndtri(p["pfa"]))

        def residual(r):
            return self._link(scene, p, env, r)[0].total - required

        m = p["receive_sensitivity_db"]
        values = {
            "source_level_db": env["sl"],
            "directivity_index_db": env["di"],
            "sound_speed_m_s": env["c"],
            "wavelength_m": env["c"] / p["freq_hz"],
            "absorption_db_per_m": env["alpha"],
            "transmission_loss_db": extra["tl"],
            "snr_db": snr,
        }
        if required is not None:
            values.update(required_snr_db=required, signal_excess_db=snr - required, snr_margin_db=snr - required)
        if pd_at is not None:
            values["pd"] = pd_at
        if needs(wanted, "detection_range_m"):
            values["detection_range_m"] = decreasing_root_log(residual, *_RANGE_BRACKET_M).root
        values.update({
            "bandwidth_hz": env["bandwidth"],
            # noise.hydrophone_voltage_v, written out: the level may leave its checked domain at extreme ranges
            "signal_voltage_v": 10.0 ** ((extra["signal"] + m) / 20.0),
        })
        if extra["noise"] is not None:
            values["noise_level_db"] = extra["noise"]
            values["noise_voltage_v"] = 10.0 ** ((extra["noise"] + m) / 20.0)
        if env["ambient_spectrum"] is not None:
            values["noise_spectrum_level_db"] = env["ambient_spectrum"]
        if active:
            prf = max_prf_hz(p["range_m"], env["c"])
            values.update(
                target_strength_db=extra["ts"] + jnp.zeros_like(snr),
                echo_level_db=extra["signal"],
                processing_gain_db=env["pg"],
                range_resolution_m=env["c"] / (2.0 * env["bandwidth"]),
                cross_range_resolution_m=cross_range_resolution_m(p["range_m"], env["az_rad"]),
                prf_hz=prf,
                duty_cycle=duty_cycle(prf, env["tau"]),
                max_pulse_length_s=max_pulse_length_s(p["max_duty_cycle"], prf),
            )
            if extra["reverb"] is not None:
                values["reverberation_level_db"] = extra["reverb"]
        else:
            values["detection_index"] = d_req
        return Evaluation(budget, values)
