"""Detection speed and accuracy, side by side in one run.

Prints time per element and maximum error against the mpmath reference (on a subsample) for
diffsense (warm jit and cold), scipy's vectorised closed forms, and the `sdr` package where it
has the function, and draws run time per point against maximum error (one labelled point per
method) to ``docs/figures/detection_speed_vs_error.png``.
Run: python benchmarks/bench_detection.py [--points 1000000] [--repeat 7] [--plot PATH | --no-plot] [--quick]
(needs the ``bench`` extras: scipy and mpmath; the `sdr` row is left out when `sdr` is missing).
``--quick`` runs the same tables on 20,000 and 200 points with 2 rounds and draws the plot to a
temporary file (the figure in docs/ is left as it is): a check that the benchmark works.

Timings on a shared machine are noisy: the warm timings are interleaved (diffsense, scipy,
diffsense, ...) and the best of ``--repeat`` rounds is reported, with the throughput ratio
``scipy time / diffsense time`` measured in the same run. "SNRs shuffled" evaluates the same
points in random order (every chunk of the kernel then spans the whole SNR range: worst case).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import _support

_support.require("bench_detection.py", "scipy", "mpmath")

import jax  # noqa: E402
import mpmath as mp  # noqa: E402
import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

import diffsense.detection as det  # noqa: E402
from diffsense.optimize.lanes import worker_count  # noqa: E402
from tests.reference import mp_detection as ref  # noqa: E402


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


_DEFAULT_PLOT = _support.ROOT / "docs" / "figures" / "detection_speed_vs_error.png"


def _plot(path, pd_rows, rsnr_rows, title_pd, title_rsnr, note):
    """Run time per point against maximum error, log-log, one labelled marker per method."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11.5, 5.0), dpi=130)
    panels = [
        (axes[0], pd_rows, 1e9, "ns", "Run time per point (ns)", "Maximum |ΔPd| against mpmath", title_pd),
        (axes[1], rsnr_rows, 1e6, "µs", "Run time per point (µs)", "Maximum |ΔSNR| (dB)", title_rsnr),
    ]
    for ax, rows, unit, unit_name, xlabel, ylabel, title in panels:
        pts = [(name, sec * unit, err) for name, sec, err, _ in rows if np.isfinite(err)]
        for (name, x, y), (colour, marker) in zip(pts, [("C0", "o"), ("C1", "s"), ("C2", "^"), ("C3", "D"), ("C4", "v")]):
            ax.scatter([x], [y], s=70, color=colour, marker=marker, zorder=3, label=name)
            value = f"{x:.0f}" if x >= 100 else f"{x:.3g}"
            ax.annotate(f"{value} {unit_name}", (x, y), textcoords="offset points", xytext=(0, -15),
                        ha="center", fontsize=7.5, color=colour)
        xs = np.array([p[1] for p in pts])
        ys = np.array([p[2] for p in pts])
        # Limits: at least a decade around the points so the markers sit inside the axes.
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(10 ** np.floor(np.log10(xs.min()) - 0.3), 10 ** np.ceil(np.log10(xs.max()) + 0.3))
        ax.set_ylim(10 ** np.floor(np.log10(ys.min()) - 0.5), 10 ** np.ceil(np.log10(ys.max()) + 0.5))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="major", alpha=0.4)
        ax.legend(loc="upper left", fontsize=8, framealpha=0.9)
    fig.suptitle("Detection: run time per point against maximum error (lower left is better)", fontsize=11)
    fig.text(0.5, 0.012, note, ha="center", fontsize=8, color="0.3", wrap=True)
    fig.tight_layout(rect=(0, 0.06, 1, 0.96))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--rsnr-points", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--plot", type=Path, default=_DEFAULT_PLOT, help="PNG of run time against error")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
    args = ap.parse_args()
    if args.quick:
        args.points, args.rsnr_points, args.repeat = 20_000, 200, 2
        if args.plot == _DEFAULT_PLOT:
            with tempfile.TemporaryDirectory() as tmp:
                args.plot = Path(tmp) / "detection_speed_vs_error.png"
                run(args)
            print("(--quick: the plot went to a temporary file, now removed)")
            return
    return run(args)


def run(args):
    """Time and check the detection functions at ``args``' sizes; print the tables, draw the plot."""
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
    out_cold = jax.block_until_ready(f(snr_db))
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
    def max_err(values):
        return float(np.max(np.abs(np.asarray(values)[sub] - truth)))

    # (label, seconds for all points, max error, label in the plot)
    rows = [
        ("diffsense pd (warm jit)", best["diffsense"], max_err(outs["diffsense"]), "diffsense pd, warm jit"),
        ("diffsense pd (warm jit, SNRs shuffled)", best["shuffled"], max_err(unshuffled), "diffsense pd, warm, SNRs shuffled"),
        ("diffsense pd (cold, incl. compile)", cold, max_err(out_cold), "diffsense pd, cold (incl. compilation)"),
        ("scipy ncx2.sf", tsp, max_err(outs["scipy"]), "scipy stats.ncx2.sf"),
    ]

    print(f"\nPd, Swerling 0, N = {n}, Pfa = {pfa:g}, {args.points} points, best of {args.repeat}")
    print(f"{'method':40s} {'s total':>9s} {'ns/point':>9s} {'max |dPd|':>10s} {'vs scipy':>9s}")
    for name, sec, err, _ in rows:
        print(f"{name:40s} {sec:9.3f} {sec / args.points * 1e9:9.1f} {err:10.2e} {tsp / sec:8.2f}x")
    print("(vs scipy: scipy time / time, i.e. throughput relative to scipy; > 1 is faster)")

    pds = np.linspace(0.1, 0.99, args.rsnr_points)
    g = jax.jit(lambda p: det.required_snr_db(p, pfa, n, 1))
    jax.block_until_ready(g(pds))
    warm, out = _time(lambda: g(pds))
    idx = np.linspace(0, args.rsnr_points - 1, 5).astype(int)
    err = max(abs(float(out[i]) - float(ref.required_snr_mp(pds[i], pfa, n, 1, dps=40))) for i in idx)
    rows2 = [("diffsense required_snr_db exact (warm)", warm, err, "diffsense required_snr_db (exact), warm jit")]
    try:
        import sdr

        ts, out_s = _time(lambda: sdr.shnidman(pds, pfa, n, 1), repeat=1)
        exact = np.asarray(out)
        rows2.append(
            ("sdr.shnidman (approximation)", ts, float(np.max(np.abs(out_s - exact))), "sdr.shnidman (approximation)")
        )
    except ImportError:
        print("\n(sdr is not installed: its row is left out; pip install sdr)", file=sys.stderr)
    print(f"\nRequired SNR, Swerling 1, N = {n}, Pfa = {pfa:g}, {args.rsnr_points} points")
    print(f"{'method':40s} {'s total':>9s} {'us/point':>9s} {'max |dSNR| dB':>14s}")
    for name, sec, err, _ in rows2:
        print(f"{name:40s} {sec:9.3f} {sec / args.rsnr_points * 1e6:9.2f} {err:14.2e}")

    if not args.no_plot:
        per_point = lambda rs, k: [(label, sec / k, e, None) for _, sec, e, label in rs]
        _plot(
            args.plot,
            per_point(rows, args.points),
            per_point(rows2, args.rsnr_points),
            f"Pd: Swerling 0, N = {n}, Pfa = {pfa:g}\n{args.points:,} SNRs from -10 to 30 dB",
            f"Required SNR: Swerling 1, N = {n}, Pfa = {pfa:g}\n{args.rsnr_points:,} Pd values from 0.1 to 0.99",
            f"{worker_count()}-core CPU shared with other work; warm times: best of {args.repeat} interleaved rounds "
            "(required SNR: best of 3).\nErrors: maximum over 25 Pd and 5 SNR values against 40-digit mpmath "
            "(sdr: against the exact value).",
        )
        print(f"\nplot: {args.plot}")


if __name__ == "__main__":
    main()
