"""Requirement specifications (``designs/*.toml``): reading and validation.

A spec says what a sensor must achieve and what the designer may change::

    name = "ore_pass"
    title = "Ore-pass level radar (Brooker 8.16)"
    sensor = "radar"                       # a chain kind (diffsense.scene.CHAINS)
    parts = ["dust"]                       # scene parts present in every case
    [options]                              # static scene options
    swerling = 1
    [fixed]                                # parameter values, with units
    range_m = "300 m"
    [variables.antenna_diameter_m]         # a continuous design variable
    lower = "100 mm"
    upper = "600 mm"
    initial = "250 mm"                     # optional; scale = "log" | "linear" (optional)
    [variables.n_pulses]                   # integer variable (relaxed, then rounded)
    lower = 1
    upper = 64
    integer = true
    [variables.freq_hz]                    # a catalog choice of one parameter
    choices = ["35 GHz", "94 GHz"]
    [choices.transmitter]                  # a catalog choice setting several parameters at once
    options = [ { name = "Gunn", peak_power_w = "20 dBm", cost = 1.0 },
                { name = "IMPATT", peak_power_w = "30 dBm", cost = 3.0 } ]
    [cases.sea_skimmer]                    # optional evaluation cases (override fixed values,
    parts = ["multipath"]                  # add parts); without cases there is one case "main"
    rcs_m2 = "0.1 m^2"
    [[requirements]]
    output = "snr_margin_db"               # "<case>.<output>" when there are several cases
    at_least = "0 dB"                      # or at_most / equals
    [objective]
    minimize = "antenna_diameter_m"        # a parameter, an output, "cost", or a weighted sum
                                           # { antenna_diameter_m = 1.0, cost = 0.1 }

Every problem is reported as one :class:`SpecError` naming the file, the key and what is
wrong; nothing is silently dropped or clamped.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Mapping, Optional, Tuple

from diffsense.errors import DomainError, SpecError, UnitError
from diffsense.numerics.checks import check_range
from diffsense.sensors.chain import Output, Param
from diffsense.scene import Scene, chain_for, sensor_kinds
from diffsense.design.units import to_unit

SENSES = ("at_least", "at_most", "equals")
_TOP_KEYS = {"name", "title", "description", "sensor", "parts", "options", "fixed", "variables",
             "choices", "cases", "requirements", "objective", "notes"}
_VARIABLE_KEYS = {"lower", "upper", "initial", "scale", "integer", "choices", "costs", "doc"}
_REQUIREMENT_KEYS = {"output", "name", "doc"} | set(SENSES)
_OBJECTIVE_KEYS = {"minimize", "maximize", "doc"}
_CASE_RESERVED = {"parts", "doc"}
DEFAULT_CASE = "main"


@dataclass(frozen=True)
class Variable:
    """A continuous or integer design variable (values in the parameter's unit)."""

    name: str
    unit: str
    lower: float
    upper: float
    initial: float
    log_scale: bool
    integer: bool


@dataclass(frozen=True)
class Choice:
    """A catalog choice: each option sets one or more parameters (and may carry a cost)."""

    name: str
    option_names: Tuple[str, ...]
    settings: Tuple[Dict[str, float], ...]  # per option: parameter -> value
    costs: Tuple[float, ...]


@dataclass(frozen=True)
class Requirement:
    """``output`` of ``case`` must be at least / at most / equal to ``limit`` (output unit)."""

    name: str
    case: str
    output: str
    sense: str
    limit: float
    unit: str


@dataclass(frozen=True)
class Objective:
    """Weighted sum of terms (parameter, output or "cost"); ``sign`` +1 minimise, −1 maximise."""

    terms: Tuple[Tuple[str, float], ...]
    sign: float
    text: str


@dataclass
class Spec:
    """A validated requirement specification."""

    path: Path
    name: str
    title: str
    description: str
    sensor: str
    scenes: Dict[str, Scene]  # case -> scene
    fixed: Dict[str, Dict[str, float]]  # case -> parameter -> value
    variables: Dict[str, Variable]
    choices: Dict[str, Choice]
    requirements: List[Requirement]
    objective: Objective
    parameters: Dict[str, Dict[str, Param]] = field(default_factory=dict)  # case -> table
    outputs: Dict[str, Dict[str, Output]] = field(default_factory=dict)  # case -> table

    @property
    def cases(self) -> List[str]:
        return list(self.scenes)

    def unit_of(self, case: str, name: str) -> str:
        if name in self.parameters[case]:
            return self.parameters[case][name].unit
        if name in self.outputs[case]:
            return self.outputs[case][name].unit
        return "1"


def _closest(name: str, names) -> str:
    import difflib

    close = difflib.get_close_matches(name, list(names), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _reject_unknown(file, prefix: str, table: Mapping, allowed) -> None:
    for key in table:
        if key not in allowed:
            raise SpecError(file, f"{prefix}{key}", f"unknown key{_closest(key, allowed)}; allowed: {sorted(allowed)}")


def _quantity(file, key: str, value, unit: str) -> float:
    try:
        out = to_unit(value, unit)
    except UnitError as exc:
        raise SpecError(file, key, f"{exc} (expected a quantity in '{unit}')") from None
    if not math.isfinite(out):
        raise SpecError(file, key, f"value {value!r} is not finite")
    return out


def _check_domain(file, key: str, prm: Param, value: float) -> None:
    try:
        check_range(prm.name, value, prm.lo, prm.hi, lo_open=prm.lo_open, hi_open=prm.hi_open)
    except DomainError as exc:
        raise SpecError(file, key, f"{value:g} {prm.unit} lies outside the model's domain: {exc}") from None


def _scene(file, key: str, sensor: str, parts, options) -> Scene:
    if not isinstance(parts, list) or not all(isinstance(p, str) for p in parts):
        raise SpecError(file, key, "'parts' must be a list of part names")
    try:
        scene = Scene(sensor, parts, options)
        chain_for(scene)
    except DomainError as exc:
        raise SpecError(file, key, str(exc)) from None
    return scene


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
    """Validate an already-parsed spec mapping (see the module docstring for the format)."""
    f = path
    _reject_unknown(f, "", raw, _TOP_KEYS)
    if "sensor" not in raw:
        raise SpecError(f, "sensor", "missing: name the sensor kind, e.g. sensor = \"radar\"")
    sensor = raw["sensor"]
    if not isinstance(sensor, str):
        raise SpecError(f, "sensor", "must be a string")
    if sensor not in sensor_kinds():
        raise SpecError(f, "sensor", f"unknown sensor kind {sensor!r}{_closest(sensor, sensor_kinds())}; "
                        f"known kinds: {sensor_kinds()}")
    options = raw.get("options", {})
    if not isinstance(options, dict):
        raise SpecError(f, "options", "must be a table")
    base_parts = raw.get("parts", [])
    base_scene = _scene(f, "parts", sensor, base_parts, options)
    chain = chain_for(base_scene)

    # cases: each is (scene, overrides)
    cases_raw = raw.get("cases", {}) or {}
    if not isinstance(cases_raw, dict):
        raise SpecError(f, "cases", "must be a table of named cases")
    scenes: Dict[str, Scene] = {}
    overrides_raw: Dict[str, Dict] = {}
    if cases_raw:
        for cname, ctable in cases_raw.items():
            if not isinstance(ctable, dict):
                raise SpecError(f, f"cases.{cname}", "must be a table")
            extra = ctable.get("parts", [])
            scenes[cname] = _scene(f, f"cases.{cname}.parts", sensor, list(base_parts) + list(extra), options)
            overrides_raw[cname] = {k: v for k, v in ctable.items() if k not in _CASE_RESERVED}
    else:
        scenes[DEFAULT_CASE] = base_scene
        overrides_raw[DEFAULT_CASE] = {}

    parameters = {c: chain.parameters(s) for c, s in scenes.items()}
    outputs = {c: chain.outputs(s) for c, s in scenes.items()}
    all_params = set().union(*[set(t) for t in parameters.values()])

    def param_of(name: str, key: str) -> Param:
        for table in parameters.values():
            if name in table:
                return table[name]
        raise SpecError(f, key, f"unknown parameter '{name}' for a {sensor} scene with parts "
                        f"{sorted(base_scene.parts)}{_closest(name, all_params)}")

    # variables (continuous/integer) and single-parameter catalogs
    variables: Dict[str, Variable] = {}
    choices: Dict[str, Choice] = {}
    vraw = raw.get("variables", {}) or {}
    if not isinstance(vraw, dict):
        raise SpecError(f, "variables", "must be a table")
    for vname, vt in vraw.items():
        key = f"variables.{vname}"
        prm = param_of(vname, key)
        if not isinstance(vt, dict):
            raise SpecError(f, key, "must be a table with lower/upper (or choices)")
        _reject_unknown(f, key + ".", vt, _VARIABLE_KEYS)
        if "choices" in vt:
            extra = set(vt) - {"choices", "costs", "doc"}
            if extra:
                raise SpecError(f, f"{key}.{sorted(extra)[0]}", "a catalog variable takes only 'choices' and 'costs'")
            opts = vt["choices"]
            if not isinstance(opts, list) or len(opts) < 1:
                raise SpecError(f, f"{key}.choices", "must be a non-empty list of values")
            vals = []
            for i, o in enumerate(opts):
                v = _quantity(f, f"{key}.choices[{i}]", o, prm.unit)
                _check_domain(f, f"{key}.choices[{i}]", prm, v)
                vals.append(v)
            costs = vt.get("costs", [0.0] * len(vals))
            if (not isinstance(costs, list) or len(costs) != len(vals)
                    or not all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in costs)):
                raise SpecError(f, f"{key}.costs", f"must be a list of {len(vals)} numbers, one per choice")
            choices[vname] = Choice(vname, tuple(str(o) for o in opts), tuple({vname: v} for v in vals),
                                    tuple(float(c) for c in costs))
            continue
        for bound in ("lower", "upper"):
            if bound not in vt:
                raise SpecError(f, f"{key}.{bound}", "missing (a design variable needs lower and upper bounds)")
        lo = _quantity(f, f"{key}.lower", vt["lower"], prm.unit)
        hi = _quantity(f, f"{key}.upper", vt["upper"], prm.unit)
        if not lo < hi:
            raise SpecError(f, key, f"bounds inverted or empty: lower {vt['lower']!r} is not below upper {vt['upper']!r}")
        _check_domain(f, f"{key}.lower", prm, lo)
        _check_domain(f, f"{key}.upper", prm, hi)
        scale = vt.get("scale", "log" if lo > 0 else "linear")
        if scale not in ("log", "linear"):
            raise SpecError(f, f"{key}.scale", f"must be 'log' or 'linear'; got {scale!r}")
        if scale == "log" and lo <= 0:
            raise SpecError(f, f"{key}.scale", "log scaling needs a positive lower bound")
        integer = vt.get("integer", prm.integer)
        if not isinstance(integer, bool):
            raise SpecError(f, f"{key}.integer", "must be true or false")
        if integer and math.floor(hi) < math.ceil(lo):
            raise SpecError(f, key, "no integer lies between the bounds")
        if "initial" in vt:
            x0 = _quantity(f, f"{key}.initial", vt["initial"], prm.unit)
            if not lo <= x0 <= hi:
                raise SpecError(f, f"{key}.initial", f"{x0:g} {prm.unit} lies outside [{lo:g}, {hi:g}]")
        else:
            x0 = math.sqrt(lo * hi) if scale == "log" else 0.5 * (lo + hi)
        variables[vname] = Variable(vname, prm.unit, lo, hi, x0, scale == "log", integer)

    # grouped catalog choices
    craw = raw.get("choices", {}) or {}
    if not isinstance(craw, dict):
        raise SpecError(f, "choices", "must be a table of named catalogs")
    for cname, ct in craw.items():
        key = f"choices.{cname}"
        if cname in choices or cname in variables:
            raise SpecError(f, key, "name already used by a variable")
        if not isinstance(ct, dict) or "options" not in ct:
            raise SpecError(f, f"{key}.options", "missing (a list of option tables)")
        _reject_unknown(f, key + ".", ct, {"options", "doc"})
        opts = ct["options"]
        if not isinstance(opts, list) or not opts or not all(isinstance(o, dict) for o in opts):
            raise SpecError(f, f"{key}.options", "must be a non-empty list of tables")
        names, settings, costs = [], [], []
        keys0 = None
        for i, o in enumerate(opts):
            okey = f"{key}.options[{i}]"
            names.append(str(o.get("name", f"option {i}")))
            cost = o.get("cost", 0.0)
            if not isinstance(cost, (int, float)) or isinstance(cost, bool):
                raise SpecError(f, f"{okey}.cost", "must be a number")
            costs.append(float(cost))
            setting = {}
            for pname, pval in o.items():
                if pname in ("name", "cost"):
                    continue
                prm = param_of(pname, f"{okey}.{pname}")
                v = _quantity(f, f"{okey}.{pname}", pval, prm.unit)
                _check_domain(f, f"{okey}.{pname}", prm, v)
                setting[pname] = v
            if keys0 is None:
                keys0 = set(setting)
            elif set(setting) != keys0:
                raise SpecError(f, okey, f"every option must set the same parameters {sorted(keys0)}; this one sets {sorted(setting)}")
            settings.append(setting)
        choices[cname] = Choice(cname, tuple(names), tuple(settings), tuple(costs))

    chosen = set(variables)
    for c in choices.values():
        overlap = chosen & set(c.settings[0])
        if overlap:
            raise SpecError(f, f"choices.{c.name}", f"sets {sorted(overlap)}, already a design variable")
        chosen |= set(c.settings[0])

    # fixed values per case
    fraw = raw.get("fixed", {}) or {}
    if not isinstance(fraw, dict):
        raise SpecError(f, "fixed", "must be a table")
    fixed: Dict[str, Dict[str, float]] = {}
    for cname, scene in scenes.items():
        table = parameters[cname]
        vals: Dict[str, float] = {}
        for src, prefix in ((fraw, "fixed."), (overrides_raw[cname], f"cases.{cname}.")):
            for pname, pval in src.items():
                key = prefix + pname
                if pname not in table:
                    if src is fraw and pname in all_params:
                        continue  # belongs to a part only some cases have
                    raise SpecError(f, key, f"unknown parameter '{pname}' for this scene{_closest(pname, table)}")
                if pname in chosen:
                    raise SpecError(f, key, f"'{pname}' is a design variable; it cannot also be fixed")
                v = _quantity(f, key, pval, table[pname].unit)
                _check_domain(f, key, table[pname], v)
                vals[pname] = v
        missing = [n for n, p in table.items() if p.default is None and n not in vals and n not in chosen]
        if missing:
            where = "fixed" if cname == DEFAULT_CASE else f"cases.{cname}"
            raise SpecError(f, f"{where}.{missing[0]}", f"missing required parameter(s) {missing}")
        fixed[cname] = vals

    # requirements
    rraw = raw.get("requirements")
    if not rraw:
        raise SpecError(f, "requirements", "missing: a spec needs at least one [[requirements]] entry")
    if not isinstance(rraw, list) or not all(isinstance(r, dict) for r in rraw):
        raise SpecError(f, "requirements", "must be an array of tables ([[requirements]])")
    requirements: List[Requirement] = []
    for i, r in enumerate(rraw):
        key = f"requirements[{i}]"
        _reject_unknown(f, key + ".", r, _REQUIREMENT_KEYS)
        if "output" not in r:
            raise SpecError(f, f"{key}.output", "missing")
        case, out = _split_case(f, f"{key}.output", r["output"], scenes)
        if out not in outputs[case]:
            raise SpecError(f, f"{key}.output", f"unknown output '{out}'{_closest(out, outputs[case])}; "
                            f"outputs: {sorted(outputs[case])}")
        senses = [s for s in SENSES if s in r]
        if len(senses) != 1:
            raise SpecError(f, key, f"needs exactly one of {list(SENSES)}")
        unit = outputs[case][out].unit
        limit = _quantity(f, f"{key}.{senses[0]}", r[senses[0]], unit)
        label = r.get("name", r["output"])
        requirements.append(Requirement(str(label), case, out, senses[0], limit, unit))

    # objective
    oraw = raw.get("objective")
    if not isinstance(oraw, dict):
        raise SpecError(f, "objective", "missing: give [objective] minimize = ... or maximize = ...")
    _reject_unknown(f, "objective.", oraw, _OBJECTIVE_KEYS)
    senses = [s for s in ("minimize", "maximize") if s in oraw]
    if len(senses) != 1:
        raise SpecError(f, "objective", "needs exactly one of 'minimize' or 'maximize'")
    sense = senses[0]
    obj = oraw[sense]
    if isinstance(obj, str):
        terms = [(obj, 1.0)]
    elif isinstance(obj, dict) and obj:
        terms = []
        for k, w in obj.items():
            if not isinstance(w, (int, float)) or isinstance(w, bool):
                raise SpecError(f, f"objective.{sense}.{k}", "weight must be a number")
            terms.append((k, float(w)))
    else:
        raise SpecError(f, f"objective.{sense}", "must be a name or a table of name = weight")
    first = next(iter(scenes))
    for tname, _ in terms:
        if tname == "cost":
            continue
        case, base = _split_case(f, f"objective.{sense}", tname, scenes, default=first)
        if base not in parameters[case] and base not in outputs[case]:
            raise SpecError(f, f"objective.{sense}", f"unknown parameter or output '{tname}'"
                            f"{_closest(base, set(parameters[case]) | set(outputs[case]))}")
    objective = Objective(tuple(terms), 1.0 if sense == "minimize" else -1.0,
                          f"{sense} " + " + ".join(f"{w:g}·{n}" if w != 1 else n for n, w in terms))

    name = raw.get("name", Path(str(path)).stem)
    return Spec(Path(str(path)), str(name), str(raw.get("title", name)), str(raw.get("description", "")),
                sensor, scenes, fixed, variables, choices, requirements, objective, parameters, outputs)


def _split_case(file, key, text, scenes, default: Optional[str] = None):
    if not isinstance(text, str):
        raise SpecError(file, key, "must be a string")
    if "." in text:
        case, out = text.split(".", 1)
        if case not in scenes:
            raise SpecError(file, key, f"unknown case '{case}'; cases: {sorted(scenes)}")
        return case, out
    if len(scenes) == 1:
        return next(iter(scenes)), text
    if default is not None:
        return default, text
    raise SpecError(file, key, f"several cases exist; write '<case>.{text}' with a case from {sorted(scenes)}")
