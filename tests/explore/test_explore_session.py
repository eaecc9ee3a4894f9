"""The explorer's session without a browser: the same numbers as the design record, a saved spec
read back unchanged, the command line's messages for bad typed values, and the stoplight."""

from pathlib import Path

import pytest

from diffsense.design.record import design_record
from diffsense.design.spec import load_spec
from diffsense.errors import SpecError
from diffsense.explore.session import ACTIVE_SLACK, ExplorerSession, requirement_status
from diffsense.report.files import safe_name
from helpers.paths import DESIGNS

SPECS = Path(__file__).parent / "specs"


@pytest.fixture(scope="module")
def session():
    return ExplorerSession(DESIGNS / "ore_pass.toml")


def test_status_is_a_stoplight():
    assert requirement_status(False, -1.0) == "unmet"
    assert requirement_status(True, ACTIVE_SLACK / 2) == "active"
    assert requirement_status(True, 1.0) == "met"


def test_saved_point_reads_back_and_evaluates_as_shown(session, tmp_path):
    s = session.fork()
    s.set_option("freq_hz", "94 GHz")
    s.set_variable("antenna_diameter_m", 0.3)
    s.set_variable("n_pulses", 20.4)
    snap = s.snapshot()
    s.out_dir = tmp_path
    spec = load_spec(s.save("here"))
    assert spec.variables["antenna_diameter_m"].initial == 0.3 and spec.variables["n_pulses"].initial == 20
    assert spec.choices["freq_hz"].option_names[0] == "94 GHz"
    again = ExplorerSession(tmp_path / "here.toml")
    record = design_record(again.model, again.model.initial, 0)
    assert snap["cases"]["main"]["outputs"]["snr_db"] == pytest.approx(
        record["cases"]["main"]["outputs"]["snr_db"]["value"], rel=1e-9)
    assert [r["met"] for r in snap["requirements"]] == [r["met"] for r in record["requirements"]]
    assert snap["objective"] == pytest.approx(record["objective"]["value"], rel=1e-12)


def test_interval_curves_and_worst_values_agree_with_the_design_record(session):
    # the page's worst values use the value-only polish; the record the optimiser's Newton polish
    # and the 10,001-point re-check: both must give the same worst value of each interval
    s = session.fork()
    s.set_variable("antenna_diameter_m", 0.4)
    snap = s.snapshot()
    assert set(snap["intervals"]) == {r.name for r in s.model.requirements if r.over}
    spec = s.spec_here()
    model = type(s.model)(spec)
    record = design_record(model, model.initial, s.combo_index)
    rows = {r["name"]: r for r in record["requirements"]}
    for name, curve in snap["intervals"].items():
        row = rows[name]
        assert curve["worst_value"] == pytest.approx(row["value"], rel=1e-9, abs=1e-9), name
        worst_on_curve = min(curve["values"]) if curve["sense"] == "at_least" else max(curve["values"])
        assert (worst_on_curve >= curve["worst_value"] - 1e-9) if curve["sense"] == "at_least" else \
            (worst_on_curve <= curve["worst_value"] + 1e-9)
        # a curve point is the chain's output at that value of the parameter
        case = spec.requirements[[r.name for r in spec.requirements].index(name)].case
        k = len(curve["grid"]) // 3
        params = dict(model.parameters(model.design_values(model.initial, s.combo_index))[case])
        params[curve["parameter"]] = curve["grid"][k]
        direct = s.model.intervals.value_at([r.name for r in spec.requirements].index(name), params,
                                            [curve["grid"][k]])
        assert curve["values"][k] == pytest.approx(float(direct), rel=1e-12, abs=1e-12)


def test_bad_typed_values_give_the_spec_message(session):
    s = session.fork()
    with pytest.raises(SpecError, match="key 'fixed.range_m'"):
        s.type_fixed("range_m", "-3 m")
    with pytest.raises(SpecError, match="key 'variables.antenna_diameter_m.initial'"):
        s.type_variable("antenna_diameter_m", "3 m")
    assert s.type_fixed("range_m", "250 m") == 250.0
    assert s.type_variable("antenna_diameter_m", "300 mm") == pytest.approx(0.3)


@pytest.fixture(scope="module")
def sonar():
    """One variable (electrical power): compiles in seconds."""
    return ExplorerSession(SPECS / "sonar_power.toml")


def test_optimize_from_here_moves_the_point_to_the_closed_form_optimum(sonar):
    # SL grows as 10 log10 P and nothing else depends on P: P* = P0 10^(-m0/10) (spec description)
    s = sonar.fork()
    p0 = s.set_variable("electrical_power_w", 400.0)
    start = s.snapshot()
    m0 = start["cases"]["main"]["outputs"]["snr_margin_db"]
    assert start["requirements"][0]["status"] == "unmet"
    result = s.optimize()
    assert result.feasible
    p_star = p0 * 10 ** (-m0 / 10)
    assert s.value("electrical_power_w") == pytest.approx(p_star, rel=1e-5)
    here = s.snapshot()
    assert here["objective"] == pytest.approx(p_star, rel=1e-5)
    assert here["cases"]["main"]["outputs"]["snr_margin_db"] == pytest.approx(0.0, abs=1e-4)
    assert here["requirements"][0]["status"] == "active"


def test_report_of_the_current_point(sonar, tmp_path):
    s = sonar.fork()
    s.set_variable("electrical_power_w", 2000.0)
    snap = s.snapshot()
    s.out_dir = tmp_path
    record = s.report("report")
    written = load_spec(tmp_path / "report" / "sonar_power.toml")
    assert written.variables["electrical_power_w"].initial == 2000.0
    assert record["mode"] == "initial_design"
    assert record["design"] and record["objective"]["value"] == pytest.approx(2000.0, rel=1e-12)
    assert float(record["cases"]["main"]["outputs"]["snr_margin_db"]["value"]) == pytest.approx(
        snap["cases"]["main"]["outputs"]["snr_margin_db"], rel=1e-12)
    assert [r["met"] for r in record["requirements"]] == [r["met"] for r in snap["requirements"]]
    for kind in ("html", "md", "json"):
        assert Path(record["files"][kind]).parent == tmp_path / "report" and Path(record["files"][kind]).is_file()


def test_the_page_shows_spec_strings_as_text(tmp_path):
    """A title (and any message) holding markup is shown as text: escaped in every HTML pane."""
    import json

    import panel as pn

    from diffsense.explore.page import ExplorerPage

    payload = '<img src=x onerror="document.title=\'owned\'">'
    text = (SPECS / "sonar_power.toml").read_text()
    text = "\n".join(f"title = {json.dumps(payload)}" if line.startswith("title") else line for line in text.splitlines())
    spec = tmp_path / "hostile.toml"
    spec.write_text(text + "\n")
    page = ExplorerPage(ExplorerSession(spec))
    page.say(f"cannot read {payload}", "error")
    html = [p.object for p in page.layout.select(pn.pane.HTML)] + [page.message.object]
    assert not any("<img" in h for h in html), [h for h in html if "<img" in h]
    assert any("&lt;img src=x onerror=&quot;document.title=&#x27;owned&#x27;&quot;&gt;" in h for h in html)


def test_files_go_only_into_the_output_folder_and_replace_only_when_confirmed(sonar, tmp_path):
    from diffsense.explore.session import FileExists, default_output_folder
    from diffsense.report.files import OutputError

    assert default_output_folder(tmp_path / "a" / "my spec.toml") == tmp_path / "a" / f"{safe_name('my spec')}_explored"
    s = sonar.fork()
    opened = Path(s.path)
    before = opened.read_bytes()
    s.out_dir = opened.parent  # even an output folder holding the spec: never written over
    with pytest.raises(OutputError, match="spec this explorer opened"):
        s.save(opened.name, replace=True)
    assert opened.read_bytes() == before
    s.out_dir = tmp_path / "out"
    for name in ("../../escaped", "/etc/passwd", "~/x", "a\\..\\b"):  # a name, never a path
        path = s.save(name)
        assert path.parent == tmp_path / "out" and path.suffix == ".toml", path
    assert not (tmp_path / "escaped.toml").exists() and sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    mine = tmp_path / "out" / "mine.toml"
    mine.write_text("# my notes\n")
    with pytest.raises(FileExists):
        s.save("mine")
    assert mine.read_text() == "# my notes\n"
    s.set_variable("electrical_power_w", 1500.0)
    s.save("mine", replace=True)  # the user confirmed on the page
    assert load_spec(mine).variables["electrical_power_w"].initial == 1500.0
    s.report("report")
    with pytest.raises(FileExists):
        s.report("report")


def test_a_report_of_a_spec_named_like_a_path_stays_in_its_folder(tmp_path):
    import json

    text = (SPECS / "sonar_power.toml").read_text().replace('name = "sonar_power"', 'name = "../../escaped"', 1)
    spec = tmp_path / "a" / "b" / "spec.toml"
    spec.parent.mkdir(parents=True)
    spec.write_text(text)
    s = ExplorerSession(spec)
    assert s.out_dir == tmp_path / "a" / "b" / "spec_explored"
    s.report("report")
    out = s.out_dir / "report"
    assert not list(tmp_path.rglob("escaped.toml"))
    assert [p.name for p in out.glob("*.toml")] == ["escaped-" + p.name.split("-")[-1] for p in out.glob("*.toml")]
    assert json.loads((out / "report.json").read_text())["written_by"] == "diffsense"
