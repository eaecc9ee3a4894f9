"""Radar option ``cfar_model``: the CFAR loss of the budget computed by the exact CA-CFAR model.

Independent references (mpmath, 30 digits):

- Swerling 1, one pulse: the CA-CFAR detector with M reference cells has Pfa = (1 + a)^-M and
  Pd = (1 + a/(1 + S))^-M (Gandhi & Kassam 1988; Richards 2014 sec. 7.4), so the SNR it needs
  is S_cfar = a / (Pd^(-1/M) - 1) - 1 with a = Pfa^(-1/M) - 1, against the known-noise
  S = ln Pfa / ln Pd - 1; the loss is 10 log10(S_cfar / S);
- Swerling 2, N pulses: Y/(Y + Z) is Beta-distributed, Pd = I_{1/(1 + a/(1 + S))}(M N, N) with
  a from Pfa = I_{1/(1 + a)}(M N, N); the known-noise Pd = Q(N, T/(1 + S)) with Q(N, T) = Pfa;
  each root found with mpmath's findroot on mpmath's betainc / gammainc.

The chain with ``cfar_model = "given"`` fed that number must give the same SNR.
"""

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.scene import Scene, complete_parameters, evaluator, parameter_table

mp.mp.dps = 30
COMMON = dict(range_m=40e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1.2e6, noise_figure_db=3.0,
              prf_hz=1e3, gain_db=33.0, beamwidth_az_deg=1.5, beamwidth_el_deg=3.0)
OPTIONS = {"antenna": "specified", "matched_filter": "matched"}


def _mp_loss_swerling1_db(pd, pfa, m):
    pd, pfa = mp.mpf(pd), mp.mpf(pfa)
    a = pfa ** (-1 / mp.mpf(m)) - 1
    s_cfar = a / (pd ** (-1 / mp.mpf(m)) - 1) - 1
    s_known = mp.log(pfa) / mp.log(pd) - 1
    return float(10 * mp.log10(s_cfar / s_known))


def _mp_loss_swerling2_db(pd, pfa, m, n):
    pd, pfa = mp.mpf(pd), mp.mpf(pfa)
    a_mn = mp.mpf(m) * n

    def upper_beta(x):  # P(Y/(Y+Z) > ...) written as I_x(M N, N), x = 1/(1 + a)
        return mp.betainc(a_mn, n, 0, x, regularized=True)

    def root(f, lo, hi):  # bisection in the logarithm of the unknown (f changes sign once)
        a, b = mp.log(lo), mp.log(hi)
        fa = f(a)
        for _ in range(120):
            c = (a + b) / 2
            if (f(c) > 0) == (fa > 0):
                a, fa = c, f(c)
            else:
                b = c
        return mp.exp((a + b) / 2)

    alpha = root(lambda la: mp.log(upper_beta(1 / (1 + mp.exp(la)))) - mp.log(pfa), 1e-3, 1e3)
    s_cfar = root(lambda ls: upper_beta(1 / (1 + alpha / (1 + mp.exp(ls)))) - pd, 1e-3, 1e6)
    t = root(lambda lt: mp.log(mp.gammainc(n, mp.exp(lt), regularized=True)) - mp.log(pfa), n, n + 300)
    s_known = root(lambda ls: mp.gammainc(n, t / (1 + mp.exp(ls)), regularized=True) - pd, 1e-3, 1e6)
    return float(10 * mp.log10(s_cfar / s_known))


CASES = [
    # swerling, pd, pfa, reference cells, pulses
    (1, 0.9, 1e-6, 16.0, 1.0),
    (1, 0.5, 1e-10, 8.0, 1.0),
    (2, 0.9, 1e-6, 24.0, 10.0),
]


@pytest.mark.parametrize("swerling,pd,pfa,cells,n", CASES)
def test_cfar_loss_term_equals_the_closed_forms_and_the_given_form(swerling, pd, pfa, cells, n):
    scene = Scene("radar", [], dict(OPTIONS, cfar_model="cell_averaging", swerling=swerling))
    values = dict(COMMON, pd=pd, pfa=pfa, cfar_reference_cells=cells, n_pulses=n)
    ev = evaluator(scene)(complete_parameters(scene, values))
    want = _mp_loss_swerling1_db(pd, pfa, cells) if n == 1 else _mp_loss_swerling2_db(pd, pfa, cells, n)
    assert abs(-float(ev.budget["cfar_loss_db"]) - want) < 1e-9
    given = Scene("radar", [], dict(OPTIONS, swerling=swerling))
    values.pop("cfar_reference_cells")
    ref = evaluator(given)(complete_parameters(given, dict(values, cfar_loss_db=want)))
    assert float(ev["snr_db"]) == pytest.approx(float(ref["snr_db"]), abs=1e-9)
    assert float(ev["detection_range_m"]) == pytest.approx(float(ref["detection_range_m"]), rel=1e-9)


def test_parameters_follow_the_option():
    computed = parameter_table(Scene("radar", [], dict(OPTIONS, cfar_model="cell_averaging")))
    assert "cfar_reference_cells" in computed and "cfar_loss_db" not in computed
    assert "cfar_reference_cells" not in parameter_table(Scene("radar", [], OPTIONS))


def test_needs_a_detection_model():
    with pytest.raises(DomainError, match="cfar_model"):
        parameter_table(Scene("radar", [], dict(OPTIONS, cfar_model="cell_averaging", detectability="given")))


def test_more_reference_cells_lose_less_and_the_gradient_matches_central_differences():
    scene = Scene("radar", [], dict(OPTIONS, cfar_model="cell_averaging", swerling=1))
    ev = evaluator(scene)

    def snr(cells):
        return ev(complete_parameters(scene, dict(COMMON, n_pulses=1.0, cfar_reference_cells=cells)))["snr_db"]

    g = float(jax.grad(snr)(12.0))
    h = 1e-4
    fd = (_mp_loss_swerling1_db(0.9, 1e-6, mp.mpf(12) - h) - _mp_loss_swerling1_db(0.9, 1e-6, mp.mpf(12) + h)) / (2 * h)
    assert g > 0
    assert g == pytest.approx(fd, rel=1e-6)

