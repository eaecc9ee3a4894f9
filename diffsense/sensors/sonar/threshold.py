"""Sonar detection: the detection index of the Gaussian receiver operating characteristic and the
detection threshold DT of a correlator, an energy detector and an envelope detector.

Sources: Peterson, Birdsall & Fox, "The theory of signal detectability", Trans. IRE PGIT-4,
171-212 (1954) (Gaussian ROC); Urick, *Principles of Underwater Sound* (1983), ch. 12
(detection threshold, detection index); Brooker, *Introduction to Sensors for Ranging and
Imaging* (2009), §12.8 (the sonar echo read off the radar Pd/Pfa curves).

Pd = 0.5 puts the threshold at the signal mean, so d = (Φ⁻¹(1 − Pfa))²; at Pfa = 1e-4 the normal
table gives Φ⁻¹(0.9999) = 3.7190 (Abramowitz & Stegun, Table 26.5):

>>> from diffsense.sensors.sonar.threshold import detection_index
>>> round(float(detection_index(0.5, 1e-4)), 2) == round(3.7190**2, 2)
True
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtri

from diffsense.detection.gaussian import gaussian_pd
from diffsense import detection
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import db10

__all__ = [
    "detection_index",
    "pd_from_detection_index",
    "detection_threshold_known_signal_db",
    "detection_threshold_energy_db",
    "detection_threshold_db",
]


def _check_pd_pfa(where, pd, pfa):
    check_range("pd", pd, 0.0, 1.0, lo_open=True, hi_open=True, where=where)
    check_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True, where=where)
    if is_concrete(pd) and is_concrete(pfa):
        gap = np.asarray(pd, dtype=float) - np.asarray(pfa, dtype=float)
        check_range("pd - pfa", gap, 0.0, None, lo_open=True, where=where)


def _deflection(pd, pfa):
    """Φ⁻¹(Pd) − Φ⁻¹(Pfa) without checks (the caller checked them)."""
    return ndtri(jnp.asarray(pd, dtype=float)) - ndtri(jnp.asarray(pfa, dtype=float))


def detection_index(pd, pfa):
    """Detection index of the Gaussian ROC ``d = (Φ⁻¹(Pd) − Φ⁻¹(Pfa))²``.

    For a decision statistic that is Gaussian with equal variance σ² under noise and under
    signal plus noise, d = (ΔM)²/σ² and Pfa = Q(T), Pd = Q(T − √d) (Peterson, Birdsall & Fox
    1954; Urick ch. 12 plots these ROC curves). Pd 0.5, Pfa 1e-4 → d = 13.8. Exact for that
    model; for envelope-detected sinusoids use :func:`detection_threshold_db`.

    Args:
        pd: detection probability, in (0, 1), > pfa.
        pfa: false-alarm probability, in (0, 1).
    """
    _check_pd_pfa("detection_index", pd, pfa)
    root = _deflection(pd, pfa)
    return root * root


def pd_from_detection_index(detection_index_, pfa):
    """Detection probability of the Gaussian ROC ``Pd = Φ(√d + Φ⁻¹(Pfa))``.

    Inverse of :func:`detection_index` in Pd. Exact for the equal-variance Gaussian model.

    Args:
        detection_index_: d, in [0, ∞) (the derivative in d is singular at d = 0).
        pfa: false-alarm probability, in (0, 1).

    >>> round(float(pd_from_detection_index(detection_index(0.9, 1e-6), 1e-6)), 12)
    0.9
    """
    w = "pd_from_detection_index"
    check_range("detection_index", detection_index_, 0.0, None, where=w)
    check_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True, where=w)
    return gaussian_pd(jnp.sqrt(jnp.asarray(detection_index_, dtype=float)), jnp.asarray(pfa, dtype=float))


def detection_threshold_known_signal_db(detection_index_, duration_s):
    """Detection threshold for a signal known exactly (cross-correlator) ``DT = 10 log10(d / 2t)`` (dB).

    Referred to the noise in a 1 Hz band (signal power over noise spectral density N0). The
    correlator output has d = 2E/N0 with E = S t the signal energy, so S/N0 = d/(2t) (Urick
    ch. 12). Exact for white Gaussian noise.

    Args:
        detection_index_: d, in (0, ∞).
        duration_s: signal duration t (s), in (0, ∞).
    """
    w = "detection_threshold_known_signal_db"
    check_range("detection_index", detection_index_, 0.0, None, lo_open=True, where=w)
    check_range("duration_s", duration_s, 0.0, None, lo_open=True, where=w)
    return db10(jnp.asarray(detection_index_) / (2.0 * jnp.asarray(duration_s)))


def detection_threshold_energy_db(detection_index_, bandwidth_hz, duration_s):
    """Detection threshold of an energy detector for a noise-like signal ``DT = 5 log10(d B / t)`` (dB).

    Referred to the noise in a 1 Hz band. With band-level SNR s = S/N and B t ≫ 1 the
    integrator output gives d = s² B t (Urick ch. 12), so S/N0 = B s = sqrt(d B / t). Subtract
    10 log10 B for the threshold in the band B: ``5 log10(d / (B t))``. Error: the Gaussian
    approximation of the chi-square statistic is optimistic for small B t. Against the exact
    chi-square detector (Gaussian signal in Gaussian noise, 2Bt degrees of freedom) at Pd 0.9,
    Pfa 1e-6 it is low by 3.5 dB at B t = 10, 1.1 dB at 100, 0.34 dB at 1e3 and 0.11 dB at 1e4
    (tests/sensors/sonar/test_sonar.py).

    Args:
        detection_index_: d, in (0, ∞).
        bandwidth_hz: receiver bandwidth B (Hz), in (0, ∞).
        duration_s: integration time t (s), in (0, ∞).
    """
    w = "detection_threshold_energy_db"
    check_range("detection_index", detection_index_, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("duration_s", duration_s, 0.0, None, lo_open=True, where=w)
    return 0.5 * db10(jnp.asarray(detection_index_) * jnp.asarray(bandwidth_hz) / jnp.asarray(duration_s))


def detection_threshold_db(pd, pfa, swerling=0):
    """Detection threshold in the receiver band for an envelope-detected echo (dB).

    The book treats the sonar echo as a sinusoid in white noise and reads the required SNR off
    the radar Pd/Pfa curves (§12.8); this is :func:`diffsense.detection.required_snr_db` for one
    pulse (exact Marcum/Swerling, ≤ 1e-9 dB).

    Args:
        pd: detection probability, in (pfa, 1 − 1e-12].
        pfa: false-alarm probability, in [1e-300, 0.5].
        swerling: echo fluctuation model 0-4 (static).

    >>> round(float(detection_threshold_db(0.9, 1e-6)), 1)  # book §12.8: 13.2 dB, steady echo
    13.2
    """
    return detection.required_snr_db(pd, pfa, 1, swerling)
