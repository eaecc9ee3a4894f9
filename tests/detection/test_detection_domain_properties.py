"""The detection API over its whole domain: eager and jitted calls accept the same inputs, no
finite clamp, gradient signs, and the edge cases that were wrong before (issue 16).

References are independent of the package: closed forms (Swerling 1 with one pulse,
Pd = Pfa^(1/(1+S)); Swerling 2, Pd = Q(N, T/(1+S))), mpmath (tests/reference/mp_detection.py,
written from first principles) and central finite differences of the function itself.
Hypothesis sweeps that take minutes are marked slow.
"""

import json
import math
import os
import subprocess
import sys
import textwrap

import jax
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffsense import detection as det
from diffsense.detection import cfar
from diffsense.detection.matched_filter import matched_filter_efficiency
from diffsense.detection.required_snr import N_DERIVATIVE_MIN_EXCESS
from diffsense.errors import DomainError
from helpers.paths import REPO
from tests.reference import mp_detection as ref

mp.mp.dps = 40

# ---------------------------------------------------------------------------------------------
# Eager and jitted calls accept the same inputs
# ---------------------------------------------------------------------------------------------

# Each public function with arguments that probe its domain edges: inside, on the bound, just
# outside, NaN and infinite. Static arguments (Swerling case, filter) are bound here.
_EDGE = [float("nan"), float("inf"), -float("inf"), -1.0, 0.0, 1e-320, 1e-300, 1e-12, 0.3, 0.5, 0.7,
         1.0 - 1e-12, 1.0 - 1e-13, 1.0, 1.5, 40.0, 1e4, 1.00001e4, 1e7]
_FUNCTIONS = {
    "pd": (lambda a, b, c: det.pd(a, b, c, 1), 3),
    "pd_sw0": (lambda a, b, c: det.pd(a, b, c, 0), 3),
    "pd_coherent": (lambda a, b, c: det.pd_coherent(a, b, c, 3), 3),
    "pd_given_threshold": (lambda a, b, c: det.pd_given_threshold(a, b, c, 4), 3),
    "required_snr_db": (lambda a, b, c: det.required_snr_db(a, b, c, 1), 3),
    "required_snr_db_sw2": (lambda a, b, c: det.required_snr_db(a, b, c, 2), 3),
    "fluctuation_loss_db": (lambda a, b, c: det.fluctuation_loss_db(a, b, c, 3), 3),
    "integration_loss_db": (lambda a, b, c: det.integration_loss_db(a, b, c, 0), 3),
    "albersheim_snr_db": (det.albersheim_snr_db, 3),
    "shnidman_snr_db": (lambda a, b, c: det.shnidman_snr_db(a, b, c, 4), 3),
    "threshold": (det.threshold, 2),
    "pfa_from_threshold": (det.pfa_from_threshold, 2),
    "voltage_threshold": (det.voltage_threshold, 2),
    "pfa_from_false_alarm_time": (det.pfa_from_false_alarm_time, 2),
    "false_alarm_time_s": (det.false_alarm_time_s, 2),
    "book_integration_gain_db": (det.book_integration_gain_db, 1),
    "matched_filter_loss_db": (lambda x: det.matched_filter_loss_db(x, "two_tuned"), 1),
    "matched_filter_efficiency": (lambda x: matched_filter_efficiency(x, "rectangular", "rectangular"), 1),
    "cfar_multiplier": (lambda a, b: det.cfar_multiplier(a, b, 2.0), 2),
    "cfar_pfa": (lambda a, b: cfar.cfar_pfa(a, b, 1.0), 2),
    "cfar_pd": (lambda a, b, c: det.cfar_pd(a, b, c, 1.0, 2), 3),
}
_JITTED = {name: jax.jit(fn) for name, (fn, _) in _FUNCTIONS.items()}


def _eager_and_jit(name, args):
    fn, _ = _FUNCTIONS[name]
    try:
        eager = float(fn(*args))
        raised = False
    except DomainError:
        eager, raised = None, True
    jitted = float(_JITTED[name](*args))
    return raised, eager, jitted


def _assert_same_acceptance(name, args):
    raised, eager, jitted = _eager_and_jit(name, args)
    if raised:
        assert math.isnan(jitted), (name, args, jitted)
    else:
        assert not math.isnan(jitted), (name, args, eager)
        assert jitted == pytest.approx(eager, rel=1e-12, abs=1e-300) or (math.isinf(eager) and eager == jitted), \
            (name, args, eager, jitted)


@pytest.mark.parametrize("name", list(_FUNCTIONS))
def test_eager_and_jit_accept_the_same_edge_inputs(name):
    arity = _FUNCTIONS[name][1]
    rng = np.random.default_rng(7)
    typical = {3: (0.9, 1e-6, 10.0), 2: (1e-6, 16.0), 1: (1.0,)}[arity]
    for pos in range(arity):
        for value in rng.choice(_EDGE, size=6, replace=False):
            args = list(typical)
            args[pos] = float(value)
            _assert_same_acceptance(name, tuple(args))


_ANY = st.one_of(st.sampled_from(_EDGE), st.floats(-1e3, 1e5, allow_nan=False), st.floats(allow_nan=True))


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(list(_FUNCTIONS)), a=_ANY, b=_ANY, c=_ANY)
def test_eager_and_jit_accept_the_same_inputs_property(name, a, b, c):
    _assert_same_acceptance(name, (a, b, c)[: _FUNCTIONS[name][1]])


def test_pd_of_any_finite_snr_is_defined_and_reaches_its_limits():
    # Swerling 1, one pulse: Pd = Pfa^(1/(1+S)) (closed form), eager equal to jit
    for snr_db in (-1000.0, -300.0, -120.0, -60.0, 90.0, 120.0, 300.0, 1e6):
        s = mp.mpf(10) ** (mp.mpf(snr_db) / 10)
        want = float(mp.mpf(1e-6) ** (1 / (1 + s)))
        eager = float(det.pd(snr_db, 1e-6, 1, 1))
        assert eager == pytest.approx(want, rel=1e-13, abs=0)
        assert float(_JITTED["pd"](snr_db, 1e-6, 1.0)) == pytest.approx(eager, rel=1e-14)
    # the limits, in every Swerling case and at N = 1e4
    for sw in range(5):
        assert float(det.pd(1e5, 1e-300, 1e4, sw)) == 1.0
        # Pfa to the accuracy of Q(N, T) at the solved threshold (~1e-14 relative at N = 1e4)
        assert float(det.pd(-1e5, 1e-6, 1e4, sw)) == pytest.approx(1e-6, rel=1e-13)


def test_pd_below_pfa_and_other_invalid_targets_are_nan_under_jit():
    rsnr = jax.jit(det.required_snr_db, static_argnums=3)
    for sw in (0, 1, 2):
        assert math.isnan(float(rsnr(0.1, 0.3, 1.0, sw)))
        assert math.isnan(float(rsnr(0.3, 0.3, 1.0, sw)))
        with pytest.raises(DomainError, match="pd must exceed pfa"):
            det.required_snr_db(0.3, 0.3, 1, sw)
    g = jax.jit(jax.grad(det.required_snr_db, argnums=(0, 1, 2)), static_argnums=3)(0.1, 0.3, 1.0, 0)
    assert all(math.isnan(float(v)) for v in g)


# ---------------------------------------------------------------------------------------------
# No finite clamp: required SNR at the extremes against closed forms and mpmath
# ---------------------------------------------------------------------------------------------

_RSNR = {sw: jax.jit(lambda p, f, n, sw=sw: det.required_snr_db(p, f, n, sw)) for sw in range(5)}
_RSNR_GRAD = {sw: jax.jit(jax.grad(lambda p, f, n, sw=sw: det.required_snr_db(p, f, n, sw), argnums=(0, 1, 2)))
              for sw in range(5)}


def _swerling1_one_pulse_db(pd, pfa):
    """S = ln Pfa / ln Pd - 1 for the float values given, in mpmath (Pd = Pfa^(1/(1+S)))."""
    pd, pfa = mp.mpf(pd), mp.mpf(pfa)
    return float(10 * mp.log10((mp.log(pfa) - mp.log(pd)) / mp.log(pd)))


def test_required_snr_beyond_the_old_bracket_matches_the_closed_form():
    # the case of the issue: 130 dB (the old bracket end) was returned for 138.39 dB
    x = float(det.required_snr_db(1 - 1e-11, 1e-300, 1, 1))
    assert x == pytest.approx(_swerling1_one_pulse_db(1 - 1e-11, 1e-300), rel=1e-12)
    # far below the old -90 dB end: Pd barely above Pfa
    for pd, pfa in [(0.5 + 1e-12, 0.5), (1e-6 * (1 + 1e-9), 1e-6), (2e-300, 1e-300)]:
        x = float(det.required_snr_db(pd, pfa, 1, 1))
        assert x == pytest.approx(_swerling1_one_pulse_db(pd, pfa), rel=1e-9)


def test_required_snr_near_pd_one_at_n_1e4_matches_mpmath():
    # Pd within 1e-12 of 1 with N = 1e4: the threshold and Pd must carry 1e-12 absolutely
    want = float(ref.required_snr_mp(1 - 1e-12, 0.5, 10000, 0, dps=40))
    got = float(det.required_snr_db(1 - 1e-12, 0.5, 1e4, 0))
    assert got == pytest.approx(want, rel=1e-9)
    g = _RSNR_GRAD[0](1 - 1e-12, 0.5, 1e4)
    assert all(np.isfinite(float(v)) for v in g)
    assert float(g[0]) > 0 > float(g[1]) and float(g[2]) < 0


def test_gradient_in_n_near_pd_one_has_the_sign_of_finite_differences():
    p, f, n, h = 1 - 1e-10, 1e-6, 1e4 - 2.0, 1.0
    fd = (float(_RSNR[3](p, f, n + h)) - float(_RSNR[3](p, f, n - h))) / (2 * h)
    ad = float(_RSNR_GRAD[3](p, f, n)[2])
    assert fd < 0 and ad < 0
    assert ad == pytest.approx(fd, rel=1e-4)
    want = float(ref.required_snr_mp(p, f, int(n), 3, dps=40))
    assert float(_RSNR[3](p, f, n)) == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize("n", [1.0, 1.5, 10.0, 1000.0, 1e4])
@pytest.mark.parametrize("q", [1e-300, 1e-15, 0.5, 0.9, 1 - 1e-12])
def test_threshold_matches_mpmath_including_targets_near_one(n, q):
    t = float(det.threshold(q, n))
    # backward error: the relative change of T that would make Q(n, T) = q exactly
    qq = mp.gammainc(n, mp.mpf(t), mp.inf, regularized=True)
    dens = mp.exp(-mp.mpf(t) + (n - 1) * mp.log(t) - mp.loggamma(n))
    assert abs(float((qq - mp.mpf(q)) / (dens * t))) < 1e-14


_LOG_PFA = st.floats(-300.0, math.log10(0.5))


@st.composite
def _extreme_targets(draw):
    """(pd, pfa) with Pd barely above Pfa or within 1e-12 ... 0.1 of 1.

    Pd just above Pfa is drawn for Pfa >= 1e-280: below, the smallest terms of Pd - Pfa are
    subnormal numbers and the root is accurate to ~1e-8 relative only (documented).
    """
    if draw(st.booleans()):
        pfa = 10.0 ** draw(_LOG_PFA)
        pd = 1.0 - 10.0 ** -draw(st.floats(1.0, 12.0))
    else:
        pfa = 10.0 ** draw(st.floats(-280.0, math.log10(0.5)))
        pd = pfa * (1.0 + 10.0 ** -draw(st.floats(0.0, 8.0)))
    if not pfa < pd <= 1 - 1e-12:
        pd = 0.5 * (pfa + 1.0)
    return pd, pfa


@settings(max_examples=30, deadline=None)
@given(target=_extreme_targets())
def test_swerling1_one_pulse_matches_closed_form_at_extremes(target):
    pd, pfa = target
    x = float(_RSNR[1](pd, pfa, 1.0))
    want = _swerling1_one_pulse_db(pd, pfa)
    assert x == pytest.approx(want, rel=1e-9, abs=1e-9)


@settings(max_examples=20, deadline=None)
@given(target=_extreme_targets(), n=st.sampled_from([1.0, 10.0, 1000.0]))
def test_swerling2_matches_closed_form_at_extremes(target, n):
    # 1 + S = T(Pfa, N) / T(Pd, N) with T solving Q(N, T) = p, thresholds from mpmath
    pd, pfa = target
    t_fa = ref.threshold_mp(pfa, n, dps=40)
    t_d = ref.threshold_mp(pd, n, dps=40)
    want = float(10 * mp.log10(t_fa / t_d - 1))
    # the ratio T_fa / T_d - 1 cancels when Pd is barely above Pfa: relative error eps T/(T - T_d)
    cond = float(t_fa / (t_fa - t_d)) * 1e-15 * 4.35
    assert float(_RSNR[2](pd, pfa, n)) == pytest.approx(want, rel=1e-9, abs=1e-9 + cond)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(sw=st.sampled_from([0, 1, 2, 3, 4]), lp=_LOG_PFA, n=st.floats(1.0, 1e4),
       k1=st.floats(0.3, 12.0), k2=st.floats(0.3, 12.0))
def test_required_snr_is_monotone_in_pd_over_the_domain(sw, lp, n, k1, k2):
    pfa = 10.0**lp
    p1, p2 = sorted((1.0 - 10.0**-k1, 1.0 - 10.0**-k2))
    if p1 <= pfa:
        return
    x1, x2 = float(_RSNR[sw](p1, pfa, n)), float(_RSNR[sw](p2, pfa, n))
    assert np.isfinite(x1) and np.isfinite(x2)
    assert x2 >= x1 - 1e-9 * max(1.0, abs(x1))


# ---------------------------------------------------------------------------------------------
# Gradient signs against central finite differences over the documented domain
# ---------------------------------------------------------------------------------------------


def _fd_and_ad(sw, pd, pfa, n):
    """Autodiff gradient of required SNR and central differences (relative steps of the small
    quantity: Pd - Pfa below 1/2, 1 - Pd above; Pfa; N)."""
    x = lambda p, f, k: float(_RSNR[sw](p, f, k))
    g = [float(v) for v in _RSNR_GRAD[sw](pd, pfa, n)]
    if 1.0 - pd < pd - pfa:
        m = 1.0 - pd
        lo, hi = 1.0 - m * 1.02, 1.0 - max(m * 0.98, 1e-12)
    else:
        e = pd - pfa
        lo, hi = pfa + e * 0.99, pfa + e * 1.01
    fd_pd = (x(hi, pfa, n) - x(lo, pfa, n)) / (hi - lo)
    f_hi = min(pfa * 1.01, 0.5, pfa + 0.5 * (pd - pfa))
    f_lo = pfa * 0.99
    f_lo = max(f_lo, 1e-300)
    fd_pfa = (x(pd, f_hi, n) - x(pd, f_lo, n)) / (f_hi - f_lo)
    h = min(0.01 * n, 1.0)
    n_lo, n_hi = max(1.0, n - h), min(1e4, n + h)
    fd_n = (x(pd, pfa, n_hi) - x(pd, pfa, n_lo)) / (n_hi - n_lo)
    return g, [fd_pd, fd_pfa, fd_n]


@pytest.mark.parametrize("sw,pd,pfa,n", [
    (0, 1 - 1e-12, 0.5, 1e4), (3, 1 - 1e-10, 1e-6, 9998.0), (1, 1 - 1e-12, 1e-300, 1.0),
    (4, 1 - 1e-12, 1e-12, 5000.0), (0, 0.9, 1e-6, 10.0), (1, 2e-6, 1e-6, 100.0), (2, 1 - 1e-12, 1e-100, 1e4),
])
def test_required_snr_gradient_signs_at_extremes(sw, pd, pfa, n):
    g, fd = _fd_and_ad(sw, pd, pfa, n)
    assert g[0] > 0 and g[1] < 0 and g[2] < 0, g
    for a, b in zip(g, fd):
        assert a == pytest.approx(b, rel=0.05), (g, fd)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(sw=st.sampled_from([0, 1, 2, 3, 4]), lp=_LOG_PFA, n=st.floats(1.0, 1e4), k=st.floats(0.3, 12.0),
       low=st.booleans())
def test_required_snr_gradient_signs_agree_with_finite_differences(sw, lp, n, k, low):
    pfa = 10.0**lp
    pd = pfa * (1.0 + 10.0**-min(k, 6.0)) if low else 1.0 - 10.0**-k
    if not pfa < pd <= 1 - 1e-12:
        return
    g, fd = _fd_and_ad(sw, pd, pfa, n)
    if pd - pfa < N_DERIVATIVE_MIN_EXCESS:
        # the N derivative is not computed there (documented): NaN, never a wrong number
        assert math.isnan(g[2]), g
        g, fd = g[:2], fd[:2]
    assert g[0] > 0 and g[1] < 0 and all(v < 0 for v in g[2:]), g
    for a, b in zip(g, fd):
        assert np.sign(a) == np.sign(b), (g, fd)


_PD = {sw: jax.jit(lambda s, f, n, sw=sw: det.pd(s, f, n, sw)) for sw in range(5)}
_PD_GRAD = {sw: jax.jit(jax.grad(lambda s, f, n, sw=sw: det.pd(s, f, n, sw), argnums=(0, 1, 2))) for sw in range(5)}


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(sw=st.sampled_from([0, 1, 2, 3, 4]), lp=_LOG_PFA, n=st.floats(1.0, 1e4), k=st.floats(-1.0, 12.0))
def test_pd_gradient_signs_agree_with_finite_differences(sw, lp, n, k):
    # at the SNR where 1 - Pd = 10^-k (Pd from 0.9 ... within 1e-12 of 1) or Pd - Pfa = 10^k Pfa
    pfa = 10.0**lp
    pd_t = 1.0 - 10.0**-k if k > 1.0 else min(pfa * (1.0 + 10.0**k), 0.9)
    if not pfa < pd_t <= 1 - 1e-12:
        return
    x = float(_RSNR[sw](pd_t, pfa, n))
    g = [float(v) for v in _PD_GRAD[sw](x, pfa, n)]
    assert g[0] > 0 and g[1] > 0 and g[2] > 0, g
    h = 0.01
    fd_x = (float(_PD[sw](x + h, pfa, n)) - float(_PD[sw](x - h, pfa, n))) / (2 * h)
    assert fd_x > 0 and g[0] == pytest.approx(fd_x, rel=0.05)


# ---------------------------------------------------------------------------------------------
# float32: matched-filter loss finite with finite derivative over its domain
# ---------------------------------------------------------------------------------------------

_F32_CHILD = textwrap.dedent("""
    import json, jax, jax.numpy as jnp, numpy as np
    import diffsense
    from diffsense.detection.matched_filter import PULSES, _domain, matched_filter_loss_db
    out = {}
    for pulse, filters in PULSES.items():
        for f in filters:
            lo, hi = _domain(f, pulse)
            x = jnp.asarray(np.geomspace(lo * 1.0001, hi * 0.9999, 3000), dtype=jnp.float32)
            v = matched_filter_loss_db(x, f, pulse)
            g = jax.vmap(jax.grad(lambda y: matched_filter_loss_db(y, f, pulse)))(x)
            bad = ~(jnp.isfinite(v) & jnp.isfinite(g))
            out[pulse + "/" + f] = [str(v.dtype), float(x[bad][0]) if bool(jnp.any(bad)) else None]
    print(json.dumps(out))
""")


def test_matched_filter_loss_and_slope_are_finite_in_float32():
    # two cascaded tuned circuits had a NaN slope beyond beta*tau ~ 18 (five: ~ 44) in float32
    env = dict(os.environ, DIFFSENSE_X64="0", PYTHONPATH=str(REPO))
    proc = subprocess.run([sys.executable, "-c", _F32_CHILD], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert all(dtype == "float32" and first_bad is None for dtype, first_bad in out.values()), out


# ---------------------------------------------------------------------------------------------
# Counterexamples the sweeps found, kept as fast checks
# ---------------------------------------------------------------------------------------------


def test_subnormal_inputs_count_as_zero_eagerly_and_under_jit():
    # XLA treats subnormals as 0 (in some fused kernels only); the eager check does the same
    with pytest.raises(DomainError, match="subnormal"):
        det.pd_given_threshold(1.0, 1e-320, 1.0, 4)
    jitted = jax.jit(lambda a, b, c: det.pd_given_threshold(a, b, c, 4))
    assert math.isnan(float(jitted(1.0, 1e-320, 1.0)))
    assert math.isnan(float(jitted(float("inf"), 1e-320, 1.0)))
    # a negative subnormal SNR is -0: admitted, Pd = Pfa, the same both ways
    eager = float(det.pd_given_threshold(-1.1125369292536007e-308, 2.0, 1.0, 4))
    assert eager == float(jitted(-1.1125369292536007e-308, 2.0, 1.0)) == pytest.approx(math.exp(-2.0), rel=1e-14)


@pytest.mark.parametrize("sw", [0, 3, 4])
@pytest.mark.parametrize("lp", [-42, -100, -300])
def test_pd_barely_above_a_tiny_pfa_keeps_its_digits_and_slopes(sw, lp):
    # Pfa < ~1e-35 at N = 1: the terms of Pd - Pfa lie below the weight window; stopping there
    # returned Pd = Pfa exactly, a zero SNR slope and an infinite required-SNR gradient
    pfa = 10.0**lp
    x = float(det.required_snr_db(1.1 * pfa, pfa, 1.0, sw))
    want = float(ref.required_snr_mp(1.1 * pfa, pfa, 1, sw, dps=40))
    # below Pfa ~ 1e-280 the smallest terms are subnormal: ~1e-8 relative (required_snr_db)
    assert x == pytest.approx(want, rel=1e-9 if lp > -280 else 1e-7)
    g, fd = _fd_and_ad(sw, 1.1 * pfa, pfa, 1.0)
    # the N derivative only where Pd - Pfa >= 1e-290 (NaN below, documented)
    assert g[0] > 0 and g[1] < 0 and (g[2] < 0 if 0.1 * pfa >= N_DERIVATIVE_MIN_EXCESS else math.isnan(g[2])), g
    assert g[0] == pytest.approx(fd[0], rel=1e-3) and g[1] == pytest.approx(fd[1], rel=0.05)


def test_swerling4_slope_in_n_when_pd_minus_pfa_is_below_1e17():
    # d Pd/dN of Swerling 4 summed D(m) from k = 0 (cancelling to ~1e-19 absolute): 2.4e-19
    # for a true 5.3e-30 at Pfa = 1e-30
    from diffsense.detection.threshold import threshold
    pfa = 1e-30
    s = 10 ** (float(det.required_snr_db(1.1 * pfa, pfa, 1.0, 4)) / 10)
    t = float(threshold(pfa, 1.0))
    f = lambda n: det.pd_given_threshold(s, t, n, 4)
    # forward difference (n >= 1; the mpmath Swerling 4 reference takes integer n only)
    h = 1e-4
    fd = (float(f(1.0 + h)) - float(f(1.0))) / h
    assert float(jax.grad(f)(1.0)) == pytest.approx(fd, rel=1e-3)
    assert 0 < fd < 1e-28


def test_required_snr_root_at_a_raised_truncation_and_mean_near_one():
    # the root finder raises L to ~250 here; the composite upper bound of K then started its
    # recursion at P(K = 171) ~ e^-710 = 0 for K's mean ~ 1, and Newton jumped to -22.9 dB
    pfa = 1e-89
    for n in (202, 203):
        want = float(ref.required_snr_mp(1.01 * pfa, pfa, n, 0, dps=40))
        assert float(det.required_snr_db(1.01 * pfa, pfa, float(n), 0)) == pytest.approx(want, rel=1e-9)


def test_n_derivative_is_nan_where_pd_minus_pfa_is_below_its_floor():
    # Pfa = 1e-300, Pd - Pfa = 1.8e-304: the parts of dPd/dN reach the subnormal range (flushed
    # by XLA); the derivative came out +8.5e-9 dB/pulse for a true -5.0e-4 (central differences)
    pfa, n = 1e-300, 3498.0
    pd = pfa * (1 + 10**-3.75)
    g = _RSNR_GRAD[0](pd, pfa, n)
    assert math.isnan(float(g[2])) and float(g[0]) > 0 > float(g[1])
    fd = (float(_RSNR[0](pd, pfa, n + 1)) - float(_RSNR[0](pd, pfa, n - 1))) / 2
    assert -6e-4 < fd < -4e-4
    # with Pd - Pfa above the floor it is computed, and agrees with central differences
    pd = 1e-280 * (1 + 10**-3.75)
    fd = (float(_RSNR[0](pd, 1e-280, n + 1)) - float(_RSNR[0](pd, 1e-280, n - 1))) / 2
    assert float(_RSNR_GRAD[0](pd, 1e-280, n)[2]) == pytest.approx(fd, rel=1e-3)
