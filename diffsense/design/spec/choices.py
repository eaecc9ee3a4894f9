"""The ``[choices.<name>]`` section: catalogs whose options set several parameters at once.

::

    [choices.transmitter]
    options = [ { name = "Gunn", peak_power_w = "20 dBm", cost = 1.0 },
                { name = "IMPATT", peak_power_w = "30 dBm", cost = 3.0 } ]

Every option sets the same parameters; ``name`` (default "option <i>") and ``cost`` (default 0)
are optional. A parameter is set by at most one variable or catalog (:func:`design_parameters`).
"""

from __future__ import annotations

from typing import Dict, Mapping, Set, Tuple

from diffsense.design.spec.cases import Cases
from diffsense.design.spec.common import (key_text, optional_table, parameter_value, plain_text, reject_unknown,
                                          weight_number)
from diffsense.design.spec.types import Choice, Variable
from diffsense.errors import SpecError


def read_choices(file, raw: Mapping, cases: Cases, taken) -> Dict[str, Choice]:
    """The grouped catalogs of the ``[choices]`` section; ``taken``: names already used by variables."""
    choices: Dict[str, Choice] = {}
    for cname, ct in optional_table(file, raw, "choices", "must be a table of named catalogs").items():
        key = f"choices.{key_text(cname)}"
        plain_text(file, key, cname)
        if cname in taken:
            raise SpecError(file, key, "name already used by a variable")
        if not isinstance(ct, dict) or "options" not in ct:
            raise SpecError(file, f"{key}.options", "missing (a list of option tables, e.g. options = [ { name = "
                            "\"A\", peak_power_w = \"1 kW\", cost = 1.0 } ])")
        reject_unknown(file, key + ".", ct, {"options", "doc"})
        opts = ct["options"]
        if not isinstance(opts, list) or not opts or not all(isinstance(o, dict) for o in opts):
            raise SpecError(file, f"{key}.options", "must be a non-empty list of tables")
        rows = []
        for i, o in enumerate(opts):
            row = _option(file, f"{key}.options[{i}]", i, o, cases)
            if rows and set(row[2]) != set(rows[0][2]):
                raise SpecError(file, f"{key}.options[{i}]", f"every option must set the same parameters "
                                f"{sorted(rows[0][2])}; this one sets {sorted(row[2])}")
            rows.append(row)
        choices[cname] = Choice(cname, tuple(r[0] for r in rows), tuple(r[2] for r in rows),
                                tuple(r[1] for r in rows))
    return choices


def _option(file, okey: str, i: int, option: Mapping, cases: Cases) -> Tuple[str, float, Dict[str, float]]:
    """``(name, cost, parameter -> value)`` of one catalog option."""
    name = plain_text(file, f"{okey}.name", option.get("name", f"option {i}"))
    cost = weight_number(file, f"{okey}.cost", option.get("cost", 0.0), "a finite cost", zero_allowed=True)
    setting = {}
    for pname, pval in option.items():
        if pname in ("name", "cost", "doc"):
            continue
        pkey = f"{okey}.{key_text(pname)}"
        prm = cases.param_of(file, pname, pkey)
        setting[pname] = parameter_value(file, pkey, prm, pval)
    if not setting:
        raise SpecError(file, okey, "sets no parameter: an option needs at least one parameter = value")
    return name, float(cost), setting


def design_parameters(file, variables: Mapping[str, Variable], choices: Mapping[str, Choice]) -> Set[str]:
    """Names of the parameters the designer sets; raise if a catalog sets one that is already set."""
    chosen = set(variables)
    for c in choices.values():
        overlap = chosen & set(c.settings[0])
        if overlap:
            raise SpecError(file, f"choices.{c.name}", f"sets {sorted(overlap)}, already a design variable")
        chosen |= set(c.settings[0])
    return chosen
