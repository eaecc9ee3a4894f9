"""float32 accuracy of diffsense.detection.pd against the mpmath reference.

Run: python benchmarks/float32_accuracy.py [--quick] (needs mpmath, in the ``bench`` extras).
``--quick`` prints the same table on a smaller grid (N = 1, 10; Pfa = 1e-6; SNR = -5, 10, 25 dB).

Grid: Swerling 0-4, N = 1, 10, 100, Pfa = 1e-3, 1e-6, 1e-10, SNR = -5, 0, ..., 25 dB. The
float32 values come from a child process started with ``DIFFSENSE_X64=0`` (JAX keeps its 32-bit
default and ``pd`` follows its float32 inputs), once through the general kernel (arrays of
Pfa and N) and, for Swerling 0, once through the fast kernel used when Pfa and N are single
numbers. The reference is ``tests/reference/mp_detection.pd_mp`` at 30 digits, evaluated at the
float32-rounded inputs (the SNRs and N are exact in float32; Pfa is rounded to float32 first).

``tests/detection/test_detection_float32.py`` asserts the error bound with the same functions.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

SWERLINGS = (0, 1, 2, 3, 4)
PULSES = (1, 10, 100)
PFAS = (1e-3, 1e-6, 1e-10)
SNRS_DB = tuple(float(x) for x in np.linspace(-5.0, 25.0, 7))
#: the smaller grid of ``--quick``
QUICK_GRID = dict(swerlings=SWERLINGS, pulses=(1, 10), pfas=(1e-6,), snrs_db=(-5.0, 10.0, 25.0))

_ROOT = Path(__file__).resolve().parent.parent


def grid(swerlings=SWERLINGS, pulses=PULSES, pfas=PFAS, snrs_db=SNRS_DB):
    """Flat arrays (swerling, n, pfa, snr_db) of the grid; pfa and snr_db rounded to float32."""
    sw, n, pfa, snr = np.meshgrid(swerlings, pulses, pfas, snrs_db, indexing="ij")
    return (
        sw.ravel().astype(int),
        n.ravel().astype(float),
        pfa.ravel().astype(np.float32).astype(float),
        snr.ravel().astype(np.float32).astype(float),
    )


def reference_pd(swerling, n, pfa, snr_db, dps=30):
    """mpmath Pd at each grid point (float64 array of the 30-digit values)."""
    import mpmath as mp

    from tests.reference import mp_detection as ref

    return np.array(
        [
            float(ref.pd_mp(mp.mpf(10) ** (mp.mpf(s) / 10), p, int(k), int(sw_), dps=dps))
            for sw_, k, p, s in zip(swerling, n, pfa, snr_db)
        ]
    )


def _evaluate_here(points):
    """Child side: Pd in float32 for the points (dict of lists), both kernels for Swerling 0."""
    import jax
    import jax.numpy as jnp

    import diffsense.detection as det

    if jax.config.jax_enable_x64:
        raise RuntimeError("float32 evaluation needs DIFFSENSE_X64=0 before diffsense is imported")
    sw = np.asarray(points["swerling"], dtype=int)
    f32 = lambda key: jnp.asarray(np.asarray(points[key], dtype=np.float32))
    snr, pfa, n = f32("snr_db"), f32("pfa"), f32("n")
    general = np.empty(len(sw))
    for case in sorted(set(sw.tolist())):
        m = np.flatnonzero(sw == case)
        f = jax.jit(lambda s, p, k, case=case: det.pd(s, p, k, case))
        out = f(snr[m], pfa[m], n[m])
        if out.dtype != jnp.float32:
            raise RuntimeError(f"expected float32 output, got {out.dtype}")
        general[m] = np.asarray(out, dtype=float)
    # Swerling 0 with one Pfa and N per call: the fast kernel (steady.py).
    fast = np.full(len(sw), np.nan)
    f0 = jax.jit(lambda s, p, k: det.pd(s, p, k, 0))
    m0 = np.flatnonzero(sw == 0)
    for key in sorted({(float(points["pfa"][i]), float(points["n"][i])) for i in m0}):
        m = m0[(np.asarray(points["pfa"])[m0] == key[0]) & (np.asarray(points["n"])[m0] == key[1])]
        fast[m] = np.asarray(f0(snr[m], jnp.float32(key[0]), jnp.float32(key[1])), dtype=float)
    return {"general": general.tolist(), "fast_swerling0": fast.tolist()}


def evaluate_float32(swerling, n, pfa, snr_db, timeout=600):
    """Pd in float32 from a child process with DIFFSENSE_X64=0: (general kernel, fast Swerling-0 kernel).

    The second array is NaN except at the Swerling-0 points.
    """
    points = {
        "swerling": np.asarray(swerling).tolist(),
        "n": np.asarray(n, dtype=float).tolist(),
        "pfa": np.asarray(pfa, dtype=float).tolist(),
        "snr_db": np.asarray(snr_db, dtype=float).tolist(),
    }
    env = dict(os.environ, DIFFSENSE_X64="0")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(_ROOT), env.get("PYTHONPATH", "")) if p)
    proc = subprocess.run(
        [sys.executable, str(Path(__file__).resolve()), "--evaluate"],
        input=json.dumps(points),
        capture_output=True,
        text=True,
        env=env,
        cwd=_ROOT,
        timeout=timeout,
    )
    if proc.returncode != 0:
        raise RuntimeError(f"float32 evaluation failed:\n{proc.stderr[-4000:]}")
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    return np.array(out["general"]), np.array(out["fast_swerling0"])


def main(quick=False):
    axes = QUICK_GRID if quick else dict(swerlings=SWERLINGS, pulses=PULSES, pfas=PFAS, snrs_db=SNRS_DB)
    sw, n, pfa, snr = grid(**axes)
    want = reference_pd(sw, n, pfa, snr)
    general, fast = evaluate_float32(sw, n, pfa, snr)
    err = np.abs(general - want)
    err_fast = np.abs(fast - want)
    print(f"float32 max |Pd - Pd_mpmath| over Pfa {'/'.join(f'{p:.0e}'.replace('e-0', 'e-') for p in axes['pfas'])} "
          f"and SNR {min(axes['snrs_db']):g}...{max(axes['snrs_db']):g} dB")
    print(f"{'Swerling':>8s} {'N':>5s} {'max |dPd|':>10s} {'at SNR dB, Pfa':>16s}")
    for case in axes["swerlings"]:
        for k in axes["pulses"]:
            m = np.flatnonzero((sw == case) & (n == k))
            i = m[np.argmax(err[m])]
            print(f"{case:8d} {k:5d} {err[i]:10.2e} {snr[i]:8.0f}, {pfa[i]:.0e}")
    m0 = sw == 0
    print(f"Swerling 0, fast kernel (scalar Pfa and N): max |dPd| = {np.max(err_fast[m0]):.2e}")
    worst = max(float(np.max(err)), float(np.max(err_fast[m0])))
    finite = bool(np.all(np.isfinite(general)) and np.all(np.isfinite(fast[m0])))
    print(f"float32 worst |dPd| = {worst:.2e} over {len(sw)} points (all finite: {finite})")


if __name__ == "__main__":
    if "--evaluate" in sys.argv[1:]:
        print(json.dumps(_evaluate_here(json.loads(sys.stdin.read()))))
    else:
        import argparse

        import _support  # the repository root on sys.path (tests.reference)

        ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
        ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
        _support.require("float32_accuracy.py", "mpmath")
        main(quick=ap.parse_args().quick)
