"""Sonar source and pressure levels: acoustic impedance, intensity, sound pressure level, the
source level of a projector (from electrical power or from its transmitting voltage response)
and the pressure level equivalent to a voltage at the hydrophone.

Levels are dB re 1 µPa (pressure), source levels dB re 1 µPa at 1 m. Sources: Brooker,
*Introduction to Sensors for Ranging and Imaging* (2009), §12.7–12.8 eqs (12.42)–(12.51), (12.65)
and §13.20 eqs (13.27)–(13.29); Urick, *Principles of Underwater Sound* (1983), ch. 4.

The ITC-5202 side-scan array of book §12.7 (1500 W, efficiency 0.4, directivity 458.4, sea water
ρc = 1026.4 × 1522 rayl):

>>> from diffsense.sensors.sonar.levels import acoustic_impedance_rayl, source_level_db
>>> z = acoustic_impedance_rayl(1026.4, 1522.0)
>>> round(float(source_level_db(1500.0, 0.4, 458.4, z)), 1)  # book eq (12.48): 225.3 dB
225.3
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10, db20

__all__ = [
    "WATER_REFERENCE_PRESSURE_PA",
    "SOURCE_LEVEL_CONSTANT_DB",
    "acoustic_impedance_rayl",
    "isotropic_intensity_w_m2",
    "sound_pressure_level_db",
    "source_level_db",
    "source_level_from_acoustic_power_db",
    "drive_voltage_rms_v",
    "source_level_from_tvr_db",
    "equivalent_pressure_level_db",
]

WATER_REFERENCE_PRESSURE_PA = 1e-6
"""Reference pressure of levels in water, 1 µPa."""


def acoustic_impedance_rayl(density_kg_m3, propagation_speed_m_s):
    """Characteristic acoustic impedance ``Z = ρ c`` (kg m⁻² s⁻¹, i.e. rayl).

    Book eq (12.45): 1026.4 × 1522 = 1.56e6 rayl for sea water; eq (13.28): 1.229 × 340 = 418
    rayl for air. Exact for a plane progressive wave.

    Args:
        density_kg_m3: density ρ (kg/m³), in (0, ∞).
        propagation_speed_m_s: sound speed c (m/s), in (0, ∞).

    >>> round(float(acoustic_impedance_rayl(1.229, 340.0)))  # book eq (13.28): 418 rayl
    418
    """
    w = "acoustic_impedance_rayl"
    check_range("density_kg_m3", density_kg_m3, 0.0, None, lo_open=True, where=w)
    check_range("propagation_speed_m_s", propagation_speed_m_s, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(density_kg_m3) * jnp.asarray(propagation_speed_m_s)


def isotropic_intensity_w_m2(electrical_power_w, efficiency, range_m=1.0):
    """Intensity of an omnidirectional projector ``I = P η / (4π R²)`` (W/m²).

    Exact (far field, lossless medium).

    Args:
        electrical_power_w: electrical input power P (W), in (0, ∞).
        efficiency: electro-acoustic conversion efficiency η, in (0, 1].
        range_m: distance R (m), in (0, ∞); 1 m for a source level.

    >>> round(float(isotropic_intensity_w_m2(1500.0, 0.4)), 1)  # book eq (12.42): 47.7 W/m²
    47.7
    """
    w = "isotropic_intensity_w_m2"
    check_range("electrical_power_w", electrical_power_w, 0.0, None, lo_open=True, where=w)
    check_range("efficiency", efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    r = jnp.asarray(range_m)
    return jnp.asarray(electrical_power_w) * jnp.asarray(efficiency) / (4.0 * np.pi * r * r)


def sound_pressure_level_db(intensity_w_m2, impedance_rayl, reference_pressure_pa=WATER_REFERENCE_PRESSURE_PA):
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
    return db10(jnp.asarray(intensity_w_m2) * jnp.asarray(impedance_rayl) / (p_ref * p_ref))


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
    return sound_pressure_level_db(intensity, impedance_rayl, WATER_REFERENCE_PRESSURE_PA)


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

    >>> import math
    >>> round(10 * math.log10(1.5e6 * 1e12 / (4 * math.pi)), 1) == SOURCE_LEVEL_CONSTANT_DB
    True
    >>> round(float(source_level_from_acoustic_power_db(1.0, 0.0)), 1)  # 1 W omnidirectional
    170.8
    """
    w = "source_level_from_acoustic_power_db"
    check_range("acoustic_power_w", acoustic_power_w, 0.0, None, lo_open=True, where=w)
    check_range("directivity_index_db", directivity_index_db, 0.0, 80.0, where=w)
    return SOURCE_LEVEL_CONSTANT_DB + db10(jnp.asarray(acoustic_power_w)) + jnp.asarray(directivity_index_db)


def drive_voltage_rms_v(electrical_power_w, conductance_s):
    """RMS drive voltage for a power into a transducer conductance ``V = sqrt(P / G)`` (V).

    Exact for a resistive load G.

    Args:
        electrical_power_w: electrical power P (W), in (0, ∞).
        conductance_s: transducer input conductance G (S), in (0, ∞).

    >>> round(float(drive_voltage_rms_v(1500.0, 5.5e-3)))  # book eqs (12.49)-(12.50): 522 V rms
    522
    """
    w = "drive_voltage_rms_v"
    check_range("electrical_power_w", electrical_power_w, 0.0, None, lo_open=True, where=w)
    check_range("conductance_s", conductance_s, 0.0, None, lo_open=True, where=w)
    return jnp.sqrt(jnp.asarray(electrical_power_w) / jnp.asarray(conductance_s))


def source_level_from_tvr_db(tvr_db, drive_voltage_rms_v_):
    """Source level from the transmitting voltage response ``SL = TVR + 20 log10 V`` (dB re 1 µPa at 1 m).

    Exact by definition of the TVR (read off the maker's curve at the operating frequency).

    Args:
        tvr_db: TVR (dB re 1 µPa/V at 1 m), in [50, 300].
        drive_voltage_rms_v_: RMS drive voltage V (V), in (0, ∞).

    >>> round(float(source_level_from_tvr_db(170.0, 522.0)), 2)  # book eq (12.51) prints 224.3 dB
    224.35
    """
    w = "source_level_from_tvr_db"
    check_range("tvr_db", tvr_db, 50.0, 300.0, where=w)
    check_range("drive_voltage_rms_v", drive_voltage_rms_v_, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(tvr_db) + db20(jnp.asarray(drive_voltage_rms_v_))


def equivalent_pressure_level_db(voltage_rms_v, receive_sensitivity_db):
    """Pressure level that would produce an RMS voltage ``L = 20 log10 V − M`` (dB re 1 µPa).

    Inverse of :func:`diffsense.physics.sea_noise.hydrophone_voltage_v` (book eqs (12.65)-(12.66));
    used to refer an amplifier's noise voltage to the water (book §12.8: 66 nV with
    M = −180 dB re 1 V/µPa → 36.4 dB).

    Args:
        voltage_rms_v: RMS voltage V (V), in (0, ∞).
        receive_sensitivity_db: open-circuit receive response M (dB re 1 V/µPa), in [-300, 0].

    The book's minimum detectable signal, 50 dB re 1 µPa, gives 10^(−130/20) V = 316 nV:

    >>> round(float(equivalent_pressure_level_db(10 ** (-130 / 20), -180.0)), 9)
    50.0
    """
    w = "equivalent_pressure_level_db"
    check_range("voltage_rms_v", voltage_rms_v, 0.0, None, lo_open=True, where=w)
    check_range("receive_sensitivity_db", receive_sensitivity_db, -300.0, 0.0, where=w)
    return db20(jnp.asarray(voltage_rms_v)) - jnp.asarray(receive_sensitivity_db)
