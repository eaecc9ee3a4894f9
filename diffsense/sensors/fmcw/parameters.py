"""The FMCW chain's scene structure (parts, options) and its parameter and output tables: names,
units (SI, dB explicit), meaning, defaults (the book's seeker, §11.12.4, where it gives one) and
domains."""

from __future__ import annotations

from diffsense.sensors.chain import Output, Param, collect
from diffsense.sensors.fmcw.windows import WINDOWS
from diffsense.sensors.radar.parameters import BOOK_BEAMWIDTH_FACTOR

__all__ = ["PARTS", "OPTIONS", "option", "fmcw_parameters", "fmcw_outputs"]

PARTS = {
    "gas": "atmospheric gases on the whole path (ITU-R P.676-12, or a given specific attenuation)",
    "rain": "rain on the whole path (ITU-R P.838-3, or a given specific attenuation)",
    "leakage": "transmitter leakage into the receiver and its residual phase noise in the target's bin "
               "(Stove 1992: range-correlated 1/f² phase noise)",
}

OPTIONS = {
    "swerling": (0, (0, 1, 2, 3, 4)),
    "window": ("hann", WINDOWS),
    "sampling": ("real", ("real", "complex")),
    "antenna": ("circular_aperture", ("circular_aperture", "specified")),
    "gas_model": ("itu_p676", ("itu_p676", "specified")),
    "rain_model": ("itu_p838", ("itu_p838", "specified")),
    "polarization": ("horizontal", ("horizontal", "vertical")),
}


def option(scene, name):
    """The value of the FMCW option ``name`` in ``scene``, or its default from :data:`OPTIONS`."""
    return scene.option(name, OPTIONS[name][0])


def _core_parameters(scene):
    ps = [
        Param("range_m", "m", "target range R", None, 0.1, 1e6),
        Param("transmit_power_w", "W", "continuous transmit power P_t (book 11.12.4.2: 100 mW)", None, 0.0, 1e4, lo_open=True),
        Param("freq_hz", "Hz", "carrier frequency f; λ = c / f (1-300 GHz: the ITU-R path models)", None, 1e9, 3e11),
        Param("sweep_bandwidth_hz", "Hz", "swept bandwidth Δf (book 11.12.4.2: 300 MHz)", None, 1e3, 1e11),
        Param("sweep_time_s", "s", "duration T_b of one (up or down) sweep (book 11.12.4.2: 500 µs)", None, 1e-7, 10.0),
        Param("sampling_rate_hz", "Hz", "ADC sampling rate f_s of the beat signal (book 11.12.4.2: 10 MHz)", None, 1e3, 1e11),
        Param("fft_size", "1", "FFT length N in samples; bin width f_s / N (book 11.12.4.8: 4096 real samples, "
              "2048 range bins)", None, 8.0, 2.0**24, integer=True),
        Param("noise_figure_db", "dB", "receiver noise figure NF (book 11.12.4.8: 15 dB for FMCW)", None, 0.0, 60.0),
        Param("rcs_m2", "m**2", "mean target radar cross-section σ", 1.0, 0.0, 1e9, lo_open=True),
        Param("transmit_loss_db", "dB", "transmit line loss L_tx", 0.0, 0.0, 60.0),
        Param("receive_loss_db", "dB", "receive line loss L_rx, added to the noise", 0.0, 0.0, 60.0),
        Param("misc_loss_db", "dB", "other two-way losses (radome, polarisation, processing)", 0.0, 0.0, 60.0),
        Param("coherent_sweeps", "1", "sweeps M integrated coherently (a Doppler FFT across sweeps): the noise "
              "bandwidth falls M-fold (1: a single sweep, the book's seeker)", 1.0, 1.0, 1e5, integer=True),
        Param("radial_speed_mps", "m/s", "radial speed of the target, closing positive; Doppler 2v/λ", 0.0, -1e4, 1e4),
        Param("pd", "1", "required probability of detection", 0.9, 0.05, 0.999999),
        Param("pfa", "1", "probability of false alarm per range bin", 1e-6, 1e-15, 1e-2),
    ]
    if option(scene, "window") == "given":
        ps.append(Param("window_bandwidth_factor", "1", "noise bandwidth of the window in FFT bins (book 11.12.4.8: 1.3)",
                        None, 1.0, 3.0))
    return ps


def _antenna_parameters(scene):
    if option(scene, "antenna") == "circular_aperture":
        return [
            Param("antenna_diameter_m", "m", "circular antenna diameter d (one antenna transmits and receives)", None, 1e-3, 100.0),
            Param("aperture_efficiency", "1", "aperture efficiency ρ in G = 4πρA/λ²", 0.7, 0.0, 1.0, lo_open=True),
            Param("beamwidth_factor", "1", "k in θ3dB = k λ / d rad (default the book's 70λ/d deg)", BOOK_BEAMWIDTH_FACTOR, 0.5, 3.0),
        ]
    return [
        Param("gain_db", "dB", "antenna gain G (transmit and receive)", None, -10.0, 80.0),
        Param("beamwidth_deg", "deg", "3 dB beamwidth (information output only)", None, 0.0, 180.0, lo_open=True),
    ]


def _path_parameters(scene):
    ps = []
    if scene.has("gas") and option(scene, "gas_model") == "itu_p676":
        ps += [
            Param("pressure_hpa", "hPa", "total air pressure (ITU-R P.676 standard 1013.25)", 1013.25, 100.0, 1200.0, part="gas"),
            Param("water_vapour_g_m3", "g/m**3", "water-vapour density (ITU-R P.676 standard 7.5)", 7.5, 0.0, 50.0, part="gas"),
            Param("air_temperature_k", "K", "air temperature (ITU-R standard 288.15)", 288.15, 233.15, 323.15, part="gas"),
        ]
    elif scene.has("gas"):
        ps.append(Param("gas_attenuation_db_km", "dB/km", "one-way gas attenuation", None, 0.0, 100.0, part="gas"))
    if scene.has("rain") and option(scene, "rain_model") == "itu_p838":
        ps.append(Param("rain_rate_mm_h", "mm/h", "rain rate", 25.0, 0.0, 500.0, lo_open=True, part="rain"))
    elif scene.has("rain"):
        ps.append(Param("rain_attenuation_db_km", "dB/km", "one-way rain attenuation", None, 0.0, 100.0, part="rain"))
    return ps


def _leakage_parameters(scene):
    if not scene.has("leakage"):
        return []
    return [
        Param("isolation_db", "dB", "transmit-receive isolation I: the leakage is P_t / I (Stove 1992: 20-30 dB "
              "for a circulator and antenna match)", 25.0, 0.0, 150.0, part="leakage"),
        Param("phase_noise_dbc_hz", "dB", "oscillator SSB phase noise 𝓛(f_0) in dBc/Hz (dB relative to the carrier in 1 Hz) "
              "at the offset phase_noise_offset_hz",
              -85.0, -200.0, 0.0, part="leakage"),
        Param("phase_noise_offset_hz", "Hz", "offset f_0 of the phase-noise datum; 𝓛 falls 20 dB/decade from there",
              1e5, 0.0, 1e10, lo_open=True, part="leakage"),
        Param("leakage_delay_s", "s", "delay τ_L of the leakage path relative to the local oscillator (1 ns: 15 cm "
              "of path in air)", 1e-9, 0.0, 1e-6, lo_open=True, part="leakage"),
    ]


def fmcw_parameters(scene):
    """``{name: Param}`` of an FMCW scene: core, antenna, path, leakage."""
    return collect(_core_parameters(scene) + _antenna_parameters(scene) + _path_parameters(scene)
                   + _leakage_parameters(scene))


_OUTPUTS = (
    Output("snr_db", "dB", "SNR in the target's FFT bin against receiver noise, after coherent_sweeps (budget total)"),
    Output("sinr_db", "dB", "SNR against receiver noise plus the leakage phase-noise floor (= snr_db without leakage)"),
    Output("received_power_dbw", "dBW", "echo power at the receiver, after losses and path attenuation"),
    Output("noise_power_dbw", "dBW", "receiver noise in one bin, k T0 β NF L_rx with β the window's noise bandwidth "
           "(book 11.12.4.8: -154 dBW)"),
    Output("total_noise_dbw", "dBW", "receiver noise plus the leakage floor in one bin"),
    Output("required_snr_db", "dB", "SNR required for pd at pfa, one detection sample (exact, Swerling option)"),
    Output("detection_margin_db", "dB", "sinr_db - required_snr_db"),
    Output("pd", "1", "probability of detection at sinr_db"),
    Output("beat_frequency_hz", "Hz", "range beat frequency f_b = Δf 2R / (c T_b) (book eq 11.22: 4 MHz at 1 km)"),
    Output("doppler_frequency_hz", "Hz", "Doppler shift f_d = 2 v / λ"),
    Output("max_beat_frequency_hz", "Hz", "f_b + |f_d|, the highest beat of the triangular sweep"),
    Output("nyquist_margin_hz", "Hz", "f_s/2 - (f_b + |f_d|) for real sampling (f_s - (f_b + |f_d|) for complex)"),
    Output("oversampling_ratio", "1", "f_s / (f_b + |f_d|) (book 11.12.4.2: 2.5 for a practical anti-alias filter)"),
    Output("max_instrumented_range_m", "m", "range whose beat reaches the Nyquist frequency: f_s c T_b / (4 Δf) real, "
           "f_s c T_b / (2 Δf) complex sampling"),
    Output("range_resolution_m", "m", "c / (2 Δf) (book eq 11.25: 0.5 m for 300 MHz)"),
    Output("bin_width_hz", "Hz", "FFT bin width f_s / N"),
    Output("resolution_bandwidth_hz", "Hz", "window noise bandwidth × bin width (book 11.12.4.8: 1.3 × 5 MHz / 2048 ≈ 3 kHz)"),
    Output("range_bin_m", "m", "range spanned by one FFT bin, c T_b (f_s/N) / (2 Δf) (book eq 11.24)"),
    Output("fft_duration_s", "s", "time the FFT's samples span, N / f_s"),
    Output("sweep_fill", "1", "N / (f_s T_b): the FFT's samples must fit in one sweep (<= 1)"),
    Output("range_doppler_error_m", "m", "range-Doppler coupling Δr = f_d T_b c / (2 Δf) (book eq 11.26)"),
    Output("doppler_resolution_hz", "Hz", "1 / (M T_b) over the coherent_sweeps M"),
    Output("velocity_resolution_mps", "m/s", "λ / (2 M T_b)"),
    Output("sweep_rate_hz_s", "Hz/s", "Δf / T_b"),
    Output("window_loss_db", "dB", "SNR loss of the window, 10 log10 ENBW (in the noise bandwidth)"),
    Output("scalloping_loss_db", "dB", "loss of a target half a bin off centre (information, not in the SNR)"),
    Output("wavelength_m", "m", "λ = c / f"),
    Output("gain_db", "dB", "antenna gain"),
    Output("beamwidth_deg", "deg", "3 dB beamwidth"),
)


def fmcw_outputs(scene):
    """``{name: Output}`` of an FMCW scene (the leakage floor and the path attenuation with their parts)."""
    outs = [o for o in _OUTPUTS if not (o.name == "scalloping_loss_db" and option(scene, "window") == "given")]
    if scene.has("leakage"):
        outs.append(Output("leakage_noise_dbw", "dBW", "leakage phase-noise floor in the target's bin (Stove 1992)"))
    if scene.has("gas") or scene.has("rain"):
        outs.append(Output("two_way_attenuation_db", "dB", "two-way path attenuation of the gas and rain parts"))
    return {o.name: o for o in outs}
