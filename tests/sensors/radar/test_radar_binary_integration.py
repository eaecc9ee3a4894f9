"""Radar option ``integration = "binary"``: M-of-N binary integration of ``n_pulses`` pulses,
at least ``binary_m`` of them over their own threshold.

Independent reference (mpmath, 30 digits), Swerling 2 (RCS independent from pulse to pulse): with
B(p) = P(Bin(N, p) >= M) = I_p(M, N - M + 1), the per-pulse false-alarm and detection
probabilities are p_f = B^-1(Pfa) and p_d = B^-1(Pd), and one exponentially fluctuating pulse
has p_d = p_f^(1 / (1 + S)), so the per-pulse SNR needed is S = ln p_f / ln p_d - 1 and the Pd at
SNR S is B(p_f^(1 / (1 + S))). The other Swerling cases against the public
:func:`diffsense.detection.required_snr_binary_db` and :func:`diffsense.detection.pd_binary`
(checked against mpmath in tests/detection/test_binary.py): the chain must hand them its counts.
"""

import math

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.detection import pd_binary, required_snr_binary_db, required_snr_db
from diffsense.errors import DomainError
from diffsense.scene import Scene, complete_parameters, evaluate, evaluator, parameter_table
from tests.reference.mp_binomial import level_mp, tail_mp

mp.mp.dps = 30
COMMON = dict(range_m=30e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1.2e6, noise_figure_db=3.0,
              prf_hz=1e3, gain_db=33.0, beamwidth_az_deg=1.5, beamwidth_el_deg=3.0)
OPTIONS = {"antenna": "specified", "matched_filter": "matched", "integration": "binary"}


def _mp_required_swerling2_db(pd, pfa, n, m):
    return float(10 * mp.log10(mp.log(level_mp(pfa, n, m)) / mp.log(level_mp(pd, n, m)) - 1))


def _mp_pd_swerling2(snr_db, pfa, n, m):
    s = mp.mpf(10) ** (mp.mpf(snr_db) / 10)
    return float(tail_mp(level_mp(pfa, n, m) ** (1 / (1 + s)), n, m))


def _evaluate(swerling, **values):
    scene = Scene("radar", [], dict(OPTIONS, swerling=swerling))
    return evaluator(scene)(complete_parameters(scene, dict(COMMON, **values)))


@pytest.mark.parametrize("pd,pfa,n,m", [(0.9, 1e-6, 10, 4), (0.5, 1e-10, 24, 12), (0.999, 1e-3, 5, 5),
                                        (0.1, 1e-12, 40, 1)])
def test_swerling2_requirement_and_pd_equal_the_closed_form(pd, pfa, n, m):
    ev = _evaluate(2, pd=pd, pfa=pfa, n_pulses=float(n), binary_m=float(m))
    assert abs(float(ev["required_snr_db"]) - _mp_required_swerling2_db(pd, pfa, n, m)) < 1e-9
    assert abs(float(ev["pd"]) - _mp_pd_swerling2(float(ev["snr_db"]), pfa, n, m)) < 1e-12
    single = float(required_snr_db(pd, pfa, 1, 2))
    assert float(ev["integration_gain_db"]) == pytest.approx(single - float(ev["required_snr_db"]), abs=1e-12)


@pytest.mark.parametrize("swerling", [0, 1, 3, 4])
def test_other_swerling_cases_equal_the_public_functions(swerling):
    ev = _evaluate(swerling, pd=0.9, pfa=1e-6, n_pulses=12.0, binary_m=6.0)
    want = float(required_snr_binary_db(0.9, 1e-6, 12, 6, swerling))
    assert abs(float(ev["required_snr_db"]) - want) < 1e-9
    assert float(ev["pd"]) == pytest.approx(float(pd_binary(float(ev["snr_db"]), 1e-6, 12, 6, swerling)), abs=1e-13)
    assert float(ev["snr_margin_db"]) == pytest.approx(float(ev["snr_db"]) - want, abs=1e-9)


def test_relaxed_counts_interpolate_between_integers_with_finite_derivatives():
    scene = Scene("radar", [], dict(OPTIONS, swerling=0))
    ev = evaluator(scene)

    def required(n, m):
        return ev(complete_parameters(scene, dict(COMMON, pd=0.9, pfa=1e-6, n_pulses=n, binary_m=m)))["required_snr_db"]

    f = {(n, m): float(required_snr_binary_db(0.9, 1e-6, n, m)) for n in (10, 11) for m in (4, 5)}
    assert float(required(10.25, 4.0)) == pytest.approx(0.75 * f[10, 4] + 0.25 * f[11, 4], abs=1e-9)
    bilinear = 0.5 * (0.75 * f[10, 4] + 0.25 * f[11, 4]) + 0.5 * (0.75 * f[10, 5] + 0.25 * f[11, 5])
    assert float(required(10.25, 4.5)) == pytest.approx(bilinear, abs=1e-9)
    dn, dm = jax.grad(required, argnums=(0, 1))(10.25, 4.5)
    assert float(dn) == pytest.approx(0.5 * (f[11, 4] - f[10, 4]) + 0.5 * (f[11, 5] - f[10, 5]), abs=1e-9)
    assert float(dm) == pytest.approx(0.75 * (f[10, 5] - f[10, 4]) + 0.25 * (f[11, 5] - f[11, 4]), abs=1e-9)
    assert f[11, 4] < f[10, 4]  # one more pulse, less SNR per pulse


def test_more_than_n_or_over_100_pulses_is_not_a_number():
    assert math.isnan(float(_evaluate(0, n_pulses=4.0, binary_m=5.0)["required_snr_db"]))  # traced: NaN
    scene = Scene("radar", [], dict(OPTIONS, swerling=0))
    with pytest.raises(DomainError, match=r"binary_m = 5 exceeds n_pulses = 4"):  # concrete: named
        evaluate(scene, dict(COMMON, n_pulses=4.0, binary_m=5.0))
    assert math.isnan(float(_evaluate(0, n_pulses=101.0, binary_m=5.0)["required_snr_db"]))


def test_parameters_follow_the_option_and_refusals():
    table = parameter_table(Scene("radar", [], OPTIONS))
    assert table["binary_m"].default is None and table["binary_m"].integer and table["binary_m"].hi == 100.0
    assert "binary_m" not in parameter_table(Scene("radar", [], dict(OPTIONS, integration="noncoherent")))
    with pytest.raises(DomainError, match="detectability='exact'"):
        parameter_table(Scene("radar", [], dict(OPTIONS, detectability="shnidman")))
    with pytest.raises(DomainError, match="cfar_model='given'"):
        parameter_table(Scene("radar", [], dict(OPTIONS, cfar_model="cell_averaging")))


def test_a_spec_with_m_above_n_is_refused_before_any_program_is_traced(capsys):
    """The M <= N check runs on the spec's plain numbers at load (Chain.check_values), so the
    command line refuses the spec without tracing the check program it used to wait for."""
    from diffsense.cli.app import main
    from diffsense.optimize import programs
    from helpers.paths import REPO

    before = dict(programs.TRACES)
    with pytest.raises(SystemExit) as info:
        main(["--quiet", "evaluate", str(REPO / "tests" / "design" / "bad_specs" / "binary_m_above_n_pulses.toml")])
    assert info.value.code == 2
    assert "binary_m = 12 exceeds n_pulses = 8" in capsys.readouterr().err
    assert programs.TRACES == before
