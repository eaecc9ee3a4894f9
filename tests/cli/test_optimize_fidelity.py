"""``diffsense optimize`` of a ``fidelity = "fast"`` spec re-evaluates its answer with the exact
models and reports the difference of every requirement."""

import json

import pytest

from diffsense.design.spec import load_spec
from diffsense.design.spec import fidelity as fid
from helpers.paths import REPO

NAV = REPO / "tests" / "design" / "trade_specs" / "navigation_radar.toml"


@pytest.fixture
def shnidman_is_fast(monkeypatch):
    monkeypatch.setattr(fid, "FAST_OPTIONS", {"radar": {"detectability": ("shnidman", "test")}})


def test_optimize_re_evaluates_a_fast_answer_with_the_exact_models(shnidman_is_fast, run_cli, tmp_path):
    spec = tmp_path / "nav_fast.toml"
    spec.write_text(NAV.read_text().replace('detectability = "exact"\n', 'fidelity = "fast"\n'))
    code, out, err = run_cli("optimize", spec, "--starts", 2, "--json", tmp_path / "o.json")
    assert code in (0, 3), err
    rec = json.loads((tmp_path / "o.json").read_text())
    check = rec["exact_check"]
    assert check["switched"] == {"detectability": "shnidman"}
    # independently: the exact spec evaluated at the same design
    from diffsense.design.model import DesignModel
    from diffsense.design.record import design_record

    exact = DesignModel(fid.exact_spec(load_spec(spec)))
    x = [rec["design"][n]["value"] for n in exact.variable_names]
    combo = exact.combo_index(rec["choices"])
    truth = design_record(exact, x, combo)["requirements"]
    for r, t, f in zip(check["requirements"], truth, rec["requirements"]):
        assert r["exact"] == pytest.approx(t["value"], rel=1e-9, abs=1e-9)
        assert r["fast"] == pytest.approx(f["value"], rel=1e-12, abs=1e-12)
        assert r["met"] == t["met"]
    # Shnidman's equation differs from the exact detectability: the margins move, the others do not
    assert abs(check["requirements"][0]["difference"]) > 1e-4
    assert check["requirements"][2]["difference"] == 0.0  # the beamwidth
    assert "re-evaluated with the exact models" in " ".join(out.split())


def test_fast_takes_the_chebyshev_detectability_and_its_answer_holds_exactly(run_cli, tmp_path):
    """The atlas's fast choice for the radar: the re-evaluation with the exact detectability moves
    each detection margin by at most the interpolant's stated error (the beam not at all)."""
    from diffsense.detection.chebyshev_snr import ERROR_BOUND_DB

    assert fid.FAST_OPTIONS["radar"]["detectability"][0] == "chebyshev"
    spec = tmp_path / "nav_fast.toml"
    spec.write_text(NAV.read_text().replace('detectability = "exact"\n', 'fidelity = "fast"\n'))
    code, out, err = run_cli("optimize", spec, "--starts", 2, "--json", tmp_path / "o.json")
    assert code == 0, err
    check = json.loads((tmp_path / "o.json").read_text())["exact_check"]
    assert check["switched"] == {"detectability": "chebyshev"} and check["met"]
    margins = [r for r in check["requirements"] if r["unit"] == "dB"]
    assert len(margins) == 2 and all(0.0 < abs(r["difference"]) <= ERROR_BOUND_DB for r in margins)
    assert check["requirements"][2]["difference"] == 0.0  # the beamwidth


def test_fast_without_an_atlas_approved_choice_says_the_exact_models_were_used(run_cli, tmp_path, monkeypatch):
    monkeypatch.setattr(fid, "FAST_OPTIONS", {})
    spec = tmp_path / "nav_fast.toml"
    spec.write_text(NAV.read_text().replace('detectability = "exact"\n', 'fidelity = "fast"\n'))
    code, out, err = run_cli("optimize", spec, "--starts", 1, "--json", tmp_path / "o.json")
    assert code == 0, err
    assert "fidelity fast: no faster model choice of this spec is within the atlas's bound" in " ".join(out.split())
    assert "exact_check" not in json.loads((tmp_path / "o.json").read_text())
