"""Sea state: the scales that turn a sea-state number into wind speed and wave height.

Three published scales are in use and they are not interchangeable, so each has its own name:

- the book's Table 12.2 (Brooker, *Introduction to Sensors for Ranging and Imaging*, §12.8):
  sea state ↔ wind speed (knots) ↔ sea-surface noise level at 1 kHz (Knudsen), used for sea
  clutter (through the Beaufort force) and for ambient sea noise;
- the Douglas / U.S. Hydrographic Office scale of wave-height bands (feet), the one the book
  quotes for sea state 5 (§14.9, "very rough, wave height 2.4 to 3.6 m");
- the WMO sea-state code (WMO code table 3700) of significant wave height H_1/3 (m), used for
  the rough-sea reflection of multipath (:mod:`diffsense.physics.propagation.multipath`).

Wind speed and the Beaufort force are linked by the WMO (1946) equivalent-speed relation
``v = 0.836 K_B^(3/2)`` m/s at 10 m height.

>>> float(sea_state_wind_speed_knots(3.0))        # Table 12.2: sea state 3 ↔ 15 knots
15.0
>>> sea_state_wave_height_range_m(5)               # Douglas 8-12 ft; book §14.9: 2.4 to 3.6 m
(2.4384, 3.6576)
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range

__all__ = [
    "KNOT_M_S",
    "SEA_STATE_TABLE_12_2",
    "SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M",
    "sea_state_wind_speed_knots",
    "beaufort_from_wind_speed",
    "beaufort_from_sea_state",
    "sea_state_wave_height_range_m",
    "rms_wave_height_from_sea_state_m",
]

KNOT_M_S = 1852.0 / 3600.0
"""One international knot in m/s (exact: 1852 m per hour)."""

SEA_STATE_TABLE_12_2 = {
    "sea_state": np.array([0.0, 0.5, 1.0, 2.0, 3.0, 6.0]),
    "wind_speed_knots": np.array([0.0, 2.0, 5.0, 10.0, 15.0, 35.0]),
    "noise_1khz_db": np.array([45.0, 50.0, 55.0, 60.0, 65.0, 70.0]),
}
"""Book Table 12.2 (§12.8): sea state, wind speed (knots) and isotropic noise spectrum level at
1 kHz (dB re 1 µPa²/Hz, 1 Hz band)."""

# Douglas / U.S. Hydrographic Office sea-state scale, wave height bands in feet.
_DOUGLAS_WAVE_HEIGHT_FT = {
    0: (0.0, 0.0),
    1: (0.0, 1.0),
    2: (1.0, 3.0),
    3: (3.0, 5.0),
    4: (5.0, 8.0),
    5: (8.0, 12.0),
    6: (12.0, 20.0),
    7: (20.0, 40.0),
    8: (40.0, float("inf")),
}
_M_PER_FT = 0.3048

#: WMO sea-state code (code table 3700): mid-band significant wave height H_1/3 (m) of the
#: bands 0: 0, 1: 0-0.1, 2: 0.1-0.5, 3: 0.5-1.25, 4: 1.25-2.5, 5: 2.5-4, 6: 4-6, 7: 6-9, 8: 9-14.
SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M = {0: 0.0, 1: 0.05, 2: 0.3, 3: 0.875, 4: 1.875, 5: 3.25,
                                       6: 5.0, 7: 7.5, 8: 11.5}


def sea_state_wind_speed_knots(sea_state):
    """Wind speed (knots) for a sea state, by linear interpolation of the book's Table 12.2.

    Table 12.2 (book §12.8): sea state 0, 0.5, 1, 2, 3, 6 ↔ wind 0, 2, 5, 10, 15, 35 knots.
    Between rows the interpolation is linear (derivative piecewise constant).

    Args:
        sea_state: sea state (continuous), in [0, 6].

    >>> float(sea_state_wind_speed_knots(6.0)), float(sea_state_wind_speed_knots(2.5))   # 35; (10 + 15)/2
    (35.0, 12.5)
    """
    check_range("sea_state", sea_state, 0.0, 6.0, where="sea_state_wind_speed_knots")
    t = SEA_STATE_TABLE_12_2
    return jnp.interp(sea_state, t["sea_state"], t["wind_speed_knots"])


def beaufort_from_wind_speed(wind_speed_m_s):
    """Beaufort force from wind speed: ``K_B = (v / 0.836)^(2/3)`` (v in m/s at 10 m height).

    Inverse of the Beaufort equivalent-speed relation ``v = 0.836 K_B^(3/2)`` m/s adopted by the
    WMO (1946). Continuous; rounding gives the Beaufort number whose band (WMO Beaufort table:
    1–3 kn force 1, …, 56–63 kn force 11, ≥64 kn force 12) contains v.

    Args:
        wind_speed_m_s: wind speed (m/s), in (0, 40]. (Zero is excluded because dK_B/dv is
            infinite there.)

    >>> float(beaufort_from_wind_speed(0.836 * 4.0 ** 1.5))   # v = 0.836 K^(3/2) with K = 4
    4.0
    """
    check_range("wind_speed_m_s", wind_speed_m_s, 0.0, 40.0, lo_open=True, where="beaufort_from_wind_speed")
    return (wind_speed_m_s / 0.836) ** (2.0 / 3.0)


def beaufort_from_sea_state(sea_state):
    """Beaufort force for a sea state: book Table 12.2 wind speed, then ``(v/0.836)^(2/3)``.

    Args:
        sea_state: sea state (continuous), in (0, 6].

    Sea state 3 is 15 knots, 7.72 m/s: Beaufort 4.4 (the WMO band of force 4 is 11-16 knots):

    >>> float(beaufort_from_sea_state(3.0)), (15 * 1852 / 3600 / 0.836) ** (2 / 3)
    (4.4003, 4.4003)
    """
    check_range("sea_state", sea_state, 0.0, 6.0, lo_open=True, where="beaufort_from_sea_state")
    return beaufort_from_wind_speed(sea_state_wind_speed_knots(sea_state) * KNOT_M_S)


def sea_state_wave_height_range_m(sea_state: int) -> tuple[float, float]:
    """Wave-height band (m) of an integer sea state (Douglas / U.S. Hydrographic Office scale).

    Bands in feet: 0: calm; 1: <1; 2: 1–3; 3: 3–5; 4: 5–8; 5: 8–12; 6: 12–20; 7: 20–40;
    8: >40, converted at 0.3048 m/ft. This is the scale the book quotes for sea state 5
    ("very rough, wave height 2.4 to 3.6 m", §14.9). A lookup on a static integer (not traced).

    Args:
        sea_state: integer sea state 0–8.
    """
    if sea_state not in _DOUGLAS_WAVE_HEIGHT_FT:
        raise DomainError(f"sea_state_wave_height_range_m: argument 'sea_state' must be an integer 0-8; got {sea_state!r}")
    lo, hi = _DOUGLAS_WAVE_HEIGHT_FT[sea_state]
    return lo * _M_PER_FT, hi * _M_PER_FT


def rms_wave_height_from_sea_state_m(sea_state):
    """RMS sea-surface height ``sigma_h = H_1/3 / 4`` (m) for a WMO sea-state code 0..8 (static int).

    H_1/3 is the mid-band significant wave height of the WMO code
    (:data:`SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M`); H_1/3 = 4 sigma_h holds for Rayleigh-distributed
    wave heights of a narrow-band sea.

    >>> rms_wave_height_from_sea_state_m(4), (1.25 + 2.5) / 2 / 4     # code 4: 1.25-2.5 m
    (0.46875, 0.46875)
    """
    if sea_state not in SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M:
        raise DomainError(
            f"rms_wave_height_from_sea_state_m: argument 'sea_state' must be an integer 0..8; got {sea_state!r}"
        )
    return SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M[sea_state] / 4.0
