"""Clutter models: surface, volume, wall and sonar reverberation.

Pure ``jnp`` formulas, jit/vmap/grad-able. Angles are in radians, lengths in metres, times in
seconds, radar cross-sections in m², reflectivities (σ°, γ) linear unless the name says ``_db``.

Sources (book = Brooker, *Introduction to Sensors for Ranging and Imaging*):

- surface clutter area, book §8.13 eqs (8.30)–(8.32) and Figs 8.38–8.39;
- constant-γ clutter and Barton's sea-clutter fit, book §8.12.4 eq (8.29);
- volume backscatter, book §8.14 eqs (8.37)–(8.45); resolution volume and beam-shape factor as
  in the book's air-surveillance example §9.9.3;
- ore-pass wall clutter, book §8.16.6;
- sonar backscatter and reverberation, book §8.15 eqs (8.46)–(8.48) and §12.7 eq (12.59);
  Lambert's law with Mackenzie's μ (Mackenzie 1961, J. Acoust. Soc. Am. 33, 1498);
  surface scattering strength of Chapman & Harris (1962, J. Acoust. Soc. Am. 34, 1592).

The sea-state scales (book Table 12.2, Beaufort force, wave heights) live in
:mod:`diffsense.physics.sea_state`, |K|² in :mod:`diffsense.physics.targets`; their names are
re-exported here.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import logsumexp

from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10, db20, from_db10
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation.dust import dust_volume_backscatter_m2_m3
from diffsense.physics.sea_state import (
    KNOT_M_S,
    SEA_STATE_TABLE_12_2,
    beaufort_from_sea_state,
    beaufort_from_wind_speed,
    sea_state_wave_height_range_m,
    sea_state_wind_speed_knots,
)
from diffsense.physics.targets import (
    dielectric_factor_k_squared,
    extended_target_rcs_m2,
    target_strength_from_cross_section_db,
)

__all__ = [
    "beam_limited_area_m2",
    "pulse_limited_area_m2",
    "surface_clutter_area_m2",
    "constant_gamma_sigma0",
    "sea_clutter_gamma_db",
    "beaufort_from_wind_speed",
    "sea_state_wind_speed_knots",
    "beaufort_from_sea_state",
    "sea_state_wave_height_range_m",
    "surface_clutter_rcs_m2",
    "dielectric_factor_k_squared",
    "rain_reflectivity_factor_mm6_m3",
    "volume_reflectivity_m2_m3",
    "rain_volume_reflectivity_m2_m3",
    "dust_volume_reflectivity_m2_m3",
    "resolution_volume_m3",
    "volume_clutter_rcs_m2",
    "cylinder_wall_area_m2",
    "signal_to_clutter_db",
    "volume_clutter_limited_range_m",
    "lambert_scattering_strength_db",
    "chapman_harris_surface_scattering_strength_db",
    "reverberation_area_m2",
    "reverberation_volume_m3",
    "reverberation_level_db",
    "surface_reverberation_level_db",
    "volume_reverberation_level_db",
    "reflectivity_target_strength_db",
    "KNOT_M_S",
    "SEA_STATE_TABLE_12_2",
    "WATER_K_SQUARED",
]

WATER_K_SQUARED = 0.93
"""|K|² of liquid water at microwave frequencies, the usual weather-radar value."""

_HALF_PI = np.pi / 2.0


# ---------------------------------------------------------------------------------------------
# Surface clutter: illuminated area
# ---------------------------------------------------------------------------------------------


def beam_limited_area_m2(range_m, az_beamwidth_rad, el_beamwidth_rad, grazing_rad, *, elliptical=False):
    """Beam-limited illuminated surface area.

    ``A = R θ_az · R θ_el / sin ψ``, times ``π/4`` when ``elliptical=True`` (the footprint as an
    ellipse with axes ``R θ_az`` and ``R θ_el / sin ψ``, book eq (8.32) ``A = π r1 r2``).
    Applies when the whole footprint lies inside one range cell (book eq (8.31), Fig 8.38).

    Args:
        range_m: slant range R (m), in (0, ∞).
        az_beamwidth_rad: azimuth beamwidth θ_az (rad), in (0, π).
        el_beamwidth_rad: elevation beamwidth θ_el (rad), in (0, π).
        grazing_rad: grazing angle ψ (rad), in (0, π/2].
        elliptical: static flag; True applies the π/4 ellipse factor.

    Exact within the small-beamwidth (flat-footprint) geometry. Source: book §8.13.

    >>> import math
    >>> float(beam_limited_area_m2(1e4, 0.02, 0.05, math.pi / 6)), 1e4**2 * 0.02 * 0.05 / 0.5
    (200000.0, 200000.0)
    """
    w = "beam_limited_area_m2"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("az_beamwidth_rad", az_beamwidth_rad, 0.0, np.pi, lo_open=True, hi_open=True, where=w)
    check_range("el_beamwidth_rad", el_beamwidth_rad, 0.0, np.pi, lo_open=True, hi_open=True, where=w)
    check_range("grazing_rad", grazing_rad, 0.0, _HALF_PI, lo_open=True, where=w)
    area = range_m**2 * az_beamwidth_rad * el_beamwidth_rad / jnp.sin(grazing_rad)
    return area * (np.pi / 4.0) if elliptical else area


def pulse_limited_area_m2(range_m, az_beamwidth_rad, pulse_width_s, grazing_rad, *, speed_m_s=SPEED_OF_LIGHT_M_S):
    """Pulse-limited (range-gate-limited) illuminated surface area.

    ``A = R θ_az · (c τ / 2) · sec ψ``: the azimuth width of the beam times the ground length of
    one range cell (book §8.13, Fig 8.39; the sonar form, eq (8.47), is the same with c the
    speed of sound).

    Args:
        range_m: slant range R (m), in (0, ∞).
        az_beamwidth_rad: azimuth beamwidth θ_az (rad), in (0, π).
        pulse_width_s: pulse width τ (s) (or compressed pulse 1/β), in (0, ∞).
        grazing_rad: grazing angle ψ (rad), in [0, π/2).
        speed_m_s: propagation speed c (m/s), default the speed of light.

    Exact within the small-beamwidth geometry. Source: book §8.13.

    A 1 µs pulse (150 m cell at c = 3e8) at 10 km, 0.02 rad beam, grazing incidence:

    >>> float(pulse_limited_area_m2(1e4, 0.02, 1e-6, 0.0, speed_m_s=3e8)), 1e4 * 0.02 * 150.0
    (30000.0, 30000.0)
    """
    w = "pulse_limited_area_m2"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("az_beamwidth_rad", az_beamwidth_rad, 0.0, np.pi, lo_open=True, hi_open=True, where=w)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=w)
    check_range("grazing_rad", grazing_rad, 0.0, _HALF_PI, hi_open=True, where=w)
    check_range("speed_m_s", speed_m_s, 0.0, None, lo_open=True, where=w)
    return range_m * az_beamwidth_rad * (speed_m_s * pulse_width_s / 2.0) / jnp.cos(grazing_rad)


def surface_clutter_area_m2(
    range_m,
    az_beamwidth_rad,
    el_beamwidth_rad,
    pulse_width_s,
    grazing_rad,
    *,
    elliptical=False,
    sharpness=16.0,
    speed_m_s=SPEED_OF_LIGHT_M_S,
):
    """Illuminated clutter area: the smaller of the beam-limited and pulse-limited areas.

    The cell area is ``min(A_beam, A_pulse)``. With ``sharpness = p`` (static float) the minimum
    is replaced by the smooth p-norm minimum

        ``A = (A_beam^-p + A_pulse^-p)^(-1/p)``

    computed in the log domain. It is differentiable everywhere and never exceeds the exact
    minimum; its relative error is largest where the two areas are equal, where
    ``A / min = 2^(-1/p)``: −10·log10(2)/p dB, i.e. −0.19 dB for the default p = 16, and it falls
    off as ``(1 + r^p)^(-1/p)`` with r the ratio of the smaller to the larger area (below 0.01 dB
    once the two areas differ by 2.2 dB at p = 16). ``sharpness=None`` returns the exact
    ``jnp.minimum`` (gradient of the active branch; undefined at the crossover).

    Args:
        range_m: slant range R (m), in (0, ∞).
        az_beamwidth_rad: azimuth beamwidth (rad), in (0, π).
        el_beamwidth_rad: elevation beamwidth (rad), in (0, π).
        pulse_width_s: pulse width (s), in (0, ∞).
        grazing_rad: grazing angle ψ (rad), in (0, π/2).
        elliptical: apply the π/4 ellipse factor to the beam-limited area.
        sharpness: p of the smooth minimum (≥ 1), or None for the exact minimum.
        speed_m_s: propagation speed (m/s).

    Source: book §8.13 (two geometries, eqs (8.31)–(8.32)).

    Where the two areas are equal the smooth minimum lies 10 log10(2)/16 = 0.19 dB below them:

    >>> import math
    >>> psi = math.atan(1e4 * 0.05 / 150.0)       # R θ_el / sin ψ = (c τ / 2) / cos ψ
    >>> exact = float(surface_clutter_area_m2(1e4, 0.02, 0.05, 1e-6, psi, speed_m_s=3e8, sharpness=None))
    >>> smooth = float(surface_clutter_area_m2(1e4, 0.02, 0.05, 1e-6, psi, speed_m_s=3e8))
    >>> 10 * math.log10(smooth / exact), -10 * math.log10(2) / 16
    (-0.188, -0.188)
    """
    w = "surface_clutter_area_m2"
    check_range("grazing_rad", grazing_rad, 0.0, _HALF_PI, lo_open=True, hi_open=True, where=w)
    if sharpness is not None and not sharpness >= 1.0:
        raise DomainError(f"{w}: argument 'sharpness' must be >= 1 or None; got {sharpness!r}")
    a_beam = beam_limited_area_m2(range_m, az_beamwidth_rad, el_beamwidth_rad, grazing_rad, elliptical=elliptical)
    a_pulse = pulse_limited_area_m2(range_m, az_beamwidth_rad, pulse_width_s, grazing_rad, speed_m_s=speed_m_s)
    if sharpness is None:
        return jnp.minimum(a_beam, a_pulse)
    p = float(sharpness)
    stacked = jnp.stack(jnp.broadcast_arrays(-p * jnp.log(a_beam), -p * jnp.log(a_pulse)), axis=0)
    return jnp.exp(-logsumexp(stacked, axis=0) / p)


def surface_clutter_rcs_m2(sigma0, area_m2):
    """Clutter cross-section ``σ = σ° A`` (book eq (8.30)); the area-extended target RCS of
    :func:`diffsense.physics.targets.extended_target_rcs_m2`.

    Args:
        sigma0: reflectivity σ° (m²/m², linear), in [0, ∞).
        area_m2: illuminated area A (m²), in [0, ∞).
    """
    w = "surface_clutter_rcs_m2"
    check_range("sigma0", sigma0, 0.0, None, where=w)
    check_range("area_m2", area_m2, 0.0, None, where=w)
    return extended_target_rcs_m2(sigma0, area_m2)


# ---------------------------------------------------------------------------------------------
# Surface reflectivity models
# ---------------------------------------------------------------------------------------------


def constant_gamma_sigma0(gamma_db, grazing_rad):
    """Constant-γ clutter reflectivity ``σ° = γ sin ψ`` (linear m²/m²).

    Args:
        gamma_db: γ (dB), in [-80, 20].
        grazing_rad: grazing angle ψ (rad), in [0, π/2].

    The model holds in the plateau region of grazing angles (roughly 1°–60° for land and
    sea); it omits the near-grazing interference region and the near-vertical specular peak.
    Source: book §8.12 (constant-γ model) and §8.12.4.

    >>> import math
    >>> float(constant_gamma_sigma0(-10.0, math.pi / 6))   # 0.1 × sin 30°
    0.05
    """
    w = "constant_gamma_sigma0"
    check_range("gamma_db", gamma_db, -80.0, 20.0, where=w)
    check_range("grazing_rad", grazing_rad, 0.0, _HALF_PI, where=w)
    return from_db10(gamma_db) * jnp.sin(grazing_rad)


def sea_clutter_gamma_db(beaufort, wavelength_m):
    """Barton's sea-clutter γ: ``10 log10 γ = 6 K_B − 10 log10 λ − 64`` (dB).

    Averaged over wind direction. ``K_B`` is the Beaufort wind force (continuous values allowed).

    Args:
        beaufort: Beaufort number K_B, in [0, 12].
        wavelength_m: radar wavelength λ (m), in [1e-3, 1] (the book gives no band limits; this
            spans millimetre waves to UHF, where the fit is used).

    Source: book §8.12.4 eq (8.29), after Barton (1988).

    >>> import math
    >>> float(sea_clutter_gamma_db(4.0, 0.03)), 6 * 4 - 10 * math.log10(0.03) - 64
    (-24.771, -24.771)
    """
    w = "sea_clutter_gamma_db"
    check_range("beaufort", beaufort, 0.0, 12.0, where=w)
    check_range("wavelength_m", wavelength_m, 1e-3, 1.0, where=w)
    return 6.0 * beaufort - db10(wavelength_m) - 64.0


# ---------------------------------------------------------------------------------------------
# Volume clutter
# ---------------------------------------------------------------------------------------------


def rain_reflectivity_factor_mm6_m3(rain_rate_mm_h, a=200.0, b=1.6):
    """Rain reflectivity factor ``Z = a R^b`` (mm⁶/m³); Marshall–Palmer a = 200, b = 1.6.

    Args:
        rain_rate_mm_h: rain rate R (mm/h), in (0, 500].
        a: Z–R coefficient, in (0, ∞).
        b: Z–R exponent, in (0, 5].

    Source: Marshall & Palmer (1948) Z = 200 R^1.6; the book's Z definition eq (8.39).

    >>> float(rain_reflectivity_factor_mm6_m3(1.0)), float(rain_reflectivity_factor_mm6_m3(10.0)), 200 * 10**1.6
    (200.0, 7962.14, 7962.14)
    """
    w = "rain_reflectivity_factor_mm6_m3"
    check_range("rain_rate_mm_h", rain_rate_mm_h, 0.0, 500.0, lo_open=True, where=w)
    check_range("a", a, 0.0, None, lo_open=True, where=w)
    check_range("b", b, 0.0, 5.0, lo_open=True, where=w)
    return a * rain_rate_mm_h**b


def volume_reflectivity_m2_m3(z_mm6_m3, wavelength_m, k_squared=WATER_K_SQUARED):
    """Rayleigh volume reflectivity ``η = π⁵ |K|² Z / λ⁴`` (m²/m³), Z converted to m⁶/m³.

    Args:
        z_mm6_m3: reflectivity factor Z (mm⁶/m³), in [0, ∞).
        wavelength_m: wavelength λ (m), in [1e-3, 10]; the Rayleigh condition 2πa/λ < 1 must
            hold for the scatterers (book §8.14.2).
        k_squared: |K|² (0.93 for water), in (0, 1].

    Source: book eq (8.37).

    >>> import math
    >>> float(volume_reflectivity_m2_m3(200.0, 0.1)), math.pi**5 * 0.93 * 200e-18 / 0.1**4
    (5.69197e-10, 5.69197e-10)
    """
    w = "volume_reflectivity_m2_m3"
    check_range("z_mm6_m3", z_mm6_m3, 0.0, None, where=w)
    check_range("wavelength_m", wavelength_m, 1e-3, 10.0, where=w)
    check_range("k_squared", k_squared, 0.0, 1.0, lo_open=True, where=w)
    return np.pi**5 * k_squared * (z_mm6_m3 * 1e-18) / wavelength_m**4


def rain_volume_reflectivity_m2_m3(rain_rate_mm_h, wavelength_m, a=200.0, b=1.6, k_squared=WATER_K_SQUARED):
    """Rain volume reflectivity η (m²/m³): ``π⁵ |K|² (a R^b · 1e-18) / λ⁴``.

    Args: as :func:`rain_reflectivity_factor_mm6_m3` and :func:`volume_reflectivity_m2_m3`.
    Rayleigh approximation: accurate below ≈ 10 GHz; at millimetre wavelengths Mie scattering by
    the large drops makes the true η differ by several dB.
    """
    z = rain_reflectivity_factor_mm6_m3(rain_rate_mm_h, a, b)
    return volume_reflectivity_m2_m3(z, wavelength_m, k_squared)


def dust_volume_reflectivity_m2_m3(wavelength_m, visibility_m, k_squared):
    """Dust/mist backscatter ``η = π⁵ |K|² · 1.125e-19 / (λ⁴ V^1.07)`` (m²/m³).

    From η = π⁵|K|²Z/λ⁴ with Z = 2.25e-9 V^-1.07 · ΣP_iD_i⁶ / ΣP_ir_i³ and the sandstorm size
    distribution ΣP_ir_i³ = 4e-14 m³, ΣP_iD_i⁶ = 2e-24 m⁶ (Ghobrial & Sharief 1987).

    Args:
        wavelength_m: wavelength λ (m), in [1e-3, 10] (Rayleigh region, 2πa/λ < 1).
        visibility_m: optical visibility V (m), in (0, 1e5].
        k_squared: |K|² of the particle material (rock ≈ 0.34), in (0, 1].

    Source: book §8.14.2 eqs (8.42)–(8.45).
    """
    w = "dust_volume_reflectivity_m2_m3"
    check_range("wavelength_m", wavelength_m, 1e-3, 10.0, where=w)
    check_range("visibility_m", visibility_m, 0.0, 1e5, lo_open=True, where=w)
    check_range("k_squared", k_squared, 0.0, 1.0, lo_open=True, where=w)
    return dust_volume_backscatter_m2_m3(wavelength_m, visibility_m, k_squared)


def resolution_volume_m3(
    range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, *, beam_shape_factor=1.33, speed_m_s=SPEED_OF_LIGHT_M_S
):
    """Radar resolution-cell volume ``V = π R² θ_az θ_el c τ / (8 α²)`` (m³).

    The elliptical beam cross-section π(Rθ_az/2)(Rθ_el/2) times the range cell cτ/2, divided
    by α² for the beam-shape factor α (1.33 in the book: the two-way Gaussian beam fills less
    than its 3 dB cone). This is the convention of the book's air-surveillance rain example
    (§9.9.3): η = 1e-7 m²/m³, 0.02 × 0.07 rad, τ = 2 µs, α = 1.33 gives σ = 1.86e-8 R² m².
    Set ``beam_shape_factor=1`` for the sonar form (book eq (8.48)).

    >>> import math
    >>> closed = math.pi * 1e3**2 * 0.02 * 0.07 * 3e8 * 2e-6 / (8 * 1.33**2)
    >>> float(resolution_volume_m3(1e3, 0.02, 0.07, 2e-6, speed_m_s=3e8)), closed
    (186481.6, 186481.6)

    Args:
        range_m: range R (m), in (0, ∞).
        az_beamwidth_rad, el_beamwidth_rad: 3 dB beamwidths (rad), in (0, π).
        pulse_width_s: pulse width τ (s), in (0, ∞).
        beam_shape_factor: α, in [1, 2].
        speed_m_s: propagation speed c (m/s).
    """
    w = "resolution_volume_m3"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("az_beamwidth_rad", az_beamwidth_rad, 0.0, np.pi, lo_open=True, hi_open=True, where=w)
    check_range("el_beamwidth_rad", el_beamwidth_rad, 0.0, np.pi, lo_open=True, hi_open=True, where=w)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=w)
    check_range("beam_shape_factor", beam_shape_factor, 1.0, 2.0, where=w)
    check_range("speed_m_s", speed_m_s, 0.0, None, lo_open=True, where=w)
    return (
        np.pi * range_m**2 * az_beamwidth_rad * el_beamwidth_rad * speed_m_s * pulse_width_s
        / (8.0 * beam_shape_factor**2)
    )


def volume_clutter_rcs_m2(
    eta_m2_m3,
    range_m,
    az_beamwidth_rad,
    el_beamwidth_rad,
    pulse_width_s,
    *,
    beam_shape_factor=1.33,
    speed_m_s=SPEED_OF_LIGHT_M_S,
):
    """Volume clutter cross-section ``σ = η V`` with V from :func:`resolution_volume_m3` (m²).

    Args:
        eta_m2_m3: volume reflectivity η (m²/m³), in [0, ∞).
        others: as :func:`resolution_volume_m3`.

    Source: book §9.9.3 (σ_clut = 1.86e-8 R² for the air-surveillance radar in heavy rain).

    >>> float(volume_clutter_rcs_m2(1e-7, 1.0, 0.02, 0.07, 2e-6, speed_m_s=3e8))   # book: 1.86e-8 R²
    1.86e-08
    """
    check_range("eta_m2_m3", eta_m2_m3, 0.0, None, where="volume_clutter_rcs_m2")
    vol = resolution_volume_m3(
        range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor=beam_shape_factor, speed_m_s=speed_m_s
    )
    return eta_m2_m3 * vol


def cylinder_wall_area_m2(diameter_m, range_gate_m):
    """Wall area of a cylindrical shaft inside one range gate: ``A = π d ΔR`` (m²).

    The ore-pass clutter area when the beam fills the pass (book §8.16.6: d = 6 m,
    ΔR = 2 m → 37.7 m², 15.8 dBm²).

    >>> float(cylinder_wall_area_m2(6.0, 2.0))
    37.7

    Args:
        diameter_m: shaft diameter d (m), in (0, ∞).
        range_gate_m: range-gate length ΔR (m), in (0, ∞).
    """
    w = "cylinder_wall_area_m2"
    check_range("diameter_m", diameter_m, 0.0, None, lo_open=True, where=w)
    check_range("range_gate_m", range_gate_m, 0.0, None, lo_open=True, where=w)
    return np.pi * diameter_m * range_gate_m


def signal_to_clutter_db(target_rcs_m2, clutter_rcs_m2):
    """Signal-to-clutter ratio ``10 log10(σ_target / σ_clutter)`` (dB).

    Args:
        target_rcs_m2: target RCS (m²), in (0, ∞).
        clutter_rcs_m2: clutter RCS in the same cell (m²), in (0, ∞).

    >>> float(signal_to_clutter_db(1.0, 0.01))
    20.0
    """
    w = "signal_to_clutter_db"
    check_range("target_rcs_m2", target_rcs_m2, 0.0, None, lo_open=True, where=w)
    check_range("clutter_rcs_m2", clutter_rcs_m2, 0.0, None, lo_open=True, where=w)
    return db10(target_rcs_m2) - db10(clutter_rcs_m2)


def volume_clutter_limited_range_m(
    target_rcs_m2,
    required_scr_db,
    eta_m2_m3,
    az_beamwidth_rad,
    el_beamwidth_rad,
    pulse_width_s,
    *,
    beam_shape_factor=1.33,
    speed_m_s=SPEED_OF_LIGHT_M_S,
):
    """Largest range at which the target still exceeds volume clutter by ``required_scr_db``.

    Volume clutter grows as ``σ_clut = K R²`` (K = η V/R²), so SCR(R) = σ_t/(K R²) and

        ``R = sqrt(σ_t / (K · 10^(SCR/10)))``.

    Exact for the model. Book §9.9.3: σ_t = 1 m², K = 1.86e-8 m²/m², SCR 15.2 dB → 1274 m
    (the unrounded K = 1.8648e-8 of c = 3e8 m/s gives 1273 m):

    >>> float(volume_clutter_limited_range_m(1.0, 15.2, 1e-7, 0.02, 0.07, 2e-6, speed_m_s=3e8))
    1.27e3

    Args:
        target_rcs_m2: target RCS (m²), in (0, ∞).
        required_scr_db: required signal-to-clutter ratio (dB), in [-50, 100].
        eta_m2_m3: volume reflectivity (m²/m³), in (0, ∞).
        others: as :func:`resolution_volume_m3`.
    """
    w = "volume_clutter_limited_range_m"
    check_range("target_rcs_m2", target_rcs_m2, 0.0, None, lo_open=True, where=w)
    check_range("required_scr_db", required_scr_db, -50.0, 100.0, where=w)
    check_range("eta_m2_m3", eta_m2_m3, 0.0, None, lo_open=True, where=w)
    k = volume_clutter_rcs_m2(
        eta_m2_m3, 1.0, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor=beam_shape_factor, speed_m_s=speed_m_s
    )
    return jnp.sqrt(target_rcs_m2 / (k * from_db10(required_scr_db)))


# ---------------------------------------------------------------------------------------------
# Sonar backscatter and reverberation
# ---------------------------------------------------------------------------------------------


def lambert_scattering_strength_db(grazing_rad, mu_db=-27.0):
    """Lambert's-law scattering strength ``S = 10 log10 μ + 10 log10 sin² ψ`` (dB re 1 m²).

    Args:
        grazing_rad: grazing angle ψ (rad), in (0, π/2].
        mu_db: 10 log10 μ (dB); Mackenzie (1961) measured −27 dB for the deep-sea bottom at
            530 and 1030 Hz. Domain [-60, 0].

    Source: Mackenzie, K. V. (1961), J. Acoust. Soc. Am. 33, 1498–1504.

    >>> import math
    >>> float(lambert_scattering_strength_db(math.pi / 6)), -27 + 20 * math.log10(0.5)
    (-33.0206, -33.0206)
    """
    w = "lambert_scattering_strength_db"
    check_range("grazing_rad", grazing_rad, 0.0, _HALF_PI, lo_open=True, where=w)
    check_range("mu_db", mu_db, -60.0, 0.0, where=w)
    return mu_db + db20(jnp.sin(grazing_rad))


def chapman_harris_surface_scattering_strength_db(grazing_rad, wind_speed_knots, freq_hz):
    """Chapman–Harris sea-surface scattering strength (dB re 1 m²).

        ``S_s = 3.3 β log10(θ/30) − 42.4 log10 β + 2.6``,  ``β = 158 (v f^(1/3))^(-0.58)``

    with θ the grazing angle in degrees, v the wind speed in knots and f the frequency in Hz.

    Args:
        grazing_rad: grazing angle (rad), in (0, π/3] (measurements up to 60°).
        wind_speed_knots: wind speed v (knots), in (0, 30] (the measured range).
        freq_hz: frequency f (Hz), in [400, 6400] (the measured octave bands).

    An empirical fit to explosive-source measurements (scatter of several dB about the fit).
    Source: Chapman, R. P. & Harris, J. H. (1962), "Surface backscattering strengths measured
    with explosive sound sources", J. Acoust. Soc. Am. 34, 1592–1597.
    """
    w = "chapman_harris_surface_scattering_strength_db"
    check_range("grazing_rad", grazing_rad, 0.0, np.pi / 3.0, lo_open=True, where=w)
    check_range("wind_speed_knots", wind_speed_knots, 0.0, 30.0, lo_open=True, where=w)
    check_range("freq_hz", freq_hz, 400.0, 6400.0, where=w)
    beta = 158.0 * (wind_speed_knots * freq_hz ** (1.0 / 3.0)) ** (-0.58)
    theta_deg = jnp.degrees(grazing_rad)
    return 3.3 * beta * jnp.log10(theta_deg / 30.0) - 42.4 * jnp.log10(beta) + 2.6


def reverberation_area_m2(range_m, az_beamwidth_rad, pulse_width_s, *, speed_m_s=1500.0):
    """Surface/bottom reverberation area of one range cell ``A = (c τ / 2) R θ_az`` (m²).

    The range-gate-limited (low-grazing) form of book eq (8.47). θ_az is the (equivalent)
    horizontal beamwidth.

    Args:
        range_m: range R (m), in (0, ∞).
        az_beamwidth_rad: horizontal beamwidth (rad), in (0, π).
        pulse_width_s: pulse length τ (s), in (0, ∞).
        speed_m_s: sound speed c (m/s), in (0, ∞); default 1500.
    """
    return pulse_limited_area_m2(range_m, az_beamwidth_rad, pulse_width_s, 0.0, speed_m_s=speed_m_s)


def reverberation_volume_m3(range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, *, speed_m_s=1500.0):
    """Volume-reverberation cell ``V = (c τ / 2) · π R² θ_az θ_el / 4`` (m³), book eq (8.48).

    No beam-shape correction, as the book notes for sonar.

    Args: as :func:`resolution_volume_m3`; speed_m_s default 1500 m/s.
    """
    return resolution_volume_m3(
        range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor=1.0, speed_m_s=speed_m_s
    )


def reverberation_level_db(source_level_db, transmission_loss_db, scattering_strength_db, area_or_volume):
    """Reverberation level ``RL = SL − 2 TL + S + 10 log10(A or V)`` (dB re 1 µPa).

    Args:
        source_level_db: SL (dB re 1 µPa at 1 m), in [0, 300].
        transmission_loss_db: one-way TL (dB), in [0, 400].
        scattering_strength_db: S_s, S_b (dB re 1 m²) or S_v (dB re 1 m³), in [-150, 0].
        area_or_volume: reverberating area (m²) or volume (m³), in (0, ∞).

    Source: the sonar equation for reverberation (Urick, *Principles of Underwater Sound*,
    ch. 8); book eqs (8.46)–(8.48) give the target-strength terms S + 10 log10(A or V).
    """
    w = "reverberation_level_db"
    check_range("source_level_db", source_level_db, 0.0, 300.0, where=w)
    check_range("transmission_loss_db", transmission_loss_db, 0.0, 400.0, where=w)
    check_range("scattering_strength_db", scattering_strength_db, -150.0, 0.0, where=w)
    check_range("area_or_volume", area_or_volume, 0.0, None, lo_open=True, where=w)
    return source_level_db - 2.0 * transmission_loss_db + scattering_strength_db + db10(area_or_volume)


def surface_reverberation_level_db(
    source_level_db, transmission_loss_db, scattering_strength_db, range_m, az_beamwidth_rad, pulse_width_s, *, speed_m_s=1500.0
):
    """Surface or bottom reverberation level with ``A = (cτ/2) R θ_az`` (dB re 1 µPa).

    Args: see :func:`reverberation_level_db` and :func:`reverberation_area_m2`.
    """
    area = reverberation_area_m2(range_m, az_beamwidth_rad, pulse_width_s, speed_m_s=speed_m_s)
    return reverberation_level_db(source_level_db, transmission_loss_db, scattering_strength_db, area)


def volume_reverberation_level_db(
    source_level_db,
    transmission_loss_db,
    scattering_strength_db,
    range_m,
    az_beamwidth_rad,
    el_beamwidth_rad,
    pulse_width_s,
    *,
    speed_m_s=1500.0,
):
    """Volume reverberation level with ``V = (cτ/2) π R² θ_az θ_el / 4`` (dB re 1 µPa).

    Args: see :func:`reverberation_level_db` and :func:`reverberation_volume_m3`.
    """
    vol = reverberation_volume_m3(range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, speed_m_s=speed_m_s)
    return reverberation_level_db(source_level_db, transmission_loss_db, scattering_strength_db, vol)


def reflectivity_target_strength_db(sigma0_db, area_m2):
    """Target strength of a patch of reflectivity σ°: ``TS = σ°_dB + 10 log10(A / 4π)`` (dB).

    The book's side-scan bottom echo (§12.7, eq (12.59)): σ = σ°A and TS = 10 log10(σ/4π).
    With S_b = −20 dB, δR = 0.25 m and θ_az = 0.0262 rad, TS = 10 log10 R − 52.8 dB:

    >>> float(reflectivity_target_strength_db(-20.0, 0.25 * 0.0262 * 1.0))   # at R = 1 m
    -52.8

    Args:
        sigma0_db: reflectivity σ° (dB), in [-100, 30].
        area_m2: insonified area (m²), in (0, ∞).
    """
    w = "reflectivity_target_strength_db"
    check_range("sigma0_db", sigma0_db, -100.0, 30.0, where=w)
    check_range("area_m2", area_m2, 0.0, None, lo_open=True, where=w)
    return sigma0_db + target_strength_from_cross_section_db(area_m2)
