"""The scene section of a spec: ``sensor``, ``parts``, ``[options]`` and ``[cases.<name>]``.

Every case is a :class:`~diffsense.scene.Scene` of the spec's sensor with the common parts plus
the case's own, and may override fixed parameter values::

    sensor = "radar"
    parts = ["dust"]              # in every case
    [options]
    swerling = 1
    [cases.sea_skimmer]           # without [cases] there is one case, "main"
    parts = ["multipath"]
    rcs_m2 = "0.1 m^2"            # overrides [fixed]

The chain's parameter and output tables of every case come with the scenes, so that the other
sections can check names and units against them.
"""

from __future__ import annotations

import re

from dataclasses import dataclass
from typing import Dict, Mapping, Set

from diffsense.design.spec.common import (DESCRIBE_HINT, clean_message, closest, echo, key_text, optional_table,
                                          unknown_parameter)
from diffsense.design.spec.fidelity import fast_options, read_fidelity
from diffsense.design.spec.types import DEFAULT_CASE
from diffsense.errors import DomainError, SpecError
from diffsense.scene import CHAINS, Scene, chain_for, sensor_kinds
from diffsense.sensors.chain import Output, Param

#: keys of a case table that are not parameter overrides
CASE_RESERVED = {"parts", "doc"}


@dataclass(frozen=True)
class Cases:
    """The evaluation cases of a spec and the chain's tables for each (all keyed by case)."""

    sensor: str
    base_scene: Scene  # the scene of the common parts
    scenes: Dict[str, Scene]
    overrides: Dict[str, Dict]  # case -> raw parameter values of its table
    parameters: Dict[str, Dict[str, Param]]
    outputs: Dict[str, Dict[str, Output]]
    fidelity: str = "exact"  # options.fidelity (:mod:`.fidelity`)
    fidelity_switched: Dict[str, str] = None  # options the fast fidelity changed -> their value

    @property
    def all_parameters(self) -> Set[str]:
        """Names of the parameters of any case."""
        return set().union(*[set(t) for t in self.parameters.values()])

    def param_of(self, file, name: str, key: str) -> Param:
        """The chain parameter ``name`` (from the first case that has it); raise if none has it."""
        for table in self.parameters.values():
            if name in table:
                return table[name]
        raise unknown_parameter(file, key, name, self.base_scene, self.all_parameters)


#: a case name: it prefixes output names ("<case>.<output>") and appears in tables and file names
CASE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,39}")

def read_sensor(file, raw: Mapping) -> str:
    """The ``sensor`` key: a known chain kind (:func:`diffsense.scene.sensor_kinds`)."""
    if "sensor" not in raw:
        raise SpecError(file, "sensor", "missing: name the sensor kind, e.g. sensor = \"radar\"")
    sensor = raw["sensor"]
    if not isinstance(sensor, str):
        raise SpecError(file, "sensor", "must be a string")
    if sensor not in sensor_kinds():
        raise SpecError(file, "sensor", f"unknown sensor kind {sensor!r}{closest(sensor, sensor_kinds())}; "
                        f"known kinds: {sensor_kinds()}")
    return sensor


def check_parts(file, key: str, sensor: str, parts) -> list:
    """``parts`` (the list at ``key``): names of parts a ``sensor`` scene knows, each once."""
    if not isinstance(parts, list) or not all(isinstance(p, str) for p in parts):
        raise SpecError(file, key, f"must be a list of part names, e.g. [\"rain\"]; got {echo(parts)}")
    chain = CHAINS[sensor]
    for i, part in enumerate(parts):
        if part not in chain.parts:
            raise SpecError(file, key, f"unknown part {echo(part)} of a {sensor} scene"
                            f"{closest(part, chain.parts)}; parts: {', '.join(chain.parts)}")
        if part in parts[:i]:
            raise SpecError(file, key, f"part {echo(part)} is listed twice")
    return parts


def _scene(file, key: str, sensor: str, parts, options) -> Scene:
    try:
        scene = Scene(sensor, parts, options)
        chain_for(scene)
    except DomainError as exc:
        raise SpecError(file, key, clean_message(exc)) from None
    return scene


def read_options(file, raw: Mapping, sensor: str) -> dict:
    """The ``[options]`` table: each a known static option of the sensor, set to one of its
    allowed values, of the same type (``swerling = true`` is not ``swerling = 1``)."""
    options = raw.get("options", {})
    if not isinstance(options, dict):
        raise SpecError(file, "options", f"must be a table of option = value; got {echo(options)}")
    known = CHAINS[sensor].options
    for name, value in options.items():
        key = f"options.{key_text(name)}"
        if name == "fidelity":  # the spec's model choices, not a chain option (:mod:`.fidelity`)
            continue
        if name not in known:
            raise SpecError(file, key, f"unknown option of a {sensor} scene{closest(name, known)}; options: "
                            f"{', '.join(sorted(known))}, fidelity ({DESCRIBE_HINT.format(kind=sensor)})")
        default, allowed = known[name]
        if allowed and not any(type(value) is type(a) and value == a for a in allowed):
            raise SpecError(file, key, f"must be one of {', '.join(echo(a) for a in allowed)} "
                            f"(default {echo(default)}); got {echo(value)}")
    return {k: v for k, v in options.items() if k != "fidelity"}


def read_cases(file, raw: Mapping, sensor: str) -> Cases:
    """The scenes of every case (``parts``, ``[options]``, ``[cases]``) and their chain tables."""
    options = read_options(file, raw, sensor)
    fidelity = read_fidelity(file, raw.get("options", {}))
    switched = {}
    if fidelity == "fast":
        options, switched = fast_options(sensor, options)
    base_parts = check_parts(file, "parts", sensor, raw.get("parts", []))
    base_scene = _scene(file, "parts", sensor, base_parts, options)
    chain = chain_for(base_scene)
    cases_raw = optional_table(file, raw, "cases", "must be a table of named cases")
    scenes: Dict[str, Scene] = {}
    overrides: Dict[str, Dict] = {}
    for cname, ctable in cases_raw.items():
        if not CASE_NAME.fullmatch(cname):
            raise SpecError(file, f"cases.{key_text(cname)}", "a case name is 1-40 letters, digits, '_' or '-', "
                            "starting with a letter (it prefixes output names: '<case>.<output>')")
        if not isinstance(ctable, dict):
            raise SpecError(file, f"cases.{cname}", "must be a table")
        extra = check_parts(file, f"cases.{cname}.parts", sensor, ctable.get("parts", []))
        scenes[cname] = _scene(file, f"cases.{cname}.parts", sensor, list(base_parts) + list(extra), options)
        overrides[cname] = {k: v for k, v in ctable.items() if k not in CASE_RESERVED}
    if not cases_raw:
        scenes[DEFAULT_CASE] = base_scene
        overrides[DEFAULT_CASE] = {}
    return Cases(sensor, base_scene, scenes, overrides, fidelity=fidelity, fidelity_switched=switched,
                 parameters={c: chain.parameters(s) for c, s in scenes.items()},
                 outputs={c: chain.outputs(s) for c, s in scenes.items()})
