"""``diffsense detection``: exact required single-pulse SNR tables for Swerling 0-4 and plots."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from diffsense.cli.output import EXIT_BAD_INPUT, clip
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
):
    """Print the exact required single-pulse SNR (dB) for Swerling 0-4 and write detection plots."""
    import numpy as np

    from diffsense import detection as det
    from diffsense.errors import DomainError

    reporter = reporter_from(ctx)
    ns = _parse_floats(pulses, "--pulses")
    pds = _parse_floats(pd_values, "--pd")
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
    if out is None:
        return
    out.mkdir(parents=True, exist_ok=True)
    from diffsense.detection.plots import pd_vs_snr_figure, roc_figure

    for n in ns:
        path = out / f"pd_vs_snr_n{n:g}.png"
        pd_vs_snr_figure(pfa=pfa, n=n).savefig(path)
        reporter.info(f"wrote {path}")
    path = out / "roc_swerling0_n1.png"
    roc_figure(n=1).savefig(path)
    reporter.info(f"wrote {path}")
