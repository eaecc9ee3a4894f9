"""The write-up of a trade study (:mod:`diffsense.design.trade`): a CSV of the front, its
figures and a Markdown report of which requirements are active along which stretch.

Figures (matplotlib, Agg, PNG): for two objectives the front with its anchors and knee marked
(axes in log scale for an objective that stays positive and spans more than a decade); for
three or more, parallel coordinates of the objectives normalised to the front's ideal–nadir box,
best at 0 (A. Inselberg, "The plane with parallel coordinates", The Visual Computer 1 (1985) 69), each
point's line coloured by its first objective, plus the 2-D front of the first two objectives.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import List

import numpy as np

from diffsense.design.trade import TradeResult
from diffsense.report.trade_glance import glance_markdown
from diffsense.optimize.continuation import normalized
from diffsense.report import style


def _axis_label(label: str, unit: str) -> str:
    return f"{label} ({unit})" if unit not in ("", "1") else label


def _log_axis(values) -> bool:
    v = np.asarray(values, dtype=float)
    return bool(v.size and np.all(v > 0) and v.max() > 10.0 * v.min())


def front_figure(result: TradeResult, path: Path, i: int = 0, j: int = 1) -> Path:
    """Objective ``j`` against objective ``i`` over the front, each axis named by its
    objective's text (its sense, terms and weights); anchors and knee marked."""
    F = np.array([p["F"] for p in result.points])
    fig, ax = style.new_figure(6.8, 4.8)
    combos = sorted({p["combo_index"] for p in result.points})
    for c in combos:
        mine = np.array([p["combo_index"] == c for p in result.points])
        name = ", ".join(result.model.combinations[c].options.values()) or "front"
        ax.plot(F[mine, i], F[mine, j], "o-", ms=3.5, lw=1.0, label=name)
    anchors = [k for k, p in enumerate(result.points) if p["anchor"] >= 0]
    if anchors:
        ax.plot(F[anchors, i], F[anchors, j], "s", ms=9, mfc="none", mec="k", label="anchor")
    if result.knee is not None:
        ax.plot(F[result.knee, i], F[result.knee, j], "*", ms=14, color="crimson", label="knee")
    for which, k in (("x", i), ("y", j)):
        if _log_axis(F[:, k]):
            style.log_scale(ax, which)
    ax.set_xlabel(_axis_label(result.objectives[i].text, result.units[i]))
    ax.set_ylabel(_axis_label(result.objectives[j].text, result.units[j]))
    style.set_title(ax, f"Pareto front: {result.model.spec.title}")
    ax.grid(True, which="both", alpha=0.3)
    style.legend(ax)
    return style.save(fig, path)


def parallel_figure(result: TradeResult, path: Path) -> Path:
    """Parallel coordinates of every objective, normalised to the front's ideal–nadir box in
    the minimised sense (0 the best value on the front, 1 the worst, a maximised objective
    flipped); each axis end is labelled with its value."""
    F = np.array([p["F"] for p in result.points])
    signs = np.array([o.sign for o in result.objectives])
    f = normalized(F * signs)  # minimised sense: 0 the best value on the front, 1 the worst
    best = np.where(signs > 0, F.min(axis=0), F.max(axis=0))
    worst = np.where(signs > 0, F.max(axis=0), F.min(axis=0))
    fig, ax = style.new_figure(7.4, 4.8)
    colours = style.pyplot().cm.viridis(f[:, 0])
    for row, col in zip(f, colours):
        ax.plot(range(F.shape[1]), row, color=col, lw=1.0, alpha=0.8)
    if result.knee is not None:
        ax.plot(range(F.shape[1]), f[result.knee], color="crimson", lw=2.5, label="knee")
    style.category_ticks(ax.xaxis, range(F.shape[1]),
                         [_axis_label(lab, u) for lab, u in zip(result.labels, result.units)])
    for k in range(F.shape[1]):
        ax.annotate(f"{best[k]:.3g}", (k, 0.0), xytext=(3, -12), textcoords="offset points", fontsize=7)
        ax.annotate(f"{worst[k]:.3g}", (k, 1.0), xytext=(3, 4), textcoords="offset points", fontsize=7)
    ax.set_ylabel("normalised objective (0 best on the front, 1 worst)")
    ax.set_ylim(-0.12, 1.12)
    style.set_title(ax, f"Trade of {F.shape[1]} objectives: {result.model.spec.title}")
    ax.grid(True, axis="x", alpha=0.4)
    style.legend(ax)
    return style.save(fig, path)


def csv_header(result: TradeResult) -> List[str]:
    """The column names of ``front.csv``, each saying what its column holds and none repeated
    (an objective may be a design variable as well): ``objective: <its text> (unit)``, each
    design variable and catalog parameter as ``name (unit)``, each catalog as ``name (catalog
    option)``, then the KKT residual, the objective a point is the anchor of, the knee and the
    active requirements."""
    model = result.model
    spec = model.spec
    first = next(iter(spec.scenes))
    names = [_axis_label(f"objective: {o.text}", u) for o, u in zip(result.objectives, result.units)]
    names += [_axis_label(n, spec.variables[n].unit) for n in model.variable_names]
    names += [_axis_label(n, spec.unit_of(first, n)) for n in model.combo_params]
    names += [f"{c} (catalog option)" for c in model.choice_names]
    names += ["kkt_residual", "anchor_of", "knee", "active_requirements"]
    seen: dict = {}
    unique = []
    for n in names:  # unique by construction; a repeat would still be told apart
        seen[n] = seen.get(n, 0) + 1
        unique.append(n if seen[n] == 1 else f"{n} #{seen[n]}")
    return unique


def write_csv(result: TradeResult, path) -> Path:
    """One row per front point (columns: :func:`csv_header`): objectives, design values,
    catalog options, KKT residual, active requirements. ``path``: a
    :class:`~diffsense.report.files.FileTarget` or a plain path (written atomically either way)."""
    import io

    from diffsense.report.files import FileTarget, write_atomically

    model = result.model
    with io.StringIO(newline="") as fh:
        w = csv.writer(fh)
        w.writerow(csv_header(result))
        for k, p in enumerate(result.points):
            combo = model.combinations[p["combo_index"]]
            values = list(p["x"]) + [model.combo_table[p["combo_index"]][j] for j in range(len(model.combo_params))]
            w.writerow([f"{v:.12g}" for v in p["F"]] + [f"{v:.12g}" for v in values]
                       + [combo.options[c] for c in model.choice_names]
                       + [f"{p['kkt_residual']:.3g}", result.labels[p["anchor"]] if p["anchor"] >= 0 else "",
                          "yes" if k == result.knee else "", "; ".join(p["active"])])
        text = fh.getvalue()
    if isinstance(path, FileTarget):
        return path.write_text(text)
    write_atomically(Path(path), text.encode("utf-8"))
    return Path(path)


def markdown(result: TradeResult, figures: List[Path], out: Path) -> str:
    """The trade report: objectives, counts, anchors and knee, the stretches of the front."""
    lines = [f"# Trade study: {result.model.spec.title}", ""] + glance_markdown(result)
    lines += ["Objectives: " + "; ".join(f"{o.text}" for o in result.objectives), ""]
    d = result.dropped
    lines += [f"{len(result.points)} points on the front ({result.solves} solves, {result.trips} solver trips, "
              f"{result.seconds:.1f} s); dropped: {d.get('unconverged', 0)} unconverged, {d.get('unmet', 0)} "
              f"missing a requirement when re-evaluated, {d.get('dominated', 0)} dominated.", ""]
    lines += ["## Anchors and knee", "", "| point | " + " | ".join(result.labels) + " |",
              "|---|" + "---|" * len(result.labels)]
    for k, p in enumerate(result.points):
        if p["anchor"] >= 0 or k == result.knee:
            what = f"best {result.labels[p['anchor']]}" if p["anchor"] >= 0 else "knee"
            if k == result.knee and p["anchor"] >= 0:
                what += " (knee)"
            lines.append(f"| {what} | " + " | ".join(f"{v:.6g}" for v in p["F"]) + " |")
    lines += ["", "## Active requirements along the front", "",
              "Points sorted by the first objective; a requirement is active where it is met with "
              "zero slack (it holds the front there).", "",
              "| points | from | to | active requirements | variables on a bound |", "|---|---|---|---|---|"]
    for s in result.stretches:
        fr = ", ".join(f"{k} {v:.4g}" for k, v in s["from"].items())
        to = ", ".join(f"{k} {v:.4g}" for k, v in s["to"].items())
        lines.append(f"| {s['first'] + 1}–{s['last'] + 1} | {fr} | {to} | {'; '.join(s['active']) or 'none'} | "
                     f"{'; '.join(s['on_bounds']) or 'none'} |")
    lines += ["", "## Figures", ""] + [f"![{f.stem}]({f.relative_to(out)})" for f in figures]
    return "\n".join(lines) + "\n"


#: the files :func:`write_trade_report` writes (besides ``figures/``)
TRADE_FILES = ("front.csv", "trade.md")


def trade_folder(out, spec_path, force: bool = False):
    """The trade's output folder, checked before any work (as
    :func:`diffsense.report.build.report_folder`)."""
    from diffsense.report.files import OutputFolder

    folder = OutputFolder(out, protect=[spec_path], force=force)
    folder.check(TRADE_FILES, folders=["figures"])
    return folder


def write_trade_report(result: TradeResult, out) -> dict:
    """front.csv, figures/*.png and trade.md in ``out`` (a folder path or the
    :class:`~diffsense.report.files.OutputFolder` of :func:`trade_folder`); returns the paths
    written."""
    from diffsense.report.files import OutputFolder

    folder = out if isinstance(out, OutputFolder) else OutputFolder(out)
    figures = []
    if len(result.points) >= 1:
        figures.append(front_figure(result, folder.file("figures/front.png")))
        if len(result.labels) >= 3:
            figures.append(parallel_figure(result, folder.file("figures/parallel_coordinates.png")))
    csv_path = write_csv(result, folder.file("front.csv"))
    md = folder.write_text("trade.md", markdown(result, figures, folder.path))
    return {"csv": csv_path, "markdown": md, "figures": figures}


__all__ = ["front_figure", "parallel_figure", "csv_header", "write_csv", "markdown", "write_trade_report", "trade_folder",
           "TRADE_FILES"]
