"""Acoustic propagation: sound speed, absorption in sea water and air, spreading loss.

All functions are pure ``jax.numpy`` expressions: they accept scalars or broadcastable
arrays, and they can be traced by ``jit``, ``vmap`` and ``grad``. Domain checks run on
concrete arguments only (see :mod:`diffsense.numerics.checks`).

Sources
-------
- R. E. Francois and G. R. Garrison, "Sound absorption based on ocean measurements.
  Part I: Pure water and magnesium sulfate contributions", J. Acoust. Soc. Am. 72(3),
  896-907 (1982); "Part II: Boric acid contribution and equation for total absorption",
  J. Acoust. Soc. Am. 72(6), 1879-1890 (1982).
- K. V. Mackenzie, "Nine-term equation for sound speed in the oceans", J. Acoust. Soc.
  Am. 70(3), 807-812 (1981).
- ISO 9613-1:1993, Acoustics - Attenuation of sound during propagation outdoors -
  Part 1: Calculation of the absorption of sound by the atmosphere, clause 6 and Annex B.
- G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009),
  sections 12.7-12.8 (eqs 12.52-12.53, the sea-water absorption formula of eq. 7.44)
  and 13.20 (ultrasonic beacon link).
"""

from __future__ import annotations

import jax.numpy as jnp

import numpy as np

from diffsense.numerics.checks import check_choice, check_range, is_concrete
from diffsense.numerics.db import db10, db20
from diffsense.physics.constants import BOLTZMANN_J_K

__all__ = [
    "AVOGADRO_PER_MOL",
    "MOLAR_GAS_CONSTANT_J_MOL_K",
    "seawater_absorption_db_per_km",
    "seawater_absorption_simple_db_per_m",
    "air_absorption_db_per_m",
    "water_vapour_molar_concentration_pct",
    "sound_speed_seawater",
    "sound_speed_gas",
    "sound_speed_humid_air",
    "spherical_spreading_loss_db",
    "cylindrical_spreading_loss_db",
    "transmission_loss_db",
    "two_way_transmission_loss_db",
]

#: Avogadro constant (exact, SI 2019).
AVOGADRO_PER_MOL = 6.02214076e23
#: Molar gas constant R = N_A k (exact, SI 2019), J/(mol K).
MOLAR_GAS_CONSTANT_J_MOL_K = AVOGADRO_PER_MOL * BOLTZMANN_J_K


# --------------------------------------------------------------------------------------
# Sea water
# --------------------------------------------------------------------------------------


def seawater_absorption_db_per_km(freq_hz, temperature_c, salinity_ppt, depth_m, ph=8.0):
    """Absorption of sound in sea water, Francois & Garrison (1982), in dB/km.

    Sum of three relaxation/viscous contributions (f in kHz, T in deg C, S in ppt,
    z = depth in m)::

        alpha = A1 P1 f1 f^2/(f1^2 + f^2)        boric acid
              + A2 P2 f2 f^2/(f2^2 + f^2)        magnesium sulphate
              + A3 P3 f^2                        pure water

        c  = 1412 + 3.21 T + 1.19 S + 0.0167 z                    (m/s)
        A1 = 8.86/c * 10^(0.78 pH - 5)                             dB/(km kHz)
        P1 = 1
        f1 = 2.8 sqrt(S/35) 10^(4 - 1245/(273 + T))                kHz
        A2 = 21.44 S/c (1 + 0.025 T)                               dB/(km kHz)
        P2 = 1 - 1.37e-4 z + 6.2e-9 z^2
        f2 = 8.17 10^(8 - 1990/(273 + T)) / (1 + 0.0018 (S - 35))  kHz
        A3 = 4.937e-4 - 2.59e-5 T + 9.11e-7 T^2 - 1.50e-8 T^3      T <= 20 deg C
           = 3.964e-4 - 1.146e-5 T + 1.45e-7 T^2 - 6.5e-10 T^3     T >  20 deg C
        P3 = 1 - 3.83e-5 z + 4.9e-10 z^2

    (Part II, eqs 2-4 and the summary in its section IV; the MgSO4 and pure-water terms
    are those of Part I.) The two A3 polynomials meet to 1e-7 dB/(km kHz^2) at 20 deg C,
    so the switch costs no visible kink.

    Args:
        freq_hz: acoustic frequency, Hz. Domain [200, 1e6] (the paper's range).
        temperature_c: water temperature, deg C. Domain [-2, 30].
        salinity_ppt: salinity, parts per thousand. Domain (0, 40]. The boric-acid
            relaxation frequency goes as sqrt(S), so the derivative in S grows as S^-1/2
            towards fresh water; use a small positive S (e.g. 0.01) for fresh water.
        depth_m: depth, m. Domain [0, 10000].
        ph: pH of the water. Domain [6, 9] (oceans 7.7-8.3).

    Returns:
        Absorption coefficient in dB/km.

    Accuracy: Francois and Garrison estimate about 5 % against ocean measurements within
    -2..22 deg C, 30..35 ppt, 0..3.5 km for 10-500 kHz (MgSO4 dominated) and 0..30 deg C,
    0..40 ppt, 0..10 km above 500 kHz (pure-water dominated). Outside those limits the
    equation still evaluates smoothly but its error is not established.
    """
    where = "seawater_absorption_db_per_km"
    check_range("freq_hz", freq_hz, 200.0, 1.0e6, where=where)
    check_range("temperature_c", temperature_c, -2.0, 30.0, where=where)
    check_range("salinity_ppt", salinity_ppt, 0.0, 40.0, lo_open=True, where=where)
    check_range("depth_m", depth_m, 0.0, 10000.0, where=where)
    check_range("ph", ph, 6.0, 9.0, where=where)

    f = jnp.asarray(freq_hz) / 1000.0
    t = jnp.asarray(temperature_c)
    s = jnp.asarray(salinity_ppt)
    z = jnp.asarray(depth_m)
    ph = jnp.asarray(ph)
    f2_sq = f * f

    c = 1412.0 + 3.21 * t + 1.19 * s + 0.0167 * z
    theta = 273.0 + t

    a1 = 8.86 / c * 10.0 ** (0.78 * ph - 5.0)
    fr1 = 2.8 * jnp.sqrt(s / 35.0) * 10.0 ** (4.0 - 1245.0 / theta)
    boric = a1 * fr1 * f2_sq / (fr1 * fr1 + f2_sq)

    a2 = 21.44 * s / c * (1.0 + 0.025 * t)
    p2 = 1.0 - 1.37e-4 * z + 6.2e-9 * z * z
    fr2 = 8.17 * 10.0 ** (8.0 - 1990.0 / theta) / (1.0 + 0.0018 * (s - 35.0))
    mgso4 = a2 * p2 * fr2 * f2_sq / (fr2 * fr2 + f2_sq)

    a3_cold = 4.937e-4 - 2.59e-5 * t + 9.11e-7 * t**2 - 1.50e-8 * t**3
    a3_warm = 3.964e-4 - 1.146e-5 * t + 1.45e-7 * t**2 - 6.5e-10 * t**3
    a3 = jnp.where(t <= 20.0, a3_cold, a3_warm)
    p3 = 1.0 - 3.83e-5 * z + 4.9e-10 * z * z
    water = a3 * p3 * f2_sq

    return boric + mgso4 + water


def seawater_absorption_simple_db_per_m(freq_hz):
    """Sea-water absorption from the book's one-line formula, dB/m.

    ``alpha = 0.036 f^2/(f^2 + 3600) + 3.2e-7 f^2`` with f in kHz (Brooker eq. 7.44,
    used in section 12.8 for 5 deg C water: 0.0329 dB/m at 117 kHz). The first term is a
    single MgSO4-like relaxation at 60 kHz, the second the viscous term.

    Args:
        freq_hz: frequency, Hz. Domain (0, 1e6].

    Returns:
        Absorption coefficient in dB/m.

    >>> float(seawater_absorption_simple_db_per_m(117e3))   # book 12.8: 0.0329 dB/m
    0.0329

    Accuracy: an engineering fit for cold (about 5 deg C) sea water; against
    :func:`seawater_absorption_db_per_km` (5 deg C, 35 ppt, surface) it is within a
    factor of about 1.5 between 20 kHz and 1 MHz and it omits the boric acid term, so it
    underestimates absorption below about 5 kHz.
    """
    check_range("freq_hz", freq_hz, 0.0, 1.0e6, lo_open=True, where="seawater_absorption_simple_db_per_m")
    f = jnp.asarray(freq_hz) / 1000.0
    f_sq = f * f
    return 0.036 * f_sq / (f_sq + 3600.0) + 3.2e-7 * f_sq


def sound_speed_seawater(temperature_c, salinity_ppt, depth_m):
    """Speed of sound in sea water, Mackenzie (1981) nine-term equation, m/s.

    ::

        c = 1448.96 + 4.591 T - 5.304e-2 T^2 + 2.374e-4 T^3 + 1.340 (S - 35)
            + 1.630e-2 D + 1.675e-7 D^2 - 1.025e-2 T (S - 35) - 7.139e-13 T D^3

    Args:
        temperature_c: temperature, deg C. Domain [-2, 30].
        salinity_ppt: salinity, parts per thousand. Domain [25, 40].
        depth_m: depth, m. Domain [0, 8000].

    Returns:
        Sound speed in m/s.

    Accuracy: standard error 0.070 m/s against the data Mackenzie fitted, in his stated
    range 2-30 deg C, 25-40 ppt, 0-8000 m; check value 1550.744 m/s at 25 deg C, 35 ppt,
    1000 m (Mackenzie 1981):

    >>> float(sound_speed_seawater(25.0, 35.0, 1000.0))
    1550.744
    """
    where = "sound_speed_seawater"
    check_range("temperature_c", temperature_c, -2.0, 30.0, where=where)
    check_range("salinity_ppt", salinity_ppt, 25.0, 40.0, where=where)
    check_range("depth_m", depth_m, 0.0, 8000.0, where=where)
    t = jnp.asarray(temperature_c)
    ds = jnp.asarray(salinity_ppt) - 35.0
    d = jnp.asarray(depth_m)
    return (
        1448.96
        + 4.591 * t
        - 5.304e-2 * t**2
        + 2.374e-4 * t**3
        + 1.340 * ds
        + 1.630e-2 * d
        + 1.675e-7 * d**2
        - 1.025e-2 * t * ds
        - 7.139e-13 * t * d**3
    )


# --------------------------------------------------------------------------------------
# Air
# --------------------------------------------------------------------------------------

_ISO_T0_K = 293.15  # reference air temperature, ISO 9613-1 clause 6.2
_ISO_T01_K = 273.16  # triple-point isotherm, ISO 9613-1 Annex B
_ISO_PR_KPA = 101.325  # reference ambient pressure


def _saturation_ratio(temperature_k):
    """p_sat/p_r from ISO 9613-1 eq. (B.1)-(B.2): 10^(-6.8346 (T01/T)^1.261 + 4.6151)."""
    c = -6.8346 * (_ISO_T01_K / temperature_k) ** 1.261 + 4.6151
    return 10.0**c


def _check_vapour_fraction(temperature_k, relative_humidity_pct, pressure_kpa, where):
    """Reject concrete states whose water-vapour mole fraction would exceed 1 (p_sat > p)."""
    args = (temperature_k, relative_humidity_pct, pressure_kpa)
    if all(is_concrete(a) for a in args):
        x = (
            np.asarray(relative_humidity_pct, dtype=float)
            / 100.0
            * 10.0 ** (-6.8346 * (_ISO_T01_K / np.asarray(temperature_k, dtype=float)) ** 1.261 + 4.6151)
            * _ISO_PR_KPA
            / np.asarray(pressure_kpa, dtype=float)
        )
        check_range("water-vapour mole fraction (relative_humidity_pct/100 * p_sat / pressure)", x, 0.0, 1.0, where=where)


def water_vapour_molar_concentration_pct(temperature_k, relative_humidity_pct, pressure_kpa=101.325):
    """Molar concentration of water vapour h (percent) from relative humidity.

    ISO 9613-1:1993 eq. (B.1): ``h = h_r (p_sat/p_r) / (p_a/p_r)`` with the saturation
    vapour pressure ratio of eq. (B.2)-(B.3):
    ``p_sat/p_r = 10^C``, ``C = -6.8346 (T01/T)^1.261 + 4.6151``, T01 = 273.16 K.

    Args:
        temperature_k: air temperature, K. Domain [200, 373.15].
        relative_humidity_pct: relative humidity, percent. Domain [0, 100].
        pressure_kpa: ambient pressure, kPa. Domain (0, 200], and jointly the result
            must not exceed 100 % (p_sat(T) x RH <= p).

    Returns:
        Molar concentration of water vapour, percent (mole fraction x 100).

    Accuracy: the standard states the saturation formula reproduces the WMO tables
    within 0.5 % between -50 deg C and +50 deg C (note to eq. B.3).

    Saturated air at 20 deg C: the WMO saturation pressure 2.339 kPa over 101.325 kPa:

    >>> float(water_vapour_molar_concentration_pct(293.15, 100.0)), 100 * 2.339 / 101.325
    (2.31, 2.31)
    """
    where = "water_vapour_molar_concentration_pct"
    check_range("temperature_k", temperature_k, 200.0, 373.15, where=where)
    check_range("relative_humidity_pct", relative_humidity_pct, 0.0, 100.0, where=where)
    check_range("pressure_kpa", pressure_kpa, 0.0, 200.0, lo_open=True, where=where)
    _check_vapour_fraction(temperature_k, relative_humidity_pct, pressure_kpa, where)
    t = jnp.asarray(temperature_k)
    return jnp.asarray(relative_humidity_pct) * _saturation_ratio(t) * _ISO_PR_KPA / jnp.asarray(pressure_kpa)


def air_absorption_db_per_m(freq_hz, temperature_k=293.15, relative_humidity_pct=50.0, pressure_kpa=101.325):
    """Pure-tone atmospheric absorption coefficient, ISO 9613-1:1993, dB/m.

    Eq. (5) of ISO 9613-1 (pa in kPa, T in K, f in Hz, h in percent)::

        alpha = 8.686 f^2 [ 1.84e-11 (pa/pr)^-1 (T/T0)^(1/2)
                + (T/T0)^(-5/2) ( 0.01275 exp(-2239.1/T) / (frO + f^2/frO)
                                 + 0.1068  exp(-3352.0/T) / (frN + f^2/frN) ) ]
        frO = (pa/pr) (24 + 4.04e4 h (0.02 + h)/(0.391 + h))                  eq. (3)
        frN = (pa/pr) (T/T0)^(-1/2) (9 + 280 h exp(-4.170 ((T/T0)^(-1/3) - 1)))  eq. (4)

    with T0 = 293.15 K, pr = 101.325 kPa, and h from
    :func:`water_vapour_molar_concentration_pct` (Annex B).

    Args:
        freq_hz: frequency, Hz. Domain [10, 1e6].
        temperature_k: air temperature, K. Domain [253, 324] (about -20 to +50 deg C).
        relative_humidity_pct: relative humidity, percent. Domain [0, 100].
        pressure_kpa: ambient pressure, kPa. Domain [1, 200], and jointly the
            water-vapour mole fraction h/100 must not exceed 1 (p_sat(T) x RH <= p).

    Returns:
        Attenuation coefficient in dB/m.

    Accuracy (ISO 9613-1 clause 7): +-10 % for water-vapour molar concentration
    0.05 %-5 %, 253-323 K, pressure below 200 kPa, and f/pa between 4e-4 and 10 Hz/Pa
    (about 40 Hz to 1 MHz at sea level); +-20 % for 0.005 %-0.05 % concentration and
    wider ranges described there.

    ISO 9613-1 Table 1 prints 4.98 dB/km at 20 deg C, 70 % RH, 1 kHz:

    >>> 1e3 * float(air_absorption_db_per_m(1e3, 293.15, 70.0))
    4.98
    """
    where = "air_absorption_db_per_m"
    check_range("freq_hz", freq_hz, 10.0, 1.0e6, where=where)
    check_range("temperature_k", temperature_k, 253.0, 324.0, where=where)
    check_range("relative_humidity_pct", relative_humidity_pct, 0.0, 100.0, where=where)
    check_range("pressure_kpa", pressure_kpa, 1.0, 200.0, where=where)
    _check_vapour_fraction(temperature_k, relative_humidity_pct, pressure_kpa, where)

    f = jnp.asarray(freq_hz)
    t = jnp.asarray(temperature_k)
    pa = jnp.asarray(pressure_kpa) / _ISO_PR_KPA
    h = jnp.asarray(relative_humidity_pct) * _saturation_ratio(t) / pa
    tr = t / _ISO_T0_K

    fr_o = pa * (24.0 + 4.04e4 * h * (0.02 + h) / (0.391 + h))
    fr_n = pa * tr ** (-0.5) * (9.0 + 280.0 * h * jnp.exp(-4.170 * (tr ** (-1.0 / 3.0) - 1.0)))
    f_sq = f * f
    classical = 1.84e-11 / pa * jnp.sqrt(tr)
    oxygen = 0.01275 * jnp.exp(-2239.1 / t) / (fr_o + f_sq / fr_o)
    nitrogen = 0.1068 * jnp.exp(-3352.0 / t) / (fr_n + f_sq / fr_n)
    return 8.686 * f_sq * (classical + tr ** (-2.5) * (oxygen + nitrogen))


def sound_speed_gas(temperature_k, gamma=1.4, molar_mass_kg_mol=0.0289645):
    """Speed of sound in an ideal gas, ``c = sqrt(gamma R T / M)``, m/s.

    Defaults are dry air (gamma = 1.4, M = 28.9645 g/mol). R = N_A k exactly.

    Args:
        temperature_k: temperature, K. Domain (0, 3000].
        gamma: ratio of specific heats. Domain (1, 5/3].
        molar_mass_kg_mol: molar mass, kg/mol. Domain (0, 1].

    Returns:
        Sound speed in m/s.

    Accuracy: exact for an ideal gas; for dry air at 0-40 deg C the ideal-gas value
    with gamma = 1.4 is within about 0.1 % of measured values (real-gas and CO2
    corrections; Cramer 1993). The book rounds to 340 m/s in air.

    >>> float(sound_speed_gas(273.15)), (1.4 * 8.314462618 * 273.15 / 0.0289645) ** 0.5   # dry air, 0 deg C
    (331.3, 331.3)
    """
    where = "sound_speed_gas"
    check_range("temperature_k", temperature_k, 0.0, 3000.0, lo_open=True, where=where)
    check_range("gamma", gamma, 1.0, 5.0 / 3.0, lo_open=True, where=where)
    check_range("molar_mass_kg_mol", molar_mass_kg_mol, 0.0, 1.0, lo_open=True, where=where)
    return jnp.sqrt(
        jnp.asarray(gamma) * MOLAR_GAS_CONSTANT_J_MOL_K * jnp.asarray(temperature_k) / jnp.asarray(molar_mass_kg_mol)
    )


_M_DRY_AIR = 0.0289645  # kg/mol
_M_WATER = 0.01801528  # kg/mol


def sound_speed_humid_air(temperature_k, relative_humidity_pct=50.0, pressure_kpa=101.325):
    """Speed of sound in humid air as an ideal-gas mixture of dry air and water vapour, m/s.

    Mole fraction of water x = h/100 from :func:`water_vapour_molar_concentration_pct`
    (ISO 9613-1 Annex B). Molar heat capacities add by mole fraction::

        M     = (1 - x) M_air + x M_w                (28.9645, 18.01528 g/mol)
        Cp/R  = (1 - x) 7/2   + x 4                  (diatomic air; non-linear triatomic H2O)
        gamma = Cp / (Cp - R)
        c     = sqrt(gamma R T / M)

    Args:
        temperature_k: air temperature, K. Domain [253, 324].
        relative_humidity_pct: relative humidity, percent. Domain [0, 100].
        pressure_kpa: ambient pressure, kPa. Domain [1, 200], and jointly the
            water-vapour mole fraction must not exceed 1 (p_sat(T) x RH <= p).

    Returns:
        Sound speed in m/s.

    Accuracy: ideal-gas mixture (no virial, CO2 or dispersion corrections). With
    ``relative_humidity_pct=0`` it equals :func:`sound_speed_gas` exactly (within 0.1 % of
    Cramer's dry-air value at 0-30 deg C). The humidity increment (about +0.6 m/s at
    20 deg C, 50 % RH) agrees with the water-vapour term of Cramer (1993, JASA 93(5) 2510)
    within 5 % over 0-30 deg C and 30-100 % RH.
    """
    where = "sound_speed_humid_air"
    check_range("temperature_k", temperature_k, 253.0, 324.0, where=where)
    check_range("relative_humidity_pct", relative_humidity_pct, 0.0, 100.0, where=where)
    check_range("pressure_kpa", pressure_kpa, 1.0, 200.0, where=where)
    _check_vapour_fraction(temperature_k, relative_humidity_pct, pressure_kpa, where)
    t = jnp.asarray(temperature_k)
    x = jnp.asarray(relative_humidity_pct) * _saturation_ratio(t) * _ISO_PR_KPA / jnp.asarray(pressure_kpa) / 100.0
    molar_mass = (1.0 - x) * _M_DRY_AIR + x * _M_WATER
    cp_over_r = (1.0 - x) * 3.5 + x * 4.0
    gamma = cp_over_r / (cp_over_r - 1.0)
    return jnp.sqrt(gamma * MOLAR_GAS_CONSTANT_J_MOL_K * t / molar_mass)


# --------------------------------------------------------------------------------------
# Spreading and transmission loss
# --------------------------------------------------------------------------------------


def spherical_spreading_loss_db(range_m, reference_range_m=1.0):
    """Spherical (inverse-square) spreading loss ``20 log10(R/R_ref)``, dB (one way).

    Args:
        range_m: range, m. Domain (0, inf).
        reference_range_m: reference range, m (1 m for sonar source levels). Domain (0, inf).

    Returns:
        Loss in dB (negative when R < R_ref).

    Source: Brooker eq. 12.52 (first term). Exact for a point source in a homogeneous,
    unbounded medium in the far field.

    >>> float(spherical_spreading_loss_db(1000.0))     # 20 log10 1000
    60.0
    """
    where = "spherical_spreading_loss_db"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=where)
    check_range("reference_range_m", reference_range_m, 0.0, None, lo_open=True, where=where)
    return db20(jnp.asarray(range_m) / jnp.asarray(reference_range_m))


def cylindrical_spreading_loss_db(range_m, transition_range_m=None, reference_range_m=1.0):
    """Cylindrical spreading loss, dB (one way).

    Without a transition range: ``10 log10(R/R_ref)`` (sound trapped in a duct or
    channel). With a transition range R_t (e.g. about the water depth): spherical
    spreading out to R_t, cylindrical beyond::

        TL = 20 log10(R/R_ref)                          R <= R_t
           = 20 log10(R_t/R_ref) + 10 log10(R/R_t)      R >  R_t

    Args:
        range_m: range, m. Domain (0, inf).
        transition_range_m: spherical-to-cylindrical transition range, m, or ``None``.
            Domain (0, inf).
        reference_range_m: reference range, m. Domain (0, inf).

    Returns:
        Loss in dB. Continuous at R_t; the slope halves there (a kink, so the gradient
        with respect to range is one-sided at exactly R = R_t).

    Source: standard sonar shallow-water model (e.g. Urick, *Principles of Underwater
    Sound*, 3rd ed., section 5.2); exact in the two limiting geometries.

    >>> float(cylindrical_spreading_loss_db(1000.0, 100.0))   # 20 log10 100 + 10 log10 10
    50.0
    """
    where = "cylindrical_spreading_loss_db"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=where)
    check_range("reference_range_m", reference_range_m, 0.0, None, lo_open=True, where=where)
    r = jnp.asarray(range_m)
    r_ref = jnp.asarray(reference_range_m)
    if transition_range_m is None:
        return db10(r / r_ref)
    check_range("transition_range_m", transition_range_m, 0.0, None, lo_open=True, where=where)
    r_t = jnp.asarray(transition_range_m)
    near = db20(r / r_ref)
    far = db20(r_t / r_ref) + db10(r / r_t)
    return jnp.where(r <= r_t, near, far)


_SPREADINGS = ("spherical", "cylindrical")


def transmission_loss_db(
    range_m,
    absorption_db_per_m,
    spreading="spherical",
    reference_range_m=1.0,
    *,
    transition_range_m=None,
    absorb_from_reference=False,
):
    """One-way acoustic transmission loss: spreading plus absorption, dB.

    ::

        H = spreading(R, R_ref) + alpha R              (Brooker eq. 12.53, section 13.20)
        H = spreading(R, R_ref) + alpha (R - R_ref)    (eq. 12.52; absorb_from_reference=True)

    The book's ultrasonic beacon (13.20) uses the first form with R_ref = 0.3 m:
    ``20 log10(3/0.3) + 1.2 x 3 = 23.6 dB``.

    Args:
        range_m: range, m. Domain (0, inf).
        absorption_db_per_m: absorption coefficient, dB/m. Domain [0, inf).
        spreading: ``"spherical"`` (20 log10) or ``"cylindrical"`` (10 log10; with
            ``transition_range_m`` spherical then cylindrical). Static.
        reference_range_m: range of the reference level, m. Domain (0, inf).
        transition_range_m: see :func:`cylindrical_spreading_loss_db`.
        absorb_from_reference: count absorption from R_ref instead of from 0. Static.

    Returns:
        Loss in dB.

    >>> float(transmission_loss_db(3.0, 1.2, reference_range_m=0.3))   # book 13.20: 23.6 dB
    23.6
    """
    where = "transmission_loss_db"
    check_choice("spreading", spreading, _SPREADINGS, where=where)
    check_range("absorption_db_per_m", absorption_db_per_m, 0.0, None, where=where)
    if spreading == "spherical":
        geometric = spherical_spreading_loss_db(range_m, reference_range_m)
    else:
        geometric = cylindrical_spreading_loss_db(range_m, transition_range_m, reference_range_m)
    path = jnp.asarray(range_m)
    if absorb_from_reference:
        path = path - jnp.asarray(reference_range_m)
    return geometric + jnp.asarray(absorption_db_per_m) * path


def two_way_transmission_loss_db(
    range_m,
    absorption_db_per_m,
    spreading="spherical",
    reference_range_m=1.0,
    *,
    transition_range_m=None,
    absorb_from_reference=False,
):
    """Two-way (echo) transmission loss ``2 H``, dB.

    For spherical spreading from 1 m this is ``40 log10 R + 2 alpha R``, the term in the
    book's echo-level equation ``E = SL - 2H + TS`` (Brooker section 12.8:
    ``225.3 - 40 log10 R - 0.0656 R - 12``). Arguments as :func:`transmission_loss_db`.
    """
    return 2.0 * transmission_loss_db(
        range_m,
        absorption_db_per_m,
        spreading,
        reference_range_m,
        transition_range_m=transition_range_m,
        absorb_from_reference=absorb_from_reference,
    )
