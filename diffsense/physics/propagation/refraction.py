"""Standard-atmosphere refraction: effective earth radius and radar horizon.

A linear refractivity gradient dN/dh = -39 N-units/km bends rays like a straight line over
an earth of radius k a, k = 4/3 (Skolnik, *Introduction to Radar Systems*, 3rd ed. §8.2;
ITU-R P.834 / P.453 median k = 4/3). Exact geometry over the effective sphere::

    horizon of a terminal at height h:   d(h) = sqrt(2 k a h + h^2)
    radar horizon (antenna h1, target h2): d(h1) + d(h2)
    lowest visible target at range R (> d(h1)):  h2 = sqrt((k a)^2 + (R - d(h1))^2) - k a
    grazing angle at a surface point at slant range r from height h:
        sin psi = (d(h)^2 - r^2) / (2 k a r)      (0 at the horizon r = d(h))

(the well-known approximations are d ≈ sqrt(2 k a h), d[km] ≈ 4.12 (sqrt(h1[m]) + sqrt(h2[m]))).
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range

__all__ = [
    "EARTH_RADIUS_M",
    "effective_earth_radius_m",
    "horizon_distance_m",
    "radar_horizon_m",
    "minimum_visible_target_height_m",
    "surface_grazing_angle_rad",
]

EARTH_RADIUS_M = 6_371_000.0  # mean earth radius (IUGG)
_WHERE = "refraction / radar horizon"


def effective_earth_radius_m(k_factor=4.0 / 3.0):
    """Effective earth radius k a (m), a = 6371 km; ``k_factor`` in [0.5, 10] (4/3 standard).

    >>> float(effective_earth_radius_m())      # 4/3 x 6371 km
    8494666.67
    """
    check_range("k_factor", k_factor, 0.5, 10.0, where=_WHERE)
    return jnp.asarray(k_factor, dtype=float) * EARTH_RADIUS_M


def horizon_distance_m(height_m, k_factor=4.0 / 3.0):
    """Distance (m) to the geometric horizon over the effective earth: sqrt(2 k a h + h^2).

    ``height_m`` h (m) in [0, 1e5]; exact in the effective-earth model. The derivative in h
    is finite for h > 0; at exactly h = 0 (where it is infinite) it is returned as 0.

    The classic rule d[km] = 4.12 sqrt(h[m]) (= sqrt(2 k a h) with k = 4/3, a = 6371 km):

    >>> float(horizon_distance_m(100.0)) / 1e3, 4.12 * 100.0**0.5
    (41.2, 41.2)
    """
    check_range("height_m", height_m, 0.0, 1e5, where=_WHERE)
    ae = effective_earth_radius_m(k_factor)
    h = jnp.asarray(height_m, dtype=float)
    positive = h > 0.0
    h_safe = jnp.where(positive, h, 1.0)
    return jnp.where(positive, jnp.sqrt(2.0 * ae * h_safe + h_safe**2), 0.0)


def radar_horizon_m(antenna_height_m, target_height_m, k_factor=4.0 / 3.0):
    """Radar horizon (m): d(h_antenna) + d(h_target), d(h) = sqrt(2 k a h + h^2).

    Args: ``antenna_height_m``, ``target_height_m`` (m) in [0, 1e5]; ``k_factor`` (4/3).
    Example: 8 m antenna, 3 m sea-skimmer, k = 4/3 -> 18.79 km.
    Source: Skolnik (2001) §8.2; effective earth radius k a.

    >>> ka = 4 / 3 * 6371e3
    >>> float(radar_horizon_m(8.0, 3.0)) / 1e3, ((2 * ka * 8 + 8**2) ** 0.5 + (2 * ka * 3 + 3**2) ** 0.5) / 1e3
    (18.79, 18.79)
    """
    return horizon_distance_m(antenna_height_m, k_factor) + horizon_distance_m(target_height_m, k_factor)


def minimum_visible_target_height_m(range_m, antenna_height_m, k_factor=4.0 / 3.0):
    """Lowest target height (m) in line of sight at ground range R from an antenna at h1.

    h2 = sqrt((k a)^2 + s^2) - k a with s = max(R - d(h1), 0) (zero inside the antenna's
    own horizon). Written as s^2 / (sqrt((k a)^2 + s^2) + k a) to avoid cancellation.

    Args: ``range_m`` R (m) in [0, 1e7]; ``antenna_height_m`` (m); ``k_factor`` (4/3).

    A target exactly at the radar horizon of a 3 m target is visible down to 3 m:

    >>> float(minimum_visible_target_height_m(radar_horizon_m(8.0, 3.0), 8.0))
    3.0
    """
    check_range("range_m", range_m, 0.0, 1e7, where=_WHERE)
    ae = effective_earth_radius_m(k_factor)
    s = jnp.maximum(jnp.asarray(range_m, dtype=float) - horizon_distance_m(antenna_height_m, k_factor), 0.0)
    return s**2 / (jnp.sqrt(ae**2 + s**2) + ae)


def surface_grazing_angle_rad(slant_range_m, height_m, k_factor=4.0 / 3.0):
    """Grazing angle (rad) at a point of the effective-earth surface seen at slant range r from a
    terminal at height h: the angle between the ray and the local horizontal at that point.

    Law of cosines in the triangle (earth centre, terminal at k a + h, surface point at k a)::

        sin psi = (2 k a h + h^2 - r^2) / (2 k a r) = (d(h) - r)(d(h) + r) / (2 k a r)

    with d(h) the horizon distance (:func:`horizon_distance_m`); the factored form avoids the
    cancellation of the first. Flat earth (k a -> inf) gives sin psi = h / r; the curvature lowers
    sin psi by about r / (2 k a). psi falls to 0 at the horizon (r = d(h)); beyond it the point is
    hidden and the value is negative. This is the one home of the grazing-angle relation: the
    sea-clutter patch and the specular point of the two-ray multipath geometry
    (:func:`diffsense.physics.propagation.multipath.two_ray_geometry`) both use it.

    Args: ``slant_range_m`` r (m) in (0, 1e7]; ``height_m`` h (m) in [0, 1e5]; ``k_factor`` (4/3).
    Exact within straight-ray geometry over the effective sphere (standard refraction).
    Source: Blake, *Radar Range-Performance Analysis* (1986), ch. 6 (geometry over the 4/3 earth);
    Skolnik (2001) §8.2.

    8 m above the sea at 5 km: the flat-earth 8/5000 less the curvature term, against the closed
    form; zero at the horizon:

    >>> import math
    >>> ka = 4 / 3 * 6371e3
    >>> float(surface_grazing_angle_rad(5e3, 8.0)), math.asin((2 * ka * 8 + 64 - 5e3**2) / (2 * ka * 5e3))
    (0.0013057, 0.0013057)
    >>> abs(float(surface_grazing_angle_rad(horizon_distance_m(8.0), 8.0))) < 1e-15
    True
    """
    check_range("slant_range_m", slant_range_m, 0.0, 1e7, lo_open=True, where=_WHERE)
    ae = effective_earth_radius_m(k_factor)
    d = horizon_distance_m(height_m, k_factor)
    r = jnp.asarray(slant_range_m, dtype=float)
    return jnp.arcsin(jnp.clip((d - r) * (d + r) / (2.0 * ae * r), -1.0, 1.0))
