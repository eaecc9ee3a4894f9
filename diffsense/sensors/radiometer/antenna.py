"""The radiometer's antenna beam: beam solid angle from the effective aperture, the half-power
width of the equivalent circular Gaussian beam and the fraction of it a target fills.

* Beam solid angle ``Ω_A = λ²/A_e`` (A_e = η_a π D²/4), main beam ``Ω_M = η_M Ω_A``.
* A target of solid angle ``Ω_t = A_t/R²`` centred in a circular Gaussian main beam fills the
  fraction ``F = 1 − exp(−Ω_t/Ω_M)`` of it (the beam power inside a disc of radius α is
  1 − exp(−4 ln2 α²/θ²), θ² = 4 ln2 Ω_M/π); F → Ω_t/Ω_M for a small target, so the antenna
  contrast tends to ``Ω_t ΔT / Ω_A`` (Kraus's point-source antenna temperature), and F → 1 when
  the target fills the beam.

Sources: Kraus, *Antennas* (2nd ed., 1988) §2-22; Kraus, *Radio Astronomy* (2nd ed., 1986), §3
and §6; Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I (1981), ch. 3–4.

Directivity 4π/Ω_A of a uniformly illuminated aperture is 4πA/λ² (Kraus §2-22):

>>> import math
>>> from diffsense.sensors.radiometer.antenna import beam_solid_angle_sr
>>> round(4 * math.pi / float(beam_solid_angle_sr(0.01, 0.5)) / (4 * math.pi * 0.5 / 0.01**2), 12)
1.0
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.checks import check_range

__all__ = ["beam_solid_angle_sr", "gaussian_beamwidth_rad", "gaussian_beam_fill_fraction"]


def beam_solid_angle_sr(wavelength_m, aperture_area_m2, aperture_efficiency=1.0):
    """Antenna beam solid angle ``Ω_A = λ²/A_e`` with ``A_e = η_a A`` (sr).

    Args:
        wavelength_m: λ (m), in (0, ∞).
        aperture_area_m2: physical aperture area A (m²), in (0, ∞).
        aperture_efficiency: η_a, in (0, 1].

    Exact (definition of the effective area, D = 4π/Ω_A = 4π A_e/λ²). Source: Kraus, *Antennas*
    (2nd ed., 1988) §2-22; Ulaby, Moore & Fung (1981) Vol. I ch. 3.
    """
    w = "beam_solid_angle_sr"
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=w)
    check_range("aperture_area_m2", aperture_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("aperture_efficiency", aperture_efficiency, 0.0, 1.0, lo_open=True, where=w)
    lam = jnp.asarray(wavelength_m, dtype=float)
    return lam * lam / (aperture_efficiency * jnp.asarray(aperture_area_m2, dtype=float))


def gaussian_beamwidth_rad(main_beam_solid_angle_sr):
    """Half-power beamwidth of a circular Gaussian beam of solid angle Ω_M: ``θ = sqrt(4 ln2 Ω_M/π)`` (rad).

    A Gaussian pattern exp(−4 ln2 ψ²/θ²) integrates to Ω_M = π θ²/(4 ln 2) = 1.133 θ² (small
    angles). Args: ``main_beam_solid_angle_sr`` Ω_M (sr), in (0, 1] (small-angle: θ < ≈ 30°).
    Source: Kraus (1986) *Radio Astronomy* §6 (Gaussian beam solid angle 1.133 θ²).
    """
    check_range("main_beam_solid_angle_sr", main_beam_solid_angle_sr, 0.0, 1.0, lo_open=True,
                where="gaussian_beamwidth_rad")
    return _gaussian_beamwidth(jnp.asarray(main_beam_solid_angle_sr, dtype=float))


def _gaussian_beamwidth(omega_m):
    return jnp.sqrt(4.0 * math.log(2.0) * omega_m / math.pi)


def gaussian_beam_fill_fraction(target_solid_angle_sr, main_beam_solid_angle_sr):
    """Fraction of a circular Gaussian main beam filled by a centred disc target ``1 − exp(−Ω_t/Ω_M)``.

    Beam-weighted: the integral of the normalised Gaussian pattern over a disc of solid angle
    Ω_t divided by its integral over the sky, Ω_M = π θ²/(4 ln 2). Small target: Ω_t/Ω_M;
    large target: → 1. Smooth (no kink where the target fills the −3 dB footprint, unlike
    :func:`diffsense.physics.antennas.beam_fill_ratio`).

    Args:
        target_solid_angle_sr: Ω_t = A_t/R² (sr), in [0, 4π].
        main_beam_solid_angle_sr: Ω_M (sr), in (0, 1].

    Exact for a Gaussian beam and a centred disc (small angles); real beams differ by their
    sidelobes, which :func:`diffsense.physics.noise.antenna_temperature_k` weights with 1 − η_M.
    Source: Ulaby, Moore & Fung (1981) Vol. I §4-5 (antenna temperature as the pattern-weighted
    brightness); Kraus (1986) §3 (source smaller than the beam).
    """
    w = "gaussian_beam_fill_fraction"
    check_range("target_solid_angle_sr", target_solid_angle_sr, 0.0, 4.0 * math.pi, where=w)
    check_range("main_beam_solid_angle_sr", main_beam_solid_angle_sr, 0.0, 1.0, lo_open=True, where=w)
    return _fill_fraction(jnp.asarray(target_solid_angle_sr, dtype=float), main_beam_solid_angle_sr)


def _fill_fraction(omega_t, omega_m):
    return -jnp.expm1(-omega_t / omega_m)
