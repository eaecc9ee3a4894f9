"""Antennas and apertures: gain, effective aperture, beamwidth, directivity, phased arrays.

The same relations serve radar antennas, lidar optics and sonar transducers (the sonar
"directivity index" is the gain in dB). Pure ``jax.numpy`` functions of broadcastable
arrays; jit/vmap/grad-able. Angles are in radians unless the name says ``_deg``.

Sources: Brooker, *Introduction to Sensors for Ranging and Imaging* (2009): eq. 5.11 as
used in 8.16.9 (G = 4 pi rho A / lambda^2), 8.16.7 (d = 70 lambda / theta_deg),
eq. 12.43 (G = 4 pi 57.3^2 / (theta phi) in degrees), eqs 12.29-12.32 (phased arrays);
M. Skolnik, *Introduction to Radar Systems*, 3rd ed. (2001), section 9.2 (uniform line
source half-power beamwidth 0.886 lambda/D, circular 1.02 lambda/D) and 9.11 (grating-lobe
condition d/lambda < 1/(1 + |sin theta_0|)).
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S

__all__ = [
    "UNIFORM_RECTANGULAR_BEAMWIDTH_FACTOR",
    "UNIFORM_CIRCULAR_BEAMWIDTH_FACTOR",
    "BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR",
    "wavelength_m",
    "circular_aperture_area_m2",
    "gain_from_aperture",
    "gain_db",
    "aperture_area_from_gain_m2",
    "effective_aperture_m2",
    "beamwidth_rad",
    "beamwidth_book_deg",
    "aperture_diameter_for_beamwidth_book_m",
    "directivity_from_beamwidths",
    "directivity_from_beamwidths_deg",
    "directivity_index_db",
    "phased_array_gain",
    "phased_array_beamwidth_rad",
    "grating_lobe_free_spacing_m",
    "grating_lobe_margin",
    "beam_fill_ratio",
]

#: Half-power beamwidth of a uniformly illuminated line/rectangular aperture, in lambda/D.
UNIFORM_RECTANGULAR_BEAMWIDTH_FACTOR = 0.886
#: Half-power beamwidth of a uniformly illuminated circular aperture, in lambda/D (1.029 exact).
UNIFORM_CIRCULAR_BEAMWIDTH_FACTOR = 1.02
#: The book's rule for a (tapered) circular aperture: theta_deg = 70 lambda / d.
BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR = 70.0

_RAD_TO_DEG = 180.0 / math.pi


def wavelength_m(freq_hz, propagation_speed_m_s=SPEED_OF_LIGHT_M_S):
    """Wavelength ``lambda = v / f``, m.

    Args:
        freq_hz: frequency, Hz. Domain (0, inf).
        propagation_speed_m_s: wave speed, m/s (c for EM; about 340 in air and 1500 in
            sea water for sound). Domain (0, inf). The book uses c = 3e8 m/s.

    >>> float(wavelength_m(94e9, 3e8))      # the book's 94 GHz radar (8.16): 3.19 mm
    0.00319
    >>> float(wavelength_m(40e3, 340.0))    # 40 kHz ultrasound in air: 340/40e3
    0.0085
    """
    where = "wavelength_m"
    check_range("freq_hz", freq_hz, 0.0, None, lo_open=True, where=where)
    check_range("propagation_speed_m_s", propagation_speed_m_s, 0.0, None, lo_open=True, where=where)
    return jnp.asarray(propagation_speed_m_s) / jnp.asarray(freq_hz)


def circular_aperture_area_m2(diameter_m):
    """Physical area of a circular aperture ``pi d^2 / 4``, m^2. Domain d in (0, inf).

    >>> import math
    >>> float(circular_aperture_area_m2(0.25)), math.pi * 0.125**2
    (0.0490874, 0.0490874)
    """
    check_range("diameter_m", diameter_m, 0.0, None, lo_open=True, where="circular_aperture_area_m2")
    d = jnp.asarray(diameter_m)
    return 0.25 * jnp.pi * d * d


def gain_from_aperture(area_m2, wavelength_m, efficiency=1.0):
    """Antenna gain from physical aperture area: ``G = 4 pi rho A / lambda^2`` (linear).

    Exact for the effective aperture ``rho A`` (reciprocity, far field); the aperture
    efficiency rho (0.5-0.8 for reflectors) carries taper, spillover and blockage.

    Args:
        area_m2: physical aperture area, m^2. Domain (0, inf).
        wavelength_m: wavelength, m. Domain (0, inf).
        efficiency: aperture efficiency rho. Domain (0, 1].

    Source: Brooker eq. 5.11 (used in 8.16.9: 250 mm, rho = 0.7, 94 GHz -> 42,432 = 46.2 dB).

    The book's numbers follow with its rounded wavelength 3.19 mm (exact c gives 42,451):

    >>> float(gain_from_aperture(circular_aperture_area_m2(0.25), 3.19e-3, 0.7))
    4.2432e4
    """
    where = "gain_from_aperture"
    check_range("area_m2", area_m2, 0.0, None, lo_open=True, where=where)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("efficiency", efficiency, 0.0, 1.0, lo_open=True, where=where)
    lam = jnp.asarray(wavelength_m)
    return 4.0 * jnp.pi * jnp.asarray(efficiency) * jnp.asarray(area_m2) / (lam * lam)


def gain_db(gain):
    """Linear power ratio to dB: ``10 log10 G`` (:func:`diffsense.numerics.db.db10`). Domain G in (0, inf).

    >>> float(gain_db(42432.0))   # Brooker 8.16.9: 42,432 is 46.28 dB (printed 46.2)
    46.28
    """
    check_range("gain", gain, 0.0, None, lo_open=True, where="gain_db")
    return db10(gain)


def aperture_area_from_gain_m2(gain, wavelength_m, efficiency=1.0):
    """Physical aperture area needed for a gain: ``A = G lambda^2 / (4 pi rho)``, m^2.

    Inverse of :func:`gain_from_aperture`. Args: gain (linear, (0, inf)), wavelength_m
    ((0, inf)), efficiency ((0, 1]).

    >>> import math
    >>> float(aperture_area_from_gain_m2(1000.0, 0.03, 0.6)), 1000.0 * 0.03**2 / (4 * math.pi * 0.6)
    (0.119366, 0.119366)
    """
    where = "aperture_area_from_gain_m2"
    check_range("gain", gain, 0.0, None, lo_open=True, where=where)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("efficiency", efficiency, 0.0, 1.0, lo_open=True, where=where)
    lam = jnp.asarray(wavelength_m)
    return jnp.asarray(gain) * lam * lam / (4.0 * jnp.pi * jnp.asarray(efficiency))


def effective_aperture_m2(gain, wavelength_m):
    """Effective (capture) aperture ``A_e = G lambda^2 / (4 pi) = rho A``, m^2.

    Args: gain (linear, (0, inf)), wavelength_m ((0, inf)). Exact by reciprocity.

    An isotropic antenna (G = 1) captures lambda^2 / (4 pi):

    >>> import math
    >>> float(effective_aperture_m2(1.0, 0.1)), 0.1**2 / (4 * math.pi)
    (0.000795775, 0.000795775)
    """
    where = "effective_aperture_m2"
    check_range("gain", gain, 0.0, None, lo_open=True, where=where)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    lam = jnp.asarray(wavelength_m)
    return jnp.asarray(gain) * lam * lam / (4.0 * jnp.pi)


def beamwidth_rad(wavelength_m, aperture_m, factor=UNIFORM_RECTANGULAR_BEAMWIDTH_FACTOR):
    """Half-power beamwidth ``theta_3dB = k lambda / D``, rad.

    ``factor`` k: 0.886 for a uniform rectangular/line aperture (exact 0.8859),
    1.02 for a uniform circular aperture (exact 1.029), larger for tapered apertures
    (the book's 70 deg -> 1.222 rad). Valid for D >> lambda (error O((lambda/D)^2)).

    Args:
        wavelength_m: wavelength, m. Domain (0, inf).
        aperture_m: aperture dimension in the plane of the beamwidth, m. Domain (0, inf).
        factor: beamwidth constant k. Domain (0, 3].

    A 1 m uniform line aperture at 3 cm: 0.886 x 0.03 rad = 1.52 deg (Skolnik 9.2):

    >>> import math
    >>> math.degrees(float(beamwidth_rad(0.03, 1.0)))
    1.523
    """
    where = "beamwidth_rad"
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("aperture_m", aperture_m, 0.0, None, lo_open=True, where=where)
    check_range("factor", factor, 0.0, 3.0, lo_open=True, where=where)
    return jnp.asarray(factor) * jnp.asarray(wavelength_m) / jnp.asarray(aperture_m)


def beamwidth_book_deg(wavelength_m, diameter_m):
    """The book's circular-aperture rule ``theta_3dB = 70 lambda / d``, degrees.

    Source: Brooker 8.16.7 (ore pass: 250 mm at 94 GHz -> 0.89 deg). Equivalent to
    :func:`beamwidth_rad` with k = 70 pi/180 = 1.222 (a moderately tapered aperture).
    Args: wavelength_m ((0, inf)), diameter_m ((0, inf)).

    >>> float(beamwidth_book_deg(3e8 / 94e9, 0.25))   # Brooker 8.16.7: 0.89 deg
    0.89
    """
    where = "beamwidth_book_deg"
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("diameter_m", diameter_m, 0.0, None, lo_open=True, where=where)
    return BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR * jnp.asarray(wavelength_m) / jnp.asarray(diameter_m)


def aperture_diameter_for_beamwidth_book_m(wavelength_m, beamwidth_deg):
    """Diameter for a beamwidth by the book's rule ``d = 70 lambda / theta_deg``, m.

    Source: Brooker 8.16.7 (1.1 deg at 94 GHz -> about 0.2 m; 1 m ultrasound transducer
    -> lambda <= 0.016 m in 8.16.2). Args: wavelength_m ((0, inf)), beamwidth_deg ((0, 180]).

    >>> float(aperture_diameter_for_beamwidth_book_m(3e8 / 94e9, 1.1))   # Brooker 8.16.7: about 0.2 m
    0.2
    """
    where = "aperture_diameter_for_beamwidth_book_m"
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("beamwidth_deg", beamwidth_deg, 0.0, 180.0, lo_open=True, where=where)
    return BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR * jnp.asarray(wavelength_m) / jnp.asarray(beamwidth_deg)


def directivity_from_beamwidths(beamwidth_az_rad, beamwidth_el_rad):
    """Directivity from the two half-power beamwidths: ``G = 4 pi / (theta phi)``.

    Approximation that ignores sidelobes and beam shape (it counts the solid angle as a
    rectangle theta x phi); for real antennas the gain is typically 0.6-0.8 of this
    (Skolnik uses 26,000/(theta_deg phi_deg) instead of 41,253). Valid for narrow beams.

    Args: beamwidths, rad. Domain (0, pi].
    """
    where = "directivity_from_beamwidths"
    check_range("beamwidth_az_rad", beamwidth_az_rad, 0.0, math.pi, lo_open=True, where=where)
    check_range("beamwidth_el_rad", beamwidth_el_rad, 0.0, math.pi, lo_open=True, where=where)
    return 4.0 * jnp.pi / (jnp.asarray(beamwidth_az_rad) * jnp.asarray(beamwidth_el_rad))


def directivity_from_beamwidths_deg(beamwidth_az_deg, beamwidth_el_deg):
    """Directivity from beamwidths in degrees: ``G = 4 pi (180/pi)^2 / (theta phi)``.

    The book writes 57.3^2 for (180/pi)^2 (eq. 12.43: 1.5 x 60 deg -> 458.4; the exact
    conversion gives 458.37). Same approximation as :func:`directivity_from_beamwidths`.
    Args: beamwidths, degrees. Domain (0, 180].

    >>> import math
    >>> float(directivity_from_beamwidths_deg(1.5, 60.0)), 4 * math.pi / (math.radians(1.5) * math.radians(60.0))
    (458.37, 458.37)
    """
    where = "directivity_from_beamwidths_deg"
    check_range("beamwidth_az_deg", beamwidth_az_deg, 0.0, 180.0, lo_open=True, where=where)
    check_range("beamwidth_el_deg", beamwidth_el_deg, 0.0, 180.0, lo_open=True, where=where)
    return 4.0 * jnp.pi * _RAD_TO_DEG**2 / (jnp.asarray(beamwidth_az_deg) * jnp.asarray(beamwidth_el_deg))


def directivity_index_db(directivity):
    """Sonar directivity index ``DI = 10 log10 G``, dB (Brooker 12.8). Domain G in (0, inf).

    >>> float(directivity_index_db(100.0))
    20.0
    """
    check_range("directivity", directivity, 0.0, None, lo_open=True, where="directivity_index_db")
    return db10(directivity)


def phased_array_gain(area_m2, wavelength_m, scan_angle_rad, efficiency=1.0):
    """Gain of a large planar array scanned off broadside: ``G = 4 pi rho A cos(theta0) / lambda^2``.

    The projected aperture shrinks as cos(theta0). Element-pattern and mismatch losses
    beyond the projection are not included (real arrays often fall as cos^1.5).

    Args:
        area_m2: array area, m^2. Domain (0, inf).
        wavelength_m: wavelength, m. Domain (0, inf).
        scan_angle_rad: scan angle from broadside, rad. Domain [-pi/2, pi/2].
        efficiency: aperture efficiency. Domain (0, 1].

    Source: Brooker eqs 12.29-12.30.

    At 60 deg the projected aperture, and the gain, halve (cos 60 deg = 1/2):

    >>> import math
    >>> float(phased_array_gain(1.0, 0.03, math.pi / 3) / phased_array_gain(1.0, 0.03, 0.0))
    0.5
    """
    where = "phased_array_gain"
    check_range("scan_angle_rad", scan_angle_rad, -0.5 * math.pi, 0.5 * math.pi, where=where)
    return gain_from_aperture(area_m2, wavelength_m, efficiency) * jnp.cos(jnp.asarray(scan_angle_rad))


def phased_array_beamwidth_rad(wavelength_m, n_elements, spacing_m, scan_angle_rad, pedestal_ratio=0.0):
    """Half-power beamwidth of a scanned linear array, rad.

    ``theta_3dB ~= 0.886 lambda / (N d cos theta0) * (1 + 0.636 (2 a1/a0)^2)``
    (Brooker eqs 12.31-12.32; ``pedestal_ratio`` = 2 a1/a0 of a cosine-on-pedestal taper
    a0 + 2 a1 cos(2 pi n/N), 0 for uniform illumination). Broadens as 1/cos(theta0);
    not valid near endfire (|theta0| -> pi/2), hence the domain.

    Args:
        wavelength_m: wavelength, m. Domain (0, inf).
        n_elements: number of elements N (may be traced as a real number). Domain [2, inf).
        spacing_m: element spacing d, m. Domain (0, inf).
        scan_angle_rad: scan angle, rad. Domain [-1.4, 1.4] (about +-80 deg).
        pedestal_ratio: 2 a1/a0. Domain [0, 1).
    """
    where = "phased_array_beamwidth_rad"
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("n_elements", n_elements, 2.0, None, where=where)
    check_range("spacing_m", spacing_m, 0.0, None, lo_open=True, where=where)
    check_range("scan_angle_rad", scan_angle_rad, -1.4, 1.4, where=where)
    check_range("pedestal_ratio", pedestal_ratio, 0.0, 1.0, hi_open=True, where=where)
    taper = 1.0 + 0.636 * jnp.asarray(pedestal_ratio) ** 2
    aperture = jnp.asarray(n_elements) * jnp.asarray(spacing_m) * jnp.cos(jnp.asarray(scan_angle_rad))
    return UNIFORM_RECTANGULAR_BEAMWIDTH_FACTOR * jnp.asarray(wavelength_m) / aperture * taper


def grating_lobe_free_spacing_m(wavelength_m, max_scan_angle_rad):
    """Largest element spacing with no grating lobe in real space: ``d < lambda / (1 + |sin theta0|)``.

    Scanning to theta0 moves a grating lobe to sin(theta) = sin(theta0) - lambda/d; it
    stays out of real space while that is below -1. (Skolnik 3rd ed. 9.11; Brooker 12.4:
    d/lambda = 0.5 gives no grating lobes at any scan.)

    Args: wavelength_m ((0, inf)), max_scan_angle_rad ([-pi/2, pi/2]).

    Scanning to 30 deg allows lambda / 1.5; to 90 deg the book's lambda / 2:

    >>> import math
    >>> float(grating_lobe_free_spacing_m(0.03, math.pi / 6)), float(grating_lobe_free_spacing_m(0.03, math.pi / 2))
    (0.02, 0.015)
    """
    where = "grating_lobe_free_spacing_m"
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("max_scan_angle_rad", max_scan_angle_rad, -0.5 * math.pi, 0.5 * math.pi, where=where)
    return jnp.asarray(wavelength_m) / (1.0 + jnp.abs(jnp.sin(jnp.asarray(max_scan_angle_rad))))


def grating_lobe_margin(spacing_m, wavelength_m, max_scan_angle_rad):
    """Constraint form of the grating-lobe condition: ``1/(1 + |sin theta0|) - d/lambda``.

    Positive when the array is free of grating lobes at the scan limit (use as an
    inequality constraint ``>= 0`` in design optimisation).
    Args: spacing_m ((0, inf)), wavelength_m ((0, inf)), max_scan_angle_rad ([-pi/2, pi/2]).
    """
    where = "grating_lobe_margin"
    check_range("spacing_m", spacing_m, 0.0, None, lo_open=True, where=where)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    check_range("max_scan_angle_rad", max_scan_angle_rad, -0.5 * math.pi, 0.5 * math.pi, where=where)
    s = jnp.abs(jnp.sin(jnp.asarray(max_scan_angle_rad)))
    return 1.0 / (1.0 + s) - jnp.asarray(spacing_m) / jnp.asarray(wavelength_m)


def beam_fill_ratio(target_area_m2, range_m, beamwidth_az_rad, beamwidth_el_rad):
    """Fraction of the half-power beam footprint filled by a target, in [0, 1].

    ``F = min(1, A_t / (pi/4 R^2 theta phi))`` with the elliptical -3 dB footprint of a
    pencil beam at range R (small-angle). Radiometers weight the target brightness by F
    (antenna temperature ``F T_t + (1 - F) T_b``, Brooker 4.7.3); a filled beam gives 1
    (its gradient with respect to the target size is then zero).

    Args:
        target_area_m2: target area normal to the beam, m^2. Domain [0, inf).
        range_m: range, m. Domain (0, inf).
        beamwidth_az_rad, beamwidth_el_rad: half-power beamwidths, rad. Domain (0, pi/2].
    """
    where = "beam_fill_ratio"
    check_range("target_area_m2", target_area_m2, 0.0, None, where=where)
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=where)
    check_range("beamwidth_az_rad", beamwidth_az_rad, 0.0, 0.5 * math.pi, lo_open=True, where=where)
    check_range("beamwidth_el_rad", beamwidth_el_rad, 0.0, 0.5 * math.pi, lo_open=True, where=where)
    r = jnp.asarray(range_m)
    footprint = 0.25 * jnp.pi * r * r * jnp.asarray(beamwidth_az_rad) * jnp.asarray(beamwidth_el_rad)
    return jnp.minimum(jnp.asarray(target_area_m2) / footprint, 1.0)
