"""One-pulse detection for the chains that decide on one square-law sample (sonar, ultrasonic,
FMCW), compiled once per Swerling case.

A chain called outside ``jit`` (sonar, ultrasonic) would otherwise trace and compile the
required-SNR root solve and the Pd series on every call; these wrappers are jitted with the
Swerling case static, so each case compiles once per process. Inside a trace they inline.

For one sample of an exponentially distributed echo power (Swerling 1 and 2 coincide) both
have closed forms, ``Pd = Pfa^(1/(1+S))`` and ``S = ln Pfa / ln Pd - 1`` (Swerling 1957;
DiFranco & Rubin 1968), which replace the series and its root solve there: the same values
(the exact solver reproduces them to 1e-9 dB, tests/detection/test_single_pulse.py) in a
program a fraction of the size. The domain is that of :func:`diffsense.detection.pd` and
:func:`diffsense.detection.required_snr_db`: eager calls outside it raise, traced ones give NaN.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.detection._domain import admit, guard
from diffsense.detection.probability import PFA_RANGE, SNR_DB_RANGE, pd
from diffsense.detection.required_snr import required_snr_db
from diffsense.numerics.db import db10, from_db10

__all__ = ["single_pulse_required_snr_db", "single_pulse_pd"]

#: Swerling cases whose one-sample detection is the exponential closed form
_EXPONENTIAL = (1, 2)


@functools.partial(jax.jit, static_argnames=("swerling",))
def single_pulse_required_snr_db(pd_target, pfa, swerling):
    """:func:`diffsense.detection.required_snr_db` for one envelope-detected pulse (dB);
    Swerling 1 and 2 by the closed form ``10 log10(ln Pfa / ln Pd - 1)``."""
    if swerling not in _EXPONENTIAL:
        return required_snr_db(pd_target, pfa, 1, swerling)
    where = "single_pulse_required_snr_db"
    pd_t, pfa = jnp.broadcast_arrays(*(jnp.asarray(a, dtype=jnp.result_type(pd_target, pfa, float))
                                       for a in (pd_target, pfa)))
    ok, _ = admit(where, [("pfa", pfa, *PFA_RANGE), ("pd", pd_t, 0.0, 1.0 - 1e-12, True, False)],
                  greater=[("pd", pd_t, "pfa", pfa)])
    pd_t, pfa = guard(pd_t, ok, 0.5), guard(pfa, ok, 1e-6)
    return guard(db10(jnp.log(pfa) / jnp.log(pd_t) - 1.0), ok)


@functools.partial(jax.jit, static_argnames=("swerling",))
def single_pulse_pd(snr_db, pfa, swerling):
    """:func:`diffsense.detection.pd` for one envelope-detected pulse at ``snr_db`` (dB);
    Swerling 1 and 2 by the closed form ``Pfa^(1/(1+S))``.

    The SNR is clipped to the documented domain [-50, 80] dB, outside which Pd equals Pfa or 1
    to within 1e-10; the clip gives it zero slope there.
    """
    snr_db = jnp.clip(snr_db, *SNR_DB_RANGE)
    if swerling not in _EXPONENTIAL:
        return pd(snr_db, pfa, 1, swerling)
    snr_db, pfa = (jnp.asarray(a, dtype=jnp.result_type(snr_db, pfa, float)) for a in (snr_db, pfa))
    ok, _ = admit("single_pulse_pd", [("snr_db", snr_db, -np.inf, np.inf, True, True), ("pfa", pfa, *PFA_RANGE)])
    pfa = guard(pfa, ok, 1e-6)
    return guard(jnp.exp(jnp.log(pfa) / (1.0 + from_db10(snr_db))), ok)
