"""Reading a spec: :func:`load_spec` (a TOML file) and :func:`parse_spec` (a parsed mapping),
which reads the sections in order, each by its own module:

1. ``sensor``, ``parts``, ``[options]``, ``[cases]`` → scenes and chain tables (:mod:`.cases`)
2. ``[variables]`` → design variables and one-parameter catalogs (:mod:`.variables`)
3. ``[choices]`` → grouped catalogs (:mod:`.choices`)
4. ``[uncertain]`` → distributions of uncertain inputs (:mod:`.uncertain`); then ``[fixed]`` and
   the case overrides → fixed values per case (:mod:`.fixed`), an uncertain input at its median
5. ``[[requirements]]`` (:mod:`.requirements`)
6. ``[objective]`` (:mod:`.objective`)
7. ``[trade]`` (:mod:`.trade`, optional)

A new section is a new module and one step here, and its key joins :data:`TOP_KEYS`.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Mapping

from diffsense.design.spec.cases import read_cases, read_sensor
from diffsense.design.spec.choices import design_parameters, read_choices
from diffsense.design.spec.common import clean_message, plain_text, reject_unknown
from diffsense.design.spec.fixed import read_fixed
from diffsense.design.spec.objective import check_goals, read_objective
from diffsense.design.spec.requirements import read_requirements
from diffsense.design.spec.limits import check_counts, check_work
from diffsense.design.spec.trade import check_trade, read_trade
from diffsense.design.spec.types import Spec
from diffsense.design.spec.uncertain import check_probabilities, nominal_values, read_uncertain
from diffsense.design.spec.variables import read_variables
from diffsense.errors import SpecError

#: the keys a spec may have at its top level
TOP_KEYS = {"name", "title", "description", "notes", "sensor", "parts", "options", "cases", "variables",
            "choices", "fixed", "requirements", "objective", "trade", "uncertain"}


#: the largest spec file read (bytes); shipped specs are a few kilobytes
MAX_SPEC_BYTES = 1_000_000


def load_spec(path) -> Spec:
    """Read and validate a TOML requirement spec; raise :class:`SpecError` on any problem
    (including a file that is not UTF-8, is empty, too large or nested too deeply)."""
    path = Path(path)
    try:
        if path.is_dir():
            raise SpecError(path, "", "is a directory, not a spec file")
        with path.open("rb") as f:
            data = f.read(MAX_SPEC_BYTES + 1)
    except OSError as exc:
        raise SpecError(path, "", f"cannot read the file: {exc.strerror or exc}") from None
    if len(data) > MAX_SPEC_BYTES:
        raise SpecError(path, "", f"file larger than {MAX_SPEC_BYTES // 1000} kB; a spec is a short text file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise SpecError(path, "", f"not valid UTF-8 text: byte {exc.start} (line {line}) cannot be decoded; "
                        "save the file as UTF-8") from None
    if not text.strip():
        raise SpecError(path, "", "the file is empty; a spec needs at least sensor, [fixed] or [variables], "
                        "[[requirements]] and [objective]")
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(path, "", f"not valid TOML: {clean_message(exc)}") from None
    except RecursionError:
        raise SpecError(path, "", "not valid TOML here: tables or arrays nested too deeply") from None
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
    uncertain = read_uncertain(file, raw, cases, chosen)
    fixed = nominal_values(read_fixed(file, raw, cases, chosen | set(uncertain.parameters if uncertain else ())),
                           uncertain, cases)
    requirements = read_requirements(file, raw, cases, set(chosen))
    check_probabilities(file, requirements, uncertain, cases)
    objective = read_objective(file, raw, cases)
    check_goals(file, objective, requirements)
    name = plain_text(file, "name", raw.get("name", Path(str(path)).stem))
    title = plain_text(file, "title", raw.get("title", name))
    description = plain_text(file, "description", raw.get("description", ""), multiline=True)
    spec = Spec(Path(str(path)), name, title, description,
                sensor, cases.scenes, fixed, variables, choices, requirements, objective,
                cases.parameters, cases.outputs, trade=read_trade(file, raw, cases, chosen),
                uncertain=uncertain,
                case_overrides={c: frozenset(o) for c, o in cases.overrides.items()},
                fidelity=cases.fidelity, fidelity_switched=dict(cases.fidelity_switched or {}))
    check_trade(file, spec)
    check_counts(file, spec)
    check_work(file, spec)
    return spec
