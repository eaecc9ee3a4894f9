"""Receiver losses: sensitivity time control (STC) and A/D-converter quantisation noise.

STC. A sensitivity-time-control attenuator lowers the receiver gain at short range, where
clutter and near targets would saturate it, following a power law in range up to a reference
range ``R_ref`` and leaving it unchanged beyond::

    G_stc(R) = (R / R_ref)^n   for R < R_ref,   1 for R >= R_ref;
    G_stc_dB = 10 n min(x, 0),  x = 10 log10(R / R_ref)  (dB of the range ratio).

With ``n = 4`` a target of constant RCS, whose echo grows as ``R^-4``, keeps inside ``R_ref``
the SNR it has at ``R_ref``; with ``n = 3`` (matched to area clutter) its SNR still grows as
``R^-1``. The STC loss of a target at range ``R`` is ``L_stc = -G_stc_dB`` (>= 0): the SNR it
loses against the same target without STC. That assumes the attenuation acts on the signal
ahead of the noise-setting stage (an RF attenuator, the usual radar-equation convention);
STC applied after the low-noise amplifier attenuates the noise too and costs (almost) no SNR.
:func:`stc_target_snr_db` gives the resulting SNR of a constant-RCS target.

Smooth knee (option). ``knee_width_db = w > 0`` replaces ``min(x, 0)`` by the soft minimum
``-w ln(1 + exp(-x / w))``: infinitely differentiable, below the hard law by at most
``n w ln 2`` dB (at ``R = R_ref``) and by less than ``n w exp(-|x|/w)`` dB at ``|x|`` dB from the
knee, so that a gradient-based design sees the knee's influence on both sides. ``w = 0`` (the
default) is the hard law, whose derivative at ``R = R_ref`` is taken from above (0).

Quantisation. A converter of ``b`` bits spanning ``[-V_fs, V_fs]`` has the step
``q = 2 V_fs / 2^b``. With the uniform (additive, white) model its error power is ``q^2/12``;
relative to thermal noise of rms ``sigma`` at its input::

    N_q / N = q^2 / (12 sigma^2),   sigma_lsb = sigma / q = 2^(b-1) / (V_fs / sigma),
    N_q / N (dB) = FS_dB + 20 log10 2 - 20 b log10 2 - 10 log10 12,  FS_dB = 20 log10(V_fs / sigma),

and the quantisation noise adds to the thermal noise, so the SNR loss is::

    L_q = 10 log10(1 + q^2 / (12 sigma^2)) = 10 log10(1 + 1 / (12 sigma_lsb^2)) dB.

Validity of the uniform model. For Gaussian noise at the input (and no clipping) the exact
error power of a mid-tread quantiser is ``q^2/12 + (q^2/pi^2) sum_k (-1)^k exp(-2 pi^2 k^2
sigma_lsb^2) / k^2`` (Widrow & Kollar); the uniform model is therefore wrong by -0.87 % at
``sigma_lsb = 0.5``, -1.8e-5 at 0.75 and -3.3e-9 at 1 (relative), checked against mpmath
quadrature in tests/detection/test_receiver_losses.py. Below ``sigma_lsb ~ 0.5`` the error is
no longer noise-like (it is a deterministic function of the signal) and the loss formula only
indicates the order of magnitude. Clipping at ``V_fs`` is not modelled: for the noise it is
negligible when ``FS_dB`` >= 15 dB (``V_fs`` >= 5.6 sigma: the clipped part of the noise power is
1.0e-9 of it); signals that exceed ``V_fs`` are outside the model.

Derivatives: closed forms (autodiff); the soft minimum uses ``logaddexp``; ``bits`` may be
real (continuous relaxation). Error: a few ulp of the dB values.

Sources
-------
- M. I. Skolnik, *Introduction to Radar Systems*, 3rd ed. (McGraw-Hill, 2001): sensitivity
  time control (R^-4 attenuation law for targets, R^-3 for area clutter).
- D. K. Barton, *Radar Equations for Modern Radar* (Artech House, 2013), ch. 10 (loss
  factors, STC loss on targets inside the STC range).
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed. (McGraw-Hill, 2014),
  ch. 3 "Sampling and quantization of pulsed radar signals" (quantisation noise ``q^2/12``,
  SQNR of about 6 dB per bit).
- W. R. Bennett, "Spectra of quantized signals", Bell Syst. Tech. J. 27, 446-472 (1948);
  B. Widrow and I. Kollar, *Quantization Noise* (Cambridge University Press, 2008) (the
  uniform model and its exact correction for Gaussian inputs).
"""

from __future__ import annotations

import jax.numpy as jnp

from diffsense.numerics.db import DB_PER_NEPER, db10, increment_db
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import as_float

__all__ = [
    "stc_gain_db",
    "stc_loss_db",
    "stc_target_snr_db",
    "quantisation_noise_db",
    "noise_rms_lsb",
    "quantisation_loss_db",
]

_TEN_LOG10_2 = 10.0 * 0.301029995663981195213738894724493027  # 10 log10 2
_TEN_LOG10_12 = 10.0 * 1.07918124604762482772250549628011741  # 10 log10 12


def _stc_gain(r, r_ref, n, w):
    x = DB_PER_NEPER * (jnp.log(r) - jnp.log(r_ref))  # 10 log10(R / R_ref)
    hard = jnp.where(x < 0.0, x, 0.0)
    smooth_on = w > 0.0
    w_safe = jnp.where(smooth_on, w, 1.0)
    soft = -w_safe * jnp.logaddexp(0.0, -x / w_safe)
    return n * jnp.where(smooth_on, soft, hard)


def _stc_admit(where, r, r_ref, n, w):
    ok, _ = admit(where, [("range_m", r, 0.0, None, True, False), ("reference_range_m", r_ref, 0.0, None, True, False),
                          ("exponent", n, 0.0, None), ("knee_width_db", w, 0.0, None)])
    return ok, (guard(r, ok, 1.0), guard(r_ref, ok, 1.0), guard(n, ok, 4.0), guard(w, ok, 0.0))


def stc_gain_db(range_m, reference_range_m, exponent=4.0, knee_width_db=0.0):
    """STC receiver gain (dB, <= 0): ``10 n log10(R / R_ref)`` below ``R_ref``, 0 beyond.

    Args:
        range_m: range (m), > 0.
        reference_range_m: range at which the STC ends, ``R_ref`` (m), > 0.
        exponent: power-law exponent ``n`` (>= 0; 4 keeps a constant-RCS target's SNR constant,
            3 matches area clutter).
        knee_width_db: ``w`` >= 0 (dB of range ratio): 0 the hard law; > 0 the soft minimum
            ``-n w ln(1 + exp(-x/w))``, ``x = 10 log10(R/R_ref)`` (module docstring).

    Returns:
        Gain in dB (<= 0; exact closed form, a few ulp).

    Source: Skolnik (2001) (sensitivity time control); Barton (2013) ch. 10.

    Half the reference range with the R^4 law: ``40 log10(1/2) = -12.04 dB``; beyond, 0 dB;
    with a 1 dB knee the gain at the reference range is ``-4 ln 2`` dB:

    >>> import math
    >>> float(stc_gain_db(5e3, 10e3)), 40 * math.log10(0.5), float(stc_gain_db(20e3, 10e3))
    (-12.0412, -12.0412, 0.0)
    >>> float(stc_gain_db(10e3, 10e3, 4.0, 1.0)), -4 * math.log(2)
    (-2.77259, -2.77259)
    """
    r, r_ref, n, w = jnp.broadcast_arrays(*as_float(range_m, reference_range_m, exponent, knee_width_db))
    ok, (r, r_ref, n, w) = _stc_admit("stc_gain_db", r, r_ref, n, w)
    return guard(_stc_gain(r, r_ref, n, w), ok)


def stc_loss_db(range_m, reference_range_m, exponent=4.0, knee_width_db=0.0):
    """STC loss (dB, >= 0) of a target at ``range_m``: ``-stc_gain_db`` (signal attenuated ahead
    of the noise-setting stage; module docstring).

    Args: as :func:`stc_gain_db`.

    >>> import math
    >>> float(stc_loss_db(2.5e3, 10e3, 3.0)), -30 * math.log10(0.25)
    (18.0618, 18.0618)
    """
    r, r_ref, n, w = jnp.broadcast_arrays(*as_float(range_m, reference_range_m, exponent, knee_width_db))
    ok, (r, r_ref, n, w) = _stc_admit("stc_loss_db", r, r_ref, n, w)
    return guard(-_stc_gain(r, r_ref, n, w), ok)


def stc_target_snr_db(range_m, reference_range_m, snr_reference_db, exponent=4.0, knee_width_db=0.0):
    """SNR (dB) of a constant-RCS target under STC: ``S_ref + 40 log10(R_ref/R) + G_stc(R)``.

    ``snr_reference_db`` is the target's SNR at ``R_ref`` (no STC there). With ``exponent = 4``
    the SNR is constant inside ``R_ref``; with ``exponent = 3`` it rises as ``10 log10(R_ref/R)``.

    Args:
        range_m, reference_range_m, exponent, knee_width_db: as :func:`stc_gain_db`.
        snr_reference_db: SNR at the reference range (dB), finite.

    Returns:
        SNR in dB (exact closed form).

    >>> float(stc_target_snr_db(3e3, 12e3, 15.0)), float(stc_target_snr_db(24e3, 12e3, 15.0))
    (15.0, 2.95880017)
    """
    r, r_ref, s_db, n, w = jnp.broadcast_arrays(*as_float(range_m, reference_range_m, snr_reference_db, exponent,
                                                         knee_width_db))
    where = "stc_target_snr_db"
    ok, (r, r_ref, n, w) = _stc_admit(where, r, r_ref, n, w)
    ok_s, _ = admit(where, [("snr_reference_db", s_db, -jnp.inf, jnp.inf, True, True)])
    ok = ok & ok_s
    s_db = guard(s_db, ok, 0.0)
    spread = 4.0 * DB_PER_NEPER * (jnp.log(r_ref) - jnp.log(r))  # 40 log10(R_ref / R)
    return guard(s_db + spread + _stc_gain(r, r_ref, n, w), ok)


def quantisation_noise_db(bits, full_scale_to_rms_noise_db):
    """Quantisation noise power ``q^2/12`` relative to the thermal noise power (dB).

    ``q = 2 V_fs / 2^b`` (converter range ``[-V_fs, V_fs]``); ``FS_dB = 20 log10(V_fs/sigma)``
    with ``sigma`` the rms thermal noise at the converter input::

        N_q/N = FS_dB + 10 log10 4 - b 10 log10 4 - 10 log10 12    (dB)

    Args:
        bits: converter bits b (real >= 1; continuous relaxation).
        full_scale_to_rms_noise_db: ``FS_dB`` (dB), finite.

    Returns:
        ``10 log10(q^2 / (12 sigma^2))`` in dB (uniform-error model: module docstring for its
        validity, -0.87 % at sigma = q/2, < 1e-8 relative for sigma >= q).

    Source: Richards (2014) ch. 3; Bennett (1948).

    Twelve bits with the noise rms at one step (V_fs = 2^11 sigma): ``10 log10(1/12)``:

    >>> import math
    >>> float(quantisation_noise_db(12, 20 * math.log10(2 ** 11))), 10 * math.log10(1 / 12)
    (-10.7918125, -10.7918125)
    """
    b, fs = jnp.broadcast_arrays(*as_float(bits, full_scale_to_rms_noise_db))
    ok, _ = admit("quantisation_noise_db", [("bits", b, 1.0, None),
                                            ("full_scale_to_rms_noise_db", fs, -jnp.inf, jnp.inf, True, True)])
    b, fs = guard(b, ok, 8.0), guard(fs, ok, 0.0)
    return guard(fs + 2.0 * _TEN_LOG10_2 * (1.0 - b) - _TEN_LOG10_12, ok)


def noise_rms_lsb(bits, full_scale_to_rms_noise_db):
    """Thermal noise rms in converter steps: ``sigma / q = 2^(b-1) 10^(-FS_dB/20)``.

    Args: as :func:`quantisation_noise_db`.

    >>> import math
    >>> float(noise_rms_lsb(10, 20 * math.log10(2 ** 9 / 1.5)))
    1.5
    """
    b, fs = jnp.broadcast_arrays(*as_float(bits, full_scale_to_rms_noise_db))
    ok, _ = admit("noise_rms_lsb", [("bits", b, 1.0, None),
                                    ("full_scale_to_rms_noise_db", fs, -jnp.inf, jnp.inf, True, True)])
    b, fs = guard(b, ok, 8.0), guard(fs, ok, 0.0)
    return guard(jnp.exp((b - 1.0) * jnp.log(2.0) - fs / (2.0 * DB_PER_NEPER)), ok)


def quantisation_loss_db(noise_rms_lsb):
    """SNR loss (dB) from quantisation noise: ``10 log10(1 + 1 / (12 sigma_lsb^2))``.

    The quantisation noise ``q^2/12`` adds to the thermal noise ``sigma^2`` (uniform-error
    model); ``sigma_lsb = sigma / q`` (:func:`noise_rms_lsb`). Evaluated as
    ``increment_db(-10 log10 12 - 20 log10 sigma_lsb)`` (``logaddexp``, no square that could
    underflow), finite with a finite derivative for any positive float sigma_lsb.

    Args:
        noise_rms_lsb: rms thermal noise at the converter input in steps (LSB), > 0. The model
            is accurate for sigma_lsb >= ~0.5 (module docstring: -0.87 % in the noise power at
            0.5, i.e. the loss there is 1.2494 dB for an exact 1.2399 dB; < 1e-8 relative in
            the noise power from 1 up).

    Returns:
        Loss in dB (> 0): 0.35 dB at 1 LSB, 0.09 dB at 2 LSB, 1.25 dB at 0.5 LSB.

    Source: Richards (2014) ch. 3 (quantisation noise); Widrow & Kollar (2008).

    >>> import math
    >>> float(quantisation_loss_db(1.0)), 10 * math.log10(1 + 1 / 12)
    (0.3476, 0.3476)
    """
    (s,) = as_float(noise_rms_lsb)
    ok, _ = admit("quantisation_loss_db", [("noise_rms_lsb", s, 0.0, None, True, False)])
    s = guard(s, ok, 1.0)
    return guard(increment_db(-_TEN_LOG10_12 - 2.0 * db10(s)), ok)
