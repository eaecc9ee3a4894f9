"""Target models: radar cross section of simple shapes, laser cross section, acoustic target
strength, dielectric reflectivity factor, Swerling fluctuation statistics, extended targets.

Pure ``jax.numpy`` functions (jit/vmap/grad-able). Cross sections in m^2, target strengths
and dB quantities in dB, angles in radians measured from the surface normal / broadside.

Sources: Brooker, *Introduction to Sensors for Ranging and Imaging* (2009), 8.2-8.4
(RCS of simple shapes, eqs 8.10-8.11), 8.8 (fluctuations), 8.10 (laser cross section,
eqs 8.19-8.20), 8.11.4 (acoustic target strength, eq. 8.24 and Table 8.6 after Waite
2002), 8.16 (ore-pass target); E. F. Knott, J. F. Shaeffer, M. T. Tuley, *Radar Cross
Section*, 2nd ed. (1993), ch. 5 (physical-optics RCS of plates, cylinders,
corner reflectors) and ch. 3 (Mie series for the sphere); P. Swerling, "Probability of
detection for fluctuating targets", IRE Trans. IT-6 (1960) 269-308.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_choice, check_range, is_concrete
from diffsense.numerics.db import db10, db20

__all__ = [
    "rcs_sphere_optical_m2",
    "rcs_sphere_rayleigh_m2",
    "rcs_dielectric_sphere_rayleigh_m2",
    "rcs_sphere_mie_m2",
    "rcs_flat_plate_m2",
    "rcs_plate_normal_m2",
    "rcs_trihedral_triangular_m2",
    "rcs_trihedral_square_m2",
    "rcs_dihedral_m2",
    "rcs_cylinder_m2",
    "laser_cross_section_lambertian_m2",
    "laser_cross_section_specular_m2",
    "target_strength_from_cross_section_db",
    "target_strength_sphere_db",
    "target_strength_convex_surface_db",
    "target_strength_plate_db",
    "target_strength_rectangular_plate_db",
    "target_strength_circular_plate_db",
    "target_strength_cylinder_db",
    "dielectric_factor_k2",
    "dielectric_factor_k_squared",
    "extended_target_rcs_m2",
    "swerling_rcs_pdf",
    "swerling_rcs_cdf",
    "swerling_rcs_sample",
]

# Floor for dB forms of patterns with exact nulls: -300 dB keeps log and its gradient finite.
_POWER_FLOOR = 1e-30


def _positive(where, **kwargs):
    for name, value in kwargs.items():
        check_range(name, value, 0.0, None, lo_open=True, where=where)


def _sinc(x):
    """sin(x)/x, with a Taylor branch near 0 (double-where) so value and gradient stay finite."""
    small = jnp.abs(x) < 1e-3
    x_safe = jnp.where(small, 1.0, x)
    x2 = x * x
    return jnp.where(small, 1.0 - x2 / 6.0 + x2 * x2 / 120.0, jnp.sin(x_safe) / x_safe)


# --------------------------------------------------------------------------------------
# Sphere
# --------------------------------------------------------------------------------------


def rcs_sphere_optical_m2(radius_m):
    """Optical-region RCS of a conducting sphere, ``sigma = pi a^2`` (projected area).

    Valid for ka = 2 pi a / lambda >~ 10, where the exact (Mie) value oscillates about
    pi a^2 with an amplitude of about +-14 % near ka = 10, +-2.5 % near ka = 30 and
    decaying further with ka (see :func:`rcs_sphere_mie_m2`). Source: Brooker 8.2.1.

    Args: radius_m, m. Domain (0, inf).

    >>> import math
    >>> float(rcs_sphere_optical_m2(1.0)), math.pi     # a 1 m radius sphere: pi m^2
    (3.14159, 3.14159)
    """
    _positive("rcs_sphere_optical_m2", radius_m=radius_m)
    a = jnp.asarray(radius_m)
    return jnp.pi * a * a


def rcs_sphere_rayleigh_m2(radius_m, wavelength_m):
    """Rayleigh-region RCS of a perfectly conducting sphere, ``sigma = 9 pi a^2 (ka)^4``.

    Leading term of the Mie series for ka -> 0: it overestimates the exact value by
    0.8 % at ka = 0.2 and 6 % at ka = 0.5, the error growing as (ka)^2 (Knott et al.
    ch. 3); use for ka < 0.3.

    Args: radius_m ((0, inf)), wavelength_m ((0, inf)).

    >>> import math
    >>> a, lam = 0.001, 0.03
    >>> float(rcs_sphere_rayleigh_m2(a, lam)), 9 * math.pi * a**2 * (2 * math.pi * a / lam) ** 4
    (5.44035e-08, 5.44035e-08)
    """
    _positive("rcs_sphere_rayleigh_m2", radius_m=radius_m, wavelength_m=wavelength_m)
    a = jnp.asarray(radius_m)
    ka = 2.0 * jnp.pi * a / jnp.asarray(wavelength_m)
    return 9.0 * jnp.pi * a * a * ka**4


def rcs_dielectric_sphere_rayleigh_m2(radius_m, wavelength_m, k_squared):
    """Rayleigh backscatter of a small dielectric sphere: ``sigma = pi^5 |K|^2 D^6 / lambda^4``.

    D = 2a, |K|^2 from :func:`dielectric_factor_k2` (0.93 for liquid water at microwave
    frequencies). Valid for ka < about 0.2 (the condition 2 pi a / lambda < 1 the book
    quotes in 8.14.2 is its outer edge). Source: Brooker 8.14 (rain/dust backscatter).

    Args: radius_m ((0, inf)), wavelength_m ((0, inf)), k_squared ([0, 1]).
    """
    where = "rcs_dielectric_sphere_rayleigh_m2"
    _positive(where, radius_m=radius_m, wavelength_m=wavelength_m)
    check_range("k_squared", k_squared, 0.0, 1.0, where=where)
    d = 2.0 * jnp.asarray(radius_m)
    return jnp.pi**5 * jnp.asarray(k_squared) * d**6 / jnp.asarray(wavelength_m) ** 4


def mie_terms_needed(ka_max):
    """Number of Mie terms for convergence: ``N = ka + 4 (ka)^(1/3) + 2`` (Wiscombe 1980)."""
    return int(math.ceil(ka_max + 4.0 * ka_max ** (1.0 / 3.0) + 2.0))


def rcs_sphere_mie_m2(radius_m, wavelength_m, n_terms=None):
    """Exact monostatic RCS of a perfectly conducting sphere (Mie series), m^2.

    ::

        sigma = (pi a^2 / x^2) | sum_{n=1}^{N} (-1)^n (2n + 1) (a_n - b_n) |^2,  x = ka
        a_n = j_n(x) / h_n(x),   b_n = [x j_n(x)]' / [x h_n(x)]'
        [x z_n(x)]' = x z_{n-1}(x) - n z_n(x),  h_n = j_n + i y_n

    (Knott, Shaeffer & Tuley, *Radar Cross Section*, 2nd ed., ch. 3; Ruck et al.
    1970.) Spherical Bessel functions by upward recurrence from j_0 = sin x / x,
    y_0 = -cos x / x; for j_n the recurrence is run only to N = x + 4 x^(1/3) + 2 terms
    (Wiscombe's criterion), where its error growth stays below about 1e-9 relative.

    Args:
        radius_m: sphere radius, m. Domain (0, inf).
        wavelength_m: wavelength, m. Domain (0, inf); with x = ka in [0.04, 250].
        n_terms: number of series terms (static). Defaults to Wiscombe's N for the
            largest ka of concrete arguments; must be given when the arguments are traced.

    Returns:
        RCS in m^2. Limits: 9 pi a^2 x^4 as x -> 0; pi a^2 as x -> inf.

    The first resonance, sigma / (pi a^2) = 3.64 near ka = 1 (Knott et al. ch. 3), and the
    approach to the optical value pi a^2 (within 2.5 % at ka = 30):

    >>> import math
    >>> lam = 0.03
    >>> a = lam / (2 * math.pi)
    >>> float(rcs_sphere_mie_m2(a, lam)) / (math.pi * a * a)
    3.64
    >>> a = 30 * lam / (2 * math.pi)
    >>> abs(float(rcs_sphere_mie_m2(a, lam)) / (math.pi * a * a) - 1) < 0.025
    True
    """
    where = "rcs_sphere_mie_m2"
    _positive(where, radius_m=radius_m, wavelength_m=wavelength_m)
    if is_concrete(radius_m) and is_concrete(wavelength_m):
        ka_c = 2.0 * np.pi * np.asarray(radius_m, dtype=float) / np.asarray(wavelength_m, dtype=float)
        check_range("ka (2 pi radius_m / wavelength_m)", ka_c, 0.04, 250.0, where=where)
        if n_terms is None:
            n_terms = mie_terms_needed(float(np.max(ka_c)))
    elif n_terms is None:
        raise DomainError(f"{where}: n_terms must be given when radius_m or wavelength_m is traced")
    n_terms = int(n_terms)

    a = jnp.asarray(radius_m)
    x = 2.0 * jnp.pi * a / jnp.asarray(wavelength_m)
    sin_x, cos_x = jnp.sin(x), jnp.cos(x)
    j0, y0 = sin_x / x, -cos_x / x  # order 0
    j1 = sin_x / x**2 - cos_x / x  # order 1
    y1 = -cos_x / x**2 - sin_x / x
    ctype = jnp.complex128 if x.dtype == jnp.float64 else jnp.complex64

    def step(carry, n):
        j_prev, j_cur, y_prev, y_cur, total = carry
        h_cur = j_cur + 1j * y_cur
        h_prev = j_prev + 1j * y_prev
        a_n = j_cur / h_cur
        b_n = (x * j_prev - n * j_cur) / (x * h_prev - n * h_cur)
        sign = 1.0 - 2.0 * jnp.mod(n, 2.0)  # (-1)^n
        total = total + sign * (2.0 * n + 1.0) * (a_n - b_n)
        # upward recurrence z_{n+1} = (2n + 1)/x z_n - z_{n-1}
        j_next = (2.0 * n + 1.0) / x * j_cur - j_prev
        y_next = (2.0 * n + 1.0) / x * y_cur - y_prev
        return (j_cur, j_next, y_cur, y_next, total), None

    orders = jnp.arange(1, n_terms + 1, dtype=x.dtype)
    init = (j0, j1, y0, y1, jnp.zeros(x.shape, dtype=ctype))
    (_, _, _, _, total), _ = jax.lax.scan(step, init, orders)
    mag2 = jnp.real(total) ** 2 + jnp.imag(total) ** 2
    return jnp.pi * a * a * mag2 / (x * x)


# --------------------------------------------------------------------------------------
# Plates, corners, cylinders
# --------------------------------------------------------------------------------------


def rcs_plate_normal_m2(area_m2, wavelength_m):
    """Normal-incidence RCS of a flat conducting plate of any shape, ``4 pi A^2 / lambda^2``.

    Physical optics; valid when both plate dimensions exceed a few wavelengths.
    Source: Brooker eq. 8.11 (with A = ab); Knott et al. Table 5.1.
    Args: area_m2 ((0, inf)), wavelength_m ((0, inf)).

    >>> import math
    >>> float(rcs_plate_normal_m2(1.0, 0.03)), 4 * math.pi * 1.0**2 / 0.03**2   # 1 m^2 at 10 GHz
    (13962.6, 13962.6)
    """
    _positive("rcs_plate_normal_m2", area_m2=area_m2, wavelength_m=wavelength_m)
    area = jnp.asarray(area_m2)
    lam = jnp.asarray(wavelength_m)
    return 4.0 * jnp.pi * area * area / (lam * lam)


def rcs_flat_plate_m2(side_a_m, side_b_m, wavelength_m, incidence_rad=0.0):
    """RCS of a rectangular plate rotated about the side-b axis (Brooker eqs 8.10-8.11).

    ``sigma = (4 pi a^2 b^2 / lambda^2) [sin(x)/x]^2 cos^2(theta)``, ``x = (2 pi a / lambda) sin theta``.

    Physical optics: accurate for a, b >> lambda and |theta| below about 60-70 deg (edge
    diffraction dominates toward grazing). The nulls are exact zeros.

    Args:
        side_a_m: side in the plane of rotation, m. Domain (0, inf).
        side_b_m: other side, m. Domain (0, inf).
        wavelength_m: wavelength, m. Domain (0, inf).
        incidence_rad: angle from the plate normal, rad. Domain [-pi/2, pi/2].

    Normal incidence gives 4 pi (ab)^2 / lambda^2; the first null lies at sin theta = lambda / a:

    >>> import math
    >>> float(rcs_flat_plate_m2(0.5, 2.0, 0.03)), 4 * math.pi * (0.5 * 2.0) ** 2 / 0.03**2
    (13962.6, 13962.6)
    >>> float(rcs_flat_plate_m2(0.5, 2.0, 0.03, math.asin(0.03 / 0.5))) < 1e-20
    True
    """
    where = "rcs_flat_plate_m2"
    _positive(where, side_a_m=side_a_m, side_b_m=side_b_m, wavelength_m=wavelength_m)
    check_range("incidence_rad", incidence_rad, -0.5 * math.pi, 0.5 * math.pi, where=where)
    a = jnp.asarray(side_a_m)
    lam = jnp.asarray(wavelength_m)
    theta = jnp.asarray(incidence_rad)
    sigma0 = rcs_plate_normal_m2(a * jnp.asarray(side_b_m), lam)
    x = 2.0 * jnp.pi * a / lam * jnp.sin(theta)
    return sigma0 * _sinc(x) ** 2 * jnp.cos(theta) ** 2


def rcs_trihedral_triangular_m2(edge_m, wavelength_m):
    """Peak RCS of a triangular trihedral corner reflector, ``4 pi a^4 / (3 lambda^2)``.

    a = length of the inner (shared) edges. On the symmetry axis; falls by about 3 dB
    at +-20 deg (wide response). Physical optics, a >> lambda. Source: Knott et al.
    Table 5.1; Brooker 8.4.3 (Table 8.1).
    Args: edge_m ((0, inf)), wavelength_m ((0, inf)).

    >>> import math
    >>> float(rcs_trihedral_triangular_m2(0.3, 0.03)), 4 * math.pi * 0.3**4 / (3 * 0.03**2)
    (37.6991, 37.6991)
    """
    _positive("rcs_trihedral_triangular_m2", edge_m=edge_m, wavelength_m=wavelength_m)
    lam = jnp.asarray(wavelength_m)
    return 4.0 * jnp.pi * jnp.asarray(edge_m) ** 4 / (3.0 * lam * lam)


def rcs_trihedral_square_m2(edge_m, wavelength_m):
    """Peak RCS of a square-faced trihedral corner reflector, ``12 pi a^4 / lambda^2``.

    Physical optics, a >> lambda. Source: Knott et al. Table 5.1.
    Args: edge_m ((0, inf)), wavelength_m ((0, inf)).
    """
    _positive("rcs_trihedral_square_m2", edge_m=edge_m, wavelength_m=wavelength_m)
    lam = jnp.asarray(wavelength_m)
    return 12.0 * jnp.pi * jnp.asarray(edge_m) ** 4 / (lam * lam)


def rcs_dihedral_m2(side_a_m, side_b_m, wavelength_m):
    """Peak RCS of a 90-deg dihedral of two a x b plates (fold along b), ``8 pi a^2 b^2 / lambda^2``.

    Physical optics at the symmetry direction, a, b >> lambda. Source: Knott et al. Table 5.1.
    Args: side_a_m, side_b_m, wavelength_m, all (0, inf).
    """
    _positive("rcs_dihedral_m2", side_a_m=side_a_m, side_b_m=side_b_m, wavelength_m=wavelength_m)
    lam = jnp.asarray(wavelength_m)
    ab = jnp.asarray(side_a_m) * jnp.asarray(side_b_m)
    return 8.0 * jnp.pi * ab * ab / (lam * lam)


def rcs_cylinder_m2(radius_m, length_m, wavelength_m, incidence_rad=0.0):
    """RCS of a conducting circular cylinder near broadside.

    ``sigma = (2 pi a L^2 / lambda) cos(theta) [sin(x)/x]^2``, ``x = (2 pi L / lambda) sin theta``,
    theta measured from broadside (normal to the axis). Broadside: 2 pi a L^2 / lambda.
    Physical optics, valid for ka >> 1, L >> lambda and |theta| below about 60 deg.
    Source: Knott et al. ch. 5 (physical optics: stationary phase around the cylinder,
    uniform phase along it); Brooker 8.4.

    Args:
        radius_m, length_m, wavelength_m: m, each (0, inf).
        incidence_rad: angle from broadside, rad. Domain [-pi/2, pi/2].
    """
    where = "rcs_cylinder_m2"
    _positive(where, radius_m=radius_m, length_m=length_m, wavelength_m=wavelength_m)
    check_range("incidence_rad", incidence_rad, -0.5 * math.pi, 0.5 * math.pi, where=where)
    length = jnp.asarray(length_m)
    lam = jnp.asarray(wavelength_m)
    theta = jnp.asarray(incidence_rad)
    x = 2.0 * jnp.pi * length / lam * jnp.sin(theta)
    return 2.0 * jnp.pi * jnp.asarray(radius_m) * length * length / lam * jnp.cos(theta) * _sinc(x) ** 2


# --------------------------------------------------------------------------------------
# Laser cross section
# --------------------------------------------------------------------------------------


def laser_cross_section_lambertian_m2(reflectivity, area_m2, incidence_rad=0.0):
    """Monostatic laser cross section of a diffuse (Lambertian) surface, ``sigma = 4 rho A cos^2(theta)``.

    The surface of area A intercepts the power of the projected area A cos(theta) and scatters
    the fraction rho with Lambert's radiant intensity I(t) = rho E A cos(theta) cos(t) / pi,
    so that sigma = 4 pi I(theta) / E = 4 rho A cos^2(theta). At normal incidence this is the
    book's sigma = rho G A of eq. 8.15 with the target gain G = 4 pi / Omega = 4 for the
    solid-angle spread Omega = pi of eqs. 8.16-8.18. Brooker's eq. 8.20 prints
    sigma = 4 pi rho A cos(theta): a factor pi (4.97 dB) above its own eqs. 8.15-8.18 with
    Omega = pi, and with one cosine instead of two; this function follows the derivation.

    Args:
        reflectivity: diffuse (hemispherical) reflectance rho. Domain [0, 1].
        area_m2: physical area of the illuminated surface, m^2. Domain [0, inf).
        incidence_rad: angle between the line of sight and the surface normal, rad. Domain
            [-pi/2, pi/2].

    A 1 m^2 white (rho = 1) diffuser seen face on has sigma = 4 A; at 60 deg cos^2 = 1/4:

    >>> import math
    >>> float(laser_cross_section_lambertian_m2(1.0, 1.0)), float(laser_cross_section_lambertian_m2(1.0, 1.0, math.pi / 3))
    (4.0, 1.0)
    """
    where = "laser_cross_section_lambertian_m2"
    check_range("reflectivity", reflectivity, 0.0, 1.0, where=where)
    check_range("area_m2", area_m2, 0.0, None, where=where)
    check_range("incidence_rad", incidence_rad, -0.5 * math.pi, 0.5 * math.pi, where=where)
    return 4.0 * jnp.asarray(reflectivity) * jnp.asarray(area_m2) * jnp.cos(jnp.asarray(incidence_rad)) ** 2


def laser_cross_section_specular_m2(reflectivity, area_m2, wavelength_m):
    """Laser cross section of a specular (mirror-like, M = 1) surface at normal incidence.

    ``sigma = 4 pi rho A^2 / lambda^2`` (Brooker eq. 8.19; the flat-plate RCS times rho).
    Args: reflectivity ([0, 1]), area_m2 ([0, inf)), wavelength_m ((0, inf)).
    """
    where = "laser_cross_section_specular_m2"
    check_range("reflectivity", reflectivity, 0.0, 1.0, where=where)
    check_range("area_m2", area_m2, 0.0, None, where=where)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=where)
    area = jnp.asarray(area_m2)
    lam = jnp.asarray(wavelength_m)
    return 4.0 * jnp.pi * jnp.asarray(reflectivity) * area * area / (lam * lam)


# --------------------------------------------------------------------------------------
# Acoustic target strength (Brooker 8.11.4, Table 8.6 after Waite 2002)
# --------------------------------------------------------------------------------------


def target_strength_from_cross_section_db(cross_section_m2):
    """Acoustic target strength from scattering cross section: ``TS = 10 log10(sigma / 4 pi)``, dB.

    Brooker eq. 12.55 (TS is referred to 1 m). Domain sigma in (0, inf).

    >>> import math
    >>> abs(float(target_strength_from_cross_section_db(4 * math.pi))) < 1e-14   # sigma = 4 pi: 0 dB
    True
    """
    _positive("target_strength_from_cross_section_db", cross_section_m2=cross_section_m2)
    return db10(jnp.asarray(cross_section_m2) / (4.0 * jnp.pi))


def target_strength_sphere_db(radius_m):
    """TS of a large sphere, ``10 log10(a^2/4)``, dB re 1 m (Brooker eq. 8.24, Table 8.6).

    Geometric (ka >> 1) limit; any incidence. 1 m diameter -> -12.04 dB (the book: -12).
    Args: radius_m ((0, inf)).

    >>> import math
    >>> float(target_strength_sphere_db(0.5)), 10 * math.log10(0.5**2 / 4)
    (-12.041, -12.041)
    """
    _positive("target_strength_sphere_db", radius_m=radius_m)
    a = jnp.asarray(radius_m)
    return db10(a * a / 4.0)


def target_strength_convex_surface_db(radius_1_m, radius_2_m):
    """TS of a large convex surface at normal incidence, ``10 log10(a b / 4)`` (Table 8.6).

    a, b = principal radii of curvature, both >> lambda. Args: radii, m, (0, inf).
    """
    _positive("target_strength_convex_surface_db", radius_1_m=radius_1_m, radius_2_m=radius_2_m)
    return db10(jnp.asarray(radius_1_m) * jnp.asarray(radius_2_m) / 4.0)


def target_strength_plate_db(area_m2, wavelength_m):
    """TS of a plate of any shape at normal incidence, ``20 log10(A / lambda)`` (Table 8.6).

    Plate dimensions >> lambda. Args: area_m2 ((0, inf)), wavelength_m ((0, inf)).

    >>> float(target_strength_plate_db(1.0, 0.01))   # 1 m^2 at lambda = 1 cm: 20 log10 100
    40.0
    """
    _positive("target_strength_plate_db", area_m2=area_m2, wavelength_m=wavelength_m)
    return db20(jnp.asarray(area_m2) / jnp.asarray(wavelength_m))


def _angle_correction_db(length, lam, theta):
    """Brooker 8.11.4.2: ``10 log10[(sin x / x)^2] + 10 log10 cos^2 theta``, x = (2 pi L/lambda) sin theta.

    Floored at -300 dB so the log stays finite at the exact pattern nulls.
    """
    x = 2.0 * jnp.pi * length / lam * jnp.sin(theta)
    pattern = _sinc(x) ** 2 * jnp.cos(theta) ** 2
    return db10(jnp.maximum(pattern, _POWER_FLOOR))


def target_strength_rectangular_plate_db(side_a_m, side_l_m, wavelength_m, incidence_rad=0.0):
    """TS of a rectangular plate a x L, ``20 log10(a L / lambda)`` plus the book's angle correction.

    Correction (Brooker 8.11.4.2): ``10 log10[(sin x/x)^2] + 10 log10 cos^2 theta`` with
    ``x = (2 pi L / lambda) sin theta`` (rotation in the plane containing side L). The dB
    pattern is floored at -300 dB at its exact nulls. Valid for a, L >> lambda.

    Args:
        side_a_m, side_l_m, wavelength_m: m, each (0, inf).
        incidence_rad: angle from the normal, rad. Domain (-pi/2, pi/2).
    """
    where = "target_strength_rectangular_plate_db"
    _positive(where, side_a_m=side_a_m, side_l_m=side_l_m, wavelength_m=wavelength_m)
    check_range("incidence_rad", incidence_rad, -0.5 * math.pi, 0.5 * math.pi, lo_open=True, hi_open=True, where=where)
    length = jnp.asarray(side_l_m)
    lam = jnp.asarray(wavelength_m)
    normal = db20(jnp.asarray(side_a_m) * length / lam)
    return normal + _angle_correction_db(length, lam, jnp.asarray(incidence_rad))


def target_strength_circular_plate_db(radius_m, wavelength_m):
    """TS of a circular plate at normal incidence, ``20 log10(pi a^2 / lambda)`` (Table 8.6).

    Args: radius_m ((0, inf)), wavelength_m ((0, inf)); a >> lambda.
    """
    _positive("target_strength_circular_plate_db", radius_m=radius_m, wavelength_m=wavelength_m)
    a = jnp.asarray(radius_m)
    return db20(jnp.pi * a * a / jnp.asarray(wavelength_m))


def target_strength_cylinder_db(radius_m, length_m, wavelength_m, incidence_rad=0.0):
    """TS of a cylinder, ``10 log10(a L^2 / (2 lambda))`` at broadside plus the book's angle correction.

    Same correction as :func:`target_strength_rectangular_plate_db` with L the cylinder
    length and theta from broadside (Brooker 8.11.4.2, Table 8.6). Valid for ka >> 1,
    L >> lambda.

    Args:
        radius_m, length_m, wavelength_m: m, each (0, inf).
        incidence_rad: angle from broadside, rad. Domain (-pi/2, pi/2).
    """
    where = "target_strength_cylinder_db"
    _positive(where, radius_m=radius_m, length_m=length_m, wavelength_m=wavelength_m)
    check_range("incidence_rad", incidence_rad, -0.5 * math.pi, 0.5 * math.pi, lo_open=True, hi_open=True, where=where)
    length = jnp.asarray(length_m)
    lam = jnp.asarray(wavelength_m)
    broadside = db10(jnp.asarray(radius_m) * length * length / (2.0 * lam))
    return broadside + _angle_correction_db(length, lam, jnp.asarray(incidence_rad))


# --------------------------------------------------------------------------------------
# Material and extended targets
# --------------------------------------------------------------------------------------


def dielectric_factor_k2(relative_permittivity):
    """Dielectric reflectivity factor ``|K|^2 = |(eps - 1)/(eps + 2)|^2``.

    Scales the RCS of dielectric targets and Rayleigh scatterers (Brooker 8.16.4: rock
    5.23 -> 0.34, water 8.45 -> 0.51). Accepts real or complex permittivity
    (eps' - j eps''), real part >= 1.

    Args:
        relative_permittivity: relative dielectric constant (real part in [1, inf);
            a complex value is not range-checked beyond that).

    >>> float(dielectric_factor_k2(5.23)), float(dielectric_factor_k2(8.45))   # book 8.16.4
    (0.34, 0.51)
    """
    if is_concrete(relative_permittivity):
        real_part = np.real(np.asarray(relative_permittivity))
        check_range("relative_permittivity (real part)", real_part, 1.0, None, where="dielectric_factor_k2")
    eps = jnp.asarray(relative_permittivity)
    k = (eps - 1.0) / (eps + 2.0)
    return jnp.real(k * jnp.conj(k))


def dielectric_factor_k_squared(eps_real, eps_imag=0.0):
    """``|K|^2 = |(eps - 1)/(eps + 2)|^2`` for eps = eps' - j eps'' given as two real numbers.

    The form used for clutter and dust (Brooker eq. 8.38); evaluated by
    :func:`dielectric_factor_k2`. Exact. Book 8.16.4: rock 5.23 -> 0.342, water 8.45 -> 0.508
    (ratio 1.49, 1.7 dB; the book rounds to 1.5 and 1.8 dB).

    Args:
        eps_real: eps' (dimensionless), in [1, 200].
        eps_imag: eps'' >= 0 (loss), in [0, 200].

    >>> float(dielectric_factor_k_squared(5.23)), (4.23 / 7.23) ** 2   # rock (book 8.16.4: 0.34)
    (0.3423, 0.3423)
    """
    where = "dielectric_factor_k_squared"
    check_range("eps_real", eps_real, 1.0, 200.0, where=where)
    check_range("eps_imag", eps_imag, 0.0, 200.0, where=where)
    return dielectric_factor_k2(jnp.asarray(eps_real, dtype=float) - 1j * jnp.asarray(eps_imag, dtype=float))


def extended_target_rcs_m2(sigma0, area_m2):
    """RCS of an area-extended target, ``sigma = sigma0 A`` (Brooker 8.13).

    Ore pass (8.16.6): sigma0 = 0.5 (-3 dB) over pi 6^2/4 = 28.3 m^2 (14.5 dBm^2) ->
    11.5 dBm^2. Args: sigma0 (reflectivity, m^2/m^2, [0, inf)), area_m2 ([0, inf)).

    >>> import math
    >>> 10 * math.log10(float(extended_target_rcs_m2(0.5, math.pi * 6.0**2 / 4)))   # book: 11.5 dBm^2
    11.5
    """
    where = "extended_target_rcs_m2"
    check_range("sigma0", sigma0, 0.0, None, where=where)
    check_range("area_m2", area_m2, 0.0, None, where=where)
    return jnp.asarray(sigma0) * jnp.asarray(area_m2)


# --------------------------------------------------------------------------------------
# Swerling fluctuation models (Swerling 1960; Brooker 8.8)
# --------------------------------------------------------------------------------------

_SWERLING_CASES = (0, 1, 2, 3, 4)


def _check_swerling(case, where):
    check_choice("case", case, _SWERLING_CASES, where=where)


def swerling_rcs_pdf(rcs_m2, mean_rcs_m2, case):
    """Probability density of the RCS for Swerling cases 1-4, 1/m^2.

    Cases 1, 2 (chi-square, 2 degrees of freedom; many comparable scatterers)::

        p(sigma) = exp(-sigma / mean) / mean

    Cases 3, 4 (chi-square, 4 degrees of freedom; one dominant scatterer plus many)::

        p(sigma) = 4 sigma / mean^2 exp(-2 sigma / mean)

    Cases 1/3 decorrelate scan to scan, 2/4 pulse to pulse (same density). Case 0
    (steady target) has no density: a DomainError is raised.

    Args:
        rcs_m2: RCS value, m^2. Domain [0, inf).
        mean_rcs_m2: mean RCS, m^2. Domain (0, inf).
        case: Swerling case 1-4 (static int).
    """
    where = "swerling_rcs_pdf"
    _check_swerling(case, where)
    if case == 0:
        raise DomainError(f"{where}: Swerling case 0 (steady target) has no density; use swerling_rcs_cdf")
    check_range("rcs_m2", rcs_m2, 0.0, None, where=where)
    _positive(where, mean_rcs_m2=mean_rcs_m2)
    s = jnp.asarray(rcs_m2)
    m = jnp.asarray(mean_rcs_m2)
    if case in (1, 2):
        return jnp.exp(-s / m) / m
    return 4.0 * s / (m * m) * jnp.exp(-2.0 * s / m)


def swerling_rcs_cdf(rcs_m2, mean_rcs_m2, case):
    """Cumulative distribution of the RCS, P(sigma' <= sigma), for Swerling cases 0-4.

    Case 0: unit step at the mean. Cases 1, 2: ``1 - exp(-sigma/mean)``.
    Cases 3, 4: ``1 - (1 + 2 sigma/mean) exp(-2 sigma/mean)``. Computed with expm1 for
    accuracy in the lower tail.

    Args: rcs_m2 ([0, inf)), mean_rcs_m2 ((0, inf)), case (static int 0-4).

    At the mean: 1 - 1/e (cases 1, 2) and 1 - 3/e^2 (cases 3, 4):

    >>> import math
    >>> float(swerling_rcs_cdf(1.0, 1.0, 1)), 1 - math.exp(-1)
    (0.632121, 0.632121)
    >>> float(swerling_rcs_cdf(1.0, 1.0, 3)), 1 - 3 * math.exp(-2)
    (0.593994, 0.593994)
    """
    where = "swerling_rcs_cdf"
    _check_swerling(case, where)
    check_range("rcs_m2", rcs_m2, 0.0, None, where=where)
    _positive(where, mean_rcs_m2=mean_rcs_m2)
    s = jnp.asarray(rcs_m2)
    m = jnp.asarray(mean_rcs_m2)
    if case == 0:
        return jnp.where(s >= m, 1.0, 0.0) + 0.0 * s
    if case in (1, 2):
        return -jnp.expm1(-s / m)
    u = 2.0 * s / m
    # 1 - (1 + u) e^-u = -expm1(-u) - u e^-u
    return -jnp.expm1(-u) - u * jnp.exp(-u)


def swerling_rcs_sample(key, mean_rcs_m2, case, n_scans=1, n_pulses=1):
    """Draw RCS samples for a Swerling case, shape ``mean.shape + (n_scans, n_pulses)``, m^2.

    Cases 1 and 3 hold one draw for all pulses of a scan (scan-to-scan decorrelation);
    cases 2 and 4 draw every pulse independently; case 0 returns the mean. Samples are
    ``mean * z`` with z a unit-mean standard variate (Exponential(1) for 1/2,
    Gamma(2)/2 for 3/4), so they are reparameterised: differentiable in ``mean_rcs_m2``.

    Args:
        key: ``jax.random`` key.
        mean_rcs_m2: mean RCS, m^2. Domain (0, inf).
        case: Swerling case 0-4 (static int).
        n_scans, n_pulses: static ints >= 1.
    """
    where = "swerling_rcs_sample"
    _check_swerling(case, where)
    _positive(where, mean_rcs_m2=mean_rcs_m2)
    if int(n_scans) < 1 or int(n_pulses) < 1:
        raise DomainError(f"{where}: n_scans and n_pulses must be >= 1; got {n_scans}, {n_pulses}")
    m = jnp.asarray(mean_rcs_m2)
    full = m.shape + (int(n_scans), int(n_pulses))
    if case == 0:
        return jnp.broadcast_to(m[..., None, None], full)
    draw_shape = full if case in (2, 4) else m.shape + (int(n_scans), 1)
    dtype = m.dtype if jnp.issubdtype(m.dtype, jnp.floating) else jnp.float64
    if case in (1, 2):
        z = jax.random.exponential(key, draw_shape, dtype=dtype)
    else:
        z = 0.5 * jax.random.gamma(key, 2.0, draw_shape, dtype=dtype)
    return jnp.broadcast_to(m[..., None, None] * z, full)
