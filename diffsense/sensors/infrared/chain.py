"""Passive infrared point-target detection (IRST): radiometry, detectivity, NETD, range.

Energy form (detector given by its specific detectivity D*, Jones = cm·Hz^½/W):

* contrast intensity of a point target of projected area A_t against the background it hides
  ``J = A_t [ε_t L(T_t) − ε_b L(T_b)]`` (W/sr), L the blackbody band radiance;
* irradiance at the aperture ``E = J τ_a(R)/R²`` (W/m²), τ_a = exp(−σR) the atmospheric
  transmission;
* point-target SNR ``SNR = E A_o τ_o D*/sqrt(A_d Δf) = E A_o τ_o / NEP`` (Hudson 1969 §11.2;
  Brooker §9.1.3.5 eq (9.8): NEP = sqrt(A_d Δf)/D*, SNR = P/NEP);
* NETD of an extended blackbody scene ``NETD = sqrt(A_d Δf)/(D* τ_o A_o Ω_d ∂L/∂T)`` with the
  detector's solid angle Ω_d = A_d/f² (f = F·D), i.e. ``4F² sqrt(Δf)/(π τ_o D* sqrt(A_d) ∂L/∂T)``
  (Dereniak & Boreman 1996 §11; Holst, *Electro-Optical Imaging System Performance*, ch. 12).

Photon form (background-limited detector, BLIP): the background photon irradiance through a
cold stop of half-angle θ is ``E_q = π sin²θ L_q(T_B)`` with L_q the band photon radiance, and

* ``D*_BLIP(λ) = (λ/hc) sqrt(η/(g E_q))`` (g = 2 photovoltaic, 4 photoconductive: g-r noise
  doubles the variance) — Dereniak & Boreman (1996) §5.3; Rogalski, *Infrared Detectors*
  (2nd ed., 2011) §3.3; Bielecki & Rogalski, *Detekcja sygnałów optycznych* eqs (2.21)–(2.22);
* point-target SNR ``η S_q / sqrt(g η E_q A_d Δf)`` with S_q the signal photon rate;
* BLIP NETD ``sqrt(g η E_q A_d Δf)/(η τ_o A_o Ω_d ∂L_q/∂T)``, equal to
  ``1/(τ_o C sqrt(η N))`` for g = 2 and Δf = 1/(2 t_int), with the thermal contrast
  C = (∂L_q/∂T)/L_q and N = E_q A_d t_int the background photons collected (Handbook of Optics
  Vol. I (2nd ed.) ch. 23, eq. (16a)).

Band photon radiance: with x = hc/(λkT), ``L_q = (2k³T³/(h³c²)) ∫ x²/(e^x − 1) dx`` over
[x(λ_hi), x(λ_lo)], evaluated with the two convergent series of Widger & Woodall (1976),
"Integration of the Planck blackbody radiation function", Bull. Am. Meteorol. Soc. 57, 1217:
the tail ``∫_x^∞ = Σ_n e^{−nx}(x²/n + 2x/n² + 2/n³)`` for x ≥ 2 (24 terms, truncation < e^{−50})
and ``2ζ(3) − ∫_0^x`` with the Bernoulli series ``∫_0^x t²/(e^t − 1) dt = Σ_k B_k x^{k+2}/((k+2)k!)``
for x < 2 (terms to B_40, truncation < (1/π)^40). Relative error < 1e-14 against mpmath
(tests/test_infrared.py).

Detection uses the Gaussian-shift statistic of :func:`diffsense.sensors.radiometer.gaussian_detection_probability`
(Pd = Q(Q⁻¹(Pfa) − SNR)); ``snr_db = 10 log10 SNR`` with SNR = P/NEP (book §9.1.3.5).
"""

from __future__ import annotations

import math
from fractions import Fraction

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtr, ndtri

from diffsense.physics import noise
from diffsense.numerics.checks import check_choice, check_range, is_concrete
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.physics.constants import BOLTZMANN_J_K, PLANCK_J_S, SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation import laser_extinction_db_per_km
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "band_photon_radiance",
    "band_photon_radiance_temperature_derivative",
    "background_photon_irradiance",
    "blip_detectivity_jones",
    "contrast_intensity_w_sr",
    "point_target_irradiance_w_m2",
    "irst_snr",
    "netd_k",
    "blip_netd_k",
    "InfraredChain",
]

_H = PLANCK_J_S
_C = SPEED_OF_LIGHT_M_S
_K = BOLTZMANN_J_K
_C2 = _H * _C / _K  # second radiation constant (m K)
_PHOTON_SCALE = 2.0 * _K**3 / (_H**3 * _C**2)  # L_q = scale · T³ · ∫ x²/(e^x − 1) dx
_ZETA3 = 1.2020569031595942853997
_DB_PER_NP = 10.0 / math.log(10.0)
_NOISE_GAIN = {"photovoltaic": 2.0, "photoconductive": 4.0}
_WAVELENGTH_DOMAIN = (1e-9, 10.0)
_CONTRAST_FLOOR = 1e-150  # |contrast| evaluated as sqrt(x² + floor²): finite SNR (dB) at zero contrast


def _bernoulli_even(m_max):
    """B_0 .. B_{2 m_max} as exact fractions (recurrence Σ_{k<n+1} C(n+1,k) B_k = 0)."""
    b = [Fraction(1)]
    for n in range(1, 2 * m_max + 1):
        acc = Fraction(0)
        for k in range(n):
            acc += math.comb(n + 1, k) * b[k]
        b.append(-acc / (n + 1))
    return b


_M_SERIES = 20
_B = _bernoulli_even(_M_SERIES)
# ∫_0^x t²/(e^t−1) dt = x²/2 − x³/6 + Σ_{m≥1} c_m x^{2m+2},  c_m = B_2m / ((2m+2)(2m)!)
_SMALL_COEFFS = np.array(
    [float(_B[2 * m] / ((2 * m + 2) * math.factorial(2 * m))) for m in range(1, _M_SERIES + 1)]
)
_SMALL_POWERS = np.array([2 * m + 2 for m in range(1, _M_SERIES + 1)], dtype=float)
_N_TAIL = np.arange(1, 25, dtype=float)
_X_SPLIT = 2.0


def _photon_tail(x):
    """``∫_x^∞ t²/(e^t − 1) dt`` for x > 0 (Widger & Woodall 1976 series; double-where safe)."""
    x = jnp.asarray(x, dtype=float)
    large = x >= _X_SPLIT
    xl = jnp.where(large, x, _X_SPLIT)[..., None]
    n = jnp.asarray(_N_TAIL)
    tail = jnp.sum(jnp.exp(-n * xl) * (xl * xl / n + 2.0 * xl / n**2 + 2.0 / n**3), axis=-1)
    xs = jnp.where(large, 1.0, x)
    head = xs * xs / 2.0 - xs**3 / 6.0 + jnp.sum(
        jnp.asarray(_SMALL_COEFFS) * xs[..., None] ** jnp.asarray(_SMALL_POWERS), axis=-1
    )
    return jnp.where(large, tail, 2.0 * _ZETA3 - head)


def _bose(x):
    e = jnp.exp(-x)
    return e / (-jnp.expm1(-x))


def _check_band(lo, hi, where):
    check_range("wavelength_lo_m", lo, *_WAVELENGTH_DOMAIN, where=where)
    check_range("wavelength_hi_m", hi, *_WAVELENGTH_DOMAIN, where=where)
    if is_concrete(lo) and is_concrete(hi):
        gap = np.asarray(hi, dtype=float) - np.asarray(lo, dtype=float)
        check_range("wavelength_hi_m - wavelength_lo_m", gap, 0.0, None, where=where)


def _photon_radiance(lo, hi, t):
    t = jnp.asarray(t, dtype=float)
    x_hi = _C2 / (jnp.asarray(hi, dtype=float) * t)  # small x: long wavelength
    x_lo = _C2 / (jnp.asarray(lo, dtype=float) * t)
    return _PHOTON_SCALE * t**3 * (_photon_tail(x_hi) - _photon_tail(x_lo))


def _photon_radiance_dt(lo, hi, t):
    t = jnp.asarray(t, dtype=float)
    x_hi = _C2 / (jnp.asarray(hi, dtype=float) * t)
    x_lo = _C2 / (jnp.asarray(lo, dtype=float) * t)
    band = _photon_tail(x_hi) - _photon_tail(x_lo)
    edges = x_hi**3 * _bose(x_hi) - x_lo**3 * _bose(x_lo)
    return _PHOTON_SCALE * t**2 * (3.0 * band + edges)


def band_photon_radiance(wavelength_lo_m, wavelength_hi_m, temperature_k):
    """Blackbody photon radiance between two wavelengths ``∫ L_λ λ/(hc) dλ`` (photons·s⁻¹·m⁻²·sr⁻¹).

    ``(2k³T³/(h³c²)) ∫ x²/(e^x − 1) dx`` over x = hc/(λkT) ∈ [x(λ_hi), x(λ_lo)], by the
    Widger–Woodall series (module docstring); relative error < 1e-14 (absolute error of the
    band ≲ 1e-15 of the larger cumulative integral when the band is very narrow).

    Args:
        wavelength_lo_m: lower wavelength (m), in [1e-9, 10].
        wavelength_hi_m: upper wavelength (m), in [1e-9, 10], ≥ wavelength_lo_m.
        temperature_k: temperature (K), in (0, 1e5].

    Example: 300 K, 0–10 µm: 1.56e21 photons s⁻¹ m⁻² sr⁻¹ (× π = 4.90e17 photons s⁻¹ cm⁻²).
    Source: Planck's law in photon units (Dereniak & Boreman 1996, §2.6); series of Widger &
    Woodall (1976).
    """
    w = "band_photon_radiance"
    _check_band(wavelength_lo_m, wavelength_hi_m, w)
    check_range("temperature_k", temperature_k, 0.0, 1e5, lo_open=True, where=w)
    return _photon_radiance(wavelength_lo_m, wavelength_hi_m, temperature_k)


def band_photon_radiance_temperature_derivative(wavelength_lo_m, wavelength_hi_m, temperature_k):
    """``∂L_q/∂T`` of the band photon radiance (photons·s⁻¹·m⁻²·sr⁻¹·K⁻¹), in closed form.

    Differentiating L_q = a T³ [G(x_hi) − G(x_lo)] (G(x) = ∫_x^∞ t²/(e^t−1) dt, x ∝ 1/T):
    ``∂L_q/∂T = a T² [3 (G(x_hi) − G(x_lo)) + x_hi³/(e^{x_hi} − 1) − x_lo³/(e^{x_lo} − 1)]``.
    Same arguments, domain and accuracy as :func:`band_photon_radiance`. The thermal contrast
    of a band is (∂L_q/∂T)/L_q (e.g. 300 K: 3.59 %/K in 3–5 µm, 1.61 %/K in 8–12 µm).
    """
    w = "band_photon_radiance_temperature_derivative"
    _check_band(wavelength_lo_m, wavelength_hi_m, w)
    check_range("temperature_k", temperature_k, 0.0, 1e5, lo_open=True, where=w)
    return _photon_radiance_dt(wavelength_lo_m, wavelength_hi_m, temperature_k)


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
    lq = band_photon_radiance(wavelength_lo_m, wavelength_hi_m, background_temperature_k)
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
    check_choice("detector", detector, tuple(_NOISE_GAIN), where=w)
    check_range("quantum_efficiency", quantum_efficiency, 0.0, 1.0, lo_open=True, where=w)
    eq = background_photon_irradiance(cuton_wavelength_m, cutoff_wavelength_m, background_temperature_k,
                                      cold_shield_half_angle_rad)
    return _blip_dstar(cutoff_wavelength_m, eq, quantum_efficiency, _NOISE_GAIN[detector])


def _blip_dstar(peak_wavelength_m, eq_m2, eta, g):
    # sqrt(η/(g E_q)) in m (E_q per m²) → ×100 for cm
    return 100.0 * peak_wavelength_m / (_H * _C) * jnp.sqrt(eta / (g * eq_m2))


def contrast_intensity_w_sr(target_area_m2, target_emissivity, target_temperature_k, background_emissivity,
                            background_temperature_k, wavelength_lo_m, wavelength_hi_m):
    """Band contrast intensity of a point target against the background it hides (W/sr).

    ``J = A_t [ε_t L(T_t) − ε_b L(T_b)]`` with L the blackbody band radiance
    (:func:`diffsense.physics.noise.band_radiance_w_m2_sr`); negative for a target darker than its
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
    lt = noise.band_radiance_w_m2_sr(wavelength_lo_m, wavelength_hi_m, target_temperature_k)
    lb = noise.band_radiance_w_m2_sr(wavelength_lo_m, wavelength_hi_m, background_temperature_k)
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
            (:func:`diffsense.physics.noise.band_radiance_temperature_derivative`), in (0, ∞).

    Source: Dereniak & Boreman (1996) §11 (NETD); Holst (2008) ch. 12; Hudson (1969) §13.
    """
    w = "netd_k"
    check_range("aperture_area_m2", aperture_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("ifov_sr", ifov_sr, 0.0, 4.0 * math.pi, lo_open=True, where=w)
    check_range("optics_transmission", optics_transmission, 0.0, 1.0, lo_open=True, where=w)
    check_range("radiance_temperature_derivative_w_m2_sr_k", radiance_temperature_derivative_w_m2_sr_k, 0.0, None,
                lo_open=True, where=w)
    nep = noise.nep_from_detectivity_w(detector_area_m2, bandwidth_hz, d_star_jones)
    return nep / (optics_transmission * aperture_area_m2 * ifov_sr * radiance_temperature_derivative_w_m2_sr_k)


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
    check_choice("detector", detector, tuple(_NOISE_GAIN), where=w)
    _check_band(wavelength_lo_m, wavelength_hi_m, w)
    check_range("background_temperature_k", background_temperature_k, 0.0, 1e5, lo_open=True, where=w)
    check_range("f_number", f_number, 0.5, 100.0, where=w)
    check_range("detector_area_m2", detector_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("quantum_efficiency", quantum_efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("optics_transmission", optics_transmission, 0.0, 1.0, lo_open=True, where=w)
    return _blip_netd(wavelength_lo_m, wavelength_hi_m, background_temperature_k, f_number, detector_area_m2,
                      bandwidth_hz, quantum_efficiency, optics_transmission, _NOISE_GAIN[detector])


def _blip_netd(lo, hi, tb, fno, ad, df, eta, tau_o, g):
    etendue_factor = math.pi / (4.0 * fno * fno)  # π sin²θ
    eq = etendue_factor * _photon_radiance(lo, hi, tb)
    noise_rate = jnp.sqrt(g * eta * eq * ad * df)
    signal_per_k = eta * tau_o * etendue_factor * ad * _photon_radiance_dt(lo, hi, tb)
    return noise_rate / signal_per_k


# ---------------------------------------------------------------------------------------------
# Scene parts
# ---------------------------------------------------------------------------------------------


@scene_part("haze")
def haze_extinction_db_per_km(visibility_m, wavelength_m):
    """Aerosol extinction (dB/km) from the visibility, Kim et al. (2001) size-distribution model."""
    return laser_extinction_db_per_km(visibility_m, wavelength_m, "kim")


# ---------------------------------------------------------------------------------------------
# Chain
# ---------------------------------------------------------------------------------------------

_DETECTION_BRACKET_M = (1.0, 1e7)


class InfraredChain(Chain):
    """Infrared search and track: a hot point target against a uniform background.

    Signal: band contrast intensity J = A_t[ε_t L(T_t) − ε_b L(T_b)], attenuated by
    exp(−σR) (σ from ``absorption_db_per_km`` plus, with the "haze" part, the Kim-model aerosol
    extinction at the band centre) and spread as 1/R². Detector option "detector":

    * ``"given"``: band-averaged D* (``d_star_jones``); SNR = E A_o τ_o D*/sqrt(A_d Δf);
    * ``"blip_photovoltaic"`` / ``"blip_photoconductive"``: ideal background-limited photon
      detector (quantum efficiency η) whose cold stop matches the optics (sin θ = 1/(2F)) and
      sees a blackbody background at ``background_temperature_k``; the signal is counted in
      photons (band photon contrast intensity).

    The whole blur spot falls on one detector. NETD refers to a blackbody scene at the
    background temperature. Detection is Gaussian: Pd = Q(Q⁻¹(Pfa) − SNR). The sun (glint,
    solar background in 3–5 µm) is not modelled: it acts as structured clutter whose level
    depends on geometry and surface reflectance, not as a noise term of this budget.
    """

    kind = "infrared"
    description = "passive infrared point-target detection (IRST)"
    parts = {"haze": "aerosol (haze/fog) extinction from the meteorological visibility (Kim et al. 2001)"}
    options = {"detector": ("given", ("given", "blip_photovoltaic", "blip_photoconductive"))}

    def parameters(self, scene):
        ps = [
            Param("range_m", "m", "range to the target", default=10e3, lo=1.0, hi=1e6),
            Param("wavelength_lo_m", "m", "lower edge of the spectral band", default=3e-6, lo=2e-7, hi=2e-5),
            Param("wavelength_hi_m", "m", "upper edge of the spectral band (> lower edge; BLIP peak)",
                  default=5e-6, lo=2e-7, hi=2e-5),
            Param("target_area_m2", "m**2", "projected radiating area of the target", default=1.0, lo=0.0, hi=1e4),
            Param("target_temperature_k", "K", "target temperature", default=500.0, lo=0.0, hi=3000.0, lo_open=True),
            Param("target_emissivity", "1", "target emissivity", default=0.9, lo=0.0, hi=1.0),
            Param("background_temperature_k", "K", "background (and NETD scene) temperature; ≥ 150 K keeps the "
                  "background photon flux of every band in the domain a normal float64 (no space backgrounds)",
                  default=280.0, lo=150.0, hi=1000.0),
            Param("background_emissivity", "1", "emissivity of the background hidden by the target",
                  default=1.0, lo=0.0, hi=1.0),
            Param("aperture_diameter_m", "m", "entrance aperture diameter", default=0.15, lo=0.0, hi=10.0,
                  lo_open=True),
            Param("f_number", "1", "working f-number F = f/D", default=2.0, lo=0.5, hi=100.0),
            Param("optics_transmission", "1", "optics transmission τ_o", default=0.7, lo=0.0, hi=1.0,
                  lo_open=True),
            Param("detector_area_m2", "m**2", "detector (pixel) area A_d", default=(25e-6) ** 2, lo=0.0, hi=1e-2,
                  lo_open=True),
            Param("bandwidth_hz", "Hz", "noise bandwidth Δf (1/(2 t_int) for an integrating detector)",
                  default=50.0, lo=0.0, hi=1e9, lo_open=True),
            Param("absorption_db_per_km", "dB/km", "band-averaged clear-air molecular extinction (from "
                  "LOWTRAN/MODTRAN or measurement; 0 = none)", default=0.0, lo=0.0, hi=100.0),
            Param("pfa", "1", "false-alarm probability per decision", default=1e-6, lo=1e-300, hi=0.5),
            Param("pd", "1", "required probability of detection (> pfa)", default=0.9, lo=0.0, hi=1.0 - 1e-12,
                  lo_open=True),
        ]
        if self.option(scene, "detector") == "given":
            ps.append(Param("d_star_jones", "cm*Hz**0.5/W", "band-averaged specific detectivity D*",
                            default=1e11, lo=0.0, hi=1e15, lo_open=True))
        else:
            ps.append(Param("quantum_efficiency", "1", "detector quantum efficiency η", default=0.7,
                            lo=0.0, hi=1.0, lo_open=True))
        if scene.has("haze"):
            ps.append(Param("visibility_m", "m", "meteorological visibility (Koschmieder, 550 nm)",
                            default=23e3, lo=50.0, hi=1e6, part="haze"))
        return collect(ps)

    def outputs(self, scene):
        outs = [
            Output("contrast_intensity_w_sr", "W/sr", "band contrast radiant intensity of the target"),
            Output("transmission", "1", "atmospheric transmission over range_m"),
            Output("irradiance_w_m2", "W/m**2", "contrast irradiance at the aperture"),
            Output("nep_w", "W", "noise-equivalent power (BLIP: at the peak wavelength)"),
            Output("d_star_jones", "cm*Hz**0.5/W", "specific detectivity used (BLIP: peak value)"),
            Output("netd_k", "K", "noise-equivalent temperature difference for a scene at the background temperature"),
            Output("ifov_rad", "rad", "detector angular subtense sqrt(A_d)/f"),
            Output("snr_db", "dB", "10 log10(signal / rms noise) at range_m"),
            Output("required_snr_db", "dB", "10 log10 of the Gaussian deflection needed for (pd, pfa)"),
            Output("snr_margin_db", "dB", "snr_db − required_snr_db"),
            Output("pd", "1", "probability of detection at range_m"),
            Output("detection_range_m", "m", "range where snr_db = required_snr_db (bracket 1 m–10,000 km)"),
        ]
        return {o.name: o for o in outs}

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the range root find is traced only when ``detection_range_m`` is wanted (see
        :class:`diffsense.sensors.chain.Chain`)."""
        where = "infrared chain"
        if is_concrete(p["pd"]) and is_concrete(p["pfa"]):
            check_range("pd - pfa", np.asarray(p["pd"]) - np.asarray(p["pfa"]), 0.0, None, lo_open=True, where=where)
        if is_concrete(p["wavelength_lo_m"]) and is_concrete(p["wavelength_hi_m"]):
            check_range("wavelength_hi_m - wavelength_lo_m",
                        np.asarray(p["wavelength_hi_m"]) - np.asarray(p["wavelength_lo_m"]), 0.0, None,
                        lo_open=True, where=where)
        lo, hi = p["wavelength_lo_m"], p["wavelength_hi_m"]
        mode = self.option(scene, "detector")
        a_o = math.pi * p["aperture_diameter_m"] ** 2 / 4.0
        focal = p["f_number"] * p["aperture_diameter_m"]
        ifov_sr = p["detector_area_m2"] / focal**2
        etendue_factor = math.pi / (4.0 * p["f_number"] ** 2)  # A_o Ω_d / A_d = π sin²θ

        # contrast intensity (energy units, reported in every mode)
        l_t = noise.band_radiance_w_m2_sr(lo, hi, p["target_temperature_k"])
        l_b = noise.band_radiance_w_m2_sr(lo, hi, p["background_temperature_k"])
        j_w = p["target_area_m2"] * (p["target_emissivity"] * l_t - p["background_emissivity"] * l_b)

        # extinction (dB/km), per source
        ext_terms = {"absorption": p["absorption_db_per_km"]}
        if scene.has("haze"):
            ext_terms["haze"] = haze_extinction_db_per_km(p["visibility_m"], 0.5 * (lo + hi))
        ext_db_per_km = sum(ext_terms.values())

        if mode == "given":
            d_star = p["d_star_jones"]
            nep = noise.nep_from_detectivity_w(p["detector_area_m2"], p["bandwidth_hz"], d_star)
            signal_source = j_w  # W/sr
            noise_equiv = nep  # W
            dldt = noise.band_radiance_temperature_derivative(lo, hi, p["background_temperature_k"])
            netd = nep / (p["optics_transmission"] * a_o * ifov_sr * dldt)
            source_label, noise_label = "target contrast intensity (dBW/sr)", "noise-equivalent power (dBW)"
        else:
            g = _NOISE_GAIN["photovoltaic" if mode == "blip_photovoltaic" else "photoconductive"]
            eta = p["quantum_efficiency"]
            eq = etendue_factor * _photon_radiance(lo, hi, p["background_temperature_k"])
            d_star = _blip_dstar(hi, eq, eta, g)
            nep = noise.nep_from_detectivity_w(p["detector_area_m2"], p["bandwidth_hz"], d_star)
            lq_t = _photon_radiance(lo, hi, p["target_temperature_k"])
            lq_b = _photon_radiance(lo, hi, p["background_temperature_k"])
            signal_source = p["target_area_m2"] * (p["target_emissivity"] * lq_t - p["background_emissivity"] * lq_b)
            # noise-equivalent photon rate: sqrt(g η E_q A_d Δf)/η (photons/s)
            noise_equiv = jnp.sqrt(g * eta * eq * p["detector_area_m2"] * p["bandwidth_hz"]) / eta
            netd = _blip_netd(lo, hi, p["background_temperature_k"], p["f_number"], p["detector_area_m2"],
                              p["bandwidth_hz"], eta, p["optics_transmission"], g)
            source_label = "target contrast photon intensity (dB photons/s/sr)"
            noise_label = "noise-equivalent photon rate (dB photons/s)"

        def snr_terms(r):
            terms = [
                (source_label, _DB_PER_NP * jnp.log(jnp.sqrt(signal_source**2 + _CONTRAST_FLOOR**2))),
                ("range spreading 1/R²", -2.0 * _DB_PER_NP * jnp.log(r)),
            ]
            for name, a in ext_terms.items():
                terms.append((f"{name} extinction", -a * r / 1e3))
            terms += [
                ("aperture area (dBm²)", _DB_PER_NP * jnp.log(a_o)),
                ("optics transmission", _DB_PER_NP * jnp.log(p["optics_transmission"])),
                (noise_label, -_DB_PER_NP * jnp.log(noise_equiv)),
            ]
            return terms

        b = BudgetBuilder()
        for name, value in snr_terms(p["range_m"]):
            b.add(name, value)
        budget = b.build()
        snr_db = budget.total
        required_db = _DB_PER_NP * jnp.log(ndtri(p["pd"]) - ndtri(p["pfa"]))

        def residual(r):
            return sum(v for _, v in snr_terms(r)) - required_db

        transmission = 10.0 ** (-ext_db_per_km * p["range_m"] / 1e4)
        values = {
            "contrast_intensity_w_sr": j_w,
            "transmission": transmission,
            "irradiance_w_m2": j_w * transmission / p["range_m"] ** 2,
            "nep_w": nep,
            "d_star_jones": d_star,
            "netd_k": netd,
            "ifov_rad": jnp.sqrt(p["detector_area_m2"]) / focal,
            "snr_db": snr_db,
            "required_snr_db": required_db,
            "snr_margin_db": snr_db - required_db,
            "pd": ndtr(10.0 ** (snr_db / 10.0) + ndtri(p["pfa"])),
        }
        if needs(wanted, "detection_range_m"):
            values["detection_range_m"] = decreasing_root_log(residual, *_DETECTION_BRACKET_M).root
        return Evaluation(budget, values)
