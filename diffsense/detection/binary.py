"""Binary (M-of-N) integration: exact detection probability and required SNR, Swerling 0-4.

**Model** (Schwartz 1956; Richards 2014, sec. 6.4; Shnidman 1998). A dwell has N trials; each
trial is one pulse or one CPI of ``n_p`` (``pulses_per_trial``) noncoherently integrated
square-law pulses, whose statistic is ``Gamma(n_p, 1)`` under noise (unit noise power per
pulse) and is compared with a threshold T set for a per-trial false-alarm probability p_f,
``Q(n_p, T) = p_f``. A detection is declared when at least M of the N trials cross. With

    B(p) = P(Bin(N, p) >= M) = sum_{k=M}^{N} C(N, k) p^k (1-p)^(N-k) = I_p(M, N-M+1)        (1)

(``I`` the regularized incomplete beta function) the overall false-alarm probability is
``Pfa = B(p_f)``, and p_f is found by inverting (1). S is the mean per-pulse SNR (linear,
``snr_db = 10 log10 S``) and ``p_d(S)`` the per-trial detection probability of
:func:`diffsense.detection.core.pd_given_threshold` at the threshold T.

* Swerling 0 (steady), 2 and 4 (independent RCS from pulse to pulse, hence from trial to
  trial): the trials are independent, ``Pd = B(p_d(S))`` with the per-trial law of the case.
* Swerling 1 and 3 (one RCS draw sigma for the whole dwell, shared by all N trials, chi-square
  with 2 and 4 degrees of freedom, mean 1): ``Pd = E_sigma[G(S sigma)]``, ``G(x) = B(p_0(x))``
  with ``p_0`` the steady-target per-trial probability.

**Binomial law.** Both tails of (1) are summed term by term (Loader's saddle-point form of the
binomial probabilities, ``_logpmf.log_binomial_pmf``, full relative accuracy), from the smaller
of p and 1 - p as computed (the per-trial miss probability ``1 - p_d`` comes from the series of
``core.py`` directly, so 1 - Pd keeps its digits when Pd is near 1). Derivatives:
``B'(p) = N P(Bin(N-1, p) = M-1)`` (the Beta(M, N-M+1) density) and
``B''(p) = N (N-1) [P(Bin(N-2, p) = M-2) - P(Bin(N-2, p) = M-1)]``.

**Inversion** (p_f from Pfa; for Swerling 0/2/4 also the per-trial p_d from Pd). Newton's
method on ``log B(e^u) = log target`` in ``u = log p`` (derivative ``M P(Bin = M) / B``),
safeguarded by bisection inside ``C(N, M) p^M >= B(p) >= p^N``, i.e.
``u in [(log target - log C(N, M)) / M, log(target) / N]``; targets above 1/2 are solved for
``1 - p`` through ``P(Bin(N, 1-p) >= N-M+1) = 1 - target``. Implicit derivative
``dp = d target / B'(p)``. M = N gives ``p = target^(1/N)``, M = 1 ``p = 1 - (1 - target)^(1/N)``.

**Shared RCS (Swerling 1, 3).** Integrating by parts in ``v = log x`` (x the per-pulse SNR of a
trial, ``s = log S``) turns the average into

    Pd - Pfa = int g(v) S_sigma(e^(v-s)) dv,     1 - Pd = int g(v) F_sigma(e^(v-s)) dv,       (2)

with ``g = dG/dv = B'(p_0(x)) x dp_0/dx`` and ``S_sigma``, ``F_sigma`` the survival and
distribution functions of the RCS: ``exp(-y)`` (Swerling 1) and ``(1 + 2y) exp(-2y)``
(Swerling 3; ``F_sigma`` by its power series below y = 1/4, so that it keeps its relative
accuracy when small). Three properties make (2) exact to round-off with a fixed rule: g does
not depend on S (one grid serves every SNR and every step of the root finder); g is a smooth
bump that decays like ``c0 e^v`` to the left (``c0 = B'(p_f) n_p pois(n_p; T)``) and faster
than exponentially to the right, while the weights are bounded, smooth functions of v - s
(analytic in the strip |Im v| < pi/2); and both integrands are positive, so Pd - Pfa and 1 - Pd
each keep their relative accuracy. (2) is summed by the trapezoidal rule on 2048 equally spaced
nodes, exponentially convergent for such integrands (Trefethen & Weideman 2014), on
``[v0, v1]``: v0 where ``c0 e^v0 = 1e-17`` (the mass of g left out; clipped to [-60, -8]), v1
where ``1 - G <= C(N, M-1) miss^(N-M+1) <= 1e-17`` by the Chernoff bound of the per-trial miss
probability ``miss(x) <= exp(T - n_p log 2 - n_p x / 2)``. The spans stay below 45 (node spacing
below 0.022); the sharpest g found (N = 100, M = 1, n_p = 100, Pfa = 1e-12) needs a spacing
of 0.025 for 1e-15 (measured by halving it). The weights are rescaled so that they sum to
``1 - Pfa`` exactly (a change of 1e-15, at most 3.6e-14), so that the two forms of (2) agree.

**Required SNR.** Swerling 0/2/4: the per-trial p_d* = B^-1(Pd) (inversion above), then the
single-trial requirement for p_d* at p_f with n_p pulses from the exact solver of
:mod:`diffsense.detection.required_snr` (its implicit derivatives included). Swerling 1/3:
safeguarded Newton iteration in s on the logarithm of the smaller of Pd - Pfa and 1 - Pd, both
from (2) on the grid (bracket +-300 dB, step tolerance 1e-13), started from G taken as a step at
the median of g.

**Derivatives** are analytic (``jax.custom_jvp``), never through an iteration. For (2):
``dPd/ds = int g rho(v - s) dv`` (rho the density of log sigma) and
``dPd/dT = -int dg/dT F_sigma dv`` (= dG(0)/dT + int dg/dT S_sigma dv, used where Pd < 1/2),
where the mixed derivative of the steady per-trial law follows from first derivatives,
``d^2 p_0 / dx dT = -n_p dp_0/dT - dp_0/dx`` (from ``d pois(a; T)/dT = pois(a-1; T) - pois(a; T)``
in the Poisson mixture of ``core.py``). The required SNR is differentiated implicitly,
``ds = (dPd - dPd/dT dT) / (dPd/ds)``. Pfa enters through p_f and T (both implicit). The counts
N, M and n_p are not differentiable: a derivative with respect to one of them is NaN.

**Domain.** ``1e-15 <= Pfa <= 0.1``; integers ``1 <= M <= N <= 100`` and
``1 <= pulses_per_trial <= 100``; any finite SNR (held at its limits beyond +-300 dB);
required SNR for ``Pfa < Pd <= 1 - 1e-6``. An eager call outside raises
:class:`~diffsense.errors.DomainError`, a traced call returns NaN (``_domain``).

**Accuracy** (float64; measured against mpmath at 30 digits over the grids of
tests/detection/test_binary.py, slow ones included: Pfa 1e-12 ... 1e-2, Pd 0.1 ... 0.999,
N 1 ... 100 with M from 1 to N, 1 and 10 pulses per trial, and 100 for the shared-RCS cases):

* per-trial p_f: relative error <= 2.2e-15;
* Pd, Swerling 0, 2, 4: |error| <= 6.2e-14 (the per-trial round-off of ``core.py`` times dB/dp,
  up to ~8 at N = 100); Swerling 1, 3: |error| <= 1.5e-15;
* required SNR: <= 7.3e-13 dB (Swerling 0, 2, 4; the reference is bracketed to 1e-12 dB) and
  <= 4.0e-13 dB (Swerling 1, 3), against the 1e-9 dB target.

The trapezoidal rule with 2048 nodes agrees with 16384 nodes to 1.1e-15 in Pd and 4e-15
relative in 1 - Pd over 360 combinations of Pfa (1e-15 ... 0.1), N, M and n_p (1 ... 100)
at SNRs from 8 dB below to 15 dB above the median of g. For the shared-RCS required SNR the
left end of the grid (mass 1e-17 left out) bounds the relative error of Pd - Pfa by
~1e-17 / (Pd - Pfa), i.e. the 1e-9 dB holds for Pd - Pfa above ~1e-7.

**Optimum M.** The M minimizing the required SNR agrees with Shnidman's (1998) fit
``M_opt = 10^b N^a`` (a = 0.8, b = -0.02 for Swerling 0, 1, 3; 0.91, -0.38 for Swerling 2;
0.873, -0.27 for Swerling 4; quoted by Richards 2014 and, as ``0.955 N^0.8``, the default M of
MathWorks' ``binaryintloss``) to within 1 for N = 5 ... 100 (steady target, Pd = 0.9,
Pfa = 1e-6: 3, 6, 10, 21, 37 at N = 5, 10, 20, 50, 100); for fluctuating targets the fit is
looser (Swerling 2, N = 50: 12 against 14.7, where the fit's M costs 0.036 dB). The older rule ``M_opt ~ 1.5 sqrt(N)`` (Schwartz 1956, as quoted by Skolnik) gives fewer: at N =
10, 24 and 100 the exact optimum is 6, 12 and 37 against 4.7, 7.3 and 15 (using M = 7 at N = 24
costs 0.40 dB). MathWorks' example ``binaryintloss(0.9, 1e-6, 24, 12) = 1.0596`` dB is
reproduced as the exact 12-of-24 requirement (3.7194 dB) minus Shnidman's estimate of the
24-pulse noncoherent requirement (2.6598 dB); against the exact 24-pulse value (2.6397 dB) the
loss is 1.0797 dB.

Sources
-------
- M. Schwartz, "A coincidence procedure for signal detection", IRE Trans. Inform. Theory IT-2,
  135-139 (1956) (M-of-N detection; ``M_opt ~ 1.5 sqrt(N)``, as quoted in M. I. Skolnik,
  *Introduction to Radar Systems*, 3rd ed., McGraw-Hill, 2001).
- D. A. Shnidman, "Binary integration for Swerling target fluctuations", IEEE Trans. AES 34(3),
  1043-1053 (1998) (Swerling cases with binary integration; the fit of M_opt).
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed., McGraw-Hill (2014),
  sec. 6.4 (binary integration), and "Binary Integration Gain", technical memo (2016; rev.
  2017) (per-trial probabilities by binomial inversion, then the single-trial SNR).
- L. N. Trefethen and J. A. C. Weideman, "The exponentially convergent trapezoidal rule", SIAM
  Review 56(3), 385-458 (2014).
- C. Loader, "Fast and accurate computation of binomial probabilities" (2000).
- MathWorks Radar Toolbox documentation, ``binaryintloss`` (R2021a and later).
"""


from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
from jax.custom_derivatives import SymbolicZero

from diffsense.errors import DomainError
from diffsense.numerics.checks import is_concrete
from diffsense.numerics.db import from_db10
from diffsense.detection._binary_shared import SAT_DB, _pd_shared, _required_shared
from diffsense.detection._binary_trials import N_MAX, _binomial_level, _pd_independent
from diffsense.detection._domain import admit, guard
from diffsense.detection._precision import as_float
from diffsense.detection.required_snr import _required_snr
from diffsense.detection.threshold import _threshold

__all__ = ["pd_binary", "required_snr_binary_db", "optimum_m_binary", "per_trial_pfa_binary"]

PULSES_MAX = 100
PFA_RANGE = (1e-15, 0.1)
PD_MAX = 1.0 - 1e-6


@jax.custom_jvp
def _with_counts(value, *counts):
    """``value``, marked as depending on integer counts: its derivative in a count is NaN.

    The counts (N, M, pulses per trial) enter the computation through ``stop_gradient``; this
    wrapper makes a derivative taken with respect to one of them NaN rather than a made-up 0.
    """
    return value


def _with_counts_jvp(primals, tangents):
    value = primals[0]
    out = jnp.zeros_like(value) if isinstance(tangents[0], SymbolicZero) else tangents[0]
    for dc in tangents[1:]:
        if not isinstance(dc, SymbolicZero):
            out = out + jnp.nan * jnp.broadcast_to(dc, jnp.broadcast_shapes(jnp.shape(dc), jnp.shape(value)))
    return value, out


_with_counts.defjvp(_with_counts_jvp, symbolic_zeros=True)


def _swerling_case(where, swerling):
    if swerling not in (0, 1, 2, 3, 4, 5):
        raise ValueError(f"{where}: swerling must be one of (0, 1, 2, 3, 4, 5); got {swerling!r}")
    return 0 if swerling == 5 else int(swerling)


def _integral(name, x, where):
    """Mask of integer-valued elements; DomainError for a concrete non-integer."""
    if is_concrete(x):
        a = np.asarray(x, dtype=float)
        bad = np.isfinite(a) & (a != np.floor(a))
        if np.any(bad):
            raise DomainError(f"{where}: argument '{name}' must be an integer; got {float(a[bad].flat[0])!r}")
    return x == jnp.floor(x)


def _admit_counts(where, n, m, n_p=None):
    """Domain of the counts: integers 1 <= m <= n <= N_MAX, 1 <= n_p <= PULSES_MAX."""
    constraints = [("n", n, 1.0, float(N_MAX)), ("m", m, 1.0, None)]
    if n_p is not None:
        constraints.append(("pulses_per_trial", n_p, 1.0, float(PULSES_MAX)))
    ok, _ = admit(where, constraints)
    if is_concrete(n) and is_concrete(m) and np.any(np.asarray(m, dtype=float) > np.asarray(n, dtype=float)):
        raise DomainError(f"{where}: argument 'm' must not exceed 'n'")
    ok = ok & (m <= n) & _integral("n", n, where) & _integral("m", m, where)
    if n_p is not None:
        ok = ok & _integral("pulses_per_trial", n_p, where)
    return ok


def per_trial_pfa_binary(pfa, n, m):
    """Per-trial false-alarm probability p_f of an M-of-N detector with overall false alarm ``pfa``.

    Solves ``P(Bin(N, p_f) >= M) = I_{p_f}(M, N-M+1) = pfa`` (module docstring: Newton's method
    on the logarithm in log p_f, bracketed by the binomial bounds; implicit derivative
    ``dp_f/dpfa = 1 / (N P(Bin(N-1, p_f) = M-1))``).

    Args:
        pfa: overall false-alarm probability, 1e-300 <= pfa < 1.
        n: number of trials N, integer 1 ... 100.
        m: trials that must cross, integer 1 <= M <= N.

    Returns:
        p_f (dimensionless). Measured relative error against a 30-digit mpmath inversion
        <= 2.2e-15 (N = 1 ... 100, Pfa 1e-12 ... 1e-2); M = N and M = 1 agree with
        ``pfa^(1/N)`` and ``1 - (1 - pfa)^(1/N)`` to 1e-14. Differentiable in ``pfa``.

    Example: 12 of 24 at Pfa = 1e-6 needs p_f = 0.1015 per trial, which scipy's independent
    binomial survival function maps back to 1e-6; 24 of 24 needs Pfa^(1/24):

    >>> from scipy.stats import binom
    >>> pf = float(per_trial_pfa_binary(1e-6, 24, 12))
    >>> pf, float(binom.sf(11, 24, pf))
    (0.1015253, 1.0e-06)
    >>> float(per_trial_pfa_binary(1e-6, 24, 24)), 1e-6 ** (1 / 24)
    (0.5623413, 0.5623413)
    """
    where = "per_trial_pfa_binary"
    pfa, n, m = jnp.broadcast_arrays(*as_float(pfa, n, m))
    ok_p, _ = admit(where, [("pfa", pfa, 1e-300, 1.0, False, True)])
    ok = ok_p & _admit_counts(where, n, m)
    pfa, n, m = guard(pfa, ok, 1e-6), guard(n, ok, 1.0), guard(m, ok, 1.0)
    return guard(_per_trial_pfa_jit(pfa, n, m), ok)


@jax.jit
def _per_trial_pfa_jit(pfa, n, m):
    stop = jax.lax.stop_gradient
    return _with_counts(_binomial_level(pfa, stop(n), stop(m))[0], n, m)


def pd_binary(snr_db, pfa, n, m, swerling=0, pulses_per_trial=1):
    """Detection probability of M-of-N binary integration (module docstring for the model).

    ``Pd = P(Bin(N, p_d(S)) >= M)`` for Swerling 0, 2, 4 (independent trials) and
    ``Pd = E_sigma[P(Bin(N, p_0(S sigma)) >= M)]`` for Swerling 1, 3 (one RCS draw for the dwell,
    exact trapezoidal quadrature of eq. (2)); per-trial threshold from p_f =
    :func:`per_trial_pfa_binary`.

    Args:
        snr_db: mean per-pulse SNR in dB, any finite value (Pd is Pfa or 1 beyond +-300 dB).
        pfa: overall false-alarm probability of the M-of-N decision, 1e-15 ... 0.1.
        n: trials N (integer 1 ... 100); m: trials that must cross (integer 1 ... N).
        swerling: 0 (steady; 5 is a synonym), 1, 2, 3 or 4 — static.
        pulses_per_trial: pulses integrated noncoherently in each trial (integer 1 ... 100).

    Returns:
        Pd. Measured against 30-digit mpmath (tests/detection/test_binary.py): |error| <= 6.2e-14
        for Swerling 0, 2, 4 (the per-trial round-off of ``core.py`` times dB/dp) and <= 1.5e-15
        for Swerling 1, 3. Differentiable in ``snr_db`` and ``pfa`` (analytic derivatives); the
        counts are not (NaN). Eagerly an argument outside the domain raises DomainError; traced,
        the result is NaN.

    Examples: a steady target at 8 dB, one pulse per trial, 3 of 10 at Pfa = 1e-6 — the per-trial
    probability from scipy's noncentral chi-square (Marcum Q) and its binomial survival function;
    one trial of a Swerling 1 target is the closed form ``Pfa^(1/(1+S))``:

    >>> import math
    >>> from scipy.stats import binom, ncx2
    >>> p = ncx2.sf(-2 * math.log(float(per_trial_pfa_binary(1e-6, 10, 3))), 2, 2 * 10 ** 0.8)
    >>> float(pd_binary(8.0, 1e-6, 10, 3)), float(binom.sf(2, 10, p))
    (0.97966652456, 0.97966652456)
    >>> float(pd_binary(20.0, 1e-6, 1, 1, swerling=1)), 1e-6 ** (1 / 101)
    (0.87215577214, 0.87215577214)
    """
    where = "pd_binary"
    swerling = _swerling_case(where, swerling)
    snr_db, pfa, n, m, n_p = as_float(snr_db, pfa, n, m, pulses_per_trial)
    ok_s, _ = admit(where, [("snr_db", snr_db, -np.inf, np.inf, True, True)])
    pfa, n, m, n_p = jnp.broadcast_arrays(pfa, n, m, n_p)
    ok_p, _ = admit(where, [("pfa", pfa, *PFA_RANGE)])
    ok_struct = ok_p & _admit_counts(where, n, m, n_p)
    snr_db = guard(snr_db, ok_s, 0.0)
    pfa, n, m, n_p = (guard(a, ok_struct, f) for a, f in ((pfa, 1e-6), (n, 1.0), (m, 1.0), (n_p, 1.0)))
    return guard(_pd_binary_jit(snr_db, pfa, n, m, n_p, swerling), ok_s & ok_struct)


def _counted(value_fn, first, pfa, n, m, n_p, swerling):
    """``value_fn`` with the counts held out of differentiation (:func:`_with_counts`)."""
    held = map(jax.lax.stop_gradient, (n, m, n_p))
    return _with_counts(value_fn(first, pfa, *held, swerling), n, m, n_p)


@partial(jax.jit, static_argnums=5)
def _pd_binary_jit(snr_db, pfa, n, m, n_p, swerling):
    return _counted(_pd_binary_value, snr_db, pfa, n, m, n_p, swerling)


def _pd_binary_value(snr_db, pfa, n, m, n_p, swerling):
    p_f = _binomial_level(pfa, n, m)[0]
    t = _threshold(p_f, n_p)
    q0 = jax.lax.stop_gradient(p_f)
    x = from_db10(jnp.clip(snr_db, -SAT_DB, SAT_DB))
    if swerling in (1, 3):
        shape = jnp.broadcast_shapes(x.shape, pfa.shape)
        out = _pd_shared(x, t, n_p, q0, jax.lax.stop_gradient(pfa), n, m, swerling)
        return jnp.broadcast_to(out, shape)
    x, t, n_p, q0, n, m = jnp.broadcast_arrays(x, t, n_p, q0, n, m)
    return _pd_independent(x, t, n_p, q0, n, m, swerling)


def required_snr_binary_db(pd, pfa, n, m, swerling=0, pulses_per_trial=1):
    """Per-pulse SNR (dB) at which M-of-N binary integration reaches detection probability ``pd``.

    Swerling 0/2/4: the single-trial requirement for the per-trial ``p_d* = B^-1(pd)`` at
    ``p_f = B^-1(pfa)`` (``required_snr``'s exact solver); Swerling 1/3: Newton's method on the
    quadrature grid of eq. (2). Derivatives are implicit (module docstring).

    Args:
        pd: required detection probability, pfa < pd <= 1 - 1e-6.
        pfa: overall false-alarm probability, 1e-15 ... 0.1.
        n, m: integers 1 <= M <= N <= 100.
        swerling: 0 (= 5), 1, 2, 3, 4 — static.
        pulses_per_trial: integer 1 ... 100.

    Returns:
        The mean per-pulse SNR in dB. Measured against 30-digit mpmath over Pd 0.1 ... 0.999,
        Pfa 1e-12 ... 1e-2, N up to 100: within 7.3e-13 dB (target 1e-9 dB; module docstring).

    Example: MathWorks' ``binaryintloss(0.9, 1e-6, 24, 12) = 1.0596`` dB is this requirement
    less Shnidman's estimate for noncoherent integration of the 24 pulses; one trial of a
    Swerling 1 target has the closed form ``S = ln Pfa / ln Pd - 1``:

    >>> import math
    >>> from diffsense.detection import shnidman_snr_db
    >>> x = float(required_snr_binary_db(0.9, 1e-6, 24, 12))
    >>> x, round(x - float(shnidman_snr_db(0.9, 1e-6, 24)), 4)
    (3.7194117, 1.0596)
    >>> float(required_snr_binary_db(0.9, 1e-6, 1, 1, swerling=1)), 10 * math.log10(math.log(1e-6) / math.log(0.9) - 1)
    (21.1436432, 21.1436432)
    """
    where = "required_snr_binary_db"
    swerling = _swerling_case(where, swerling)
    pd, pfa, n, m, n_p = jnp.broadcast_arrays(*as_float(pd, pfa, n, m, pulses_per_trial))
    ok_p, _ = admit(where, [("pfa", pfa, *PFA_RANGE), ("pd", pd, 0.0, PD_MAX, True, False)],
                    greater=[("pd", pd, "pfa", pfa)])
    ok = ok_p & _admit_counts(where, n, m, n_p)
    pd, pfa, n, m, n_p = (guard(a, ok, f) for a, f in ((pd, 0.5), (pfa, 1e-6), (n, 1.0), (m, 1.0), (n_p, 1.0)))
    return guard(_required_jit(pd, pfa, n, m, n_p, swerling), ok)


@partial(jax.jit, static_argnums=5)
def _required_jit(pd, pfa, n, m, n_p, swerling):
    return _counted(_required_value, pd, pfa, n, m, n_p, swerling)


def _required_value(pd, pfa, n, m, n_p, swerling):
    p_f = _binomial_level(pfa, n, m)[0]
    if swerling in (1, 3):
        t = _threshold(p_f, n_p)
        return _required_shared(pd, t, n_p, jax.lax.stop_gradient(p_f), jax.lax.stop_gradient(pfa), n, m, swerling)
    p_star = _binomial_level(pd, n, m)[0]
    return _required_snr(p_star, p_f, n_p, swerling)


def optimum_m_binary(pd, pfa, n, swerling=0, pulses_per_trial=1):
    """The M (1 <= M <= N) that minimises the per-pulse SNR required for ``pd`` at ``pfa``.

    Evaluates :func:`required_snr_binary_db` for every M = 1 ... N in one call and returns the
    smallest minimiser (an int). Concrete scalar arguments only (not traceable); domain as for
    :func:`required_snr_binary_db`. Checked against a brute-force 30-digit mpmath search; it
    follows Shnidman's (1998) fit ``M_opt = 10^b N^a`` (module docstring).

    Example: 24 trials, steady target, Pd = 0.9, Pfa = 1e-6: Shnidman's fit gives
    ``10^-0.02 24^0.8 = 12.1``:

    >>> optimum_m_binary(0.9, 1e-6, 24)
    12
    """
    where = "optimum_m_binary"
    swerling = _swerling_case(where, swerling)
    for name, value in (("pd", pd), ("pfa", pfa), ("n", n), ("pulses_per_trial", pulses_per_trial)):
        if not is_concrete(value) or np.ndim(value) != 0:
            raise DomainError(f"{where}: argument '{name}' must be a concrete scalar")
    n_int = int(n)
    if n_int != n or not 1 <= n_int <= N_MAX:
        raise DomainError(f"{where}: argument 'n' must be an integer in [1, {N_MAX}]; got {n!r}")
    # all M of one call, padded to N_MAX elements so that every N reuses one compiled program
    ms = np.minimum(np.arange(1.0, N_MAX + 1.0), n_int)
    x = np.asarray(required_snr_binary_db(pd, pfa, float(n_int), ms, swerling, pulses_per_trial))[:n_int]
    return int(np.argmin(x)) + 1
