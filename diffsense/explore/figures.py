"""The explorer's live charts (Bokeh figures fed by column data sources, so that a slider move
replaces numbers, never figures): the link-budget waterfall, SNR and Pd against range with the
requirement markers, and the elasticity tornado. Each ``*_data`` function is pure: it turns a
snapshot's numbers into the columns its figure draws.
"""

from __future__ import annotations

from typing import List, Optional

import numpy as np
from bokeh.models import CategoricalAxis, ColumnDataSource, CustomJSTickFormatter, HoverTool, Range1d, Span
from bokeh.plotting import figure

GREEN, RED, BLUE, ORANGE, GREY = "#2e7d32", "#c62828", "#1565c0", "#ef6c00", "#757575"
TOTAL_LABEL = "SNR (sum of the terms)"
TORNADO_BARS = 12
#: the waterfall's value axis: the label of term ``tick`` is its ``text`` in the source
VALUE_LABEL_JS = "const d = source.data; const k = d.term.indexOf(tick); return k < 0 ? '' : d.text[k];"


def _figure(title: str, **kwargs):
    fig = figure(title=title, toolbar_location=None, sizing_mode="stretch_width", **kwargs)
    fig.title.text_font_size = "13px"
    fig.outline_line_color = None
    fig.grid.grid_line_alpha = 0.35
    return fig


def waterfall_data(rows: List[dict]) -> dict:
    """Floating bars from the running total before each term to the one after it (dB), and the
    total from 0; colours: gain green, loss red, total blue."""
    values = np.array([r["db"] for r in rows], dtype=float)
    ends = np.cumsum(values)
    starts = ends - values
    total = float(ends[-1]) if len(ends) else 0.0
    names = [r["term"] for r in rows] + [TOTAL_LABEL]
    left = list(np.minimum(starts, ends)) + [min(0.0, total)]
    right = list(np.maximum(starts, ends)) + [max(0.0, total)]
    shown = list(values) + [total]
    return {"term": names, "left": left, "right": right,
            "colour": [GREEN if v >= 0 else RED for v in values] + [BLUE],
            "text": [_db_text(v) for v in shown], "db": shown}


def _db_text(value: float) -> str:
    """A budget term as shown: signed, two decimals, "0.00 dB" for what rounds to zero, padded
    with figure spaces (U+2007, one digit wide) so that a column of them lines up."""
    number = "0.00" if abs(value) < 0.005 else f"{value:+.2f}"
    return number.rjust(7, "\u2007") + " dB"


def waterfall_figure(source: ColumnDataSource, required: Span):
    """The waterfall; each term's value is written on a second axis right of the frame, where
    no bar hides it and the frame's edge cannot clip it."""
    terms = list(source.data["term"])
    fig = _figure("Link budget (running total, dB)", y_range=terms[::-1], x_range=Range1d(-1.0, 1.0),
                  height=max(260, 24 * len(terms) + 70), x_axis_label="dB")
    fig.hbar(y="term", left="left", right="right", height=0.65, color="colour", line_color="black",
             line_width=0.4, source=source)
    # the right axis shares the terms' range; its labels are the values in the source (looked up
    # by the browser when it draws, so a slider move only replaces the source's numbers)
    value_of = CustomJSTickFormatter(args={"source": source}, code=VALUE_LABEL_JS)
    fig.add_layout(CategoricalAxis(formatter=value_of, axis_line_color=None, major_tick_line_color=None,
                                   major_label_text_font_size="11px", major_label_text_color="#333333"), "right")
    fig.add_layout(Span(location=0.0, dimension="height", line_color="black", line_width=1))
    fig.add_layout(required)
    fig.add_tools(HoverTool(tooltips=[("term", "@term"), ("value", "@text")]))
    show_waterfall(fig, source.data)
    return fig


def show_waterfall(fig, data: dict) -> None:
    """Point the waterfall ``fig`` at the terms of ``data`` (:func:`waterfall_data`): their
    order and the dB span with a small margin."""
    fig.y_range.factors = list(data["term"])[::-1]
    lo, hi = min(list(data["left"]) + [0.0]), max(list(data["right"]) + [0.0])
    pad = 0.04 * (hi - lo) or 1.0
    fig.x_range.start, fig.x_range.end = lo - pad, hi + pad


def required_span() -> Span:
    """The SNR the main margin requirement needs (dB), drawn across the waterfall."""
    return Span(location=0.0, dimension="height", line_color=ORANGE, line_dash="dashed", line_width=2)


def sweep_data(sweep: Optional[dict], output: str) -> dict:
    """Columns of one swept output against range (km)."""
    if sweep is None or output not in sweep["outputs"]:
        return {"range_km": [], "y": []}
    return {"range_km": np.asarray(sweep["range_m"]) / 1e3, "y": np.asarray(sweep["outputs"][output])}


def snr_figure(snr: ColumnDataSource, threshold: ColumnDataSource, design: Span):
    fig = _figure("SNR against range", height=300, x_axis_label="range (km)", y_axis_label="dB")
    fig.line("range_km", "y", source=snr, color=BLUE, line_width=2, legend_label="SNR")
    fig.line("range_km", "y", source=threshold, color=ORANGE, line_dash="dashed", line_width=2,
             legend_label="SNR the margin requirement needs")
    fig.add_layout(design)
    fig.legend.location = "top_right"
    fig.legend.label_text_font_size = "11px"
    return fig


def pd_figure(pd: ColumnDataSource, required: Span, design: Span):
    fig = _figure("Probability of detection against range", height=300, x_axis_label="range (km)",
                  y_axis_label="Pd", y_range=(-0.02, 1.02))
    fig.line("range_km", "y", source=pd, color=BLUE, line_width=2, legend_label="Pd")
    fig.add_layout(required)
    fig.add_layout(design)
    fig.legend.location = "bottom_left"
    fig.legend.label_text_font_size = "11px"
    return fig


def design_range_span() -> Span:
    """The case's design range (km), drawn on the range charts."""
    return Span(location=0.0, dimension="height", line_color=GREY, line_dash="dotted", line_width=2)


def required_pd_span() -> Span:
    return Span(location=0.0, dimension="width", line_color=ORANGE, line_dash="dashed", line_width=2)


def tornado_data(labels: List[str], elasticities, top: int = TORNADO_BARS) -> dict:
    """The ``top`` inputs with the largest |elasticity| (largest first)."""
    e = np.asarray(elasticities, dtype=float)
    order = [k for k in np.argsort(-np.abs(np.nan_to_num(e))) if np.isfinite(e[k]) and abs(e[k]) > 1e-12][:top]
    return {"input": [labels[k] for k in order], "zero": [0.0] * len(order), "e": [float(e[k]) for k in order],
            "colour": [GREEN if e[k] > 0 else RED for k in order], "text": [f"{e[k]:+.3g}" for k in order]}


def tornado_figure(source: ColumnDataSource):
    fig = _figure("Elasticities (dB per dB, % per %)", y_range=list(source.data["input"])[::-1],
                  height=24 * TORNADO_BARS + 80, x_axis_label="elasticity")
    fig.hbar(y="input", left="zero", right="e", height=0.65, color="colour", line_color="black", line_width=0.4,
             source=source)
    fig.add_layout(Span(location=0.0, dimension="height", line_color="black", line_width=1))
    fig.add_tools(HoverTool(tooltips=[("input", "@input"), ("elasticity", "@text")]))
    return fig


def interval_data(curve: Optional[dict]) -> dict:
    """Columns of an interval requirement's output against its parameter (snapshot ``intervals``)."""
    if curve is None:
        return {"x": [], "y": [], "limit": []}
    x = np.asarray(curve["grid"])
    return {"x": x, "y": np.asarray(curve["values"]), "limit": np.full(x.shape, curve["limit"])}


def interval_worst_data(curve: Optional[dict]) -> dict:
    """The worst point of the curve's grid (min for at_least, max for at_most)."""
    if curve is None or not len(curve["values"]):
        return {"x": [], "y": []}
    v = np.asarray(curve["values"])
    k = int(np.nanargmax(v) if curve["sense"] == "at_most" else np.nanargmin(v))
    return {"x": [float(curve["grid"][k])], "y": [float(v[k])]}


def interval_title(curve: dict) -> str:
    sense = {"at_least": "≥", "at_most": "≤"}.get(curve["sense"], "=")
    return (f"{curve['output']} over {curve['parameter']}: worst {curve['worst_value']:.4g} "
            f"{sense} {curve['limit']:.4g} required ({curve['status']})")


def interval_figure(source: ColumnDataSource, worst: ColumnDataSource, log_x: bool = False):
    """The chosen interval requirement's output over its parameter (log axis where every
    interval's search grid is log-spaced), its limit (a line of the source, so that the axis
    range always holds it) and the worst grid point."""
    fig = _figure("Requirement over its interval", height=300, x_axis_type="log" if log_x else "linear")
    fig.line("x", "y", source=source, color=BLUE, line_width=2, legend_label="output")
    fig.line("x", "limit", source=source, color=ORANGE, line_dash="dashed", line_width=2, legend_label="limit")
    fig.scatter("x", "y", source=worst, color=RED, size=9, legend_label="worst point of the curve")
    fig.legend.location = "top_right"
    fig.legend.label_text_font_size = "11px"
    return fig


__all__ = ["waterfall_data", "waterfall_figure", "show_waterfall", "required_span", "sweep_data", "snr_figure", "pd_figure",
           "design_range_span", "required_pd_span", "tornado_data", "tornado_figure", "interval_data",
           "interval_worst_data", "interval_title", "interval_figure"]
