"""Reading a spec: :func:`load_spec` (a TOML file) and :func:`parse_spec` (a parsed mapping),
which reads the sections in order, each by its own module:

1. ``sensor``, ``parts``, ``[options]``, ``[cases]`` → scenes and chain tables (:mod:`.cases`)
2. ``[variables]`` → design variables and one-parameter catalogs (:mod:`.variables`)
3. ``[choices]`` → grouped catalogs (:mod:`.choices`)
4. ``[fixed]`` and the case overrides → fixed values per case (:mod:`.fixed`)
5. ``[[requirements]]`` (:mod:`.requirements`)
6. ``[objective]`` (:mod:`.objective`)

A new section is a new module and one step here, and its key joins :data:`TOP_KEYS`.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Mapping

from diffsense.design.spec.cases import read_cases, read_sensor
from diffsense.design.spec.choices import design_parameters, read_choices
from diffsense.design.spec.common import reject_unknown
from diffsense.design.spec.fixed import read_fixed
from diffsense.design.spec.objective import read_objective
from diffsense.design.spec.requirements import read_requirements
from diffsense.design.spec.types import Spec
from diffsense.design.spec.variables import read_variables
from diffsense.errors import SpecError

#: the keys a spec may have at its top level
TOP_KEYS = {"name", "title", "description", "notes", "sensor", "parts", "options", "cases", "variables",
            "choices", "fixed", "requirements", "objective"}


def load_spec(path) -> Spec:
    """Read and validate a TOML requirement spec; raise :class:`SpecError` on any problem."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise SpecError(path, "", f"cannot read the file: {exc.strerror}") from None
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(path, "", f"not valid TOML: {exc}") from None
    return parse_spec(raw, path)


def parse_spec(raw: Mapping, path="<spec>") -> Spec:
    """Validate an already-parsed spec mapping (see :mod:`diffsense.design.spec` for the format).

    The first problem found is raised as :class:`SpecError` naming ``path`` and the key:

    >>> parse_spec({"parts": []})
    Traceback (most recent call last):
    ...
    diffsense.errors.SpecError: <spec>: key 'sensor': missing: name the sensor kind, e.g. sensor = "radar"
    """
    file = path
    reject_unknown(file, "", raw, TOP_KEYS)
    sensor = read_sensor(file, raw)
    cases = read_cases(file, raw, sensor)
    variables, choices = read_variables(file, raw, cases)
    choices.update(read_choices(file, raw, cases, taken=set(choices) | set(variables)))
    chosen = design_parameters(file, variables, choices)
    fixed = read_fixed(file, raw, cases, chosen)
    requirements = read_requirements(file, raw, cases)
    objective = read_objective(file, raw, cases)
    name = raw.get("name", Path(str(path)).stem)
    return Spec(Path(str(path)), str(name), str(raw.get("title", name)), str(raw.get("description", "")),
                sensor, cases.scenes, fixed, variables, choices, requirements, objective,
                cases.parameters, cases.outputs)
