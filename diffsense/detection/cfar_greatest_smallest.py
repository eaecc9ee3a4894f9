"""Greatest-of and smallest-of CFAR (GO-CFAR, SO-CFAR), single pulse, exact.

Model. As in :mod:`diffsense.detection.cfar_ordered`: one square-law sample per cell, noise of
unit mean, so that every reference cell is exponential with mean 1 under noise alone. The
``n`` reference cells (n even) are split into a leading and a lagging half window of
``m = n/2`` cells; their sums ``Z1, Z2`` are independent ``Gamma(m, 1)``. GO-CFAR (Hansen &
Sawyers 1980) estimates the noise by ``X = max(Z1, Z2)``, SO-CFAR (Trunk 1978; Weiss 1982) by
``X = min(Z1, Z2)``, and the cell under test ``Y`` is declared a detection when ``Y > T X``.
``T`` multiplies a half-window *sum*; on the half-window *average* the multiplier is ``m T``
(the convention of Richards' ``alpha_GO``). ``S`` is the mean SNR of the cell under test.

The law of the estimate, exact in closed form (``f_m``, ``P(m, .)``, ``Q(m, .)``: the
Gamma(m, 1) density and regularized incomplete gamma functions; ``I_x(a, b)`` the regularized
incomplete beta function, for integers ``P(Binomial(a + b - 1, x) >= a)``):

* density ``2 f_m(x) P(m, x)`` (GO) or ``2 f_m(x) Q(m, x)`` (SO);
* Laplace transform ``L(c) = E[exp(-c X)]``: tilting one half-window sum by ``exp(-c Z)`` makes
  it ``Gamma(m)/(1 + c)``, and the event ``Z_other < Z`` (GO) becomes a beta probability::

      L_GO(c) = 2 (1 + c)^(-m) I_{1/(2+c)}(m, m),
      L_SO(c) = 2 (1 + c)^(-m) I_{(1+c)/(2+c)}(m, m)

  (their sum is ``2 (1 + c)^(-m)``, twice the CA transform of one half window); equal to the
  sums of Gandhi & Kassam (1988), e.g. ``L_SO(c) = 2 sum_{i<m} C(m-1+i, i) (2+c)^(-(m+i))``;
* tilted mean ``E[X exp(-c X)] / L(c)``, the same way with ``Z f_m(Z) = m f_{m+1}(Z)``:
  ``m/(1+c) I_{1/(2+c)}(m, m+1) / I_{1/(2+c)}(m, m)`` (GO) and
  ``m/(1+c) I_{(1+c)/(2+c)}(m+1, m) / I_{(1+c)/(2+c)}(m, m)`` (SO);
* distribution function ``P(m, x)^2`` (GO, ``~ x^(2m)`` at 0) and ``1 - Q(m, x)^2 = P(m, x)
  (1 + Q(m, x))`` (SO, ``~ x^m``), with ``Q(m, x) = e^-x sum_{j<m} x^j/j!`` and ``P(m, x)`` from
  its series ``e^-x sum_{j>=m} x^j/j!`` for ``x < m`` (truncated where the remaining terms are
  below e^-40 of the sum) and ``1 - Q`` otherwise (then ``Q < 1/2``), all positive terms in the
  log domain.

Everything else is the engine :mod:`diffsense.detection._cfar_engine` applied to this law:
``Pfa = L(T)`` (Weiss 1982; Gandhi & Kassam 1988), the multiplier by safeguarded Newton
iteration on ``log T`` inside the bracket given by ``Z1 + Z2 >= max >= (Z1 + Z2)/2 >= min``,
``min <= Z1`` and ``L_SO <= 2 (1 + T)^-m`` (GO: ``a <= T <= 2 a`` with ``a = Pfa^(-1/n) - 1``;
SO: ``Pfa^(-1/m) - 1 <= T <= (2/Pfa)^(1/m) - 1``); Swerling 1/2 ``Pd = L(T/(1+S))`` and
Swerling 3/4 ``Pd = L(c) (1 + b0 T mu(c))`` in closed form; Swerling 0 ``Pd = E_Y[F(Y/T)]``
by a 64-node trapezoidal rule; required SNR in closed form for Swerling 1/2 (``S = T(Pfa)/T(Pd)
- 1``) and by implicitly differentiated Newton iteration otherwise; loss against
:func:`diffsense.detection.required_snr_db` with one pulse.

Homogeneous noise (Richards sec. 6.5.5, after Hansen & Sawyers 1980 and Weiss 1982): both
split-window detectors lose more than CA-CFAR with the same n cells; GO-CFAR's extra loss is
small, SO-CFAR's larger, the more so the fewer the cells. tests/detection/
test_cfar_greatest_smallest.py checks CA < GO < SO in loss.

Static structure. ``n_cells`` is a static, even Python int (>= 2); other arguments may be
traced arrays. One compiled program serves GO and SO and all n <= 128 (padded tables). Single
pulse only (no noncoherent integration). SO-CFAR is poor with few cells (at n = 8 and Pfa =
1e-12 the multiplier is ~1.2e3), but the formulas stay exact.

Accuracy (measured in tests/detection/test_cfar_greatest_smallest.py against 30-digit mpmath
references: Gandhi & Kassam's / Weiss's sums and their roots, mpmath quadrature of the
definition ``E_X[Pd_fixed(T X)]`` over the density of the estimate, with the Marcum Q
function from its Poisson series; n = 8-64, Pfa 1e-12 ... 1e-2, Pd 0.1 ... 0.999, SNR -5 ...
35 dB): see the public functions.

Sources
-------
- V. G. Hansen and J. H. Sawyers, "Detectability loss due to 'greatest of' selection in a
  cell-averaging CFAR", IEEE Trans. AES 16(1), 115-118 (1980).
- G. V. Trunk, "Range resolution of targets using automatic detectors", IEEE Trans. AES 14(5),
  750-755 (1978) (smallest-of selection).
- M. Weiss, "Analysis of some modified cell-averaging CFAR processors in multiple-target
  situations", IEEE Trans. AES 18(1), 102-114 (1982).
- P. P. Gandhi and S. A. Kassam, "Analysis of CFAR processors in nonhomogeneous background",
  IEEE Trans. AES 24(4), 427-445 (1988).
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed. (McGraw-Hill, 2014), sec.
  6.5.5 (SOCA/GOCA CFAR; eq. 6.155 and the example N = 20: alpha_GO = 7.24 on the half-window
  average, at the Pfa of 1e-3 of the section's examples).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.special import gammaln

from diffsense.detection._cfar_engine import (
    law_loss_db,
    binomial_tail_table,
    binomial_tail_table_traced,
    log_binomial_tail,
    log_expm1,
    logsumexp,
    loss_api,
    multiplier_api,
    padded,
    pd_api,
    pfa_api,
    required_snr_api,
    static_int,
    table_length,
)
from diffsense.errors import DomainError

__all__ = [
    "go_cfar_multiplier",
    "go_cfar_pfa",
    "go_cfar_pd",
    "go_cfar_required_snr_db",
    "go_cfar_loss_db",
    "so_cfar_multiplier",
    "so_cfar_pfa",
    "so_cfar_pd",
    "so_cfar_required_snr_db",
    "so_cfar_loss_db",
    "split_window_cfar_loss_db_traced",
]

#: most cells per half window of :func:`split_window_cfar_loss_db_traced` (its tables' lengths)
TRACED_MAX_HALF_WINDOW = 32

_LOG2 = math.log(2.0)


# --------------------------------------------------------------------------------------
# The law of the greatest / smallest half-window sum
# --------------------------------------------------------------------------------------


def _series_length(m: int) -> int:
    """Terms of sum_{j>=m} x^j/j! for x < m: the ratio of term m+J to term m is below
    prod_{i<=J} m/(m+i) <= exp(-J^2/(2(m+J))) < e^-40 for this J."""
    return int(math.ceil(40.0 + math.sqrt(1600.0 + 80.0 * m))) + 1


def _poisson_table(j_lo: int, j_hi: int):
    """Rows ``j`` and ``log j!`` for j = j_lo .. j_hi - 1, padded (j = 0, log j! = inf)."""
    j = np.arange(j_lo, j_hi, dtype=float)
    log_fact = [math.log(math.factorial(i)) for i in range(j_lo, j_hi)]  # correctly rounded
    length = table_length(len(j))
    return np.stack([padded(j, length, 0.0), padded(log_fact, length, np.inf)])


def _log_poisson_sum(table, log_x):
    """log sum_j x^j/j! over the table's terms."""
    return logsumexp(table[0] * log_x[..., None] - table[1])


@partial(jax.tree_util.register_dataclass,
         data_fields=["m", "greatest", "ibeta_table", "tilt_table", "q_table", "p_table"], meta_fields=[])
@dataclass(frozen=True)
class _HalfWindowExtreme:
    """Law of max (``greatest = 1``) or min (``greatest = 0``) of two independent Gamma(m, 1)
    sums, as arrays (a pytree): the binomial tails of ``I(m, m)`` and of the tilted mean's
    ``I(m, m+1)`` (GO) or ``I(m+1, m)`` (SO), and the Poisson terms of ``Q(m, .)`` and of the
    series of ``P(m, .)``."""

    m: object
    greatest: object
    ibeta_table: object
    tilt_table: object
    q_table: object
    p_table: object

    @property
    def cdf_power(self):
        return jnp.where(self.greatest > 0, 2.0 * self.m, self.m)

    def _beta_args(self, log_c):
        """log x and log(1 - x) of the incomplete beta argument 1/(2+c) (GO), (1+c)/(2+c) (SO),
        and log(1 + c)."""
        log_1c = jax.nn.softplus(log_c)  # log(1 + c)
        log_2c = _LOG2 + jax.nn.softplus(log_c - _LOG2)  # log(2 + c)
        small, large = -log_2c, log_1c - log_2c  # log(1/(2+c)), log((1+c)/(2+c))
        go = self.greatest > 0
        return jnp.where(go, small, large), jnp.where(go, large, small), log_1c

    def log_laplace(self, log_c):
        """log E[exp(-c X)] = log 2 - m log(1 + c) + log I_x(m, m)."""
        log_x, log_1mx, log_1c = self._beta_args(log_c)
        return _LOG2 - self.m * log_1c + log_binomial_tail(self.ibeta_table, log_x, log_1mx)

    def tilted_mean(self, log_c):
        """E[X exp(-c X)] / E[exp(-c X)] (module docstring)."""
        log_x, log_1mx, log_1c = self._beta_args(log_c)
        log_tilt = log_binomial_tail(self.tilt_table, log_x, log_1mx)
        log_ratio = log_tilt - log_binomial_tail(self.ibeta_table, log_x, log_1mx)
        return self.m * jnp.exp(log_ratio - log_1c)

    def log_cdf(self, log_x):
        """log P(X <= x): 2 log P(m, x) (GO), log P(m, x) + log(1 + Q(m, x)) (SO)."""
        x = jnp.exp(log_x)
        log_q = -x + _log_poisson_sum(self.q_table, log_x)
        use_series = x < self.m
        q = jnp.where(use_series, 0.5, jnp.exp(log_q))
        log_p = jnp.where(use_series, -x + _log_poisson_sum(self.p_table, log_x), jnp.log1p(-q))
        return jnp.where(self.greatest > 0, 2.0 * log_p, log_p + jnp.log1p(jnp.exp(log_q)))

    def log_multiplier_bracket(self, log_pfa):
        """Bracket of log T (module docstring)."""
        go_lo = log_expm1(-log_pfa / (2.0 * self.m))  # a = Pfa^(-1/n) - 1
        so_lo = log_expm1(-log_pfa / self.m)
        so_hi = log_expm1((_LOG2 - log_pfa) / self.m)
        go = self.greatest > 0
        return jnp.where(go, go_lo, so_lo), jnp.where(go, _LOG2 + go_lo, so_hi)


def _law(where, n_cells, greatest: bool):
    n = static_int(where, "n_cells", n_cells, 2)
    if n % 2:
        raise DomainError(f"{where}: argument 'n_cells' must be even (two half windows); got {n}")
    m = n // 2
    a, b = (m, m + 1) if greatest else (m + 1, m)
    return _HalfWindowExtreme(
        m=np.float64(m),
        greatest=np.float64(greatest),
        ibeta_table=binomial_tail_table(2 * m - 1, m, table_length(m + 1)),
        tilt_table=binomial_tail_table(a + b - 1, a, table_length(m + 1)),
        q_table=_poisson_table(0, m),
        p_table=_poisson_table(m, m + _series_length(m)),
    )


def _poisson_table_traced(j_lo, count, length: int):
    """:func:`_poisson_table` (``count`` terms from ``j_lo``) from numbers that may be traced."""
    j = j_lo + jnp.arange(float(length))
    inside = jnp.arange(float(length)) < count
    return jnp.stack([jnp.where(inside, j, 0.0), jnp.where(inside, gammaln(j + 1.0), jnp.inf)])


def _law_traced(half_window_cells, greatest: bool):
    """:class:`_HalfWindowExtreme` from a half-window size m that may be traced (integer, 1 <= m
    <= 32; ``log C`` and ``log j!`` from ``gammaln``, ~1e-14 relative, against the correctly
    rounded tables of :func:`_law`)."""
    m = jnp.asarray(half_window_cells, dtype=float)
    a, b = (m, m + 1.0) if greatest else (m + 1.0, m)
    series = jnp.ceil(40.0 + jnp.sqrt(1600.0 + 80.0 * m)) + 1.0  # :func:`_series_length`
    longest = _series_length(TRACED_MAX_HALF_WINDOW)
    return _HalfWindowExtreme(
        m=m,
        greatest=np.float64(greatest),
        ibeta_table=binomial_tail_table_traced(2.0 * m - 1.0, m, TRACED_MAX_HALF_WINDOW),
        tilt_table=binomial_tail_table_traced(a + b - 1.0, a, TRACED_MAX_HALF_WINDOW + 1),
        q_table=_poisson_table_traced(0.0, m, TRACED_MAX_HALF_WINDOW),
        p_table=_poisson_table_traced(m, series, longest),
    )


def split_window_cfar_loss_db_traced(pd, pfa, half_window_cells, greatest: bool, swerling=0):
    """GO-CFAR (``greatest=True``) or SO-CFAR loss (dB) as :func:`go_cfar_loss_db` /
    :func:`so_cfar_loss_db` with ``n_cells = 2 half_window_cells``, the half window a number that
    may be traced (a budget's parameter, integer 1 ... 32). No argument checks: the caller's
    parameter bounds hold pd and pfa (``pfa < pd <= 0.9999``, ``1e-100 <= pfa <= 0.5``) in the
    domain. Equal to the public functions to ~1e-12 dB (tables from ``gammaln``).

    >>> a = float(split_window_cfar_loss_db_traced(0.9, 1e-6, 8.0, True, swerling=1))
    >>> abs(a - float(go_cfar_loss_db(0.9, 1e-6, 16, swerling=1))) < 1e-12
    True
    """
    return law_loss_db(_law_traced(half_window_cells, greatest), swerling, pd, pfa)


# --------------------------------------------------------------------------------------
# Public API: GO-CFAR
# --------------------------------------------------------------------------------------


def go_cfar_multiplier(pfa, n_cells):
    """GO-CFAR multiplier ``T``: detection when ``Y > T max(Z1, Z2)`` (half-window sums).

    Root of ``Pfa = 2 (1 + T)^(-m) I_{1/(2+T)}(m, m)``, ``m = n/2`` (Weiss 1982; Gandhi &
    Kassam 1988), by safeguarded Newton iteration in ``log T`` (relative error ~1e-15),
    implicitly differentiated in ``pfa``.

    Args:
        pfa: false-alarm probability, 1e-100 <= pfa < 1 (array).
        n_cells: reference cells n in both half windows together (static even int >= 2).

    Returns:
        ``T`` on the half-window sum (``m T`` on the half-window average).

    Richards, *Fundamentals of Radar Signal Processing*, sec. 6.5.5: N = 20 and Pfa = 1e-3
    give alpha_GO = 7.24 on the average of a half window, i.e. 10 T:

    >>> round(10 * float(go_cfar_multiplier(1e-3, 20)), 2)
    7.24
    """
    where = "go_cfar_multiplier"
    return multiplier_api(where, _law(where, n_cells, True), pfa)


def go_cfar_pfa(multiplier, n_cells):
    """False-alarm probability of GO-CFAR, ``2 (1 + T)^(-m) I_{1/(2+T)}(m, m)``.

    Args:
        multiplier: T > 0 on the half-window sum (array).
        n_cells: reference cells (static even int >= 2).

    Two cells (m = 1): the maximum of two unit exponentials has the distribution function
    ``(1 - e^-x)^2``, so that ``E[exp(-T max)] = 2/((1 + T)(2 + T))``:

    >>> float(go_cfar_pfa(3.0, 2)), 2 / (4 * 5)
    (0.1, 0.1)
    """
    where = "go_cfar_pfa"
    return pfa_api(where, _law(where, n_cells, True), multiplier)


def go_cfar_pd(snr_db, pfa, n_cells, swerling=0):
    """Detection probability of GO-CFAR for one square-law pulse per cell.

    Swerling 1/2: ``L_GO(T/(1 + S))`` (Gandhi & Kassam 1988); Swerling 3/4: closed form with the
    tilted mean; Swerling 0: 64-node trapezoidal rule over the Rician law of the cell under
    test (absolute error < 5e-15; :mod:`diffsense.detection.cfar_ordered`).

    Args:
        snr_db: mean SNR of the cell under test in dB (-100 ... 100).
        pfa: false-alarm probability, 1e-100 <= pfa < 1.
        n_cells: reference cells (static even int >= 2).
        swerling: 0-4 (static int; one pulse, so 1 = 2 and 3 = 4).

    Returns:
        Pd in [Pfa, 1].

    Swerling 1, n = 16: the false-alarm formula at ``T/(1 + S)``, written with scipy's
    incomplete beta function and an independent (Brent) multiplier:

    >>> from scipy.optimize import brentq
    >>> from scipy.special import betainc
    >>> pfa_go = lambda t: 2 * (1 + t) ** -8 * betainc(8, 8, 1 / (2 + t))
    >>> t = brentq(lambda t: pfa_go(t) / 1e-6 - 1, 0.1, 10.0, xtol=1e-15, rtol=1e-15)
    >>> float(go_cfar_pd(20.0, 1e-6, 16, swerling=1)), float(pfa_go(t / 101.0))
    (0.79670889, 0.79670889)
    """
    where = "go_cfar_pd"
    return pd_api(where, _law(where, n_cells, True), snr_db, pfa, swerling)


def go_cfar_required_snr_db(pd, pfa, n_cells, swerling=0):
    """SNR (dB) of one pulse at which GO-CFAR reaches ``pd``.

    Swerling 1/2 closed form ``S = T(Pfa)/T(Pd) - 1``; otherwise the implicitly differentiated
    root of ``go_cfar_pd = pd`` (converged to 1e-12 dB).

    Args:
        pd: detection probability, pfa < pd <= 0.9999.
        pfa: false-alarm probability, 1e-100 <= pfa < 1.
        n_cells: reference cells (static even int >= 2).
        swerling: 0-4 (static int).

    Returns:
        SNR in dB (NaN if the root lies outside [-100, 100] dB).

    Swerling 1 closed form from two independent (Brent) multipliers:

    >>> import math
    >>> from scipy.optimize import brentq
    >>> from scipy.special import betainc
    >>> pfa_go = lambda t: 2 * (1 + t) ** -8 * betainc(8, 8, 1 / (2 + t))
    >>> t_fa = brentq(lambda t: pfa_go(t) / 1e-6 - 1, 0.1, 10.0, xtol=1e-15, rtol=1e-15)
    >>> t_d = brentq(lambda t: pfa_go(t) / 0.9 - 1, 1e-6, 1.0, xtol=1e-17, rtol=1e-15)
    >>> float(go_cfar_required_snr_db(0.9, 1e-6, 16, swerling=1)), 10 * math.log10(t_fa / t_d - 1)
    (23.3823728, 23.3823728)
    """
    where = "go_cfar_required_snr_db"
    return required_snr_api(where, _law(where, n_cells, True), pd, pfa, swerling)


def go_cfar_loss_db(pd, pfa, n_cells, swerling=0):
    """GO-CFAR loss (dB): required SNR minus the known-noise single-pulse requirement.

    Args:
        pd: detection probability, pfa < pd <= 0.9999.
        pfa: false-alarm probability, 1e-100 <= pfa <= 0.5.
        n_cells: reference cells (static even int >= 2).
        swerling: 0-4 (static int).

    Returns:
        Loss in dB; a little above the CA-CFAR loss with the same n (Hansen & Sawyers 1980:
        less than 0.3 dB more over a wide range of parameters).

    Swerling 1 closed form ``10 log10[(T(Pfa)/T(Pd) - 1) / (ln Pfa / ln Pd - 1)]`` with
    independent (Brent) multipliers:

    >>> import math
    >>> from scipy.optimize import brentq
    >>> from scipy.special import betainc
    >>> pfa_go = lambda t: 2 * (1 + t) ** -8 * betainc(8, 8, 1 / (2 + t))
    >>> t_fa = brentq(lambda t: pfa_go(t) / 1e-6 - 1, 0.1, 10.0, xtol=1e-15, rtol=1e-15)
    >>> t_d = brentq(lambda t: pfa_go(t) / 0.9 - 1, 1e-6, 1.0, xtol=1e-17, rtol=1e-15)
    >>> closed = 10 * math.log10((t_fa / t_d - 1) / (math.log(1e-6) / math.log(0.9) - 1))
    >>> float(go_cfar_loss_db(0.9, 1e-6, 16, swerling=1)), closed
    (2.2387296, 2.2387296)
    """
    where = "go_cfar_loss_db"
    return loss_api(where, _law(where, n_cells, True), pd, pfa, swerling)


# --------------------------------------------------------------------------------------
# Public API: SO-CFAR
# --------------------------------------------------------------------------------------


def so_cfar_multiplier(pfa, n_cells):
    """SO-CFAR multiplier ``T``: detection when ``Y > T min(Z1, Z2)`` (half-window sums).

    Root of ``Pfa = 2 (1 + T)^(-m) I_{(1+T)/(2+T)}(m, m) = 2 sum_{i<m} C(m-1+i, i)
    (2+T)^(-(m+i))`` (Weiss 1982; Gandhi & Kassam 1988), by safeguarded Newton iteration in
    ``log T``, implicitly differentiated.

    Args:
        pfa: false-alarm probability, 1e-100 <= pfa < 1 (array).
        n_cells: reference cells (static even int >= 2).

    Returns:
        ``T`` on the half-window sum (``m T`` on the average).

    Two cells (m = 1): ``Pfa = 2/(2 + T)``, so ``T = 2/Pfa - 2``:

    >>> float(so_cfar_multiplier(1e-3, 2))
    1998.0
    """
    where = "so_cfar_multiplier"
    return multiplier_api(where, _law(where, n_cells, False), pfa)


def so_cfar_pfa(multiplier, n_cells):
    """False-alarm probability of SO-CFAR, ``2 sum_{i<m} C(m-1+i, i) (2+T)^(-(m+i))``.

    Args:
        multiplier: T > 0 on the half-window sum (array).
        n_cells: reference cells (static even int >= 2).

    Four cells (m = 2): ``2 (2+T)^-2 (1 + 2/(2+T))`` (Gandhi & Kassam's sum):

    >>> float(so_cfar_pfa(3.0, 4)), 2 / 25 * (1 + 2 / 5)
    (0.112, 0.112)
    """
    where = "so_cfar_pfa"
    return pfa_api(where, _law(where, n_cells, False), multiplier)


def so_cfar_pd(snr_db, pfa, n_cells, swerling=0):
    """Detection probability of SO-CFAR for one square-law pulse per cell.

    Swerling 1/2: ``L_SO(T/(1 + S))``; Swerling 3/4: closed form with the tilted mean;
    Swerling 0: 64-node trapezoidal rule (absolute error < 5e-15).

    Args:
        snr_db: mean SNR of the cell under test in dB (-100 ... 100).
        pfa: false-alarm probability, 1e-100 <= pfa < 1.
        n_cells: reference cells (static even int >= 2).
        swerling: 0-4 (static int).

    Returns:
        Pd in [Pfa, 1].

    Swerling 1, n = 16: Gandhi & Kassam's sum at ``T/(1 + S)``, independent (Brent) multiplier:

    >>> from math import comb
    >>> from scipy.optimize import brentq
    >>> pfa_so = lambda t: 2 * sum(comb(7 + i, i) * (2 + t) ** -(8 + i) for i in range(8))
    >>> t = brentq(lambda t: pfa_so(t) / 1e-6 - 1, 1.0, 100.0, xtol=1e-14, rtol=1e-15)
    >>> float(so_cfar_pd(20.0, 1e-6, 16, swerling=1)), pfa_so(t / 101.0)
    (0.7, 0.7)
    """
    where = "so_cfar_pd"
    return pd_api(where, _law(where, n_cells, False), snr_db, pfa, swerling)


def so_cfar_required_snr_db(pd, pfa, n_cells, swerling=0):
    """SNR (dB) of one pulse at which SO-CFAR reaches ``pd``.

    Args:
        pd: detection probability, pfa < pd <= 0.9999.
        pfa: false-alarm probability, 1e-100 <= pfa < 1.
        n_cells: reference cells (static even int >= 2).
        swerling: 0-4 (static int).

    Returns:
        SNR in dB (NaN if the root lies outside [-100, 100] dB).

    Swerling 1 closed form, multipliers from Gandhi & Kassam's sum (Brent roots):

    >>> import math
    >>> from scipy.optimize import brentq
    >>> pfa_so = lambda t: 2 * sum(math.comb(7 + i, i) * (2 + t) ** -(8 + i) for i in range(8))
    >>> t_fa = brentq(lambda t: pfa_so(t) / 1e-6 - 1, 1.0, 100.0, xtol=1e-14, rtol=1e-15)
    >>> t_d = brentq(lambda t: pfa_so(t) / 0.9 - 1, 1e-6, 1.0, xtol=1e-17, rtol=1e-15)
    >>> float(so_cfar_required_snr_db(0.9, 1e-6, 16, swerling=1)), 10 * math.log10(t_fa / t_d - 1)
    (25.0, 25.0)
    """
    where = "so_cfar_required_snr_db"
    return required_snr_api(where, _law(where, n_cells, False), pd, pfa, swerling)


def so_cfar_loss_db(pd, pfa, n_cells, swerling=0):
    """SO-CFAR loss (dB): required SNR minus the known-noise single-pulse requirement.

    Args:
        pd: detection probability, pfa < pd <= 0.9999.
        pfa: false-alarm probability, 1e-100 <= pfa <= 0.5.
        n_cells: reference cells (static even int >= 2).
        swerling: 0-4 (static int).

    Returns:
        Loss in dB; the largest of CA, GO and SO in homogeneous noise (Weiss 1982).

    >>> import math
    >>> from scipy.optimize import brentq
    >>> pfa_so = lambda t: 2 * sum(math.comb(7 + i, i) * (2 + t) ** -(8 + i) for i in range(8))
    >>> t_fa = brentq(lambda t: pfa_so(t) / 1e-6 - 1, 1.0, 100.0, xtol=1e-14, rtol=1e-15)
    >>> t_d = brentq(lambda t: pfa_so(t) / 0.9 - 1, 1e-6, 1.0, xtol=1e-17, rtol=1e-15)
    >>> closed = 10 * math.log10((t_fa / t_d - 1) / (math.log(1e-6) / math.log(0.9) - 1))
    >>> float(so_cfar_loss_db(0.9, 1e-6, 16, swerling=1)), closed
    (3.7779877, 3.7779877)
    """
    where = "so_cfar_loss_db"
    return loss_api(where, _law(where, n_cells, False), pd, pfa, swerling)
