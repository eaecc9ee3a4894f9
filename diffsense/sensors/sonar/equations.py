"""The sonar equations (echo level, active and passive signal excess) and the duty-cycle limit
of the pulse length.

All terms in dB: SL, NL, RL, EL dB re 1 µPa (SL at 1 m), TS dB re 1 m, TL, DI, DT in dB.
Sources: Urick, *Principles of Underwater Sound* (1983), ch. 2 (the sonar equations); Brooker,
*Introduction to Sensors for Ranging and Imaging* (2009), §12.7–12.8 eqs (12.41), (12.57).
The resolutions, PRF and duty cycle of a sonar are the waveform relations of
:mod:`diffsense.physics.waveforms` with ``propagation_speed_m_s`` the speed of sound.

The book's sphere echo (eq (12.58)): SL 225.3 dB, TS −12 dB, at 500 m with α = 0.0328 dB/m:

>>> import math
>>> from diffsense.sensors.sonar.equations import echo_level_db
>>> tl = 20 * math.log10(500.0) + 0.0328 * 500.0
>>> abs(float(echo_level_db(225.3, tl, -12.0)) - (225.3 - 40 * math.log10(500.0) - 0.0656 * 500.0 - 12.0)) < 1e-9
True
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.checks import check_range

__all__ = [
    "echo_level_db",
    "active_signal_excess_noise_db",
    "active_signal_excess_reverberation_db",
    "passive_signal_excess_db",
    "max_pulse_length_s",
]


def echo_level_db(source_level_db_, transmission_loss_db, target_strength_db):
    """Echo level at the receiver ``EL = SL − 2 TL + TS`` (dB re 1 µPa), book eq (12.57).

    Args:
        source_level_db_: SL (dB re 1 µPa at 1 m), in [0, 300].
        transmission_loss_db: one-way TL (dB), in [-100, 1e5].
        target_strength_db: TS (dB re 1 m), in [-150, 100].
    """
    w = "echo_level_db"
    check_range("source_level_db", source_level_db_, 0.0, 300.0, where=w)
    check_range("transmission_loss_db", transmission_loss_db, -100.0, 1e5, where=w)
    check_range("target_strength_db", target_strength_db, -150.0, 100.0, where=w)
    return jnp.asarray(source_level_db_) - 2.0 * jnp.asarray(transmission_loss_db) + jnp.asarray(target_strength_db)


def active_signal_excess_noise_db(
    source_level_db_, transmission_loss_db, target_strength_db, noise_level_db, directivity_index_db, detection_threshold_db_
):
    """Noise-limited active sonar equation ``SE = SL − 2 TL + TS − (NL − DI) − DT`` (dB).

    NL is the isotropic noise level in the receiver band (dB re 1 µPa), DI the receive
    directivity index and DT the detection threshold in the same band (Urick ch. 2). SE ≥ 0 means
    detection at the (Pd, Pfa) that defines DT. Exact bookkeeping of the terms (all dB).

    Args: levels in dB (SL, NL re 1 µPa; TS re 1 m; TL, DI, DT in dB), any real values.
    """
    return (
        jnp.asarray(source_level_db_)
        - 2.0 * jnp.asarray(transmission_loss_db)
        + jnp.asarray(target_strength_db)
        - (jnp.asarray(noise_level_db) - jnp.asarray(directivity_index_db))
        - jnp.asarray(detection_threshold_db_)
    )


def active_signal_excess_reverberation_db(
    source_level_db_, transmission_loss_db, target_strength_db, reverberation_level_db, detection_threshold_db_
):
    """Reverberation-limited active sonar equation ``SE = SL − 2 TL + TS − RL − DT`` (dB).

    RL is the reverberation level at the receiver (dB re 1 µPa, see
    :func:`diffsense.physics.clutter.reverberation_level_db`); directivity enters RL through the
    reverberating area or volume, so no DI term appears (Urick ch. 2).

    Args: levels in dB, any real values.
    """
    return (
        jnp.asarray(source_level_db_)
        - 2.0 * jnp.asarray(transmission_loss_db)
        + jnp.asarray(target_strength_db)
        - jnp.asarray(reverberation_level_db)
        - jnp.asarray(detection_threshold_db_)
    )


def passive_signal_excess_db(source_level_db_, transmission_loss_db, noise_level_db, directivity_index_db, detection_threshold_db_):
    """Passive sonar equation ``SE = SL − TL − (NL − DI) − DT`` (dB).

    SL is the target's radiated level in the receiver band (dB re 1 µPa at 1 m), TL one way
    (Urick ch. 2).

    Args: levels in dB, any real values.
    """
    return (
        jnp.asarray(source_level_db_)
        - jnp.asarray(transmission_loss_db)
        - (jnp.asarray(noise_level_db) - jnp.asarray(directivity_index_db))
        - jnp.asarray(detection_threshold_db_)
    )


def max_pulse_length_s(max_duty_cycle, prf_hz):
    """Longest pulse (chirp) allowed by a duty-cycle limit ``τ = χ / f_pr`` (s).

    The inverse in τ of :func:`diffsense.physics.waveforms.duty_cycle`.

    Args:
        max_duty_cycle: χ (fraction), in (0, 1].
        prf_hz: f_pr (Hz), in (0, ∞).

    >>> round(float(max_pulse_length_s(0.05, 1.52)) * 1e3, 1)  # book eq (12.41): 5 % → 32.9 ms
    32.9
    """
    w = "max_pulse_length_s"
    check_range("max_duty_cycle", max_duty_cycle, 0.0, 1.0, lo_open=True, where=w)
    check_range("prf_hz", prf_hz, 0.0, None, lo_open=True, where=w)
    return jnp.asarray(max_duty_cycle) / jnp.asarray(prf_hz)
