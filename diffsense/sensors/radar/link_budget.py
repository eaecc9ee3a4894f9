"""The radar chain's link-budget stage: antenna, matched-filter mismatch, path attenuation and
multipath, and the signed dB terms whose sum is the single-pulse SNR (Brooker §9.9.1, §8.16.11).

Terms, top to bottom (see :mod:`diffsense.sensors.radar.chain`)::

    peak_power_dbw 10 log10 Pt, transmit_loss_db −L_tx, two_way_gain_db +2 G,
    wavelength_db 10 log10(λ²/(4π)³), rcs_dbsm 10 log10 σ, range_db −40 log10 R,
    scan/matched_filter/cfar/misc losses −L each,
    <part>_attenuation_db −2 α R/1000, multipath_db +40 log10|F|,
    boltzmann_db −10 log10(k T0), bandwidth_db −10 log10 β, noise_figure_db −NF, receive_loss_db −L_rx.

With the option ``noise_input="temperature"`` the line ``noise_figure_db`` becomes
``system_temperature_db`` −10 log10(Ts/T0): N = k Ts β L_rx, identical to the figure form when
Ts = T0 F (Ts = Ta + T0 (F − 1) with Ta = T0; IEEE Std 145-1993, Blake 1986 ch. 4).

The echo leaves the IF filter :func:`received_width_s` wide (half-amplitude width, τ for the ideal
matched filter, :mod:`diffsense.physics.received_pulse`); the range resolution c W/2, the range
gate and the clutter cells follow that width.

The terms that do not depend on range are evaluated once; :class:`Link` evaluates the others at
any range, so the detection-range root finds reuse it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp

from diffsense import detection as _det
from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import DB_PER_NEPER, db10, from_db10
from diffsense.physics import antennas as _ant
from diffsense.physics.measurement_accuracy import folded_range_rate_accuracy_mps
from diffsense.physics.constants import BOLTZMANN_J_K, REFERENCE_TEMPERATURE_K, SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation.free_space import atmospheric_two_way_loss_db
from diffsense.physics.propagation.refraction import radar_horizon_m
from diffsense.physics.received_pulse import received_pulse_width_s
from diffsense.physics.waveforms import duty_cycle, range_resolution_pulse_m, unambiguous_range_m, update_rate_hz
from diffsense.sensors.chain import Budget, BudgetBuilder, needs
from diffsense.sensors.radar import equation as eq
from diffsense.sensors.radar import parts
from diffsense.sensors.radar.loss_models import modelled_losses_db
from diffsense.sensors.radar.structure import option

__all__ = ["Antenna", "antenna", "matched_filter_loss_db", "received_width_s", "specific_attenuations_db_km",
           "check_inside_horizon", "Link", "link_outputs"]

#: −10 log10(k T0) (dBW/Hz): the noise density of the reference temperature, with its sign in the budget.
_BOLTZMANN_TERM_DB = -DB_PER_NEPER * math.log(BOLTZMANN_J_K * REFERENCE_TEMPERATURE_K)


class Antenna(NamedTuple):
    """Antenna gain (dB) and 3 dB beamwidths (rad)."""

    gain_db: jnp.ndarray
    beamwidth_az_rad: jnp.ndarray
    beamwidth_el_rad: jnp.ndarray


def antenna(scene, p, wavelength_m) -> Antenna:
    """Option ``antenna``: a circular aperture (G = 4πρA/λ², A = πd²/4, θ = k λ/d, book eq 5.11),
    a rectangular aperture w wide and h high (G = 4πρ w h/λ², θ_az = k λ/w, θ_el = k λ/h: a fan
    beam when h < w; Skolnik, *Radar Handbook* 3rd ed. ch. 9, Balanis *Antenna Theory* 4th ed.
    §12.5: uniform illumination k = 0.886) or a specified gain and beamwidths."""
    if option(scene, "antenna") == "circular_aperture":
        d = p["antenna_diameter_m"]
        gain_db = db10(_ant.gain_from_aperture(_ant.circular_aperture_area_m2(d), wavelength_m, p["aperture_efficiency"]))
        bw = _ant.beamwidth_rad(wavelength_m, d, p["beamwidth_factor"])
        return Antenna(gain_db, bw, bw)
    if option(scene, "antenna") == "rectangular_aperture":
        w, h = p["aperture_width_m"], p["aperture_height_m"]
        gain_db = db10(_ant.gain_from_aperture(w * h, wavelength_m, p["aperture_efficiency"]))
        k = p["beamwidth_factor"]
        return Antenna(gain_db, _ant.beamwidth_rad(wavelength_m, w, k), _ant.beamwidth_rad(wavelength_m, h, k))
    return Antenna(p["gain_db"], jnp.deg2rad(p["beamwidth_az_deg"]), jnp.deg2rad(p["beamwidth_el_deg"]))


def matched_filter_loss_db(scene, p):
    """Mismatch loss (dB) of the IF filter of option ``matched_filter`` at βτ, or ``None`` for an
    ideal matched filter (book §8.16.9.3)."""
    mf = option(scene, "matched_filter")
    if mf == "matched":
        return None
    bt = p["bandwidth_hz"] * p["pulse_width_s"]
    if is_concrete(bt):
        lo, hi = (0.01, 2.86) if mf == "rectangular" else (0.01, 50.0)
        check_range("bandwidth_hz * pulse_width_s", bt, lo, hi, where=f"radar chain, matched_filter={mf!r}")
    return _det.matched_filter_loss_db(bt, mf)


def received_width_s(scene, p):
    """Half-amplitude width (s) of the echo after the IF filter of option ``matched_filter``
    (:func:`diffsense.physics.received_pulse.received_pulse_width_s`; τ for ``"matched"``)."""
    return received_pulse_width_s(p["pulse_width_s"], p["bandwidth_hz"], option(scene, "matched_filter"))


def _noise_terms(scene, p):
    """The noise lines of the budget: −10 log10(k T0), −10 log10 β, −NF (or −10 log10(Ts/T0)), −L_rx."""
    beta = p["bandwidth_hz"]
    if option(scene, "noise_input") == "temperature":
        receiver = ("system_temperature_db", -db10(p["system_noise_temperature_k"] / REFERENCE_TEMPERATURE_K))
    else:
        receiver = ("noise_figure_db", -p["noise_figure_db"])
    return [
        ("boltzmann_db", _BOLTZMANN_TERM_DB * jnp.ones_like(beta)),
        ("bandwidth_db", -db10(beta)),
        receiver,
        ("receive_loss_db", -p["receive_loss_db"]),
    ]


def specific_attenuations_db_km(scene, p):
    """``{part: one-way specific attenuation (dB/km)}`` of the attenuation parts present
    (independent of range)."""
    alphas = {}
    if scene.has("gas"):
        if option(scene, "gas_model") == "itu_p676":
            alphas["gas"] = parts.gas_itu_attenuation_db_km(p["freq_hz"], p["pressure_hpa"], p["air_temperature_k"],
                                                            p["water_vapour_g_m3"])
        elif option(scene, "gas_model") == "itu_p676_approx":
            alphas["gas"] = parts.gas_itu_approx_attenuation_db_km(p["freq_hz"], p["pressure_hpa"], p["air_temperature_k"],
                                                             p["water_vapour_g_m3"])
        else:
            alphas["gas"] = parts.gas_given_attenuation_db_km(p["gas_attenuation_db_km"])
    if scene.has("rain"):
        if option(scene, "rain_model") == "itu_p838":
            tilt = 0.0 if option(scene, "polarization") == "horizontal" else 90.0
            alphas["rain"] = parts.rain_itu_attenuation_db_km(p["freq_hz"], p["rain_rate_mm_h"], jnp.asarray(tilt))
        else:
            alphas["rain"] = parts.rain_given_attenuation_db_km(p["rain_attenuation_db_km"])
    if scene.has("fog"):
        alphas["fog"] = parts.fog_attenuation_db_km(p["freq_hz"], p["liquid_water_g_m3"], p["air_temperature_k"])
    if scene.has("dust"):
        alphas["dust"] = parts.dust_attenuation_db_km(p["freq_hz"], p["visibility_m"])
    return alphas


def check_inside_horizon(scene, p):
    """With multipath, a concrete ``range_m`` must lie inside the radar horizon (DomainError)."""
    if not scene.has("multipath"):
        return
    r0, ha, ht = p["range_m"], p["antenna_height_m"], p["target_height_m"]
    if not all(is_concrete(x) for x in (r0, ha, ht)):
        return
    with jax.ensure_compile_time_eval():  # concrete inputs: evaluate eagerly even under a trace
        horizon = radar_horizon_m(ha, ht)
        outside = bool(jnp.any(r0 >= horizon))
    if outside:
        raise DomainError("radar chain, multipath: 'range_m' must lie inside the radar horizon "
                          f"d(h_antenna) + d(h_target) = {float(jnp.min(horizon)):.1f} m")


def _multipath_db(scene, p):
    """The two-way multipath term as a function of range, or ``None`` without the part."""
    if not scene.has("multipath"):
        return None
    fn = parts.multipath_horizontal_db if option(scene, "polarization") == "horizontal" else parts.multipath_vertical_db
    return lambda r: fn(r, p["antenna_height_m"], p["target_height_m"], p["freq_hz"], p["sea_state"])


class Link:
    """The budget of one radar scene: the range-independent terms, evaluated once, and the
    range terms as functions of R (m)."""

    def __init__(self, scene, p, wavelength_m, ant: Antenna, need_width: bool = True):
        self.alphas = specific_attenuations_db_km(scene, p)
        self.multipath = _multipath_db(scene, p)
        mf_loss = matched_filter_loss_db(scene, p)
        self._scene, self._p = scene, p
        # the received pulse's width (two root finds) when an output asked for needs it
        self._received_width_s = received_width_s(scene, p) if need_width else None
        self.const_terms = [
            ("peak_power_dbw", db10(p["peak_power_w"])),
            ("transmit_loss_db", -p["transmit_loss_db"]),
            ("two_way_gain_db", 2.0 * ant.gain_db),
            ("wavelength_db", 2.0 * db10(wavelength_m) - eq.FOUR_PI_CUBED_DB),
            ("rcs_dbsm", db10(p["rcs_m2"])),
        ]
        # the declared losses (:mod:`diffsense.sensors.radar.loss_models`), the filter's mismatch
        # after the first (the book's order: scan, matched filter, CFAR, miscellaneous)
        modelled = [(name, -loss) for name, loss in modelled_losses_db(scene, p, option)]
        mismatch = [] if mf_loss is None else [("matched_filter_loss_db", -mf_loss)]
        self.loss_terms = modelled[:1] + mismatch + modelled[1:]
        self.noise_terms = _noise_terms(scene, p)
        self.signal_const = sum(v for _, v in self.const_terms + self.loss_terms)
        #: receiver noise N = k T0 β F L_rx = k Ts β L_rx (dBW)
        self.noise_dbw = -sum(v for _, v in self.noise_terms)

    @property
    def received_width_s(self):
        """Half-amplitude width of the echo after the IF filter (s): range resolution, gates,
        clutter cells; computed with the budget when the chain's wanted outputs need it (else
        computed anew on each use, never kept: a value traced inside a root find must not
        outlive it)."""
        if self._received_width_s is None:
            return received_width_s(self._scene, self._p)
        return self._received_width_s

    @property
    def alpha_total_db_km(self):
        """Sum of the one-way specific attenuations (dB/km), or ``None`` without attenuation parts."""
        return sum(self.alphas.values()) if self.alphas else None

    def range_terms(self, r):
        """The terms that depend on range: spreading, two-way attenuation of each part, multipath."""
        terms = [("range_db", -4.0 * db10(r))]
        for name, a in self.alphas.items():
            terms.append((f"{name}_attenuation_db", -atmospheric_two_way_loss_db(r, a)))
        if self.multipath is not None:
            terms.append(("multipath_db", self.multipath(r)))
        return terms

    def signal_dbw(self, r):
        """Received echo power (dBW) and the multipath term (dB, or ``None``) at range r."""
        terms = self.range_terms(r)
        mp = dict(terms).get("multipath_db")
        return self.signal_const + sum(v for _, v in terms), mp

    def budget(self, r) -> Budget:
        """The named budget at range r, in the book's order; its total is the single-pulse SNR."""
        bb = BudgetBuilder()
        for name, v in self.const_terms:
            bb.add(name, v)
        rterms = dict(self.range_terms(r))
        bb.add("range_db", rterms.pop("range_db"))
        for name, v in self.loss_terms + list(rterms.items()) + self.noise_terms:
            bb.add(name, v)
        return bb.build()


def link_outputs(p, link: Link, ant: Antenna, wavelength_m, snr_db, signal_dbw, wanted=None):
    """The budget's own outputs at ``range_m`` and the waveform's (resolution, ambiguity, timing,
    power), with the IF gain of book §8.16.12; the range resolution (the received pulse's width,
    two root finds) only when ``wanted`` asks for it (:func:`diffsense.sensors.chain.needs`)."""
    tau, prf = p["pulse_width_s"], p["prf_hz"]
    duty = duty_cycle(prf, tau)
    values = {
        "snr_db": snr_db,
        "received_power_dbm": signal_dbw + 30.0,
        "noise_power_dbm": link.noise_dbw + 30.0,
        "wavelength_m": wavelength_m,
        "gain_db": ant.gain_db,
        "beamwidth_deg": jnp.rad2deg(ant.beamwidth_az_rad),
        "beamwidth_el_deg": jnp.rad2deg(ant.beamwidth_el_rad),
        "unambiguous_range_m": unambiguous_range_m(prf),
        "update_rate_hz": update_rate_hz(prf, p["n_pulses"]),
        "duty_cycle": duty,
        "average_power_w": p["peak_power_w"] * duty,
        "eirp_dbw": db10(p["peak_power_w"]) - p["transmit_loss_db"] + ant.gain_db,
        "power_aperture_w_m2": p["peak_power_w"] * duty * from_db10(ant.gain_db) * wavelength_m**2 / (4.0 * math.pi),
        "minimum_range_m": 0.5 * SPEED_OF_LIGHT_M_S * tau,
        "first_blind_speed_mps": 0.5 * wavelength_m * prf,
        "range_rate_accuracy_mps": folded_range_rate_accuracy_mps(snr_db, p["n_pulses"], prf, tau, wavelength_m),
        "if_gain_db": eq.if_gain_required_db(signal_dbw + 30.0, p["receive_loss_db"], p["mixer_loss_db"],
                                             p["rcs_fade_db"], p["tangential_sensitivity_dbm"], p["tss_margin_db"]),
    }
    if needs(wanted, "range_resolution_m"):
        values["range_resolution_m"] = range_resolution_pulse_m(link.received_width_s)
    if link.alphas:
        values["two_way_attenuation_db"] = eq.two_way_attenuation_db(p["range_m"], *link.alphas.values())
    return values
