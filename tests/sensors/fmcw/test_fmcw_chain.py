"""Tests of the FMCW chain (kind "fmcw") through the public chain API.

References: the book's seeker numbers (Brooker §11.12.4: 4 MHz beat, 0.5 m, ≈ 3 kHz bin,
≈ −154 dBW noise floor), 40-digit mpmath evaluations of every formula written out here from the
radar equation and the FMCW relations, Harris (1978) Table 1 and large-N discrete windows for
the window numbers, closed forms for the detection probability (Swerling 1: Pd = Pfa^(1/(1+S));
Swerling 0: scipy's noncentral chi-square, both independent of diffsense.detection), and
central differences for the gradients.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.scene import Scene, complete_parameters, compute, describe, evaluate, evaluator, sensor_kinds
from diffsense.sensors.fmcw import leakage_noise_dbw, noise_bandwidth_bins, scalloping_loss_db

MPMATH_DPS = 40
C = 299792458.0
K_B = mp.mpf("1.380649e-23")
T0 = mp.mpf(290)

# --- the book's seeker, §11.12.4 ---------------------------------------------------------------
BOOK_SCENE = Scene("fmcw", [], {"window": "given", "swerling": 1})
BOOK = dict(range_m=1000.0, transmit_power_w=0.1, freq_hz=94e9, sweep_bandwidth_hz=300e6, sweep_time_s=500e-6,
            sampling_rate_hz=10e6, fft_size=4096.0, window_bandwidth_factor=1.3, noise_figure_db=15.0,
            antenna_diameter_m=0.15, rcs_m2=10.0)

# --- a scene with every part: gas and rain given, leakage, Doppler, coherent sweeps -------------
FULL_SCENE = Scene("fmcw", ["gas", "rain", "leakage"], {"window": "blackman", "swerling": 1, "gas_model": "specified",
                                                        "rain_model": "specified"})
FULL = dict(range_m=700.0, transmit_power_w=0.05, freq_hz=77e9, sweep_bandwidth_hz=1.2e9, sweep_time_s=80e-6,
            sampling_rate_hz=25e6, fft_size=1024.0, noise_figure_db=11.0, antenna_diameter_m=0.03, rcs_m2=3.0,
            aperture_efficiency=0.6, transmit_loss_db=0.7, receive_loss_db=1.1, misc_loss_db=1.5, coherent_sweeps=64.0,
            radial_speed_mps=-30.0, gas_attenuation_db_km=0.4, rain_attenuation_db_km=3.0, isolation_db=28.0,
            phase_noise_dbc_hz=-88.0, phase_noise_offset_hz=2e5, leakage_delay_s=2e-9, pd=0.8, pfa=1e-5)
BLACKMAN = (mp.mpf("0.42"), mp.mpf("0.5"), mp.mpf("0.08"))


def db(x):
    return 10 * mp.log10(x)


def mp_reference(p, enbw, real=True):
    """Every output of the chain from the formulas, at 40 digits (book §11.7, §11.12.4; radar
    equation of book eq 9.x as in the radar chain; Stove 1992 leakage)."""
    g = {k: mp.mpf(v) for k, v in p.items()}
    lam = C / g["freq_hz"]
    area = mp.pi * g["antenna_diameter_m"] ** 2 / 4
    gain = 4 * mp.pi * g.get("aperture_efficiency", mp.mpf("0.7")) * area / lam**2
    r = g["range_m"]
    alpha = g.get("gas_attenuation_db_km", 0) + g.get("rain_attenuation_db_km", 0)
    atten_db = 2 * alpha * r / 1000
    pr_dbw = (db(g["transmit_power_w"] * gain**2 * lam**2 * g["rcs_m2"] / ((4 * mp.pi) ** 3 * r**4))
              - g.get("transmit_loss_db", 0) - g.get("misc_loss_db", 0) - atten_db)
    bin_hz = g["sampling_rate_hz"] / g["fft_size"]
    beta = enbw * bin_hz
    n_dbw = db(K_B * T0 * beta) + g["noise_figure_db"] + g.get("receive_loss_db", 0)
    m = g.get("coherent_sweeps", mp.mpf(1))
    snr = pr_dbw + db(m) - n_dbw
    fb = g["sweep_bandwidth_hz"] * 2 * r / (C * g["sweep_time_s"])
    fd = 2 * g.get("radial_speed_mps", 0) / lam
    top = fb + abs(fd)
    nyq = g["sampling_rate_hz"] / 2 if real else g["sampling_rate_hz"]
    out = dict(
        received_power_dbw=pr_dbw, noise_power_dbw=n_dbw, snr_db=snr, beat_frequency_hz=fb, doppler_frequency_hz=fd,
        max_beat_frequency_hz=top, nyquist_margin_hz=nyq - top, oversampling_ratio=g["sampling_rate_hz"] / top,
        max_instrumented_range_m=nyq * C * g["sweep_time_s"] / (2 * g["sweep_bandwidth_hz"]),
        range_resolution_m=C / (2 * g["sweep_bandwidth_hz"]), bin_width_hz=bin_hz, resolution_bandwidth_hz=beta,
        range_bin_m=C * g["sweep_time_s"] * bin_hz / (2 * g["sweep_bandwidth_hz"]),
        fft_duration_s=g["fft_size"] / g["sampling_rate_hz"], sweep_fill=g["fft_size"] / (g["sampling_rate_hz"] * g["sweep_time_s"]),
        range_doppler_error_m=fd * g["sweep_time_s"] * C / (2 * g["sweep_bandwidth_hz"]),
        doppler_resolution_hz=1 / (m * g["sweep_time_s"]), velocity_resolution_mps=lam / (2 * m * g["sweep_time_s"]),
        sweep_rate_hz_s=g["sweep_bandwidth_hz"] / g["sweep_time_s"], window_loss_db=db(enbw), wavelength_m=lam,
        gain_db=db(gain), beamwidth_deg=mp.degrees(g.get("beamwidth_factor", 70 * mp.pi / 180) * lam / g["antenna_diameter_m"]),
    )
    total_noise = n_dbw
    if "isolation_db" in g:
        l_fb = g["phase_noise_dbc_hz"] - 20 * mp.log10(top / g["phase_noise_offset_hz"])
        corr = db(4 * mp.sin(mp.pi * top * g["leakage_delay_s"]) ** 2)
        leak = db(g["transmit_power_w"]) - g["isolation_db"] + l_fb + corr + db(beta)
        total_noise = db(10 ** (n_dbw / 10) + 10 ** (leak / 10))
        out["leakage_noise_dbw"] = leak
        out["two_way_attenuation_db"] = atten_db
    out["total_noise_dbw"] = total_noise
    out["sinr_db"] = snr - (total_noise - n_dbw)
    return out


def test_registered_and_described():
    assert "fmcw" in sensor_kinds()
    d = describe(FULL_SCENE)
    assert d["parameters"]["sweep_time_s"]["unit"] == "s"
    assert "leakage_noise_dbw" in d["outputs"] and "scalloping_loss_db" in d["outputs"]
    assert "scalloping_loss_db" not in describe(BOOK_SCENE)["outputs"]


# --- the book's numbers ------------------------------------------------------------------------


def test_book_seeker_numbers():
    """§11.12.4: 300 MHz → 0.5 m; 1 km, 500 µs → 4 MHz; 10 MHz = 2.5 × 4 MHz; bin 1.3 × 5 MHz/2048
    ≈ 3 kHz; noise floor 10 log10(k T β) + NF ≈ −154 dBW. The book writes c = 3e8 m/s."""
    ev = evaluate(BOOK_SCENE, BOOK)
    book_c = 3e8
    assert float(ev["beat_frequency_hz"]) * C / book_c == pytest.approx(4e6, rel=1e-14)
    assert float(ev["range_resolution_m"]) * book_c / C == pytest.approx(0.5, rel=1e-14)
    assert float(ev["oversampling_ratio"]) * book_c / C == pytest.approx(2.5, rel=1e-14)
    assert float(ev["resolution_bandwidth_hz"]) == pytest.approx(1.3 * 5e6 / 2048, rel=1e-14)
    assert abs(float(ev["resolution_bandwidth_hz"]) - 3e3) < 0.06 * 3e3  # the book's "≈ 3 kHz"
    noise = float(ev["noise_power_dbw"])
    book = float(10 * mp.log10(K_B * T0 * mp.mpf(1.3) * mp.mpf(5e6) / 2048) + 15)
    assert noise == pytest.approx(book, abs=1e-9)
    assert round(noise) == -154
    # real sampling: the beat reaches f_s/2 at R = f_s c T_b / (4 Δf) = 1250 m (c = 3e8)
    assert float(ev["max_instrumented_range_m"]) * book_c / C == pytest.approx(1250.0, rel=1e-14)


# --- every formula against an independent computation ---------------------------------------


@pytest.mark.parametrize("scene,params,enbw,real", [
    (BOOK_SCENE, BOOK, mp.mpf("1.3"), True),
    (FULL_SCENE, FULL, (BLACKMAN[0] ** 2 + (BLACKMAN[1] ** 2 + BLACKMAN[2] ** 2) / 2) / BLACKMAN[0] ** 2, True),
    (Scene("fmcw", ["gas", "rain", "leakage"], dict(FULL_SCENE.options, sampling="complex")), FULL,
     (BLACKMAN[0] ** 2 + (BLACKMAN[1] ** 2 + BLACKMAN[2] ** 2) / 2) / BLACKMAN[0] ** 2, False),
])
def test_outputs_match_mpmath(scene, params, enbw, real):
    ev = evaluate(scene, params)
    ref = mp_reference(params, enbw, real)
    for name, want in ref.items():
        got = float(ev[name])
        if name.endswith("_db") or name.endswith("_dbw"):
            assert got == pytest.approx(float(want), abs=1e-9), name
        else:
            assert got == pytest.approx(float(want), rel=1e-12, abs=1e-300), name
    assert float(ev.budget.total) == pytest.approx(float(ref["snr_db"]), abs=1e-9)


def test_itu_rain_and_gas_parts_enter_the_budget():
    """With the ITU models the budget holds −2 α R/1000 for each part, α from the physics functions."""
    from diffsense.physics.propagation.gas import gas_attenuation_db_per_km
    from diffsense.physics.propagation.rain import rain_attenuation_db_per_km

    scene = Scene("fmcw", ["gas", "rain"], {})
    p = dict(BOOK, rain_rate_mm_h=4.0)
    p.pop("window_bandwidth_factor")
    ev = evaluate(scene, p)
    a_rain = float(rain_attenuation_db_per_km(94e9, 4.0, "horizontal"))
    a_gas = float(gas_attenuation_db_per_km(94e9, 1013.25, 288.15, 7.5))
    assert float(ev.budget["rain_attenuation_db"]) == pytest.approx(-2 * a_rain, rel=1e-12)
    assert float(ev.budget["gas_attenuation_db"]) == pytest.approx(-2 * a_gas, rel=1e-12)


def test_detection_against_closed_forms():
    """Swerling 1, one sample: Pd = Pfa^(1/(1+S)), so S_req = ln Pfa / ln Pd − 1 (Marcum and
    Swerling 1960); Swerling 0: Pd = Q_1(√(2S), √(−2 ln Pfa)) = ncx2.sf(−2 ln Pfa, 2, 2S)."""
    ev = evaluate(FULL_SCENE, FULL)
    s = 10 ** (float(ev["sinr_db"]) / 10)
    pfa, pd = FULL["pfa"], FULL["pd"]
    assert float(ev["pd"]) == pytest.approx(pfa ** (1 / (1 + s)), abs=1e-12)
    assert float(ev["required_snr_db"]) == pytest.approx(10 * math.log10(math.log(pfa) / math.log(pd) - 1), abs=1e-9)
    assert float(ev["detection_margin_db"]) == pytest.approx(float(ev["sinr_db"]) - float(ev["required_snr_db"]), abs=1e-12)
    scene0 = Scene("fmcw", ["gas", "rain", "leakage"], dict(FULL_SCENE.options, swerling=0))
    p0 = dict(FULL, range_m=2500.0)  # lower SNR, Pd away from 1
    ev0 = evaluate(scene0, p0)
    s0 = 10 ** (float(ev0["sinr_db"]) / 10)
    assert float(ev0["pd"]) == pytest.approx(stats.ncx2.sf(-2 * math.log(pfa), 2, 2 * s0), abs=1e-10)


def test_windows_against_large_n_discrete_windows_and_harris():
    """ENBW = N Σw²/(Σw)² and the half-bin loss of N = 2^16 periodic windows (their difference
    from the large-N limit is O(1/N²)); Harris (1978) Table 1 to its two decimals
    (except the Hamming half-bin loss, module docstring of diffsense.sensors.fmcw.windows)."""
    n = 2**16
    k = np.arange(n)
    u = k / n - 0.5
    windows = {"rectangular": np.ones(n), "hann": 0.5 + 0.5 * np.cos(2 * np.pi * u),
               "hamming": 0.54 + 0.46 * np.cos(2 * np.pi * u),
               "blackman": 0.42 + 0.5 * np.cos(2 * np.pi * u) + 0.08 * np.cos(4 * np.pi * u)}
    harris = {"rectangular": (1.00, 3.92), "hann": (1.50, 1.42), "hamming": (1.36, 1.78), "blackman": (1.73, 1.10)}
    for name, w in windows.items():
        enbw = n * np.sum(w**2) / np.sum(w) ** 2
        half = abs(np.sum(w * np.exp(-1j * np.pi * k / n))) / np.sum(w)
        assert noise_bandwidth_bins(name) == pytest.approx(enbw, rel=1e-8), name
        assert scalloping_loss_db(name) == pytest.approx(-20 * np.log10(half), abs=1e-6), name
        assert round(noise_bandwidth_bins(name), 2) == harris[name][0]
        if name == "hamming":  # Harris lists 1.78 dB; the 0.54/0.46 window's half-bin loss is 1.75 dB
            assert scalloping_loss_db(name) == pytest.approx(1.7514, abs=1e-4)
        else:
            assert round(scalloping_loss_db(name), 2) == harris[name][1]


def test_leakage_floor_is_flat_in_beat_frequency_for_short_delays():
    """For f τ ≪ 1, 𝓛(f) 4 sin²(π f τ) → 𝓛(f_0) f_0² (2π τ)²: independent of f (Stove 1992)."""
    tau, l0, f0 = 1e-9, -90.0, 1e5
    flat = -10.0 - 30.0 + l0 + 20 * math.log10(f0 * 2 * math.pi * tau) + 10 * math.log10(3e3)
    for fb in (1e4, 1e5, 1e6):
        got = float(leakage_noise_dbw(-10.0, 30.0, l0, f0, fb, tau, 3e3))
        assert got == pytest.approx(flat, abs=2e-4 * (fb / 1e6) ** 2 + 1e-9)


# --- gradients -------------------------------------------------------------------------------


@pytest.mark.parametrize("output", ["snr_db", "sinr_db", "detection_margin_db", "oversampling_ratio", "pd",
                                    "range_doppler_error_m", "nyquist_margin_hz"])
def test_gradients_match_central_differences(output):
    names = ["range_m", "transmit_power_w", "sweep_bandwidth_hz", "sweep_time_s", "antenna_diameter_m",
             "sampling_rate_hz", "fft_size", "radial_speed_mps", "isolation_db", "leakage_delay_s", "coherent_sweeps"]
    base = complete_parameters(FULL_SCENE, dict(FULL, range_m=2000.0))
    f = evaluator(FULL_SCENE)

    def g(x):
        p = dict(base)
        p.update(dict(zip(names, x)))
        return f(p)[output]

    x0 = jnp.array([float(base[n]) for n in names])
    grad = np.asarray(jax.grad(g)(x0))
    assert np.all(np.isfinite(grad))
    for i in range(len(names)):
        h = 1e-6 * abs(float(x0[i]))
        e = jnp.zeros_like(x0).at[i].set(h)
        fd = (float(g(x0 + e)) - float(g(x0 - e))) / (2 * h)
        assert grad[i] == pytest.approx(fd, rel=1e-5, abs=1e-9 * max(1.0, abs(fd))), names[i]


# --- properties, wanted outputs, domains ----------------------------------------------------


FULL_EVAL = evaluator(FULL_SCENE)
FULL_COMPLETE = complete_parameters(FULL_SCENE, FULL)


@settings(max_examples=15, deadline=None)
@given(r1=st.floats(1.0, 5e3), r2=st.floats(1.0, 5e3))
def test_snr_and_nyquist_margin_fall_with_range(r1, r2):
    lo, hi = sorted((r1, r2))
    a = FULL_EVAL(dict(FULL_COMPLETE, range_m=jnp.asarray(lo)))
    b = FULL_EVAL(dict(FULL_COMPLETE, range_m=jnp.asarray(hi)))
    assert float(b["snr_db"]) <= float(a["snr_db"]) + 1e-12
    assert float(b["sinr_db"]) <= float(a["sinr_db"]) + 1e-12
    assert float(b["nyquist_margin_hz"]) <= float(a["nyquist_margin_hz"]) + 1e-6


def test_wanted_outputs_equal_full_evaluation():
    p = complete_parameters(FULL_SCENE, FULL)
    full = compute(FULL_SCENE, p)
    for wanted in ({"snr_db"}, {"pd"}, {"detection_margin_db", "beat_frequency_hz"}):
        part = compute(FULL_SCENE, p, wanted)
        for name in wanted:
            assert float(part[name]) == float(full[name])


def test_domain_errors():
    with pytest.raises(DomainError):
        evaluate(Scene("fmcw", [], {"window": "kaiser"}), BOOK)
    with pytest.raises(DomainError):  # "given" needs its factor
        evaluate(BOOK_SCENE, {k: v for k, v in BOOK.items() if k != "window_bandwidth_factor"})
    with pytest.raises(DomainError):
        evaluate(BOOK_SCENE, dict(BOOK, fft_size=2.0))
    with pytest.raises(DomainError):
        evaluate(Scene("fmcw", ["clutter"], {}), BOOK)
