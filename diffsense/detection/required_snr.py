"""Required single-pulse SNR (detectability factor) for given Pd, Pfa and N.

``method="exact"`` inverts the exact :func:`diffsense.detection.pd` by a safeguarded Newton
iteration in x = SNR in dB on the logarithm of the small one of ``Pd - Pfa`` and ``1 - Pd``
(whichever is smaller at the target), both summed by the series with full relative accuracy
(``core``, eq. (1) and (2)), with a truncation lowered by the target (``_root_tail_exponent``).
So the root stays accurate when Pd is within 1e-12 of 1 or barely above Pfa, where Pd itself
carries none of the needed digits. The bracket is [-300, 300] dB, inside which the root lies for
every admissible input (at its ends Pd rounds to Pfa and to 1); no finite value is ever
substituted for an unreachable root (a root at an end would be returned as NaN). Derivatives
are implicit, dx = (dPd_target - dPd/dPfa dPfa - dPd/dN dN) / (dPd/dx), never through the
iterations. The derivative with respect to N is the derivative of Pd - Pfa, formed from parts
of Pfa's size that cancel; it is returned only where Pd - Pfa >= 1e-290 and is NaN below (where
its parts near 1e-308 reach float64's subnormal range, which XLA flushes to zero: at Pfa = 1e-300,
Pd - Pfa = 1.8e-304, N = 3498 it came out as +8.5e-9 dB/pulse for a true -5.0e-4). Swerling 2 has the closed form 1 + S = T(Pfa, N) / T(Pd, N) because
Pd = Q(N, T/(1+S)) (the threshold solver keeps T(Pd, N) accurate for Pd near 1).

Approximations (their measured error over the acceptance grid is tabulated in the README):

* ``"albersheim"`` — Albersheim (1981) for a steady target and a linear detector:
  SNR = -5 log10 N + (6.2 + 4.54/sqrt(N + 0.44)) log10(A + 0.12 A B + 1.7 B),
  A = ln(0.62/Pfa), B = ln(Pd/(1-Pd)). Published domain 1e-7 <= Pfa <= 1e-3,
  0.1 <= Pd <= 0.9, 1 <= N <= 8096 (only that domain is accepted), with a stated error
  < 0.2 dB. Measured against the 40-digit reference (square law, N 1-1000): up to 0.29 dB for
  Pd >= 0.5, but 4.08 dB at Pd = 0.1, Pfa = 1e-3, N = 1, where A + 0.12AB + 1.7B ≈ 1 and
  the formula gives ≈ 0 dB for a true 4.08 dB.
* ``"shnidman"`` — Shnidman (2002), "Determination of required SNR values", IEEE T-AES 38(3),
  for Swerling 0-4 (square-law). Published domain 0.1 <= Pd <= 0.99, 1e-9 <= Pfa <= 1e-3,
  1 <= N <= 100 (only that domain is accepted), stated error ~0.5 dB. Measured against the
  40-digit reference: Swerling 0 ≤ 0.30 dB, Swerling 4 ≤ 0.40 dB, Swerling 3 ≤ 0.67 dB,
  Swerling 1 and 2 ≤ 1.04 dB (worst at Pd = 0.1, N = 1 and at Pd = 0.99, N ≥ 20).
* ``"barton"`` — Barton's universal equations (IEEE T-AES 41(3), 2005; *Radar Equations for
  Modern Radar*, 2013, ch. 4), Swerling 0-4: North's single-pulse approximation with Barton's
  integration loss for a steady target, the chi-square equation with ne independent samples
  for a fluctuating one (exact for Swerling 2). Domain 0.1 <= Pd <= 0.999, 1e-12 <= Pfa <= 1e-2,
  1 <= N <= 100 (only that domain is accepted); formulas and measured errors in
  :mod:`diffsense.detection.barton`.

* ``"chebyshev"`` — a Chebyshev interpolant of the exact values (Swerling 0-4, 0.05 <= Pd <=
  1 - 1e-6, 1e-15 <= Pfa <= 1e-2, real 1 <= N <= 1e4; only that domain is accepted), within
  0.005 dB of the exact solver at a few operations per point: :mod:`diffsense.detection.chebyshev_snr`.

The book's integration rule (Brooker 8.16.13): a postdetection integration gain of G dB takes
N = 10^(G/8) pulses (gain 8 log10 N, i.e. N^0.8), plus 7 more pulses for the SDLA (linear/log)
detector the ore-pass radar uses — see :func:`book_pulses_for_integration_gain`.
"""

from __future__ import annotations

import math
from functools import partial

import jax
import jax.numpy as jnp
from jax.custom_derivatives import SymbolicZero

from diffsense.errors import DomainError
from diffsense.numerics.db import DB_PER_NEPER, db10, from_db10
from diffsense.detection._bounds import tail_exponent
from diffsense.detection._domain import admit, guard
from diffsense.detection.barton import barton_snr_db
from diffsense.detection.chebyshev_snr import chebyshev_snr_db
from diffsense.detection.core import SWERLING_CASES, _chunked, _mixture_sum, pd_given_threshold
from diffsense.detection.probability import N_RANGE, PFA_RANGE, saturation_db
from diffsense.detection.threshold import _threshold, _threshold_tangents

__all__ = [
    "required_snr_db",
    "albersheim_snr_db",
    "shnidman_snr_db",
    "book_integration_gain_db",
    "book_pulses_for_integration_gain",
    "BOOK_SDLA_EXTRA_PULSES",
]

#: Extra pulses the book adds when an SDLA (linear) detector replaces the square law (8.16.13).
BOOK_SDLA_EXTRA_PULSES = 7

# Bracket of the root (dB). For every admissible (pd, pfa, n) the root lies strictly inside:
# at -300 dB Pd rounds to Pfa < pd and at +300 dB the miss probability rounds to 0 < 1 - pd
# (probability.saturation_db; float32: +-150 dB). A result at an end is returned as NaN.
_TOL_DB = 1e-11
#: smallest Pd - Pfa at which the derivative with respect to N is computed (module docstring)
N_DERIVATIVE_MIN_EXCESS = 1e-290
_MAX_ITER = 60


def _root_tail_exponent(pd_t, pfa, base):
    """Truncation exponent for the root finder: ``L + ln(1/m)``, m = min(pd - pfa, 1 - pd).

    The series is truncated where its omitted terms are below exp(-L) absolutely; the root
    finder compares Pd - Pfa (pd <= 1/2) or 1 - Pd (pd > 1/2) with a target that may be as
    small as 1e-12 or less, so the truncation is lowered by that target to stay below exp(-L)
    relative to it. Capped where exp(-L) approaches the smallest normal number.
    """
    cap = 0.85 * -math.log(float(jnp.finfo(jnp.result_type(pd_t)).tiny))
    margin = jnp.minimum(pd_t - pfa, 1.0 - pd_t)
    return jnp.clip(base - jnp.log(margin), base, cap)


def _log_tail_and_slope(x_db, t, n, pfa, high, tail_l, swerling, partials="snr"):
    """g(x) = log(Pd - Pfa) or, for ``high`` targets, -log(1 - Pd); dg/dx (x in dB); and the
    partial derivatives of Pd that ``partials`` asks for (:func:`diffsense.detection.core._mixture_sum`)."""
    snr = from_db10(x_db)
    _, excess, miss, (dp, dp_t, dp_n) = _mixture_sum(snr, t, n, pfa, swerling, with_partials=partials, tail_l=tail_l)
    small = jnp.where(high, miss, excess)
    g = jnp.where(high, -jnp.log(small), jnp.log(small))
    return g, dp * snr / (DB_PER_NEPER * small), (dp * snr / DB_PER_NEPER, dp_t, dp_n)


def _solve(pd_t, pfa, n, swerling, t=None, partials=None):
    """Safeguarded Newton iteration on g(x) = g_target, x in dB (g increasing).

    g is the logarithm of the small one of Pd - Pfa and 1 - Pd: both are summed by the series
    with full relative accuracy (``core``: DOWN and UP walks), so the root keeps its accuracy
    when Pd is within 1e-12 of 1 or barely above Pfa, where Pd itself carries no digits of
    them. log(Pd - Pfa) is nearly linear in x at low SNR (Pd - Pfa ~ S) and -log(1 - Pd)
    nearly quadratic at high SNR, so Newton's method from Shnidman's estimate converges in a few
    steps; bisection of the bracket takes over where a step would leave it.

    ``t``: the threshold T(Pfa, N) when the caller has it. ``partials`` (not for Swerling 2):
    also return Pd's partial derivatives at the last point the iteration evaluated, ``(∂Pd/∂x
    (per dB), ∂Pd/∂T, ∂Pd/∂N at fixed T)`` (None where not asked for), with ``partials`` as
    :func:`diffsense.detection.core._mixture_sum`'s ``with_partials``; the iteration stops once a
    step moves x by less than 1e-11 dB, so they are Pd's derivatives at the root to ~1e-12
    relative, without a second copy of the series.
    """
    t = _threshold(pfa, n) if t is None else t
    lim = saturation_db(pd_t)
    if swerling == 2:
        return db10(t / _threshold(pd_t, n) - 1.0)
    high = 1.0 - pd_t < pd_t - pfa  # which of 1 - Pd and Pd - Pfa is the small one
    tail_l = _root_tail_exponent(pd_t, pfa, tail_exponent(pd_t))
    g_t = jnp.where(high, -jnp.log1p(-pd_t), jnp.log(pd_t - pfa))
    x0 = _start(pd_t, pfa, n, swerling, lim)
    mode = partials or "snr"

    def body(s):
        x, lo, hi, _, it, _ = s
        g, dg, found = _log_tail_and_slope(x, t, n, pfa, high, tail_l, swerling, mode)
        h = g - g_t
        above = h > 0
        lo = jnp.where(above, lo, x)
        hi = jnp.where(above, x, hi)
        x_newton = x - h / dg
        ok = jnp.isfinite(x_newton) & (x_newton >= lo) & (x_newton <= hi)
        x_new = jnp.where(ok, x_newton, 0.5 * (lo + hi))
        done = h == 0
        x_new = jnp.where(done, x, x_new)
        kept = tuple(f for f in found if f is not None) if partials else ()
        return x_new, lo, hi, jnp.where(done, 0.0, jnp.abs(x_new - x)), it + 1, kept

    def cond(s):
        # a step below 1024 roundings of x (1024 eps (|x| + 1) dB) ends it too: in float32 the
        # 1e-11 dB step is far below the resolution of x and the loop would run all _MAX_ITER
        # trips (float32 error after this stop: <= 4e-5 dB against float64 on Pd 0.1-0.999,
        # Pfa 1e-12-1e-2, N 1-100; float64 is unchanged below 43 dB, where 1e-11 dB is larger)
        tol = jnp.maximum(_TOL_DB, 1024.0 * jnp.finfo(s[0].dtype).eps * (jnp.abs(s[0]) + 1.0))
        return (s[4] < _MAX_ITER) & jnp.any(s[3] > tol)

    lo0 = jnp.full_like(x0, -lim)
    hi0 = jnp.full_like(x0, lim)
    n_kept = {"snr": 1, "snr_t": 2, True: 3}[mode] if partials else 0
    init = (x0, lo0, hi0, jnp.full_like(x0, jnp.inf), 0, tuple(jnp.zeros_like(x0) for _ in range(n_kept)))
    x, _, _, _, _, kept = jax.lax.while_loop(cond, body, init)
    # The root is inside the bracket for every admissible input; an end means it was not found.
    x = jnp.where(jnp.abs(x) < lim - 1e-6, x, jnp.nan)
    if not partials:
        return x
    return x, kept + (None,) * (3 - n_kept)


def _start(pd_t, pfa, n, swerling, lim):
    """Shnidman's estimate, clamped into the bracket (used only as a starting point)."""
    x0 = _shnidman(jnp.clip(pd_t, 0.01, 0.999), jnp.clip(pfa, 1e-300, 0.5), n, swerling)
    return jnp.clip(jnp.nan_to_num(x0, nan=10.0), -lim + 1.0, lim - 1.0)


def _pd_db(x_db, pfa, n, swerling):
    return pd_given_threshold(from_db10(x_db), _threshold(pfa, n), n, swerling, pfa=pfa)


@partial(jax.custom_jvp, nondiff_argnums=(3,))
def _required_snr(pd_t, pfa, n, swerling):
    return _chunked(lambda p, f, k: _solve(p, f, k, swerling), pd_t, pfa, n)


def _required_snr_jvp(swerling, primals, tangents):
    pd_t, pfa, n = primals
    n_is_constant = isinstance(tangents[2], SymbolicZero)
    if swerling == 2:
        return _required_snr_jvp_linearized(swerling, primals, tangents)
    dpd = jnp.zeros_like(pd_t) if isinstance(tangents[0], SymbolicZero) else tangents[0]
    # one threshold and one copy of the Pd series: the iteration keeps Pd's partials at its
    # last point (_solve), and T's tangents come from the implicit function theorem
    t = _threshold(pfa, n)
    dt_pfa, dt_n = _threshold_tangents(t, n, tangents[1], tangents[2])
    mode = True if not n_is_constant else ("snr_t" if dt_pfa is not None else "snr")
    x, (dpd_dx, dpd_dt, dpd_dn) = _chunked(lambda p, f, k, tt: _solve(p, f, k, swerling, tt, partials=mode),
                                           pd_t, pfa, n, t)
    dpd_pfa = 0.0 if dt_pfa is None else dpd_dt * dt_pfa
    dx = (dpd - dpd_pfa) / dpd_dx
    if n_is_constant:
        return x, dx
    # dPd/dN at fixed Pfa is Pd - Pfa's derivative, formed from parts of Pfa's size that cancel;
    # below N_DERIVATIVE_MIN_EXCESS its own size approaches float64's subnormal range, which XLA
    # flushes to zero, and the result is not even of the right sign: NaN there, never a made-up number
    # (a primal-only factor keeps the tangent linear; it is skipped when N is not differentiated)
    dpd_n = dpd_dt * dt_n + dpd_dn * tangents[2]
    scale = jnp.where(pd_t - pfa < N_DERIVATIVE_MIN_EXCESS, jnp.nan, 1.0)
    return x, dx - scale * dpd_n / dpd_dx


def _required_snr_jvp_linearized(swerling, primals, tangents):
    """Swerling 2 (closed form in the thresholds): the derivative from a linearisation of Pd."""
    pd_t, pfa, n = primals
    n_is_constant = isinstance(tangents[2], SymbolicZero)
    dpd, dpfa, dn = (jnp.zeros_like(p) if isinstance(t, SymbolicZero) else t for p, t in zip(primals, tangents))
    x = _required_snr(pd_t, pfa, n, swerling)
    f = lambda xx, pp, nn: _pd_db(xx, pp, nn, swerling)
    # both directional derivatives of Pd from one linearisation (one copy of the Pd series in
    # the compiled program, its linear map applied twice); N is linearised only where it is
    # differentiated: ∂Pd/∂N goes through the incomplete gamma function's order derivative,
    # which JAX cannot differentiate again (second derivatives in the other inputs stay possible)
    if n_is_constant:
        _, lin2 = jax.linearize(lambda xx, pp: f(xx, pp, n), x, pfa)
        pd_lin = lambda a, b, c: lin2(a, b)  # noqa: E731
    else:
        _, pd_lin = jax.linearize(f, x, pfa, n)
    dpd_dx = pd_lin(jnp.ones_like(x), jnp.zeros_like(pfa), jnp.zeros_like(n))
    dpd_pfa = pd_lin(jnp.zeros_like(x), dpfa, jnp.zeros_like(n))
    dpd_n = pd_lin(jnp.zeros_like(x), jnp.zeros_like(pfa), dn)
    # dPd/dN at fixed Pfa is Pd - Pfa's derivative, formed from parts of Pfa's size that cancel;
    # below N_DERIVATIVE_MIN_EXCESS its own size approaches float64's subnormal range, which XLA
    # flushes to zero, and the result is not even of the right sign: NaN there, never a made-up number
    # (a primal-only factor keeps the tangent linear; it is skipped when N is not differentiated)
    dx = (dpd - dpd_pfa) / dpd_dx
    if n_is_constant:
        return x, dx
    scale = jnp.where(pd_t - pfa < N_DERIVATIVE_MIN_EXCESS, jnp.nan, 1.0)
    return x, dx - scale * dpd_n / dpd_dx


_required_snr.defjvp(_required_snr_jvp, symbolic_zeros=True)


def required_snr_db(pd, pfa, n=1, swerling=0, method="exact"):
    """Single-pulse SNR (dB) needed for detection probability ``pd`` at ``pfa`` with N pulses.

    Args:
        pd: required detection probability, pfa < pd <= 1 - 1e-12.
        pfa: false-alarm probability, 1e-300 ... 0.5.
        n: pulses integrated noncoherently, real 1 ... 1e4 (exact method).
        swerling: 0 (=5), 1, 2, 3, 4 — static.
        method: ``"exact"`` (default), ``"albersheim"``, ``"shnidman"``, ``"barton"`` or
            ``"chebyshev"`` — static (each approximation accepts only the domain the module
            docstring states for it).

    Returns:
        The detectability factor in dB, between about -230 dB (Pd barely above Pfa) and
        150 dB (Swerling 1, Pd = 1 - 1e-12, Pfa = 1e-300). Exact method: within 1e-9 dB
        (relative, for |x| > 1 dB) of a 40-digit mpmath inversion or a closed form over the whole
        domain, including Pd within 1e-12 of 1 at N = 1e4 (tests/detection/
        test_detection_accuracy.py, test_detection_domain_properties.py); where Pd - Pfa is
        below ~1e-8 Pd the inputs themselves limit it (a relative rounding eps of Pd moves the
        root by eps Pd / (Pd - Pfa) relative in S; Swerling 2 similarly through T(Pfa)/T(Pd) - 1).
        Differentiable implicitly in pd, pfa, n (in n where pd - pfa >= 1e-290; NaN below).

    Domain: the same eagerly and under ``jit``: an eager call outside it (including
    pd <= pfa) raises DomainError, a traced call returns NaN, value and gradient.

    Examples: DiFranco & Rubin's tables (reproduced by Skolnik) give 13.18 dB for a steady
    target at Pd = 0.9, Pfa = 1e-6, one pulse. Swerling 1 with one pulse has the closed form
    Pd = Pfa^(1/(1+S)), i.e. S = ln Pfa / ln Pd - 1 (the tables' 21.14 dB):

    >>> import math
    >>> float(required_snr_db(0.9, 1e-6))
    13.18
    >>> s1 = float(required_snr_db(0.9, 1e-6, 1, swerling=1))
    >>> closed = 10 * math.log10(math.log(1e-6) / math.log(0.9) - 1)
    >>> s1, closed, abs(s1 - closed) < 1e-9
    (21.1436, 21.1436, True)

    Far beyond the old bracket end of 130 dB, still the closed form (Pfa = 1e-300):

    >>> pd = 1 - 1e-11
    >>> float(required_snr_db(pd, 1e-300, 1, swerling=1)), 10 * math.log10(math.log(1e-300) / math.log(pd) - 1)
    (138.393369074833, 138.393369074833)
    """
    where = "required_snr_db"
    if swerling not in SWERLING_CASES:
        raise ValueError(f"{where}: swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    if method == "albersheim":
        if swerling not in (0, 5):
            raise DomainError(f"{where}: Albersheim's equation is for a steady target (swerling 0); got swerling={swerling}")
        return albersheim_snr_db(pd, pfa, n)
    if method == "shnidman":
        return shnidman_snr_db(pd, pfa, n, swerling)
    if method == "barton":
        return barton_snr_db(pd, pfa, n, swerling)
    if method == "chebyshev":
        return chebyshev_snr_db(pd, pfa, n, swerling)
    if method != "exact":
        raise ValueError(f"{where}: method must be 'exact', 'albersheim', 'shnidman', 'barton' or 'chebyshev'; "
                         f"got {method!r}")
    dtype = jnp.result_type(pd, pfa, n, float)
    pd_t, pfa, n = jnp.broadcast_arrays(*(jnp.asarray(a, dtype=dtype) for a in (pd, pfa, n)))
    ok, _ = admit(where, [("pfa", pfa, *PFA_RANGE), ("n", n, *N_RANGE), ("pd", pd_t, 0.0, 1.0 - 1e-12, True, False)],
               greater=[("pd", pd_t, "pfa", pfa)])
    pd_t, pfa, n = (guard(a, ok, fill) for a, fill in ((pd_t, 0.5), (pfa, 1e-6), (n, 1.0)))
    return guard(_required_snr(pd_t, pfa, n, 0 if swerling == 5 else swerling), ok)


def albersheim_snr_db(pd, pfa, n=1):
    """Albersheim's closed-form estimate of the required single-pulse SNR (dB), steady target.

    Domain (Albersheim 1981): 1e-7 <= pfa <= 1e-3, 0.1 <= pd <= 0.9, 1 <= n <= 8096. Measured
    error against the exact square-law value: ≤ 0.29 dB for pd >= 0.5, up to 4.08 dB at
    pd = 0.1 (see the module docstring).

    At DiFranco & Rubin's Pd = 0.9, Pfa = 1e-6, N = 1 (13.18 dB) it is within Albersheim's
    stated 0.2 dB:

    >>> abs(float(albersheim_snr_db(0.9, 1e-6)) - 13.18) < 0.2
    True
    """
    where = "albersheim_snr_db"
    dtype = jnp.result_type(pd, pfa, n, float)
    pd, pfa, n = (jnp.asarray(a, dtype=dtype) for a in (pd, pfa, n))
    ok, each = admit(where, [("pd", pd, 0.1, 0.9), ("pfa", pfa, 1e-7, 1e-3), ("n", n, 1.0, 8096.0)])
    pd, pfa, n = (guard(a, m, f) for a, m, f in zip((pd, pfa, n), each, (0.5, 1e-6, 1.0)))
    a = jnp.log(0.62 / pfa)
    b = jnp.log(pd / (1.0 - pd))
    x = -5.0 * jnp.log10(n) + (6.2 + 4.54 / jnp.sqrt(n + 0.44)) * jnp.log10(a + 0.12 * a * b + 1.7 * b)
    return guard(x, ok)


def shnidman_snr_db(pd, pfa, n=1, swerling=0):
    """Shnidman's (2002) closed-form estimate of the required single-pulse SNR (dB).

    Domain: 0.1 <= pd <= 0.99, 1e-9 <= pfa <= 1e-3, 1 <= n <= 100. Measured error against the
    exact value up to 0.30 dB (Swerling 0) and 1.04 dB (Swerling 1, 2); module docstring.

    Against the published 13.18 dB (steady) and the Swerling 1 closed form
    10 log10(ln Pfa / ln Pd - 1) = 21.14 dB at Pd = 0.9, Pfa = 1e-6, N = 1, within Shnidman's
    stated 0.5 dB:

    >>> import math
    >>> abs(float(shnidman_snr_db(0.9, 1e-6)) - 13.18) < 0.5
    True
    >>> closed = 10 * math.log10(math.log(1e-6) / math.log(0.9) - 1)
    >>> abs(float(shnidman_snr_db(0.9, 1e-6, 1, swerling=1)) - closed) < 0.5
    True
    """
    where = "shnidman_snr_db"
    if swerling not in SWERLING_CASES:
        raise ValueError(f"{where}: swerling must be one of {SWERLING_CASES}; got {swerling!r}")
    dtype = jnp.result_type(pd, pfa, n, float)
    pd, pfa, n = (jnp.asarray(a, dtype=dtype) for a in (pd, pfa, n))
    ok, each = admit(where, [("pd", pd, 0.1, 0.99), ("pfa", pfa, 1e-9, 1e-3), ("n", n, 1.0, 100.0)])
    pd, pfa, n = (guard(a, m, f) for a, m, f in zip((pd, pfa, n), each, (0.5, 1e-6, 1.0)))
    return guard(_shnidman(pd, pfa, n, swerling), ok)


def _shnidman(pd, pfa, n, swerling):
    if swerling in (0, 5):
        k = jnp.inf
    else:
        k = {1: 1.0, 2: n, 3: 2.0, 4: 2.0 * n}[swerling]
    alpha = jnp.where(n < 40.0, 0.0, 0.25)
    eta = jnp.sqrt(-0.8 * jnp.log(4.0 * pfa * (1.0 - pfa))) + jnp.sign(pd - 0.5) * jnp.sqrt(
        -0.8 * jnp.log(4.0 * pd * (1.0 - pd))
    )
    x_inf = eta * (eta + 2.0 * jnp.sqrt(n / 2.0 + (alpha - 0.25)))
    if swerling in (0, 5):
        c_db = jnp.zeros_like(x_inf)
    else:
        c1 = (((17.7006 * pd - 18.4496) * pd + 14.5339) * pd - 3.525) / k
        c2 = (1.0 / k) * (jnp.exp(27.31 * pd - 25.14) + (pd - 0.8) * (0.7 * jnp.log(1e-5 / pfa) + (2.0 * n - 20.0) / 80.0))
        c_db = jnp.where(pd <= 0.872, c1, c1 + c2)
    return c_db + db10(x_inf / n)


def book_integration_gain_db(n):
    """The book's postdetection integration gain rule, 10 log10(N^0.8) = 8 log10 N dB (Brooker 8.16.13).

    >>> float(book_integration_gain_db(10.0))   # 10 log10(10^0.8)
    8.0
    """
    n = jnp.asarray(n, dtype=jnp.result_type(n, float))
    ok, _ = admit("book_integration_gain_db", [("n", n, 1.0, None)])
    return guard(8.0 * jnp.log10(guard(n, ok, 1.0)), ok)


def book_pulses_for_integration_gain(gain_db, detector="square_law"):
    """Pulses needed for an integration gain by the book's N^0.8 rule, rounded as the book does.

    ``detector="sdla"`` adds the book's 7 extra pulses for the linear (SDLA) detector.
    Ore pass: 7.7 dB -> 10^(7.7/8) = 9.18 -> 9 pulses; with SDLA 16 (Brooker 8.16.13).
    Returns a float (the rounded count) so the function can be traced; not differentiable.

    >>> float(book_pulses_for_integration_gain(7.7)), float(book_pulses_for_integration_gain(7.7, "sdla"))
    (9.0, 16.0)
    """
    if detector not in ("square_law", "sdla"):
        raise ValueError(f"detector must be 'square_law' or 'sdla'; got {detector!r}")
    n = jnp.round(10.0 ** (jnp.asarray(gain_db, dtype=jnp.result_type(gain_db, float)) / 8.0))
    return n + (BOOK_SDLA_EXTRA_PULSES if detector == "sdla" else 0)
