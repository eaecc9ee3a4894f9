"""Printing a design record (``diffsense evaluate/optimize``): the design, each case's link budget
with its total, and the requirements with their slack."""

from __future__ import annotations

from rich.text import Text

from diffsense.cli.output import Reporter, fmt, fmt_db

_SENSE = {"at_least": ">=", "at_most": "<=", "equals": "="}


def print_design(record: dict, reporter: Reporter) -> None:
    rows = [(name, fmt(d["value"]), d["unit"], d["kind"]) for name, d in record["design"].items()]
    # a one-parameter catalog is already its parameter's row
    rows += [(name, option, "", "catalog option") for name, option in record.get("choices", {}).items()
             if name not in record["design"]]
    reporter.table("Design", ("parameter", "value", "unit", "kind"), rows, right=("value",))


def print_budgets(record: dict, reporter: Reporter) -> None:
    for case, c in record["cases"].items():
        if not c["budget"]:
            continue
        rows = [(row["term"], fmt_db(row["db"])) for row in c["budget"]]
        total = sum(row["db"] for row in c["budget"])
        rows.append((Text("total", style="bold"), Text(fmt_db(total), style="bold")))
        reporter.table(f"Link budget ({case})", ("term", "dB"), rows, right=("dB",))


def print_requirements(record: dict, reporter: Reporter) -> None:
    rows = []
    for row in record["requirements"]:
        met = Text("yes", style="green") if row["met"] else Text("NO", style="bold red")
        rows.append((row["name"], fmt(row["value"]), f"{_SENSE[row['sense']]} {fmt(row['limit'])}", row["unit"],
                     fmt(row["slack"]), met))
    reporter.table("Requirements", ("requirement", "value", "limit", "unit", "slack", "met"), rows,
                   right=("value", "limit", "slack"))


def print_record(record: dict, reporter: Reporter, *, title_prefix: str = "") -> None:
    """The whole record: title, design, budgets, requirements and the objective."""
    reporter.out.print(Text.assemble((f"{title_prefix}{record['title']}", "bold"), f" ({record['sensor']})"))
    print_design(record, reporter)
    print_budgets(record, reporter)
    print_requirements(record, reporter)
    reporter.info(f"objective: {record['objective']['text']} = {fmt(record['objective']['value'])}")


def unmet(record: dict) -> list:
    """Names of the requirements the record's design leaves unmet."""
    return [row["name"] for row in record["requirements"] if not row["met"]]
