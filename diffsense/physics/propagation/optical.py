"""Optical/laser extinction in haze and fog from the meteorological visibility.

Koschmieder law (2 % contrast threshold): beta = -ln(0.02)/V = 3.912/V.
Wavelength scaling with the particle size-distribution exponent q(V)::

    beta(lambda) = (3.912 / V) (lambda / 550 nm)^(-q)              [1/length]
    attenuation  = 10 log10(e) beta = 4.343 beta                    [dB per length]

Kruse et al. (1962), *Elements of Infrared Technology* (Wiley), V in km:
    q = 1.6 (V > 50), 1.3 (6 < V <= 50), 0.585 V^(1/3) (V <= 6).
Kim, McArthur & Korevaar (2001), "Comparison of laser beam propagation at 785 nm and 1550 nm
in fog and haze for optical wireless communications", Proc. SPIE 4214:26-37, V in km:
    q = 1.6 (V > 50), 1.3 (6 < V <= 50), 0.16 V + 0.34 (1 < V <= 6),
        V - 0.5 (0.5 < V <= 1), 0 (V <= 0.5).
q(V) is piecewise: both models jump at V = 50 km and Kruse also at 6 km; derivatives are
the branch derivatives (finite), undefined exactly at a jump.
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_choice, check_range
from diffsense.numerics.db import DB_PER_NEPER

__all__ = [
    "koschmieder_extinction_per_m",
    "size_distribution_exponent",
    "laser_extinction_db_per_km",
]

_WHERE = "optical extinction"
KOSCHMIEDER_CONSTANT = 3.912  # -ln(0.02), rounded as in Kim et al. (2001)


def koschmieder_extinction_per_m(visibility_m):
    """Extinction coefficient beta = 3.912 / V (1/m) at 550 nm (Koschmieder, 2 % contrast).

    ``visibility_m``: meteorological visibility V (m), [1, 1e6]. Exact by definition of V.

    >>> import math
    >>> float(koschmieder_extinction_per_m(1e3)) * 1e3, -math.log(0.02)   # beta V = -ln 0.02
    (3.912, 3.912)
    """
    check_range("visibility_m", visibility_m, 1.0, 1e6, where=_WHERE)
    return KOSCHMIEDER_CONSTANT / jnp.asarray(visibility_m, dtype=float)


def size_distribution_exponent(visibility_m, model="kim"):
    """Size-distribution exponent q(V) of the Kim (2001) or Kruse (1962) model.

    ``visibility_m`` V (m), [1, 1e6]; ``model`` "kim" or "kruse" (static). See module docstring.

    >>> float(size_distribution_exponent(3e3)), 0.16 * 3 + 0.34                        # Kim, 1 < V <= 6 km
    (0.82, 0.82)
    >>> float(size_distribution_exponent(3e3, "kruse")), 0.585 * 3 ** (1 / 3)          # Kruse, V <= 6 km
    (0.843716, 0.843716)
    """
    check_choice("model", model, ("kim", "kruse"), where=_WHERE)
    check_range("visibility_m", visibility_m, 1.0, 1e6, where=_WHERE)
    v = jnp.asarray(visibility_m, dtype=float) / 1e3
    if model == "kruse":
        low = 0.585 * jnp.cbrt(v)
    else:
        low = jnp.where(v > 1.0, 0.16 * v + 0.34, jnp.where(v > 0.5, v - 0.5, 0.0 * v))
    return jnp.where(v > 50.0, 1.6, jnp.where(v > 6.0, 1.3, low))


def laser_extinction_db_per_km(visibility_m, wavelength_m, model="kim"):
    """Laser extinction (dB/km, one way) from visibility: 4.343 (3.912/V)(lambda/550nm)^-q(V).

    Args:
        visibility_m: meteorological visibility V (m), [1, 1e6].
        wavelength_m: laser wavelength (m), [2e-7, 2e-5] (UV to thermal IR; the models were
            fitted in the visible/near-IR windows, outside absorption bands).
        model: "kim" (Kim et al. 2001, default) or "kruse" (Kruse et al. 1962), static.

    Error: empirical scattering-only fits (no molecular absorption); Kim et al. report the
    Kruse law overestimates the wavelength dependence in fog (V < 0.5 km).
    Example: V = 1 km, 1550 nm, Kim: q = 0.5 -> 16.99 * (1550/550)^-0.5 = 10.12 dB/km:

    >>> import math
    >>> float(laser_extinction_db_per_km(1e3, 1550e-9)), 10 * math.log10(math.e) * 3.912 * (1550 / 550) ** -0.5
    (10.12, 10.12)
    """
    check_range("wavelength_m", wavelength_m, 2e-7, 2e-5, where=_WHERE)
    q = size_distribution_exponent(visibility_m, model)
    beta_per_km = KOSCHMIEDER_CONSTANT / (jnp.asarray(visibility_m, dtype=float) / 1e3)
    ratio = jnp.asarray(wavelength_m, dtype=float) / 550e-9
    return DB_PER_NEPER * beta_per_km * jnp.exp(-q * jnp.log(ratio))
