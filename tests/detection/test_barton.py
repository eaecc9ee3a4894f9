"""Barton's universal equations (``required_snr_db(method="barton")``) against the 50-digit
mpmath reference (tests/data/detection_reference.json and live ``required_snr_mp``), the exact
method, closed forms, and DiFranco & Rubin's published 13.18 dB; and the radar option
``detectability`` with the approximations ("shnidman", "albersheim", "barton").

The error bounds asserted are the ones :mod:`diffsense.detection.barton` states (its table); the
grid's worst points reach them, so the tests fail if the equations or the reference change.
"""

import json
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from diffsense import detection as det
from diffsense.detection.barton import BARTON_DOMAIN, barton_snr_db
from diffsense.errors import DomainError
from diffsense.scene import Scene, evaluate
from helpers.paths import DATA
from tests.reference import mp_detection as ref

ROWS = [r for r in json.loads((DATA / "detection_reference.json").read_text())["required_snr"]
        if 1e-12 <= r["pfa"] <= 1e-2 and r["n"] <= 100]

#: the module docstring's table: worst |error| (dB) for Pfa <= 1e-3, for Pd >= 0.5 with
#: Pfa <= 1e-4, and over the whole domain (reached at Pd = 0.1, Pfa = 1e-2, n = 100)
BOUND_PFA_1E3 = {0: 0.70, 1: 0.55, 3: 0.66, 4: 1.16}
BOUND_HIGH_PD = {0: 0.38, 1: 0.09, 3: 0.11, 4: 0.47}
BOUND_DOMAIN = {0: 1.31, 1: 1.21, 3: 1.37, 4: 2.49}


def _grid(sw):
    rows = [r for r in ROWS if r["swerling"] == sw]
    pd, pfa, n = (np.array([r[k] for r in rows], dtype=float) for k in ("pd", "pfa", "n"))
    want = np.array([float(r["snr_db_str"]) for r in rows])
    return pd, pfa, n, want


def test_reference_grid_covers_the_domain_corners():
    pd, pfa, n, _ = _grid(0)
    assert pd.min() == 0.1 and pd.max() == 0.999 and pfa.min() == 1e-12 and pfa.max() == 1e-3
    assert n.min() == 1 and n.max() == 100 and len(pd) == 160


def test_swerling_2_is_the_closed_form_for_every_n():
    pd, pfa, n, want = _grid(2)
    got = np.asarray(barton_snr_db(pd, pfa, n, 2))
    assert np.max(np.abs(got - want)) < 1e-9


def test_swerling_1_one_pulse_and_swerling_3_two_pulses_are_exact():
    # Swerling 1, n = 1: D = ln Pfa / ln Pd - 1 (the statistic is (1 + D) Exp(1))
    for pd, pfa in [(0.1, 1e-2), (0.5, 1e-6), (0.9, 1e-6), (0.999, 1e-12)]:
        closed = 10 * math.log10(math.log(pfa) / math.log(pd) - 1)
        assert abs(float(barton_snr_db(pd, pfa, 1, 1)) - closed) < 1e-9
    # Swerling 3, n = 2: the statistic is (1 + D) Gamma(2, 1), as the reference's closed form
    pd, pfa, n, want = _grid(3)
    two = n == 2
    assert np.max(np.abs(np.asarray(barton_snr_db(pd[two], pfa[two], 2.0, 3)) - want[two])) < 1e-9


def test_difranco_rubin_steady_target_within_north_approximation():
    # DiFranco & Rubin's tables (reproduced by Skolnik): 13.18 dB at Pd = 0.9, Pfa = 1e-6, N = 1
    assert abs(float(barton_snr_db(0.9, 1e-6)) - 13.18) < 0.02


@pytest.mark.parametrize("sw", [0, 1, 3, 4])
def test_error_against_reference_reaches_the_stated_bounds(sw):
    pd, pfa, n, want = _grid(sw)
    err = np.abs(np.asarray(barton_snr_db(pd, pfa, n, sw)) - want)
    # Pfa <= 1e-3: the stored grid holds the worst point (Pd = 0.1, Pfa = 1e-3, n = 100)
    assert BOUND_PFA_1E3[sw] - 0.01 <= err.max() <= BOUND_PFA_1E3[sw]
    worst = np.argmax(err)
    assert (pd[worst], pfa[worst], n[worst]) == (0.1, 1e-3, 100)
    high = (pd >= 0.5) & (pfa <= 1e-4)
    assert err[high].max() <= BOUND_HIGH_PD[sw]


@pytest.mark.parametrize("sw", [0, 1, 3, 4])
def test_whole_domain_bound_at_its_worst_point(sw):
    # Pd = 0.1, Pfa = 1e-2, n = 100: the worst point of the whole domain (module docstring)
    want = float(ref.required_snr_mp(0.1, 1e-2, 100, sw, dps=30))
    err = abs(float(barton_snr_db(0.1, 1e-2, 100, sw)) - want)
    assert BOUND_DOMAIN[sw] - 0.01 <= err <= BOUND_DOMAIN[sw]


@pytest.mark.parametrize("sw", [0, 1, 2, 3, 4])
def test_against_exact_method_on_random_real_inputs(sw):
    rng = np.random.default_rng(7 + sw)
    k = 200
    pd = rng.uniform(0.1, 0.999, k)
    pfa = 10.0 ** rng.uniform(-12, -2, k)
    n = rng.uniform(1.0, 100.0, k)  # real-valued N
    exact = np.asarray(det.required_snr_db(pd, pfa, n, sw))
    err = np.abs(np.asarray(det.required_snr_db(pd, pfa, n, sw, method="barton")) - exact)
    assert err.max() <= (1e-9 if sw == 2 else BOUND_DOMAIN[sw])
    if sw != 2:
        high = (pd >= 0.5) & (pfa <= 1e-4)
        assert err[high].max() <= BOUND_HIGH_PD[sw]


def test_dispatch_domain_and_traced_nan():
    assert float(det.required_snr_db(0.8, 1e-5, 7.0, 3, method="barton")) == float(barton_snr_db(0.8, 1e-5, 7.0, 3))
    for name, (lo, hi) in BARTON_DOMAIN.items():
        args = {"pd": 0.5, "pfa": 1e-6, "n": 10.0}
        for bad in (lo * 0.99, hi * 1.01):
            args[name] = bad
            with pytest.raises(DomainError):
                barton_snr_db(args["pd"], args["pfa"], args["n"], 1)
    got = jax.jit(lambda p: det.required_snr_db(p, 1e-6, 10.0, 4, method="barton"))(jnp.array([0.05, 0.5]))
    assert np.isnan(got[0]) and np.isfinite(got[1])
    with pytest.raises(ValueError):
        det.required_snr_db(0.5, 1e-6, 1, 0, method="bartons")


@pytest.mark.parametrize("sw", [0, 1, 2, 4])
def test_derivatives_match_central_differences(sw):
    f = lambda p, q, n: barton_snr_db(p, q, n, sw)  # noqa: E731
    x = (0.8, 1e-5, 12.0)
    grads = jax.grad(f, argnums=(0, 1, 2))(*x)
    for i, h in enumerate((1e-6, 1e-11, 1e-5)):
        up, dn = list(x), list(x)
        up[i] += h
        dn[i] -= h
        fd = (float(f(*up)) - float(f(*dn))) / (2 * h)
        assert abs(float(grads[i]) - fd) <= 1e-5 * max(1.0, abs(fd))


def test_float32_agrees_with_float64():
    pd, pfa, n, _ = _grid(1)
    f64 = np.asarray(barton_snr_db(pd, pfa, n, 1))
    f32 = np.asarray(barton_snr_db(pd.astype(np.float32), pfa.astype(np.float32), n.astype(np.float32), 1))
    assert f32.dtype == np.float32 and np.max(np.abs(f32 - f64)) < 1e-3


# --- the radar option ``detectability`` -----------------------------------------------------

RADAR = dict(range_m=20e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1.2e6, rcs_m2=2.0,
             noise_figure_db=3.0, prf_hz=1e3, n_pulses=12.0, gain_db=33.0, beamwidth_az_deg=1.5,
             beamwidth_el_deg=3.0, pd=0.8, pfa=1e-6)


@pytest.mark.parametrize("method,sw", [("shnidman", 1), ("shnidman", 4), ("albersheim", 0), ("barton", 0),
                                       ("barton", 3)])
def test_radar_spec_with_each_approximation_evaluates_to_its_method(method, sw):
    scene = Scene("radar", [], {"antenna": "specified", "detectability": method, "swerling": sw,
                                "matched_filter": "matched"})
    ev = evaluate(scene, RADAR)
    want = float(det.required_snr_db(0.8, 1e-6, 12.0, sw, method=method))
    assert float(ev["required_snr_db"]) == pytest.approx(want, abs=1e-12)
    # the gain is the same method's 1-pulse minus N-pulse requirement; Pd stays the exact model's
    gain = float(det.required_snr_db(0.8, 1e-6, 1.0, sw, method=method)) - want
    assert float(ev["integration_gain_db"]) == pytest.approx(gain, abs=1e-12)
    assert float(ev["pd"]) == pytest.approx(float(det.pd(ev["snr_db"], 1e-6, 12.0, sw)), abs=1e-12)
    exact = evaluate(Scene("radar", [], {"antenna": "specified", "swerling": sw, "matched_filter": "matched"}), RADAR)
    assert float(ev["snr_db"]) == float(exact["snr_db"])


def test_radar_albersheim_refuses_a_fluctuating_target():
    scene = Scene("radar", [], {"antenna": "specified", "detectability": "albersheim", "swerling": 1})
    with pytest.raises(DomainError):
        evaluate(scene, RADAR)


def test_describe_radar_lists_the_new_detectability_values(capsys, monkeypatch):
    import os

    from diffsense.cli.app import main

    for name in ("XLA_FLAGS", "DIFFSENSE_CACHE_DIR"):
        if name in os.environ:
            monkeypatch.setenv(name, os.environ[name])
    keys = ("jax_compilation_cache_dir", "jax_persistent_cache_min_compile_time_secs")
    saved = {k: getattr(jax.config, k) for k in keys}
    try:
        with pytest.raises(SystemExit) as info:
            main(["--quiet", "describe", "radar"])
    finally:
        for k, v in saved.items():
            jax.config.update(k, v)
    out = capsys.readouterr().out
    assert info.value.code == 0
    row = out[out.index("detectability"):out.index("matched_filter")]  # the option's table row
    words = set(row.replace(",", " ").replace("│", " ").split())
    assert {"exact", "book", "given", "shnidman", "albersheim", "barton"} <= words
