"""Values each key accepts alone but the chain rejects together: checked once, at load.

Every key of a spec is checked against its own domain as it is read; some domains are joint
(the radiometer needs pd > pfa) and some values inside every domain still leave the chain
without a finite answer (a target radius of 1e-308 m gives an SNR of -inf, and a gradient
solver never moves from there). :func:`check_evaluable` evaluates each case's chain at the
spec's initial design and at the corners of the variables' box, for every catalog option
combination, through the design model's compiled check program, and raises one :class:`SpecError` for the first
point where a requirement or objective output is not finite, naming the keys that set the
values involved and the output. The point is then re-evaluated eagerly so that a joint-domain
check of the chain (a :class:`DomainError`) names its arguments.
"""

from __future__ import annotations

import itertools
import re
from typing import Dict, List, Tuple

import numpy as np

from diffsense.design.spec.common import clean_message
from diffsense.design.spec.types import Spec
from diffsense.errors import DomainError, SpecError
from diffsense.scene import check_values, evaluate, number_text

#: with more variables than this only the initial design and one-at-a-time extremes are checked
MAX_CORNER_VARIABLES = 6
#: catalog option combinations checked (the first ones, in catalog order)
MAX_COMBINATIONS = 64

Point = Tuple[str, Dict[str, float]]  # (where, design parameter -> value)


def _design_points(spec: Spec) -> List[Point]:
    """The initial design and the box corners, for every catalog combination (capped)."""
    names = list(spec.variables)
    initial = {n: v.initial for n, v in spec.variables.items()}
    if len(names) <= MAX_CORNER_VARIABLES:
        corners = [dict(zip(names, ends)) for ends in itertools.product(("lower", "upper"), repeat=len(names))]
    else:
        corners = [{n: end} for n in names for end in ("lower", "upper")]
    choices = list(spec.choices.values())
    combos = itertools.islice(itertools.product(*[range(len(c.settings)) for c in choices]), MAX_COMBINATIONS)
    points: List[Point] = []
    for combo in combos:
        setting: Dict[str, float] = {}
        for c, i in zip(choices, combo):
            setting.update(c.settings[i])
        chosen = "".join(f", {_choice_key(spec, c)} = {c.option_names[i]!r}" for c, i in zip(choices, combo))
        points.append((f"the initial design{chosen}", {**initial, **setting}))
        for corner in corners:
            if not corner:
                continue
            values = dict(initial)
            values.update({n: getattr(spec.variables[n], end) for n, end in corner.items()})
            where = ", ".join(f"variables.{n} = {end} ({_with_unit(values[n], spec.variables[n].unit)})"
                              for n, end in corner.items())
            points.append((f"the corner {where}{chosen}", {**values, **setting}))
    return points


def _with_unit(value: float, unit: str) -> str:
    """``value`` and its unit, the unit left out for a pure number (unit "1")."""
    return number_text(value) if unit in ("", "1") else f"{number_text(value)} {unit}"


def _choice_key(spec: Spec, choice) -> str:
    """The spec key of a catalog: ``variables.<p>`` for a one-parameter catalog variable."""
    single = len(choice.settings[0]) == 1 and choice.name in choice.settings[0]
    return f"variables.{choice.name}" if single and choice.name not in spec.variables else f"choices.{choice.name}"


def _key_of(spec: Spec, case: str, name: str) -> str:
    """The spec key that sets parameter ``name`` in ``case`` (or where its default applies)."""
    if name in spec.variables:
        return f"variables.{name}"
    for c in spec.choices.values():
        if name in c.settings[0]:
            return _choice_key(spec, c)
    if name in spec.fixed[case]:
        return "fixed." + name if len(spec.scenes) == 1 else f"fixed.{name} (or cases.{case}.{name})"
    return f"{name} (its default)"


def _case_outputs(spec: Spec, case: str) -> Dict[str, str]:
    """The outputs of ``case`` the spec uses -> the key that uses each."""
    used: Dict[str, str] = {}
    for i, r in enumerate(spec.requirements):
        if r.case == case:
            used.setdefault(r.output, f"requirements[{i}].output")
    first = next(iter(spec.scenes))
    for name, _ in spec.objective.terms:
        c, _, base = name.rpartition(".")
        if (c or first) == case and base in spec.outputs[case]:
            used.setdefault(base, "objective")
    return used


def _case_parameters(spec: Spec, case: str, values: Dict[str, float]) -> Dict[str, float]:
    """Every parameter of ``case`` at one design point (defaults filled)."""
    table = spec.parameters[case]
    return {name: values.get(name, spec.fixed[case].get(name, prm.default)) for name, prm in table.items()}


def check_joint_values(spec: Spec) -> None:
    """Raise :class:`SpecError` at the first design point of :func:`check_evaluable` (the initial
    design and the box corners, every catalog combination) whose values a case's chain rejects
    together by a check it makes on plain numbers (:meth:`Chain.check_values`, e.g. the radar's
    M-of-N ``binary_m <= n_pulses``): before any program is compiled, so such a spec is refused
    in a fraction of a second. The command line runs it as it reads a spec; :func:`check_evaluable`
    meets the same values through the chain's own check when it re-evaluates a point eagerly, with
    the same message."""
    for where, design in _design_points(spec):
        for case, scene in spec.scenes.items():
            params = _case_parameters(spec, case, design)
            try:
                check_values(scene, params)
            except DomainError as exc:
                _refuse_joint(spec, case, params, where, exc, "")


def check_evaluable(model):
    """Raise :class:`SpecError` unless every output the spec uses, and the objective, is finite
    at the initial design and at the corners of the box of every catalog combination (see the
    module text), evaluated by the model's own compiled program (no program of its own).
    Returns ``(where, V, evaluations)``: the points' descriptions, input vectors and
    evaluations, for further checks of the same points."""
    spec = model.spec
    points = _design_points(spec)
    used = {case: _case_outputs(spec, case) for case in spec.scenes}
    V = np.stack([_vector(model, values) for _, values in points])
    evaluations, _, _, objective = model.programs.values_rows(V)
    for case, outs in used.items():
        for out, key in outs.items():
            values = np.asarray(evaluations[case].values[out], dtype=float)
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:
                j = int(bad[0])
                where, design = points[j]
                _diagnose(spec, case, spec.scenes[case], _case_parameters(spec, case, design), where, out, key,
                          float(values[j]))
    objective = np.asarray(objective, dtype=float)
    bad = np.flatnonzero(~np.isfinite(objective))
    if bad.size:
        j = int(bad[0])
        raise SpecError(spec.path, "objective", f"the objective ({spec.objective.text}) is "
                        f"{number_text(objective[j])} at {points[j][0]}: its weights overflow the numbers; "
                        "rescale them (only their ratios matter)")
    return [where for where, _ in points], V, evaluations


def _vector(model, design: Dict[str, float]) -> np.ndarray:
    """The model's input vector with the design variables and catalog parameters of ``design``."""
    v = np.asarray(model.layout.values, dtype=float).copy()
    for name, value in design.items():
        v[model.layout.index(name)] = value
    return v


def _refuse_joint(spec: Spec, case: str, params: Dict[str, float], where: str, exc: DomainError, key: str):
    """Raise the error for values ``params`` the chain rejected together (``exc``) at ``where``,
    naming the keys that set the values the chain's message names (else ``key``)."""
    at = f"at {where}" + (f" in case '{case}'" if len(spec.scenes) > 1 else "")
    text = clean_message(exc)
    names = [n for n in dict.fromkeys(re.findall(r"[a-z][a-z0-9_]*", text.split(";")[0])) if n in params]
    keys = [_key_of(spec, case, n) for n in names]
    shown = ", ".join(f"{_key_of(spec, case, n)} = {number_text(params[n])}" for n in names)
    # the reason first: a long corner description is what the one-line limit cuts
    raise SpecError(spec.path, keys[0].split(" ")[0] if keys else key,
                    f"values accepted one by one are rejected together: {text}"
                    + (f" (set by {shown})" if shown else "") + f"; {at}") from None


def _diagnose(spec: Spec, case: str, scene, params: Dict[str, float], where: str, out: str, key: str,
              value: float) -> None:
    """Raise the error for a point where output ``out`` is ``value`` (not finite)."""
    at = f"at {where}" + (f" in case '{case}'" if len(spec.scenes) > 1 else "")
    try:
        evaluate(scene, params)
    except DomainError as exc:
        _refuse_joint(spec, case, params, where, exc, key)
    extreme = [n for n, v in params.items() if v != 0 and not 1e-150 < abs(v) < 1e150]
    named = [_key_of(spec, case, n) for n in extreme]
    shown = ", ".join(f"{k} = {number_text(params[n])}" for k, n in zip(named, extreme))
    raise SpecError(spec.path, named[0].split(" ")[0] if named else key,
                    f"output '{out}' is {number_text(value)} {at}: the chain has no finite answer there"
                    + (f"; the extreme values {shown} are the likely cause" if shown else "")
                    + "; a solver cannot start or move from such a point")

