"""Cumulative detection probability (diffsense.detection.cumulative).

Independent references:
- mpmath products at 30 digits: Pc = 1 - prod(1 - Pd_i) (Skolnik 2001 ch. 2; Mahafza 2013),
  and its partial derivatives prod_{i != j}(1 - Pd_i).
- For a closing Swerling 1 target with one pulse per scan the single-scan law
  Pd(R) = Pfa^(1/(1 + S0 (R0/R)^4)) evaluated in mpmath, the looks R + i v T counted in exact
  rational arithmetic (fractions), and the product taken in mpmath.
"""

import math
from fractions import Fraction

import jax
import jax.numpy as jnp
import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.detection.cumulative import (
    closing_target_ranges_m,
    cumulative_pd,
    cumulative_pd_closing,
    swerling1_single_scan_pd,
)

MPMATH_DPS = 30


def _mp_cumulative(ps):
    # 1 - prod(1 - p) cancels about -log10(min p) digits: carry them beyond the working 30
    extra = int(max(0.0, -math.log10(min((p for p in ps if p > 0), default=1.0))))
    with mpmath.workdps(mpmath.mp.dps + extra + 5):
        prod = mpmath.mpf(1)
        for p in ps:
            prod *= 1 - mpmath.mpf(p)
        return +(1 - prod)


def _mp_swerling1(r, pfa, snr_db, r0):
    s = mpmath.mpf(10) ** (mpmath.mpf(snr_db) / 10) * (mpmath.mpf(r0) / mpmath.mpf(r)) ** 4
    return mpmath.mpf(pfa) ** (1 / (1 + s))


# --------------------------------------------------------------------------------------
# cumulative_pd
# --------------------------------------------------------------------------------------


def test_cumulative_pd_matches_mpmath_product():
    # relative error of order K ulp from the sum of K logarithms (docstring: <= 5.4e-16 measured)
    rng = np.random.default_rng(7)
    cases = [
        rng.uniform(0, 1, 5),
        rng.uniform(0, 1, 40),
        np.array([1e-20, 3e-18, 2e-19]),
        np.array([1 - 1e-12, 0.3, 1e-9]),
        np.array([0.0, 0.0]),
        np.array([0.0, 1.0, 0.5]),
        10.0 ** rng.uniform(-12, -1, 30),
    ]
    for ps in cases:
        got = float(cumulative_pd(ps))
        ref = _mp_cumulative([float(p) for p in ps])
        assert abs(got - float(ref)) <= 2e-15 * float(ref), (ps, got, ref)
        # the miss probability near 1 also to a few ulp absolute
        assert abs((1 - got) - float(1 - ref)) <= 4e-16


def test_cumulative_pd_batch_over_last_axis():
    ps = np.array([[0.1, 0.2, 0.3], [0.5, 0.5, 0.5]])
    np.testing.assert_allclose(np.asarray(cumulative_pd(ps)), [1 - 0.9 * 0.8 * 0.7, 1 - 0.125], rtol=1e-15)
    assert float(cumulative_pd(np.zeros((0,)))) == 0.0


def test_gradient_is_product_of_the_others_even_at_one_and_zero():
    for ps in ([0.2, 1.0, 0.7], [1.0, 1.0, 0.3], [0.0, 0.0, 0.0], [0.3, 0.6, 0.9, 0.1]):
        g = np.asarray(jax.grad(cumulative_pd)(jnp.asarray(ps)))
        ref = [float(mpmath.fprod(1 - mpmath.mpf(q) for k, q in enumerate(ps) if k != j)) for j in range(len(ps))]
        np.testing.assert_allclose(g, ref, rtol=1e-15, atol=1e-300)
    # forward mode and jit agree
    p = jnp.array([0.2, 1.0, 0.7])
    _, t = jax.jvp(jax.jit(cumulative_pd), (p,), (jnp.array([1.0, 1.0, 1.0]),))
    assert float(t) == pytest.approx(0.8 * 0.3, rel=1e-15)  # only the scan with Pd = 1 moves Pc


def test_gradient_matches_central_difference():
    p0 = np.array([0.12, 0.55, 0.31, 0.9])
    g = np.asarray(jax.grad(cumulative_pd)(jnp.asarray(p0)))
    h = 1e-6
    for j in range(len(p0)):
        e = np.zeros_like(p0)
        e[j] = h
        fd = (float(cumulative_pd(p0 + e)) - float(cumulative_pd(p0 - e))) / (2 * h)
        assert g[j] == pytest.approx(fd, rel=1e-8)


_PADDED = 13
_cumulative_jit = jax.jit(cumulative_pd)
_cumulative_grad_jit = jax.jit(jax.grad(cumulative_pd))


@settings(max_examples=40, deadline=None)
@given(ps=st.lists(st.floats(0.0, 1.0, allow_subnormal=False), min_size=1, max_size=_PADDED - 1),
       extra=st.floats(0.0, 1.0, allow_subnormal=False))
def test_cumulative_at_least_max_single_and_monotone_in_scans(ps, extra):
    # subnormal Pd are outside the compiled domain (XLA on CPU flushes them to zero: see below)
    # padding with Pd = 0 scans keeps one compiled shape (a scan with Pd = 0 changes nothing)
    padded = np.zeros(_PADDED)
    padded[: len(ps)] = ps
    pc = float(_cumulative_jit(padded))
    assert max(ps) * (1 - 2e-15) <= pc <= 1.0  # the documented relative error
    padded[len(ps)] = extra
    assert float(_cumulative_jit(padded)) >= pc - 1e-15
    assert np.all(np.isfinite(np.asarray(_cumulative_grad_jit(jnp.asarray(padded)))))


def test_a_subnormal_pd_counts_as_zero_when_compiled():
    # the documented behaviour: XLA's CPU kernels flush subnormals, so 1 - (1 - 2.2e-313) is 0
    assert float(_cumulative_jit(np.array([2.2250738585e-313] + [0.0] * (_PADDED - 1)))) == 0.0
    assert float(_cumulative_jit(np.array([2.2250738585072014e-308] + [0.0] * (_PADDED - 1)))) > 0.0


def test_cumulative_domain():
    with pytest.raises(DomainError):
        cumulative_pd([0.5, 1.1])
    with pytest.raises(DomainError):
        cumulative_pd(0.5)
    assert math.isnan(float(jax.jit(cumulative_pd)(jnp.array([0.5, -0.1]))))


# --------------------------------------------------------------------------------------
# Closing target
# --------------------------------------------------------------------------------------


def test_closing_target_ranges():
    got = np.asarray(closing_target_ranges_m(np.array([10e3, 5e3]), 250.0, 4.0, 4))
    np.testing.assert_array_equal(got, [[10e3, 11e3, 12e3, 13e3], [5e3, 6e3, 7e3, 8e3]])
    with pytest.raises(DomainError):
        closing_target_ranges_m(10e3, 250.0, 0.0, 4)


def _mp_closing_reference(r, v, t, r_start, pfa, snr_db, r0):
    """Looks counted exactly: i = 0..floor((R_start - R) / (v T)) (binary values as fractions)."""
    span, step = Fraction(r_start) - Fraction(r), Fraction(v) * Fraction(t)
    looks = math.floor(span / step) + 1
    ranges = [mpmath.mpf(r) + i * mpmath.mpf(v) * mpmath.mpf(t) for i in range(looks)]
    return _mp_cumulative([_mp_swerling1(x, pfa, snr_db, r0) for x in ranges]), looks


@pytest.mark.parametrize("r,v,t,r_start", [(20e3, 300.0, 10.0, 40e3), (5e3, 30.0, 2.5, 60e3),
                                            (80e3, 1000.0, 12.0, 80e3), (31e3, 222.0, 5.0, 50e3)])
def test_swerling1_closing_target_matches_mpmath_product(r, v, t, r_start):
    pfa, snr_db, r0 = 1e-6, 13.0, 40e3
    ref, looks = _mp_closing_reference(r, v, t, r_start, pfa, snr_db, r0)
    assert looks <= 1024
    pd1 = lambda x: swerling1_single_scan_pd(x, pfa, snr_db, r0)
    got = float(cumulative_pd_closing(pd1, r, v, t, r_start, max_scans=1024))
    assert abs(got - float(ref)) <= 1e-14


def test_closing_jits_and_vmaps_with_traced_speed():
    pfa, snr_db, r0 = 1e-6, 13.0, 40e3
    pd1 = lambda x: swerling1_single_scan_pd(x, pfa, snr_db, r0)
    f = jax.jit(lambda v: cumulative_pd_closing(pd1, 20e3, v, 10.0, 60e3, max_scans=64))
    speeds = np.array([70.0, 150.0, 300.0, 900.0])  # 29, 14, 7 and 3 looks (by floor(40e3/(10 v)) + 1)
    batched = np.asarray(jax.vmap(f)(jnp.asarray(speeds)))
    for v, b in zip(speeds, batched):
        ref, _ = _mp_closing_reference(20e3, v, 10.0, 60e3, pfa, snr_db, r0)
        assert abs(b - float(ref)) <= 1e-14
        assert float(f(v)) == pytest.approx(b, abs=1e-15)
    # the look landing on the start range up to rounding counts (40e3 / (10 * 400) = 10 exactly)
    ref, looks = _mp_closing_reference(20e3, 400.0, 10.0, 60e3, pfa, snr_db, r0)
    assert looks == 11 and abs(float(f(400.0)) - float(ref)) <= 1e-14


def test_closing_gradients_match_central_differences():
    pfa, snr_db, r0 = 1e-6, 13.0, 40e3
    pd1 = lambda x: swerling1_single_scan_pd(x, pfa, snr_db, r0)
    # 40e3 / (10 v) is 9.3 here: far from a jump of the look count
    fn = jax.jit(lambda r, v, t: cumulative_pd_closing(pd1, r, v, t, 60e3, max_scans=32))
    args = (20e3, 430.0, 10.0)
    grads = jax.jit(jax.grad(fn, argnums=(0, 1, 2)))(*args)
    for k, g in enumerate(grads):
        h = 1e-6 * args[k]
        up = list(args)
        dn = list(args)
        up[k] += h
        dn[k] -= h
        fd = (float(fn(*up)) - float(fn(*dn))) / (2 * h)
        assert float(g) == pytest.approx(fd, rel=1e-7)
    assert float(jax.grad(lambda s: cumulative_pd_closing(pd1, 20e3, 430.0, 10.0, s, max_scans=32))(60e3)) == 0.0


def _closing_swerling1(start, v):
    pd1 = lambda x: swerling1_single_scan_pd(x, 1e-6, 13.0, 40e3)
    return cumulative_pd_closing(pd1, 20e3, v, 10.0, start, max_scans=128)


_closing_jit = jax.jit(_closing_swerling1)


@settings(max_examples=25, deadline=None)
@given(extra=st.floats(0.0, 30e3), v=st.floats(50.0, 1000.0))
def test_closing_monotone_in_start_range_and_at_least_last_look(extra, v):
    near, far = float(_closing_jit(20e3 + extra, v)), float(_closing_jit(20e3 + extra + 5e3, v))
    assert far >= near - 1e-15
    assert near >= float(swerling1_single_scan_pd(20e3, 1e-6, 13.0, 40e3)) - 1e-15


def test_closing_domain():
    pd1 = lambda x: swerling1_single_scan_pd(x, 1e-6, 13.0, 40e3)
    with pytest.raises(DomainError, match="max_scans"):
        cumulative_pd_closing(pd1, 20e3, 10.0, 1.0, 60e3, max_scans=16)  # needs 4001 looks
    with pytest.raises(DomainError):
        cumulative_pd_closing(pd1, 20e3, 300.0, 10.0, 19e3)  # start inside the final range
    with pytest.raises(DomainError):
        cumulative_pd_closing(pd1, 20e3, 0.0, 10.0, 30e3)
    f = jax.jit(lambda v: cumulative_pd_closing(pd1, 20e3, v, 1.0, 60e3, max_scans=16))
    assert math.isnan(float(f(10.0))) and math.isfinite(float(f(5e3)))


# --------------------------------------------------------------------------------------
# Swerling 1 single-scan law
# --------------------------------------------------------------------------------------


def test_swerling1_single_scan_matches_mpmath_and_edges_are_finite():
    for r in (1.0, 1e3, 20e3, 40e3, 1e5, 1e7):
        for pfa in (1e-3, 1e-8, 1e-300):
            ref = _mp_swerling1(r, pfa, 13.0, 40e3)
            got = float(swerling1_single_scan_pd(r, pfa, 13.0, 40e3))
            assert abs(got - float(ref)) <= 1e-15 * (1 + abs(float(mpmath.log(ref)))) * float(ref) + 1e-320
    g = jax.grad(lambda r: swerling1_single_scan_pd(r, 1e-6, 13.0, 40e3))
    for r in (1e-300, 1e-200, 1.0, 40e3, 1e200, 1e300):
        assert math.isfinite(float(g(r)))
    r0, h = 50e3, 1.0
    fd = float((_mp_swerling1(r0 + h, 1e-6, 13.0, 40e3) - _mp_swerling1(r0 - h, 1e-6, 13.0, 40e3)) / 2)
    assert float(g(r0)) == pytest.approx(fd, rel=1e-8)
