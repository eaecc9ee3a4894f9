"""Quantities with units for requirement specs: "94 GHz", "250 mm", "20 dBm", "11.5 dBsm".

Linear units and the logarithmic power units dBm, dBW and dB are handled by the ``pint``
units library; "dBsm" (dB relative to 1 m², radar cross-section) and "dBi" (antenna gain,
dB relative to isotropic) are added here as 10·log10 power ratios. A bare number is read in
the parameter's own unit; nothing is guessed.

The conversions most specs need are done without pint (importing it and building its
registry took 0.6–1 s of every command): a value already in the target unit ("m^2" for
"m**2"), an SI-prefixed unit to its base ("94 GHz" to Hz, "250 mm" to m: one multiplication by
the prefix, which is what pint computes, bit for bit — ``tests/design/test_units.py``), and
the power levels dBm and dBW to watts, 10^(L/10) W (× 1e-3 for dBm), which is more accurate
than pint's conversion (within 15 ulp of the exact value over −150…80 dBm, against 55 ulp:
pint gave 0.10000000000000005 W for 20 dBm). Every other unit goes through pint.
"""

from __future__ import annotations

import functools
import math
import os
import re
from typing import Union

from diffsense.errors import UnitError


def db10(x: float) -> float:
    """10 log10 x of a Python number (a spec's value: no JAX dispatch at load)."""
    return 10.0 * math.log10(x)


def from_db10(x_db: float) -> float:
    """10^(x/10) of a Python number."""
    return 10.0 ** (x_db / 10.0)

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_QUANTITY = re.compile(rf"^\s*({_NUMBER})\s*(.*?)\s*$")

# logarithmic units that are not in pint's default registry: name -> (linear unit, factor)
_EXTRA_LOG_UNITS = {"dBsm": "m**2", "dBi": "dimensionless"}
_UNIT_ALIASES = {"dBsm": "dBsm", "dBm2": "dBsm", "dBi": "dBi"}


# absolute levels: name -> (linear unit, level of 1 linear unit in this scale)
_LOG_LEVELS = {"dBm": ("W", 30.0), "dBW": ("W", 0.0), "dBsm": ("m**2", 0.0)}

#: SI prefixes read without pint, and the base units they may prefix there
_PREFIXES = {"T": 1e12, "G": 1e9, "M": 1e6, "k": 1e3, "c": 1e-2, "m": 1e-3, "u": 1e-6, "µ": 1e-6, "n": 1e-9,
             "p": 1e-12}
_PREFIXED_BASES = frozenset({"Hz", "W", "m", "s", "A", "V", "ohm", "rad", "J"})
#: power levels read without pint: the watts of 0 in each scale
_POWER_LEVELS = {"dBm": 1e-3, "dBW": 1.0}


def _without_pint(value: float, unit: str, target: str):
    """``value`` in ``unit`` converted to ``target`` when this module does it without pint (the
    module docstring), else None.

    >>> _without_pint(94.0, "GHz", "Hz"), _without_pint(3.0, "m^2", "m**2"), _without_pint(20.0, "dBm", "W")
    (94000000000.0, 3.0, 0.1)
    >>> _without_pint(2.0, "pA/Hz^0.5", "A/Hz**0.5"), _without_pint(1.0, "mi", "m"), _without_pint(1.0, "mm^2", "m**2")
    (2e-12, None, None)
    """
    written = unit.replace("^", "**")
    if written == target:
        return value
    # a prefix on the target's leading base when that base stands alone ("pA/Hz**0.5" for
    # "A/Hz**0.5", not "mm**2" for "m**2")
    lead = re.match(r"[A-Za-z]+", target)
    rest = target[lead.end():] if lead else ""
    alone = rest == "" or (rest[0] in "/*" and not rest.startswith("**"))
    if lead and lead.group(0) in _PREFIXED_BASES and alone and written.endswith(target):
        factor = _PREFIXES.get(written[:-len(target)])
        if factor is not None:
            return value * factor
    if target == "W" and unit in _POWER_LEVELS:
        return 10.0 ** (value / 10.0) * _POWER_LEVELS[unit]
    return None


@functools.lru_cache(maxsize=1)
def registry():
    """The shared ``pint`` unit registry; its parsed definitions are cached in
    ``DIFFSENSE_CACHE_DIR/pint`` when that is set (pint's own cache: the registry then builds in
    about a tenth of the time)."""
    import pint

    base = os.environ.get("DIFFSENSE_CACHE_DIR")
    if base:
        try:
            return pint.UnitRegistry(cache_folder=os.path.join(base, "pint"))
        except Exception:  # noqa: BLE001 - an unusable cache folder: build without it
            pass
    return pint.UnitRegistry()


def _shown(text: str, limit: int = 40) -> str:
    """``text`` quoted for a message, at most ``limit`` characters (an ellipsis beyond)."""
    return repr(text if len(text) <= limit else text[:limit - 1] + "…")


def split_quantity(text: str):
    """Split ``"94 GHz"`` into ``(94.0, "GHz")``; raise :class:`UnitError` if malformed."""
    m = _QUANTITY.match(text)
    if not m:
        raise UnitError(f"cannot read {_shown(text)} as '<number> <unit>'")
    return float(m.group(1)), m.group(2)


def angle_power(unit: str) -> float:
    """The power of the radian in ``unit`` (1 for "deg", 2 for "sr", 0 for "%"), which pint's
    dimensions do not show: it treats angles as dimensionless, so "60 %" would convert to 0.6 rad.

    >>> angle_power("deg"), angle_power("W/sr"), angle_power("percent")
    (1, -2, 0)
    """
    try:
        root = registry().Quantity(1.0, unit or "dimensionless").to_root_units()
    except Exception:  # logarithmic units (dB/km) have no root units: not angles
        return 0
    return dict(root.unit_items()).get("radian", 0)


def _to_linear(value: float, unit: str, target: str) -> float:
    if unit in _EXTRA_LOG_UNITS:
        base = _EXTRA_LOG_UNITS[unit]
        return _to_linear(float(from_db10(value)), base, target)
    fast = _without_pint(value, unit or "dimensionless", target or "dimensionless")
    if fast is not None:
        return float(fast)
    ureg = registry()
    try:
        q = ureg.Quantity(value, unit or "dimensionless")
        out = float(q.to(target or "dimensionless").magnitude)
        if unit and angle_power(unit) != angle_power(target):
            raise UnitError(f"unit {_shown(unit)} is not an angle unit; write the angle in an angle unit "
                            f"(deg, rad) or as a plain number in {target!r}" if angle_power(target)
                            else f"unit {_shown(unit)} is an angle; {target!r} is not")
        return out
    except UnitError:
        raise
    except Exception as exc:  # pint raises several exception types
        name = type(exc).__name__
        if name == "UndefinedUnitError":
            raise UnitError(f"unknown unit {_shown(unit)}") from None
        if name == "DimensionalityError":
            raise UnitError(f"unit {_shown(unit)} cannot be converted to {target!r}") from None
        raise UnitError(f"cannot convert {value} {_shown(unit)} to {target!r}: {_shown(str(exc), 80)}") from None


def to_unit(value: Union[str, int, float], target: str) -> float:
    """Convert ``value`` (a number already in ``target``, or a string "<number> <unit>") to
    ``target``.

    For ``target`` "dB" the value must be a bare number or carry "dB"/"dBi"; absolute levels
    (dBm, dBW, dBsm) are refused there. For a dimensionless ``target`` a "dB" value is turned
    into its power ratio. Raises :class:`UnitError` with a message naming the offending unit.

    >>> to_unit("250 mm", "m"), to_unit(94e9, "Hz")
    (0.25, 94000000000.0)
    >>> to_unit("20 dBm", "W")                                    # 10^(20/10) mW
    0.1
    >>> abs(to_unit("11.5 dBsm", "m**2") - 10 ** (11.5 / 10)) < 1e-12
    True
    >>> to_unit("-105 dBW", "dBm")                                # +30 dB from W to mW
    -75.0
    """
    if isinstance(value, bool):
        raise UnitError(f"expected a number or a quantity string, got the boolean {value!r}")
    if isinstance(value, (int, float)):
        if not math.isfinite(float(value)):
            raise UnitError(f"value {value!r} is not finite")
        return float(value)
    if not isinstance(value, str):
        raise UnitError(f"expected a number or a quantity string, got {type(value).__name__} {_shown(repr(value))}")
    number, unit = split_quantity(value)
    if len(unit) > 64:
        raise UnitError(f"unit {_shown(unit)} is too long ({len(unit)} characters) to be a unit")
    unit = _UNIT_ALIASES.get(unit, unit)
    if target == "dB":
        if unit in ("", "dB", "dBi"):
            return number
        if unit in ("dBsm", "dBm", "dBW"):
            raise UnitError(f"unit {_shown(unit)} is an absolute level; this value is a ratio in dB")
        raise UnitError(f"unit {_shown(unit)} cannot be converted to 'dB' (write e.g. '3 dB')")
    if unit == "" and target not in ("", "1", "dimensionless"):
        return number
    if target in _LOG_LEVELS:
        if unit == target:
            return number
        if unit in _LOG_LEVELS and _LOG_LEVELS[unit][0] == _LOG_LEVELS[target][0]:
            return number - _LOG_LEVELS[unit][1] + _LOG_LEVELS[target][1]
        linear = _to_linear(number, unit, _LOG_LEVELS[target][0])
        if linear <= 0:
            raise UnitError(f"{_shown(value)} is not positive, so it has no level in {target}")
        return float(db10(linear)) + _LOG_LEVELS[target][1]
    if unit == "dB" and target in ("", "1", "dimensionless"):
        return float(from_db10(number))
    return _to_linear(number, unit, target)


def check_unit(unit: str) -> None:
    """Raise :class:`UnitError` unless ``unit`` is a unit this module can convert to."""
    if unit in ("dB", "", "1") or unit in _EXTRA_LOG_UNITS:
        return
    try:
        registry().parse_units(unit)
    except Exception:
        raise UnitError(f"unknown unit {_shown(unit)}") from None
