"""Underwater ambient noise and its voltage at a hydrophone.

Pure ``jnp`` formulas, jit/vmap/grad-able. Levels in dB: noise spectrum levels dB re 1 µPa²/Hz,
band levels and pressure levels dB re 1 µPa, receive responses dB re 1 V/µPa.

Sources (book = Brooker, *Introduction to Sensors for Ranging and Imaging*): sea-surface noise
§12.8 eq (12.61) and Table 12.2 (Knudsen's levels); thermal noise of the water §9.1.4 eq (9.10)
(Mellen 1952); band level through a directive receiver eq (12.64); hydrophone voltage eqs
(12.65)–(12.66).

The side-scan example of book §12.8 (sea state 3 at 117 kHz, 3 kHz band, directivity 458.4):

>>> from diffsense.physics.sea_noise import band_noise_level_db, sea_surface_noise_spectrum_level_db
>>> n_f = sea_surface_noise_spectrum_level_db(3.0, 117e3)
>>> round(float(n_f)), round(float(band_noise_level_db(n_f, 3e3, 458.4)))  # book: 30 dB, 38 dB
(30, 38)
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10, from_db20, power_sum_db
from diffsense.physics.sea_state import SEA_STATE_TABLE_12_2

__all__ = [
    "sea_surface_noise_1khz_db",
    "sea_surface_noise_spectrum_level_db",
    "thermal_sea_noise_spectrum_level_db",
    "ambient_sea_noise_spectrum_level_db",
    "band_noise_level_db",
    "hydrophone_voltage_v",
]


def sea_surface_noise_1khz_db(sea_state):
    """Sea-surface noise spectrum level at 1 kHz (dB re 1 µPa²/Hz) for a sea state.

    Linear interpolation of the book's Table 12.2: sea state 0, 0.5, 1, 2, 3, 6 →
    45, 50, 55, 60, 65, 70 dB (Knudsen's levels; isotropic, 1 Hz band).

    Args:
        sea_state: sea state (continuous), in [0, 6].
    """
    check_range("sea_state", sea_state, 0.0, 6.0, where="sea_surface_noise_1khz_db")
    t = SEA_STATE_TABLE_12_2
    return jnp.interp(sea_state, t["sea_state"], t["noise_1khz_db"])


def sea_surface_noise_spectrum_level_db(sea_state, freq_hz):
    """Wind/wave noise spectrum level ``N_f = N_1 − 17 log10 f_kHz`` (dB re 1 µPa²/Hz).

    Knudsen's −17 dB/decade (−5 dB/octave) slope from the 1 kHz level of Table 12.2 (book
    eq (12.61)); e.g. sea state 3 at 117 kHz → 65 − 35.2 = 30 dB.

    Args:
        sea_state: in [0, 6].
        freq_hz: frequency (Hz), in [500, 2e5]. Below ≈ 500 Hz shipping noise dominates
            (Wenz); above ≈ 50–100 kHz thermal noise takes over at low sea states (see
            :func:`ambient_sea_noise_spectrum_level_db`).
    """
    check_range("freq_hz", freq_hz, 500.0, 2e5, where="sea_surface_noise_spectrum_level_db")
    return sea_surface_noise_1khz_db(sea_state) - 17.0 * jnp.log10(freq_hz / 1e3)


def thermal_sea_noise_spectrum_level_db(freq_hz):
    """Molecular thermal noise of sea water ``N_therm = −15 + 20 log10 f_kHz`` (dB re 1 µPa²/Hz).

    Source: Mellen, R. H. (1952), "The thermal-noise limit in the detection of underwater
    acoustic signals", J. Acoust. Soc. Am. 24, 478–480; quoted in the book as eq (9.10)
    (after Waite 2002).

    Args:
        freq_hz: frequency (Hz), in [1e3, 1e7].

    >>> round(float(thermal_sea_noise_spectrum_level_db(100e3)), 9)  # −15 + 20 log10(100)
    25.0
    """
    check_range("freq_hz", freq_hz, 1e3, 1e7, where="thermal_sea_noise_spectrum_level_db")
    return -15.0 + 20.0 * jnp.log10(freq_hz / 1e3)


def ambient_sea_noise_spectrum_level_db(sea_state, freq_hz):
    """Sea-surface plus thermal noise, summed as powers (dB re 1 µPa²/Hz).

    Args:
        sea_state: in [0, 6].
        freq_hz: frequency (Hz), in [1e3, 2e5].
    """
    check_range("freq_hz", freq_hz, 1e3, 2e5, where="ambient_sea_noise_spectrum_level_db")
    a = sea_surface_noise_spectrum_level_db(sea_state, freq_hz)
    b = thermal_sea_noise_spectrum_level_db(freq_hz)
    return power_sum_db(a, b)


def band_noise_level_db(spectrum_level_db, bandwidth_hz, directivity=1.0):
    """Noise level in a band seen by a directive receiver ``L_N = N_f + 10 log10 β − 10 log10 G``.

    Isotropic noise; G is the directivity (linear) of the receiving array. Book eq (12.64):
    30 + 10 log10(3000) − 10 log10(458.4) = 38 dB.

    Args:
        spectrum_level_db: noise spectrum level (dB re 1 µPa²/Hz), in [-100, 200].
        bandwidth_hz: receiver bandwidth β (Hz), in (0, ∞).
        directivity: directivity G (linear), in [1, ∞).
    """
    w = "band_noise_level_db"
    check_range("spectrum_level_db", spectrum_level_db, -100.0, 200.0, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("directivity", directivity, 1.0, None, where=w)
    return spectrum_level_db + db10(bandwidth_hz) - db10(directivity)


def hydrophone_voltage_v(pressure_level_db, receive_sensitivity_db):
    """Open-circuit RMS output voltage ``V = 10^((L + M)/20)`` (V) of a hydrophone.

    Args:
        pressure_level_db: pressure level L (dB re 1 µPa), in [-100, 300].
        receive_sensitivity_db: open-circuit receive response M (dB re 1 V/µPa), in [-300, 0].

    Book eqs (12.65)–(12.66): 50 dB with −180 dB re 1 V/µPa → 316 nV (printed 320 nV):

    >>> round(float(hydrophone_voltage_v(50.0, -180.0)) * 1e9, 1)  # 10^(−130/20) V in nV
    316.2
    """
    w = "hydrophone_voltage_v"
    check_range("pressure_level_db", pressure_level_db, -100.0, 300.0, where=w)
    check_range("receive_sensitivity_db", receive_sensitivity_db, -300.0, 0.0, where=w)
    return from_db20(jnp.asarray(pressure_level_db) + jnp.asarray(receive_sensitivity_db))
