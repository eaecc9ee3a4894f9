"""The CFAR family of the run-time-against-error atlas (benchmarks/_fidelity_cfar.py) on its quick
grid.

Independent source: mpmath. The family's reference takes each processor's Laplace transform
L(t) = E[exp(-t X)] of its noise estimate X in closed form; here every closed form is checked
against mpmath quadrature of its definition (the density of X: Gamma(n) for the sum, the k-th
order statistic of n unit exponentials, the greater / smaller of two iid Gamma(m) sums), so the
family's error column rests on the definitions, not on formulas taken on trust.
"""

import sys

import mpmath as mp
import pytest

from helpers.paths import REPO

sys.path.insert(0, str(REPO / "benchmarks"))
import _fidelity_cfar as fc  # noqa: E402

pytestmark = pytest.mark.slow  # the family compiles four programs and runs mpmath (~20 s)


@pytest.fixture(scope="module")
def family():
    [fam] = fc.run(quick=True)
    return fam


def test_the_family_is_complete(family):
    assert family.key == "cfar" and family.default == "given" and family.fast is None
    assert [c.name for c in family.choices] == [*fc.PROCESSORS, "universal curve (CA)", "cfarloss GO", "given"]
    assert all(c.seconds_per_eval > 0 and c.hlo_ops > 0 for c in family.choices if c.name in fc.PROCESSORS)


def test_every_processor_is_exact_against_the_reference(family):
    for name in fc.PROCESSORS:
        assert family.by_name[name].error_vs_reference < 1e-9, name  # dB, the bound


def _density(processor, x, n):
    """Density of the noise estimate X at x (n unit-mean exponential cells; GO/SO: two halves of m)."""
    if processor == "cell_averaging":
        return x ** (n - 1) * mp.exp(-x) / mp.gamma(n)
    if processor == "ordered_statistic":
        k = fc.os_rank(n)
        F = -mp.expm1(-x)
        return (mp.factorial(n) / (mp.factorial(k - 1) * mp.factorial(n - k))) * F ** (k - 1) * mp.exp(-x * (n - k + 1))
    m = n // 2
    f = x ** (m - 1) * mp.exp(-x) / mp.gamma(m)
    F = mp.gammainc(m, 0, x, regularized=True)
    return 2 * f * (F if processor == "greatest_of" else 1 - F)


@pytest.mark.parametrize("processor", fc.PROCESSORS)
@pytest.mark.parametrize("n,t", [(8, 0.05), (16, 0.3), (16, 2.5), (32, 0.01), (8, 12.0)])
def test_laplace_transforms_equal_quadrature_of_their_definitions(processor, n, t):
    with mp.workdps(30):
        t = mp.mpf(t)
        closed = fc.laplace_mp(processor, t, n)
        quad = mp.quad(lambda x: _density(processor, x, n) * mp.exp(-t * x), [0, 1, 4, 16, 64, mp.inf])
        assert abs(closed / quad - 1) < 1e-20, (processor, n, t, closed, quad)


def test_the_os_transform_reproduces_a_published_multiplier():
    # Richards (2014), sec. 6.5.6: with n = 20 and k = 15 a multiplier of 6.857 gives Pfa = 1e-3; the
    # root of Rohling's product is 6.8554 (the book's four digits are 0.03 % off)
    with mp.workdps(30):
        log_pfa = lambda t: mp.log(mp.fprod((20 - i) / (20 - i + t) for i in range(15)))  # noqa: E731
        root = mp.findroot(lambda t: log_pfa(t) - mp.log(mp.mpf("1e-3")), 6.8)
        family_pfa = fc.laplace_mp("ordered_statistic", root, 20)  # the family's rank for n = 20 is 15
    assert abs(float(root) - 6.857) < 2e-3
    assert abs(float(family_pfa) / 1e-3 - 1) < 1e-25


def _ca_swerling1_loss_db(pd, pfa, n):
    """Closed form (Swerling 1, CA): T(p) = p^(-1/n) - 1 solves (1 + T)^-n = p, S = T(Pfa)/T(Pd) - 1."""
    with mp.workdps(30):
        pd, pfa = mp.mpf(pd), mp.mpf(pfa)
        s = (pfa ** (-mp.mpf(1) / n) - 1) / (pd ** (-mp.mpf(1) / n) - 1) - 1
        return float(10 * mp.log10(s / (mp.log(pfa) / mp.log(pd) - 1)))


def test_the_pd_free_bound_is_the_least_error_of_any_curve_of_chi_alone():
    import numpy as np

    cells, pds, pfas = fc.FULL_CELLS, fc.FULL_PDS, fc.FULL_PFAS
    row = [(pd, pfa) for pfa in pfas for pd in pds]
    losses = np.array([[_ca_swerling1_loss_db(pd, pfa, n) for pd, pfa in row] for n in cells])
    bound = fc.pd_free_error_bound(losses, cells, row, chi_only=True)
    # (1e-3, 8 cells) and (1e-6, 16 cells) share chi = 3/8: one value of a chi-only curve serves both
    a, b = _ca_swerling1_loss_db(0.9, 1e-3, 8), _ca_swerling1_loss_db(0.9, 1e-6, 16)
    assert abs(a - b) > 1e-3 and bound >= abs(a - b) / 2  # 2.005 against 2.007 dB
    assert bound >= fc.pd_free_error_bound(losses, cells, row, chi_only=False) > 0
    # the bound is attained (each chi group's midrange) and not beaten by other curves of chi
    chi = np.array([[round(-np.log10(pfa)) / n for _, pfa in row] for n in cells])
    keys = sorted(set(chi.ravel()))
    mid = {k: (losses[chi == k].max() + losses[chi == k].min()) / 2 for k in keys}
    assert abs(max(abs(losses[chi == k] - mid[k]).max() for k in keys) - bound) < 1e-12
    rng = np.random.default_rng(0)
    for _ in range(200):
        curve = {k: mid[k] + rng.normal(0, 0.05) for k in keys}
        assert max(abs(losses[chi == k] - curve[k]).max() for k in keys) >= bound - 1e-12
