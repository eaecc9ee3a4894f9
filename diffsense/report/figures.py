"""Figures of the design report (matplotlib, Agg backend, PNG files).

Each function takes plain NumPy data (from :mod:`diffsense.report.sweeps` and
:mod:`diffsense.report.jacobian`), writes one PNG and returns its path. Every axis carries
its quantity and unit. Every figure is drawn in the one style of :mod:`diffsense.report.style`
(constrained layout, titles and legend labels wrapped to the axes, legends kept off the data,
tick labels thinned) and checked by :func:`diffsense.report.layout_check.layout_problems` as it is
saved.
"""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import numpy as np

from diffsense.report import style


def _finish(fig, ax, path, title, grid) -> Path:
    """Title, grid (``grid``: keyword arguments of ``ax.grid``), the legend of the labelled
    artists, then fit and save to ``path`` (:func:`diffsense.report.style.save`)."""
    style.set_title(ax, title)
    ax.grid(True, **grid)
    style.legend(ax)
    return style.save(fig, path)


def _range_axis(r_m):
    """(scaled ranges, unit label): km above 5 km, else m."""
    r = np.asarray(r_m, dtype=float)
    if np.nanmax(r) >= 5000.0:
        return r / 1000.0, "km", 1000.0
    return r, "m", 1.0


def waterfall(path, rows: List[dict], *, title: str, required_db: Optional[float] = None,
              required_label: str = "SNR needed") -> Path:
    """Link-budget waterfall: each signed term as a floating bar from the running total before it
    to the running total after it, and the final SNR as a bar from 0 (dB). Each bar's value is
    written past its end, above the lines on a white background (a reference line passing
    behind a label leaves it legible)."""
    names = [r["term"] for r in rows] + ["SNR (sum of the terms)"]
    values = np.array([r["db"] for r in rows])
    ends = np.cumsum(values)
    starts = ends - values
    total = float(ends[-1])
    n = len(names)
    fig, ax = style.new_figure(8.8, 0.42 * n + 2.0)
    y = np.arange(n)[::-1]
    colours = ["#2e7d32" if v >= 0 else "#c62828" for v in values] + ["#1565c0"]
    lefts = np.concatenate([np.minimum(starts, ends), [min(0.0, total)]])
    widths = np.concatenate([np.abs(values), [abs(total)]])
    ax.barh(y, widths, left=lefts, color=colours, height=0.62, edgecolor="black", linewidth=0.4)
    for k in range(n - 2):
        ax.plot([ends[k], ends[k]], [y[k] - 0.31, y[k + 1] + 0.31], color="grey", linewidth=0.6)
    span = max(np.max(np.concatenate([ends, starts, [0.0]])) - np.min(np.concatenate([ends, starts, [0.0]])), 1.0)
    for k in range(n):
        v = values[k] if k < n - 1 else total
        right = lefts[k] + widths[k]
        text = "0.00 dB" if abs(v) < 0.005 else f"{v:+.2f} dB"
        style.data_label(ax, right + 0.01 * span, y[k], text, va="center", ha="left")
    ax.set_yticks(y)
    ax.set_yticklabels(names, fontsize=9)
    ax.axvline(0.0, color="black", linewidth=0.6)
    if required_db is not None and np.isfinite(required_db):
        ax.axvline(required_db, color="#ef6c00", linestyle="--", linewidth=1.2,
                   label=f"{required_label} = {required_db:.2f} dB")
    lo = min(np.min(np.concatenate([starts, ends])), 0.0)
    hi = max(np.max(np.concatenate([starts, ends])), 0.0)
    ax.set_xlim(lo - 0.03 * span, hi + 0.16 * span)
    ax.set_xlabel("Running total of the budget (dB)")
    return _finish(fig, ax, path, title, grid=dict(axis="x", alpha=0.35))


def tornado(path, labels: List[str], elasticities, *, title: str, xlabel: str, top: int = 15) -> Path:
    """Tornado chart: the ``top`` inputs with the largest |elasticity|, largest at the top."""
    e = np.asarray(elasticities, dtype=float)
    nonzero = [k for k in np.argsort(-np.abs(e)) if np.isfinite(e[k]) and abs(e[k]) > 1e-12]
    if not nonzero:
        raise ValueError("no input has a non-zero elasticity")
    order = nonzero[:top]
    if len(nonzero) > top:
        title = f"{title}\n(the {top} largest of {len(nonzero)} non-zero elasticities)"
    vals = e[order]
    names = [labels[k] for k in order]
    n = len(order)
    fig, ax = style.new_figure(8.4, 0.42 * n + 1.9)
    y = np.arange(n)[::-1]
    ax.barh(y, vals, color=["#2e7d32" if v > 0 else "#c62828" for v in vals], height=0.62,
            edgecolor="black", linewidth=0.4)
    span = max(float(np.max(np.abs(vals))), 1e-12)
    for yy, v in zip(y, vals):
        style.data_label(ax, v + (0.02 if v >= 0 else -0.02) * span, yy, f"{v:+.3g}", va="center",
                         ha="left" if v >= 0 else "right")
    ax.set_yticks(y)
    ax.set_yticklabels(names, fontsize=9)
    ax.axvline(0.0, color="black", linewidth=0.8)
    lo, hi = min(0.0, float(np.min(vals))), max(0.0, float(np.max(vals)))
    ax.set_xlim(lo - 0.25 * span, hi + 0.25 * span)
    ax.set_xlabel(xlabel)
    return _finish(fig, ax, path, title, grid=dict(axis="x", alpha=0.35))


def _mark(ax, rc, yc, unit, label="requirement just met"):
    """The marker of the range ``rc`` (axis units) where a requirement is just met."""
    ax.plot([rc], [yc], marker="o", color="#ef6c00", markersize=6, zorder=5, linestyle="none",
            label=f"{label} at {rc:.4g} {unit}")


def _required_range(ax, data: dict, div: float, unit: str) -> None:
    """Where the main margin requirement holds: the interval of ranges it must hold over,
    shaded (``required_range_m`` of :func:`~diffsense.report.sweeps.range_sweep`), or else the
    case's range, a dotted line."""
    span = data.get("required_range_m")
    if span is not None:
        lo, hi = span[0] / div, span[1] / div
        ax.axvspan(lo, hi, color="#9e9e9e", alpha=0.18, linewidth=0,
                   label=f"required at every range from {lo:g} to {hi:g} {unit}")
        return
    r0 = data["design_range_m"] / div
    ax.axvline(r0, color="black", linestyle=":", linewidth=1.2, label=f"requirement range {r0:g} {unit}")


def _at(r, curve, rc) -> float:
    """``curve`` (on the grid ``r``) interpolated at ``rc``."""
    c = np.asarray(curve, dtype=float)
    ok = np.isfinite(c)
    return float(np.interp(rc, np.asarray(r)[ok], c[ok]))


def snr_vs_range(path, data: dict, *, title: str) -> Path:
    """SNR against range with the required SNR, where the main margin requirement applies (its
    range, or the interval of ranges it holds over: :func:`_required_range`) and the range where
    it is just met (``met_to_m`` of the sweep).

    When the requirement states its own condition (``condition`` of
    :func:`~diffsense.report.sweeps.range_sweep`, e.g. the target in its deepest fade), the SNR
    in that condition is the solid curve, meeting the required SNR at the marked range, and the
    chain's SNR of the mean target is dashed; the Pd figure draws the same two conditions."""
    r, unit, div = _range_axis(data["range_m"])
    out = data["outputs"]
    cond = data.get("condition")
    fig, ax = style.new_figure(7.8, 4.8)
    shown = [np.asarray(out["snr_db"])]
    if cond is not None:
        ax.plot(r, cond["snr_db"], color="#1565c0", linewidth=1.8,
                label=f"SNR {cond['text']} (the requirement's condition)")
        if not _same(cond["snr_db"], out["snr_db"], 1e-6):  # a curve lying under another is not drawn
            ax.plot(r, out["snr_db"], color="#1565c0", linestyle="--", linewidth=1.1, alpha=0.8,
                    label="SNR of the mean target (the chain's snr_db)")
        shown.append(np.asarray(cond["snr_db"]))
        marked = cond["snr_db"]
    else:
        ax.plot(r, out["snr_db"], color="#1565c0", linewidth=1.8, label="SNR at range (chain)")
        marked = out["snr_db"]
    if "required_snr_db" in out:
        ax.plot(r, out["required_snr_db"], color="#6a1b9a", linestyle="--", linewidth=1.2,
                label="required SNR (detectability for Pd, Pfa)")
        shown.append(np.asarray(out["required_snr_db"]))
    thr = data.get("threshold_db")
    if cond is None and thr is not None and (
            "required_snr_db" not in out or np.nanmax(np.abs(thr - out["required_snr_db"])) > 1e-6):
        ax.plot(r, thr, color="#ef6c00", linestyle="-.", linewidth=1.2,
                label=f"SNR needed by '{data['margin_requirement']['name']}'")
        shown.append(np.asarray(thr))
    _required_range(ax, data, div, unit)
    if data.get("met_to_m") is not None:
        rc = data["met_to_m"] / div
        _mark(ax, rc, _at(r, marked, rc), unit)
    ax.set_xlabel(f"Range ({unit})")
    ax.set_ylabel("Signal-to-noise ratio (dB)")
    finite = np.concatenate([c[np.isfinite(c)] for c in shown])
    if finite.size:
        hi = float(np.max(finite)) + 5.0
        ax.set_ylim(max(float(np.min(finite)) - 3.0, hi - 160.0), hi)
    ax.set_xlim(0.0, float(np.max(r)))
    return _finish(fig, ax, path, title, grid=dict(alpha=0.35))


def _same(a, b, tol: float) -> bool:
    """The two curves agree to ``tol`` wherever both are finite (one would hide the other)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    ok = np.isfinite(a) & np.isfinite(b)
    return bool(np.all(np.isfinite(a) == np.isfinite(b)) and np.all(np.abs(a[ok] - b[ok]) <= tol))


def pd_vs_range(path, data: dict, *, required_pd: Optional[float], pfa: Optional[float], title: str) -> Path:
    """Pd against range with the required Pd, where the main margin requirement applies
    (:func:`_required_range`) and the range where it is just met (``met_to_m``, the range the
    SNR figure marks).

    When the requirement states its own condition (see :func:`snr_vs_range`) the Pd in that
    condition is the solid curve, reaching the required Pd at the marked range, and the
    chain's Pd of the mean target is dashed. Without a margin requirement the marker is where
    the chain's Pd falls to the required Pd."""
    r, unit, div = _range_axis(data["range_m"])
    pd = np.asarray(data["outputs"]["pd"])
    cond = data.get("condition")
    at = f", Pfa = {pfa:.0e}" if pfa is not None else ""
    fig, ax = style.new_figure(7.8, 4.8)
    if cond is not None and cond.get("pd") is not None:
        ax.plot(r, cond["pd"], color="#1565c0", linewidth=1.8,
                label=f"Pd {cond['text']} (the requirement's condition){at}")
        if not _same(cond["pd"], pd, 1e-6):  # a curve lying under another is not drawn
            ax.plot(r, pd, color="#1565c0", linestyle="--", linewidth=1.1, alpha=0.8,
                    label="Pd of the mean target (the chain's pd)")
        marked = cond["pd"]
    else:
        ax.plot(r, pd, color="#1565c0", linewidth=1.8, label=f"Pd at range (chain){at}")
        marked = pd
    _required_range(ax, data, div, unit)
    if required_pd is not None:
        ax.axhline(required_pd, color="#ef6c00", linestyle="--", linewidth=1.2, label=f"required Pd = {required_pd:g}")
    if data.get("met_to_m") is not None:
        rc = data["met_to_m"] / div
        _mark(ax, rc, _at(r, marked, rc), unit)
    elif required_pd is not None:
        from diffsense.report.sweeps import last_crossing

        rc = last_crossing(r, pd - required_pd)
        if rc is not None:
            _mark(ax, rc, required_pd, unit, label="Pd falls to the required value")
    ax.set_xlabel(f"Range ({unit})")
    ax.set_ylabel("Probability of detection Pd")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(0.0, float(np.max(r)))
    return _finish(fig, ax, path, title, grid=dict(alpha=0.35))


def roc(path, data: dict, *, required_pd: Optional[float], title: str) -> Path:
    """ROC: Pd against Pfa (log axis) at the design (first curve) and at longer ranges, with the
    required operating point."""
    fig, ax = style.new_figure(7.6, 4.9)
    styles = ["-", "--", "-.", ":"]
    colours = ["#1565c0", "#2e7d32", "#6a1b9a", "#c62828"]
    for c, curve in enumerate(data["curves"]):
        what = "design" if c == 0 else "longer range"
        parts = []
        if curve["range_m"] is not None:
            parts.append(f"R = {curve['range_m']:.4g} m")
        if curve["snr_db"] is not None:
            parts.append(f"SNR = {curve['snr_db']:.2f} dB")
        ax.plot(data["pfa"], curve["pd"], color=colours[c % 4], linestyle=styles[c % 4],
                linewidth=1.9 if c == 0 else 1.3, label=f"{what}: " + ", ".join(parts))
    style.log_scale(ax, "x")
    pfa0 = data["design_pfa"]
    ax.axvline(pfa0, color="black", linestyle=":", linewidth=1.0, label=f"design Pfa = {pfa0:.0e}")
    if required_pd is not None:
        ax.plot([pfa0], [required_pd], marker="*", markersize=13, color="#ef6c00", linestyle="none",
                label=f"required (Pfa, Pd) = ({pfa0:.0e}, {required_pd:g})")
    ax.set_xlabel("Probability of false alarm Pfa")
    ax.set_ylabel("Probability of detection Pd")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(float(np.min(data["pfa"])), float(np.max(data["pfa"])))
    return _finish(fig, ax, path, title, grid=dict(which="both", alpha=0.3))


def blake_chart(path, data: dict, *, title: str) -> Path:
    """Range-height-angle coverage: the detection contour with elevation-angle guide lines
    and the horizon over the 4/3 earth."""
    from diffsense.report.sweeps import height_over_effective_earth_m

    ranges = np.asarray(data["range_m"], dtype=float)
    ok = np.isfinite(ranges)
    if not ok.any():
        raise ValueError("no elevation angle reaches detection on the range grid")
    r_max = float(np.nanmax(ranges)) * 1.15
    rr = np.linspace(0.0, r_max, 200)
    r_plot, unit, div = _range_axis(rr)
    fig, ax = style.new_figure(8.2, 4.9)
    h0 = data["antenna_height_m"]
    el = data["elevation_deg"][ok]
    rc = ranges[ok]
    hc = height_over_effective_earth_m(rc, el, h0)
    ax.fill(np.concatenate([[0.0], rc / div, [0.0]]), np.concatenate([[h0], hc, [h0]]), color="#90caf9", alpha=0.6,
            label=f"detection: {data['output']} ≥ {data['limit']:g} dB")
    ax.plot(rc / div, hc, color="#0d47a1", linewidth=1.5)
    b = data["beamwidth_deg"]
    h_top = float(np.nanmax(hc))
    guides = [0.0, data["boresight_deg"], data["boresight_deg"] + b, data["boresight_deg"] + 2 * b]
    for g in guides:
        hg = height_over_effective_earth_m(rr, g, h0)
        ax.plot(r_plot, hg, color="grey", linewidth=0.7, linestyle="--" if g else "-")
        k = int(np.searchsorted(hg, 1.05 * h_top)) if np.any(hg > 1.05 * h_top) else len(rr) - 1
        k = min(max(k, 1), len(rr) - 1)
        style.data_label(ax, r_plot[k], hg[k], f"{g:.3g}°", color="dimgrey", ha="right", va="bottom")
    ax.set_xlim(0.0, r_max / div)
    ax.set_ylim(min(0.0, float(np.nanmin(hc))) - 0.02 * h_top, 1.12 * h_top)
    ax.set_xlabel(f"Slant range ({unit})")
    ax.set_ylabel("Height above the surface (m)")
    return _finish(fig, ax, path, f"{title}\nGaussian beam {b:.3g}° wide, boresight {data['boresight_deg']:.3g}° "
                   f"elevation, antenna height {data['antenna_height_m']:g} m; grey lines: elevation angles",
                   grid=dict(alpha=0.3))


__all__ = ["waterfall", "tornado", "snr_vs_range", "pd_vs_range", "roc", "blake_chart"]
