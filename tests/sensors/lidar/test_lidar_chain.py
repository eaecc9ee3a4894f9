"""The lidar chain through the public API: ``evaluate(Scene("lidar", ...), params)``.

References used by the assertions:
- Brooker §8.16.2 (worked_examples.md §3, ore pass): dust mass loading M = 37.3·V^−1.07 =
  1.5 g/m³ at 20 m visibility, laser extinction 0.1–0.43 (dB/km)/(mg/m³) → 150–645 dB/km one
  way, at least 90 dB two-way over 300 m: "impractical" for a 10–300 m rangefinder.
- Kim, McArthur & Korevaar (2001) haze extinction, the extended-target laser range equation
  (Jelalian 1992), Brooker §9.1.3 photodiode noise, the single-pole pulse response and the
  Gaussian threshold statistics: closed forms evaluated independently in mpmath.
- The optimum APD gain: the maximum of the chain's own SNR over the gain (numeric optimum).
- Gradients: float64 central differences of the chain.
"""

import math

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.scene import CHAINS, complete_parameters, evaluate, output_table, parameter_table
from diffsense.sensors.parts import traced_parts
from diffsense.physics.constants import BOLTZMANN_J_K, ELEMENTARY_CHARGE_C, PLANCK_J_S, SPEED_OF_LIGHT_M_S
from diffsense.scene import Scene
from diffsense.design.units import registry

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)
Q = mp.mpf(ELEMENTARY_CHARGE_C)
KB = mp.mpf(BOLTZMANN_J_K)
HC = mp.mpf(PLANCK_J_S) * mp.mpf(SPEED_OF_LIGHT_M_S)
LN10 = math.log(10.0)

SCENE = Scene("lidar", ["haze", "dust", "sun"])  # APD, extended target (defaults)
BATCH = 16


_EVAL = jax.jit(jax.vmap(lambda p: CHAINS["lidar"].compute(SCENE, p)))


def _stack(rows):
    full = [complete_parameters(SCENE, r) for r in rows]
    return {k: jnp.asarray([float(f[k]) for f in full]) for k in full[0]}


def _run(rows):
    """Evaluate parameter rows through jit(vmap(chain)) as one batch of 16 (one compiled shape)."""
    rows = list(rows) + [rows[-1]] * (BATCH - len(rows))
    return _EVAL(_stack(rows))


def _book_k(db_per_km_per_mg_m3):
    """The book's (dB/km)/(mg/m³) as the chain's mass extinction coefficient (m²/g)."""
    return db_per_km_per_mg_m3 * LN10 / 10.0


# --------------------------------------------------------------------------------------
# Book: the ore-pass laser is rejected because of dust (Brooker 8.16.2)
# --------------------------------------------------------------------------------------


def test_ore_pass_dust_rejects_laser_book_8_16():
    rows = [
        dict(range_m=300.0, dust_visibility_m=20.0, dust_mass_extinction_m2_g=_book_k(0.1)),
        dict(range_m=300.0, dust_visibility_m=20.0, dust_mass_extinction_m2_g=_book_k(0.43)),
        dict(range_m=300.0, dust_visibility_m=20.0, dust_mass_extinction_m2_g=0.0),
    ]
    ev = _run(rows)
    dust = -np.asarray(ev.budget["dust (two-way)"])
    m = 37.3 * mp.power(20, -1.07)  # 1.5123 g/m³; the book prints 1.5
    for i, k_book in enumerate((0.1, 0.43)):
        one_way_db_km = dust[i] / 0.6
        assert one_way_db_km == pytest.approx(float(k_book * 1000 * m), rel=1e-12)
        # book: 150 and 645 dB/km one way with M rounded to 1.5 (0.8 % rounding)
        assert one_way_db_km == pytest.approx((150.0, 645.0)[i], rel=0.01)
    # "a minimum two-way attenuation of 90 dB" (book rounds M to 1.5: 90.0; unrounded 90.74)
    assert dust[0] >= 90.0
    assert dust[2] == 0.0
    # the laser rangefinder of the default design reaches 300 m in clear air but not in the dust
    margin = np.asarray(ev["snr_margin_db"])
    assert margin[2] > 0.0 > margin[0] > margin[1]
    assert float(ev["detection_range_m"][0]) < 300.0 < float(ev["detection_range_m"][2])


# --------------------------------------------------------------------------------------
# Closed forms through the chain
# --------------------------------------------------------------------------------------


def _mp_kim_db_per_m(vis_m, lam):
    v = mp.mpf(vis_m) / 1000
    # Kim et al. (2001) size-distribution exponent q(V), V in km
    if v > 50:
        q = mp.mpf("1.6")
    elif v > 6:
        q = mp.mpf("1.3")
    elif v > 1:
        q = mp.mpf("0.16") * v + mp.mpf("0.34")
    elif v > mp.mpf("0.5"):
        q = v - mp.mpf("0.5")
    else:
        q = mp.mpf(0)
    return 10 / mp.log(10) * mp.mpf("3.912") / v * mp.power(mp.mpf(lam) / mp.mpf("550e-9"), -q) / 1000


CASES = [
    dict(range_m=150.0, visibility_m=23e3, dust_visibility_m=200.0, apd_gain=50.0, bandwidth_hz=3e7),
    dict(range_m=40.0, visibility_m=3e3, dust_visibility_m=50.0, apd_gain=200.0, wavelength_m=1.55e-6,
         ionization_ratio=0.4, solar_irradiance_w_m2_nm=0.2699, incidence_rad=0.7, reflectivity=0.12),
    dict(range_m=900.0, visibility_m=800.0, dust_visibility_m=2e3, apd_gain=10.0, pulse_width_s=4e-9,
         receiver_fov_rad=1e-2, n_pulses=7.0),
]


def test_chain_matches_range_equation_noise_and_statistics_closed_forms():
    ev = _run(CASES)
    for i, case in enumerate(CASES):
        p = {k: mp.mpf(float(v)) for k, v in complete_parameters(SCENE, case).items()}
        r = p["range_m"]
        ar = mp.pi * p["receiver_diameter_m"] ** 2 / 4
        haze = 2 * r * _mp_kim_db_per_m(p["visibility_m"], p["wavelength_m"])
        mass = mp.mpf("37.3") * mp.power(p["dust_visibility_m"], mp.mpf("-1.07"))
        dust = 2 * r * p["dust_mass_extinction_m2_g"] * 10 / mp.log(10) * mass  # dB/m per g/m³ x M
        t2 = mp.power(10, -(haze + dust) / 10)
        pr = (p["peak_power_w"] * p["reflectivity"] * mp.cos(p["incidence_rad"]) * ar * t2
              * p["transmit_efficiency"] * p["receive_efficiency"] / (mp.pi * r * r))
        assert float(ev["received_power_w"][i]) == pytest.approx(float(pr), rel=1e-11)
        assert float(ev["path_loss_db"][i]) == pytest.approx(float(haze + dust), rel=1e-12)
        # solar background from the sunlit target filling the field of view, one-way path
        omega = 2 * mp.pi * (1 - mp.cos(p["receiver_fov_rad"] / 2))
        pb = (p["solar_irradiance_w_m2_nm"] * p["filter_bandwidth_m"] * 10**9 * p["reflectivity"] / mp.pi * omega
              * ar * p["receive_efficiency"] * mp.sqrt(t2))
        assert float(ev["background_power_w"][i]) == pytest.approx(float(pb), rel=1e-11)
        # APD noise (Brooker 9.1.3 with McIntyre F) and the single-pole pulse response
        resp = p["quantum_efficiency"] * Q * p["wavelength_m"] / HC
        m, k, bw = p["apd_gain"], p["ionization_ratio"], p["bandwidth_hz"]
        f = k * m + (1 - k) * (2 - 1 / m)

        def var(ps):
            return (2 * Q * (resp * (ps + pb) + p["dark_current_a"]) * m**2 * f * bw
                    + 4 * KB * p["receiver_temperature_k"] * bw / p["load_resistance_ohm"]
                    + p["amplifier_noise_a_rthz"] ** 2 * bw)

        snr = (resp * m * pr) ** 2 / var(pr) * (1 - mp.exp(-4 * bw * p["pulse_width_s"])) ** 2
        assert float(ev["snr_db"][i]) == pytest.approx(float(10 * mp.log10(snr)), abs=1e-9)
        assert float(ev["nep_w"][i]) == pytest.approx(float(mp.sqrt(var(pr)) / (resp * m)), rel=1e-11)
        # the budget terms add up to the SNR; the optical terms to the received power
        terms = ev.budget.as_dict()
        assert float(sum(v[i] for v in terms.values())) == pytest.approx(float(ev["snr_db"][i]), abs=1e-10)
        optical = sum(v[i] for name, v in terms.items() if name not in (
            "noise-equivalent power", "square-law detection (SNR ~ P_r^2)", "pulse response (receiver filter)"))
        assert float(optical) + 30.0 == pytest.approx(float(ev["received_power_dbm"][i]), abs=1e-10)
        # threshold statistics with the signal shot noise (σ0/σ1) and N averaged pulses
        ratio = mp.sqrt(var(0) / var(pr))
        zfa = mp.sqrt(2) * mp.erfinv(1 - 2 * p["pfa"])
        zd = mp.sqrt(2) * mp.erfinv(2 * p["pd"] - 1)
        req = 20 * mp.log10(zd + ratio * zfa) - 10 * mp.log10(p["n_pulses"])
        assert float(ev["required_snr_db"][i]) == pytest.approx(float(req), abs=1e-9)
        pd = mp.erfc((ratio * zfa - mp.sqrt(p["n_pulses"] * snr)) / mp.sqrt(2)) / 2
        assert float(ev["pd"][i]) == pytest.approx(float(pd), abs=1e-12)
        assert float(ev["range_resolution_m"][i]) == pytest.approx(float(p["pulse_width_s"]) * SPEED_OF_LIGHT_M_S / 2,
                                                                     rel=1e-15)
        # the photoelectron count per pulse η P_r τ/(h ν)
        assert float(ev["signal_photoelectrons"][i]) == pytest.approx(
            float(p["quantum_efficiency"] * pr * p["pulse_width_s"] * p["wavelength_m"] / HC), rel=1e-11)


def test_detection_range_is_where_the_margin_vanishes():
    ev = _run(CASES)
    back = _run([dict(c, range_m=float(ev["detection_range_m"][i])) for i, c in enumerate(CASES)])
    for i, case in enumerate(CASES):
        assert float(back["snr_margin_db"][i]) == pytest.approx(0.0, abs=1e-8)
        assert float(back["pd"][i]) == pytest.approx(float(complete_parameters(SCENE, case)["pd"]), abs=1e-9)


def test_optimum_apd_gain_maximises_the_chain_snr():
    base = dict(range_m=200.0, visibility_m=5e3, dust_visibility_m=500.0, ionization_ratio=0.05)
    m_opt = float(_run([base])["optimum_apd_gain"][0])
    assert 1.0 < m_opt < 1e4
    factors = np.exp(np.concatenate([np.linspace(-0.3, 0.3, 13), [1e-5, -1e-5]]))
    ev = _run([dict(base, apd_gain=m_opt * f) for f in factors])
    snr = np.asarray(ev["snr_db"][:15])
    assert int(np.argmax(snr[:13])) == 6  # the closed-form gain is the best of the scan
    # and the SNR is stationary there: central difference in ln M below 1e-7 dB, while 10 %
    # away the slope is of order 0.1 dB
    slope = (snr[13] - snr[14]) / 2e-5
    assert abs(slope) < 1e-7
    assert abs(snr[7] - snr[5]) / 0.1 > 1e-4 or abs(snr[8] - snr[6]) > 1e-4
    # the chain reports the closed form at its own operating point
    assert float(ev["optimum_apd_gain"][6]) == pytest.approx(m_opt, rel=1e-12)


# --------------------------------------------------------------------------------------
# jit + vmap + grad
# --------------------------------------------------------------------------------------

ALL_OUTPUTS = tuple(sorted(output_table(SCENE)))
OUTS = ("snr_margin_db", "detection_range_m", "pd", "received_power_dbm", "snr_db")
OUT_INDEX = [ALL_OUTPUTS.index(name) for name in OUTS]


def _outputs(p):
    ev = CHAINS["lidar"].compute(SCENE, p)
    return jnp.stack([ev[name] for name in ALL_OUTPUTS])


_JAC = jax.jit(jax.vmap(jax.jacfwd(_outputs)))


def _values(ev, n):
    return np.stack([np.asarray(ev[name][:n]) for name in ALL_OUTPUTS], axis=1)


FD_PARAMS = ("range_m", "peak_power_w", "apd_gain", "visibility_m", "dust_visibility_m", "receiver_diameter_m",
             "pd")


def test_chain_jit_vmap_grad_match_central_differences():
    bases = [dict(range_m=120.0, dust_visibility_m=300.0, visibility_m=4e3, pd=0.8),
             dict(range_m=35.0, dust_visibility_m=60.0, visibility_m=900.0, apd_gain=30.0, pd=0.95)]
    jac = _JAC(_stack(bases))
    vals = _values(_run(bases), 2)  # jit(vmap(chain)) values
    for b, base in enumerate(bases):
        p0 = complete_parameters(SCENE, base)
        rows = []
        steps = {}
        for name in FD_PARAMS:
            x = float(p0[name])
            h = 1e-6 * x
            steps[name] = h
            rows += [dict(base, **{name: x + h}), dict(base, **{name: x - h})]
        fd_vals = _values(_run(rows), len(rows))
        f0 = np.abs(np.asarray(vals[b]))[OUT_INDEX]
        for n, name in enumerate(FD_PARAMS):
            fd = (np.asarray(fd_vals[2 * n]) - np.asarray(fd_vals[2 * n + 1]))[OUT_INDEX] / (2 * steps[name])
            g = np.asarray(jac[name][b])[OUT_INDEX]
            assert np.all(np.isfinite(g))
            # central-difference error: round-off (and root tolerance) ~1e-14 |f| / h, truncation ~h²
            tol = 2e-5 * np.maximum(np.abs(g), np.abs(fd)) + 1e-12 * (1 + f0) / steps[name]
            assert np.all(np.abs(g - fd) <= tol), (name, b, g, fd)


DOMAIN = {name: prm for name, prm in parameter_table(SCENE).items()}


def _draw_row(data):
    """One parameter set drawn over the documented domain (log-uniform on wide positive ranges)."""
    row = {}
    for name, prm in DOMAIN.items():
        lo, hi = prm.lo, prm.hi
        u = data.draw(st.floats(0.0, 1.0))
        if lo > 0 and hi / lo > 100:
            x = math.exp(math.log(lo) + u * (math.log(hi) - math.log(lo)))
        elif name in ("dark_current_a", "amplifier_noise_a_rthz"):  # [0, hi]: 0 or 12 decades below hi
            x = hi * 10 ** (-12 * (1 - u)) if u > 0 else 0.0
        else:
            x = lo + u * (hi - lo)
        if prm.hi_open and x >= hi:
            x = hi - 1e-9 * (hi - lo)
        row[name] = min(max(x, lo), hi)
    row["pfa"] = min(row["pfa"], 0.5 * row["pd"])
    return row


@settings(max_examples=8, deadline=None)
@given(data=st.data())
def test_values_and_gradients_finite_over_the_domain(data):
    rows = [_draw_row(data), _draw_row(data)]
    jac = _JAC(_stack(rows))
    vals = _values(_run(rows), 2)
    assert np.all(np.isfinite(vals)), rows
    for name, g in jac.items():
        assert np.all(np.isfinite(np.asarray(g))), (name, rows)


# --------------------------------------------------------------------------------------
# Structure: parts traced, parameters, outputs, domain errors
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("parts", [(), ("dust",), ("haze", "sun"), ("haze", "dust", "sun")])
def test_absent_parts_are_not_traced(parts):
    scene = Scene("lidar", parts, {"detector": "pin"})
    p = complete_parameters(scene, {"range_m": 100.0})
    jx = jax.make_jaxpr(lambda q: evaluate(scene, q).values)(p)
    assert traced_parts(jx) == set(parts)


def test_parameters_and_outputs_follow_the_scene():
    ureg = registry()
    plain = parameter_table(Scene("lidar", [], {"detector": "pin"}))
    assert not {"visibility_m", "dust_visibility_m", "solar_irradiance_w_m2_nm", "apd_gain", "lo_power_w",
                "target_area_m2", "beam_divergence_rad"} & set(plain)
    full = parameter_table(Scene("lidar", ["haze", "dust", "sun"], {"target": "point"}))
    assert {"visibility_m", "dust_visibility_m", "dust_mass_extinction_m2_g", "solar_irradiance_w_m2_nm",
            "filter_bandwidth_m", "receiver_fov_rad", "background_reflectivity", "apd_gain", "ionization_ratio",
            "target_area_m2", "beam_divergence_rad"} <= set(full)
    assert full["visibility_m"].part == "haze" and full["dust_visibility_m"].part == "dust"
    assert full["n_pulses"].integer
    het = parameter_table(Scene("lidar", [], {"detector": "heterodyne"}))
    assert {"lo_power_w", "mixing_efficiency"} <= set(het) and "apd_gain" not in het
    for table in (plain, full, het):
        for prm in table.values():
            ureg(prm.unit)  # every unit string is understood by pint
            assert prm.doc
    # the default dust extinction is the book's optimistic 0.1 (dB/km)/(mg/m³)
    assert full["dust_mass_extinction_m2_g"].default == pytest.approx(0.1 * LN10 / 10, rel=1e-15)
    # outputs: the evaluation returns exactly the documented outputs
    scene = Scene("lidar", ["haze", "sun"], {"target": "point"})
    out = jax.eval_shape(lambda q: evaluate(scene, q).values, complete_parameters(scene, {"range_m": 50.0}))
    assert set(out) == set(output_table(scene))
    assert {"crossover_range_m", "background_power_w", "path_loss_db", "optimum_apd_gain"} <= set(out)


def test_domain_errors():
    with pytest.raises(DomainError):
        evaluate(Scene("lidar", ["rain"]), range_m=10.0)
    with pytest.raises(DomainError):
        evaluate(Scene("lidar", [], {"detector": "spad"}), range_m=10.0)
    with pytest.raises(DomainError):
        evaluate(Scene("lidar", [], {"colour": "red"}), range_m=10.0)
    with pytest.raises(DomainError):  # a steady-signal threshold model cannot take Swerling 1
        evaluate(Scene("lidar", [], {"swerling": 1}), range_m=10.0)
    with pytest.raises(DomainError):
        evaluate(Scene("lidar"), range_m=10.0, reflectivity=1.5)
    with pytest.raises(DomainError):
        evaluate(Scene("lidar"), range_m=0.0)
    with pytest.raises(DomainError):
        evaluate(Scene("lidar"), range_m=10.0, pd=0.3)
    with pytest.raises(DomainError):
        evaluate(Scene("lidar"))  # range_m is required
    with pytest.raises(DomainError):
        evaluate(Scene("lidar"), range_m=10.0, visibility_m=1e4)  # haze absent: unknown parameter
    with pytest.raises(DomainError):
        evaluate(Scene("lidar", ["dust"]), range_m=10.0, dust_visibility_m=0.5)
