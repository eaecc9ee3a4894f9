"""JSON-ready records of one design: its values with units, requirements, objective and, per
case, the link budget and every output (what ``diffsense evaluate/optimize --json`` write)."""

from __future__ import annotations

import numpy as np

from diffsense.design.model import DesignModel


def _jsonable(value):
    arr = np.asarray(value)
    return float(arr) if arr.ndim == 0 else arr.tolist()


def design_table(model: DesignModel, x, combo_index: int) -> dict:
    """name → {value, unit, kind, (lower, upper)} for every design variable and every parameter
    set by the catalog combination ``combo_index``."""
    spec = model.spec
    combo = model.combo_table[combo_index]
    design = {}
    for i, n in enumerate(model.variable_names):
        v = spec.variables[n]
        design[n] = {"value": float(x[i]), "unit": v.unit, "kind": "integer" if v.integer else "continuous",
                     "lower": v.lower, "upper": v.upper}
    first = next(iter(spec.scenes))
    for j, n in enumerate(model.combo_params):
        design[n] = {"value": float(combo[j]), "unit": spec.unit_of(first, n), "kind": "catalog"}
    return design


def design_record(model: DesignModel, x, combo_index: int, every_output: bool = True) -> dict:
    """JSON-ready description of one design: the design values with units, requirements,
    objective, and per case the link budget and its outputs — every one, or (``every_output``
    False, for a printed summary) those the requirements and the objective read."""
    spec = model.spec
    x = np.asarray(x, dtype=float)
    design = design_table(model, x, combo_index)
    choices = dict(model.combinations[combo_index].options)
    evaluations, requirements, objective = model.programs.assess(x[None, :], [combo_index], full=every_output)[0]
    cases = {}
    for case, ev in evaluations.items():
        outs = spec.outputs[case]
        cases[case] = {
            "parts": sorted(spec.scenes[case].parts),
            "options": dict(spec.scenes[case].options),
            "budget": ([{"term": n, "db": _jsonable(v)} for n, v in zip(ev.budget.names, ev.budget.values)]
                       if ev.budget is not None else []),
            "outputs": {k: {"value": _jsonable(v), "unit": outs[k].unit if k in outs else ""}
                        for k, v in ev.values.items()},
        }
    return {
        "name": spec.name,
        "title": spec.title,
        "sensor": spec.sensor,
        "design": design,
        "choices": choices,
        "requirements": requirements,
        "objective": {"text": spec.objective.text, "value": objective},
        "cases": cases,
    }
