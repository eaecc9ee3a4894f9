"""The FMCW radar chain (kind ``"fmcw"``): a linear-FM continuous-wave radar with FFT range
processing, after Brooker §11.7 and the 94 GHz seeker of §11.12.4.

Waveform (pure relations of :mod:`diffsense.physics.waveforms`, book §11.7):

* beat frequency f_b = (Δf / T_b)(2R / c) (eq 11.22; 300 MHz, 500 µs, 1 km → 4 MHz), Doppler
  f_d = 2v/λ (eq 10.7), highest beat f_b + |f_d| (triangular sweep, §11.12.4.2);
* sampling: a real ADC (option ``sampling="real"``) holds beats below f_s/2, an I/Q (complex)
  ADC below f_s; the Nyquist margin is f_s/2 − (f_b + |f_d|) (or f_s − ...), the oversampling
  ratio f_s / (f_b + |f_d|) (the book asks 2.5, §11.12.4.2), and the maximum instrumented range,
  where the beat reaches the Nyquist frequency, R_max = f_s c T_b / (4Δf) (real) or
  f_s c T_b / (2Δf) (complex);
* range resolution c / (2Δf) (eq 11.25; 300 MHz → 0.5 m), FFT bin width f_s/N, range bin
  c T_b (f_s/N) / (2Δf) (eq 11.24), the FFT's span N/f_s ≤ T_b (``sweep_fill`` ≤ 1);
* range-Doppler coupling Δr = f_d T_b c / (2Δf) (eq 11.26: the Doppler shift read as range);
  Doppler resolution 1/(M T_b) and velocity resolution λ/(2 M T_b) over M coherent sweeps.

Link budget (the radar equation of a CW radar in the FFT bin, book §11.12.4.8; the FFT's
processing gain is the narrow bin): every term a signed dB contribution, total = ``snr_db``::

    transmit_power_dbw     10 log10 P_t
    transmit_loss_db       −L_tx
    two_way_gain_db        +2 G                  (G = 4πρA/λ², one antenna, as the radar chain)
    wavelength_db          10 log10(λ² / (4π)³)
    rcs_dbsm               10 log10 σ
    range_db               −40 log10 R
    misc_loss_db           −L_misc
    gas/rain_attenuation_db  −2 α R / 1000        (parts present only)
    coherent_sweep_gain_db +10 log10 M
    boltzmann_db           −10 log10(k T0)
    bin_width_db           −10 log10(f_s / N)
    window_bandwidth_db    −10 log10 ENBW         (the window's SNR loss, :mod:`.windows`)
    noise_figure_db        −NF
    receive_loss_db        −L_rx

The noise in one bin, k T0 β NF L_rx with β = ENBW f_s/N, is the book's floor (§11.12.4.8:
10 log10(k T β) + NF with β = 1.3 × 5 MHz / 2048 ≈ 3 kHz and NF = 15 dB gives −154 dBW).
With the part ``leakage`` the transmitter leakage's residual phase noise adds a floor
(:mod:`.leakage`, Stove 1992) and ``sinr_db`` is the SNR against both; without it
``sinr_db = snr_db``.

Detection: one detection sample per bin (after the M-sweep coherent integration), the exact
required SNR of :func:`diffsense.detection.required_snr_db` for (pd, pfa) and option
``swerling``; ``detection_margin_db = sinr_db − required_snr_db``, ``pd`` at ``sinr_db``
(:func:`diffsense.detection.pd`, SINR clipped to [−50, 80] dB where Pd is Pfa-like or 1).
With ``wanted`` (see :class:`diffsense.sensors.chain.Chain`) the required-SNR solve and the Pd
series are traced only when asked for.

Sources: G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech 2009), §11.7,
§11.10 (windows, Table 11.4), §11.12.4 (seeker); A. G. Stove, "Linear FMCW radar techniques",
IEE Proc. F 139(5), 343-350 (1992); F. J. Harris, Proc. IEEE 66(1), 51-83 (1978).
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.detection.single_pulse import single_pulse_pd, single_pulse_required_snr_db
from diffsense.numerics.db import DB_PER_NEPER, db10, power_sum_db
from diffsense.physics import antennas as _ant
from diffsense.physics import waveforms as _wf
from diffsense.physics.constants import BOLTZMANN_J_K, REFERENCE_TEMPERATURE_K, SPEED_OF_LIGHT_M_S
from diffsense.physics.propagation.free_space import atmospheric_two_way_loss_db
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, needs
from diffsense.sensors.fmcw.leakage import leakage_noise_dbw
from diffsense.sensors.fmcw.parameters import OPTIONS, PARTS, fmcw_outputs, fmcw_parameters, option
from diffsense.sensors.fmcw.windows import noise_bandwidth_bins, scalloping_loss_db
from diffsense.sensors.radar.link_budget import specific_attenuations_db_km

__all__ = ["FmcwChain", "PARTS", "OPTIONS", "noise_bandwidth_factor"]

_C = SPEED_OF_LIGHT_M_S
#: −10 log10(k T0) (dBW/Hz) with its sign in the budget
_BOLTZMANN_TERM_DB = -DB_PER_NEPER * math.log(BOLTZMANN_J_K * REFERENCE_TEMPERATURE_K)
#: 10 log10 (4π)³
_FOUR_PI_CUBED_DB = 30.0 * math.log10(4.0 * math.pi)


def noise_bandwidth_factor(scene, p):
    """The window's noise bandwidth in bins (ENBW): the option's large-N value, or the parameter
    ``window_bandwidth_factor`` for ``window="given"`` (book §11.12.4.8: 1.3)."""
    window = option(scene, "window")
    if window == "given":
        return p["window_bandwidth_factor"]
    return jnp.asarray(noise_bandwidth_bins(window))


def _antenna(scene, p, lam):
    """(gain dB, 3 dB beamwidth deg): circular aperture G = 4πρA/λ², θ = k λ/d (book eq 5.11), or given."""
    if option(scene, "antenna") == "circular_aperture":
        d = p["antenna_diameter_m"]
        gain_db = db10(_ant.gain_from_aperture(_ant.circular_aperture_area_m2(d), lam, p["aperture_efficiency"]))
        return gain_db, jnp.rad2deg(_ant.beamwidth_rad(lam, d, p["beamwidth_factor"]))
    return p["gain_db"], p["beamwidth_deg"]


def _budget(scene, p, lam, gain_db, alphas, enbw):
    """The named link budget in the FFT bin (module docstring); its total is ``snr_db``."""
    bb = BudgetBuilder()
    bb.add("transmit_power_dbw", db10(p["transmit_power_w"]))
    bb.add("transmit_loss_db", -p["transmit_loss_db"])
    bb.add("two_way_gain_db", 2.0 * gain_db)
    bb.add("wavelength_db", 2.0 * db10(lam) - _FOUR_PI_CUBED_DB)
    bb.add("rcs_dbsm", db10(p["rcs_m2"]))
    bb.add("range_db", -4.0 * db10(p["range_m"]))
    bb.add("misc_loss_db", -p["misc_loss_db"])
    for name, alpha in alphas.items():
        bb.add(f"{name}_attenuation_db", -atmospheric_two_way_loss_db(p["range_m"], alpha))
    bb.add("coherent_sweep_gain_db", db10(p["coherent_sweeps"]))
    bb.add("boltzmann_db", _BOLTZMANN_TERM_DB * jnp.ones_like(p["sampling_rate_hz"]))
    bb.add("bin_width_db", -db10(p["sampling_rate_hz"] / p["fft_size"]))
    bb.add("window_bandwidth_db", -db10(enbw))
    bb.add("noise_figure_db", -p["noise_figure_db"])
    bb.add("receive_loss_db", -p["receive_loss_db"])
    return bb.build()


def waveform_outputs(scene, p, lam):
    """The sweep's and the sampling's outputs (book §11.7, §11.12.4.2; module docstring)."""
    df, tb, fs, n, m = p["sweep_bandwidth_hz"], p["sweep_time_s"], p["sampling_rate_hz"], p["fft_size"], p["coherent_sweeps"]
    fb = _wf.fmcw_beat_frequency_hz(p["range_m"], df, tb)
    fd = _wf.doppler_shift_hz(p["radial_speed_mps"], lam)
    top = fb + jnp.abs(fd)
    nyquist = 0.5 * fs if option(scene, "sampling") == "real" else fs
    bin_width = fs / n
    return {
        "beat_frequency_hz": fb,
        "doppler_frequency_hz": fd,
        "max_beat_frequency_hz": top,
        "nyquist_margin_hz": nyquist - top,
        "oversampling_ratio": fs / top,
        "max_instrumented_range_m": _wf.fmcw_range_from_beat_m(nyquist, df, tb),
        "range_resolution_m": _wf.fmcw_range_resolution_m(df),
        "bin_width_hz": bin_width,
        "range_bin_m": _wf.fmcw_range_from_beat_m(bin_width, df, tb),
        "fft_duration_s": n / fs,
        "sweep_fill": n / (fs * tb),
        "range_doppler_error_m": fd * tb * _C / (2.0 * df),
        "doppler_resolution_hz": 1.0 / (m * tb),
        "velocity_resolution_mps": lam / (2.0 * m * tb),
        "sweep_rate_hz_s": df / tb,
        "wavelength_m": lam,
    }


class FmcwChain(Chain):
    """Linear FMCW radar with FFT range processing (book §11.7, §11.12.4)."""

    kind = "fmcw"
    description = ("linear FMCW radar (Brooker 11.7, 11.12.4): beat frequency, sampling, FFT-bin SNR, "
                   "leakage phase noise, Pd")
    parts = PARTS
    options = OPTIONS

    def parameters(self, scene):
        return fmcw_parameters(scene)

    def outputs(self, scene):
        return fmcw_outputs(scene)

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; the required-SNR solve and Pd only when
        ``wanted`` (None: every output) asks for them."""
        lam = _ant.wavelength_m(p["freq_hz"])
        gain_db, beamwidth_deg = _antenna(scene, p, lam)
        alphas = specific_attenuations_db_km(scene, p)  # the radar's gas and rain parts, same options
        enbw = noise_bandwidth_factor(scene, p)
        budget = _budget(scene, p, lam, gain_db, alphas, enbw)
        snr = budget.total
        values = waveform_outputs(scene, p, lam)
        beta = enbw * values["bin_width_hz"]
        noise = -sum(budget[k] for k in ("boltzmann_db", "bin_width_db", "window_bandwidth_db", "noise_figure_db",
                                         "receive_loss_db"))
        received = snr + noise - budget["coherent_sweep_gain_db"]
        total_noise = noise
        if scene.has("leakage"):
            leak = leakage_noise_dbw(db10(p["transmit_power_w"]), p["isolation_db"], p["phase_noise_dbc_hz"],
                                     p["phase_noise_offset_hz"], values["max_beat_frequency_hz"], p["leakage_delay_s"], beta)
            values["leakage_noise_dbw"] = leak
            total_noise = power_sum_db(noise, leak)
        sinr = snr - (total_noise - noise)
        values.update({
            "snr_db": snr, "sinr_db": sinr, "received_power_dbw": received, "noise_power_dbw": noise,
            "total_noise_dbw": total_noise, "resolution_bandwidth_hz": beta, "window_loss_db": db10(enbw),
            "gain_db": gain_db, "beamwidth_deg": beamwidth_deg,
        })
        if option(scene, "window") != "given":
            values["scalloping_loss_db"] = jnp.asarray(scalloping_loss_db(option(scene, "window")))
        if alphas:
            values["two_way_attenuation_db"] = sum(atmospheric_two_way_loss_db(p["range_m"], a) for a in alphas.values())
        swerling = option(scene, "swerling")
        if needs(wanted, "required_snr_db", "detection_margin_db"):
            req = single_pulse_required_snr_db(p["pd"], p["pfa"], swerling)
            values["required_snr_db"] = req
            values["detection_margin_db"] = sinr - req
        if needs(wanted, "pd"):
            values["pd"] = single_pulse_pd(sinr, p["pfa"], swerling)
        return Evaluation(budget, {name: values[name] for name in fmcw_outputs(scene) if name in values})
