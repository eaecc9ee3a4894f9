"""Pulse-detection statistics of a direct-detection laser receiver: a threshold on the
baseband photocurrent in Gaussian noise.

The receiver compares the filtered photocurrent with a threshold i_t. Without a pulse the
output is Gaussian with standard deviation σ_0 (thermal, dark, background shot noise); at the
pulse peak it is Gaussian with mean i_s and standard deviation σ_1 ≥ σ_0 (the signal adds its
own shot noise). With z_fa = Q⁻¹(P_fa) (Q the standard normal tail)::

    P_fa = Q(i_t / σ_0),   P_d = Q((i_t − i_s) / σ_1) = Φ(sqrt(SNR) − r z_fa),
    SNR = i_s² / σ_1²,     r = σ_0 / σ_1 ∈ (0, 1].

Averaging N pulse returns (waveform averaging before the threshold) multiplies the SNR by N.
The required SNR for a given P_d is therefore closed-form::

    SNR_req = (Φ⁻¹(P_d) + r z_fa)² / N.

Statistical model: a steady (non-fluctuating) return — the receiver aperture averages many
speckle cells of a rough target, so the speckle fluctuation is negligible (Swerling 0). The
Gaussian approximation of the shot noise needs many photoelectrons per
pulse (Brooker §9.1.3.2: the Poisson count is close to normal above ~1000); for a few
photoelectrons and negligible thermal noise, photon-counting (Poisson) statistics apply instead
and the Gaussian tails used here are not accurate. Sources: the threshold
detection model of Kingston, *Detection of Optical and Infrared Radiation* (1978), ch. 2, and
its use for laser rangefinders in Burns, Christodoulou & Boreman (1991), "System design of a
pulsed laser rangefinder", Opt. Eng. 30(3):323–329.
"""

from __future__ import annotations

import jax.numpy as jnp
from jax.scipy.special import ndtr, ndtri

from diffsense.numerics.checks import check_range
from diffsense.numerics.db import db10, db20, from_db20

__all__ = ["threshold_detection_pd", "threshold_required_snr_db"]

def _f(x):
    return jnp.asarray(x, dtype=jnp.result_type(float, x))


def _check(where, pfa, n, noise_ratio):
    check_range("pfa", pfa, 1e-300, 0.5, where=where)
    check_range("n", n, 1.0, 1e4, where=where)
    check_range("noise_ratio", noise_ratio, 0.0, 1.0, lo_open=True, where=where)


def threshold_detection_pd(snr_db, pfa, n=1.0, noise_ratio=1.0):
    """Detection probability ``P_d = Φ(sqrt(N · SNR) − r Q⁻¹(P_fa))`` of a steady pulse.

    Args:
        snr_db: single-pulse peak SNR i_s²/σ_1² (dB), in [−300, 300].
        pfa: false-alarm probability per decision, in [1e-300, 0.5].
        n: number of averaged pulses N (real, ≥ 1), in [1, 1e4].
        noise_ratio: r = σ_0/σ_1, the noise without the signal over the noise with it, (0, 1].

    Exact for Gaussian noise (float64 round-off of ``ndtr``/``ndtri``); see the module
    docstring for the model and its sources. At SNR 16 dB with Pfa 1e-6 and r = 1, against
    the normal distribution of the standard library:

    >>> from statistics import NormalDist
    >>> std = NormalDist()
    >>> float(threshold_detection_pd(16.0, 1e-6)), std.cdf(10 ** (16.0 / 20) + std.inv_cdf(1e-6))
    (0.940164, 0.940164)
    """
    w = "threshold_detection_pd"
    check_range("snr_db", snr_db, -300.0, 300.0, where=w)
    _check(w, pfa, n, noise_ratio)
    amplitude = jnp.sqrt(_f(n)) * from_db20(snr_db)
    return ndtr(amplitude + _f(noise_ratio) * ndtri(_f(pfa)))


def threshold_required_snr_db(pd, pfa, n=1.0, noise_ratio=1.0):
    """Single-pulse SNR (dB) a steady pulse needs for ``pd``: ``20 log10(Φ⁻¹(P_d) + r z_fa) − 10 log10 N``.

    Args:
        pd: required detection probability, in [0.5, 1 − 1e-12].
        pfa: false-alarm probability, in [1e-300, 0.5].
        n: averaged pulses N, in [1, 1e4].
        noise_ratio: r = σ_0/σ_1, in (0, 1].

    With pd ≥ 0.5 and pfa ≤ 0.5 the bracket is positive unless both equal 0.5 (then the
    required SNR is 0, −∞ dB). Exact inverse of :func:`threshold_detection_pd`. Example: Pd
    0.9, Pfa 1e-6, r = 1 -> (1.28155 + 4.75342)² = 36.42 -> 15.61 dB:

    >>> import math
    >>> from statistics import NormalDist
    >>> z = NormalDist().inv_cdf
    >>> float(threshold_required_snr_db(0.9, 1e-6)), 20 * math.log10(z(0.9) - z(1e-6))
    (15.6135, 15.6135)
    """
    w = "threshold_required_snr_db"
    check_range("pd", pd, 0.5, 1.0 - 1e-12, where=w)
    _check(w, pfa, n, noise_ratio)
    amplitude = ndtri(_f(pd)) - _f(noise_ratio) * ndtri(_f(pfa))
    return db20(amplitude) - db10(n)
