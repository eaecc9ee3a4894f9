"""Rain specific attenuation: ITU-R P.838-3 power law gamma_R = k R^alpha (1-1000 GHz).

Rec. ITU-R P.838-3 (03/2005), eqs. (1)-(5)::

    gamma_R = k R^alpha                                                      [dB/km]
    log10 k = sum_{j=1..4} a_j exp(-((log10 f - b_j)/c_j)^2) + m_k log10 f + c_k
    alpha   = sum_{j=1..5} a_j exp(-((log10 f - b_j)/c_j)^2) + m_a log10 f + c_a
    k       = [k_H + k_V + (k_H - k_V) cos^2(theta) cos(2 tau)] / 2
    alpha   = [k_H a_H + k_V a_V + (k_H a_H - k_V a_V) cos^2(theta) cos(2 tau)] / (2 k)

with f in GHz, R the rain rate (mm/h), theta the path elevation angle and tau the
polarization tilt angle relative to the horizontal (0° horizontal, 90° vertical, 45°
circular). Coefficients: P.838-3 Tables 1 (k_H), 2 (k_V), 3 (alpha_H), 4 (alpha_V).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range

__all__ = ["rain_attenuation_db_per_km", "rain_coefficients"]

_WHERE = "ITU-R P.838-3 rain attenuation"

# P.838-3 Table 1: coefficients for k_H (rows j = 1..4: a_j, b_j, c_j); m_k, c_k
_KH_ABC = np.array([[-5.33980, -0.10008, 1.13098],
                    [-0.35351, 1.26970, 0.45400],
                    [-0.23789, 0.86036, 0.15354],
                    [-0.94158, 0.64552, 0.16817]])
_KH_M, _KH_C = -0.18961, 0.71147
# P.838-3 Table 2: coefficients for k_V
_KV_ABC = np.array([[-3.80595, 0.56934, 0.81061],
                    [-3.44965, -0.22911, 0.51059],
                    [-0.39902, 0.73042, 0.11899],
                    [0.50167, 1.07319, 0.27195]])
_KV_M, _KV_C = -0.16398, 0.63297
# P.838-3 Table 3: coefficients for alpha_H (rows j = 1..5); m_alpha, c_alpha
_AH_ABC = np.array([[-0.14318, 1.82442, -0.55187],
                    [0.29591, 0.77564, 0.19822],
                    [0.32177, 0.63773, 0.13164],
                    [-5.37610, -0.96230, 1.47828],
                    [16.1721, -3.29980, 3.43990]])
_AH_M, _AH_C = 0.67849, -1.95537
# P.838-3 Table 4: coefficients for alpha_V
_AV_ABC = np.array([[-0.07771, 2.33840, -0.76284],
                    [0.56727, 0.95545, 0.54039],
                    [-0.20238, 1.14520, 0.26809],
                    [-48.2991, 0.791669, 0.116226],
                    [48.5833, 0.791459, 0.116479]])
_AV_M, _AV_C = -0.053739, 0.83433

_NAMED_TILTS_DEG = {"horizontal": 0.0, "vertical": 90.0, "circular": 45.0}


def _gauss_sum(log_f, abc, m, c):
    a, b, cc = (jnp.asarray(abc[:, i]) for i in range(3))
    x = log_f[..., None]
    return jnp.sum(a * jnp.exp(-(((x - b) / cc) ** 2)), axis=-1) + m * log_f + c


def _tilt_deg(polarization):
    if isinstance(polarization, str):
        if polarization not in _NAMED_TILTS_DEG:
            raise DomainError(
                f"{_WHERE}: argument 'polarization' must be one of "
                f"{sorted(_NAMED_TILTS_DEG)} or a tilt angle in degrees; got {polarization!r}"
            )
        return _NAMED_TILTS_DEG[polarization]
    check_range("polarization (tilt, deg)", polarization, -90.0, 180.0, where=_WHERE)
    return jnp.asarray(polarization, dtype=float)


def rain_coefficients(freq_hz, polarization="horizontal", elevation_deg=0.0):
    """Coefficients (k, alpha) of gamma_R = k R^alpha, ITU-R P.838-3 eqs. (2)-(5).

    Args:
        freq_hz: frequency (Hz), 1e9 ... 1e12.
        polarization: "horizontal" (tau = 0°), "vertical" (90°), "circular" (45°), or the
            polarization tilt angle tau in degrees (number or array, may be traced).
        elevation_deg: path elevation angle theta (degrees), [0, 90].

    Returns ``(k, alpha)``; k in (dB/km)/(mm/h)^alpha, alpha dimensionless.
    Accuracy: the recommendation's regression itself (P.838-3 states the fits to the
    scattering calculations); reproduces the ITU-R SG3 validation examples to 1e-7.
    Source: Rec. ITU-R P.838-3 (03/2005), Tables 1-4, eqs. (2)-(5).

    ITU-R SG3 validation example (CG-3M3J-13-ValEx-Rev5.1): 29 GHz, elevation 31.077°,
    horizontal polarization -> k = 0.22106804, alpha = 0.95320005:

    >>> k, alpha = rain_coefficients(29e9, "horizontal", 31.07699124)
    >>> float(k), float(alpha)
    (0.22106804, 0.95320005)
    """
    check_range("freq_hz", freq_hz, 1e9, 1e12, where=_WHERE)
    check_range("elevation_deg", elevation_deg, 0.0, 90.0, where=_WHERE)
    tau = jnp.deg2rad(_tilt_deg(polarization))
    log_f = jnp.log10(jnp.asarray(freq_hz, dtype=float) / 1e9)
    k_h = 10.0 ** _gauss_sum(log_f, _KH_ABC, _KH_M, _KH_C)
    k_v = 10.0 ** _gauss_sum(log_f, _KV_ABC, _KV_M, _KV_C)
    a_h = _gauss_sum(log_f, _AH_ABC, _AH_M, _AH_C)
    a_v = _gauss_sum(log_f, _AV_ABC, _AV_M, _AV_C)
    mix = jnp.cos(jnp.deg2rad(jnp.asarray(elevation_deg, dtype=float))) ** 2 * jnp.cos(2.0 * tau)
    k = 0.5 * (k_h + k_v + (k_h - k_v) * mix)
    alpha = (k_h * a_h + k_v * a_v + (k_h * a_h - k_v * a_v) * mix) / (2.0 * k)
    return k, alpha


def rain_attenuation_db_per_km(freq_hz, rain_mm_per_h, polarization="horizontal", elevation_deg=0.0):
    """Specific attenuation of rain gamma_R = k R^alpha (dB/km, one way), ITU-R P.838-3.

    Args:
        freq_hz: frequency (Hz), 1e9 ... 1e12 (1-1000 GHz).
        rain_mm_per_h: rain rate R (mm/h), [0, 500]. R = 0 gives 0; the derivative in R at
            exactly R = 0 is returned as 0 (it is infinite for alpha < 1), finite for R > 0.
        polarization: "horizontal", "vertical", "circular", or tilt angle in degrees (static
            string or number/array).
        elevation_deg: path elevation angle (degrees), [0, 90].

    Formula and coefficients: see :func:`rain_coefficients` and the module docstring.
    Source: Rec. ITU-R P.838-3 (03/2005), eq. (1).

    The validation example of :func:`rain_coefficients` at R = 26.48052 mm/h: 5.02180189 dB/km:

    >>> float(rain_attenuation_db_per_km(29e9, 26.48052, "horizontal", 31.07699124))
    5.02180189
    """
    check_range("rain_mm_per_h", rain_mm_per_h, 0.0, 500.0, where=_WHERE)
    k, alpha = rain_coefficients(freq_hz, polarization, elevation_deg)
    r = jnp.asarray(rain_mm_per_h, dtype=float)
    positive = r > 0.0
    r_safe = jnp.where(positive, r, 1.0)
    return jnp.where(positive, k * jnp.exp(alpha * jnp.log(r_safe)), 0.0)
