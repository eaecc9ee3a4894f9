"""Passive millimetre-wave radiometer: brightness temperatures, contrast, sensitivity, detection.

Radiative transfer in Rayleigh–Jeans-equivalent brightness temperature (linear in power, so
emission, reflection and absorption add exactly):

* Planck brightness of a black body at frequency f: ``B(T) = (hf/k) / (exp(hf/kT) − 1)``
  (→ T − hf/2k for hf ≪ kT; 2.26 K below T at 94 GHz). Every physical temperature (target,
  ground, air, reference load, cosmic background) enters through B.
* An isothermal absorbing layer of opacity τ (Np) and temperature T_m seen against a
  background of brightness T_b: ``T = T_b e^−τ + B(T_m)(1 − e^−τ)``. The sky is this with the
  cosmic background behind the atmosphere (mean radiating temperature T_m).
* A specular surface of emissivity ε (reflectivity 1 − ε, Kirchhoff) at temperature T reflecting
  the sky: apparent temperature ``T_ap = ε B(T) + (1 − ε) T_sky``. A metal target (ε ≈ 0)
  mirrors the cold sky; ground (ε ≈ 0.9) emits near its physical temperature — the contrast that
  passive mm-wave anti-armour submunition sensors detect.
* Antenna: beam solid angle ``Ω_A = λ²/A_e`` (A_e = η_a π D²/4), main beam ``Ω_M = η_M Ω_A``.
  A target of solid angle ``Ω_t = A_t/R²`` centred in a circular Gaussian main beam fills the
  fraction ``F = 1 − exp(−Ω_t/Ω_M)`` of it (the beam power inside a disc of radius α is
  1 − exp(−4 ln2 α²/θ²), θ² = 4 ln2 Ω_M/π); F → Ω_t/Ω_M for a small target, so the antenna
  contrast tends to ``Ω_t ΔT / Ω_A`` (Kraus's point-source antenna temperature), and F → 1 when
  the target fills the beam.
* Sensitivity: total power ``ΔT = T_sys sqrt(1/(Bτ) + (ΔG/G)²)`` and the balanced Dicke
  ``2 T_sys/sqrt(Bτ)`` from :mod:`diffsense.physics.noise`; the unbalanced Dicke radiometer
  ``ΔT = sqrt([2(T_A + T_R)² + 2(T_ref + T_R)²]/(Bτ) + (ΔG/G)² (T_A − T_ref)²)`` here.
* Detection: after integration over Bτ ≫ 1 independent samples the radiometer output is
  Gaussian (central limit theorem), so detecting a mean shift ΔT_c in noise of standard
  deviation ΔT_rms is the Gaussian-shift problem: ``Pd = Q(Q⁻¹(Pfa) − d)`` with
  ``d = |ΔT_c|/ΔT_rms``. The chain reports ``snr_db = 10 log10 d`` (the ratio of the contrast to
  the rms, both temperatures, i.e. powers k T B — the book's convention SNR = P/NEP, §9.1.3.5).

Sources: Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I (1981): ch. 4 (brightness and
apparent temperature, antenna temperature, beam efficiency), ch. 5 (atmospheric emission of an
absorbing layer, secant law), ch. 6 (total-power, Dicke and unbalanced Dicke sensitivity);
Skou & Le Vine, *Microwave Radiometer Systems* (2nd ed., 2006), ch. 2–3; Kraus, *Radio
Astronomy* (2nd ed., 1986), §3 (antenna temperature of a source smaller than the beam).
Specific attenuations: ITU-R P.676-12 (gases), P.838-3 (rain), P.840-7 (cloud and fog) via
:mod:`diffsense.physics.propagation`.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtr, ndtri

from diffsense.physics import antennas, noise
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.physics.constants import BOLTZMANN_J_K, PLANCK_J_S
from diffsense.physics.propagation import (
    cloud_attenuation_db_per_km,
    oxygen_attenuation_db_per_km,
    rain_attenuation_db_per_km,
    water_vapour_attenuation_db_per_km,
)
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "COSMIC_BACKGROUND_TEMPERATURE_K",
    "opacity_from_attenuation_db",
    "planck_brightness_temperature_k",
    "slant_opacity_np",
    "brightness_through_layer_k",
    "sky_brightness_temperature_k",
    "apparent_temperature_k",
    "brightness_contrast_k",
    "beam_solid_angle_sr",
    "gaussian_beamwidth_rad",
    "gaussian_beam_fill_fraction",
    "unbalanced_dicke_delta_t_k",
    "gaussian_detection_probability",
    "gaussian_required_deflection",
    "RadiometerChain",
]

#: Cosmic microwave background temperature (K): Fixsen, D. J. (2009), ApJ 707, 916.
COSMIC_BACKGROUND_TEMPERATURE_K = 2.72548

_NP_PER_DB = math.log(10.0) / 10.0
_DB_PER_NP = 10.0 / math.log(10.0)
_HF_OVER_K = PLANCK_J_S / BOLTZMANN_J_K  # hf/k = 4.799e-11 K per Hz
_CONTRAST_FLOOR_K = 1e-9  # |ΔT| is evaluated as sqrt(ΔT² + floor²) so SNR (dB) stays finite


def _db(x):
    return _DB_PER_NP * jnp.log(x)


def _smooth_abs(x, floor):
    return jnp.sqrt(x * x + floor * floor)


# ---------------------------------------------------------------------------------------------
# Brightness temperatures
# ---------------------------------------------------------------------------------------------


def opacity_from_attenuation_db(attenuation_db):
    """Opacity (optical depth) ``τ = A ln10 / 10`` (Np) of a path of attenuation A (dB).

    Args:
        attenuation_db: one-way attenuation A (dB), in [0, 1000]. Exact.
    """
    check_range("attenuation_db", attenuation_db, 0.0, 1000.0, where="opacity_from_attenuation_db")
    return jnp.asarray(attenuation_db, dtype=float) * _NP_PER_DB


def planck_brightness_temperature_k(physical_temperature_k, freq_hz):
    """Rayleigh–Jeans-equivalent brightness of a black body ``B = (hf/k)/(exp(hf/kT) − 1)`` (K).

    The temperature a Rayleigh–Jeans radiometer assigns to a black body at T: ``B → T − hf/2k``
    for hf ≪ kT (94 GHz: hf/k = 4.51 K, so 290 K → 287.7 K; the cosmic background 2.725 K →
    1.07 K). Evaluated as (hf/k)·e^−x/(1 − e^−x), x = hf/kT: exact, finite value and gradient
    for all T > 0.

    Args:
        physical_temperature_k: T (K), in (0, 1e4].
        freq_hz: frequency f (Hz), in (0, 1e13].

    Source: Ulaby, Moore & Fung (1981) Vol. I §4-1 (Planck's law in brightness temperature);
    Skou & Le Vine (2006) §2.1.
    """
    w = "planck_brightness_temperature_k"
    check_range("physical_temperature_k", physical_temperature_k, 0.0, 1e4, lo_open=True, where=w)
    check_range("freq_hz", freq_hz, 0.0, 1e13, lo_open=True, where=w)
    return _planck_brightness(physical_temperature_k, freq_hz)


def _planck_brightness(t, f):
    t0 = _HF_OVER_K * jnp.asarray(f, dtype=float)
    x = t0 / jnp.asarray(t, dtype=float)
    e = jnp.exp(-x)
    return t0 * e / (-jnp.expm1(-x))


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

    Both physical temperatures enter through :func:`planck_brightness_temperature_k`.
    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 5 (sky brightness of a non-scattering
    atmosphere); Kraus (1986) ch. 3.
    """
    w = "sky_brightness_temperature_k"
    check_range("opacity_np", opacity_np, 0.0, 100.0, where=w)
    check_range("mean_radiating_temperature_k", mean_radiating_temperature_k, 0.0, 400.0, lo_open=True, where=w)
    check_range("freq_hz", freq_hz, 0.0, 1e13, lo_open=True, where=w)
    check_range("cosmic_temperature_k", cosmic_temperature_k, 0.0, 10.0, lo_open=True, where=w)
    return _through_layer(_planck_brightness(cosmic_temperature_k, freq_hz), opacity_np,
                          _planck_brightness(mean_radiating_temperature_k, freq_hz))


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


# ---------------------------------------------------------------------------------------------
# Antenna beam
# ---------------------------------------------------------------------------------------------


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
    return jnp.sqrt(4.0 * math.log(2.0) * jnp.asarray(main_beam_solid_angle_sr, dtype=float) / math.pi)


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
    return -jnp.expm1(-jnp.asarray(target_solid_angle_sr, dtype=float) / main_beam_solid_angle_sr)


# ---------------------------------------------------------------------------------------------
# Sensitivity and detection
# ---------------------------------------------------------------------------------------------


def unbalanced_dicke_delta_t_k(antenna_temperature_k, receiver_noise_temperature_k, reference_temperature_k,
                               bandwidth_hz, integration_time_s, gain_variation=0.0):
    """Sensitivity of a Dicke radiometer whose reference differs from the antenna temperature (K).

    ``ΔT = sqrt([2 (T_A + T_R)² + 2 (T_ref + T_R)²]/(Bτ) + (ΔG/G)² (T_A − T_ref)²)``:
    half the integration time on each input (hence the factors 2) and the residual gain
    fluctuation of the unbalanced difference. For T_ref = T_A it is the balanced Dicke
    ``2 (T_A + T_R)/sqrt(Bτ)`` of :func:`diffsense.physics.noise.dicke_radiometer_delta_t_k`.

    Args:
        antenna_temperature_k: T_A (K), in [0, 1e5].
        receiver_noise_temperature_k: T_R (K), in [0, 1e6].
        reference_temperature_k: brightness of the reference load T_ref (K), in [0, 1e5].
        bandwidth_hz: predetection bandwidth B (Hz), in (0, ∞).
        integration_time_s: τ (s), in (0, ∞).
        gain_variation: RMS ΔG/G over the integration time, in [0, 1].

    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 6 (unbalanced Dicke radiometer); Skou & Le
    Vine (2006) ch. 3.
    """
    w = "unbalanced_dicke_delta_t_k"
    check_range("antenna_temperature_k", antenna_temperature_k, 0.0, 1e5, where=w)
    check_range("receiver_noise_temperature_k", receiver_noise_temperature_k, 0.0, 1e6, where=w)
    check_range("reference_temperature_k", reference_temperature_k, 0.0, 1e5, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("integration_time_s", integration_time_s, 0.0, None, lo_open=True, where=w)
    check_range("gain_variation", gain_variation, 0.0, 1.0, where=w)
    return _unbalanced_dicke(antenna_temperature_k, receiver_noise_temperature_k, reference_temperature_k,
                             bandwidth_hz, integration_time_s, gain_variation)


def _unbalanced_dicke(ta, tr, tref, b, tau, g):
    radiometric = 2.0 * ((ta + tr) ** 2 + (tref + tr) ** 2) / (b * tau)
    return jnp.sqrt(radiometric + (g * (ta - tref)) ** 2)


def gaussian_detection_probability(deflection, pfa):
    """Pd of a mean shift d (in standard deviations) in Gaussian noise: ``Pd = Q(Q⁻¹(Pfa) − d)``.

    Written ``Φ(d + Φ⁻¹(Pfa))`` (Φ the standard normal CDF) so that small Pfa keeps full
    precision. Applies to any detector whose statistic is Gaussian with a signal-independent
    variance: a radiometer integrating Bτ ≫ 1 samples, an IR point-target detector in
    Gaussian (shot/g-r/Johnson) noise.

    Args:
        deflection: d = mean shift / rms noise, in [0, 1e4].
        pfa: false-alarm probability, in [1e-300, 0.5].

    Exact. Source: Van Trees, *Detection, Estimation and Modulation Theory* Pt I (1968) §2.2
    (Gaussian shift, d²); Hudson, *Infrared System Engineering* (1969) ch. 11.
    """
    w = "gaussian_detection_probability"
    check_range("deflection", deflection, 0.0, 1e4, where=w)
    check_range("pfa", pfa, 1e-300, 0.5, where=w)
    return ndtr(jnp.asarray(deflection, dtype=float) + ndtri(jnp.asarray(pfa, dtype=float)))


def gaussian_required_deflection(pd, pfa):
    """Deflection needed for (Pd, Pfa) with a Gaussian statistic: ``d = Φ⁻¹(Pd) − Φ⁻¹(Pfa)``.

    Inverse of :func:`gaussian_detection_probability`. Args: ``pd`` in (Pfa, 1 − 1e-16];
    ``pfa`` in [1e-300, 0.5]. Example: Pd 0.9, Pfa 1e-6 → 1.2816 + 4.7534 = 6.035.
    """
    w = "gaussian_required_deflection"
    check_range("pfa", pfa, 1e-300, 0.5, where=w)
    check_range("pd", pd, 0.0, 1.0 - 1e-16, lo_open=True, where=w)
    if is_concrete(pd) and is_concrete(pfa):
        gap = np.asarray(pd, dtype=float) - np.asarray(pfa, dtype=float)
        check_range("pd - pfa", gap, 0.0, None, lo_open=True, where=w)
    return ndtri(jnp.asarray(pd, dtype=float)) - ndtri(jnp.asarray(pfa, dtype=float))


# ---------------------------------------------------------------------------------------------
# Scene parts (path attenuation)
# ---------------------------------------------------------------------------------------------


@scene_part("gas")
def gas_specific_attenuation_db_per_km(oxygen_db_per_km, water_vapour_db_per_km):
    """Gaseous specific attenuation of the sensor–target path γ_o + γ_w (dB/km), ITU-R P.676-12
    Annex 1 eq. (1); the surface values are the ones the clear-sky opacity already computed."""
    return oxygen_db_per_km + water_vapour_db_per_km


@scene_part("rain")
def rain_specific_attenuation_db_per_km(freq_hz, rain_rate_mm_h):
    """Rain specific attenuation (dB/km), ITU-R P.838-3 with tilt 45° (unpolarised thermal
    emission: the mean of horizontal and vertical)."""
    return rain_attenuation_db_per_km(freq_hz, rain_rate_mm_h, polarization="circular")


@scene_part("fog")
def fog_specific_attenuation_db_per_km(freq_hz, liquid_water_g_m3, temperature_k):
    """Fog (cloud-droplet) specific attenuation (dB/km), ITU-R P.840-7 Rayleigh model."""
    return cloud_attenuation_db_per_km(freq_hz, liquid_water_g_m3, temperature_k)


# ---------------------------------------------------------------------------------------------
# Chain
# ---------------------------------------------------------------------------------------------

_DETECTION_BRACKET_M = (1.0, 1e5)
_ROOT_SLOPE_GUARD_DB = 1e-12  # shifts the detection range by < 1e-12 dB of margin


class RadiometerChain(Chain):
    """Passive mm-wave radiometer detecting a target by its brightness contrast (e.g. a metal
    vehicle mirroring the cold sky against warm ground, seen from a descending submunition).

    Geometry: the radiometer looks down at ``depression_angle_deg`` over the slant range
    ``range_m``; both target and ground reflect the sky in the specular direction (elevation =
    depression angle). The sky is the clear atmosphere (ITU-R P.676 specific attenuation at the
    surface times oxygen and water-vapour equivalent heights, secant law) plus, when the scene
    has them, a rain column of ``rain_height_m`` and a fog layer of ``fog_thickness_m``.
    The parts "gas", "rain", "fog" also attenuate the sensor–target path (whole path inside the
    rain/fog) and add its emission at the air temperature. Receiver: "total_power" (with gain
    fluctuations) or "dicke" (unbalanced, reference load at ``reference_temperature_k``).
    Detection: Gaussian statistic, Pd = Q(Q⁻¹(Pfa) − d), d = |ΔT_A|/ΔT_rms.
    """

    kind = "radiometer"
    description = "passive mm-wave radiometer: target/ground brightness contrast against radiometric noise"
    parts = {
        "gas": "oxygen and water-vapour absorption and emission on the sensor-target path (ITU-R P.676-12)",
        "rain": "rain on the path and in the sky column (ITU-R P.838-3)",
        "fog": "fog on the path and in a fog layer above the target (ITU-R P.840-7)",
    }
    options = {"receiver": ("total_power", ("total_power", "dicke"))}

    def parameters(self, scene):
        ps = [
            Param("freq_hz", "Hz", "radiometer centre frequency", default=94e9, lo=1e9, hi=1e12),
            Param("bandwidth_hz", "Hz", "predetection bandwidth B", default=1e9, lo=0.0, hi=1e11, lo_open=True),
            Param("integration_time_s", "s", "post-detection integration time τ (dwell on the target)",
                  default=1e-3, lo=0.0, hi=1e4, lo_open=True),
            Param("noise_figure_db", "dB", "receiver noise figure (front-end losses included); T_R = 290 (F − 1)",
                  default=6.0, lo=0.0, hi=30.0),
            Param("gain_variation", "1", "RMS receiver gain fluctuation ΔG/G over the integration time",
                  default=1e-4, lo=0.0, hi=0.1),
            Param("antenna_diameter_m", "m", "antenna (circular aperture) diameter", default=0.15,
                  lo=0.0, hi=100.0, lo_open=True),
            Param("aperture_efficiency", "1", "aperture efficiency η_a (A_e = η_a π D²/4)", default=0.6,
                  lo=0.0, hi=1.0, lo_open=True),
            Param("main_beam_efficiency", "1", "main-beam efficiency η_M (sidelobes see the ground)",
                  default=0.9, lo=0.0, hi=1.0, lo_open=True),
            Param("range_m", "m", "slant range to the target", default=150.0, lo=1.0, hi=1e5),
            Param("depression_angle_deg", "deg", "depression angle of the line of sight (= elevation of "
                  "the specularly reflected sky)", default=60.0, lo=5.0, hi=90.0),
            Param("target_area_m2", "m**2", "target area normal to the line of sight", default=20.0,
                  lo=0.0, hi=1e4, lo_open=True),
            Param("target_emissivity", "1", "target emissivity (metal ≈ 0)", default=0.0, lo=0.0, hi=1.0),
            Param("target_temperature_k", "K", "target physical temperature", default=300.0, lo=0.0, hi=1000.0,
                  lo_open=True),
            Param("ground_emissivity", "1", "ground (background) emissivity", default=0.9, lo=0.0, hi=1.0),
            Param("ground_temperature_k", "K", "ground physical temperature", default=290.0, lo=0.0, hi=1000.0,
                  lo_open=True),
            Param("air_temperature_k", "K", "surface air temperature (path emission, gas and fog models)",
                  default=288.15, lo=233.15, hi=323.15),
            Param("pressure_hpa", "hPa", "surface barometric pressure", default=1013.25, lo=300.0, hi=1100.0),
            Param("water_vapour_g_m3", "g/m**3", "surface water-vapour density", default=7.5, lo=0.0, hi=30.0),
            Param("oxygen_equivalent_height_m", "m", "equivalent height of oxygen absorption (zenith "
                  "opacity = surface γ_o × height; ≈ 5–6 km outside the 60/118 GHz lines)", default=6000.0,
                  lo=0.0, hi=20000.0),
            Param("water_vapour_equivalent_height_m", "m", "equivalent height of water-vapour absorption "
                  "(≈ 1.7–2 km outside the 22/183 GHz lines)", default=2000.0, lo=0.0, hi=10000.0),
            Param("sky_mean_radiating_temperature_k", "K", "mean radiating temperature of the atmosphere",
                  default=275.0, lo=150.0, hi=320.0),
            Param("cosmic_temperature_k", "K", "cosmic background temperature", default=COSMIC_BACKGROUND_TEMPERATURE_K,
                  lo=0.0, hi=10.0, lo_open=True),
            Param("pfa", "1", "false-alarm probability per decision", default=1e-6, lo=1e-300, hi=0.5),
            Param("pd", "1", "required probability of detection (> pfa)", default=0.9, lo=0.0, hi=1.0 - 1e-12,
                  lo_open=True),
        ]
        if self.option(scene, "receiver") == "dicke":
            ps.append(Param("reference_temperature_k", "K", "physical temperature of the Dicke reference load",
                            default=290.0, lo=0.0, hi=1000.0, lo_open=True))
        if scene.has("rain"):
            ps += [
                Param("rain_rate_mm_h", "mm/h", "rain rate", default=4.0, lo=0.0, hi=200.0, part="rain"),
                Param("rain_height_m", "m", "height of the rain column above the target (≈ 0 °C isotherm)",
                      default=3000.0, lo=0.0, hi=10000.0, part="rain"),
            ]
        if scene.has("fog"):
            ps += [
                Param("fog_liquid_water_g_m3", "g/m**3", "fog liquid water content (0.05 moderate, 0.5 thick)",
                      default=0.1, lo=0.0, hi=5.0, part="fog"),
                Param("fog_thickness_m", "m", "fog layer thickness above the target", default=100.0,
                      lo=0.0, hi=2000.0, part="fog"),
            ]
        return collect(ps)

    def outputs(self, scene):
        outs = [
            Output("sky_temperature_k", "K", "sky brightness in the specular direction (incl. rain/fog columns)"),
            Output("target_apparent_temperature_k", "K", "target apparent temperature at the surface"),
            Output("ground_apparent_temperature_k", "K", "ground apparent temperature at the surface"),
            Output("contrast_k", "K", "apparent-temperature contrast target − ground at the surface"),
            Output("path_transmission", "1", "transmissivity of the sensor-target path e^−τ"),
            Output("antenna_gain_db", "dB", "antenna gain 10 log10(4π/Ω_A) = 10 log10(4π η_a A/λ²)"),
            Output("beamwidth_rad", "rad", "half-power beamwidth of the equivalent Gaussian main beam"),
            Output("footprint_diameter_m", "m", "half-power footprint diameter normal to the beam at range_m"),
            Output("beam_fill", "1", "fraction of the main beam filled by the target"),
            Output("antenna_temperature_k", "K", "antenna temperature, ground only in the beam"),
            Output("antenna_temperature_target_k", "K", "antenna temperature, target centred in the beam"),
            Output("antenna_contrast_k", "K", "antenna-temperature contrast (signed)"),
            Output("system_temperature_k", "K", "system noise temperature T_A + T_R"),
            Output("delta_t_k", "K", "radiometric sensitivity ΔT_rms"),
            Output("snr_db", "dB", "10 log10(|antenna contrast| / ΔT_rms)"),
            Output("required_snr_db", "dB", "10 log10 of the Gaussian deflection needed for (pd, pfa)"),
            Output("snr_margin_db", "dB", "snr_db − required_snr_db"),
            Output("pd", "1", "probability of detection at range_m"),
            Output("detection_range_m", "m", "slant range where snr_db = required_snr_db (bracket 1 m–100 km)"),
        ]
        return {o.name: o for o in outs}

    # ---- model -------------------------------------------------------------------------

    def _sky_and_specific(self, scene, p):
        """Sky brightness and the parts' specific attenuations (dB/km): range independent, computed
        once outside the detection-range solve."""
        f = p["freq_hz"]
        gamma_o = oxygen_attenuation_db_per_km(f, p["pressure_hpa"], p["air_temperature_k"], p["water_vapour_g_m3"])
        gamma_w = water_vapour_attenuation_db_per_km(f, p["pressure_hpa"], p["air_temperature_k"],
                                                     p["water_vapour_g_m3"])
        zenith_db = (gamma_o * p["oxygen_equivalent_height_m"] + gamma_w * p["water_vapour_equivalent_height_m"]) / 1e3
        specific = {}
        if scene.has("gas"):
            specific["gas"] = gas_specific_attenuation_db_per_km(gamma_o, gamma_w)
        if scene.has("rain"):
            specific["rain"] = rain_specific_attenuation_db_per_km(f, p["rain_rate_mm_h"])
            zenith_db = zenith_db + specific["rain"] * p["rain_height_m"] / 1e3
        if scene.has("fog"):
            specific["fog"] = fog_specific_attenuation_db_per_km(f, p["fog_liquid_water_g_m3"], p["air_temperature_k"])
            zenith_db = zenith_db + specific["fog"] * p["fog_thickness_m"] / 1e3
        sin_el = jnp.sin(jnp.deg2rad(p["depression_angle_deg"]))
        tau_sky = zenith_db * _NP_PER_DB / sin_el
        t_sky = _through_layer(_planck_brightness(p["cosmic_temperature_k"], f), tau_sky,
                               _planck_brightness(p["sky_mean_radiating_temperature_k"], f))
        return t_sky, specific

    def _path_db(self, scene, p, specific, range_m):
        """Per-part one-way attenuation (dB) of the sensor-target path at ``range_m``."""
        return {part: gamma * range_m / 1e3 for part, gamma in specific.items()}

    def _at_range(self, scene, p, t_sky, specific, range_m):
        """Everything that depends on the range: returns a dict of named quantities."""
        f = p["freq_hz"]
        lam = antennas.wavelength_m(f)
        t_target = _apparent(p["target_emissivity"], _planck_brightness(p["target_temperature_k"], f), t_sky)
        t_ground = _apparent(p["ground_emissivity"], _planck_brightness(p["ground_temperature_k"], f), t_sky)
        path_terms = self._path_db(scene, p, specific, range_m)
        path_db = sum(path_terms.values()) if path_terms else jnp.zeros_like(range_m)
        tau = path_db * _NP_PER_DB
        t_air = _planck_brightness(p["air_temperature_k"], f)
        t_target_s = _through_layer(t_target, tau, t_air)
        t_ground_s = _through_layer(t_ground, tau, t_air)

        area = antennas.circular_aperture_area_m2(p["antenna_diameter_m"])
        omega_a = lam * lam / (p["aperture_efficiency"] * area)
        omega_m = p["main_beam_efficiency"] * omega_a
        fill = -jnp.expm1(-(p["target_area_m2"] / (range_m * range_m)) / omega_m)
        eta = p["main_beam_efficiency"]
        main = fill * t_target_s + (1.0 - fill) * t_ground_s
        ta_target = noise.antenna_temperature_k(main, t_ground_s, eta)
        ta_ground = noise.antenna_temperature_k(t_ground_s, t_ground_s, eta)
        t_rec = noise.noise_temperature_k(p["noise_figure_db"])
        t_sys = ta_ground + t_rec
        if self.option(scene, "receiver") == "dicke":
            t_ref = _planck_brightness(p["reference_temperature_k"], f)
            delta_t = _unbalanced_dicke(ta_ground, t_rec, t_ref, p["bandwidth_hz"], p["integration_time_s"],
                                        p["gain_variation"])
        else:
            delta_t = noise.total_power_radiometer_delta_t_k(t_sys, p["bandwidth_hz"], p["integration_time_s"],
                                                             p["gain_variation"])
        contrast = t_target - t_ground
        return dict(
            t_target=t_target, t_ground=t_ground, contrast=contrast, path_terms=path_terms, tau=tau,
            omega_a=omega_a, omega_m=omega_m, fill=fill, ta_target=ta_target, ta_ground=ta_ground, t_sys=t_sys,
            delta_t=delta_t, antenna_contrast=ta_target - ta_ground,
        )

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the range root find is traced only when ``detection_range_m`` is wanted (see
        :class:`diffsense.sensors.chain.Chain`)."""
        if is_concrete(p["pd"]) and is_concrete(p["pfa"]):
            check_range("pd - pfa", np.asarray(p["pd"]) - np.asarray(p["pfa"]), 0.0, None, lo_open=True,
                        where="radiometer chain")
        t_sky, specific = self._sky_and_specific(scene, p)
        q = self._at_range(scene, p, t_sky, specific, p["range_m"])
        d_required = ndtri(p["pd"]) - ndtri(p["pfa"])
        required_db = _db(d_required)

        b = BudgetBuilder()
        b.add("surface brightness contrast (dBK)", _db(_smooth_abs(q["contrast"], _CONTRAST_FLOOR_K)))
        for part, a_db in q["path_terms"].items():
            b.add(f"{part} path attenuation", -a_db)
        b.add("main-beam efficiency", _db(p["main_beam_efficiency"]))
        b.add("beam fill", _db(q["fill"]))
        b.add("radiometric sensitivity ΔT (dBK)", -_db(q["delta_t"]))
        budget = b.build()
        snr_db = budget.total
        deflection = 10.0 ** (snr_db / 10.0)

        def residual(r):
            qr = self._at_range(scene, p, t_sky, specific, r)
            d = _smooth_abs(qr["antenna_contrast"], _CONTRAST_FLOOR_K) / qr["delta_t"]
            # a 1e-12 dB/Np slope keeps the residual strictly decreasing where the beam is filled
            # and the path is clear (flat SNR), so the implicit derivative of the root stays finite
            return _db(d) - required_db - _ROOT_SLOPE_GUARD_DB * jnp.log(r)

        beamwidth = jnp.sqrt(4.0 * math.log(2.0) * q["omega_m"] / math.pi)
        values = {
            "sky_temperature_k": t_sky,
            "target_apparent_temperature_k": q["t_target"],
            "ground_apparent_temperature_k": q["t_ground"],
            "contrast_k": q["contrast"],
            "path_transmission": jnp.exp(-q["tau"]),
            "antenna_gain_db": _db(4.0 * math.pi / q["omega_a"]),
            "beamwidth_rad": beamwidth,
            "footprint_diameter_m": p["range_m"] * beamwidth,
            "beam_fill": q["fill"],
            "antenna_temperature_k": q["ta_ground"],
            "antenna_temperature_target_k": q["ta_target"],
            "antenna_contrast_k": q["antenna_contrast"],
            "system_temperature_k": q["t_sys"],
            "delta_t_k": q["delta_t"],
            "snr_db": snr_db,
            "required_snr_db": required_db,
            "snr_margin_db": snr_db - required_db,
            "pd": ndtr(deflection + ndtri(p["pfa"])),
        }
        if needs(wanted, "detection_range_m"):
            values["detection_range_m"] = decreasing_root_log(residual, *_DETECTION_BRACKET_M).root
        return Evaluation(budget, values)

