"""Printing a design record (``diffsense evaluate/optimize``): the design, each case's link budget
with its total, and the requirements with their slack."""

from __future__ import annotations

from rich.text import Text

from diffsense.cli.output import Reporter, fmt, fmt_db
from diffsense.design.spec.types import SENSE_ASCII


def print_design(record: dict, reporter: Reporter) -> None:
    rows = [(name, fmt(d["value"]), d["unit"], d["kind"]) for name, d in record["design"].items()]
    # a one-parameter catalog is already its parameter's row
    rows += [(name, option, "", "catalog option") for name, option in record.get("choices", {}).items()
             if name not in record["design"]]
    reporter.table("Design", ("parameter", "value", "unit", "kind"), rows, right=("value",))


def term_label(term: str, sensor: str, options: dict) -> str:
    """A budget term's name, with the static option that sets it and whether that option was
    left at its default, so that a default that changes the answer is visible.

    >>> term_label("matched_filter_loss_db", "radar", {})
    'matched_filter_loss_db (matched_filter = two_tuned, the default)'
    >>> term_label("matched_filter_loss_db", "radar", {"matched_filter": "gaussian"})
    'matched_filter_loss_db (matched_filter = gaussian)'
    """
    from diffsense.scene import CHAINS

    for option, (default, _) in (CHAINS[sensor].options.items() if sensor in CHAINS else ()):
        if term.startswith(option + "_"):
            if option in options:
                return f"{term} ({option} = {options[option]})"
            return f"{term} ({option} = {default}, the default)"
    return term


def print_budgets(record: dict, reporter: Reporter) -> None:
    for case, c in record["cases"].items():
        if not c["budget"]:
            continue
        options = c.get("options", {})
        rows = [(term_label(row["term"], record["sensor"], options), fmt_db(row["db"])) for row in c["budget"]]
        total = sum(row["db"] for row in c["budget"])
        rows.append((Text("total", style="bold"), Text(fmt_db(total), style="bold")))
        reporter.table(f"Link budget ({case})", ("term", "dB"), rows, right=("dB",))


def worst_point_text(row: dict) -> str:
    """`` (worst at range_m = 11968.2 m; 10001 points re-checked)`` for a requirement over an
    interval, ``""`` otherwise."""
    if "worst_at" not in row:
        return ""
    where = ", ".join(f"{k} = {fmt(v)} {row['over'][k][2]}" for k, v in row["worst_at"].items())
    return f" (worst at {where}; {row['dense_points']} points re-checked)"


_GOAL_STYLE = {"PASS": "green", "WARN": "yellow", "FAIL": "bold red"}


def goal_text(row: dict) -> str:
    """``"WARN (goal >= 3)"`` for a requirement row with a goal, ``""`` without one.

    >>> goal_text({"sense": "at_least", "goal": 3.0, "goal_status": "WARN"})
    'WARN (goal >= 3)'
    """
    if "goal" not in row:
        return ""
    return f"{row['goal_status']} (goal {SENSE_ASCII[row['sense']]} {fmt(row['goal'])})"


def print_requirements(record: dict, reporter: Reporter) -> None:
    """The requirements table; with a ``goal`` column (PASS / WARN / FAIL) when any has a goal."""
    goals = any("goal" in row for row in record["requirements"])
    rows = []
    for row in record["requirements"]:
        met = Text("yes", style="green") if row["met"] else Text("NO", style="bold red")
        cells = (row["name"] + worst_point_text(row), fmt(row["value"]),
                 f"{SENSE_ASCII[row['sense']]} {fmt(row['limit'])}", row["unit"], fmt(row["slack"]), met)
        if goals:
            cells += (Text(goal_text(row), style=_GOAL_STYLE.get(row.get("goal_status"), "")),)
        rows.append(cells)
    columns = ("requirement", "value", "limit", "unit", "slack", "met") + (("goal",) if goals else ())
    reporter.table("Requirements", columns, rows, right=("value", "limit", "slack"))


def print_probabilities(record: dict, reporter: Reporter) -> None:
    """Each requirement's probability of being met under the declared uncertainty, with its
    interval (rows that carry a Monte Carlo ``probability`` check)."""
    rows = []
    for row in record["requirements"]:
        chk = row.get("probability")
        if chk is None:
            continue
        asked = "" if chk["asked"] is None else f">= {chk['asked']:g}"
        lo, hi = chk["interval"]
        rows.append((row["name"], asked, f"{chk['estimate']:.5f}", f"[{lo:.5f}, {hi:.5f}]", str(chk["samples"]),
                     chk["status"] or ""))
    if rows:
        conf = next(r["probability"]["confidence"] for r in record["requirements"] if r.get("probability"))
        reporter.table(f"Probability met under the declared uncertainty (Monte Carlo, {conf:g} Wilson interval)",
                       ("requirement", "asked", "probability", "interval", "draws", "check"), rows,
                       right=("probability",))


def print_record(record: dict, reporter: Reporter, *, title_prefix: str = "") -> None:
    """The whole record: title, design, budgets, requirements and the objective."""
    reporter.out.print(Text.assemble((f"{title_prefix}{record['title']}", "bold"), f" ({record['sensor']})"))
    print_design(record, reporter)
    print_budgets(record, reporter)
    print_requirements(record, reporter)
    print_probabilities(record, reporter)
    reporter.info(f"objective: {record['objective']['text']} = {fmt(record['objective']['value'])}")


def unmet(record: dict) -> list:
    """Names of the requirements the record's design leaves unmet."""
    return [row["name"] for row in record["requirements"] if not row["met"]]


def _with_unit(value: float, unit: str) -> str:
    return fmt(value) + ("" if unit in ("", "1") else f" {unit}")


def unmet_line(row: dict) -> str:
    """One line for an unmet requirement row: its value, its limit and the shortfall (short of
    a lower limit, over an upper one, off an equality), in the requirement's unit, and where an
    interval requirement is worst.

    >>> unmet_line({"name": "beam", "value": 1.1162, "limit": 1.1, "unit": "deg", "sense": "at_most",
    ...             "slack": -0.0162, "met": False})
    "requirement 'beam' not met: 1.1162 deg, limit <= 1.1 deg, over by 0.0162 deg"
    """
    how = {"at_least": "short by", "at_most": "over by", "equals": "off by"}[row["sense"]]
    return (f"requirement {row['name']!r} not met: {_with_unit(row['value'], row['unit'])}, "
            f"limit {SENSE_ASCII[row['sense']]} {_with_unit(row['limit'], row['unit'])}, "
            f"{how} {_with_unit(-row['slack'], row['unit'])}{worst_point_text(row)}")


def print_unmet(record: dict, reporter: Reporter) -> None:
    """A line for each requirement the record's design leaves unmet (:func:`unmet_line`), on
    standard output: a design that misses a requirement is a result, not an error."""
    for row in record["requirements"]:
        if not row["met"]:
            reporter.info(unmet_line(row), wrap=False)
