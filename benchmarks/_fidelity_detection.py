"""Fidelity families of the detection-side model choices (for ``bench_fidelity.py``).

1. **Detectability** (the radar option ``detectability``): the per-pulse SNR needed for Pd at Pfa
   with N pulses integrated noncoherently, Swerling 0-4. Choices: ``exact``
   (:func:`diffsense.detection.required_snr_db`), the same in float32 (the package run with
   ``DIFFSENSE_X64=0``, in a child process), ``book`` (the exact single-pulse value less the
   book's 8 log10 N gain, Brooker 8.16.13), ``shnidman`` (Shnidman 2002), ``albersheim``
   (Albersheim 1981, steady target only), ``barton`` (Barton 2005,
   :mod:`diffsense.detection.barton`), ``chebyshev`` (the interpolant of the exact values,
   :mod:`diffsense.detection.chebyshev_snr`) and ``given`` (the spec writes the number: no model).
   Reference: the mpmath inversion of the exact Pd (``tests/reference/mp_detection.py``).
2. **Matched filter** (the radar option ``matched_filter``): the mismatch loss of a rectangular
   pulse through each receiver filter (:func:`diffsense.detection.matched_filter_loss_db`) against
   the same loss by quadrature of its definition (scipy ``quad``: the peak of the pulse convolved
   with the filter's impulse response, over the filter's noise bandwidth integrated in frequency).
3. **Received-pulse width** (the range resolution c W / 2 and the range gate): the half-amplitude
   width of the echo after the IF filter, root-found (:func:`diffsense.physics.received_pulse.
   received_pulse_width_s`) or the closed form W = τ (the book's c τ / 2, exact only for the
   matched filter), against mpmath root finds on each filter's step response.

Times: each choice compiled once with the package's "optimized" XLA preset
(:mod:`diffsense.optimize.compile`; programs compiled two at a time in background threads),
warm median per evaluation over a batch (:func:`_fidelity_support.time_per_eval`); ``quick``
compiles with the "fast" preset (optimisation level 0), so its times are indicative only.

Run alone: python benchmarks/_fidelity_detection.py [--quick] (needs scipy and mpmath, in the
``bench`` extras). ``--quick``: the stored 50-digit reference grid of the detection tests plus
60 live mpmath points at Pfa = 1e-2, small filter grids (the width on four filters), the float32
child alongside the float64 programs.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path
from typing import Sequence

import _support

_support.require("_fidelity_detection.py", "scipy", "mpmath")

import diffsense  # noqa: E402,F401  (float64 throughout, unless the child below sets DIFFSENSE_X64=0)
import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from _fidelity_support import Choice, Family, compile_all, main_alone, time_per_eval, worst  # noqa: E402

#: the bound fidelity = "fast" must meet for a dB quantity (family 1 and 2)
DB_BOUND = 0.01
#: the bound of the received-pulse width (relative): 0.1 % of the range resolution
WIDTH_BOUND = 1e-3

SWERLINGS = (0, 1, 2, 3, 4)
FULL_PDS = (0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.95, 0.99, 0.999)
FULL_PFAS = (1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
FULL_NS = (1, 2, 3, 5, 10, 20, 30, 50, 100)
#: quick mode: live mpmath points at Pfa = 1e-2 (the stored grid stops at 1e-3)
QUICK_LIVE = [(pd, 1e-2, n) for pd in (0.1, 0.5, 0.9, 0.999) for n in (1, 10, 100)]
REFERENCE_DPS = 30

#: (Pd, Pfa) domains of the approximations (diffsense.detection.required_snr)
SHNIDMAN_DOMAIN = ((0.1, 0.99), (1e-9, 1e-3))
ALBERSHEIM_DOMAIN = ((0.1, 0.9), (1e-7, 1e-3))
#: detectability values a spec may set that take the same parameters as "exact"
SAME_PARAMETER_OPTIONS = ("book", "shnidman", "albersheim", "barton", "chebyshev")


def _us(seconds):
    return f"{seconds * 1e6:.3g} µs" if seconds > 0 else "0"


# --- 1. detectability ------------------------------------------------------------------------


def _required_snr_fn(method: str, cases: Sequence[int]):
    import diffsense.detection as det

    def f(pd, pfa, n):
        return jnp.stack([det.required_snr_db(pd, pfa, n, sw, method=method) for sw in cases])

    return f


def _mp_required_snr(pd, pfa, n, sw):
    from tests.reference import mp_detection as ref

    return float(ref.required_snr_mp(pd, pfa, n, sw, dps=REFERENCE_DPS))


def _grid_points(quick: bool):
    """``(points [(pd, pfa, n)], stored {(sw, pd, pfa, n): dB} or {}, words)``: the same points for
    every Swerling case."""
    if not quick:
        points = [(pd, pfa, float(n)) for pd in FULL_PDS for pfa in FULL_PFAS for n in FULL_NS]
        words = (f"Pd {', '.join(map(str, FULL_PDS))} × Pfa {', '.join(f'{p:g}' for p in FULL_PFAS)} × "
                 f"N {', '.join(map(str, FULL_NS))}; Swerling 0-4: {len(points) * 5} points")
        return points, {}, words
    rows = json.loads((_support.ROOT / "tests" / "data" / "detection_reference.json").read_text())["required_snr"]
    rows = [r for r in rows if 1e-12 <= r["pfa"] <= 1e-2 and r["n"] <= 100]
    stored = {(r["swerling"], r["pd"], r["pfa"], float(r["n"])): float(r["snr_db_str"]) for r in rows}
    points = sorted({k[1:] for k in stored}) + [(pd, pfa, float(n)) for pd, pfa, n in QUICK_LIVE]
    words = (f"Pd 0.1, 0.5, 0.9, 0.99, 0.999 × Pfa 1e-3, 1e-6, 1e-9, 1e-12 × N 1, 2, 3, 5, 10, 20, 50, 100, "
             f"and Pd 0.1, 0.5, 0.9, 0.999 × Pfa 1e-2 × N 1, 10, 100; Swerling 0-4: {len(points) * 5} points")
    return points, stored, words


def _grid_reference(points, stored):
    """The reference (5, m): the stored value where there is one, else mpmath now."""
    return np.array([[stored.get((sw, *p)) if (sw, *p) in stored else _mp_required_snr(*p, sw) for p in points]
                     for sw in SWERLINGS])


def detectability_grid(quick: bool):
    """``(pd, pfa, n, reference (5, m), words)``: the family's grid and its reference."""
    points, stored, words = _grid_points(quick)
    pd, pfa, n = (np.array(c, dtype=float) for c in zip(*points))
    return pd, pfa, n, _grid_reference(points, stored), words


def _float32_child(args_path: str, out_path: str, repeats: int, quick: bool):
    """Run inside ``DIFFSENSE_X64=0``: compile, time and evaluate the exact method in float32."""
    assert not jax.config.jax_enable_x64
    a = np.load(args_path)
    args = tuple(jnp.asarray(a[k], dtype=jnp.float32) for k in ("pd", "pfa", "n"))
    [(compiled, ops)] = compile_all([(_required_snr_fn("exact", SWERLINGS), args)], quick)
    out = np.asarray(compiled(*args))
    sec = time_per_eval(compiled, *args, batch=out.size, repeats=repeats)
    np.savez(out_path, out=out, sec=sec, ops=ops, dtype=str(out.dtype))


def _start_float32(pd, pfa, n, repeats, quick, tmp: Path):
    np.savez(tmp / "args.npz", pd=pd, pfa=pfa, n=n)
    env = dict(os.environ, DIFFSENSE_X64="0")
    cmd = [sys.executable, str(Path(__file__).resolve()), "--float32-child", str(tmp / "args.npz"),
           str(tmp / "out.npz"), str(repeats), "quick" if quick else "full"]
    return subprocess.Popen(cmd, env=env, cwd=_support.ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _finish_float32(proc, tmp: Path):
    _, err = proc.communicate()
    if proc.returncode != 0:
        raise RuntimeError(f"float32 child failed ({proc.returncode}):\n{err[-3000:]}")
    r = np.load(tmp / "out.npz")
    return r["out"].astype(float), float(r["sec"]), int(r["ops"]), str(r["dtype"])


def _per_case(out, ref, cases, mask=None):
    """'Swerling k x.xx' worst |out − ref| per case (dB)."""
    m = slice(None) if mask is None else mask
    return ", ".join(f"{sw}: {worst(o[m], ref[sw][m]):.3g}" for sw, o in zip(cases, out))


def _in(x, lo_hi):
    return (x >= lo_hi[0]) & (x <= lo_hi[1])


def detectability(quick: bool) -> Family:
    """Family 1 (module docstring)."""
    repeats = 2 if quick else 5
    points, stored, words = _grid_points(quick)
    pd, pfa, n = (np.array(c, dtype=float) for c in zip(*points))
    args = tuple(jnp.asarray(a) for a in (pd, pfa, n))
    reference = []  # filled by mpmath while the programs compile
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        child = _start_float32(pd, pfa, n, repeats, quick, tmp)
        if not quick:  # full: the child's compile and timing do not share the cores with ours
            f32 = _finish_float32(child, tmp)
        shn = _in(pd, SHNIDMAN_DOMAIN[0]) & _in(pfa, SHNIDMAN_DOMAIN[1])
        alb = _in(pd, ALBERSHEIM_DOMAIN[0]) & _in(pfa, ALBERSHEIM_DOMAIN[1])
        sub = lambda mask: tuple(jnp.asarray(a[mask]) for a in (pd, pfa, n))  # noqa: E731
        jobs = [(_required_snr_fn("exact", SWERLINGS), args), (_required_snr_fn("barton", SWERLINGS), args),
                (_required_snr_fn("shnidman", SWERLINGS), sub(shn)), (_required_snr_fn("albersheim", (0,)), sub(alb)),
                (_required_snr_fn("chebyshev", SWERLINGS), args)]
        (c_ex, ops_ex), (c_ba, ops_ba), (c_sh, ops_sh), (c_al, ops_al), (c_ch, ops_ch) = compile_all(
            jobs, quick, alongside=lambda: reference.append(_grid_reference(points, stored)))
        ref = reference[0]
        m = len(pd)
        exact = np.asarray(c_ex(*args))
        t_ex = time_per_eval(c_ex, *args, batch=5 * m, repeats=repeats)
        ones = jnp.ones_like(args[2])
        book = np.asarray(c_ex(args[0], args[1], ones)) - 8.0 * np.log10(n)
        t_book = time_per_eval(c_ex, args[0], args[1], ones, batch=5 * m, repeats=repeats)
        barton = np.asarray(c_ba(*args))
        t_ba = time_per_eval(c_ba, *args, batch=5 * m, repeats=repeats)
        shnid = np.asarray(c_sh(*sub(shn)))
        t_sh = time_per_eval(c_sh, *sub(shn), batch=shnid.size, repeats=repeats)
        cheb = np.asarray(c_ch(*args))
        t_ch = time_per_eval(c_ch, *args, batch=5 * m, repeats=repeats)
        albers = np.asarray(c_al(*sub(alb)))
        t_al = time_per_eval(c_al, *sub(alb), batch=albers.size, repeats=repeats)
        if quick:
            f32 = _finish_float32(child, tmp)
    out32, t32, ops32, dtype32 = f32
    rows = [
        Choice("exact", t_ex, ops_ex, 0.0, worst(exact, ref),
               "safeguarded Newton on the exact Pd series, float64; per Swerling case vs reference (dB): "
               + _per_case(exact, ref, SWERLINGS)),
        Choice("exact float32", t32, ops32, worst(out32, exact), worst(out32, ref),
               f"the same method with DIFFSENSE_X64=0 ({dtype32} throughout; child process); per Swerling case "
               "vs reference (dB): " + _per_case(out32, ref, SWERLINGS) + "; a precision, not an option value"),
        Choice("book", t_book, ops_ex, worst(book, exact), worst(book, ref),
               "exact single-pulse value − 8 log10 N (Brooker 8.16.13, square law): timed and sized as the exact "
               "program at N = 1 (the subtraction is negligible); per Swerling case vs reference (dB): "
               + _per_case(book, ref, SWERLINGS)),
        Choice("shnidman", t_sh, ops_sh, worst(shnid, exact[:, shn]), worst(shnid, ref[:, shn]),
               f"Shnidman 2002, Swerling 0-4, only on its domain Pd 0.1-0.99, Pfa 1e-9-1e-3 ({int(shn.sum()) * 5} of "
               f"{m * 5} points; NaN outside, so it does not cover the grid); per Swerling case vs reference (dB): "
               + _per_case(shnid, ref[:, shn], SWERLINGS)),
        Choice("albersheim", t_al, ops_al, worst(albers, exact[:1, alb]), worst(albers, ref[:1, alb]),
               f"Albersheim 1981, steady target (Swerling 0) only, on its domain Pd 0.1-0.9, Pfa 1e-7-1e-3 "
               f"({int(alb.sum())} points; refused for Swerling 1-4, NaN outside)"),
        Choice("barton", t_ba, ops_ba, worst(barton, exact), worst(barton, ref),
               "Barton 2005 universal equations (diffsense.detection.barton), the whole grid; per Swerling case "
               "vs reference (dB): " + _per_case(barton, ref, SWERLINGS)),
        Choice("chebyshev", t_ch, ops_ch, worst(cheb, exact), worst(cheb, ref),
               "Chebyshev interpolant of the exact values in (ln N, ln(ln Pfa/ln Pd − 1), ln(−ln Pfa)) "
               "(diffsense.detection.chebyshev_snr), the whole grid; per Swerling case vs reference (dB): "
               + _per_case(cheb, ref, SWERLINGS)),
        Choice("given", 0.0, 0, math.nan, math.nan,
               "the spec writes the per-pulse requirement (parameter detectability_db): no model and no cost; "
               "its error is the user's"),
    ]
    covers = {"book": True, "barton": True, "chebyshev": True, "shnidman": bool(shn.all()), "albersheim": False}
    fast = _fastest(rows, "exact", {k: v for k, v in covers.items() if v}, DB_BOUND)
    bound = (f"{DB_BOUND} dB against the reference over the whole grid; the option values that take the same "
             "parameters as exact (" + ", ".join(SAME_PARAMETER_OPTIONS) + ") are the candidates (float32 is a "
             "precision, not an option value)")
    return Family(
        key="detectability", title="Detectability: per-pulse SNR for Pd, Pfa, N pulses (radar option detectability)",
        domain=words + " (the domain of Barton's equations; Shnidman and Albersheim are measured on their own, "
        "smaller domains)", error_unit="dB",
        reference=(f"mpmath inversion of the exact Pd (tests/reference/mp_detection.py, {REFERENCE_DPS} digits, "
                   "root to 1e-12 dB)" + ("; the stored 50-digit grid tests/data/detection_reference.json where "
                                          "it has the point" if quick else "")),
        exact="exact", default="exact",
        why_default="exact to 1e-9 dB over the whole domain (Swerling 0-4, real N up to 1e4, Pfa down to 1e-300) "
        "at tens of µs per point; the approximations are off by up to 1-4 dB at Pd = 0.1 and cover smaller domains",
        choices=rows, fast=fast, fast_bound=bound if fast else bound + ": none meets it")


def _fastest(rows, default, eligible, bound):
    """The fastest eligible choice faster than ``default`` whose error vs the reference is within
    ``bound`` over the whole grid, or None."""
    t_default = next(c.seconds_per_eval for c in rows if c.name == default)
    ok = [c for c in rows if c.name in eligible and c.seconds_per_eval < t_default and c.error_vs_reference <= bound]
    return min(ok, key=lambda c: c.seconds_per_eval).name if ok else None


# --- 2. matched filter -----------------------------------------------------------------------


def _mf_reference_loss_db(x, filt):
    """Mismatch loss (dB) of a rectangular pulse (τ = 1, on [0, 1]) through ``filt`` of 3 dB
    bandwidth β = x, by quadrature of the definition ρ = max_t y(t)² / (τ ∫|H|² df), with
    y(t) = ∫_{t−τ}^{t} h(u) du and h the filter's impulse response (the inverse Fourier transform
    of H, low-pass equivalent cut off at β/2)."""
    from scipy import integrate

    def quad(f, a, b, **kw):  # round-off warnings at the requested 1e-13 are expected and harmless
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", integrate.IntegrationWarning)
            return integrate.quad(f, a, b, epsabs=1e-15, epsrel=1e-13, limit=500, **kw)[0]

    if filt == "matched":  # h(t) = s(−t): the autocorrelation of the pulse
        noise, h, span = quad(lambda t: 1.0, -1.0, 0.0), (lambda u: 1.0 if -1.0 <= u <= 0.0 else 0.0), (-1.0, 1.0)
    elif filt == "rectangular":  # H = 1 for |f| < β/2
        noise = quad(lambda f: 1.0, -x / 2, x / 2)
        h, span = (lambda u: x * np.sinc(x * u)), (-1.0, 2.0)
    elif filt == "gaussian":  # |H|² = 2^(−(2f/β)²), H = exp(−a f²)
        a = 2.0 * math.log(2.0) / x**2
        noise = quad(lambda f: math.exp(-2.0 * a * f * f), -np.inf, np.inf)
        h, span = (lambda u: math.sqrt(math.pi / a) * math.exp(-math.pi**2 * u * u / a)), (-1.0, 2.0)
    else:  # n single-tuned stages, H = (1 + j f/f0)^−n, h = ω0^n t^(n−1) e^(−ω0 t)/(n−1)!
        k = {"single_tuned": 1, "two_tuned": 2, "three_tuned": 3, "four_tuned": 4, "five_tuned": 5}[filt]
        f0 = 0.5 * x / math.sqrt(2.0 ** (1.0 / k) - 1.0)
        w0 = 2.0 * math.pi * f0
        noise = quad(lambda f: (1.0 + (f / f0) ** 2) ** -k, -np.inf, np.inf)
        h = lambda u: w0**k * u ** (k - 1) * math.exp(-w0 * u) / math.factorial(k - 1) if u > 0 else 0.0  # noqa: E731
        span = (0.0, 1.0 + (40.0 + 10.0 * k) / w0)

    def y(t):  # the breakpoints of h (its jumps and kinks) inside the interval
        inside = [p for p in (-1.0, 0.0) if t - 1.0 < p < t]
        return quad(h, t - 1.0, t, points=inside or None)

    ts = np.linspace(*span, 241)
    ys = np.array([y(t) for t in ts])
    i = int(np.argmax(ys))
    peak = y(_golden_max(y, float(ts[max(i - 1, 0)]), float(ts[min(i + 1, len(ts) - 1)])))
    return -10.0 * math.log10(peak**2 / noise)


def matched_filter(quick: bool) -> Family:
    """Family 2 (module docstring)."""
    import diffsense.detection as det
    from diffsense.detection.matched_filter import FILTERS

    names = ("matched",) + tuple(FILTERS)
    xs = np.geomspace(0.1, 2.86, 8 if quick else 40)
    # one batch: the grid's points first (their errors), then a dense sweep (the timing)
    dense = jnp.asarray(np.concatenate([xs, np.geomspace(0.1, 2.86, 2000 if quick else 20000)]))
    repeats = 3 if quick else 7

    def fn(name):
        if name == "matched":  # the chain drops the term: 0 dB
            return lambda x: jnp.zeros_like(x)
        return lambda x: det.matched_filter_loss_db(x, name)

    compiled = compile_all([(fn(k), (dense,)) for k in names], quick)
    rows = []
    for name, (c, ops) in zip(names, compiled):
        got = np.asarray(c(dense))[:len(xs)]
        want = np.array([_mf_reference_loss_db(float(x), name) for x in xs])
        t = time_per_eval(c, dense, batch=dense.size, repeats=repeats)
        note = (f"loss {want.min():.4g}-{want.max():.4g} dB over the grid; "
                + ("no term in the chain (0 dB)" if name == "matched" else "closed form (Skolnik Table 5.1 models)")
                + "; a different filter from the others, so no error against another choice")
        rows.append(Choice(name, t, ops, math.nan, worst(got, want), note))
    return Family(
        key="matched_filter",
        title="Matched filter: mismatch loss of the receiver filter (radar option matched_filter)",
        domain=f"βτ {xs[0]:g}-{xs[-1]:g}, {len(xs)} log-spaced points per filter (the rectangular filter's domain "
        "ends at 2.86); rectangular pulse", error_unit="dB",
        reference="quadrature of the definition (scipy quad, 1e-13 relative): peak of the pulse convolved with the "
        "filter's impulse response, maximised over time (241-point scan, then golden-section search), over the noise "
        "bandwidth ∫|H|² df",
        exact="matched", default="two_tuned",
        why_default="the book's receiver: two cascaded single-tuned circuits (Brooker Table 9.1 and example 9.9.1, "
        "0.56 dB at βτ = 0.613; Skolnik Table 5.1)",
        choices=rows, fast=None,
        fast_bound="none: each choice models a different receiver filter, each exact against its own definition; "
        "switching would change the radar, not the fidelity (error vs exact n/a for that reason)")


# --- 3. received-pulse width -----------------------------------------------------------------


def _golden_max(f, a, b, iterations=90):
    """Maximiser of a unimodal ``f`` on [a, b] by golden-section search, in the arithmetic of
    ``a`` and ``b`` (floats or mpmath numbers); the bracket shrinks by 0.618 per step, 90 steps
    to 1e-19 of its width: the value is then exact to round-off even at a kink (the peak of one
    tuned circuit's output, at t = τ), where a parabolic search stalls."""
    r = (5 ** type(a)(0.5) - 1) / 2
    c, d = b - r * (b - a), a + r * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iterations):
        if fc >= fd:
            b, d, fd = d, c, fc
            c = b - r * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + r * (b - a)
            fd = f(d)
    return (a + b) / 2


def _width_reference(x, filt):
    """Half-amplitude width over τ of a rectangular pulse (τ = 1, on [0, 1]) after ``filt`` (β = x):
    the envelope y(t) = g(t) − g(t − 1) from the step response g (mpmath, 30 digits), its peak by
    golden-section search and the two crossings of y = peak/2, each bracketed by a dense float64
    scan (scipy's incomplete gamma, sine integral, erf) and solved by mpmath's Anderson–Björck
    bracketing root finder."""
    import mpmath as mp
    from scipy import special

    k = {"single_tuned": 1, "two_tuned": 2, "three_tuned": 3, "four_tuned": 4, "five_tuned": 5}.get(filt)
    with mp.workdps(30):
        if k:
            w0 = 2 * mp.pi * mp.mpf(x) / 2 / mp.sqrt(mp.mpf(2) ** (mp.mpf(1) / k) - 1)
            g = lambda t: mp.gammainc(k, 0, w0 * t, regularized=True) if t > 0 else mp.mpf(0)  # noqa: E731
            gf = lambda t: special.gammainc(k, float(w0) * np.maximum(t, 0.0))  # noqa: E731
            span = (0.0, 1.0 + (60.0 + 10.0 * k) / float(w0))
        elif filt == "rectangular":
            g = lambda t: mp.mpf(1) / 2 + mp.si(mp.pi * x * t) / mp.pi  # noqa: E731
            gf = lambda t: 0.5 + special.sici(np.pi * x * t)[0] / np.pi  # noqa: E731
            span = (-0.5 - 8.0 / x, 1.5 + 8.0 / x)
        else:
            rate = mp.pi * x / mp.sqrt(2 * mp.log(2))
            g = lambda t: (1 + mp.erf(rate * t)) / 2  # noqa: E731
            gf = lambda t: 0.5 * (1.0 + special.erf(float(rate) * t))  # noqa: E731
            span = (-0.5 - 4.0 / x, 1.5 + 4.0 / x)
        y = lambda t: g(t) - g(t - 1)  # noqa: E731
        ts = np.linspace(*span, 20001)
        ys = gf(ts) - gf(ts - 1.0)
        i = int(np.argmax(ys))
        half = y(_golden_max(y, mp.mpf(ts[max(i - 1, 0)]), mp.mpf(ts[i + 1]))) / 2
        above = ys >= float(half)
        i0, i1 = int(np.argmax(above)), len(ys) - 1 - int(np.argmax(above[::-1]))
        rise = mp.findroot(lambda t: y(t) - half, (ts[i0 - 1], ts[i0]), solver="anderson")
        fall = mp.findroot(lambda t: y(t) - half, (ts[i1], ts[i1 + 1]), solver="anderson")
        return float(fall - rise)


def received_pulse_width(quick: bool) -> Family:
    """Family 3 (module docstring)."""
    from diffsense.physics.received_pulse import TUNED_STAGES, received_pulse_width_s

    filters = ("rectangular", "gaussian") + (("single_tuned", "two_tuned") if quick else tuple(TUNED_STAGES))
    k = 4 if quick else 30
    xs = {f: np.geomspace(0.1, 2.86 if f == "rectangular" else 10.0, k) for f in filters}
    kd = 300 if quick else 3000
    # one batch per filter: the grid's points first (their errors), then a dense sweep (the timing)
    dense = {f: jnp.asarray(np.concatenate([xs[f], np.geomspace(0.1, 2.86 if f == "rectangular" else 10.0, kd)]))
             for f in filters}
    repeats = 3 if quick else 7

    def root_found(*xx):  # τ = 1 µs, β = x / τ; vmapped: the tuned cascades take one β τ per call
        return jnp.stack([jax.vmap(lambda b, f=f: received_pulse_width_s(1e-6, b * 1e6, f))(x)
                          for f, x in zip(filters, xx)]) / 1e-6

    def closed_form(*xx):  # W = τ whatever the filter (the book's c τ / 2)
        return jnp.stack([jnp.full_like(x, 1e-6) for x in xx]) / 1e-6

    args = tuple(dense[f] for f in filters)
    (c_rf, ops_rf), (c_cf, ops_cf) = compile_all([(root_found, args), (closed_form, args)], quick)
    rf = np.asarray(c_rf(*args))[:, :k]
    cf = np.asarray(c_cf(*args))[:, :k]
    want = np.array([[_width_reference(float(x), f) for x in xs[f]] for f in filters])
    t_rf = time_per_eval(c_rf, *args, batch=(k + kd) * len(filters), repeats=repeats)
    t_cf = time_per_eval(c_cf, *args, batch=(k + kd) * len(filters), repeats=repeats)
    per = ", ".join(f"{f} {worst(r, w, relative=True):.2g}" for f, r, w in zip(filters, rf, want))
    rows = [
        Choice("root_found", t_rf, ops_rf, 0.0, worst(rf, want, relative=True),
               "half-amplitude crossings by safeguarded Newton on the closed-form envelope; per filter: " + per),
        Choice("closed_form", t_cf, ops_cf, worst(cf, rf, relative=True), worst(cf, want, relative=True),
               f"W = τ (the book's c τ / 2; exact for the matched filter, which the chain then uses); W/τ ranges "
               f"{want.min():.3g}-{want.max():.3g} over the grid, worst at βτ = 0.1"),
    ]
    return Family(
        key="received_pulse_width", title="Received-pulse width: range resolution c W / 2 after the IF filter",
        domain=f"βτ 0.1-10 (rectangular filter 0.1-2.86), {k} log-spaced points for each of {', '.join(filters)}",
        error_unit="relative",
        reference="mpmath (30 digits): the envelope from each filter's step response (incomplete gamma, sine "
        "integral, erf), its peak and half-amplitude crossings bracketed on a 20,001-point scan and root-found",
        exact="root_found", default="root_found",
        why_default="the chain's received width for every filter but the matched one (range resolution, range gate, "
        "clutter-cell length); the closed form τ is exact only for the matched filter",
        choices=rows, fast=None,
        fast_bound=f"{WIDTH_BOUND:g} relative (0.1 % of the range resolution): the closed form is off by up to "
        f"{rows[1].error_vs_reference:.2g}")


# --- the module's entry points ---------------------------------------------------------------


def run(quick: bool) -> list:
    """The three families of this module (module docstring)."""
    return [detectability(quick), matched_filter(quick), received_pulse_width(quick)]


def _num(x):
    if x is None:
        return "–"
    return "n/a" if isinstance(x, float) and math.isnan(x) else f"{x:.3g}"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "--float32-child":
        return _float32_child(argv[1], argv[2], int(argv[3]), argv[4] == "quick")
    main_alone(run, __doc__, argv)


if __name__ == "__main__":
    main()
