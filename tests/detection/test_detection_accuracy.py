"""Exact detection functions against the independent 50-digit mpmath reference (tests/reference)."""

import itertools

import jax
import mpmath as mp
import numpy as np
import pytest
from scipy import special as sps

from diffsense import detection as det
from tests.reference import mp_detection as ref


# The grid tests call the detection functions through one jitted program per Swerling case (the
# numbers are arguments), not eagerly: read back from the session's persistent compilation cache,
# the eager programs of required_snr_db (a while_loop per primitive call) crashed the pytest worker
# inside XLA's executable deserialisation in four CI runs, always at 100 pulses, Pfa 0.1, Swerling 4.
_required_snr_db = jax.jit(det.required_snr_db, static_argnums=(3,))
_pd = jax.jit(det.pd, static_argnums=(3,))


def test_classic_required_snr_values():
    # DiFranco & Rubin / Skolnik: Pd 0.9, Pfa 1e-6, N 1 -> 13.18 dB steady, 21.14 dB Swerling 1
    assert float(det.required_snr_db(0.9, 1e-6, 1, 0)) == pytest.approx(13.18, abs=0.005)
    assert float(det.required_snr_db(0.9, 1e-6, 1, 1)) == pytest.approx(21.14, abs=0.005)


@pytest.mark.parametrize("n", [1, 1.5, 10, 100, 1000, 10000])
@pytest.mark.parametrize("pfa", [0.5, 1e-1, 1e-6, 1e-12, 1e-15, 1e-100, 1e-300])
def test_threshold_matches_mpmath(n, pfa):
    t = float(det.threshold(pfa, n))
    q = mp.gammainc(n, t, mp.inf, regularized=True)
    rel = abs(float(q / mp.mpf(pfa) - 1))
    assert rel < (3e-11 if n > 3000 else 5e-12)


def test_threshold_beats_the_gammaincinv_trap():
    # gammaincinv(N, 1 - Pfa) cannot represent 1 - Pfa below 1.1e-16 and loses the threshold.
    pfa, n = 1e-20, 10
    naive = sps.gammaincinv(n, 1.0 - pfa)
    exact = float(ref.threshold_mp(pfa, n))
    assert abs(naive - exact) > 1.0  # the trap is real
    assert float(det.threshold(pfa, n)) == pytest.approx(exact, rel=1e-13)


FULL_GRID = list(itertools.product([0, 1, 2, 3, 4], [1, 3, 10, 100, 1000], [1e-1, 1e-6, 1e-12, 1e-15]))
QUICK_GRID = list(itertools.product([0, 1, 2, 3, 4], [1, 10, 300], [1e-6, 1e-15]))
SLOW_GRID = [g for g in FULL_GRID if g not in QUICK_GRID]


def _grid_params(quick, slow):
    return [pytest.param(*g) for g in quick] + [pytest.param(*g, marks=pytest.mark.slow) for g in slow]


@pytest.mark.parametrize("swerling,n,pfa", _grid_params(QUICK_GRID, SLOW_GRID))
def test_pd_matches_mpmath_reference(swerling, n, pfa):
    # SNRs across the transition: required SNR for Pd 0.1, 0.5, 0.9, 0.999 and two far points
    x50 = float(_required_snr_db(0.5, pfa, n, swerling))
    snrs = np.array([x50 - 15.0, x50 - 3.0, x50, x50 + 3.0, x50 + 8.0, x50 + 25.0])
    got = np.asarray(_pd(snrs, pfa, n, swerling))
    want = np.array([float(ref.pd_mp(mp.mpf(10) ** (mp.mpf(s) / 10), pfa, n, swerling, dps=40)) for s in snrs])
    assert np.max(np.abs(got - want)) <= 1e-12


@pytest.mark.parametrize(
    "swerling,n,pfa",
    _grid_params([g for g in QUICK_GRID if g[1] <= 10], [g for g in FULL_GRID if g[1] <= 100 and g not in QUICK_GRID]),
)
def test_required_snr_matches_mpmath(swerling, n, pfa):
    for p in (0.1, 0.9, 0.999):
        if p <= pfa:
            continue
        got = float(_required_snr_db(p, pfa, n, swerling))
        want = float(ref.required_snr_mp(p, pfa, n, swerling, dps=40))
        assert abs(got - want) <= 1e-6


def test_pd_quadrature_trap_high_pd():
    # A coarse quadrature reports Pd = 1.000000 where the truth is below 1 (e.g. 0.99625);
    # the exact sum keeps the miss probability.
    x = float(det.required_snr_db(0.99625, 1e-6, 10, 1))
    assert float(det.pd(x, 1e-6, 10, 1)) == pytest.approx(0.99625, abs=1e-12)


def test_swerling4_large_n_no_gram_charlier_error():
    # Gram-Charlier series are off by ~3e-2 in Pd for Swerling 4 at N >= 50; exact stays < 1e-12.
    for n in (50, 200):
        x = float(det.required_snr_db(0.9, 1e-8, n, 4))
        want = float(ref.pd_mp(mp.mpf(10) ** (mp.mpf(x) / 10), 1e-8, n, 4, dps=40))
        assert float(det.pd(x, 1e-8, n, 4)) == pytest.approx(want, abs=1e-12)


@pytest.mark.parametrize("swerling", [0, 1, 2, 3, 4])
@pytest.mark.parametrize("snr_db,pfa,n", [(3.0, 1e-6, 10.0), (12.0, 1e-3, 2.5), (0.0, 1e-9, 40.0)])
def test_gradients_match_mpmath_finite_differences(swerling, snr_db, pfa, n):
    g = jax.grad(det.pd, argnums=(0, 1, 2))(snr_db, pfa, n, swerling)
    mp.mp.dps = 40
    if swerling == 4:
        # Swerling 4 for real N: negative-binomial(2N) mixture of Q(N + k, T), summed term by term.
        def f(s, p, nn):
            lam = nn * mp.mpf(10) ** (s / 10)
            t = ref.threshold_mp(p, nn, dps=40)
            return ref._pd_geometric_series(lam, nn, t, mp.mpf("1e-45"), 2 * nn)
    else:
        f = lambda s, p, nn: ref.pd_mp(
            mp.mpf(10) ** (s / 10), p, nn, swerling, dps=40, method="series" if swerling in (1, 3) else "closed"
        )
    s0, p0, n0 = mp.mpf(snr_db), mp.mpf(pfa), mp.mpf(n)
    want = [
        mp.diff(lambda s: f(s, p0, n0), s0),
        mp.diff(lambda p: f(s0, p, n0), p0, h=p0 * mp.mpf("1e-12")),
        mp.diff(lambda nn: f(s0, p0, nn), n0),
    ]
    for got, w in zip(g, want):
        assert float(got) == pytest.approx(float(w), rel=1e-7, abs=1e-12)


def test_required_snr_gradients_are_implicit():
    # d(required SNR)/d(pd) = 1 / (dPd/dSNR) at the solution
    x = det.required_snr_db(0.9, 1e-6, 10.0, 1)
    dx_dpd = jax.grad(det.required_snr_db)(0.9, 1e-6, 10.0, 1)
    dpd_dx = jax.grad(det.pd)(x, 1e-6, 10.0, 1)
    assert float(dx_dpd) == pytest.approx(1.0 / float(dpd_dx), rel=1e-10)
    dx_dn = jax.grad(det.required_snr_db, argnums=2)(0.9, 1e-6, 10.0, 1)
    h = 1e-4
    fd = (float(det.required_snr_db(0.9, 1e-6, 10.0 + h, 1)) - float(det.required_snr_db(0.9, 1e-6, 10.0 - h, 1))) / (2 * h)
    assert float(dx_dn) == pytest.approx(fd, rel=1e-6)


def test_coherent_integration_and_refusal_for_pulse_to_pulse():
    assert float(det.pd_coherent(5.0, 1e-6, 10, 1)) == pytest.approx(float(det.pd(15.0, 1e-6, 1, 1)), rel=1e-14)
    with pytest.raises(ValueError, match="coherently"):
        det.pd_coherent(5.0, 1e-6, 10, 2)


def test_real_n_relaxation_equals_integer_values_and_is_smooth():
    ns = np.array([3.0, 4.0])
    for sw in range(5):
        at_int = np.asarray(det.pd(6.0, 1e-6, ns, sw))
        want = [float(ref.pd_mp(mp.mpf(10) ** mp.mpf("0.6"), 1e-6, int(k), sw, dps=40)) for k in ns]
        assert np.max(np.abs(at_int - want)) < 1e-12
        mid = np.asarray(det.pd(6.0, 1e-6, np.linspace(3.0, 4.0, 11), sw))
        assert np.all(np.diff(mid) > 0)  # more pulses, more detection, continuously
