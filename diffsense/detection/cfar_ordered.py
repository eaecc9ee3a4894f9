"""Order-statistic CFAR (OS-CFAR, Rohling 1983), single pulse, exact.

Model. One square-law sample per cell (no pulse integration), noise normalised to unit mean:
under noise alone every cell is exponential with mean 1. The cell under test ``Y`` is compared
with ``T X``, where ``X = X_(k)`` is the k-th smallest of the n reference cells (k = 1: the
minimum, k = n: the maximum; k near 3n/4 is the usual choice) and ``T`` the threshold
multiplier. ``S`` is the mean signal-to-noise ratio of the cell under test (linear;
``snr_db = 10 log10 S``).

The law of the estimate, exact:

* Laplace transform (Renyi's representation ``X_(k) = sum_{i<k} E_i/(n - i)`` with independent
  unit exponentials ``E_i``)::

      L(c) = E[exp(-c X_(k))] = prod_{i=0}^{k-1} (n - i) / (n - i + c);

* tilted mean ``E[X exp(-c X)] / L(c) = -d log L/dc = sum_{i<k} 1/(n - i + c)``;
* distribution function ``F(x) = P(Binomial(n, 1 - e^-x) >= k)`` (David & Nagaraja, sec.
  2.1), a finite sum of positive terms, with ``F(x) ~ x^k`` at 0 and elasticity
  ``x F'(x)/F(x) <= k`` (the density over ``x^(k-1)`` decreases).

False alarms: ``Pfa = L(T)`` (Rohling 1983; Gandhi & Kassam 1988 eq. 37 with S = 0). The
multiplier is the root of ``log L(T) = log Pfa`` inside ``(n - k + 1) a <= T <= n a``,
``a = Pfa^(-1/k) - 1`` (each factor of L lies between those of the smallest and the largest
``n - i``). Detection: Swerling 1/2 ``Pd = L(T/(1 + S))`` (Rohling 1983; Gandhi & Kassam 1988
eq. 37), Swerling 3/4 ``Pd = L(c) (1 + b0 T sum_{i<k} 1/(n - i + c))`` with ``c = T/(1 +
S/2)``, ``b0 = (S/2)/(1 + S/2)^2``, Swerling 0 ``Pd = E_Y[F(Y/T)]`` by a 64-node trapezoidal
rule over the Rician law of the cell under test; required SNR in closed form for Swerling 1/2
(``S = T(Pfa)/T(Pd) - 1``), otherwise by implicitly differentiated Newton iteration; loss
against :func:`diffsense.detection.required_snr_db` with one pulse. The derivations, the
quadrature and the derivatives are those of the engine, :mod:`diffsense.detection._cfar_engine`.

Static structure. ``n_cells`` and ``k`` are static Python ints; every other argument may be a
traced array and is broadcast. One compiled program serves all n <= 64 (the law's tables are
padded arrays). Only single-pulse detection is covered: noncoherent integration of N > 1
pulses per cell is not implemented.

Accuracy (measured in tests/detection/test_cfar_ordered.py against 30-digit mpmath references:
Rohling's product and its root, the exact discrete series and mpmath quadrature of the
definition ``E_X[Pd_fixed(T X)]`` with the Marcum Q function from its Poisson series;
n = 8-64, k = 1 ... n, Pfa 1e-12 ... 1e-2, Pd 0.1 ... 0.999, SNR -5 ... 35 dB): see the
public functions.

Sources
-------
- H. Rohling, "Radar CFAR thresholding in clutter and multiple target situations", IEEE Trans.
  AES 19(4), 608-621 (1983) (OS-CFAR, Pfa and Swerling 1 Pd as products).
- P. P. Gandhi and S. A. Kassam, "Analysis of CFAR processors in nonhomogeneous background",
  IEEE Trans. AES 24(4), 427-445 (1988) (eq. 37: OS-CFAR Pd for a Swerling 1 target).
- M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed. (McGraw-Hill, 2014), sec.
  6.5.6 "Order statistic CFAR", eqs. 6.158-6.168 and Fig. 6.29: with N = 20 and k = 15 a
  multiplier of 6.857 gives Pfa = 1e-3.
- A. Renyi, "On the theory of order statistics", Acta Math. Acad. Sci. Hung. 4, 191-231 (1953)
  (exponential order statistics as sums of independent exponentials).
- H. A. David and H. N. Nagaraja, *Order Statistics*, 3rd ed. (Wiley, 2003), sec. 2.1 (law of
  the k-th order statistic, binomial form of its distribution function).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.detection._cfar_engine import (
    law_loss_db,
    binomial_tail_table,
    binomial_tail_table_traced,
    log_binomial_tail,
    log_expm1,
    log_one_minus_exp_neg,
    loss_api,
    multiplier_api,
    padded,
    pd_api,
    pfa_api,
    required_snr_api,
    static_int,
    table_length,
)

__all__ = [
    "os_cfar_multiplier",
    "os_cfar_pfa",
    "os_cfar_pd",
    "os_cfar_required_snr_db",
    "os_cfar_loss_db",
    "os_cfar_loss_db_traced",
]

#: most reference cells of :func:`os_cfar_loss_db_traced` (its tables' fixed length)
TRACED_MAX_CELLS = 64


@partial(jax.tree_util.register_dataclass, data_fields=["n", "k", "weight", "log_rank", "cdf_table"], meta_fields=[])
@dataclass(frozen=True)
class _OrderStatistic:
    """Law of the k-th smallest of n unit exponentials, as padded arrays (a pytree).

    ``weight[i] = 1`` and ``log_rank[i] = log(n - i)`` for ``i < k`` (padding: 0 and 0);
    ``cdf_table``: the binomial tail ``j = k .. n`` of :func:`binomial_tail_table`.
    """

    n: object
    k: object
    weight: object
    log_rank: object
    cdf_table: object

    @property
    def cdf_power(self):
        return self.k

    def log_laplace(self, log_c):
        """log E[exp(-c X)] = -sum_{i<k} log(1 + c/(n - i))."""
        return -jnp.sum(self.weight * jax.nn.softplus(log_c[..., None] - self.log_rank), axis=-1)

    def tilted_mean(self, log_c):
        """E[X exp(-c X)] / E[exp(-c X)] = sum_{i<k} 1/(n - i + c)."""
        return jnp.sum(self.weight * jnp.exp(-jnp.logaddexp(self.log_rank, log_c[..., None])), axis=-1)

    def log_cdf(self, log_x):
        """log P(X_(k) <= x) = log P(Binomial(n, 1 - e^-x) >= k)."""
        return log_binomial_tail(self.cdf_table, log_one_minus_exp_neg(log_x), -jnp.exp(log_x))

    def log_multiplier_bracket(self, log_pfa):
        """Bracket of log T: L(T) lies between ((n-k+1)/(n-k+1+T))^k and (n/(n+T))^k."""
        log_a = log_expm1(-log_pfa / self.k)
        return jnp.log(self.n - self.k + 1.0) + log_a, jnp.log(self.n) + log_a


def _os_law(where, n_cells, k):
    n = static_int(where, "n_cells", n_cells, 1)
    k = static_int(where, "k", k, 1, n)
    length = table_length(n)
    ranks = np.arange(n, n - k, -1, dtype=float)
    return _OrderStatistic(
        n=np.float64(n),
        k=np.float64(k),
        weight=padded(np.ones(k), length, 0.0),
        log_rank=padded(np.log(ranks), length, 0.0),
        cdf_table=binomial_tail_table(n, k, length),
    )


def _os_law_traced(n_cells, rank):
    """The law of :class:`_OrderStatistic` from numbers that may be traced (n <= 64).

    The binomial tail of the distribution function is :func:`binomial_tail_table_traced`
    (coefficients from ``gammaln``); padding as in :func:`_os_law`. Real n interpolates the
    product smoothly between integers; the rank counts the factors ``i < k``.
    """
    n = jnp.asarray(n_cells, dtype=float)
    k = jnp.asarray(rank, dtype=float)
    i = jnp.arange(float(TRACED_MAX_CELLS))
    used = i < k
    weight = jnp.where(used, 1.0, 0.0)
    log_rank = jnp.where(used, jnp.log(jnp.where(used, n - i, 1.0)), 0.0)
    cdf_table = binomial_tail_table_traced(n, k, TRACED_MAX_CELLS)  # j = k .. n
    return _OrderStatistic(n=n, k=k, weight=weight, log_rank=log_rank, cdf_table=cdf_table)


def os_cfar_loss_db_traced(pd, pfa, n_cells, rank, swerling=0):
    """OS-CFAR loss (dB) as :func:`os_cfar_loss_db`, with ``n_cells`` and ``rank`` numbers that may
    be traced (a budget's parameters): ``1 <= rank <= n_cells <= 64``, integers (real ``n_cells``
    is a smooth relaxation between them). No argument checks: the caller's parameter bounds hold
    pd, pfa (``pfa < pd <= 0.9999``, ``1e-100 <= pfa <= 0.5``) and the counts in the domain.
    Equal to :func:`os_cfar_loss_db` to ~1e-12 dB (the binomial coefficients from ``gammaln``).

    >>> a = float(os_cfar_loss_db_traced(0.9, 1e-6, 24.0, 18.0, swerling=1))
    >>> abs(a - float(os_cfar_loss_db(0.9, 1e-6, 24, 18, swerling=1))) < 1e-12
    True
    """
    return law_loss_db(_os_law_traced(n_cells, rank), swerling, pd, pfa)


# --------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------


def os_cfar_multiplier(pfa, n_cells, k):
    """OS-CFAR threshold multiplier ``T``: detection when ``Y > T X_(k)``.

    Root of ``Pfa = prod_{i=0}^{k-1} (n - i)/(n - i + T)`` (Rohling 1983), by safeguarded
    Newton iteration in ``log T`` converged to round-off (relative error of T ~1e-15),
    implicitly differentiated in ``pfa``.

    Args:
        pfa: false-alarm probability, 1e-100 <= pfa < 1 (array).
        n_cells: number of reference cells n (static int >= 1).
        k: rank of the order statistic, 1 <= k <= n (static int; k = 1 is the minimum).

    Returns:
        ``T`` (dimensionless), the multiplier of the k-th smallest reference-cell power.

    Source: Rohling (1983); Gandhi & Kassam (1988) eq. 37; Richards, *Fundamentals of Radar
    Signal Processing*, sec. 6.5.6 and Fig. 6.29, whose example reads N = 20, k = 15,
    multiplier 6.857 for Pfa = 1e-3:

    >>> float(os_cfar_multiplier(1e-3, 20, 15))     # Richards reads 6.857 off his Fig. 6.29
    6.855
    >>> float(os_cfar_pfa(6.857, 20, 15))
    0.000999
    """
    where = "os_cfar_multiplier"
    return multiplier_api(where, _os_law(where, n_cells, k), pfa)


def os_cfar_pfa(multiplier, n_cells, k):
    """False-alarm probability of OS-CFAR, ``prod_{i=0}^{k-1} (n - i)/(n - i + T)``.

    Args:
        multiplier: threshold multiplier T > 0 (array).
        n_cells: reference cells n (static int >= 1).
        k: rank of the order statistic, 1 <= k <= n (static int).

    Source: Rohling (1983); Gandhi & Kassam (1988) eq. 37 with S = 0.

    k = 1 (the minimum of n exponentials is exponential with mean 1/n): ``n/(n + T)``.

    >>> float(os_cfar_pfa(9.0, 3, 1)), 3 / (3 + 9.0)
    (0.25, 0.25)
    """
    where = "os_cfar_pfa"
    return pfa_api(where, _os_law(where, n_cells, k), multiplier)


def os_cfar_pd(snr_db, pfa, n_cells, k, swerling=0):
    """Detection probability of OS-CFAR for one square-law pulse per cell.

    ``Pd = P(Y > T X_(k))`` with ``T = os_cfar_multiplier(pfa, n, k)``. Swerling 1/2:
    ``prod_{i<k} (n - i)/(n - i + T/(1 + S))`` (Rohling 1983; Gandhi & Kassam 1988 eq. 37);
    Swerling 3/4: ``L(c) (1 + b0 T sum_{i<k} 1/(n - i + c))``, ``c = T/(1 + S/2)``,
    ``b0 = (S/2)/(1 + S/2)^2`` (exact); Swerling 0: the expectation of the order statistic's
    distribution function over the Rician law of the cell under test, by a 64-node trapezoidal
    rule (absolute error < 5e-15, see the module docstring).

    Args:
        snr_db: mean SNR of the cell under test in dB (-100 ... 100).
        pfa: false-alarm probability, 1e-100 <= pfa < 1.
        n_cells: reference cells n (static int >= 1).
        k: rank of the order statistic, 1 <= k <= n (static int).
        swerling: 0-4 (static int; one pulse, so 1 = 2 and 3 = 4).

    Returns:
        Pd in [Pfa, 1].

    Swerling 1, n = 24, k = 18 (Rohling's 3n/4), Pfa = 1e-6, 20 dB: Rohling's product, with the
    multiplier found independently (scipy's Brent root of the Pfa product):

    >>> import math
    >>> from scipy.optimize import brentq
    >>> pfa_os = lambda t: math.prod((24 - i) / (24 - i + t) for i in range(18))
    >>> t = brentq(lambda t: pfa_os(t) - 1e-6, 1.0, 1e3, xtol=1e-13, rtol=1e-15)
    >>> float(os_cfar_pd(20.0, 1e-6, 24, 18, swerling=1)), pfa_os(t / 101.0)
    (0.808599654, 0.808599654)
    """
    where = "os_cfar_pd"
    return pd_api(where, _os_law(where, n_cells, k), snr_db, pfa, swerling)


def os_cfar_required_snr_db(pd, pfa, n_cells, k, swerling=0):
    """SNR (dB) of one pulse at which OS-CFAR reaches detection probability ``pd``.

    Swerling 1/2 in closed form, ``S = T(Pfa)/T(Pd) - 1`` with ``T(.)`` the multiplier;
    otherwise the root of ``os_cfar_pd = pd`` (safeguarded Newton iteration on
    ``log(-log Pd)``, converged to 1e-12 dB, implicitly differentiated in pd and pfa).

    Args:
        pd: detection probability, pfa < pd <= 0.9999.
        pfa: false-alarm probability, 1e-100 <= pfa < 1.
        n_cells: reference cells n (static int >= 1).
        k: rank of the order statistic, 1 <= k <= n (static int).
        swerling: 0-4 (static int).

    Returns:
        SNR in dB (NaN if the root lies outside [-100, 100] dB). Accuracy: within 1e-10 dB
        of 30-digit mpmath roots over the tested domain (module docstring).

    Swerling 1 closed form from two multipliers, each found independently (Brent roots of
    Rohling's product):

    >>> import math
    >>> from scipy.optimize import brentq
    >>> pfa_os = lambda t: math.prod((24 - i) / (24 - i + t) for i in range(18))
    >>> t_fa = brentq(lambda t: pfa_os(t) - 1e-6, 1.0, 1e3, xtol=1e-13, rtol=1e-15)
    >>> t_d = brentq(lambda t: pfa_os(t) - 0.9, 1e-6, 1.0, xtol=1e-16, rtol=1e-15)
    >>> float(os_cfar_required_snr_db(0.9, 1e-6, 24, 18, swerling=1)), 10 * math.log10(t_fa / t_d - 1)
    (23.08263400, 23.08263400)
    """
    where = "os_cfar_required_snr_db"
    return required_snr_api(where, _os_law(where, n_cells, k), pd, pfa, swerling)


def os_cfar_loss_db(pd, pfa, n_cells, k, swerling=0):
    """OS-CFAR loss (dB): required SNR with OS-CFAR minus the known-noise requirement.

    ``L = os_cfar_required_snr_db(pd, pfa, n, k, swerling) - required_snr_db(pd, pfa, 1,
    swerling)``. Swerling 1 closed form: ``10 log10[(T(Pfa)/T(Pd) - 1) / (ln Pfa / ln Pd -
    1)]``.

    Args:
        pd: detection probability, pfa < pd <= 0.9999.
        pfa: false-alarm probability, 1e-100 <= pfa <= 0.5.
        n_cells: reference cells n (static int >= 1).
        k: rank of the order statistic, 1 <= k <= n (static int).
        swerling: 0-4 (static int).

    Returns:
        Loss in dB (> 0; it decreases towards 0 as n grows with k/n fixed).

    Source: Rohling (1983) (OS-CFAR loss, n = 24, k = 18 in his examples); Richards,
    *Fundamentals of Radar Signal Processing*, sec. 6.5.6.

    Swerling 1, n = 24, k = 18, Pd = 0.9, Pfa = 1e-6 (closed form above, multipliers from
    Brent roots of Rohling's product):

    >>> import math
    >>> from scipy.optimize import brentq
    >>> pfa_os = lambda t: math.prod((24 - i) / (24 - i + t) for i in range(18))
    >>> t_fa = brentq(lambda t: pfa_os(t) - 1e-6, 1.0, 1e3, xtol=1e-13, rtol=1e-15)
    >>> t_d = brentq(lambda t: pfa_os(t) - 0.9, 1e-6, 1.0, xtol=1e-16, rtol=1e-15)
    >>> closed = 10 * math.log10((t_fa / t_d - 1) / (math.log(1e-6) / math.log(0.9) - 1))
    >>> float(os_cfar_loss_db(0.9, 1e-6, 24, 18, swerling=1)), closed
    (1.93899080, 1.93899080)
    """
    where = "os_cfar_loss_db"
    return loss_api(where, _os_law(where, n_cells, k), pd, pfa, swerling)
