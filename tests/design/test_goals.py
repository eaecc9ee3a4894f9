"""``[objective] reach_goals``: after the thresholds, the goals are bought cheapest first.

The side-scan sonar spec (least electrical power detecting a 1 m sphere from 50 to 750 m) with
three goals, each with an answer known in closed form:

- SNR margin at least 0 dB, goal 3 dB: the sonar equation is linear in 10 log10 of the source
  power, so with the other variables where they were, the goal's power is 10^(3/10) times the
  threshold's, and the optimum must equal the spec solved with 3 dB as its threshold;
- range resolution at most 0.1 m, goal 0.05 m: met by the thresholds' optimum already (free);
- cross-range resolution at most 15 m, goal 12 m: the beam cannot be narrower than 1 deg, and
  750 m x 1 deg = 13.09 m > 12 m, so no design reaches it (unreachable).
"""

import dataclasses
import math

import pytest

from diffsense.design.goals import goal_statuses, optimize_with_goals
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import optimize_design
from diffsense.design.spec import load_spec
from diffsense.errors import SpecError
from helpers.paths import DESIGNS


def _spec_text(reach="true"):
    text = (DESIGNS / "sidescan_sonar.toml").read_text()
    text = text.replace('at_least = "0 dB"\n', 'at_least = "0 dB"\ngoal = "3 dB"\n', 1)
    text = text.replace('at_most = "0.1 m"\n', 'at_most = "0.1 m"\ngoal = "0.05 m"\n', 1)
    text = text.replace('at_most = "15 m"\n', 'at_most = "15 m"\ngoal = "12 m"\n', 1)
    return text.replace('minimize = "electrical_power_w"\n', f'minimize = "electrical_power_w"\nreach_goals = {reach}\n')


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    path = tmp_path_factory.mktemp("goals") / "sonar_goals.toml"
    path.write_text(_spec_text())
    return load_spec(path)


def test_goals_are_bought_cheapest_first_and_checked(spec):
    model = DesignModel(spec)
    thresholds = optimize_design(model, n_starts=4)
    optimum, plan = optimize_with_goals(model, n_starts=4)
    assert thresholds.feasible and optimum.feasible
    assert [b["name"] for b in plan.bought] == [spec.requirements[0].name]
    assert plan.free == [spec.requirements[1].name]
    assert plan.unreachable == [spec.requirements[2].name]
    bought = plan.bought[0]
    assert bought["objective_before"] == pytest.approx(thresholds.objective, rel=1e-9)
    assert optimum.objective / thresholds.objective == pytest.approx(10 ** 0.3, rel=1e-6)
    # the same design as the spec solved with the goal as its threshold
    raised = [dataclasses.replace(r, limit=r.goal) if j == 0 else r for j, r in enumerate(spec.requirements)]
    direct = optimize_design(DesignModel(dataclasses.replace(spec, requirements=raised)), n_starts=4)
    assert optimum.objective == pytest.approx(direct.objective, rel=1e-9)
    # re-checked against the spec's own thresholds and goals: PASS, PASS, WARN
    assert goal_statuses(model, optimum) == ["PASS", "PASS", "WARN"]
    assert 750.0 * math.radians(1.0) > 12.0  # why the cross-range goal is out of reach


@pytest.mark.parametrize("edit,message", [
    (lambda t: t.replace("reach_goals = true", 'reach_goals = "yes"'), "must be true or false"),
    (lambda t: t.replace('goal = "3 dB"\n', "").replace('goal = "0.05 m"\n', "").replace('goal = "12 m"\n', ""),
     "no requirement has a goal"),
])
def test_bad_reach_goals_is_one_clear_line(tmp_path, edit, message):
    path = tmp_path / "bad.toml"
    path.write_text(edit(_spec_text()))
    with pytest.raises(SpecError, match=message) as err:
        load_spec(path)
    assert "objective.reach_goals" in str(err.value) and "\n" not in str(err.value)
