"""Public detection-probability functions: noncoherent and coherent integration.

``db_to_linear`` and ``linear_to_db`` are the public detection-layer names of
:func:`diffsense.numerics.db.from_db10` and :func:`diffsense.numerics.db.db10` (one home of the
dB conversions).
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10 as linear_to_db
from diffsense.numerics.db import from_db10 as db_to_linear
from diffsense.detection.core import SWERLING_CASES, pd_given_threshold
from diffsense.detection.threshold import _threshold

__all__ = ["pd", "pd_coherent", "db_to_linear", "linear_to_db"]

#: Documented domain of the detection functions (values and gradients are finite here).
SNR_DB_RANGE = (-50.0, 80.0)
PFA_RANGE = (1e-300, 0.5)
N_RANGE = (1.0, 1e4)


def _check_common(where, snr_db, pfa, n, swerling):
    if swerling not in SWERLING_CASES:
        raise ValueError(f"{where}: swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    check_range("snr_db", snr_db, *SNR_DB_RANGE, where=where)
    check_range("pfa", pfa, PFA_RANGE[0], PFA_RANGE[1], where=where)
    check_range("n", n, *N_RANGE, where=where)


def pd(snr_db, pfa, n=1, swerling=0):
    """Probability of detection of N noncoherently integrated square-law samples.

    Args:
        snr_db: mean single-pulse signal-to-noise ratio in dB (-50 ... 80).
        pfa: false-alarm probability per decision (1e-300 ... 0.5).
        n: number of pulses integrated noncoherently (real, 1 ... 1e4; non-integer values are the
           smooth noncentral-gamma relaxation, equal to the exact value at integers).
        swerling: target fluctuation model, static: 0 (steady; 5 is a synonym), 1 and 3
           (scan-to-scan, chi-square with 2 and 4 degrees of freedom), 2 and 4 (pulse-to-pulse).

    Returns:
        Pd, exact to float64 round-off: |error| < 1e-13 against a 40-digit mpmath reference
        over Swerling 0-4, N 1-1000, Pfa 1e-1-1e-15 (tests/test_detection_accuracy.py).
        Terms below 8.5e-18 are truncated, so Pd - Pfa is resolved to that absolute level.

    Broadcasts over its array arguments; jit/vmap/grad-able in ``snr_db``, ``pfa`` and ``n``.

    Examples: DiFranco & Rubin's classic point, Pd = 0.9 at Pfa = 1e-6 with one pulse, needs
    13.18 dB for a steady target and 21.14 dB for Swerling 1. For one pulse on a steady target
    2Y is noncentral chi-square with 2 degrees of freedom and noncentrality 2S under the
    threshold 2T = -2 ln Pfa (Marcum's Q function; scipy's independent implementation is the
    check), and Swerling 1 has the closed form Pd = Pfa^(1/(1+S)):

    >>> import math
    >>> from scipy.stats import ncx2
    >>> float(pd(13.18, 1e-6)), float(ncx2.sf(-2 * math.log(1e-6), 2, 2 * 10 ** 1.318))
    (0.8995, 0.8995)
    >>> float(pd(21.14, 1e-6, 1, swerling=1)), 1e-6 ** (1 / (1 + 10 ** 2.114))
    (0.89992, 0.89992)
    """
    _check_common("pd", snr_db, pfa, n, swerling)
    dtype = jnp.result_type(snr_db, pfa, n, float)
    snr_db, pfa, n = (jnp.asarray(a, dtype=dtype) for a in (snr_db, pfa, n))
    pfa_b, n_b = jnp.broadcast_arrays(pfa, n)
    t = _threshold(pfa_b, n_b)
    return pd_given_threshold(db_to_linear(snr_db), t, n_b, swerling, pfa=pfa_b)


def pd_coherent(snr_db, pfa, n=1, swerling=0):
    """Pd after coherent (predetection) integration of N pulses.

    Coherent integration adds the N complex samples before the envelope detector, so the
    integrated SNR is N times the single-pulse SNR (Brooker 9.5) and a single square-law
    decision follows: ``pd(snr_db + 10 log10 N, pfa, 1, swerling)``. This holds for a target
    whose echo keeps its phase over the N pulses: steady (0) or scan-to-scan fluctuating (1, 3).
    Pulse-to-pulse decorrelated echoes (2, 4) do not add coherently; asking for them raises.

    Ten coherent pulses of 3.18 dB give the 13.18 dB of one pulse (10 log10 10 = 10 dB):

    >>> float(pd_coherent(3.18, 1e-6, 10)), float(pd(13.18, 1e-6))
    (0.8995, 0.8995)
    """
    if swerling in (2, 4):
        raise ValueError(
            "pd_coherent: swerling 2 and 4 decorrelate from pulse to pulse, so their echoes do not "
            "integrate coherently; use pd(...) for noncoherent integration"
        )
    check_range("n", n, *N_RANGE, where="pd_coherent")
    n = jnp.asarray(n, dtype=jnp.result_type(n, float))
    return pd(jnp.asarray(snr_db) + linear_to_db(n), pfa, 1.0, swerling)
