"""The binary-integration family of the run-time-against-error atlas
(benchmarks/_fidelity_binary.py) on its quick grid.

Independent source: mpmath at 30 digits — the per-pulse probabilities by bisection of the
regularized incomplete beta function, then the single-pulse requirement of
tests/reference/mp_detection.py (Swerling 1: the closed form S = ln p_f / ln p_d − 1). The
per-pulse equations are checked here against that reference directly, computed again in this
test, so the family's error column is not trusted on its own.
"""

import math
import sys

import mpmath as mp
import pytest

from helpers.paths import REPO

sys.path.insert(0, str(REPO / "benchmarks"))
import _fidelity_binary as fb  # noqa: E402

pytestmark = pytest.mark.slow  # the family compiles three programs and runs mpmath (~20 s)


@pytest.fixture(scope="module")
def family():
    [fam] = fb.run(quick=True)
    return fam


def test_the_family_is_complete(family):
    assert family.key == "binary" and family.exact == "exact" and family.default == "exact"
    assert [c.name for c in family.choices] == ["exact", "per-pulse Shnidman", "per-pulse Albersheim"]
    assert all(c.seconds_per_eval > 0 and c.hlo_ops > 0 for c in family.choices)
    assert family.fast is None  # the per-pulse equations are not options


def test_exact_is_exact_and_the_per_pulse_equations_are_not(family):
    rows = family.by_name
    assert rows["exact"].error_vs_reference < 1e-9  # dB, the bound
    # at the quick grid's per-pulse probabilities (p_f ~ 0.1 for 12 of 24 at 1e-6) the equations are
    # evaluated far outside the Pfa <= 1e-3 they were fitted to: tenths of a dB
    assert 0.05 < rows["per-pulse Shnidman"].error_vs_reference < 3.0
    assert 0.05 < rows["per-pulse Albersheim"].error_vs_reference < 3.0


def test_reference_of_one_point_against_a_closed_form():
    """Swerling 2, 12 of 24, Pd 0.9, Pfa 1e-6: p_f, p_d by mpmath's binomial inversion here
    (findroot on betainc, not the family's bisection), then S = ln p_f / ln p_d − 1."""
    [(value, p_d, p_f)] = fb._reference([(0.9, 1e-6, 24, 12, 2)])
    with mp.workdps(30):
        level = lambda t: mp.findroot(lambda p: mp.betainc(12, 13, 0, p, regularized=True) - t, 0.2)  # noqa: E731
        pf, pd = level(mp.mpf("1e-6")), level(mp.mpf("0.9"))
        want = float(10 * mp.log10(mp.log(pf) / mp.log(pd) - 1))
    assert value == pytest.approx(want, abs=1e-10)
    assert p_f == pytest.approx(float(pf), rel=1e-12) and p_d == pytest.approx(float(pd), rel=1e-12)
    assert math.isclose(p_f, 0.1015253, rel_tol=1e-6)  # the package's doctest value, as scipy's binomial confirms
