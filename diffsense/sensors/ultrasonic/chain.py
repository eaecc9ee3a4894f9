"""The ``"ultrasonic"`` chain: an ultrasonic beacon (one way) or pulse-echo ranging in air, from
the transmitter's SPL to the receiver voltage, SNR, Pd and detection range.

The level relations are in :mod:`.levels`; absorption and sound speed in air are ISO 9613-1
(:func:`diffsense.physics.propagation.acoustic.air_absorption_db_per_m`) or given; the target
strength of a sphere is book eq (12.56) (:mod:`diffsense.physics.targets`). Source: G. Brooker,
*Introduction to Sensors for Ranging and Imaging* (SciTech, 2009), §13.20.
"""

from __future__ import annotations

from typing import Dict

import jax.numpy as jnp

from diffsense.detection.single_pulse import single_pulse_pd, single_pulse_required_snr_db
from diffsense.errors import DomainError
from diffsense.numerics.db import db10, db20, from_db20
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics import noise, targets, waveforms
from diffsense.physics.constants import NOMINAL_AIR_SOUND_SPEED_M_S
from diffsense.physics.propagation import acoustic
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.sensors.ultrasonic.levels import SPL_TO_MICROBAR_DB, spl_at_reference_db

__all__ = ["UltrasonicChain", "receiver_noise_voltage_v", "ambient_noise_voltage_v"]


# ---------------------------------------------------------------------------------------------
# Scene parts
# ---------------------------------------------------------------------------------------------


#: Preamplifier input noise voltage in the band e_n √B (V).
receiver_noise_voltage_v = scene_part("receiver_noise")(noise.voltage_noise_rms_v)


@scene_part("ambient_noise")
def ambient_noise_voltage_v(spectrum_level_db, bandwidth_hz, sensitivity_db_v_per_ubar):
    """Acoustic background noise in the band at the receiver output (V): the band SPL
    N_f + 10 log10 B seen through the µbar sensitivity (unchecked form of
    :func:`diffsense.sensors.ultrasonic.levels.receiver_output_voltage_v`)."""
    band_spl = spectrum_level_db + db10(bandwidth_hz)
    return from_db20(band_spl + sensitivity_db_v_per_ubar + SPL_TO_MICROBAR_DB)


# ---------------------------------------------------------------------------------------------
# The chain
# ---------------------------------------------------------------------------------------------

_NOISE_PARTS = ("receiver_noise", "ambient_noise")
_RANGE_BRACKET_M = (0.01, 1.0e4)


class UltrasonicChain(Chain):
    """Ultrasonic link in air: beacon (one way) or pulse-echo ranging (book §13.20).

    Budget, top to bottom: the transmitter's SPL at its reference distance for the reference
    drive, the drive-level correction 20 log10(V/V0), spreading from the reference distance and
    absorption (ISO 9613-1 or given), for pulse-echo also the target strength and the return
    path from 1 m, giving the SPL at the receiver; then the receiver's µbar sensitivity and the
    20 µPa → µbar conversion, giving the output voltage (dB re 1 V). With a noise part the last
    term is the noise voltage and the budget total is the SNR; without one the total is the
    output level in dB re 1 V.

    Noise parts: ``receiver_noise`` (preamplifier voltage-noise density in the bandwidth) and
    ``ambient_noise`` (acoustic background spectrum level, dB re 20 µPa²/Hz, at the receiver,
    seen through the receiver's sensitivity). With noise the chain gives the SNR, the required
    SNR of one envelope-detected pulse for (pd, pfa) (:func:`diffsense.detection.required_snr_db`),
    Pd, the margin and the detection range (bracket [1 cm, 10 km]).
    """

    kind = "ultrasonic"
    description = "ultrasonic beacon or pulse-echo ranging in air: SPL, transmission loss, receiver voltage, SNR"
    parts = {
        "receiver_noise": "preamplifier input voltage noise",
        "ambient_noise": "acoustic background noise at the receiver (spectrum level, dB re 20 µPa²/Hz)",
    }
    options = {
        "mode": ("one_way", ("one_way", "pulse_echo")),
        "absorption": ("iso9613", ("iso9613", "given")),
        "target": ("given", ("given", "sphere")),
        "swerling": (0, (0, 1, 2, 3, 4)),
    }

    def validate_scene(self, scene) -> None:
        super().validate_scene(scene)
        if self.option(scene, "mode") == "one_way" and any(k == "target" for k, _ in scene.options):
            raise DomainError("ultrasonic scene: option 'target' applies only to mode='pulse_echo'")

    def _has_noise(self, scene):
        return any(scene.has(p) for p in _NOISE_PARTS)

    def parameters(self, scene) -> Dict[str, Param]:
        self.validate_scene(scene)
        ps = [
            Param("range_m", "m", "range R (beacon to receiver, or to the target)", lo=_RANGE_BRACKET_M[0], hi=_RANGE_BRACKET_M[1]),
            Param("freq_hz", "Hz", "operating frequency; muRata MA40S4S/MA40B8R 40 kHz (book §13.20)",
                  default=40e3, lo=1e3, hi=1e6),
            Param("reference_spl_db", "dB", "transmitter SPL at the reference distance for the reference drive, dB re 20 µPa; "
                  "MA40S4S 120 dB (book §13.20)", default=120.0, lo=0.0, hi=200.0),
            Param("reference_range_m", "m", "distance at which the transmitter SPL is specified (book: 0.3 m)",
                  default=0.3, lo=0.0, lo_open=True, hi=10.0),
            Param("reference_drive_voltage_v", "V", "drive voltage of the SPL specification (book: 10 Vpp)",
                  default=10.0, lo=0.0, lo_open=True, hi=1e4),
            Param("drive_voltage_v", "V", "actual drive voltage, same convention (book: 20 Vpp)",
                  default=20.0, lo=0.0, lo_open=True, hi=1e4),
            Param("receive_sensitivity_db", "dB", "receiver sensitivity, dB re 1 V/µbar; MA40B8R −63 dB (book §13.20)",
                  default=-63.0, lo=-200.0, hi=50.0),
            Param("pulse_width_s", "s", "transmitted pulse length (book: 1 ms)", default=1e-3, lo=1e-6, hi=10.0),
        ]
        if self.option(scene, "absorption") == "iso9613":
            ps += [
                Param("temperature_k", "K", "air temperature", default=293.15, lo=253.0, hi=323.0),
                Param("relative_humidity_pct", "percent", "relative humidity (percent)", default=50.0, lo=1.0, hi=100.0),
                Param("pressure_kpa", "kPa", "ambient pressure", default=101.325, lo=50.0, hi=110.0),
            ]
        else:
            ps += [
                Param("absorption_db_per_m", "dB/m", "absorption coefficient α (book §13.20: ≈1.2 dB/m at 40 kHz)",
                      default=1.2, lo=0.0, hi=100.0),
                Param("sound_speed_m_s", "m/s", "speed of sound (book: 340 m/s)", default=NOMINAL_AIR_SOUND_SPEED_M_S,
                      lo=200.0, hi=400.0),
            ]
        if self.option(scene, "mode") == "pulse_echo":
            if self.option(scene, "target") == "given":
                ps.append(Param("target_strength_db", "dB", "target strength TS, dB re 1 m", lo=-100.0, hi=60.0))
            else:
                ps.append(Param("target_radius_m", "m", "radius of a large (ka ≫ 1) sphere", lo=0.0, lo_open=True, hi=100.0))
        if self._has_noise(scene):
            ps += [
                Param("bandwidth_hz", "Hz", "receiver noise bandwidth (matched: 1/pulse length)", default=1e3,
                      lo=0.0, lo_open=True, hi=1e6),
                Param("pd", "1", "required detection probability", default=0.9, lo=0.1, hi=0.999999),
                Param("pfa", "1", "false-alarm probability", default=1e-6, lo=1e-15, hi=0.05),
            ]
        if scene.has("receiver_noise"):
            ps.append(Param("amplifier_noise_density_v_rthz", "V/Hz**0.5", "preamplifier input voltage-noise density",
                            default=10e-9, lo=0.0, lo_open=True, hi=1e-3, part="receiver_noise"))
        if scene.has("ambient_noise"):
            ps.append(Param("ambient_noise_spectrum_level_db", "dB",
                            "acoustic background noise spectrum level at the receiver, dB re 20 µPa²/Hz",
                            lo=-100.0, hi=150.0, part="ambient_noise"))
        return collect(ps)

    def outputs(self, scene) -> Dict[str, Output]:
        self.validate_scene(scene)
        outs = [
            Output("source_spl_db", "dB", "transmitter SPL at the reference distance for the actual drive, dB re 20 µPa"),
            Output("transmission_loss_db", "dB", "one-way transmission loss from the reference distance to range_m"),
            Output("absorption_db_per_m", "dB/m", "absorption coefficient α"),
            Output("sound_speed_m_s", "m/s", "speed of sound"),
            Output("wavelength_m", "m", "acoustic wavelength"),
            Output("received_spl_db", "dB", "SPL at the receiver, dB re 20 µPa"),
            Output("output_level_dbv", "dB", "receiver output, dB re 1 V rms"),
            Output("output_voltage_v", "V", "receiver output voltage (rms)"),
            Output("time_of_flight_s", "s", "propagation time (one way, or out and back for pulse-echo)"),
        ]
        if self.option(scene, "mode") == "pulse_echo":
            outs += [
                Output("target_strength_db", "dB", "target strength TS"),
                Output("range_resolution_m", "m", "range resolution c τ / 2"),
            ]
        if self._has_noise(scene):
            outs += [
                Output("noise_voltage_v", "V", "noise voltage at the receiver output (rms)"),
                Output("snr_db", "dB", "signal-to-noise ratio at range_m"),
                Output("required_snr_db", "dB", "required SNR for (pd, pfa), one pulse"),
                Output("snr_margin_db", "dB", "snr_db − required_snr_db"),
                Output("pd", "1", "detection probability at range_m"),
                Output("detection_range_m", "m", "range where SNR = required SNR (bracket [0.01 m, 10 km])"),
            ]
        return {o.name: o for o in outs}

    def _environment(self, scene, p):
        if self.option(scene, "absorption") == "iso9613":
            alpha = acoustic.air_absorption_db_per_m(p["freq_hz"], p["temperature_k"], p["relative_humidity_pct"], p["pressure_kpa"])
            c = acoustic.sound_speed_humid_air(p["temperature_k"], p["relative_humidity_pct"], p["pressure_kpa"])
        else:
            alpha, c = p["absorption_db_per_m"], p["sound_speed_m_s"]
        env = {"alpha": alpha, "c": c}
        env["source"] = spl_at_reference_db(p["reference_spl_db"], p["drive_voltage_v"], p["reference_drive_voltage_v"])
        if self.option(scene, "mode") == "pulse_echo":
            if self.option(scene, "target") == "given":
                env["ts"] = p["target_strength_db"]
            else:
                env["ts"] = targets.target_strength_sphere_db(p["target_radius_m"])
        noise_v = None
        if scene.has("receiver_noise"):
            noise_v = receiver_noise_voltage_v(p["amplifier_noise_density_v_rthz"], p["bandwidth_hz"])
        if scene.has("ambient_noise"):
            amb = ambient_noise_voltage_v(p["ambient_noise_spectrum_level_db"], p["bandwidth_hz"], p["receive_sensitivity_db"])
            noise_v = amb if noise_v is None else jnp.sqrt(noise_v * noise_v + amb * amb)
        env["noise_v"] = noise_v
        return env

    def _link(self, scene, p, env, r):
        b = BudgetBuilder()
        alpha, r_ref = env["alpha"], p["reference_range_m"]
        b.add("reference_spl", p["reference_spl_db"])
        b.add("drive_level", env["source"] - p["reference_spl_db"])
        out_tl = acoustic.transmission_loss_db(r, alpha, "spherical", r_ref)
        if self.option(scene, "mode") == "one_way":
            b.add("spreading", -(out_tl - alpha * r))
            b.add("absorption", -alpha * r)
        else:
            back_tl = acoustic.transmission_loss_db(r, alpha, "spherical", 1.0)
            b.add("spreading_to_target", -(out_tl - alpha * r))
            b.add("absorption_to_target", -alpha * r)
            b.add("target_strength", env["ts"])
            b.add("spreading_from_target", -(back_tl - alpha * r))
            b.add("absorption_from_target", -alpha * r)
        spl = b.build().total
        b.add("receive_sensitivity", p["receive_sensitivity_db"])
        b.add("pressure_reference_20upa_to_1ubar", SPL_TO_MICROBAR_DB + jnp.zeros_like(spl))
        level_dbv = spl + p["receive_sensitivity_db"] + SPL_TO_MICROBAR_DB
        if env["noise_v"] is not None:
            b.add("noise_voltage", -db20(env["noise_v"]))
        return b.build(), {"tl": out_tl, "spl": spl, "dbv": level_dbv}

    def compute(self, scene, p, wanted=None) -> Evaluation:
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the required-SNR solve, the Pd series and the range root find are traced only when a
        wanted output needs them (see :class:`diffsense.sensors.chain.Chain`)."""
        env = self._environment(scene, p)
        budget, extra = self._link(scene, p, env, p["range_m"])
        echo = self.option(scene, "mode") == "pulse_echo"
        values = {
            "source_spl_db": env["source"],
            "transmission_loss_db": extra["tl"],
            "absorption_db_per_m": env["alpha"],
            "sound_speed_m_s": env["c"],
            "wavelength_m": env["c"] / p["freq_hz"],
            "received_spl_db": extra["spl"],
            "output_level_dbv": extra["dbv"],
            "output_voltage_v": from_db20(extra["dbv"]),
            "time_of_flight_s": (2.0 if echo else 1.0) * p["range_m"] / env["c"],
        }
        if echo:
            values["target_strength_db"] = env["ts"] + jnp.zeros_like(extra["spl"])
            values["range_resolution_m"] = waveforms.range_resolution_pulse_m(p["pulse_width_s"],
                                                                              propagation_speed_m_s=env["c"])
        if env["noise_v"] is not None:
            snr = budget.total
            swerling = self.option(scene, "swerling")
            values.update(noise_voltage_v=env["noise_v"], snr_db=snr)
            if needs(wanted, "required_snr_db", "snr_margin_db", "detection_range_m"):
                required = single_pulse_required_snr_db(p["pd"], p["pfa"], swerling)
                values.update(required_snr_db=required, snr_margin_db=snr - required)
            if needs(wanted, "pd"):
                values["pd"] = single_pulse_pd(snr, p["pfa"], swerling)
            if needs(wanted, "detection_range_m"):
                def residual(r):
                    return self._link(scene, p, env, r)[0].total - required

                values["detection_range_m"] = decreasing_root_log(residual, *_RANGE_BRACKET_M).root
        return Evaluation(budget, values)
