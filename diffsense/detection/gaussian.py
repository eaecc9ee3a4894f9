"""Detection of a Gaussian statistic with a signal-independent variance: the equal-variance
Gaussian ROC shared by every chain whose decision statistic is (close to) normal — radiometers
integrating Bτ ≫ 1 samples, infrared point-target detectors, sonar detection indices, lidar
photocurrents above the shot-noise regime.

With the deflection d (mean shift over the rms noise), ``Pfa = Q(T)`` and ``Pd = Q(T − d)``, so

    Pd = Φ(d + Φ⁻¹(Pfa)),      d = Φ⁻¹(Pd) − Φ⁻¹(Pfa)

(Φ the standard normal CDF; written with Φ⁻¹(Pfa) rather than Q⁻¹ so that small Pfa keeps full
precision). Exact for that model to float64 round-off of ``ndtr``/``ndtri``. Sources: Peterson,
Birdsall & Fox, "The theory of signal detectability", IRE Trans. PGIT 4 (1954); Van Trees,
*Detection, Estimation and Modulation Theory* Pt I (1968) §2.2.

>>> round(float(gaussian_required_deflection(0.9, 1e-6)), 4) == round(1.2816 + 4.7534, 4)
True
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtr, ndtri

from diffsense.numerics.checks import check_range, is_concrete

__all__ = ["gaussian_detection_probability", "gaussian_required_deflection", "gaussian_pd"]


def gaussian_detection_probability(deflection, pfa):
    """Pd of a mean shift d (in standard deviations) in Gaussian noise: ``Pd = Q(Q⁻¹(Pfa) − d)``.

    Written ``Φ(d + Φ⁻¹(Pfa))`` (Φ the standard normal CDF) so that small Pfa keeps full
    precision. Applies to any detector whose statistic is Gaussian with a signal-independent
    variance: a radiometer integrating Bτ ≫ 1 samples, an IR point-target detector in
    Gaussian (shot/g-r/Johnson) noise.

    Args:
        deflection: d = mean shift / rms noise, in [0, 1e4].
        pfa: false-alarm probability, in [1e-300, 0.5].

    Exact. Source: Van Trees, *Detection, Estimation and Modulation Theory* Pt I (1968) §2.2
    (Gaussian shift, d²); Hudson, *Infrared System Engineering* (1969) ch. 11.
    """
    w = "gaussian_detection_probability"
    check_range("deflection", deflection, 0.0, 1e4, where=w)
    check_range("pfa", pfa, 1e-300, 0.5, where=w)
    return gaussian_pd(jnp.asarray(deflection, dtype=float), jnp.asarray(pfa, dtype=float))


def gaussian_pd(deflection, pfa):
    """``Φ(d + Φ⁻¹(Pfa))`` without domain checks: the form the sensor chains trace (their
    parameters are checked when the spec is read)."""
    return ndtr(deflection + ndtri(pfa))


def gaussian_required_deflection(pd, pfa):
    """Deflection needed for (Pd, Pfa) with a Gaussian statistic: ``d = Φ⁻¹(Pd) − Φ⁻¹(Pfa)``.

    Inverse of :func:`gaussian_detection_probability`. Args: ``pd`` in (Pfa, 1 − 1e-16];
    ``pfa`` in [1e-300, 0.5]. Example: Pd 0.9, Pfa 1e-6 → 1.2816 + 4.7534 = 6.035.
    """
    w = "gaussian_required_deflection"
    check_range("pfa", pfa, 1e-300, 0.5, where=w)
    check_range("pd", pd, 0.0, 1.0 - 1e-16, lo_open=True, where=w)
    if is_concrete(pd) and is_concrete(pfa):
        gap = np.asarray(pd, dtype=float) - np.asarray(pfa, dtype=float)
        check_range("pd - pfa", gap, 0.0, None, lo_open=True, where=w)
    return ndtri(jnp.asarray(pd, dtype=float)) - ndtri(jnp.asarray(pfa, dtype=float))
