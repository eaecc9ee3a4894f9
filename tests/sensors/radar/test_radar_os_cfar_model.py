"""Radar options ``cfar_model = "ordered_statistic" | "greatest_of" | "smallest_of"``: the budget's
CFAR loss from the exact OS-CFAR (Rohling 1983) and GO/SO-CFAR models, one sample per cell
(coherent integration).

Independent reference (mpmath, 30 digits), Swerling 1: the k-th smallest of n unit exponentials
has the Laplace transform prod_{i<k} (n - i)/(n - i + T) (Renyi), so Pfa = L(T) and Pd =
L(T/(1 + S)); the SNR the detector needs is S = T(Pfa)/T(Pd) - 1 with T(p) the root of L(T) = p,
against the known-noise S = ln Pfa / ln Pd - 1. Other Swerling cases against the public
:func:`diffsense.detection.os_cfar_loss_db` (itself checked against mpmath in
tests/detection/test_cfar_ordered.py), whose law is built from correctly rounded tables. GO/SO,
Swerling 1, from the Laplace transforms of the greater / smaller half-window sum (below).
"""

import math

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.detection import os_cfar_loss_db
from diffsense.errors import DomainError
from diffsense.scene import Scene, complete_parameters, evaluator, parameter_table

mp.mp.dps = 30
COMMON = dict(range_m=40e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1.2e6, noise_figure_db=3.0,
              prf_hz=1e3, gain_db=33.0, beamwidth_az_deg=1.5, beamwidth_el_deg=3.0, n_pulses=8.0)
OPTIONS = {"antenna": "specified", "matched_filter": "matched", "integration": "coherent",
           "cfar_model": "ordered_statistic"}


def _mp_multiplier(p, n, k):
    log_l = lambda t: mp.fsum(mp.log(n - i) - mp.log(n - i + t) for i in range(k))
    lo, hi = mp.mpf("1e-30"), mp.mpf("1e30")
    for _ in range(400):  # bisection in log T: log L decreases in T
        mid = mp.sqrt(lo * hi)
        lo, hi = (mid, hi) if log_l(mid) > mp.log(p) else (lo, mid)
    return mp.sqrt(lo * hi)


def _mp_loss_swerling1_db(pd, pfa, n, k):
    pd, pfa = mp.mpf(pd), mp.mpf(pfa)
    s_cfar = _mp_multiplier(pfa, n, k) / _mp_multiplier(pd, n, k) - 1
    return float(10 * mp.log10(s_cfar / (mp.log(pfa) / mp.log(pd) - 1)))


def _loss(swerling, pd, pfa, cells, fraction):
    scene = Scene("radar", [], dict(OPTIONS, swerling=swerling))
    values = dict(COMMON, pd=pd, pfa=pfa, cfar_reference_cells=cells, cfar_rank_fraction=fraction)
    ev = evaluator(scene)(complete_parameters(scene, values))
    return ev, values


@pytest.mark.parametrize("pd,pfa,cells,fraction,k", [(0.9, 1e-6, 24.0, 0.75, 18), (0.5, 1e-10, 10.0, 0.7, 7),
                                                     (0.999, 1e-3, 64.0, 1.0, 64)])
def test_os_cfar_loss_term_equals_rohlings_closed_form_and_the_given_form(pd, pfa, cells, fraction, k):
    ev, values = _loss(1, pd, pfa, cells, fraction)
    want = _mp_loss_swerling1_db(pd, pfa, int(cells), k)  # k = ceil(fraction n)
    assert abs(-float(ev.budget["cfar_loss_db"]) - want) < 1e-9
    given = Scene("radar", [], dict(OPTIONS, swerling=1, cfar_model="given"))
    for name in ("cfar_reference_cells", "cfar_rank_fraction"):
        values.pop(name)
    ref = evaluator(given)(complete_parameters(given, dict(values, cfar_loss_db=want)))
    assert float(ev["snr_db"]) == pytest.approx(float(ref["snr_db"]), abs=1e-9)
    assert float(ev["detection_range_m"]) == pytest.approx(float(ref["detection_range_m"]), rel=1e-9)


@pytest.mark.parametrize("swerling", [0, 3])
def test_os_cfar_loss_term_equals_the_public_function(swerling):
    ev, _ = _loss(swerling, 0.9, 1e-6, 24.0, 0.75)
    want = float(os_cfar_loss_db(0.9, 1e-6, 24, 18, swerling))
    assert abs(-float(ev.budget["cfar_loss_db"]) - want) < 1e-9
    assert math.isfinite(want) and want > 0


def test_parameters_follow_the_option_and_refusals():
    table = parameter_table(Scene("radar", [], OPTIONS))
    assert {"cfar_reference_cells", "cfar_rank_fraction"} <= set(table) and "cfar_loss_db" not in table
    assert table["cfar_reference_cells"].hi == 64.0
    with pytest.raises(DomainError, match="integration='coherent'"):
        parameter_table(Scene("radar", [], dict(OPTIONS, integration="noncoherent")))
    with pytest.raises(DomainError, match="detectability='given'"):
        parameter_table(Scene("radar", [], dict(OPTIONS, detectability="given")))


def _mp_split_window_loss_swerling1_db(pd, pfa, m, greatest):
    """Swerling 1: Pfa = L(T), Pd = L(T/(1+S)) with L the Laplace transform of the greater / smaller
    of two Gamma(m) half-window sums (Weiss 1982; Gandhi & Kassam 1988):
    L_SO(c) = 2 sum_{i<m} C(m-1+i, i) (2+c)^-(m+i), L_GO(c) = 2 (1+c)^-m - L_SO(c)."""
    def log_l(t):
        with mp.workdps(mp.mp.dps + 20 + int(2 * m * mp.log10(2 + t))):  # GO cancels digits
            so = 2 * mp.fsum(mp.binomial(m - 1 + i, i) * (2 + t) ** -(m + i) for i in range(m))
            return +mp.log(2 * (1 + t) ** -m - so if greatest else so)

    def root(p):
        lo, hi = mp.mpf("1e-30"), mp.mpf("1e30")
        for _ in range(400):
            mid = mp.sqrt(lo * hi)
            lo, hi = (mid, hi) if log_l(mid) > mp.log(p) else (lo, mid)
        return mp.sqrt(lo * hi)

    pd, pfa = mp.mpf(pd), mp.mpf(pfa)
    return float(10 * mp.log10((root(pfa) / root(pd) - 1) / (mp.log(pfa) / mp.log(pd) - 1)))


@pytest.mark.parametrize("model,greatest", [("greatest_of", True), ("smallest_of", False)])
def test_go_so_cfar_loss_terms_equal_the_closed_forms(model, greatest):
    scene = Scene("radar", [], dict(OPTIONS, swerling=1, cfar_model=model))
    values = dict(COMMON, pd=0.9, pfa=1e-6, cfar_half_window_cells=8.0)
    ev = evaluator(scene)(complete_parameters(scene, values))
    assert abs(-float(ev.budget["cfar_loss_db"]) - _mp_split_window_loss_swerling1_db(0.9, 1e-6, 8, greatest)) < 1e-9


def test_a_relaxed_cell_count_interpolates_between_integers():
    scene = Scene("radar", [], dict(OPTIONS, swerling=0))
    ev = evaluator(scene)

    def loss(cells):
        values = dict(COMMON, pd=0.9, pfa=1e-6, cfar_reference_cells=cells, cfar_rank_fraction=0.75)
        return -ev(complete_parameters(scene, values)).budget["cfar_loss_db"]

    low, high = float(os_cfar_loss_db(0.9, 1e-6, 20, 15, 0)), float(os_cfar_loss_db(0.9, 1e-6, 21, 16, 0))
    assert float(loss(20.25)) == pytest.approx(0.75 * low + 0.25 * high, abs=1e-9)
    assert float(jax.grad(loss)(20.25)) == pytest.approx(high - low, abs=1e-9)
    assert high < low  # more cells, less loss
