"""Every number a spec's chains read, as one input vector with a layout fixed by the spec's structure.

A design model's compiled programs take the spec's numbers as *inputs*, never as constants, so
that editing a value in a spec reuses the compiled programs (only a change of structure — parts,
options, the variable set, the requirement set — compiles anew). The input vector lists:

* ``variable`` — each design variable (one input, feeding every case that has the parameter);
* ``catalog`` — each parameter a catalog option sets;
* ``fixed`` — every other parameter of every case: one input for the cases that take it from
  ``[fixed]`` (or from the chain's default), and one per case whose own ``[cases.<name>]``
  table sets it, named ``<case>.<parameter>``.

The grouping depends only on which section sets a parameter, never on its value, so the layout
(and with it every compiled program) is a function of the spec's structure alone.
:func:`input_layout` builds it; :class:`InputLayout` maps the vector to each case's parameter
dict and writes a design (variables and catalog row) into it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Dict, List, Optional, Tuple

import jax.numpy as jnp
import numpy as np

from diffsense.design.spec.types import Spec

#: the kinds of input, in the order they appear in the vector
KINDS = ("variable", "catalog", "fixed")


@dataclass(frozen=True)
class Input:
    """One numeric input of the design.

    ``name``: display name (parameter name, or ``<case>.<parameter>``); ``param``: the chain
    parameter it sets; ``cases``: the cases it feeds; ``kind``: one of :data:`KINDS`;
    ``unit``: the parameter's unit; ``value``: its value (at the spec's initial design, or at the
    design an :class:`InputLayout` was asked about); ``lo``/``hi``: the chain's documented domain
    (``None`` when unbounded); ``integer``: a count relaxed to reals; ``doc``: the parameter's
    description.
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

    @property
    def structure(self) -> tuple:
        """What a compiled program depends on: name, parameter, cases and kind (not the value)."""
        return (self.name, self.param, self.cases, self.kind)


def _default_groups(spec: Spec, name: str, cases: Tuple[str, ...]) -> List[Tuple[str, ...]]:
    """The cases taking parameter ``name`` from a shared source, grouped: one group when
    ``[fixed]`` sets it (or all defaults agree), else one group per distinct default value."""
    groups: Dict[float, List[str]] = {}
    for c in cases:
        if name in spec.fixed[c]:
            key = "fixed"
        else:
            key = spec.parameters[c][name].default
        groups.setdefault(key, []).append(c)
    return [tuple(g) for g in groups.values()]


def input_layout(spec: Spec, variables: List[str], catalog_params: List[str],
                 initial: Optional[Dict[str, float]] = None) -> List["Input"]:
    """The inputs of ``spec`` (module docstring), valued at the spec's fixed values, each
    variable's ``initial`` and each catalog parameter's first option (``initial`` overrides
    those two by name)."""
    cases = list(spec.scenes)
    initial = dict(initial or {})
    out: List[Input] = []

    def cases_with(param):
        return tuple(c for c in cases if param in spec.parameters[c])

    def make(name, param, group, kind, value):
        prm = spec.parameters[group[0]][param]
        return Input(name, param, group, kind, spec.unit_of(group[0], param), float(value), prm.lo, prm.hi,
                     bool(prm.integer), prm.doc)

    for name in variables:
        value = initial.get(name, spec.variables[name].initial)
        out.append(make(name, name, cases_with(name), "variable", value))
        out[-1] = replace(out[-1], unit=spec.variables[name].unit, integer=bool(spec.variables[name].integer))
    first = {}
    for choice in spec.choices.values():
        first.update(choice.settings[0])
    for name in catalog_params:
        out.append(make(name, name, cases_with(name), "catalog", initial.get(name, first[name])))
    taken = set(variables) | set(catalog_params)
    names: List[str] = []
    for c in cases:
        for name in spec.parameters[c]:
            if name not in taken and name not in names:
                names.append(name)
    for name in names:
        having = cases_with(name)
        own = [c for c in having if name in spec.case_overrides.get(c, ())]
        shared = tuple(c for c in having if c not in own)
        shared_groups = _default_groups(spec, name, shared) if shared else []
        labelled = [(g, name if len(shared_groups) == 1 else f"{g[0]}.{name}") for g in shared_groups]
        labelled += [((c,), f"{c}.{name}") for c in own]
        for group, label in labelled:
            value = spec.fixed[group[0]].get(name, spec.parameters[group[0]][name].default)
            out.append(make(label, name, group, "fixed", value))
    return out


class InputLayout:
    """The input vector of a spec (module docstring): which entry feeds which case's parameter.

    ``inputs``: the :class:`Input` list; ``variable_slots``/``catalog_slots``: the vector's
    entries of the design variables and catalog parameters, in the order given; ``structure``:
    the layout as a hashable tuple (what compiled programs depend on).
    """

    def __init__(self, spec: Spec, variables: List[str], catalog_params: List[str]):
        self.spec = spec
        self.inputs = input_layout(spec, variables, catalog_params)
        by_name = {i.name: k for k, i in enumerate(self.inputs)}
        self.variable_slots = np.array([by_name[n] for n in variables], dtype=int)
        self.catalog_slots = np.array([by_name[n] for n in catalog_params], dtype=int)
        #: case -> [(parameter, input index)] in the case's parameter-table order
        self.feeds: Dict[str, List[Tuple[str, int]]] = {c: [] for c in spec.scenes}
        for k, inp in enumerate(self.inputs):
            for c in inp.cases:
                self.feeds[c].append((inp.param, k))
        self.structure = tuple(i.structure for i in self.inputs)

    def __len__(self) -> int:
        return len(self.inputs)

    @property
    def values(self) -> np.ndarray:
        """The vector at the spec's values (variables at ``initial``, the first catalog option)."""
        return np.array([i.value for i in self.inputs], dtype=float)

    def index(self, name: str) -> int:
        """The entry of the input named ``name``."""
        for k, i in enumerate(self.inputs):
            if i.name == name:
                return k
        raise KeyError(name)

    def slot(self, param: str, case: str) -> Optional[int]:
        """The entry that feeds parameter ``param`` of ``case`` (None when the case lacks it)."""
        for p, k in self.feeds[case]:
            if p == param:
                return k
        return None

    def case_parameters(self, values) -> Dict[str, Dict[str, jnp.ndarray]]:
        """Per case, the chain's parameter dict read from the vector ``values`` (traceable)."""
        return {c: {p: values[k] for p, k in feeds} for c, feeds in self.feeds.items()}

    def with_design(self, values, x, catalog):
        """``values`` with the design variables set to ``x`` (their order) and the catalog
        parameters to ``catalog`` (traceable)."""
        values = jnp.asarray(values, dtype=float)
        if self.variable_slots.size:
            values = values.at[self.variable_slots].set(jnp.asarray(x, dtype=float)[: self.variable_slots.size])
        if self.catalog_slots.size:
            values = values.at[self.catalog_slots].set(jnp.asarray(catalog, dtype=float)[: self.catalog_slots.size])
        return values

    def valued(self, values) -> List[Input]:
        """The inputs with their values replaced by ``values``."""
        return [replace(i, value=float(v)) for i, v in zip(self.inputs, np.asarray(values, dtype=float))]


__all__ = ["Input", "InputLayout", "input_layout", "KINDS"]
