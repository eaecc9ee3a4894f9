"""Generate tests/data/detection_reference.json from the mpmath reference.

Run from the repository root:  python tests/reference/make_detection_reference.py
Options: --workers W (default 2), --quick (tiny grid, for smoke testing),
--out PATH.

Contents (see ``mp_detection`` for every formula):
  thresholds    T with Q(N, T) = Pfa, N in the grid, Pfa down to 1e-300.
  required_snr  mean per-pulse SNR (dB) for Pd in {0.1, 0.5, 0.9, 0.99, 0.999}
                (pairs with Pd <= Pfa omitted), bracket width <= 1e-25 dB.
  pd_points     Pd at SNRs around each curve's transition: the required SNRs
                rounded to 0.1 dB, plus 20 and 10 dB below the Pd = 0.1 (or the
                lowest) point and 3 and 10 dB above the Pd = 0.999 point.
  checks        precision verification: the whole pd_points set and the
                required SNRs for Pfa in {1e-6, 1e-15} re-evaluated at dps 70;
                Swerling 1/3 closed forms vs the series route (pd points with
                N*S <= 3000)
                and vs mp.quad (subset); Swerling 0 series vs the Bessel
                integral (subset); Pd(required SNR) round trip.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from multiprocessing import Pool

from mpmath import mp, mpf

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mp_detection as ref  # noqa: E402

DPS = 50
CHECK_DPS = 70
QUAD_DPS = 30
SWERLINGS = [0, 1, 2, 3, 4]
NS = [1, 2, 3, 5, 10, 20, 50, 100, 300, 1000]
PFAS = ["1e-1", "1e-3", "1e-6", "1e-9", "1e-12", "1e-15"]
PDS = ["0.1", "0.5", "0.9", "0.99", "0.999"]
THRESHOLD_PFAS = PFAS + ["1e-30", "1e-100", "1e-300"]
ROOT_CHECK_PFAS = {"1e-6", "1e-15"}
QUAD_SUBSET = {(n, "1e-6") for n in (1, 3, 10)}
SERIES_MAX_LAM = 3000  # series length grows like N*S*log(1/eps)
ROOT_TOL_DB = mpf("1e-25")
INTEGRAL_SUBSET = {(n, "1e-6") for n in (1, 2, 5, 10)}


def _s(x, digits=30):
    return mp.nstr(x, digits, strip_zeros=False)


def _lin(db_str):
    with mp.workdps(DPS + 20):
        return mp.power(10, mpf(db_str) / 10)


def _round_db(x):
    """Round to 0.1 dB and return the decimal string."""
    return f"{round(float(x) * 10) / 10:.1f}"


def curve_task(key):
    with mp.workdps(DPS + 20):
        return _curve_task(key)


def _curve_task(key):
    sw, n, pfa = key
    t0 = time.time()
    method = "closed"
    t = ref.threshold_mp(pfa, n, dps=DPS + 5)
    req = []
    checks = {"pd_dps_diff": 0.0, "snr_dps_diff": 0.0, "series_diff": 0.0,
              "quad_diff": None, "integral_diff": None, "roundtrip_diff": 0.0}
    for pd in PDS:
        if mpf(pd) <= mpf(pfa):
            continue
        db = ref.required_snr_mp(pd, pfa, n, sw, dps=DPS, tol_db=ROOT_TOL_DB)
        pd_back = ref.pd_from_threshold_mp(mp.power(10, db / 10), t, n, sw, dps=DPS)
        checks["roundtrip_diff"] = max(checks["roundtrip_diff"], float(abs(pd_back - mpf(pd))))
        if pfa in ROOT_CHECK_PFAS:
            db70 = ref.required_snr_mp(pd, pfa, n, sw, dps=CHECK_DPS, tol_db=ROOT_TOL_DB)
            checks["snr_dps_diff"] = max(checks["snr_dps_diff"], float(abs(db70 - db)))
        req.append({"swerling": sw, "n": n, "pfa": float(pfa), "pfa_str": pfa,
                    "pd": float(pd), "snr_db": float(db), "snr_db_str": _s(db)})
    dbs = [r["snr_db"] for r in req]
    grid = {_round_db(d) for d in dbs}
    grid |= {_round_db(dbs[0] - 20), _round_db(dbs[0] - 10),
             _round_db(dbs[-1] + 3), _round_db(dbs[-1] + 10)}
    grid = sorted(grid, key=float)
    t70 = ref.threshold_mp(pfa, n, dps=CHECK_DPS + 5)
    points = []
    for db in grid:
        s = _lin(db)
        pd = ref.pd_from_threshold_mp(s, t, n, sw, dps=DPS, method=method)
        pd70 = ref.pd_from_threshold_mp(s, t70, n, sw, dps=CHECK_DPS, method=method)
        checks["pd_dps_diff"] = max(checks["pd_dps_diff"], float(abs(pd70 - pd)))
        if sw in (1, 3) and n * s <= SERIES_MAX_LAM:
            pd_ser = ref.pd_from_threshold_mp(s, t, n, sw, dps=DPS, method="series")
            checks["series_diff"] = max(checks["series_diff"], float(abs(pd_ser - pd)))
        points.append({"swerling": sw, "n": n, "pfa": float(pfa), "pfa_str": pfa,
                       "snr_db": float(db), "snr_db_str": db, "pd": float(pd),
                       "pd_str": _s(pd)})
    # quadrature / Bessel-integral cross-checks on a subset (Pd near 0.5 and 0.9)
    sub = [_round_db(dbs[1]), _round_db(dbs[2])] if len(dbs) >= 3 else []
    if sw in (1, 3) and (n, pfa) in QUAD_SUBSET:
        tq = ref.threshold_mp(pfa, n, dps=QUAD_DPS + 5)
        diffs = []
        for db in sub:
            s = _lin(db)
            a = ref.pd_from_threshold_mp(s, tq, n, sw, dps=QUAD_DPS, method="quad")
            b = ref.pd_from_threshold_mp(s, tq, n, sw, dps=QUAD_DPS, method="closed")
            diffs.append(float(abs(a - b)))
        checks["quad_diff"] = max(diffs)
    if sw == 0 and (n, pfa) in INTEGRAL_SUBSET:
        diffs = []
        for db in sub:
            s = _lin(db)
            a = ref.pd_from_threshold_mp(s, t, n, 0, dps=DPS, method="integral")
            b = ref.pd_from_threshold_mp(s, t, n, 0, dps=DPS)
            diffs.append(float(abs(a - b)))
        checks["integral_diff"] = max(diffs)
    return key, req, points, checks, time.time() - t0


def threshold_task(key):
    n, pfa = key
    t = ref.threshold_mp(pfa, n, dps=DPS)
    t70 = ref.threshold_mp(pfa, n, dps=CHECK_DPS)
    with mp.workdps(DPS + 10):
        resid = abs(mp.log(mp.gammainc(n, t, mp.inf, regularized=True)) - mp.log(mpf(pfa)))
    return {"n": n, "pfa": float(pfa), "pfa_str": pfa, "threshold": float(t),
            "threshold_str": _s(t, 40)}, float(abs(t70 - t) / t70), float(resid)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--quick", action="store_true")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--out", default=os.path.join(here, "..", "data", "detection_reference.json"))
    args = ap.parse_args(argv)
    ns, pfas = (NS, PFAS) if not args.quick else ([1, 3], ["1e-3", "1e-6"])
    t_start = time.time()
    keys = [(sw, n, pfa) for sw in SWERLINGS for n in ns for pfa in pfas]
    # most expensive first (large n, Swerling 0/4, series checks for 1/3)
    keys.sort(key=lambda k: (-k[1], k[0] in (2,)))
    tkeys = [(n, pfa) for n in ns for pfa in THRESHOLD_PFAS]
    with Pool(args.workers) as pool:
        thr = pool.map(threshold_task, tkeys)
        results = []
        for i, res in enumerate(pool.imap_unordered(curve_task, keys)):
            results.append(res)
            key, _, _, _, dt = res
            print(f"[{i + 1}/{len(keys)}] swerling={key[0]} n={key[1]} pfa={key[2]}: {dt:.1f}s",
                  flush=True)
    results.sort(key=lambda r: (r[0][0], r[0][1], float(r[0][2])))
    required, points = [], []
    agg = {"pd_dps50_vs_dps70_max_abs": 0.0, "snr_db_dps50_vs_dps70_max_abs": 0.0,
           "sw13_closed_vs_series_max_abs": 0.0, "sw13_closed_vs_quad_max_abs": 0.0,
           "sw0_series_vs_bessel_integral_max_abs": 0.0, "pd_of_required_snr_max_abs_err": 0.0}
    for _, req, pts, ch, _ in results:
        required += req
        points += pts
        agg["pd_dps50_vs_dps70_max_abs"] = max(agg["pd_dps50_vs_dps70_max_abs"], ch["pd_dps_diff"])
        agg["snr_db_dps50_vs_dps70_max_abs"] = max(agg["snr_db_dps50_vs_dps70_max_abs"],
                                                   ch["snr_dps_diff"])
        agg["sw13_closed_vs_series_max_abs"] = max(agg["sw13_closed_vs_series_max_abs"],
                                                   ch["series_diff"])
        if ch["quad_diff"] is not None:
            agg["sw13_closed_vs_quad_max_abs"] = max(agg["sw13_closed_vs_quad_max_abs"],
                                                     ch["quad_diff"])
        if ch["integral_diff"] is not None:
            agg["sw0_series_vs_bessel_integral_max_abs"] = max(
                agg["sw0_series_vs_bessel_integral_max_abs"], ch["integral_diff"])
        agg["pd_of_required_snr_max_abs_err"] = max(agg["pd_of_required_snr_max_abs_err"],
                                                    ch["roundtrip_diff"])
    agg["threshold_dps50_vs_dps70_max_rel"] = max(r[1] for r in thr)
    agg["threshold_log_residual_max"] = max(r[2] for r in thr)
    agg["counts"] = {"thresholds": len(thr), "required_snr": len(required),
                     "pd_points": len(points)}
    elapsed = time.time() - t_start
    out = {
        "metadata": {
            "description": (
                "Radar detection reference: square-law detector, N pulses integrated "
                "noncoherently, noise-only statistic Gamma(N, 1), threshold T with "
                "Q(N, T) = Pfa (regularised upper incomplete gamma). snr is the mean "
                "per-pulse SNR. Swerling 0: Poisson mixture of Q(N+k, T) with explicit "
                "tail bound; 1: closed form Q(N-1,T) + (1+1/(NS))^(N-1) "
                "P(N-1, T/(1+1/(NS))) exp(-T/(1+NS)) (N=1: exp(-T/(1+S))); 2: "
                "Q(N, T/(1+S)); 3: closed form Q(N-2,T) + exp(-T/b) c^-(N-2) "
                "[(1+T/b) P(N-2,cT) - (N-2)/(bc) P(N-1,cT)], b = 1+NS/2, c = 1-1/b "
                "(N=1: exp(-T/b)(1+cT/b); N=2: exp(-T/b)(1+T/b)); 4: binomial mixture "
                "sum_m C(N,m) p^m (1-p)^(N-m) Q(N+m, T/b), b = 1+S/2, p = 1-1/b. "
                "Required SNR by Illinois root finding in dB to a 1e-25 dB bracket. "
                "See tests/reference/mp_detection.py."),
            "mp_dps": DPS,
            "check_dps": CHECK_DPS,
            "quad_check_dps": QUAD_DPS,
            "grid": {"swerling": SWERLINGS, "n": ns, "pfa": pfas, "pd": PDS,
                     "threshold_pfa": THRESHOLD_PFAS},
            "generation_seconds": round(elapsed, 1),
            "workers": args.workers,
        },
        "checks": agg,
        "thresholds": [r[0] for r in thr],
        "required_snr": required,
        "pd_points": points,
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=0, separators=(",", ":"))
        fh.write("\n")
    print(json.dumps(agg, indent=1))
    print(f"wrote {args.out} ({os.path.getsize(args.out) / 1e6:.2f} MB) in {elapsed:.1f} s")


if __name__ == "__main__":
    main()
