"""Infrared detectors: background-limited (BLIP) photon detectors, the point-target SNR of a
detector given by its D*, and the noise-equivalent temperature difference (NETD).

* Energy form: point-target ``SNR = E A_o τ_o D*/sqrt(A_d Δf) = E A_o τ_o / NEP`` (Hudson 1969
  §11.2; Brooker §9.1.3.5 eq (9.8): NEP = sqrt(A_d Δf)/D*, SNR = P/NEP); NETD of an extended
  blackbody scene ``NETD = sqrt(A_d Δf)/(D* τ_o A_o Ω_d ∂L/∂T)`` with the detector's solid angle
  Ω_d = A_d/f² (f = F·D), i.e. ``4F² sqrt(Δf)/(π τ_o D* sqrt(A_d) ∂L/∂T)`` (Dereniak & Boreman
  1996 §11; Holst, *Electro-Optical Imaging System Performance*, ch. 12).
* Photon form (BLIP): the background photon irradiance through a cold stop of half-angle θ is
  ``E_q = π sin²θ L_q(T_B)`` with L_q the band photon radiance
  (:func:`diffsense.physics.radiance.band_photon_radiance`), and
  ``D*_BLIP(λ) = (λ/hc) sqrt(η/(g E_q))`` (g = 2 photovoltaic, 4 photoconductive: g-r noise
  doubles the variance) — Dereniak & Boreman (1996) §5.3; Rogalski, *Infrared Detectors* (2nd
  ed., 2011) §3.3; Bielecki & Rogalski, *Detekcja sygnałów optycznych* eqs (2.21)–(2.22). BLIP
  NETD ``sqrt(g η E_q A_d Δf)/(η τ_o A_o Ω_d ∂L_q/∂T)``, equal to ``1/(τ_o C sqrt(η N))`` for
  g = 2 and Δf = 1/(2 t_int), with the thermal contrast C = (∂L_q/∂T)/L_q and N = E_q A_d t_int
  the background photons collected (Handbook of Optics Vol. I (2nd ed.) ch. 23, eq. (16a)).

A photoconductor's g-r noise doubles the noise variance, so its BLIP D* is lower by √2
(Dereniak & Boreman §5.3):

>>> import math
>>> from diffsense.sensors.infrared.detector import blip_detectivity_jones
>>> pv = blip_detectivity_jones(10e-6, 300.0)
>>> pc = blip_detectivity_jones(10e-6, 300.0, detector="photoconductive")
>>> round(float(pv / pc) / math.sqrt(2.0), 12)
1.0
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.checks import check_choice, check_range
from diffsense.physics import noise, radiance
from diffsense.physics.constants import PLANCK_J_S, SPEED_OF_LIGHT_M_S

__all__ = [
    "NOISE_GAIN",
    "background_photon_irradiance",
    "blip_detectivity_jones",
    "irst_snr",
    "netd_k",
    "blip_netd_k",
]

_H = PLANCK_J_S
_C = SPEED_OF_LIGHT_M_S

NOISE_GAIN = {"photovoltaic": 2.0, "photoconductive": 4.0}
"""Noise gain g of a photon detector: 2 for shot noise (photovoltaic), 4 for
generation–recombination noise (photoconductive)."""


def background_photon_irradiance(wavelength_lo_m, wavelength_hi_m, background_temperature_k,
                                 cold_shield_half_angle_rad=0.5 * math.pi):
    """Background photon irradiance on a cold-shielded detector ``E_q = π sin²θ L_q(T_B)`` (photons·s⁻¹·m⁻²).

    A Lambertian blackbody background filling the cone of half-angle θ defined by the cold
    stop; θ = π/2 is the hemispherical (2π sr) field of view. For optics of working f-number F,
    sin θ = 1/(2F).

    Args:
        wavelength_lo_m, wavelength_hi_m: detector spectral band (m), in [1e-9, 10].
        background_temperature_k: T_B (K), in (0, 1e5].
        cold_shield_half_angle_rad: θ (rad), in (0, π/2].

    Source: Dereniak & Boreman (1996) §5.3 (Q_B = sin²(θ/2) ∫ M_q dλ with θ the full cone
    angle); Bielecki & Rogalski eq (2.22).
    """
    w = "background_photon_irradiance"
    check_range("cold_shield_half_angle_rad", cold_shield_half_angle_rad, 0.0, 0.5 * math.pi, lo_open=True, where=w)
    lq = radiance.band_photon_radiance(wavelength_lo_m, wavelength_hi_m, background_temperature_k)
    return math.pi * jnp.sin(jnp.asarray(cold_shield_half_angle_rad, dtype=float)) ** 2 * lq


def blip_detectivity_jones(cutoff_wavelength_m, background_temperature_k, quantum_efficiency=1.0,
                           cold_shield_half_angle_rad=0.5 * math.pi, *, cuton_wavelength_m=1e-9,
                           detector="photovoltaic"):
    """Background-limited (BLIP) peak specific detectivity ``D* = (λ_c/hc) sqrt(η/(g E_q))`` (Jones).

    An ideal photon detector responding to all photons between the cut-on and the cut-off
    wavelength λ_c (its peak), limited by the shot (photovoltaic, g = 2) or
    generation–recombination (photoconductive, g = 4) noise of the background photon flux
    E_q of :func:`background_photon_irradiance`. Result in cm·Hz^½·W⁻¹.

    Args:
        cutoff_wavelength_m: λ_c (m), in [1e-9, 10].
        background_temperature_k: T_B (K), in (0, 1e5].
        quantum_efficiency: η, in (0, 1].
        cold_shield_half_angle_rad: θ (rad), in (0, π/2] (π/2: 2π sr field of view).
        cuton_wavelength_m: short-wavelength edge (m), in [1e-9, λ_c]; default 1 nm (all
            photons shorter than λ_c).
        detector: "photovoltaic" or "photoconductive" (static).

    Example: λ_c = 10 µm, 300 K, 2π sr, η = 1: E_q = 4.90e17 photons s⁻¹ cm⁻², D* = 5.09e10
    (photovoltaic), 3.60e10 (photoconductive). Exact given the photon integral.
    Source: Dereniak & Boreman (1996) §5.3 eqs for D*_BLIP; Rogalski (2011) §3.3.
    """
    w = "blip_detectivity_jones"
    check_choice("detector", detector, tuple(NOISE_GAIN), where=w)
    check_range("quantum_efficiency", quantum_efficiency, 0.0, 1.0, lo_open=True, where=w)
    eq = background_photon_irradiance(cuton_wavelength_m, cutoff_wavelength_m, background_temperature_k,
                                      cold_shield_half_angle_rad)
    return _blip_dstar(cutoff_wavelength_m, eq, quantum_efficiency, NOISE_GAIN[detector])


def _blip_dstar(peak_wavelength_m, eq_m2, eta, g):
    # sqrt(η/(g E_q)) in m (E_q per m²) → ×100 for cm
    return 100.0 * peak_wavelength_m / (_H * _C) * jnp.sqrt(eta / (g * eq_m2))


def irst_snr(irradiance_w_m2, aperture_area_m2, optics_transmission, d_star_jones, detector_area_m2, bandwidth_hz):
    """Point-target SNR of an IRST ``E A_o τ_o D*/sqrt(A_d Δf)`` (ratio of signal to rms noise).

    The signal power E A_o τ_o (the blur spot falls on one detector) divided by
    NEP = sqrt(A_d Δf)/D* (:func:`diffsense.physics.noise.nep_from_detectivity_w`, A_d converted to
    cm²).

    Args:
        irradiance_w_m2: E at the aperture (W/m²), in [0, ∞) (use |E| for a negative contrast).
        aperture_area_m2: A_o (m²), in (0, ∞).
        optics_transmission: τ_o, in (0, 1].
        d_star_jones: D* (cm·Hz^½/W), in (0, ∞).
        detector_area_m2: A_d (m²), in (0, ∞).
        bandwidth_hz: noise bandwidth Δf (Hz), in (0, ∞).

    Source: Hudson (1969) §11.2 (range equation of a search system); Brooker eq (9.8).
    """
    w = "irst_snr"
    check_range("irradiance_w_m2", irradiance_w_m2, 0.0, None, where=w)
    check_range("aperture_area_m2", aperture_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("optics_transmission", optics_transmission, 0.0, 1.0, lo_open=True, where=w)
    nep = noise.nep_from_detectivity_w(detector_area_m2, bandwidth_hz, d_star_jones)
    return irradiance_w_m2 * aperture_area_m2 * optics_transmission / nep


def netd_k(detector_area_m2, bandwidth_hz, d_star_jones, aperture_area_m2, ifov_sr, optics_transmission,
           radiance_temperature_derivative_w_m2_sr_k):
    """Noise-equivalent temperature difference ``NETD = sqrt(A_d Δf)/(D* τ_o A_o Ω_d ∂L/∂T)`` (K).

    The scene temperature change whose radiance change, collected over the étendue A_o Ω_d
    (aperture area × detector solid angle A_d/f²), equals the NEP. With A_o Ω_d = π A_d/(4F²):
    ``NETD = 4F² sqrt(Δf)/(π τ_o D* sqrt(A_d) ∂L/∂T)``; scales as F².

    Args:
        detector_area_m2: A_d (m²), in (0, ∞).
        bandwidth_hz: Δf (Hz), in (0, ∞).
        d_star_jones: band-averaged D* (cm·Hz^½/W), in (0, ∞).
        aperture_area_m2: A_o (m²), in (0, ∞).
        ifov_sr: detector solid angle Ω_d (sr), in (0, 4π].
        optics_transmission: τ_o, in (0, 1].
        radiance_temperature_derivative_w_m2_sr_k: band ∂L/∂T of the scene (W·m⁻²·sr⁻¹·K⁻¹)
            (:func:`diffsense.physics.radiance.band_radiance_temperature_derivative`), in (0, ∞).

    Source: Dereniak & Boreman (1996) §11 (NETD); Holst (2008) ch. 12; Hudson (1969) §13.
    """
    w = "netd_k"
    check_range("aperture_area_m2", aperture_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("ifov_sr", ifov_sr, 0.0, 4.0 * math.pi, lo_open=True, where=w)
    check_range("optics_transmission", optics_transmission, 0.0, 1.0, lo_open=True, where=w)
    check_range("radiance_temperature_derivative_w_m2_sr_k", radiance_temperature_derivative_w_m2_sr_k, 0.0, None,
                lo_open=True, where=w)
    nep = noise.nep_from_detectivity_w(detector_area_m2, bandwidth_hz, d_star_jones)
    return _netd(nep, aperture_area_m2, ifov_sr, optics_transmission, radiance_temperature_derivative_w_m2_sr_k)


def _netd(nep_w, aperture_area_m2, ifov_sr, optics_transmission, dl_dt):
    return nep_w / (optics_transmission * aperture_area_m2 * ifov_sr * dl_dt)


def blip_netd_k(wavelength_lo_m, wavelength_hi_m, background_temperature_k, f_number, detector_area_m2,
                bandwidth_hz, quantum_efficiency, optics_transmission, detector="photovoltaic"):
    """NETD of a background-limited photon detector viewing a blackbody scene at T_B (K).

    ``NETD = sqrt(g η E_q A_d Δf) / (η τ_o (π A_d/(4F²)) ∂L_q/∂T)`` with
    ``E_q = π L_q(T_B)/(4F²)``: the scene fills the cold stop (sin θ = 1/(2F)) and the optics
    are at the scene temperature, so the background flux does not depend on τ_o. For a
    photovoltaic detector with Δf = 1/(2 t_int) this is ``1/(τ_o C sqrt(η N))``, C the thermal
    contrast and N = E_q A_d t_int (Handbook of Optics Vol. I ch. 23 eq. (16a)).

    Args:
        wavelength_lo_m, wavelength_hi_m: band (m), in [1e-9, 10].
        background_temperature_k: scene temperature T_B (K), in (0, 1e5].
        f_number: working f-number F = 1/(2 sin θ), in [0.5, 100].
        detector_area_m2: A_d (m²), in (0, ∞).
        bandwidth_hz: Δf (Hz), in (0, ∞).
        quantum_efficiency: η, in (0, 1].
        optics_transmission: τ_o, in (0, 1].
        detector: "photovoltaic" or "photoconductive" (static).
    """
    w = "blip_netd_k"
    check_choice("detector", detector, tuple(NOISE_GAIN), where=w)
    check_range("background_temperature_k", background_temperature_k, 0.0, 1e5, lo_open=True, where=w)
    check_range("f_number", f_number, 0.5, 100.0, where=w)
    check_range("detector_area_m2", detector_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("quantum_efficiency", quantum_efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("optics_transmission", optics_transmission, 0.0, 1.0, lo_open=True, where=w)
    return _blip_netd(wavelength_lo_m, wavelength_hi_m, background_temperature_k, f_number, detector_area_m2,
                      bandwidth_hz, quantum_efficiency, optics_transmission, NOISE_GAIN[detector])


def _blip_netd(lo, hi, tb, fno, ad, df, eta, tau_o, g):
    etendue_factor = math.pi / (4.0 * fno * fno)  # π sin²θ
    eq = etendue_factor * radiance.band_photon_radiance(lo, hi, tb)
    noise_rate = jnp.sqrt(g * eta * eq * ad * df)
    signal_per_k = eta * tau_o * etendue_factor * ad * radiance.band_photon_radiance_temperature_derivative(lo, hi, tb)
    return noise_rate / signal_per_k
