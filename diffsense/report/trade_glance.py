"""The one-page summary at the top of a trade report (:mod:`diffsense.report.trade`).

* the stoplight of every requirement along the front: ``ACTIVE`` at how many of the front's
  points (it shapes the front there), or ``met`` everywhere with its smallest slack, at which
  point and (interval requirements) where over its interval;
* what sets the front: the requirements active somewhere, the variables on a bound and at
  which points, the catalog options the front uses;
* the warnings: a variable on the same bound at every point (the bound, not the trade, sets
  it), a requirement no variable moves (:func:`diffsense.design.activity.fixed_requirements`,
  probed at the knee, else the first point), the points dropped.

The sensitivities of a single design are a design report's (``diffsense report``); a front has
one design per point, so this page names the knee's design for them.
"""

from __future__ import annotations

from typing import List

import numpy as np

from diffsense.design.activity import fixed_requirements
from diffsense.design.trade import TradeResult
from diffsense.report.render import fmt, unit_text, worst_point_text


def _where(r: dict) -> str:
    where = worst_point_text(r)
    return f" (worst at {where})" if where else ""


def requirement_lines(result: TradeResult) -> List[str]:
    """One table row (Markdown) per requirement: status along the front, smallest slack, where."""
    model = result.model
    n = len(result.points)
    rows = ["| status | requirement | active at | smallest slack | at point |", "|---|---|---|---|---|"]
    for j, req in enumerate(model.requirements):
        active = sum(req.name in p["active"] for p in result.points)
        slacks = np.array([p["requirements"][j]["slack"] for p in result.points])
        k = int(np.argmin(slacks))
        r = result.points[k]["requirements"][j]
        status = "ACTIVE" if active else "met"
        rows.append(f"| {status} | {req.name} | {active} of {n} points | {fmt(r['slack'])} {unit_text(r['unit'])}"
                    f"{_where(r)} | {k + 1} |")
    return rows


def bound_counts(result: TradeResult) -> dict:
    """``{"<variable> at its lower/upper bound": points of the front where it is}``."""
    counts = {}
    for p in result.points:
        for b in p["on_bounds"]:
            counts[b] = counts.get(b, 0) + 1
    return counts


def bound_warnings(result: TradeResult, counts=None) -> List[str]:
    """A variable on the same bound at every point of the front."""
    counts = bound_counts(result) if counts is None else counts
    return [f"{b} at every point of the front: the bound, not the trade, sets it"
            for b, c in counts.items() if c == len(result.points)]


def glance_markdown(result: TradeResult) -> List[str]:
    """The summary's Markdown lines."""
    model = result.model
    if not result.points:
        return ["## At a glance", "", "No point of the front met every requirement: nothing to summarise.", ""]
    lines = ["## At a glance", "", f"{len(result.points)} designs on the front, every one meeting every requirement "
             "on the exact re-evaluation (dense re-check of the interval requirements).", ""]
    lines += requirement_lines(result) + [""]
    sets = []
    active = [r.name for r in model.requirements if any(r.name in p["active"] for p in result.points)]
    sets.append("Active requirements somewhere on the front: " + ("; ".join(active) if active else "none"))
    counts = bound_counts(result)
    if counts:
        sets.append("Variables on a bound: " + "; ".join(f"{b} ({c} of {len(result.points)} points)"
                                                         for b, c in counts.items()))
    if model.spec.choices:
        used = sorted({", ".join(f"{k} = {v}" for k, v in model.combinations[p["combo_index"]].options.items())
                       for p in result.points})
        sets.append("Catalog choices on the front: " + " | ".join(used))
    lines += ["### What sets the front", ""] + [f"- {s}" for s in sets] + [""]
    probe = result.points[result.knee if result.knee is not None else 0]
    fixed = fixed_requirements(model, probe["x"], probe["combo_index"])
    warns = bound_warnings(result, counts)
    warns += [f"requirement '{model.requirements[j].name}' does not depend on any variable: it is a check, "
              "not a constraint" for j in fixed]
    d = result.dropped
    if d.get("unconverged") or d.get("unmet"):
        warns.append(f"{d.get('unconverged', 0)} point(s) not converged and {d.get('unmet', 0)} missing a requirement "
                     "on the re-evaluation were dropped: the front may have gaps there")
    if warns:
        lines += ["### Warnings", ""] + [f"- {w}" for w in warns] + [""]
    lines += ["Sensitivities belong to one design: `diffsense report` gives them for a spec set to a front point's "
              "design (each point's values are in front.csv).", ""]
    return lines


__all__ = ["glance_markdown", "requirement_lines", "bound_counts", "bound_warnings"]
