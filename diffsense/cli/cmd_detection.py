"""``diffsense detection``: exact required single-pulse SNR tables for Swerling 0-4 and plots."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from diffsense.cli.output import EXIT_BAD_INPUT, clip, refuse
from diffsense.cli.state import reporter_from


def _parse_floats(text: str, name: str) -> List[float]:
    try:
        values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise typer.BadParameter(f"must be a comma-separated list of numbers; got {clip(text)!r}", param_hint=name)
    if not values:
        raise typer.BadParameter("needs at least one number", param_hint=name)
    return values


def detection(
    ctx: typer.Context,
    pfa: float = typer.Option(1e-6, help="False-alarm probability (1e-300 ... 0.5)."),
    pulses: str = typer.Option("1,10,100", help="Comma-separated pulse counts N (noncoherent integration)."),
    pd_values: str = typer.Option("0.5,0.9,0.95,0.99", "--pd", help="Comma-separated detection probabilities."),
    out: Optional[Path] = typer.Option(None, help="Directory for Pd-versus-SNR and ROC plots (PNG)."),
    force: bool = typer.Option(False, "--force", help="Replace plots in --out that diffsense did not write."),
):
    """Print the exact required single-pulse SNR (dB) for Swerling 0-4 and write detection plots."""
    import numpy as np

    from diffsense import detection as det
    from diffsense.errors import DomainError

    from diffsense.report.files import OutputError, OutputFolder

    reporter = reporter_from(ctx)
    ns = _parse_floats(pulses, "--pulses")
    pds = _parse_floats(pd_values, "--pd")
    names = [f"pd_vs_snr_n{n:g}.png" for n in ns] + ["roc_swerling0_n1.png"]
    folder = None
    if out is not None:
        try:
            folder = OutputFolder(out, force=force)
            folder.check(names)
        except OutputError as exc:
            refuse(reporter, str(exc))
    grid_n, grid_pd = (a.ravel() for a in np.meshgrid(np.asarray(ns), np.asarray(pds), indexing="ij"))
    try:
        with reporter.step("computing the exact detectability"):
            columns = [np.asarray(det.required_snr_db(grid_pd, pfa, grid_n, sw)) for sw in range(5)]
    except DomainError as exc:
        reporter.error(str(exc))
        raise typer.Exit(code=EXIT_BAD_INPUT)
    rows = [(f"{grid_n[i]:g}", f"{grid_pd[i]:g}", *(f"{c[i]:.3f}" for c in columns)) for i in range(grid_n.size)]
    reporter.table(f"Required single-pulse SNR (dB), square-law detector, Pfa = {pfa:g}",
                   ("N", "Pd") + tuple(f"Swerling {sw}" for sw in range(5)), rows,
                   right=("N", "Pd") + tuple(f"Swerling {sw}" for sw in range(5)))
    if folder is None:
        return
    from diffsense.detection.plots import pd_vs_snr_figure, roc_figure

    figures = [pd_vs_snr_figure(pfa=pfa, n=n) for n in ns] + [roc_figure(n=1)]
    for name, fig in zip(names, figures):
        reporter.info(f"wrote {folder.save_figure(name, fig)}")
