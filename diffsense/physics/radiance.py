"""Blackbody radiation: Planck's law per wavelength, integrated over a band (in energy and in
photon units), and as the brightness temperature of a radiometer.

Pure ``jnp`` formulas, jit/vmap/grad-able. SI units: wavelengths in m, temperatures in K,
radiances per steradian (Lambertian exitance = π × radiance). Every form goes through the mean
occupation number ``1/(e^x − 1)`` of :func:`bose_einstein_occupation`, written so that its value
and gradient stay finite where the exponential under- or overflows.

Sources: Planck's law and its band integrals (Dereniak & Boreman, *Infrared Detectors and
Systems*, 1996, §2); the photon-band series of Widger & Woodall (1976), "Integration of the
Planck blackbody radiation function", Bull. Am. Meteorol. Soc. 57, 1217; brightness temperature
(Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I, 1981, §4-1). Book (Brooker,
*Introduction to Sensors for Ranging and Imaging*) §9.1.3 uses the blackbody background of
photodetectors.

Stefan–Boltzmann: a band wide enough to hold all of the spectrum gives σT⁴ (CODATA σ):

>>> from diffsense.physics.radiance import band_exitance_w_m2
>>> sigma = 5.670374419e-8  # W m⁻² K⁻⁴, CODATA 2018
>>> round(float(band_exitance_w_m2(1e-8, 1.0, 300.0)) / (sigma * 300.0**4), 9)
1.0
"""

from __future__ import annotations

import math
from fractions import Fraction

import jax.numpy as jnp
import numpy as np

from diffsense.numerics.checks import check_range, is_concrete
from diffsense.physics.constants import BOLTZMANN_J_K, PLANCK_J_S, SPEED_OF_LIGHT_M_S

__all__ = [
    "bose_einstein_occupation",
    "planck_spectral_radiance",
    "planck_spectral_exitance",
    "band_radiance_w_m2_sr",
    "band_exitance_w_m2",
    "band_fraction",
    "band_radiance_temperature_derivative",
    "band_photon_radiance",
    "band_photon_radiance_temperature_derivative",
    "planck_brightness_temperature_k",
]

_K = BOLTZMANN_J_K
_H = PLANCK_J_S
_C = SPEED_OF_LIGHT_M_S
_C1L = 2.0 * _H * _C**2  # 2hc² (W m² sr⁻¹)
_C2 = _H * _C / _K  # second radiation constant hc/k (m K)
_HF_OVER_K = _H / _K  # h/k (K per Hz)
_WAVELENGTH_DOMAIN = (1e-9, 10.0)

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(16)


def bose_einstein_occupation(x):
    """Mean occupation number of a photon mode ``1/(e^x − 1)``, x = hν/kT (dimensionless).

    Written ``e^−x / (1 − e^−x)``: finite value and gradient for every x > 0 (no overflow of
    e^x at large x, no cancellation at small x thanks to expm1).

    Args:
        x: hν/(kT), in (0, ∞).

    >>> import math
    >>> round(float(bose_einstein_occupation(math.log(2.0))), 12)  # 1/(2 − 1)
    1.0
    """
    e = jnp.exp(-x)
    return e / (-jnp.expm1(-x))


def _check_band(lo, hi, where):
    check_range("wavelength_lo_m", lo, *_WAVELENGTH_DOMAIN, where=where)
    check_range("wavelength_hi_m", hi, *_WAVELENGTH_DOMAIN, where=where)
    if is_concrete(lo) and is_concrete(hi):
        gap = np.asarray(hi, dtype=float) - np.asarray(lo, dtype=float)
        check_range("wavelength_hi_m - wavelength_lo_m", gap, 0.0, None, where=where)


# ---------------------------------------------------------------------------------------------
# Spectral radiance
# ---------------------------------------------------------------------------------------------


def planck_spectral_radiance(wavelength_m, temperature_k):
    """Planck spectral radiance ``L_λ = 2hc²/λ⁵ / (exp(hc/λkT) − 1)`` (W·m⁻²·sr⁻¹·m⁻¹).

    Args:
        wavelength_m: wavelength λ (m), in [1e-9, 10].
        temperature_k: temperature T (K), in (0, 1e5].

    Exact (evaluated with expm1, finite gradient even where the exponential under/overflows).
    Its peak lies at Wien's λ_max = b/T, b = 2.897771955e-3 m·K (CODATA 2018):

    >>> import jax
    >>> slope = jax.grad(planck_spectral_radiance)
    >>> b = 2.897771955e-3
    >>> float(slope(0.999 * b / 5000.0, 5000.0)) > 0.0 > float(slope(1.001 * b / 5000.0, 5000.0))
    True
    """
    w = "planck_spectral_radiance"
    check_range("wavelength_m", wavelength_m, *_WAVELENGTH_DOMAIN, where=w)
    check_range("temperature_k", temperature_k, 0.0, 1e5, lo_open=True, where=w)
    x = _C2 / (wavelength_m * temperature_k)
    return _C1L / wavelength_m**5 * bose_einstein_occupation(x)


def planck_spectral_exitance(wavelength_m, temperature_k):
    """Planck spectral exitance ``M_λ = π L_λ`` (W·m⁻²·m⁻¹) of a Lambertian blackbody."""
    return np.pi * planck_spectral_radiance(wavelength_m, temperature_k)


# ---------------------------------------------------------------------------------------------
# Band integrals in energy units (Gauss–Legendre in ln x)
# ---------------------------------------------------------------------------------------------


def _band_quadrature(wavelength_lo_m, wavelength_hi_m, temperature_k, integrand, n_panels):
    """Composite Gauss–Legendre in u = ln x, x = hc/(λkT), over [x(λ_hi), x(λ_lo)]."""
    w = "band integral"
    _check_band(wavelength_lo_m, wavelength_hi_m, w)
    check_range("temperature_k", temperature_k, 0.0, 1e5, lo_open=True, where=w)
    u_a = jnp.log(_C2 / (wavelength_hi_m * temperature_k))
    u_b = jnp.log(_C2 / (wavelength_lo_m * temperature_k))
    u_a, u_b = jnp.broadcast_arrays(u_a, u_b)
    width = (u_b - u_a) / n_panels
    panel = jnp.arange(n_panels, dtype=u_a.dtype)
    t = (panel[:, None] + (jnp.asarray(_GL_NODES)[None, :] + 1.0) / 2.0).reshape(-1)
    weights = jnp.tile(jnp.asarray(_GL_WEIGHTS), n_panels)
    u = u_a[..., None] + width[..., None] * t
    return jnp.sum(weights * integrand(jnp.exp(u)), axis=-1) * width / 2.0


def _energy_integrand(x):
    return x**4 * bose_einstein_occupation(x)


def band_radiance_w_m2_sr(wavelength_lo_m, wavelength_hi_m, temperature_k, *, n_panels=8):
    """Blackbody radiance between two wavelengths ``∫ L_λ dλ`` (W·m⁻²·sr⁻¹).

    With x = hc/(λkT) the integral is ``2 k⁴T⁴/(h³c²) ∫ x⁴/(e^x − 1) d(ln x)`` over
    [x(λ_hi), x(λ_lo)], evaluated by composite Gauss–Legendre quadrature: ``n_panels`` equal
    panels in ln x (static, default 8) of 16 nodes each.

    Error bound: the integrand is analytic in ln x within the strip |Im| < π/2 (its poles are at
    x = 2πik), so on a panel of half-width h the 16-node rule converges like ρ^-32 with
    ρ = (π/2 + sqrt(π²/4 + h²))/h (Trefethen, *Approximation Theory and Approximation
    Practice*, Thm 19.3). For λ_hi/λ_lo ≤ 1e8 and 8 panels (h ≤ 1.15, ρ ≥ 3.0) the bound is
    below 1e-14 relative; the tests measure the error against mpmath quadrature (< 1e-12
    relative for bands from 0.2 µm–1 mm at 200–6000 K and for 1e-8–1 m at 300 K).

    Args:
        wavelength_lo_m: lower wavelength (m), in [1e-9, 10].
        wavelength_hi_m: upper wavelength (m), in [1e-9, 10], ≥ wavelength_lo_m.
        temperature_k: temperature (K), in (0, 1e5].
        n_panels: static number of Gauss–Legendre panels.

    The whole spectrum holds σT⁴/π (σ = 2π⁵k⁴/(15h³c²)):

    >>> import math
    >>> k, h, c = 1.380649e-23, 6.62607015e-34, 299792458.0
    >>> sigma = 2 * math.pi**5 * k**4 / (15 * h**3 * c**2)
    >>> round(float(band_radiance_w_m2_sr(1e-8, 1.0, 300.0)) * math.pi / (sigma * 300.0**4), 9)
    1.0
    """
    scale = _RADIANCE_SCALE * temperature_k**4
    integral = _band_quadrature(wavelength_lo_m, wavelength_hi_m, temperature_k, _energy_integrand, n_panels)
    return scale * integral


def band_exitance_w_m2(wavelength_lo_m, wavelength_hi_m, temperature_k, *, n_panels=8):
    """Blackbody exitance between two wavelengths ``π ∫ L_λ dλ`` (W·m⁻²). See
    :func:`band_radiance_w_m2_sr` for the method and error bound."""
    return np.pi * band_radiance_w_m2_sr(wavelength_lo_m, wavelength_hi_m, temperature_k, n_panels=n_panels)


def band_fraction(wavelength_lo_m, wavelength_hi_m, temperature_k, *, n_panels=8):
    """Fraction of the total blackbody exitance σT⁴ emitted between two wavelengths.

    ``(15/π⁴) ∫ x³/(e^x − 1) dx``, same quadrature as :func:`band_radiance_w_m2_sr`.

    The two halves of the spectrum split at any wavelength add to the whole:

    >>> lo, mid, hi = 1e-8, 10e-6, 1.0
    >>> round(float(band_fraction(lo, mid, 300.0) + band_fraction(mid, hi, 300.0)), 9)
    1.0
    """
    integral = _band_quadrature(wavelength_lo_m, wavelength_hi_m, temperature_k, _energy_integrand, n_panels)
    return 15.0 / np.pi**4 * integral


def band_radiance_temperature_derivative(wavelength_lo_m, wavelength_hi_m, temperature_k, *, n_panels=8):
    """Temperature derivative of the band radiance ``∫ ∂L_λ/∂T dλ`` (W·m⁻²·sr⁻¹·K⁻¹).

    ``∂L_λ/∂T = L_λ · x e^x / ((e^x − 1) T)``, so the band integral is
    ``2 k⁴T³/(h³c²) ∫ x⁵ e^x/(e^x − 1)² d(ln x)``, same quadrature (and the same strip of
    analyticity, so the same error bound) as :func:`band_radiance_w_m2_sr`. Multiply by π for
    the exitance derivative dM/dT.
    """
    scale = _RADIANCE_SCALE * temperature_k**3

    def integrand(x):
        b = bose_einstein_occupation(x)
        return x**5 * b * (1.0 + b)  # e^x/(e^x-1)^2 = b(1+b)

    return scale * _band_quadrature(wavelength_lo_m, wavelength_hi_m, temperature_k, integrand, n_panels)


# ---------------------------------------------------------------------------------------------
# Band integrals in photon units (Widger–Woodall series)
# ---------------------------------------------------------------------------------------------
#
# L_q = (2k³T³/(h³c²)) ∫ x²/(e^x − 1) dx over [x(λ_hi), x(λ_lo)] with the two convergent series
# of Widger & Woodall (1976): the tail ∫_x^∞ = Σ_n e^{−nx}(x²/n + 2x/n² + 2/n³) for x ≥ 2
# (24 terms, truncation < e^{−50}) and 2ζ(3) − ∫_0^x with the Bernoulli series
# ∫_0^x t²/(e^t − 1) dt = Σ_k B_k x^{k+2}/((k+2)k!) for x < 2 (terms to B_40, truncation
# < (1/π)^40). Relative error < 1e-14 against mpmath (tests/sensors/infrared/test_infrared.py).

_RADIANCE_SCALE = 2.0 * _K**4 / (_H**3 * _C**2)  # 2k⁴/(h³c²), a Python float: k⁴ and h³ underflow in float32
_PHOTON_SCALE = 2.0 * _K**3 / (_H**3 * _C**2)  # L_q = scale · T³ · ∫ x²/(e^x − 1) dx
_ZETA3 = 1.2020569031595942853997


def _bernoulli_even(m_max):
    """B_0 .. B_{2 m_max} as exact fractions (recurrence Σ_{k<n+1} C(n+1,k) B_k = 0)."""
    b = [Fraction(1)]
    for n in range(1, 2 * m_max + 1):
        acc = Fraction(0)
        for k in range(n):
            acc += math.comb(n + 1, k) * b[k]
        b.append(-acc / (n + 1))
    return b


_M_SERIES = 20
_B = _bernoulli_even(_M_SERIES)
# ∫_0^x t²/(e^t−1) dt = x²/2 − x³/6 + Σ_{m≥1} c_m x^{2m+2},  c_m = B_2m / ((2m+2)(2m)!)
_SMALL_COEFFS = np.array(
    [float(_B[2 * m] / ((2 * m + 2) * math.factorial(2 * m))) for m in range(1, _M_SERIES + 1)]
)
_SMALL_POWERS = np.array([2 * m + 2 for m in range(1, _M_SERIES + 1)], dtype=float)
_N_TAIL = np.arange(1, 25, dtype=float)
_X_SPLIT = 2.0


def _photon_tail(x):
    """``∫_x^∞ t²/(e^t − 1) dt`` for x > 0 (Widger & Woodall 1976 series; double-where safe)."""
    x = jnp.asarray(x, dtype=float)
    large = x >= _X_SPLIT
    xl = jnp.where(large, x, _X_SPLIT)[..., None]
    n = jnp.asarray(_N_TAIL)
    tail = jnp.sum(jnp.exp(-n * xl) * (xl * xl / n + 2.0 * xl / n**2 + 2.0 / n**3), axis=-1)
    xs = jnp.where(large, 1.0, x)
    head = xs * xs / 2.0 - xs**3 / 6.0 + jnp.sum(
        jnp.asarray(_SMALL_COEFFS) * xs[..., None] ** jnp.asarray(_SMALL_POWERS), axis=-1
    )
    return jnp.where(large, tail, 2.0 * _ZETA3 - head)


def _band_x(lo, hi, t):
    t = jnp.asarray(t, dtype=float)
    x_hi = _C2 / (jnp.asarray(hi, dtype=float) * t)  # small x: long wavelength
    x_lo = _C2 / (jnp.asarray(lo, dtype=float) * t)
    return t, x_hi, x_lo


def band_photon_radiance(wavelength_lo_m, wavelength_hi_m, temperature_k):
    """Blackbody photon radiance between two wavelengths ``∫ L_λ λ/(hc) dλ`` (photons·s⁻¹·m⁻²·sr⁻¹).

    ``(2k³T³/(h³c²)) ∫ x²/(e^x − 1) dx`` over x = hc/(λkT) ∈ [x(λ_hi), x(λ_lo)], by the
    Widger–Woodall series (see the comment above); relative error < 1e-14 (absolute error of the
    band ≲ 1e-15 of the larger cumulative integral when the band is very narrow).

    Args:
        wavelength_lo_m: lower wavelength (m), in [1e-9, 10].
        wavelength_hi_m: upper wavelength (m), in [1e-9, 10], ≥ wavelength_lo_m.
        temperature_k: temperature (K), in (0, 1e5].

    Example: 300 K, 0–10 µm: 1.56e21 photons s⁻¹ m⁻² sr⁻¹ (× π = 4.90e17 photons s⁻¹ cm⁻²).
    Source: Planck's law in photon units (Dereniak & Boreman 1996, §2.6); series of Widger &
    Woodall (1976). The whole spectrum holds 4ζ(3)k³T³/(h³c²) (photon Stefan–Boltzmann law):

    >>> k, h, c, zeta3 = 1.380649e-23, 6.62607015e-34, 299792458.0, 1.2020569031595943
    >>> total = 4 * zeta3 * k**3 * 300.0**3 / (h**3 * c**2)
    >>> round(float(band_photon_radiance(1e-9, 10.0, 300.0)) / total, 9)
    1.0
    """
    w = "band_photon_radiance"
    _check_band(wavelength_lo_m, wavelength_hi_m, w)
    check_range("temperature_k", temperature_k, 0.0, 1e5, lo_open=True, where=w)
    t, x_hi, x_lo = _band_x(wavelength_lo_m, wavelength_hi_m, temperature_k)
    return _PHOTON_SCALE * t**3 * (_photon_tail(x_hi) - _photon_tail(x_lo))


def band_photon_radiance_temperature_derivative(wavelength_lo_m, wavelength_hi_m, temperature_k):
    """``∂L_q/∂T`` of the band photon radiance (photons·s⁻¹·m⁻²·sr⁻¹·K⁻¹), in closed form.

    Differentiating L_q = a T³ [G(x_hi) − G(x_lo)] (G(x) = ∫_x^∞ t²/(e^t−1) dt, x ∝ 1/T):
    ``∂L_q/∂T = a T² [3 (G(x_hi) − G(x_lo)) + x_hi³/(e^{x_hi} − 1) − x_lo³/(e^{x_lo} − 1)]``.
    Same arguments, domain and accuracy as :func:`band_photon_radiance`. The thermal contrast
    of a band is (∂L_q/∂T)/L_q (e.g. 300 K: 3.59 %/K in 3–5 µm, 1.61 %/K in 8–12 µm).

    Over the whole spectrum L_q ∝ T³, so the contrast is 3/T:

    >>> round(float(band_photon_radiance_temperature_derivative(1e-9, 10.0, 300.0)
    ...             / band_photon_radiance(1e-9, 10.0, 300.0)) * 300.0, 9)
    3.0
    """
    w = "band_photon_radiance_temperature_derivative"
    _check_band(wavelength_lo_m, wavelength_hi_m, w)
    check_range("temperature_k", temperature_k, 0.0, 1e5, lo_open=True, where=w)
    t, x_hi, x_lo = _band_x(wavelength_lo_m, wavelength_hi_m, temperature_k)
    band = _photon_tail(x_hi) - _photon_tail(x_lo)
    edges = x_hi**3 * bose_einstein_occupation(x_hi) - x_lo**3 * bose_einstein_occupation(x_lo)
    return _PHOTON_SCALE * t**2 * (3.0 * band + edges)


# ---------------------------------------------------------------------------------------------
# Brightness temperature (radio and millimetre waves)
# ---------------------------------------------------------------------------------------------


def planck_brightness_temperature_k(physical_temperature_k, freq_hz):
    """Rayleigh–Jeans-equivalent brightness of a black body ``B = (hf/k)/(exp(hf/kT) − 1)`` (K).

    The temperature a Rayleigh–Jeans radiometer assigns to a black body at T: ``B → T − hf/2k``
    for hf ≪ kT (94 GHz: hf/k = 4.51 K, so 290 K → 287.7 K; the cosmic background 2.725 K →
    1.07 K). Evaluated as (hf/k)·e^−x/(1 − e^−x), x = hf/kT: exact, finite value and gradient
    for all T > 0.

    Args:
        physical_temperature_k: T (K), in (0, 1e4].
        freq_hz: frequency f (Hz), in (0, 1e13].

    Source: Ulaby, Moore & Fung (1981) Vol. I §4-1 (Planck's law in brightness temperature);
    Skou & Le Vine, *Microwave Radiometer Systems* (2006) §2.1. The high-temperature series
    ``T − hf/2k + (hf/k)²/(12 T)`` agrees to 1e-6 K at 290 K and 94 GHz:

    >>> t0 = 6.62607015e-34 / 1.380649e-23 * 94e9  # hf/k (K)
    >>> abs(float(planck_brightness_temperature_k(290.0, 94e9)) - (290.0 - t0 / 2 + t0**2 / (12 * 290.0))) < 1e-5
    True
    """
    w = "planck_brightness_temperature_k"
    check_range("physical_temperature_k", physical_temperature_k, 0.0, 1e4, lo_open=True, where=w)
    check_range("freq_hz", freq_hz, 0.0, 1e13, lo_open=True, where=w)
    t0 = _HF_OVER_K * jnp.asarray(freq_hz, dtype=float)
    return t0 * bose_einstein_occupation(t0 / jnp.asarray(physical_temperature_k, dtype=float))
