"""Barton's universal equations for the detectability factor (square-law detector, N pulses
integrated noncoherently, Swerling 0-4).

Sources: D. K. Barton, "Universal equations for radar target detection", IEEE Trans. AES 41(3),
2005, pp. 1049-1052; D. K. Barton, *Radar Equations for Modern Radar*, Artech House 2013, ch. 4.

Notation: D is the per-pulse SNR (linear) needed for Pd at Pfa with n pulses; T(p, k) is the
upper quantile of the Gamma(k, 1) distribution, Q(k, T) = p (for k = n and p = Pfa it is the
false-alarm threshold of the integrated square-law statistic, :func:`diffsense.detection.threshold`).

* Steady target (Swerling 0): North's single-pulse approximation (a Gaussian approximation of
  the envelope detector),

      D0(1) = [sqrt(ln(1/Pfa)) - erfc^-1(2 Pd)]^2 - 1/2,

  times Barton's noncoherent integration loss, D0(n) = D0(1) Li(n) / n with

      Li(n) = [1 + sqrt(1 + 9.2 n / D0(1))] / [1 + sqrt(1 + 9.2 / D0(1))].

* Chi-square target with ne independent RCS samples per dwell (2 ne degrees of freedom;
  Swerling 1: ne = 1, 2: ne = n, 3: ne = 2, 4: ne = 2n): the integrated statistic is taken as
  (n - ne) + (1 + n D / ne) Gamma(ne, 1) — the n - ne noise-only degrees of freedom are replaced
  by their mean — so that Pd = Q(ne, (T(Pfa, n) - (n - ne)) / (1 + n D / ne)) and

      D = (ne / n) [ (T(Pfa, n) - (n - ne)) / T(Pd, ne) - 1 ].

  This is exact where the statistic really is (1 + n D / ne) Gamma(ne, 1): Swerling 2 for every
  n (1 + D = T(Pfa, n) / T(Pd, n)), Swerling 1 at n = 1 (D = ln Pfa / ln Pd - 1) and Swerling 3
  at n = 2.

Domain (only this is accepted): 0.1 <= Pd <= 0.999, 1e-12 <= Pfa <= 1e-2, 1 <= n <= 100 (real).
The error bounds are measured here, not quoted: the worst |error| against the mpmath reference
(``tests/reference/mp_detection.py``, 30 digits) over Pd in {0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.95,
0.99, 0.999}, Pfa in {1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12} and n in {1, 2, 3, 5, 10, 20,
30, 50, 100} (``benchmarks/_fidelity_detection.py`` measures it again; tests/detection/
test_barton.py checks it on the stored reference grid and at Pfa = 1e-2):

========  =============  ==================  ===========================
Swerling  whole domain   Pfa <= 1e-3         Pd >= 0.5 and Pfa <= 1e-4
========  =============  ==================  ===========================
0         1.31 dB        0.70 dB             0.38 dB
1         1.21 dB        0.55 dB             0.09 dB
2         5e-13 dB       (closed form)       (closed form)
3         1.37 dB        0.66 dB             0.11 dB
4         2.49 dB        1.16 dB             0.47 dB
========  =============  ==================  ===========================

Every worst case is at Pd = 0.1, Pfa = 1e-2, n = 100 (for Pfa <= 1e-3 at Pd = 0.1, Pfa = 1e-3,
n = 100). The steady-target equations are low (optimistic) by 0.1-0.4 dB over most of the
domain; the fluctuating ones are worst at Pd = 0.1 (Swerling 1 and 3 high, Swerling 4 low) and
within 0.1 dB (Swerling 1, 3) or 0.5 dB (Swerling 4) for Pd >= 0.5, Pfa <= 1e-4.

Cost: one threshold solve T(Pfa, n) and one T(Pd, ne) (Swerling 1-4) or a closed form
(Swerling 0), against the exact method's Newton iteration on the Pd series.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
from jax.scipy.special import ndtri

from diffsense.detection._domain import admit, guard
from diffsense.detection.core import SWERLING_CASES
from diffsense.detection.threshold import _threshold
from diffsense.numerics.db import db10

__all__ = ["barton_snr_db", "BARTON_DOMAIN", "INTEGRATION_LOSS_CONSTANT"]

#: (lo, hi) of pd, pfa and n accepted by :func:`barton_snr_db` (module docstring)
BARTON_DOMAIN = {"pd": (0.1, 0.999), "pfa": (1e-12, 1e-2), "n": (1.0, 100.0)}
#: the constant 9.2 of Barton's integration loss Li(n)
INTEGRATION_LOSS_CONSTANT = 9.2


def _steady(pd, pfa, n):
    """D0(n) = D0(1) Li(n) / n (linear), North's D0(1) and Barton's Li(n)."""
    # erfc^-1(2 Pd) = -Phi^-1(Pd) / sqrt(2)
    d1 = (jnp.sqrt(-jnp.log(pfa)) + ndtri(pd) / math.sqrt(2.0)) ** 2 - 0.5
    c = INTEGRATION_LOSS_CONSTANT
    loss = (1.0 + jnp.sqrt(1.0 + c * n / d1)) / (1.0 + jnp.sqrt(1.0 + c / d1))
    return d1 * loss / n


def _chi_square(pd, pfa, n, ne):
    """(ne / n) [(T(Pfa, n) - (n - ne)) / T(Pd, ne) - 1] (linear)."""
    return (ne / n) * ((_threshold(pfa, n) - (n - ne)) / _threshold(pd, ne) - 1.0)


def barton_snr_db(pd, pfa, n=1, swerling=0):
    """Barton's universal equations: required per-pulse SNR (dB) for ``pd`` at ``pfa`` with ``n``
    pulses integrated noncoherently (square law), Swerling 0-4 (module docstring for the formulas).

    Domain: 0.1 <= pd <= 0.999, 1e-12 <= pfa <= 1e-2, 1 <= n <= 100; an eager call outside it
    raises DomainError, a traced call returns NaN. Error against the exact value: module
    docstring (Swerling 2 exact; the others up to 2.49 dB, Swerling 4 at Pd = 0.1,
    Pfa = 1e-2, n = 100; at most 0.47 dB for Pd >= 0.5 and Pfa <= 1e-4).

    Swerling 2 is the closed form 1 + D = T(Pfa, n) / T(Pd, n); Swerling 1 with one pulse is
    D = ln Pfa / ln Pd - 1 (21.14 dB at Pd = 0.9, Pfa = 1e-6, DiFranco & Rubin's tables); for a
    steady target North's approximation gives 13.19 dB against the tables' 13.18 dB:

    >>> import math
    >>> closed = 10 * math.log10(math.log(1e-6) / math.log(0.9) - 1)
    >>> round(float(barton_snr_db(0.9, 1e-6, 1, swerling=1)), 4), round(closed, 4)
    (21.1436, 21.1436)
    >>> round(float(barton_snr_db(0.9, 1e-6)), 2)
    13.19
    """
    where = "barton_snr_db"
    if swerling not in SWERLING_CASES:
        raise ValueError(f"{where}: swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    dtype = jnp.result_type(pd, pfa, n, float)
    pd, pfa, n = (jnp.asarray(a, dtype=dtype) for a in (pd, pfa, n))
    ok, each = admit(where, [("pd", pd, *BARTON_DOMAIN["pd"]), ("pfa", pfa, *BARTON_DOMAIN["pfa"]),
                             ("n", n, *BARTON_DOMAIN["n"])])
    pd, pfa, n = (guard(a, m, f) for a, m, f in zip((pd, pfa, n), each, (0.5, 1e-6, 1.0)))
    if swerling in (0, 5):
        d = _steady(pd, pfa, n)
    else:
        ne = {1: jnp.ones_like(n), 2: n, 3: 2.0 * jnp.ones_like(n), 4: 2.0 * n}[swerling]
        d = _chi_square(pd, pfa, n, ne)
    return guard(db10(d), ok)
