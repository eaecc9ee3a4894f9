"""Ultrasound in air: transducer SPL, transmission loss, receiver voltage, pulse-echo ranging and
the ``"ultrasonic"`` sensor chain.

Levels in air are sound pressure levels (SPL), dB re 20 µPa. Transducer makers quote the
transmitter's SPL at a reference distance (30 cm for the muRata MA40S4S) for a reference drive
voltage, and the receiver's sensitivity in dB re 1 V/µbar (1 µbar = 0.1 Pa).

Sources
-------
- G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009): §13.20
  (ultrasonic beacon, eqs (13.26)-(13.31)); §8.16.2 (ultrasound rejected for the ore pass:
  beamwidth rule θ = 70 λ/d, absorption); §12.8 (target strength of a sphere, eq (12.56)).
- ISO 9613-1:1993, atmospheric absorption (:func:`diffsense.physics.propagation.acoustic.air_absorption_db_per_m`).
"""

from __future__ import annotations

from typing import Dict

import jax.numpy as jnp
import numpy as np

from diffsense.physics import antennas, noise, targets
from diffsense.errors import DomainError
from diffsense.numerics.checks import check_range
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.detection.single_pulse import single_pulse_pd, single_pulse_required_snr_db
from diffsense.physics.propagation import acoustic
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "AIR_REFERENCE_PRESSURE_PA",
    "MICROBAR_PA",
    "spl_at_reference_db",
    "receiver_output_voltage_v",
    "receiver_output_level_dbv",
    "one_way_received_spl_db",
    "pulse_echo_received_spl_db",
    "max_wavelength_for_beamwidth_book_m",
    "min_frequency_for_beamwidth_book_hz",
    "UltrasonicChain",
]

AIR_REFERENCE_PRESSURE_PA = 20e-6
"""Reference pressure of SPL in air, 20 µPa (book eq (13.26))."""

MICROBAR_PA = 0.1
"""1 µbar = 0.1 Pa (book §13.20)."""

_LN10 = float(np.log(10.0))
#: 20 log10(20 µPa / 1 µbar) = 20 log10(2e-4) = −73.98 dB (the book's "−74").
_SPL_TO_MICROBAR_DB = 20.0 * float(np.log10(AIR_REFERENCE_PRESSURE_PA / MICROBAR_PA))


def _db20(x):
    return (20.0 / _LN10) * jnp.log(x)


def spl_at_reference_db(reference_spl_db, drive_voltage_v, reference_drive_voltage_v):
    """Transmitter SPL at its reference distance for a drive voltage ``L = L0 + 20 log10(V / V0)`` (dB re 20 µPa).

    Pressure is proportional to drive voltage in a linear transducer, so SPL scales as the
    square of V (book §13.20: MA40S4S 120 dB at 30 cm for 10 Vpp, driven at 20 Vpp → 126 dB).
    V and V0 in the same convention (both peak-to-peak or both RMS). Exact while the transducer
    stays linear (below its rated maximum drive).

    Args:
        reference_spl_db: L0, SPL at the reference distance for V0 (dB re 20 µPa), in [0, 250].
        drive_voltage_v: drive voltage V (V), in (0, ∞).
        reference_drive_voltage_v: V0 (V), in (0, ∞).
    """
    w = "spl_at_reference_db"
    check_range("reference_spl_db", reference_spl_db, 0.0, 250.0, where=w)
    check_range("drive_voltage_v", drive_voltage_v, 0.0, None, lo_open=True, where=w)
    check_range("reference_drive_voltage_v", reference_drive_voltage_v, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(reference_spl_db) + _db20(jnp.asarray(drive_voltage_v) / jnp.asarray(reference_drive_voltage_v))


def receiver_output_level_dbv(spl_db, sensitivity_db_v_per_ubar):
    """Receiver output ``20 log10 V = L + M + 20 log10(20 µPa / 1 µbar)`` (dB re 1 V).

    The SPL L (re 20 µPa) is converted to µbar (20 µPa = 2e-4 µbar, −73.98 dB) and multiplied
    by the sensitivity M (dB re 1 V/µbar). Book §13.20: 102.4 − 63 − 74 → 18.6 mV. Exact.

    Args:
        spl_db: SPL at the receiver (dB re 20 µPa), in [-100, 250].
        sensitivity_db_v_per_ubar: M (dB re 1 V/µbar), in [-200, 50].
    """
    w = "receiver_output_level_dbv"
    check_range("spl_db", spl_db, -100.0, 250.0, where=w)
    check_range("sensitivity_db_v_per_ubar", sensitivity_db_v_per_ubar, -200.0, 50.0, where=w)
    return jnp.asarray(spl_db) + jnp.asarray(sensitivity_db_v_per_ubar) + _SPL_TO_MICROBAR_DB


def receiver_output_voltage_v(spl_db, sensitivity_db_v_per_ubar):
    """RMS receiver output voltage (V) for an SPL and a µbar sensitivity; see :func:`receiver_output_level_dbv`."""
    return 10.0 ** (receiver_output_level_dbv(spl_db, sensitivity_db_v_per_ubar) / 20.0)


def one_way_received_spl_db(source_spl_db, range_m, absorption_db_per_m, reference_range_m=0.3):
    """SPL at a receiver ``L_r = L_p − [20 log10(R / R_ref) + α R]`` (dB re 20 µPa), book eqs (13.30)-(13.31).

    Spherical spreading from the reference distance of the source level plus absorption over the
    whole path (the book's form). 126 dB at 0.3 m, 3 m, 1.2 dB/m → 102.4 dB. Exact for spherical
    spreading in a homogeneous medium in the far field.

    Args:
        source_spl_db: SPL at the reference distance (dB re 20 µPa), in [0, 250].
        range_m: R (m), in (0, ∞).
        absorption_db_per_m: α (dB/m), in [0, ∞).
        reference_range_m: R_ref (m), in (0, ∞).
    """
    check_range("source_spl_db", source_spl_db, 0.0, 250.0, where="one_way_received_spl_db")
    tl = acoustic.transmission_loss_db(range_m, absorption_db_per_m, "spherical", reference_range_m)
    return jnp.asarray(source_spl_db) - tl


def pulse_echo_received_spl_db(source_spl_db, range_m, absorption_db_per_m, target_strength_db, reference_range_m=0.3):
    """Echo SPL back at a co-located receiver (dB re 20 µPa).

    ``L_e = L_p − [20 log10(R/R_ref) + α R] + TS − [20 log10(R / 1 m) + α R]``: the incident
    level at the target, plus the target strength TS (dB re 1 m: the echo level 1 m from the
    target relative to the incident level, book eq (12.54)), spread back from 1 m to R.

    Args:
        source_spl_db: SPL at the reference distance (dB re 20 µPa), in [0, 250].
        range_m: target range R (m), in (0, ∞).
        absorption_db_per_m: α (dB/m), in [0, ∞).
        target_strength_db: TS (dB re 1 m), in [-150, 60].
        reference_range_m: R_ref (m), in (0, ∞).
    """
    check_range("target_strength_db", target_strength_db, -150.0, 60.0, where="pulse_echo_received_spl_db")
    incident = one_way_received_spl_db(source_spl_db, range_m, absorption_db_per_m, reference_range_m)
    back = acoustic.transmission_loss_db(range_m, absorption_db_per_m, "spherical", 1.0)
    return incident + jnp.asarray(target_strength_db) - back


def max_wavelength_for_beamwidth_book_m(diameter_m, beamwidth_deg):
    """Longest wavelength giving a beamwidth with an aperture, by the book's rule ``λ = θ d / 70`` (m).

    Inverse of :func:`diffsense.physics.antennas.beamwidth_book_deg` (θ_deg = 70 λ/d, a moderately
    tapered circular aperture). Book §8.16.2: d = 1 m, θ = 1.1° → 0.016 m. Accuracy that of the
    rule (the uniform circular aperture has 58.9 λ/d).

    Args:
        diameter_m: aperture diameter d (m), in (0, ∞).
        beamwidth_deg: required 3 dB beamwidth θ (degrees), in (0, 180].
    """
    w = "max_wavelength_for_beamwidth_book_m"
    check_range("diameter_m", diameter_m, 0.0, None, lo_open=True, where=w)
    check_range("beamwidth_deg", beamwidth_deg, 0.0, 180.0, lo_open=True, where=w)
    return jnp.asarray(beamwidth_deg) * jnp.asarray(diameter_m) / antennas.BOOK_CIRCULAR_BEAMWIDTH_DEG_FACTOR


def min_frequency_for_beamwidth_book_hz(diameter_m, beamwidth_deg, sound_speed_m_s=340.0):
    """Lowest frequency giving a beamwidth with an aperture ``f = 70 c / (θ d)`` (Hz).

    Book §8.16.2: 1 m transducer, 1.1°, 340 m/s → 21.6 kHz.

    Args:
        diameter_m: aperture diameter d (m), in (0, ∞).
        beamwidth_deg: 3 dB beamwidth θ (degrees), in (0, 180].
        sound_speed_m_s: c (m/s), in (0, ∞).
    """
    check_range("sound_speed_m_s", sound_speed_m_s, 0.0, None, lo_open=True, where="min_frequency_for_beamwidth_book_hz")
    return jnp.asarray(sound_speed_m_s) / max_wavelength_for_beamwidth_book_m(diameter_m, beamwidth_deg)


# ---------------------------------------------------------------------------------------------
# Scene parts and detection helper
# ---------------------------------------------------------------------------------------------


@scene_part("receiver_noise")
def receiver_noise_voltage_v(noise_density_v_rthz, bandwidth_hz):
    """Preamplifier input noise voltage in the band e_n √B (V)."""
    return noise.voltage_noise_rms_v(noise_density_v_rthz, bandwidth_hz)


@scene_part("ambient_noise")
def ambient_noise_voltage_v(spectrum_level_db, bandwidth_hz, sensitivity_db_v_per_ubar):
    """Acoustic background noise in the band at the receiver output (V)."""
    band_spl = spectrum_level_db + (10.0 / _LN10) * jnp.log(bandwidth_hz)
    return 10.0 ** ((band_spl + sensitivity_db_v_per_ubar + _SPL_TO_MICROBAR_DB) / 20.0)


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
                Param("sound_speed_m_s", "m/s", "speed of sound (book: 340 m/s)", default=340.0, lo=200.0, hi=400.0),
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
        b.add("pressure_reference_20upa_to_1ubar", _SPL_TO_MICROBAR_DB + jnp.zeros_like(spl))
        level_dbv = spl + p["receive_sensitivity_db"] + _SPL_TO_MICROBAR_DB
        if env["noise_v"] is not None:
            b.add("noise_voltage", -_db20(env["noise_v"]))
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
            "output_voltage_v": 10.0 ** (extra["dbv"] / 20.0),
            "time_of_flight_s": (2.0 if echo else 1.0) * p["range_m"] / env["c"],
        }
        if echo:
            values["target_strength_db"] = env["ts"] + jnp.zeros_like(extra["spl"])
            values["range_resolution_m"] = env["c"] * p["pulse_width_s"] / 2.0
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
