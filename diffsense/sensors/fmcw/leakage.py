"""Transmitter leakage and its phase noise: the noise floor of a single-antenna FMCW radar.

An FMCW radar transmits while it receives, so some transmitter power P_L = P_t / I (I the
transmit-receive isolation: circulator, antenna mismatch, radome) reaches the mixer, delayed by
τ_L relative to the local oscillator. Its phase noise is largely the LO's own and cancels in
the mixer; what remains is the range-correlation residue (Stove 1992, §4-5)

    S_L(f) = P_L · 𝓛(f) · 4 sin²(π f τ_L)                     (W/Hz at beat frequency f),

with 𝓛(f) the oscillator's single-sideband phase noise (dBc/Hz) at offset f and
4 sin²(π f τ) = |1 − e^{−j2πfτ}|² the transfer of a phase fluctuation through the delay
difference. The oscillator is taken in its 1/f² (−20 dB/decade) region (Leeson 1966),

    𝓛(f) = 𝓛(f_0) − 20 log10(f / f_0)                         (dBc/Hz),

anchored at a datasheet point 𝓛(f_0). The floor in the target's FFT bin of noise bandwidth β is
S_L(f_b) β. For f τ_L ≪ 1 it is flat in f_b: 𝓛 f² · (2πτ)² no longer depends on f.

Model and domain: a simple floor, not a spectrum simulation. It keeps the leading term for a
short leakage delay (0 < f_b τ_L ≤ ½; longer delays are clipped at ½, the first maximum of the
sine) and ignores the AM noise and the 1/f³ flicker region; the single/double-sideband
convention makes it uncertain by about 3 dB. Smooth (sin, log) in every argument over the domain.

Sources: A. G. Stove, "Linear FMCW radar techniques", IEE Proc. F 139(5), 343-350 (1992),
§4-5 (leakage, phase noise, range correlation); D. B. Leeson, "A simple model of feedback
oscillator noise spectrum", Proc. IEEE 54(2), 329-330 (1966); Brooker §11.12.4.2 (single-antenna
FMCW: leakage limits the transmit power to about 50 mW without active cancellation).
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense.numerics.db import db10, db20

__all__ = ["phase_noise_dbc_hz", "range_correlation_db", "leakage_noise_dbw"]


def phase_noise_dbc_hz(offset_hz, reference_dbc_hz, reference_offset_hz):
    """SSB phase noise (dBc/Hz) at ``offset_hz`` in the 1/f² region: 𝓛_0 − 20 log10(f/f_0).

    Offsets f, f_0 > 0 (Hz). Source: Leeson (1966).

    >>> round(float(phase_noise_dbc_hz(1e6, -85.0, 1e5)), 9)   # one decade out: 20 dB lower
    -105.0
    """
    return jnp.asarray(reference_dbc_hz, dtype=float) - db20(jnp.asarray(offset_hz, dtype=float) / reference_offset_hz)


def range_correlation_db(offset_hz, delay_s):
    """10 log10(4 sin²(π f τ)) (dB): the residue of correlated phase noise after a delay τ.

    Domain f > 0 (Hz), τ > 0 (s); f τ is clipped at ½ (the first maximum, +6.02 dB).
    Source: Stove (1992) §5.

    >>> round(float(range_correlation_db(1e6, 1e-9)), 4)   # 20 log10(2 sin(π·1e-3))
    -44.0364
    """
    x = math.pi * jnp.minimum(jnp.asarray(offset_hz, dtype=float) * delay_s, 0.5)
    return db20(2.0 * jnp.sin(x))


def leakage_noise_dbw(transmit_power_dbw, isolation_db, reference_dbc_hz, reference_offset_hz, beat_frequency_hz,
                      delay_s, bandwidth_hz):
    """Leakage phase-noise power (dBW) in a bin of noise bandwidth β at the beat frequency f_b:

        P_t − I + 𝓛(f_b) + 10 log10(4 sin²(π f_b τ_L)) + 10 log10 β.

    Args are in dBW, dB, dBc/Hz, Hz, Hz, s and Hz. Source: Stove (1992) §4-5 (module docstring).

    >>> round(float(leakage_noise_dbw(-10.0, 25.0, -85.0, 1e5, 4e6, 1e-9, 3173.83)), 2)
    -149.02
    """
    return (jnp.asarray(transmit_power_dbw, dtype=float) - isolation_db
            + phase_noise_dbc_hz(beat_frequency_hz, reference_dbc_hz, reference_offset_hz)
            + range_correlation_db(beat_frequency_hz, delay_s) + db10(bandwidth_hz))
