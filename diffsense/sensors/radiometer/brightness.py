"""Radiative transfer of a passive millimetre-wave radiometer in Rayleigh–Jeans-equivalent
brightness temperature (linear in power, so emission, reflection and absorption add exactly).

* The Planck brightness B(T) of a black body (:func:`diffsense.physics.radiance.planck_brightness_temperature_k`)
  carries every physical temperature (target, ground, air, reference load, cosmic background).
* An isothermal absorbing layer of opacity τ (Np) and temperature T_m seen against a
  background of brightness T_b: ``T = T_b e^−τ + B(T_m)(1 − e^−τ)``. The sky is this with the
  cosmic background behind the atmosphere (mean radiating temperature T_m).
* A specular surface of emissivity ε (reflectivity 1 − ε, Kirchhoff) at temperature T reflecting
  the sky: apparent temperature ``T_ap = ε B(T) + (1 − ε) T_sky``. A metal target (ε ≈ 0)
  mirrors the cold sky; ground (ε ≈ 0.9) emits near its physical temperature — the contrast that
  passive mm-wave anti-armour submunition sensors detect.

Sources: Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I (1981): ch. 4 (brightness and
apparent temperature), ch. 5 (atmospheric emission of an absorbing layer, secant law); Skou &
Le Vine, *Microwave Radiometer Systems* (2nd ed., 2006), ch. 2.

A metal target (ε = 0) on ground (ε = 0.9, 290 K) under a 20 K sky: ΔT = −0.9 (290 − 20) K.

>>> from diffsense.sensors.radiometer.brightness import brightness_contrast_k
>>> round(float(brightness_contrast_k(0.0, 300.0, 0.9, 290.0, 20.0)), 9)
-243.0
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import DB_PER_NEPER
from diffsense.physics.radiance import planck_brightness_temperature_k

__all__ = [
    "COSMIC_BACKGROUND_TEMPERATURE_K",
    "opacity_from_attenuation_db",
    "slant_opacity_np",
    "brightness_through_layer_k",
    "sky_brightness_temperature_k",
    "apparent_temperature_k",
    "brightness_contrast_k",
]

#: Cosmic microwave background temperature (K): Fixsen, D. J. (2009), ApJ 707, 916.
COSMIC_BACKGROUND_TEMPERATURE_K = 2.72548


def opacity_from_attenuation_db(attenuation_db):
    """Opacity (optical depth) ``τ = A ln10 / 10`` (Np) of a path of attenuation A (dB).

    Args:
        attenuation_db: one-way attenuation A (dB), in [0, 1000]. Exact: e^−τ = 10^(−A/10).

    >>> import math
    >>> abs(float(opacity_from_attenuation_db(10.0)) - math.log(10.0)) < 1e-12  # 10 dB: e^−τ = 1/10
    True
    """
    check_range("attenuation_db", attenuation_db, 0.0, 1000.0, where="opacity_from_attenuation_db")
    return jnp.asarray(attenuation_db, dtype=float) / DB_PER_NEPER


def slant_opacity_np(zenith_opacity_np, elevation_deg):
    """Opacity along a slant path through a horizontally stratified atmosphere ``τ_z / sin(el)`` (Np).

    Plane-parallel (secant) law. Args: ``zenith_opacity_np`` τ_z (Np), in [0, 100];
    ``elevation_deg`` el (deg), in [5, 90]. Error from Earth curvature below ≈ 1 % above 10°
    elevation for a 2–8 km scale-height atmosphere (grows towards the horizon; not for el < 5°).
    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 5 (τ(θ) = τ(0) sec θ).
    """
    w = "slant_opacity_np"
    check_range("zenith_opacity_np", zenith_opacity_np, 0.0, 100.0, where=w)
    check_range("elevation_deg", elevation_deg, 5.0, 90.0, where=w)
    return jnp.asarray(zenith_opacity_np, dtype=float) / jnp.sin(jnp.deg2rad(jnp.asarray(elevation_deg, dtype=float)))


def brightness_through_layer_k(background_brightness_k, opacity_np, layer_brightness_k):
    """Brightness behind an isothermal absorbing layer ``T_b e^−τ + T_m (1 − e^−τ)`` (K).

    Solution of the radiative-transfer equation without scattering for a layer of opacity τ
    whose own brightness (Planck brightness of its temperature) is T_m. Exact for an isothermal,
    non-scattering layer; for the real atmosphere T_m is the mean radiating temperature.

    Args:
        background_brightness_k: brightness entering the far side T_b (K), in [0, 1e4].
        opacity_np: layer opacity τ (Np), in [0, 100].
        layer_brightness_k: layer brightness T_m (K), in [0, 1e4].

    Source: Ulaby, Moore & Fung (1981) Vol. I §4-7 and ch. 5 (upwelling/downwelling emission).
    """
    w = "brightness_through_layer_k"
    check_range("background_brightness_k", background_brightness_k, 0.0, 1e4, where=w)
    check_range("opacity_np", opacity_np, 0.0, 100.0, where=w)
    check_range("layer_brightness_k", layer_brightness_k, 0.0, 1e4, where=w)
    return _through_layer(background_brightness_k, opacity_np, layer_brightness_k)


def _through_layer(tb, tau, tm):
    tau = jnp.asarray(tau, dtype=float)
    return tb * jnp.exp(-tau) - tm * jnp.expm1(-tau)


def sky_brightness_temperature_k(opacity_np, mean_radiating_temperature_k, freq_hz,
                                 cosmic_temperature_k=COSMIC_BACKGROUND_TEMPERATURE_K):
    """Downwelling sky brightness ``T_sky = B(T_m)(1 − e^−τ) + B(T_c) e^−τ`` (K).

    Args:
        opacity_np: total opacity of the atmosphere along the look direction τ (Np), in
            [0, 100] (use :func:`slant_opacity_np` for a slant path).
        mean_radiating_temperature_k: mean radiating temperature of the atmosphere T_m (K), in
            (0, 400] (typically 260–280 K; 15–20 K below the surface air temperature).
        freq_hz: frequency (Hz), in (0, 1e13].
        cosmic_temperature_k: cosmic background T_c (K), in (0, 10]; default 2.72548 K.

    Both physical temperatures enter through
    :func:`diffsense.physics.radiance.planck_brightness_temperature_k`.
    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 5 (sky brightness of a non-scattering
    atmosphere); Kraus (1986) ch. 3.
    """
    w = "sky_brightness_temperature_k"
    check_range("opacity_np", opacity_np, 0.0, 100.0, where=w)
    check_range("mean_radiating_temperature_k", mean_radiating_temperature_k, 0.0, 400.0, lo_open=True, where=w)
    check_range("freq_hz", freq_hz, 0.0, 1e13, lo_open=True, where=w)
    check_range("cosmic_temperature_k", cosmic_temperature_k, 0.0, 10.0, lo_open=True, where=w)
    return _through_layer(planck_brightness_temperature_k(cosmic_temperature_k, freq_hz), opacity_np,
                          planck_brightness_temperature_k(mean_radiating_temperature_k, freq_hz))


def apparent_temperature_k(emissivity, surface_brightness_k, sky_brightness_k):
    """Apparent temperature of a specular surface ``T_ap = ε T_s + (1 − ε) T_sky`` (K).

    Emission plus the reflected sky (reflectivity 1 − ε by Kirchhoff's law); ``T_s`` is the
    Planck brightness of the surface's physical temperature (≈ the physical temperature).
    Rough surfaces reflect an average over the hemisphere; this specular form is exact for
    smooth surfaces and for metal (ε ≈ 0 reflects the sky in the specular direction).

    Args:
        emissivity: ε, in [0, 1].
        surface_brightness_k: T_s (K), in [0, 1e4].
        sky_brightness_k: T_sky in the specular direction (K), in [0, 1e4].

    Source: Ulaby, Moore & Fung (1981) Vol. I §4-7 (apparent temperature T_AP = T_B + T_SC).
    """
    w = "apparent_temperature_k"
    check_range("emissivity", emissivity, 0.0, 1.0, where=w)
    check_range("surface_brightness_k", surface_brightness_k, 0.0, 1e4, where=w)
    check_range("sky_brightness_k", sky_brightness_k, 0.0, 1e4, where=w)
    return _apparent(emissivity, surface_brightness_k, sky_brightness_k)


def _apparent(eps, ts, tsky):
    return eps * ts + (1.0 - eps) * tsky


def brightness_contrast_k(target_emissivity, target_brightness_k, background_emissivity,
                          background_brightness_k, sky_brightness_k):
    """Apparent-temperature contrast of a target against its background, both reflecting the sky (K).

    ``ΔT = [ε_t T_t + (1 − ε_t) T_sky] − [ε_b T_b + (1 − ε_b) T_sky]``; negative for a metal
    target (ε_t ≈ 0) on ground (ε_b ≈ 0.9) under a cold sky: ΔT ≈ −ε_b (T_b − T_sky).

    Args: emissivities in [0, 1]; brightness temperatures (K) in [0, 1e4].
    Source: Ulaby, Moore & Fung (1981) Vol. I §4-7; the anti-armour radiometric contrast in
    Brooker, *Sensors for Ranging and Imaging*, §4.13 (outside the excerpt held here).
    """
    t = apparent_temperature_k(target_emissivity, target_brightness_k, sky_brightness_k)
    b = apparent_temperature_k(background_emissivity, background_brightness_k, sky_brightness_k)
    return t - b
