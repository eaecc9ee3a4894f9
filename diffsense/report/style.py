"""The one plotting style of every report and trade-study figure, fitted until its text fits
(the check is :mod:`diffsense.report.layout_check`).

A figure is drawn on a constrained-layout canvas (:func:`new_figure`), takes its title from
:func:`set_title`, its legend from :func:`legend`, log axes from :func:`log_scale`, and is
written by :func:`save`, which first fits it (:func:`fit`), pass after pass until nothing
changes:

* a title is wrapped at word boundaries to the width of its axes in pixels (measured by the
  renderer), never truncated; so are legend labels (to half the axes' width inside the axes,
  to the figure's width below it) and category tick labels (to the spacing of their ticks);
* a legend stays where matplotlib's ``loc="best"`` puts it only when its box then covers none
  of the axes' lines, markers, bars, fills or data labels; otherwise it goes below the axes,
  outside the data;
* overlapping tick labels are thinned: on a log axis the labels of minor ticks go first
  (all digits, then 2, 3, 5 and 7, then 2 and 5, then none), then ticks are dropped; on a
  linear axis ticks are dropped;
* a data label (``ax.text``, ``ax.annotate``) that reaches past its axes widens the axis
  limits on that side, so the label stays inside the plot;
* a text still leaving the figure is shrunk.

:func:`layout_problems` then lists what is still wrong, one sentence per problem: a text
(title, axis label, tick label, legend text, annotation) whose box leaves the figure, a data
label leaving its axes, two tick labels of one axis that overlap, a legend covering data, a
data label crossed by a line drawn over it (a label drawn above a line on an opaque background
is legible and passes). :func:`save` writes the figure whatever remains, so that a report is
never short of a figure; the tests require the list to be empty for every shipped design.
"""

from __future__ import annotations

import math
import weakref
from pathlib import Path
from typing import Callable, List, Optional, Tuple

import numpy as np

from diffsense.report.layout_check import (TOL as _TOL, _inside, _overlap, _renderer, _visible, _texts,
                                           covered_data, drawn_tick_labels, layout_problems)

#: resolution of every figure (dots per inch), on screen and in the PNG
DPI = 110
#: font sizes (points)
TITLE_SIZE = 10.0
LEGEND_SIZE = 8.0
LABEL_SIZE = 8.0
#: passes of :func:`fit` at most
_PASSES = 8

# What fit() arranges, keyed weakly by the artist it belongs to; the values hold no artist, so
# an entry goes with its figure. Titles: title -> its unwrapped text. Legends: axes ->
# {"outside": below the axes, "height": the figure's height without that legend}.
# Category axes: axis -> the unwrapped tick labels.
_TITLES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_LEGENDS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_CATEGORIES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def pyplot():
    """matplotlib's pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def new_figure(width: float, height: float):
    """(figure, axes) of ``width`` × ``height`` inches at :data:`DPI`, constrained layout."""
    return pyplot().subplots(figsize=(width, height), dpi=DPI, layout="constrained")


def set_title(ax, text: str, size: float = TITLE_SIZE) -> None:
    """Title of ``ax``; :func:`fit` wraps it to the axes' width."""
    ax.set_title(text, fontsize=size)
    _TITLES[ax.title] = text


def legend(ax) -> None:
    """Legend of ``ax``'s labelled artists; :func:`fit` places it (module docstring)."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    _LEGENDS[ax] = {"outside": False, "height": None}
    ax.legend(handles, labels, loc="best", fontsize=LEGEND_SIZE, framealpha=0.95)


def category_ticks(axis, positions, labels, size: float = LABEL_SIZE) -> None:
    """Tick labels of a category axis (one label per position); :func:`fit` wraps each to the
    spacing of the ticks."""
    axis.set_ticks(list(positions))
    axis.set_ticklabels(list(labels), fontsize=size)
    _CATEGORIES[axis] = list(labels)


def data_label(ax, x, y, text: str, **kw):
    """A label in the data (a bar's value, a line's name) at ``(x, y)``, drawn above the lines on
    an opaque white background so that a line passing behind it leaves it legible."""
    kw.setdefault("fontsize", LABEL_SIZE)
    return ax.text(x, y, text, zorder=6, bbox=dict(boxstyle="square,pad=0.1", facecolor="white",
                                                  edgecolor="none", alpha=1.0), **kw)


# --- log axes ------------------------------------------------------------------------------


def _plain(axis) -> bool:
    """The whole view of a log ``axis`` lies between 0.001 and 99999: plain-digit labels."""
    lo, hi = sorted(axis.get_view_interval())
    return 1e-3 <= lo and hi < 1e5


def _number(x: float, plain: bool) -> str:
    """A tick value: plain digits (``plain``), else m×10^e (mathtext)."""
    if plain:
        return f"{x:.6g}"
    e = math.floor(math.log10(abs(x)) + 1e-9)
    m = x / 10.0 ** e
    if abs(m - round(m)) < 1e-6 and round(m) == 1:
        return rf"$\mathdefault{{10^{{{e}}}}}$"
    return rf"$\mathdefault{{{m:.3g}\times10^{{{e}}}}}$"


#: the leading digits of the minor ticks labelled on a log axis, by level (fit() lowers it)
_MINOR_DIGITS = {3: (2, 3, 4, 5, 6, 7, 8, 9), 2: (2, 3, 5, 7), 1: (2, 5), 0: ()}


def _first_level(axis) -> int:
    """The level of minor labels a log axis starts with: all of them up to about a decade,
    those at 2 and 5 up to 2.5 decades, none beyond."""
    lo, hi = sorted(axis.get_view_interval())
    decades = math.log10(hi / lo) if lo > 0 else np.inf
    return 3 if decades <= 1.05 else 1 if decades <= 2.5 else 0


def _log_formatter(minor: bool):
    from matplotlib.ticker import Formatter

    class LogLabels(Formatter):
        """Labels of a log axis: every decade, and the minor ticks of :data:`_MINOR_DIGITS` at
        ``level`` (:func:`_first_level` until :func:`fit` lowers it where labels overlap)."""

        def __init__(self):
            self.level: Optional[int] = None

        def __call__(self, x, pos=None):
            if not np.isfinite(x) or x <= 0:
                return ""
            if minor:
                level = _first_level(self.axis) if self.level is None else self.level
                if round(x / 10.0 ** math.floor(math.log10(x) + 1e-9)) not in _MINOR_DIGITS[level]:
                    return ""
            return _number(x, _plain(self.axis))

    return LogLabels()


def log_scale(ax, which: str) -> None:
    """Put axis ``which`` ("x" or "y") of ``ax`` on a log scale: labels in plain digits when
    the axis stays between 0.001 and 99999, else as powers of ten; minor ticks labelled when
    the axis spans few decades."""
    axis = ax.xaxis if which == "x" else ax.yaxis
    (ax.set_xscale if which == "x" else ax.set_yscale)("log")
    axis.set_major_formatter(_log_formatter(False))
    axis.set_minor_formatter(_log_formatter(True))


# --- geometry ------------------------------------------------------------------------------


# --- fitting -------------------------------------------------------------------------------


def wrap_text(text: str, width: float, fontproperties, renderer) -> str:
    """``text`` with its lines broken at spaces so that each is at most ``width`` pixels wide
    in ``fontproperties`` (a word wider than that keeps a line of its own)."""
    def px(s: str) -> float:
        return renderer.get_text_width_height_descent(s, fontproperties, ismath=False)[0]

    lines = []
    for paragraph in text.split("\n"):
        line = ""
        for word in paragraph.split(" "):
            candidate = f"{line} {word}" if line else word
            if not line or px(candidate) <= width:
                line = candidate
            else:
                lines.append(line)
                line = word
        lines.append(line)
    return "\n".join(lines)


def _fit_titles(fig, renderer) -> bool:
    """Wrap each title of :func:`set_title` to its axes' width."""
    changed = False
    for t, raw in list(_TITLES.items()):
        if t.axes is None or t.axes.figure is not fig:
            continue
        width = t.axes.get_window_extent(renderer).width
        text = wrap_text(raw, max(width - 4.0, 20.0), t.get_fontproperties(), renderer)
        if text != t.get_text():
            t.set_text(text)
            changed = True
    return changed


def _fit_categories(fig, renderer) -> bool:
    """Wrap each label of :func:`category_ticks` to the spacing of its ticks."""
    changed = False
    for axis, raw in list(_CATEGORIES.items()):
        if axis.axes.figure is not fig or len(raw) == 0:
            continue
        locs = np.asarray(axis.get_ticklocs(), dtype=float)
        pos = axis.axes.transData.transform(np.column_stack([locs, locs]))[:, 0 if axis.axis_name == "x" else 1]
        spacing = float(np.min(np.diff(np.sort(pos)))) if len(pos) > 1 else axis.axes.get_window_extent(renderer).width
        labels = axis.get_ticklabels()
        props = labels[0].get_fontproperties() if labels else None
        wrapped = [wrap_text(r, max(0.92 * spacing - 4.0, 20.0), props, renderer) for r in raw]
        if [t.get_text() for t in labels] != wrapped:
            axis.set_ticklabels(wrapped, fontsize=props.get_size_in_points() if props else LABEL_SIZE)
            changed = True
    return changed


def _fit_legends(fig, renderer) -> bool:
    """Wrap each legend of :func:`legend`; move it below the axes when it covers data there, and
    grow the figure by its height. The three are measured on the same renderer, in one step: a
    legend inside its axes does not move them, and a legend's size does not depend on where it
    is placed (each further layout pass of a figure costs a full draw)."""
    changed = False
    for ax, entry in list(_LEGENDS.items()):
        if ax.figure is not fig:
            continue
        handles, raw = ax.get_legend_handles_labels()
        if not handles:
            continue
        if not entry["outside"]:
            current = ax.get_legend()
            if current is None:
                continue
            texts = current.get_texts()
            probe = texts[0].get_fontproperties()
            width = 0.5 * ax.get_window_extent(renderer).width
            labels = [wrap_text(s, width, probe, renderer) for s in raw]
            if labels != [t.get_text() for t in texts]:
                current = ax.legend(handles, labels, loc="best", fontsize=LEGEND_SIZE, framealpha=0.95)
                changed = True
            if covered_data(ax, current.get_window_extent(renderer), renderer):
                current.remove()
                entry.update(outside=True, height=fig.get_figheight())
                labels = [wrap_text(s, 0.92 * fig.bbox.width - 60.0, probe, renderer) for s in raw]
                below = fig.legend(handles, labels, loc="outside lower center", fontsize=LEGEND_SIZE,
                                   framealpha=0.95)
                # the figure grows by the legend's height: the plot keeps its size
                fig.set_figheight(entry["height"] + below.get_window_extent(renderer).height / fig.dpi + 0.08)
                changed = True
            continue
        (below,) = fig.legends
        texts = below.get_texts()
        labels = [wrap_text(s, 0.92 * fig.bbox.width - 60.0, texts[0].get_fontproperties(), renderer) for s in raw]
        if labels != [t.get_text() for t in texts]:
            below.remove()
            fig.legend(handles, labels, loc="outside lower center", fontsize=LEGEND_SIZE, framealpha=0.95)
            changed = True
            continue
        # the figure grows by the legend's height: the plot keeps its size
        height = entry["height"] + below.get_window_extent(renderer).height / fig.dpi + 0.08
        if abs(height - fig.get_figheight()) > 0.02:
            fig.set_figheight(height)
            changed = True
    return changed


def _fit_ticks(fig, renderer) -> bool:
    """Thin the tick labels of every axis whose labels overlap (module docstring)."""
    from matplotlib.ticker import FixedLocator, LogLocator, MaxNLocator

    changed = False
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            drawn = drawn_tick_labels(axis)
            boxes = [t.get_window_extent(renderer) for t, _ in drawn]
            if not any(_overlap(boxes[i], boxes[j]) for i in range(len(boxes)) for j in range(i + 1, len(boxes))):
                continue
            minor = axis.get_minor_formatter()
            n_major = sum(1 for _, m in drawn if not m)
            if hasattr(minor, "level") and any(m for _, m in drawn):
                level = _first_level(axis) if minor.level is None else minor.level
                # fewer minor labels; those at 2 and 5 stay where fewer than two decades are labelled
                if level > (1 if n_major < 2 else 0):
                    minor.level = level - 1
                    changed = True
                    continue
            if isinstance(axis.get_major_locator(), FixedLocator) or n_major < 2:
                continue  # category labels are wrapped, never dropped; a last label stays
            if axis.get_scale() == "log":
                axis.set_major_locator(LogLocator(base=10.0, numticks=max(2, n_major // 2 + 1)))
            else:
                axis.set_major_locator(MaxNLocator(nbins=max(2, n_major - 2)))
            changed = True
    return changed


def _anchored_in_data(t, ax) -> bool:
    """``t`` is placed at a data point (so wider axis limits move it inwards)."""
    if hasattr(t, "xycoords"):
        return t.xycoords == "data"
    return t.get_transform() is ax.transData


def _fit_data_labels(fig, renderer) -> bool:
    """Widen an axis's limits on the side where a data label reaches past its axes."""
    changed = False
    for ax in fig.axes:
        frame = ax.get_window_extent(renderer)
        boxes = [t.get_window_extent(renderer) for t in ax.texts if _visible(t) and _anchored_in_data(t, ax)]
        if not boxes:
            continue
        pad = 3.0
        over = {"left": max(0.0, frame.x0 + pad - min(b.x0 for b in boxes)),
                "right": max(0.0, max(b.x1 for b in boxes) - frame.x1 + pad),
                "bottom": max(0.0, frame.y0 + pad - min(b.y0 for b in boxes)),
                "top": max(0.0, max(b.y1 for b in boxes) - frame.y1 + pad)}
        if max(over.values()) <= pad + _TOL:
            continue
        inv = ax.transData.inverted()
        if over["left"] > pad + _TOL or over["right"] > pad + _TOL:
            lo = inv.transform((frame.x0 - over["left"], frame.y0))[0] if over["left"] > pad + _TOL else None
            hi = inv.transform((frame.x1 + over["right"], frame.y0))[0] if over["right"] > pad + _TOL else None
            x0, x1 = ax.get_xlim()
            ax.set_xlim(lo if lo is not None else x0, hi if hi is not None else x1)
            changed = True
        if over["bottom"] > pad + _TOL or over["top"] > pad + _TOL:
            lo = inv.transform((frame.x0, frame.y0 - over["bottom"]))[1] if over["bottom"] > pad + _TOL else None
            hi = inv.transform((frame.x0, frame.y1 + over["top"]))[1] if over["top"] > pad + _TOL else None
            y0, y1 = ax.get_ylim()
            ax.set_ylim(lo if lo is not None else y0, hi if hi is not None else y1)
            changed = True
    return changed


def _shrink_escaping(fig, renderer) -> bool:
    """Shrink by a tenth (to 6 points at least) every text but tick and data labels that
    still leaves the figure."""
    changed = False
    for what, t, _ in _texts(fig):
        if what.endswith("tick label") or what == "data label":
            continue
        if not _inside(t.get_window_extent(renderer), fig.bbox) and t.get_fontsize() > 6.0:
            t.set_fontsize(0.9 * t.get_fontsize())
            changed = True
    return changed


def fit(fig) -> List[str]:
    """Fit ``fig`` (module docstring) and return :func:`layout_problems` of the result."""
    _fit(fig)
    return layout_problems(fig)


def _fit(fig) -> None:
    """The fitting passes of :func:`fit`: each step measures on a renderer of the figure as it
    stands (laid out again only after a step changed it), until a pass changes nothing."""
    steps: Tuple[Callable, ...] = (_fit_titles, _fit_categories, _fit_data_labels, _fit_ticks, _fit_legends,
                                   _shrink_escaping)
    renderer = _renderer(fig)
    for _ in range(_PASSES):
        changed = False
        for step in steps:
            if step(fig, renderer):
                changed = True
                renderer = _renderer(fig)
        if not changed:
            break
    # the last pass laid the figure out as it stands: keep that layout for the drawing that
    # saves it instead of laying it out once more (a third to a half of a draw's time)
    fig.set_layout_engine("none")


def save(fig, path) -> Path:
    """Fit ``fig`` and write it as PNG to ``path``: a :class:`~diffsense.report.files.FileTarget`
    (a file of a command's output folder) or a plain path, atomically either way; the figure is
    closed; returns the path."""
    from diffsense.report.files import write_atomically

    try:
        _fit(fig)  # layout_problems of the result is checked on every shipped report by the tests
        if hasattr(path, "save_figure"):  # a FileTarget, or a worker's MemoryTarget (report.drawing)
            return path.save_figure(fig, dpi=DPI)
        import io

        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=DPI)
        write_atomically(Path(path), buf.getvalue())
        return Path(path)
    finally:
        pyplot().close(fig)


__all__ = ["DPI", "pyplot", "new_figure", "set_title", "legend", "category_ticks", "data_label", "log_scale",
           "drawn_tick_labels", "covered_data", "layout_problems", "wrap_text", "fit", "save"]
