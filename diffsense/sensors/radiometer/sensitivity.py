"""Radiometer sensitivity and detection: the unbalanced Dicke radiometer's ΔT (the total-power
and balanced Dicke forms are in :mod:`diffsense.physics.noise`) and detection of a mean shift in
Gaussian noise.

After integration over Bτ ≫ 1 independent samples the radiometer output is Gaussian (central
limit theorem), so detecting a mean shift ΔT_c in noise of standard deviation ΔT_rms is the
Gaussian-shift problem: ``Pd = Q(Q⁻¹(Pfa) − d)`` with ``d = |ΔT_c|/ΔT_rms``.

Sources: Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I (1981), ch. 6; Skou & Le Vine,
*Microwave Radiometer Systems* (2006), ch. 3; Van Trees, *Detection, Estimation and Modulation
Theory* Pt I (1968) §2.2.

Pd 0.9 at Pfa 1e-6 needs d = z(0.9) + z(1e-6) = 1.2816 + 4.7534 (normal table, Abramowitz &
Stegun Table 26.5):

>>> from diffsense.sensors.radiometer.sensitivity import gaussian_required_deflection
>>> round(float(gaussian_required_deflection(0.9, 1e-6)), 4) == round(1.2816 + 4.7534, 4)
True
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.detection.gaussian import gaussian_detection_probability, gaussian_required_deflection  # noqa: F401  (re-exported)
from diffsense.numerics.checks import check_range

__all__ = ["unbalanced_dicke_delta_t_k", "gaussian_detection_probability", "gaussian_required_deflection"]


def unbalanced_dicke_delta_t_k(antenna_temperature_k, receiver_noise_temperature_k, reference_temperature_k,
                               bandwidth_hz, integration_time_s, gain_variation=0.0):
    """Sensitivity of a Dicke radiometer whose reference differs from the antenna temperature (K).

    ``ΔT = sqrt([2 (T_A + T_R)² + 2 (T_ref + T_R)²]/(Bτ) + (ΔG/G)² (T_A − T_ref)²)``:
    half the integration time on each input (hence the factors 2) and the residual gain
    fluctuation of the unbalanced difference. For T_ref = T_A it is the balanced Dicke
    ``2 (T_A + T_R)/sqrt(Bτ)`` of :func:`diffsense.physics.noise.dicke_radiometer_delta_t_k`.

    Args:
        antenna_temperature_k: T_A (K), in [0, 1e5].
        receiver_noise_temperature_k: T_R (K), in [0, 1e6].
        reference_temperature_k: brightness of the reference load T_ref (K), in [0, 1e5].
        bandwidth_hz: predetection bandwidth B (Hz), in (0, ∞).
        integration_time_s: τ (s), in (0, ∞).
        gain_variation: RMS ΔG/G over the integration time, in [0, 1].

    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 6 (unbalanced Dicke radiometer); Skou & Le
    Vine (2006) ch. 3.
    """
    w = "unbalanced_dicke_delta_t_k"
    check_range("antenna_temperature_k", antenna_temperature_k, 0.0, 1e5, where=w)
    check_range("receiver_noise_temperature_k", receiver_noise_temperature_k, 0.0, 1e6, where=w)
    check_range("reference_temperature_k", reference_temperature_k, 0.0, 1e5, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("integration_time_s", integration_time_s, 0.0, None, lo_open=True, where=w)
    check_range("gain_variation", gain_variation, 0.0, 1.0, where=w)
    return _unbalanced_dicke(antenna_temperature_k, receiver_noise_temperature_k, reference_temperature_k,
                             bandwidth_hz, integration_time_s, gain_variation)


def _unbalanced_dicke(ta, tr, tref, b, tau, g):
    radiometric = 2.0 * ((ta + tr) ** 2 + (tref + tr) ** 2) / (b * tau)
    return jnp.sqrt(radiometric + (g * (ta - tref)) ** 2)


