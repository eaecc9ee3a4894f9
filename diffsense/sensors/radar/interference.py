"""The radar chain's interference stage: clutter in the target's resolution cell and noise jamming.

Clutter parts give the signal-to-clutter ratio ``SCR = 10 log10(σ F⁴ / Σ σ_clutter)`` (dB):
target and clutter share range, antenna gain, losses and path attenuation, which cancel, and
integration does not improve it (book §8.16.6). A noise jammer adds its power J in the receiver
band to the noise N (book §9.10, eq 9.31): ``SJNR = S − 10 log10(N + J)`` (dB). All levels are
evaluated at any range R (m), so the detection-range and burn-through root finds reuse them.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from diffsense.numerics.checks import is_concrete
from diffsense.numerics.db import db10, power_sum_db
from diffsense.physics.sea_clutter import sea_clutter_sigma0_db
from diffsense.physics.waveforms import range_resolution_pulse_m
from diffsense.sensors.chain import needs
from diffsense.sensors.radar import equation as eq
from diffsense.sensors.radar import parts
from diffsense.sensors.radar.link_budget import Antenna, Link
from diffsense.sensors.radar.structure import clutter_parts_present, option

__all__ = ["Interference", "check_sea_clutter_domain"]


def _sea_clutter_part(scene):
    """The sea-clutter part function of options ``sea_clutter_model`` and ``polarization``."""
    if option(scene, "sea_clutter_model") == "constant_gamma":
        return parts.sea_clutter_rcs_constant_gamma_m2
    if option(scene, "polarization") == "vertical":
        return parts.sea_clutter_rcs_nrl_vertical_m2
    return parts.sea_clutter_rcs_nrl_horizontal_m2


def check_sea_clutter_domain(scene, p):
    """With sea clutter and concrete inputs, the sea-clutter model must hold at ``range_m``
    (DomainError otherwise): NRL 0.5-35 GHz, sea state 0-6, grazing up to 60° (any grazing angle
    below, through its ψ⁴ continuation); constant γ grazing 1°-60° (the plateau region)."""
    if not scene.has("sea_clutter"):
        return
    args = (p["range_m"], p["antenna_height_m"], p["freq_hz"], p["sea_state"])
    if not all(is_concrete(x) for x in args):
        return
    with jax.ensure_compile_time_eval():  # concrete inputs: evaluate eagerly even under a trace
        psi = jnp.maximum(eq.sea_grazing_angle_rad(p["range_m"], p["antenna_height_m"]), eq.SEA_GRAZING_FLOOR_RAD)
        sea_clutter_sigma0_db(psi, p["freq_hz"], p["sea_state"], option(scene, "sea_clutter_model"),
                              option(scene, "polarization"))


class Interference:
    """Clutter and jamming of one radar scene, as functions of range R (m)."""

    def __init__(self, scene, p, link: Link, wavelength_m, ant: Antenna):
        self._scene, self._p, self._link, self._lam, self._ant = scene, p, link, wavelength_m, ant
        self.clutter_present = clutter_parts_present(scene)
        self.has_jammer = scene.has("jammer")
        self.self_screening = option(scene, "jammer_type") == "self_screening"

    def jamming_dbw(self, r):
        """Jamming power in the receiver band (dBW) with a target at range r: a self-screening
        jammer rides on the target in the main beam, a stand-off jammer sits at its own range in a
        sidelobe; the one-way path attenuation applies to its range."""
        p, link = self._p, self._link
        if self.self_screening:
            rj, gr = r, self._ant.gain_db
        else:
            rj, gr = p["jammer_range_m"], p["jammer_sidelobe_gain_db"]
        alpha = link.alpha_total_db_km
        att = alpha * rj / 1e3 if alpha is not None else jnp.zeros_like(rj)
        return parts.jamming_power_dbw(p["jammer_power_w"], p["jammer_gain_db"], gr, self._lam, rj,
                                       p["jammer_bandwidth_hz"], p["bandwidth_hz"], att)

    def clutter_rcs_m2(self, r):
        """Total clutter cross-section (m²) in the resolution cell at range r; the cell is as long
        as the echo leaving the IF filter (c W/2, :attr:`Link.received_width_s`)."""
        scene, p, lam = self._scene, self._p, self._lam
        bw_az, bw_el, width = self._ant.beamwidth_az_rad, self._ant.beamwidth_el_rad, self._link.received_width_s
        total = 0.0
        if scene.has("rain_clutter"):
            if option(scene, "rain_clutter_model") == "marshall_palmer":
                total = total + parts.rain_clutter_rcs_marshall_palmer_m2(r, p["rain_rate_mm_h"], lam, bw_az, bw_el, width,
                                                                          p["beam_shape_factor"])
            else:
                total = total + parts.rain_clutter_rcs_given_m2(r, p["rain_reflectivity_m2_m3"], bw_az, bw_el, width,
                                                                p["beam_shape_factor"])
        if scene.has("dust_clutter"):
            total = total + parts.dust_clutter_rcs_m2(r, p["visibility_m"], lam, bw_az, bw_el, width, p["beam_shape_factor"])
        if scene.has("sea_clutter"):
            total = total + _sea_clutter_part(scene)(r, p["antenna_height_m"], bw_az, bw_el, width, lam, p["sea_state"])
        if scene.has("wall_clutter"):
            gate = range_resolution_pulse_m(width)
            if option(scene, "wall_illumination") == "gaussian_beam":
                total = total + parts.wall_clutter_rcs_gaussian_beam_m2(r, p["pass_diameter_m"], gate,
                                                                        p["wall_reflectivity_db"], bw_az,
                                                                        p["sidelobe_level_db"])
            else:
                total = total + parts.wall_clutter_rcs_filled_m2(r, p["pass_diameter_m"], gate, p["wall_reflectivity_db"])
        return total

    def scr_db(self, r, multipath_db):
        """Signal-to-clutter ratio (dB) at range r; ``multipath_db`` (or ``None``) lifts the target only."""
        target = db10(self._p["rcs_m2"])
        if multipath_db is not None:
            target = target + multipath_db
        return target - db10(self.clutter_rcs_m2(r))

    def sjnr_db(self, r, signal_dbw):
        """Signal to jamming-plus-noise ratio (dB) of the echo ``signal_dbw`` at range r (S/N
        without a jammer)."""
        if not self.has_jammer:
            return signal_dbw - self._link.noise_dbw
        return signal_dbw - power_sum_db(self._link.noise_dbw, self.jamming_dbw(r))

    def outputs(self, r0, signal_dbw, multipath_db, required_scr_db, wanted=None):
        """SCR and its margin, S/J, S/(J+N) and S/(N+J+C) at the range ``r0`` (dB), for the
        interference present, as far as ``wanted`` asks for them (the clutter cell follows the
        received pulse's width, two root finds: :func:`diffsense.sensors.chain.needs`)."""
        values = {}
        noise_plus = self._link.noise_dbw
        sinr = needs(wanted, "sinr_db") and (self.has_jammer or self.clutter_present)
        if self.clutter_present and (sinr or needs(wanted, "scr_db", "scr_margin_db")):
            scr0 = self.scr_db(r0, multipath_db)
            values["scr_db"] = scr0
            values["scr_margin_db"] = scr0 - required_scr_db
        if self.has_jammer and (sinr or needs(wanted, "sjr_db", "sjnr_db")):
            j0 = self.jamming_dbw(r0)
            values["sjr_db"] = signal_dbw - j0
            values["sjnr_db"] = self.sjnr_db(r0, signal_dbw)
            noise_plus = power_sum_db(noise_plus, j0)
        if sinr:
            if self.clutter_present:
                noise_plus = power_sum_db(noise_plus, signal_dbw - values["scr_db"])
            values["sinr_db"] = signal_dbw - noise_plus
        return values
