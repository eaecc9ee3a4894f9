"""The ``"sonar"`` chain: active and passive sonar link budgets (book ch. 12; Urick's sonar
equations), from the source level to the signal excess, Pd and detection range.

Equations live beside it: source levels (:mod:`.levels`), the sonar equations (:mod:`.equations`),
detection thresholds (:mod:`.threshold`) and the scene parts (:mod:`.parts`). Physics reused from
the rest of the package: absorption, sound speed and spreading
(:mod:`diffsense.physics.propagation.acoustic`), sea noise (:mod:`diffsense.physics.sea_noise`),
reverberation and scattering strengths (:mod:`diffsense.physics.clutter`), target strengths
(:mod:`diffsense.physics.targets`), directivity (:mod:`diffsense.physics.antennas`), resolutions,
PRF and duty cycle (:mod:`diffsense.physics.waveforms`, with the speed of sound) and the detection
layer (:mod:`diffsense.detection`).

Sources: G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009), ch. 12:
side-scan sonar §12.7-12.8, eqs (12.37)-(12.66), Tables 12.1-12.2; reverberation §8.15, eqs
(8.47)-(8.48). R. J. Urick, *Principles of Underwater Sound*, 3rd ed. (1983), ch. 2 and 12.
"""

from __future__ import annotations

from typing import Dict

import jax.numpy as jnp
import numpy as np

from diffsense.detection.gaussian import gaussian_pd
from diffsense.detection.single_pulse import single_pulse_pd, single_pulse_required_snr_db
from diffsense.errors import DomainError
from diffsense.numerics.db import db10, from_db10, from_db20, increment_db, power_sum_db
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics import antennas, clutter, sea_noise, targets, waveforms
from diffsense.physics.constants import NOMINAL_SEA_SOUND_SPEED_M_S
from diffsense.physics.propagation import acoustic
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.sonar import parts as sonar_parts
from diffsense.sensors.sonar.equations import max_pulse_length_s
from diffsense.sensors.sonar.levels import (
    acoustic_impedance_rayl,
    drive_voltage_rms_v,
    source_level_db,
    source_level_from_tvr_db,
)
from diffsense.sensors.sonar.threshold import detection_index, detection_threshold_energy_db

__all__ = ["SonarChain"]

_DEG = float(np.pi / 180.0)

_NOISE_PARTS = ("sea_noise", "thermal_noise", "receiver_noise")
_AMBIENT_PARTS = ("sea_noise", "thermal_noise")
_REVERB_PARTS = ("surface_reverberation", "bottom_reverberation", "volume_reverberation")
_ACTIVE_ONLY_OPTIONS = ("waveform", "source", "target", "swerling", "surface_scattering", "bottom_scattering")
_RANGE_BRACKET_M = (1.0, 1.0e6)


class SonarChain(Chain):
    """Active and passive sonar link budget (book ch. 12; Urick's sonar equations).

    Active (``mode="active"``)::

        SNR = SL − 2 TL + TS − 10 log10( (NL_amb − DI ⊕ NL_rx) / PG  ⊕  RL )      (⊕: power sum)

    with SL from electrical power, efficiency and directivity (book eqs (12.42)-(12.48)), from
    the TVR and drive voltage (eq (12.51)) or given; TL = 20 log10 R + α R (eq (12.53)) or
    spherical-then-cylindrical; TS of a sphere, given, or of the sea-floor patch (eq (12.59));
    ambient noise band level N_f + 10 log10 B − DI (eq (12.64)); the amplifier's noise referred
    to the water through the receive response (§12.8); reverberation levels from scattering
    strengths (eqs (8.47)-(8.48)); PG = 10 log10(B τ) the pulse-compression gain of a chirp
    (0 dB for a plain pulse, B = 1/τ). The detection threshold is the book's: the required
    single-pulse SNR of an envelope detector for (Pd, Pfa) and the Swerling option
    (:func:`diffsense.sensors.sonar.threshold.detection_threshold_db`). ``signal_excess_db`` = SNR − DT.

    Passive (``mode="passive"``): SNR = SL − TL − (NL_amb − DI ⊕ NL_rx) in the band B, and the
    threshold of an energy detector integrating for t seconds, DT = 5 log10(d / (B t)) with the
    detection index d of (Pd, Pfa) (:func:`diffsense.sensors.sonar.threshold.detection_threshold_energy_db`; Urick's large-Bt form,
    optimistic by 1.1 dB at B t = 100 and 0.34 dB at 1000); Pd from the Gaussian ROC.

    ``detection_range_m`` solves SNR(R) = DT in [1 m, 1000 km] (:func:`diffsense.numerics.rootfind.decreasing_root_log`);
    where SNR stays above (below) DT over the whole bracket it returns the bracket end with zero
    gradient. ``snr_margin_db`` at ``range_m`` is the smooth constraint to use instead.
    """

    kind = "sonar"
    description = "active/passive sonar: source level, transmission loss, target strength, sea noise, reverberation"
    parts = {
        "sea_noise": "wind/wave noise of the sea surface (Knudsen, sea state; book Table 12.2, eq (12.61))",
        "thermal_noise": "molecular thermal noise of the water (Mellen 1952, book eq (9.10))",
        "receiver_noise": "preamplifier voltage noise referred to the water through the receive response",
        "surface_reverberation": "sea-surface reverberation (constant strength or Chapman-Harris)",
        "bottom_reverberation": "sea-floor reverberation (constant strength or Lambert's law)",
        "volume_reverberation": "volume reverberation (scattering strength S_v)",
    }
    options = {
        "mode": ("active", ("active", "passive")),
        "waveform": ("pulse", ("pulse", "chirp")),
        "source": ("power", ("power", "tvr", "level")),
        "target": ("sphere", ("sphere", "given", "seafloor")),
        "swerling": (0, (0, 1, 2, 3, 4)),
        "absorption": ("francois_garrison", ("francois_garrison", "book", "given")),
        "sound_speed": ("given", ("given", "mackenzie")),
        "spreading": ("spherical", ("spherical", "cylindrical")),
        "surface_scattering": ("constant", ("constant", "chapman_harris")),
        "bottom_scattering": ("constant", ("constant", "lambert")),
    }

    # -- structure ------------------------------------------------------------------------

    def validate_scene(self, scene) -> None:
        super().validate_scene(scene)
        mode = self.option(scene, "mode")
        if mode == "passive":
            bad = sorted(p for p in scene.parts if p in _REVERB_PARTS)
            if bad:
                raise DomainError(f"sonar scene: reverberation part(s) {bad} need mode='active'")
            opts = sorted(k for k, _ in scene.options if k in _ACTIVE_ONLY_OPTIONS)
            if opts:
                raise DomainError(f"sonar scene: option(s) {opts} apply only to mode='active'")
            if not any(scene.has(p) for p in _NOISE_PARTS):
                raise DomainError(f"sonar scene (passive): needs at least one noise part of {list(_NOISE_PARTS)}")
        elif not any(scene.has(p) for p in _NOISE_PARTS + _REVERB_PARTS):
            raise DomainError(
                f"sonar scene: needs at least one noise or reverberation part of {list(_NOISE_PARTS + _REVERB_PARTS)}"
            )

    def _freq_domain(self, scene):
        lo, hi = 1.0e3, 1.0e6
        if scene.has("sea_noise"):
            hi = min(hi, 2.0e5)
        if scene.has("surface_reverberation") and self.option(scene, "surface_scattering") == "chapman_harris":
            hi = min(hi, 6400.0)
        return lo, hi

    def parameters(self, scene) -> Dict[str, Param]:
        self.validate_scene(scene)
        active = self.option(scene, "mode") == "active"
        f_lo, f_hi = self._freq_domain(scene)
        ps = [
            Param("range_m", "m", "range to the target R", lo=_RANGE_BRACKET_M[0], hi=_RANGE_BRACKET_M[1]),
            Param("freq_hz", "Hz", "acoustic (centre) frequency", lo=f_lo, hi=f_hi),
            Param("beamwidth_az_deg", "deg", "horizontal (azimuth) 3 dB beamwidth; ITC-5202 1.5° (book Table 12.1)",
                  default=1.5, lo=0.0, hi=180.0, lo_open=True),
            Param("beamwidth_el_deg", "deg", "vertical (elevation) 3 dB beamwidth; ITC-5202 60° (book Table 12.1)",
                  default=60.0, lo=0.0, hi=180.0, lo_open=True),
            Param("receive_sensitivity_db", "dB", "open-circuit receive response M, dB re 1 V/µPa; ITC-5202 −180 dB (book §12.8)",
                  default=-180.0, lo=-300.0, hi=0.0),
            Param("pd", "1", "required detection probability", default=0.9, lo=0.1, hi=0.999999),
            Param("pfa", "1", "false-alarm probability", default=1e-6, lo=1e-15, hi=0.05),
        ]
        mackenzie = self.option(scene, "sound_speed") == "mackenzie"
        absorption = self.option(scene, "absorption")
        if not mackenzie:
            ps.append(Param("sound_speed_m_s", "m/s", "speed of sound in the water; book §12.8: 1522 m/s",
                            default=NOMINAL_SEA_SOUND_SPEED_M_S, lo=1400.0, hi=1650.0))
        needs_water = mackenzie or absorption == "francois_garrison"
        if needs_water:
            ps.append(Param("temperature_c", "degC", "water temperature (°C)", default=5.0, lo=-2.0, hi=30.0))
            ps.append(Param("salinity_ppt", "1", "salinity, parts per thousand",
                            default=35.0, lo=25.0 if mackenzie else 0.0, hi=40.0, lo_open=not mackenzie))
            ps.append(Param("depth_m", "m", "depth of the sound path", default=0.0, lo=0.0,
                            hi=8000.0 if mackenzie else 10000.0))
        if absorption == "francois_garrison":
            ps.append(Param("ph", "1", "pH of the water (Francois-Garrison boric-acid term)", default=8.0, lo=6.0, hi=9.0))
        elif absorption == "given":
            ps.append(Param("absorption_db_per_m", "dB/m", "absorption coefficient α (one way)",
                            default=0.0329, lo=0.0, hi=10.0))
        if self.option(scene, "spreading") == "cylindrical":
            ps.append(Param("transition_range_m", "m", "spherical-to-cylindrical transition range (about the water depth)",
                            default=100.0, lo=1.0, hi=1.0e5))
        if active:
            ps += self._active_parameters(scene)
        else:
            ps += [
                Param("source_level_db", "dB", "target's radiated level in the receiver band, dB re 1 µPa at 1 m",
                      lo=0.0, hi=300.0),
                Param("bandwidth_hz", "Hz", "receiver bandwidth B", default=100.0, lo=0.0, lo_open=True, hi=1.0e6),
                Param("integration_time_s", "s", "energy-detector integration time t", default=1.0,
                      lo=0.0, lo_open=True, hi=1.0e5),
            ]
        if scene.has("sea_noise"):
            ps.append(Param("sea_state", "1", "sea state (book Table 12.2)", default=3.0, lo=0.0, hi=6.0, part="sea_noise"))
        if scene.has("receiver_noise"):
            ps.append(Param("amplifier_noise_density_v_rthz", "V/Hz**0.5",
                            "preamplifier input voltage-noise density; book §12.8: 1.2 nV/√Hz",
                            default=1.2e-9, lo=0.0, lo_open=True, hi=1e-3, part="receiver_noise"))
        return collect(ps)

    def _active_parameters(self, scene):
        ps = [Param("pulse_width_s", "s", "transmitted pulse (or chirp) length τ; book §12.8: 333 µs",
                    default=333e-6, lo=1e-6, hi=10.0),
              Param("max_duty_cycle", "1", "transmitter duty-cycle limit (book §12.8: 5 %)",
                    default=0.05, lo=0.0, lo_open=True, hi=1.0)]
        if self.option(scene, "waveform") == "chirp":
            ps.append(Param("chirp_bandwidth_hz", "Hz", "swept chirp bandwidth Δf; book §12.8: 15 kHz",
                            default=15e3, lo=1.0, hi=1e6))
        source = self.option(scene, "source")
        if source in ("power", "tvr"):
            ps.append(Param("electrical_power_w", "W", "electrical drive power; ITC-5202 1500 W (book Table 12.1)",
                            default=1500.0, lo=0.0, lo_open=True, hi=1e7))
        if source == "power":
            ps.append(Param("efficiency", "1", "electro-acoustic efficiency; ITC-5202 0.4 (book Table 12.1)",
                            default=0.4, lo=0.0, lo_open=True, hi=1.0))
            ps.append(Param("water_density_kg_m3", "kg/m**3", "water density ρ (book §12.8: 1026.4)",
                            default=1026.4, lo=990.0, hi=1050.0))
        elif source == "tvr":
            ps.append(Param("tvr_db", "dB", "transmitting voltage response, dB re 1 µPa/V at 1 m (book: 170 dB)",
                            default=170.0, lo=50.0, hi=300.0))
            ps.append(Param("conductance_s", "S", "transducer input conductance (book: 5.5 mS)",
                            default=5.5e-3, lo=0.0, lo_open=True, hi=100.0))
        else:
            ps.append(Param("source_level_db", "dB", "source level, dB re 1 µPa at 1 m", lo=0.0, hi=300.0))
        target = self.option(scene, "target")
        if target == "sphere":
            ps.append(Param("target_radius_m", "m", "radius of a large (ka ≫ 1) sphere; book §12.8: 0.5 m",
                            default=0.5, lo=0.0, lo_open=True, hi=1e3))
        elif target == "given":
            ps.append(Param("target_strength_db", "dB", "target strength TS, dB re 1 m", lo=-100.0, hi=60.0))
        else:
            ps.append(Param("seafloor_scattering_strength_db", "dB",
                            "bottom scattering strength S_b of the imaged sea floor (book §12.8: −20 dB, pebbles and rock)",
                            default=-20.0, lo=-100.0, hi=0.0))
        return ps + self._reverberation_parameters(scene)

    def _reverberation_parameters(self, scene):
        ps = []
        if scene.has("surface_reverberation"):
            if self.option(scene, "surface_scattering") == "constant":
                ps.append(Param("surface_scattering_strength_db", "dB",
                                "sea-surface scattering strength S_s (book Table 8.9: −45 to −58 dB at sea state 2)",
                                default=-50.0, lo=-150.0, hi=0.0, part="surface_reverberation"))
            else:
                ps.append(Param("wind_speed_knots", "knot", "wind speed for Chapman-Harris", default=10.0,
                                lo=0.0, lo_open=True, hi=30.0, part="surface_reverberation"))
                ps.append(Param("surface_grazing_angle_deg", "deg", "grazing angle at the sea surface",
                                default=10.0, lo=0.0, lo_open=True, hi=60.0, part="surface_reverberation"))
        if scene.has("bottom_reverberation"):
            if self.option(scene, "bottom_scattering") == "constant":
                ps.append(Param("bottom_scattering_strength_db", "dB",
                                "sea-floor scattering strength S_b (book Table 8.9: −24 to −32 dB pebbles and rock)",
                                default=-28.0, lo=-150.0, hi=0.0, part="bottom_reverberation"))
            else:
                ps.append(Param("lambert_mu_db", "dB", "Lambert parameter 10 log10 μ (Mackenzie 1961: −27 dB)",
                                default=-27.0, lo=-60.0, hi=0.0, part="bottom_reverberation"))
                ps.append(Param("bottom_grazing_angle_deg", "deg", "grazing angle at the sea floor",
                                default=10.0, lo=0.0, lo_open=True, hi=90.0, part="bottom_reverberation"))
        if scene.has("volume_reverberation"):
            ps.append(Param("volume_scattering_strength_db", "dB", "volume scattering strength S_v (book §8.15.2: ≈ −80 dB)",
                            default=-80.0, lo=-150.0, hi=0.0, part="volume_reverberation"))
        return ps

    def outputs(self, scene) -> Dict[str, Output]:
        self.validate_scene(scene)
        active = self.option(scene, "mode") == "active"
        has_noise = any(scene.has(p) for p in _NOISE_PARTS)
        outs = [
            Output("source_level_db", "dB", "source level, dB re 1 µPa at 1 m" + ("" if active else " (target, in band)")),
            Output("directivity_index_db", "dB", "directivity index DI = 10 log10(4π/(θ_az θ_el))"),
            Output("sound_speed_m_s", "m/s", "speed of sound used"),
            Output("wavelength_m", "m", "acoustic wavelength c/f"),
            Output("absorption_db_per_m", "dB/m", "absorption coefficient α"),
            Output("transmission_loss_db", "dB", "one-way transmission loss TL at range_m"),
            Output("snr_db", "dB", "signal to noise (plus reverberation) ratio at range_m after matched filtering"),
            Output("required_snr_db", "dB", "detection threshold DT for (pd, pfa) in the receiver band"),
            Output("signal_excess_db", "dB", "signal excess SE = SNR − DT at range_m"),
            Output("snr_margin_db", "dB", "same as signal_excess_db (constraint form)"),
            Output("pd", "1", "detection probability at range_m for pfa"),
            Output("detection_range_m", "m", "range where SNR = DT (bracket [1 m, 1000 km])"),
            Output("bandwidth_hz", "Hz", "receiver (noise) bandwidth"),
            Output("signal_voltage_v", "V", "RMS open-circuit voltage of the echo (signal) at the transducer"),
        ]
        if has_noise:
            outs += [
                Output("noise_level_db", "dB", "noise in the band referred to the water on axis: NL_amb − DI ⊕ NL_rx, dB re 1 µPa"),
                Output("noise_voltage_v", "V", "RMS noise voltage at the transducer output (incl. amplifier noise)"),
            ]
        if any(scene.has(p) for p in _AMBIENT_PARTS):
            outs.append(Output("noise_spectrum_level_db", "dB", "ambient noise spectrum level, dB re 1 µPa²/Hz"))
        if active:
            outs += [
                Output("target_strength_db", "dB", "target strength TS at range_m"),
                Output("echo_level_db", "dB", "echo level EL = SL − 2TL + TS, dB re 1 µPa"),
                Output("processing_gain_db", "dB", "pulse-compression gain 10 log10(B τ)"),
                Output("range_resolution_m", "m", "range resolution c/(2B): cτ/2 (pulse) or c/(2Δf) (chirp)"),
                Output("cross_range_resolution_m", "m", "cross-range resolution R θ_az at range_m"),
                Output("prf_hz", "Hz", "highest unambiguous PRF c/(2 range_m)"),
                Output("duty_cycle", "1", "duty cycle at that PRF (fraction)"),
                Output("max_pulse_length_s", "s", "longest pulse the duty-cycle limit allows at that PRF"),
            ]
            if any(scene.has(p) for p in _REVERB_PARTS):
                outs.append(Output("reverberation_level_db", "dB", "total reverberation level, dB re 1 µPa"))
        else:
            outs.append(Output("detection_index", "1", "detection index d of (pd, pfa), Gaussian ROC"))
        return {o.name: o for o in outs}

    # -- evaluation -----------------------------------------------------------------------

    def _medium(self, scene, p):
        """Sound speed (m/s) and absorption (dB/m) of the water."""
        if self.option(scene, "sound_speed") == "mackenzie":
            c = acoustic.sound_speed_seawater(p["temperature_c"], p["salinity_ppt"], p["depth_m"])
        else:
            c = p["sound_speed_m_s"]
        absorption = self.option(scene, "absorption")
        if absorption == "francois_garrison":
            alpha = acoustic.seawater_absorption_db_per_km(
                p["freq_hz"], p["temperature_c"], p["salinity_ppt"], p["depth_m"], p["ph"]) / 1000.0
        elif absorption == "book":
            alpha = acoustic.seawater_absorption_simple_db_per_m(p["freq_hz"])
        else:
            alpha = p["absorption_db_per_m"]
        return c, alpha

    def _transmit(self, scene, p, env):
        """Active mode: receiver bandwidth, pulse-compression gain and source level into ``env``."""
        tau = p["pulse_width_s"]
        if self.option(scene, "waveform") == "chirp":
            bandwidth = p["chirp_bandwidth_hz"]
            env["pg"] = waveforms.pulse_compression_gain_db(bandwidth, tau)
        else:
            bandwidth = 1.0 / tau
            env["pg"] = jnp.zeros_like(tau)
        env.update(tau=tau, bandwidth=bandwidth)
        source = self.option(scene, "source")
        if source == "power":
            z = acoustic_impedance_rayl(p["water_density_kg_m3"], env["c"])
            env["sl"] = source_level_db(p["electrical_power_w"], p["efficiency"], env["gain"], z)
        elif source == "tvr":
            v = drive_voltage_rms_v(p["electrical_power_w"], p["conductance_s"])
            env["sl"] = source_level_from_tvr_db(p["tvr_db"], v)
        else:
            env["sl"] = p["source_level_db"]

    def _noise(self, scene, p, env):
        """Ambient spectrum and band levels and the amplifier noise level into ``env``."""
        ambient = None
        if scene.has("sea_noise"):
            ambient = sonar_parts.sea_noise_spectrum_level_db(p["sea_state"], p["freq_hz"])
        if scene.has("thermal_noise"):
            th = sonar_parts.thermal_noise_spectrum_level_db(p["freq_hz"])
            ambient = th if ambient is None else power_sum_db(ambient, th)
        env["ambient_spectrum"] = ambient
        if ambient is not None:
            env["ambient_band"] = sea_noise.band_noise_level_db(ambient, env["bandwidth"], env["gain"])
        env["receiver"] = (
            sonar_parts.receiver_noise_level_db(p["amplifier_noise_density_v_rthz"], env["bandwidth"],
                                          p["receive_sensitivity_db"])
            if scene.has("receiver_noise") else None
        )

    def _environment(self, scene, p):
        """Everything that does not depend on the range: medium, beam, source, band and noise."""
        c, alpha = self._medium(scene, p)
        gain = antennas.directivity_from_beamwidths_deg(p["beamwidth_az_deg"], p["beamwidth_el_deg"])
        env = dict(c=c, alpha=alpha, gain=gain, di=antennas.directivity_index_db(gain),
                   az_rad=p["beamwidth_az_deg"] * _DEG, el_rad=p["beamwidth_el_deg"] * _DEG)
        if self.option(scene, "mode") == "active":
            self._transmit(scene, p, env)
        else:
            env.update(bandwidth=p["bandwidth_hz"], sl=p["source_level_db"])
        self._noise(scene, p, env)
        return env

    def _transmission_loss(self, scene, p, env, r):
        spreading = self.option(scene, "spreading")
        kw = {"transition_range_m": p["transition_range_m"]} if spreading == "cylindrical" else {}
        tl = acoustic.transmission_loss_db(r, env["alpha"], spreading, 1.0, **kw)
        absorption = env["alpha"] * r
        return tl, tl - absorption, absorption

    def _target_strength(self, scene, p, env, r):
        target = self.option(scene, "target")
        if target == "sphere":
            return targets.target_strength_sphere_db(p["target_radius_m"])
        if target == "given":
            return p["target_strength_db"]
        # sea-floor patch δR × R θ_az (book eq (12.59))
        cell_m = waveforms.range_resolution_bandwidth_m(env["bandwidth"], propagation_speed_m_s=env["c"])
        return clutter.reflectivity_target_strength_db(p["seafloor_scattering_strength_db"], cell_m * r * env["az_rad"])

    def _scattering_strengths(self, scene, p):
        """Surface and bottom scattering strengths (dB) of the parts the scene holds."""
        s = {}
        if scene.has("surface_reverberation"):
            if self.option(scene, "surface_scattering") == "constant":
                s["surface"] = p["surface_scattering_strength_db"]
            else:
                s["surface"] = sonar_parts.surface_chapman_harris_strength_db(
                    p["surface_grazing_angle_deg"] * _DEG, p["wind_speed_knots"], p["freq_hz"])
        if scene.has("bottom_reverberation"):
            if self.option(scene, "bottom_scattering") == "constant":
                s["bottom"] = p["bottom_scattering_strength_db"]
            else:
                s["bottom"] = sonar_parts.bottom_lambert_strength_db(p["bottom_grazing_angle_deg"] * _DEG, p["lambert_mu_db"])
        return s

    def _reverberation(self, scene, p, env, r, tl):
        """Total reverberation level (dB re 1 µPa) at range ``r``, or None without reverberation parts."""
        levels = []
        tau_eff = 1.0 / env["bandwidth"]  # compressed cell length c/(2B)
        sl, c, az = env["sl"], env["c"], env["az_rad"]
        strengths = self._scattering_strengths(scene, p)
        if "surface" in strengths:
            levels.append(sonar_parts.surface_reverberation_level_db(sl, tl, strengths["surface"], r, az, tau_eff, c))
        if "bottom" in strengths:
            levels.append(sonar_parts.bottom_reverberation_level_db(sl, tl, strengths["bottom"], r, az, tau_eff, c))
        if scene.has("volume_reverberation"):
            levels.append(sonar_parts.volume_reverberation_level_db(sl, tl, p["volume_scattering_strength_db"], r,
                                                              az, env["el_rad"], tau_eff, c))
        if not levels:
            return None
        total = levels[0]
        for lv in levels[1:]:
            total = power_sum_db(total, lv)
        return total

    def _add_noise_terms(self, b, env):
        """Noise terms of the budget, referred to the water on axis, in the band (before
        compression); returns the noise level (dB re 1 µPa) or None."""
        ambient, receiver = env.get("ambient_band"), env["receiver"]
        if ambient is not None:
            b.add("noise_spectrum_level", -env["ambient_spectrum"])
            b.add("noise_bandwidth", -db10(env["bandwidth"]))
            b.add("receive_directivity_index", env["di"])
            if receiver is None:
                return ambient
            b.add("receiver_noise", -increment_db(receiver - ambient))
            return power_sum_db(ambient, receiver)
        if receiver is not None:
            b.add("receiver_noise_level", -receiver)
        return receiver

    def _link(self, scene, p, env, r):
        """Budget at range ``r`` and the intermediate levels."""
        active = self.option(scene, "mode") == "active"
        b = BudgetBuilder()
        tl, spreading, absorption = self._transmission_loss(scene, p, env, r)
        extra = {"tl": tl}
        b.add("source_level", env["sl"])
        if active:
            b.add("two_way_spreading", -2.0 * spreading)
            b.add("two_way_absorption", -2.0 * absorption)
            ts = self._target_strength(scene, p, env, r)
            b.add("target_strength", ts)
            extra.update(ts=ts, signal=env["sl"] - 2.0 * tl + ts)
        else:
            b.add("spreading", -spreading)
            b.add("absorption", -absorption)
            extra["signal"] = env["sl"] - tl
        noise_db = self._add_noise_terms(b, env)
        reverb = self._reverberation(scene, p, env, r, tl) if active else None
        extra.update(noise=noise_db, reverb=reverb)
        if noise_db is not None:
            if active and self.option(scene, "waveform") == "chirp":
                b.add("processing_gain", env["pg"])
            if reverb is not None:
                b.add("reverberation", -increment_db(reverb + env["pg"] - noise_db))
        else:
            b.add("reverberation_level", -reverb)
        return b.build(), extra

    def _detection(self, scene, p, snr, wanted):
        """Required SNR (detection threshold in the band), Pd at ``snr`` and, passive, the
        detection index; a value not needed by ``wanted`` is None."""
        if self.option(scene, "mode") == "active":
            # pd and pfa were checked against their domains (pd >= 0.1 > 0.05 >= pfa) by complete_parameters
            swerling = self.option(scene, "swerling")
            need_required = needs(wanted, "required_snr_db", "signal_excess_db", "snr_margin_db", "detection_range_m")
            required = single_pulse_required_snr_db(p["pd"], p["pfa"], swerling) if need_required else None
            pd_at = single_pulse_pd(snr, p["pfa"], swerling) if needs(wanted, "pd") else None
            return required, pd_at, None
        d_req = detection_index(p["pd"], p["pfa"])
        bt = p["bandwidth_hz"] * p["integration_time_s"]
        required = detection_threshold_energy_db(d_req, p["bandwidth_hz"], p["integration_time_s"]) - db10(p["bandwidth_hz"])
        # achieved index d = (S/N)^2 B t ; sqrt(d) = (S/N) sqrt(Bt)
        root_d = from_db10(jnp.clip(snr, -300.0, 300.0)) * jnp.sqrt(bt)
        return required, gaussian_pd(root_d, p["pfa"]), d_req

    def _active_values(self, p, env, extra, snr):
        """Outputs of the active mode: echo, target strength, resolutions and timing."""
        c, r = env["c"], p["range_m"]
        prf = waveforms.max_prf_hz(r, propagation_speed_m_s=c)
        values = dict(
            target_strength_db=extra["ts"] + jnp.zeros_like(snr),
            echo_level_db=extra["signal"],
            processing_gain_db=env["pg"],
            range_resolution_m=waveforms.range_resolution_bandwidth_m(env["bandwidth"], propagation_speed_m_s=c),
            cross_range_resolution_m=waveforms.real_aperture_cross_range_m(r, env["az_rad"]),
            prf_hz=prf,
            duty_cycle=waveforms.duty_cycle(prf, env["tau"]),
            max_pulse_length_s=max_pulse_length_s(p["max_duty_cycle"], prf),
        )
        if extra["reverb"] is not None:
            values["reverberation_level_db"] = extra["reverb"]
        return values

    def _level_values(self, p, env, extra):
        """Bandwidth, voltages and noise levels at the transducer."""
        m = p["receive_sensitivity_db"]
        # the hydrophone voltage 10^((L + M)/20) unchecked: the level may leave the checked
        # domain of diffsense.physics.sea_noise.hydrophone_voltage_v at extreme ranges
        values = {"bandwidth_hz": env["bandwidth"], "signal_voltage_v": from_db20(extra["signal"] + m)}
        if extra["noise"] is not None:
            values["noise_level_db"] = extra["noise"]
            values["noise_voltage_v"] = from_db20(extra["noise"] + m)
        if env["ambient_spectrum"] is not None:
            values["noise_spectrum_level_db"] = env["ambient_spectrum"]
        return values

    def compute(self, scene, p, wanted=None) -> Evaluation:
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the active detection threshold solve, the Pd series and the range root find are traced
        only when a wanted output needs them (see :class:`diffsense.sensors.chain.Chain`)."""
        env = self._environment(scene, p)
        budget, extra = self._link(scene, p, env, p["range_m"])
        snr = budget.total
        required, pd_at, d_req = self._detection(scene, p, snr, wanted)
        values = {
            "source_level_db": env["sl"],
            "directivity_index_db": env["di"],
            "sound_speed_m_s": env["c"],
            "wavelength_m": env["c"] / p["freq_hz"],
            "absorption_db_per_m": env["alpha"],
            "transmission_loss_db": extra["tl"],
            "snr_db": snr,
        }
        if required is not None:
            values.update(required_snr_db=required, signal_excess_db=snr - required, snr_margin_db=snr - required)
        if pd_at is not None:
            values["pd"] = pd_at
        if needs(wanted, "detection_range_m"):
            def residual(r):
                return self._link(scene, p, env, r)[0].total - required

            values["detection_range_m"] = decreasing_root_log(residual, *_RANGE_BRACKET_M).root
        values.update(self._level_values(p, env, extra))
        if self.option(scene, "mode") == "active":
            values.update(self._active_values(p, env, extra, snr))
        else:
            values["detection_index"] = d_req
        return Evaluation(budget, values)
