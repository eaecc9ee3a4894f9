"""The report's one-page summary and the placement of its figures: every figure written is
shown, a skipped chart says why, the stoplight and 'what sets the design' agree with the exact
slacks, a probability of detection is measured by its miss probability, and a design set by a
bound or carrying a requirement no variable moves says so."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from diffsense.design.model import DesignModel
from diffsense.design.spec import load_spec
from diffsense.detection import required_snr_db
from helpers.paths import REPO

ORE = REPO / "designs" / "ore_pass.toml"
SONAR = REPO / "tests" / "design" / "trade_specs" / "band_sonar.toml"


@pytest.fixture(scope="module")
def ore(tmp_path_factory):
    from diffsense.report import build_report

    out = tmp_path_factory.mktemp("ore")
    return out, build_report(ORE, out)


@pytest.fixture(scope="module")
def sonar(tmp_path_factory):
    from diffsense.report import build_report

    out = tmp_path_factory.mktemp("sonar")
    return out, build_report(SONAR, out, n_starts=4)


def _pngs(out: Path):
    return sorted(p.relative_to(out).as_posix() for p in (out / "figures").glob("*.png"))


@pytest.mark.parametrize("which", ["ore", "sonar"])
def test_every_png_written_is_shown_in_markdown_and_html(which, request):
    out, rep = request.getfixturevalue(which)
    md, html = (out / "report.md").read_text(), (out / "report.html").read_text()
    pngs = _pngs(out)
    assert pngs and pngs == sorted(f["file"] for f in rep["figures"])
    for f in pngs:
        assert f"]({f})" in md and f'src="{f}"' in html, f


def test_interval_figures_are_shown_under_their_requirement(ore):
    out, rep = ore
    md = (out / "report.md").read_text()
    section = md.split("## Requirements over their intervals", 1)[1].split("\n## ", 1)[0]
    for j, r in enumerate(rep["requirements"]):
        if r.get("curve"):
            assert f"### {r['name']}" in section and f"(figures/interval_{j}.png)" in section
    assert "figures/interval_0.png" in section and "figures/interval_2.png" in section


def test_a_skipped_coverage_chart_says_why_under_its_heading(ore):
    out, rep = ore
    md = (out / "report.md").read_text()
    body = md.split("## Coverage chart", 1)[1].split("\n## ", 1)[0].strip()
    reason = next(s["reason"] for s in rep["skipped_figures"] if s["figure"].startswith("Coverage chart"))
    assert body and reason in body and "looks down a shaft" in body


def test_pd_is_measured_by_its_miss_probability(ore):
    # elasticity of the faded margin m = SNR - fade - D(pd) with respect to 1 - pd in dB, against
    # central differences of the exact detectability D (Swerling 0, square law, N pulses)
    out, rep = ore
    jac = rep["jacobian"]
    names = [i["name"] for i in jac["inputs"]]
    pd = jac["inputs"][names.index("pd")]["value"]
    n = rep["design"]["n_pulses"]["value"]
    h = 1e-3

    def detectability(q_db):
        return float(required_snr_db(1.0 - 10 ** (q_db / 10.0), 1e-12, n, 0))

    q0 = 10 * math.log10(1.0 - pd)
    expected = -(detectability(q0 + h) - detectability(q0 - h)) / (2 * h)
    got = jac["elasticity"][0][names.index("pd")]
    assert got == pytest.approx(expected, rel=1e-5)
    assert 0.0 < got < 1.0  # more misses allowed, more margin: a fraction of a dB per dB, not -9.5
    # so the fixed pd no longer tops the margin's tornado
    E = np.abs(np.asarray(jac["elasticity"][0], dtype=float))
    assert names[int(np.nanargmax(E))] != "pd"


def test_stoplight_and_what_sets_the_design_agree_with_the_exact_slacks(ore):
    out, rep = ore
    model = DesignModel(load_spec(ORE))
    md = (out / "report.md").read_text()
    glance = md.split("## At a glance", 1)[1].split("\n## ", 1)[0]
    for r, scale in zip(rep["requirements"], model.scales):
        expected = "ACTIVE" if r["slack"] / scale <= 1e-6 else "met"
        assert re.search(rf"\| {expected} \| {re.escape(r['name'])} \|", glance), (r["name"], r["slack"])
    assert rep["findings"]["active"] == ["beam inside the pass (6 m at 300 m)"]
    assert rep["findings"]["choice"] == {"freq_hz": "94 GHz", "transmitter": "Gunn oscillator, 20 dBm"}
    assert "### Most sensitive inputs of the tightest requirement ('beam inside the pass (6 m at 300 m)')" in glance
    assert md.index("## At a glance") < md.index("## Design")


def test_a_design_set_by_a_bound_and_a_check_requirement_are_said(sonar):
    out, rep = sonar
    warnings = rep["findings"]["warnings"]
    assert ("electrical_power_w", "lower") in [tuple(b) for b in rep["findings"]["bounds"]]
    assert any(w.startswith("electrical_power_w at its lower bound") and "every requirement has slack" in w
               for w in warnings), warnings
    assert "requirement 'pulse within the duty-cycle limit' does not depend on any variable: it is a check, " \
           "not a constraint" in warnings
    # a pulse's range resolution c tau / 2 = 0.3 m is fixed too; the detection margin moves
    assert rep["findings"]["fixed"] == ["range resolution", "pulse within the duty-cycle limit"]
    assert rep["requirements"][1]["value"] == pytest.approx(1500 * 0.4e-3 / 2, rel=1e-12)
    md = (out / "report.md").read_text()
    assert "### Warnings" in md.split("## Design", 1)[0]
