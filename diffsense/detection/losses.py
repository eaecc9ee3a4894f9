"""Detection losses derived exactly from the detection model (Brooker 9.5-9.6).

All values are differences of exact detectability factors (:func:`required_snr_db`), so they
inherit its accuracy (< 1e-9 dB) and its implicit derivatives.

* fluctuation loss: extra single-pulse SNR a fluctuating target needs over a steady one at the
  same Pd, Pfa and N.
* integration gain: the reduction of the required single-pulse SNR when N pulses are
  integrated instead of one, gain_dB = SNR_1 - SNR_N = 10 log10 I(N), where I(N) = S_1 / S_N
  is the integration improvement factor (the book's "improvement", Figure 9.17).
* integration loss: 10 log10 N - gain_dB, the shortfall of noncoherent integration with respect
  to perfect coherent integration.
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.db import db10
from diffsense.detection.required_snr import required_snr_db

__all__ = ["fluctuation_loss_db", "integration_gain_db", "integration_loss_db"]


def fluctuation_loss_db(pd, pfa, n=1, swerling=1):
    """SNR_required(swerling) - SNR_required(steady), dB, at the same Pd, Pfa and N.

    DiFranco & Rubin's tables at Pd = 0.9, Pfa = 1e-6, one pulse: 21.14 - 13.18 dB:

    >>> float(fluctuation_loss_db(0.9, 1e-6, 1, swerling=1))
    7.96
    """
    return required_snr_db(pd, pfa, n, swerling) - required_snr_db(pd, pfa, n, 0)


def integration_gain_db(pd, pfa, n, swerling=0):
    """Noncoherent integration improvement SNR_required(N=1) - SNR_required(N), dB.

    Swerling 2 has Pd = Q(N, T/(1+S)), so S_N = T(Pfa, N)/T(Pd, N) - 1 with the inverse
    incomplete gamma function (scipy's, independent of this package):

    >>> import math
    >>> from scipy.special import gammainccinv
    >>> s = lambda n: gammainccinv(n, 1e-6) / gammainccinv(n, 0.9) - 1.0
    >>> float(integration_gain_db(0.9, 1e-6, 10, swerling=2)), 10 * math.log10(s(1) / s(10))
    (14.8518, 14.8518)
    """
    one = jnp.ones_like(jnp.asarray(n, dtype=jnp.result_type(n, float)))
    return required_snr_db(pd, pfa, one, swerling) - required_snr_db(pd, pfa, n, swerling)


def integration_loss_db(pd, pfa, n, swerling=0):
    """10 log10 N - integration gain: what noncoherent integration loses against coherent, dB."""
    n = jnp.asarray(n, dtype=jnp.result_type(n, float))
    return db10(n) - integration_gain_db(pd, pfa, n, swerling)
