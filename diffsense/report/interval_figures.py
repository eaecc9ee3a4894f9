"""The report's figure of a requirement over an interval: the requirement output against the
interval's parameter on the dense re-check grid, the limit, and the worst point marked."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from diffsense.report import style
from diffsense.report.figures import _finish, _range_axis

__all__ = ["interval_margin", "interval_caption"]


def interval_caption(row: dict) -> str:
    """The figure's caption for a requirement row with ``over`` and ``curve``."""
    (name,) = row["over"]
    lo, hi, unit = row["over"][name]
    return (f"{row['case']}.{row['output']} against {name} from {lo:g} to {hi:g} {unit}: the requirement must hold at "
            f"every point. The curve is the independent re-check on {row['dense_points']} points (every "
            f"{max(1, round(row['dense_points'] / len(row['curve']['parameter'])))}th drawn); the marker is the worst "
            "point (the solver's search refined by Newton steps, or the dense grid's, whichever is worse).")


def interval_margin(path, row: dict, *, title: str) -> Path:
    """Draw ``row``'s output over its one-parameter interval with the limit and the worst point."""
    (name,) = row["over"]
    unit = row["over"][name][2]
    p = np.asarray(row["curve"]["parameter"], dtype=float)
    v = np.asarray(row["curve"]["value"], dtype=float)
    worst_p = row["worst_at"][name]
    if unit == "m":
        x, xunit, div = _range_axis(p)
    else:
        x, xunit, div = p, unit, 1.0
    fig, ax = style.new_figure(7.8, 4.6)
    ax.plot(x, v, color="#1565c0", linewidth=1.4, label=f"{row['output']} ({row['unit']})")
    ax.axhline(row["limit"], color="#c62828", linestyle="--", linewidth=1.2,
               label=f"limit: {'at least' if row['sense'] == 'at_least' else 'at most'} {row['limit']:g} {row['unit']}")
    ax.plot([worst_p / div], [row["value"]], marker="o", color="#ef6c00", markersize=7, zorder=5,
            label=f"worst point: {row['value']:.4g} {row['unit']} at {worst_p / div:.5g} {xunit}")
    finite = v[np.isfinite(v)]
    if finite.size:
        lo = min(float(np.min(finite)), row["limit"])
        hi = max(float(np.max(finite)), row["limit"])
        span = hi - lo if hi > lo else 1.0
        ax.set_ylim(lo - 0.08 * span, min(hi + 0.08 * span, lo + 200.0))
    if p[0] > 0 and p[-1] / p[0] >= 10:
        style.log_scale(ax, "x")
    ax.set_xlabel(f"{name} ({xunit})")
    ax.set_ylabel(f"{row['output']} ({row['unit']})")
    return _finish(fig, ax, path, title, grid=dict(which="both", alpha=0.35))
