"""Sonar relations (diffsense.sensors.sonar): source level, sonar equations, detection threshold,
and the side-scan geometry through the waveform relations (diffsense.physics.waveforms) at the
speed of sound.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging*, §12.7-12.8 (side-scan sonar with the
  ITC-5202 array, eqs (12.37)-(12.66)) and §13.20 eqs (13.28)-(13.29) (SPL in air).
- Closed forms: p² = I Z; a matched filter on a known signal has Pd = Q(Q⁻¹(Pfa) − sqrt(2E/N0))
  (evaluated with scipy.stats.norm, an implementation independent of jax.scipy); an energy
  detector on a Gaussian signal in Gaussian noise with 2Bt degrees of freedom is exactly a scaled
  chi-square (scipy.stats.chi2), which Urick's 5 log10(d B/t) approximates for large Bt.
- Urick, *Principles of Underwater Sound* (1983) ch. 12: the Gaussian ROC (Pd = 0.5 ⇒ d =
  (Φ⁻¹(1 − Pfa))²).
- Book eqs (8.47)-(8.48) for the reverberating area and volume (closed forms computed here with
  numpy from the inputs).
"""

import math

import pytest
from scipy import stats

import diffsense  # noqa: F401  (float64)
from diffsense.physics import sea_noise
from diffsense.physics import waveforms as wf
from diffsense.sensors import sonar
from diffsense.errors import DomainError
from diffsense.scene import evaluate
from diffsense.scene import Scene

from helpers.function_suite import argument_suite

# -------------------------------------------------------------------------------------------
# Book values (§12.8)
# -------------------------------------------------------------------------------------------


def test_water_impedance_book_12_45():
    # Z = 1026.4 × 1522 = 1.56e6 rayl (book prints three figures).
    assert float(sonar.acoustic_impedance_rayl(1026.4, 1522.0)) == pytest.approx(1.56e6, rel=0.005)


def test_air_impedance_book_13_28():
    # Z_air = 1.229 × 340 = 418 (book rounds to three figures).
    assert float(sonar.acoustic_impedance_rayl(1.229, 340.0)) == pytest.approx(418.0, abs=0.5)


def test_isotropic_intensity_book_12_42():
    # 1500 W × 0.4 / 4π = 47.7 W/m² at 1 m.
    assert float(sonar.isotropic_intensity_w_m2(1500.0, 0.4)) == pytest.approx(47.7, abs=0.05)


def test_sound_pressure_level_intensity_form_book_12_48():
    # S = 120 + 10 log10(21864 × 1.56e6) = 225.3 dB re 1 µPa (book rounds to 0.1 dB).
    assert float(sonar.sound_pressure_level_db(21864.0, 1.56e6)) == pytest.approx(225.3, abs=0.05)


def test_sound_pressure_level_air_book_13_29():
    # L_p = 10 log10 I + 10 log10 Z_air − 20 log10 P_ref = 10 log10 I + 26.21 + 93.98 (book: "+ 120").
    got = float(sonar.sound_pressure_level_db(1.0, 418.0, 20e-6))
    assert got == pytest.approx(26.21 + 93.98, abs=0.01)
    assert got == pytest.approx(120.0, abs=0.25)


def test_source_level_from_power_book_12_48():
    # 1500 W, η = 0.4, G = 4π·57.3²/(1.5·60) = 458.4, Z = 1026.4 × 1522 → 225.3 dB.
    z = sonar.acoustic_impedance_rayl(1026.4, 1522.0)
    assert float(sonar.source_level_db(1500.0, 0.4, 458.4, z)) == pytest.approx(225.3, abs=0.05)


def test_source_level_170_8_form_agrees_with_intensity_form():
    # 170.8 = 10 log10(1.5e6 × 1e12 / 4π) rounded: at Z = 1.5e6 the two forms differ by the rounding
    # of 170.769 to 170.8 only (0.031 dB); at the book's Z = 1.562e6 by 10 log10(Z/1.5e6) more.
    exact_constant = 10 * math.log10(1.5e6 * 1e12 / (4 * math.pi))
    assert sonar.SOURCE_LEVEL_CONSTANT_DB == pytest.approx(exact_constant, abs=0.05)  # printed to 0.1 dB
    for power, eff, g in [(1500.0, 0.4, 458.37), (10.0, 0.7, 1.0), (2e5, 0.2, 3e4)]:
        urick = float(sonar.source_level_from_acoustic_power_db(power * eff, 10 * math.log10(g)))
        intensity = float(sonar.source_level_db(power, eff, g, 1.5e6))
        assert urick - intensity == pytest.approx(sonar.SOURCE_LEVEL_CONSTANT_DB - exact_constant, abs=1e-9)
    z = 1026.4 * 1522.0
    urick = float(sonar.source_level_from_acoustic_power_db(600.0, 10 * math.log10(458.37)))
    intensity = float(sonar.source_level_db(1500.0, 0.4, 458.37, z))
    assert intensity - urick == pytest.approx(10 * math.log10(z / 1.5e6) - (170.8 - exact_constant), abs=1e-9)
    assert urick == pytest.approx(225.3, abs=0.2)  # the book's 225.3 within the impedance difference


def test_drive_voltage_book_12_50():
    # V = sqrt(1500 / 5.5e-3) = 522 V rms.
    assert float(sonar.drive_voltage_rms_v(1500.0, 5.5e-3)) == pytest.approx(522.0, abs=0.5)


def test_source_level_from_tvr_book_12_51():
    # S = 170 + 20 log10(522) = 224.3 dB; the book notes the 1 dB gap to 225.3 (graph reading).
    v = sonar.drive_voltage_rms_v(1500.0, 5.5e-3)
    assert float(sonar.source_level_from_tvr_db(170.0, v)) == pytest.approx(224.3, abs=0.1)


def test_equivalent_pressure_level_inverts_hydrophone_voltage_book_12_65():
    # 50 dB with −180 dB re 1 V/µPa → 320 nV (book rounds 316 nV); 38 dB → 79 nV.
    assert float(sonar.equivalent_pressure_level_db(320e-9, -180.0)) == pytest.approx(50.0, abs=0.15)
    assert float(sonar.equivalent_pressure_level_db(79e-9, -180.0)) == pytest.approx(38.0, abs=0.1)
    for level in (-20.0, 38.0, 150.0):
        v = sea_noise.hydrophone_voltage_v(level, -180.0)
        assert float(sonar.equivalent_pressure_level_db(v, -180.0)) == pytest.approx(level, abs=1e-10)


def test_echo_level_sphere_book_12_58():
    # E = 225.3 − 40 log10 R − 0.0656 R − 12 with H = 20 log10 R + 0.0328 R (exact arithmetic).
    for r in (100.0, 500.0, 900.0):
        tl = 20 * math.log10(r) + 0.0328 * r
        book = 225.3 - 40 * math.log10(r) - 0.0656 * r - 12.0
        assert float(sonar.echo_level_db(225.3, tl, -12.0)) == pytest.approx(book, abs=1e-9)


def test_side_scan_resolutions_and_timing_book_12_37_to_12_41():
    # the book prints two decimals (1522/30000 = 0.0507)
    assert float(wf.range_resolution_bandwidth_m(15e3, 1522.0)) == pytest.approx(0.05, abs=0.005)
    assert float(wf.range_resolution_pulse_m(333e-6, 1522.0)) == pytest.approx(0.25, abs=0.005)
    assert float(wf.real_aperture_cross_range_m(500.0, 1.5 * math.pi / 180)) == pytest.approx(13.1, abs=0.05)
    prf = wf.max_prf_hz(500.0, 1522.0)
    assert float(prf) == pytest.approx(1.52, abs=0.005)
    assert 100 * float(wf.duty_cycle(1.52, 333e-6)) == pytest.approx(0.05, abs=0.005)  # printed "0.05 %"
    # τ_pc = 5 / (100 × 1.52) = 32.9 ms (the book uses the rounded 1.52 Hz)
    assert float(sonar.max_pulse_length_s(0.05, 1.52)) == pytest.approx(32.9e-3, abs=0.05e-3)


def test_pulse_compression_gain_closed_form():
    assert float(wf.pulse_compression_gain_db(15e3, 32.9e-3)) == pytest.approx(10 * math.log10(15e3 * 32.9e-3), abs=1e-12)
    assert float(wf.pulse_compression_gain_db(1 / 333e-6, 333e-6)) == pytest.approx(0.0, abs=1e-12)


# -------------------------------------------------------------------------------------------
# Sonar equations
# -------------------------------------------------------------------------------------------


def test_sonar_equations_term_by_term():
    # SE = SL − 2TL + TS − (NL − DI) − DT etc., checked against hand sums.
    assert float(sonar.active_signal_excess_noise_db(220.0, 60.0, -12.0, 60.0, 20.0, 10.0)) == pytest.approx(
        220 - 120 - 12 - 40 - 10, abs=1e-12)
    assert float(sonar.active_signal_excess_reverberation_db(220.0, 60.0, -12.0, 70.0, 10.0)) == pytest.approx(
        220 - 120 - 12 - 70 - 10, abs=1e-12)
    assert float(sonar.passive_signal_excess_db(150.0, 80.0, 70.0, 15.0, 3.0)) == pytest.approx(
        150 - 80 - 55 - 3, abs=1e-12)


# -------------------------------------------------------------------------------------------
# Detection threshold
# -------------------------------------------------------------------------------------------


@pytest.mark.parametrize("pd,pfa", [(0.5, 1e-4), (0.9, 1e-6), (0.99, 1e-2), (0.2, 1e-10)])
def test_detection_index_matches_scipy_gaussian_roc(pd, pfa):
    expected = (stats.norm.ppf(pd) - stats.norm.ppf(pfa)) ** 2
    assert float(sonar.detection_index(pd, pfa)) == pytest.approx(expected, rel=1e-10)
    assert float(sonar.pd_from_detection_index(expected, pfa)) == pytest.approx(pd, rel=1e-10)


def test_detection_index_pd_half_urick():
    # Pd = 0.5 puts the threshold at the signal mean: d = (Φ⁻¹(1 − Pfa))² = 3.719² = 13.83 at 1e-4.
    assert float(sonar.detection_index(0.5, 1e-4)) == pytest.approx(13.83, abs=0.01)


@pytest.mark.parametrize("pd,pfa,t", [(0.5, 1e-4, 0.01), (0.9, 1e-6, 0.333e-3), (0.99, 1e-3, 2.0)])
def test_known_signal_threshold_gives_matched_filter_pd(pd, pfa, t):
    # S/N0 = 10^(DT/10), E/N0 = S t / N0; the correlator has Pd = Q(Q⁻¹(Pfa) − sqrt(2E/N0)).
    d = sonar.detection_index(pd, pfa)
    e_over_n0 = 10 ** (float(sonar.detection_threshold_known_signal_db(d, t)) / 10) * t
    assert stats.norm.sf(stats.norm.isf(pfa) - math.sqrt(2 * e_over_n0)) == pytest.approx(pd, rel=1e-9)


@pytest.mark.parametrize("pd,pfa", [(0.5, 1e-3), (0.9, 1e-4)])
def test_energy_detector_threshold_against_exact_chi_square(pd, pfa):
    # A Gaussian signal of band SNR s in Gaussian noise: the integrator output over n = 2Bt real
    # samples is σ²χ²_n without and σ²(1 + s)χ²_n with the signal (exact). Urick's DT applies for
    # Bt ≫ 1; at Bt = 1e5 the exact Pd at that SNR matches the requested Pd within 0.01.
    b, t = 1e3, 100.0
    n = 2 * b * t
    d = sonar.detection_index(pd, pfa)
    dt_band = float(sonar.detection_threshold_energy_db(d, b, t)) - 10 * math.log10(b)
    s = 10 ** (dt_band / 10)
    thr = stats.chi2.isf(pfa, n)
    assert stats.chi2.sf(thr / (1 + s), n) == pytest.approx(pd, abs=0.01)


@pytest.mark.parametrize("bt,bound_db", [(1e3, 0.35), (1e4, 0.12)])
def test_energy_detector_threshold_error_bound_against_exact_chi_square(bt, bound_db):
    # The documented error of 5 log10(d/(Bt)) at Pd 0.9, Pfa 1e-6: optimistic (low) by at most
    # 0.34 dB at Bt = 1e3 and 0.11 dB at 1e4 against the exact chi-square detector.
    from scipy import optimize

    pd, pfa, n = 0.9, 1e-6, 2 * bt
    dt = float(sonar.detection_threshold_energy_db(sonar.detection_index(pd, pfa), bt, 1.0)) - 10 * math.log10(bt)
    thr = stats.chi2.isf(pfa, n)
    s = optimize.brentq(lambda s: stats.chi2.sf(thr / (1 + s), n) - pd, 1e-9, 1e6, xtol=1e-14)
    error = dt - 10 * math.log10(s)
    assert -bound_db <= error <= 0.0


def test_detection_threshold_book_13_2_db():
    # Pd 0.9, Pfa 1e-6, steady echo, one pulse: 13.18 dB (DiFranco & Rubin), the book's 13.2 dB.
    assert float(sonar.detection_threshold_db(0.9, 1e-6)) == pytest.approx(13.2, abs=0.05)


# -------------------------------------------------------------------------------------------
# The chain against the sonar equations (closed forms from the inputs)
# -------------------------------------------------------------------------------------------


def test_reverberation_limited_chain_matches_eq_8_48():
    # Volume reverberation only: SNR = TS − S_v − 10 log10((cτ/2) π R² θ_az θ_el / 4), independent
    # of SL and TL; the chain's signal excess equals active_signal_excess_reverberation_db.
    scene = Scene("sonar", ["volume_reverberation"], {"target": "given", "absorption": "given"})
    r, c, tau, az, el = 400.0, 1500.0, 1e-3, 2.0, 10.0
    e = evaluate(scene, range_m=r, freq_hz=50e3, target_strength_db=5.0, pulse_width_s=tau,
                 beamwidth_az_deg=az, beamwidth_el_deg=el, volume_scattering_strength_db=-70.0,
                 absorption_db_per_m=0.01, sound_speed_m_s=c)
    vol = c * tau / 2 * math.pi * r**2 * math.radians(az) * math.radians(el) / 4
    assert float(e["snr_db"]) == pytest.approx(5.0 + 70.0 - 10 * math.log10(vol), abs=1e-9)
    tl = 20 * math.log10(r) + 0.01 * r
    se = sonar.active_signal_excess_reverberation_db(
        e["source_level_db"], tl, 5.0, e["reverberation_level_db"], e["required_snr_db"])
    assert float(e["signal_excess_db"]) == pytest.approx(float(se), abs=1e-9)
    assert float(e.budget.total) == pytest.approx(float(e["snr_db"]), abs=1e-9)


def test_passive_chain_matches_sonar_equation_and_energy_detector():
    # Passive, thermal noise only: SNR = SL − TL − (N_th + 10 log10 B − DI); DT = 5 log10(d/(Bt));
    # Pd from the Gaussian ROC with d = (S/N)² B t.
    scene = Scene("sonar", ["thermal_noise"], {"mode": "passive", "absorption": "given"})
    r, f, b, t, sl, az, el = 2000.0, 20e3, 200.0, 0.5, 120.0, 10.0, 20.0
    e = evaluate(scene, range_m=r, freq_hz=f, source_level_db=sl, bandwidth_hz=b, integration_time_s=t,
                 absorption_db_per_m=0.003, beamwidth_az_deg=az, beamwidth_el_deg=el, pd=0.8, pfa=1e-4)
    di = 10 * math.log10(4 * math.pi / (math.radians(az) * math.radians(el)))
    n_th = -15 + 20 * math.log10(f / 1e3)
    tl = 20 * math.log10(r) + 0.003 * r
    snr = sl - tl - (n_th + 10 * math.log10(b) - di)
    assert float(e["snr_db"]) == pytest.approx(snr, abs=1e-9)
    d = (stats.norm.ppf(0.8) - stats.norm.ppf(1e-4)) ** 2
    assert float(e["required_snr_db"]) == pytest.approx(5 * math.log10(d / (b * t)), abs=1e-9)
    s_lin = 10 ** (snr / 10)
    assert float(e["pd"]) == pytest.approx(stats.norm.cdf(s_lin * math.sqrt(b * t) + stats.norm.ppf(1e-4)), rel=1e-9)
    se = sonar.passive_signal_excess_db(sl, tl, n_th + 10 * math.log10(b), di, e["required_snr_db"])
    assert float(e["signal_excess_db"]) == pytest.approx(float(se), abs=1e-9)
    # at the detection range the SNR equals the threshold
    r_det = float(e["detection_range_m"])
    e2 = evaluate(scene, range_m=r_det, freq_hz=f, source_level_db=sl, bandwidth_hz=b, integration_time_s=t,
                  absorption_db_per_m=0.003, beamwidth_az_deg=az, beamwidth_el_deg=el, pd=0.8, pfa=1e-4)
    assert float(e2["snr_margin_db"]) == pytest.approx(0.0, abs=1e-8)


# -------------------------------------------------------------------------------------------
# jit, vmap, gradients, domains of the functions
# -------------------------------------------------------------------------------------------

# (function, point, index of the argument to differentiate, (lo, hi) of that argument for hypothesis)
_CASES = {
    "acoustic_impedance_rayl": (sonar.acoustic_impedance_rayl, (1026.4, 1522.0), 1, (1.0, 5000.0)),
    "isotropic_intensity_w_m2": (sonar.isotropic_intensity_w_m2, (1500.0, 0.4, 3.0), 2, (0.01, 1e4)),
    "sound_pressure_level_db": (sonar.sound_pressure_level_db, (2e4, 1.5e6), 0, (1e-12, 1e9)),
    "source_level_db": (sonar.source_level_db, (1500.0, 0.4, 458.4, 1.56e6), 2, (1.0, 1e6)),
    "source_level_from_acoustic_power_db": (sonar.source_level_from_acoustic_power_db, (600.0, 26.6), 0, (1e-6, 1e7)),
    "drive_voltage_rms_v": (sonar.drive_voltage_rms_v, (1500.0, 5.5e-3), 1, (1e-6, 10.0)),
    "source_level_from_tvr_db": (sonar.source_level_from_tvr_db, (170.0, 522.0), 1, (1e-3, 1e5)),
    "equivalent_pressure_level_db": (sonar.equivalent_pressure_level_db, (1e-7, -180.0), 0, (1e-12, 1.0)),
    "echo_level_db": (sonar.echo_level_db, (225.0, 70.0, -12.0), 1, (0.0, 300.0)),
    "detection_index": (sonar.detection_index, (0.9, 1e-6), 0, (0.01, 0.999)),
    "pd_from_detection_index": (sonar.pd_from_detection_index, (20.0, 1e-6), 0, (0.01, 200.0)),
    "detection_threshold_known_signal_db": (sonar.detection_threshold_known_signal_db, (20.0, 0.01), 1, (1e-6, 100.0)),
    "detection_threshold_energy_db": (sonar.detection_threshold_energy_db, (20.0, 100.0, 1.0), 1, (1e-3, 1e6)),
    "range_resolution_pulse_m": (wf.range_resolution_pulse_m, (333e-6, 1522.0), 0, (1e-7, 10.0)),
    "range_resolution_bandwidth_m": (wf.range_resolution_bandwidth_m, (15e3, 1522.0), 0, (1.0, 1e6)),
    "real_aperture_cross_range_m": (wf.real_aperture_cross_range_m, (500.0, 0.026), 1, (1e-4, 3.0)),
    "max_prf_hz": (wf.max_prf_hz, (500.0, 1522.0), 0, (0.1, 1e6)),
    "duty_cycle": (wf.duty_cycle, (1.52, 333e-6), 0, (1e-3, 1e3)),
    "max_pulse_length_s": (sonar.max_pulse_length_s, (0.05, 1.52), 1, (1e-3, 1e3)),
    "pulse_compression_gain_db": (wf.pulse_compression_gain_db, (15e3, 0.0329), 0, (1.0, 1e6)),
}


globals().update(argument_suite(_CASES))


@pytest.mark.parametrize(
    "call",
    [
        lambda: sonar.acoustic_impedance_rayl(-1.0, 1500.0),
        lambda: sonar.isotropic_intensity_w_m2(100.0, 1.5),
        lambda: sonar.sound_pressure_level_db(0.0, 1.5e6),
        lambda: sonar.source_level_db(100.0, 0.5, 0.5, 1.5e6),
        lambda: sonar.source_level_from_acoustic_power_db(10.0, -3.0),
        lambda: sonar.drive_voltage_rms_v(100.0, 0.0),
        lambda: sonar.source_level_from_tvr_db(400.0, 10.0),
        lambda: sonar.equivalent_pressure_level_db(1e-6, 10.0),
        lambda: sonar.echo_level_db(350.0, 10.0, 0.0),
        lambda: sonar.detection_index(1e-6, 0.9),
        lambda: sonar.detection_index(1.0, 1e-6),
        lambda: sonar.pd_from_detection_index(-1.0, 1e-6),
        lambda: sonar.detection_threshold_known_signal_db(0.0, 1.0),
        lambda: sonar.detection_threshold_energy_db(10.0, 100.0, -1.0),
        lambda: wf.range_resolution_pulse_m(-1e-3),
        lambda: wf.range_resolution_bandwidth_m(0.0),
        lambda: wf.real_aperture_cross_range_m(100.0, 4.0),
        lambda: wf.max_prf_hz(0.0),
        lambda: wf.duty_cycle(1.0, 0.0),
        lambda: sonar.max_pulse_length_s(1.5, 1.0),
        lambda: wf.pulse_compression_gain_db(1e3, float("nan")),
    ],
)
def test_out_of_domain_raises(call):
    with pytest.raises(DomainError):
        call()
