"""Budget losses of a scanning, sampling radar: beam shape, array scan, range and Doppler
straddle, eclipsing. Exact closed forms (or exact quadrature), differentiable, in dB.

Each loss is the ratio of the SNR a target would give at the best point (beam peak, sample on
the matched-filter peak, signal at the centre of an FFT bin, echo clear of the transmit pulse)
to the SNR it gives where it is, ``L = -10 log10 rho`` with ``rho <= 1`` the power ratio. An
*average* loss is the ratio for the *mean* SNR over a uniformly distributed position,
``L = -10 log10 E[rho]`` (the SNR-averaged or coherent-equivalent loss: what an ideal energy
integrator over the interval loses, and the loss of the mean SNR of a target placed at
random). It is neither the mean of the dB loss (larger, by Jensen's inequality) nor a
Pd-weighted ("statistical") loss, which depends on the detection model.

Beam shape (two-way gain, scan in one or two angles). With ``g(u)`` the one-way power pattern,
``u`` the angle in one-way 3-dB beamwidths (``g(0) = 1``, ``g(+-1/2) = 1/2``) and beam
positions (or the integrated stretch of a continuous scan) ``s`` beamwidths apart::

    L_1D(s) = s / int_{-s/2}^{s/2} g(u)^2 du,       L_2D(s) = L_1D(s)^2

(2-D: a raster with spacing ``s`` in both angles; exact for the separable patterns here).

- Gaussian ``g = exp(-4 ln2 u^2)``: ``L = x / E(x)``, ``x = s sqrt(2 ln 2)``,
  ``E(x) = int_0^x exp(-t^2) dt = (sqrt(pi)/2) erf(x)``.
- Uniform line aperture ``g = sinc^2(pi v)``, ``v = 2 v0 u`` (``v0 = 0.442946`` the half-power
  point, the familiar 0.886 lambda/D beamwidth): ``L = X / F(X)``, ``X = pi v0 s``,
  ``F(X) = int_0^X (sin y/y)^4 dy`` in closed form (four integrations by parts)::

      F = (4 Si(4X) - 2 Si(2X))/3 - sin^4 X/(3 X^3) - 2 sin^3 X cos X/(3 X^2)
          + (2 sin^4 X/3 - 2 sin^2 X cos^2 X)/X

Values: contiguous beams (``s = 1``) lose 1.672 dB (Gaussian) / 1.622 dB (sinc) in 1-D and
3.343 / 3.244 dB in 2-D. The figures usually budgeted, 1.6 dB and 3.2 dB (Blake; quoted by
Skolnik, and Brooker's example 9.9.1 budgets "1D scanning loss = 1.6 dB"), are *two-way*
numbers: averaging the one-way Gaussian pattern would give 0.915 dB. They match the sinc
pattern to the printed digits and the Gaussian to 0.07 dB. Barton's dense-sampling value
(pulse count referred to the 3-dB beamwidth, all pulses integrated) is the large-``s`` limit
``L(s)/s -> sqrt(8 ln2 / pi)``: 1.234 dB (1-D), 2.468 dB (2-D).

Array scan. A planar array steered ``theta`` off broadside has one-way gain ``G(0) cos^n
theta`` (``n = 1``: projected aperture, Brooker eq. (12.30); ``n ~ 1.5`` with the element
pattern); the two-way (transmit and receive) loss is ``L = -20 n log10 cos theta``.

Range straddle. A rectangular pulse of length ``tau`` through its matched filter gives the
triangular amplitude ``1 - |t|/tau``; a sample ``delta tau`` off the peak loses
``-20 log10(1 - |delta|)``. For samples ``Delta tau`` apart and a uniform offset (``a =
Delta/2``): ``E[rho] = 1 - a + a^2/3`` (``a <= 1``), ``1/(3a)`` (``a > 1``, targets between
the triangles give nothing); worst case ``-20 log10(1 - a)``. An ideal band-limited
(compressed, e.g. large time-bandwidth LFM) pulse has the response ``sinc(pi delta)``, offsets
in resolution cells ``1/B``: the same as the rectangular Doppler window.

Doppler straddle. A signal ``delta`` bins off the centre of an FFT bin, window ``w(t) = a0 -
a1 cos(2 pi t/T)`` (rectangular, Hann, Hamming), has the amplitude response, relative to the
bin centre (continuous-time limit, i.e. many samples)::

    W(delta) = sinc(pi delta) (1 + (a1/a0) delta^2 / (1 - delta^2)),   |delta| <= 1/2

Rectangular window at half a bin: ``(2/pi)^2`` = 3.922 dB (Richards; Harris's "scallop
loss", 3.92 dB; Hann 1.42 dB). The window's own on-bin processing loss is not included. The
average over a uniform offset in ``[-Delta/2, Delta/2]`` (``Delta`` the bin spacing in
``1/T``, < 1 when zero-padded) is a 24-node Gauss-Legendre rule of an entire integrand
(measured error below 1e-15 dB against mpmath).

Eclipsing. The receiver is blanked while transmitting (``[k T, k T + tau]``, ``T = 1/PRF``).
An echo of delay ``2R/c``, apparent delay ``p T`` (``p`` = fractional part of ``2 R PRF / c``,
i.e. ``R`` modulo the unambiguous range ``c/(2 PRF)``), keeps the fraction::

    f = 1 - max(0, 1 - p/d) - max(0, 1 - (1 - p)/d),     d = tau PRF (duty cycle) < 1

of its energy, and a filter matched to the surviving part (or the full-length filter in a
blanked receiver, where noise is blanked too) loses ``-10 log10 f``. (A receiver that keeps
its noise while the signal is blanked would lose ``-20 log10 f``; not modelled.) A fully
eclipsed echo (``f = 0``: ``R`` a multiple of the unambiguous range) has no finite loss; the
loss is clipped at ``max_loss_db`` (``f`` floored at ``10^(-max_loss_db/10)``, derivative 0
there), so it is never inf or NaN. Over a uniformly distributed range ``E[f] = 1 - d`` (the
mean blanked fraction), so the SNR-averaged loss is ``-10 log10(1 - d)``.

Domain, derivatives, accuracy. Inputs outside a function's documented domain raise
:class:`~diffsense.errors.DomainError` when eager and give NaN (value and derivative) when
traced (:mod:`diffsense.detection._domain`). Small arguments use Taylor series (Gaussian and
sinc^4 averages below ``x = 0.5`` / ``X = 1``, ``log cos`` through ``log1p(-2 sin^2(theta/2))``,
``cos`` near 90 degrees as ``sin`` of ``pi/2 - |theta|`` with pi/2 split in two doubles), so
values and derivatives are finite at zero spacing, offset and angle. Derivatives are JAX
autodiff of the closed forms, except ``F`` (custom JVP: ``F' = sinc^4``). Measured error
against 30-digit mpmath (tests/detection/test_scan_losses.py): beam shape below 8e-15 dB
(largest just above the sinc series limit, where the closed form cancels by a factor 4),
straddle losses below 2.5e-15 dB (1.2e-16 relative near the triangle's zero), scan loss below
7e-16 relative up to fl(pi/2) (also when jitted: an optimization barrier stops XLA from
folding the split pi/2 back into one double), eclipsing averages below 4e-16 relative, the
eclipsing loss to the rounding of the apparent delay ``p`` (relative ~ ``2 R PRF / c`` ulp).
``log1p`` is XLA's only where it is accurate (:func:`_log1p`).

Sources
-------
- L. V. Blake, *Radar Range-Performance Analysis* (Lexington Books, 1980; Munro, 1986): the
  antenna pattern (beam-shape) loss of a scanning radar, 1.6 dB per scanned coordinate.
- D. K. Barton, *Radar Equations for Modern Radar* (Artech House, 2013), ch. 5 (beamshape loss
  for dense and sparse sampling, one- and two-coordinate scans; phased-array scan loss) and its
  treatment of eclipsing and range/Doppler straddle in the loss budget.
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed. (McGraw-Hill, 2014):
  range and Doppler straddle loss, 3.92 dB for the rectangular window at half a bin.
- M. I. Skolnik, *Introduction to Radar Systems*, 3rd ed. (McGraw-Hill, 2001): beam-shape loss
  in the radar equation (Blake's 1.6 dB / 3.2 dB).
- F. J. Harris, "On the use of windows for harmonic analysis with the discrete Fourier
  transform", Proc. IEEE 66(1), 51-83 (1978), Table 1 (scallop loss).
- G. Brooker, *Introduction to Sensors for Ranging and Imaging* (SciTech, 2009), eq. (12.30)
  and worked example 9.9.1.
"""

from __future__ import annotations

import math
from fractions import Fraction

import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.special import erf

from diffsense.numerics.checks import check_choice
from diffsense.numerics.db import DB_PER_NEPER
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import as_float
from diffsense.detection.matched_filter import sine_integral

__all__ = [
    "PATTERNS",
    "WINDOWS",
    "PULSE_SHAPES",
    "SPEED_OF_LIGHT_M_S",
    "beam_shape_loss_db",
    "scan_sector_loss_db",
    "range_straddle_loss_db",
    "range_straddle_loss_average_db",
    "doppler_straddle_loss_db",
    "doppler_straddle_loss_average_db",
    "eclipsing_loss_db",
    "eclipsing_loss_average_db",
]

#: Beam patterns of :func:`beam_shape_loss_db`.
PATTERNS = ("gaussian", "sinc")
#: FFT windows ``a0 - a1 cos(2 pi t / T)`` of the Doppler straddle loss: (a0, a1).
WINDOWS = {"rect": (1.0, 0.0), "hann": (0.5, 0.5), "hamming": (0.54, 0.46)}
#: Pulse shapes of the range straddle loss (matched-filter response triangle or sinc).
PULSE_SHAPES = ("rect", "sinc")
#: Speed of light in vacuum (m/s), exact (SI).
SPEED_OF_LIGHT_M_S = 299792458.0

_LN2 = math.log(2.0)
_HALF_SQRT_PI = 0.5 * math.sqrt(math.pi)
_GAUSS_X_PER_BEAMWIDTH = math.sqrt(2.0 * _LN2)
#: root of sinc^2(pi v) = 1/2 (mpmath, 40 digits: 0.44294647068945234030836999...)
_SINC_HALF_POWER_V = 0.44294647068945234
_SINC_X_PER_BEAMWIDTH = math.pi * _SINC_HALF_POWER_V
_HALF_PI_LO = 6.123233995736766e-17  # pi/2 - fl(pi/2) (float64)
_SERIES_TERMS = 16
_GAUSS_SERIES_LIMIT = 0.5  # last omitted term 0.5^32/(16! 33) < 2e-25
_SINC_SERIES_LIMIT = 1.0  # last omitted term ~ 4^36/(8 36! 33) < 1e-22
_SINC_TAYLOR_LIMIT = 0.05  # sin(x)/x series through x^8: omitted x^10/11! < 3e-21
_QUAD_NODES = 24


# --------------------------------------------------------------------------------------
# Series coefficients (exact rationals, rounded once)
# --------------------------------------------------------------------------------------


def _product(a, b, terms):
    return [sum(a[i] * b[k - i] for i in range(k + 1)) for k in range(terms)]


def _gauss_mean_coefficients(terms):
    """E(x)/x = sum_k (-1)^k x^(2k) / (k! (2k+1)); returns the k >= 1 coefficients."""
    return tuple(float(Fraction((-1) ** k, math.factorial(k) * (2 * k + 1))) for k in range(1, terms))


def _sinc4_mean_coefficients(terms):
    """F(X)/X = sum_k c_k X^(2k) / (2k+1), (sin y/y)^4 = sum_k c_k y^(2k); k >= 1 returned."""
    sinc = [Fraction((-1) ** k, math.factorial(2 * k + 1)) for k in range(terms)]
    square = _product(sinc, sinc, terms)
    fourth = _product(square, square, terms)
    return tuple(float(fourth[k] / (2 * k + 1)) for k in range(1, terms))


_GAUSS_MEAN_COEFFS = _gauss_mean_coefficients(_SERIES_TERMS)
_SINC4_MEAN_COEFFS = _sinc4_mean_coefficients(_SERIES_TERMS)


def _series_minus_one(y, coeffs):
    """sum_{k>=1} coeffs[k-1] y^k (Horner)."""
    acc = jnp.zeros_like(y)
    for c in reversed(coeffs):
        acc = acc * y + c
    return acc * y


def _log1p(x):
    """log(1 + x) to 5e-16 relative for x > -1: XLA's CPU log1p errs up to 2.6e-14 relative on
    about [-0.414, -0.367] (measured against mpmath, jax 0.10), so log(1 + x) is used for
    |x| >= 1/4, where rounding 1 + x costs at most 5e-16 relative."""
    x = jnp.asarray(x)
    near_zero = jnp.abs(x) < 0.25
    return jnp.where(near_zero, jnp.log1p(jnp.where(near_zero, x, 0.0)), jnp.log(1.0 + jnp.where(near_zero, 0.5, x)))


def _admitted(where, constraints, fills):
    """``(ok, placeholders)``: DomainError if eager, inadmissible elements replaced if traced."""
    ok, _ = admit(where, constraints)
    return ok, [guard(c[1], ok, f) for c, f in zip(constraints, fills)]


# --------------------------------------------------------------------------------------
# Beam shape
# --------------------------------------------------------------------------------------


def _log_mean_gain_gauss(x):
    """log(E(x)/x), E(x) = int_0^x exp(-t^2) dt: the log mean two-way Gaussian gain."""
    small = x <= _GAUSS_SERIES_LIMIT
    xs = jnp.where(small, x, 0.0)
    xl = jnp.where(small, 1.0, x)
    series = _log1p(_series_minus_one(xs * xs, _GAUSS_MEAN_COEFFS))
    closed = jnp.log(_HALF_SQRT_PI * erf(xl) / xl)
    return jnp.where(small, series, closed)


@jax.custom_jvp
def _sinc4_integral(x):
    """F(x) = int_0^x (sin y / y)^4 dy for x >= 1 (closed form; its terms cancel by at most 4x there)."""
    s, c = jnp.sin(x), jnp.cos(x)
    s2 = s * s
    return ((4.0 * sine_integral(4.0 * x) - 2.0 * sine_integral(2.0 * x)) / 3.0
            - s2 * s2 / (3.0 * x**3) - 2.0 * s2 * s * c / (3.0 * x * x)
            + (2.0 * s2 * s2 / 3.0 - 2.0 * s2 * c * c) / x)


@_sinc4_integral.defjvp
def _sinc4_integral_jvp(primals, tangents):
    (x,), (dx,) = primals, tangents
    return _sinc4_integral(x), (jnp.sin(x) / x) ** 4 * dx


def _log_mean_gain_sinc(x):
    """log(F(X)/X): the log mean two-way gain of the sinc^2 (uniform aperture) pattern."""
    small = x <= _SINC_SERIES_LIMIT
    xs = jnp.where(small, x, 0.0)
    xl = jnp.where(small, 2.0, x)
    series = _log1p(_series_minus_one(xs * xs, _SINC4_MEAN_COEFFS))
    closed = jnp.log(_sinc4_integral(xl) / xl)
    return jnp.where(small, series, closed)


def beam_shape_loss_db(beam_spacing, dims: int = 1, pattern: str = "gaussian"):
    """Beam-shape loss (dB): peak over mean two-way gain across ``beam_spacing`` beamwidths.

    ``L_1D = s / int_{-s/2}^{s/2} g(u)^2 du`` (``g`` the one-way power pattern, ``u`` in one-way
    3-dB beamwidths), ``L_2D = L_1D^2``; Gaussian ``g = exp(-4 ln2 u^2)`` in closed form
    ``L = x / ((sqrt(pi)/2) erf(x))``, ``x = s sqrt(2 ln 2)``; uniform-aperture ``g =
    sinc^2`` through the sine integral (module docstring). The SNR-averaged loss of a target
    uniformly placed between beam positions ``s`` apart, equally the loss of ideal integration
    of the pulses over a scan of ``s`` beamwidths centred on the target.

    Args:
        beam_spacing: ``s`` >= 0, spacing of beam positions (or integrated scan extent) in
            one-way 3-dB (half-power) beamwidths; 0 gives 0 dB.
        dims: 1 (scan in one angle) or 2 (raster in azimuth and elevation, spacing ``s`` in
            each, in that axis's beamwidths); static.
        pattern: ``"gaussian"`` or ``"sinc"`` (uniform line/rectangular aperture); static.

    Returns:
        Loss in dB (>= 0), increasing in ``s``; error < 1e-14 dB (mpmath quadrature).

    Source: Blake (1980), Skolnik (2001): 1.6 dB (1-D) and 3.2 dB (2-D) for contiguous beams;
    Barton (2013) ch. 5. Gaussian, contiguous beams (``s = 1``), against a scipy quadrature of
    the definition; the sinc pattern gives the quoted 1.6 / 3.2 dB to their digits:

    >>> import math
    >>> from scipy.integrate import quad
    >>> mean = quad(lambda u: math.exp(-8 * math.log(2) * u * u), -0.5, 0.5)[0]
    >>> float(beam_shape_loss_db(1.0)), -10 * math.log10(mean)
    (1.671620, 1.671620)
    >>> round(float(beam_shape_loss_db(1.0, pattern="sinc")), 1), round(float(beam_shape_loss_db(1.0, 2, "sinc")), 1)
    (1.6, 3.2)
    """
    where = "beam_shape_loss_db"
    check_choice("dims", dims, (1, 2), where=where)
    check_choice("pattern", pattern, PATTERNS, where=where)
    (s,) = as_float(beam_spacing)
    ok, (s,) = _admitted(where, [("beam_spacing", s, 0.0, None)], (1.0,))
    if pattern == "gaussian":
        log_mean = _log_mean_gain_gauss(_GAUSS_X_PER_BEAMWIDTH * s)
    else:
        log_mean = _log_mean_gain_sinc(_SINC_X_PER_BEAMWIDTH * s)
    return guard(-float(dims) * DB_PER_NEPER * log_mean, ok)


# --------------------------------------------------------------------------------------
# Phased-array scan loss
# --------------------------------------------------------------------------------------


def _half_pi_parts(dtype):
    """(hi, lo) with hi = pi/2 rounded to ``dtype`` and hi + lo = pi/2 to double precision."""
    hi = float(np.asarray(math.pi / 2.0, dtype=dtype))
    return hi, (math.pi / 2.0 - hi) + _HALF_PI_LO


def _largest_angle(dtype):
    """The largest ``dtype`` number below pi/2 (fl(pi/2) itself in float64)."""
    hi, lo = _half_pi_parts(dtype)
    return hi if lo > 0.0 else float(np.nextafter(np.asarray(hi, dtype=dtype), np.asarray(0.0, dtype=dtype)))


def _log_cos(theta):
    """log cos(theta), |theta| < pi/2, accurate relative to its size at both ends."""
    a = jnp.abs(theta)
    near_zero = a <= 0.25 * math.pi
    hi, lo = _half_pi_parts(theta.dtype)
    t_small = jnp.where(near_zero, theta, 0.0)
    t_large = jnp.where(near_zero, 1.0, a)
    h = jnp.sin(0.5 * t_small)
    small = _log1p(-2.0 * h * h)  # cos = 1 - 2 sin^2(theta/2)
    # hi - t is exact (Sterbenz) for t >= pi/4; the barrier keeps XLA from folding the two
    # constants into (hi + lo) - t = hi - t, which loses lo (found: -inf at fl(pi/2) when jitted)
    large = jnp.log(jnp.sin(jax.lax.optimization_barrier(hi - t_large) + lo))
    return jnp.where(near_zero, small, large)


def scan_sector_loss_db(scan_angle_rad, exponent=1.5, two_way: bool = True):
    """Electronic scan loss (dB) of a phased array steered ``scan_angle_rad`` off broadside.

    One-way gain ``G(theta) = G(0) cos^n theta``; the loss is ``-10 log10 cos^n theta`` per
    pass, doubled for transmit and receive through the same array (``two_way=True``, the
    default): ``L = -20 n log10 cos theta``. ``n = 1`` is the projected-aperture law
    (Brooker eq. 12.30); the default ``n = 1.5`` adds the typical element-pattern fall-off.
    (A two-way cosine power ``m``, the ``cos^m`` form of MathWorks' ``arrayscanloss``, is
    ``exponent = m/2`` here.)

    Args:
        scan_angle_rad: ``theta`` in radians, ``|theta| < pi/2`` (every float64 up to
            fl(pi/2) = 1.5707963267948966, which lies 6.1e-17 below pi/2).
        exponent: one-way cosine exponent ``n >= 0``.
        two_way: True for the transmit-and-receive loss, False for one pass; static.

    Returns:
        Loss in dB (>= 0); relative error < 2e-15 up to fl(pi/2) (cos near pi/2 is evaluated
        as ``sin(pi/2 - |theta|)`` with pi/2 in two parts). Derivative
        ``(20 n / ln 10) tan theta`` (two-way), 0 at broadside.

    Source: Barton (2013) ch. 5; Skolnik (2001); Brooker eq. (12.30). One pass of the
    projected-aperture law at 60 degrees loses ``-10 log10(1/2)``:

    >>> import math
    >>> float(scan_sector_loss_db(math.radians(60.0), 1.0, two_way=False)), -10 * math.log10(0.5)
    (3.0103, 3.0103)
    >>> float(scan_sector_loss_db(math.radians(60.0))), -30 * math.log10(0.5)
    (9.0309, 9.0309)
    """
    where = "scan_sector_loss_db"
    check_choice("two_way", two_way, (True, False), where=where)
    theta, n = jnp.broadcast_arrays(*as_float(scan_angle_rad, exponent))
    bound = _largest_angle(theta.dtype)
    ok, (theta, n) = _admitted(where, [("scan_angle_rad", theta, -bound, bound), ("exponent", n, 0.0, None)],
                               (0.0, 1.0))
    passes = 2.0 if two_way else 1.0
    return guard(-passes * DB_PER_NEPER * n * _log_cos(theta), ok)


# --------------------------------------------------------------------------------------
# Straddle losses
# --------------------------------------------------------------------------------------


def _sinc_pi(d):
    """sin(pi d)/(pi d), with its Taylor series near 0 (finite derivatives there)."""
    x = math.pi * d
    small = jnp.abs(x) < _SINC_TAYLOR_LIMIT
    xs = jnp.where(small, x, 0.0)
    xl = jnp.where(small, 1.0, x)
    x2 = xs * xs
    series = 1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0)))
    return jnp.where(small, series, jnp.sin(xl) / xl)


def _window_amplitude(d, window):
    """W(delta)/W(0) of the window ``a0 - a1 cos``, |delta| <= 1/2 (positive there)."""
    a0, a1 = WINDOWS[window]
    amp = _sinc_pi(d)
    if a1 != 0.0:
        d2 = d * d
        amp = amp * (1.0 + (a1 / a0) * d2 / (1.0 - d2))
    return amp


def _gauss_legendre_unit(n):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


_QUAD_T, _QUAD_W = _gauss_legendre_unit(_QUAD_NODES)


def _mean_power_gain(half_width, window):
    """(1/A) int_0^A W(delta)^2 d delta (Gauss-Legendre, entire integrand; A <= 1/2)."""
    t = jnp.asarray(_QUAD_T, dtype=half_width.dtype)
    w = jnp.asarray(_QUAD_W, dtype=half_width.dtype)
    amp = _window_amplitude(half_width[..., None] * t, window)
    return jnp.sum(w * amp * amp, axis=-1)


def _doppler_point(offset, window, where, name):
    (d,) = as_float(offset)
    ok, (d,) = _admitted(where, [(name, d, -0.5, 0.5)], (0.0,))
    return guard(-2.0 * DB_PER_NEPER * jnp.log(_window_amplitude(d, window)), ok)


def _doppler_average(spacing, window, where, name):
    (s,) = as_float(spacing)
    ok, (s,) = _admitted(where, [(name, s, 0.0, 1.0)], (1.0,))
    return guard(-DB_PER_NEPER * jnp.log(_mean_power_gain(0.5 * s, window)), ok)


def doppler_straddle_loss_db(bin_offset, window: str = "rect"):
    """Doppler (FFT bin) straddle loss (dB) of a signal ``bin_offset`` bins off a bin centre.

    ``L = -20 log10 W(delta)``, ``W(delta) = sinc(pi delta) (1 + (a1/a0) delta^2/(1 -
    delta^2))`` for the window ``a0 - a1 cos(2 pi t/T)`` (continuous-time, many-sample limit;
    relative to the same window on the bin centre, so its processing loss is excluded).

    Args:
        bin_offset: ``delta`` in FFT bins (1/T, T the coherent interval), ``|delta| <= 1/2``.
        window: ``"rect"``, ``"hann"`` or ``"hamming"``; static.

    Returns:
        Loss in dB (>= 0), error < 3e-15 dB. Worst case at half a bin: rect 3.922 dB, Hann
        1.424 dB, Hamming 1.751 dB.

    Source: Richards (2014) (3.92 dB, rectangular window); Harris (1978) Table 1 (scallop loss
    3.92 dB rectangle, 1.42 dB Hann). Half a bin, rectangular window, ``(2/pi)^2``:

    >>> import math
    >>> float(doppler_straddle_loss_db(0.5)), -20 * math.log10(2 / math.pi)
    (3.9224, 3.9224)
    >>> round(float(doppler_straddle_loss_db(0.5, "hann")), 2)
    1.42
    """
    check_choice("window", window, tuple(WINDOWS), where="doppler_straddle_loss_db")
    return _doppler_point(bin_offset, window, "doppler_straddle_loss_db", "bin_offset")


def doppler_straddle_loss_average_db(bin_spacing=1.0, window: str = "rect"):
    """Doppler straddle loss (dB) of the mean SNR over a uniform offset between FFT bins.

    ``L = -10 log10[(2/Delta) int_0^{Delta/2} W(delta)^2 d delta]`` with ``W`` of
    :func:`doppler_straddle_loss_db`; 24-node Gauss-Legendre rule (the integrand is entire;
    measured error < 1e-15 dB against mpmath).

    Args:
        bin_spacing: ``Delta`` in resolution cells 1/T, ``0 <= Delta <= 1`` (1 = plain FFT,
            1/k = zero-padded k times).
        window: ``"rect"``, ``"hann"`` or ``"hamming"``; static.

    Returns:
        Loss in dB (>= 0): 1.114 dB (rect), 0.451 dB (Hann), 0.549 dB (Hamming) at
        ``Delta = 1``. The worst case is ``doppler_straddle_loss_db(Delta / 2)``.

    Source: Richards (2014); Barton (2013). The rectangular window has the closed form
    ``(Si(pi Delta) - sin^2(pi Delta/2)/(pi Delta/2)) / (pi Delta/2)`` (scipy's ``sici``):

    >>> import math
    >>> from scipy.special import sici
    >>> ref = -10 * math.log10((sici(math.pi)[0] - 1 / (math.pi / 2)) / (math.pi / 2))
    >>> float(doppler_straddle_loss_average_db(1.0)), ref
    (1.114302, 1.114302)
    """
    check_choice("window", window, tuple(WINDOWS), where="doppler_straddle_loss_average_db")
    return _doppler_average(bin_spacing, window, "doppler_straddle_loss_average_db", "bin_spacing")


def range_straddle_loss_db(offset_fraction, pulse_shape: str = "rect"):
    """Range straddle loss (dB) of a sample ``offset_fraction`` off the matched-filter peak.

    ``"rect"``: rectangular pulse, triangular matched-filter output, ``L = -20 log10(1 -
    |delta|)`` with ``delta`` in pulse lengths, ``|delta| < 1``. ``"sinc"``: ideal band-limited
    (compressed) pulse, ``L = -20 log10 sinc(pi delta)`` with ``delta`` in resolution cells
    ``1/B``, ``|delta| <= 1/2``.

    Args:
        offset_fraction: ``delta`` (see above).
        pulse_shape: ``"rect"`` or ``"sinc"``; static.

    Returns:
        Loss in dB (>= 0), exact to rounding (relative error < 1e-15). At ``delta = 0`` (the corner of
        the triangle) the derivative is the one-sided one for ``delta -> 0+``,
        ``20/ln 10 = 8.69`` dB per pulse length.

    Source: Richards (2014); Barton (2013). Half a pulse length off the peak: amplitude 1/2:

    >>> float(range_straddle_loss_db(0.5)), float(range_straddle_loss_db(-0.5))
    (6.0206, 6.0206)
    """
    where = "range_straddle_loss_db"
    check_choice("pulse_shape", pulse_shape, PULSE_SHAPES, where=where)
    if pulse_shape == "sinc":
        return _doppler_point(offset_fraction, "rect", where, "offset_fraction")
    (d,) = as_float(offset_fraction)
    ok, (d,) = _admitted(where, [("offset_fraction", d, -1.0, 1.0, True, True)], (0.0,))
    return guard(-2.0 * DB_PER_NEPER * _log1p(-jnp.abs(d)), ok)


def range_straddle_loss_average_db(sample_spacing, pulse_shape: str = "rect"):
    """Range straddle loss (dB) of the mean SNR over a uniform target offset between samples.

    ``"rect"`` (triangle; ``a = Delta/2``, ``Delta`` the sample spacing in pulse lengths)::

        E[rho] = 1 - a + a^2/3  (a <= 1),     1/(3a)  (a > 1),     L = -10 log10 E[rho]

    (continuous with its derivative at ``a = 1``). ``"sinc"``: as
    :func:`doppler_straddle_loss_average_db` with the rectangular window, ``Delta`` in
    resolution cells ``1/B``, ``0 <= Delta <= 1``. The worst case is
    ``range_straddle_loss_db(Delta / 2)``.

    Args:
        sample_spacing: ``Delta >= 0`` (``"rect"``), ``0 <= Delta <= 1`` (``"sinc"``).
        pulse_shape: ``"rect"`` or ``"sinc"``; static.

    Returns:
        Loss in dB (>= 0); one sample per pulse length (``Delta = 1``) loses 2.341 dB on
        average (worst case 6.02 dB), two per pulse length 1.130 dB.

    Source: Richards (2014); Barton (2013). Against a scipy quadrature of ``(1 - x)^2`` over
    the offsets ``[0, 1/2]``:

    >>> import math
    >>> from scipy.integrate import quad
    >>> ref = -10 * math.log10(quad(lambda x: (1 - x) ** 2, 0, 0.5)[0] / 0.5)
    >>> float(range_straddle_loss_average_db(1.0)), ref
    (2.340832, 2.340832)
    """
    where = "range_straddle_loss_average_db"
    check_choice("pulse_shape", pulse_shape, PULSE_SHAPES, where=where)
    if pulse_shape == "sinc":
        return _doppler_average(sample_spacing, "rect", where, "sample_spacing")
    (s,) = as_float(sample_spacing)
    ok, (s,) = _admitted(where, [("sample_spacing", s, 0.0, None)], (1.0,))
    a = 0.5 * s
    inside = a <= 1.0
    a_in = jnp.where(inside, a, 0.0)
    a_out = jnp.where(inside, 2.0, a)
    log_mean = jnp.where(inside, _log1p(a_in * (a_in / 3.0 - 1.0)), -jnp.log(3.0 * a_out))
    return guard(-DB_PER_NEPER * log_mean, ok)


# --------------------------------------------------------------------------------------
# Eclipsing
# --------------------------------------------------------------------------------------


def _surviving_fraction(range_m, pulse_width_s, prf_hz):
    """Fraction f of the echo energy outside the transmit (blanking) intervals."""
    duty = pulse_width_s * prf_hz
    p = jnp.mod(2.0 * range_m * prf_hz / SPEED_OF_LIGHT_M_S, 1.0)
    head = jnp.maximum(0.0, 1.0 - p / duty)  # eclipsed by the pulse just transmitted
    tail = jnp.maximum(0.0, 1.0 - (1.0 - p) / duty)  # eclipsed by the next pulse
    return 1.0 - head - tail


def eclipsing_loss_db(range_m, pulse_width_s, prf_hz, max_loss_db=60.0):
    """Eclipsing loss (dB) of an echo from ``range_m`` partly received during transmission.

    ``L = -10 log10 max(f, 10^(-max_loss_db/10))`` with the surviving energy fraction
    ``f = 1 - max(0, 1 - p/d) - max(0, 1 - (1 - p)/d)``, ``p`` the fractional part of
    ``2 R PRF / c`` (range modulo the unambiguous range ``c/(2 PRF)``) and ``d = tau PRF``
    (matched filter for the surviving part, or a blanked receiver; module docstring). A fully
    eclipsed echo (``f = 0``) returns ``max_loss_db`` with derivative 0, never inf or NaN.

    Args:
        range_m: target range R (m) >= 0.
        pulse_width_s: transmitted pulse length tau (s) > 0.
        prf_hz: pulse repetition frequency (Hz) > 0, with duty cycle ``tau PRF < 1``.
        max_loss_db: clip level (dB) > 0 for (nearly) fully eclipsed echoes.

    Returns:
        Loss in dB in ``[0, max_loss_db]``; periodic in R with period ``c/(2 PRF)``; 0 outside
        the eclipsed zones ``p < d`` and ``p > 1 - d``. Exact to rounding; the relative error of
        ``f`` is that of ``p`` (about ``2 R PRF/c`` ulp).

    Source: Barton (2013), eclipsing in the loss budget. Pulse 10 us, PRF 1 kHz (unambiguous
    range 149.9 km): an echo from 1.2 km arrives 8 us after the pulse began, so 8 of its 10 us
    survive:

    >>> import math
    >>> float(eclipsing_loss_db(1199.169832, 10e-6, 1e3)), -10 * math.log10(0.8)
    (0.9691, 0.9691)
    >>> float(eclipsing_loss_db(0.0, 10e-6, 1e3))    # fully eclipsed: clipped
    60.0
    """
    where = "eclipsing_loss_db"
    r, tau, prf, cap = jnp.broadcast_arrays(*as_float(range_m, pulse_width_s, prf_hz, max_loss_db))
    constraints = [("range_m", r, 0.0, None), ("pulse_width_s", tau, 0.0, None, True, False),
                   ("prf_hz", prf, 0.0, None, True, False), ("max_loss_db", cap, 0.0, None, True, False),
                   ("duty cycle pulse_width_s * prf_hz", tau * prf, 0.0, 1.0, True, True)]
    ok, (r, tau, prf, cap) = _admitted(where, constraints, (0.0, 1e-6, 1e3, 60.0))
    floor = jnp.exp(-cap / DB_PER_NEPER)
    f = _surviving_fraction(r, tau, prf)
    return guard(-DB_PER_NEPER * jnp.log(jnp.maximum(f, floor)), ok)


def eclipsing_loss_average_db(duty_cycle):
    """Eclipsing loss (dB) of the mean SNR over a range uniform in the unambiguous interval.

    ``E[f] = 1 - d`` exactly for every duty cycle ``d = tau PRF < 1`` (the mean blanked
    fraction: the two ramps of :func:`eclipsing_loss_db` each average ``d/2``), so
    ``L = -10 log10(1 - d)``.

    Args:
        duty_cycle: ``d`` (dimensionless), ``0 <= d < 1``.

    Returns:
        Loss in dB (>= 0), exact to rounding.

    Source: Barton (2013), eclipsing in the loss budget. Against a scipy quadrature of the
    surviving fraction over the apparent delay, duty cycle 5 %:

    >>> import math
    >>> from scipy.integrate import quad
    >>> d = 0.05
    >>> mean = quad(lambda p: 1 - max(0, 1 - p / d) - max(0, 1 - (1 - p) / d), 0, 1, points=[d, 1 - d])[0]
    >>> float(eclipsing_loss_average_db(d)), -10 * math.log10(mean)
    (0.222764, 0.222764)
    """
    (d,) = as_float(duty_cycle)
    ok, (d,) = _admitted("eclipsing_loss_average_db", [("duty_cycle", d, 0.0, 1.0, False, True)], (0.0,))
    return guard(-DB_PER_NEPER * _log1p(-d), ok)
