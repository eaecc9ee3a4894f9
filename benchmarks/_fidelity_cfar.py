"""Fidelity family of the CFAR loss (for ``bench_fidelity.py``).

**CFAR loss** (the radar option ``cfar_model``): the extra SNR a detector whose threshold is set
from reference cells needs over one that knows the noise, for Pd at Pfa, one square-law sample
per cell. Choices — each a different processor, exact against its own definition (as the
matched-filter family's filters are), not approximations of one another:

* ``cell_averaging`` — the sum of n cells (:func:`diffsense.detection.cfar_loss_db`);
* ``ordered_statistic`` — the k-th smallest of n cells, k = ceil(3n/4) (``os_cfar_loss_db``);
* ``greatest_of`` / ``smallest_of`` — the greater / smaller of two half-window sums of n/2 cells
  each (``go_cfar_loss_db``, ``so_cfar_loss_db``);
* ``given`` — the spec writes the loss (book 9.9.1: 0.7 dB): no model and no cost.

Reference (Swerling 1, mpmath at 30 digits): with L(t) = E[exp(-t X)] the Laplace transform of
the processor's noise estimate X (unit-mean cells), Pfa = L(T) and Pd = L(T/(1 + S)), so the
required SNR is S = T_fa/T_d - 1 with L(T_fa) = Pfa, L(T_d) = Pd (mpmath ``findroot``, log form),
and the loss 10 log10(S / S0) against the known-noise S0 = ln Pfa / ln Pd - 1. The transforms:
CA (1 + t)^-n; OS Rohling's product prod_{i<k} (n - i)/(n - i + t); GO
2 (1 + t)^-m I_{1/(2+t)}(m, m) and SO 2 (1 + t)^-m - L_GO(t) with m = n/2 (the greater and the
smaller of two iid Gamma(m) sums add up to both sums; ``tests/benchmarks/test_fidelity_cfar.py``
checks both against mpmath quadrature of their definitions).

MathWorks' ``cfarloss`` approximates the CA loss by Gregers-Hansen's universal curve, a loss of
the CFAR ratio chi = -log10(Pfa)/n alone, and has a GO method; neither takes Pd. The curve is not
published as a formula, so it is not reproduced; but a loss of chi alone takes one value at grid
points of equal chi, so its worst error on the grid is at least half the spread of the exact
losses over each such group (every Pd of a (Pfa, n) pair, and pairs such as (1e-3, 8),
(1e-6, 16), (1e-12, 32)); a loss of (Pfa, n) alone, at least half the spread over Pd. The rows
``universal curve (CA)`` (chi alone) and ``cfarloss GO`` ((Pfa, n) alone: how MathWorks maps the
GO window onto the curve is not published) state those lower bounds (:func:`pd_free_error_bound`);
they have no time, since nothing of ours runs.

Times: each choice jitted over the grid, one row per cell count (the counts are static in the
package's functions), the grid's points repeated to 512 columns per row (``quick``: 64), warm
median per point; HLO operations per row; compiled with the package's "optimized" XLA options
(``quick``: "fast", so its times are indicative only).

Run alone: python benchmarks/_fidelity_cfar.py [--quick] (needs mpmath, in the ``bench`` extras).
"""

from __future__ import annotations

import math
import sys

import _support

_support.require("_fidelity_cfar.py", "mpmath")

import diffsense  # noqa: E402,F401  (float64)
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from _fidelity_support import Choice, Family, main_alone, measure_tiled, worst  # noqa: E402

FULL_CELLS, QUICK_CELLS = (8, 16, 32, 64), (16,)
FULL_PDS, QUICK_PDS = (0.5, 0.9, 0.99), (0.5, 0.9)
FULL_PFAS, QUICK_PFAS = (1e-3, 1e-6, 1e-9, 1e-12), (1e-6,)
TIMING_COLUMNS, QUICK_TIMING_COLUMNS = 512, 64
REFERENCE_DPS = 30
#: the OS rank as a fraction of the cells (Rohling 1983: about 3/4; the radar's default)
RANK_FRACTION = 0.75
PROCESSORS = ("cell_averaging", "ordered_statistic", "greatest_of", "smallest_of")


def os_rank(n: int) -> int:
    return math.ceil(RANK_FRACTION * n - 1e-9)


def laplace_mp(processor: str, t, n: int):
    """L(t) of the processor's noise estimate with n unit-mean exponential cells (mpmath)."""
    from mpmath import mp

    if processor == "cell_averaging":
        return (1 + t) ** (-n)
    if processor == "ordered_statistic":
        return mp.fprod((n - i) / (n - i + t) for i in range(os_rank(n)))
    m = n // 2
    go = 2 * (1 + t) ** (-m) * mp.betainc(m, m, 0, 1 / (2 + t), regularized=True)
    return go if processor == "greatest_of" else 2 * (1 + t) ** (-m) - go


def loss_mp(processor: str, pd, pfa, n: int) -> float:
    """The Swerling 1 CFAR loss (dB) of the module docstring, at 30 digits."""
    from mpmath import mp

    with mp.workdps(REFERENCE_DPS):
        def root(target):  # L decreases from 1: solve log L(e^u) = log target in u = log t
            f = lambda u: mp.log(laplace_mp(processor, mp.exp(u), n)) - mp.log(target)  # noqa: E731
            lo, hi = mp.mpf(-60), mp.mpf(60)
            for _ in range(60):  # a bracket for the secant iteration
                mid = (lo + hi) / 2
                lo, hi = (mid, hi) if f(mid) > 0 else (lo, mid)
            return mp.exp(mp.findroot(f, (lo, hi), solver="anderson"))

        pd, pfa = mp.mpf(pd), mp.mpf(pfa)
        s = root(pfa) / root(pd) - 1
        s0 = mp.log(pfa) / mp.log(pd) - 1
        return float(10 * mp.log10(s / s0))


def pd_free_error_bound(losses, cells, row, chi_only: bool) -> float:
    """The least worst error (dB) against ``losses`` (one row per cell count of ``cells``, one
    column per (pd, pfa) of ``row``) of any loss that does not depend on Pd: half the largest
    spread of the losses over a group of grid points it cannot tell apart. ``chi_only``: it
    depends on chi = -log10(Pfa)/n alone (groups: equal chi, as an exact fraction of the rounded
    decades of Pfa and n; a Pfa not a power of ten is its own group); else on (Pfa, n)."""
    from fractions import Fraction

    groups = {}
    for i, n in enumerate(cells):
        for j, (_, pfa) in enumerate(row):
            decades = -math.log10(pfa)
            whole = abs(decades - round(decades)) < 1e-12
            key = Fraction(round(decades), n) if chi_only and whole else (pfa, n)
            groups.setdefault(key, []).append(float(losses[i][j]))
    return max((max(v) - min(v)) / 2 for v in groups.values())


def _loss_fn(processor: str, cells):
    """``f(pd, pfa)`` (one row per cell count) -> the package's loss (dB), Swerling 1."""
    import diffsense.detection as det

    def one(pd, pfa, n):
        if processor == "cell_averaging":
            return det.cfar_loss_db(pd, pfa, float(n), 1.0, 1)
        if processor == "ordered_statistic":
            return det.os_cfar_loss_db(pd, pfa, n, os_rank(n), 1)
        return (det.go_cfar_loss_db if processor == "greatest_of" else det.so_cfar_loss_db)(pd, pfa, n, 1)

    def f(pd, pfa):
        return jnp.stack([one(pd[i], pfa[i], n) for i, n in enumerate(cells)])

    return f


def cfar_loss(quick: bool) -> Family:
    """The family (module docstring)."""
    repeats = 3 if quick else 7
    columns = QUICK_TIMING_COLUMNS if quick else TIMING_COLUMNS
    cells, pds, pfas = (QUICK_CELLS, QUICK_PDS, QUICK_PFAS) if quick else (FULL_CELLS, FULL_PDS, FULL_PFAS)
    row = [(pd, pfa) for pfa in pfas for pd in pds]
    grid = tuple(jnp.asarray(np.array([[p[k] for p in row]] * len(cells), dtype=float)) for k in (0, 1))
    rows, refs = [], {}
    measured = measure_tiled([(_loss_fn(processor, cells), grid) for processor in PROCESSORS], repeats, columns,
                             quick)
    for processor, (out, seconds, ops) in zip(PROCESSORS, measured):
        ref = refs[processor] = np.array([[loss_mp(processor, pd, pfa, n) for pd, pfa in row] for n in cells])
        per_n = ", ".join(f"n = {n}: {worst(out[i], ref[i]):.2g}" for i, n in enumerate(cells))
        span = f"{np.min(ref):.3g}-{np.max(ref):.3g} dB"
        what = {"cell_averaging": "sum of n cells",
                "ordered_statistic": f"k-th smallest of n cells, k = ceil({RANK_FRACTION} n)",
                "greatest_of": "greater of two half-window sums (n/2 cells each)",
                "smallest_of": "smaller of two half-window sums (n/2 cells each)"}[processor]
        rows.append(Choice(processor, seconds, ops, math.nan, worst(out, ref),
                           f"{what}; losses over the grid {span}; worst error per cell count (dB): {per_n}"))
    for processor, name, chi_only in (("cell_averaging", "universal curve (CA)", True),
                                      ("greatest_of", "cfarloss GO", False)):
        bound = pd_free_error_bound(refs[processor], cells, row, chi_only)
        of = "chi = -log10(Pfa)/n alone" if chi_only else "Pfa and n alone (not of Pd)"
        rows.append(Choice(name, math.nan, None, math.nan, math.nan,
                           f"MathWorks cfarloss (Gregers-Hansen's curve; not published as a formula, so not reproduced "
                           f"or timed): any loss of {of} is off by at least {bound:.2g} dB somewhere on this grid "
                           f"(half the spread of the exact {processor} losses over points it cannot tell apart)"))
    rows.append(Choice("given", 0.0, 0, math.nan, math.nan,
                       "the spec writes the loss (parameter cfar_loss_db; book 9.9.1: 0.7 dB): no model and no cost; "
                       "its error is the user's"))
    words = (f"Swerling 1, one square-law sample per cell; n = {', '.join(map(str, cells))} reference cells "
             f"(GO/SO: two half windows of n/2; OS: k = ceil({RANK_FRACTION} n)) × Pd {', '.join(map(str, pds))} × "
             f"Pfa {', '.join(f'{p:g}' for p in pfas)}: {len(cells) * len(row)} points per processor")
    return Family(
        key="cfar", title="CFAR loss (radar option cfar_model)", domain=words, error_unit="dB",
        reference=f"mpmath ({REFERENCE_DPS} digits): the multipliers T(Pfa), T(Pd) as roots of each processor's "
        "Laplace transform (CA, Rohling's OS product, the GO/SO incomplete-beta forms), then "
        "10 log10[(T(Pfa)/T(Pd) - 1) / (ln Pfa / ln Pd - 1)]",
        exact="cell_averaging", default="given",
        why_default="the book's budget states the CFAR loss as a number (0.7 dB); a spec that names a processor "
        "gets its exact loss",
        choices=rows, fast=None,
        fast_bound="none: each processor is a different detector, each exact against its own definition; switching "
        "would change the radar, not the fidelity (error vs exact n/a for that reason); MathWorks' cfarloss is "
        "not reproduced: its rows state the least error any loss without Pd has on the grid")


def run(quick: bool) -> list:
    """The family of this module."""
    return [cfar_loss(quick)]


if __name__ == "__main__":
    main_alone(run, __doc__, sys.argv[1:])
