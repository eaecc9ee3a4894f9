"""Shared RCS (Swerling 1 and 3) for M-of-N binary integration: the exact trapezoidal quadrature
of eq. (2) of :mod:`diffsense.detection.binary` (whose docstring states the model, the grid, the
derivatives and the measured accuracy).

    Pd - Pfa = int g(v) S_sigma(e^(v-s)) dv,     1 - Pd = int g(v) F_sigma(e^(v-s)) dv
"""

from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp
from jax.scipy.special import gammaln

from diffsense.numerics.bracketed_newton import newton_decreasing
from diffsense.numerics.db import DB_PER_NEPER
from diffsense.detection._binary_trials import _binomial_pmf, _trial
from diffsense.detection._logpmf import log_poisson_pmf

_GRID_NODES = 2048
_SNR_CHUNK = 256
_GRID_EPS = 1e-17
_V_MIN = -60.0
_V_LEFT_MAX = -8.0
#: SNR (dB) beyond which Pd is held at its limit
SAT_DB = 300.0
_ROOT_MAX_ITER = 100
_ROOT_TOL = 1e-13


def _grid(t, n_p, q0, base, n, m):
    """Quadrature grid of the shared-RCS average (module docstring, eq. (2)).

    Returns ``(v, wg, wg_t, boundary_t)``: nodes v (log per-pulse SNR, shape ``t.shape + (K,)``),
    trapezoid weight times dG/dv and times d(dG/dv)/dT, and dG(0)/dT = B'(p_f) dQ(n_p, T)/dT.
    """
    dtype = t.dtype
    r0 = 1.0 - q0
    # left end: dG/dv ~ c0 e^v below the transition, c0 = B'(p_f) n_p pois(n_p; T) (log-gamma
    # form: it only places the end); the mass left out is c0 e^v0 <= _GRID_EPS
    log_c0 = (jnp.log(n) + gammaln(n) - gammaln(m) - gammaln(n - m + 1.0) + (m - 1.0) * jnp.log(q0)
              + (n - m) * jnp.log(r0) + jnp.log(n_p) + log_poisson_pmf(n_p, t))
    v0 = jnp.clip(jnp.log(_GRID_EPS) - log_c0, _V_MIN, _V_LEFT_MAX)
    # right end: 1 - G(x) <= C(n, m-1) miss(x)^(n-m+1) and the Chernoff bound
    # miss(x) <= exp(T - n_p log 2 - n_p x / 2); the mass left out is 1 - G(e^v1) <= _GRID_EPS
    log_comb = gammaln(n + 1.0) - gammaln(m) - gammaln(n - m + 2.0)  # log C(n, m - 1)
    l_star = (-jnp.log(_GRID_EPS) + log_comb) / (n - m + 1.0)
    x_end = 2.0 * (t - n_p * jnp.log(2.0) + l_star) / n_p
    v1 = jnp.maximum(jnp.log(jnp.maximum(x_end, 1e-300)), v0 + 10.0)
    h = (v1 - v0) / (_GRID_NODES - 1)
    idx = jnp.arange(_GRID_NODES, dtype=dtype)
    v = v0[..., None] + h[..., None] * idx
    x = jnp.exp(v)
    p, q, p_x, p_t = _trial(x, t[..., None], n_p[..., None], q0[..., None], 0)
    # B'(p), B''(p) at the nodes and B'(p_f) (appended), from one call of the pmf
    ne, me, npe = n[..., None], m[..., None], n_p[..., None]
    p_all = jnp.concatenate([p, q0[..., None]], axis=-1)
    q_all = jnp.concatenate([q, r0[..., None]], axis=-1)
    ks = jnp.stack([me - 1.0, me - 2.0, me - 1.0])
    sizes = jnp.stack([ne - 1.0, ne - 2.0, ne - 2.0])
    pmf = _binomial_pmf(ks, sizes, p_all, q_all)
    slope_all = ne * pmf[0]
    slope = slope_all[..., :-1]
    curv = ne * (ne - 1.0) * (pmf[1] - pmf[2])[..., :-1]
    g = slope * x * p_x
    # d(dG/dv)/dT with d^2p/dx dT = -n_p dp/dT - dp/dx (steady law, see the module docstring)
    g_t = curv * p_t * x * p_x + slope * x * (-npe * p_t - p_x)
    w = jnp.where((idx == 0) | (idx == _GRID_NODES - 1), 0.5, 1.0) * h[..., None]
    # the weights of dG/dv sum to G(inf) - G(0) = 1 - Pfa up to rounding (median 1e-15, at most
    # 3.6e-14 over the domain's corners: the rounding of p_d amplified by the steep B'(p) at
    # N = 100); dividing that out makes Pfa + (Pd - Pfa) + (1 - Pd) = 1 exactly, so that Pd is
    # continuous where it switches from one sum to the other
    w = w * ((1.0 - base) / jnp.sum(w * g, axis=-1))[..., None]
    boundary_t = -slope_all[..., -1] * jnp.exp(log_poisson_pmf(n_p - 1.0, t))
    return v, w * g, w * g_t, boundary_t


def _survival(z, swerling):
    """P(sigma > e^z) for the RCS law (mean 1): Swerling 1 exponential, 3 chi-square 4 dof."""
    if swerling == 1:
        return jnp.exp(-jnp.exp(z))
    a = 2.0 * jnp.exp(z)
    return (1.0 + a) * jnp.exp(-a)


def _cdf(z, swerling):
    """P(sigma <= e^z), to full relative accuracy when small."""
    if swerling == 1:
        return -jnp.expm1(-jnp.exp(z))
    a = 2.0 * jnp.exp(z)
    small = a < 0.5
    a_s = jnp.where(small, a, 0.25)
    a_l = jnp.where(small, 1.0, a)
    direct = -jnp.expm1(-a_l) - a_l * jnp.exp(-a_l)
    return jnp.where(small, _gamma2_series(a_s), direct)


def _gamma2_series(a):
    """1 - (1 + a) e^-a = sum_{k>=2} (-1)^k (k-1) a^k / k! for 0 <= a < 0.5 (last term < 1e-33)."""
    term = 0.5 * a * a
    total = term
    for k in range(3, 30):
        term = term * (-a) / k
        total = total + (k - 1.0) * term
    return total


def _density(z, swerling):
    """Density of log(sigma) at z: -d/dz P(sigma > e^z)."""
    if swerling == 1:
        return jnp.exp(z - jnp.exp(z))
    a = 2.0 * jnp.exp(z)
    return a * a * jnp.exp(-a)


def _excess_and_miss(s, v, wg, swerling):
    """(Pd - Pfa, 1 - Pd) at log-SNR s (shape of s; grid arrays broadcast against s[..., None])."""
    z = v - s[..., None]
    return jnp.sum(wg * _survival(z, swerling), axis=-1), jnp.sum(wg * _cdf(z, swerling), axis=-1)


def _shared_partials(s, v, wg, wg_t, boundary_t, swerling):
    """(Pd - Pfa, 1 - Pd, dPd/ds, dPd/dT) at log-SNR s.

    dPd/dT = dG(0)/dT + sum wg_t P(sigma > .) = -sum wg_t P(sigma <= .) (the two agree because
    the integral of d(dG/dv)/dT is d(1 - Pfa)/dT); the first is used where Pd < 1/2, the second,
    free of the cancellation of the first as Pd approaches 1, elsewhere.
    """
    z = v - s[..., None]
    surv = _survival(z, swerling)
    cdf = _cdf(z, swerling)
    excess = jnp.sum(wg * surv, axis=-1)
    miss = jnp.sum(wg * cdf, axis=-1)
    d_s = jnp.sum(wg * _density(z, swerling), axis=-1)
    d_t = jnp.where(miss < 0.5, -jnp.sum(wg_t * cdf, axis=-1), boundary_t + jnp.sum(wg_t * surv, axis=-1))
    return excess, miss, d_s, d_t


def _log_snr(x):
    return jnp.log(jnp.clip(x, 1e-30, 1e30))


def _over_snr(fn, s, *grid):
    """``fn(s, *grid)`` elementwise in s; for a grid shared by all SNRs (1-D) and many SNRs, in
    chunks of _SNR_CHUNK SNRs (lax.map), so that the (SNRs x nodes) arrays stay small."""
    if grid[0].ndim != 1 or s.size <= _SNR_CHUNK:
        return fn(s, *grid)
    flat = s.reshape(-1)
    flat = jnp.concatenate([flat, jnp.broadcast_to(flat[:1], ((-flat.size) % _SNR_CHUNK,))])
    out = jax.lax.map(lambda c: fn(c, *grid), flat.reshape(-1, _SNR_CHUNK))
    return jax.tree_util.tree_map(lambda o: o.reshape(-1)[:s.size].reshape(s.shape), out)


@partial(jax.custom_jvp, nondiff_argnums=(7,))
def _pd_shared(x, t, n_p, q0, base, n, m, swerling):
    """Pd of M-of-N with one RCS draw per dwell; x (per-pulse SNR) may have its own shape."""
    v, wg, _, _ = _grid(t, n_p, q0, base, n, m)
    excess, miss = _over_snr(lambda s, v_, w_: _excess_and_miss(s, v_, w_, swerling), _log_snr(x), v, wg)
    return jnp.where(miss < 0.5, 1.0 - miss, base + excess)


@_pd_shared.defjvp
def _pd_shared_jvp(swerling, primals, tangents):
    x, t, n_p, q0, base, n, m = primals
    dx, dt = tangents[:2]
    v, wg, wg_t, boundary_t = _grid(t, n_p, q0, base, n, m)
    excess, miss, d_s, d_t = _over_snr(lambda s, *g: _shared_partials(s, *g, swerling), _log_snr(x),
                                       v, wg, wg_t, boundary_t)
    inside = (x > 1e-30) & (x < 1e30)  # beyond, Pd is held at its limit value
    d_x = jnp.where(inside, d_s / jnp.where(inside, x, 1.0), 0.0)
    return jnp.where(miss < 0.5, 1.0 - miss, base + excess), d_x * dx + d_t * dt


def _solve_shared(pd_t, base, v, wg, swerling):
    """Log-SNR s with Pd(s) = pd_t: safeguarded Newton on the log of the small one of Pd - Pfa and
    1 - Pd (both summed directly on the grid), bracket [-300, 300] dB."""
    high = 1.0 - pd_t < pd_t - base
    goal = jnp.where(high, -jnp.log1p(-pd_t), jnp.log(pd_t - base))
    # start: G taken as a step at its median v50: Pd = P(sigma > e^(v50 - s)); for Swerling 1
    # s = v50 - log(-log Pd) (Swerling 3 starts from the same formula)
    cum = jnp.cumsum(wg, axis=-1)
    i50 = jnp.argmax(cum >= 0.5 * cum[..., -1:], axis=-1)
    v50 = jnp.take_along_axis(v, i50[..., None], axis=-1)[..., 0]
    lim = SAT_DB / DB_PER_NEPER
    s0 = jnp.clip(v50 - jnp.log(-jnp.log(pd_t)), -lim + 1.0, lim - 1.0)

    def decreasing_residual(s):  # -(f, f'): f increases in s
        z = v - s[..., None]
        excess = jnp.sum(wg * _survival(z, swerling), axis=-1)
        miss = jnp.sum(wg * _cdf(z, swerling), axis=-1)
        dens = jnp.sum(wg * _density(z, swerling), axis=-1)
        small = jnp.where(high, miss, excess)
        f = jnp.where(high, -jnp.log(small), jnp.log(small)) - goal
        return -f, -dens / small

    s, _, _ = newton_decreasing(decreasing_residual, s0, jnp.full_like(s0, -lim), jnp.full_like(s0, lim),
                                lambda s: _ROOT_TOL, _ROOT_MAX_ITER)
    return jnp.where(jnp.abs(s) < lim - 1e-6, s, jnp.nan)


@partial(jax.custom_jvp, nondiff_argnums=(7,))
def _required_shared(pd_t, t, n_p, q0, base, n, m, swerling):
    v, wg, _, _ = _grid(t, n_p, q0, base, n, m)
    return DB_PER_NEPER * _solve_shared(pd_t, base, v, wg, swerling)


@_required_shared.defjvp
def _required_shared_jvp(swerling, primals, tangents):
    pd_t, t, n_p, q0, base, n, m = primals
    dpd, dt = tangents[:2]
    v, wg, wg_t, boundary_t = _grid(t, n_p, q0, base, n, m)
    s = _solve_shared(pd_t, base, v, wg, swerling)
    _, _, d_s, d_t = _shared_partials(s, v, wg, wg_t, boundary_t, swerling)
    # implicit: Pd(s, T) = pd_t  =>  ds = (dpd - dPd/dT dT) / (dPd/ds)
    return DB_PER_NEPER * s, DB_PER_NEPER * (dpd - d_t * dt) / d_s


# --------------------------------------------------------------------------------------
# public functions
