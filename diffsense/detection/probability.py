"""Public detection-probability functions: noncoherent and coherent integration.

``db_to_linear`` and ``linear_to_db`` are the public detection-layer names of
:func:`diffsense.numerics.db.from_db10` and :func:`diffsense.numerics.db.db10` (one home of the
dB conversions).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.numerics.db import db10 as linear_to_db
from diffsense.numerics.db import from_db10 as db_to_linear
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import single_precision
from diffsense.detection.core import SWERLING_CASES, _pd_given_threshold
from diffsense.detection.threshold import _threshold

__all__ = ["pd", "pd_coherent", "db_to_linear", "linear_to_db"]

#: SNRs (dB) over which the accuracy of Pd is documented; Pd is defined for every finite SNR.
SNR_DB_RANGE = (-50.0, 80.0)
#: Domain of the false-alarm probability and the pulse count of the detection functions.
PFA_RANGE = (1e-300, 0.5)
N_RANGE = (1.0, 1e4)
# SNR (dB) beyond which Pd equals its limits Pfa (below) and 1 (above) to the working precision,
# whatever Pfa, N and the Swerling case: at -300 dB, Pd/Pfa - 1 < N S T < 1e-20; at +300 dB the
# most fluctuating case (Swerling 1, N = 1) misses with probability -ln(Pfa)/S < 1e-27 (float64).
# float32 (eps 6e-8) saturates at +-150 dB, inside the range where its arithmetic cannot overflow.
_SATURATION_DB = 300.0
_SATURATION_DB_SINGLE = 150.0


def saturation_db(x) -> float:
    """SNR (dB) beyond which Pd is Pfa or 1 to the precision of ``x`` (see above)."""
    return _SATURATION_DB_SINGLE if single_precision(x) else _SATURATION_DB


def _admit_common(where, snr_db, pfa, n, swerling):
    """Domain of :func:`pd`: finite SNR, Pfa in PFA_RANGE, N in N_RANGE (masks; raises if eager)."""
    if swerling not in SWERLING_CASES:
        raise ValueError(f"{where}: swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    return admit(where, [
        ("snr_db", snr_db, -np.inf, np.inf, True, True),
        ("pfa", pfa, *PFA_RANGE),
        ("n", n, *N_RANGE),
    ])


def pd(snr_db, pfa, n=1, swerling=0):
    """Probability of detection of N noncoherently integrated square-law samples.

    Args:
        snr_db: mean single-pulse signal-to-noise ratio in dB, any finite value. Pd tends to Pfa
           as the SNR falls and to 1 as it rises; beyond +-300 dB (float32: +-150 dB) it equals
           those limits to the working precision and is returned as such (zero slope).
        pfa: false-alarm probability per decision (1e-300 ... 0.5).
        n: number of pulses integrated noncoherently (real, 1 ... 1e4; non-integer values are the
           smooth noncentral-gamma relaxation, equal to the exact value at integers).
        swerling: target fluctuation model, static: 0 (steady; 5 is a synonym), 1 and 3
           (scan-to-scan, chi-square with 2 and 4 degrees of freedom), 2 and 4 (pulse-to-pulse).

    Returns:
        Pd, exact to float64 round-off: |error| < 1e-13 against a 40-digit mpmath reference
        over Swerling 0-4, N 1-1000, Pfa 1e-1-1e-15 (tests/test_detection_accuracy.py).
        Terms below 8.5e-18 are truncated, so Pd - Pfa is resolved to that absolute level.

    Domain: the same eagerly and under ``jit``. An eager call with a NaN or infinite SNR, Pfa
    outside [1e-300, 0.5], N outside [1, 1e4] or an unknown Swerling case raises
    :class:`~diffsense.errors.DomainError` (ValueError for ``swerling``); a traced call returns
    NaN (value and gradient) for those elements. Broadcasts over its array arguments;
    jit/vmap/grad-able in ``snr_db``, ``pfa`` and ``n``.

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

    Far outside the usual range the limits hold (Swerling 1, one pulse, closed form):

    >>> float(pd(120.0, 1e-6, 1, swerling=1)), 1e-6 ** (1 / (1 + 1e12))
    (0.99999999998618, 0.99999999998618)
    >>> float(pd(-120.0, 1e-6, 1, swerling=1)) / 1e-6, 1e-6 ** (1 / (1 + 1e-12)) / 1e-6
    (1.0000000000138, 1.0000000000138)
    """
    dtype = jnp.result_type(snr_db, pfa, n, float)
    snr_db, pfa, n = (jnp.asarray(a, dtype=dtype) for a in (snr_db, pfa, n))
    ok, each = _admit_common("pd", snr_db, pfa, n, swerling)
    snr_db, pfa, n = (guard(a, m, fill) for a, m, fill in zip((snr_db, pfa, n), each, (0.0, 1e-6, 1.0)))
    pfa_b, n_b = jnp.broadcast_arrays(pfa, n)
    t = _threshold(pfa_b, n_b)
    lim = saturation_db(snr_db)
    snr = db_to_linear(jnp.clip(snr_db, -lim, lim))
    return guard(_pd_given_threshold(snr, t, n_b, swerling, pfa_b), ok)


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
    n = jnp.asarray(n, dtype=jnp.result_type(n, float))
    ok, _ = admit("pd_coherent", [("n", n, *N_RANGE)])
    n = guard(n, ok, 1.0)
    return guard(pd(jnp.asarray(snr_db) + linear_to_db(n), pfa, 1.0, swerling), ok)
