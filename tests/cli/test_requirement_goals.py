"""Requirements with a threshold and a goal (``goal = ...``): PASS / WARN / FAIL.

The side-scan sonar spec evaluated at its initial design (1500 W, 15 kHz chirp, 1.5 deg beam):
its values are computed independently of the goals, so each verdict is checked against the
definition: PASS when the value reaches the goal, WARN when it meets only the threshold, FAIL
when it misses the threshold.
"""

import json

import pytest

from diffsense.design.spec import load_spec
from diffsense.design.spec.types import goal_status
from helpers.paths import DESIGNS


def _spec_with_goals(tmp_path, margin_goal, resolution_goal, margin_threshold="0 dB"):
    text = (DESIGNS / "sidescan_sonar.toml").read_text()
    text = text.replace('at_least = "0 dB"\n', f'at_least = "{margin_threshold}"\ngoal = "{margin_goal}"\n', 1)
    text = text.replace('at_most = "15 m"\n', f'at_most = "15 m"\ngoal = "{resolution_goal}"\n', 1)
    path = tmp_path / "sonar_goals.toml"
    path.write_text(text)
    return path


def test_goals_are_read_in_the_outputs_unit(tmp_path):
    spec = load_spec(_spec_with_goals(tmp_path, "3 dB", "1000 cm"))
    goals = [r.goal for r in spec.requirements]
    assert goals == [3.0, None, pytest.approx(10.0)]


def test_goal_status_reads_each_row_against_its_goal_and_threshold(tmp_path, run_cli):
    path = _spec_with_goals(tmp_path, "1000 dB", "1 m", margin_threshold="-100 dB")
    code, out, _ = run_cli("evaluate", path, "--json", tmp_path / "ev.json")
    rows = json.loads((tmp_path / "ev.json").read_text())["requirements"]
    margin, resolution, cross = rows
    assert "goal" not in resolution
    # the initial design meets a -100 dB threshold but not a 1000 dB goal: WARN
    assert margin["met"] and margin["value"] < 1000 and margin["goal_status"] == "WARN"
    # cross-range resolution at most 15 m, goal 1 m
    expect = "FAIL" if not cross["met"] else ("PASS" if cross["value"] <= 1.0 else "WARN")
    assert cross["goal_status"] == expect
    assert cross["goal"] == 1.0
    # the terminal table shows the goal column
    assert "goal" in out and "WARN" in out and "1000" in out


def test_goal_met_reads_pass(tmp_path, run_cli):
    path = _spec_with_goals(tmp_path, "0 dB", "15 m")
    run_cli("evaluate", path, "--json", tmp_path / "ev.json")
    rows = json.loads((tmp_path / "ev.json").read_text())["requirements"]
    for row in rows:
        if "goal" in row:
            assert row["goal_status"] == ("PASS" if row["met"] else "FAIL")


@pytest.mark.parametrize("sense,value,limit,goal,met,status", [
    ("at_least", 5.0, 0.0, 3.0, True, "PASS"), ("at_least", 1.0, 0.0, 3.0, True, "WARN"),
    ("at_least", -1.0, 0.0, 3.0, False, "FAIL"), ("at_most", 0.5, 1.0, 0.5, True, "PASS"),
    ("at_most", 0.9, 1.0, 0.5, True, "WARN"), ("at_most", 1.2, 1.0, 0.5, False, "FAIL"),
])
def test_goal_status_definition(sense, value, limit, goal, met, status):
    assert goal_status(sense, value, limit, goal, met) == status
