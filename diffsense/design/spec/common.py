"""Checks shared by every section of a spec: unknown keys (with a "did you mean"), quantities
in a parameter's unit, the model's domain, numbers, optional tables and "<case>.<name>" keys.

Each raises :class:`~diffsense.errors.SpecError` naming the file, the dotted key and the problem.
"""

from __future__ import annotations

import difflib
import math
from typing import Mapping, Optional

from diffsense.design.units import to_unit
from diffsense.errors import DomainError, SpecError, UnitError
from diffsense.numerics.checks import check_range
from diffsense.sensors.chain import Param


def closest(name: str, names) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``names`` to ``name``, or ``""``.

    >>> closest("rnge_m", ["range_m", "freq_hz"])
    " (did you mean 'range_m'?)"
    """
    close = difflib.get_close_matches(name, list(names), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def reject_unknown(file, prefix: str, table: Mapping, allowed) -> None:
    """Raise for the first key of ``table`` not in ``allowed`` (key reported as ``prefix + key``)."""
    for key in table:
        if key not in allowed:
            raise SpecError(file, f"{prefix}{key}", f"unknown key{closest(key, allowed)}; allowed: {sorted(allowed)}")


def quantity(file, key: str, value, unit: str) -> float:
    """``value`` (a number in ``unit`` or a string "<number> <unit>") converted to ``unit``; finite."""
    try:
        out = to_unit(value, unit)
    except UnitError as exc:
        raise SpecError(file, key, f"{exc} (expected a quantity in '{unit}')") from None
    if not math.isfinite(out):
        raise SpecError(file, key, f"value {value!r} is not finite")
    return out


def check_domain(file, key: str, prm: Param, value: float) -> None:
    """Raise unless ``value`` lies in the documented domain of the chain parameter ``prm``."""
    try:
        check_range(prm.name, value, prm.lo, prm.hi, lo_open=prm.lo_open, hi_open=prm.hi_open)
    except DomainError as exc:
        raise SpecError(file, key, f"{value:g} {prm.unit} lies outside the model's domain: {exc}") from None


def parameter_value(file, key: str, prm: Param, value) -> float:
    """A value for the chain parameter ``prm``: converted to its unit and inside its domain."""
    out = quantity(file, key, value, prm.unit)
    check_domain(file, key, prm, out)
    return out


def is_number(value) -> bool:
    """True for an int or float that is not a boolean (TOML's true/false are not weights)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def optional_table(file, raw: Mapping, key: str, problem: str = "must be a table") -> dict:
    """The table ``raw[key]`` (empty when absent or empty); raise ``problem`` if it is no table."""
    table = raw.get(key, {}) or {}
    if not isinstance(table, dict):
        raise SpecError(file, key, problem)
    return table


def split_case(file, key: str, text, scenes: Mapping, default: Optional[str] = None):
    """``(case, name)`` from ``"<case>.<name>"``, or from ``"<name>"`` when the spec has one case
    (or a ``default`` case is given)."""
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
