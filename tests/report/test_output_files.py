"""The files the commands write (diffsense/report/files.py): inside the folder named, never over
the spec or a file diffsense did not write (without --force), names from spec strings made safe,
writes atomic. The command-line tests stop before any compilation, so they are quick."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffsense.cli.app import main
from diffsense.report.files import MANIFEST, OutputError, OutputFolder, check_single_file, safe_name, write_json_file

REPO = Path(__file__).resolve().parents[2]
SPEC = REPO / "designs" / "irst.toml"


def _run(args, capsys):
    with pytest.raises(SystemExit) as info:
        main(["--quiet", *map(str, args)])
    out = capsys.readouterr()
    return info.value.code, out.out, out.err


def _one_error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "Traceback" not in err, err
    return lines[0]


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=80))
def test_a_safe_name_is_one_plain_component(text):
    name = safe_name(text)
    assert re.fullmatch(r"[A-Za-z0-9_.+-]+", name), name
    assert not name.startswith(".") and ".." not in name and "/" not in name
    assert len(name) <= 48 + 7
    if re.fullmatch(r"[A-Za-z0-9+][A-Za-z0-9_.+-]*", text) and ".." not in text and "__" not in text \
            and not text.endswith((".", "_", "-")) and len(text) <= 48:
        assert name == text  # a name that is already safe is kept


@given(st.text(min_size=1, max_size=30), st.text(min_size=1, max_size=30))
def test_distinct_names_stay_distinct(a, b):
    if a != b:
        assert safe_name(a) != safe_name(b)


def test_traversal_names_stay_inside(tmp_path):
    folder = OutputFolder(tmp_path / "out")
    path = folder.write_text(f"figures/{safe_name('budget_x/../../../../escaped_case')}.png", "data")
    assert path.parent == tmp_path / "out" / "figures"
    assert not (tmp_path / "escaped_case.png").exists()
    for bad in ("../x.png", "figures/../../x.png", "/etc/x", "a//b", ".hidden"):
        with pytest.raises(OutputError):
            folder.target(bad)


def test_a_folder_never_replaces_what_diffsense_did_not_write(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("my notes")
    folder = OutputFolder(out)
    with pytest.raises(OutputError, match="report.md: exists and was not written by diffsense"):
        folder.check(["report.md"])
    assert (out / "report.md").read_text() == "my notes"
    # its own files it replaces: listed in the manifest
    folder.write_text("report.html", "one")
    again = OutputFolder(out)
    again.check(["report.html"])
    again.write_text("report.html", "two")
    assert (out / "report.html").read_text() == "two"
    assert list(json.loads((out / MANIFEST).read_text())["files"]) == ["report.html"]
    # one the user changed since is theirs now
    (out / "report.html").write_text("edited by hand")
    with pytest.raises(OutputError, match="changed since"):
        OutputFolder(out).check(["report.html"])
    # a foreign file in a subfolder it writes into is refused up front
    (out / "figures").mkdir()
    (out / "figures" / "holiday.png").write_bytes(b"\x89PNG")
    with pytest.raises(OutputError, match="holiday.png"):
        OutputFolder(out).check(folders=["figures"])
    # --force replaces, but never the spec read
    forced = OutputFolder(out, protect=[out / "spec.toml"], force=True)
    forced.write_text("report.md", "replaced")
    assert (out / "report.md").read_text() == "replaced"
    (out / "spec.toml").write_text("name = 'x'")
    with pytest.raises(OutputError, match="spec"):
        OutputFolder(out, protect=[out / "spec.toml"], force=True).target("spec.toml")
    assert not [p for p in out.rglob("*.tmp")]  # atomic writes leave no temporary files


def test_a_single_json_file(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text("x")
    with pytest.raises(OutputError, match="spec"):
        check_single_file(spec, [spec], force=True)
    mine = tmp_path / "result.json"
    mine.write_text('{"a": 1}')
    with pytest.raises(OutputError, match="not written by diffsense"):
        write_json_file(mine, {"b": 2})
    write_json_file(mine, {"b": 2}, force=True)
    write_json_file(mine, {"b": 3})  # written by diffsense now: replaced without --force
    assert json.loads(mine.read_text()) == {"written_by": "diffsense", "b": 3}
    with pytest.raises(OutputError, match="folder"):
        check_single_file(tmp_path, [spec])


def test_json_over_the_spec_is_refused_before_any_work(tmp_path, capsys):
    spec = tmp_path / "irst.toml"
    shutil.copy(SPEC, spec)
    before = spec.read_bytes()
    for command in ("evaluate", "optimize"):
        code, _, err = _run([command, spec, "--json", spec, "--force"], capsys)
        assert code == 2
        assert "refusing to write over the spec" in _one_error_line(err)
        assert spec.read_bytes() == before


def test_json_over_a_users_file_needs_force(tmp_path, capsys):
    target = tmp_path / "notes.json"
    target.write_text('{"mine": true}')
    code, _, err = _run(["evaluate", SPEC, "--json", target], capsys)
    assert code == 2 and "pass --force" in _one_error_line(err)
    assert json.loads(target.read_text()) == {"mine": True}


def test_report_and_trade_refuse_a_folder_holding_the_users_files(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("my report")
    code, _, err = _run(["report", SPEC, "--out", out], capsys)
    assert code == 2 and "report.md: exists and was not written by diffsense" in _one_error_line(err)
    assert (out / "report.md").read_text() == "my report"
    (out / "trade.md").write_text("my trade")
    code, _, err = _run(["trade", REPO / "designs" / "ore_pass.toml", "--out", out], capsys)
    assert code == 2 and "trade.md" in _one_error_line(err)
    assert (out / "trade.md").read_text() == "my trade"
    # a file where the folder should be
    code, _, err = _run(["report", SPEC, "--out", out / "report.md"], capsys)
    assert code == 2 and "is a file, not a folder" in _one_error_line(err)


def test_detection_plots_go_through_the_folder(tmp_path, capsys):
    out = tmp_path / "plots"
    code, _, err = _run(["detection", "--pulses", "1", "--pd", "0.9", "--out", out], capsys)
    assert code in (0, None), err
    written = sorted(p.name for p in out.iterdir())
    assert written == [MANIFEST, "pd_vs_snr_n1.png", "roc_swerling0_n1.png"]
    # running again replaces its own plots; a plot the user changed is refused
    code, _, err = _run(["detection", "--pulses", "1", "--pd", "0.9", "--out", out], capsys)
    assert code in (0, None), err
    (out / "roc_swerling0_n1.png").write_bytes(b"mine")
    code, _, err = _run(["detection", "--pulses", "1", "--pd", "0.9", "--out", out], capsys)
    assert code == 2 and "changed since" in _one_error_line(err)
    assert (out / "roc_swerling0_n1.png").read_bytes() == b"mine"


def test_a_report_writes_every_figure_through_its_folder(tmp_path):
    from diffsense.report import build_report

    out = tmp_path / "report"
    record = build_report(SPEC, out, optimize=False)
    # no figure lost to the way it is written (each figure function saves through the folder)
    assert not [s for s in record["skipped_figures"] if "Error" in s["reason"]], record["skipped_figures"]
    assert any(f["file"].startswith("figures/interval_") for f in record["figures"])
    listed = json.loads((out / MANIFEST).read_text())["files"]
    on_disk = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file() and p.name != MANIFEST)
    assert sorted(listed) == on_disk
    assert sorted(f["file"] for f in record["figures"]) == sorted(f for f in listed if f.startswith("figures/"))
    # the same report again replaces its own files
    build_report(SPEC, out, optimize=False)
