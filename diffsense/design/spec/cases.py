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

from dataclasses import dataclass
from typing import Dict, Mapping, Set

from diffsense.design.spec.common import closest, optional_table
from diffsense.design.spec.types import DEFAULT_CASE
from diffsense.errors import DomainError, SpecError
from diffsense.scene import Scene, chain_for, sensor_kinds
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

    @property
    def all_parameters(self) -> Set[str]:
        """Names of the parameters of any case."""
        return set().union(*[set(t) for t in self.parameters.values()])

    def param_of(self, file, name: str, key: str) -> Param:
        """The chain parameter ``name`` (from the first case that has it); raise if none has it."""
        for table in self.parameters.values():
            if name in table:
                return table[name]
        raise SpecError(file, key, f"unknown parameter '{name}' for a {self.sensor} scene with parts "
                        f"{sorted(self.base_scene.parts)}{closest(name, self.all_parameters)}")


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


def _scene(file, key: str, sensor: str, parts, options) -> Scene:
    if not isinstance(parts, list) or not all(isinstance(p, str) for p in parts):
        raise SpecError(file, key, "'parts' must be a list of part names")
    try:
        scene = Scene(sensor, parts, options)
        chain_for(scene)
    except DomainError as exc:
        raise SpecError(file, key, str(exc)) from None
    return scene


def read_cases(file, raw: Mapping, sensor: str) -> Cases:
    """The scenes of every case (``parts``, ``[options]``, ``[cases]``) and their chain tables."""
    options = raw.get("options", {})
    if not isinstance(options, dict):
        raise SpecError(file, "options", "must be a table")
    base_parts = raw.get("parts", [])
    base_scene = _scene(file, "parts", sensor, base_parts, options)
    chain = chain_for(base_scene)
    cases_raw = optional_table(file, raw, "cases", "must be a table of named cases")
    scenes: Dict[str, Scene] = {}
    overrides: Dict[str, Dict] = {}
    for cname, ctable in cases_raw.items():
        if not isinstance(ctable, dict):
            raise SpecError(file, f"cases.{cname}", "must be a table")
        extra = ctable.get("parts", [])
        scenes[cname] = _scene(file, f"cases.{cname}.parts", sensor, list(base_parts) + list(extra), options)
        overrides[cname] = {k: v for k, v in ctable.items() if k not in CASE_RESERVED}
    if not cases_raw:
        scenes[DEFAULT_CASE] = base_scene
        overrides[DEFAULT_CASE] = {}
    return Cases(sensor, base_scene, scenes, overrides,
                 parameters={c: chain.parameters(s) for c, s in scenes.items()},
                 outputs={c: chain.outputs(s) for c, s in scenes.items()})
