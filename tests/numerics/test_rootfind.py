"""Differentiable detection-range root: the free-space-plus-attenuation range equation
40 log10 R + 2 alpha R / 1000 = C (book 9.9.1) has the closed form
R = (40 / (k ln 10)) W(k ln 10 / 40 · 10^(C/40)) with k = 2 alpha / 1000 (Lambert W), evaluated
here with mpmath at 40 digits."""

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.numerics.rootfind import decreasing_root_log

MPMATH_DPS = 40  # working precision of this module's tests (set per test by tests/conftest.py)


def _range_mp(c_db, alpha_db_per_km):
    c = mp.mpf(c_db)
    if alpha_db_per_km == 0:
        return mp.power(10, c / 40)
    k = 2 * mp.mpf(alpha_db_per_km) / 1000
    a = k * mp.log(10) / 40
    return mp.lambertw(a * mp.power(10, c / 40)) / a


def _solve(c_db, alpha):
    return decreasing_root_log(lambda r: c_db - 40.0 * jnp.log10(r) - 2.0 * alpha * r / 1e3, 1.0, 1e9)


_solve_j = jax.jit(lambda c, a: _solve(c, a).root)
_grad_j = jax.jit(jax.grad(lambda c, a: _solve(c, a).root, argnums=(0, 1)))


@pytest.mark.parametrize("alpha", [0.0, 0.003, 0.02, 0.2, 5.0])
def test_range_matches_lambert_w_closed_form(alpha):
    # C = 230.1 - 8.2 dB is the air-surveillance radar of book 9.9.1 (SNR10 = 8.2 dB)
    c = 230.1 - 8.2
    got = float(_solve_j(c, alpha))
    ref = float(_range_mp(c, alpha))
    assert got == pytest.approx(ref, rel=1e-13)


def test_book_air_surveillance_ranges_9_9_1():
    # book: 352.8 km free space, ~316-320 km at 0.003 dB/km, ~216 km at 0.02 dB/km
    r = np.asarray(jax.vmap(_solve_j, in_axes=(None, 0))(230.1 - 8.2, jnp.array([0.0, 0.003, 0.02])))
    assert r[0] / 1e3 == pytest.approx(352.8, abs=0.05)
    assert r[1] / 1e3 == pytest.approx(316.3, abs=0.05)
    assert r[2] / 1e3 == pytest.approx(216, rel=0.01)


@pytest.mark.parametrize("alpha", [0.0, 0.003, 0.2])
def test_implicit_gradient_matches_closed_form_derivative(alpha):
    c = 222.0
    dc, da = (float(g) for g in _grad_j(c, alpha))
    ref_dc = mp.diff(lambda cc: _range_mp(cc, alpha), c)
    assert dc == pytest.approx(float(ref_dc), rel=1e-9)
    if alpha > 0:
        ref_da = mp.diff(lambda aa: _range_mp(c, aa), alpha)
        assert da == pytest.approx(float(ref_da), rel=1e-9)


def test_no_root_inside_bracket_is_flagged_and_has_zero_gradient():
    res = _solve(-5.0, 0.0)  # root would be R = 10^(-5/40) < 1 m, below the bracket
    assert not bool(res.bracketed)
    assert float(res.root) == 1.0
    g = jax.grad(lambda c: _solve(c, 0.0).root)(-5.0)
    assert float(g) == 0.0
    res = _solve(500.0, 0.0)  # beyond the 1e9 m upper end
    assert not bool(res.bracketed) and float(res.root) == pytest.approx(1e9)


def test_gradient_is_zero_not_nan_where_the_residual_is_flat_and_unbracketed():
    # no root in [1, 10] and f independent of x there: the bracket end is returned, and its
    # derivative with respect to the parameter is exactly 0 (the implicit solve divides by f' = 0)
    def root(c):
        return decreasing_root_log(lambda x: -c + 0.0 * x, 1.0, 10.0).root

    assert float(jax.grad(root)(2.0)) == 0.0
