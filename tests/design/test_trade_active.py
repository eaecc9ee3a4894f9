"""The active requirements along a trade front are the requirements met with zero slack: the
rows of an interval requirement (one per worst point) are mapped to their requirement, never by
position (a navigation radar whose rain requirement keeps tens of dB of slack along the front)."""

from pathlib import Path

import numpy as np
import pytest

from diffsense.design.activity import ACTIVE_SLACK, active_mask
from diffsense.design.model import DesignModel
from diffsense.design.spec import load_spec
from diffsense.design.trade import trade_design, trade_spec

SPECS = Path(__file__).parent / "trade_specs"


@pytest.fixture(scope="module")
def navigation_front():
    model = DesignModel(trade_spec(load_spec(SPECS / "navigation_radar.toml")))
    return model, trade_design(model, points=6)


def test_interval_requirements_carry_several_rows(navigation_front):
    model, _ = navigation_front
    counts = np.bincount(model.row_owner, minlength=len(model.requirements))
    assert counts[0] >= 3 and counts[1] >= 3 and counts[2] == 1  # over_worst = 3 (+ exchange points)


def test_active_list_is_the_zero_slack_requirements(navigation_front):
    model, result = navigation_front
    assert len(result.points) >= 5
    clear, rain, beam = (r.name for r in model.requirements)
    for p in result.points:
        slack = {r["name"]: r["slack"] / s for r, s in zip(p["requirements"], model.scales)}
        exact = {name for name, s in slack.items() if abs(s) <= ACTIVE_SLACK}
        assert set(p["active"]) == exact, (p["active"], slack)
        # the clear-air detection sets the power along the whole front; rain never does
        assert clear in p["active"]
        assert rain not in p["active"] and slack[rain] > 10.0
    # the beamwidth limit holds the smallest antenna: active at that anchor only
    sizes = [p["x"][model.variable_names.index("antenna_diameter_m")] for p in result.points]
    smallest = result.points[int(np.argmin(sizes))]
    assert beam in smallest["active"]
    assert sum(beam in p["active"] for p in result.points) == 1


class _Model:
    """Three requirements: an interval one with three rows, then two point ones."""

    scales = np.ones(3)
    is_equality = np.zeros(3, dtype=bool)
    row_owner = np.array([0, 0, 0, 1, 2])
    row_is_equality = np.zeros(5, dtype=bool)
    requirements = [None] * 3

    from diffsense.design.model import DesignModel as _D

    inequality_multipliers = _D.inequality_multipliers
    row_multipliers = _D.row_multipliers


def test_row_multipliers_go_to_their_owner_not_to_the_row_position():
    m = _Model()
    # the third worst row of requirement 0 carries the multiplier; 1 and 2 have slack
    lam = m.inequality_multipliers(np.array([0.0, 0.0, 0.7, 0.0, 0.0]))
    assert lam.tolist() == [0.7, 0.0, 0.0]
    rows = [{"slack": 0.0}, {"slack": 10.5}, {"slack": 0.31}]
    assert active_mask(m, rows, lam).tolist() == [True, False, False]
    # a positive multiplier on a requirement with visible slack does not make it active
    assert active_mask(m, rows, np.array([0.0, 0.2, 0.0])).tolist() == [True, False, False]


def test_trade_report_opens_with_the_stoplight_of_the_front(navigation_front, tmp_path):
    from diffsense.report.trade import write_trade_report

    model, result = navigation_front
    write_trade_report(result, tmp_path)
    md = (tmp_path / "trade.md").read_text()
    glance = md.split("## At a glance", 1)[1].split("\n## ", 1)[0]
    n = len(result.points)
    clear, rain, beam = (r.name for r in model.requirements)
    assert f"| ACTIVE | {clear} | {n} of {n} points |" in glance
    assert f"| met | {rain} | 0 of {n} points |" in glance
    assert f"| ACTIVE | {beam} | 1 of {n} points |" in glance
    # the rain requirement's smallest slack over the front, from the exact re-evaluation
    smallest = min(p["requirements"][1]["slack"] for p in result.points)
    assert smallest > 10.0 and f"{smallest:.5g} dB" in glance
    assert md.index("## At a glance") < md.index("## Anchors and knee")
