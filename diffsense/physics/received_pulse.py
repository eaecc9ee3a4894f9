"""The echo of a rectangular pulse as the receiver passes it: envelope after the IF filter and its
width, from which the range resolution, the range gate and the clutter-cell length follow.

A rectangular pulse of length τ (s) through a band-pass IF filter of 3 dB bandwidth β (Hz) leaves
the filter as the envelope y(t) (amplitude, normalized to the unfiltered pulse); its low-pass
equivalent filter is cut off at β/2. With x = β τ:

* ideal matched filter (``"matched"``): the triangle of base 2τ; its half-amplitude width is τ.
* brick-wall filter (``"rectangular"``), t from the pulse centre::

      y(t) = [Si(π β (t + τ/2)) − Si(π β (t − τ/2))] / π,       peak y(0) = (2/π) Si(π x / 2)

  (the centre stays the maximum for x ≤ 2.86, the domain of this filter; ``Si`` the sine integral).
* Gaussian filter ``|H|² = 2^(−(2f/β)²)``, t from the pulse centre::

      y(t) = [erf(a (t + τ/2)) − erf(a (t − τ/2))] / 2,   a = π β / sqrt(2 ln 2)

* n cascaded identical single-tuned circuits ``H = (1 + j f/f0)^−n``,
  ``f0 = (β/2) / sqrt(2^(1/n) − 1)`` (the cascade's 3 dB band is β): the step response of n
  identical single-pole filters is ``1 − exp(−u) Σ_{k<n} u^k/k! = P(n, u)`` with u = ω0 t,
  ω0 = 2π f0 and P the regularized lower incomplete gamma function, so with t from the pulse's
  leading edge::

      y(t) = P(n, ω0 t) − P(n, ω0 (t − τ))        (the second term 0 for t < τ)

  whose maximum lies at ω0 t* = w / (1 − exp(−w/(n − 1))), w = ω0 τ (t* = τ for n = 1).

The width reported is the **half-amplitude (−6 dB) width** of y: the time between the two
crossings of y = y_max/2, found by a safeguarded Newton iteration on each side of the maximum
(:func:`diffsense.numerics.rootfind.decreasing_root_log`; differentiated implicitly). This
convention makes the ideal matched filter's triangle exactly τ wide and the unfiltered pulse
(β → ∞) τ wide, so the range resolution reduces to the book's c τ / 2 in both limits (book
§8.16.3, eq (11.4)); a narrow filter (β τ ≪ 1) stretches the echo to about its own impulse
response, e.g. 0.501/β for two tuned circuits, so the resolution becomes ≈ c · 0.5/β.

Sources: the filter models and the pulse responses as in Skolnik, *Introduction to Radar
Systems*, 3rd ed. (2001), §5.2 and Table 5.1 (reproduced as Brooker Table 9.1); the step
response of cascaded single-pole (tuned) stages, e.g. Valley & Wallman, *Vacuum Tube
Amplifiers*, MIT Rad. Lab. Series 18 (1948), ch. 2 (rise time of synchronously tuned stages);
Abramowitz & Stegun 6.5.2 and 6.5.13 (P(n, u) = 1 − exp(−u) Σ_{k<n} u^k/k!).
"""

from __future__ import annotations

import math
from functools import partial

import jax
import jax.numpy as jnp
from jax.scipy.special import erf, sici

from diffsense.numerics.checks import check_choice, check_range
from diffsense.numerics.rootfind import decreasing_root_log

__all__ = [
    "RECEIVER_FILTERS",
    "TUNED_STAGES",
    "tuned_circuit_corner_frequency_hz",
    "received_pulse_envelope",
    "received_pulse_width_s",
]

#: Number of cascaded single-tuned circuits of each tuned filter name.
TUNED_STAGES = {"single_tuned": 1, "two_tuned": 2, "three_tuned": 3, "four_tuned": 4, "five_tuned": 5}
#: Receiver filters: the ideal matched filter, the brick-wall and Gaussian filters and the tuned cascades.
RECEIVER_FILTERS = ("matched", "rectangular", "gaussian") + tuple(TUNED_STAGES)

_GAUSS_RATE = math.pi / math.sqrt(2.0 * math.log(2.0))  # a / β
_ROOT_ITERATIONS = 60
_WHERE = "received pulse"


def tuned_circuit_corner_frequency_hz(bandwidth_hz, n_stages: int):
    """Corner frequency f0 (Hz) of each of n identical single-tuned circuits whose cascade has
    the 3 dB bandwidth β: ``|1 + j f/f0|^(−2n) = 1/2`` at f = β/2, i.e.
    ``f0 = (β/2) / sqrt(2^(1/n) − 1)``.

    Args:
        bandwidth_hz: band-pass 3 dB bandwidth β of the cascade (Hz), in (0, ∞).
        n_stages: number of stages n ≥ 1 (static).

    One circuit has f0 = β/2; two have f0 = (β/2)/sqrt(√2 − 1):

    >>> float(tuned_circuit_corner_frequency_hz(2.0, 1)), float(tuned_circuit_corner_frequency_hz(2.0, 2)), 1 / (2**0.5 - 1) ** 0.5
    (1.0, 1.553774, 1.553774)
    """
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=_WHERE)
    if int(n_stages) < 1:
        raise ValueError("n_stages must be >= 1")
    return 0.5 * jnp.asarray(bandwidth_hz, dtype=float) / math.sqrt(2.0 ** (1.0 / int(n_stages)) - 1.0)


def _tuned_envelope(u, w, n: int):
    """y = P(n, u) − P(n, u − w) (u = ω0 t from the leading edge, w = ω0 τ): both terms by one
    call of :func:`_gamma_p` on the stacked arguments (one copy of the series in a program)."""
    u, w = jnp.broadcast_arrays(jnp.asarray(u, dtype=float), jnp.asarray(w, dtype=float))
    both = _gamma_p(n, jnp.stack([u, u - w]))
    return both[0] - both[1]


def _gamma_density(n: int, u):
    """dP(n, u)/du = u^(n−1) e^(−u) / (n − 1)!, the Gamma(n, 1) density (0 for u ≤ 0)."""
    positive = u > 0.0
    v = jnp.where(positive, u, 1.0)
    return jnp.where(positive, jnp.exp(-v) * v ** (n - 1) / math.factorial(n - 1), 0.0)


def _series_terms(n: int) -> int:
    """Terms J of the series of P(n, u) below u = n: the last term's share Π_{j≤J} n/(n + j)
    falls below 1e-17 (J = 22 for n = 1, 31 for n = 5)."""
    share, j = 1.0, 0
    while share >= 1e-17:
        j += 1
        share *= n / (n + j)
    return j


def _series_coefficients(n: int):
    """n!/(n + j)! for j = 0 … J (:func:`_series_terms`), each an exact ratio rounded once."""
    return [math.factorial(n) / math.factorial(n + j) for j in range(_series_terms(n) + 1)]


@partial(jax.custom_jvp, nondiff_argnums=(0,))
def _gamma_p(n: int, u):
    """P(n, u) for u > 0 and 0 for u <= 0, with a finite derivative everywhere, in closed form
    for the integer n of a tuned cascade (A&S 6.5.13 and 6.5.29), without an iterative special
    function: below u = n the power series ``exp(−u) u^n/n! Σ_j u^j n!/(n + j)!`` (positive
    terms and coefficients summed by Horner's rule: no cancellation where P is small;
    :func:`_series_terms` terms), above it ``1 − exp(−u) Σ_{k<n} u^k/k!`` (where P ≥ 1/2 the
    subtraction loses nothing). Relative error below 1e-15 for n ≤ 5."""
    positive = u > 0.0
    v = jnp.where(positive, u, 1.0)
    low = v < n
    s = jnp.where(low, v, 1.0)  # the series branch's argument (double where: finite derivative)
    coefficients = _series_coefficients(n)
    acc = jnp.full_like(s, coefficients[-1])
    for c in reversed(coefficients[:-1]):
        acc = acc * s + c
    series = jnp.exp(-s) * s**n / math.factorial(n) * acc
    upper = jnp.exp(-v) * sum(v**k / math.factorial(k) for k in range(n))
    return jnp.where(positive, jnp.where(low, series, 1.0 - upper), 0.0)


@_gamma_p.defjvp
def _gamma_p_jvp(n, primals, tangents):
    """dP(n, u)/du: the closed form :func:`_gamma_density`, so that a derivative does not go
    through the series."""
    (u,), (du,) = primals, tangents
    return _gamma_p(n, u), _gamma_density(n, u) * du


def _tuned_peak_u(w, n: int):
    if n == 1:
        return w
    return w / (-jnp.expm1(-w / (n - 1)))


def _centred_envelope(s, x, filter: str):
    """Envelope of the symmetric filters at s = β t from the pulse centre, x = β τ."""
    if filter == "rectangular":
        return (sici(jnp.pi * (s + 0.5 * x))[0] - sici(jnp.pi * (s - 0.5 * x))[0]) / jnp.pi
    return 0.5 * (erf(_GAUSS_RATE * (s + 0.5 * x)) - erf(_GAUSS_RATE * (s - 0.5 * x)))


def received_pulse_envelope(time_s, pulse_width_s, bandwidth_hz, filter: str = "two_tuned"):
    """Envelope y(t) of a unit rectangular pulse after the receiver filter (see the module
    docstring); t is measured from the pulse centre for ``"rectangular"``, ``"gaussian"`` and
    ``"matched"`` (the triangle 1 − |t|/τ, normalized to its peak), from the leading edge for
    the tuned cascades.

    Args:
        time_s: time t (s), any real.
        pulse_width_s: pulse length τ (s), in (0, ∞).
        bandwidth_hz: 3 dB band-pass bandwidth β (Hz), in (0, ∞) (unused for ``"matched"``).
        filter: one of :data:`RECEIVER_FILTERS` (static).

    One tuned circuit (n = 1, ω0 = π β) ends the pulse at 1 − exp(−π β τ):

    >>> import math
    >>> float(received_pulse_envelope(1e-6, 1e-6, 1e6, "single_tuned")), 1 - math.exp(-math.pi)
    (0.956786, 0.956786)
    """
    check_choice("filter", filter, RECEIVER_FILTERS, where=_WHERE)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=_WHERE)
    t = jnp.asarray(time_s, dtype=float)
    tau = jnp.asarray(pulse_width_s, dtype=float)
    if filter == "matched":
        return jnp.maximum(1.0 - jnp.abs(t) / tau, 0.0)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=_WHERE)
    beta = jnp.asarray(bandwidth_hz, dtype=float)
    if filter in TUNED_STAGES:
        n = TUNED_STAGES[filter]
        w0 = 2.0 * jnp.pi * tuned_circuit_corner_frequency_hz(beta, n)
        return _tuned_envelope(w0 * t, w0 * tau, n)
    return _centred_envelope(beta * t, beta * tau, filter)


def _crossings(x, filter: str):
    """The half-amplitude crossings of the envelope at x = β τ (no derivative): tuned cascades
    ``(w, u_rise, u_fall)`` in u = ω0 t (w = ω0 τ), the symmetric filters ``(s,)`` in s = β t."""
    if filter in TUNED_STAGES:
        n = TUNED_STAGES[filter]
        w = 2.0 * jnp.pi * x * tuned_circuit_corner_frequency_hz(1.0, n)  # ω0 τ
        u_peak = _tuned_peak_u(w, n)
        # both crossings in one root find (elementwise over [rise, fall]; one loop in the program):
        # the envelope rises to its peak and falls after it; the envelope at the bracket ends
        # (start, peak, tail) and the half-peak level from one evaluation
        falling = jnp.array([-1.0, 1.0])
        start, tail = 1e-9 * u_peak, u_peak + w + 60.0 + 10.0 * n
        at = _tuned_envelope(jnp.stack([start, u_peak, tail]), w, n)
        half = 0.5 * at[1]
        ends = (falling * (at[:2] - half), falling * (at[1:] - half))
        roots = decreasing_root_log(lambda u: falling * (_tuned_envelope(u, w, n) - half), jnp.stack([start, u_peak]),
                                    jnp.stack([u_peak, tail]), iterations=_ROOT_ITERATIONS, differentiable=False,
                                    ends=ends, with_residual=False).root
        return w, roots[0], roots[1]
    half = 0.5 * _centred_envelope(0.0, x, filter)
    s = decreasing_root_log(lambda s: _centred_envelope(s, x, filter) - half, 1e-9 * (1.0 + x), 0.5 * x + 3.0,
                            iterations=_ROOT_ITERATIONS, differentiable=False, with_residual=False).root
    return (s,)


@partial(jax.custom_jvp, nondiff_argnums=(1,))
def _relative_width(x, filter: str):
    """Half-amplitude width over τ as a function of x = β τ (dimensionless); its derivative by
    the implicit function theorem at the crossings (:func:`_relative_width_jvp`), so that a
    derivative never passes through the root finds."""
    c = _crossings(jax.lax.stop_gradient(x), filter)
    if filter in TUNED_STAGES:
        w, rise, fall = c
        return (fall - rise) / w
    return 2.0 * c[0] / x


def _partials(fn, a, b):
    """(∂fn/∂a, ∂fn/∂b) of fn(a, b) at (a, b)."""
    da = jax.jvp(lambda t: fn(t, b), (a,), (jnp.ones_like(a),))[1]
    db = jax.jvp(lambda t: fn(a, t), (b,), (jnp.ones_like(b),))[1]
    return da, db


@_relative_width.defjvp
def _relative_width_jvp(filter, primals, tangents):
    """At a crossing y(u_c, w) = half(w): du_c/dw = (half'(w) − ∂y/∂w) / (∂y/∂u) (the implicit
    function theorem); half'(w) = ½ ∂y/∂w at the peak, where ∂y/∂u = 0. Same with (s, x) for
    the symmetric filters."""
    (x,), (dx,) = primals, tangents
    c = _crossings(x, filter)
    if filter in TUNED_STAGES:
        n = TUNED_STAGES[filter]
        w, rise, fall = c
        # y(u, w) = P(n, u) − P(n, u − w): ∂y/∂u = p(u) − p(u − w), ∂y/∂w = p(u − w) with p the
        # Gamma(n, 1) density; half'(w) = ½ p(u* − w) at the peak u* (∂y/∂u = 0 there) for n ≥ 2,
        # and ½ p(w) for n = 1 (the peak is the corner u* = w): closed forms only
        u_c = jnp.stack([rise, fall])
        peak = jnp.broadcast_to(w if n == 1 else _tuned_peak_u(w, n) - w, u_c.shape)
        p = _gamma_density(n, jnp.stack([u_c, u_c - w, peak]))
        y_u, y_w, dhalf = p[0] - p[1], p[1], 0.5 * p[2]
        slopes = (dhalf - y_w) / y_u
        dw_dx = 2.0 * jnp.pi * tuned_circuit_corner_frequency_hz(1.0, n)
        width = (fall - rise) / w
        return width, ((slopes[1] - slopes[0]) - width) / w * dw_dx * dx
    s = c[0]
    env = lambda ss, xx: _centred_envelope(ss, xx, filter)  # noqa: E731
    dhalf = 0.5 * jax.jvp(lambda xx: env(0.0, xx), (x,), (jnp.ones_like(x),))[1]
    y_s, y_x = _partials(env, s, x)
    ds = (dhalf - y_x) / y_s
    return 2.0 * s / x, (2.0 * ds / x - 2.0 * s / x**2) * dx


def received_pulse_width_s(pulse_width_s, bandwidth_hz, filter: str = "two_tuned"):
    """Half-amplitude (−6 dB) width W (s) of a rectangular pulse after the receiver filter.

    W = τ for the ideal matched filter (``"matched"``, the triangle of base 2τ); for the others
    the width between the two half-amplitude crossings of the envelope of
    :func:`received_pulse_envelope`, a smooth function of β τ (differentiable in τ and β by the
    implicit function theorem), tending to τ as β τ → ∞. See the module docstring for the models.

    Args:
        pulse_width_s: transmitted pulse length τ (s), in (0, ∞).
        bandwidth_hz: IF 3 dB bandwidth β (Hz), in (0, ∞) (unused for ``"matched"``).
        filter: one of :data:`RECEIVER_FILTERS` (static).

    Domain: β τ in [0.01, 50] ([0.01, 2.86] for ``"rectangular"``), as
    :func:`diffsense.detection.matched_filter_loss_db`. Error: the root finds converge to
    float64 round-off (the tests compare with an mpmath root find of the closed forms to 1e-9).

    One tuned circuit in closed form: the envelope rises as 1 − exp(−u) and falls as
    exp(−(u − w)) − exp(−u) (u = π β t, w = π β τ), so W = τ + ln(1 + exp(−π β τ)) / (π β):

    >>> import math
    >>> tau, beta = 1e-6, 0.5e6
    >>> float(received_pulse_width_s(tau, beta, "single_tuned")), tau + math.log(1 + math.exp(-math.pi * beta * tau)) / (math.pi * beta)
    (1.12024e-06, 1.12024e-06)
    >>> float(received_pulse_width_s(2e-8, 1e6, "matched"))
    2e-08
    """
    check_choice("filter", filter, RECEIVER_FILTERS, where=_WHERE)
    check_range("pulse_width_s", pulse_width_s, 0.0, None, lo_open=True, where=_WHERE)
    tau = jnp.asarray(pulse_width_s, dtype=float)
    if filter == "matched":
        return tau * 1.0
    hi = 2.86 if filter == "rectangular" else 50.0
    x = jnp.asarray(bandwidth_hz, dtype=float) * tau
    check_range("bandwidth_hz * pulse_width_s", x, 0.01, hi, where=f"{_WHERE}, filter={filter!r}")
    return tau * _relative_width(x, filter)
