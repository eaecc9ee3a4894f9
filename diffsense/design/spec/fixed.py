"""The ``[fixed]`` section and the per-case overrides: the parameter values the designer does
not change, per case, converted to each parameter's unit and checked against its domain::

    [fixed]
    range_m = "300 m"
    [cases.far]
    range_m = "1 km"              # overrides [fixed] in case "far"

A ``[fixed]`` value of a parameter that only some cases have (it belongs to a part of those
cases) is ignored in the others. Every parameter without a default must be fixed or be a
design variable in every case.
"""

from __future__ import annotations

from typing import Dict, Mapping, Set

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import key_text, optional_table, parameter_value, unknown_parameter
from diffsense.design.spec.types import DEFAULT_CASE
from diffsense.errors import SpecError


def read_fixed(file, raw: Mapping, cases: Cases, chosen: Set[str]) -> Dict[str, Dict[str, float]]:
    """case -> parameter -> value; ``chosen``: the design parameters (they cannot be fixed)."""
    fraw = optional_table(file, raw, "fixed")
    return {cname: _case_values(file, cname, fraw, cases, chosen) for cname in cases.scenes}


def _case_values(file, cname: str, fraw: Mapping, cases: Cases, chosen: Set[str]) -> Dict[str, float]:
    table = cases.parameters[cname]
    vals: Dict[str, float] = {}
    for src, prefix in ((fraw, "fixed."), (cases.overrides[cname], f"cases.{cname}.")):
        for pname, pval in src.items():
            key = prefix + key_text(pname)
            if pname not in table:
                if src is fraw and pname in cases.all_parameters:
                    continue  # belongs to a part only some cases have
                raise unknown_parameter(file, key, pname, cases.scenes[cname], table)
            if pname in chosen:
                raise SpecError(file, key, f"'{pname}' is a design variable; it cannot also be fixed")
            vals[pname] = parameter_value(file, key, table[pname], pval)
    missing = [n for n, p in table.items() if p.default is None and n not in vals and n not in chosen]
    if missing:
        where = "fixed" if cname == DEFAULT_CASE else f"cases.{cname}"
        raise SpecError(file, f"{where}.{missing[0]}", f"missing required parameter(s) {missing}")
    return vals
