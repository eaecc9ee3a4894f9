"""The ``[[requirements]]`` section: what the design must achieve, one output and limit each::

    [[requirements]]
    output = "snr_margin_db"      # "<case>.<output>" when the spec has several cases
    at_least = "0 dB"             # or at_most / equals, in the output's unit
    name = "detection margin"     # optional label (default: the output key)
    goal = "3 dB"                 # optional objective beyond the threshold: PASS / WARN / FAIL

A spec needs at least one requirement. ``goal`` (``at_least`` or ``at_most`` only) is the value the
design should reach beyond the threshold: a requirement then reads PASS (goal met), WARN (only
the threshold met) or FAIL, as the threshold and objective of MATLAB's Radar Designer; the
optimiser meets the thresholds.
"""

from __future__ import annotations

from typing import List, Mapping

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.intervals import OVER_KEYS, read_over
from diffsense.design.spec.common import closest, echo, plain_text, quantity, reject_unknown, split_case
from diffsense.design.spec.types import SENSES, Requirement
from diffsense.design.spec.uncertain import read_probability
from diffsense.errors import SpecError
from diffsense.scene import describe_command

REQUIREMENT_KEYS = {"output", "name", "doc", "probability", "goal"} | set(SENSES) | OVER_KEYS


def read_requirements(file, raw: Mapping, cases: Cases, design_names=frozenset()) -> List[Requirement]:
    """The requirements, in the order of the spec; each limit in its output's unit.
    ``design_names``: the parameters set by variables and catalogs (not allowed in ``over``)."""
    rraw = raw.get("requirements")
    if not rraw:
        raise SpecError(file, "requirements", "missing: a spec needs at least one [[requirements]] entry")
    if not isinstance(rraw, list) or not all(isinstance(r, dict) for r in rraw):
        raise SpecError(file, "requirements", "must be an array of tables ([[requirements]])")
    return [_requirement(file, f"requirements[{i}]", r, cases, design_names) for i, r in enumerate(rraw)]


def _requirement(file, key: str, r: Mapping, cases: Cases, design_names=frozenset()) -> Requirement:
    reject_unknown(file, key + ".", r, REQUIREMENT_KEYS)
    if "output" not in r:
        raise SpecError(file, f"{key}.output", "missing")
    case, out = split_case(file, f"{key}.output", r["output"], cases.scenes)
    outputs = cases.outputs[case]
    if out not in outputs:
        raise SpecError(file, f"{key}.output", f"unknown output {echo(out, 60)}{closest(out, outputs)}; "
                        f"run '{describe_command(cases.scenes[case])}' for the outputs")
    senses = [s for s in SENSES if s in r]
    if len(senses) != 1:
        raise SpecError(file, key, f"needs exactly one of {list(SENSES)}")
    unit = outputs[out].unit
    limit = quantity(file, f"{key}.{senses[0]}", r[senses[0]], unit)
    label = plain_text(file, f"{key}.name", r["name"]) if "name" in r else r["output"]
    over, points, worst = read_over(file, key, r, case, cases, design_names)
    probability = read_probability(file, key, r)
    goal = _goal(file, key, r, senses[0], limit, unit)
    return Requirement(label, case, out, senses[0], limit, unit, over, points, worst, probability, goal)


def _goal(file, key: str, r: Mapping, sense: str, limit: float, unit: str):
    """The requirement's ``goal`` in the output's unit (None when absent): beyond the threshold
    on the side the sense asks for."""
    if "goal" not in r:
        return None
    if sense == "equals":
        raise SpecError(file, f"{key}.goal", "an equality has no goal beyond it; use at_least or at_most")
    goal = quantity(file, f"{key}.goal", r["goal"], unit)
    if (goal < limit) if sense == "at_least" else (goal > limit):
        side = "at or above" if sense == "at_least" else "at or below"
        raise SpecError(file, f"{key}.goal", f"must lie {side} the threshold {sense} = {limit:g} {unit}; got {goal:g} {unit}")
    return goal
