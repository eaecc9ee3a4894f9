"""The ``[[requirements]]`` section: what the design must achieve, one output and limit each::

    [[requirements]]
    output = "snr_margin_db"      # "<case>.<output>" when the spec has several cases
    at_least = "0 dB"             # or at_most / equals, in the output's unit
    name = "detection margin"     # optional label (default: the output key)

A spec needs at least one requirement.
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

REQUIREMENT_KEYS = {"output", "name", "doc", "probability"} | set(SENSES) | OVER_KEYS


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
    return Requirement(label, case, out, senses[0], limit, unit, over, points, worst, probability)
