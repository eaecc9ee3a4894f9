"""Cloud and fog attenuation: ITU-R P.840-7 Rayleigh model with double-Debye water permittivity.

Rec. ITU-R P.840-7 (12/2017), §2, eqs. (1)-(10)::

    gamma_c = K_l(f, T) M                                            [dB/km]
    K_l     = 0.819 f / (eps'' (1 + eta^2))                          [(dB/km)/(g/m^3)]
    eta     = (2 + eps') / eps''
    eps''   = f (eps0 - eps1) / (f_p (1 + (f/f_p)^2)) + f (eps1 - eps2) / (f_s (1 + (f/f_s)^2))
    eps'    = (eps0 - eps1) / (1 + (f/f_p)^2) + (eps1 - eps2) / (1 + (f/f_s)^2) + eps2
    eps0    = 77.66 + 103.3 (theta - 1),  eps1 = 0.0671 eps0,  eps2 = 3.52,  theta = 300/T
    f_p     = 20.20 - 146 (theta - 1) + 316 (theta - 1)^2    [GHz]   (principal relaxation)
    f_s     = 39.8 f_p                                         [GHz]   (secondary relaxation)

f in GHz, M the liquid water density (g/m^3). The permittivity model is the double-Debye
fit of Liebe, Hufford & Manabe (1991), Int. J. Infrared Millim. Waves 12(7):659-675.
The Rayleigh approximation holds for droplets much smaller than the wavelength (cloud
and fog droplets < 0.1 mm), i.e. up to 1000 GHz (P.840-7 §2).
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range

__all__ = ["cloud_attenuation_coefficient", "cloud_attenuation_db_per_km", "liquid_water_permittivity"]

_WHERE = "ITU-R P.840-7 cloud attenuation"


def liquid_water_permittivity(freq_hz, temperature_k):
    """Complex relative permittivity of liquid water eps' - j eps'' (P.840-7 eqs. (6)-(10)).

    Args:
        freq_hz: frequency (Hz), 1e8 ... 1e12.
        temperature_k: water temperature (K), [233.15, 323.15] (supercooled to 50 °C).

    Returns ``(eps_real, eps_imag)`` with eps_imag = eps'' >= 0 (loss).
    Source: Rec. ITU-R P.840-7 §2 (double-Debye model of Liebe et al. 1991).
    """
    check_range("freq_hz", freq_hz, 1e8, 1e12, where=_WHERE)
    check_range("temperature_k", temperature_k, 233.15, 323.15, where=_WHERE)
    f = jnp.asarray(freq_hz, dtype=float) / 1e9
    theta = 300.0 / jnp.asarray(temperature_k, dtype=float)
    eps0 = 77.66 + 103.3 * (theta - 1.0)
    eps1 = 0.0671 * eps0
    eps2 = 3.52
    fp = 20.20 - 146.0 * (theta - 1.0) + 316.0 * (theta - 1.0) ** 2
    fs = 39.8 * fp
    eps_imag = f * (eps0 - eps1) / (fp * (1.0 + (f / fp) ** 2)) + f * (eps1 - eps2) / (
        fs * (1.0 + (f / fs) ** 2)
    )
    eps_real = (eps0 - eps1) / (1.0 + (f / fp) ** 2) + (eps1 - eps2) / (1.0 + (f / fs) ** 2) + eps2
    return eps_real, eps_imag


def cloud_attenuation_coefficient(freq_hz, temperature_k):
    """Cloud/fog specific attenuation coefficient K_l ((dB/km)/(g/m^3)), ITU-R P.840-7.

    K_l = 0.819 f / (eps'' (1 + eta^2)), eta = (2 + eps')/eps'' (P.840-7 eq. (2)), with
    the double-Debye permittivity of :func:`liquid_water_permittivity`; f in GHz.

    Args:
        freq_hz: frequency (Hz), 1e8 ... 1e12 (the recommendation states validity up to
            1000 GHz; its figures start at 5 GHz).
        temperature_k: cloud liquid water temperature (K), [233.15, 323.15].

    Accuracy: exact evaluation of the recommendation's equations (Rayleigh approximation,
    valid for droplets << wavelength).
    Source: Rec. ITU-R P.840-7 (12/2017), §2, eqs. (2)-(10).

    The ITU-R SG3 validation examples for P.840-8 (CG-3M3J-13-ValEx-Rev5.1), which evaluate
    K_l at 273.15 K with the same equations, give cloud attenuations 1.77246907 dB at 29 GHz
    and 0.45516982 dB at 14.25 GHz for the same path, hence the ratio of K_l:

    >>> float(cloud_attenuation_coefficient(29e9, 273.15) / cloud_attenuation_coefficient(14.25e9, 273.15))
    3.894083
    >>> 1.77246907 / 0.45516982
    3.894083
    """
    eps_real, eps_imag = liquid_water_permittivity(freq_hz, temperature_k)
    f = jnp.asarray(freq_hz, dtype=float) / 1e9
    eta = (2.0 + eps_real) / eps_imag
    return 0.819 * f / (eps_imag * (1.0 + eta**2))


def cloud_attenuation_db_per_km(freq_hz, liquid_water_g_m3, temperature_k):
    """Specific attenuation within a cloud or fog gamma_c = K_l M (dB/km, one way).

    Args:
        freq_hz: frequency (Hz), 1e8 ... 1e12.
        liquid_water_g_m3: liquid water density M (g/m^3), [0, 10] (fog ~0.05-0.5,
            dense cloud up to ~5 g/m^3).
        temperature_k: temperature of the liquid water (K), [233.15, 323.15].

    Source: Rec. ITU-R P.840-7 (12/2017), eq. (1).
    """
    check_range("liquid_water_g_m3", liquid_water_g_m3, 0.0, 10.0, where=_WHERE)
    return cloud_attenuation_coefficient(freq_hz, temperature_k) * jnp.asarray(liquid_water_g_m3, dtype=float)
