"""A requirement spec's TOML text with the explorer's current point written in.

The explorer edits a copy of the spec's own document (``tomlkit`` keeps its comments, its
description and the order of its keys), so that a saved spec differs from the original only
where the user moved something:

* each design variable's ``initial`` is its current value, a bare number in the parameter's
  own unit (read back exactly: :mod:`diffsense.design.units` reads a bare number in that unit);
* each catalog lists its current option first (``diffsense evaluate`` evaluates the first
  option of every catalog, ``diffsense optimize`` still considers them all); a one-parameter
  catalog's ``costs`` move with its ``choices``;
* a fixed value typed by the user replaces the value in ``[fixed]`` (and in every case table
  that overrides it), or in one case table for a per-case input named ``<case>.<parameter>``.
"""

from __future__ import annotations

from typing import Mapping, Tuple

import tomlkit

from diffsense.design.spec import parse_spec


def read_document(text: str):
    """The spec's TOML document (comments and layout kept)."""
    return tomlkit.parse(text)


def copy_document(doc):
    """An independent copy of a document."""
    return tomlkit.parse(doc.as_string())


def set_initial(doc, name: str, value: float, integer: bool) -> None:
    """``[variables.<name>] initial = value`` (a bare number in the parameter's unit)."""
    doc["variables"][name]["initial"] = int(round(value)) if integer else float(value)


def _reordered(items, first: int) -> list:
    items = list(items)
    return [items[first]] + items[:first] + items[first + 1:]


def put_option_first(doc, catalog: str, option: int) -> None:
    """Move option ``option`` of ``catalog`` (a one-parameter catalog variable or a
    ``[choices]`` catalog) to the front of its list."""
    if option == 0:
        return
    variables = doc.get("variables", {})
    if catalog in variables and "choices" in variables[catalog]:
        table = variables[catalog]
        table["choices"] = _reordered(table["choices"].unwrap(), option)
        if "costs" in table:
            table["costs"] = _reordered(table["costs"].unwrap(), option)
        return
    table = doc["choices"][catalog]
    options = table["options"]
    if isinstance(options, tomlkit.items.AoT):
        items = [o.unwrap() for o in options]
        table["options"] = tomlkit.aot()
        for o in _reordered(items, option):
            table["options"].append(o)
        return
    array = tomlkit.array()
    for o in _reordered(options.unwrap(), option):
        inline = tomlkit.inline_table()
        inline.update(o)
        array.append(inline)
    array.multiline(True)
    table["options"] = array


def set_fixed(doc, name: str, param: str, text: str) -> None:
    """A fixed value typed by the user (``text``, e.g. ``"250 m"``) for the input ``name``:
    ``<case>.<parameter>`` sets that case's table, a plain parameter name sets ``[fixed]`` and
    every case table that overrides it."""
    value = _toml_value(text)
    if name != param:
        case = name.split(".", 1)[0]
        doc["cases"][case][param] = value
        return
    if "fixed" not in doc:
        doc["fixed"] = tomlkit.table()
    doc["fixed"][param] = value
    for case in doc.get("cases", {}).values():
        if param in case:
            case[param] = value


def _toml_value(text: str):
    """A typed value as TOML: a bare number stays a number, anything else a string."""
    stripped = text.strip()
    try:
        return int(stripped) if stripped.lstrip("+-").isdigit() else float(stripped)
    except ValueError:
        return stripped


def checked_spec(doc, path):
    """Validate ``doc`` exactly as :func:`diffsense.design.spec.load_spec` validates a file
    (raises :class:`~diffsense.errors.SpecError` with the same message the CLI prints)."""
    return parse_spec(doc.unwrap(), path)


def write_point(doc, *, initial: Mapping[str, Tuple[float, bool]], options: Mapping[str, int],
                fixed: Mapping[str, Tuple[str, str]]):
    """A copy of ``doc`` with the current point: ``initial`` {variable: (value, integer)},
    ``options`` {catalog: index of the current option in the original list}, ``fixed``
    {input name: (parameter, typed text)}."""
    out = copy_document(doc)
    for name, (param, text) in fixed.items():
        set_fixed(out, name, param, text)
    for name, (value, integer) in initial.items():
        set_initial(out, name, value, integer)
    for catalog, option in options.items():
        put_option_first(out, catalog, option)
    return out


__all__ = ["read_document", "copy_document", "set_initial", "put_option_first", "set_fixed", "checked_spec",
           "write_point"]
