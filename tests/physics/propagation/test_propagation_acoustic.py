"""Acoustic propagation: sea-water and air absorption, sound speed, spreading loss.

References used by the assertions:
- Brooker, *Introduction to Sensors for Ranging and Imaging*: 12.8 (side-scan sonar,
  worked example 4), 13.20 (ultrasonic beacon, worked example 5), 8.16.2 (ore pass,
  worked example 3).
- ISO 9613-1:1993 Table 1 (pure-tone attenuation, dB/km, at 101.325 kPa, computed at the
  exact one-third-octave midbands f = 1000 * 10^(k/10) Hz, clause 6 note 5).
- Mackenzie (1981) JASA 70(3) 807: check value 1550.744 m/s at 25 deg C, 35 ppt, 1000 m.
- Ainslie & McColm (1998) JASA 103(3) 1671: their simplified formula stays within 10 % of
  Francois & Garrison from 100 Hz to 1 MHz for -6..35 deg C (S 35, pH 8, z 0),
  pH 7.7..8.3, S 5..50 ppt, z 0..7 km (the other parameters at T 10 deg C, S 35, pH 8, z 0).
- Cramer (1993) JASA 93(5) 2510, eq. for the speed of sound in air: zero-pressure,
  dry, CO2-free limit a0 + a1 t + a2 t^2, and the water-vapour term
  (a3 + a4 t + a5 t^2) x_w + a12 x_w^2.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401  (enables float64)
from diffsense.physics import propagation
from diffsense.errors import DomainError
from diffsense.physics.propagation import acoustic as ac

# Contract names go through the package; if this import fails the package __init__ does
# not re-export the acoustic module.
seawater_absorption_db_per_km = propagation.seawater_absorption_db_per_km
sound_speed_seawater = propagation.sound_speed_seawater
air_absorption_db_per_m = propagation.air_absorption_db_per_m


def central_difference(fn, x, rel_step=1e-6):
    h = rel_step * max(abs(x), 1.0)
    return (fn(x + h) - fn(x - h)) / (2.0 * h)


def assert_grad_matches_fd(fn, x, rtol=1e-5, rel_step=1e-6):
    g = float(jax.grad(fn)(jnp.float64(x)))
    fd = float(central_difference(fn, x, rel_step))
    assert math.isfinite(g)
    assert g == pytest.approx(fd, rel=rtol, abs=1e-12 * max(1.0, abs(fd)))


# --------------------------------------------------------------------------------------
# Book worked examples
# --------------------------------------------------------------------------------------


def test_side_scan_sonar_absorption_book_12_8():
    # Worked example 4: alpha = 0.036 f^2/(f^2 + 3600) + 3.2e-7 f^2 at 117 kHz = 0.0329 dB/m.
    a = float(ac.seawater_absorption_simple_db_per_m(117e3))
    assert a == pytest.approx(0.0329, abs=5e-5)  # the book prints 3 significant figures


def test_side_scan_echo_two_way_absorption_term_book_12_8():
    # E = 225.3 - 40 log10 R - 0.0656 R - 12: the range coefficient is 2 alpha (book rounds
    # alpha to 0.0328); the spreading part of 2H at R = 500 m is 40 log10 500.
    alpha = float(ac.seawater_absorption_simple_db_per_m(117e3))
    two_way = float(ac.two_way_transmission_loss_db(500.0, alpha))
    assert two_way == pytest.approx(40 * math.log10(500.0) + 0.0656 * 500.0, abs=0.2)


def test_ultrasonic_beacon_transmission_loss_book_13_20():
    # Worked example 5: H = 20 log10(3/0.3) + 1.2 x 3 = 23.6 dB; received 126 - 23.6 = 102.4 dB.
    h = float(ac.transmission_loss_db(3.0, 1.2, "spherical", reference_range_m=0.3))
    assert h == pytest.approx(23.6, abs=1e-12)
    assert 126.0 - h == pytest.approx(102.4, abs=1e-12)


def test_transmission_loss_eq_12_52_counts_absorption_from_reference():
    # Eq. 12.52: H = 20 log10(R2/R1) + alpha (R2 - R1).
    h = float(ac.transmission_loss_db(3.0, 1.2, reference_range_m=0.3, absorb_from_reference=True))
    assert h == pytest.approx(20.0 + 1.2 * 2.7, abs=1e-12)


def test_ore_pass_ultrasound_attenuation_book_8_16_2():
    # The book: a 1 m transducer with theta = 1.1 deg needs lambda <= 0.016 m, i.e. f >= 21.6 kHz
    # at c = 340 m/s, "about 0.6 dB/m one way as read from the graphs in Figure 7.16", so
    # 360 dB two-way over 300 m. The book does not state the air state in the excerpt; ISO
    # 9613-1 at 20 deg C and 50 % RH (the usual room condition) gives 0.59 dB/m. Tolerance
    # 10 %: a value read off a log-scale graph.
    wavelength = (1.1 / 70.0) * 1.0
    freq = 340.0 / wavelength
    assert freq == pytest.approx(21.6e3, rel=2e-3)
    a = float(air_absorption_db_per_m(freq, 293.15, 50.0))
    assert a == pytest.approx(0.6, rel=0.10)
    assert 2 * 300 * a == pytest.approx(360.0, rel=0.10)


# --------------------------------------------------------------------------------------
# ISO 9613-1 Table 1
# --------------------------------------------------------------------------------------

# (temperature deg C, relative humidity %, midband index k, alpha dB/km) from Table 1.
ISO_9613_1_TABLE_1 = [
    (-20, 10, -13, 0.589),
    (-20, 70, 0, 11.5),
    (-10, 50, 0, 12.9),
    (0, 15, 0, 18.3),
    (0, 100, -9, 0.354),
    (10, 70, 0, 3.66),
    (10, 10, 6, 57.3),
    (15, 70, 6, 26.4),
    (20, 50, -10, 0.294),
    (20, 70, 0, 4.98),
    (20, 10, 6, 109.0),
    (20, 100, 6, 19.4),
    (30, 70, 0, 7.41),
    (30, 10, 6, 96.0),
    (40, 70, 0, 8.66),
    (50, 10, 9, 155.0),
    (50, 70, 9, 80.3),
]


@pytest.mark.parametrize("t_c, rh, k, expected", ISO_9613_1_TABLE_1)
def test_air_absorption_iso_9613_1_table_1(t_c, rh, k, expected):
    f = 1000.0 * 10.0 ** (k / 10.0)
    got = 1000.0 * float(air_absorption_db_per_m(f, t_c + 273.15, rh, 101.325))
    # Table 1 prints three significant figures: half a unit in the last place is <= 0.9 %.
    assert got == pytest.approx(expected, rel=0.009)


def test_air_absorption_npl_validation_points():
    # NPL Technical Guide "Atmospheric absorption - validation data" (ISO 9613-1 Table 1
    # entries at the printed frequencies 50.12, 251.19, 1000, 10000 Hz).
    for f, t_c, rh, expected in [
        (50.12, -20, 10, 0.589),
        (251.19, 15, 70, 1.13),
        (1000.0, 45, 20, 10.1),
        (10000.0, 20, 15, 267.0),
    ]:
        got = 1000.0 * float(air_absorption_db_per_m(f, t_c + 273.15, rh))
        assert got == pytest.approx(expected, rel=0.006)


def test_air_absorption_classical_limit_at_zero_humidity_high_frequency():
    # With f >> both relaxation frequencies the relaxation terms fall as 1/f^2 relative to
    # the classical term; at 1 MHz, 20 deg C, 0 % RH: frO = 24 Hz, so alpha -> 8.686 f^2
    # [1.84e-11 + (0.01275 e^(-2239.1/T) frO + 0.1068 e^(-3352/T) frN)/f^2] (eq. 5 limit).
    t = 293.15
    f = 1.0e6
    fr_o, fr_n = 24.0, 9.0
    limit = 8.686 * (1.84e-11 * f * f + 0.01275 * math.exp(-2239.1 / t) * fr_o + 0.1068 * math.exp(-3352.0 / t) * fr_n)
    got = float(air_absorption_db_per_m(f, t, 0.0))
    assert got == pytest.approx(limit, rel=1e-6)


def test_water_vapour_concentration_at_20c_saturation():
    # ISO 9613-1 Annex B: at 20 deg C, p_sat = 2.337 kPa (WMO table value 2.339 kPa, within
    # the 0.5 % the standard claims) -> h = 100 % x 2.34/101.325 = 2.31 %.
    h = float(ac.water_vapour_molar_concentration_pct(293.15, 100.0, 101.325))
    assert h == pytest.approx(100.0 * 2.339 / 101.325, rel=5e-3)


# --------------------------------------------------------------------------------------
# Sea water
# --------------------------------------------------------------------------------------


def test_mackenzie_check_value():
    assert float(sound_speed_seawater(25.0, 35.0, 1000.0)) == pytest.approx(1550.744, abs=5e-4)


def _ainslie_mccolm_db_per_km(f_khz, t, s, z_m, ph):
    z = z_m / 1000.0
    f1 = 0.78 * math.sqrt(s / 35.0) * math.exp(t / 26.0)
    f2 = 42.0 * math.exp(t / 17.0)
    boric = 0.106 * f1 * f_khz**2 / (f_khz**2 + f1**2) * math.exp((ph - 8.0) / 0.56)
    mgso4 = 0.52 * (1 + t / 43.0) * (s / 35.0) * f2 * f_khz**2 / (f_khz**2 + f2**2) * math.exp(-z / 6.0)
    water = 0.00049 * f_khz**2 * math.exp(-(t / 27.0 + z / 17.0))
    return boric + mgso4 + water


@pytest.mark.parametrize(
    "t, s, z, ph",
    [(t, 35.0, 0.0, 8.0) for t in (-2.0, 5.0, 10.0, 20.0, 30.0)]
    + [(10.0, 35.0, 0.0, ph) for ph in (7.7, 8.3)]
    + [(10.0, s, 0.0, 8.0) for s in (5.0, 20.0, 40.0)]
    + [(10.0, 35.0, z, 8.0) for z in (1000.0, 4000.0, 7000.0)],
)
def test_francois_garrison_within_ten_percent_of_ainslie_mccolm(t, s, z, ph):
    freqs = np.geomspace(200.0, 1.0e6, 41)
    fg = np.asarray(seawater_absorption_db_per_km(freqs, t, s, z, ph))
    am = np.array([_ainslie_mccolm_db_per_km(f / 1000.0, t, s, z, ph) for f in freqs])
    assert np.max(np.abs(fg / am - 1.0)) < 0.10


def test_francois_garrison_pure_water_term_pinkerton_scale():
    # S -> 0 leaves only the viscous term A3 f^2 (boric and MgSO4 vanish with S).
    # At 0 deg C, surface, A3 = 4.937e-4 dB/(km kHz^2): 1 MHz -> 493.7 dB/km.
    got = float(seawater_absorption_db_per_km(1.0e6, 0.0, 1e-12, 0.0))
    assert got == pytest.approx(493.7, rel=1e-4)


def test_francois_garrison_boric_term_scales_with_ph():
    # Only A1 depends on pH: 10^(0.78 dpH). At 400 Hz (boric dominated) the difference of
    # two pH values isolates the boric term.
    f, t, s, z = 400.0, 4.0, 35.0, 0.0
    a8 = float(seawater_absorption_db_per_km(f, t, s, z, 8.0))
    a7 = float(seawater_absorption_db_per_km(f, t, s, z, 7.0))
    a6 = float(seawater_absorption_db_per_km(f, t, s, z, 6.0))
    # boric(pH) = B 10^(0.78 (pH - 8)); rest R is pH independent.
    # (a8 - a7)/(a7 - a6) = 10^0.78.
    assert (a8 - a7) / (a7 - a6) == pytest.approx(10**0.78, rel=1e-9)


def test_simple_and_full_seawater_absorption_agree_at_117_khz_5c():
    # The book's one-line formula is a cold-water fit: F&G at 5 deg C, 35 ppt, surface,
    # 117 kHz gives 33.5 dB/km against the book's 32.9 dB/km (2 %).
    fg = float(seawater_absorption_db_per_km(117e3, 5.0, 35.0, 0.0)) / 1000.0
    simple = float(ac.seawater_absorption_simple_db_per_m(117e3))
    assert simple == pytest.approx(fg, rel=0.05)


# --------------------------------------------------------------------------------------
# Sound speed in gases
# --------------------------------------------------------------------------------------


def test_sound_speed_gas_closed_form_mpmath():
    import mpmath as mp

    mp.mp.dps = 30
    r = mp.mpf("6.02214076e23") * mp.mpf("1.380649e-23")
    exact = mp.sqrt(mp.mpf("1.4") * r * mp.mpf("293.15") / mp.mpf("0.0289645"))
    assert float(ac.sound_speed_gas(293.15)) == pytest.approx(float(exact), rel=1e-14)


@pytest.mark.parametrize("t_c", [0.0, 10.0, 20.0, 30.0])
def test_dry_air_sound_speed_within_0p1_percent_of_cramer(t_c):
    cramer = 331.5024 + 0.603055 * t_c - 0.000528 * t_c**2
    assert float(ac.sound_speed_gas(t_c + 273.15)) == pytest.approx(cramer, rel=1e-3)


def test_book_speed_of_sound_in_air_340():
    # The book uses 340 m/s in air: the ideal-gas value between about 14 and 16 deg C.
    assert float(ac.sound_speed_gas(288.15)) == pytest.approx(340.0, abs=0.5)


@pytest.mark.parametrize("t_c", [0.0, 15.0, 30.0])
@pytest.mark.parametrize("rh", [30.0, 70.0, 100.0])
def test_humid_air_increment_matches_cramer_water_term(t_c, rh):
    t = t_c + 273.15
    x_w = float(ac.water_vapour_molar_concentration_pct(t, rh)) / 100.0
    cramer_increment = (51.471935 + 0.1495874 * t_c - 0.000782 * t_c**2) * x_w - 2.835149 * x_w**2
    ours = float(ac.sound_speed_humid_air(t, rh)) - float(ac.sound_speed_humid_air(t, 0.0))
    assert ours == pytest.approx(cramer_increment, rel=0.05)


def test_humid_air_at_zero_humidity_equals_dry_gas():
    assert float(ac.sound_speed_humid_air(293.15, 0.0)) == pytest.approx(float(ac.sound_speed_gas(293.15)), rel=1e-15)


# --------------------------------------------------------------------------------------
# Spreading
# --------------------------------------------------------------------------------------


def test_spreading_laws():
    assert float(ac.spherical_spreading_loss_db(1000.0)) == pytest.approx(60.0, abs=1e-12)
    assert float(ac.cylindrical_spreading_loss_db(1000.0)) == pytest.approx(30.0, abs=1e-12)
    # transition at 100 m: 40 dB spherical, then 10 log10(10) = 10 dB more.
    assert float(ac.cylindrical_spreading_loss_db(1000.0, 100.0)) == pytest.approx(50.0, abs=1e-12)
    assert float(ac.cylindrical_spreading_loss_db(50.0, 100.0)) == pytest.approx(20 * math.log10(50.0), abs=1e-12)
    tl = float(ac.transmission_loss_db(1000.0, 0.001, "cylindrical", transition_range_m=100.0))
    assert tl == pytest.approx(51.0, abs=1e-12)


# --------------------------------------------------------------------------------------
# jit / vmap / grad / domain
# --------------------------------------------------------------------------------------

FUNCS = {
    "fg": (lambda x: seawater_absorption_db_per_km(x, 10.0, 35.0, 500.0), 5e4),
    "fg_T": (lambda x: seawater_absorption_db_per_km(3e4, x, 35.0, 500.0), 12.0),
    "fg_S": (lambda x: seawater_absorption_db_per_km(1e3, 10.0, x, 500.0), 30.0),
    "fg_z": (lambda x: seawater_absorption_db_per_km(3e4, 10.0, 35.0, x), 800.0),
    "fg_ph": (lambda x: seawater_absorption_db_per_km(1e3, 10.0, 35.0, 0.0, x), 8.1),
    "simple": (ac.seawater_absorption_simple_db_per_m, 117e3),
    "mackenzie_T": (lambda x: sound_speed_seawater(x, 35.0, 1000.0), 12.0),
    "mackenzie_D": (lambda x: sound_speed_seawater(12.0, 35.0, x), 2000.0),
    "air_f": (lambda x: air_absorption_db_per_m(x, 293.15, 50.0), 4000.0),
    "air_T": (lambda x: air_absorption_db_per_m(4000.0, x, 50.0), 290.0),
    "air_rh": (lambda x: air_absorption_db_per_m(4000.0, 293.15, x), 40.0),
    "air_p": (lambda x: air_absorption_db_per_m(4000.0, 293.15, 50.0, x), 90.0),
    "gas": (ac.sound_speed_gas, 300.0),
    "humid": (lambda x: ac.sound_speed_humid_air(293.15, x), 40.0),
    "tl": (lambda x: ac.transmission_loss_db(x, 0.03), 150.0),
    "tl_cyl": (lambda x: ac.transmission_loss_db(x, 0.03, "cylindrical", transition_range_m=100.0), 150.0),
}


@pytest.mark.parametrize("name", sorted(FUNCS))
def test_jit_matches_eager_and_grad_matches_fd(name):
    fn, x0 = FUNCS[name]
    assert float(jax.jit(fn)(x0)) == pytest.approx(float(fn(x0)), rel=1e-13)
    assert_grad_matches_fd(fn, x0)


def test_vmap_and_broadcast():
    f = jnp.array([1e3, 1e4, 1e5])
    t = jnp.array([[2.0], [15.0]])
    out = seawater_absorption_db_per_km(f, t, 35.0, 100.0)
    assert out.shape == (2, 3)
    v = jax.jit(jax.vmap(lambda x: seawater_absorption_db_per_km(x, 15.0, 35.0, 100.0)))(f)
    np.testing.assert_allclose(v, out[1], rtol=1e-14)
    v_air = jax.jit(jax.vmap(lambda rh: air_absorption_db_per_m(4000.0, 293.15, rh)))(jnp.array([10.0, 50.0]))
    np.testing.assert_allclose(v_air, air_absorption_db_per_m(4000.0, 293.15, jnp.array([10.0, 50.0])), rtol=1e-14)
    c = jax.jit(jax.vmap(sound_speed_seawater, in_axes=(0, None, None)))(jnp.array([5.0, 25.0]), 35.0, 1000.0)
    assert float(c[1]) == pytest.approx(1550.744, abs=5e-4)


_grad_fg = jax.jit(jax.grad(seawater_absorption_db_per_km, argnums=(0, 1, 2, 3, 4)))
_grad_air = jax.jit(jax.grad(air_absorption_db_per_m, argnums=(0, 1, 2, 3)))
_grad_humid = jax.jit(jax.grad(ac.sound_speed_humid_air, argnums=(0, 1, 2)))
_grad_mackenzie = jax.jit(jax.grad(sound_speed_seawater, argnums=(0, 1, 2)))


@settings(max_examples=30, deadline=None)
@given(
    f=st.floats(200.0, 1e6),
    t=st.floats(-2.0, 30.0),
    s=st.floats(0.01, 40.0),
    z=st.floats(0.0, 10000.0),
    ph=st.floats(6.0, 9.0),
)
def test_seawater_absorption_gradient_finite(f, t, s, z, ph):
    g = _grad_fg(f, t, s, z, ph)
    assert all(np.isfinite(float(x)) for x in g)
    assert float(seawater_absorption_db_per_km(f, t, s, z, ph)) > 0.0


@settings(max_examples=30, deadline=None)
@given(
    f=st.floats(10.0, 1e6),
    t=st.floats(253.0, 324.0),
    rh=st.floats(0.0, 100.0),
    p=st.floats(1.0, 200.0),
)
def test_air_absorption_gradient_finite(f, t, rh, p):
    # Joint domain: the water-vapour mole fraction may not exceed 1.
    assume(float(ac.water_vapour_molar_concentration_pct(t, 100.0, 101.325)) * 101.325 / p * rh / 100.0 <= 100.0)
    g = _grad_air(f, t, rh, p)
    assert all(np.isfinite(float(x)) for x in g)
    gh = _grad_humid(t, rh, p)
    assert all(np.isfinite(float(x)) for x in gh)


@settings(max_examples=30, deadline=None)
@given(t=st.floats(-2.0, 30.0), s=st.floats(25.0, 40.0), d=st.floats(0.0, 8000.0))
def test_mackenzie_gradient_finite(t, s, d):
    g = _grad_mackenzie(t, s, d)
    assert all(np.isfinite(float(x)) for x in g)


@pytest.mark.parametrize(
    "call",
    [
        lambda: seawater_absorption_db_per_km(100.0, 10.0, 35.0, 0.0),
        lambda: seawater_absorption_db_per_km(1e3, 35.0, 35.0, 0.0),
        lambda: seawater_absorption_db_per_km(1e3, 10.0, 0.0, 0.0),
        lambda: seawater_absorption_db_per_km(1e3, 10.0, 35.0, -1.0),
        lambda: seawater_absorption_db_per_km(1e3, 10.0, 35.0, 0.0, 10.0),
        lambda: seawater_absorption_db_per_km(float("nan"), 10.0, 35.0, 0.0),
        lambda: ac.seawater_absorption_simple_db_per_m(0.0),
        lambda: sound_speed_seawater(10.0, 20.0, 0.0),
        lambda: sound_speed_seawater(10.0, 35.0, 9000.0),
        lambda: air_absorption_db_per_m(1e3, 200.0, 50.0),
        lambda: air_absorption_db_per_m(1e3, 293.15, 120.0),
        lambda: air_absorption_db_per_m(2e6, 293.15, 50.0),
        lambda: air_absorption_db_per_m(1e3, 293.15, 50.0, 0.0),
        lambda: air_absorption_db_per_m(1e3, 315.0, 33.0, 1.0),
        lambda: ac.sound_speed_humid_air(315.0, 33.0, 1.0),
        lambda: ac.sound_speed_gas(-1.0),
        lambda: ac.sound_speed_gas(300.0, gamma=0.9),
        lambda: ac.spherical_spreading_loss_db(0.0),
        lambda: ac.cylindrical_spreading_loss_db(10.0, 0.0),
        lambda: ac.transmission_loss_db(10.0, -0.1),
        lambda: ac.transmission_loss_db(10.0, 0.1, "plane"),
    ],
)
def test_out_of_domain_raises(call):
    with pytest.raises(DomainError):
        call()
