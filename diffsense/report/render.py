"""Writing a report: Markdown, self-contained HTML and JSON from one list of blocks.

A report's text is a list of blocks — ``("h1"|"h2"|"h3", text)``, ``("p", text)``,
``("ul", [items])``, ``("table", headers, rows)``, ``("img", relative_path, caption)`` — so
the Markdown and HTML versions say the same thing. Images are referenced by relative paths
(the PNG files sit next to the report). The JSON file is the machine-readable report dict;
NumPy values become plain numbers and NaN/inf become ``null``.
"""

from __future__ import annotations

import html
import json
import math
from pathlib import Path
from typing import List

import numpy as np

_CSS = """
body { font-family: -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; max-width: 1060px;
       margin: 2em auto; padding: 0 1em; color: #1a1a1a; line-height: 1.45; }
h1 { border-bottom: 2px solid #1565c0; padding-bottom: .2em; }
h2 { border-bottom: 1px solid #ccc; padding-bottom: .15em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: .6em 0 1.2em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: .25em .55em; text-align: left; vertical-align: top; }
th { background: #e3eaf3; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
tr:nth-child(even) td { background: #f7f9fb; }
figure { margin: 1em 0 1.6em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.88em; color: #444; margin-top: .3em; }
code { background: #f2f2f2; padding: 0 .2em; }
"""


def to_jsonable(value):
    """NumPy/JAX values to plain JSON types (NaN and inf to None), recursively."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (str, bool)) or value is None:
        return value
    if isinstance(value, (np.bool_,)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    arr = np.asarray(value)
    if arr.dtype == object:
        return [to_jsonable(v) for v in arr.tolist()]
    if arr.ndim == 0:
        f = float(arr)
        return f if math.isfinite(f) else None
    return [to_jsonable(v) for v in arr]


def fmt(value, digits: int = 5) -> str:
    """A number for a table: ``digits`` significant digits, '—' for missing values."""
    if value is None:
        return "—"
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, str):
        return value
    v = float(value)
    if not math.isfinite(v):
        return "—"
    if v == 0:
        return "0"
    if 1e-4 <= abs(v) < 1e10:
        return np.format_float_positional(v, precision=digits, unique=True, fractional=False, trim="-")
    return f"{v:.{digits}g}"


_SI_PREFIXES = ((1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"),
                (1e-12, "p"))
_SI_UNITS = {"Hz", "W", "s", "m", "V", "J"}


def worst_point_text(row: dict) -> str:
    """Where an interval requirement's report row (``worst_at``, ``over``) found its worst value;
    empty for a requirement without an interval.

    >>> worst_point_text({"worst_at": {"range_m": 11968.2}, "over": {"range_m": (1e4, 2e4, "m")}})
    'range_m = 11968 m'
    >>> worst_point_text({"value": 3.0})
    ''
    """
    if "worst_at" not in row:
        return ""
    return ", ".join(f"{k} = {fmt(v)} {row['over'][k][2]}" for k, v in row["worst_at"].items())


def si_text(value, unit: str, digits: int = 4) -> str:
    """A value with its unit for a figure label: SI prefixes for Hz, W, s, m, V, J
    (``2.4e10 Hz`` -> ``24 GHz``), otherwise :func:`fmt` and :func:`unit_text`."""
    v = float(value)
    if unit in _SI_UNITS and math.isfinite(v) and v != 0:
        for factor, prefix in _SI_PREFIXES:
            if abs(v) >= factor * (1 - 1e-12):
                return f"{fmt(v / factor, digits)} {prefix}{unit}"
        return f"{fmt(v, digits)} {unit}"
    return f"{fmt(v, digits)} {unit_text(unit)}".rstrip()


def unit_text(unit: str) -> str:
    """A unit string for reading: ``m**3`` -> ``m^3``; the dimensionless ``1`` -> empty."""
    return "" if unit == "1" else unit.replace("**", "^")


def _is_number(cell) -> bool:
    if cell is None:
        return True
    if isinstance(cell, (bool, np.bool_)):
        return False
    if isinstance(cell, (int, float, np.floating, np.integer)):
        return True
    return isinstance(cell, np.ndarray) and cell.ndim == 0 and np.issubdtype(cell.dtype, np.number)


def _cell_text(cell) -> str:
    return fmt(cell) if _is_number(cell) or isinstance(cell, (bool, np.bool_)) else str(cell)


def _md_escape(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def to_markdown(blocks: List[tuple]) -> str:
    """Markdown text of the blocks."""
    out = []
    for b in blocks:
        kind = b[0]
        if kind in ("h1", "h2", "h3"):
            out.append("#" * int(kind[1]) + " " + b[1] + "\n")
        elif kind == "p":
            out.append(b[1] + "\n")
        elif kind == "ul":
            out.append("\n".join(f"- {item}" for item in b[1]) + "\n")
        elif kind == "table":
            headers, rows = b[1], b[2]
            lines = ["| " + " | ".join(_md_escape(h) for h in headers) + " |",
                     "| " + " | ".join("---:" if rows and _is_number(rows[0][k]) else "---"
                                       for k in range(len(headers))) + " |"]
            for r in rows:
                lines.append("| " + " | ".join(_md_escape(_cell_text(c)) for c in r) + " |")
            out.append("\n".join(lines) + "\n")
        elif kind == "img":
            out.append(f"![{_md_escape(b[2])}]({b[1]})\n\n*{b[2]}*\n")
    return "\n".join(out)


def to_html(blocks: List[tuple], title: str) -> str:
    """A self-contained HTML page of the blocks (inline CSS, images by relative path)."""
    e = html.escape
    body = []
    for b in blocks:
        kind = b[0]
        if kind in ("h1", "h2", "h3"):
            body.append(f"<{kind}>{e(b[1])}</{kind}>")
        elif kind == "p":
            body.append(f"<p>{e(b[1])}</p>")
        elif kind == "ul":
            body.append("<ul>" + "".join(f"<li>{e(str(i))}</li>" for i in b[1]) + "</ul>")
        elif kind == "table":
            headers, rows = b[1], b[2]
            head = "".join(f"<th>{e(h)}</th>" for h in headers)
            trs = []
            for r in rows:
                tds = "".join(f'<td class="num">{e(_cell_text(c))}</td>' if _is_number(c) else f"<td>{e(_cell_text(c))}</td>"
                              for c in r)
                trs.append(f"<tr>{tds}</tr>")
            body.append(f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(trs)}</tbody></table>")
        elif kind == "img":
            body.append(f'<figure><img src="{e(b[1])}" alt="{e(b[2])}"><figcaption>{e(b[2])}</figcaption></figure>')
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{e(title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n"
            + "\n".join(body) + "\n</body>\n</html>\n")


#: the files :func:`write_report` writes into the report's folder
REPORT_FILES = ("report.json", "report.md", "report.html")


def write_report(out_dir, report: dict, blocks: List[tuple]) -> dict:
    """Write ``report.json``, ``report.md`` and ``report.html`` into ``out_dir`` (a folder path or
    an :class:`~diffsense.report.files.OutputFolder`, whose rules apply); returns the paths."""
    from diffsense.report.files import WRITTEN_BY, OutputFolder

    folder = out_dir if isinstance(out_dir, OutputFolder) else OutputFolder(out_dir)
    data = {WRITTEN_BY: "diffsense", **to_jsonable(report)}
    return {"json": folder.write_text("report.json", json.dumps(data, indent=2, allow_nan=False)),
            "md": folder.write_text("report.md", to_markdown(blocks)),
            "html": folder.write_text("report.html", to_html(blocks, report.get("title", "design report")))}


__all__ = ["to_jsonable", "fmt", "worst_point_text", "si_text", "unit_text", "to_markdown", "to_html", "write_report", "REPORT_FILES"]
