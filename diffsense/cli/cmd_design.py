"""``diffsense evaluate``, ``optimize`` and ``report``: a requirement spec checked, optimised or
written up. Exit codes: 0 every requirement met, 2 an invalid spec, 3 a requirement left unmet."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from diffsense.cli.output import EXIT_BAD_INPUT, EXIT_UNMET, Reporter, check_json_target, clip, refuse, write_json
from diffsense.cli.records import print_record, print_unmet, unmet
from diffsense.cli.state import reporter_from

DESIGN_FILE = typer.Argument(..., help="Requirement spec (TOML), e.g. designs/ore_pass.toml.", show_default=False)
FORCE = typer.Option(False, "--force", help="Replace output files that diffsense did not write (never the spec).")


def load_model(design_file: Path, reporter: Reporter, *, starts: Optional[int] = None, tangents: bool = False):
    """Read, validate and model a spec; on an invalid spec print one error line and exit 2.

    Besides each key's own checks, the chain is evaluated once at the initial design and the
    corners of the box (:func:`diffsense.design.evaluable.check_evaluable`), so that values the
    chain rejects together, or cannot evaluate to a finite answer, are reported here. With
    ``starts`` the optimiser's programs begin compiling first (in background threads, while the
    others are traced; the solver's program, whose compilation is the longest, before the small
    check program); ``tangents``: the program of derivatives too (a report)."""
    from diffsense.design.evaluable import check_evaluable, check_joint_values
    from diffsense.design.model import DesignModel
    from diffsense.design.optimizer import prepare
    from diffsense.design.spec import load_spec
    from diffsense.design.spec.limits import DEFAULT_STARTS, check_work, require_variables
    from diffsense.errors import SpecError

    try:
        with reporter.step(f"reading {clip(design_file)}"):
            spec = load_spec(design_file)
            check_joint_values(spec)  # values the chain rejects together on plain numbers: before compiling
            if starts:
                require_variables(spec)
                if starts != DEFAULT_STARTS:
                    check_work(spec.path, spec, starts, starts_key="--starts")
            model = DesignModel(spec)
        with reporter.step("compiling the design programs" if starts else "compiling the evaluation programs"):
            # the solver's program first, whose compilation is the longest: it compiles on one core
            # while this thread traces the small check program, which the other core compiles
            if starts:
                prepare(model, n_starts=starts)
            # a report's program of derivatives, the longest to compile after the solver's, before
            # the interval programs: it compiles while they are traced and the solve runs
            model.programs.start("check", *(("evaluation",) if tangents else ()), "search", "dense")
        with reporter.step("checking the chain at the initial design and the box corners"):
            check_evaluable(model)
        return model
    except SpecError as exc:
        reporter.error(str(exc))
        raise typer.Exit(code=EXIT_BAD_INPUT)


def check_probabilities(model, record: dict, x, combo_index: int, reporter: Reporter) -> None:
    """Add each requirement's probability of being met under the spec's ``[uncertain]`` inputs,
    from an independent Monte Carlo sample (:mod:`diffsense.design.monte_carlo`), to ``record``."""
    if model.spec.uncertain is None:
        return
    from diffsense.design.monte_carlo import attach_probabilities

    with reporter.step(f"checking probabilities with {model.spec.uncertain.check_samples} Monte Carlo draws"):
        attach_probabilities(model, record, x, combo_index)


def _fail_if_unmet(names, reporter: Reporter) -> None:
    if names:
        reporter.error("these requirements are not met: " + "; ".join(names))
        raise typer.Exit(code=EXIT_UNMET)


def evaluate(
    ctx: typer.Context,
    design_file: Path = DESIGN_FILE,
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the evaluation as JSON here."),
    force: bool = FORCE,
):
    """Evaluate a spec at its initial design (each variable's 'initial', each catalog's first
    option); exit 3 when a requirement is not met."""
    from diffsense.design.record import design_record

    reporter = reporter_from(ctx)
    check_json_target(json_out, reporter, [design_file], force)
    model = load_model(design_file, reporter)
    with reporter.step(f"evaluating the initial design ({len(model.requirements)} requirements)"):
        record = design_record(model, model.initial, 0, every_output=json_out is not None)
    check_probabilities(model, record, model.initial, 0, reporter)
    record["converged"] = None
    print_record(record, reporter, title_prefix="Evaluation: ")
    write_json(record, json_out, reporter, [design_file], force)
    _fail_if_unmet(unmet(record), reporter)


def print_findings(findings: dict, reporter: Reporter) -> None:
    """What sets the design (:func:`diffsense.design.activity.design_findings`): one line, then
    each warning."""
    parts = ["active: " + ("; ".join(findings["active"]) or "none")]
    if findings["bounds"]:
        parts.append("on a bound: " + ", ".join(f"{n} ({side})" for n, side in findings["bounds"]))
    if findings["choice"]:
        parts.append("catalog: " + ", ".join(f"{k} = {v}" for k, v in findings["choice"].items()))
    reporter.info("what sets the design: " + "; ".join(parts))
    for w in findings["warnings"]:
        reporter.warn("warning", w)


def print_exact_check(check: dict, reporter: Reporter) -> bool:
    """The exact re-evaluation of a fast-fidelity answer (:func:`diffsense.design.exact_check.exact_recheck`):
    the options switched, then each requirement fast → exact; True when the exact models meet
    every requirement."""
    reporter.info("fidelity fast (" + ", ".join(f"{k} = {v}" for k, v in check["switched"].items())
                  + "): the answer re-evaluated with the exact models")
    for r in check["requirements"]:
        reporter.info(f"  {r['name']}: {r['fast']:.6g} -> {r['exact']:.6g} {r['unit']} "
                      f"(difference {r['difference']:+.3g}){'' if r['met'] else '; NOT MET'}")
    return check["met"]


def optimize(
    ctx: typer.Context,
    design_file: Path = DESIGN_FILE,
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the optimised design as JSON here."),
    starts: int = typer.Option(8, min=1, help="Starts per catalog combination (the spec's initial design + Latin hypercube)."),
    seed: int = typer.Option(0, help="Seed of the multi-start design."),
    force: bool = FORCE,
):
    """Optimise a spec: the best design meeting every requirement (exit 3 when none can)."""
    from diffsense.design.exact_check import exact_recheck
    from diffsense.design.goals import optimize_with_goals, plan_lines, plan_record, solved_findings
    from diffsense.design.record import design_record

    reporter = reporter_from(ctx)
    check_json_target(json_out, reporter, [design_file], force)
    t0 = time.perf_counter()
    model = load_model(design_file, reporter, starts=starts)
    lanes = len(model.combinations) * starts
    goals = ", then buying the requirements' goals, cheapest first" if model.spec.objective.reach_goals else ""
    with reporter.step(f"compiling and solving {lanes} lanes "
                       f"({len(model.combinations)} catalog combinations x {starts} starts){goals}"):
        result, plan = optimize_with_goals(model, n_starts=starts, seed=seed)
    with reporter.step("re-evaluating the optimum"):
        record = design_record(model, result.x, result.combo_index, every_output=json_out is not None)
    check_probabilities(model, record, result.x, result.combo_index, reporter)
    record["converged"] = result.converged
    record["feasible"] = result.feasible
    record["multistart"] = {"starts": result.starts, "converged": result.starts_converged,
                            "reached_best": result.starts_at_best}
    record["candidates"] = result.candidates
    record["canonical"] = result.canonical
    if plan is not None:
        record["goals"] = plan_record(plan)
    for row, lam in zip(record["requirements"], result.multipliers):
        row["multiplier"] = float(lam)
    record["solve_time_s"] = time.perf_counter() - t0
    print_record(record, reporter, title_prefix="Optimum: " if result.feasible else "Best compromise: ")
    reporter.info(f"converged: {result.converged}; starts reaching the best: {result.starts_at_best}/{result.starts}; "
                  f"time {record['solve_time_s']:.1f} s")
    if result.canonical:
        c = result.canonical
        reporter.info(f"{c['rule']}: {c['flat_directions']} flat direction(s); smallest such slack "
                      f"{c['smallest_slack_before']:.4g} -> {c['smallest_slack_after']:.4g} (scaled)")
    if plan is not None:
        for line in plan_lines(record["goals"], model.spec.objective.text):
            reporter.info(line)
    findings = solved_findings(model, plan, result.x, result.combo_index, record["requirements"], result.multipliers)
    record["findings"] = findings
    print_findings(findings, reporter)
    exact_ok = True
    if model.spec.fidelity == "fast" and not model.spec.fidelity_switched:
        reporter.info("fidelity fast: no faster model choice of this spec is within the atlas's bound "
                      "(docs/speed_accuracy.md); the exact models were used")
    if model.spec.fidelity_switched:
        with reporter.step("re-evaluating with the exact models"):
            check = exact_recheck(model, result.x, result.combo_index, record["requirements"])
        record["exact_check"] = check
        exact_ok = print_exact_check(check, reporter)
    write_json(record, json_out, reporter, [design_file], force)
    if result.feasible and not exact_ok:
        reporter.error("the fast models' answer misses a requirement under the exact models: optimise with "
                       "fidelity = \"exact\"")
        raise typer.Exit(code=EXIT_UNMET)
    if not result.feasible:
        reporter.error("infeasible: these requirements cannot be met together within the bounds: "
                       + "; ".join(result.unmet))
        raise typer.Exit(code=EXIT_UNMET)


#: worker processes that draw a report's figures while the main process computes (two cores
#: draw the dozen figures of a design in about half the time: README, Compiled programs and job speed)
FIGURE_WORKERS = 2


def report(
    ctx: typer.Context,
    design_file: Path = DESIGN_FILE,
    out: Path = typer.Option(..., "--out", help="Directory for report.md, report.html, report.json and figures/."),
    no_optimize: bool = typer.Option(False, "--no-optimize", help="Report the spec's initial design instead of the optimum."),
    starts: int = typer.Option(8, min=1, help="Starts per catalog combination when optimising."),
    seed: int = typer.Option(0, help="Seed of the multi-start design."),
    force: bool = FORCE,
):
    """Write a design report: budgets, detection plots, elasticities and post-optimal
    sensitivities (exit 2 on an invalid spec, 3 when the design leaves a requirement unmet: each
    such requirement is printed with its value, limit and shortfall). Files in --out that
    diffsense did not write are not replaced without --force."""
    from diffsense.errors import SpecError
    from diffsense.report import build_report
    from diffsense.report.build import report_folder
    from diffsense.report.files import OutputError

    reporter = reporter_from(ctx)
    try:
        folder = report_folder(out, design_file, force)
    except OutputError as exc:
        refuse(reporter, str(exc))
    # exit 2 here, with the CLI's checks, on an invalid spec; the report reuses the model's programs
    model = load_model(design_file, reporter, starts=None if no_optimize else starts, tangents=True)
    try:
        with reporter.step(f"{'optimising and ' if not no_optimize else ''}writing the report of {clip(design_file)}"):
            record = build_report(design_file, folder, optimize=not no_optimize, n_starts=starts, seed=seed, model=model,
                                  figure_workers=FIGURE_WORKERS)
    except (SpecError, OutputError) as exc:
        reporter.error(str(exc))
        raise typer.Exit(code=EXIT_BAD_INPUT)
    for kind in ("md", "html", "json"):
        reporter.info(f"wrote {record['files'][kind]}")
    reporter.info(f"figures: {len(record['figures'])} in {out / 'figures'}")
    for item in record["unavailable"]:
        reporter.warn("not available", f"{item['section']}: {item['reason']}")
    for item in record["skipped_figures"]:
        reporter.warn("figure skipped", f"{item['figure']}: {item['reason']}")
    if record.get("findings"):
        print_findings(record["findings"], reporter)
    if not record["feasible"]:  # a result, not an error: each unmet requirement on stdout, exit 3
        if not no_optimize:
            reporter.info("infeasible: no design within the bounds meets every requirement; "
                          "the report shows the best compromise", wrap=False)
        print_unmet(record, reporter)
        raise typer.Exit(code=EXIT_UNMET)
