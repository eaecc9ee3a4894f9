"""``diffsense optimize`` says what sets the design: a design held by a variable's bound with
slack in every requirement, and requirements no variable moves, are warned about."""

import json

from helpers.paths import REPO

SONAR = REPO / "tests" / "design" / "trade_specs" / "band_sonar.toml"
ORE = REPO / "designs" / "ore_pass.toml"


def test_bound_set_design_and_check_requirements_are_warned(run_cli, tmp_path):
    code, out, err = run_cli("optimize", SONAR, "--starts", 2, "--json", tmp_path / "o.json")
    assert code == 0, err
    text = " ".join(err.split())
    assert ("warning: electrical_power_w at its lower bound; every requirement has slack: the bound sets the "
            "design, not a requirement") in text
    for name in ("range resolution", "pulse within the duty-cycle limit"):
        assert f"warning: requirement '{name}' does not depend on any variable: it is a check, not a constraint" in text
    record = json.loads((tmp_path / "o.json").read_text())
    # independently: the power sits on its 10 W bound and every requirement keeps slack
    assert abs(record["design"]["electrical_power_w"]["value"] - 10.0) <= 1e-9
    assert all(r["slack"] > 1e-3 for r in record["requirements"])
    assert record["findings"]["active"] == []
    assert "what sets the design: active: none; on a bound: electrical_power_w (lower)" in " ".join(out.split())


def test_a_design_set_by_its_requirements_has_no_warning(run_cli, tmp_path):
    code, out, err = run_cli("optimize", ORE, "--starts", 2)
    assert code == 0, err
    assert "warning:" not in err
    assert "what sets the design: active: beam inside the pass (6 m at 300 m)" in " ".join(out.split())
