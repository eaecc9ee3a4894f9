"""Required SNR from a Chebyshev interpolant of the exact values: the fast detectability.

``chebyshev_snr_db(pd, pfa, n, swerling)`` is a tensor-product Chebyshev series fitted to the
exact :func:`diffsense.detection.required_snr_db` (noncoherent integration of N square-law
pulses, Swerling 0-4) in three coordinates on which the requirement is smooth,

    a = ln N,    b = ln(ln Pfa / ln Pd - 1),    c = ln(-ln Pfa),

each mapped linearly onto [-1, 1] over the box that holds the domain below. ``b`` makes
Swerling 1 with one pulse exactly linear (S = ln Pfa / ln Pd - 1, so 10 log10 S = 10 b / ln 10)
and moves the logarithmic singularity of the requirement at Pd = Pfa to b = -inf, off the box;
``c`` spreads the false-alarm decades evenly. The coefficients come from the exact values at the
tensor grid of Chebyshev points of the first kind (a discrete cosine transform per axis:
interpolation, not a least-squares fit) and are stored in ``data/chebyshev_snr.npz``, written by
``python -m diffsense.detection.chebyshev_fit --write`` (:mod:`diffsense.detection.chebyshev_fit`). Evaluation is the three
three-term recurrences and one contraction with the coefficients: tens of operations in a
compiled program instead of the exact solver's thousands, with derivatives in pd, pfa and n
those of the polynomial (smooth, never through an iteration).

**Domain** (the radar's ``pd``, ``pfa`` and ``n_pulses`` parameters): 0.05 <= Pd <= 1 - 1e-6,
1e-15 <= Pfa <= 1e-2, real 1 <= N <= 1e4. An eager call outside raises
:class:`~diffsense.errors.DomainError`; a traced call returns NaN.

**Error** (stated bound :data:`ERROR_BOUND_DB` = 0.001 dB, asserted by
tests/detection/test_chebyshev_snr.py): against the exact solver at 20,000 random points of the
domain per Swerling case the worst error measured 1.2e-4 dB (Swerling 0), 5.5e-5 (1) and 6.0e-5
(2, 3, 4); the test also checks every midpoint between Chebyshev points (where an interpolant
errs most) and the Swerling 1 closed form. Derivatives, in dB per unit of logit(pd), ln pfa and
ln n, are within 3.5e-4, 2.8e-4 and 2.5e-4 dB of the exact implicit ones (400 random points, a
quarter with Pd within 0.1 of 1; the test asserts 0.002 dB). Against the 30-digit mpmath reference on the
run-time-against-error atlas's grid: ``benchmarks/bench_fidelity.py``, docs/speed_accuracy.md.

Sources: L. N. Trefethen, *Approximation Theory and Approximation Practice*, SIAM (2013), ch. 3-8
(Chebyshev interpolation, its convergence for analytic functions, the cosine transform).
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path
from typing import Dict, Tuple

import jax.numpy as jnp
import numpy as np

from diffsense.detection._domain import admit, guard
from diffsense.detection.core import SWERLING_CASES

__all__ = ["chebyshev_snr_db", "coordinates", "inputs_at", "series", "box", "PD_RANGE", "PFA_RANGE", "N_RANGE", "POINTS",
           "ERROR_BOUND_DB", "DATA"]

PD_RANGE = (0.05, 1.0 - 1e-6)
PFA_RANGE = (1e-15, 1e-2)
N_RANGE = (1.0, 1e4)
#: points per axis (a = ln N, b, c): the series has degree one less on each
POINTS = (20, 18, 8)
#: worst error against the exact solver over the domain, stated (the test asserts it)
ERROR_BOUND_DB = 0.001
DATA = Path(__file__).resolve().parent / "data" / "chebyshev_snr.npz"


def box() -> Tuple[Tuple[float, float], ...]:
    """The (lo, hi) of each coordinate over the domain's corners (b is monotone in Pd and Pfa)."""
    b = lambda pd, pfa: math.log(math.log(pfa) / math.log(pd) - 1.0)
    return ((0.0, math.log(N_RANGE[1])),
            (b(PD_RANGE[0], PFA_RANGE[1]), b(PD_RANGE[1], PFA_RANGE[0])),
            (math.log(-math.log(PFA_RANGE[1])), math.log(-math.log(PFA_RANGE[0]))))


def coordinates(pd, pfa, n):
    """(a, b, c) mapped onto [-1, 1]."""
    log_pd, log_pfa = jnp.log(pd), jnp.log(pfa)
    raw = (jnp.log(n), jnp.log((log_pfa - log_pd) / log_pd), jnp.log(-log_pfa))
    return tuple((2.0 * r - (lo + hi)) / (hi - lo) for r, (lo, hi) in zip(raw, box()))


def inputs_at(xs):
    """(pd, pfa, n) at mapped coordinates ``xs = (a, b, c)`` (each in [-1, 1], NumPy, broadcast):
    the inverse of :func:`coordinates`."""
    raw = [0.5 * (lo + hi) + 0.5 * (hi - lo) * np.asarray(x) for x, (lo, hi) in zip(xs, box())]
    log_pfa = -np.exp(raw[2])
    log_pd = log_pfa / (1.0 + np.exp(raw[1]))
    return np.exp(log_pd), np.exp(log_pfa), np.exp(raw[0])


def _chebyshev_values(x, size: int):
    """T_0(x) ... T_{size-1}(x) along a new last axis (three-term recurrence)."""
    out = [jnp.ones_like(x), x]
    for _ in range(size - 2):
        out.append(2.0 * x * out[-1] - out[-2])
    return jnp.stack(out[:size], axis=-1)


def series(coefficients, a, b, c):
    """sum_ijk C_ijk T_i(a) T_j(b) T_k(c) for mapped coordinates (broadcast)."""
    ta, tb, tc = (_chebyshev_values(x, k) for x, k in zip((a, b, c), coefficients.shape))
    inner = jnp.einsum("...k,ijk->...ij", tc, coefficients)
    return jnp.einsum("...i,...j,...ij->...", ta, tb, inner)


@lru_cache(maxsize=1)
def _stored() -> Dict[int, np.ndarray]:
    with np.load(DATA) as data:
        return {sw: np.asarray(data[f"swerling{sw}"], dtype=np.float64) for sw in (0, 1, 2, 3, 4)}


def chebyshev_snr_db(pd, pfa, n=1, swerling=0):
    """Per-pulse SNR (dB) for detection probability ``pd`` at ``pfa`` with ``n`` noncoherently
    integrated square-law pulses, from the Chebyshev interpolant of the exact values (module
    docstring).

    Args:
        pd: detection probability, 0.05 ... 1 - 1e-6.
        pfa: false-alarm probability, 1e-15 ... 1e-2.
        n: pulses, real 1 ... 1e4.
        swerling: 0 (= 5), 1, 2, 3, 4 — static.

    Returns:
        The detectability factor in dB, within :data:`ERROR_BOUND_DB` of the exact
        :func:`diffsense.detection.required_snr_db` over the domain (measured, module docstring).
        Differentiable in pd, pfa and n.

    Example: DiFranco & Rubin's 13.18 dB (steady target, Pd 0.9, Pfa 1e-6, one pulse) and the
    Swerling 1 closed form S = ln Pfa / ln Pd - 1 (21.1436 dB):

    >>> import math
    >>> round(float(chebyshev_snr_db(0.9, 1e-6)), 2)
    13.18
    >>> abs(float(chebyshev_snr_db(0.9, 1e-6, 1, 1)) - 10 * math.log10(math.log(1e-6) / math.log(0.9) - 1)) < 0.001
    True
    """
    where = "chebyshev_snr_db"
    if swerling not in SWERLING_CASES:
        raise ValueError(f"{where}: swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    dtype = jnp.result_type(pd, pfa, n, float)
    pd, pfa, n = jnp.broadcast_arrays(*(jnp.asarray(v, dtype=dtype) for v in (pd, pfa, n)))
    ok, _ = admit(where, [("pd", pd, *PD_RANGE), ("pfa", pfa, *PFA_RANGE), ("n", n, *N_RANGE)])
    pd, pfa, n = (guard(v, ok, fill) for v, fill in ((pd, 0.5), (pfa, 1e-6), (n, 1.0)))
    coefficients = jnp.asarray(_stored()[0 if swerling == 5 else int(swerling)], dtype=dtype)
    return guard(series(coefficients, *coordinates(pd, pfa, n)), ok)
