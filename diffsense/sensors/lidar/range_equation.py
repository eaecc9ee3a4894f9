"""Laser range equation: received power from extended and point Lambertian targets, the
cross-over between them, the solar background collected by the receiver, photon energy.

Geometry and conventions
------------------------
The transmitted beam is a uniform (flat-top) circular cone of full divergence angle θ_t; at
range R it illuminates the footprint A_f = π (R tan(θ_t/2))² (:func:`beam_footprint_area_m2`).
The target is a Lambertian (diffuse) surface of hemispherical reflectance ρ whose normal makes
the angle θ with the line of sight. A Lambertian surface element dA lit by the irradiance E
has the radiance L = ρ E cos θ / π, independent of the viewing direction.

* Extended target (the target intercepts the whole beam): all the transmitted power
  P_t τ_t T^(1/2) lands on the surface; its radiant intensity towards the sensor is
  I = ρ P_t τ_t T^(1/2) cos θ / π, and a receiver of area A_r at range R collects I A_r/R²::

      P_r = P_t τ_t τ_r ρ cos θ A_r T / (π R²)                                  (1/R²)

* Point target (smaller than the footprint): the irradiance on it is P_t τ_t T^(1/2)/A_f and
  the radar-like range equation with the laser cross section σ applies::

      P_r = P_t τ_t τ_r σ A_r T / (4π R² A_f),   A_f = π R² θ_t²/4 (small angles)   (1/R⁴)

  For a flat Lambertian plate of physical area A (bidirectional reflectance ρ/π) the
  monostatic cross section is σ = 4π (ρ/π) A cos² θ = 4 ρ A cos² θ
  (:func:`lambertian_cross_section_m2`).

Both forms are the same law P_r = P_extended · f, with f the fraction of the beam power the
target intercepts (f = 1 extended; f = A cos θ / A_f point). They are equal at the
cross-over range where the footprint equals the target's projected area A cos θ
(:func:`crossover_range_m`); :func:`intercepted_fraction` joins the two regimes smoothly.

T is the two-way atmospheric transmission and τ_t, τ_r the transmit and receive optics
efficiencies. Sources: Jelalian, A. V., *Laser Radar Systems* (Artech House, 1992), ch. 1
(laser range equations for extended and point targets); Wehr, A. & Lohr, U. (1999),
"Airborne laser scanning — an introduction and overview", ISPRS J. Photogramm. Remote Sens.
54:68–82 (extended-target form); the cross section of a diffuse surface from its BRDF:
Nicodemus et al. (1977), NBS Monograph 160 (Lambertian BRDF = ρ/π).

Note on Brooker eq. (8.20): the book prints σ = 4πρA cos θ for a Lambertian surface; its own
eqs (8.16)–(8.18) with the solid-angle spread Ω = π give the gain G = 4π/Ω = 4, i.e.
σ = 4 ρ A cos θ (A projected), which is the value used here (with A the physical area,
σ = 4 ρ A cos² θ). Only this value makes the point-target form meet the extended-target form
at the cross-over; 4πρA cos θ would make the received power jump by π (5 dB) there.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
from jax.scipy.special import logsumexp

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range
from diffsense.physics.constants import PLANCK_J_S, SPEED_OF_LIGHT_M_S

__all__ = [
    "photon_energy_j",
    "cone_solid_angle_sr",
    "beam_footprint_area_m2",
    "lambertian_cross_section_m2",
    "crossover_range_m",
    "intercepted_fraction",
    "received_power_extended_w",
    "received_power_point_w",
    "solar_background_power_w",
    "ASTM_G173_GLOBAL_TILT_W_M2_NM",
    "ASTM_G173_DIRECT_W_M2_NM",
    "ASTM_G173_EXTRATERRESTRIAL_W_M2_NM",
]

_HALF_PI = 0.5 * math.pi

#: ASTM G173-03 (reapproved 2012), "Standard Tables for Reference Solar Spectral Irradiances:
#: Direct Normal and Hemispherical on 37° Tilted Surface", column "Global tilt" (W m⁻² nm⁻¹),
#: at common laser wavelengths (nm). AM1.5, cloudless reference atmosphere (SMARTS 2.9.2).
ASTM_G173_GLOBAL_TILT_W_M2_NM = {532: 1.5998, 850: 0.89372, 905: 0.81709, 1064: 0.63196, 1550: 0.26990}
#: ASTM G173-03 column "Direct + circumsolar" (W m⁻² nm⁻¹).
ASTM_G173_DIRECT_W_M2_NM = {532: 1.4094, 850: 0.82900, 905: 0.76337, 1064: 0.59722, 1550: 0.26226}
#: ASTM G173-03 column "Etr" (extraterrestrial, AM0; W m⁻² nm⁻¹).
ASTM_G173_EXTRATERRESTRIAL_W_M2_NM = {532: 1.9580, 850: 0.91000, 905: 0.91800, 1064: 0.64621, 1550: 0.26961}


def _pos(name, x, where, hi=None):
    check_range(name, x, 0.0, hi, lo_open=True, where=where)


def _f(x):
    return jnp.asarray(x, dtype=jnp.result_type(float, x))


def photon_energy_j(wavelength_m):
    """Photon energy ``h ν = h c / λ`` (J).

    Args:
        wavelength_m: wavelength λ (m), in [1e-9, 1e-2].

    Exact (SI defining constants h and c). Example: 1.064 µm -> 1.8670e-19 J, with the defining
    values h = 6.62607015e-34 J s and c = 299792458 m/s:

    >>> float(photon_energy_j(1.064e-6)), 6.62607015e-34 * 299792458 / 1.064e-6
    (1.86696e-19, 1.86696e-19)
    """
    check_range("wavelength_m", wavelength_m, 1e-9, 1e-2, where="photon_energy_j")
    return PLANCK_J_S * SPEED_OF_LIGHT_M_S / _f(wavelength_m)


def cone_solid_angle_sr(full_angle_rad):
    """Solid angle of a circular cone of full apex angle θ: ``Ω = 4π sin²(θ/4)`` (sr).

    Equal to 2π(1 − cos(θ/2)); for small angles Ω ≈ π θ²/4 (relative error θ²/48).

    Args:
        full_angle_rad: full cone angle θ (rad), in (0, 2π].

    A cone of full angle π is a hemisphere (2π sr), one of 2π the whole sphere (4π sr):

    >>> import math
    >>> float(cone_solid_angle_sr(math.pi)) / math.pi, float(cone_solid_angle_sr(2 * math.pi)) / math.pi
    (2.0, 4.0)
    """
    _pos("full_angle_rad", full_angle_rad, "cone_solid_angle_sr", hi=2.0 * math.pi)
    s = jnp.sin(0.25 * _f(full_angle_rad))
    return 4.0 * jnp.pi * s * s


def beam_footprint_area_m2(range_m, beam_divergence_rad):
    """Area of a uniform circular beam of full divergence θ_t at range R: ``π (R tan(θ_t/2))²`` (m²).

    Args:
        range_m: range R (m), in (0, ∞).
        beam_divergence_rad: full divergence angle θ_t (rad), in (0, π).

    The beam leaves a point source (the transmit aperture is neglected against the footprint,
    i.e. far field of the transmitter). Exact for the cone; ≈ π R² θ_t²/4 for small θ_t.
    """
    w = "beam_footprint_area_m2"
    _pos("range_m", range_m, w)
    check_range("beam_divergence_rad", beam_divergence_rad, 0.0, math.pi, lo_open=True, hi_open=True, where=w)
    r = _f(range_m) * jnp.tan(0.5 * _f(beam_divergence_rad))
    return jnp.pi * r * r


def lambertian_cross_section_m2(reflectivity, area_m2, incidence_rad=0.0):
    """Laser cross section of a flat Lambertian plate: ``σ = 4 ρ A cos² θ`` (m²).

    Monostatic cross section σ = 4π f_r A cos² θ with the Lambertian BRDF f_r = ρ/π
    (Nicodemus et al. 1977); with the projected area A_p = A cos θ, σ = 4 ρ A_p cos θ.

    Args:
        reflectivity: hemispherical (diffuse) reflectance ρ, in [0, 1].
        area_m2: physical plate area A (m²), in [0, ∞).
        incidence_rad: angle θ between the plate normal and the line of sight (rad), in
            [−π/2, π/2].

    Exact for an ideal Lambertian plate smaller than the beam. Brooker eq. (8.20) prints
    4πρA cos θ; see the module docstring for why 4 ρ A cos θ (projected A) is used here.
    A 1 m² plate of ρ = 0.5 seen 60° off its normal (cos² 60° = 1/4): 4 × 0.5 × 1 × 0.25:

    >>> import math
    >>> float(lambertian_cross_section_m2(0.5, 1.0, math.radians(60.0)))
    0.5
    """
    w = "lambertian_cross_section_m2"
    check_range("reflectivity", reflectivity, 0.0, 1.0, where=w)
    check_range("area_m2", area_m2, 0.0, None, where=w)
    check_range("incidence_rad", incidence_rad, -_HALF_PI, _HALF_PI, where=w)
    c = jnp.cos(_f(incidence_rad))
    return 4.0 * _f(reflectivity) * _f(area_m2) * c * c


def crossover_range_m(projected_area_m2, beam_divergence_rad):
    """Range where the beam footprint equals the target's projected area (m).

    ``R_c = sqrt(A_p / π) / tan(θ_t / 2)``: below R_c the target intercepts the whole beam
    (extended target, P_r ∝ 1/R²), beyond it only the fraction A_p/A_f (point target,
    P_r ∝ 1/R⁴). The two forms of :func:`received_power_extended_w` and
    :func:`received_power_point_w` (with σ = 4 ρ A_p cos θ) are equal at R_c.

    Args:
        projected_area_m2: target area projected normal to the line of sight A_p (m²), (0, ∞).
        beam_divergence_rad: full divergence θ_t (rad), in (0, π).

    At R_c a 2.5 mrad beam covers exactly the 1 m² target, and the point-target received power
    (σ = 4 ρ A) equals the extended-target one:

    >>> r_c = crossover_range_m(1.0, 2.5e-3)
    >>> float(beam_footprint_area_m2(r_c, 2.5e-3))
    1.0
    >>> point = received_power_point_w(1.0, lambertian_cross_section_m2(0.5, 1.0), 1e-3, r_c, 2.5e-3)
    >>> float(point / received_power_extended_w(1.0, 0.5, 1e-3, r_c))
    1.0
    """
    w = "crossover_range_m"
    _pos("projected_area_m2", projected_area_m2, w)
    check_range("beam_divergence_rad", beam_divergence_rad, 0.0, math.pi, lo_open=True, hi_open=True, where=w)
    return jnp.sqrt(_f(projected_area_m2) / jnp.pi) / jnp.tan(0.5 * _f(beam_divergence_rad))


def intercepted_fraction(projected_area_m2, footprint_area_m2, sharpness=16.0):
    """Fraction of the beam power a target intercepts: smooth ``min(1, A_p / A_f)``.

    ``f = (1 + (A_f/A_p)^p)^(−1/p)``, evaluated in the log domain: differentiable everywhere,
    never above the exact minimum; its largest error is at the cross-over (A_p = A_f), where
    f = 2^(−1/p): −10 log10(2)/p dB (−0.19 dB for p = 16). One decade away from the
    cross-over the error is below 1e-16 relative. ``sharpness=None`` gives the exact minimum.

    Args:
        projected_area_m2: target projected area A_p (m²), in (0, ∞).
        footprint_area_m2: beam footprint A_f (m²), in (0, ∞).
        sharpness: p (static float ≥ 1) or None.

    >>> float(intercepted_fraction(1.0, 1.0)), 2 ** (-1 / 16)
    (0.957603, 0.957603)
    >>> float(intercepted_fraction(1.0, 1e3))
    0.001
    """
    w = "intercepted_fraction"
    _pos("projected_area_m2", projected_area_m2, w)
    _pos("footprint_area_m2", footprint_area_m2, w)
    log_ratio = jnp.log(_f(projected_area_m2)) - jnp.log(_f(footprint_area_m2))
    if sharpness is None:
        return jnp.minimum(1.0, jnp.exp(log_ratio))
    if not sharpness >= 1.0:
        raise DomainError(f"{w}: argument 'sharpness' must be >= 1 or None; got {sharpness!r}")
    p = float(sharpness)
    stacked = jnp.stack(jnp.broadcast_arrays(jnp.zeros_like(log_ratio), -p * log_ratio), axis=0)
    return jnp.exp(-logsumexp(stacked, axis=0) / p)


def received_power_extended_w(peak_power_w, reflectivity, receiver_area_m2, range_m, incidence_rad=0.0,
                              transmission=1.0, optics_efficiency=1.0):
    """Received peak power from an extended Lambertian target (W).

    ``P_r = P_t ρ cos θ A_r T η / (π R²)`` — the target intercepts the whole beam.

    Args:
        peak_power_w: transmitted peak power P_t (W), in (0, ∞).
        reflectivity: diffuse reflectance ρ, in [0, 1].
        receiver_area_m2: receiver aperture area A_r (m²), in (0, ∞).
        range_m: range R (m), in (0, ∞); far field of the receiver (R ≫ aperture).
        incidence_rad: angle θ of the target normal to the line of sight (rad), [0, π/2].
        transmission: two-way atmospheric transmission T, in [0, 1].
        optics_efficiency: product of transmit and receive optics efficiencies η, in [0, 1].

    Source: Jelalian (1992) ch. 1; Wehr & Lohr (1999) (see module docstring).
    """
    w = "received_power_extended_w"
    _pos("peak_power_w", peak_power_w, w)
    check_range("reflectivity", reflectivity, 0.0, 1.0, where=w)
    _pos("receiver_area_m2", receiver_area_m2, w)
    _pos("range_m", range_m, w)
    check_range("incidence_rad", incidence_rad, 0.0, _HALF_PI, where=w)
    check_range("transmission", transmission, 0.0, 1.0, where=w)
    check_range("optics_efficiency", optics_efficiency, 0.0, 1.0, where=w)
    r = _f(range_m)
    return (_f(peak_power_w) * _f(reflectivity) * jnp.cos(_f(incidence_rad)) * _f(receiver_area_m2)
            * _f(transmission) * _f(optics_efficiency) / (jnp.pi * r * r))


def received_power_point_w(peak_power_w, cross_section_m2, receiver_area_m2, range_m, beam_divergence_rad,
                           transmission=1.0, optics_efficiency=1.0):
    """Received peak power from a point target smaller than the beam footprint (W).

    ``P_r = P_t σ A_r T η / (4π R² A_f)`` with the footprint A_f = π (R tan(θ_t/2))²
    (≈ P_t σ A_r T η / (π² θ_t² R⁴) for small θ_t).

    Args:
        peak_power_w: transmitted peak power P_t (W), in (0, ∞).
        cross_section_m2: laser cross section σ (m²), in [0, ∞) (e.g.
            :func:`lambertian_cross_section_m2`).
        receiver_area_m2: receiver aperture area A_r (m²), in (0, ∞).
        range_m: range R (m), in (0, ∞).
        beam_divergence_rad: full beam divergence θ_t (rad), in (0, π).
        transmission: two-way atmospheric transmission T, in [0, 1].
        optics_efficiency: optics efficiency η, in [0, 1].

    Valid beyond the cross-over range (target inside the footprint); below it the formula
    overestimates (the target cannot intercept more than the beam).
    Source: Jelalian (1992) ch. 1 (radar form of the laser range equation with the
    transmitter gain 4π/Ω_beam).
    """
    w = "received_power_point_w"
    _pos("peak_power_w", peak_power_w, w)
    check_range("cross_section_m2", cross_section_m2, 0.0, None, where=w)
    _pos("receiver_area_m2", receiver_area_m2, w)
    check_range("transmission", transmission, 0.0, 1.0, where=w)
    check_range("optics_efficiency", optics_efficiency, 0.0, 1.0, where=w)
    a_f = beam_footprint_area_m2(range_m, beam_divergence_rad)
    r = _f(range_m)
    return (_f(peak_power_w) * _f(cross_section_m2) * _f(receiver_area_m2) * _f(transmission)
            * _f(optics_efficiency) / (4.0 * jnp.pi * r * r * a_f))


def solar_background_power_w(solar_irradiance_w_m2_nm, filter_bandwidth_m, reflectivity, receiver_fov_rad,
                             receiver_area_m2, optics_efficiency=1.0, transmission=1.0):
    """Sunlight reflected by a Lambertian scene into the receiver (W).

    ``P_b = E_λ Δλ (ρ/π) Ω_fov A_r η T``: the sunlit surface has the radiance
    L = ρ E_λ Δλ / π within the optical filter bandwidth Δλ; a receiver of area A_r and field
    of view Ω_fov = 4π sin²(θ_fov/4) filled by that surface collects L A_r Ω_fov (étendue).

    Args:
        solar_irradiance_w_m2_nm: solar spectral irradiance on the surface E_λ
            (W m⁻² nm⁻¹), in [0, 3] (e.g. :data:`ASTM_G173_GLOBAL_TILT_W_M2_NM`; it includes
            the sun's incidence angle on the surface).
        filter_bandwidth_m: optical filter bandwidth Δλ (m), in (0, 1e-5].
        reflectivity: diffuse reflectance ρ of the surface filling the field of view, [0, 1].
        receiver_fov_rad: full field-of-view angle θ_fov (rad), in (0, π].
        receiver_area_m2: receiver aperture area A_r (m²), in (0, ∞).
        optics_efficiency: receive optics and filter transmission η, in [0, 1].
        transmission: one-way atmospheric transmission surface-to-receiver T, in [0, 1].

    Assumes the scene fills the field of view and E_λ is constant across Δλ (error of order
    the relative variation of E_λ across the filter); sky radiance scattered into the field of
    view (path radiance) is neglected. Source: Measures, R. M., *Laser Remote Sensing*
    (Wiley, 1984), ch. 7 (background radiance); Jelalian (1992) ch. 3.
    """
    w = "solar_background_power_w"
    check_range("solar_irradiance_w_m2_nm", solar_irradiance_w_m2_nm, 0.0, 3.0, where=w)
    _pos("filter_bandwidth_m", filter_bandwidth_m, w, hi=1e-5)
    check_range("reflectivity", reflectivity, 0.0, 1.0, where=w)
    _pos("receiver_area_m2", receiver_area_m2, w)
    check_range("optics_efficiency", optics_efficiency, 0.0, 1.0, where=w)
    check_range("transmission", transmission, 0.0, 1.0, where=w)
    check_range("receiver_fov_rad", receiver_fov_rad, 0.0, math.pi, lo_open=True, where=w)
    omega = cone_solid_angle_sr(receiver_fov_rad)
    radiance = _f(solar_irradiance_w_m2_nm) * (_f(filter_bandwidth_m) * 1e9) * _f(reflectivity) / jnp.pi
    return radiance * omega * _f(receiver_area_m2) * _f(optics_efficiency) * _f(transmission)
