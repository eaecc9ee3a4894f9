"""The echo of a rectangular pulse after the receiver filter and its half-amplitude width.

References used by the assertions: the closed-form envelopes of the module docstring evaluated
in mpmath (30 digits: regularized incomplete gamma for the tuned cascades, erf for the Gaussian
filter, the sine integral for the brick-wall filter), their half-amplitude crossings found by
mpmath's root finder independently of the package's solver; the single-tuned closed form
W = τ + ln(1 + exp(−π β τ))/(π β); central differences for the derivatives.
"""

import math

import jax
import mpmath as mp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.errors import DomainError
from diffsense.physics import received_pulse as rp
from diffsense.physics import waveforms as wf


def mp_width_over_tau(filter, x):
    """Half-amplitude width / τ for β τ = x, from the closed-form envelope (τ = 1)."""
    x = mp.mpf(x)
    if filter in rp.TUNED_STAGES:
        n = rp.TUNED_STAGES[filter]
        w = 2 * mp.pi * (x / 2) / mp.sqrt(mp.mpf(2) ** (mp.mpf(1) / n) - 1)  # ω0 τ
        p = lambda u: mp.gammainc(n, 0, u, regularized=True) if u > 0 else mp.mpf(0)
        y = lambda u: p(u) - p(u - w)
        u_peak = w if n == 1 else w / (1 - mp.exp(-w / (n - 1)))
        half = y(u_peak) / 2
        rise = mp.findroot(lambda u: y(u) - half, (mp.mpf("1e-20"), u_peak), solver="anderson")
        fall = mp.findroot(lambda u: y(u) - half, (u_peak, u_peak + w + 80), solver="anderson")
        return (fall - rise) / w
    if filter == "gaussian":
        a = mp.pi / mp.sqrt(2 * mp.log(2))
        y = lambda s: (mp.erf(a * (s + x / 2)) - mp.erf(a * (s - x / 2))) / 2
    else:
        y = lambda s: (mp.si(mp.pi * (s + x / 2)) - mp.si(mp.pi * (s - x / 2))) / mp.pi
    half = y(0) / 2
    s = mp.findroot(lambda s: y(s) - half, (mp.mpf("1e-20"), x / 2 + 1), solver="anderson")
    return 2 * s / x


CASES = [(f, x) for f in ("single_tuned", "two_tuned", "five_tuned", "gaussian") for x in (0.02, 0.613, 2.0)] + [
    ("three_tuned", 0.3), ("four_tuned", 5.0), ("gaussian", 0.3)] + [("rectangular", x) for x in (0.02, 1.37, 2.5)]


@pytest.mark.parametrize("filter, x", CASES)
def test_width_equals_mpmath_root_find_of_the_closed_form(filter, x):
    tau = 1e-6
    got = float(rp.received_pulse_width_s(tau, x / tau, filter)) / tau
    assert got == pytest.approx(float(mp_width_over_tau(filter, x)), rel=1e-9)


def test_single_tuned_closed_form_and_the_two_limits():
    for x in (0.05, 0.5, 3.0):
        want = 1 + math.log(1 + math.exp(-math.pi * x)) / (math.pi * x)
        assert float(rp.received_pulse_width_s(1.0, x, "single_tuned")) == pytest.approx(want, rel=1e-11)
    # matched filter: the triangle of base 2τ is τ wide at half amplitude; a wide filter passes τ
    assert float(rp.received_pulse_width_s(2e-8, 5e6, "matched")) == 2e-8
    for f in ("two_tuned", "five_tuned", "gaussian"):
        assert float(rp.received_pulse_width_s(1.0, 40.0, f)) == pytest.approx(1.0, abs=1e-9)
    # a narrow filter stretches the echo to its impulse response: two tuned circuits ≈ 0.5012/β
    w = float(rp.received_pulse_width_s(1.0, 0.01, "two_tuned"))
    assert w * 0.01 == pytest.approx(0.5012, abs=2e-3)


def test_envelope_peak_of_two_tuned_circuits_at_the_closed_form_time():
    # h(t) = h(t − τ) for the Gamma(2) impulse response: ω0 t* = w / (1 − e^−w)
    tau, beta = 1e-6, 0.613e6
    w0 = 2 * math.pi * float(rp.tuned_circuit_corner_frequency_hz(beta, 2))
    t_star = tau / (1 - math.exp(-w0 * tau))
    y = lambda t: float(rp.received_pulse_envelope(t, tau, beta, "two_tuned"))
    h = 1e-10
    assert y(t_star) > y(t_star - h) and y(t_star) > y(t_star + h)
    u = w0 * t_star
    want = float(mp.gammainc(2, 0, u, regularized=True) - mp.gammainc(2, 0, u - w0 * tau, regularized=True))
    assert y(t_star) == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("filter", ["single_tuned", "two_tuned", "four_tuned", "gaussian", "rectangular"])
def test_width_gradients_match_central_differences(filter):
    tau = 1e-6
    for x in (0.05, 0.613, 1.3):
        beta = x / tau
        g_beta, g_tau = jax.grad(lambda b, t: rp.received_pulse_width_s(t, b, filter), argnums=(0, 1))(beta, tau)
        hb, ht = beta * 1e-4, tau * 1e-4  # W is exact to ~1e-12 relative: O(h²) truncation dominates
        fd_beta = (rp.received_pulse_width_s(tau, beta + hb, filter) - rp.received_pulse_width_s(tau, beta - hb, filter)) / (2 * hb)
        fd_tau = (rp.received_pulse_width_s(tau + ht, beta, filter) - rp.received_pulse_width_s(tau - ht, beta, filter)) / (2 * ht)
        assert float(g_beta) * beta == pytest.approx(float(fd_beta) * beta, rel=1e-5, abs=1e-8 * tau)
        assert float(g_tau) == pytest.approx(float(fd_tau), rel=1e-5, abs=1e-8)  # dW/dτ is 0 at W's minimum
        assert np.isfinite(float(g_beta)) and np.isfinite(float(g_tau))


def test_range_resolution_follows_the_received_echo():
    c = 299792458.0
    # matched: c τ / 2 exactly; the ore-pass optimum before the change, τ = 10.9 ns with β = 5.96 MHz
    # through two tuned circuits: the echo is ~12.6 m long, not 1.63 m
    assert float(wf.range_resolution_received_m(10.9e-9, 5.96e6, "matched")) == pytest.approx(c * 10.9e-9 / 2, rel=1e-15)
    got = float(wf.range_resolution_received_m(10.9e-9, 5.96e6, "two_tuned"))
    want = c / 2 * 10.9e-9 * float(mp_width_over_tau("two_tuned", 5.96e6 * 10.9e-9))
    assert got == pytest.approx(want, rel=1e-9)
    assert 12.0 < got < 13.5


def test_domain():
    with pytest.raises(DomainError):
        rp.received_pulse_width_s(1e-6, 1e3, "two_tuned")  # βτ = 0.001 < 0.01
    with pytest.raises(DomainError):
        rp.received_pulse_width_s(1e-6, 3e6, "rectangular")  # βτ = 3 > 2.86
    with pytest.raises(DomainError):
        rp.received_pulse_width_s(1e-6, 1e6, "six_tuned")
    with pytest.raises(DomainError):
        rp.received_pulse_width_s(-1e-6, 1e6, "gaussian")
