"""The one-page summary at the top of a design report: the page an engineer reads first.

* the verdict — every requirement met or not, the optimiser converged or not;
* the stoplight of every requirement: ``UNMET`` (with its shortfall), ``ACTIVE`` (met with zero
  slack: it holds the design where it is) or ``met`` with its slack, and for a requirement over
  an interval the point where it is worst;
* what sets the design: the active requirements, the variables on a bound, the catalog choice
  (:func:`diffsense.design.activity.design_findings`);
* the three inputs the tightest requirement is most sensitive to (largest |elasticity|,
  :mod:`diffsense.report.jacobian`), with what a 1 dB (1 %) change of each does to it;
* the warnings: a design set by a bound alone, a requirement no variable moves, a solve that
  did not converge, sections that could not be computed.
"""

from __future__ import annotations

from typing import List

import numpy as np

from diffsense.report.render import fmt, si_text, unit_text, worst_point_text
from diffsense.design.spec.types import SENSE_SYMBOLS

_LIGHT = {"unmet": "UNMET", "active": "ACTIVE", "met": "met"}


def stoplight_rows(report: dict) -> List[list]:
    """One row per requirement: status, name, value, limit, slack, worst point."""
    status = (report.get("findings") or {}).get("status") or [
        "met" if r["met"] else "unmet" for r in report["requirements"]]
    rows = []
    for r, st in zip(report["requirements"], status):
        unit = unit_text(r["unit"])
        rows.append([_LIGHT[st], r["name"], f"{fmt(r['value'])} {unit}".rstrip(),
                     f"{SENSE_SYMBOLS[r['sense']]} {fmt(r['limit'])} {unit}".rstrip(), f"{fmt(r['slack'])} {unit}".rstrip(),
                     worst_point_text(r)])
    return rows


def sensitive_inputs(report: dict, top: int = 3) -> List[str]:
    """The ``top`` inputs with the largest |elasticity| on the tightest requirement, as sentences."""
    jac = report.get("jacobian")
    j = (report.get("findings") or {}).get("tightest")
    if not jac or j is None:
        return []
    E = np.asarray(jac["elasticity"], dtype=float)[j]
    order = [k for k in np.argsort(-np.nan_to_num(np.abs(E), nan=-1.0)) if np.isfinite(E[k]) and abs(E[k]) > 1e-12]
    name = report["requirements"][j]["name"]
    out = []
    for k in order[:top]:
        inp = jac["inputs"][k]
        measure = "1 − pd" if inp["param"] == "pd" else inp["name"]
        out.append(f"{inp['name']} ({inp['kind']}, {si_text(inp['value'], inp['unit'])}): {fmt(E[k], 3)} dB of "
                   f"'{name}' per dB of {measure}")
    return out


def warning_lines(report: dict) -> List[str]:
    """Every warning the summary shows."""
    out = list((report.get("findings") or {}).get("warnings") or [])
    if report["mode"] == "optimum" and not report.get("converged"):
        out.append("the optimiser did not converge on a design that meets every requirement")
    if report.get("unavailable"):
        out.append(f"{len(report['unavailable'])} section(s) could not be computed: see 'Sections and figures not "
                   "produced' at the end")
    return out


def glance_blocks(report: dict) -> List[tuple]:
    """The summary's report blocks (:mod:`diffsense.report.render`)."""
    rows = stoplight_rows(report)
    unmet = sum(r[0] == "UNMET" for r in rows)
    what = "optimum" if report["mode"] == "optimum" else "initial design"
    verdict = (f"The {what} meets every requirement ({len(rows)})." if not unmet
               else f"The {what} does not meet {unmet} of {len(rows)} requirement(s).")
    blocks: List[tuple] = [("h2", "At a glance"), ("p", verdict),
                           ("table", ["status", "requirement", "value", "limit", "slack", "worst at"], rows)]
    f = report.get("findings")
    if f:
        sets = []
        sets.append("Active requirements: " + ("; ".join(f["active"]) if f["active"] else "none"))
        if f["bounds"]:
            sets.append("Variables on a bound: " + ", ".join(f"{n} ({side})" for n, side in f["bounds"]))
        if f["choice"]:
            sets.append("Catalog choice: " + ", ".join(f"{k} = {v}" for k, v in f["choice"].items()))
        blocks += [("h3", "What sets the design"), ("ul", sets)]
    sens = sensitive_inputs(report)
    if sens:
        name = report["requirements"][report["findings"]["tightest"]]["name"]
        blocks += [("h3", f"Most sensitive inputs of the tightest requirement ('{name}')"), ("ul", sens)]
    warns = warning_lines(report)
    if warns:
        blocks += [("h3", "Warnings"), ("ul", warns)]
    return blocks


__all__ = ["glance_blocks", "stoplight_rows", "sensitive_inputs", "warning_lines"]
