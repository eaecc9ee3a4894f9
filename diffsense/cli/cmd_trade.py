"""``diffsense trade``: the Pareto front of a spec's ``[trade]`` objectives (CSV, figures, a
Markdown report and optionally JSON). Exit codes: 0 a front was found, 2 an invalid spec or no
``[trade]`` section, 3 no design on the front meets every requirement."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from diffsense.cli.cmd_design import DESIGN_FILE, FORCE
from diffsense.cli.output import EXIT_BAD_INPUT, EXIT_UNMET, check_json_target, clip, fmt, refuse, write_json
from diffsense.cli.state import reporter_from


def trade(
    ctx: typer.Context,
    design_file: Path = DESIGN_FILE,
    out: Path = typer.Option(..., "--out", help="Directory for front.csv, trade.md and figures/."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the front as JSON here."),
    points: Optional[int] = typer.Option(None, min=2, help="Points on the front (default: the spec's [trade] "
                                         "points; at most 200)."),
    force: bool = FORCE,
):
    """Trace the Pareto front of the spec's [trade] objectives by epsilon-constraint continuation."""
    from diffsense.design.evaluable import check_evaluable, check_joint_values
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.design.spec.limits import MAX_TRADE_POINTS, check_trade_work, require_variables
    from diffsense.design.trade import check_trade_objectives, trade_design, trade_record, trade_spec
    from diffsense.errors import SpecError
    from diffsense.report.files import OutputError
    from diffsense.report.trade import trade_folder, write_trade_report

    reporter = reporter_from(ctx)
    if points is not None and points > MAX_TRADE_POINTS:
        refuse(reporter, f"--points {points}: at most {MAX_TRADE_POINTS} points on a front")
    check_json_target(json_out, reporter, [design_file], force)
    try:
        folder = trade_folder(out, design_file, force)
    except OutputError as exc:
        refuse(reporter, str(exc))
    try:
        with reporter.step(f"reading {clip(design_file)}"):
            spec = trade_spec(load_spec(design_file))
            require_variables(spec)
            check_joint_values(spec)
            check_trade_work(spec.path, spec, points or spec.trade.points,
                             "--points" if points else "trade.points")
        with reporter.step("building the design model"):
            model = DesignModel(spec)
        with reporter.step("checking the chain and the objectives at the initial design and the box corners"):
            check_trade_objectives(model, *check_evaluable(model))
    except SpecError as exc:
        reporter.error(str(exc))
        raise typer.Exit(code=EXIT_BAD_INPUT)
    with reporter.step(f"tracing the front ({len(model.combinations)} catalog combinations)"):
        result = trade_design(model, points=points)
    record = trade_record(result)
    if result.points:
        rows = [[fmt(v) for v in p["objectives"].values()] + [fmt(p["kkt_residual"]),
                ("anchor " if p["anchor_of"] else "") + ("knee" if p["knee"] else "")] for p in record["front"]]
        reporter.table(f"Pareto front: {spec.title}", result.labels + ["KKT residual", ""], rows,
                       right=tuple(result.labels))
    d = result.dropped
    reporter.info(f"{len(result.points)} points; dropped {d['unconverged']} unconverged, {d['unmet']} unmet, "
                  f"{d['dominated']} dominated; time {result.seconds:.1f} s")
    files = write_trade_report(result, folder)
    for kind in ("csv", "markdown"):
        reporter.info(f"wrote {files[kind]}")
    reporter.info(f"figures: {len(files['figures'])} in {out / 'figures'}")
    write_json(record, json_out, reporter, [design_file], force)
    if not result.points:
        reporter.error("no design meets every requirement: the front is empty")
        raise typer.Exit(code=EXIT_UNMET)
