"""Checks of the mpmath detection reference itself (independent of the package).

Sources: published required-SNR values (DiFranco & Rubin; Skolnik, Radar Handbook
detection tables: Pd = 0.9, Pfa = 1e-6, one pulse -> 13.18 dB steady target,
21.14 dB Swerling 1), closed forms derived in ``tests/reference/mp_detection.py``,
independent integration routes (mp.quad, Bessel density), and Monte Carlo.
"""

import json
import math
import os

import pytest
from mpmath import mp, mpf

from tests.reference import mp_detection as ref
from helpers.paths import DATA

DATA = str(DATA / "detection_reference.json")


def test_required_snr_classic_single_pulse_pd09_pfa1e6():
    # Published: 13.18 dB steady (Swerling 0), 21.14 dB Swerling 1; table rounding 0.01 dB.
    steady = ref.required_snr_mp(0.9, "1e-6", 1, 0, dps=30)
    sw1 = ref.required_snr_mp(0.9, "1e-6", 1, 1, dps=30)
    assert abs(float(steady) - 13.18) <= 0.01
    assert abs(float(sw1) - 21.14) <= 0.01


def test_required_snr_swerling1_single_pulse_matches_closed_inverse():
    # N = 1: Pd = exp(-T/(1+S)), T = ln(1/Pfa)  =>  S = ln(Pfa)/ln(Pd) - 1 exactly.
    with mp.workdps(40):
        for pd, pfa in [("0.5", "1e-3"), ("0.99", "1e-9"), ("0.9", "1e-6")]:
            exact = 10 * mp.log10(mp.log(mpf(pfa)) / mp.log(mpf(pd)) - 1)
            got = ref.required_snr_mp(pd, pfa, 1, 1, dps=30)
            assert abs(got - exact) < mpf("1e-11")


def test_swerling2_equals_swerling1_at_one_pulse():
    # Both reduce to exp(-T/(1+S)) for N = 1.
    with mp.workdps(40):
        t = ref.threshold_mp("1e-6", 1, dps=35)
        for s in ["0.1", "3", "40", "1000"]:
            p1 = ref.pd_from_threshold_mp(mpf(s), t, 1, 1, dps=30)
            p2 = ref.pd_from_threshold_mp(mpf(s), t, 1, 2, dps=30)
            exact = mp.exp(-t / (1 + mpf(s)))
            assert abs(p1 - p2) < mpf("1e-28")
            assert abs(p1 - exact) < mpf("1e-28")


def test_swerling4_equals_swerling3_at_one_pulse():
    # One pulse: scan-to-scan and pulse-to-pulse chi-square-4 fluctuation coincide;
    # binomial mixture (Swerling 4) vs closed form exp(-T/b)(1 + cT/b) (Swerling 3).
    with mp.workdps(40):
        t = ref.threshold_mp("1e-6", 1, dps=35)
        for s in ["0.5", "20", "300"]:
            p3 = ref.pd_from_threshold_mp(mpf(s), t, 1, 3, dps=30)
            p4 = ref.pd_from_threshold_mp(mpf(s), t, 1, 4, dps=30)
            assert abs(p3 - p4) < mpf("1e-28")


@pytest.mark.parametrize("n,s", [(1, "10"), (2, "5")])
def test_swerling1_quad_matches_closed_form(n, s):
    with mp.workdps(40):
        t = ref.threshold_mp("1e-6", n, dps=30)
        closed = ref.pd_from_threshold_mp(mpf(s), t, n, 1, dps=25, method="closed")
        quad = ref.pd_from_threshold_mp(mpf(s), t, n, 1, dps=25, method="quad")
        assert abs(closed - quad) < mpf("1e-20")


def test_swerling3_quad_matches_closed_form():
    with mp.workdps(40):
        t = ref.threshold_mp("1e-3", 3, dps=30)
        closed = ref.pd_from_threshold_mp(mpf(4), t, 3, 3, dps=25, method="closed")
        quad = ref.pd_from_threshold_mp(mpf(4), t, 3, 3, dps=25, method="quad")
        assert abs(closed - quad) < mpf("1e-20")


@pytest.mark.parametrize("sw,n", [(1, 1), (1, 7), (3, 1), (3, 2), (3, 9), (1, 2.5), (3, 4.5)])
def test_swerling13_closed_form_matches_negative_binomial_series(sw, n):
    with mp.workdps(50):
        t = ref.threshold_mp("1e-9", n, dps=45)
        for s in ["0.3", "6", "50"]:
            a = ref.pd_from_threshold_mp(mpf(s), t, n, sw, dps=40, method="closed")
            b = ref.pd_from_threshold_mp(mpf(s), t, n, sw, dps=40, method="series")
            assert abs(a - b) < mpf("1e-38")


@pytest.mark.parametrize("n,s", [(1, "20"), (3, "4")])
def test_swerling0_series_matches_bessel_density_integral(n, s):
    with mp.workdps(40):
        t = ref.threshold_mp("1e-6", n, dps=30)
        a = ref.pd_from_threshold_mp(mpf(s), t, n, 0, dps=25)
        b = ref.pd_from_threshold_mp(mpf(s), t, n, 0, dps=25, method="integral")
        assert abs(a - b) < mpf("1e-20")


@pytest.mark.parametrize(
    "sw,n,snr_db",
    [(0, 1, 11.0), (1, 2, 12.0), (2, 3, 6.0), (3, 4, 6.0), (4, 5, 3.0), (0, 10, 0.0)],
)
def test_monte_carlo_agrees_within_4_sigma(sw, n, snr_db):
    s = 10 ** (snr_db / 10)
    pd = float(ref.pd_mp(s, "1e-3", n, sw, dps=25))
    samples = 200_000
    mc = ref.monte_carlo_pd(s, 1e-3, n, sw, samples=samples, seed=1234 + 17 * sw + n)
    sigma = math.sqrt(pd * (1 - pd) / samples)
    assert 0.05 < pd < 0.995  # the point actually tests the transition region
    assert abs(mc.pd - pd) <= 4 * sigma


@pytest.mark.parametrize("n", [1, 2, 7.5, 100, 1000])
@pytest.mark.parametrize("pfa", ["1e-1", "1e-15", "1e-100", "1e-300"])
def test_threshold_round_trip(n, pfa):
    with mp.workdps(60):
        t = ref.threshold_mp(pfa, n, dps=50)
        q = mp.gammainc(n, t, mp.inf, regularized=True)
        assert abs(q / mpf(pfa) - 1) < mpf("1e-45")
        if n == 1:  # Q(1, T) = exp(-T)
            assert abs(t - mp.log(1 / mpf(pfa))) < mpf("1e-45") * t


def test_reference_json_matches_reference_code():
    if not os.path.exists(DATA):
        pytest.skip("tests/data/detection_reference.json not generated")
    with open(DATA) as fh:
        data = json.load(fh)
    pts = [p for p in data["pd_points"] if p["n"] <= 20]
    picks = pts[:: max(1, len(pts) // 8)][:8]
    with mp.workdps(50):
        for p in picks:
            s = mp.power(10, mpf(p["snr_db_str"]) / 10)
            pd = ref.pd_mp(s, p["pfa_str"], p["n"], p["swerling"], dps=30)
            assert abs(pd - mpf(p["pd_str"])) < mpf("1e-25")
        for r in data["thresholds"][::7]:
            t = ref.threshold_mp(r["pfa_str"], r["n"], dps=30)
            assert abs(t / mpf(r["threshold_str"]) - 1) < mpf("1e-25")
    assert data["checks"]["pd_dps50_vs_dps70_max_abs"] < 1e-40
    assert data["checks"]["snr_db_dps50_vs_dps70_max_abs"] < 1e-20


def test_reference_json_swerling0_2_match_scipy_float64():
    # Independent float64 implementations: noncentral chi-square survival
    # (Pd_sw0 = ncx2.sf(2T; 2N, 2NS)) and Q(N, T/(1+S)) for Swerling 2.
    if not os.path.exists(DATA):
        pytest.skip("tests/data/detection_reference.json not generated")
    from scipy import special, stats

    with open(DATA) as fh:
        data = json.load(fh)
    thr = {(t["n"], t["pfa_str"]): t["threshold"] for t in data["thresholds"]}
    worst = 0.0
    for p in data["pd_points"]:
        if p["swerling"] not in (0, 2):
            continue
        n, t, s = p["n"], thr[(p["n"], p["pfa_str"])], 10 ** (p["snr_db"] / 10)
        if p["swerling"] == 0:
            v = stats.ncx2.sf(2 * t, 2 * n, 2 * n * s)
        else:
            v = special.gammaincc(n, t / (1 + s))
        worst = max(worst, abs(v - p["pd"]))
    assert worst < 1e-12
