"""Dust and smoke: mass loading from visibility, laser and radar extinction, radar backscatter.

Book: Brooker, *Introduction to Sensors for Ranging and Imaging*, §7.2.6 (attenuation
through dust and smoke), §8.14.2 (dust backscatter, eqs. (8.37)-(8.45)) and the ore-pass
worked example §8.16.2.

* Mass loading from visibility (book eq. (7.10) / (8.42), after Ghobrial & Sharief 1987
  and Goldhirsh 2001): M = C V^-gamma g/m^3 with C = 37.3, gamma = 1.07, V in metres.
* Laser extinction (book §8.16.2): 0.1 - 0.43 dB/km per mg/m^3 of dust.
* Radar attenuation: the book's excerpt gives no formula, so the Rayleigh-regime absorption
  of small dielectric spheres is used (Bohren & Huffman 1983, eq. (5.11); the form used by
  Goldhirsh 2001 for dust storms): with K = (eps - 1)/(eps + 2) and the particle volume
  fraction M/rho,  alpha = (6 pi / lambda) Im(-K) M / rho  [1/m, power], i.e.
  alpha_dB/km = 4343 (6 pi/lambda) * 3 eps'' / ((eps' + 2)^2 + eps''^2) * M / rho.
* Volume backscatter (book eq. (8.45)): eta = pi^5 |K|^2 1.125e-19 / (lambda^4 V^1.07) m^2/m^3.

|K|^2 of the book's rock dust, eps = 5.23 - j0.26 (book eq. (8.38)):

>>> from diffsense.physics.propagation.dust import ROCK_DUST_K_SQUARED
>>> ROCK_DUST_K_SQUARED, abs((5.23 - 0.26j - 1) / (5.23 - 0.26j + 2)) ** 2
(0.343147276, 0.343147276)
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import DB_PER_NEPER
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.physics.targets import dielectric_factor_k_squared

__all__ = [
    "dust_mass_loading_g_m3",
    "dust_laser_extinction_db_per_km",
    "dust_radar_attenuation_db_per_km",
    "dust_volume_backscatter_m2_m3",
    "dielectric_factor_k_squared",
]

_WHERE = "dust/smoke model"

#: |K|^2 of rock dust, eps = 5.23 - j0.26 (book 8.16.4 for eps'; loss tangent as in dust_radar_attenuation_db_per_km).
ROCK_DUST_K_SQUARED = 0.3431472760099732


def dust_mass_loading_g_m3(visibility_m, coefficient_c=37.3, exponent_gamma=1.07):
    """Dust (or water) mass loading M = C V^-gamma (g/m^3) from the visibility V (m).

    Args:
        visibility_m: optical visibility V (m), [1, 1e5].
        coefficient_c: C (g/m^3 at V = 1 m); book value 37.3.
        exponent_gamma: gamma; book value 1.07.

    Source: Brooker eq. (7.10)/(8.42); Ghobrial & Sharief (1987), Goldhirsh (2001). The
    constants depend on particle type and meteorology (empirical, sand/dust storms).

    >>> float(dust_mass_loading_g_m3(20.0))     # book §8.16.2: V = 20 m -> "1.5 g/m^3"
    1.5
    """
    check_range("visibility_m", visibility_m, 1.0, 1e5, where=_WHERE)
    check_range("coefficient_c", coefficient_c, 0.0, None, lo_open=True, where=_WHERE)
    check_range("exponent_gamma", exponent_gamma, 0.0, 3.0, lo_open=True, where=_WHERE)
    v = jnp.asarray(visibility_m, dtype=float)
    return coefficient_c * jnp.exp(-exponent_gamma * jnp.log(v))


def dust_laser_extinction_db_per_km(mass_loading_g_m3, db_per_km_per_mg_m3=0.1):
    """Laser extinction through dust (dB/km, one way) = k * M, with M in mg/m^3.

    Args:
        mass_loading_g_m3: dust mass loading M (g/m^3), [0, 100].
        db_per_km_per_mg_m3: specific extinction k ((dB/km)/(mg/m^3)). The book gives the
            range 0.1 - 0.43 (§8.16.2); the default is the optimistic end.

    Source: Brooker §7.2.6.2 and §8.16.2.

    >>> float(dust_laser_extinction_db_per_km(1.5)), float(dust_laser_extinction_db_per_km(1.5, 0.43))   # book §8.16.2
    (150.0, 645.0)
    """
    check_range("mass_loading_g_m3", mass_loading_g_m3, 0.0, 100.0, where=_WHERE)
    check_range("db_per_km_per_mg_m3", db_per_km_per_mg_m3, 0.0, 10.0, where=_WHERE)
    return db_per_km_per_mg_m3 * 1e3 * jnp.asarray(mass_loading_g_m3, dtype=float)


def dust_radar_attenuation_db_per_km(freq_hz, mass_loading_g_m3, eps_real=5.23, eps_imag=0.26,
                                     particle_density_kg_m3=2440.0):
    """Radar attenuation by dust in the Rayleigh regime (dB/km, one way).

    alpha = 4343 * (6 pi / lambda) * Im(-K) * M / rho,  Im(-K) = 3 eps''/((eps'+2)^2 + eps''^2),
    M/rho the particle volume fraction. Absorption only; Rayleigh scattering loss is smaller
    by (2 pi a / lambda)^3 and is neglected.

    Args:
        freq_hz: frequency (Hz), [1e8, 3e11]; validity needs 2 pi a / lambda < 1 for the
            particle radius a (book §8.14.2) — true for storm dust (< 100 um) up to ~300 GHz.
        mass_loading_g_m3: dust mass loading M (g/m^3), [0, 100].
        eps_real, eps_imag: particle relative permittivity eps' - j eps'' (book's rock dust
            5.23 - j0.26, §8.14.2 Fig. 8.43).
        particle_density_kg_m3: particle material density rho (book: 2440 kg/m^3).

    Error: Rayleigh approximation, error O((2 pi a/lambda)^2) relative.
    Source: Rayleigh absorption cross-section (Bohren & Huffman 1983, eq. (5.11)), as used
    for dust storms by Goldhirsh (2001), IEEE Trans. AP-49(12):1703-1711.

    The ore-pass dust (1.5 g/m^3) at 94 GHz, the closed form evaluated directly:

    >>> import math
    >>> lam = 299792458.0 / 94e9
    >>> closed = 10 / math.log(10) * 1e3 * 6 * math.pi / lam * 3 * 0.26 / (7.23**2 + 0.26**2) * 1.5e-3 / 2440
    >>> float(dust_radar_attenuation_db_per_km(94e9, 1.5)), closed
    (0.235153, 0.235153)
    """
    check_range("freq_hz", freq_hz, 1e8, 3e11, where=_WHERE)
    check_range("mass_loading_g_m3", mass_loading_g_m3, 0.0, 100.0, where=_WHERE)
    check_range("eps_real", eps_real, 1.0, 200.0, where=_WHERE)
    check_range("eps_imag", eps_imag, 0.0, 200.0, where=_WHERE)
    check_range("particle_density_kg_m3", particle_density_kg_m3, 100.0, 3e4, where=_WHERE)
    lam = SPEED_OF_LIGHT_M_S / jnp.asarray(freq_hz, dtype=float)
    er = jnp.asarray(eps_real, dtype=float)
    ei = jnp.asarray(eps_imag, dtype=float)
    im_minus_k = 3.0 * ei / ((er + 2.0) ** 2 + ei**2)
    volume_fraction = jnp.asarray(mass_loading_g_m3, dtype=float) * 1e-3 / jnp.asarray(particle_density_kg_m3, dtype=float)
    alpha_per_m = 6.0 * jnp.pi / lam * im_minus_k * volume_fraction
    return DB_PER_NEPER * 1e3 * alpha_per_m


def dust_volume_backscatter_m2_m3(wavelength_m, visibility_m, k_squared=ROCK_DUST_K_SQUARED):
    """Dust volume backscatter eta = pi^5 |K|^2 1.125e-19 / (lambda^4 V^1.07)  (m^2/m^3).

    Args:
        wavelength_m: radar wavelength lambda (m), [1e-4, 10] (Rayleigh regime required).
        visibility_m: visibility V (m), [1, 1e5].
        k_squared: |K|^2 of the particle material (default rock dust, eps = 5.23 - j0.26: 0.3431).

    The constant 1.125e-19 = 2.25e-9 * (sum P_i D_i^6)/(sum P_i r_i^3) with the sandstorm
    size-distribution sums 2e-24 m^6 and 4e-14 m^3 (book eqs. (8.43)-(8.45)).
    Source: Brooker eq. (8.45), after Ghobrial & Sharief (1987) and Goldhirsh (2001).

    >>> import math
    >>> lam = 3e8 / 94e9
    >>> closed = math.pi**5 * 0.34 * (2.25e-9 * 2e-24 / 4e-14) / (lam**4 * 20.0**1.07)
    >>> float(dust_volume_backscatter_m2_m3(lam, 20.0, 0.34)), closed
    (4.57409e-09, 4.57409e-09)
    """
    check_range("wavelength_m", wavelength_m, 1e-4, 10.0, where=_WHERE)
    check_range("visibility_m", visibility_m, 1.0, 1e5, where=_WHERE)
    check_range("k_squared", k_squared, 0.0, 1.0, where=_WHERE)
    lam = jnp.asarray(wavelength_m, dtype=float)
    v = jnp.asarray(visibility_m, dtype=float)
    return jnp.pi**5 * k_squared * 1.125e-19 / (lam**4 * jnp.exp(1.07 * jnp.log(v)))
