"""The Chebyshev interpolant of the exact required SNR (diffsense.detection.chebyshev_snr).

References: the exact solver (itself within 1e-9 dB of mpmath, tests/detection/
test_detection_accuracy.py) at points the fit never saw — the midpoints between Chebyshev points
on every axis (where an interpolant errs most) and random points of the domain —, the Swerling 1
closed form S = ln Pfa / ln Pd - 1 at N = 1, and DiFranco & Rubin's tables.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.detection import chebyshev_snr as cs
from diffsense.detection.chebyshev_fit import fit_coefficients
from diffsense.detection import chebyshev_snr_db, required_snr_db
from diffsense.detection.required_snr import _required_snr
from diffsense.errors import DomainError

SWERLINGS = (0, 1, 2, 3, 4)


def _midpoints(size):
    """Midpoints (in angle) between neighbouring Chebyshev points of the first kind, and the ends."""
    return np.concatenate([[1.0], np.cos(np.pi * np.arange(1, size) / size), [-1.0]])


def _inside(pd, pfa, n):
    return ((pd >= cs.PD_RANGE[0]) & (pd <= cs.PD_RANGE[1]) & (pfa >= cs.PFA_RANGE[0]) & (pfa <= cs.PFA_RANGE[1])
            & (n >= cs.N_RANGE[0]) & (n <= cs.N_RANGE[1]))


@pytest.fixture(scope="module")
def exact():
    return {sw: jax.jit(lambda p, f, n, sw=sw: _required_snr(p, f, n, sw)) for sw in SWERLINGS}


@pytest.mark.parametrize("swerling", SWERLINGS)
def test_within_the_stated_bound_between_the_chebyshev_points(swerling, exact):
    axes = [_midpoints(k) for k in cs.POINTS]
    pd, pfa, n = (v.ravel() for v in cs.inputs_at(np.meshgrid(*axes, indexing="ij")))
    keep = _inside(pd, pfa, n)
    pd, pfa, n = pd[keep], pfa[keep], n[keep]
    want = np.asarray(exact[swerling](pd, pfa, n))
    got = np.asarray(chebyshev_snr_db(pd, pfa, n, swerling))
    assert np.all(np.isfinite(want)) and np.all(np.isfinite(got))
    assert np.max(np.abs(got - want)) <= cs.ERROR_BOUND_DB


@pytest.mark.parametrize("swerling", SWERLINGS)
def test_within_the_stated_bound_at_random_points(swerling, exact):
    rng = np.random.default_rng(20261129 + swerling)
    size = 4000
    pd = np.concatenate([rng.uniform(*cs.PD_RANGE, size // 2), 1.0 - 10 ** rng.uniform(-6, -1, size // 2)])
    pfa = 10 ** rng.uniform(-15, -2, size)
    n = np.exp(rng.uniform(0.0, math.log(1e4), size))
    n[: size // 8] = np.round(n[: size // 8])  # whole pulse counts too
    err = np.abs(np.asarray(chebyshev_snr_db(pd, pfa, n, swerling)) - np.asarray(exact[swerling](pd, pfa, n)))
    assert np.max(err) <= cs.ERROR_BOUND_DB


def test_swerling1_single_pulse_equals_the_closed_form():
    pd = np.linspace(0.05, 0.999, 60)[:, None]
    pfa = np.logspace(-15, -2, 27)[None, :]
    closed = 10 * np.log10(np.log(pfa) / np.log(pd) - 1)
    assert np.max(np.abs(np.asarray(chebyshev_snr_db(pd, pfa, 1.0, 1)) - closed)) <= cs.ERROR_BOUND_DB


def test_difranco_rubin_table_value():
    assert float(chebyshev_snr_db(0.9, 1e-6, 1, 0)) == pytest.approx(13.18, abs=0.01)
    assert float(required_snr_db(0.9, 1e-6, 10, 3, method="chebyshev")) == pytest.approx(
        float(required_snr_db(0.9, 1e-6, 10, 3)), abs=cs.ERROR_BOUND_DB)


def test_derivatives_are_finite_and_follow_the_exact_ones():
    """The interpolant's derivatives against the exact implicit ones in dB per unit of logit(pd),
    ln pfa and ln n: within 0.002 dB at random points of the domain (Pd near 1 included)."""
    rng = np.random.default_rng(7)
    m = 200
    pts = np.stack([rng.uniform(*cs.PD_RANGE, m), 10 ** rng.uniform(-15, -2, m),
                    np.exp(rng.uniform(0.0, math.log(1e4), m))], axis=1)
    pts[:20, 0] = 1.0 - 10 ** rng.uniform(-6, -2, 20)
    for sw in SWERLINGS:
        g = jax.jit(jax.vmap(jax.grad(lambda a: chebyshev_snr_db(a[0], a[1], a[2], sw))))(jnp.asarray(pts))
        e = jax.jit(jax.vmap(jax.grad(lambda a: required_snr_db(a[0], a[1], a[2], sw))))(jnp.asarray(pts))
        assert np.all(np.isfinite(np.asarray(g)))
        scale = pts * np.array([1.0, 1.0, 1.0])
        scale[:, 0] = pts[:, 0] * (1.0 - pts[:, 0])  # d/d logit(pd) = pd (1 - pd) d/d pd
        assert np.max(np.abs((np.asarray(g) - np.asarray(e)) * scale)) <= 0.002


def test_domain_is_refused_eagerly_and_nan_when_traced():
    with pytest.raises(DomainError, match="pd"):
        chebyshev_snr_db(0.01, 1e-6, 1)
    with pytest.raises(DomainError, match="pfa"):
        chebyshev_snr_db(0.9, 0.1, 1)
    with pytest.raises(DomainError, match="n"):
        chebyshev_snr_db(0.9, 1e-6, 2e4)
    assert math.isnan(float(jax.jit(chebyshev_snr_db)(0.9, 1e-16, 1.0)))


@pytest.mark.slow
def test_stored_coefficients_are_the_fit_of_the_exact_values():
    """The shipped file is what ``python -m diffsense.detection.chebyshev_fit --write`` computes."""
    stored = cs._stored()
    for sw in SWERLINGS:
        assert np.allclose(fit_coefficients(sw), stored[sw], rtol=0, atol=1e-9)
