"""Detection speed and accuracy, side by side in one run.

Prints time per element and maximum error against the mpmath reference (on a subsample) for
diffsense (warm jit and cold), scipy's vectorised closed forms, and the `sdr` package where it
has the function. Run: python benchmarks/bench_detection.py [--points 1000000] [--repeat 7]

Timings on a shared machine are noisy: the warm timings are interleaved (diffsense, scipy,
diffsense, ...) and the best of ``--repeat`` rounds is reported, with the throughput ratio
``scipy time / diffsense time`` measured in the same run. "SNRs shuffled" evaluates the same
points in random order (every chunk of the kernel then spans the whole SNR range: worst case).
"""

from __future__ import annotations

import argparse
import time

import jax
import mpmath as mp
import numpy as np
from scipy import special, stats

import diffsense.detection as det
from tests.reference import mp_detection as ref


def _time(fn, repeat=3):
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        jax.block_until_ready(out)
        best = min(best, time.perf_counter() - t)
    return best, out


def _time_interleaved(fns, repeat):
    """Best wall time of each callable over ``repeat`` interleaved rounds, and its last output."""
    best = {k: float("inf") for k in fns}
    outs = {}
    for _ in range(repeat):
        for k, fn in fns.items():
            t = time.perf_counter()
            outs[k] = jax.block_until_ready(fn())
            best[k] = min(best[k], time.perf_counter() - t)
    return best, outs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--rsnr-points", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    n, pfa = 10, 1e-6
    snr_db = np.linspace(-10.0, 30.0, args.points)
    s = 10.0 ** (snr_db / 10.0)
    t = float(det.threshold(pfa, n))
    sub = np.linspace(0, args.points - 1, 25).astype(int)
    truth = np.array([float(ref.pd_mp(mp.mpf(10) ** (mp.mpf(snr_db[i]) / 10), pfa, n, 0, dps=40)) for i in sub])
    perm = np.random.default_rng(0).permutation(args.points)
    snr_db_shuffled = snr_db[perm]

    f = jax.jit(lambda x: det.pd(x, pfa, n, 0))
    t0 = time.perf_counter()
    jax.block_until_ready(f(snr_db))
    cold = time.perf_counter() - t0
    best, outs = _time_interleaved(
        {
            "diffsense": lambda: f(snr_db),
            "scipy": lambda: stats.ncx2.sf(2 * t, 2 * n, 2 * n * s),
            "shuffled": lambda: f(snr_db_shuffled),
        },
        args.repeat,
    )
    unshuffled = np.empty(args.points)
    unshuffled[perm] = np.asarray(outs["shuffled"])
    tsp = best["scipy"]
    rows = [
        ("diffsense pd (warm jit)", best["diffsense"], np.max(np.abs(np.asarray(outs["diffsense"])[sub] - truth))),
        ("diffsense pd (warm jit, SNRs shuffled)", best["shuffled"], np.max(np.abs(unshuffled[sub] - truth))),
        ("diffsense pd (cold, incl. compile)", cold, np.nan),
        ("scipy ncx2.sf", tsp, np.max(np.abs(outs["scipy"][sub] - truth))),
    ]

    print(f"\nPd, Swerling 0, N = {n}, Pfa = {pfa:g}, {args.points} points, best of {args.repeat}")
    print(f"{'method':40s} {'s total':>9s} {'ns/point':>9s} {'max |dPd|':>10s} {'vs scipy':>9s}")
    for name, sec, err in rows:
        print(f"{name:40s} {sec:9.3f} {sec / args.points * 1e9:9.1f} {err:10.2e} {tsp / sec:8.2f}x")
    print("(vs scipy: scipy time / time, i.e. throughput relative to scipy; > 1 is faster)")

    pds = np.linspace(0.1, 0.99, args.rsnr_points)
    g = jax.jit(lambda p: det.required_snr_db(p, pfa, n, 1))
    jax.block_until_ready(g(pds))
    warm, out = _time(lambda: g(pds))
    idx = np.linspace(0, args.rsnr_points - 1, 5).astype(int)
    err = max(abs(float(out[i]) - float(ref.required_snr_mp(pds[i], pfa, n, 1, dps=40))) for i in idx)
    rows2 = [("diffsense required_snr_db exact (warm)", warm, err)]
    try:
        import sdr

        ts, out_s = _time(lambda: sdr.shnidman(pds, pfa, n, 1), repeat=1)
        exact = np.asarray(out)
        rows2.append(("sdr.shnidman (approximation)", ts, float(np.max(np.abs(out_s - exact)))))
    except ImportError:
        pass
    print(f"\nRequired SNR, Swerling 1, N = {n}, Pfa = {pfa:g}, {args.rsnr_points} points")
    print(f"{'method':40s} {'s total':>9s} {'us/point':>9s} {'max |dSNR| dB':>14s}")
    for name, sec, err in rows2:
        print(f"{name:40s} {sec:9.3f} {sec / args.rsnr_points * 1e6:9.2f} {err:14.2e}")


if __name__ == "__main__":
    main()
