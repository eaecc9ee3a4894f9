"""Fidelity family of M-of-N binary integration (for ``bench_fidelity.py``).

**Binary integration** (the radar option ``integration = "binary"``, parameter ``binary_m``): the
per-pulse SNR needed for an overall Pd at an overall Pfa when a detection is declared on at least
M of N pulses, each thresholded on its own. Swerling 0, 2 and 4 (the pulses' fluctuations are
independent, so the crossings are Bernoulli trials; Swerling 1 and 3 share one RCS draw over the
dwell and have no per-pulse shortcut). Choices:

* ``exact`` — :func:`diffsense.detection.required_snr_binary_db` (the package's only choice:
  binomial inversion for the per-pulse probabilities, then the exact single-pulse solver);
* ``per-pulse Shnidman`` and ``per-pulse Albersheim`` — what a tool without the exact law does
  (Richards 2014, sec. 6.4; MathWorks' ``binaryintloss`` reports the per-pulse probabilities for
  this use): the same exact per-pulse probabilities p_d = B^-1(Pd), p_f = B^-1(Pfa), with
  B(p) = P(Bin(N, p) >= M), then Shnidman's (2002) single-pulse equation for the per-pulse case
  (Swerling 0 -> 0, 2 -> 1, 4 -> 3) or Albersheim's (1981, Swerling 0). The per-pulse p_f of a
  useful M lies far above the 1e-3 both equations were fitted to, so they are evaluated by their
  formulas outside their stated domains (the package refuses that; these rows are not options).

Reference: mpmath (30 digits) — p_f and p_d by bisection of the regularized incomplete beta
function ``B(p) = I_p(M, N - M + 1)`` (``tests/reference/mp_binomial.py``), then the single-pulse requirement of the per-pulse case by
``tests/reference/mp_detection.py`` (Swerling 1: the closed form S = ln p_f / ln p_d - 1).

Times: each choice jitted over the grid, one row per Swerling case (the case is static in the
package's functions, the counts are arrays), the grid's points repeated to 512 columns per case
(``quick``: 64), warm median per point; HLO operations per case (a program holds one copy per case); compiled
with the package's "optimized" XLA options (``quick``: "fast", so its times are indicative only).

Run alone: python benchmarks/_fidelity_binary.py [--quick] (needs mpmath, in the ``bench`` extras).
"""

from __future__ import annotations

import math
import sys

import _support

_support.require("_fidelity_binary.py", "mpmath")

import diffsense  # noqa: E402,F401  (float64)
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from _fidelity_support import Choice, Family, main_alone, measure_tiled, worst  # noqa: E402

#: the per-pulse Swerling case of each overall case with independent pulses
PER_PULSE = {0: 0, 2: 1, 4: 3}
FULL_PDS = (0.5, 0.9, 0.99, 0.999)
FULL_PFAS = (1e-3, 1e-6, 1e-9, 1e-12)
#: (N, M) near the optimum M of a steady target (Shnidman's fit 10^-0.02 N^0.8), and two far from it
NEAR_OPTIMUM = ((5, 3), (10, 6), (24, 12), (50, 21), (100, 37))
FULL_COUNTS = NEAR_OPTIMUM + ((10, 2), (10, 10))
QUICK_PDS, QUICK_PFAS, QUICK_COUNTS, QUICK_CASES = (0.5, 0.9), (1e-6,), ((24, 12),), (0, 2)
#: columns of the timing batch per Swerling case: the grid's points repeated
TIMING_COLUMNS, QUICK_TIMING_COLUMNS = 512, 64
REFERENCE_DPS = 30
DB_BOUND = 0.01


def _reference(points):
    """Per point (pd, pfa, n, m, swerling): the mpmath per-pulse requirement (dB) and (p_d, p_f)."""
    import mpmath as mp

    from tests.reference import mp_detection as ref
    from tests.reference.mp_binomial import level_mp

    out = []
    with mp.workdps(REFERENCE_DPS):
        for pd, pfa, n, m, sw in points:
            p_d, p_f = level_mp(pd, n, m), level_mp(pfa, n, m)
            if PER_PULSE[sw] == 1:
                value = float(10 * mp.log10(mp.log(p_f) / mp.log(p_d) - 1))
            else:
                value = float(ref.required_snr_mp(p_d, p_f, 1, PER_PULSE[sw], dps=REFERENCE_DPS))
            out.append((value, float(p_d), float(p_f)))
    return out


def _axes(quick: bool):
    """(Pd values, Pfa values, (N, M) pairs, Swerling cases) of the grid."""
    if quick:
        return QUICK_PDS, QUICK_PFAS, QUICK_COUNTS, QUICK_CASES
    return FULL_PDS, FULL_PFAS, FULL_COUNTS, tuple(PER_PULSE)


def _grid(quick: bool):
    pds, pfas, counts, cases = _axes(quick)
    points = [(pd, pfa, n, m, sw) for sw in cases for (n, m) in counts for pfa in pfas for pd in pds]
    words = (f"Pd {', '.join(map(str, pds))} × Pfa {', '.join(f'{p:g}' for p in pfas)} × (N, M) "
             f"{', '.join(f'({n}, {m})' for n, m in counts)}; Swerling {', '.join(map(str, cases))}: "
             f"{len(points)} points")
    return points, words


def _exact_fn(cases):
    """``f(pd, pfa, n, m)`` (rows: the Swerling cases ``cases``) -> required per-pulse SNR (dB); the
    case is static in the package's function, the counts are arrays."""
    import diffsense.detection as det

    def f(pd, pfa, n, m):
        return jnp.stack([det.required_snr_binary_db(pd[i], pfa[i], n[i], m[i], sw) for i, sw in enumerate(cases)])

    return f


def _per_pulse_fn(equation, cases):
    """The per-pulse probabilities by the package's exact binomial inversion, then ``equation``."""
    from diffsense.detection import per_trial_pfa_binary

    def f(pd, pfa, n, m):
        return jnp.stack([equation(per_trial_pfa_binary(pd[i], n[i], m[i]), per_trial_pfa_binary(pfa[i], n[i], m[i]),
                                   PER_PULSE[sw]) for i, sw in enumerate(cases)])

    return f


def _shnidman(p_d, p_f, sw):
    from diffsense.detection.required_snr import _shnidman as shnidman_formula

    return shnidman_formula(p_d, p_f, jnp.ones_like(p_d), sw)


def _albersheim(p_d, p_f, sw):
    """Albersheim's (1981) equation with one pulse: (6.2 + 4.54/sqrt(1.44)) log10(A + 0.12 A B + 1.7 B),
    A = ln(0.62/p_f), B = ln(p_d/(1 - p_d)); by its formula, without the package's domain check."""
    a = jnp.log(0.62 / p_f)
    b = jnp.log(p_d / (1.0 - p_d))
    return (6.2 + 4.54 / math.sqrt(1.44)) * jnp.log10(a + 0.12 * a * b + 1.7 * b)


def binary_integration(quick: bool) -> Family:
    """The family (module docstring)."""
    repeats = 3 if quick else 7
    columns = QUICK_TIMING_COLUMNS if quick else TIMING_COLUMNS
    points, words = _grid(quick)
    pds, pfas, counts, cases = _axes(quick)
    row = [(n, m, pd, pfa) for (n, m) in counts for pfa in pfas for pd in pds]  # one case's points
    grid = tuple(jnp.asarray(np.array([[p[k] for p in row]] * len(cases), dtype=float)) for k in (2, 3, 0, 1))
    ref_rows = _reference(points)
    ref = np.array([r[0] for r in ref_rows]).reshape(grid[0].shape)
    total = ref.size

    (exact, t_ex, ops_ex), (shn, t_sh, ops_sh), (alb, t_al, ops_al) = measure_tiled(
        [(_exact_fn(cases), grid), (_per_pulse_fn(_shnidman, cases), grid),
         (_per_pulse_fn(_albersheim, (0,)), tuple(a[:1] for a in grid))],
        repeats, columns, quick)
    p_f = np.array([r[2] for r in ref_rows])
    outside = int(np.sum(p_f > 1e-3))
    near = np.array([p[:2] in NEAR_OPTIMUM for p in row])  # columns at (N, M) near the optimum M
    alb_ok = np.isfinite(alb)

    def per_case(out, which, columns=None):
        r = ref if columns is None else ref[:, columns]
        return ", ".join(f"Swerling {sw}: {worst(out[i], r[i]):.3g}" for i, sw in enumerate(which))

    rows = [
        Choice("exact", t_ex, ops_ex, 0.0, worst(exact, ref),
               "required_snr_binary_db: binomial inversion, then the exact single-pulse solver; per case vs "
               "reference (dB): " + per_case(exact, cases)),
        Choice("per-pulse Shnidman", t_sh, ops_sh, worst(shn, exact), worst(shn, ref),
               f"exact per-pulse probabilities, then Shnidman's single-pulse equation (Swerling 0→0, 2→1, 4→3); "
               f"the per-pulse Pfa exceeds its fitted 1e-3 at {outside} of {total} points; not an option; per case "
               f"vs reference (dB): {per_case(shn, cases)}; at M near the optimum only: "
               f"{per_case(shn[:, near], cases, near)}"),
        Choice("per-pulse Albersheim", t_al, ops_al, worst(alb[alb_ok], exact[:1][alb_ok]),
               worst(alb[alb_ok], ref[:1][alb_ok]),
               "exact per-pulse probabilities, then Albersheim's equation, Swerling 0 only; outside its fitted "
               f"Pd 0.1-0.9, Pfa 1e-7-1e-3 at most points; not a number at {int((~alb_ok).sum())} of {alb.size} "
               "points (the argument of its logarithm turns negative; the errors are over the others); not an "
               f"option; at M near the optimum only: {worst(alb[alb_ok & near], ref[:1][alb_ok & near]):.3g} dB"),
    ]
    return Family(
        key="binary", title="Binary (M-of-N) integration: per-pulse SNR for overall Pd, Pfa (radar option "
        "integration = \"binary\")",
        domain=words, error_unit="dB",
        reference=f"mpmath ({REFERENCE_DPS} digits): binomial inversion by bisection of I_p(M, N-M+1), then the "
        "single-pulse requirement of tests/reference/mp_detection.py (Swerling 1 closed form)",
        exact="exact", default="exact",
        why_default="the only model the package offers for M-of-N integration; exact to 1e-9 dB",
        choices=rows, fast=None,
        fast_bound=f"none: {DB_BOUND} dB; the per-pulse equations are not options (and miss it: see their errors)")


def run(quick: bool) -> list:
    """The family of this module."""
    return [binary_integration(quick)]


if __name__ == "__main__":
    main_alone(run, __doc__, sys.argv[1:])
