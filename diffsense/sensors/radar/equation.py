"""The radar range equation and the radar-specific relations built on it.

Pure ``jax.numpy`` functions of broadcastable arrays, jit/vmap/grad-able, evaluated in the log
domain (sums of ``10 log10`` terms) so that values and gradients stay finite over wide ranges.
Boltzmann's constant and the speed of light are the exact SI values of
:mod:`diffsense.physics.constants`; the book (Brooker) rounds k = 1.38e-23 J/K (0.0021 dB) and
c = 3e8 m/s (0.012 dB per λ²).

Physics that exists elsewhere in the package is reused, not re-implemented: thermal noise and
jamming (:mod:`diffsense.physics.noise`), clutter areas and reflectivities (:mod:`diffsense.physics.clutter`),
dust (:mod:`diffsense.physics.propagation.dust`), sea multipath
(:func:`diffsense.physics.propagation.propagation_factor_db`), root finding
(:func:`diffsense.numerics.rootfind.decreasing_root_log`).

Sources (book = Brooker, *Introduction to Sensors for Ranging and Imaging*, 2009): radar
equation and link budget §9.9.1 (Pr = Pt G² λ² σ / ((4π)³ R⁴ L), N = k T0 β F, Table-style
budget); volume clutter §9.9.3; ore-pass radar §8.16 (wall clutter §8.16.6, IF gain §8.16.12);
noise jamming §9.10 eq (9.31). The energy form and the search-radar (power-aperture) form are in
M. I. Skolnik, *Introduction to Radar Systems*, 3rd ed. (McGraw-Hill, 2001), §2.2 and §2.12.

The waveform relations a radar design also needs (range resolution c τ/2, unambiguous range,
maximum PRF, update rate, hits per scan, pulse-compression gain) live in
:mod:`diffsense.physics.waveforms`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from diffsense.physics import clutter as _clutter
from diffsense.physics import noise as _noise
from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import DB_PER_NEPER, db10, from_db10
from diffsense.physics.constants import BOLTZMANN_J_K, REFERENCE_TEMPERATURE_K, SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation.dust import ROCK_DUST_K_SQUARED
from diffsense.physics.propagation.free_space import atmospheric_two_way_loss_db
from diffsense.physics.propagation.multipath import SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M, propagation_factor_db
from diffsense.physics.propagation.refraction import surface_grazing_angle_rad
from diffsense.physics.sea_clutter import sea_clutter_sigma0
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "snr_db",
    "snr_energy_db",
    "received_power_dbw",
    "received_power_dbm",
    "received_power_w",
    "snr_peak_power_db",
    "search_radar_snr_db",
    "volume_clutter_scr_db",
    "rain_clutter_scr_db",
    "dust_clutter_scr_db",
    "SEA_GRAZING_FLOOR_RAD",
    "sea_grazing_angle_rad",
    "sea_clutter_rcs_m2",
    "sea_clutter_scr_db",
    "wall_illumination_factor",
    "wall_clutter_rcs_m2",
    "wall_clutter_scr_db",
    "jamming_power_w",
    "signal_to_jamming_db",
    "rms_wave_height_m",
    "multipath_factor_db",
    "two_way_attenuation_db",
    "free_space_detection_range_m",
    "detection_range_m",
    "DetectionRange",
    "if_gain_required_db",
    "RANGE_SEARCH_M",
]

#: 10 log10((4π)³), dB.
FOUR_PI_CUBED_DB = 30.0 * math.log10(4.0 * math.pi)
#: Default bracket of the detection-range search (m).
RANGE_SEARCH_M = (1.0, 1.0e7)
_GAIN_DB_RANGE = (-50.0, 100.0)
_LOSS_DB_RANGE = (-50.0, 300.0)


def _f(x):
    return jnp.asarray(x, dtype=jnp.result_type(float, x))


# ---------------------------------------------------------------------------------------------
# Signal-to-noise ratio: energy form (the public contract) and peak-power form (book 9.9.1)
# ---------------------------------------------------------------------------------------------


def snr_db(range_m, peak_power_w, pulse_width_s, wavelength_m, gain_db, rcs_m2=1.0, system_temp_k=290.0, loss_db=0.0):
    """Single-pulse matched-filter SNR of a monostatic radar (dB), energy form.

    ``SNR = Pt τ G² λ² σ / ((4π)³ k Ts R⁴ L)``: the pulse energy Pt τ against the noise
    density k Ts after an ideal matched filter (output SNR E/N0 of the received echo energy).

    Args:
        range_m: target range R (m), (0, ∞).
        peak_power_w: transmitted peak power Pt (W), (0, ∞).
        pulse_width_s: pulse length τ (s), (0, ∞).
        wavelength_m: wavelength λ (m), (0, ∞).
        gain_db: antenna gain G (dB), same antenna on transmit and receive, [-50, 100].
        rcs_m2: target radar cross-section σ (m²), (0, ∞).
        system_temp_k: system noise temperature Ts (K), (0, ∞).
        loss_db: total system loss L (dB), [-50, 300].

    Exact (k = 1.380649e-23 J/K exact SI). Broadcasts over all arguments.
    Source: Skolnik, *Introduction to Radar Systems*, 3rd ed., §2.2 (energy form of the radar
    equation, E/N0 = Pt τ G Ae σ / ((4π)² k Ts R⁴ L) with Ae = G λ²/(4π)); Brooker §9.9.1.

    1 MW for 1 µs, G = 40 dB, λ = 3 cm, σ = 1 m², 290 K, at 10 km, against the formula:

    >>> import math
    >>> float(snr_db(1e4, 1e6, 1e-6, 0.03, 40.0, 1.0, 290.0))
    60.5413
    >>> 10 * math.log10(1e6 * 1e-6 * 1e4**2 * 0.03**2 / ((4 * math.pi)**3 * 1.380649e-23 * 290.0 * 1e4**4))
    60.5413
    """
    w = "radar.snr_db"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("peak_power_w", peak_power_w, 0.0, None, lo_open=True, where=w)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=w)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=w)
    check_range("gain_db", gain_db, *_GAIN_DB_RANGE, where=w)
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where=w)
    check_range("system_temp_k", system_temp_k, 0.0, None, lo_open=True, where=w)
    check_range("loss_db", loss_db, *_LOSS_DB_RANGE, where=w)
    return (
        db10(peak_power_w)
        + db10(pulse_width_s)
        + 2.0 * _f(gain_db)
        + 2.0 * db10(wavelength_m)
        + db10(rcs_m2)
        - FOUR_PI_CUBED_DB
        - DB_PER_NEPER * math.log(BOLTZMANN_J_K)
        - db10(system_temp_k)
        - 4.0 * db10(range_m)
        - _f(loss_db)
    )


def snr_energy_db(range_m, energy_j, wavelength_m, gain_db, rcs_m2=1.0, system_temp_k=290.0, loss_db=0.0):
    """Energy form of the radar equation, ``E G² λ² σ / ((4π)³ k Ts R⁴ L)`` (dB), E in J.

    Identical to :func:`snr_db` with ``E = Pt τ`` (any waveform: a compressed pulse or a coherent
    train of N pulses has E = N Pt τ). Domains as :func:`snr_db`; ``energy_j`` in (0, ∞).
    Source: Skolnik, 3rd ed., §2.2.
    """
    check_range("energy_j", energy_j, 0.0, None, lo_open=True, where="radar.snr_energy_db")
    return snr_db(range_m, energy_j, 1.0, wavelength_m, gain_db, rcs_m2, system_temp_k, loss_db)


def received_power_dbw(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2=1.0, loss_db=0.0):
    """Peak received echo power ``Pr = Pt G² λ² σ / ((4π)³ R⁴ L)`` in dBW.

    Args:
        range_m: R (m), (0, ∞). peak_power_w: Pt (W), (0, ∞). gain_db: G (dB), [-50, 100].
        wavelength_m: λ (m), (0, ∞). rcs_m2: σ (m²), (0, ∞). loss_db: L (dB), [-50, 300].

    Book §9.9.1.2: Pr = 65 + 2×36 − 45.7 + 0 − 4.16 − 40 log10 R = 87.14 − 40 log10 R dBW.
    Exact. The book's radar (5 MW, 2 dB transmit line, 4.16 dB of losses, λ = 0.23 m) at 1 m;
    the book adds terms rounded to 0.1 dB:

    >>> float(received_power_dbw(1.0, 5e6, 36.0, 0.23, 1.0, 2.0 + 4.16))
    87.1
    """
    w = "radar.received_power_dbw"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("peak_power_w", peak_power_w, 0.0, None, lo_open=True, where=w)
    check_range("gain_db", gain_db, *_GAIN_DB_RANGE, where=w)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=w)
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where=w)
    check_range("loss_db", loss_db, *_LOSS_DB_RANGE, where=w)
    return (
        db10(peak_power_w)
        + 2.0 * _f(gain_db)
        + 2.0 * db10(wavelength_m)
        - FOUR_PI_CUBED_DB
        + db10(rcs_m2)
        - 4.0 * db10(range_m)
        - _f(loss_db)
    )


def received_power_dbm(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2=1.0, loss_db=0.0):
    """:func:`received_power_dbw` + 30 (dBm). Book §8.16.11: −59.6 dBm for the ore pass at 300 m."""
    return received_power_dbw(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2, loss_db) + 30.0


def received_power_w(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2=1.0, loss_db=0.0):
    """:func:`received_power_dbw` in watts."""
    return from_db10(received_power_dbw(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2, loss_db))


def snr_peak_power_db(
    range_m,
    peak_power_w,
    gain_db,
    wavelength_m,
    bandwidth_hz,
    noise_figure_db,
    rcs_m2=1.0,
    loss_db=0.0,
    receive_loss_db=0.0,
    temperature_k=REFERENCE_TEMPERATURE_K,
):
    """Peak-power form of the single-pulse SNR, the book's link budget (dB).

    ``SNR = Pr / N``, ``Pr = Pt G² λ² σ / ((4π)³ R⁴ L)``, ``N = k T0 β F · L_rx`` (the receive
    line loss added to the noise figure, book §9.9.1.3). A practical IF filter of bandwidth β is
    charged separately with its mismatch loss (in ``loss_db``), as the book does.

    Args:
        range_m, peak_power_w, gain_db, wavelength_m, rcs_m2, loss_db: as
            :func:`received_power_dbw`.
        bandwidth_hz: receiver noise bandwidth β (Hz), (0, ∞).
        noise_figure_db: receiver noise figure NF (dB), [0, 60].
        receive_loss_db: receive-line loss ahead of the receiver (dB), [0, 60].
        temperature_k: reference temperature T0 (K), default 290.

    Book §9.9.1.3: N = −149 + 4 + 2 = −143 dBW, SNR = 230.1 − 40 log10 R. Exact.
    """
    pr = received_power_dbw(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2, loss_db)
    n = _noise.receiver_noise_power_dbw(bandwidth_hz, noise_figure_db, loss_db=receive_loss_db, temperature_k=temperature_k)
    return pr - n


def search_radar_snr_db(
    range_m, average_power_w, effective_aperture_m2, solid_angle_sr, scan_time_s, rcs_m2=1.0, system_temp_k=290.0, loss_db=0.0
):
    """Search-radar (power-aperture) form of the radar equation (dB).

    ``SNR = Pav Ae σ t_s / (4π Ω k Ts L R⁴)``: a radar of average power Pav and effective
    aperture Ae that searches the solid angle Ω once every t_s seconds collects on a target the
    energy of a dwell t_s Ω_beam/Ω; wavelength and gain cancel.

    Args:
        range_m: R (m), (0, ∞). average_power_w: Pav (W), (0, ∞).
        effective_aperture_m2: Ae (m²), (0, ∞). solid_angle_sr: Ω (sr), (0, 4π].
        scan_time_s: t_s (s), (0, ∞). rcs_m2: σ (m²), (0, ∞).
        system_temp_k: Ts (K), (0, ∞). loss_db: L (dB), [-50, 300].

    Exact. Source: Skolnik, *Introduction to Radar Systems*, 3rd ed., §2.12 (search radar
    equation R⁴ = Pav Ae σ t_s / (4π k T0 F (S/N) L Ω)).
    """
    w = "radar.search_radar_snr_db"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("average_power_w", average_power_w, 0.0, None, lo_open=True, where=w)
    check_range("effective_aperture_m2", effective_aperture_m2, 0.0, None, lo_open=True, where=w)
    check_range("solid_angle_sr", solid_angle_sr, 0.0, 4.0 * math.pi, lo_open=True, where=w)
    check_range("scan_time_s", scan_time_s, 0.0, None, lo_open=True, where=w)
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where=w)
    check_range("system_temp_k", system_temp_k, 0.0, None, lo_open=True, where=w)
    check_range("loss_db", loss_db, *_LOSS_DB_RANGE, where=w)
    return (
        db10(average_power_w)
        + db10(effective_aperture_m2)
        + db10(rcs_m2)
        + db10(scan_time_s)
        - DB_PER_NEPER * math.log(4.0 * math.pi * BOLTZMANN_J_K)
        - db10(solid_angle_sr)
        - db10(system_temp_k)
        - _f(loss_db)
        - 4.0 * db10(range_m)
    )


# ---------------------------------------------------------------------------------------------
# Clutter-limited signal-to-clutter ratios
# ---------------------------------------------------------------------------------------------


def volume_clutter_scr_db(rcs_m2, eta_m2_m3, range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor=1.33):
    """Signal-to-volume-clutter ratio ``10 log10(σ / (η V))`` (dB), V the resolution cell.

    ``V = π R² θ_az θ_el c τ / (8 α²)`` (:func:`diffsense.physics.clutter.resolution_volume_m3`). Target
    and clutter share range, antenna gain and path attenuation, so these cancel.

    Args:
        rcs_m2: target σ (m²), (0, ∞). eta_m2_m3: volume reflectivity η (m²/m³), (0, ∞).
        range_m: R (m), (0, ∞). az_beamwidth_rad, el_beamwidth_rad: 3 dB beamwidths (rad),
        (0, π). pulse_width_s: τ (s), (0, ∞). beam_shape_factor: α, [1, 2] (book 1.33).

    Book §9.9.3: η = 1e-7, 0.02 × 0.07 rad, 2 µs: σ_clut = 1.86e-8 R²; SCR = 15.2 dB at 1274 m:

    >>> float(volume_clutter_scr_db(1.0, 1e-7, 1274.0, 0.02, 0.07, 2e-6))
    15.2
    """
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where="radar.volume_clutter_scr_db")
    check_range("eta_m2_m3", eta_m2_m3, 0.0, None, lo_open=True, where="radar.volume_clutter_scr_db")
    sigma_c = _clutter.volume_clutter_rcs_m2(
        eta_m2_m3, range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor=beam_shape_factor
    )
    return db10(rcs_m2) - db10(sigma_c)


def rain_clutter_scr_db(rcs_m2, rain_rate_mm_h, wavelength_m, range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor=1.33):
    """Signal-to-rain-clutter ratio (dB): :func:`volume_clutter_scr_db` with the Rayleigh rain
    reflectivity η = π⁵ |K|² Z / λ⁴, Z = 200 R^1.6 (Marshall–Palmer; book eqs (8.37), (8.39);
    :func:`diffsense.physics.clutter.rain_volume_reflectivity_m2_m3`). Accurate below ≈ 10 GHz (Rayleigh).

    Args: rain_rate_mm_h (0, 500]; wavelength_m [1e-3, 10]; others as
    :func:`volume_clutter_scr_db`.
    """
    eta = _clutter.rain_volume_reflectivity_m2_m3(rain_rate_mm_h, wavelength_m)
    return volume_clutter_scr_db(rcs_m2, eta, range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor)


def dust_clutter_scr_db(rcs_m2, visibility_m, wavelength_m, range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s,
                        beam_shape_factor=1.33, k_squared=ROCK_DUST_K_SQUARED):
    """Signal-to-dust-clutter ratio (dB): :func:`volume_clutter_scr_db` with the dust backscatter
    η = π⁵ |K|² 1.125e-19 / (λ⁴ V^1.07) (book eq (8.45),
    :func:`diffsense.physics.clutter.dust_volume_reflectivity_m2_m3`; rock dust |K|² = 0.343).

    Args: visibility_m (0, 1e5]; wavelength_m [1e-3, 10]; k_squared (0, 1]; others as
    :func:`volume_clutter_scr_db`.
    """
    eta = _clutter.dust_volume_reflectivity_m2_m3(wavelength_m, visibility_m, k_squared)
    return volume_clutter_scr_db(rcs_m2, eta, range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, beam_shape_factor)


#: Grazing angle (rad) below which the sea surface counts as hidden (beyond the antenna's horizon):
#: the clutter patch is evaluated there, where the NRL model's ψ⁴ continuation is ~120 dB down.
SEA_GRAZING_FLOOR_RAD = 1e-6


def sea_grazing_angle_rad(range_m, antenna_height_m, k_factor=4.0 / 3.0):
    """Grazing angle of the sea surface at slant range R from an antenna at height h (rad).

    ``sin ψ = (d(h)² − R²)/(2 k a R)`` over the effective earth k a (k = 4/3), d(h) the horizon
    distance: the relation of :func:`diffsense.physics.propagation.refraction.surface_grazing_angle_rad`,
    which the two-ray multipath geometry uses at its specular point too. Flat earth would give
    arcsin(h/R); the curvature lowers sin ψ by about R/(2 k a) and brings ψ to 0 at the horizon
    (negative beyond it: the surface is hidden).

    Args: range_m R (m) > antenna_height_m, ≤ 1e7; antenna_height_m h (m), (0, 1e5];
    k_factor: effective-earth factor, [0.5, 10].

    8 m mast, 5 km: 0.0748° (flat earth: 0.0917°):

    >>> import math
    >>> round(math.degrees(float(sea_grazing_angle_rad(5e3, 8.0))), 4)
    0.0748
    """
    w = "radar.sea_grazing_angle_rad"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("antenna_height_m", antenna_height_m, 0.0, None, lo_open=True, where=w)
    if is_concrete(range_m) and is_concrete(antenna_height_m):
        if np.any(np.asarray(range_m, float) <= np.asarray(antenna_height_m, float)):
            raise DomainError(f"{w}: 'range_m' must exceed 'antenna_height_m'")
    return surface_grazing_angle_rad(range_m, antenna_height_m, k_factor)


def sea_clutter_rcs_m2(range_m, antenna_height_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, wavelength_m, sea_state,
                       model="nrl", polarization="horizontal"):
    """Sea-clutter cross-section ``σ_c = σ° A`` (m²) of one resolution cell.

    σ° of :func:`diffsense.physics.sea_clutter.sea_clutter_sigma0` (``model`` ``"nrl"``: the NRL
    model, continued as ψ⁴ below 0.1°; ``"constant_gamma"``: γ sin ψ with Barton's γ, book eq
    (8.29), grazing 1°-60° only), ψ from :func:`sea_grazing_angle_rad` (4/3 earth; beyond the
    antenna's horizon ψ is held at :data:`SEA_GRAZING_FLOOR_RAD`, where the NRL clutter has
    vanished), and A the smooth minimum of the beam- and pulse-limited areas (book §8.13,
    :func:`diffsense.physics.clutter.surface_clutter_area_m2`, ≤ 0.19 dB below the exact minimum
    at the crossover).

    Args: range_m (> antenna height); antenna_height_m (0, ∞); beamwidths (rad) (0, π);
    pulse_width_s: the width of the received echo (s), τ for an ideal matched filter
    (:func:`diffsense.physics.received_pulse.received_pulse_width_s`), (0, ∞);
    wavelength_m (0, ∞) (frequency in the model's domain); sea_state (continuous, see the model);
    model, polarization: static.
    """
    psi = jnp.maximum(sea_grazing_angle_rad(range_m, antenna_height_m), SEA_GRAZING_FLOOR_RAD)
    sigma0 = sea_clutter_sigma0(psi, SPEED_OF_LIGHT_M_S / _f(wavelength_m), sea_state, model, polarization)
    area = _clutter.surface_clutter_area_m2(range_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, psi)
    return sigma0 * area


def sea_clutter_scr_db(rcs_m2, range_m, antenna_height_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, wavelength_m, sea_state,
                       model="nrl", polarization="horizontal"):
    """Signal-to-sea-clutter ratio ``10 log10(σ / σ_c)`` (dB), σ_c from :func:`sea_clutter_rcs_m2`.

    Args: rcs_m2 (0, ∞) and those of :func:`sea_clutter_rcs_m2`.
    """
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where="radar.sea_clutter_scr_db")
    sc = sea_clutter_rcs_m2(range_m, antenna_height_m, az_beamwidth_rad, el_beamwidth_rad, pulse_width_s, wavelength_m, sea_state,
                            model, polarization)
    return db10(rcs_m2) - db10(sc)


def wall_illumination_factor(range_m, pass_diameter_m, beamwidth_rad, sidelobe_level_db=None):
    """Two-way beam weight on the wall of a shaft looked down along its axis (0 ... 1).

    The wall inside a range gate at range R lies at the off-axis angle θ_w = arctan(d / (2R)).
    The one-way power pattern is the Gaussian main lobe g(θ) = exp(−4 ln 2 θ²/θ3²)
    (relative to the peak) resting on a sidelobe floor s (one-way power, relative to the peak):

        ``g(θ) = exp(−4 ln 2 θ²/θ3²) + s (1 − exp(−4 ln 2 θ²/θ3²))``,   ``w = g(θ_w)²``

    (1 on the axis, s² two-way far off it: the wall seen through the sidelobes on transmit and
    receive). The two-way weight is relative to a beam that fills the pass (the book's worst case,
    §8.16.6, Fig. 8.45). Without ``sidelobe_level_db`` (None) the floor is absent and
    w = exp(−8 ln 2 θ_w²/θ3²), which falls without bound as the beam narrows.

    Args: range_m R (m), (0, ∞); pass_diameter_m d (m), (0, ∞); beamwidth_rad θ3 (rad), (0, π);
    sidelobe_level_db: s (dB), [-80, 0], or None.
    Sources: Gaussian main-lobe approximation (e.g. Probert-Jones 1962, Q. J. R. Meteorol. Soc.
    88:485; Doviak & Zrnić, *Doppler Radar and Weather Observations*); the first sidelobe of a
    uniformly illuminated circular aperture is −17.6 dB (the Airy pattern), that of a tapered
    reflector −25 to −30 dB (Skolnik, *Introduction to Radar Systems*, 3rd ed., §9.3).

    A wall one beamwidth off the axis (θ_w = θ3) with a −25 dB floor, against the formula:

    >>> import math
    >>> g = 2 ** -4 + 10 ** -2.5 * (1 - 2 ** -4)
    >>> float(wall_illumination_factor(1.0, 2 * math.tan(0.01), 0.01, -25.0)), g * g
    (0.00428562, 0.00428562)
    """
    w = "radar.wall_illumination_factor"
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("pass_diameter_m", pass_diameter_m, 0.0, None, lo_open=True, where=w)
    check_range("beamwidth_rad", beamwidth_rad, 0.0, math.pi, lo_open=True, hi_open=True, where=w)
    theta_w = jnp.arctan(0.5 * _f(pass_diameter_m) / _f(range_m))
    main = jnp.exp(-4.0 * math.log(2.0) * (theta_w / _f(beamwidth_rad)) ** 2)
    if sidelobe_level_db is None:
        return main * main
    check_range("sidelobe_level_db", sidelobe_level_db, -80.0, 0.0, where=w)
    s = from_db10(sidelobe_level_db)
    g = main + s * (1.0 - main)
    return g * g


def wall_clutter_rcs_m2(pass_diameter_m, range_gate_m, wall_reflectivity_db, illumination=1.0):
    """Wall-clutter cross-section of a cylindrical shaft, ``σ_c = σ°_w π d ΔR · w`` (m²).

    π d ΔR is the wall area inside one range gate (:func:`diffsense.physics.clutter.cylinder_wall_area_m2`)
    and w the beam weight (:func:`wall_illumination_factor`; 1 when the beam fills the pass).

    Args: pass_diameter_m d (m), (0, ∞); range_gate_m ΔR (m), (0, ∞); wall_reflectivity_db σ°_w
    (dB), [-60, 20]; illumination w, (0, 1].
    Book §8.16.6: d = 6 m, ΔR = 2 m, σ° = −10 dB → 15.8 − 10 = 5.8 dBm²:

    >>> from diffsense.numerics.db import db10
    >>> float(db10(wall_clutter_rcs_m2(6.0, 2.0, -10.0)))
    5.8
    """
    check_range("wall_reflectivity_db", wall_reflectivity_db, -60.0, 20.0, where="radar.wall_clutter_rcs_m2")
    check_range("illumination", illumination, 0.0, 1.0, lo_open=True, where="radar.wall_clutter_rcs_m2")
    area = _clutter.cylinder_wall_area_m2(pass_diameter_m, range_gate_m)
    return area * from_db10(wall_reflectivity_db) * _f(illumination)


def wall_clutter_scr_db(rcs_m2, pass_diameter_m, range_gate_m, wall_reflectivity_db, illumination=1.0):
    """Target-to-wall-clutter ratio ``10 log10(σ / σ_c)`` (dB) with σ_c from :func:`wall_clutter_rcs_m2`.

    Book §8.16.6: 11.5 − 5.8 = 5.7 dB when the beam fills the pass (< 13 dB needed):

    >>> from diffsense.numerics.db import from_db10
    >>> float(wall_clutter_scr_db(from_db10(11.5), 6.0, 2.0, -10.0))
    5.7
    """
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where="radar.wall_clutter_scr_db")
    return db10(rcs_m2) - db10(wall_clutter_rcs_m2(pass_diameter_m, range_gate_m, wall_reflectivity_db, illumination))


# ---------------------------------------------------------------------------------------------
# Noise jamming
# ---------------------------------------------------------------------------------------------


def jamming_power_w(jammer_power_w, jammer_gain_db, radar_gain_db, wavelength_m, jammer_range_m, jammer_bandwidth_hz, receiver_bandwidth_hz):
    """Jamming power in the receiver band, ``J = N_j min(β_r, β_j)`` (W).

    N_j = P_j G_j G_r λ² / ((4π)² R_j² β_j) is the jammer noise density at the radar (book eq
    (9.31), :func:`diffsense.physics.noise.jammer_noise_density_w_hz`); the receiver of bandwidth β_r
    passes min(β_r, β_j) of it. Args as that function, plus ``receiver_bandwidth_hz`` β_r (Hz),
    (0, ∞). Exact (the min is the only non-smooth point).
    """
    check_range("receiver_bandwidth_hz", receiver_bandwidth_hz, 0.0, None, lo_open=True, where="radar.jamming_power_w")
    nj = _noise.jammer_noise_density_w_hz(jammer_power_w, jammer_gain_db, radar_gain_db, wavelength_m, jammer_range_m, jammer_bandwidth_hz)
    return nj * jnp.minimum(_f(receiver_bandwidth_hz), _f(jammer_bandwidth_hz))


def signal_to_jamming_db(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2, loss_db, jammer_power_w, jammer_gain_db,
                         jammer_bandwidth_hz, receiver_bandwidth_hz, jammer_range_m=None, radar_gain_toward_jammer_db=None):
    """Signal-to-jamming ratio ``S/J`` (dB) of a noise jammer.

    S from :func:`received_power_dbw`, J from :func:`jamming_power_w`. A self-screening jammer
    (the defaults: ``jammer_range_m = range_m``, radar gain toward it = ``gain_db``) gives
    ``S/J = Pt G σ β_j / (4π P_j G_j β_r R² L)`` for β_r ≤ β_j, which reaches the required ratio
    at the burn-through range of :func:`diffsense.physics.noise.self_screening_burn_through_range_m`.
    A stand-off jammer enters through the sidelobe gain ``radar_gain_toward_jammer_db``.

    Args: as :func:`received_power_dbw` and :func:`jamming_power_w`. Source: book §9.10.
    """
    jr = range_m if jammer_range_m is None else jammer_range_m
    gr = gain_db if radar_gain_toward_jammer_db is None else radar_gain_toward_jammer_db
    s = received_power_dbw(range_m, peak_power_w, gain_db, wavelength_m, rcs_m2, loss_db)
    j = jamming_power_w(jammer_power_w, jammer_gain_db, gr, wavelength_m, jr, jammer_bandwidth_hz, receiver_bandwidth_hz)
    return s - db10(j)


# ---------------------------------------------------------------------------------------------
# Propagation: multipath and atmospheric attenuation
# ---------------------------------------------------------------------------------------------

_SEA_STATES = np.array(sorted(SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M), dtype=float)
_RMS_HEIGHTS = np.array([SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M[int(s)] / 4.0 for s in _SEA_STATES])


def rms_wave_height_m(sea_state):
    """RMS sea-surface height σ_h = H_1/3 / 4 (m) for a continuous sea state in [0, 8].

    Linear interpolation between the integer WMO sea-state codes of
    :data:`diffsense.physics.propagation.multipath.SEA_STATE_SIGNIFICANT_WAVE_HEIGHT_M` (mid-band
    significant wave heights), so that the sea state can be a traced, differentiable parameter.
    Equal to :func:`diffsense.physics.propagation.rms_wave_height_from_sea_state_m` at integers.
    """
    check_range("sea_state", sea_state, 0.0, 8.0, where="radar.rms_wave_height_m")
    return jnp.interp(_f(sea_state), _SEA_STATES, _RMS_HEIGHTS)


def multipath_factor_db(range_m, antenna_height_m, target_height_m, freq_hz, sea_state=3.0, polarization="horizontal"):
    """Two-way sea-multipath propagation factor ``40 log10 |F|`` (dB) with a continuous sea state.

    :func:`diffsense.physics.propagation.propagation_factor_db` (two-ray, curved 4/3 earth, Fresnel
    reflection of sea water, Miller–Brown–Vegh roughness) with the rms wave height from
    :func:`rms_wave_height_m`. Domain: inside the radar horizon, 0.1–100 GHz (see there).
    """
    return propagation_factor_db(range_m, antenna_height_m, target_height_m, freq_hz, polarization=polarization,
                                 rms_wave_height_m=rms_wave_height_m(sea_state))


def two_way_attenuation_db(range_m, *one_way_db_per_km):
    """Two-way path loss ``2 R Σ α_i / 1000`` (dB) for one-way specific attenuations α_i (dB/km)
    of gases, rain, fog, dust... uniform along the path (book §9.9.1.4: 2 α R_km).

    Args: range_m R (m), [0, ∞); each α_i ≥ 0 (dB/km). Exact for a homogeneous path.
    """
    total = sum(_f(a) for a in one_way_db_per_km) if one_way_db_per_km else 0.0
    return atmospheric_two_way_loss_db(range_m, total)


# ---------------------------------------------------------------------------------------------
# Detection range
# ---------------------------------------------------------------------------------------------


class DetectionRange(NamedTuple):
    """``range_m``: the detection range (m); ``found``: True where the SNR crosses the required
    value inside the search bracket (otherwise ``range_m`` is the bracket end)."""

    range_m: jnp.ndarray
    found: jnp.ndarray


def free_space_detection_range_m(snr_at_1m_db, required_snr_db):
    """Free-space detection range ``R = 10^((SNR(1 m) − SNR_req)/40)`` (m).

    SNR(R) = SNR(1 m) − 40 log10 R. Book §9.9.1.4: 10^((230.1 − 8.2)/40) = 352,776.8 m. Exact.
    Args: dB values, any real.

    >>> float(free_space_detection_range_m(230.1, 8.2))
    352776.8
    """
    return from_db10((_f(snr_at_1m_db) - _f(required_snr_db)) / 4.0)


def detection_range_m(snr_at_1m_db, required_snr_db, one_way_attenuation_db_per_km=0.0, *, lo_m=RANGE_SEARCH_M[0], hi_m=RANGE_SEARCH_M[1]):
    """Detection range with uniform attenuation: solves ``SNR(1 m) − 40 log10 R − 2 α R/1000 = SNR_req``.

    The equation is transcendental (book §9.9.1.4, solved there graphically: 320 km for
    0.003 dB/km); here by :func:`diffsense.numerics.rootfind.decreasing_root_log` in [lo_m, hi_m],
    differentiable implicitly in all arguments. Returns :class:`DetectionRange`.

    Args: snr_at_1m_db, required_snr_db (dB); one_way_attenuation_db_per_km α ≥ 0;
    lo_m, hi_m: search bracket (m), 0 < lo_m < hi_m.

    The book's case (0.003 dB/km): the root satisfies the equation, and it is the 320 km the
    book reads off its graph to two figures:

    >>> import math
    >>> r = float(detection_range_m(230.1, 8.2, 0.003).range_m)
    >>> round(230.1 - 40 * math.log10(r) - 2 * 0.003 * r / 1e3, 9)
    8.2
    >>> round(r, -4)
    320000.0
    """
    check_range("one_way_attenuation_db_per_km", one_way_attenuation_db_per_km, 0.0, None, where="radar.detection_range_m")
    s0 = _f(snr_at_1m_db)
    req = _f(required_snr_db)
    alpha = _f(one_way_attenuation_db_per_km)

    def residual(r):
        return s0 - 4.0 * db10(r) - 2.0 * alpha * r / 1e3 - req

    res = decreasing_root_log(residual, lo_m, hi_m)
    return DetectionRange(res.root, res.bracketed)


# ---------------------------------------------------------------------------------------------
# Receiver gain
# ---------------------------------------------------------------------------------------------


def if_gain_required_db(received_power_dbm, receive_loss_db, mixer_loss_db, rcs_fade_db, tangential_sensitivity_dbm, tss_margin_db=13.0):
    """IF gain needed to lift the weakest echo to the detector's working level (dB).

    ``G_IF = (TSS + M) − (Pr − L_rx − L_mixer − fade)``: the lowest signal must sit M dB above the
    detector's tangential sensitivity TSS; the weakest IF signal is the mean received power less
    the receive loss, the mixer conversion loss and the RCS fade depth.

    Args (all dB / dBm, any real): received_power_dbm Pr; receive_loss_db; mixer_loss_db;
    rcs_fade_db; tangential_sensitivity_dbm TSS; tss_margin_db M.
    Book §8.16.12: (−75 + 13) − (−59.6 − 1.2 − 8 − 15) = 21.8 dB. Exact.

    >>> float(if_gain_required_db(-59.6, 1.2, 8.0, 15.0, -75.0, 13.0))
    21.8
    """
    weakest = _f(received_power_dbm) - _f(receive_loss_db) - _f(mixer_loss_db) - _f(rcs_fade_db)
    return _f(tangential_sensitivity_dbm) + _f(tss_margin_db) - weakest
