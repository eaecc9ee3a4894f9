"""Infrared radiometry of a point target: the band contrast intensity of a grey target against
the background it hides and the irradiance it produces at the aperture.

* contrast intensity ``J = A_t [ε_t L(T_t) − ε_b L(T_b)]`` (W/sr), L the blackbody band radiance
  (:func:`diffsense.physics.radiance.band_radiance_w_m2_sr`);
* irradiance at the aperture ``E = J τ_a(R)/R²`` (W/m²), τ_a the atmospheric transmission.

Sources: Hudson, *Infrared System Engineering* (1969), ch. 2 and §11.2; Dereniak & Boreman,
*Infrared Detectors and Systems* (1996), §2.

A black target of 1 m² against a black background at the same temperature shows no contrast:

>>> from diffsense.sensors.infrared.radiometry import contrast_intensity_w_sr
>>> float(contrast_intensity_w_sr(1.0, 1.0, 300.0, 1.0, 300.0, 8e-6, 12e-6))
0.0
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.physics import radiance

__all__ = ["contrast_intensity_w_sr", "point_target_irradiance_w_m2"]


def contrast_intensity_w_sr(target_area_m2, target_emissivity, target_temperature_k, background_emissivity,
                            background_temperature_k, wavelength_lo_m, wavelength_hi_m):
    """Band contrast intensity of a point target against the background it hides (W/sr).

    ``J = A_t [ε_t L(T_t) − ε_b L(T_b)]`` with L the blackbody band radiance
    (:func:`diffsense.physics.radiance.band_radiance_w_m2_sr`); negative for a target darker than its
    background. Lambertian grey bodies; path radiance is common to target and background lines
    of sight and cancels.

    Args:
        target_area_m2: projected area A_t (m²), in [0, 1e6].
        target_emissivity, background_emissivity: in [0, 1].
        target_temperature_k, background_temperature_k: (K), in (0, 1e5].
        wavelength_lo_m, wavelength_hi_m: band (m), in [1e-9, 10].

    Source: Hudson (1969) ch. 2 and §11.2 (contrast radiant intensity of a point source).
    """
    w = "contrast_intensity_w_sr"
    check_range("target_area_m2", target_area_m2, 0.0, 1e6, where=w)
    check_range("target_emissivity", target_emissivity, 0.0, 1.0, where=w)
    check_range("background_emissivity", background_emissivity, 0.0, 1.0, where=w)
    lt = radiance.band_radiance_w_m2_sr(wavelength_lo_m, wavelength_hi_m, target_temperature_k)
    lb = radiance.band_radiance_w_m2_sr(wavelength_lo_m, wavelength_hi_m, background_temperature_k)
    return target_area_m2 * (target_emissivity * lt - background_emissivity * lb)


def point_target_irradiance_w_m2(intensity_w_sr, range_m, transmission=1.0):
    """Irradiance at the aperture from a point source ``E = I τ_a / R²`` (W/m²).

    Args:
        intensity_w_sr: (contrast) radiant intensity I (W/sr), any real value.
        range_m: R (m), in (0, ∞).
        transmission: atmospheric transmission τ_a, in [0, 1].

    Exact (inverse-square law). Source: Hudson (1969) §11.2; Dereniak & Boreman (1996) §2.
    """
    w = "point_target_irradiance_w_m2"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("transmission", transmission, 0.0, 1.0, where=w)
    r = jnp.asarray(range_m, dtype=float)
    return jnp.asarray(intensity_w_sr, dtype=float) * transmission / (r * r)
