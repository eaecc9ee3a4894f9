"""HTML of the explorer's text panes: the headline numbers and the stoplight requirements table.

Every number carries its full value in a ``data-value`` attribute beside the rounded text, and
every requirement row its status in ``data-status``, so a browser test reads exactly what the
page shows.
"""

from __future__ import annotations

from html import escape
from typing import List

from diffsense.report.render import fmt
from diffsense.design.spec.types import SENSE_SYMBOLS

#: (background, text colour) per requirement status
STOPLIGHT = {"met": ("#e8f5e9", "#1b5e20"), "active": ("#fff8e1", "#8d6e00"), "unmet": ("#ffebee", "#b71c1c"),
             "pending": ("#f6f8fa", "#57606a")}  # an interval requirement whose search is still compiling
STYLE = """
<style>
.ds-table {border-collapse: collapse; width: 100%; font-size: 13px;}
.ds-table th {text-align: left; border-bottom: 2px solid #bbb; padding: 4px 6px; color: #444;}
.ds-table td {padding: 4px 6px; border-bottom: 1px solid #e4e4e4;}
.ds-num {text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap;}
.ds-chip {display: inline-block; padding: 1px 8px; border-radius: 9px; font-weight: 600; font-size: 12px;}
.ds-cards {display: flex; gap: 12px; flex-wrap: wrap;}
.ds-card {border: 1px solid #d0d7de; border-radius: 8px; padding: 6px 14px; background: #fafbfc; min-width: 150px;}
.ds-card .ds-label {font-size: 12px; color: #57606a;}
.ds-card .ds-big {font-size: 22px; font-weight: 600; color: #1f2328;}
</style>
"""


#: text colour of a goal chip: PASS (goal met), WARN (threshold only), FAIL
GOAL_COLOURS = {"PASS": "#1b5e20", "WARN": "#8d6e00", "FAIL": "#b71c1c"}


def _goal_cell(r: dict) -> str:
    """The goal column of one row: a PASS / WARN / FAIL chip and the goal (empty without one)."""
    if "goal" not in r:
        return "<td></td>"
    if r["status"] == "pending":
        return f'<td>{SENSE_SYMBOLS[r["sense"]]} {fmt(r["goal"])}</td>'
    fg = GOAL_COLOURS[r["goal_status"]]
    return (f'<td data-goal="{r["goal_status"]}"><span class="ds-chip" style="color:{fg};border:1px solid {fg}">'
            f'{r["goal_status"]}</span> {SENSE_SYMBOLS[r["sense"]]} {fmt(r["goal"])}</td>')


def requirements_html(rows: List[dict]) -> str:
    """The requirements with value, limit, slack and a met / active / unmet chip; a goal column
    (PASS / WARN / FAIL) when any requirement has a goal."""
    goals = any("goal" in r for r in rows)
    body = []
    for r in rows:
        bg, fg = STOPLIGHT[r["status"]]
        body.append(
            f'<tr class="ds-req" data-name="{escape(r["name"])}" data-status="{r["status"]}" '
            f'style="background:{bg}">'
            f'<td>{escape(r["name"])}</td>'
            f'<td class="ds-num" data-value="{r["value"]!r}">{fmt(r["value"])}</td>'
            f'<td class="ds-num">{SENSE_SYMBOLS[r["sense"]]} {fmt(r["limit"])}</td>'
            f'<td>{escape(r["unit"])}</td>'
            f'<td class="ds-num" data-value="{r["slack"]!r}">{fmt(r["slack"])}</td>'
            f'<td><span class="ds-chip" style="color:{fg};border:1px solid {fg}">{r["status"]}</span></td>'
            + (_goal_cell(r) if goals else "") + '</tr>')
    head = ("<tr><th>requirement</th><th>value</th><th>limit</th><th>unit</th><th>slack</th><th>status</th>"
            + ("<th>goal</th>" if goals else "") + "</tr>")
    return f'{STYLE}<table class="ds-table" id="ds-requirements">{head}{"".join(body)}</table>'


def card(label: str, value: float, unit: str, role: str, digits: int = 3) -> str:
    """One headline number: its label, the value rounded to ``digits`` decimals, its unit."""
    return (f'<div class="ds-card"><div class="ds-label">{escape(label)}</div>'
            f'<div class="ds-big" data-role="{role}" data-value="{value!r}">{value:.{digits}f} '
            f'<span style="font-size:14px">{escape(unit)}</span></div></div>')


def headline_html(snapshot: dict, objective_text: str, units: dict) -> str:
    """Each case's headline output, the number of requirements met and the objective."""
    cards = []
    several = len(snapshot["cases"]) > 1
    for case, c in snapshot["cases"].items():
        name = c["headline"]
        if name is not None:
            label = f"{name} ({case})" if several else name
            cards.append(card(label, c["outputs"][name], units.get((case, name), ""), f"headline-{case}"))
    met = sum(r["status"] in ("met", "active") for r in snapshot["requirements"])
    pending = sum(r["status"] == "pending" for r in snapshot["requirements"])
    total = len(snapshot["requirements"])
    colour = STOPLIGHT["met" if met == total else "pending" if met + pending == total else "unmet"][1]
    more = f' <span style="font-size:13px">({pending} pending)</span>' if pending else ""
    cards.append(f'<div class="ds-card"><div class="ds-label">requirements met</div>'
                 f'<div class="ds-big" data-role="met" style="color:{colour}">{met} / {total}{more}</div></div>')
    cards.append(card(f"objective: {objective_text}", snapshot["objective"], "", "objective", digits=4))
    return f'{STYLE}<div class="ds-cards">{"".join(cards)}</div>'


__all__ = ["requirements_html", "headline_html", "card", "STOPLIGHT"]
