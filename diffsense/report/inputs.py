"""The numeric inputs of a design and one function of all of them.

A report differentiates the requirement outputs with respect to *every* number the design
depends on, not only the design variables. :func:`design_inputs` lists them in one vector:

* ``variable`` — the spec's continuous and integer design variables (value at the design),
* ``catalog`` — every parameter set by the chosen catalog option (e.g. ``freq_hz``),
* ``fixed`` — every other numeric parameter of every case: the spec's ``[fixed]`` values and
  the chain defaults it did not override.

A fixed parameter that holds the same value in every case containing it is one input; one
that differs between cases (e.g. each case's ``range_m``) is one input per case, named
``<case>.<parameter>``.

:func:`input_evaluator` returns a pure JAX function of that vector giving each case's chain
evaluation, the requirement outputs and the objective — the same numbers as
:class:`~diffsense.design.model.DesignModel` at the same design, but with the fixed parameters
traced as well.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

import jax.numpy as jnp
import numpy as np

from diffsense.scene import chain_for
from diffsense.design.model import DesignModel

KINDS = ("variable", "catalog", "fixed")


@dataclass(frozen=True)
class Input:
    """One numeric input of the design.

    ``name``: display name (parameter name, or ``<case>.<parameter>``); ``param``: the chain
    parameter it sets; ``cases``: the cases it feeds; ``kind``: one of :data:`KINDS`;
    ``unit``: the parameter's unit; ``value``: its value at the design; ``lo``/``hi``: the
    chain's documented domain (``None`` when unbounded); ``integer``: a count relaxed to reals.
    """

    name: str
    param: str
    cases: Tuple[str, ...]
    kind: str
    unit: str
    value: float
    lo: Optional[float]
    hi: Optional[float]
    integer: bool
    doc: str


def _domain(model: DesignModel, param: str, cases) -> tuple:
    prm = model.spec.parameters[cases[0]][param]
    return prm.lo, prm.hi, bool(prm.integer), prm.doc


def design_inputs(model: DesignModel, x, combo_index: int) -> List[Input]:
    """All numeric inputs at design ``x`` (variables, their units) and catalog row ``combo_index``."""
    spec = model.spec
    x = np.asarray(x, dtype=float)
    combo = model.combo_table[combo_index]
    cases = list(spec.scenes)
    out: List[Input] = []

    def cases_with(param):
        return tuple(c for c in cases if param in spec.parameters[c])

    for i, name in enumerate(model.variable_names):
        cs = cases_with(name)
        lo, hi, integer, doc = _domain(model, name, cs)
        out.append(Input(name, name, cs, "variable", spec.variables[name].unit, float(x[i]), lo, hi,
                         bool(spec.variables[name].integer), doc))
    for j, name in enumerate(model.combo_params):
        cs = cases_with(name)
        lo, hi, integer, doc = _domain(model, name, cs)
        out.append(Input(name, name, cs, "catalog", spec.unit_of(cs[0], name), float(combo[j]), lo, hi, integer, doc))
    names: List[str] = []
    for c in cases:
        for name in model.fixed[c]:
            if name not in names:
                names.append(name)
    for name in names:
        cs = tuple(c for c in cases if name in model.fixed[c])
        values = [float(np.asarray(model.fixed[c][name])) for c in cs]
        groups = [cs] if all(v == values[0] for v in values) else [(c,) for c in cs]
        for group in groups:
            lo, hi, integer, doc = _domain(model, name, group)
            label = name if len(groups) == 1 else f"{group[0]}.{name}"
            value = float(np.asarray(model.fixed[group[0]][name]))
            out.append(Input(label, name, group, "fixed", spec.unit_of(group[0], name), value, lo, hi, integer, doc))
    return out


def input_vector(inputs: List[Input]) -> np.ndarray:
    """The values of ``inputs`` as a float64 vector."""
    return np.array([i.value for i in inputs], dtype=float)


def case_parameters(spec, inputs: List[Input], v) -> Dict[str, dict]:
    """Per case, the chain's parameter dict (arrays) at input vector ``v`` (or a dict
    ``{input index: value}``, as :func:`input_evaluator` takes)."""
    params: Dict[str, dict] = {case: {} for case in spec.scenes}
    for k, inp in enumerate(inputs):
        for case in inp.cases:
            params[case][inp.param] = jnp.asarray(v[k], dtype=float)
    return params


def input_evaluator(model: DesignModel, inputs: List[Input], combo_index: int):
    """``fn(v) -> (evaluations, requirement_values, objective)`` for an input vector ``v``.

    ``v`` may also be a dict ``{input index: value}`` covering every input; entries given as
    Python/NumPy numbers stay constants under JAX transformations (only the traced entries
    are differentiated). ``evaluations``: per case the chain's :class:`~diffsense.sensors.chain.Evaluation`;
    ``requirement_values``: the requirement outputs in spec order (their units);
    ``objective``: the spec's objective value (as stated: minimised or maximised).
    The objective's dependence on a *fixed* parameter is not traced (the model reads fixed
    values it holds itself).
    """
    spec = model.spec
    cost = float(model.combo_table[combo_index][-1])
    var_index = {i.name: k for k, i in enumerate(inputs) if i.kind == "variable"}
    cat_index = {i.name: k for k, i in enumerate(inputs) if i.kind == "catalog"}

    def fn(v):
        case_params = case_parameters(spec, inputs, v)
        evaluations = {case: chain_for(scene).compute(scene, case_params[case]) for case, scene in spec.scenes.items()}
        x = jnp.stack([jnp.asarray(v[var_index[n]], dtype=float) for n in model.variable_names]) \
            if model.variable_names else jnp.zeros((0,))
        combo = jnp.stack([jnp.asarray(v[cat_index[n]], dtype=float) for n in model.combo_params]
                          + [jnp.asarray(cost)])
        req = model.requirement_values(x, combo, evaluations, case_params)
        objective = model.raw_objective(x, combo, evaluations) * spec.objective.sign
        return evaluations, req, objective

    return fn


__all__ = ["Input", "KINDS", "design_inputs", "input_vector", "input_evaluator", "case_parameters"]
