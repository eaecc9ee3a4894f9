"""The ``[variables.<parameter>]`` section: what the designer may change, one parameter each.

A variable is continuous or integer between bounds, or a catalog of values of its parameter::

    [variables.antenna_diameter_m]
    lower = "100 mm"
    upper = "600 mm"
    initial = "250 mm"            # optional
    scale = "log"                 # optional: "log" (default for a positive lower bound) | "linear"
    [variables.n_pulses]
    lower = 1
    upper = 64
    integer = true                # default: the chain parameter's own integer flag
    [variables.freq_hz]
    choices = ["35 GHz", "94 GHz"]
    costs = [1.0, 2.0]            # optional, one per choice

Without ``initial`` the design starts at the middle of the range in the variable's scale: the
geometric mean √(lower·upper) for a log scale, (lower + upper)/2 for a linear one. A catalog
variable becomes a one-parameter :class:`~diffsense.design.spec.types.Choice`.
"""

from __future__ import annotations

import math
from typing import Dict, Mapping, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import (check_domain, echo, key_text, optional_table, parameter_value, quantity,
                                          reject_unknown, weight_number)
from diffsense.design.spec.types import Choice, Variable
from diffsense.errors import SpecError
from diffsense.scene import number_text
from diffsense.sensors.chain import Param

VARIABLE_KEYS = {"lower", "upper", "initial", "scale", "integer", "choices", "costs", "doc"}


def read_variables(file, raw: Mapping, cases: Cases) -> Tuple[Dict[str, Variable], Dict[str, Choice]]:
    """``(variables, catalog variables)`` of the ``[variables]`` section, each keyed by parameter.

    >>> import math
    >>> from diffsense.design.spec import parse_spec
    >>> spec = parse_spec({"sensor": "sonar", "parts": ["sea_noise"], "options": {"absorption": "book"},
    ...     "fixed": {"range_m": "500 m", "freq_hz": "117 kHz"},
    ...     "variables": {"electrical_power_w": {"lower": "10 W", "upper": "5 kW"}},
    ...     "requirements": [{"output": "snr_margin_db", "at_least": "0 dB"}],
    ...     "objective": {"minimize": "electrical_power_w"}})
    >>> v = spec.variables["electrical_power_w"]
    >>> v.lower, v.upper, v.log_scale
    (10.0, 5000.0, True)
    >>> math.isclose(v.initial, math.sqrt(10.0 * 5000.0))
    True
    """
    variables: Dict[str, Variable] = {}
    catalogs: Dict[str, Choice] = {}
    for vname, vt in optional_table(file, raw, "variables").items():
        key = f"variables.{key_text(vname)}"
        prm = cases.param_of(file, vname, key)
        if not isinstance(vt, dict):
            raise SpecError(file, key, "must be a table with lower/upper (or choices)")
        reject_unknown(file, key + ".", vt, VARIABLE_KEYS)
        if "choices" in vt:
            catalogs[vname] = _catalog_variable(file, key, vname, vt, prm)
        else:
            variables[vname] = _range_variable(file, key, vname, vt, prm)
    return variables, catalogs


def _catalog_variable(file, key: str, name: str, vt: Mapping, prm: Param) -> Choice:
    extra = set(vt) - {"choices", "costs", "doc"}
    if extra:
        raise SpecError(file, f"{key}.{sorted(extra)[0]}", "a catalog variable takes only 'choices' and 'costs'")
    opts = vt["choices"]
    if not isinstance(opts, list) or len(opts) < 1:
        raise SpecError(file, f"{key}.choices", f"must be a non-empty list of values; got {echo(opts)}")
    vals = [parameter_value(file, f"{key}.choices[{i}]", prm, o) for i, o in enumerate(opts)]
    costs = vt.get("costs", [0.0] * len(vals))
    if not isinstance(costs, list) or len(costs) != len(vals):
        raise SpecError(file, f"{key}.costs", f"must be a list of {len(vals)} numbers, one per choice")
    costs = [weight_number(file, f"{key}.costs[{i}]", c, "a finite cost", zero_allowed=True) for i, c in enumerate(costs)]
    return Choice(name, tuple(str(o) for o in opts), tuple({name: v} for v in vals), tuple(costs))


def _range_variable(file, key: str, name: str, vt: Mapping, prm: Param) -> Variable:
    for bound in ("lower", "upper"):
        if bound not in vt:
            raise SpecError(file, f"{key}.{bound}", "missing (a design variable needs lower and upper bounds)")
    lo = quantity(file, f"{key}.lower", vt["lower"], prm.unit)
    hi = quantity(file, f"{key}.upper", vt["upper"], prm.unit)
    if lo == hi:
        raise SpecError(file, key, f"lower equals upper ({echo(vt['lower'])}): the range is empty; to hold the "
                        "value put it under [fixed]")
    if not lo < hi:
        raise SpecError(file, key, f"bounds inverted: lower {echo(vt['lower'])} is above upper {echo(vt['upper'])}")
    check_domain(file, f"{key}.lower", prm, lo)
    check_domain(file, f"{key}.upper", prm, hi)
    scale = vt.get("scale", "log" if lo > 0 else "linear")
    if scale not in ("log", "linear"):
        raise SpecError(file, f"{key}.scale", f"must be 'log' or 'linear'; got {echo(scale)}")
    if scale == "log" and lo <= 0:
        raise SpecError(file, f"{key}.scale", "log scaling needs a positive lower bound")
    integer = vt.get("integer", prm.integer)
    if not isinstance(integer, bool):
        raise SpecError(file, f"{key}.integer", f"must be true or false; got {echo(integer)}")
    if integer:
        for bound, value in (("lower", lo), ("upper", hi)):
            if value != math.floor(value):
                raise SpecError(file, f"{key}.{bound}", f"must be a whole number for an integer variable; "
                                f"got {echo(vt[bound])}")
    if "initial" in vt:
        x0 = quantity(file, f"{key}.initial", vt["initial"], prm.unit)
        if not lo <= x0 <= hi:
            raise SpecError(file, f"{key}.initial", f"{echo(vt['initial'])} lies outside the bounds "
                            f"[{number_text(lo)}, {number_text(hi)}] {prm.unit}")
        if integer and x0 != math.floor(x0):
            raise SpecError(file, f"{key}.initial", f"must be a whole number for an integer variable; "
                            f"got {echo(vt['initial'])}")
    else:
        x0 = math.sqrt(lo * hi) if scale == "log" else 0.5 * (lo + hi)
    return Variable(name, prm.unit, lo, hi, x0, scale == "log", integer)
