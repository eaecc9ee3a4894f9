"""One-pulse detection for chains that evaluate eagerly, compiled once per Swerling case.

A chain called outside ``jit`` (sonar, ultrasonic) would otherwise trace and compile the
required-SNR root solve and the Pd series on every call; these wrappers are jitted with the
Swerling case static, so each case compiles once per process. Inside a trace they inline.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp

from diffsense.detection.probability import SNR_DB_RANGE, pd
from diffsense.detection.required_snr import required_snr_db

__all__ = ["single_pulse_required_snr_db", "single_pulse_pd"]


@functools.partial(jax.jit, static_argnames=("swerling",))
def single_pulse_required_snr_db(pd_target, pfa, swerling):
    """:func:`diffsense.detection.required_snr_db` for one envelope-detected pulse (dB)."""
    return required_snr_db(pd_target, pfa, 1, swerling)


@functools.partial(jax.jit, static_argnames=("swerling",))
def single_pulse_pd(snr_db, pfa, swerling):
    """:func:`diffsense.detection.pd` for one envelope-detected pulse at ``snr_db`` (dB).

    The SNR is clipped to the documented domain [-50, 80] dB, outside which Pd equals Pfa or 1
    to within 1e-10; the clip gives it zero slope there.
    """
    return pd(jnp.clip(snr_db, *SNR_DB_RANGE), pfa, 1, swerling)
