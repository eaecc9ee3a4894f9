"""Checks shared by every section of a spec: unknown keys (with a "did you mean"), quantities
in a parameter's unit, the model's domain, numbers, optional tables and "<case>.<name>" keys.

Each raises :class:`~diffsense.errors.SpecError` naming the file, the dotted key and the problem.
"""

from __future__ import annotations

import difflib
import math
import re
from typing import Mapping, Optional

from diffsense.design.units import to_unit
from diffsense.errors import DomainError, SpecError, UnitError, escaped
from diffsense.numerics.checks import check_range
from diffsense.scene import Scene, describe_command, domain_text, number_text, unknown_name_hint
from diffsense.sensors.chain import Param

#: the longest piece of a spec's own text echoed in a message (characters)
MAX_ECHO = 80
#: where every message about an unknown name points
DESCRIBE_HINT = "run 'diffsense describe {kind}' for the full list"


def one_line(text: str, limit: int = MAX_ECHO) -> str:
    """``text`` on one line (control characters escaped), at most ``limit`` characters: an
    ellipsis and the full length beyond.

    >>> one_line("x" * 100, 20)
    'xxxxxxxxxxxxxxxxx… (100 characters)'
    """
    text = escaped(text)
    if len(text) <= limit:
        return text
    return f"{text[:limit - 3]}… ({len(text)} characters)"


def key_text(name) -> str:
    """A key of the spec as part of a dotted key in a message (at most 60 characters)."""
    return one_line(name, 60)


def echo(value, limit: int = MAX_ECHO) -> str:
    """A value of the spec as it may appear in a message: its TOML-like text on one line, at
    most ``limit`` characters (:func:`one_line`); numbers without NumPy reprs.

    >>> echo("60 %"), echo(1.5), echo(True)
    ("'60 %'", '1.5', 'true')
    """
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, float):
        text = number_text(value)
    else:
        try:
            text = repr(value)
        except RecursionError:
            text = f"<{type(value).__name__} nested too deeply>"
    return one_line(text, limit)


def close_names(name: str, names, n: int = 3) -> list:
    """Up to ``n`` of ``names`` that look like ``name`` (closest first).

    >>> close_names("rnge_m", ["range_m", "freq_hz", "ranges_m"])
    ['range_m', 'ranges_m']
    """
    if not isinstance(name, str):
        return []
    return difflib.get_close_matches(name, [str(x) for x in names], n=n)


def closest(name: str, names) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``names`` to ``name`` (up to three), or ``""``.

    >>> closest("rnge_m", ["range_m", "freq_hz"])
    " (did you mean 'range_m'?)"
    >>> closest("snr_db", ["snr_margin_db", "sir_db", "snr_dbw", "scr_db"])
    " (did you mean 'snr_dbw', 'sir_db' or 'scr_db'?)"
    """
    close = close_names(name, names)
    if not close:
        return ""
    quoted = [f"'{c}'" for c in close]
    text = quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " or " + quoted[-1]
    return f" (did you mean {text}?)"


def unknown_parameter(file, key: str, name, scene: Scene, names) -> SpecError:
    """The error for ``name``, not a parameter of ``scene`` (``names``: those it has): what the
    chain knows about the name, or up to three close names, and the ``diffsense describe``
    command that lists them all."""
    hint = unknown_name_hint(scene, name) if isinstance(name, str) else ""
    told = f"; {hint}" if hint else closest(name, names)
    return SpecError(file, key, f"unknown parameter {echo(name, 60)} of a {scene.sensor} scene{told}; "
                     f"run '{describe_command(scene)}' for its parameters")


def reject_unknown(file, prefix: str, table: Mapping, allowed) -> None:
    """Raise for the first key of ``table`` not in ``allowed`` (key reported as ``prefix + key``)."""
    for key in table:
        if key not in allowed:
            raise SpecError(file, f"{prefix}{key_text(key)}",
                            f"unknown key{closest(key, allowed)}; allowed: {', '.join(sorted(allowed))}")


def quantity(file, key: str, value, unit: str) -> float:
    """``value`` (a number in ``unit`` or a string "<number> <unit>") converted to ``unit``; finite."""
    if isinstance(value, float) and not math.isfinite(value):
        raise SpecError(file, key, f"value {echo(value)} is not finite")
    try:
        out = to_unit(value, unit)
    except UnitError as exc:
        raise SpecError(file, key, f"{clean_message(exc)} (expected a quantity in '{unit}')") from None
    if not math.isfinite(out):
        raise SpecError(file, key, f"value {echo(value)} is not finite in '{unit}'")
    return out


def clean_message(exc: Exception) -> str:
    """The text of an exception from a lower layer, with NumPy reprs (``np.float64(1.5)``) shown
    as plain numbers and clipped to one line."""
    text = re.sub(r"np\.(?:float|int)\d+\(([^()]*)\)", r"\1", str(exc))
    return one_line(text, 300) if text else type(exc).__name__


def _with_unit(value: float, unit: str) -> str:
    return number_text(value) + ("" if unit in ("", "1") else f" {unit}")


def check_domain(file, key: str, prm: Param, value: float) -> None:
    """Raise unless ``value`` lies in the documented domain of the chain parameter ``prm``."""
    try:
        check_range(prm.name, value, prm.lo, prm.hi, lo_open=prm.lo_open, hi_open=prm.hi_open)
    except DomainError as exc:
        unit = "" if prm.unit in ("", "1") else f" (in {prm.unit})"
        subnormal = " (a subnormal number, which the computation treats as 0)" if "subnormal" in str(exc) else ""
        raise SpecError(file, key, f"{_with_unit(value, prm.unit)}{subnormal} lies outside the model's domain "
                        f"{domain_text(prm)}{unit} of '{prm.name}'") from None


def parameter_value(file, key: str, prm: Param, value) -> float:
    """A value for the chain parameter ``prm``: converted to its unit, inside its domain, and a
    whole number when the parameter counts something."""
    out = quantity(file, key, value, prm.unit)
    check_domain(file, key, prm, out)
    if prm.integer and out != math.floor(out):
        raise SpecError(file, key, f"'{prm.name}' counts something: it needs a whole number, got {echo(value)}")
    return out


def is_number(value) -> bool:
    """True for an int or float that is not a boolean (TOML's true/false are not weights)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def finite_number(file, key: str, value, what: str = "a number") -> float:
    """``value`` as a float: a finite int or float (not a boolean, nan or inf); raise otherwise."""
    if not is_number(value):
        raise SpecError(file, key, f"must be {what}; got {echo(value)}")
    if not math.isfinite(value):
        raise SpecError(file, key, f"must be {what}, finite; got {echo(value)}")
    return float(value)


def whole_number(file, key: str, value, lo: int, hi: int) -> int:
    """``value`` as an int: a whole number (an int, or a float with no fraction) from ``lo`` to
    ``hi``; raise naming the range and echoing the value as written otherwise.

    >>> whole_number("s.toml", "trade.points", 12.0, 2, 200)
    12
    >>> whole_number("s.toml", "trade.points", 1e7, 2, 200)
    Traceback (most recent call last):
    ...
    diffsense.errors.SpecError: s.toml: key 'trade.points': must be a whole number from 2 to 200; got 1e+07
    """
    if not is_number(value) or not math.isfinite(value) or int(value) != value or not lo <= value <= hi:
        raise SpecError(file, key, f"must be a whole number from {lo} to {hi}; got {echo(value)}")
    return int(value)


#: characters allowed in a name besides printable ones: none (``description`` also takes newlines and tabs)
MULTILINE_CONTROLS = "\n\t\r"


def plain_text(file, key: str, value, multiline: bool = False) -> str:
    """``value`` as a string of printable characters: a name, title or label of the spec shown in
    tables, reports and the explorer. Control and format characters (escape sequences, NUL,
    bidirectional overrides, …) are refused; ``multiline`` allows newlines and tabs.

    >>> plain_text("s.toml", "title", "Ore pass")
    'Ore pass'
    >>> plain_text("s.toml", "title", "a\x1b[2Jb")
    Traceback (most recent call last):
    ...
    diffsense.errors.SpecError: s.toml: key 'title': contains a control character (U+001B); write plain text
    """
    if not isinstance(value, str):
        raise SpecError(file, key, f"must be a string; got {echo(value)}")
    allowed = MULTILINE_CONTROLS if multiline else ""
    for ch in value:
        if not ch.isprintable() and ch not in allowed:
            raise SpecError(file, key, f"contains a control character (U+{ord(ch):04X}); write plain text")
    return value


#: the largest magnitude of an objective weight or a catalog cost: sums and products of such
#: terms with the chain's values (up to ~1e30) stay far from float64's overflow at 1.8e308
MAX_WEIGHT = 1e100


def weight_number(file, key: str, value, what: str = "a finite weight", zero_allowed: bool = False) -> float:
    """An objective weight or a catalog cost: a finite number of magnitude at most
    :data:`MAX_WEIGHT` (a cost may be 0, a weight not: a zero weight leaves its term out)."""
    out = finite_number(file, key, value, what)
    if abs(out) > MAX_WEIGHT:
        raise SpecError(file, key, f"{echo(value)} is too large: {what} must be at most {MAX_WEIGHT:g} in magnitude "
                        "(rescale the terms; only ratios of weights matter)")
    if not zero_allowed and out == 0:
        raise SpecError(file, key, "a weight of 0 leaves the term out; remove the term")
    return out


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
