"""Assemble a design report: evaluate, differentiate, sweep, draw and write.

:func:`build_report` runs each section independently: a section that cannot be computed
(a missing output, a derivative JAX does not implement, a degenerate optimum) is listed under
``unavailable`` with its reason, and the rest of the report is still written.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import List, Optional

import numpy as np

from diffsense.design.goals import solved_findings
from diffsense.design.model import DesignModel
from diffsense.design.monte_carlo import attach_probabilities
from diffsense.design.record import design_table
from diffsense.design.spec import load_spec
from diffsense.scene import chain_for
from diffsense.report import figures
from diffsense.report.interval_figures import interval_caption, interval_margin
from diffsense.report.batch import BatchEvaluator, row
from diffsense.design.runner import objective_scale
from diffsense.report.content import report_blocks
from diffsense.report.drawing import Drawer
from diffsense.report.inputs import design_inputs
from diffsense.report.jacobian import jacobian_section, miss_measured
from diffsense.report.postoptimal import post_optimal_section
from diffsense.report.files import OutputFolder, safe_name
from diffsense.report.render import REPORT_FILES, si_text, unit_text, write_report
from diffsense.report.sweeps import (
    blake_coverage,
    coverage_applies,
    coverage_skip_reason,
    budget_rows,
    input_index,
    main_margin,
    range_sweep,
    roc_sweep,
)

FIGURE_DIR = "figures"


def _reason(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else ''}".strip()


def _span_text(sweep: dict) -> str:
    """"every range from A to B m" when the sweep's main margin requirement holds over an
    interval of ranges (``required_range_m``), else ""."""
    span = sweep.get("required_range_m")
    return "" if span is None else f"every range from {span[0]:g} to {span[1]:g} m"


def _objective_unit(model: DesignModel) -> str:
    terms = model.spec.objective.terms
    if len(terms) == 1 and terms[0][0] != "cost":
        name = terms[0][0]
        case, base = name.split(".", 1) if "." in name else (next(iter(model.spec.scenes)), name)
        return model.spec.unit_of(case, base)
    return ""  # a weighted sum of terms in different units


def report_folder(out_dir, spec_path, force: bool = False) -> OutputFolder:
    """The report's output folder (:class:`~diffsense.report.files.OutputFolder`), checked before
    any work: the spec ``spec_path`` is never written over, and without ``force`` no report file
    or figure is written over a file diffsense did not write there (raises
    :class:`~diffsense.report.files.OutputError`)."""
    folder = OutputFolder(out_dir, protect=[spec_path], force=force)
    folder.check(REPORT_FILES, folders=[FIGURE_DIR])
    return folder


def build_report(spec_path, out_dir, *, optimize: bool = True, n_starts: int = 8, seed: int = 0,
                 optimum=None, model: Optional[DesignModel] = None, force: bool = False,
                 figure_workers: int = 0) -> dict:
    """Write ``report.md``, ``report.html``, ``report.json`` and the figures (PNG, in
    ``out_dir/figures``) for the spec ``spec_path``; return the report dict (as in the JSON).

    ``out_dir``: a folder path, or the :class:`~diffsense.report.files.OutputFolder` of
    :func:`report_folder`; files diffsense did not write there are not replaced unless ``force``
    (:class:`~diffsense.report.files.OutputError`, raised before any work).

    ``optimize``: report the optimum of :func:`~diffsense.design.optimizer.optimize_design`
    (``n_starts``, ``seed``); ``False`` reports the spec's initial design (each variable's
    ``initial``, each catalog's first option), like ``diffsense evaluate``.
    ``optimum``: a :class:`~diffsense.design.optimizer.DesignOptimum` already computed for this
    spec; it is reported instead of optimising again (``optimize`` is then ignored).
    ``model``: the spec's :class:`DesignModel` when the caller has built it (its compiled
    programs are reused).
    ``figure_workers``: draw the figures in that many worker processes while this one computes
    (:mod:`diffsense.report.drawing`; the command line uses two); 0 draws them here.
    Raises :class:`~diffsense.errors.SpecError` for an invalid spec; every other failure only
    removes the section it concerns (listed under ``unavailable``).
    """
    t_start = time.perf_counter()
    spec_path = Path(spec_path)
    folder = out_dir if isinstance(out_dir, OutputFolder) else report_folder(out_dir, spec_path, force)
    if model is None:
        model = DesignModel(load_spec(spec_path))
    spec = model.spec
    model.programs.start("evaluation", "check", "search", "dense")
    # the figures' worker processes start now: their imports overlap the optimisation
    drawer = Drawer(folder, figure_workers)
    try:
        unavailable: List[dict] = []
        report: dict = {"name": spec.name, "title": spec.title, "sensor": spec.sensor,
                        "coverage_charts": any(chain_for(sc).draws_coverage for sc in spec.scenes.values()),
                        "description": spec.description.strip(), "spec_file": str(spec_path),
                        "objective_text": spec.objective.text}

        multipliers = None
        plan = None  # the goals bought (reach_goals), whose limits the optimum was solved for
        optimize = optimize or optimum is not None
        if optimize:
            t0 = time.perf_counter()
            if optimum is None:
                from diffsense.design.goals import optimize_with_goals, plan_record

                result, plan = optimize_with_goals(model, n_starts=n_starts, seed=seed)
                if plan is not None:
                    report["goals"] = plan_record(plan)
            else:
                result = optimum
            x, combo_index = np.asarray(result.x, dtype=float), int(result.combo_index)
            multipliers = np.asarray(result.multipliers, dtype=float)
            report.update(mode="optimum", converged=bool(result.converged), feasible=bool(result.feasible),
                          unmet=list(result.unmet), candidates=result.candidates, canonical=result.canonical,
                          multistart={"starts": result.starts, "converged": result.starts_converged,
                                      "reached_best": result.starts_at_best},
                          optimize_time_s=time.perf_counter() - t0)
        else:
            x, combo_index = np.asarray(model.initial, dtype=float), 0
            report.update(mode="initial_design", converged=None, feasible=None)

        inputs = design_inputs(model, x, combo_index)
        batch = BatchEvaluator(model, x, combo_index)
        v0 = np.array([i.value for i in inputs])
        values, _ = batch(v0[None, :])
        evaluations, req_values, objective = row(values, 0)
        req_values = np.asarray(req_values, dtype=float)
        report["design"] = design_table(model, x, combo_index)
        report["choices"] = dict(model.combinations[combo_index].options)
        checks = model.programs.dense_checks(batch.values0, batch.inputs, req_values)
        report["requirements"] = model.requirement_rows(req_values, checks=checks)
        try:
            attach_probabilities(model, report, x, combo_index)
        except Exception as exc:  # noqa: BLE001 - a failed section must not stop the report
            unavailable.append({"section": "requirements under uncertainty (Monte Carlo check)", "reason": _reason(exc)})
        if not optimize:
            report["feasible"] = all(r["met"] for r in report["requirements"])
        report["objective"] = {"text": spec.objective.text, "value": float(objective), "unit": _objective_unit(model)}
        report["cases"] = {}
        for case, ev in evaluations.items():
            outs = spec.outputs[case]
            rows = budget_rows(ev)
            report["cases"][case] = {
                "parts": sorted(spec.scenes[case].parts),
                "options": dict(spec.scenes[case].options),
                "budget": rows,
                "budget_total_db": rows[-1]["running_total_db"] if rows else None,
                "outputs": {k: {"value": np.asarray(v), "unit": outs[k].unit if k in outs else ""} for k, v in ev.values.items()},
            }

        # --- Jacobian and elasticities -------------------------------------------------------
        out_meta = [{"name": r.name, "case": r.case, "output": r.output, "unit": r.unit} for r in model.requirements]
        out_meta.append({"name": "objective", "case": None, "output": spec.objective.text, "unit": report["objective"]["unit"]})
        jac = None
        try:
            jac = jacobian_section(batch, inputs, out_meta)
            report["jacobian"] = {
                "inputs": [{"name": i.name, "param": i.param, "cases": list(i.cases), "kind": i.kind, "unit": i.unit,
                            "value": i.value} for i in inputs],
                "outputs": [dict(o, value=float(v)) for o, v in zip(out_meta, jac["values"])],
                "autodiff": jac["autodiff"],
                "autodiff_error": jac["autodiff_error"],
                "derivative": jac["derivative"],
                "elasticity": jac["elasticity"],
                "fd_check": _fd_json(jac["fd_check"], inputs, out_meta),
            }
            if not jac["autodiff"]:
                unavailable.append({"section": "automatic derivatives", "reason": jac["autodiff_error"]})
        except Exception as exc:  # noqa: BLE001 - a failed section must not stop the report
            unavailable.append({"section": "Jacobian and elasticities", "reason": _reason(exc)})

        # --- multipliers and post-optimal sensitivities --------------------------------------
        if optimize:
            report["multipliers"] = [{"requirement": r.name, "multiplier": float(m)} for r, m in zip(model.requirements, multipliers)]
            try:
                if jac is None or not jac["autodiff"]:
                    raise RuntimeError("needs the automatic derivatives of the Jacobian section")
                post = post_optimal_section(model if plan is None else plan.model, inputs, batch, x, combo_index, jac["derivative"], req_values,
                                            multipliers, objective_scale(model))
                report["post_optimal"] = _post_json(post, model, report)
                if post.get("reason"):
                    unavailable.append({"section": "post-optimal sensitivities d(design)/d(limit)", "reason": post["reason"]})
            except Exception as exc:  # noqa: BLE001
                report["post_optimal"] = {"available": False, "reason": _reason(exc)}
                unavailable.append({"section": "post-optimal sensitivities", "reason": _reason(exc)})
        else:
            reason = "the report describes the spec's initial design, not an optimum (build it with optimisation on)"
            report["post_optimal"] = {"available": False, "reason": reason}
            unavailable.append({"section": "multipliers and post-optimal sensitivities", "reason": reason})

        # --- what sets the design --------------------------------------------------------------
        try:
            report["findings"] = solved_findings(model, plan, x, combo_index, report["requirements"], multipliers)
        except Exception as exc:  # noqa: BLE001
            unavailable.append({"section": "what sets the design", "reason": _reason(exc)})

        # --- figures -------------------------------------------------------------------------
        figs, skipped = _figures(drawer, model, inputs, batch, report, jac)
        report["figures"] = figs
        report["skipped_figures"] = skipped
        report["unavailable"] = unavailable
        report["report_time_s"] = time.perf_counter() - t_start
        blocks = report_blocks(report)
        paths = write_report(folder, report, blocks)
        report["files"] = {k: str(p) for k, p in paths.items()}
        return report
    finally:
        drawer.close()


def _fd_json(check: dict, inputs, out_meta) -> dict:
    def pairs(key):
        return [{"output": out_meta[i]["name"], "input": inputs[j].name} for i, j in check.get(key, [])]

    return {
        "max_rel_diff": check.get("max_rel_diff"),
        "n_compared": check.get("n_compared"),
        "n_below_resolution": check.get("n_below_resolution"),
        "not_smooth": pairs("not_smooth"),
        "one_sided": pairs("one_sided"),
        "not_finite": pairs("not_finite"),
        "fd_derivative": check.get("fd"),
        "rel_diff": check.get("rel_diff"),
        "status": check.get("status"),
        "step": check.get("step"),
        "resolution": check.get("resolution"),
        "reason": check.get("reason"),
    }


def _per(numerator: str, denominator: str) -> str:
    """'W per dB'; a dimensionless numerator reads 'per dB', a dimensionless denominator 'per unit'."""
    return f"{unit_text(numerator)} per {unit_text(denominator) or 'unit'}".strip()


def _post_json(post: dict, model: DesignModel, report: dict) -> dict:
    names = model.variable_names
    dx = post.get("dx_dlimit")
    table = None
    if dx is not None:
        table = {}
        for a, r in enumerate(model.requirements):
            table[r.name] = {n: {"value": dx[i, a], "unit": _per(model.spec.variables[n].unit, r.unit)}
                             for i, n in enumerate(names)}
    obj_unit = report["objective"]["unit"]
    shadow = []
    for a, r in enumerate(model.requirements):
        shadow.append({"requirement": r.name, "active": post["active"][a],
                       "d_objective_d_limit": post["shadow_price_kkt"][a] if post["active"][a] else 0.0,
                       "d_objective_d_limit_from_optimizer_multiplier": post["shadow_price_optimizer"][a],
                       "unit": _per(obj_unit or "objective units", r.unit)})
    return {
        "available": dx is not None and not post.get("reason"),
        "reason": post.get("reason"),
        "method": post.get("method"),
        "hessian": post.get("hessian"),
        "hessian_note": post.get("hessian_note"),
        "hessian_fd_rel_diff": post.get("hessian_fd_rel_diff"),
        "variable_status": dict(zip(names, post["variable_status"])),
        "active_requirements": [r.name for r, a in zip(model.requirements, post["active"]) if a],
        "weakly_active": [model.requirements[a].name for a in post.get("weakly_active", [])],
        "stationarity_rel_residual": post.get("stationarity_rel_residual"),
        "dx_dlimit": table,
        "shadow_prices": shadow,
    }


def _figures(drawer: Drawer, model: DesignModel, inputs, batch, report: dict, jac: Optional[dict]):
    """The report's figures: each one's numbers computed here, its drawing handed to ``drawer``
    (here or in a worker process); returns (figures written, figures skipped with the reason)."""
    skipped: List[dict] = []
    pending: list = []
    spec = model.spec

    def attempt(name: str, title: str, caption: str, request, section: str):
        """``request()`` -> (figure function, its arguments after the target, its keywords)."""
        try:
            fn, args, kwargs = request()
            # names carry case names from the spec: made safe, never a path of their own
            drawing = drawer.draw(fn, f"{FIGURE_DIR}/{safe_name(name)}.png", *args, **kwargs)
            pending.append((drawing, {"title": title, "caption": caption, "section": section}))
        except Exception as exc:  # noqa: BLE001 - a figure that cannot be drawn is listed, not fatal
            skipped.append({"figure": title, "reason": _reason(exc)})

    for case, data in report["cases"].items():
        tag = "" if len(report["cases"]) == 1 else f" ({case})"
        outs = data["outputs"]
        m = main_margin(model, case)
        needed = None
        label = "SNR needed"
        if m is not None and "snr_db" in outs:
            req = model.requirements[m]
            needed = float(outs["snr_db"]["value"]) - float(outs[req.output]["value"]) + req.limit
            label = f"SNR needed by '{req.name}'"
        if data["budget"]:
            attempt(f"budget_{case}", f"Link budget{tag}",
                    f"Link budget{tag}: each term (dB) as a bar from the running total before it to the one after it; "
                    "the last bar is the SNR, the sum of the terms.",
                    lambda d=data, nd=needed, lb=label: (figures.waterfall, (d["budget"],), dict(
                        title=f"{spec.title}: link budget{tag}", required_db=nd, required_label=lb)),
                    f"budget:{case}")
        else:
            skipped.append({"figure": f"Link budget{tag}", "reason": "the chain produces no budget"})
        p_idx = input_index(inputs, "pd", case)
        pfa_idx = input_index(inputs, "pfa", case)
        req_pd = inputs[p_idx].value if p_idx is not None else None
        pfa = inputs[pfa_idx].value if pfa_idx is not None else None
        try:
            sweep = range_sweep(batch, model, inputs, case)
        except Exception as exc:  # noqa: BLE001
            sweep = None
            for t in ("SNR versus range", "Pd versus range"):
                skipped.append({"figure": f"{t}{tag}", "reason": _reason(exc)})
        if sweep is not None:
            where = _span_text(sweep)
            if "snr_db" in sweep["outputs"]:
                attempt(f"snr_vs_range_{case}", f"SNR versus range{tag}",
                        f"SNR{tag} against range with every other input at its design value; "
                        + (f"shaded: the ranges the main margin requirement must hold at ({where})"
                           if where else "dotted: the range the requirements are stated at")
                        + "; the marker shows where the main margin requirement is just met.",
                        lambda: (figures.snr_vs_range, (sweep,), dict(title=f"{spec.title}: SNR versus range{tag}")),
                        f"range:{case}")
            else:
                skipped.append({"figure": f"SNR versus range{tag}", "reason": "the chain has no snr_db output"})
            if "pd" in sweep["outputs"]:
                attempt(f"pd_vs_range_{case}", f"Pd versus range{tag}",
                        f"Probability of detection{tag} against range: the chain's pd output (its detector and "
                        "target statistics); where the main margin requirement states its own condition (a faded "
                        "target), solid in that condition and dashed at the mean target strength; the marker shows "
                        "where that requirement is just met, the same range as in the SNR figure"
                        + (f"; shaded: the ranges it must hold at ({where})." if where else "."),
                        lambda: (figures.pd_vs_range, (sweep,), dict(required_pd=req_pd, pfa=pfa,
                                                                     title=f"{spec.title}: Pd versus range{tag}")),
                        f"range:{case}")
            else:
                skipped.append({"figure": f"Pd versus range{tag}", "reason": "the chain has no pd output for this scene"})
        attempt(f"roc_{case}", f"ROC{tag}",
                f"Receiver operating characteristic{tag}: the chain's Pd as Pfa varies over the chain's domain of "
                "pfa, at the design (its range and SNR) and at the longer ranges where the design's Pd falls to "
                "0.9, 0.5 and 0.1, at the mean target strength; the star is the required operating point.",
                lambda: (figures.roc, (roc_sweep(batch, inputs, case),), dict(required_pd=req_pd,
                                                                             title=f"{spec.title}: ROC{tag}")),
                f"roc:{case}")
        if coverage_applies(spec.scenes[case]):
            attempt(f"coverage_{case}", f"Coverage chart (Blake){tag}",
                    f"Range-height coverage{tag} over the 4/3 earth. Assumptions: the main margin requirement "
                    "defines detection; Gaussian elevation beam of the chain's elevation beamwidth, boresight half a "
                    "beamwidth above the horizon, two-way pattern loss added to the chain's margin at each range "
                    "(the margin as the case computes it, including any clutter or multipath term at the case's own "
                    "target height: lobing with elevation angle is not modelled); antenna height 0 m unless the "
                    "scene has antenna_height_m.",
                    lambda: (figures.blake_chart, (blake_coverage(batch, model, inputs, case),),
                             dict(title=f"{spec.title}: coverage over the 4/3 earth{tag}")),
                    f"coverage:{case}")
        else:
            skipped.append({"figure": f"Coverage chart (Blake){tag}", "reason": coverage_skip_reason(spec.scenes[case])})
    for j, row in enumerate(report["requirements"]):
        if row.get("curve"):
            attempt(f"interval_{j}", f"'{row['name']}' over its interval",
                    interval_caption(row), lambda row=row: (interval_margin, (row,), dict(title=f"{spec.title}: {row['name']}")),
                    f"interval:{j}")
    if jac is not None:
        labels = [f"{i.name} = {si_text(i.value, i.unit)}" + (" (as 1 − pd, dB)" if miss_measured(i.param, i.value) else "")
                  for i in inputs]
        status = jac["fd_check"].get("status")
        for a, r in enumerate(model.requirements):
            marked = [lab + (" (kink)" if status is not None and status[a, j] == "not_smooth" else "")
                      for j, lab in enumerate(labels)]
            attempt(f"tornado_{a}", f"Elasticities of '{r.name}'",
                    f"Elasticity of {r.case}.{r.output} with respect to each input (dB per dB, or % per % for linear "
                    "quantities; a probability of detection as its miss probability 1 − Pd in dB), largest influence "
                    "at the top; green raises the output, red lowers it. "
                    "'(kink)': the output is not smooth in that input at the design; the bar is the "
                    "automatic derivative, a one-sided slope.",
                    lambda a=a, r=r, marked=marked: (figures.tornado, (marked, jac["elasticity"][a]), dict(
                        title=f"Elasticities of {r.output} ('{r.name}')",
                        xlabel="Elasticity (dB per dB; % per % for linear quantities)")),
                    f"tornado:{a}")
    figs: List[dict] = []
    for drawing, entry in pending:
        try:
            path = drawing.result()
            figs.append({"file": f"{FIGURE_DIR}/{path.name}", **entry})
        except Exception as exc:  # noqa: BLE001
            skipped.append({"figure": entry["title"], "reason": _reason(exc)})
    return figs, skipped


__all__ = ["build_report", "report_folder", "FIGURE_DIR"]
