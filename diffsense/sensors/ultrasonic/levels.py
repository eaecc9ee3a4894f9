"""Ultrasound in air: transducer SPL for a drive voltage, receiver output for a µbar
sensitivity, one-way and pulse-echo received levels, and the book's beamwidth rule solved for
the wavelength or frequency.

Levels in air are sound pressure levels (SPL), dB re 20 µPa. Transducer makers quote the
transmitter's SPL at a reference distance (30 cm for the muRata MA40S4S) for a reference drive
voltage, and the receiver's sensitivity in dB re 1 V/µbar (1 µbar = 0.1 Pa).

Sources: G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009): §13.20
(ultrasonic beacon, eqs (13.26)-(13.31)); §8.16.2 (ultrasound rejected for the ore pass:
beamwidth rule θ = 70 λ/d, absorption); §12.8 (target strength, eq (12.54)).

The ultrasonic beacon of book §13.20: a MA40S4S (120 dB at 30 cm for 10 Vpp) driven at 20 Vpp,
received 3 m away through 1.2 dB/m by a MA40B8R (−63 dB re 1 V/µbar):

>>> from diffsense.sensors.ultrasonic.levels import (
...     one_way_received_spl_db, receiver_output_voltage_v, spl_at_reference_db)
>>> source = spl_at_reference_db(120.0, 20.0, 10.0)
>>> round(float(source))  # book: 126 dB
126
>>> received = one_way_received_spl_db(source, 3.0, 1.2)
>>> round(float(source - received), 1)  # book: 20 log10(3/0.3) + 1.2 × 3 = 23.6 dB
23.6
>>> round(float(receiver_output_voltage_v(102.4, -63.0)) * 1e3, 2)  # book: 18.6 mV (with −74 for −73.98 dB)
18.67
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db20, from_db20
from diffsense.physics import antennas
from diffsense.physics.constants import NOMINAL_AIR_SOUND_SPEED_M_S
from diffsense.physics.propagation import acoustic

__all__ = [
    "AIR_REFERENCE_PRESSURE_PA",
    "MICROBAR_PA",
    "SPL_TO_MICROBAR_DB",
    "spl_at_reference_db",
    "receiver_output_voltage_v",
    "receiver_output_level_dbv",
    "one_way_received_spl_db",
    "pulse_echo_received_spl_db",
    "max_wavelength_for_beamwidth_book_m",
    "min_frequency_for_beamwidth_book_hz",
]

AIR_REFERENCE_PRESSURE_PA = 20e-6
"""Reference pressure of SPL in air, 20 µPa (book eq (13.26))."""

MICROBAR_PA = 0.1
"""1 µbar = 0.1 Pa (book §13.20)."""

SPL_TO_MICROBAR_DB = 20.0 * math.log10(AIR_REFERENCE_PRESSURE_PA / MICROBAR_PA)
"""20 log10(20 µPa / 1 µbar) = 20 log10(2e-4) = −73.98 dB (the book's "−74")."""


def spl_at_reference_db(reference_spl_db, drive_voltage_v, reference_drive_voltage_v):
    """Transmitter SPL at its reference distance for a drive voltage ``L = L0 + 20 log10(V / V0)`` (dB re 20 µPa).

    Pressure is proportional to drive voltage in a linear transducer, so SPL scales as the
    square of V (book §13.20: MA40S4S 120 dB at 30 cm for 10 Vpp, driven at 20 Vpp → 126 dB).
    V and V0 in the same convention (both peak-to-peak or both RMS). Exact while the transducer
    stays linear (below its rated maximum drive).

    Args:
        reference_spl_db: L0, SPL at the reference distance for V0 (dB re 20 µPa), in [0, 250].
        drive_voltage_v: drive voltage V (V), in (0, ∞).
        reference_drive_voltage_v: V0 (V), in (0, ∞).
    """
    w = "spl_at_reference_db"
    check_range("reference_spl_db", reference_spl_db, 0.0, 250.0, where=w)
    check_range("drive_voltage_v", drive_voltage_v, 0.0, None, lo_open=True, where=w)
    check_range("reference_drive_voltage_v", reference_drive_voltage_v, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(reference_spl_db) + db20(jnp.asarray(drive_voltage_v) / jnp.asarray(reference_drive_voltage_v))


def receiver_output_level_dbv(spl_db, sensitivity_db_v_per_ubar):
    """Receiver output ``20 log10 V = L + M + 20 log10(20 µPa / 1 µbar)`` (dB re 1 V).

    The SPL L (re 20 µPa) is converted to µbar (20 µPa = 2e-4 µbar, −73.98 dB) and multiplied
    by the sensitivity M (dB re 1 V/µbar). Book §13.20: 102.4 − 63 − 74 → 18.6 mV. Exact.

    Args:
        spl_db: SPL at the receiver (dB re 20 µPa), in [-100, 250].
        sensitivity_db_v_per_ubar: M (dB re 1 V/µbar), in [-200, 50].
    """
    w = "receiver_output_level_dbv"
    check_range("spl_db", spl_db, -100.0, 250.0, where=w)
    check_range("sensitivity_db_v_per_ubar", sensitivity_db_v_per_ubar, -200.0, 50.0, where=w)
    return jnp.asarray(spl_db) + jnp.asarray(sensitivity_db_v_per_ubar) + SPL_TO_MICROBAR_DB


def receiver_output_voltage_v(spl_db, sensitivity_db_v_per_ubar):
    """RMS receiver output voltage (V) for an SPL and a µbar sensitivity; see :func:`receiver_output_level_dbv`."""
    return from_db20(receiver_output_level_dbv(spl_db, sensitivity_db_v_per_ubar))


def one_way_received_spl_db(source_spl_db, range_m, absorption_db_per_m, reference_range_m=0.3):
    """SPL at a receiver ``L_r = L_p − [20 log10(R / R_ref) + α R]`` (dB re 20 µPa), book eqs (13.30)-(13.31).

    Spherical spreading from the reference distance of the source level plus absorption over the
    whole path (the book's form). 126 dB at 0.3 m, 3 m, 1.2 dB/m → 102.4 dB. Exact for spherical
    spreading in a homogeneous medium in the far field.

    Args:
        source_spl_db: SPL at the reference distance (dB re 20 µPa), in [0, 250].
        range_m: R (m), in (0, ∞).
        absorption_db_per_m: α (dB/m), in [0, ∞).
        reference_range_m: R_ref (m), in (0, ∞).
    """
    check_range("source_spl_db", source_spl_db, 0.0, 250.0, where="one_way_received_spl_db")
    tl = acoustic.transmission_loss_db(range_m, absorption_db_per_m, "spherical", reference_range_m)
    return jnp.asarray(source_spl_db) - tl


def pulse_echo_received_spl_db(source_spl_db, range_m, absorption_db_per_m, target_strength_db, reference_range_m=0.3):
    """Echo SPL back at a co-located receiver (dB re 20 µPa).

    ``L_e = L_p − [20 log10(R/R_ref) + α R] + TS − [20 log10(R / 1 m) + α R]``: the incident
    level at the target, plus the target strength TS (dB re 1 m: the echo level 1 m from the
    target relative to the incident level, book eq (12.54)), spread back from 1 m to R.

    Args:
        source_spl_db: SPL at the reference distance (dB re 20 µPa), in [0, 250].
        range_m: target range R (m), in (0, ∞).
        absorption_db_per_m: α (dB/m), in [0, ∞).
        target_strength_db: TS (dB re 1 m), in [-150, 60].
        reference_range_m: R_ref (m), in (0, ∞).
    """
    check_range("target_strength_db", target_strength_db, -150.0, 60.0, where="pulse_echo_received_spl_db")
    incident = one_way_received_spl_db(source_spl_db, range_m, absorption_db_per_m, reference_range_m)
    back = acoustic.transmission_loss_db(range_m, absorption_db_per_m, "spherical", 1.0)
    return incident + jnp.asarray(target_strength_db) - back


def max_wavelength_for_beamwidth_book_m(diameter_m, beamwidth_deg):
    """Longest wavelength giving a beamwidth with an aperture, by the book's rule ``λ = θ d / 70`` (m).

    Inverse of :func:`diffsense.physics.antennas.beamwidth_book_deg` (θ_deg = 70 λ/d, a moderately
    tapered circular aperture). Book §8.16.2: d = 1 m, θ = 1.1° → 0.016 m. Accuracy that of the
    rule (the uniform circular aperture has 58.9 λ/d).

    Args:
        diameter_m: aperture diameter d (m), in (0, ∞).
        beamwidth_deg: required 3 dB beamwidth θ (degrees), in (0, 180].
    """
    w = "max_wavelength_for_beamwidth_book_m"
    check_range("diameter_m", diameter_m, 0.0, None, lo_open=True, where=w)
    check_range("beamwidth_deg", beamwidth_deg, 0.0, 180.0, lo_open=True, where=w)
    return jnp.asarray(beamwidth_deg) * jnp.asarray(diameter_m) / antennas.BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR


def min_frequency_for_beamwidth_book_hz(diameter_m, beamwidth_deg, propagation_speed_m_s=NOMINAL_AIR_SOUND_SPEED_M_S):
    """Lowest frequency giving a beamwidth with an aperture ``f = 70 c / (θ d)`` (Hz).

    Args:
        diameter_m: aperture diameter d (m), in (0, ∞).
        beamwidth_deg: 3 dB beamwidth θ (degrees), in (0, 180].
        propagation_speed_m_s: sound speed c (m/s), in (0, ∞); default 340 m/s (air).

    >>> round(float(min_frequency_for_beamwidth_book_hz(1.0, 1.1)) / 1e3, 1)  # book §8.16.2: 21.6 kHz
    21.6
    """
    check_range("propagation_speed_m_s", propagation_speed_m_s, 0.0, None, lo_open=True,
                where="min_frequency_for_beamwidth_book_hz")
    return jnp.asarray(propagation_speed_m_s) / max_wavelength_for_beamwidth_book_m(diameter_m, beamwidth_deg)
