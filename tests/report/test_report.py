"""Design reports of the side-scan sonar spec (Brooker 12.7-12.8): files and figures written,
numbers equal to ``diffsense evaluate``, Jacobian against central differences and closed forms,
post-optimal sensitivities against the closed-form optimum, CLI error handling.

The two reports (optimum and initial design) are built once per test run and shared between
pytest-xdist workers through a lock file, so the optimiser and the report's chain program are
compiled once.
"""

import fcntl
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers.paths import REPO


ROOT = REPO
SIDESCAN = ROOT / "tests" / "report" / "specs" / "sidescan_point.toml"  # the side-scan design with its requirements at 750 m (the shipped one holds them over the swath)
LN10_10 = math.log(10.0) / 10.0


def _shared_dir(tmp_path_factory) -> Path:
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def _cli(*args):
    return subprocess.Popen([sys.executable, "-m", "diffsense.cli", *map(str, args)], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def closed_form_optimum(initial_report):
    """The sidescan optimum in closed form (book eqs 12.42-12.48: SNR = const + 10 log10 P
    - 20 log10 theta_az, nothing else depends on P or theta_az; the chirp bandwidth cancels).

    The least power puts the azimuth beam on its 1 deg bound and the margin on 0 dB:
    P* = P0 10^(-m1/10) with m1 = m(P0, 1 deg) = m(P0, 1.5 deg) + 20 log10 1.5. The objective
    is P normalised by its initial 1500 W, so the margin's multiplier is P* ln10/10 / 1500."""
    from diffsense.design.optimizer import DesignOptimum

    m_initial = initial_report["requirements"][0]["value"]
    d = initial_report["design"]
    p0, theta0 = d["electrical_power_w"]["value"], d["beamwidth_az_deg"]["value"]
    theta = d["beamwidth_az_deg"]["lower"]
    m1 = m_initial + 20.0 * math.log10(theta0 / theta)
    p = p0 * 10 ** (-m1 / 10)
    x = np.array([p, d["chirp_bandwidth_hz"]["value"], theta])
    lam = np.array([p * LN10_10 / p0, 0.0, 0.0])
    return DesignOptimum(x=x, combo_index=0, objective=p, converged=True, feasible=True, multipliers=lam,
                         starts=1, starts_converged=1, starts_at_best=1, unmet=[],
                         candidates=[{"options": {}, "objective": p, "feasible": True}])


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """{'optimum': (dir, json), 'initial': (dir, json), 'evaluate': json of `diffsense evaluate`}.

    The initial design's report is built first; the optimum's report is built for the
    closed-form optimum (:func:`closed_form_optimum`) without running the optimiser, reusing
    the compiled chain program. ``diffsense evaluate --json`` runs alongside as a command."""
    root = _shared_dir(tmp_path_factory) / "sidescan_reports"
    root.mkdir(exist_ok=True)
    with open(root / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (root / "done").exists():
            proc = subprocess.Popen([sys.executable, "-m", "diffsense.cli", "evaluate", str(SIDESCAN), "--json",
                                     str(root / "evaluate.json")], cwd=ROOT, stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, text=True)
            from diffsense.report import build_report

            initial = build_report(SIDESCAN, root / "initial", optimize=False)
            build_report(SIDESCAN, root / "optimum", optimum=closed_form_optimum(initial))
            stdout, stderr = proc.communicate(timeout=300)
            # evaluate exits 3 when the initial design leaves a requirement unmet, 0 otherwise
            assert proc.returncode == (0 if initial["feasible"] else 3), stdout + stderr
            (root / "done").write_text("ok")
    out = {k: (root / k, json.loads((root / k / "report.json").read_text())) for k in ("optimum", "initial")}
    out["evaluate"] = json.loads((root / "evaluate.json").read_text())
    return out


def _jac(report):
    j = report["jacobian"]
    names = [i["name"] for i in j["inputs"]]
    outs = [o["output"] if o["case"] else "objective" for o in j["outputs"]]
    return j, names, outs


def _entry(report, output, name, key="elasticity"):
    j, names, outs = _jac(report)
    return j[key][outs.index(output)][names.index(name)]


# --- files --------------------------------------------------------------------------------


@pytest.mark.parametrize("which", ["optimum", "initial"])
def test_report_writes_markdown_html_json_and_every_figure(reports, which):
    out_dir, rep = reports[which]
    for name in ("report.md", "report.html", "report.json"):
        assert (out_dir / name).stat().st_size > 1000
    files = [f["file"] for f in rep["figures"]]
    stems = {Path(f).stem for f in files}
    assert stems == {"budget_main", "snr_vs_range_main", "pd_vs_range_main", "roc_main",
                     "tornado_0", "tornado_1", "tornado_2"}
    md = (out_dir / "report.md").read_text()
    html = (out_dir / "report.html").read_text()
    for f in files:
        png = (out_dir / f).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
        assert not Path(f).is_absolute()
        assert f"({f})" in md and f'src="{f}"' in html
    # the Blake chart is a radar figure: skipped for the sonar, with the reason in the report
    assert [s["figure"] for s in rep["skipped_figures"]] == ["Coverage chart (Blake)"]
    assert "does not apply to the sonar chain" in md


# --- numbers against `diffsense evaluate` -------------------------------------------------


def test_initial_report_numbers_equal_diffsense_evaluate_json(reports):
    _, rep = reports["initial"]
    ev = reports["evaluate"]
    assert rep["design"] == ev["design"]
    assert len(rep["requirements"]) == len(ev["requirements"])
    for a, b in zip(rep["requirements"], ev["requirements"]):
        assert (a["name"], a["output"], a["unit"], a["sense"], a["met"]) == (b["name"], b["output"], b["unit"], b["sense"], b["met"])
        assert a["limit"] == b["limit"]
        assert a["value"] == pytest.approx(b["value"], rel=1e-12, abs=1e-12)
        assert a["slack"] == pytest.approx(b["slack"], rel=1e-12, abs=1e-12)
    assert rep["objective"]["value"] == pytest.approx(ev["objective"]["value"], rel=1e-14)
    budget, budget_ev = rep["cases"]["main"]["budget"], ev["cases"]["main"]["budget"]
    assert [t["term"] for t in budget] == [t["term"] for t in budget_ev]
    for t, u in zip(budget, budget_ev):
        assert t["db"] == pytest.approx(u["db"], rel=1e-12, abs=1e-12)
    outs, outs_ev = rep["cases"]["main"]["outputs"], ev["cases"]["main"]["outputs"]
    assert set(outs) == set(outs_ev)
    for k in outs_ev:
        # the detection range is a root found iteratively (1e-10 relative is its own tolerance)
        assert outs[k]["value"] == pytest.approx(outs_ev[k]["value"], rel=1e-10), k
        assert outs[k]["unit"] == outs_ev[k]["unit"]
    # running total of the budget ends at the SNR output (the budget's definition)
    assert budget[-1]["running_total_db"] == pytest.approx(outs_ev["snr_db"]["value"], abs=1e-10)


def test_report_budget_source_level_is_the_books_225_3_db(reports):
    # Brooker 12.8: 1500 W, 40 %, G = 458.4, Z = 1522 x 1026.4 rayl -> SL = 225.3 dB (rounded to 0.1 dB)
    _, rep = reports["initial"]
    sl = {t["term"]: t["db"] for t in rep["cases"]["main"]["budget"]}["source_level"]
    assert sl == pytest.approx(225.3, abs=0.05)


# --- Jacobian -----------------------------------------------------------------------------


def test_jacobian_equals_central_differences_where_smooth(reports):
    _, rep = reports["optimum"]
    fd = rep["jacobian"]["fd_check"]
    assert rep["jacobian"]["autodiff"] is True
    assert fd["n_compared"] >= 15
    assert fd["max_rel_diff"] < 1e-6
    # the only kink: sea state 3 is a breakpoint of the book's Table 12.2 noise levels
    # (5 dB per sea state below, 5/3 dB above), so its one-sided slopes differ
    assert fd["not_smooth"] == [{"output": "detect a 1 m sphere at 750 m", "input": "sea_state"}]
    assert _entry(rep, "snr_margin_db", "sea_state", "derivative") == pytest.approx(-5.0 / 3.0, rel=1e-12)


def test_elasticities_equal_the_sonar_equation_closed_forms(reports):
    # SL = 120 + 10 log10(P eta G rho c / 4 pi), G = 4 pi (180/pi)^2 / (az el) (book eqs 12.42-12.48),
    # noise band level N_f + 10 log10 B - DI and pulse-compression gain 10 log10(B tau) (eq 12.64),
    # TS = 10 log10(a^2/4) (eq 8.24), two-way TL = 40 log10 R + 2 alpha R with the book's
    # alpha = 0.036 f^2/(f^2 + 3600) + 3.2e-7 f^2 dB/m, f in kHz (eq 7.44)
    _, rep = reports["optimum"]
    exact = {"electrical_power_w": 1.0, "efficiency": 1.0, "water_density_kg_m3": 1.0, "pulse_width_s": 1.0,
             "chirp_bandwidth_hz": 0.0, "beamwidth_az_deg": -2.0, "beamwidth_el_deg": -2.0, "target_radius_m": 2.0,
             "receive_sensitivity_db": 0.0}
    for name, value in exact.items():
        assert _entry(rep, "snr_margin_db", name) == pytest.approx(value, abs=1e-9), name
    f = 117.0
    alpha = 0.036 * f * f / (f * f + 3600.0) + 3.2e-7 * f * f
    r = 750.0
    assert _entry(rep, "snr_margin_db", "range_m") == pytest.approx(-4.0 - 2.0 * alpha * r * LN10_10, rel=1e-12)
    p = rep["design"]["electrical_power_w"]["value"]
    assert _entry(rep, "snr_margin_db", "electrical_power_w", "derivative") == pytest.approx(1.0 / (LN10_10 * p), rel=1e-12)
    # resolutions: c / (2 B) and R theta_az
    assert _entry(rep, "range_resolution_m", "chirp_bandwidth_hz") == pytest.approx(-1.0, abs=1e-12)
    assert _entry(rep, "range_resolution_m", "sound_speed_m_s") == pytest.approx(1.0, abs=1e-12)
    assert _entry(rep, "cross_range_resolution_m", "range_m") == pytest.approx(1.0, abs=1e-12)
    assert _entry(rep, "cross_range_resolution_m", "beamwidth_az_deg") == pytest.approx(1.0, abs=1e-12)
    assert _entry(rep, "objective", "electrical_power_w") == pytest.approx(1.0, abs=1e-12)


# --- post-optimal sensitivities -----------------------------------------------------------


def test_optimal_power_moves_with_the_margin_limit_by_the_closed_form(reports):
    # SNR grows as 10 log10 P and nothing else at the optimum depends on P, so P* = K 10^(b/10)
    # for a margin limit b: dP*/db = P* ln10/10 W per dB; the shadow price of the requirement is
    # the same number (objective = P).
    _, rep = reports["optimum"]
    assert all(r["met"] for r in rep["requirements"])
    assert rep["requirements"][0]["value"] == pytest.approx(0.0, abs=1e-10)
    post = rep["post_optimal"]
    assert post["available"]
    p = rep["design"]["electrical_power_w"]["value"]
    req = "detect a 1 m sphere at 750 m"
    assert post["active_requirements"] == [req]
    assert post["dx_dlimit"][req]["electrical_power_w"]["value"] == pytest.approx(p * LN10_10, rel=1e-9)
    assert post["dx_dlimit"][req]["electrical_power_w"]["unit"] == "W per dB"
    shadow = {s["requirement"]: s for s in post["shadow_prices"]}
    assert shadow[req]["d_objective_d_limit"] == pytest.approx(p * LN10_10, rel=1e-9)
    # the multiplier in the optimiser's normalisation converts to the same shadow price
    assert shadow[req]["d_objective_d_limit_from_optimizer_multiplier"] == pytest.approx(p * LN10_10, rel=1e-12)
    # the azimuth beam sits on its 1 deg bound; the chirp bandwidth cancels out of the SNR
    # (-10 log10 B noise band + 10 log10 B tau compression gain), so the optimum is not unique in it
    assert post["variable_status"] == {"electrical_power_w": "free", "chirp_bandwidth_hz": "not_unique",
                                       "beamwidth_az_deg": "lower"}
    assert post["dx_dlimit"][req]["chirp_bandwidth_hz"]["value"] is None
    for other in ("range resolution", "cross-range resolution at 750 m"):
        assert shadow[other]["d_objective_d_limit"] == 0.0
        assert post["dx_dlimit"][other]["electrical_power_w"]["value"] == 0.0
    # the Hessian of the Lagrangian by differences of the exact forward-mode gradients, its
    # estimate with half the step within 1e-6 (relative to its largest entry)
    assert post["hessian"] == "central differences of forward-mode gradients"
    assert post["hessian_fd_rel_diff"] < 1e-6


def test_initial_design_report_says_post_optimal_is_unavailable(reports):
    out_dir, rep = reports["initial"]
    assert rep["mode"] == "initial_design" and rep["post_optimal"]["available"] is False
    assert "initial design" in rep["post_optimal"]["reason"]
    assert "Post-optimal sensitivity" in (out_dir / "report.md").read_text()


@pytest.mark.slow
def test_optimised_report_matches_the_closed_form_optimum(tmp_path):
    # the full path: diffsense's optimiser, then the report of its answer
    from diffsense.report import build_report

    rep = build_report(SIDESCAN, tmp_path, optimize=True, n_starts=4, seed=1)
    assert rep["converged"] and rep["feasible"]
    post = rep["post_optimal"]
    req = "detect a 1 m sphere at 750 m"
    p = rep["design"]["electrical_power_w"]["value"]
    assert post["dx_dlimit"][req]["electrical_power_w"]["value"] == pytest.approx(p * LN10_10, rel=1e-6)
    shadow = {s["requirement"]: s for s in post["shadow_prices"]}
    # the optimiser's multiplier, to its convergence tolerance
    assert shadow[req]["d_objective_d_limit_from_optimizer_multiplier"] == pytest.approx(p * LN10_10, rel=1e-5)
    assert post["variable_status"]["beamwidth_az_deg"] == "lower"


@pytest.mark.slow
def test_interior_optimum_sensitivities_equal_closed_form(tmp_path):
    # minimise P - w theta_az subject to margin(P, theta) >= b: the margin is
    # m0 + 10 log10(P/P0) - 20 log10(theta/theta0), so on the constraint P = K theta^2 with
    # K = P0 10^((b - m0)/10) / theta0^2, the optimum theta* = w/(2K), P* = w^2/(4K) is interior
    # and dtheta*/db = -theta* ln10/10, dP*/db = -P* ln10/10, dF*/db = P* ln10/10.
    from diffsense.design.model import DesignModel
    from diffsense.report.batch import BatchEvaluator, row
    from diffsense.report.inputs import design_inputs
    from diffsense.report.jacobian import jacobian_section
    from diffsense.report.postoptimal import post_optimal_section
    from diffsense.design.spec import load_spec

    w = 2400.0
    text = SIDESCAN.read_text().replace('minimize = "electrical_power_w"',
                                        f'minimize = {{ electrical_power_w = 1.0, beamwidth_az_deg = -{w} }}')
    path = tmp_path / "interior.toml"
    path.write_text(text)
    model = DesignModel(load_spec(path))
    inputs = design_inputs(model, model.initial, 0)
    batch = BatchEvaluator(model, model.initial, 0)
    v0 = np.array([i.value for i in inputs])
    m0 = float(row(batch(v0[None])[0], 0)[1][0])
    p0, b0, th0 = model.initial
    k = p0 * 10 ** (-m0 / 10) / th0**2
    th, p = w / (2 * k), w * w / (4 * k)
    x = np.array([p, b0, th])
    inputs = design_inputs(model, x, 0)
    batch = BatchEvaluator(model, x, 0)
    outs = [{"unit": r.unit} for r in model.requirements] + [{"unit": "1"}]
    jac = jacobian_section(batch, inputs, outs)
    req = jac["values"][:-1]
    post = post_optimal_section(model, inputs, batch, x, 0, jac["derivative"], req, np.array([1.0, 0.0, 0.0]), 1.0)
    assert post["method"].startswith("implicit function theorem")
    assert post["dx_dlimit"][0, 0] == pytest.approx(-p * LN10_10, rel=1e-8)
    assert post["dx_dlimit"][2, 0] == pytest.approx(-th * LN10_10, rel=1e-8)
    assert post["shadow_price_kkt"][0] == pytest.approx(p * LN10_10, rel=1e-8)


# --- CLI ------------------------------------------------------------------------------------


def test_cli_report_invalid_spec_exits_2_without_traceback(tmp_path):
    import jax
    from typer.testing import CliRunner

    from diffsense.cli import app

    bad = tmp_path / "bad.toml"
    bad.write_text(SIDESCAN.read_text().replace('lower = "10 W"', 'lower = "10 kW"'))
    # the command line's start-up enables a persistent compilation cache: keep this process's setting
    saved = {k: getattr(jax.config, k) for k in ("jax_compilation_cache_dir", "jax_persistent_cache_min_compile_time_secs")}
    try:
        result = CliRunner().invoke(app, ["report", str(bad), "--out", str(tmp_path / "r")])
    finally:
        for k, v in saved.items():
            jax.config.update(k, v)
    assert result.exit_code == 2
    assert isinstance(result.exception, SystemExit)
    assert "Traceback" not in result.output
    assert "variables.electrical_power_w" in result.output
    assert not (tmp_path / "r" / "report.json").exists()


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(p.stem for p in (ROOT / "designs").glob("*.toml")))
def test_every_shipped_design_report_builds_and_equals_evaluate(tmp_path, name):
    # the spec's initial design of every shipped spec: the report's requirement values, budget
    # and outputs equal `diffsense evaluate` (design_record); nothing in the report is missing
    from diffsense.design.model import DesignModel
    from diffsense.design.record import design_record
    from diffsense.report import build_report
    from diffsense.design.spec import load_spec

    spec = ROOT / "designs" / f"{name}.toml"
    rep = build_report(spec, tmp_path, optimize=False)
    model = DesignModel(load_spec(spec))
    ev = design_record(model, model.initial, 0)
    for a, b in zip(rep["requirements"], ev["requirements"]):
        assert a["value"] == pytest.approx(b["value"], rel=1e-10, abs=1e-12), (name, a["name"])
    for case, c in ev["cases"].items():
        for t, u in zip(rep["cases"][case]["budget"], c["budget"]):
            assert t["db"] == pytest.approx(u["db"], rel=1e-12, abs=1e-12), (name, t["term"])
    for f in ("report.md", "report.html", "report.json"):
        assert (tmp_path / f).stat().st_size > 0
    # every figure written is shown in both documents
    md, html = (tmp_path / "report.md").read_text(), (tmp_path / "report.html").read_text()
    for png in (tmp_path / "figures").glob("*.png"):
        f = png.relative_to(tmp_path).as_posix()
        assert f"]({f})" in md and f'src="{f}"' in html, (name, f)
