"""The text of a design report: blocks (see :mod:`diffsense.report.render`) from the report dict."""

from __future__ import annotations

from typing import List

import numpy as np

from diffsense.design.goals import plan_lines
from diffsense.report.glance import glance_blocks
from diffsense.report.jacobian import FD_STEP
from diffsense.report.render import fmt, unit_text
from diffsense.design.spec.types import SENSE_SYMBOLS


def _figure_blocks(report: dict, section: str) -> List[tuple]:
    """The figures of ``section`` (the ``section`` key :func:`~diffsense.report.build.build_report`
    gives each figure it wrote: ``budget:<case>``, ``range:<case>``, ``roc:<case>``,
    ``coverage:<case>``, ``interval:<j>``, ``tornado:<j>``)."""
    return [("img", f["file"], f["caption"]) for f in report.get("figures", []) if f.get("section") == section]


def _skipped_line(report: dict, title: str) -> List[tuple]:
    """One line saying why the figure titled ``title`` was not drawn (nothing if it was not skipped)."""
    return [("p", f"Not drawn: {s['reason']}") for s in report.get("skipped_figures", []) if s["figure"] == title]


def description_blocks(text: str) -> List[tuple]:
    """A spec's description as report blocks: paragraphs separated by blank lines, and bullet
    lists whose items start with ``*`` or ``-`` (an indented line continues the item above).

    >>> description_blocks("Intro line\\nwraps.\\n\\nList:\\n* one\\n  more\\n* two")
    [('p', 'Intro line wraps.'), ('p', 'List:'), ('ul', ['one more', 'two'])]
    """
    blocks: List[tuple] = []
    para: List[str] = []
    items: List[str] = []

    def flush():
        if para:
            blocks.append(("p", " ".join(para)))
            para.clear()
        if items:
            blocks.append(("ul", list(items)))
            items.clear()

    for raw in text.strip().splitlines():
        line = raw.strip()
        if not line:
            flush()
        elif line[:2] in ("* ", "- "):
            if para:
                flush()
            items.append(line[2:].strip())
        elif items and raw[:1] in (" ", "\t"):
            items[-1] += " " + line
        else:
            if items:
                flush()
            para.append(line)
    flush()
    return blocks


def _summary(report: dict) -> List[tuple]:
    blocks = [("h1", f"Design report: {report['title']}")]
    mode = ("the optimum found by diffsense's optimiser" if report["mode"] == "optimum"
            else "the spec's initial design (each variable's initial value, each catalog's first option)")
    blocks.append(("p", f"Spec file {report['spec_file']} ({report['sensor']}). This report describes {mode}."))
    if report.get("description"):
        blocks.extend(description_blocks(report["description"]))
    items = [f"Objective: {report['objective']['text']} = {fmt(report['objective']['value'])} "
             f"{unit_text(report['objective']['unit'])}".rstrip()]
    if report["mode"] == "optimum":
        items.append(f"Optimiser converged: {fmt(report['converged'])}; every requirement met: {fmt(report['feasible'])}")
        ms = report.get("multistart", {})
        if ms:
            items.append(f"Starts reaching the best design: {ms['reached_best']} of {ms['starts']}")
        if report.get("unmet"):
            items.append("Requirements not met: " + "; ".join(report["unmet"]))
        if report.get("goals"):
            items.extend(f"Goals, cheapest first: {line}" for line in plan_lines(report["goals"], report["objective"]["text"]))
        c = report.get("canonical")
        if c:
            items.append(f"Choice among equally good designs: {c['rule']}. The optimal set has {c['flat_directions']} "
                         f"flat direction(s); the smallest scaled slack of those requirements went from "
                         f"{fmt(c['smallest_slack_before'])} to {fmt(c['smallest_slack_after'])}.")
        else:
            items.append("Choice among equally good designs: none needed (no flat direction of the optimal set was "
                         "found at the optimum).")
    else:
        items.append(f"Every requirement met at this design: {fmt(report['feasible'])}")
    blocks.append(("ul", items))
    return blocks


def _design(report: dict) -> List[tuple]:
    status = (report.get("post_optimal") or {}).get("variable_status") or {}
    rows = []
    for name, d in report["design"].items():
        rows.append([name, d["value"], unit_text(d["unit"]), d["kind"], d.get("lower"), d.get("upper"),
                     status.get(name, "")])
    for name, option in report.get("choices", {}).items():
        if name not in report["design"]:  # a one-parameter catalog is already its parameter's row
            rows.append([name, option, "", "catalog option", None, None, ""])
    return [("h2", "Design"),
            ("table", ["parameter", "value", "unit", "kind", "lower", "upper", "at the optimum"], rows)]


def _worst_text(r: dict) -> str:
    """`` (over range_m 10000-20000 m: worst at 11968.2 m, 10001 points)`` for an interval requirement."""
    if "worst_at" not in r:
        return ""
    parts = [f"{k} {fmt(lo)}-{fmt(hi)} {u}" for k, (lo, hi, u) in r["over"].items()]
    where = ", ".join(f"{fmt(v)} {r['over'][k][2]}" for k, v in r["worst_at"].items())
    return f" (over {'; '.join(parts)}: worst at {where}, {r['dense_points']} points re-checked)"


def _requirements(report: dict) -> List[tuple]:
    post = report.get("post_optimal") or {}
    shadow = {s["requirement"]: s for s in post.get("shadow_prices") or []}
    mult = {m["requirement"]: m["multiplier"] for m in report.get("multipliers") or []}
    goals = any("goal" in r for r in report["requirements"])
    rows = []
    for r in report["requirements"]:
        s = shadow.get(r["name"], {})
        row = [r["name"] + _worst_text(r), f"{r['case']}.{r['output']}", r["value"], f"{SENSE_SYMBOLS[r['sense']]} {fmt(r['limit'])}",
               unit_text(r["unit"]), r["slack"], r["met"]]
        if goals:
            row.append(f"{r['goal_status']}: {SENSE_SYMBOLS[r['sense']]} {fmt(r['goal'])}" if "goal" in r else "")
        rows.append(row + [s.get("active", None) if s else None, mult.get(r["name"]), s.get("d_objective_d_limit")])
    columns = ["requirement", "output", "value", "limit", "unit", "slack", "met"] + (["goal"] if goals else [])
    blocks = [("h2", "Requirements"),
              ("table", columns + ["active", "multiplier (optimiser, normalised)", "d objective / d limit"], rows)]
    if goals:
        blocks.append(("p", "goal: PASS where the design reaches the goal, WARN where it meets only the threshold "
                            "(the limit the optimiser enforces), FAIL where it misses the threshold."))
    if shadow:
        unit = unit_text(report["objective"]["unit"]) or "objective units"
        blocks.append(("p", "d objective / d limit is the shadow price of each requirement: how much the optimal "
                            f"objective changes per unit of the limit ({unit} per requirement unit), "
                            "from the stationarity condition with the report's derivatives; the normalised multiplier "
                            "is the optimiser's own (objective divided by its value at the initial design, per "
                            "normalised requirement)."))
    return blocks


def _probabilities(report: dict) -> List[tuple]:
    """Each requirement's probability of being met under the declared uncertainty (the rows
    that carry a Monte Carlo ``probability`` check, :mod:`diffsense.design.monte_carlo`)."""
    checked = [r for r in report["requirements"] if r.get("probability")]
    if not checked:
        return []
    rows = [[r["name"], r["probability"]["asked"], r["probability"]["estimate"], r["probability"]["interval"][0],
             r["probability"]["interval"][1], r["probability"]["samples"], r["probability"]["status"] or ""]
            for r in checked]
    first = checked[0]["probability"]
    inputs = "; ".join(f"{u['parameter']}: {u['distribution']} ({u['spec']})" for u in report.get("uncertain", []))
    return [("h2", "Requirements under uncertainty"),
            ("p", f"Uncertain inputs: {inputs}. Probability that each requirement is met, from an independent Monte "
                  f"Carlo sample of {first['samples']} draws (seed {first['seed']}), with its "
                  f"{first['confidence']:g} Wilson interval; a requirement that asks for a probability meets it "
                  "through a smoothed-quantile chance constraint on a separate, fixed design sample (its value above "
                  "is that quantile). 'check': where the asked probability lies relative to the interval."),
            ("table", ["requirement", "asked", "probability", "lower", "upper", "draws", "check"], rows)]


def _budgets(report: dict) -> List[tuple]:
    blocks = []
    multi = len(report["cases"]) > 1
    for case, c in report["cases"].items():
        tag = f" ({case})" if multi else ""
        blocks.append(("h2", f"Link budget{tag}"))
        if not c["budget"]:
            blocks.append(("p", "The chain of this case has no link budget."))
            continue
        rows = [[r["term"], r["db"], r["running_total_db"]] for r in c["budget"]]
        rows.append(["SNR (sum of the terms)", c["budget_total_db"], c["budget_total_db"]])
        blocks.append(("table", ["term", "dB", "running total (dB)"], rows))
        blocks += _figure_blocks(report, f"budget:{case}")
        outs = c["outputs"]
        keys = [k for k in ("snr_db", "required_snr_db", "snr_margin_db", "faded_snr_margin_db", "pd",
                            "detection_range_m") if k in outs]
        if keys:
            blocks.append(("table", ["output", "value", "unit"],
                           [[k, float(np.asarray(outs[k]["value"])), unit_text(outs[k]["unit"])] for k in keys]))
    return blocks


def _detection(report: dict) -> List[tuple]:
    """Range sweeps, ROC and (for chains that draw it) coverage of every case; a heading whose figures were all
    skipped says why in one line."""
    cases = list(report["cases"])
    multi = len(cases) > 1
    blocks: List[tuple] = []
    for heading, key, titles in (("Detection against range", "range", ("SNR versus range", "Pd versus range")),
                                 ("Receiver operating characteristic", "roc", ("ROC",)),
                                 ("Coverage chart", "coverage", ("Coverage chart (Blake)",))):
        if key == "coverage" and not report["coverage_charts"]:
            continue
        body: List[tuple] = []
        for case in cases:
            tag = f" ({case})" if multi else ""
            figs = _figure_blocks(report, f"{key}:{case}")
            body += figs
            if not figs:
                for t in titles:
                    body += [("p", f"{t}{tag}: {b[1][len('Not drawn: '):]}") for b in _skipped_line(report, f"{t}{tag}")]
        if body:
            blocks += [("h2", heading)] + body
    return blocks


def _intervals(report: dict) -> List[tuple]:
    """Each interval requirement's margin over its interval (figures ``interval:<j>``)."""
    body: List[tuple] = []
    for j, r in enumerate(report["requirements"]):
        figs = _figure_blocks(report, f"interval:{j}")
        if figs:
            body += [("h3", r["name"])] + figs
    return [("h2", "Requirements over their intervals")] + body if body else []


def _elasticities(report: dict) -> List[tuple]:
    jac = report.get("jacobian")
    blocks = [("h2", "Sensitivity of the requirements: derivatives and elasticities")]
    if not jac:
        blocks.append(("p", "Not available (see the list of unavailable sections)."))
        return blocks
    blocks.append(("p", "Derivatives by forward-mode automatic differentiation through the whole chain, with respect "
                        "to every numeric input: design variables, catalog parameters and fixed parameters. The "
                        "elasticity measures each quantity in dB (its value for dB quantities, 10 log10 of a positive "
                        "linear quantity): dB of output per dB of input, which for two linear quantities is the "
                        "percentage change of the output per percent of the input. Only inputs with a non-zero "
                        "derivative are listed (|elasticity| above 1e-12 where it is defined)."))
    inputs = jac["inputs"]
    D = np.asarray(jac["derivative"], dtype=float)
    E = np.asarray(jac["elasticity"], dtype=float)
    fd = jac["fd_check"]
    rel = np.asarray(fd["rel_diff"], dtype=float) if fd.get("rel_diff") is not None else np.full(D.shape, np.nan)
    status = np.asarray(fd["status"], dtype=object) if fd.get("status") is not None else np.full(D.shape, "", dtype=object)
    for a, out in enumerate(jac["outputs"]):
        label = out["name"] if out["case"] is None else f"{out['name']} ({out['case']}.{out['output']})"
        blocks.append(("h3", f"{label} = {fmt(out['value'])} {unit_text(out['unit'])}".rstrip()))
        order = sorted(range(len(inputs)), key=lambda j: -abs(E[a, j]) if np.isfinite(E[a, j]) else -0.0)
        rows = []
        for j in order:
            if D[a, j] == 0 or not np.isfinite(D[a, j]) or (np.isfinite(E[a, j]) and abs(E[a, j]) <= 1e-12):
                continue
            check = fmt(rel[a, j], 2) if np.isfinite(rel[a, j]) else str(status[a, j]).replace("_", " ")
            rows.append([inputs[j]["name"], inputs[j]["kind"], inputs[j]["value"], unit_text(inputs[j]["unit"]), D[a, j],
                         f"{unit_text(out['unit']) or '1'} per {unit_text(inputs[j]['unit']) or '1'}", E[a, j], check])
        if rows:
            blocks.append(("table", ["input", "kind", "value", "unit", "derivative", "derivative unit", "elasticity",
                                     "FD rel. diff"], rows))
        else:
            blocks.append(("p", "No input changes this output."))
        blocks += _figure_blocks(report, f"tornado:{a}")
    mx = fd.get("max_rel_diff")
    text = (f"Finite-difference check: fourth-order central differences (step {FD_STEP:g} in ln u for positive inputs, "
            f"{FD_STEP:g}·max(1, |u|) otherwise) against the automatic derivatives. Largest relative difference over "
            f"the {fd.get('n_compared', 0)} entries that could be compared: {fmt(mx, 3)}. "
            f"{fd.get('n_below_resolution', 0)} entries change the output by less than "
            f"{fd.get('resolution', 0):g}·max(1, |y|) over the step (zero or below what differencing resolves).")
    if fd.get("reason"):
        text += " " + fd["reason"] + "."
    blocks.append(("p", text))
    extra = []
    for key, what in (("not_smooth", "not smooth at the design (one-sided slopes differ: a kink, e.g. a table breakpoint)"),
                      ("one_sided", "differenced one-sidedly (the input sits at the edge of its domain)"),
                      ("not_finite", "not finite")):
        for p in fd.get(key) or []:
            extra.append(f"{p['output']} / {p['input']}: {what}")
    if extra:
        blocks.append(("ul", extra))
    return blocks


def _post_optimal(report: dict) -> List[tuple]:
    post = report.get("post_optimal") or {}
    blocks = [("h2", "Post-optimal sensitivity: the optimum per unit change of each requirement limit")]
    if report["mode"] != "optimum":
        blocks.append(("p", f"Not available: {post.get('reason', '')}"))
        return blocks
    if post.get("dx_dlimit") is None:
        blocks.append(("p", f"Not available: {post.get('reason', 'unknown reason')}"))
        return blocks
    text = f"Method: {post.get('method')}."
    if post.get("hessian"):
        text += f" Hessian of the Lagrangian: {post['hessian']}"
        text += f" ({post['hessian_note']})." if post.get("hessian_note") else "."
        if post.get("hessian_fd_rel_diff") is not None:
            text += (" Largest difference from its finite-difference estimate, relative to max |W|: "
                     f"{fmt(post['hessian_fd_rel_diff'], 2)}.")
    if post.get("stationarity_rel_residual") is not None:
        text += f" Relative residual of the stationarity condition: {fmt(post['stationarity_rel_residual'], 2)}."
    if post.get("reason"):
        text += f" Not computed: {post['reason']}."
    blocks.append(("p", text))
    reqs = [r["name"] for r in report["requirements"]]
    status = post.get("variable_status", {})
    table = post["dx_dlimit"]
    headers = ["variable", "status"] + [f"d/d limit of '{r}'" for r in reqs]
    rows = []
    for name, st in status.items():
        cells = [name, st]
        for r in reqs:
            e = table[r][name]
            cells.append(f"{fmt(e['value'])} {e['unit']}" if e["value"] is not None and np.isfinite(e["value"]) else "—")
        rows.append(cells)
    blocks.append(("table", headers, rows))
    blocks.append(("ul", [
        "free: a derivative by the implicit function theorem; lower/upper: held at that bound (0 while it stays "
        "active); integer: held at its rounded value; not_unique: neither the objective nor an active requirement "
        "depends on it, so the optimum is not unique along it and has no derivative (—).",
        "Inactive requirements (" + (", ".join(r for r in reqs if r not in post.get("active_requirements", [])) or "none")
        + ") do not move the optimum for small changes of their limits.",
    ] + ([f"Weakly active (zero multiplier, one-sided derivative): {', '.join(post['weakly_active'])}"]
         if post.get("weakly_active") else [])))
    return blocks


def _unavailable(report: dict) -> List[tuple]:
    items = [f"{u['section']}: {u['reason']}" for u in report.get("unavailable", [])]
    items += [f"Figure '{s['figure']}': {s['reason']}" for s in report.get("skipped_figures", [])]
    if not items:
        return []
    return [("h2", "Sections and figures not produced"), ("ul", items)]


def _orphans(report: dict, blocks: List[tuple]) -> List[tuple]:
    """Every figure written that no section above shows (none, when each figure's section is
    known): a figure written is always shown."""
    shown = {b[1] for b in blocks if b[0] == "img"}
    rest = [("img", f["file"], f["caption"]) for f in report.get("figures", []) if f["file"] not in shown]
    return [("h2", "Other figures")] + rest if rest else []


def report_blocks(report: dict) -> List[tuple]:
    """All blocks of the report, in reading order: the one-page summary
    (:mod:`diffsense.report.glance`) first."""
    blocks = (_summary(report)[:1] + glance_blocks(report) + _summary(report)[1:] + _design(report)
              + _requirements(report) + _intervals(report) + _probabilities(report) + _budgets(report)
              + _detection(report) + _elasticities(report) + _post_optimal(report))
    return blocks + _orphans(report, blocks) + _unavailable(report)


__all__ = ["report_blocks"]
