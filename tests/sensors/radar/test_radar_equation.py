"""Tests of diffsense.sensors.radar.equation: the radar range equation and its radar-specific relations.

Independent references: 40-digit mpmath evaluations of the formulas, closed forms, the book's
worked numbers (Brooker §8.16, §9.9) and one published example of the search-radar equation.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401  (float64)
from diffsense.physics import noise, propagation
from diffsense.errors import DomainError
from diffsense.physics.constants import BOLTZMANN_J_K, SPEED_OF_LIGHT_M_S
from diffsense.physics import waveforms as wf
from diffsense.sensors.radar import equation as eq
from diffsense.sensors.radar import snr_db

MPMATH_DPS = 40  # working precision of this module's tests (set per test by tests/conftest.py)


def mp_snr_db(r, pt, tau, lam, g_db, rcs, ts, loss_db):
    """The contract formula 10 log10(Pt τ G² λ² σ / ((4π)³ k Ts R⁴ L)) in 40-digit arithmetic."""
    r, pt, tau, lam, g_db, rcs, ts, loss_db = (mp.mpf(str(x)) for x in (r, pt, tau, lam, g_db, rcs, ts, loss_db))
    g = mp.mpf(10) ** (g_db / 10)
    l = mp.mpf(10) ** (loss_db / 10)
    k = mp.mpf("1.380649e-23")
    return 10 * mp.log10(pt * tau * g**2 * lam**2 * rcs / ((4 * mp.pi) ** 3 * k * ts * r**4 * l))


CASES = [
    # range, Pt, tau, lambda, G dB, rcs, Ts, L dB
    (300e3, 5e6, 2e-6, 0.23, 36.0, 1.0, 290.0, 4.16),
    (300.0, 0.1, 20e-9, 3.19e-3, 46.2, 14.1, 290.0, 0.0),
    (1.0, 1e-3, 1e-9, 1e-3, -10.0, 1e-4, 10.0, 30.0),
    (1e7, 1e9, 1e-2, 3.0, 60.0, 1e4, 5000.0, -3.0),
]


@pytest.mark.parametrize("case", CASES)
def test_contract_snr_db_equals_mpmath_formula(case):
    got = float(snr_db(*case))
    assert abs(got - float(mp_snr_db(*case))) < 1e-11


def test_contract_snr_db_defaults_are_one_square_metre_290_k_no_loss():
    r, pt, tau, lam, g = 50e3, 1e6, 1e-6, 0.1, 30.0
    assert abs(float(snr_db(r, pt, tau, lam, g)) - float(mp_snr_db(r, pt, tau, lam, g, 1.0, 290.0, 0.0))) < 1e-11


_snr_jit = jax.jit(snr_db)
_snr_grad = jax.jit(jax.grad(snr_db, argnums=tuple(range(8))))


def test_contract_snr_db_jit_and_vmap_match_eager():
    args = CASES[0]
    assert abs(float(_snr_jit(*args)) - float(snr_db(*args))) < 1e-12
    ranges = jnp.array([1e3, 1e4, 1e5])
    batched = jax.vmap(lambda r: snr_db(r, *args[1:]))(ranges)
    for r, b in zip(ranges, batched):
        assert abs(float(b) - float(mp_snr_db(float(r), *args[1:]))) < 1e-11


def test_contract_snr_db_broadcasts():
    r = jnp.array([[1e3], [2e3], [4e3]])
    g = jnp.array([10.0, 20.0, 30.0, 40.0])
    out = snr_db(r, 1e3, 1e-6, 0.03, g)
    assert out.shape == (3, 4)
    # 40 log10 R per range doubling, 2 dB per dB of gain
    assert np.allclose(np.diff(np.asarray(out), axis=0), -40 * math.log10(2), atol=1e-12)
    assert np.allclose(np.diff(np.asarray(out), axis=1), 20.0, atol=1e-12)


@pytest.mark.parametrize("case", CASES[:2])
def test_contract_snr_db_gradient_equals_central_differences(case):
    grads = _snr_grad(*[float(x) for x in case])
    for i, x in enumerate(case):
        h = 1e-6 if i in (4, 7) else 1e-6 * abs(x)  # dB arguments: absolute step; others relative
        hi = list(case)
        lo = list(case)
        hi[i] = x + h
        lo[i] = x - h
        fd = (float(mp_snr_db(*hi)) - float(mp_snr_db(*lo))) / (2 * h)
        # mpmath differences: truncation error O(h²) ~ 1e-12 relative
        assert abs(float(grads[i]) - fd) <= 1e-7 * max(abs(fd), 1e-12) + 1e-12, (i, float(grads[i]), fd)


def test_contract_snr_db_gradient_closed_forms():
    r, pt, tau, lam, g, rcs, ts, l = CASES[0]
    d = _snr_grad(r, pt, tau, lam, g, rcs, ts, l)
    ln10 = math.log(10.0)
    expected = [-40 / (r * ln10), 10 / (pt * ln10), 10 / (tau * ln10), 20 / (lam * ln10), 2.0, 10 / (rcs * ln10), -10 / (ts * ln10), -1.0]
    for got, want in zip(d, expected):
        assert abs(float(got) - want) <= 1e-12 * abs(want)


@settings(max_examples=30, deadline=None)
@given(
    st.floats(0.0, 7.0), st.floats(-3.0, 9.0), st.floats(-9.0, -1.0), st.floats(-3.0, 0.5),
    st.floats(-50.0, 100.0), st.floats(-4.0, 4.0), st.floats(0.0, 4.0), st.floats(-50.0, 300.0),
)
def test_contract_snr_db_gradients_finite_over_domain(lr, lp, lt, ll, g, ls, lts, loss):
    args = (10.0**lr, 10.0**lp, 10.0**lt, 10.0**ll, g, 10.0**ls, 10.0**lts, loss)
    assert all(np.isfinite(float(x)) for x in _snr_grad(*args))
    assert np.isfinite(float(_snr_jit(*args)))


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(range_m=0.0), dict(range_m=-5.0), dict(peak_power_w=0.0), dict(pulse_width_s=-1e-6),
        dict(wavelength_m=0.0), dict(gain_db=120.0), dict(rcs_m2=0.0), dict(system_temp_k=0.0),
        dict(loss_db=400.0), dict(range_m=float("nan")),
    ],
)
def test_contract_snr_db_rejects_out_of_domain(kwargs):
    args = dict(range_m=1e3, peak_power_w=1e3, pulse_width_s=1e-6, wavelength_m=0.03, gain_db=30.0)
    args.update(kwargs)
    with pytest.raises(DomainError):
        snr_db(**args)


def test_energy_form_equals_peak_power_form_with_matched_bandwidth():
    # SNR = Pt τ ... / (k T0 ...) equals Pr / (k T0 β F) with β = 1/τ, F = 1 (identity of the forms)
    r, pt, tau, lam, g, rcs, l = 80e3, 2e5, 1e-6, 0.1, 33.0, 3.0, 2.5
    peak = eq.snr_peak_power_db(r, pt, g, lam, 1.0 / tau, 0.0, rcs, l)
    assert abs(float(peak) - float(snr_db(r, pt, tau, lam, g, rcs, 290.0, l))) < 1e-11
    assert abs(float(eq.snr_energy_db(r, pt * tau, lam, g, rcs, 290.0, l)) - float(snr_db(r, pt, tau, lam, g, rcs, 290.0, l))) < 1e-11


def test_received_power_air_surveillance_book_9_9_1_2():
    # Pr = 65 + 2x36 - 45.7 + 0 - 4.16 - 40 log10 R = 87.14 - 40 log10 R dBW. Book rounds
    # 10 log10(λ²/(4π)³) to -45.7 (exact -45.74 for λ = 0.23 m): tolerance 0.06 dB.
    pt = 10 ** (65 / 10)  # radiated power after the 2 dB transmit line
    for r in (1e4, 1e5, 3.5e5):
        got = float(eq.received_power_dbw(r, pt, 36.0, 0.23, 1.0, 4.16))
        assert abs(got - (87.14 - 40 * math.log10(r))) < 0.06


def test_snr_air_surveillance_book_9_9_1_3():
    # SNR = 230.1 - 40 log10 R; noise -149 + 4 + 2 = -143 dBW. The book rounds 10 log10(kTβ)
    # = -149.11 dBW to -149 and λ²/(4π)³ to -45.7: together 0.2 dB at most.
    pt = 10 ** (65 / 10)
    for r in (1e4, 3.5e5):
        got = float(eq.snr_peak_power_db(r, pt, 36.0, 0.23, 306e3, 4.0, 1.0, 4.16, receive_loss_db=2.0))
        assert abs(got - (230.1 - 40 * math.log10(r))) < 0.2


def test_received_power_ore_pass_book_8_16_11():
    # Pr = 18.8 + 2x46 - 82.9 + 11.5 - 99 = -59.6 dBm (book rounds 40 log10 300 = 99.08 to 99
    # and uses c = 3e8 for λ): tolerance 0.1 dB.
    lam = 3e8 / 94e9
    got = float(eq.received_power_dbm(300.0, 10 ** (18.8 / 10) / 1e3, 46.0, lam, 10 ** 1.15))
    assert abs(got - (-59.6)) < 0.1


def test_pulse_compression_gain_closed_form():
    assert abs(float(wf.pulse_compression_gain_db(100e6, 10e-6)) - 30.0) < 1e-12
    assert abs(float(wf.pulse_compression_gain_db(1e6, 1e-6))) < 1e-12


def test_search_radar_equation_published_example():
    # Published example (MathWorks radareqsearchpap documentation): R = 111 km, SNR 13 dB,
    # Ts = 487 K, L = 20 dB, 12.5 rpm (ts = 4.8 s), Ω = 2π sin 45° sr (az ±180°, el 0-45°)
    # needs Pav·Ae = 2.3689e4 W m². Printed to 5 digits (2e-5 relative = 1e-4 dB).
    omega = 2 * math.pi * math.sin(math.radians(45.0))
    got = float(eq.search_radar_snr_db(111e3, 2.3689e4, 1.0, omega, 60 / 12.5, 1.0, 487.0, 20.0))
    assert abs(got - 13.0) < 2e-4


def test_search_radar_equation_equals_mpmath_formula():
    r, pav, ae, om, ts, rcs, t, l = 150e3, 5e3, 3.0, 2.0, 10.0, 2.0, 500.0, 6.0
    f = [mp.mpf(str(x)) for x in (r, pav, ae, om, ts, rcs, t, l)]
    want = 10 * mp.log10(f[1] * f[2] * f[5] * f[4] / (4 * mp.pi * f[3] * mp.mpf("1.380649e-23") * f[6] * mp.mpf(10) ** (f[7] / 10) * f[0] ** 4))
    assert abs(float(eq.search_radar_snr_db(r, pav, ae, om, ts, rcs, t, l)) - float(want)) < 1e-11


def test_rain_clutter_scr_book_9_9_3():
    # η = 1e-7, 0.02 x 0.07 rad, 2 µs, α = 1.33: σ_clut = 1.86e-8 R²; at 1274 m SCR = 15.2 dB
    # (book rounds the coefficient to 3 digits and uses c = 3e8): tolerance 0.02 dB.
    got = float(eq.volume_clutter_scr_db(1.0, 1e-7, 1274.0, 0.02, 0.07, 2e-6))
    assert abs(got - 15.2) < 0.02
    # the clutter grows as R²: 20 log10 per decade
    d = float(eq.volume_clutter_scr_db(1.0, 1e-7, 100.0, 0.02, 0.07, 2e-6) - eq.volume_clutter_scr_db(1.0, 1e-7, 1000.0, 0.02, 0.07, 2e-6))
    assert abs(d - 20.0) < 1e-10


def test_rain_clutter_scr_uses_marshall_palmer_rayleigh_reflectivity():
    # η = π⁵ |K|² (200 R^1.6 1e-18) / λ⁴ with |K|² = 0.93 (closed form, mpmath)
    rate, lam = 50.0, 0.23
    eta = mp.pi**5 * mp.mpf("0.93") * 200 * mp.mpf(rate) ** mp.mpf("1.6") * mp.mpf("1e-18") / mp.mpf(lam) ** 4
    want = float(eq.volume_clutter_scr_db(1.0, float(eta), 1000.0, 0.02, 0.07, 2e-6))
    assert abs(float(eq.rain_clutter_scr_db(1.0, rate, lam, 1000.0, 0.02, 0.07, 2e-6)) - want) < 1e-10


def test_dust_clutter_scr_book_eq_8_45():
    lam, vis = 3.19e-3, 20.0
    eta = mp.pi**5 * mp.mpf("0.3431472760099732") * mp.mpf("1.125e-19") / (mp.mpf(lam) ** 4 * mp.mpf(vis) ** mp.mpf("1.07"))
    want = float(eq.volume_clutter_scr_db(10.0, float(eta), 300.0, 0.0156, 0.0156, 20e-9))
    assert abs(float(eq.dust_clutter_scr_db(10.0, vis, lam, 300.0, 0.0156, 0.0156, 20e-9)) - want) < 1e-10


def test_sea_clutter_pulse_limited_closed_form():
    # Pulse-limited cell (beam-limited area 18 dB larger, so the smooth minimum is within
    # 1e-3 dB): σ_c = σ° R θ_az (c τ/2) / cos ψ, ψ over the 4/3 earth from the law of cosines
    # (sin ψ = (2 k a h + h² − R²)/(2 k a R), 2.86° here). Constant γ: σ° = γ sin ψ with Barton's
    # γ, sea state 3 = 15 kn (book Table 12.2) -> Beaufort (v/0.836)^(2/3); NRL: the published
    # formula (Gregers-Hansen & Mital 2012) with its horizontal coefficients.
    r, h, az, el, tau, lam = 2e3, 100.0, 0.02, 0.05, 0.2e-6, 0.03
    ka = 4 / 3 * 6371e3
    psi = math.asin((2 * ka * h + h * h - r * r) / (2 * ka * r))
    assert math.degrees(psi) == pytest.approx(math.degrees(math.asin(h / r)) - math.degrees(r / (2 * ka)), abs=1e-4)
    kb = (15 * 1852 / 3600 / 0.836) ** (2 / 3)
    gamma = 10 ** ((6 * kb - 10 * math.log10(lam) - 64) / 10)
    a_pulse = r * az * SPEED_OF_LIGHT_M_S * tau / 2 / math.cos(psi)
    a_beam = r * r * az * el / math.sin(psi)
    assert 10 * math.log10(a_beam / a_pulse) > 10.0
    want = gamma * math.sin(psi) * a_pulse
    got = float(eq.sea_clutter_rcs_m2(r, h, az, el, tau, lam, 3.0, "constant_gamma"))
    assert abs(10 * math.log10(got / want)) < 1e-3
    assert abs(float(eq.sea_clutter_scr_db(5.0, r, h, az, el, tau, lam, 3.0, "constant_gamma"))
               - 10 * math.log10(5.0 / got)) < 1e-10
    f_ghz, d = SPEED_OF_LIGHT_M_S / lam / 1e9, math.degrees(psi)
    nrl_db = (-73.0 + 20.781 * math.log10(math.sin(psi)) + (27.5 + 7.351 * d) * math.log10(f_ghz) / (1 + 0.95 * d)
              + 25.65 * 4.0 ** (1 / (2 + 0.085 * d + 0.033 * 3.0)) + 0.0054 * d * d)
    got_nrl = float(eq.sea_clutter_rcs_m2(r, h, az, el, tau, lam, 3.0))
    assert abs(10 * math.log10(got_nrl / (10 ** (nrl_db / 10) * a_pulse))) < 1e-3


def test_sea_clutter_models_enforce_their_domains():
    # constant γ only in its plateau region (1°-60°): an 8 m mast at 5 km sees 0.075°
    with pytest.raises(DomainError, match="constant-gamma"):
        eq.sea_clutter_rcs_m2(5e3, 8.0, 0.02, 0.05, 0.2e-6, 0.03, 3.0, "constant_gamma")
    assert float(eq.sea_clutter_rcs_m2(5e3, 8.0, 0.02, 0.05, 0.2e-6, 0.03, 3.0)) > 0.0  # NRL continued below 0.1°
    with pytest.raises(DomainError, match="NRL"):
        eq.sea_clutter_rcs_m2(5e3, 8.0, 0.02, 0.05, 0.2e-6, 3e8 / 94e9, 3.0)  # 94 GHz: above 35 GHz
    with pytest.raises(DomainError, match="NRL"):
        eq.sea_clutter_rcs_m2(120.0, 110.0, 0.02, 0.05, 0.2e-6, 0.03, 3.0)  # grazing 66° > 60°


def test_wall_clutter_book_8_16_6():
    # π d ΔR = 37.7 m² (15.8 dBm²), σ° = -10 dB -> 5.8 dBm²; SCR = 11.5 - 5.8 = 5.7 dB when the
    # beam fills the pass. Book rounds to 0.1 dB: tolerance 0.05 dB.
    sc = float(eq.wall_clutter_rcs_m2(6.0, 2.0, -10.0))
    assert abs(10 * math.log10(sc) - 5.8) < 0.05
    assert abs(float(eq.wall_clutter_scr_db(10 ** 1.15, 6.0, 2.0, -10.0)) - 5.7) < 0.05


def test_wall_illumination_gaussian_beam_closed_form():
    r, d, th = 300.0, 6.0, math.radians(0.893)
    want = math.exp(-8 * math.log(2) * (math.atan(d / (2 * r)) / th) ** 2)
    assert abs(float(eq.wall_illumination_factor(r, d, th)) - want) < 1e-14
    # a beam much wider than the pass sees the whole wall: factor -> 1
    assert float(eq.wall_illumination_factor(300.0, 6.0, 1.0)) > 0.999


def test_signal_to_jamming_equals_required_at_burn_through_range():
    # S/J = required ratio exactly at noise.self_screening_burn_through_range_m (derived there
    # from S/J = Pt G σ β_j / (4π P_j G_j β_r R²), without λ): two independent forms agree.
    pt, g, rcs, pj, gj, bj, br, req = 1e6, 35.0, 5.0, 100.0, 3.0, 50e6, 1e6, 12.0
    rbt = float(noise.self_screening_burn_through_range_m(pt, g, rcs, pj, gj, bj, br, req))
    got = float(eq.signal_to_jamming_db(rbt, pt, g, 0.03, rcs, 0.0, pj, gj, bj, br))
    assert abs(got - req) < 1e-9
    # self-screening: S/J falls as R² (20 dB per decade)
    s1 = float(eq.signal_to_jamming_db(1e3, pt, g, 0.03, rcs, 0.0, pj, gj, bj, br))
    s2 = float(eq.signal_to_jamming_db(1e4, pt, g, 0.03, rcs, 0.0, pj, gj, bj, br))
    assert abs(s1 - s2 - 20.0) < 1e-10


def test_jamming_power_band_limited_by_the_narrower_band():
    args = (100.0, 3.0, 30.0, 0.03, 50e3)
    nj = float(noise.jammer_noise_density_w_hz(*args, 10e6))
    assert abs(float(eq.jamming_power_w(*args, 10e6, 1e6)) / (nj * 1e6) - 1) < 1e-14
    assert abs(float(eq.jamming_power_w(*args, 10e6, 20e6)) / (nj * 10e6) - 1) < 1e-14


def test_multipath_factor_matches_propagation_model_at_integer_sea_states():
    for ss in (1, 3, 5):
        a = float(eq.multipath_factor_db(8e3, 10.0, 5.0, 10e9, float(ss)))
        b = float(propagation.propagation_factor_db(8e3, 10.0, 5.0, 10e9, sea_state=ss))
        assert abs(a - b) < 1e-9
    assert abs(float(eq.rms_wave_height_m(3.0)) - propagation.rms_wave_height_from_sea_state_m(3)) < 1e-15


def test_multipath_factor_gradient_in_sea_state_finite():
    g = jax.grad(lambda s: eq.multipath_factor_db(8e3, 10.0, 5.0, 10e9, s))(3.5)
    assert np.isfinite(float(g))


def test_two_way_attenuation_sums_parts():
    assert abs(float(eq.two_way_attenuation_db(353e3, 0.003)) - 2.118) < 1e-12  # book: 2.1 dB over 353 km
    assert abs(float(eq.two_way_attenuation_db(10e3, 0.01, 0.02, 0.5)) - 10.6) < 1e-12


def test_free_space_detection_range_book_9_9_1_4():
    # R = 10^((230.1 - 8.2)/40) = 352,776.8 m (book prints to 0.1 m)
    assert abs(float(eq.free_space_detection_range_m(230.1, 8.2)) - 352776.8) < 0.05


@pytest.mark.parametrize("alpha", [0.0, 0.003, 0.02])
def test_detection_range_with_attenuation_equals_mpmath_root(alpha):
    f = lambda r: mp.mpf("230.1") - 40 * mp.log10(r) - 2 * mp.mpf(str(alpha)) * r / 1000 - mp.mpf("8.2")
    want = float(mp.findroot(f, 3e5))
    res = eq.detection_range_m(230.1, 8.2, alpha)
    assert bool(res.found)
    assert abs(float(res.range_m) / want - 1) < 1e-10


def test_detection_range_book_graph_320_km():
    # book Fig. 9.24 reads 320 km off a graph for 0.003 dB/km; exact root 316.3 km: 2 % tolerance
    r = float(eq.detection_range_m(230.1, 8.2, 0.003).range_m)
    assert abs(r / 320e3 - 1) < 0.02


def test_detection_range_gradient_is_implicit_derivative():
    s0, req, a = 230.1, 8.2, 0.02
    r = float(eq.detection_range_m(s0, req, a).range_m)
    dfdr = -40 / (r * math.log(10)) - 2 * a / 1000
    g_s0, g_a = jax.grad(lambda s, al: eq.detection_range_m(s, req, al).range_m, argnums=(0, 1))(s0, a)
    assert abs(float(g_s0) - (-1.0 / dfdr)) < 1e-8 * abs(1.0 / dfdr)
    assert abs(float(g_a) - (-(-2 * r / 1000) / dfdr)) < 1e-8 * abs(2 * r / 1000 / dfdr)


def test_detection_range_outside_bracket_is_flagged():
    res = eq.detection_range_m(10.0, 20.0)  # needs R < 1 m
    assert not bool(res.found)
    assert float(res.range_m) == pytest.approx(1.0)


def test_if_gain_book_8_16_12():
    # (-75 + 13) - (-59.6 - 1.2 - 8 - 15) = 21.8 dB
    assert abs(float(eq.if_gain_required_db(-59.6, 1.2, 8.0, 15.0, -75.0, 13.0)) - 21.8) < 1e-12


def test_timing_relations_book_8_16_and_9_9():
    # PRF c/(2 Rmax) = 500 kHz for 300 m (book c = 3e8; exact c is 0.07 % lower)
    assert abs(float(wf.max_prf_hz(300.0)) / 500e3 - 1) < 1e-3
    assert abs(float(wf.max_prf_hz(300.0, 3e8)) - 500e3) < 1e-6
    assert float(wf.update_rate_hz(500e3, 16.0)) == pytest.approx(31250.0, rel=1e-15)
    assert float(wf.hits_per_scan(1.25, 360.0, 6.0)) == pytest.approx(12.5, rel=1e-15)  # book 9.9.1.1
    assert abs(float(wf.range_resolution_pulse_m(13.3e-9)) - 2.0) < 0.01  # book 8.16.3: 2 m <-> 13.3 ns
    assert abs(float(wf.unambiguous_range_m(500e3, 3e8)) - 300.0) < 1e-9


@pytest.mark.parametrize(
    "call",
    [
        lambda: eq.received_power_dbw(-1.0, 1.0, 30.0, 0.03),
        lambda: eq.search_radar_snr_db(1e3, 1.0, 1.0, 20.0, 1.0),
        lambda: eq.volume_clutter_scr_db(1.0, 0.0, 1e3, 0.02, 0.07, 1e-6),
        lambda: eq.sea_grazing_angle_rad(5.0, 10.0),
        lambda: eq.wall_clutter_rcs_m2(6.0, 2.0, 30.0),
        lambda: eq.wall_illumination_factor(300.0, 6.0, 0.0),
        lambda: wf.pulse_compression_gain_db(0.0, 1e-6),
        lambda: wf.update_rate_hz(1e3, 0.5),
        lambda: eq.detection_range_m(200.0, 10.0, -0.1),
        lambda: eq.rms_wave_height_m(9.0),
    ],
)
def test_equation_functions_reject_out_of_domain(call):
    with pytest.raises(DomainError):
        call()


def test_exact_constants_are_used():
    # 10 log10(k) with the exact SI k (the book's 1.38e-23 differs by 0.0021 dB)
    base = float(snr_db(1.0, 1.0, 1.0, 1.0, 0.0))
    assert abs(base - (-30 * math.log10(4 * math.pi) - 10 * math.log10(BOLTZMANN_J_K * 290.0))) < 1e-12


def test_waveform_relations_live_in_waveforms_only():
    # one home per relation: the radar equation module keeps no copy of the waveform relations
    removed = ("range_resolution_m", "unambiguous_range_m", "max_prf_hz", "update_rate_hz", "hits_per_scan",
               "pulse_compression_gain_db")
    assert not any(hasattr(eq, name) for name in removed)
    assert all(callable(getattr(wf, name)) for name in removed[1:] + ("range_resolution_pulse_m",))
